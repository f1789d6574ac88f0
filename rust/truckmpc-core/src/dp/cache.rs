//! Transition costs of one stage, kept across solves on a fixed (absolute) velocity grid.
//!
//! Successive receding-horizon solves share most of their stages: a stage at absolute road position
//! k is solved by every horizon that covers it. A row of costs depends only on the stage's
//! [`StageKey`] (its slope, the two grids it joins and the next stage's v_max), the velocity index
//! and the target gear, so it is computed once and reused by every stage with that key, in this
//! solve or a later one (`cache/stages.rs`); stages behind the vehicle are dropped. On a fixed grid
//! the grids never change. On a moving grid each stage's grid starts at its lower bound, which
//! changes with the start speed, but is most often the same from one solve to the next (clamped at
//! v_min, or carried by the same chain of bounds): a stage whose key changed takes its new key's
//! rows. A solve without the cache (the first stage, whose grid is the start speed, or a horizon
//! off the stage boundaries) fills a scratch [`StageRows`] the same way; the whole-road plan keeps
//! its stages' rows by key instead ([`RecentRows`]).
//!
//! Layout: per target gear, blocks of `LANES` consecutive source velocities whose rows are stored
//! transposed ([`Block`]), because the DP's first pass walks one target gear at a time over all
//! source velocities, a block per SIMD step.

use super::rows::RowSpan;

mod recent;
mod stages;

pub use self::recent::RecentRows;
pub use self::stages::RowCache;

/// Values for a contiguous range of source keys (grid indices), grown at either end on demand.
/// The buffer keeps slack in front of the first value, so growing downwards (the usual way a
/// stage's range moves between solves) does not move the values.
#[derive(Debug, Clone)]
pub struct Keyed<T> {
    /// Key of `data[start]`.
    key_lo: i64,
    start: usize,
    data: Vec<T>,
}

impl<T> Default for Keyed<T> {
    fn default() -> Self {
        Keyed { key_lo: 0, start: 0, data: Vec::new() }
    }
}

/// Slack kept in front of the first value when the buffer is (re)built.
const FRONT_SLACK: usize = 32;

impl<T> Keyed<T> {
    /// The memory the values hold [bytes].
    fn bytes(&self) -> usize {
        self.data.capacity() * std::mem::size_of::<T>()
    }
}

impl<T: Copy + Default> Keyed<T> {
    fn clear(&mut self) {
        self.data.clear();
        self.start = 0;
    }

    fn len(&self) -> usize {
        self.data.len() - self.start
    }

    /// Make sure keys `lo..=hi` have values, computing the missing ones with `make` (a request
    /// that leaves a gap to the present range fills the gap too, so the range stays contiguous).
    /// Returns how many values were computed.
    pub fn fill(&mut self, lo: i64, hi: i64, mut make: impl FnMut(i64) -> T) -> u64 {
        if self.len() == 0 {
            self.data.clear();
            self.data.resize(FRONT_SLACK, T::default());
            self.start = FRONT_SLACK;
            self.key_lo = lo;
            self.data.extend((lo..=hi).map(&mut make));
            return (hi - lo + 1) as u64;
        }
        let present_hi = self.key_lo + self.len() as i64 - 1;
        let mut computed = 0;
        if lo < self.key_lo {
            let missing = (self.key_lo - lo) as usize;
            if missing > self.start {
                // Rebuild with fresh slack in front.
                let mut data = vec![T::default(); missing + FRONT_SLACK];
                data.extend_from_slice(&self.data[self.start..]);
                self.start = missing + FRONT_SLACK;
                self.data = data;
            }
            self.start -= missing;
            for (slot, key) in self.data[self.start..self.start + missing].iter_mut().zip(lo..) {
                *slot = make(key);
            }
            self.key_lo = lo;
            computed += missing as u64;
        }
        if hi > present_hi {
            self.data.extend((present_hi + 1..=hi).map(&mut make));
            computed += (hi - present_hi) as u64;
        }
        computed
    }

    /// The value of `key` if it has been filled.
    #[inline]
    pub fn at(&self, key: i64) -> Option<&T> {
        let offset = key.checked_sub(self.key_lo)?;
        (offset >= 0 && (offset as usize) < self.len()).then(|| &self.data[self.start + offset as usize])
    }

