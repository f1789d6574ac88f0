//! The longitudinal truck model of the thesis, chapter 2 and appendix B.1: engine fits (2.3)–(2.8),
//! stiff driveline with gearbox and final drive, air drag, rolling resistance and gravity, in the
//! compact form (B.1), fuel mass flow (B.2) and engine speed (2.9).
//!
//! Units: speeds in m/s, engine speed in rpm, torque in Nm, fuel in g, fueling in mg/stroke,
//! slope as a grade (Δh/ΔL, dimensionless) used directly as the angle α.

use super::interface::{AffineAccel, Control, EnergyStore, Powertrain, RateForm, NEUTRAL};
use crate::error::CoreResult;
use crate::params::{ParamSet, VehicleParams};

/// The gear-dependent constants of (B.1): c1 [m/(kg m²)·...] so that dv/dt = c1·(torque sum) in m/s²,
/// c3 = η_t i_t η_f i_f [-] and c4 = 30 i_t i_f / (π r_w) [rpm per m/s]. Neutral has c3 = c4 = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GearConstants {
    /// r_w / (J_w + m r_w² + η_t i_t² η_f i_f² J_e) [1/(kg m)].
    pub c1: f64,
    /// Torque gain from engine to wheel η_t i_t η_f i_f [-].
    pub c3: f64,
    /// Engine speed per vehicle speed 30 i_t i_f / (π r_w) [rpm/(m/s)].
    pub c4: f64,
}

/// The thesis's truck, validated, with the constants of (B.1) precomputed.
#[derive(Debug, Clone)]
pub struct ThesisModel {
    params: VehicleParams,
    gears: Vec<GearConstants>,
    /// ½ c_w A_a ρ_a r_w [N m s²/m²].
    c2: f64,
    /// n_cyl / (6·10⁴ n_r): fuel flow [g/s] per rpm·mg/stroke.
    c5: f64,
    /// m g r_w sqrt(1 + c_r²) [Nm].
    c6: f64,
    /// arctan c_r [rad].
    c7: f64,
}

impl ThesisModel {
    /// Validate the parameters and precompute the model constants.
    pub fn new(params: VehicleParams) -> CoreResult<Self> {
        params.check_ranges()?;
        params.check_gearbox()?;
        let p = &params;
        let base_inertia = p.wheel_inertia_kgm2 + p.mass_kg * p.wheel_radius_m.powi(2);
        let mut gears = vec![GearConstants { c1: p.wheel_radius_m / base_inertia, c3: 0.0, c4: 0.0 }];
        for (&i_t, &eta_t) in p.gear_ratios.iter().zip(&p.gear_efficiencies) {
            let i_f = p.final_drive_ratio;
            let reflected = eta_t * i_t * i_t * p.final_drive_efficiency * i_f * i_f * p.engine_inertia_kgm2;
            gears.push(GearConstants {
                c1: p.wheel_radius_m / (base_inertia + reflected),
                c3: eta_t * i_t * p.final_drive_efficiency * i_f,
                c4: 30.0 * i_t * i_f / (std::f64::consts::PI * p.wheel_radius_m),
            });
        }
        let c2 = 0.5 * p.air_drag_coefficient * p.frontal_area_m2 * p.air_density_kgpm3 * p.wheel_radius_m;
        let c5 = p.cylinders / (6.0e4 * p.revolutions_per_stroke);
        let c6 = p.mass_kg * p.gravity_mps2 * p.wheel_radius_m * (1.0 + p.rolling_resistance.powi(2)).sqrt();
        let c7 = p.rolling_resistance.atan();
        Ok(ThesisModel { params, gears, c2, c5, c6, c7 })
    }

    /// The parameters this model was built from.
    pub fn params(&self) -> &VehicleParams {
        &self.params
    }

    /// The (B.1) constants of every gear, neutral first.
    pub fn gears(&self) -> &[GearConstants] {
        &self.gears
    }

    /// Air drag constant c2 of (B.1) [N m s²/m²]: air drag torque at the wheel is c2·v².
    #[inline]
    pub fn c2(&self) -> f64 {
        self.c2
    }

    /// Fuel constant c5 of (B.2): mass flow [g/s] = c5 · N [rpm] · δ [mg/stroke].
    #[inline]
    pub fn c5(&self) -> f64 {
        self.c5
    }

