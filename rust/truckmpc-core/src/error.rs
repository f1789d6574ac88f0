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
