//! The scalar figures of a run.

use super::shifts::{per_100km, GearCounts};
use super::KMH_PER_MPS;
use crate::control::{RuleStats, SolverStats};
use crate::plant::PlantState;
use crate::powertrain::{EnergyStore, ThermalState};

/// Outcome of a run in figures. Fuel in kg, distances in m, times in s, speeds in km/h, energies
/// in kJ; the wall-clock fields are measured around the run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSummary {
    pub distance_m: f64,
    pub fuel_kg: f64,
    /// None when the truck did not move.
    pub fuel_kg_per_100km: Option<f64>,
    pub time_s: f64,
    pub mean_speed_kmh: f64,
    pub start_speed_kmh: f64,
    pub end_speed_kmh: f64,
    /// Changes between forward gears, a stretch in neutral bridged ([`super::shifts`]).
    pub gear_shifts: u64,
    /// Entries into neutral.
    pub neutral_engagements: u64,
    /// Gear shifts per 100 km; None when the truck did not move.
    pub gear_shifts_per_100km: Option<f64>,
    /// Neutral engagements per 100 km; None when the truck did not move.
    pub neutral_engagements_per_100km: Option<f64>,
    pub brake_energy_kj: f64,
    /// Distance driven in neutral [m].
    pub neutral_distance_m: f64,
    /// Wall time of the run [s].
    pub compute_time_s: f64,
    /// Compute time / simulated time; None when no time was simulated.
    pub realtime_ratio: Option<f64>,
    pub stalled: bool,
    /// Where the truck stalled; None unless stalled.
    pub stall_distance_m: Option<f64>,
    /// One-line note on an abnormal end (a stall, or inputs that no longer move the truck).
    pub message: Option<String>,
    pub plant_dt_s: f64,
    /// The solves of an optimising controller.
    pub solver: Option<SolverStats>,
    /// What a rule-based controller with look-ahead (the PCC) did.
    pub rules: Option<RuleStats>,
    /// A battery-electric truck's energy; None for a fuel tank.
    pub battery: Option<BatteryFigures>,
}

/// A battery-electric truck's energy over a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BatteryFigures {
    /// Net energy drawn from the battery [kWh] (recovered energy deducted).
    pub energy_kwh: f64,
    /// Net energy per 100 km [kWh/100km]; None when the truck did not move.
    pub energy_kwh_per_100km: Option<f64>,
    /// Energy returned to the battery [kWh] (while it took in more than the truck drew).
    pub recovered_kwh: f64,
    /// State of charge at the start and at the end [%].
    pub soc_start_pct: f64,
    pub soc_end_pct: f64,
    /// Whether the usable charge ran out (the run ended there).
    pub empty: bool,
    /// Time the machines ran derated below their rated torque limits [s]; None for machines
    /// that are not rated.
    pub derated_s: Option<f64>,
    /// Energy lost in the machines (their drag while off included) and in the battery [kWh].
    pub machine_loss_kwh: f64,
    pub battery_loss_kwh: f64,
}

impl BatteryFigures {
    /// The figures of a run drawing on `store` that ended in `last` after `distance_m`, as
    /// `outcome` ended it (its machines' thermal buffer and losses).
    fn new(store: EnergyStore, last: &PlantState, distance_m: f64, outcome: &LoopOutcome) -> Option<Self> {
        let start = store.state_of_charge(0.0)?;
        let end = store.state_of_charge(last.fuel_g)?;
        let energy_kwh = last.fuel_g / J_PER_KWH;
        Some(BatteryFigures {
            energy_kwh,
            energy_kwh_per_100km: (distance_m > 0.0).then(|| energy_kwh / (distance_m / 1e5)),
            recovered_kwh: last.returned / J_PER_KWH,
            soc_start_pct: 100.0 * start,
            soc_end_pct: 100.0 * end,
            empty: store.is_empty(last.fuel_g),
            derated_s: outcome.thermal.map(|t| t.derated_s),
            machine_loss_kwh: outcome.losses_j[0] / J_PER_KWH,
            battery_loss_kwh: outcome.losses_j[1] / J_PER_KWH,
        })
    }
}

