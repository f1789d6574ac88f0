//! Transition costs of one DP state towards one target gear: a "row" over the next stage's grid.
//!
//! The part of the stage cost (5.9) that depends only on the two speeds, the gear and the slope —
//! fuel (Q1), speed change (Q3) and brake (Q5) — is computed here; the speed deviation (Q2) and the
//! shift (Q4) terms depend on the state alone and are added by the solver. A row covers the
//! contiguous band of grid indices reached with a pedal level in [−ε, 1 + ε] (B.5 is affine in the
//! end speed), extended down to the brake points next to v_max; indices in between that no input
//! reaches hold +∞. Speeds of grid indices come from [`GridIndex`], so a row computed for an
//! absolute grid is the same whichever solve asks for it (what makes caching exact).

use super::params::{DpSettings, GridAnchor, StageModel};
use super::stage::{self, Branch};
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

/// The per-state constants of a row: both affine maps of (B.1) at v_i and the full-pedal fuel
/// (Euler: the whole stage's; trapezoid: the half at v_i), and with the trapezoid stage what the
/// maps at the end speed need.
#[derive(Debug, Clone, Copy)]
struct RowMaps<'a> {
    pedal: AffineAccel,
    brake: AffineAccel,
    full_fuel_g: f64,
    trapezoid: Option<EndMaps<'a>>,
}

/// What a trapezoid stage evaluates at its end speed (the vehicle, the gear and the slope), and the
/// pedal levels its row accepts ([`trapezoid_pedal_band`], a function of v_i alone).
#[derive(Debug, Clone, Copy)]
struct EndMaps<'a> {
    vehicle: &'a Vehicle,
    gear: usize,
    slope_torque: f64,
    pedal_band: (f64, f64),
}

fn maps<'a>(vehicle: &'a Vehicle, p: &DpSettings, v_i: f64, gear: usize, slope_torque: f64) -> RowMaps<'a> {
    let trapezoid = p.stage_model == StageModel::Trapezoid;
    let pedal = pedal_accel_on(vehicle, v_i, gear, slope_torque);
    RowMaps {
        pedal,
        brake: brake_accel_on(vehicle, v_i, gear, slope_torque),
        full_fuel_g: if trapezoid {
            stage::half_stage_fuel_g(vehicle, v_i, 1.0, gear, p.stage_m)
        } else {
            stage_fuel_g(vehicle, v_i, 1.0, gear, p.stage_m)
        },
        trapezoid: trapezoid.then(|| {
            let pedal_band = if pedal.gain > 0.0 { trapezoid_pedal_band(p, v_i, pedal.gain) } else { (0.0, 0.0) };
            EndMaps { vehicle, gear, slope_torque, pedal_band }
        }),
    }
}

/// [`pair`] on a trapezoid stage: the inputs from the maps at both ends, the fuel from the fuel
/// per metre at both ends.
#[inline]
fn pair_trapezoid(p: &DpSettings, m: &RowMaps, end: &EndMaps, v_i: f64, v_j: f64, v_max: f64) -> Option<(Inputs, f64)> {
    let h = p.stage_m;
    let change = change_cost(p.q_speed_change, p.q_speed_change_sq, v_i - v_j);
    let model = StageModel::Trapezoid;
    if m.pedal.gain > 0.0 {
        let at_j = pedal_accel_on(end.vehicle, v_j, end.gear, end.slope_torque);
        let pedal = stage::input_for(model, &m.pedal, &at_j, (v_i, v_j), h);
        let (pedal_lo, pedal_hi) = end.pedal_band;
        if pedal >= pedal_lo && pedal <= pedal_hi {
            let fuel_per_pedal = m.full_fuel_g + stage::half_stage_fuel_g(end.vehicle, v_j, 1.0, end.gear, h);
            let clipped = pedal.clamp(0.0, 1.0);
            return Some((Inputs { pedal: clipped, brake: 0.0 }, p.q_fuel * fuel_per_pedal * clipped + change));
        }
        if pedal > pedal_hi {
            return None;
        }
    }
    if (v_j - v_max).abs() < p.delta_mps() * BRAKE_WINDOW {
        let at_j = brake_accel_on(end.vehicle, v_j, end.gear, end.slope_torque);
        let brake = stage::input_for(model, &m.brake, &at_j, (v_i, v_j), h);
        if (0.0..=1.0).contains(&brake) {
            return Some((Inputs { pedal: 0.0, brake }, p.q_brake * brake + change));
        }
    }
    None
}

