//! The keys of a truck read from VECTO's files (a `.vecto` job or a declaration XML): what
//! declaration mode adds to the components (mission, load, trailer, cross wind, auxiliaries), the
//! driveline losses where the job gives no loss map, and a battery's state of charge at the start. With the thesis's truck they keep their
//! defaults.

use super::Range;
use crate::{choice_enum, declare_params};

/// The longest a gear shift may interrupt traction [s].
pub const TRACTION_INTERRUPTION_RANGE_S: Range = Range::between(0.0, 10.0);

choice_enum! {
    /// VECTO's mission profile, which picks the vehicle group's trailer and reference load.
    pub enum Mission {
        /// Long haul.
        LongHaul = "LongHaul",
    }
}

choice_enum! {
    /// VECTO's speed-dependent cross-wind correction of the drag area.
    pub enum CrossWind {
        /// A 3 m/s wind from every direction with VECTO 3's parameters (2017).
        Vecto3 = "vecto3",
        /// The wind growing with height over the vehicle's height (VECTO since about 2019).
        HeightProfile = "height_profile",
        /// The declared Cd·A at every speed.
        NoCorrection = "none",
    }
}

declare_params! {
    /// A VECTO truck's keys. Null: VECTO's value for this truck or the value its files give.
    pub struct VectoParams in "vecto" {
        /// VECTO mission profile, which picks the group's standard trailer and reference load.
        mission: Mission = Mission::LongHaul, unit "-", range Range::ANY;
        /// Load; null: the group's reference load on the mission (VECTO's value for this truck).
        payload_kg: Option<f64> = None, unit "kg", range Range::between(0.0, 1e6);
        /// Mass of the trailer; null: the group's standard trailer (VECTO's value for this truck).
        trailer_mass_kg: Option<f64> = None, unit "kg", range Range::between(0.0, 1e6);
        /// Cross-wind correction of the drag area: vecto3 (VECTO 3's), height_profile (VECTO's since 2019) or none.
        cross_wind: CrossWind = CrossWind::Vecto3, unit "-", range Range::ANY;
        /// Auxiliary power; null: VECTO's for the job's technologies.
        aux_power_w: Option<f64> = None, unit "W", range Range::between(0.0, 1e6);
        /// Gearbox efficiency where the job gives no loss maps (fitted on VECTO's generic tractor).
        gear_efficiency: f64 = 1.0 - 0.04541, unit "-", range Range::FRACTION;
        /// Axle efficiency where the job gives no axle loss map.
        axle_efficiency: f64 = 1.0, unit "-", range Range::FRACTION;
        /// Driveline drag torque at the gearbox input where the job gives no loss maps (fitted on VECTO's generic tractor).
        loss_torque_nm: f64 = 102.33 / (1.0 - 0.04541), unit "Nm", range Range::between(0.0, 1e5);
        /// Use the job's loss maps where it gives them (false: the affine losses above everywhere).
        use_loss_maps: bool = true, unit "-", range Range::ANY;
        /// How long a gear shift interrupts traction; null: the gearbox file's value (TracInt).
        traction_interruption_s: Option<f64> = None, unit "s", range TRACTION_INTERRUPTION_RANGE_S;
        /// State of charge a battery-electric truck starts from; null: the middle of its usable window (VECTO's declaration run).
        soc_start_pct: Option<f64> = None, unit "%", range Range::between(0.0, 100.0);
    }
}
