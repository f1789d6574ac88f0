//! What the first pass of a stage leaves for the second (per target gear and source speed, the
//! cheapest way into that gear and its next-grid index), and the decision kept per state for the
//! traceback. Costs are in the units of (5.9), indices are grid indices of the next stage.

use super::INF;
use crate::dp::cache::LANES;
use crate::params::MAX_PEDAL_LEVELS;

/// What the first pass of a stage finds, per target gear and source slot [gear * width + slot]
/// (slot = source grid index − `base_key`, blocks of `LANES` aligned): the cheapest way into that
/// gear (fuel, speed change, brake and cost-to-go; +∞ when none) and the next-stage index it
/// reaches, and the same among targets that allow a shift now.
#[derive(Debug, Clone, Default)]
pub(super) struct Choices {
    pub(super) base_key: i64,
    pub(super) width: usize,
    pub(super) all_cost: Vec<f64>,
    pub(super) all_j: Vec<u32>,
    pub(super) shift_cost: Vec<f64>,
    pub(super) shift_j: Vec<u32>,
    /// For a truck whose gearbox interrupts traction, the same as `shift_cost` and `shift_j` for a
    /// shift from another forward gear: the stage starts with the interruption's roll in neutral
    /// ([`crate::dp::shift`]). Leaving neutral has no interruption and takes `shift_cost`.
    pub(super) ishift_cost: Vec<f64>,
    pub(super) ishift_j: Vec<u32>,
    /// Per slot, the counter of the neutral choice (the interpolating rule takes the smaller of
    /// the two neighbours', so it is not the counter at all_j).
    pub(super) neutral_counter: Vec<u32>,
    /// Per slot, the best and second-best shift targets over all gears: cost and gear.
    pub(super) first_cost: Vec<f64>,
    pub(super) first_gear: Vec<u32>,
    pub(super) second_cost: Vec<f64>,
    pub(super) second_gear: Vec<u32>,
    /// Per slot, the speed-deviation cost Q2·max(v_ref − v, 0)² of the source velocity.
    pub(super) penalty: Vec<f64>,
    /// Per slot, the neutral state's best and second-best shifts when they differ from every
    /// other state's (only the highest usable gear, or leaving neutral free of Q4): cost and gear.
    pub(super) exit_cost: Vec<f64>,
    pub(super) exit_gear: Vec<u32>,
    pub(super) exit2_cost: Vec<f64>,
    pub(super) exit2_gear: Vec<u32>,
}

/// No gear (in the two best shifts).
pub(super) const NO_GEAR: u32 = u32::MAX;

impl Choices {
    /// Room for `gears` target gears and source grid indices `key_lo..=key_hi`.
    pub(super) fn prepare(&mut self, gears: usize, key_lo: i64, key_hi: i64) {
        let lanes = LANES as i64;
        self.base_key = key_lo.div_euclid(lanes) * lanes;
        self.width = (key_hi.div_euclid(lanes) * lanes + lanes - self.base_key) as usize;
        let size = gears * self.width;
        for v in [&mut self.all_cost, &mut self.shift_cost, &mut self.ishift_cost] {
            if v.len() < size {
                v.resize(size, INF);
            }
        }
        for v in [&mut self.all_j, &mut self.shift_j, &mut self.ishift_j] {
            if v.len() < size {
                v.resize(size, 0);
            }
        }
        for v in [&mut self.first_cost, &mut self.second_cost, &mut self.exit_cost, &mut self.exit2_cost] {
            if v.len() < self.width {
                v.resize(self.width, INF);
            }
            v[..self.width].fill(INF);
        }
        for v in [&mut self.first_gear, &mut self.second_gear, &mut self.exit_gear, &mut self.exit2_gear] {
            if v.len() < self.width {
                v.resize(self.width, NO_GEAR);
            }
            v[..self.width].fill(NO_GEAR);
        }
        for v in [&mut self.neutral_counter] {
            if v.len() < self.width {
                v.resize(self.width, 0);
            }
        }
        if self.penalty.len() < self.width {
            self.penalty.resize(self.width, 0.0);
        }
    }
}

/// The decision stored for a state: the next state (grid index, gear) and how the stage is driven
/// (its flag byte: a row, or an exact arc of fuel cut, full pedal or a pedal level). `repr(C)`: the
/// AVX2 second pass writes it as one u32, j in the low half, the gear in the byte above and the top
/// byte of the choice's index (its flag) last.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
#[repr(C)]
pub(super) struct Decision {
    pub(super) j: u16,
    pub(super) gear: u8,
    pub(super) arc: u8,
}

impl Decision {
    /// The decision for a choice's next-grid index `j` (with its flag byte) into `gear`.
    #[inline]
    pub(super) fn new(j: u32, gear: u32) -> Self {
        Decision { j: j as u16, gear: gear as u8, arc: (j >> 24) as u8 }
    }
}

/// Flag on a choice's next-grid index (`all_j`, `shift_j`; its top byte holds the flag): the way
/// into the target gear is its fuel-cut arc, whose end speed is off the grid and whose control is
/// zero pedal and brake; the index is the grid point nearest to the arc's end. Grid indices stay
/// below 2^16.
pub(super) const ARC: u32 = 1 << 24;

/// Flag on a choice's next-grid index: the way into the target gear is its full-pedal arc (a
/// trapezoid stage's), whose end speed is off the grid and whose control is full pedal.
pub(super) const FULL: u32 = 1 << 25;

/// The flag byte of pedal level 1 less one: the way into the target gear is the arc of pedal
/// level l/K (1 ≤ l < K, `pedal_levels`), flagged `(LEVEL0 + l) << 24`.
const LEVEL0: u32 = 2;

// The flag of the most pedal levels `pedal_levels` allows fits the byte.
const _: () = assert!(LEVEL0 + MAX_PEDAL_LEVELS <= u8::MAX as u32);

/// The flag of the arc of pedal level `l` on a choice's next-grid index.
#[inline]
pub(super) fn level_flag(l: u32) -> u32 {
    debug_assert!(l < MAX_PEDAL_LEVELS, "pedal level {l} beyond the flag byte");
    (LEVEL0 + l) << 24
}

/// The pedal level l of a decision's flag byte, if it is a pedal-level arc's.
#[inline]
pub(super) fn level_of(arc: u8) -> Option<u32> {
    (arc as u32 > LEVEL0 && arc as u32 != GLIDE >> 24).then(|| arc as u32 - LEVEL0)
}

/// Flag on a choice's next-grid index: the way into the target gear is its glide arc, whose end
/// speed is off the grid and whose control is the glide pedal at the arc's start speed
/// (`glide_arcs`: a battery-electric truck's machines drawing no electric power).
pub(super) const GLIDE: u32 = 0xff << 24;

// The glide's flag is above every pedal level's.
const _: () = assert!(LEVEL0 + MAX_PEDAL_LEVELS < GLIDE >> 24);

/// Every flag bit of a choice's next-grid index (its top byte).
pub(super) const FLAGS: u32 = 0xff00_0000;
