//! The speed band along a road: the set speed v_ref(s), the hard top v_max(s) and the soft bottom
//! v_min(s) every cruise controller works to at position s.
//!
//! On a road without target speeds the band is the cruise band everywhere: v_ref, v_ref + v_inc
//! and v_ref − v_dec. On a road with target speeds a stretch's set speed is
//! min(v_ref, target) + target_offset (v_ref caps the road's targets; the offset lets the
//! equal-time search move every stretch at once), and the band follows it, with one addition:
//! ahead of a lower set speed the top falls no faster than the deceleration `target_decel_mps2`,
//! i.e. at s it is the lowest over the stretches ahead of √(top_c² + 2·a·(c − s)) (speeds in m/s,
//! c the stretch's start). A truck at the top can therefore reach every lower stretch by its start
//! braking at that rate, never harder. The set speed follows the falling top (it stays v_inc below
//! it), and v_min stays v_dec below the set speed, but not below 5 km/h.

use crate::params::CruiseParams;
use crate::road::Road;
use crate::KMH_PER_MPS;

/// Lowest v_min [km/h] a stretch's band takes (unless the cruise band's own is lower).
pub const V_MIN_FLOOR_KMH: f64 = 5.0;

/// The band at one position [km/h].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BandAt {
    /// The set speed v_ref(s).
    pub v_ref_kmh: f64,
    /// The soft lower bound v_ref(s) − v_dec.
    pub v_min_kmh: f64,
    /// The hard upper bound: v_ref(s) + v_inc, or lower ahead of a lower set speed.
    pub v_max_kmh: f64,
}

impl BandAt {
    /// The cruise band of `cruise` (no target speeds).
    pub fn uniform(cruise: &CruiseParams) -> Self {
        BandAt {
            v_ref_kmh: cruise.v_ref_kmh,
            v_min_kmh: cruise.v_ref_kmh - cruise.v_dec_kmh,
            v_max_kmh: cruise.v_ref_kmh + cruise.v_inc_kmh,
        }
    }

    /// v_ref [m/s].
    pub fn v_ref_mps(&self) -> f64 {
        self.v_ref_kmh / KMH_PER_MPS
    }

    /// v_min [m/s].
    pub fn v_min_mps(&self) -> f64 {
        self.v_min_kmh / KMH_PER_MPS
    }

    /// v_max [m/s].
    pub fn v_max_mps(&self) -> f64 {
        self.v_max_kmh / KMH_PER_MPS
    }
}

/// The band along one road for one cruise setting; see the module's documentation.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedBand {
    uniform: BandAt,
    v_inc_kmh: f64,
    v_dec_kmh: f64,
    decel_mps2: f64,
    /// Stretches of constant set speed: their starts [m] and set speeds [km/h], in order; empty
    /// on a road without target speeds.
    starts_m: Vec<f64>,
    set_kmh: Vec<f64>,
    /// Beyond this distance [m] no stretch ahead can pull the top down.
    reach_m: f64,
}

impl SpeedBand {
    /// The cruise band of `cruise` everywhere.
    pub fn uniform(cruise: &CruiseParams) -> Self {
        SpeedBand {
            uniform: BandAt::uniform(cruise),
            v_inc_kmh: cruise.v_inc_kmh,
            v_dec_kmh: cruise.v_dec_kmh,
            decel_mps2: cruise.target_decel_mps2,
            starts_m: Vec::new(),
            set_kmh: Vec::new(),
            reach_m: 0.0,
        }
    }

    /// The band of `cruise` along `road` (uniform without target speeds).
    pub fn new(road: &Road, cruise: &CruiseParams) -> Self {
        let mut band = Self::uniform(cruise);
        if let Some(targets) = road.target_speeds_kmh() {
            for (&start_m, &target_kmh) in road.distance_m().iter().zip(targets) {
                let set_kmh = (cruise.v_ref_kmh.min(target_kmh) + cruise.target_offset_kmh).max(1.0);
                if band.set_kmh.last() != Some(&set_kmh) {
                    band.starts_m.push(start_m);
                    band.set_kmh.push(set_kmh);
                }
            }
            let top_mps = (band.set_kmh.iter().copied().fold(0.0, f64::max) + cruise.v_inc_kmh) / KMH_PER_MPS;
            band.reach_m = top_mps * top_mps / (2.0 * band.decel_mps2);
        }
        band
    }

