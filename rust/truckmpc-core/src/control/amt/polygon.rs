//! VECTO's declaration-mode shift lines of a gearbox with a clutch (AMT and manual), computed from
//! the engine's full-load curve, its idle speed and the gear ratios as VECTO's
//! `DeclarationData.Gearbox.ComputeManualTransmissionShiftPolygon` computes them, and the tests
//! of an operating point against them (`ShiftPolygon.IsBelowDownshiftCurve` and its siblings).
//!
//! Points are (engine speed [rad/s], torque at the gearbox input [Nm]), in VECTO's units, so its
//! tolerances carry over. The corner points, named as VECTO names them:
//! - P1 (idle/2, 0), P2 (1.1·idle, 0), P3 (0.9·n_vhigh, full load there), where n_vhigh is the
//!   lower of the rated speed and the engine speed at 85 km/h in the top gear;
//! - P4 (n_vhigh·(1 + r/3), 0), with r the top two gears' step less one; P5 (n95h, the highest
//!   full-load torque), n95h the highest speed giving 95 % of the rated power;
//! - P6 on P1–P3 at P2's speed, P7 on P2–P5 at P4's speed.
//!
//! The downshift line (not in gear 1) runs from the drag torque ×1.1 at P2's speed to P6–P3,
//! moved down in parallel until it stays below 98 % of the full-load curve, up to 1.1 × the highest
//! full-load torque. The upshift line (not in the top gear) is the lower of P4–P7–P5 and the next
//! gear's downshift line P2–P6–P3 seen in this gear (speeds times the step and 1.07, torques over
//! the step), sweeping down from the highest speed to the first point at zero torque.

use super::geometry::{intersect, Pt};

/// VECTO's `TruckMaxAllowedSpeed`: the top gear's engine speed at 85 km/h bounds the shift lines.
const TRUCK_MAX_SPEED_MPS: f64 = 85.0 / 3.6;
/// VECTO's `ShiftPolygonRPMMargin`: the next gear's downshift line is moved 7 % up in speed.
const RPM_MARGIN: f64 = 1.07;
/// VECTO's `ShiftPolygonEngineFldMargin`: the downshift line stays below 98 % of full load.
const FLD_MARGIN: f64 = 0.98;
/// Tolerance of VECTO's `IsEqual` on doubles.
const TOLERANCE: f64 = 1e-6;

/// What the shift lines are computed from.
#[derive(Debug, Clone)]
pub struct ShiftLineInputs {
    /// Full-load curve: (engine speed [rad/s], full-load torque [Nm]), speeds increasing.
    pub full_load: Vec<(f64, f64)>,
    /// The most negative drag torque of the engine [Nm].
    pub min_drag_nm: f64,
    /// Idle speed [rad/s].
    pub idle_rad_s: f64,
    /// Gear ratios, first gear first.
    pub gear_ratios: Vec<f64>,
    /// Axle ratio.
    pub axle_ratio: f64,
    /// Dynamic tyre radius [m].
    pub wheel_radius_m: f64,
}

/// One gear's shift lines: points (engine speed [rad/s], torque [Nm]) in increasing speed; empty
/// where the gear has none (no downshift from gear 1, no upshift from the top gear).
#[derive(Debug, Clone, PartialEq)]
pub struct ShiftPolygon {
    pub down: Vec<Pt>,
    pub up: Vec<Pt>,
}

impl ShiftLineInputs {
    /// The full-load torque at `n` [rad/s], linear in its section (extrapolated at the ends),
    /// VECTO's `FullLoadStationaryTorque`.
    pub fn full_load_nm(&self, n: f64) -> f64 {
        // VECTO's `GetSection` on the curve's points, without building them (a driver asks this
        // several times a plant step).
        let last = self.full_load.len() - 1;
        let kept = self.full_load.iter().enumerate().position(|(i, p)| !(p.0 < n && i < last)).unwrap_or(last);
        let i = kept.saturating_sub(1).min(last - 1);
        let ((x0, y0), (x1, y1)) = (self.full_load[i], self.full_load[i + 1]);
        y0 + (y1 - y0) * (n - x0) / (x1 - x0)
    }