/// The pedal levels a trapezoid row accepts from `v_i`: never above full pedal (a level clipped to
/// full pedal would reach the grid point past the full-pedal end for nothing: a path pulsing
/// between full pedal and a glide gained half a grid step a stage), the full-pedal end being an
/// exact arc of the solver's instead; and from zero when fuel cut is an exact arc too (a level
/// below zero, clipped to zero, is fuel cut in the plant, whose engine drag brakes much harder
/// than the map at zero pedal the row assumed), else from −ε as the Euler rows.
/// On the moving grid, whose top bound is the continuous full-pedal speed, the top would be out of
/// reach at full pedal (its solves were infeasible, 58 in the first 10 km of VECTO 108 km): there
/// the band is the Euler rows' [−ε, 1 + ε].
#[inline]
fn trapezoid_pedal_band(p: &DpSettings, v_i: f64, gain: f64) -> (f64, f64) {
    let (lo, hi) = p.pedal_band(v_i, gain);
    match p.grid {
        GridAnchor::Fixed => (if p.fuel_cut_arcs { 0.0 } else { lo }, 1.0),
        GridAnchor::Moving => (lo, hi),
    }
}

/// [`forward_row`] on a trapezoid stage: the span from the end speeds of the pedal band's ends
/// (one index wider each way, the implicit step being solved to rounding), each cost from
/// [`pair_trapezoid`].
#[allow(clippy::too_many_arguments)]
fn forward_row_trapezoid(
    vehicle: &Vehicle,
    p: &DpSettings,
    v_i: f64,
    gear: usize,
    slope_torque: f64,
    grid: GridIndex,
    v_max: f64,
    out: &mut Vec<f64>,
) -> (RowSpan, usize) {
    let start = out.len();
    let m = maps(vehicle, p, v_i, gear, slope_torque);
    let end = m.trapezoid.expect("a trapezoid row");
    let h = p.stage_m;
    let (mut first, mut last) = (i64::MAX, i64::MIN);
    let pedal_on = m.pedal.gain > 0.0;
    let mut band_lo = f64::INFINITY;
    if pedal_on {
        let (pedal_lo, pedal_hi) = end.pedal_band;
        let at =
            |u: f64| stage::end_speed(StageModel::Trapezoid, vehicle, (v_i, h), gear, slope_torque, (Branch::Pedal, u));
        band_lo = at(pedal_lo);
        first = grid.ceil(band_lo) - 1;
        last = grid.floor(at(pedal_hi)) + 1;
    }
    if band_lo > v_max - p.delta_mps() {
        first = first.min(grid.floor(v_max - p.delta_mps()));
        last = last.max(grid.ceil(v_max + p.delta_mps()));
    }
    first = first.max(grid.ceil(0.0) + 1);
    if last < first {
        return (RowSpan { first: 0, len: 0 }, start);
    }
    out.extend((first..=last).map(|index| {
        pair_trapezoid(p, &m, &end, v_i, grid.speed(index), v_max).map_or(f64::INFINITY, |(_, cost)| cost)
    }));
    trim(out, start, first)
}

