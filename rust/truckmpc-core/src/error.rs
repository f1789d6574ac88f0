//! Errors returned by the core. Each message names the offending parameter and what was expected,
//! so the binding layer can pass it to the user unchanged.

/// An invalid parameter or argument given to the core.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CoreError {
    /// A named parameter is outside its admissible range.
    #[error("{name}: {message}")]
    InvalidParameter { name: String, message: String },
}

impl CoreError {
    /// Shorthand for [`CoreError::InvalidParameter`].
    pub fn invalid(name: &str, message: impl Into<String>) -> Self {
        CoreError::InvalidParameter { name: name.to_string(), message: message.into() }
    }
}

/// Result alias of the core.
pub type CoreResult<T> = Result<T, CoreError>;

/// Check every named value with `ok`; the error names the first that fails and says it was
/// `expected` ("a number > 0"). NaN fails any range check.
pub fn check_each(values: &[(&str, f64)], ok: impl Fn(f64) -> bool, expected: &str) -> CoreResult<()> {
    match values.iter().find(|(_, value)| !(value.is_finite() && ok(*value))) {
        Some((name, value)) => Err(CoreError::invalid(name, format!("expected {expected}, got {value}"))),
        None => Ok(()),
    }
}