    /// Whether the band changes along the road (the road has target speeds).
    pub fn varies(&self) -> bool {
        !self.starts_m.is_empty()
    }

    /// The band at `s_m` [m]. `hint` is the stretch of the previous query (for a truck moving
    /// forward, so each query starts where the last one ended).
    pub fn at(&self, s_m: f64, hint: &mut usize) -> BandAt {
        if !self.varies() {
            return self.uniform;
        }
        let i = self.stretch(s_m, hint);
        let own_top_kmh = self.set_kmh[i] + self.v_inc_kmh;
        let mut top_kmh = own_top_kmh;
        for j in i + 1..self.starts_m.len() {
            let ahead_m = self.starts_m[j] - s_m;
            if ahead_m > self.reach_m {
                break;
            }
            let top_j = (self.set_kmh[j] + self.v_inc_kmh) / KMH_PER_MPS;
            let ramp_kmh = (top_j * top_j + 2.0 * self.decel_mps2 * ahead_m).sqrt() * KMH_PER_MPS;
            if ramp_kmh < top_kmh {
                top_kmh = ramp_kmh;
            }
        }
        let v_ref_kmh = if top_kmh < own_top_kmh { top_kmh - self.v_inc_kmh } else { self.set_kmh[i] };
        // A low stretch must not take v_min to or below zero (a relaxed band's v_dec is v_ref − 5).
        let floor_kmh = self.uniform.v_min_kmh.min(V_MIN_FLOOR_KMH);
        BandAt { v_ref_kmh, v_min_kmh: (v_ref_kmh - self.v_dec_kmh).max(floor_kmh), v_max_kmh: top_kmh }
    }

    /// The set speed of the stretch at `s_m` [km/h], without the falling top: where the truck
    /// is asked to be once it is in that stretch.
    pub fn set_speed_kmh(&self, s_m: f64, hint: &mut usize) -> f64 {
        if !self.varies() {
            return self.uniform.v_ref_kmh;
        }
        self.set_kmh[self.stretch(s_m, hint)]
    }

    /// The next stretch starting after `s_m` with a lower set speed than the one at `s_m`, within
    /// `within_m` [m]: its start [m] and set speed [km/h].
    pub fn next_drop(&self, s_m: f64, within_m: f64, hint: &mut usize) -> Option<(f64, f64)> {
        if !self.varies() {
            return None;
        }
        let i = self.stretch(s_m, hint);
        (i + 1..self.starts_m.len())
            .take_while(|&j| self.starts_m[j] - s_m <= within_m)
            .find(|&j| self.set_kmh[j] < self.set_kmh[i])
            .map(|j| (self.starts_m[j], self.set_kmh[j]))
    }

