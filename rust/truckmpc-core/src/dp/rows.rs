//! Transition costs of one DP state towards one target gear: a "row" over the next stage's grid.
//!
//! The part of the stage cost (5.9) that depends only on the two speeds, the gear and the slope —
//! fuel (Q1), speed change (Q3) and brake (Q5) — is computed here; the speed deviation (Q2) and the
//! shift (Q4) terms depend on the state alone and are added by the solver. A row covers the
//! contiguous band of grid indices reached with a pedal level in [−ε, 1 + ε] (B.5 is affine in the
//! end speed), extended down to the brake points next to v_max; indices in between that no input
//! reaches hold +∞. Speeds of grid indices come from [`GridIndex`], so a row computed for an
//! absolute grid is the same whichever solve asks for it (what makes caching exact).

use super::params::DpSettings;
use crate::levels::{brake_accel_on, pedal_accel_on, stage_fuel_g, AffineAccel};
use crate::vehicle::Vehicle;

/// Speed of a grid index: v = origin + index·δ [m/s]. A moving grid has its origin at the stage's
/// lower bound; a fixed grid has origin 0, so an index names the same speed at every stage.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridIndex {
    /// Speed of index 0 [m/s].
    pub origin_mps: f64,
    /// Grid step δ [m/s].
    pub delta_mps: f64,
}

impl GridIndex {
    /// Speed of `index` [m/s].
    #[inline]
    pub fn speed(&self, index: i64) -> f64 {
        self.origin_mps + index as f64 * self.delta_mps
    }

    /// Smallest index whose speed is at least `v_mps` (to rounding).
    #[inline]
    pub fn ceil(&self, v_mps: f64) -> i64 {
        ceil_i64((v_mps - self.origin_mps) / self.delta_mps - 1e-9)
    }

    /// Largest index whose speed is at most `v_mps` (to rounding).
    #[inline]
    pub fn floor(&self, v_mps: f64) -> i64 {
        floor_i64((v_mps - self.origin_mps) / self.delta_mps + 1e-9)
    }
}

/// `x.ceil() as i64` without the libm call that `ceil` is on x86-64 without SSE4.1: truncate, and
/// step up where that lost a positive fraction. The same integer for every x (saturating at the
/// ends of i64, 0 for NaN, as `as` does).
#[inline]
pub fn ceil_i64(x: f64) -> i64 {
    let t = x as i64;
    if (t as f64) < x {
        t.saturating_add(1)
    } else {
        t
    }
}

/// `x.floor() as i64` without the libm call, as [`ceil_i64`].
#[inline]
pub fn floor_i64(x: f64) -> i64 {
    let t = x as i64;
    if (t as f64) > x {
        t.saturating_sub(1)
    } else {
        t
    }
}

/// |v_j − v_max| must be below δ times this for a brake transition (5.4.3).
pub const BRAKE_WINDOW: f64 = 1.0 - 1e-9;

/// Where a row's costs start on the next grid, and how many there are.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RowSpan {
    /// Grid index of the first cost.
    pub first: i64,
    /// Number of costs (0: no admissible target).
    pub len: usize,
}

/// The inputs joining v_i to v_j in forward gear g: the pedal when some P ∈ [−ε, 1 + ε] does
/// (clipped to [0, 1]), else the brake at fuel cut when v_j is next to v_max and B ∈ [0, 1].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inputs {
    pub pedal: f64,
    pub brake: f64,
}

/// The per-state constants of a row: both affine maps of (B.1) at v_i and the full-pedal fuel.
#[derive(Debug, Clone, Copy)]
struct RowMaps {
    pedal: AffineAccel,
    brake: AffineAccel,
    full_fuel_g: f64,
}

fn maps(vehicle: &Vehicle, p: &DpSettings, v_i: f64, gear: usize, slope_torque: f64) -> RowMaps {
    RowMaps {
        pedal: pedal_accel_on(vehicle, v_i, gear, slope_torque),
        brake: brake_accel_on(vehicle, v_i, gear, slope_torque),
        full_fuel_g: stage_fuel_g(vehicle, v_i, 1.0, gear, p.stage_m),
    }
}

/// Inputs and their stage cost (Q1·fuel + Q3·|Δv| + Q5·B) for one pair, None if inadmissible.
#[inline]
fn pair(p: &DpSettings, m: &RowMaps, v_i: f64, v_j: f64) -> Option<(Inputs, f64)> {
    let h = p.stage_m;
    let change = p.q_speed_change * (v_i - v_j).abs();
    if m.pedal.gain > 0.0 {
        let pedal = m.pedal.input_for(v_i, v_j, h);
        if pedal >= -p.epsilon && pedal <= 1.0 + p.epsilon {
            let clipped = pedal.clamp(0.0, 1.0);
            return Some((Inputs { pedal: clipped, brake: 0.0 }, p.q_fuel * m.full_fuel_g * clipped + change));
        }
        if pedal > 1.0 + p.epsilon {
            return None;
        }
    }
    // No pedal level reaches v_j because even fuel cut ends faster: brake, but only next to v_max
    // (strictly closer than δ; a grid point exactly δ away does not qualify, whatever the rounding).
    if (v_j - p.v_max_mps()).abs() < p.delta_mps() * BRAKE_WINDOW {
        let brake = m.brake.input_for(v_i, v_j, h);
        if (0.0..=1.0).contains(&brake) {
            return Some((Inputs { pedal: 0.0, brake }, p.q_brake * brake + change));
        }
    }
    None
}

