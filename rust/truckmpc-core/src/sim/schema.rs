//! The outputs of a run, declared once: every figure of a controller's summary and every column of
//! its trace, each with its name (unit in the name), unit, meaning, which runs carry it, where it is
//! computed and how a road driven as several legs joins it. The binding converts a run's outputs by
//! walking [`SUMMARY`] and [`TRACE`]; the Python package reads them for the legs' join, the sweep's
//! columns, the run table and the outputs reference page.
//!
//! The tables' order is the order of `summary.json`'s figures, of the trace's columns and of
//! `sweep.csv`'s figure columns, which an unfinished sweep resumes by: add entries, never reorder.

use super::shifts::per_100km;
use super::summary::RunSummary;
use super::trace::Trace;
use crate::params::Value;

use self::build::{battery, column, column_of, core, count, maybe, num, numbers, plan, python, rules, solver};
use self::{Kind::*, Merge::*, Runs::*, Sweep::*};

/// Which runs carry a figure.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Runs {
    /// Every run.
    Every,
    /// Runs of VECTO's rule-based predictive cruise control (`pcc`).
    Pcc,
    /// Runs of a controller that solves the DP (`mpc`, `optimal`).
    Dp,
    /// Runs of the whole-road optimum (`optimal`).
    Optimal,
    /// Runs over a road with stops, driven as its stop-free legs.
    Legs,
    /// Runs of a battery-electric truck.
    Electric,
}

/// Where a figure is computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Source {
    /// The core's closed loop ([`RunSummary`], [`Trace`]).
    Core,
    /// The Python package, after the core's run.
    Python,
}

/// What a figure's value is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A float (null where the figure says so).
    Number,
    /// A whole number.
    Count,
    /// True or false.
    Flag,
    /// A line of text, or null.
    Text,
    /// A mapping or a list of them.
    Record,
}

/// How a road driven as several legs joins a figure of its legs' summaries (a trace column of
/// their traces). A recomputed figure follows from the joined figures it names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Merge {
    /// The legs' sum, when every leg has a value (else the last leg's value).
    Sum,
    /// The legs' sum; null when any leg stalled.
    SumUnlessStalled,
    /// The largest leg's.
    Max,
    /// The first leg's.
    First,
    /// The last leg's.
    Last,
    /// True when any leg's is.
    Any,
    /// The legs' values weighted by their `solves`.
    MeanPerSolve,
    /// Recomputed: the joined figure named per 100 km of the joined distance.
    Per100km(&'static str),
    /// Recomputed: the joined figure named over the joined trip time.
    PerTime(&'static str),
    /// Recomputed: the joined distance over the joined trip time (the start speed when no time).
    MeanSpeed,
    /// Made by the join from the legs.
    Built,
    /// Trace: the legs' samples one after another, counted on from where the previous leg ended.
    Continued,
    /// Trace: the legs' samples one after another.
    Joined,
}

impl Merge {
    /// The rule's name, as Python reads it.
    pub fn name(self) -> &'static str {
        match self {
            Sum => "sum",
            SumUnlessStalled => "sum_unless_stalled",
            Max => "max",
            First => "first",
            Last => "last",
            Any => "any",
            MeanPerSolve => "mean_per_solve",
            Per100km(_) => "per_100km",
            PerTime(_) => "per_time_s",
            MeanSpeed => "mean_speed",
            Built => "built",
            Continued => "continued",
            Joined => "joined",
        }
    }

    /// The figure a recomputed figure is recomputed from.
    pub fn of(self) -> Option<&'static str> {
        match self {
            Per100km(name) | PerTime(name) => Some(name),
            _ => None,
        }
    }
}

/// Which controllers' columns of `sweep.csv` carry a figure.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sweep {
    /// None.
    No,
    /// Every controller's (`pi`, `pcc`, `mpc`).
    All,
    /// The look-ahead controllers' (`pcc`, `mpc`).
    LookAhead,
    /// The MPC's.
    Mpc,
}

