//! VECTO's eco-roll: when the truck, rolling in gear at fuel cut, is on a gentle descent, it
//! declutches and rolls in neutral (idle fuel) until it falls below the set speed or brakes.
//!
//! Eco-roll's conditions, checked every plant step (VECTO's driver checks them every time step):
//! - the speed is at least `eco_roll_min_speed_kmh`, and at most the set speed plus the allowed
//!   overspeed less [`BELOW_OVERSPEED_KMH`];
//! - the road falls (slope below zero), and the truck in neutral would accelerate by between
//!   `eco_roll_accel_min_mps2` and `eco_roll_accel_max_mps2` (rolling, air and slope alone);
//! - in the previous step the pedal was idle (in gear at fuel cut) and the brake off.
//!
//! Once they have held for longer than `eco_roll_delay_s` eco-roll engages; it ends when the
//! speed falls below the set speed, or when the truck brakes.

/// How far below the overspeed limit [km/h] eco-roll may still engage (VECTO's fixed margin).
pub const BELOW_OVERSPEED_KMH: f64 = 2.0;

/// Eco-roll's state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EcoRoll {
    /// Rolling in gear (or driving).
    Off,
    /// The conditions hold since this time [s].
    Arming { since_s: f64 },
    /// Rolling in neutral.
    On,
}

/// What eco-roll looks at in one step.
#[derive(Debug, Clone, Copy)]
pub struct EcoRollInputs {
    /// Whether every engagement condition holds now.
    pub conditions_met: bool,
    /// Whether the speed is below the set speed.
    pub below_target: bool,
    /// Whether the truck braked in the previous step.
    pub braked: bool,
    /// The time now [s].
    pub t_s: f64,
}

impl EcoRoll {
    /// The state after one step with `inputs`, engaging after `delay_s` [s] of met conditions.
    pub fn next(self, inputs: &EcoRollInputs, delay_s: f64) -> EcoRoll {
        match self {
            EcoRoll::Off if inputs.conditions_met => EcoRoll::Arming { since_s: inputs.t_s },
            EcoRoll::Off => EcoRoll::Off,
            EcoRoll::Arming { .. } if !inputs.conditions_met => EcoRoll::Off,
            EcoRoll::Arming { since_s } if inputs.t_s - since_s > delay_s => EcoRoll::On,
            arming @ EcoRoll::Arming { .. } => arming,
            EcoRoll::On if inputs.below_target || inputs.braked => EcoRoll::Off,
            EcoRoll::On => EcoRoll::On,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inputs(conditions_met: bool, t_s: f64) -> EcoRollInputs {
        EcoRollInputs { conditions_met, below_target: false, braked: false, t_s }
    }

    /// Engages only after the conditions held for longer than the delay, without a break.
    #[test]
    fn engages_after_the_delay_of_met_conditions() {
        let mut state = EcoRoll::Off;
        for (met, t) in [(true, 0.0), (true, 1.0), (false, 1.5), (true, 2.0), (true, 4.0), (true, 4.05)] {
            state = state.next(&inputs(met, t), 2.0);
        }
        assert_eq!(state, EcoRoll::On);
        let early = [(true, 0.0), (true, 2.0)].iter().fold(EcoRoll::Off, |s, &(m, t)| s.next(&inputs(m, t), 2.0));
        assert_eq!(early, EcoRoll::Arming { since_s: 0.0 });
    }

    /// Once on, it ends below the set speed or on braking, whatever the conditions.
    #[test]
    fn ends_below_the_set_speed_or_on_braking() {
        let on = |below_target, braked| {
            EcoRoll::On.next(&EcoRollInputs { conditions_met: false, below_target, braked, t_s: 9.0 }, 2.0)
        };
        assert_eq!(on(false, false), EcoRoll::On);
        assert_eq!(on(true, false), EcoRoll::Off);
        assert_eq!(on(false, true), EcoRoll::Off);
    }
}