/// Append to `out` the costs of joining `v_i` in forward `gear` to the grid indices of the next
/// stage; return their span and where its first cost is in `out`. Indices no input reaches inside
/// the span hold +∞; a row with no admissible target appends nothing (len 0).
///
/// Each cost is computed by the same operations as [`pair`] (same bits); only the constants of
/// the row are hoisted out of the loop.
pub fn forward_row(
    vehicle: &Vehicle,
    p: &DpSettings,
    v_i: f64,
    gear: usize,
    slope_torque: f64,
    grid: GridIndex,
    out: &mut Vec<f64>,
) -> (RowSpan, usize) {
    let start = out.len();
    let m = maps(vehicle, p, v_i, gear, slope_torque);
    let h = p.stage_m;
    let (mut first, mut last) = (i64::MAX, i64::MIN);
    let pedal_on = m.pedal.gain > 0.0;
    if pedal_on {
        first = grid.ceil(m.pedal.step(v_i, h, -p.epsilon));
        last = grid.floor(m.pedal.step(v_i, h, 1.0 + p.epsilon));
    }
    // Brake points lie within δ of v_max and below the pedal band (`pair` decides which qualify);
    // only a band that starts above v_max − δ leaves room for them.
    let v_max = p.v_max_mps();
    let band_lo = if pedal_on { m.pedal.step(v_i, h, -p.epsilon) } else { f64::INFINITY };
    if band_lo > v_max - p.delta_mps() {
        first = first.min(grid.floor(v_max - p.delta_mps()));
        last = last.max(grid.ceil(v_max + p.delta_mps()));
    }
    if last < first {
        return (RowSpan { first: 0, len: 0 }, start);
    }
    // The terms of `pair`, evaluated in the same order.
    let (q_change, q_brake) = (p.q_speed_change, p.q_brake);
    let fuel_per_pedal = p.q_fuel * m.full_fuel_g;
    let (pedal_lo, pedal_hi) = (-p.epsilon, 1.0 + p.epsilon);
    let window = p.delta_mps() * BRAKE_WINDOW;
    let (a_pedal, g_pedal) = (m.pedal.accel_at_zero, m.pedal.gain);
    let (a_brake, g_brake) = (m.brake.accel_at_zero, m.brake.gain);
    out.extend((first..=last).map(|index| {
        let v_j = grid.speed(index);
        let change = q_change * (v_i - v_j).abs();
        let demand = v_i * (v_j - v_i) / h;
        if pedal_on {
            let pedal = (demand - a_pedal) / g_pedal;
            if pedal >= pedal_lo && pedal <= pedal_hi {
                return fuel_per_pedal * pedal.clamp(0.0, 1.0) + change;
            }
            if pedal > pedal_hi {
                return f64::INFINITY;
            }
        }
        if (v_j - v_max).abs() < window {
            let brake = (demand - a_brake) / g_brake;
            if (0.0..=1.0).contains(&brake) {
                return q_brake * brake + change;
            }
        }
        f64::INFINITY
    }));
    // Trim unreachable ends so the min-plus loop never scans them.
    let row = &out[start..];
    let Some(lead) = row.iter().position(|c| c.is_finite()) else {
        out.truncate(start);
        return (RowSpan { first: 0, len: 0 }, start);
    };
    let trail = row.iter().rev().take_while(|c| !c.is_finite()).count();
    let len = row.len() - lead - trail;
    out.truncate(start + lead + len);
    (RowSpan { first: first + lead as i64, len }, start + lead)
}

/// The inputs of one admissible pair (the solver recomputes them for the path it keeps).
pub fn inputs(vehicle: &Vehicle, p: &DpSettings, v_i: f64, v_j: f64, gear: usize, slope_torque: f64) -> Option<Inputs> {
    pair(p, &maps(vehicle, p, v_i, gear, slope_torque), v_i, v_j).map(|(inputs, _)| inputs)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integer_ceil_and_floor_equal_the_libm_ones() {
        let mut values = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            1e-300,
            -1e-300,
            2.5,
            -2.5,
            4503599627370495.5,
            -4503599627370495.5,
            9007199254740993.0,
            9.3e18,
            -9.3e18,
            9_223_372_036_854_775_808.0, // 2^63
            -9_223_372_036_854_775_808.0,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            f64::MAX,
            f64::MIN,
        ];
        let mut seed = 11u64;
        for _ in 0..100_000 {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let x = f64::from_bits(seed);
            values.push(x);
            values.push((seed >> 11) as f64 * 1e-6 - 4e6);
        }
        for x in values {
            assert_eq!(ceil_i64(x), x.ceil() as i64, "ceil {x:e}");
            assert_eq!(floor_i64(x), x.floor() as i64, "floor {x:e}");
        }
    }
}