    /// The highest full-load torque [Nm].
    pub fn max_torque_nm(&self) -> f64 {
        self.full_load.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max)
    }

    /// (Rated speed [rad/s], rated power [W]): the full-load curve's highest power, within a
    /// section where the power's parabola peaks inside it (VECTO's `ComputeRatedSpeed`).
    pub fn rated(&self) -> (f64, f64) {
        let mut best = (0.0, 0.0);
        for w in self.full_load.windows(2) {
            let ((n1, t1), (n2, t2)) = (w[0], w[1]);
            let k = (t2 - t1) / (n2 - n1);
            let d = t2 - k * n2;
            let candidate = if k.abs() < TOLERANCE {
                (n2, t2 * n2)
            } else {
                let peak = -d / (2.0 * k);
                if peak < n1 - TOLERANCE || peak > n2 + TOLERANCE {
                    if t2 * n2 > t1 * n1 {
                        (n2, t2 * n2)
                    } else {
                        (n1, t1 * n1)
                    }
                } else {
                    (peak, (k * peak + d) * peak)
                }
            };
            if candidate.1 > best.1 {
                best = candidate;
            }
        }
        best
    }

    /// The highest engine speed [rad/s] at which the full-load curve gives 95 % of the rated
    /// power (VECTO's `N95hSpeed`).
    pub fn n95h_rad_s(&self) -> f64 {
        let target = 0.95 * self.rated().1;
        let mut found = f64::NEG_INFINITY;
        for w in self.full_load.windows(2) {
            let ((n1, t1), (n2, t2)) = (w[0], w[1]);
            let k = (t2 - t1) / (n2 - n1);
            let d = t2 - k * n2;
            // k·n² + d·n − P = 0 on the section.
            let roots: Vec<f64> = if k.abs() < TOLERANCE {
                vec![target / d]
            } else {
                let disc = d * d + 4.0 * k * target;
                if disc < 0.0 {
                    vec![]
                } else {
                    vec![(-d + disc.sqrt()) / (2.0 * k), (-d - disc.sqrt()) / (2.0 * k)]
                }
            };
            for n in roots.into_iter().filter(|&n| n >= n1 && n <= n2) {
                found = found.max(n);
            }
        }
        found
    }

    /// Gear `gear`'s (1..=n) shift lines.
    pub fn polygon(&self, gear: usize) -> ShiftPolygon {
        let ratios = &self.gear_ratios;
        let top = ratios.len();
        let n85_top = TRUCK_MAX_SPEED_MPS / self.wheel_radius_m * self.axle_ratio * ratios[top - 1];
        let n_vhigh = n85_top.min(self.rated().0);
        let diff_ratio = if top >= 2 { ratios[top - 2] / ratios[top - 1] - 1.0 } else { 0.0 };
        let max_drag = self.min_drag_nm * 1.1;
        let max_torque = self.max_torque_nm();
        let p1 = Pt { x: self.idle_rad_s / 2.0, y: 0.0 };
        let p2 = Pt { x: self.idle_rad_s * 1.1, y: 0.0 };
        let p3 = Pt { x: n_vhigh * 0.9, y: self.full_load_nm(n_vhigh * 0.9) };
        let p4 = Pt { x: n_vhigh * (1.0 + diff_ratio / 3.0), y: 0.0 };
        let p5 = Pt { x: self.n95h_rad_s(), y: max_torque };
        let p6 = Pt { x: p2.x, y: through(p1, p3, p2.x) };
        let p7 = Pt { x: p4.x, y: through(p2, p5, p4.x) };
        let margin: Vec<Pt> = self
            .full_load
            .iter()
            .take_while(|p| p.0 < p3.x * 0.95)
            .map(|&(x, y)| Pt { x, y: y * FLD_MARGIN })
            .collect();
        let (p6_corr, p3_corr) = below_full_load((p6, p3), &margin, 1.1 * max_torque);
        let down = if gear > 1 { vec![Pt { x: p2.x, y: max_drag }, p6_corr, p3_corr] } else { vec![] };
        if gear >= top {
            return ShiftPolygon { down, up: vec![] };
        }
        let step = ratios[gear - 1] / ratios[gear];
        let seen = |p: Pt| Pt { x: p.x * step * RPM_MARGIN, y: p.y / step };
        let (p2p, p3p, p6p) = (seen(p2), seen(p3), seen(p6));
        let (k, d) = line(p6p, p3p);
        let p3p_ext = Pt { x: (1.1 * p5.y - d) / k, y: 1.1 * p5.y };
        let mut up = lower_envelope(&[p4, p7, p5], &[p2p, p6p, p3p_ext]);
        up[0].y = max_drag;
        ShiftPolygon { down, up }
    }
}

