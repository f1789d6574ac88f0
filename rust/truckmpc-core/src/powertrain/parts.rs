//! A map-based truck's component data as a file reader gives it (engine, gearbox and axle, body),
//! and the one place that data becomes a [`MapTruck`]: every value is checked by the part it
//! builds, the error naming the value.

use super::retarder::{Retarder, RetarderPosition};
use super::{Body, Driveline, Engine, MapTruck};
use crate::CoreResult;

/// Points (x, y, z) of a map or curve; each field that holds them says the columns and units.
pub type Rows = Vec<(f64, f64, f64)>;

/// An engine's data.
#[derive(Debug, Clone, PartialEq)]
pub struct EngineData {
    /// Idle speed [rpm].
    pub idle_speed_rpm: f64,
    /// Rotating inertia of the engine and what turns with it [kg m²].
    pub inertia_kgm2: f64,
    /// Full-load curve: (speed [rpm], full-load torque [Nm], drag torque [Nm]).
    pub full_load: Rows,
    /// Fuel map: (speed [rpm], torque [Nm], fuel [g/h]).
    pub fuel_map: Rows,
}

/// A gearbox and axle with their losses, and the tyres' radius.
#[derive(Debug, Clone, PartialEq)]
pub struct DrivelineData {
    /// Gear ratios, first gear first (decreasing) [-].
    pub gear_ratios: Vec<f64>,
    /// Axle ratio [-].
    pub axle_ratio: f64,
    /// Gearbox efficiency (0, 1] where no loss map is given.
    pub gear_efficiency: f64,
    /// Axle efficiency (0, 1] where no loss map is given.
    pub axle_efficiency: f64,
    /// Drag torque at the gearbox input [Nm] (≥ 0) where no loss maps are given.
    pub loss_torque_nm: f64,
    /// Dynamic tyre radius [m].
    pub wheel_radius_m: f64,
    /// One loss map per gear, first gear first: (input speed [rpm], input torque [Nm], torque loss [Nm]).
    pub gear_loss_maps: Option<Vec<Rows>>,
    /// The axle's loss map, as a gear's.
    pub axle_loss_map: Option<Rows>,
    /// The retarder's loss map, `(retarder speed [rpm], torque loss [Nm])`, or none without a
    /// retarder whose losses count.
    pub retarder_loss_map: Option<Vec<(f64, f64)>>,
    /// The retarder's speed per speed of its shaft [-].
    pub retarder_ratio: f64,
    /// Which gearbox shaft it turns with: `input` or `output`.
    pub retarder_position: String,
}

/// A truck's parts: engine, driveline, body, and the drag area over speed that replaces the body's
/// constant one where a file gives it (`(speed [m/s], Cd·A [m²])`, e.g. VECTO's cross-wind correction).
#[derive(Debug, Clone, PartialEq)]
pub struct TruckParts {
    /// The engine.
    pub engine: EngineData,
    /// The gearbox, axle and tyres.
    pub driveline: DrivelineData,
    /// Mass, inertia, air and rolling resistance, auxiliaries.
    pub body: Body,
    /// Cd·A over speed, or none for the body's constant `cda_m2`.
    pub cda_curve: Option<Vec<(f64, f64)>>,
}