impl Sweep {
    /// The name Python reads ("" for none).
    pub fn name(self) -> &'static str {
        match self {
            No => "",
            All => "all",
            LookAhead => "look_ahead",
            Mpc => "mpc",
        }
    }
}

impl Runs {
    /// The name Python reads.
    pub fn name(self) -> &'static str {
        match self {
            Every => "every",
            Pcc => "pcc",
            Dp => "dp",
            Optimal => "optimal",
            Legs => "legs",
            Electric => "electric",
        }
    }
}

impl Source {
    /// The name Python reads.
    pub fn name(self) -> &'static str {
        match self {
            Source::Core => "core",
            Source::Python => "python",
        }
    }
}

impl Kind {
    /// The name Python reads.
    pub fn name(self) -> &'static str {
        match self {
            Number => "number",
            Count => "count",
            Flag => "flag",
            Text => "text",
            Record => "record",
        }
    }
}

/// One declared output: a summary figure or a trace column.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OutputSpec {
    /// Key in the summary (column of the trace), its unit in the name.
    pub name: &'static str,
    /// Unit ("-" for none).
    pub unit: &'static str,
    /// Short label for tables.
    pub label: &'static str,
    /// One-line meaning.
    pub doc: &'static str,
    pub kind: Kind,
    pub runs: Runs,
    pub source: Source,
    pub merge: Merge,
    pub sweep: Sweep,
    /// Decimals the trace's CSV writes (None for summary figures and whole numbers).
    pub decimals: Option<u8>,
}

impl OutputSpec {
    /// The spec as named values, as the binding hands it on: name, unit, label, doc, kind, runs,
    /// source, merge (each by its name), merge_of (null unless recomputed), sweep ("" for none)
    /// and decimals (null for summary figures and whole numbers).
    pub fn record(&self) -> Vec<(&'static str, Value)> {
        let text = |s: &str| Value::Text(s.to_string());
        // Every field named, so that a field added to the struct is a compile error here.
        let OutputSpec { name, unit, label, doc, kind, runs, source, merge, sweep, decimals } = *self;
        vec![
            ("name", text(name)),
            ("unit", text(unit)),
            ("label", text(label)),
            ("doc", text(doc)),
            ("kind", text(kind.name())),
            ("runs", text(runs.name())),
            ("source", text(source.name())),
            ("merge", text(merge.name())),
            ("merge_of", merge.of().map_or(Value::Null, text)),
            ("sweep", text(sweep.name())),
            ("decimals", decimals.map_or(Value::Null, |d| Value::Int(i64::from(d)))),
        ]
    }
}

/// A summary figure's value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Figure<'a> {
    Number(f64),
    Count(u64),
    Flag(bool),
    Text(&'a str),
    Null,
}

impl Figure<'_> {
    /// The figure as a value of the kind it is (a count as a whole number; beyond i64, which no
    /// count reaches, as a number).
    pub fn value(self) -> Value {
        match self {
            Figure::Number(x) => Value::Float(x),
            Figure::Count(n) => i64::try_from(n).map_or(Value::Float(n as f64), Value::Int),
            Figure::Flag(b) => Value::Bool(b),
            Figure::Text(text) => Value::Text(text.to_string()),
            Figure::Null => Value::Null,
        }
    }
}

/// Reads a figure from a run's summary; None when the run does not carry it.
pub type ReadFigure = for<'a> fn(&'a RunSummary) -> Option<Figure<'a>>;

/// A declared summary figure and how the core reads it (None for those added in Python).
#[derive(Debug, Clone, Copy)]
pub struct SummaryFigure {
    pub spec: OutputSpec,
    pub read: Option<ReadFigure>,
}

/// A trace column's samples.
#[derive(Debug, Clone, PartialEq)]
pub enum Column {
    Number(Vec<f64>),
    Count(Vec<i64>),
}

/// A declared trace column and how it is taken out of a trace.
#[derive(Debug, Clone, Copy)]
pub struct TraceColumn {
    pub spec: OutputSpec,
    pub take: fn(&mut Trace) -> Column,
}

