//! Rows of the whole-road plan's stages (a solve off the window of absolute stages), kept by key
//! within a memory budget, the least recently used replaced first. A road's grades come back (the
//! US long-haul road's 32 184 stages of 25 m have 2 278 distinct grades), so the plan computes most
//! keys' rows once instead of once a stage.

use std::collections::HashMap;

use super::{StageKey, StageRows};

/// The memory the kept rows may hold before the least recently used set is reused [bytes] (256 MiB;
/// the set being filled when it is reached comes on top): about 1 100 sets of a 12-gear truck's
/// rows at δ 0.05 km/h, which take the whole-road solve of the US long-haul road from 32 184
/// stages' rows computed to about 4 300.
const BUDGET_BYTES: usize = 256 << 20;

/// Rows by key, for stages solved off the window.
#[derive(Debug, Clone, Default)]
pub struct RecentRows {
    slots: Vec<StageRows>,
    /// When each slot was last asked for (a count of requests).
    last_use: Vec<u64>,
    /// Each slot's memory when last measured [bytes], and their sum.
    bytes: Vec<usize>,
    total_bytes: usize,
    by_key: HashMap<[u64; 4], usize>,
    requests: u64,
    /// The slot handed out last: its rows have grown since.
    last: Option<usize>,
}

impl RecentRows {
    /// The rows of `key`: those kept for it, else an emptied set (a new one while the kept sets
    /// hold less than [`BUDGET_BYTES`], else the least recently used one's).
    pub fn rows(&mut self, key: StageKey) -> &mut StageRows {
        self.requests += 1;
        if let Some(last) = self.last {
            let now = self.slots[last].bytes();
            self.total_bytes = self.total_bytes + now - self.bytes[last];
            self.bytes[last] = now;
        }
        let slot = match self.by_key.get(&key.bits()) {
            Some(&slot) => slot,
            None => self.emptied(key),
        };
        self.last_use[slot] = self.requests;
        self.last = Some(slot);
        &mut self.slots[slot]
    }

    /// A slot emptied for `key`.
    fn emptied(&mut self, key: StageKey) -> usize {
        let slot = if self.total_bytes < BUDGET_BYTES || self.slots.is_empty() {
            self.slots.push(StageRows::default());
            self.last_use.push(0);
            self.bytes.push(0);
            self.slots.len() - 1
        } else {
            let (oldest, _) = self.last_use.iter().enumerate().min_by_key(|&(_, used)| *used).expect("a slot");
            self.by_key.remove(&self.slots[oldest].key.bits());
            oldest
        };
        self.slots[slot].reset(key);
        self.by_key.insert(key.bits(), slot);
        slot
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(slope_torque_nm: f64) -> StageKey {
        StageKey { slope_torque_nm, origin_mps: 0.0, next_origin_mps: 0.0, next_v_max_mps: 25.0 }
    }

    /// Rows of a megabyte each: the budget keeps 256 sets.
    fn grow(rows: &mut StageRows) {
        rows.gear(1).costs.reserve_exact((1 << 20) / size_of::<f64>());
    }

    /// A key asked for again finds its rows (the same set, not emptied); once the budget is full, a
    /// new key takes the set of the least recently used one, and a key used in between stays.
    #[test]
    fn a_key_keeps_its_rows_until_the_budget_is_full_and_others_were_used_after_it() {
        let mut recent = RecentRows::default();
        let first: *const StageRows = recent.rows(key(1.0));
        grow(recent.rows(key(1.0)));
        assert!(std::ptr::eq(first, recent.rows(key(1.0))));
        let kept = BUDGET_BYTES >> 20;
        for n in 1..kept {
            grow(recent.rows(key(100.0 + n as f64)));
        }
        assert_eq!(recent.slots.len(), kept);
        recent.rows(key(1.0)); // used again: now the most recent
        recent.rows(key(-1.0)); // replaces the least recently used, key 101
        assert!(recent.by_key.contains_key(&key(1.0).bits()));
        assert!(!recent.by_key.contains_key(&key(101.0).bits()));
        assert_eq!((recent.slots.len(), recent.by_key.len()), (kept, kept));
        assert!(recent.total_bytes >= BUDGET_BYTES && recent.total_bytes < BUDGET_BYTES + (2 << 20));
    }
}
