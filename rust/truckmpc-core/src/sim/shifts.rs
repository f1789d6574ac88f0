//! Gear shifts and neutral engagements, counted apart from the gears a run applies in order.
//!
//! A shift is a change between forward gears. A stretch in neutral (eco-roll, coasting declutched)
//! is bridged: the gear engaged after it against the gear before it counts one shift if they
//! differ and none if they are equal, so declutching and re-engaging the same gear is one neutral
//! engagement and no shift. The first gear applied is where the count starts: it is neither.

use crate::vehicle::NEUTRAL;

/// The running counts of a run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct GearCounts {
    /// Changes between forward gears (across stretches in neutral).
    pub gear_shifts: u64,
    /// Entries into neutral from a forward gear.
    pub neutral_engagements: u64,
    /// The gear applied last, if any.
    last: Option<usize>,
    /// The forward gear engaged last, if any.
    last_forward: Option<usize>,
}

impl GearCounts {
    /// Note the gear of the next decision applied (0 = neutral).
    pub fn apply(&mut self, gear: usize) {
        if gear == NEUTRAL {
            if self.last.is_some_and(|g| g != NEUTRAL) {
                self.neutral_engagements += 1;
            }
        } else {
            if self.last_forward.is_some_and(|g| g != gear) {
                self.gear_shifts += 1;
            }
            self.last_forward = Some(gear);
        }
        self.last = Some(gear);
    }
}

/// `count` per 100 km of `distance_m`; None when the truck did not move.
pub fn per_100km(count: u64, distance_m: f64) -> Option<f64> {
    (distance_m > 0.0).then(|| count as f64 / (distance_m / 1e5))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn counts(gears: &[usize]) -> (u64, u64) {
        let mut c = GearCounts::default();
        gears.iter().for_each(|&g| c.apply(g));
        (c.gear_shifts, c.neutral_engagements)
    }

    #[test]
    fn shifts_between_forward_gears_count_once_each() {
        assert_eq!(counts(&[]), (0, 0));
        assert_eq!(counts(&[12, 12, 12]), (0, 0));
        assert_eq!(counts(&[10, 11, 12, 11]), (3, 0));
    }

    #[test]
    fn a_stretch_in_neutral_is_one_engagement_and_bridged_for_shifts() {
        // Eco-roll in 12 and back into 12: no shift. Out of 12, back in 11: one shift.
        assert_eq!(counts(&[12, 0, 0, 0, 12]), (0, 1));
        assert_eq!(counts(&[12, 0, 11]), (1, 1));
        // Three eco-rolls, the last ending a gear lower, then a shift up.
        assert_eq!(counts(&[12, 0, 12, 12, 0, 0, 12, 0, 11, 12]), (2, 3));
        // Ending in neutral still counts the engagement.
        assert_eq!(counts(&[11, 12, 0]), (1, 1));
    }

    #[test]
    fn a_run_starting_in_neutral_counts_from_its_first_gear() {
        assert_eq!(counts(&[0, 0, 12]), (0, 0));
        assert_eq!(counts(&[0, 12, 0, 11]), (1, 1));
    }

    #[test]
    fn per_100km_scales_by_distance() {
        assert_eq!(per_100km(30, 150_000.0), Some(20.0));
        assert_eq!(per_100km(3, 0.0), None);
    }
}
