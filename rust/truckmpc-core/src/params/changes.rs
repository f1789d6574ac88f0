//! Keys renamed, replaced or added since runs were first recorded, in one registry: a file or an
//! override naming an old key is refused with its successor named, and a record made before a key
//! existed (a `summary.json`, a sweep directory) is read with the value that drove it.

use super::{ParamSet, Value, VectoParams};

/// How a key changed.
#[derive(Debug, Clone, PartialEq)]
pub enum Change {
    /// Renamed, same meaning: a recorded value carries over under `new`.
    Renamed {
        /// The key's name now.
        new: &'static str,
    },
    /// Replaced by a key of another meaning: a value under the old name is refused.
    Replaced {
        /// The key that took its place.
        new: &'static str,
        /// Why, in a parenthesis that follows the new key's name.
        why: &'static str,
    },
    /// Added: a record made before it existed replays with `replays_with`.
    Added {
        /// The value that drove the runs recorded before the key existed.
        replays_with: Value,
    },
}

/// One change of a key, with the version of truckmpc that made it.
#[derive(Debug, Clone, PartialEq)]
pub struct KeyChange {
    /// The key as it was (renamed, replaced) or as it is (added).
    pub key: &'static str,
    /// What happened to it.
    pub change: Change,
    /// The version of truckmpc that changed it.
    pub version: &'static str,
}

impl KeyChange {
    /// The change as named values, as the binding hands it on: key, kind (renamed, replaced or
    /// added), new (the successor; null for an added key), why (null unless replaced),
    /// replays_with (null unless added) and version.
    pub fn record(&self) -> Vec<(&'static str, Value)> {
        let text = |s: &str| Value::Text(s.to_string());
        // Every field named, so that a field added to the struct is a compile error here.
        let KeyChange { key, change, version } = self;
        let (kind, new, why, replays_with) = match change {
            Change::Renamed { new } => ("renamed", text(new), Value::Null, Value::Null),
            Change::Replaced { new, why } => ("replaced", text(new), text(why), Value::Null),
            Change::Added { replays_with } => ("added", Value::Null, Value::Null, replays_with.clone()),
        };
        vec![
            ("key", text(key)),
            ("kind", text(kind)),
            ("new", new),
            ("why", why),
            ("replays_with", replays_with),
            ("version", text(version)),
        ]
    }
}

/// Why the PCC's own under- and overspeed were replaced.
const ONE_BAND: &str = "(one speed band for every controller: v_dec_kmh below v_ref, v_inc_kmh above)";

/// Every change of a key, oldest first.
pub fn key_changes() -> Vec<KeyChange> {
    let replaced = |key, new| KeyChange { key, change: Change::Replaced { new, why: ONE_BAND }, version: "0.1.0" };
    let mut changes = vec![
        replaced("pcc_underspeed_kmh", "v_dec_kmh"),
        replaced("pcc_overspeed_kmh", "v_inc_kmh"),
        KeyChange { key: "pedal_levels", change: Change::Added { replays_with: Value::Int(0) }, version: "0.1.0" },
        KeyChange { key: "air_density_kg_m3", change: Change::Renamed { new: "air_density_kgpm3" }, version: "0.1.0" },
    ];
    // The VECTO truck's keys entered the declaration with the defaults every earlier run used.
    let defaults = VectoParams::default();
    changes.extend(VectoParams::specs().into_iter().map(|spec| KeyChange {
        key: spec.name,
        change: Change::Added { replays_with: defaults.get(spec.name).expect("declared") },
        version: "0.1.0",
    }));
    changes
}

/// The change of a key no longer declared (renamed or replaced), if `key` is one.
pub fn retired(key: &str) -> Option<KeyChange> {
    key_changes().into_iter().find(|c| c.key == key && !matches!(c.change, Change::Added { .. }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::RunSettings;

    #[test]
    fn retired_keys_are_not_declared_and_their_successors_are() {
        let specs = RunSettings::specs();
        let declared = |key: &str| specs.iter().any(|spec| spec.name == key);
        for change in key_changes() {
            match change.change {
                Change::Renamed { new } | Change::Replaced { new, .. } => {
                    assert!(!declared(change.key) && declared(new), "{}", change.key)
                }
                Change::Added { replays_with } => {
                    assert!(declared(change.key), "{}", change.key);
                    let mut settings = RunSettings::default();
                    settings.set(change.key, &replays_with).unwrap();
                }
            }
        }
    }

    #[test]
    fn a_record_has_every_field_of_the_change() {
        let text = |s: &str| Value::Text(s.to_string());
        let replaced = key_changes().into_iter().find(|c| c.key == "pcc_underspeed_kmh").expect("registered");
        let expected = vec![
            ("key", text("pcc_underspeed_kmh")),
            ("kind", text("replaced")),
            ("new", text("v_dec_kmh")),
            ("why", text(ONE_BAND)),
            ("replays_with", Value::Null),
            ("version", text("0.1.0")),
        ];
        assert_eq!(replaced.record(), expected);
        let added = key_changes().into_iter().find(|c| c.key == "pedal_levels").expect("registered").record();
        assert_eq!(
            added[1..5],
            [("kind", text("added")), ("new", Value::Null), ("why", Value::Null), ("replays_with", Value::Int(0))]
        );
    }
}
