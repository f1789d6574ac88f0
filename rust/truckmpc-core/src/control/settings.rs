//! Parameters of the built-in PI controller and of the closed-loop simulation, as plain structs.

/// The PI cruise controller (thesis section 2.5, tables A.3 and A.4). Speeds in km/h, gains per
/// km/h, integrator states and their clamps in km/h·s; gear thresholds [rpm] per forward gear,
/// lowest first, `None` where a gear has no lower (gear 1) or higher (top gear) neighbour.
#[derive(Debug, Clone, PartialEq)]
pub struct PiParams {
    pub v_ref_kmh: f64,
    pub v_inc_kmh: f64,
    pub pedal_kp: f64,
    pub pedal_ki: f64,
    pub pedal_integrator_limit: f64,
    pub brake_kp: f64,
    pub brake_ki: f64,
    pub brake_integrator_limit: f64,
    pub gear_down_rpm: Vec<Option<f64>>,
    pub gear_up_rpm: Vec<Option<f64>>,
}

/// Closed-loop simulation settings: the plant's RK4 step [s], the trace's sample spacing [m] and
/// the speed at the road's start [km/h] (`None`: the PI's v_ref).
#[derive(Debug, Clone, PartialEq)]
pub struct SimParams {
    pub plant_dt_s: f64,
    pub trace_step_m: f64,
    pub start_speed_kmh: Option<f64>,
}