/// Every figure of a controller's summary, in `summary.json`'s order.
#[rustfmt::skip]
pub const SUMMARY: &[SummaryFigure] = &[
    core("distance_m", "m", Number, Every, Sum, No, "distance", "Distance driven.", |s| num(s.distance_m)),
    core("fuel_kg", "kg", Number, Every, Sum, All, "fuel", "Fuel used (none for a battery-electric truck).",
        |s| s.battery.is_none().then_some(Figure::Number(s.fuel_kg))),
    python(("fuel_corrected_kg", "kg", Number, Every, SumUnlessStalled, All, "fuel, end speed corrected",
        "Fuel plus what would bring the end speed back to the start speed; null if the truck stalled.")),
    core("fuel_kg_per_100km", "kg/100km", Number, Every, Per100km("fuel_kg"), No, "fuel per 100 km",
        "Fuel per 100 km driven; null when the truck did not move.",
        |s| s.battery.is_none().then(|| s.fuel_kg_per_100km.map_or(Figure::Null, Figure::Number))),
    core("energy_kwh", "kWh", Number, Electric, Sum, All, "battery energy",
        "Net energy drawn from the battery, what braking returned deducted.", |s| battery(s, |b| b.energy_kwh)),
    core("energy_kwh_per_100km", "kWh/100km", Number, Electric, Per100km("energy_kwh"), No,
        "battery energy per 100 km", "Net battery energy per 100 km driven; null when the truck did not move.",
        |s| s.battery.map(|b| b.energy_kwh_per_100km.map_or(Figure::Null, Figure::Number))),
    python(("energy_corrected_kwh", "kWh", Number, Electric, SumUnlessStalled, All,
        "battery energy, end speed corrected",
        "Net battery energy plus what would bring the end speed back to the start speed; null if the truck stalled.")),
    core("recovered_kwh", "kWh", Number, Electric, Sum, All, "recovered energy",
        "Energy returned to the battery while braking returned more than the truck drew.",
        |s| battery(s, |b| b.recovered_kwh)),
    core("soc_start_pct", "%", Number, Electric, First, No, "state of charge at the start",
        "The battery's state of charge at the start.", |s| battery(s, |b| b.soc_start_pct)),
    core("soc_end_pct", "%", Number, Electric, Last, All, "state of charge at the end",
        "The battery's state of charge at the end.", |s| battery(s, |b| b.soc_end_pct)),
    core("machine_loss_kwh", "kWh", Number, Electric, Sum, No, "machine losses",
        "Energy lost in the electric machines (their drag while switched off included).",
        |s| battery(s, |b| b.machine_loss_kwh)),
    core("battery_loss_kwh", "kWh", Number, Electric, Sum, No, "battery losses",
        "Energy lost in the battery's internal resistance.", |s| battery(s, |b| b.battery_loss_kwh)),
    core("derated_s", "s", Number, Electric, Sum, No, "machines derated",
        "Time the machines' thermal buffer held them to their continuous torque where that is below their rated \
         limits (null: machines not rated).",
        |s| s.battery.map(|b| b.derated_s.map_or(Figure::Null, Figure::Number))),
    core("battery_empty", "-", Flag, Electric, Any, No, "battery empty",
        "Whether the usable charge ran out before the road's end (the run stopped there: no figure for the trip).",
        |s| s.battery.map(|b| Figure::Flag(b.empty))),
    core("time_s", "s", Number, Every, Sum, All, "trip time", "Trip time.", |s| num(s.time_s)),
    core("mean_speed_kmh", "km/h", Number, Every, MeanSpeed, No, "mean speed",
        "Distance over trip time (the start speed when no time passed).", |s| num(s.mean_speed_kmh)),
    core("start_speed_kmh", "km/h", Number, Every, First, No, "start speed", "Speed at the start.",
        |s| num(s.start_speed_kmh)),
    core("end_speed_kmh", "km/h", Number, Every, Last, All, "end speed", "Speed at the end.", |s| num(s.end_speed_kmh)),
    core("brake_energy_kj", "kJ", Number, Every, Sum, All, "brake energy", "Energy taken by the brakes.",
        |s| num(s.brake_energy_kj)),
    core("gear_shifts", "-", Count, Every, Sum, All, "gear shifts",
        "Changes between forward gears (a stretch in neutral bridged: the gear after it against the gear before).",
        |s| count(s.gear_shifts)),
    core("gear_shifts_per_100km", "1/100km", Number, Every, Per100km("gear_shifts"), All, "gear shifts per 100 km",
        "Gear shifts per 100 km; null when the truck did not move.", |s| maybe(s.gear_shifts_per_100km)),
    core("neutral_engagements", "-", Count, Every, Sum, All, "neutral coasting: entries",
        "Entries into neutral (coasting episodes, eco-roll's among them).", |s| count(s.neutral_engagements)),
    core("neutral_engagements_per_100km", "1/100km", Number, Every, Per100km("neutral_engagements"), All,
        "neutral coasting: entries per 100 km", "Neutral engagements per 100 km; null when the truck did not move.",
        |s| maybe(s.neutral_engagements_per_100km)),
    core("neutral_distance_m", "m", Number, Every, Sum, LookAhead, "neutral coasting: distance",
        "Distance coasted in neutral.", |s| num(s.neutral_distance_m)),
    core("stalled", "-", Flag, Every, Any, All, "stalled",
        "Whether the truck stalled (its speed fell below where gear 1 turns the engine at idle) or its battery ran empty.",
        |s| Some(Figure::Flag(s.stalled))),
    core("stall_distance_m", "m", Number, Every, Last, No, "stall distance",
        "Where the truck stalled; null unless it did.",
        |s| maybe(s.stall_distance_m)),
    core("message", "-", Text, Every, Last, No, "message",
        "One-line note on an abnormal end (a stall, inputs that no longer move the truck); null otherwise.",
        |s| Some(s.message.as_deref().map_or(Figure::Null, Figure::Text))),
    core("compute_time_s", "s", Number, Every, Sum, No, "compute time", "Wall-clock time of the run.",
        |s| num(s.compute_time_s)),
    core("realtime_ratio", "-", Number, Every, PerTime("compute_time_s"), Mpc, "realtime ratio",
        "Compute time over simulated time; null when no time was simulated.", |s| maybe(s.realtime_ratio)),
    core("plant_dt_s", "s", Number, Every, Last, No, "plant step", "The simulation's time step.",
        |s| num(s.plant_dt_s)),
    core("pcc_events", "-", Count, Pcc, Sum, No, "PCC coasting starts (use cases 1, 2)",
        "The PCC's use case 1 and 2 starts.", |s| rules(s, |r| Figure::Count(r.pcc_events))),
    core("eco_roll_entries", "-", Count, Pcc, Sum, No, "PCC eco-roll entries",
        "The PCC's eco-roll engagements (each also a neutral engagement).",
        |s| rules(s, |r| Figure::Count(r.eco_roll_entries))),
    core("eco_roll_entries_per_100km", "1/100km", Number, Pcc, Per100km("eco_roll_entries"), No,
        "PCC eco-roll entries per 100 km", "Eco-roll entries per 100 km; null when the truck did not move.",
        |s| s.rules.map(|r| per_100km(r.eco_roll_entries, s.distance_m).map_or(Figure::Null, Figure::Number))),
    core("solves", "-", Count, Dp, Sum, No, "solves",
        "Decisions: each a solve over the horizon or, between those, one stage against the stored cost-to-go.",
        |s| solver(s, |x| Figure::Count(x.solves))),
    core("horizon_solves", "-", Count, Dp, Sum, No, "horizon solves", "Of the solves, those over the whole horizon.",
        |s| solver(s, |x| Figure::Count(x.horizon_solves))),
    core("solve_ms_mean", "ms", Number, Dp, MeanPerSolve, Mpc, "solve time mean", "Mean wall time of a solve.",
        |s| solver(s, |x| Figure::Number(x.solve_ms_mean()))),
    core("solve_ms_max", "ms", Number, Dp, Max, Mpc, "solve time max", "Wall time of the longest solve.",
        |s| solver(s, |x| Figure::Number(x.solve_ms_max()))),
    core("infeasible_solves", "-", Count, Dp, Sum, Mpc, "infeasible solves", "Solves that found no admissible plan.",
        |s| solver(s, |x| Figure::Count(x.infeasible_solves))),
    core("states_per_solve", "-", Number, Dp, MeanPerSolve, No, "states per solve", "Mean states of a solve.",
        |s| solver(s, |x| Figure::Number(x.states_per_solve()))),
    core("transitions_per_solve", "-", Number, Dp, MeanPerSolve, Mpc, "transitions per solve",
        "Mean transitions of a solve.", |s| solver(s, |x| Figure::Number(x.transitions_per_solve()))),
    core("fallback_relaxed", "-", Count, Dp, Sum, No, "relaxed solves driven",
        "Relaxed solves (lower speed bound and shift limit relaxed) whose plan was driven.",
        |s| solver(s, |x| Figure::Count(x.fallback_relaxed))),
    core("fallback_rescues", "-", Count, Dp, Sum, No, "rescues",
        "Falls back to the rescue policy (the PI's gear logic, full pedal) where no plan was found.",
        |s| solver(s, |x| Figure::Count(x.fallback_rescues))),
    core("fallback_rescue_m", "m", Number, Dp, Sum, No, "rescue distance", "Distance driven on the rescue policy.",
        |s| solver(s, |x| Figure::Number(x.fallback_rescue_m))),
    core("plan_fuel_kg", "kg", Number, Optimal, Sum, No, "plan fuel",
        "Fuel of following the whole-road plan on the DP's own stage model (NaN where it has no path).",
        |s| s.battery.is_none().then(|| plan(s, |p| Figure::Number(p.fuel_kg))).flatten()),
    core("plan_energy_kwh", "kWh", Number, Optimal, Sum, No, "plan battery energy",
        "A battery-electric truck's net battery energy of following the whole-road plan on the DP's own stage model.",
        |s| s.battery.and_then(|_| plan(s, |p| Figure::Number(p.fuel_kg * 1000.0 / 3.6e6)))),
    core("plan_time_s", "s", Number, Optimal, Sum, No, "plan trip time",
        "Trip time of following the whole-road plan on the DP's own stage model.",
        |s| plan(s, |p| Figure::Number(p.time_s))),
    core("plan_end_speed_kmh", "km/h", Number, Optimal, Last, No, "plan end speed",
        "Speed at the road's end of following the whole-road plan on the DP's own stage model.",
        |s| plan(s, |p| Figure::Number(p.end_v_mps * crate::KMH_PER_MPS))),
    python(("plan_gap_pct", "%", Number, Optimal, Max, No, "plant against plan, at equal time and end speed",
        "How far what the plant used is from what the plan predicted, with the run brought to the plan's end speed \
         and trip time (the time priced at β): in % of the plan's fuel or battery energy, as a magnitude (the \
         largest leg's on a road with stops).")),
    core("plan_cost", "-", Number, Optimal, Sum, No, "plan cost", "The plan's optimal cost J_0.",
        |s| plan(s, |p| Figure::Number(p.cost))),
    core("plan_solve_s", "s", Number, Optimal, Sum, No, "plan solve time", "Wall time of the whole-road solve.",
        |s| plan(s, |p| Figure::Number(p.solve_s))),
    core("plan_stages", "-", Count, Optimal, Sum, No, "plan stages", "Stages of the plan.",
        |s| plan(s, |p| Figure::Count(p.stages))),
    core("plan_table_mb", "MB", Number, Optimal, Max, No, "plan table", "Memory of the plan's stored cost-to-go.",
        |s| plan(s, |p| Figure::Number(p.table_bytes as f64 / 1e6))),
    python(("settings", "-", Record, Dp, Last, No, "settings",
        "The DP's parameters as it took them (k_lim, Q2 and Q5 per stage resolved, the fuel_time cost's β).")),
    python(("legs", "-", Record, Legs, Built, No, "legs",
        "Each stop-free leg's start_m, end_m, entry_speed_kmh, exit_speed_kmh, fuel_kg and time_s.")),
    python(("stops_not_simulated", "-", Record, Legs, Built, No, "stops not simulated",
        "The stops left out: their count, total_stop_s, the number of legs and a note on why.")),
];