    /// Upper fueling bound δ_max(N) (2.6) [mg/stroke], never below zero (the fit turns negative near
    /// 2500 rpm, where no fuel can be injected).
    #[inline]
    pub fn fueling_max_mg(&self, n_rpm: f64) -> f64 {
        let p = &self.params;
        (p.fueling_max_a_mg_per_rpm2 * n_rpm * n_rpm + p.fueling_max_b_mg_per_rpm * n_rpm + p.fueling_max_c_mg).max(0.0)
    }

    /// d δ_max / dN [mg/(stroke·rpm)], zero where the bound is clamped.
    #[inline]
    fn fueling_max_slope(&self, n_rpm: f64) -> f64 {
        let p = &self.params;
        if self.fueling_max_mg(n_rpm) > 0.0 {
            2.0 * p.fueling_max_a_mg_per_rpm2 * n_rpm + p.fueling_max_b_mg_per_rpm
        } else {
            0.0
        }
    }

    /// Drag torque T_drag(N) (2.4) [Nm], the engine torque at fuel cut (negative).
    #[inline]
    pub fn drag_torque_nm(&self, n_rpm: f64) -> f64 {
        self.params.drag_torque_a_nm_per_rpm * n_rpm + self.params.drag_torque_b_nm
    }

    /// Engine torque (2.8) [Nm]: the map at fueling P·δ_max(N) for P > 0, the drag torque for
    /// P ≤ 0 (the jump between the two at P = 0 is the thesis's), zero in neutral. The upper torque
    /// bound is the map at δ_max (2.7), so it needs no separate clamp.
    #[inline]
    pub fn engine_torque_nm(&self, n_rpm: f64, pedal: f64, gear: usize) -> f64 {
        let p = &self.params;
        if gear == NEUTRAL {
            0.0
        } else if pedal > 0.0 {
            p.torque_map_a_nm_per_rpm * n_rpm
                + p.torque_map_b_nm_stroke_per_mg * pedal * self.fueling_max_mg(n_rpm)
                + p.torque_map_c_nm
        } else {
            self.drag_torque_nm(n_rpm)
        }
    }

    /// Fuel mass flow (B.2) [g/s]: c5·N·P·δ_max(N) in gear (zero at fuel cut), idle fueling in neutral.
    #[inline]
    pub fn fuel_rate_gps(&self, v_mps: f64, pedal: f64, gear: usize) -> f64 {
        if gear == NEUTRAL {
            self.c5 * self.params.idle_speed_rpm * self.params.idle_fueling_mg_per_stroke
        } else if pedal > 0.0 {
            let n = self.gears[gear].c4 * v_mps;
            self.c5 * n * pedal * self.fueling_max_mg(n)
        } else {
            0.0
        }
    }

    /// Brake force at the wheel contact [N] for brake level B.
    #[inline]
    pub fn brake_force_n(&self, brake: f64) -> f64 {
        self.params.brake_torque_max_nm * brake / self.params.wheel_radius_m
    }

    /// Highest engine speed [rpm] at which fuel can still be injected: the upper root of the fueling
    /// bound (2.6) (about 2500 rpm for the thesis's engine); infinite if the bound never closes.
    pub fn max_engine_speed_rpm(&self) -> f64 {
        let p = &self.params;
        let (a, b, c) = (p.fueling_max_a_mg_per_rpm2, p.fueling_max_b_mg_per_rpm, p.fueling_max_c_mg);
        let discriminant = b * b - 4.0 * a * c;
        if a >= 0.0 || discriminant < 0.0 {
            return f64::INFINITY;
        }
        (-b - discriminant.sqrt()) / (2.0 * a)
    }
}

impl Powertrain for ThesisModel {
    fn forward_gears(&self) -> usize {
        self.gears.len() - 1
    }

    /// Engine speed (2.9) [rpm]: c4·v in gear, idle speed in neutral.
    #[inline]
    fn engine_speed_rpm(&self, v_mps: f64, gear: usize) -> f64 {
        if gear == NEUTRAL {
            self.params.idle_speed_rpm
        } else {
            self.gears[gear].c4 * v_mps
        }
    }

    /// The speed at which the lowest gear turns the engine at idle (the model has no clutch slip).
    fn stall_speed_mps(&self) -> f64 {
        self.params.idle_speed_rpm / self.gears[1].c4
    }