impl TruckParts {
    /// The truck these parts make; the error names the first value its part refuses.
    pub fn build(&self) -> CoreResult<MapTruck> {
        let e = &self.engine;
        let engine = Engine::new(e.idle_speed_rpm, e.inertia_kgm2, &e.full_load, &e.fuel_map)?;
        let d = &self.driveline;
        let losses = (d.gear_efficiency, d.axle_efficiency, d.loss_torque_nm);
        let driveline = Driveline::new((&d.gear_ratios, d.axle_ratio), losses, d.wheel_radius_m)?
            .with_loss_maps(d.gear_loss_maps.as_deref(), d.axle_loss_map.as_deref())?;
        let driveline = match &d.retarder_loss_map {
            Some(map) => {
                let position = RetarderPosition::named("retarder_position", &d.retarder_position)?;
                driveline.with_retarder(Retarder::new(position, d.retarder_ratio, map)?)
            }
            None => driveline,
        };
        let truck = MapTruck::new(engine, driveline, self.body)?;
        match &self.cda_curve {
            Some(curve) => truck.with_cda_curve(curve),
            None => Ok(truck),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::powertrain::tests::{body, plane, plane_points};
    use crate::CoreError;

    fn parts() -> TruckParts {
        TruckParts {
            engine: EngineData {
                idle_speed_rpm: 600.0,
                inertia_kgm2: 4.0,
                full_load: vec![(600.0, 1000.0, -100.0), (1200.0, 2000.0, -150.0), (1800.0, 1600.0, -200.0)],
                fuel_map: plane_points(),
            },
            driveline: DrivelineData {
                gear_ratios: vec![3.0, 2.0, 1.0],
                axle_ratio: 3.0,
                gear_efficiency: 0.98,
                axle_efficiency: 0.97,
                loss_torque_nm: 20.0,
                wheel_radius_m: 0.5,
                gear_loss_maps: None,
                axle_loss_map: None,
                retarder_loss_map: None,
                retarder_ratio: 1.0,
                retarder_position: "output".into(),
            },
            body: body(),
            cda_curve: None,
        }
    }

    /// Every part reaches the truck: the engine's idle speed, inertia, full-load and drag curves
    /// and fuel map; the ratios and radius (engine speed at 20 m/s in gear 2 is 240 rad/s), the
    /// efficiencies and drag torque; the body; then the drag-area curve and the loss maps.
    #[test]
    fn every_part_reaches_the_truck() {
        let truck = parts().build().unwrap();
        let engine = truck.engine();
        assert_eq!((engine.idle_rpm(), engine.inertia_kgm2()), (600.0, 4.0));
        assert_eq!((engine.max_torque_nm(1200.0), engine.drag_torque_nm(1200.0)), (2000.0, -150.0));
        assert!((engine.fuel_rate_g_per_h(900.0, 500.0) - plane(900.0, 500.0)).abs() < 1e-6);
        let expected_rpm = 240.0 * 60.0 / (2.0 * std::f64::consts::PI);
        assert!((truck.driveline().engine_speed_rpm(20.0, 2) - expected_rpm).abs() < 1e-9);
        assert!((truck.driveline().efficiency() - 0.98 * 0.97).abs() < 1e-12);
        assert_eq!(truck.driveline().loss_torque_nm(), 20.0);
        assert_eq!(*truck.body(), body());
        assert_eq!((truck.cda_m2(15.0), truck.driveline().has_loss_maps()), (6.0, (false, false)));

        let map: Rows = vec![(0.0, 0.0, 10.0), (3000.0, 0.0, 10.0), (0.0, 3000.0, 40.0), (3000.0, 3000.0, 40.0)];
        let mut with = parts();
        with.cda_curve = Some(vec![(0.0, 5.0), (20.0, 7.0)]);
        with.driveline.gear_loss_maps = Some(vec![map.clone(); 3]);
        with.driveline.axle_loss_map = Some(map);
        let truck = with.build().unwrap();
        assert_eq!((truck.cda_m2(15.0), truck.driveline().has_loss_maps()), (6.5, (true, true)));
    }

    /// A refused value is named, whichever part holds it.
    #[test]
    fn a_bad_value_is_named_by_its_part() {
        let mut idle = parts();
        idle.engine.idle_speed_rpm = 0.0;
        let mut radius = parts();
        radius.driveline.wheel_radius_m = -1.0;
        let mut mass = parts();
        mass.body.mass_kg = 0.0;
        let mut curve = parts();
        curve.cda_curve = Some(vec![(0.0, -1.0), (20.0, 7.0)]);
        for (bad, name) in
            [(idle, "idle_speed_rpm"), (radius, "wheel_radius_m"), (mass, "mass_kg"), (curve, "cda_curve")]
        {
            let CoreError::Invalid { key, .. } = bad.build().unwrap_err();
            assert_eq!(key, name);
        }
    }
}