/// Every column of the trace, in the CSV's order.
#[rustfmt::skip]
pub const TRACE: &[TraceColumn] = &[
    column("distance_m", "m", Some(3), Joined, "distance", "From the road's start.",
        |t| numbers(&mut t.distance_m)),
    column("time_s", "s", Some(4), Continued, "time", "Since the run's start.",
        |t| numbers(&mut t.time_s)),
    column("speed_kmh", "km/h", Some(5), Joined, "speed", "Speed.", |t| numbers(&mut t.speed_kmh)),
    column("gear", "-", None, Joined, "gear", "Gear engaged, 0 = neutral.",
        |t| Column::Count(std::mem::take(&mut t.gear))),
    column("pedal", "-", Some(6), Joined, "pedal", "Accelerator pedal, 0 … 1.",
        |t| numbers(&mut t.pedal)),
    column("brake", "-", Some(6), Joined, "brake", "Brake level, 0 … 1.", |t| numbers(&mut t.brake)),
    column("engine_speed_rpm", "rpm", Some(2), Joined, "engine speed", "Engine speed.",
        |t| numbers(&mut t.engine_speed_rpm)),
    column("slope", "-", Some(6), Joined, "slope",
        "The road's grade ahead as a fraction, 0.01 = 1 % (the last segment's at the end).",
        |t| numbers(&mut t.slope)),
    column("altitude_m", "m", Some(4), Joined, "altitude", "The road's altitude.",
        |t| numbers(&mut t.altitude_m)),
    column("fuel_g", "g", Some(4), Continued, "fuel", "Fuel used since the run's start (not for a battery-electric truck).",
        |t| numbers(&mut t.fuel_g)),
    column("brake_energy_kj", "kJ", Some(4), Continued, "brake energy",
        "Energy taken by the brakes since the run's start.",
        |t| numbers(&mut t.brake_energy_kj)),
    column_of(Electric, "battery_energy_kwh", "kWh", 6, Continued, "battery energy",
        "Net energy drawn from the battery since the run's start.", |t| numbers(&mut t.battery_energy_kwh)),
    column_of(Electric, "soc_pct", "%", 4, Joined, "state of charge", "The battery's state of charge.",
        |t| numbers(&mut t.soc_pct)),
    column_of(Electric, "battery_power_kw", "kW", 3, Joined, "battery power",
        "Power drawn from the battery under the sample's inputs; negative while braking returns energy.",
        |t| numbers(&mut t.battery_power_kw)),
    column_of(Electric, "machine_torque_nm", "Nm", 2, Joined, "machine torque",
        "The electric machines' torque under the sample's inputs (all of them; negative while they brake or drag).",
        |t| numbers(&mut t.machine_torque_nm)),
];

impl RunSummary {
    /// The figures this run carries, in [`SUMMARY`]'s order, each with its declaration.
    pub fn figures(&self) -> impl Iterator<Item = (&'static OutputSpec, Figure<'_>)> + '_ {
        SUMMARY.iter().filter_map(move |f| f.read.and_then(|read| read(self)).map(|value| (&f.spec, value)))
    }
}

impl Trace {
    /// The trace's columns in [`TRACE`]'s order, each with its declaration; a column this run
    /// does not carry (no samples: another kind of truck's) is left out.
    pub fn into_columns(mut self) -> impl Iterator<Item = (&'static OutputSpec, Column)> {
        let carried = |c: &Column| !matches!(c, Column::Number(values) if values.is_empty());
        TRACE.iter().map(move |c| (&c.spec, (c.take)(&mut self))).filter(move |(_, column)| carried(column))
    }
}

mod build;
#[cfg(test)]
mod tests;