    /// The thesis's gearbox shifts instantly.
    #[inline]
    fn traction_interruption_s(&self) -> f64 {
        0.0
    }

    #[inline]
    fn interrupted_energy_rate(&self, _v_mps: f64) -> f64 {
        0.0
    }

    /// c6 sin(α + c7) [Nm], the slope taken as the angle.
    #[inline]
    fn slope_torque_nm(&self, grade: f64) -> f64 {
        self.c6 * (grade + self.c7).sin()
    }

    /// The fuelled branch of (2.8); `gain` is zero where δ_max(N) is zero.
    #[inline]
    fn pedal_affine(&self, v_mps: f64, gear: usize, slope_torque_nm: f64) -> AffineAccel {
        debug_assert!(gear != NEUTRAL);
        let g = self.gears[gear];
        let p = &self.params;
        let n = g.c4 * v_mps;
        let load = self.c2 * v_mps * v_mps + slope_torque_nm;
        AffineAccel {
            accel_at_zero: g.c1 * (g.c3 * (p.torque_map_a_nm_per_rpm * n + p.torque_map_c_nm) - load),
            gain: g.c1 * g.c3 * p.torque_map_b_nm_stroke_per_mg * self.fueling_max_mg(n),
        }
    }

    /// At fuel cut (drag torque) in a gear, or coasting in neutral.
    #[inline]
    fn brake_affine(&self, v_mps: f64, gear: usize, slope_torque_nm: f64) -> AffineAccel {
        let g = self.gears[gear];
        let drag = if gear == NEUTRAL { 0.0 } else { self.drag_torque_nm(g.c4 * v_mps) };
        let load = self.c2 * v_mps * v_mps + slope_torque_nm;
        AffineAccel { accel_at_zero: g.c1 * (g.c3 * drag - load), gain: -g.c1 * self.params.brake_torque_max_nm }
    }

    /// (B.1).
    #[inline]
    fn accel_on(&self, v_mps: f64, pedal: f64, brake: f64, gear: usize, slope_torque_nm: f64) -> f64 {
        let g = self.gears[gear];
        let torque = if gear == NEUTRAL { 0.0 } else { self.engine_torque_nm(g.c4 * v_mps, pedal, gear) };
        g.c1 * (g.c3 * torque - self.params.brake_torque_max_nm * brake - self.c2 * v_mps * v_mps - slope_torque_nm)
    }

    /// The derivative of (B.1) in the speed.
    fn accel_derivative_per_s(&self, v_mps: f64, pedal: f64, gear: usize) -> f64 {
        let g = self.gears[gear];
        let p = &self.params;
        let dtorque_dn = if gear == NEUTRAL {
            0.0
        } else if pedal > 0.0 {
            p.torque_map_a_nm_per_rpm + p.torque_map_b_nm_stroke_per_mg * pedal * self.fueling_max_slope(g.c4 * v_mps)
        } else {
            p.drag_torque_a_nm_per_rpm
        };
        g.c1 * (g.c3 * dtorque_dn * g.c4 - 2.0 * self.c2 * v_mps)
    }

    /// Fuel (B.2) [g/s]; the brakes take nothing back.
    #[inline]
    fn energy_rate(&self, v_mps: f64, u: Control) -> f64 {
        self.fuel_rate_gps(v_mps, u.pedal, u.gear)
    }

    #[inline]
    fn friction_brake_force_n(&self, _v_mps: f64, u: Control) -> f64 {
        self.brake_force_n(u.brake)
    }

    fn rate_form(&self) -> RateForm {
        RateForm::ProportionalToPedal
    }

    /// The thesis's engine jumps from the torque map to its drag torque at P = 0.
    fn zero_pedal_is_cut(&self) -> bool {
        false
    }

    /// Torque and fuel are both affine in fueling at a fixed engine speed, so every unit of ½v²
    /// costs c5·c4 / (c1·c3·b) grams whatever the speed and load (b the torque map's fueling
    /// coefficient).
    fn kinetic_energy_price(&self, gear: usize) -> Option<f64> {
        let g = self.gears[gear];
        Some(self.c5 * g.c4 / (g.c1 * g.c3 * self.params.torque_map_b_nm_stroke_per_mg))
    }

    fn store(&self) -> EnergyStore {
        EnergyStore::FuelTank
    }
}
