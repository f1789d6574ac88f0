//! How the tables of [`super::SUMMARY`] and [`super::TRACE`] are written: one constructor per
//! kind of entry, and the readers their entries take a run's figures with.

use super::{Column, Figure, Kind, Merge, OutputSpec, ReadFigure, Runs, Source, SummaryFigure, Sweep, TraceColumn};
use crate::control::{PlanStats, RuleStats, SolverStats};
use crate::sim::summary::{BatteryFigures, RunSummary};
use crate::sim::trace::Trace;
use Kind::{Count, Number};
use Runs::Every;
use Sweep::No;

/// A figure the core's summary gives.
#[allow(clippy::too_many_arguments)]
pub(super) const fn core(
    name: &'static str,
    unit: &'static str,
    kind: Kind,
    runs: Runs,
    merge: Merge,
    sweep: Sweep,
    label: &'static str,
    doc: &'static str,
    read: ReadFigure,
) -> SummaryFigure {
    let spec = OutputSpec { name, unit, label, doc, kind, runs, source: Source::Core, merge, sweep, decimals: None };
    SummaryFigure { spec, read: Some(read) }
}

/// What a summary figure declares besides how it is read: name, unit, kind, runs, merge, sweep,
/// label, doc (the fields of [`OutputSpec`] of those names).
pub(super) type Declared = (&'static str, &'static str, Kind, Runs, Merge, Sweep, &'static str, &'static str);

/// A figure the Python package adds to the core's summary.
pub(super) const fn python((name, unit, kind, runs, merge, sweep, label, doc): Declared) -> SummaryFigure {
    let spec = OutputSpec { name, unit, label, doc, kind, runs, source: Source::Python, merge, sweep, decimals: None };
    SummaryFigure { spec, read: None }
}

/// A trace column only `runs` carry (their trace's samples; other runs' are empty, and left out).
#[allow(clippy::too_many_arguments)]
pub(super) const fn column_of(
    runs: Runs,
    name: &'static str,
    unit: &'static str,
    decimals: u8,
    merge: Merge,
    label: &'static str,
    doc: &'static str,
    take: fn(&mut Trace) -> Column,
) -> TraceColumn {
    let decimals = Some(decimals);
    let spec =
        OutputSpec { name, unit, label, doc, kind: Number, runs, source: Source::Core, merge, sweep: No, decimals };
    TraceColumn { spec, take }
}

/// A trace column of `decimals` decimals in the CSV (None: a whole number).
pub(super) const fn column(
    name: &'static str,
    unit: &'static str,
    decimals: Option<u8>,
    merge: Merge,
    label: &'static str,
    doc: &'static str,
    take: fn(&mut Trace) -> Column,
) -> TraceColumn {
    let kind = if decimals.is_some() { Number } else { Count };
    let spec =
        OutputSpec { name, unit, label, doc, kind, runs: Every, source: Source::Core, merge, sweep: No, decimals };
    TraceColumn { spec, take }
}

pub(super) fn num(x: f64) -> Option<Figure<'static>> {
    Some(Figure::Number(x))
}

pub(super) fn count(n: u64) -> Option<Figure<'static>> {
    Some(Figure::Count(n))
}

pub(super) fn maybe(x: Option<f64>) -> Option<Figure<'static>> {
    Some(x.map_or(Figure::Null, Figure::Number))
}

pub(super) fn numbers(column: &mut Vec<f64>) -> Column {
    Column::Number(std::mem::take(column))
}

pub(super) fn battery(s: &RunSummary, read: fn(&BatteryFigures) -> f64) -> Option<Figure<'static>> {
    s.battery.as_ref().map(|b| Figure::Number(read(b)))
}

pub(super) fn rules(s: &RunSummary, read: fn(&RuleStats) -> Figure<'static>) -> Option<Figure<'static>> {
    s.rules.as_ref().map(read)
}

pub(super) fn solver(s: &RunSummary, read: fn(&SolverStats) -> Figure<'static>) -> Option<Figure<'static>> {
    s.solver.as_ref().map(read)
}

pub(super) fn plan(s: &RunSummary, read: fn(&PlanStats) -> Figure<'static>) -> Option<Figure<'static>> {
    s.solver.as_ref().and_then(|x| x.plan.as_ref()).map(read)
}
