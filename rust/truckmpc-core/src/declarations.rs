//! What the core declares, as records for the tools above it: every parameter, every renamed,
//! replaced or added key, every figure of a run's summary and every column of its trace.

use crate::error::{CoreError, CoreResult};
use crate::figures::Figures;
use crate::params::{key_changes, RunSettings};
use crate::sim::schema::{SUMMARY, TRACE};

/// The declarations [`records`] gives, by name.
pub const NAMES: [&str; 4] = ["parameters", "key_changes", "summary", "trace"];

/// The records of the declaration `name` (one of [`NAMES`]), in its order: each parameter's
/// (`ParamSpec::record`, section by section), each key change's (`KeyChange::record`, oldest
/// first), each summary figure's and each trace column's (`OutputSpec::record`, in `summary.json`'s
/// and the trace CSV's order).
pub fn records(name: &str) -> CoreResult<Vec<Figures>> {
    Ok(match name {
        "parameters" => RunSettings::specs().iter().map(|spec| spec.record()).collect(),
        "key_changes" => key_changes().iter().map(|change| change.record()).collect(),
        "summary" => SUMMARY.iter().map(|figure| figure.spec.record()).collect(),
        "trace" => TRACE.iter().map(|column| column.spec.record()).collect(),
        _ => return Err(CoreError::invalid("declaration", format!("one of {}", NAMES.join(", "))).got(name)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each declaration gives one record per entry, each naming its entry; an unknown name is refused.
    #[test]
    fn every_declaration_gives_a_named_record_per_entry() {
        let lengths = [RunSettings::specs().len(), key_changes().len(), SUMMARY.len(), TRACE.len()];
        for (name, length) in NAMES.into_iter().zip(lengths) {
            let records = records(name).unwrap();
            assert_eq!(records.len(), length, "{name}");
            let field = if name == "key_changes" { "key" } else { "name" };
            assert!(records.iter().all(|r| r.iter().any(|(k, _)| *k == field)), "{name}: each has its {field}");
        }
        let CoreError::Invalid { key, .. } = records("outputs").unwrap_err();
        assert_eq!(key, "declaration");
    }
}
