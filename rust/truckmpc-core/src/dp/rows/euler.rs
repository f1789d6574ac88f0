//! Rows of the explicit Euler stage (B.5): the pedal level joining two speeds is affine in the
//! end speed [m/s], so a row is the band of grid indices whose pedal is in [−ε, 1 + ε], plus the
//! brake points next to v_max; costs in the units of (5.9). On x86-64 with AVX2 the pedal costs
//! are computed four at a time, with the same operations.

use super::{change_cost, clamp_span, maps, trim, GridIndex, Inputs, RowMaps, RowSpan, BRAKE_WINDOW};
use crate::dp::params::{DpSettings, StageModel};
use crate::dp::stage;
use crate::powertrain::Powertrain;
use crate::vehicle::Vehicle;

/// [`pair`](super::pair) on an Euler stage: the inputs from the affine maps at v_i, the fuel from
/// the full-pedal fuel of the stage.
#[inline]
pub(super) fn pair_euler(p: &DpSettings, m: &RowMaps, v_i: f64, v_j: f64, v_max: f64) -> Option<(Inputs, f64)> {
    let h = p.mpc.stage_m;
    let change = change_cost(p.mpc.q_speed_change, p.q_speed_change_sq, v_i - v_j);
    if m.pedal.gain > 0.0 {
        let pedal = m.pedal.input_for(v_i, v_j, h);
        let (pedal_lo, pedal_hi) = p.pedal_band(v_i, m.pedal.gain);
        if pedal >= pedal_lo && pedal <= pedal_hi {
            let clipped = pedal.clamp(0.0, 1.0);
            let fuel = match m.map_fuel {
                None => p.mpc.q_fuel * m.full_fuel_g * clipped,
                Some(_) => p.mpc.q_fuel * m.euler_fuel_g(v_i, clipped, h),
            };
            return Some((Inputs { pedal: clipped, brake: 0.0 }, fuel + change));
        }
        if pedal > pedal_hi {
            return None;
        }
    }
    // No pedal level reaches v_j because even fuel cut ends faster: brake, but only next to v_max
    // (strictly closer than δ; a grid point exactly δ away does not qualify, whatever the rounding).
    if (v_j - v_max).abs() < p.delta_mps() * BRAKE_WINDOW {
        let brake = m.brake.expect("an Euler row's brake map").input_for(v_i, v_j, h);
        if (0.0..=1.0).contains(&brake) {
            return Some((
                Inputs { pedal: 0.0, brake },
                p.q_brake * brake + change + brake_cost(p, m, (v_i, v_j), brake),
            ));
        }
    }
    None
}

/// Q1 times the energy of an Euler braking stage for a truck whose braking draws energy (zero,
/// and no evaluation, for the others).
#[inline]
fn brake_cost(p: &DpSettings, m: &RowMaps, (v_i, v_j): (f64, f64), brake: f64) -> f64 {
    match m.map_fuel {
        Some((vehicle, gear)) if vehicle.brake_draws_energy() => {
            p.mpc.q_fuel * stage::brake_energy(StageModel::Euler, vehicle, (v_i, v_j), brake, gear, p.mpc.stage_m)
        }
        _ => 0.0,
    }
}

/// [`forward_row`](super::forward_row) on an Euler stage: the span from the end speeds of the pedal
/// band's ends, widened to the brake points next to v_max.
///
/// Each cost is computed by the same operations as [`pair`](super::pair) (same bits); only the
/// constants of the row are hoisted out of the loop. `v_max_mps` is the top of the next stage's
/// band.
pub(super) fn forward_row_euler(
    (vehicle, p): (&Vehicle, &DpSettings),
    (v_i, gear, slope_torque): (f64, usize, f64),
    (grid, v_max_mps): (GridIndex, f64),
    out: &mut Vec<f64>,
) -> (RowSpan, usize) {
    let start = out.len();
    let m = maps(vehicle, p, v_i, gear, slope_torque);
    let h = p.mpc.stage_m;
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
    // No target beyond the next stage's band (a vehicle with a huge pedal gain would otherwise ask
    // for a row of billions of grid points) nor at or below standstill.
    (first, last) = clamp_span((first, last), grid, v_max, p.delta_mps());
    if last < first {
        return (RowSpan { first: 0, len: 0 }, start);
    }
    // The terms of `pair`, evaluated in the same order.
    let (q_change, q_change_sq, q_brake) = (p.mpc.q_speed_change, p.q_speed_change_sq, p.q_brake);
    let fuel_per_pedal = p.mpc.q_fuel * m.full_fuel_g;
    let window = p.delta_mps() * BRAKE_WINDOW;
    let (a_pedal, g_pedal) = (m.pedal.accel_at_zero, m.pedal.gain);
    let brake = m.brake.expect("an Euler row's brake map");
    let (a_brake, g_brake) = (brake.accel_at_zero, brake.gain);
    let cost = |index: i64| {
        let v_j = grid.speed(index);
        let change = change_cost(q_change, q_change_sq, v_i - v_j);
        let demand = v_i * (v_j - v_i) / h;
        if pedal_on {
            let pedal = (demand - a_pedal) / g_pedal;
            if pedal >= pedal_lo && pedal <= pedal_hi {
                if m.map_fuel.is_some() {
                    return p.mpc.q_fuel * m.euler_fuel_g(v_i, pedal.clamp(0.0, 1.0), h) + change;
                }
                return fuel_per_pedal * pedal.clamp(0.0, 1.0) + change;
            }
            if pedal > pedal_hi {
                return f64::INFINITY;
            }
        }
        if (v_j - v_max).abs() < window {
            let brake = (demand - a_brake) / g_brake;
            if (0.0..=1.0).contains(&brake) {
                return q_brake * brake + change + brake_cost(p, &m, (v_i, v_j), brake);
            }
        }
        f64::INFINITY
    };
    #[cfg(target_arch = "x86_64")]
    if pedal_on && m.map_fuel.is_none() && std::arch::is_x86_feature_detected!("avx2") {
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
/// [`forward_row`](super::forward_row)'s `cost` with the same operations in the same order (grid
/// speed, speed change, demand, pedal, f64::clamp as two selects, cost); lanes whose pedal is below
/// the band (or NaN), which `cost` sends on to the brake test, are computed by `cost` itself.
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
