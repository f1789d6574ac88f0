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

    /// The spec as named values, as the binding hands it on: name, section, kind (its name), unit,
    /// doc, default, choices (the names a choice accepts; null for other kinds) and expected (the
    /// kind and range in words, which stand for the range).
    pub fn record(&self) -> Vec<(&'static str, Value)> {
        // Every field named, so that a field added to the struct is a compile error here.
        let ParamSpec { name, section, kind, unit, doc, range: _, default } = self;
        let choices = match kind {
            Kind::Choice(names) => Value::List(names.iter().map(|n| Value::Text(n.to_string())).collect()),
            _ => Value::Null,
        };
        vec![
            ("name", Value::Text(name.to_string())),
            ("section", Value::Text(section.to_string())),
            ("kind", Value::Text(kind.name().to_string())),
            ("unit", Value::Text(unit.to_string())),
            ("doc", Value::Text(doc.clone())),
            ("default", default.clone()),
            ("choices", choices),
            ("expected", Value::Text(self.expected())),
        ]
    }
}

#[cfg(test)]
mod tests {
    use crate::params::{RunSettings, Value};

    fn text(s: &str) -> Value {
        Value::Text(s.to_string())
    }

    fn record_of(key: &str) -> Vec<(&'static str, Value)> {
        RunSettings::specs().into_iter().find(|spec| spec.name == key).expect("declared").record()
    }

    #[test]
    fn a_record_has_every_field_of_the_spec_as_declared() {
        // delta_kmh: f64 = 0.05, unit "km/h", range (0, 100], in the mpc section.
        let record = record_of("delta_kmh");
        let names: Vec<&str> = record.iter().map(|(name, _)| *name).collect();
        assert_eq!(names, ["name", "section", "kind", "unit", "doc", "default", "choices", "expected"]);
        let values: Vec<Value> = record.into_iter().map(|(_, value)| value).collect();
        let doc = text("δ, step of the DP's speed grid.");
        let expected = text("a number in (0, 100]");
        let values_expected = [
            text("delta_kmh"),
            text("mpc"),
            text("number"),
            text("km/h"),
            doc,
            Value::Float(0.05),
            Value::Null,
            expected,
        ];
        assert_eq!(values, values_expected);
    }

    #[test]
    fn a_choices_record_names_the_choices() {
        // grid: GridAnchor = Fixed, a choice of "moving" or "fixed".
        let record = record_of("grid");
        let field = |key: &str| record.iter().find(|(name, _)| *name == key).map(|(_, value)| value.clone());
        assert_eq!(field("kind"), Some(text("choice")));
        assert_eq!(field("default"), Some(text("fixed")));
        assert_eq!(field("choices"), Some(Value::List(vec![text("moving"), text("fixed")])));
    }
}
