//! The trace of a run: plant states sampled at fixed distances by interpolation across plant steps.

use super::{ARRIVAL_TOLERANCE_M, KMH_PER_MPS};
use crate::plant::{derated_control, Control, PlantState};
use crate::powertrain::{EnergyStore, Powertrain};
use crate::road::Road;
use crate::vehicle::Vehicle;

/// The sampled trace, one entry per sample in every column. `fuel_g` and `brake_energy_kj` are
/// cumulative; `slope` is the grade of the segment ahead (the last segment's at the end point).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Trace {
    pub distance_m: Vec<f64>,
    pub time_s: Vec<f64>,
    pub speed_kmh: Vec<f64>,
    /// Gear, 0 = neutral.
    pub gear: Vec<i64>,
    pub pedal: Vec<f64>,
    pub brake: Vec<f64>,
    pub engine_speed_rpm: Vec<f64>,
    pub slope: Vec<f64>,
    pub altitude_m: Vec<f64>,
    /// Fuel used since the start [g] (empty for a battery-electric truck).
    pub fuel_g: Vec<f64>,
    pub brake_energy_kj: Vec<f64>,
    /// A battery-electric truck's net battery energy since the start [kWh], its state of charge [%]
    /// and its battery power [kW] (negative while charging) under the sample's inputs; empty for a
    /// fuel tank.
    pub battery_energy_kwh: Vec<f64>,
    pub soc_pct: Vec<f64>,
    pub battery_power_kw: Vec<f64>,
    /// A battery-electric truck's machine torque [Nm] under the sample's inputs.
    pub machine_torque_nm: Vec<f64>,
}

/// One sample: the interpolated state and the inputs applied over the step that crossed it.
#[derive(Debug, Clone, Copy)]
struct Sample {
    s_m: f64,
    t_s: f64,
    v_mps: f64,
    fuel_g: f64,
    brake_energy_j: f64,
    control: Control,
    /// Whether the drive ran derated.
    derated: bool,
}

/// Collects states at the trace's sample distances `start_m + k·step_m` (up to `end_m`).
#[derive(Debug, Clone)]
pub struct TraceRecorder {
    start_m: f64,
    step_m: f64,
    /// Number of sample distances.
    count: usize,
    next_index: usize,
    /// The next sample distance [m]; infinite after the last.
    pub next_s_m: f64,
    /// Whether the drive runs derated over the steps being crossed.
    pub derated: bool,
    samples: Vec<Sample>,
}

impl TraceRecorder {
    /// Samples every `step_m` metres from `start_m` to `end_m` [m].
    pub fn new(start_m: f64, end_m: f64, step_m: f64) -> Self {
        let candidates = ((end_m - start_m) / step_m + 1e-9).floor() as usize + 1;
        let at = |k: usize| start_m + step_m * k as f64;
        let count = (0..candidates).take_while(|&k| at(k) <= end_m).count();
        let next_s_m = if count > 0 { start_m } else { f64::INFINITY };
        let samples = Vec::with_capacity(count + 1);
        TraceRecorder { start_m, step_m, count, next_index: 0, next_s_m, derated: false, samples }
    }

    /// Record every sample in (a.s_m, b.s_m] (a.s_m included for the first one), `u` applied from a
    /// to b.
    pub fn cross(&mut self, a: &PlantState, b: &PlantState, u: Control) {
        let ds = b.s_m - a.s_m;
        while self.next_s_m <= b.s_m + ARRIVAL_TOLERANCE_M {
            let f = if ds <= 0.0 { 1.0 } else { unit_fraction((self.next_s_m - a.s_m) / ds) };
            self.samples.push(Sample {
                s_m: if f < 1.0 { self.next_s_m } else { b.s_m },
                t_s: a.t_s + f * (b.t_s - a.t_s),
                v_mps: a.v_mps + f * (b.v_mps - a.v_mps),
                fuel_g: a.fuel_g + f * (b.fuel_g - a.fuel_g),
                brake_energy_j: a.brake_energy_j + f * (b.brake_energy_j - a.brake_energy_j),
                control: u,
                derated: self.derated,
            });
            self.next_index += 1;
            self.next_s_m = if self.next_index < self.count {
                self.start_m + self.step_m * self.next_index as f64
            } else {
                f64::INFINITY
            };
        }
    }

