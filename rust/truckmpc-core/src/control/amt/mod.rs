//! VECTO's gear shifting for a truck with an automated manual gearbox, as VECTO's declaration mode
//! has it: the shift lines computed from the engine and the gearbox ([`polygon`]), their geometry
//! ([`geometry`]), and the classic AMT strategy that shifts by them ([`strategy`]).

pub mod geometry;
pub mod polygon;
pub mod strategy;

#[cfg(test)]
mod tests;

pub use polygon::{ShiftLineInputs, ShiftPolygon};
pub use strategy::{AmtShifter, Request, LOOKAHEAD_M};