    /// The values of keys `lo..=hi` (which must have been filled).
    #[inline]
    pub fn get(&self, lo: i64, hi: i64) -> &[T] {
        let at = self.start as i64 - self.key_lo;
        &self.data[(at + lo) as usize..=(at + hi) as usize]
    }
}

/// Source velocities per block: the min-plus pass runs the rows of this many consecutive source
/// velocities side by side, one per SIMD lane.
pub const LANES: usize = 4;

/// Margin of +∞ values on each side of a gear's block of cost-to-go values: a block whose reach
/// starts up to this many grid points before the next grid (and ends within as many after it)
/// needs no clipping.
pub const PAD: usize = 24;

/// One block of rows: the transition costs from `LANES` consecutive source velocities (keys
/// `LANES·b ..`) towards one target gear, transposed so that each step of the min-plus pass
/// loads one cost per lane. Lane l at step d targets next-grid index `first + l + d`: as the
/// source speed rises by one grid step, so does the band it reaches, so one diagonal band holds
/// every lane's row with little waste. Costs where a lane's row has no admissible target are +∞.
#[derive(Debug, Clone, Copy, Default)]
pub struct Block {
    /// Next-grid index targeted by lane 0 at step 0.
    pub first: i32,
    /// Number of steps d.
    pub steps: u32,
    /// Start of the block's `steps × LANES` costs in the cost buffer.
    pub offset: u32,
    /// Per lane, its row's span on the next grid: (first index, length).
    pub spans: [(i32, u32); LANES],
    /// Sum of the lanes' lengths: the block's transitions when all its targets are states.
    pub reach: u32,
}

/// The row blocks of one stage towards one forward target gear, keyed by block index.
#[derive(Debug, Clone, Default)]
pub struct GearBlocks {
    pub blocks: Keyed<Block>,
    pub costs: Vec<f64>,
}

/// Buffers for building blocks, kept by the solver so that filling allocates nothing.
#[derive(Debug, Clone, Default)]
pub struct RowScratch {
    /// A block's rows end to end, before transposing.
    rows: Vec<f64>,
}

impl GearBlocks {
    /// Make sure the blocks holding source keys `lo..=hi` exist; `row(key, out)` appends one
    /// row's costs to `out` and returns its span and where its first cost is in `out`. Returns the
    /// rows computed.
    pub fn fill(
        &mut self,
        lo: i64,
        hi: i64,
        scratch: &mut RowScratch,
        mut row: impl FnMut(i64, &mut Vec<f64>) -> (RowSpan, usize),
    ) -> u64 {
        let costs = &mut self.costs;
        let lanes = LANES as i64;
        let mut spans = [(RowSpan::default(), 0usize); LANES];
        LANES as u64
            * self.blocks.fill(lo.div_euclid(lanes), hi.div_euclid(lanes), |b| {
                scratch.rows.clear();
                for (l, slot) in spans.iter_mut().enumerate() {
                    *slot = row(b * lanes + l as i64, &mut scratch.rows);
                }
                transpose(&spans, &scratch.rows, costs)
            })
    }

    /// The blocks holding source keys `lo..=hi` (filled before), the first block's first key.
    #[inline]
    pub fn get(&self, lo: i64, hi: i64) -> (&[Block], i64) {
        let lanes = LANES as i64;
        (self.blocks.get(lo.div_euclid(lanes), hi.div_euclid(lanes)), lo.div_euclid(lanes) * lanes)
    }
}

/// Append the rows of one block (spans and where each row starts in `row_costs`) to `costs`,
/// transposed onto the block's diagonal band; returns the block.
fn transpose(rows: &[(RowSpan, usize); LANES], row_costs: &[f64], costs: &mut Vec<f64>) -> Block {
    let spans = std::array::from_fn(|l| (rows[l].0.first as i32, rows[l].0.len as u32));
    // The band: from the lowest lane start to the highest lane end, both shifted by the lane.
    let (mut first, mut end) = (i64::MAX, i64::MIN);
    for (l, (span, _)) in rows.iter().enumerate() {
        if span.len > 0 {
            first = first.min(span.first - l as i64);
            end = end.max(span.first - l as i64 + span.len as i64);
        }
    }
    if first > end {
        return Block { first: 0, steps: 0, offset: costs.len() as u32, spans, reach: 0 };
    }
    let steps = (end - first) as usize;
    let offset = costs.len();
    costs.resize(offset + steps * LANES, f64::INFINITY);
    let band = &mut costs[offset..];
    for (l, &(span, start)) in rows.iter().enumerate() {
        if span.len > 0 {
            let d0 = (span.first - l as i64 - first) as usize;
            let lane = band[d0 * LANES + l..].iter_mut().step_by(LANES);
            for (slot, &cost) in lane.zip(&row_costs[start..start + span.len]) {
                *slot = cost;
            }
        }
    }
    let reach = rows.iter().map(|(span, _)| span.len as u32).sum();
    Block { first: first as i32, steps: steps as u32, offset: offset as u32, spans, reach }
}

