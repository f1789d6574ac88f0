//! The whole map-based truck: the loads the road puts on it, and the engine's operating point
//! (speed, torque, fuel rate) that meets them in a gear.

use super::{Curve, Driveline, Engine, RPM_PER_RAD_S};
use crate::{CoreError, CoreResult};

/// Gravitational acceleration [m/s²], the standard value VECTO 3 uses (the thesis's model keeps its 9.81).
pub const G_MPS2: f64 = 9.80665;

/// The vehicle body: what the road, the air and the wheels' inertia see.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Body {
    /// Mass of the whole combination [kg]: vehicle, trailer, load.
    pub mass_kg: f64,
    /// Rotating inertia of all wheels [kg m²].
    pub wheels_inertia_kgm2: f64,
    /// Air drag area Cd·A [m²] (when no speed-dependent curve is given, see [`MapTruck::with_cda_curve`]).
    pub cda_m2: f64,
    /// Air density [kg/m³].
    pub air_density_kgpm3: f64,
    /// Rolling resistance coefficient of the combination [-].
    pub rolling_resistance: f64,
    /// Power of the auxiliaries (fan, steering pump, compressor, electrics, air conditioning) [W],
    /// taken from the engine whenever it runs.
    pub aux_power_w: f64,
}

/// The powers [W] the road asks of the wheels at a speed, acceleration and slope; positive where
/// they resist motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoadLoads {
    /// Air drag ½ρ·CdA(v)·v³.
    pub air_w: f64,
    /// Rolling resistance m·g·cos α·c_r·v.
    pub rolling_w: f64,
    /// Gravity along the slope m·g·sin α·v.
    pub slope_w: f64,
    /// Accelerating the mass m·a·v.
    pub vehicle_inertia_w: f64,
    /// Accelerating the wheels (I/r²)·a·v.
    pub wheels_inertia_w: f64,
}

impl RoadLoads {
    /// Power at the wheels [W]: the sum of the loads.
    pub fn wheel_w(&self) -> f64 {
        self.air_w + self.rolling_w + self.slope_w + self.vehicle_inertia_w + self.wheels_inertia_w
    }
}

/// The engine's operating point in a gear.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OperatingPoint {
    /// Engine speed [rpm].
    pub engine_speed_rpm: f64,
    /// Engine torque [Nm] the road asks for, including what the auxiliaries and the engine's own
    /// inertia take; below the drag torque the engine gives its drag torque and the brakes the rest.
    pub engine_torque_nm: f64,
    /// Fuel rate [g/h]; NaN at an engine speed the full-load curve does not cover.
    pub fuel_g_per_h: f64,
    /// Power the service brakes take at the wheels [W] where the engine's drag is not enough.
    pub brake_power_w: f64,
    /// Whether the engine can deliver the torque (at most its full-load torque) at a speed its
    /// full-load curve covers.
    pub feasible: bool,
}

/// A truck built from component data.
#[derive(Debug, Clone)]
pub struct MapTruck {
    engine: Engine,
    driveline: Driveline,
    body: Body,
    /// Cd·A [m²] over speed [m/s], when the drag area depends on speed (VECTO's cross-wind
    /// correction); `None`: the body's constant `cda_m2`.
    cda_curve: Option<Curve>,
}

impl MapTruck {
    /// A truck from its engine, driveline and body; the body's values are checked.
    pub fn new(engine: Engine, driveline: Driveline, body: Body) -> CoreResult<Self> {
        check_body(&body)?;
        Ok(MapTruck { engine, driveline, body, cda_curve: None })
    }

    /// The same truck with a drag area that depends on speed: `(speed [m/s], Cd·A [m²])` points,
    /// linear between them (the end segments continued).
    pub fn with_cda_curve(mut self, points: &[(f64, f64)]) -> CoreResult<Self> {
        Self::check_cda_points(points)?;
        self.cda_curve = Some(Curve::new("cda_curve", points)?);
        Ok(self)
    }

    /// Refuses a drag area below zero, naming `cda_curve`.
    pub(crate) fn check_cda_points(points: &[(f64, f64)]) -> CoreResult<()> {
        if let Some(&(v, cda)) = points.iter().find(|p| !(p.1 >= 0.0)) {
            return Err(CoreError::invalid("cda_curve", "Cd·A >= 0 at every speed").got(format!("{cda} m² at {v} m/s")));
        }
        Ok(())
    }

    /// The same truck at another total mass [kg] (a different load), checked as in [`MapTruck::new`].
    pub fn with_mass_kg(&self, mass_kg: f64) -> CoreResult<Self> {
        let body = Body { mass_kg, ..self.body };
        let truck = MapTruck::new(self.engine.clone(), self.driveline.clone(), body)?;
        Ok(MapTruck { cda_curve: self.cda_curve.clone(), ..truck })
    }

