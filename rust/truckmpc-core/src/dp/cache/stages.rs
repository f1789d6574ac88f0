//! The cached stages of the solves under way: a window of absolute stages, each pointing at the
//! rows of its [`StageKey`]. Rows depend on the key alone, so stages with the same key (a road's
//! grade is often the same over several stages, and comes back) share one set, and the sets of
//! keys that left the window are kept a while for a key that comes back.

use std::collections::{HashMap, VecDeque};

use super::{StageKey, StageRows};

/// Sets of rows kept for keys no stage of the window uses, at most.
const KEPT: usize = 16;

/// One set of rows and how many stages of the window use it.
#[derive(Debug, Clone, Default)]
struct Slot {
    rows: StageRows,
    uses: u32,
}

/// Cached stages for a window of absolute stages.
#[derive(Debug, Clone, Default)]
pub struct RowCache {
    first_stage: u64,
    /// The slot of each stage of the window, from `first_stage` on.
    window: VecDeque<usize>,
    slots: Vec<Slot>,
    /// The slot holding each key's rows.
    by_key: HashMap<[u64; 4], usize>,
    /// Slots no stage of the window uses, the longest unused first.
    idle: VecDeque<usize>,
    /// Rows computed (cache misses) since creation, for diagnostics.
    pub computed: u64,
}

impl RowCache {
    /// Drop the stages before `stage` and make sure `stage..stage + count` exist with these keys.
    /// A stage whose key changed (another road, or a moving grid that moved) takes its new key's
    /// rows.
    pub fn prepare(&mut self, stage: u64, keys: impl Iterator<Item = StageKey>) {
        while self.first_stage < stage && !self.window.is_empty() {
            let slot = self.window.pop_front().unwrap();
            self.release(slot);
            self.first_stage += 1;
        }
        if self.window.is_empty() || self.first_stage > stage {
            while let Some(slot) = self.window.pop_front() {
                self.release(slot);
            }
            self.first_stage = stage;
        }
        for (k, key) in keys.enumerate() {
            let at = (stage - self.first_stage) as usize + k;
            if at == self.window.len() {
                let slot = self.acquire(key);
                self.window.push_back(slot);
            } else if !self.slots[self.window[at]].rows.key.same(&key) {
                self.release(self.window[at]);
                self.window[at] = self.acquire(key);
            }
        }
    }

    /// The rows of absolute `stage` (`prepare` must have covered it) and the miss counter.
    #[inline]
    pub fn stage(&mut self, stage: u64) -> (&mut StageRows, &mut u64) {
        let slot = self.window[(stage - self.first_stage) as usize];
        (&mut self.slots[slot].rows, &mut self.computed)
    }

    /// The slot of `key`'s rows, one more use of it: the slot already holding them, else an
    /// emptied one (a new slot while fewer than [`KEPT`] are idle, else the longest idle).
    fn acquire(&mut self, key: StageKey) -> usize {
        if let Some(&slot) = self.by_key.get(&key.bits()) {
            if self.slots[slot].uses == 0 {
                let at = self.idle.iter().position(|&s| s == slot).expect("an unused slot is idle");
                self.idle.remove(at);
            }
            self.slots[slot].uses += 1;
            return slot;
        }
        let reused = if self.idle.len() > KEPT { self.idle.pop_front() } else { None };
        let slot = match reused {
            Some(slot) => {
                self.by_key.remove(&self.slots[slot].rows.key.bits());
                slot
            }
            None => {
                self.slots.push(Slot::default());
                self.slots.len() - 1
            }
        };
        self.slots[slot].rows.reset(key);
        self.slots[slot].uses = 1;
        self.by_key.insert(key.bits(), slot);
        slot
    }

    fn release(&mut self, slot: usize) {
        self.slots[slot].uses -= 1;
        if self.slots[slot].uses == 0 {
            self.idle.push_back(slot);
        }
    }
}
