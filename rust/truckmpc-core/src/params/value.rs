//! Parameter values as a user writes them (YAML, `--set`, Python), and their conversion into the
//! typed fields of the parameter structs.

use std::fmt;

use super::spec::{expected_text, Kind, Range};
use crate::error::{CoreError, CoreResult};

/// A value as written by a user, before it is checked against a parameter's kind.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// YAML `null`, Python `None`.
    Null,
    /// true or false.
    Bool(bool),
    /// A whole number.
    Int(i64),
    /// A number with a fraction or exponent.
    Float(f64),
    /// Text (YAML reads `1e5`, without a signed exponent, as text).
    Text(String),
    /// A list.
    List(Vec<Value>),
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Null => write!(f, "null"),
            Value::Bool(b) => write!(f, "{b}"),
            Value::Int(i) => write!(f, "{i}"),
            Value::Float(x) => write!(f, "{x:?}"),
            Value::Text(t) => write!(f, "'{t}'"),
            Value::List(items) => {
                let parts: Vec<String> = items.iter().map(|v| v.to_string()).collect();
                write!(f, "[{}]", parts.join(", "))
            }
        }
    }
}

impl Value {
    /// The value as a number, if it is one (numeric text included); not for booleans.
    fn number(&self) -> Option<f64> {
        match self {
            Value::Int(i) => Some(*i as f64),
            Value::Float(x) => Some(*x),
            Value::Text(t) => t.trim().parse::<f64>().ok(),
            _ => None,
        }
    }
}

/// A Rust type a parameter can have: how a [`Value`] becomes one, and back.
pub trait ParamValue: Sized {
    /// The kind a user sees.
    const KIND: Kind;
    /// Convert and range-check `value` for the parameter `key`.
    fn from_value(key: &str, value: &Value, range: &Range) -> CoreResult<Self>;
    /// The value as a user would write it.
    fn to_value(&self) -> Value;
    /// Range-check a value built in Rust (e.g. a struct literal in a test).
    fn check(&self, key: &str, range: &Range) -> CoreResult<()> {
        Self::from_value(key, &self.to_value(), range).map(|_| ())
    }
}

fn type_error(key: &str, kind: Kind, range: &Range, value: &Value) -> CoreError {
    CoreError::invalid(key, expected_text(kind, range)).got(value)
}

fn range_error(key: &str, kind: Kind, range: &Range, value: &Value, x: f64) -> CoreError {
    let expected = expected_text(kind, range);
    let expected = if x.is_finite() { expected } else { expected.replacen("a number", "a finite number", 1) };
    CoreError::invalid(key, expected).got(value)
}

fn number_in(key: &str, kind: Kind, range: &Range, value: &Value) -> CoreResult<f64> {
    let x = value.number().ok_or_else(|| type_error(key, kind, range, value))?;
    if range.contains(x) {
        Ok(x)
    } else {
        Err(range_error(key, kind, range, value, x))
    }
}

impl ParamValue for f64 {
    const KIND: Kind = Kind::Number;
    fn from_value(key: &str, value: &Value, range: &Range) -> CoreResult<Self> {
        number_in(key, Self::KIND, range, value)
    }
    fn to_value(&self) -> Value {
        Value::Float(*self)
    }
}

impl ParamValue for Option<f64> {
    const KIND: Kind = Kind::NumberOrNull;
    fn from_value(key: &str, value: &Value, range: &Range) -> CoreResult<Self> {
        match value {
            Value::Null => Ok(None),
            _ => number_in(key, Self::KIND, range, value).map(Some),
        }
    }
    fn to_value(&self) -> Value {
        self.map_or(Value::Null, Value::Float)
    }
}

fn whole(key: &str, kind: Kind, range: &Range, value: &Value) -> CoreResult<u32> {
    match value {
        Value::Int(i) if range.contains(*i as f64) && (0..=i64::from(u32::MAX)).contains(i) => Ok(*i as u32),
        _ => Err(type_error(key, kind, range, value)),
    }
}

