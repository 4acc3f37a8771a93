//! The S–N curve of a chain's link plates, written for the chain's own load
//! cycle, the pulsating one (0 → F → 0, a link passing from the slack
//! strand to the tight one and back): a cycle of peak F lasts
//! N = N_D (F_D / F)^m cycles above the fatigue limit F_D and for ever below
//! it (Miner's rule in its original form: cycles below the limit do no
//! damage).
//!
//! **Mean stress**, by Goodman's line through the tensile strength F_u: a
//! cycle of amplitude F_a about the mean F_m is as damaging as the fully
//! reversed amplitude F_a / (1 − F_m / F_u), and as the pulsating cycle of
//! peak F₀ = 2 F_ar / (1 + F_ar / F_u) on the same line
//! ([`SnCurve::pulsating_equivalent_n`]); a pulsating cycle is its own
//! equivalent.
//!
//! It does not say where a curve comes from (the rating or the scene: that
//! is [`super::fatigue`]'s) and counts no cycles ([`super::link_cycles`]).

use serde::{Deserialize, Serialize};

/// The turning points of a link's force are found with a gate of this
/// fraction of the fatigue limit: a reversal pair smaller than the gate
/// does no damage at any mean below 7/8 of the tensile strength.
pub const GATE_FRACTION: f64 = 0.125;

/// An S–N curve of pulsating cycles with Goodman's mean-stress correction
/// ([module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SnCurve {
    /// Slope m of N = N_D (F_D / F)^m.
    pub slope: f64,
    /// Fatigue limit F_D: the peak of a pulsating cycle lasting
    /// `knee_cycles`, and for ever below, N.
    pub fatigue_limit_n: f64,
    /// N_D.
    pub knee_cycles: f64,
    /// Tensile strength F_u (the Goodman line's end), N.
    pub tensile_strength_n: f64,
}

impl SnCurve {
    /// The peak of the pulsating cycle as damaging as a cycle of `range_n`
    /// about `mean_n` (Goodman; a compressive mean counts as zero); at most
    /// 2 F_u, which a mean at the strength reaches.
    pub fn pulsating_equivalent_n(&self, range_n: f64, mean_n: f64) -> f64 {
        let fu = self.tensile_strength_n;
        let amplitude = 0.5 * range_n.abs();
        let left = 1.0 - mean_n.max(0.0) / fu;
        if left <= 0.0 {
            return 2.0 * fu;
        }
        let reversed = amplitude / left;
        2.0 * reversed / (1.0 + reversed / fu)
    }

    /// Miner's damage of one cycle of peak `pulsating_n` (a pulsating
    /// equivalent): 1 / N, zero below the fatigue limit, at most 1.
    pub fn damage_of_pulsating(&self, pulsating_n: f64) -> f64 {
        if !(pulsating_n >= self.fatigue_limit_n) {
            return 0.0;
        }
        ((pulsating_n / self.fatigue_limit_n).powf(self.slope) / self.knee_cycles).min(1.0)
    }

    /// The cycles a pulsating cycle of peak `pulsating_n` lasts on the
    /// curve, N_D (F_D / F)^m; infinite at or below the fatigue limit.
    pub fn cycles_to_failure(&self, pulsating_n: f64) -> f64 {
        if !(pulsating_n > self.fatigue_limit_n) {
            return f64::INFINITY;
        }
        self.knee_cycles * (self.fatigue_limit_n / pulsating_n).powf(self.slope)
    }

    /// A curve for tests: m = 10, F_D = 2 kN at N_D = 5·10⁶, F_u = 20 kN.
    #[cfg(test)]
    pub(crate) fn for_tests() -> Self {
        Self {
            slope: 10.0,
            fatigue_limit_n: 2000.0,
            knee_cycles: 5e6,
            tensile_strength_n: 20_000.0,
        }
    }

    /// Miner's damage of one cycle of `range_n` about `mean_n`.
    #[cfg(test)]
    pub fn damage(&self, range_n: f64, mean_n: f64) -> f64 {
        self.damage_of_pulsating(self.pulsating_equivalent_n(range_n, mean_n))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pulsating cycle (mean = amplitude) is its own equivalent.
    #[test]
    fn a_pulsating_cycle_is_its_own_equivalent() {
        let c = SnCurve::for_tests();
        for peak in [100.0, 2500.0, 9000.0] {
            approx::assert_relative_eq!(
                c.pulsating_equivalent_n(peak, 0.5 * peak),
                peak,
                max_relative = 1e-14
            );
        }
    }

    /// By hand: range 2 kN about 5 kN on F_u = 20 kN: F_ar = 1 / (1 − 0.25)
    /// = 4/3 kN; F₀ = 2 · (4/3) / (1 + (4/3)/20) = (8/3) / (16/15) = 2.5 kN.
    #[test]
    fn goodman_maps_a_cycle_onto_the_pulsating_line() {
        approx::assert_relative_eq!(
            SnCurve::for_tests().pulsating_equivalent_n(2000.0, 5000.0),
            2500.0,
            max_relative = 1e-14
        );
        assert_eq!(
            SnCurve::for_tests().pulsating_equivalent_n(10.0, 25_000.0),
            40_000.0
        );
    }

    /// The pulsating equivalent is the correction JIS B 1811 applies to a
    /// fatigue test whose smallest load is not zero:
    /// F_d = F_u (F_max − F_min) / (F_u − F_min).
    #[test]
    fn goodman_is_the_jis_correction_to_a_zero_minimum() {
        let c = SnCurve::for_tests();
        for (lo, hi) in [(0.0, 3000.0), (4000.0, 6000.0), (1500.0, 12_000.0)] {
            let jis = 20_000.0 * (hi - lo) / (20_000.0 - lo);
            approx::assert_relative_eq!(
                c.pulsating_equivalent_n(hi - lo, 0.5 * (hi + lo)),
                jis,
                max_relative = 1e-13
            );
        }
    }

    /// N = N_D (F_D / F)^m: twice the limit lasts 5e6 / 1024 cycles.
    #[test]
    fn cycles_to_failure_follow_the_line_and_never_end_below_the_limit() {
        let c = SnCurve::for_tests();
        approx::assert_relative_eq!(c.cycles_to_failure(4000.0), 5e6 / 1024.0);
        assert_eq!(c.cycles_to_failure(2000.0), f64::INFINITY);
        assert_eq!(c.cycles_to_failure(f64::NAN), f64::INFINITY);
    }

    #[test]
    fn below_the_fatigue_limit_a_cycle_does_no_damage() {
        let c = SnCurve::for_tests();
        assert_eq!(c.damage_of_pulsating(1999.0), 0.0);
        approx::assert_relative_eq!(c.damage_of_pulsating(2000.0), 1.0 / 5e6);
        assert_eq!(c.damage_of_pulsating(f64::NAN), 0.0);
        assert_eq!(c.damage_of_pulsating(1e9), 1.0);
    }

    /// Pulsating cycles of twice the peak do 2^m times the damage.
    #[test]
    fn damage_scales_as_the_slope_says_when_the_peak_doubles() {
        let c = SnCurve::for_tests();
        let one = c.damage(3000.0, 1500.0);
        let two = c.damage(6000.0, 3000.0);
        approx::assert_relative_eq!(two / one, 2f64.powi(10), max_relative = 1e-12);
    }
}
