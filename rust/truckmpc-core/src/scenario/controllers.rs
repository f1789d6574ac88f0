//! The built-in controllers by name: one registry, which the closed loop, the binding and the
//! command line read.

use std::sync::Arc;

use crate::control::{Controller, GearLogic, PccController, PiController, RecedingController, VectoDriver};
use crate::dp::DpSettings;
use crate::error::{CoreError, CoreResult};
use crate::params::RunSettings;
use crate::vehicle::Vehicle;

/// A built-in controller: its name, what it is, and whether it solves the DP.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ControllerKind {
    /// The name a user selects it by (`"mpc"`).
    pub name: &'static str,
    /// One line saying what it is.
    pub doc: &'static str,
    /// Whether it plans with the DP (its summary then carries the DP's settings and solves).
    pub solves_dp: bool,
}

/// Every built-in controller, in the order outputs list them.
pub const CONTROLLERS: [ControllerKind; 5] = [
    ControllerKind { name: "pi", doc: "the thesis's PI cruise control (section 2.5)", solves_dp: false },
    ControllerKind {
        name: "vecto_cc",
        doc: "VECTO's cruise driver, a truck without predictive cruise control",
        solves_dp: false,
    },
    ControllerKind {
        name: "pcc",
        doc: "VECTO's rule-based predictive cruise control with eco-roll, acting through its cruise driver",
        solves_dp: false,
    },
    ControllerKind {
        name: "mpc",
        doc: "the look-ahead controller: the DP over the next horizon, solved again as the truck drives",
        solves_dp: true,
    },
    ControllerKind {
        name: "optimal",
        doc: "the whole-road optimum: the same DP solved once over the entire road, driven against its cost-to-go",
        solves_dp: true,
    },
];

/// The built-in controller named `name`; the error names `controller` and lists the names.
pub fn kind(name: &str) -> CoreResult<&'static ControllerKind> {
    CONTROLLERS.iter().find(|k| k.name == name).ok_or_else(|| {
        let names: Vec<String> = CONTROLLERS.iter().map(|k| format!("'{}'", k.name)).collect();
        CoreError::invalid("controller", format!("one of {}", names.join(", "))).got(format!("'{name}'"))
    })
}

/// A new controller `name` modelling `vehicle`, set up from `settings`.
pub fn build(name: &str, vehicle: &Arc<Vehicle>, settings: &RunSettings) -> CoreResult<Box<dyn Controller + Send>> {
    let s = settings;
    let vehicle = vehicle.clone();
    Ok(match kind(name)?.name {
        "pi" => Box::new(PiController::new(vehicle, &s.pi, &s.cruise)?),
        "vecto_cc" => Box::new(VectoDriver::new(vehicle, &s.pi, &s.cruise, &s.pcc, s.sim.plant_dt_s)?),
        "pcc" => Box::new(PccController::new(vehicle, &s.pi, &s.cruise, &s.pcc, s.sim.plant_dt_s)?),
        whole => {
            let gears = GearLogic::new(&vehicle, &s.pi)?;
            let dp = DpSettings::new(&s.mpc, &s.cruise)?;
            if whole == "optimal" {
                Box::new(RecedingController::whole_road(vehicle, dp, gears))
            } else {
                Box::new(RecedingController::new(vehicle, dp, gears))
            }
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_registered_controller_is_built_under_its_own_name() {
        let settings = RunSettings::default();
        let vehicle = Arc::new(Vehicle::new(settings.vehicle.clone()).unwrap());
        for kind in CONTROLLERS {
            assert_eq!(build(kind.name, &vehicle, &settings).unwrap().name(), kind.name);
        }
        let err = build("cruise", &vehicle, &settings).err().unwrap();
        assert_eq!(
            err.to_string(),
            "controller: expected one of 'pi', 'vecto_cc', 'pcc', 'mpc', 'optimal', got 'cruise'"
        );
    }
}