impl ParamValue for u32 {
    const KIND: Kind = Kind::Count;
    fn from_value(key: &str, value: &Value, range: &Range) -> CoreResult<Self> {
        whole(key, Self::KIND, range, value)
    }
    fn to_value(&self) -> Value {
        Value::Int(i64::from(*self))
    }
}

impl ParamValue for Option<u32> {
    const KIND: Kind = Kind::CountOrNull;
    fn from_value(key: &str, value: &Value, range: &Range) -> CoreResult<Self> {
        match value {
            Value::Null => Ok(None),
            _ => whole(key, Self::KIND, range, value).map(Some),
        }
    }
    fn to_value(&self) -> Value {
        self.map_or(Value::Null, |n| Value::Int(i64::from(n)))
    }
}

impl ParamValue for bool {
    const KIND: Kind = Kind::Flag;
    fn from_value(key: &str, value: &Value, range: &Range) -> CoreResult<Self> {
        match value {
            Value::Bool(b) => Ok(*b),
            _ => Err(type_error(key, Self::KIND, range, value)),
        }
    }
    fn to_value(&self) -> Value {
        Value::Bool(*self)
    }
}

impl ParamValue for Vec<f64> {
    const KIND: Kind = Kind::Numbers;
    fn from_value(key: &str, value: &Value, range: &Range) -> CoreResult<Self> {
        let Value::List(items) = value else { return Err(type_error(key, Self::KIND, range, value)) };
        let numbers: Option<Vec<f64>> = items.iter().map(Value::number).collect();
        let numbers = numbers.ok_or_else(|| type_error(key, Self::KIND, range, value))?;
        match numbers.iter().find(|x| !range.contains(**x)) {
            Some(&x) => Err(range_error(key, Self::KIND, range, value, x)),
            None => Ok(numbers),
        }
    }
    fn to_value(&self) -> Value {
        Value::List(self.iter().map(|x| Value::Float(*x)).collect())
    }
}

impl ParamValue for Vec<Option<f64>> {
    const KIND: Kind = Kind::NumbersOrNulls;
    fn from_value(key: &str, value: &Value, range: &Range) -> CoreResult<Self> {
        let Value::List(items) = value else { return Err(type_error(key, Self::KIND, range, value)) };
        if items.is_empty() {
            return Err(type_error(key, Self::KIND, range, value));
        }
        let mut out = Vec::with_capacity(items.len());
        for item in items {
            if *item == Value::Null {
                out.push(None);
                continue;
            }
            let x = item.number().ok_or_else(|| type_error(key, Self::KIND, range, value))?;
            if !range.contains(x) {
                return Err(range_error(key, Self::KIND, range, value, x));
            }
            out.push(Some(x));
        }
        Ok(out)
    }
    fn to_value(&self) -> Value {
        Value::List(self.iter().map(|x| x.map_or(Value::Null, Value::Float)).collect())
    }
}

/// Declare an enum whose values a user names (`grid: fixed`), with its [`ParamValue`] impl.
#[macro_export]
macro_rules! choice_enum {
    (
        $(#[doc = $doc:literal])*
        pub enum $name:ident { $( $(#[doc = $vdoc:literal])* $variant:ident = $text:literal, )+ }
    ) => {
        $(#[doc = $doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        pub enum $name { $( $(#[doc = $vdoc])* $variant, )+ }

        impl $name {
            /// The name a user writes for this value.
            pub fn as_str(&self) -> &'static str {
                match self { $( $name::$variant => $text, )+ }
            }
        }

        impl $crate::params::ParamValue for $name {
            const KIND: $crate::params::Kind = $crate::params::Kind::Choice(&[$($text),+]);
            fn from_value(key: &str, value: &$crate::params::Value, range: &$crate::params::Range)
                -> $crate::error::CoreResult<Self> {
                match value {
                    $( $crate::params::Value::Text(t) if t == $text => Ok($name::$variant), )+
                    _ => Err($crate::error::CoreError::invalid(
                        key, $crate::params::expected_text(Self::KIND, range)).got(value)),
                }
            }
            fn to_value(&self) -> $crate::params::Value {
                $crate::params::Value::Text(self.as_str().to_string())
            }
        }
    };
}