/// Joules per kilowatt-hour.
const J_PER_KWH: f64 = 3.6e6;

/// How the loop ended, besides the final plant state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoopOutcome {
    pub start_m: f64,
    pub end_m: f64,
    pub start_speed_kmh: f64,
    /// Gear shifts and neutral engagements so far.
    pub gears: GearCounts,
    pub neutral_distance_m: f64,
    /// The controller's inputs stopped moving the truck.
    pub stuck: bool,
    /// The host asked the run to stop ([`crate::stop`]).
    pub stopped: bool,
    pub stall_speed_mps: f64,
    pub plant_dt_s: f64,
    /// The store the truck drew on.
    pub store: EnergyStore,
    /// The drive's thermal buffer at the end (none for a drive that never derates).
    pub thermal: Option<ThermalState>,
    /// Energy lost in the machines and in the battery [J] (a battery-electric truck's).
    pub losses_j: [f64; 2],
}

impl RunSummary {
    /// The figures of a run ending in `last` after `compute_time_s` of wall time.
    pub fn new(
        last: &PlantState,
        outcome: &LoopOutcome,
        compute_time_s: f64,
        solver: Option<SolverStats>,
        rules: Option<RuleStats>,
    ) -> Self {
        let distance_m = last.s_m - outcome.start_m;
        let moved = last.t_s > 0.0;
        let battery = BatteryFigures::new(outcome.store, last, distance_m, outcome);
        RunSummary {
            distance_m,
            fuel_kg: last.fuel_g / 1000.0,
            fuel_kg_per_100km: (distance_m > 0.0).then(|| last.fuel_g / 1000.0 / (distance_m / 1e5)),
            time_s: last.t_s,
            mean_speed_kmh: if moved { distance_m / last.t_s * KMH_PER_MPS } else { outcome.start_speed_kmh },
            start_speed_kmh: outcome.start_speed_kmh,
            end_speed_kmh: last.v_mps * KMH_PER_MPS,
            gear_shifts: outcome.gears.gear_shifts,
            neutral_engagements: outcome.gears.neutral_engagements,
            gear_shifts_per_100km: per_100km(outcome.gears.gear_shifts, distance_m),
            neutral_engagements_per_100km: per_100km(outcome.gears.neutral_engagements, distance_m),
            brake_energy_kj: last.brake_energy_j / 1000.0,
            neutral_distance_m: outcome.neutral_distance_m,
            compute_time_s,
            realtime_ratio: moved.then(|| compute_time_s / last.t_s),
            stalled: last.stalled,
            stall_distance_m: last.stalled.then_some(last.s_m),
            message: message(last, outcome),
            plant_dt_s: outcome.plant_dt_s,
            solver,
            rules,
            battery,
        }
    }
}

fn message(last: &PlantState, outcome: &LoopOutcome) -> Option<String> {
    let km = last.s_m / 1000.0;
    if last.stalled && outcome.store.is_empty(last.fuel_g) {
        let soc = 100.0 * outcome.store.state_of_charge(last.fuel_g).unwrap_or(0.0);
        Some(format!(
            "battery empty at km {km:.2}: the usable charge ended there (state of charge {soc:.1} %), the trip was not driven"
        ))
    } else if last.stalled {
        Some(format!(
            "stalled at km {km:.2}: the speed fell below {:.1} km/h, where gear 1 turns the engine at idle",
            outcome.stall_speed_mps * KMH_PER_MPS
        ))
    } else if outcome.stuck && outcome.end_m - last.s_m > 1e-3 {
        Some(format!("stopped at km {km:.2}: the controller's inputs no longer move the truck"))
    } else {
        None
    }
}
