//! The stretches where VECTO's PCC may act (VECTO's PCC segment preprocessing), found once per run.
//!
//! A segment opens at the first road segment steeper downhill than the grade α* on which the truck,
//! coasting at the set speed (in neutral with eco-roll, else in gear at fuel cut), would keep
//! accelerating: its `x_low_m`, where the speed should be lowest. It closes at the first road
//! segment less steep than α* again: its `end_m`, by when the truck should be back at the set
//! speed. It starts `preview` before `x_low_m`, but not before the last change of set speed. Only
//! stretches of one set speed at least the enabling speed count; a descent still open at the
//! road's end makes no segment (VECTO closes a segment only where the road flattens).

use crate::road::Road;

/// One PCC segment: distances [m], its set speed [m/s] and the specific energies [J/kg] the use
/// cases aim at (g·h + v²/2: the mass cancels).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PccSegment {
    /// Where use case 1 may start.
    pub start_m: f64,
    /// Where the speed should be lowest: the descent's start.
    pub x_low_m: f64,
    /// Where the descent ends.
    pub end_m: f64,
    /// The set speed over the segment [m/s].
    pub target_mps: f64,
    /// g·h + (target − underspeed)²/2 at `x_low_m` [J/kg].
    pub energy_low: f64,
    /// g·h + target²/2 at `end_m` [J/kg].
    pub energy_end: f64,
}

/// What the preprocessing needs besides the road.
pub struct SegmentRules<'a> {
    /// The set speed [m/s] of the stretch at a distance [m].
    pub target_at: &'a dyn Fn(f64) -> f64,
    /// α*: the grade [-] at which coasting at a set speed [m/s] holds it.
    pub coasting_grade: &'a dyn Fn(f64) -> f64,
    /// PCC acts only where the set speed is at least this [m/s].
    pub enabling_mps: f64,
    /// Use case 1's preview [m].
    pub preview_m: f64,
    /// Allowed underspeed [m/s].
    pub underspeed_mps: f64,
    /// Gravity [m/s²].
    pub gravity_mps2: f64,
}

/// The PCC segments of `road`, in order.
pub fn pcc_segments(road: &Road, rules: &SegmentRules<'_>) -> Vec<PccSegment> {
    let (x, slopes) = (road.distance_m(), road.slopes());
    let energy = |s_m: f64, v_mps: f64| rules.gravity_mps2 * road.altitude_at(s_m) + 0.5 * v_mps * v_mps;
    let mut out = Vec::new();
    let mut open: Option<PccSegment> = None;
    let mut target_changed_m = 0.0;
    let mut grade = (f64::NAN, f64::NAN);
    for (i, &slope) in slopes.iter().enumerate() {
        let (x0, x1) = (x[i], x[i + 1]);
        let target = (rules.target_at)(x0);
        if target < rules.enabling_mps || target != (rules.target_at)(x1) {
            target_changed_m = x1;
            open = None;
            continue;
        }
        if open.is_some_and(|o| o.target_mps != target) {
            open = None;
            continue;
        }
        if grade.0 != target {
            grade = (target, (rules.coasting_grade)(target));
        }
        if open.is_none() && slope < grade.1 {
            let low = target - rules.underspeed_mps;
            open = Some(PccSegment {
                start_m: x0 - (x0 - target_changed_m - 1.0).min(rules.preview_m),
                x_low_m: x0,
                end_m: f64::INFINITY,
                target_mps: target,
                energy_low: energy(x0, low),
                energy_end: f64::NAN,
            });
        }
        if let Some(segment) = open.filter(|_| slope > grade.1) {
            out.push(PccSegment { end_m: x0, energy_end: energy(x0, target), ..segment });
            open = None;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rules<'a>(target: &'a dyn Fn(f64) -> f64, grade: &'a dyn Fn(f64) -> f64) -> SegmentRules<'a> {
        SegmentRules {
            target_at: target,
            coasting_grade: grade,
            enabling_mps: 80.0 / 3.6,
            preview_m: 1500.0,
            underspeed_mps: 8.0 / 3.6,
            gravity_mps2: 9.81,
        }
    }

    /// Segments span the runs of segments steeper than α*, from the preview before them (not
    /// before the road's start) to where the road flattens; one still open at the road's end is
    /// dropped, as VECTO closes a segment only where the road flattens.
    #[test]
    fn segments_span_steep_runs_and_need_an_end() {
        let x = vec![0.0, 1000.0, 2000.0, 3000.0, 5000.0, 6000.0, 7000.0];
        let slopes = vec![0.0, -0.02, -0.03, 0.0, 0.0, -0.02];
        let road = Road::new(x, slopes).unwrap();
        let v85 = |_: f64| 85.0 / 3.6;
        let grade = |_: f64| -0.0125;
        let found = pcc_segments(&road, &rules(&v85, &grade));
        assert_eq!(found.len(), 1, "{found:?}");
        let s = found[0];
        assert_eq!((s.start_m, s.x_low_m, s.end_m), (1.0, 1000.0, 3000.0));
        let h_end = road.altitude_at(3000.0);
        assert!((s.energy_end - (9.81 * h_end + 0.5 * (85.0f64 / 3.6).powi(2))).abs() < 1e-9);
        let low = (85.0 - 8.0) / 3.6;
        assert!((s.energy_low - (9.81 * road.altitude_at(1000.0) + 0.5 * low * low)).abs() < 1e-9);
    }

    /// Below the enabling speed, or across a change of set speed, no segment opens.
    #[test]
    fn segments_need_one_set_speed_above_the_enabling_speed() {
        let road = Road::new(vec![0.0, 2000.0, 3000.0, 4000.0], vec![0.0, -0.03, 0.0]).unwrap();
        let grade = |_: f64| -0.0125;
        let v70 = |_: f64| 70.0 / 3.6;
        assert!(pcc_segments(&road, &rules(&v70, &grade)).is_empty());
        let drop = |s: f64| if s < 3000.0 { 85.0 / 3.6 } else { 82.0 / 3.6 };
        assert!(pcc_segments(&road, &rules(&drop, &grade)).is_empty());
        let v85 = |_: f64| 85.0 / 3.6;
        let found = pcc_segments(&road, &rules(&v85, &grade));
        assert_eq!(found.len(), 1);
        assert_eq!(found[0].start_m, 500.0);
    }
}
