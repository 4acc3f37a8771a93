//! The crate's one seeded pseudo-random generator, for what must be
//! random yet the same on every machine and version: a design study's
//! Latin hypercube, the fuzzer's scene mutations, the samples of property
//! and oracle tests.
//!
//! It is SplitMix64 (Steele, Lea and Flood, "Fast splittable pseudorandom
//! number generators", OOPSLA 2014): 64 bits of state, every seed valid, a
//! fixed sequence per seed. The simulation itself draws no random numbers
//! (a run is a deterministic function of its scene); nothing here is fit
//! for cryptography.

/// A seeded SplitMix64 generator: the same seed, the same sequence
/// (its tests show its use).
#[derive(Clone, Debug)]
pub struct SeededRng(u64);

impl SeededRng {
    /// The generator whose state is `seed`.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1): the top 53 bits over 2⁵³.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in (0, 1]: never 0, so its logarithm is finite.
    #[cfg(test)]
    pub fn unit_open_at_zero(&mut self) -> f64 {
        ((self.next_u64() >> 11) + 1) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [lo, hi).
    #[cfg(test)]
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform in 0..n (0 when n is 0).
    pub fn below(&mut self, n: usize) -> usize {
        let n = n.max(1);
        ((self.unit() * n as f64) as usize).min(n - 1)
    }

    /// Standard normal, by Box–Muller (one of the pair).
    #[cfg(test)]
    pub fn normal(&mut self) -> f64 {
        let (u, v) = (self.unit_open_at_zero(), self.unit_open_at_zero());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sequence_is_splitmix64s() {
        // The first outputs of SplitMix64 from state 0, as published with
        // the algorithm's reference implementation (Vigna, splitmix64.c).
        let mut r = SeededRng::new(0);
        assert_eq!(r.next_u64(), 0xE220_A839_7B1D_CDAF);
        assert_eq!(r.next_u64(), 0x6E78_9E6A_A1B9_65F4);
        assert_eq!(r.next_u64(), 0x06C4_5D18_8009_454F);
    }

    #[test]
    fn below_covers_its_range_and_nothing_else() {
        let mut r = SeededRng::new(3);
        let mut seen = [0usize; 5];
        for _ in 0..10_000 {
            seen[r.below(5)] += 1;
        }
        // 2,000 expected per value; 5 standard deviations is ±200.
        assert!(seen.iter().all(|&n| n.abs_diff(2000) < 200), "{seen:?}");
        assert_eq!(r.below(0), 0);
        assert_eq!(r.below(1), 0);
    }

    #[test]
    fn the_normal_has_mean_zero_and_variance_one() {
        // Over n = 100,000 draws the mean's standard error is 1/√n ≈ 0.0032
        // and the variance's √(2/n) ≈ 0.0045: 5 of each.
        let mut r = SeededRng::new(11);
        let n = 100_000;
        let x: Vec<f64> = (0..n).map(|_| r.normal()).collect();
        let mean = x.iter().sum::<f64>() / n as f64;
        let var = x.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n as f64;
        assert!(mean.abs() < 0.016, "{mean}");
        assert!((var - 1.0).abs() < 0.023, "{var}");
    }

    #[test]
    fn same_seed_same_sequence() {
        let mut a = SeededRng::new(42);
        let mut b = SeededRng::new(42);
        assert_eq!(a.next_u64(), b.next_u64());
        let x = a.unit();
        assert!((0.0..1.0).contains(&x));
    }
}
