//! The cost-to-go of every state of every stage, kept by a whole-road solve: the table the
//! whole-road optimum ([`crate::control::RecedingController::whole_road`]) reads to choose each
//! stage's control from the truck's measured state with a one-stage solve.

/// One stage's grid and the optimal cost-to-go and shift counter of each of its states.
#[derive(Debug, Clone, Default)]
pub struct StageValues {
    /// Speed of grid index 0 [m/s] and the grid step [m/s].
    pub origin_mps: f64,
    pub delta_mps: f64,
    /// Grid index of the stage's first speed, and the number of speeds.
    pub first: i64,
    pub count: usize,
    /// Per gear, the inclusive range of speeds (0-based in the stage) with a state; empty when
    /// lo > hi.
    pub ranges: Vec<(u32, u32)>,
    /// Per gear, where its range starts in `cost` and `counter`.
    offsets: Vec<usize>,
    /// Cost-to-go J_k of each state (+∞ where no admissible path continues).
    cost: Vec<f64>,
    /// Stages until the next shift on each state's optimal continuation.
    counter: Vec<u32>,
}

impl StageValues {
    /// An empty stage for `ranges`; fill each gear with [`StageValues::set_gear`].
    pub fn new(origin_mps: f64, delta_mps: f64, first: i64, count: usize, ranges: &[(u32, u32)]) -> Self {
        let mut offsets = Vec::with_capacity(ranges.len());
        let mut total = 0;
        for &(lo, hi) in ranges {
            offsets.push(total);
            total += if hi >= lo { (hi - lo + 1) as usize } else { 0 };
        }
        StageValues {
            origin_mps,
            delta_mps,
            first,
            count,
            ranges: ranges.to_vec(),
            offsets,
            cost: vec![f64::INFINITY; total],
            counter: vec![0; total],
        }
    }

    /// Set the values of `gear`'s states from slices over its whole range.
    pub fn set_gear(&mut self, gear: usize, cost: &[f64], counter: &[u32]) {
        let at = self.offsets[gear];
        self.cost[at..at + cost.len()].copy_from_slice(cost);
        self.counter[at..at + counter.len()].copy_from_slice(counter);
    }

    /// (cost-to-go, counter) of the state (gear, speed j of the stage); None outside its range.
    #[inline]
    pub fn get(&self, gear: usize, j: usize) -> Option<(f64, u32)> {
        let (lo, hi) = *self.ranges.get(gear)?;
        if hi < lo || j < lo as usize || j > hi as usize {
            return None;
        }
        let at = self.offsets[gear] + j - lo as usize;
        Some((self.cost[at], self.counter[at]))
    }

    /// Bytes held by the values: 8 of cost and 4 of counter a state, a range and an offset a gear.
    pub fn bytes(&self) -> usize {
        self.cost.len() * (size_of::<f64>() + size_of::<u32>())
            + self.ranges.len() * (size_of::<(u32, u32)>() + size_of::<usize>())
    }
}

/// The values of a whole-road solve, stage k of the road at index k (0 is the start state).
#[derive(Debug, Clone, Default)]
pub struct ValueTable {
    pub stages: Vec<StageValues>,
}

impl ValueTable {
    /// Bytes held by the stages' values.
    pub fn bytes(&self) -> usize {
        self.stages.iter().map(StageValues::bytes).sum()
    }
}