/// A coasting arc from one source speed (neutral, or fuel cut in a forward gear): where it ends and
/// the part of its cost that does not depend on the cost-to-go (fuel and speed change). `repr(C)`:
/// the solver loads four arcs as two pairs of (end speed, cost).
#[derive(Debug, Clone, Copy, Default)]
#[repr(C)]
pub struct CoastArc {
    /// End speed after the stage [m/s].
    pub v_end_mps: f64,
    /// Q1·fuel + Q3·|Δv|.
    pub cost: f64,
}

/// What a stage's rows depend on besides the vehicle and the parameters: the slope, the speeds
/// of the two grids' index 0 and the top of the next stage's band (compared bit for bit).
#[derive(Debug, Clone, Copy, Default)]
pub struct StageKey {
    /// Slope as wheel torque [Nm].
    pub slope_torque_nm: f64,
    /// Speed of grid index 0 at the stage [m/s].
    pub origin_mps: f64,
    /// Speed of grid index 0 at the next stage [m/s].
    pub next_origin_mps: f64,
    /// Top of the next stage's band [m/s] (rows end there, save the brake points next to it).
    pub next_v_max_mps: f64,
}

impl StageKey {
    fn bits(&self) -> [u64; 4] {
        [self.slope_torque_nm, self.origin_mps, self.next_origin_mps, self.next_v_max_mps].map(f64::to_bits)
    }

    fn same(&self, other: &StageKey) -> bool {
        self.bits() == other.bits()
    }
}

/// Everything one stage keeps: its key, its rows per target gear and its coasting arcs.
#[derive(Debug, Clone, Default)]
pub struct StageRows {
    key: StageKey,
    /// Indexed by gear; entry 0 (neutral) is unused.
    gears: Vec<GearBlocks>,
    /// Exact arcs by slot: neutral at 0, then per forward gear g fuel cut at g, full pedal at
    /// gears + g and pedal level l at (l + 1)·gears + g (gears counting neutral), when used.
    arcs: Vec<Keyed<CoastArc>>,
}

impl StageRows {
    /// The memory the rows and arcs hold [bytes] (emptied ones keep theirs for the next key).
    pub fn bytes(&self) -> usize {
        let gears: usize = self.gears.iter().map(|g| g.blocks.bytes() + g.costs.capacity() * size_of::<f64>()).sum();
        gears + self.arcs.iter().map(Keyed::bytes).sum::<usize>()
    }

    /// Empty the stage for a key.
    pub fn reset(&mut self, key: StageKey) {
        self.key = key;
        for rows in &mut self.gears {
            rows.blocks.clear();
            rows.costs.clear();
        }
        for arcs in &mut self.arcs {
            arcs.clear();
        }
    }

    /// The exact arcs of `slot` (the layout of [`StageRows::arcs`]'s field).
    #[inline]
    pub fn arcs(&mut self, slot: usize) -> &mut Keyed<CoastArc> {
        if self.arcs.len() <= slot {
            self.arcs.resize_with(slot + 1, Keyed::default);
        }
        &mut self.arcs[slot]
    }

    /// The row blocks towards forward `gear` with the arcs of two slots (filled or not).
    pub fn gear_with_arcs(&mut self, gear: usize, slots: [usize; 2]) -> (&mut GearBlocks, [&Keyed<CoastArc>; 2]) {
        self.gear(gear);
        self.arcs(slots[0].max(slots[1]));
        (&mut self.gears[gear], slots.map(|slot| &self.arcs[slot]))
    }

    /// The row blocks towards forward `gear`.
    #[inline]
    pub fn gear(&mut self, gear: usize) -> &mut GearBlocks {
        if self.gears.len() <= gear {
            self.gears.resize_with(gear + 1, GearBlocks::default);
        }
        &mut self.gears[gear]
    }
}