    /// The drag area Cd·A [m²] at `v_mps`.
    pub fn cda_m2(&self, v_mps: f64) -> f64 {
        self.cda_curve.as_ref().map_or(self.body.cda_m2, |c| c.at(v_mps))
    }

    /// The engine.
    pub fn engine(&self) -> &Engine {
        &self.engine
    }

    /// The driveline.
    pub fn driveline(&self) -> &Driveline {
        &self.driveline
    }

    /// The body.
    pub fn body(&self) -> &Body {
        &self.body
    }

    /// The road's loads at speed `v_mps`, acceleration `acc_mps2` and slope `slope_rad`.
    pub fn road_loads(&self, v_mps: f64, acc_mps2: f64, slope_rad: f64) -> RoadLoads {
        let b = &self.body;
        let r = self.driveline.wheel_radius_m();
        RoadLoads {
            air_w: 0.5 * b.air_density_kgpm3 * self.cda_m2(v_mps) * v_mps.powi(3),
            rolling_w: b.mass_kg * G_MPS2 * slope_rad.cos() * b.rolling_resistance * v_mps,
            slope_w: b.mass_kg * G_MPS2 * slope_rad.sin() * v_mps,
            vehicle_inertia_w: b.mass_kg * acc_mps2 * v_mps,
            wheels_inertia_w: b.wheels_inertia_kgm2 / (r * r) * acc_mps2 * v_mps,
        }
    }

    /// The engine's operating point meeting the road's loads in `gear` (1..=n) at `v_mps`,
    /// accelerating at `acc_mps2` on `slope_rad`: `None` unless the speed is positive and the
    /// inputs finite, or for a gear the truck does not have.
    pub fn operating_point(&self, v_mps: f64, acc_mps2: f64, slope_rad: f64, gear: usize) -> Option<OperatingPoint> {
        let inputs_ok = v_mps > 0.0 && v_mps.is_finite() && acc_mps2.is_finite() && slope_rad.is_finite();
        if !inputs_ok || gear == 0 || gear > self.driveline.gears() {
            return None;
        }
        let r = self.driveline.wheel_radius_m();
        let speed_rpm = self.driveline.engine_speed_rpm(v_mps, gear);
        let omega = speed_rpm / RPM_PER_RAD_S;
        let wheel_torque = self.road_loads(v_mps, acc_mps2, slope_rad).wheel_w() / v_mps * r;
        let engine_accel = acc_mps2 / r * self.driveline.ratio(gear);
        let extra = self.body.aux_power_w / omega + self.engine.inertia_kgm2() * engine_accel;
        let torque = self.driveline.engine_torque_nm(wheel_torque, gear, speed_rpm) + extra;
        let (lo, hi) = self.engine.speed_range_rpm();
        let in_range = speed_rpm >= lo && speed_rpm <= hi;
        let drag = self.engine.drag_torque_nm(speed_rpm);
        // Braking: the wheel torque the engine's drag holds, less what the road asks for.
        let brake_power_w = if torque < drag {
            (self.driveline.wheel_torque_nm(drag - extra, gear, speed_rpm) - wheel_torque) / r * v_mps
        } else {
            0.0
        };
        Some(OperatingPoint {
            engine_speed_rpm: speed_rpm,
            engine_torque_nm: torque,
            fuel_g_per_h: if in_range { self.engine.fuel_rate_g_per_h(speed_rpm, torque) } else { f64::NAN },
            brake_power_w,
            feasible: in_range && torque <= self.engine.max_torque_nm(speed_rpm),
        })
    }
}

/// Refuses a body value out of its range, naming its key.
pub(crate) fn check_body(body: &Body) -> CoreResult<()> {
    let checks = [
        ("mass_kg", body.mass_kg, body.mass_kg > 0.0, "a number > 0"),
        ("wheels_inertia_kgm2", body.wheels_inertia_kgm2, body.wheels_inertia_kgm2 >= 0.0, "a number >= 0"),
        ("cda_m2", body.cda_m2, body.cda_m2 >= 0.0, "a number >= 0"),
        ("air_density_kgpm3", body.air_density_kgpm3, body.air_density_kgpm3 > 0.0, "a number > 0"),
        ("rolling_resistance", body.rolling_resistance, body.rolling_resistance >= 0.0, "a number >= 0"),
        ("aux_power_w", body.aux_power_w, body.aux_power_w >= 0.0, "a number >= 0"),
    ];
    for (key, value, ok, expected) in checks {
        if !(value.is_finite() && ok) {
            return Err(CoreError::invalid(key, expected).got(value));
        }
    }
    Ok(())
}
