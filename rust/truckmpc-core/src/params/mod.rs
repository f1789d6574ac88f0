//! Every parameter of a run, declared once: name (unit in the name), type, default, admissible
//! range and one-line doc. The declarations ([`declare_params!`]) generate the structs the core
//! uses, their defaults, their range checks, the conversion from user values ([`Value`]) and the
//! specs ([`ParamSpec`]) from which the Python side derives the YAML defaults, the `--set` and
//! `--grid` parsing, the error messages and the documentation's key tables.
//!
//! Keys are unique across sections, so a run's settings are one flat namespace ([`RunSettings`]).

mod changes;
mod cruise;
mod declaration;
mod mpc;
mod pcc;
mod pi;
mod settings;
mod sim;
mod spec;
mod value;
mod vecto;
mod vehicle;

pub use changes::{key_changes, retired, Change, KeyChange};
pub use cruise::CruiseParams;
pub use declaration::ParamSpec;
pub use mpc::{stages_in, CostKind, GridAnchor, MpcParams, NeutralRule, OnInfeasible, StageModel, MAX_PEDAL_LEVELS};
pub use pcc::PccParams;
pub use pi::PiParams;
pub use settings::RunSettings;
pub use sim::SimParams;
pub use spec::{expected_text, join_doc, Bound, Kind, Range};
pub use value::{ParamValue, Value};
pub use vecto::{CrossWind, Mission, VectoParams, TRACTION_INTERRUPTION_RANGE_S};
pub use vehicle::VehicleParams;

use crate::error::CoreResult;

/// A group of declared parameters (a section of the settings).
pub trait ParamSet: Default + Clone {
    /// The section's name (`"mpc"`).
    const SECTION: &'static str;
    /// The declarations, in order.
    fn specs() -> Vec<ParamSpec>;
    /// Set `key` from a user value, checking its type and range. `Ok(false)` if the key is not
    /// of this section.
    fn set(&mut self, key: &str, value: &Value) -> CoreResult<bool>;
    /// The value of `key` as a user would write it; `None` if the key is not of this section.
    fn get(&self, key: &str) -> Option<Value>;
    /// Check every field against its declared range (for structs built in Rust).
    fn check_ranges(&self) -> CoreResult<()>;
}

/// Declare a section of parameters: a struct, its `Default`, and its [`ParamSet`] impl.
///
/// ```ignore
/// declare_params! {
///     /// Simulation settings.
///     pub struct SimParams in "sim" {
///         /// Time step of the plant's RK4 integration.
///         plant_dt_s: f64 = 0.05, unit "s", range Range::FRACTION;
///     }
/// }
/// ```
#[macro_export]
macro_rules! declare_params {
    (
        $(#[doc = $sdoc:literal])*
        pub struct $name:ident in $section:literal {
            $(
                $(#[doc = $doc:literal])+
                $field:ident : $ty:ty = $default:expr, unit $unit:literal, range $range:expr;
            )+
        }
    ) => {
        $(#[doc = $sdoc])*
        #[derive(Debug, Clone, PartialEq)]
        pub struct $name {
            $( $(#[doc = $doc])+ #[doc = concat!("\n\nUnit: ", $unit, ".")] pub $field: $ty, )+
        }

        impl Default for $name {
            fn default() -> Self {
                Self { $( $field: $default, )+ }
            }
        }

        impl $crate::params::ParamSet for $name {
            const SECTION: &'static str = $section;

            fn specs() -> Vec<$crate::params::ParamSpec> {
                use $crate::params::ParamValue;
                let defaults = Self::default();
                vec![$(
                    $crate::params::ParamSpec {
                        name: stringify!($field),
                        section: $section,
                        kind: <$ty as $crate::params::ParamValue>::KIND,
                        unit: $unit,
                        doc: $crate::params::join_doc(&[$($doc),+]),
                        range: $range,
                        default: defaults.$field.to_value(),
                    },
                )+]
            }

            fn set(&mut self, key: &str, value: &$crate::params::Value) -> $crate::error::CoreResult<bool> {
                match key {
                    $( stringify!($field) => {
                        self.$field = <$ty as $crate::params::ParamValue>::from_value(key, value, &$range)?;
                        Ok(true)
                    } )+
                    _ => Ok(false),
                }
            }

            fn get(&self, key: &str) -> Option<$crate::params::Value> {
                use $crate::params::ParamValue;
                match key {
                    $( stringify!($field) => Some(self.$field.to_value()), )+
                    _ => None,
                }
            }

            fn check_ranges(&self) -> $crate::error::CoreResult<()> {
                use $crate::params::ParamValue;
                $( self.$field.check(stringify!($field), &$range)?; )+
                Ok(())
            }
        }
    };
}