/// Trim a row's unreachable ends (appended to `out` from `start`, its first index `first`) so the
/// min-plus loop never scans them.
fn trim(out: &mut Vec<f64>, start: usize, first: i64) -> (RowSpan, usize) {
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

/// The cost of a speed change `dv` [m/s] over a stage: Q3·|Δv| plus, with the fuel_time cost,
/// the Euler stage's energy error priced in fuel ([`DpSettings::q_speed_change_sq`]).
#[inline]
pub fn change_cost(q_change: f64, q_change_sq: f64, dv: f64) -> f64 {
    q_change * dv.abs() + q_change_sq * (dv * dv)
}

/// Inputs and their stage cost (Q1·fuel + Q3·|Δv| (+ Euler correction) + Q5·B) for one pair,
/// None if inadmissible; `v_max` [m/s] is the top of the next stage's band.
#[inline]
fn pair(p: &DpSettings, m: &RowMaps, v_i: f64, v_j: f64, v_max: f64) -> Option<(Inputs, f64)> {
    if let Some(end) = &m.trapezoid {
        return pair_trapezoid(p, m, end, v_i, v_j, v_max);
    }
    let h = p.stage_m;
    let change = change_cost(p.q_speed_change, p.q_speed_change_sq, v_i - v_j);
    if m.pedal.gain > 0.0 {
        let pedal = m.pedal.input_for(v_i, v_j, h);
        let (pedal_lo, pedal_hi) = p.pedal_band(v_i, m.pedal.gain);
        if pedal >= pedal_lo && pedal <= pedal_hi {
            let clipped = pedal.clamp(0.0, 1.0);
            return Some((Inputs { pedal: clipped, brake: 0.0 }, p.q_fuel * m.full_fuel_g * clipped + change));
        }
        if pedal > pedal_hi {
            return None;
        }
    }
    // No pedal level reaches v_j because even fuel cut ends faster: brake, but only next to v_max
    // (strictly closer than δ; a grid point exactly δ away does not qualify, whatever the rounding).
    if (v_j - v_max).abs() < p.delta_mps() * BRAKE_WINDOW {
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
/// the row are hoisted out of the loop. `v_max_mps` is the top of the next stage's band.
#[allow(clippy::too_many_arguments)]
pub fn forward_row(
    vehicle: &Vehicle,
    p: &DpSettings,
    v_i: f64,
    gear: usize,
    slope_torque: f64,
    grid: GridIndex,
    v_max_mps: f64,
    out: &mut Vec<f64>,
) -> (RowSpan, usize) {
    if p.stage_model == StageModel::Trapezoid {
        return forward_row_trapezoid(vehicle, p, v_i, gear, slope_torque, grid, v_max_mps, out);
    }
    let start = out.len();
    let m = maps(vehicle, p, v_i, gear, slope_torque);
    let h = p.stage_m;
    let (mut first, mut last) = (i64::MAX, i64::MIN);
    let pedal_on = m.pedal.gain > 0.0;
    let (pedal_lo, pedal_hi) = p.pedal_band(v_i, m.pedal.gain);
    if pedal_on {
        first = grid.ceil(m.pedal.step(v_i, h, pedal_lo));
        last = grid.floor(m.pedal.step(v_i, h, pedal_hi));
    }
    // Brake points lie within δ of v_max and below the pedal band (`pair` decides which qualify);
    // only a band that starts above v_max − δ leaves room for them.
    let v_max = v_max_mps;
    let band_lo = if pedal_on { m.pedal.step(v_i, h, pedal_lo) } else { f64::INFINITY };
    if band_lo > v_max - p.delta_mps() {
        first = first.min(grid.floor(v_max - p.delta_mps()));
        last = last.max(grid.ceil(v_max + p.delta_mps()));
    }
    if last < first {
        return (RowSpan { first: 0, len: 0 }, start);
    }
    // The terms of `pair`, evaluated in the same order.
    let (q_change, q_change_sq, q_brake) = (p.q_speed_change, p.q_speed_change_sq, p.q_brake);
    let fuel_per_pedal = p.q_fuel * m.full_fuel_g;
    let window = p.delta_mps() * BRAKE_WINDOW;
    let (a_pedal, g_pedal) = (m.pedal.accel_at_zero, m.pedal.gain);
    let (a_brake, g_brake) = (m.brake.accel_at_zero, m.brake.gain);
    let cost = |index: i64| {
        let v_j = grid.speed(index);
        let change = change_cost(q_change, q_change_sq, v_i - v_j);
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
    };
    #[cfg(target_arch = "x86_64")]
    if pedal_on && std::arch::is_x86_feature_detected!("avx2") {
        let row =
            PedalRow { v_i, h, grid, q_change, q_change_sq, fuel_per_pedal, pedal_lo, pedal_hi, a_pedal, g_pedal };
        // SAFETY: the CPU has AVX2 (checked just above).
        unsafe { pedal_row_avx2(&row, first, last, out, cost) };
    } else {
        out.extend((first..=last).map(cost));
    }
    #[cfg(not(target_arch = "x86_64"))]
    out.extend((first..=last).map(cost));
    trim(out, start, first)
}

/// The constants of a row's pedal costs.
#[cfg(target_arch = "x86_64")]
struct PedalRow {
    v_i: f64,
    h: f64,
    grid: GridIndex,
    q_change: f64,
    q_change_sq: f64,
    fuel_per_pedal: f64,
    pedal_lo: f64,
    pedal_hi: f64,
    a_pedal: f64,
    g_pedal: f64,
}

/// Append the costs of indices `first..=last` four at a time in AVX2: the pedal branch of
/// [`forward_row`]'s `cost` with the same operations in the same order (grid speed, speed change,
/// demand, pedal, f64::clamp as two selects, cost); lanes whose pedal is below the band (or NaN),
/// which `cost` sends on to the brake test, are computed by `cost` itself.
///
/// # Safety
/// The CPU must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn pedal_row_avx2(row: &PedalRow, first: i64, last: i64, out: &mut Vec<f64>, cost: impl Fn(i64) -> f64) {
    use std::arch::x86_64::*;
    let n = (last - first + 1) as usize;
    // Room for whole groups of four; only the first n values are kept.
    out.reserve(n + 3);
    let at = out.len();
    let dst = out.spare_capacity_mut().as_mut_ptr().cast::<f64>();
    let splat = _mm256_set1_pd;
    let (v_i, h, origin, delta) = (splat(row.v_i), splat(row.h), splat(row.grid.origin_mps), splat(row.grid.delta_mps));
    let (q_change, q_change_sq, fuel_per_pedal) =
        (splat(row.q_change), splat(row.q_change_sq), splat(row.fuel_per_pedal));
    let (pedal_lo, pedal_hi, a_pedal, g_pedal) =
        (splat(row.pedal_lo), splat(row.pedal_hi), splat(row.a_pedal), splat(row.g_pedal));
    let (zero, one, inf, sign) = (splat(0.0), splat(1.0), splat(f64::INFINITY), splat(-0.0));
    let lanes = _mm256_setr_pd(0.0, 1.0, 2.0, 3.0);
    let mut t = 0;
    while t < n {
        let index = first + t as i64;
        // Exact: small integers.
        let v_j = _mm256_add_pd(origin, _mm256_mul_pd(_mm256_add_pd(splat(index as f64), lanes), delta));
        let dv = _mm256_sub_pd(v_i, v_j);
        let change = _mm256_add_pd(
            _mm256_mul_pd(q_change, _mm256_andnot_pd(sign, dv)),
            _mm256_mul_pd(q_change_sq, _mm256_mul_pd(dv, dv)),
        );
        let demand = _mm256_div_pd(_mm256_mul_pd(v_i, _mm256_sub_pd(v_j, v_i)), h);
        let pedal = _mm256_div_pd(_mm256_sub_pd(demand, a_pedal), g_pedal);
        let in_band =
            _mm256_and_pd(_mm256_cmp_pd::<_CMP_GE_OQ>(pedal, pedal_lo), _mm256_cmp_pd::<_CMP_LE_OQ>(pedal, pedal_hi));
        let above = _mm256_cmp_pd::<_CMP_GT_OQ>(pedal, pedal_hi);
        let clipped = _mm256_blendv_pd(
            _mm256_blendv_pd(pedal, zero, _mm256_cmp_pd::<_CMP_LT_OQ>(pedal, zero)),
            one,
            _mm256_cmp_pd::<_CMP_GT_OQ>(pedal, one),
        );
        let costs = _mm256_blendv_pd(inf, _mm256_add_pd(_mm256_mul_pd(fuel_per_pedal, clipped), change), in_band);
        // SAFETY: t + 3 < n + 3, within the capacity reserved above.
        _mm256_storeu_pd(dst.add(t), costs);
        let other = !_mm256_movemask_pd(_mm256_or_pd(in_band, above)) & 0b1111;
        if other != 0 {
            for l in 0..(n - t).min(4) {
                if other & (1 << l) != 0 {
                    *dst.add(t + l) = cost(index + l as i64);
                }
            }
        }
        t += 4;
    }
    // SAFETY: the first n values after `at` were written above.
    out.set_len(at + n);
}

/// The inputs of one admissible pair (the solver recomputes them for the path it keeps); `v_max`
/// [m/s] is the top of the next stage's band.
pub fn inputs(
    vehicle: &Vehicle,
    p: &DpSettings,
    (v_i, v_j, v_max): (f64, f64, f64),
    gear: usize,
    slope_torque: f64,
) -> Option<Inputs> {
    pair(p, &maps(vehicle, p, v_i, gear, slope_torque), v_i, v_j, v_max).map(|(inputs, _)| inputs)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vehicle::VehicleParams;

    /// Every cost of a row is `pair`'s, bit for bit (whichever path computed it), and the row is
    /// trimmed to its finite ends: over speeds, gears and slopes, with brake points next to v_max.
    #[test]
    fn rows_hold_the_costs_of_pair() {
        let thesis = DpSettings::thesis();
        rows_hold_the_costs_of_pair_in(&thesis);
        rows_hold_the_costs_of_pair_in(&DpSettings { stage_model: StageModel::Trapezoid, ..thesis });
        rows_hold_the_costs_of_pair_in(&DpSettings::default());
    }

    fn rows_hold_the_costs_of_pair_in(p: &DpSettings) {
        let vehicle = Vehicle::new(VehicleParams::default()).unwrap();
        let p = p.clone();
        let mut out = vec![1.0; 3];
        for (s, slope) in [-0.06, -0.03, -0.01, 0.0, 0.01, 0.03, 0.06].into_iter().enumerate() {
            let torque = vehicle.slope_torque_nm(slope);
            for gear in 1..=vehicle.forward_gears() {
                for step in 0..60 {
                    let v_i = p.v_max_mps() - 0.37 * step as f64 / 3.6;
                    let grid = GridIndex { origin_mps: 15.0 + 0.013 * s as f64, delta_mps: p.delta_mps() };
                    let before = out.len();
                    let (span, at) = forward_row(&vehicle, &p, v_i, gear, torque, grid, p.v_max_mps(), &mut out);
                    assert_eq!(out.len(), at + span.len);
                    assert!(at >= before);
                    let m = maps(&vehicle, &p, v_i, gear, torque);
                    let reference = |index: i64| {
                        pair(&p, &m, v_i, grid.speed(index), p.v_max_mps()).map_or(f64::INFINITY, |(_, c)| c)
                    };
                    for (t, &c) in out[at..].iter().enumerate() {
                        assert_eq!(c.to_bits(), reference(span.first + t as i64).to_bits(), "v {v_i} gear {gear}");
                    }
                    if span.len > 0 {
                        assert!(out[at].is_finite() && out[at + span.len - 1].is_finite());
                        // Just outside the span nothing is admissible.
                        assert!(
                            !reference(span.first - 1).is_finite()
                                && !reference(span.first + span.len as i64).is_finite()
                        );
                    }
                    out.truncate(3);
                }
            }
        }
    }

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