    /// Every stretch starting after `s_m` within `within_m` [m] whose set speed is lower than the
    /// one at `s_m`, in order: their starts [m] and set speeds [km/h].
    pub fn drops(&self, s_m: f64, within_m: f64, hint: &mut usize) -> impl Iterator<Item = (f64, f64)> + '_ {
        let (i, here_kmh) = if self.varies() {
            let i = self.stretch(s_m, hint);
            (i, self.set_kmh[i])
        } else {
            (self.starts_m.len(), 0.0)
        };
        (i + 1..self.starts_m.len())
            .take_while(move |&j| self.starts_m[j] - s_m <= within_m)
            .filter(move |&j| self.set_kmh[j] < here_kmh)
            .map(move |j| (self.starts_m[j], self.set_kmh[j]))
    }

    /// Index of the stretch containing `s_m` (the first before its start, the last beyond).
    fn stretch(&self, s_m: f64, hint: &mut usize) -> usize {
        let last = self.starts_m.len() - 1;
        let mut i = (*hint).min(last);
        // The hint's stretch or the next one (a truck moving forward), else a binary search.
        if i < last && s_m >= self.starts_m[i + 1] {
            i += 1;
        }
        let inside = s_m >= self.starts_m[i] || i == 0;
        if !inside || (i < last && s_m >= self.starts_m[i + 1]) {
            i = self.starts_m.partition_point(|&d| d <= s_m).saturating_sub(1);
        }
        *hint = i;
        i
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn road(targets: Vec<f64>) -> Road {
        let n = targets.len();
        let x: Vec<f64> = (0..=n).map(|i| 1000.0 * i as f64).collect();
        Road::new(x, vec![0.0; n]).unwrap().with_target_speeds(targets).unwrap()
    }

    /// Without target speeds the band is the cruise band, bit for bit, everywhere.
    #[test]
    fn without_targets_the_band_is_the_cruise_band() {
        let plain = Road::new(vec![0.0, 1000.0], vec![0.01]).unwrap();
        let cruise = CruiseParams { v_ref_kmh: 83.3, ..CruiseParams::default() };
        let band = SpeedBand::new(&plain, &cruise);
        let at = band.at(500.0, &mut 0);
        assert_eq!(at.v_max_mps().to_bits(), ((83.3 + 5.0) / 3.6f64).to_bits());
        assert_eq!(at, BandAt::uniform(&cruise));
        assert!(!band.varies());
    }

    /// Ahead of a drop from 85 to 60 km/h the top follows √(v_c² + 2·a·d): at the drop it is the
    /// lower top, at the distance that braking at `a` needs from the higher top it is that top.
    #[test]
    fn the_top_falls_at_the_set_deceleration_before_a_drop() {
        let cruise = CruiseParams { v_dec_kmh: 5.0, ..CruiseParams::default() };
        let band = SpeedBand::new(&road(vec![85.0, 60.0, 85.0]), &cruise);
        let (hi, lo) = (90.0 / 3.6, 65.0 / 3.6);
        let reach = (hi * hi - lo * lo) / (2.0 * cruise.target_decel_mps2);
        let at = |s: f64| band.at(s, &mut 0);
        assert!((at(1000.0).v_max_kmh - 65.0).abs() < 1e-9);
        assert!((at(1000.0 - reach - 1.0).v_max_kmh - 90.0).abs() < 1e-9);
        let d = 100.0;
        let expected = (lo * lo + 2.0 * cruise.target_decel_mps2 * d).sqrt() * 3.6;
        let mid = at(1000.0 - d);
        assert!((mid.v_max_kmh - expected).abs() < 1e-9);
        assert!((mid.v_ref_kmh - (expected - 5.0)).abs() < 1e-9 && (mid.v_min_kmh - (expected - 10.0)).abs() < 1e-9);
        // Rising again, the band steps up at the stretch's start.
        assert_eq!(at(2000.0).v_ref_kmh, 85.0);
        assert_eq!(at(1999.0).v_ref_kmh, 60.0);
    }

    /// A stretch far below v_ref keeps v_min above zero: the relaxed band (v_dec = v_ref − 5 km/h)
    /// at a 30 km/h stretch has v_min 5 km/h, not −50.
    #[test]
    fn a_low_stretch_keeps_v_min_above_zero() {
        let relaxed = CruiseParams { v_dec_kmh: 80.0, ..CruiseParams::default() };
        let band = SpeedBand::new(&road(vec![85.0, 30.0]), &relaxed);
        assert_eq!(band.at(1500.0, &mut 0).v_min_kmh, V_MIN_FLOOR_KMH);
        assert_eq!(band.at(10.0, &mut 0).v_min_kmh, 5.0);
        let normal = SpeedBand::new(&road(vec![85.0, 30.0]), &CruiseParams::default());
        assert_eq!(normal.at(1500.0, &mut 0).v_min_kmh, 30.0 - CruiseParams::default().v_dec_kmh);
    }

    /// The cruise v_ref caps the targets; the offset moves every stretch.
    #[test]
    fn v_ref_caps_the_targets_and_the_offset_moves_them() {
        let cruise = CruiseParams { v_ref_kmh: 80.0, target_offset_kmh: 2.0, ..CruiseParams::default() };
        let band = SpeedBand::new(&road(vec![85.0, 60.0]), &cruise);
        assert_eq!(band.set_speed_kmh(10.0, &mut 0), 82.0);
        assert_eq!(band.set_speed_kmh(1500.0, &mut 0), 62.0);
        assert_eq!(band.next_drop(10.0, 2000.0, &mut 0), Some((1000.0, 62.0)));
        assert_eq!(band.next_drop(10.0, 500.0, &mut 0), None);
        assert_eq!(band.drops(10.0, 2000.0, &mut 0).next(), Some((1000.0, 62.0)));
        assert_eq!(band.drops(10.0, 500.0, &mut 0).count(), 0);
    }
}
