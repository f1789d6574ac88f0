//! Errors returned by the core. Each names the offending key and what was expected, as data, so
//! the binding can hand the key to Python (which maps it to the file, line or `--set` it came from)
//! without parsing a message.

/// An invalid parameter or argument given to the core.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CoreError {
    /// A named value is outside what is admissible.
    #[error("{key}: expected {expected}{}", got.as_ref().map(|g| format!(", got {g}")).unwrap_or_default())]
    Invalid {
        /// The parameter (or argument) at fault, e.g. `"mass_kg"`.
        key: String,
        /// What was expected, e.g. `"a number > 0"`.
        expected: String,
        /// The value given, as text; `None` when `expected` already says it.
        got: Option<String>,
        /// Other parameters the check involved (e.g. `v_ref_kmh` for `v_dec_kmh < v_ref_kmh`): the
        /// one the user changed last is the likelier culprit.
        related: Vec<String>,
    },
}

impl CoreError {
    /// `key`: expected `expected` (no value shown).
    pub fn invalid(key: &str, expected: impl Into<String>) -> Self {
        CoreError::Invalid { key: key.to_string(), expected: expected.into(), got: None, related: Vec::new() }
    }

    /// The same error, showing the value given.
    pub fn got(self, value: impl std::fmt::Display) -> Self {
        let CoreError::Invalid { key, expected, related, .. } = self;
        CoreError::Invalid { key, expected, got: Some(value.to_string()), related }
    }

    /// The same error, naming the other parameters the check involved.
    pub fn related(self, keys: &[&str]) -> Self {
        let CoreError::Invalid { key, expected, got, .. } = self;
        CoreError::Invalid { key, expected, got, related: keys.iter().map(|k| k.to_string()).collect() }
    }

    /// The parameter at fault.
    pub fn key(&self) -> &str {
        let CoreError::Invalid { key, .. } = self;
        key
    }
}

/// Result alias of the core.
pub type CoreResult<T> = Result<T, CoreError>;
