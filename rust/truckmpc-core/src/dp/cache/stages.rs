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
        let reused = if self.idle.len() >= KEPT { self.idle.pop_front() } else { None };
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

#[cfg(test)]
mod tests {
    use super::*;

    fn key(slope_torque_nm: f64, next_v_max_mps: f64) -> StageKey {
        StageKey { slope_torque_nm, origin_mps: 0.0, next_origin_mps: 0.0, next_v_max_mps }
    }

    /// The slot holding a stage's rows: equal slots are shared rows.
    fn rows_of(cache: &mut RowCache, stage: u64) -> usize {
        cache.window[(stage - cache.first_stage) as usize]
    }

    #[test]
    fn stages_share_rows_exactly_when_their_keys_are_equal() {
        let mut cache = RowCache::default();
        let keys = [key(100.0, 25.0), key(-50.0, 25.0), key(100.0, 25.0), key(100.0, 24.0)];
        cache.prepare(10, keys.into_iter());
        assert_eq!(rows_of(&mut cache, 10), rows_of(&mut cache, 12));
        assert_ne!(rows_of(&mut cache, 10), rows_of(&mut cache, 11));
        // Another top of the next band is another key.
        assert_ne!(rows_of(&mut cache, 10), rows_of(&mut cache, 13));
        // The window moves on: stage 10 leaves, stage 12 keeps the shared rows, and a key that
        // comes back after leaving the window finds its rows kept.
        let shared = rows_of(&mut cache, 12);
        cache.prepare(11, [key(-50.0, 25.0), key(100.0, 25.0), key(100.0, 24.0), key(7.0, 25.0)].into_iter());
        assert_eq!(rows_of(&mut cache, 12), shared);
        let gone = rows_of(&mut cache, 14);
        cache.prepare(15, [key(1.0, 25.0), key(2.0, 25.0)].into_iter());
        cache.prepare(17, [key(7.0, 25.0)].into_iter());
        assert_eq!(rows_of(&mut cache, 17), gone);
        // Every slot in use or idle is indexed by its key, and no slot is both.
        assert_eq!(cache.by_key.len(), cache.slots.len());
        assert!(cache.idle.iter().all(|&s| cache.slots[s].uses == 0));
        assert_eq!(cache.slots.iter().map(|s| s.uses as usize).sum::<usize>(), cache.window.len());
    }
}
