//! One declared parameter as a whole: its name, section, kind, unit, doc, range and default.

use super::spec::{expected_text, Kind, Range};
use super::value::Value;

/// One declared parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamSpec {
    /// Key as typed in YAML, `--set` and `--grid`, unit in the name (`horizon_m`).
    pub name: &'static str,
    /// Group it belongs to: `vehicle`, `cruise`, `pi`, `mpc` or `sim`.
    pub section: &'static str,
    /// Type of its value.
    pub kind: Kind,
    /// Unit in words (`"m"`, `"km/h"`, `"-"`).
    pub unit: &'static str,
    /// One-line description.
    pub doc: String,
    /// Admissible numbers (each number, for lists).
    pub range: Range,
    /// Default value.
    pub default: Value,
}

impl ParamSpec {
    /// What the value must be, in words: `"a number > 0"`, `"'moving' or 'fixed'"`, ...
    pub fn expected(&self) -> String {
        expected_text(self.kind, &self.range)
    }
}