/// y at `x` on the line through `a` and `b`.
fn through(a: Pt, b: Pt, x: f64) -> f64 {
    a.y + (b.y - a.y) * (x - a.x) / (b.x - a.x)
}

/// (slope, offset) of the line through `a` and `b`: y = slope·x + offset.
fn line(a: Pt, b: Pt) -> (f64, f64) {
    let k = (b.y - a.y) / (b.x - a.x);
    (k, b.y - k * b.x)
}

/// The downshift line's slope `p6`–`p3` moved down in parallel until no point of `margin` is
/// below it, running up to `max_torque` (VECTO's `MoveDownshiftBelowFld`).
fn below_full_load((p6, p3): (Pt, Pt), margin: &[Pt], max_torque: f64) -> (Pt, Pt) {
    let (k, d0) = line(p6, p3);
    let d = margin.iter().map(|p| p.y - k * p.x).fold(d0, f64::min);
    (Pt { x: p6.x, y: p6.x * k + d }, Pt { x: (max_torque - d) / k, y: max_torque })
}

/// VECTO's `IntersectTakeHigherShiftLine`: every point of both lines, their crossings and each
/// line's points projected on the other's segments' lines, swept from the highest speed down
/// taking the lowest non-zero torque at each speed, until a point at zero torque; collinear middle
/// points dropped; ordered by speed, then torque.
fn lower_envelope(orig: &[Pt], other: &[Pt]) -> Vec<Pt> {
    let mut set: Vec<Pt> = orig.iter().chain(other).copied().collect();
    for a in orig.windows(2) {
        for b in other.windows(2) {
            set.extend(intersect((a[0], a[1]), (b[0], b[1])));
        }
    }
    set.extend(projected(orig, other));
    set.extend(projected(other, orig));
    let mut xs: Vec<f64> = set.iter().map(|p| p.x).collect();
    xs.sort_by(|a, b| b.total_cmp(a));
    xs.dedup();
    let mut out = Vec::new();
    for x in xs {
        let at_x = set.iter().filter(|p| (p.x - x).abs() < TOLERANCE);
        if let Some(lowest) = at_x.clone().filter(|p| p.y.abs() >= TOLERANCE).min_by(|a, b| a.y.total_cmp(&b.y)) {
            out.push(*lowest);
        }
        if let Some(zero) = at_x.clone().find(|p| p.y.abs() < TOLERANCE) {
            out.push(*zero);
            break;
        }
    }
    drop_collinear(&mut out);
    out.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    out
}

/// Each of `points` moved to the line of each non-vertical segment of `segments` at its speed.
fn projected(segments: &[Pt], points: &[Pt]) -> Vec<Pt> {
    let mut out = Vec::new();
    for s in segments.windows(2) {
        if (s[0].x - s[1].x).abs() < TOLERANCE {
            continue;
        }
        let (k, d) = line(s[0], s[1]);
        out.extend(points.iter().map(|p| Pt { x: p.x, y: p.x * k + d }));
    }
    out
}

/// Removes every middle point lying on the line through its neighbours two apart, as VECTO does
/// (the candidates are found first, then removed).
fn drop_collinear(points: &mut Vec<Pt>) {
    let mut remove = Vec::new();
    for i in 0..points.len().saturating_sub(2) {
        let (a, m, b) = (points[i], points[i + 1], points[i + 2]);
        if (a.x - b.x).abs() >= TOLERANCE {
            let (k, d) = line(a, b);
            if (k * m.x + d - m.y).abs() < 1e-9 {
                remove.push(m);
            }
        }
    }
    points.retain(|p| !remove.contains(p));
}