    /// End the trace on the final state `last` (unless the last sample is already there).
    pub fn finish(&mut self, last: &PlantState, u: Control) {
        if self.samples.last().is_none_or(|x| last.s_m - x.s_m > ARRIVAL_TOLERANCE_M) {
            self.samples.push(Sample {
                s_m: last.s_m,
                t_s: last.t_s,
                v_mps: last.v_mps,
                fuel_g: last.fuel_g,
                brake_energy_j: last.brake_energy_j,
                control: u,
                derated: self.derated,
            });
        }
    }

    /// The trace columns; the altitude interpolated in the profile points (`road`'s distances,
    /// `altitude_m` at each).
    pub fn into_trace(self, road: &Road, altitude_m: &[f64], vehicle: &Vehicle) -> Trace {
        let mut trace = Trace::default();
        let mut segment = 0;
        let store = vehicle.store();
        let derated = self.samples.iter().any(|x| x.derated).then(|| vehicle.derated()).flatten();
        for x in &self.samples {
            trace.distance_m.push(x.s_m);
            trace.time_s.push(x.t_s);
            trace.speed_kmh.push(x.v_mps * KMH_PER_MPS);
            trace.gear.push(x.control.gear as i64);
            trace.pedal.push(x.control.pedal);
            trace.brake.push(x.control.brake);
            trace.engine_speed_rpm.push(vehicle.engine_speed_rpm(x.v_mps, x.control.gear));
            segment = road.segment(x.s_m, segment);
            trace.slope.push(road.slopes()[segment]);
            trace.altitude_m.push(interpolate(x.s_m, road.distance_m(), altitude_m));
            match store {
                EnergyStore::FuelTank => trace.fuel_g.push(x.fuel_g),
                EnergyStore::Battery { .. } => {
                    trace.battery_energy_kwh.push(x.fuel_g / J_PER_KWH);
                    trace.soc_pct.push(100.0 * store.state_of_charge(x.fuel_g).unwrap_or(f64::NAN));
                    let (drive, u) = match &derated {
                        Some(d) if x.derated => (d, derated_control(vehicle, d, x.v_mps, x.control).0),
                        _ => (vehicle, x.control),
                    };
                    trace.battery_power_kw.push(drive.energy_rate(x.v_mps, u) / 1000.0);
                    trace.machine_torque_nm.push(drive.machine_torque_nm(x.v_mps, u));
                }
            }
            trace.brake_energy_kj.push(x.brake_energy_j / 1000.0);
        }
        trace
    }
}

/// Joules per kilowatt-hour.
const J_PER_KWH: f64 = 3.6e6;

/// `x` limited to [0, 1], NaN taken as 0.
fn unit_fraction(x: f64) -> f64 {
    let at_least_zero = if x > 0.0 { x } else { 0.0 };
    if at_least_zero < 1.0 {
        at_least_zero
    } else {
        1.0
    }
}

/// Piecewise-linear interpolation of the points (`xs`, `ys`) at `x`, held constant outside them;
/// the same operations as numpy's `interp`, so the figures agree to the bit.
pub fn interpolate(x: f64, xs: &[f64], ys: &[f64]) -> f64 {
    let last = xs.len() - 1;
    if x.is_nan() {
        return x;
    }
    if x < xs[0] {
        return ys[0];
    }
    if x >= xs[last] {
        return ys[last];
    }
    let j = xs.partition_point(|&d| d <= x) - 1;
    if xs[j] == x {
        return ys[j];
    }
    let slope = (ys[j + 1] - ys[j]) / (xs[j + 1] - xs[j]);
    slope * (x - xs[j]) + ys[j]
}
