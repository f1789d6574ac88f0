//! A hydrodynamic retarder's drag while it is off, as VECTO charges it: a torque loss over the
//! retarder's own speed (its loss map), on the shaft it sits on through its step-up ratio.
//!
//! A retarder at the gearbox input turns with the engine whenever a gear is engaged; one at the
//! gearbox output turns with the wheels, so it drags in neutral too. Braking with the retarder is
//! not modelled: the service brakes take what the engine's drag leaves.

use super::Curve;
use crate::{CoreError, CoreResult};

/// Where the retarder sits in the driveline.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RetarderPosition {
    /// On the gearbox's input shaft (engine speed).
    GearboxInput,
    /// On the gearbox's output shaft (the axle's input speed).
    GearboxOutput,
}

impl RetarderPosition {
    /// The position a reader names: `input` or `output` (of the gearbox); `key` names it in errors.
    pub fn named(key: &str, name: &str) -> CoreResult<Self> {
        match name {
            "input" => Ok(RetarderPosition::GearboxInput),
            "output" => Ok(RetarderPosition::GearboxOutput),
            _ => Err(CoreError::invalid(key, "input or output (of the gearbox)").got(name)),
        }
    }
}

/// A retarder's loss map on its shaft.
#[derive(Debug, Clone)]
pub struct Retarder {
    position: RetarderPosition,
    ratio: f64,
    /// Torque loss [Nm] over the retarder's speed [rpm], linear between the map's points.
    loss: Curve,
}

impl Retarder {
    /// A retarder at `position` turning `ratio` (> 0) times as fast as its shaft, losing the map's
    /// `(retarder speed [rpm], torque loss [Nm])` points (losses ≥ 0).
    pub fn new(position: RetarderPosition, ratio: f64, points: &[(f64, f64)]) -> CoreResult<Self> {
        if !(ratio.is_finite() && ratio > 0.0) {
            return Err(CoreError::invalid("retarder_ratio", "a number > 0").got(ratio));
        }
        if let Some(&(n, loss)) = points.iter().find(|p| !(p.1 >= 0.0)) {
            return Err(
                CoreError::invalid("retarder_loss_map", "torque losses >= 0").got(format!("{loss} Nm at {n} rpm"))
            );
        }
        Ok(Retarder { position, ratio, loss: Curve::new("retarder_loss_map", points)? })
    }

    /// Where it sits.
    pub fn position(&self) -> RetarderPosition {
        self.position
    }

    /// Torque [Nm] it takes from its shaft turning at `shaft_rpm`: the map's loss at the retarder's
    /// speed, times the ratio (the map's end values beyond its speeds).
    #[inline]
    pub fn loss_nm(&self, shaft_rpm: f64) -> f64 {
        self.loss.at(shaft_rpm.abs() * self.ratio) * self.ratio
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_loss_is_the_maps_at_the_retarders_speed_seen_through_its_ratio() {
        let map = [(0.0, 10.0), (1000.0, 12.0), (2000.0, 18.0)];
        let direct = Retarder::new(RetarderPosition::GearboxOutput, 1.0, &map).unwrap();
        assert!((direct.loss_nm(500.0) - 11.0).abs() < 1e-12);
        // Twice as fast as its shaft: the map at 1500 rpm (15 Nm), twice the torque on the shaft.
        let stepped = Retarder::new(RetarderPosition::GearboxInput, 2.0, &map).unwrap();
        assert!((stepped.loss_nm(750.0) - 30.0).abs() < 1e-12);
    }

    #[test]
    fn refuses_a_negative_loss_a_bad_ratio_and_an_unknown_position() {
        let bad = Retarder::new(RetarderPosition::GearboxOutput, 1.0, &[(0.0, 1.0), (100.0, -1.0)]);
        assert_eq!(bad.unwrap_err().key(), "retarder_loss_map");
        let ratio = Retarder::new(RetarderPosition::GearboxOutput, 0.0, &[(0.0, 1.0), (100.0, 1.0)]);
        assert_eq!(ratio.unwrap_err().key(), "retarder_ratio");
        assert_eq!(RetarderPosition::named("retarder_position", "axle").unwrap_err().key(), "retarder_position");
    }
}
