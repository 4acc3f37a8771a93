//! Estimators that say how sure a statistic is: the standard error of a
//! correlated series' mean by batch means, the RMS about the mean, and a
//! stationarity test. They take plain slices of samples in time order and
//! know nothing of chains.
//!
//! # The batch rule
//!
//! A series of `n` samples is cut into [`BATCHES`] = 20 consecutive batches
//! of `m = ⌊n / 20⌋` samples; the `n − 20 m` oldest samples are left out (the
//! window's end is the run's end, so its start gives way). The batch means
//! are treated as independent: SE = sd(batch means) / √20, with the sample
//! standard deviation (divisor 19). Twenty lies in the 10–30 that Schmeiser
//! (1982) recommends: fewer batches make the SE itself noisy (its relative
//! spread is about 1/√(2·19) ≈ 16 %), more make each batch shorter and the
//! estimate biased low when a batch is not much longer than the series'
//! correlation time. A series of fewer than 20 samples is its own batches
//! (m = 1, the independent-sample formula s/√n); fewer than 2 samples give 0.
//!
//! # Stationarity
//!
//! A series is stationary unless the means of its first and last thirds
//! differ by more than three combined standard errors,
//! |m₁ − m₃| > 3 √(SE₁² + SE₃²), each third's SE by the batch rule above.
//! This is the trend test too: a linear drift of Δ across the window moves
//! the thirds' means apart by 2Δ/3. Differences below 10⁻⁹ of the series'
//! scale (|mean| + RMS) are rounding, not drift. A series of fewer than
//! [`MIN_JUDGED`] samples is not judged (reported stationary).

/// Batches of the batch-means rule.
pub(crate) const BATCHES: usize = 20;

/// Fewest samples whose stationarity is judged.
pub(crate) const MIN_JUDGED: usize = 60;

/// Combined standard errors by which the first and last thirds' means may differ.
pub(crate) const STATIONARITY_SE: f64 = 3.0;

/// Mean of a slice; 0 when empty.
pub(crate) fn mean(x: &[f64]) -> f64 {
    if x.is_empty() {
        0.0
    } else {
        x.iter().sum::<f64>() / x.len() as f64
    }
}

/// Root mean square of the fluctuation about the mean, √(Σ (x − x̄)² / n); 0 when empty.
pub(crate) fn rms_about_mean(x: &[f64]) -> f64 {
    if x.is_empty() {
        return 0.0;
    }
    let m = mean(x);
    (x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / x.len() as f64).sqrt()
}

/// The batch means of `x` under the batch rule (module docs).
pub(crate) fn batch_means(x: &[f64]) -> Vec<f64> {
    let n = x.len();
    if n < BATCHES {
        return x.to_vec();
    }
    let m = n / BATCHES;
    x[n - BATCHES * m..].chunks_exact(m).map(mean).collect()
}

/// Standard error of the mean of `x` by batch means (module docs); 0 with
/// fewer than 2 samples.
pub(crate) fn standard_error(x: &[f64]) -> f64 {
    let b = batch_means(x);
    let k = b.len();
    if k < 2 {
        return 0.0;
    }
    let m = mean(&b);
    let var = b.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / (k - 1) as f64;
    (var / k as f64).sqrt()
}

/// Standard error of the RMS about the mean, by the delta method on the
/// mean of squared deviations: SE(r) ≈ SE(mean (x − x̄)²) / (2 r); 0 when
/// the RMS is 0.
pub(crate) fn rms_standard_error(x: &[f64]) -> f64 {
    let r = rms_about_mean(x);
    if r <= 0.0 {
        return 0.0;
    }
    let m = mean(x);
    let squares: Vec<f64> = x.iter().map(|v| (v - m) * (v - m)).collect();
    standard_error(&squares) / (2.0 * r)
}

/// The stationarity test's numbers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Stationarity {
    /// Mean of the first third.
    pub first_mean: f64,
    /// Mean of the last third.
    pub last_mean: f64,
    /// √(SE₁² + SE₃²).
    pub combined_se: f64,
    /// The verdict (module docs).
    pub stationary: bool,
}

impl Stationarity {
    /// |m₁ − m₃| in combined standard errors (∞ when they are 0 and the means differ).
    pub(crate) fn z(&self) -> f64 {
        let d = (self.last_mean - self.first_mean).abs();
        if self.combined_se > 0.0 {
            d / self.combined_se
        } else if d > 0.0 {
            f64::INFINITY
        } else {
            0.0
        }
    }
}

/// Tests `x` for stationarity (module docs).
pub(crate) fn stationarity(x: &[f64]) -> Stationarity {
    let n = x.len();
    let third = n / 3;
    let (first, last) = (&x[..third], &x[n - third..]);
    let (first_mean, last_mean) = (mean(first), mean(last));
    let combined_se = standard_error(first).hypot(standard_error(last));
    let scale = mean(x).abs() + rms_about_mean(x);
    let d = (last_mean - first_mean).abs();
    let stationary = n < MIN_JUDGED || d <= 1e-9 * scale || d <= STATIONARITY_SE * combined_se;
    Stationarity {
        first_mean,
        last_mean,
        combined_se,
        stationary,
    }
}

/// Mean, least and largest of the finite values, and their count (`None`
/// when there is none).
pub(crate) fn finite_stats(values: impl Iterator<Item = f64>) -> Option<(f64, f64, f64, usize)> {
    let (mut sum, mut n, mut lo, mut hi) = (0.0, 0usize, f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        sum += v;
        n += 1;
        lo = lo.min(v);
        hi = hi.max(v);
    }
    (n > 0).then(|| (sum / n as f64, lo, hi, n))
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::rng::SeededRng;

    /// AR(1): x_k = ρ x_{k−1} + e_k, e ~ N(0, σ_e²), started in its stationary
    /// law (x₀ ~ N(0, σ²), σ² = σ_e² / (1 − ρ²)).
    fn ar1(rng: &mut SeededRng, n: usize, rho: f64, sigma: f64) -> Vec<f64> {
        let sigma_e = sigma * (1.0 - rho * rho).sqrt();
        let mut x = sigma * rng.normal();
        (0..n)
            .map(|_| {
                let v = x;
                x = rho * x + sigma_e * rng.normal();
                v
            })
            .collect()
    }

    /// Mean over `trials` series of the squared batch-means SE, against the
    /// closed form for an AR(1) series' mean: Var(x̄) ≈ σ²/n · (1+ρ)/(1−ρ)
    /// (large n; the exact sum differs by O(1/n)). The mean of 400 estimates
    /// of SE², each with 19 degrees of freedom, has a relative spread of
    /// √(2/19/400) ≈ 1.6 %; batch-length bias is about 2ρ/((1−ρ²) m) ≈ 1 %
    /// at ρ = 0.9, m = 2000. Tolerance 8 %.
    fn check_ar1(rho: f64, n: usize, seed: u64) {
        let sigma = 2.0;
        let mut rng = SeededRng::new(seed);
        let trials = 400;
        let estimated = (0..trials)
            .map(|_| standard_error(&ar1(&mut rng, n, rho, sigma)).powi(2))
            .sum::<f64>()
            / trials as f64;
        let exact = sigma * sigma / n as f64 * (1.0 + rho) / (1.0 - rho);
        let ratio = (estimated / exact).sqrt();
        assert!((ratio - 1.0).abs() < 0.08, "rho {rho}: SE ratio {ratio}");
    }

    #[test]
    fn batch_means_se_of_white_noise_is_sigma_over_root_n() {
        check_ar1(0.0, 4000, 1);
    }

    #[test]
    fn batch_means_se_of_an_ar1_series_matches_the_closed_form() {
        check_ar1(0.5, 10_000, 2);
        check_ar1(0.9, 40_000, 3);
    }

    #[test]
    fn the_independent_formula_would_be_wrong_for_ar1() {
        // The check above can fail: s/√n (every sample a batch) underestimates
        // the AR(1) SE at ρ = 0.9 by √19 ≈ 4.4.
        let mut rng = SeededRng::new(4);
        let x = ar1(&mut rng, 40_000, 0.9, 1.0);
        let naive = rms_about_mean(&x) / (x.len() as f64).sqrt();
        let batch = standard_error(&x);
        assert!(batch / naive > 3.0, "{batch} vs {naive}");
    }

    #[test]
    fn rms_of_a_sine_is_amplitude_over_root_two() {
        // A sin over whole periods: RMS = A/√2 exactly, whatever the offset.
        let (a, n, periods) = (3.0, 10_000, 50.0);
        let x: Vec<f64> = (0..n)
            .map(|k| 7.0 + a * (std::f64::consts::TAU * periods * k as f64 / n as f64).sin())
            .collect();
        let r = rms_about_mean(&x);
        assert!((r - a / 2f64.sqrt()).abs() < 1e-9, "{r}");
    }

    #[test]
    fn rms_se_of_white_noise() {
        // For Gaussian white noise, Var(s²) ≈ 2σ⁴/n, so SE(s) ≈ σ/√(2n).
        let mut rng = SeededRng::new(5);
        let (n, sigma, trials) = (4000, 1.5, 200);
        let est = (0..trials)
            .map(|_| rms_standard_error(&ar1(&mut rng, n, 0.0, sigma)).powi(2))
            .sum::<f64>()
            / trials as f64;
        let ratio = (est / (sigma * sigma / (2.0 * n as f64))).sqrt();
        assert!((ratio - 1.0).abs() < 0.08, "{ratio}");
    }

    #[test]
    fn a_linear_trend_is_not_stationary() {
        // 1000 samples rising by 1 % of the mean, with noise of 0.5 % (white):
        // the thirds differ by 0.67 %, each third's SE is 0.5 %/√333 ≈ 0.03 %.
        let mut rng = SeededRng::new(6);
        let x: Vec<f64> = (0..1000)
            .map(|k| 100.0 + k as f64 / 1000.0 + 0.5 * rng.normal())
            .collect();
        let s = stationarity(&x);
        assert!(!s.stationary, "{s:?}");
        assert!(s.z() > 10.0, "{s:?}");
        // Without noise too.
        let ramp: Vec<f64> = (0..1000).map(|k| k as f64).collect();
        assert!(!stationarity(&ramp).stationary);
    }

    #[test]
    fn a_sine_of_many_periods_is_stationary() {
        // 1 s at 1 kHz of a 120 Hz tooth-frequency sine (not a whole number of
        // periods per batch or per third) on a mean, with and without noise.
        for (noise, seed) in [(0.0, 7), (0.3, 8)] {
            let mut rng = SeededRng::new(seed);
            let x: Vec<f64> = (0..1000)
                .map(|k| {
                    let t = k as f64 * 1e-3;
                    50.0 + 5.0 * (std::f64::consts::TAU * 120.0 * t + 0.3).sin()
                        + noise * rng.normal()
                })
                .collect();
            let s = stationarity(&x);
            assert!(s.stationary, "noise {noise}: {s:?}");
        }
        // White noise and a stationary AR(1) series are not flagged (at 3
        // combined SE the false alarm rate is about 0.3 %; fixed seeds).
        let mut rng = SeededRng::new(9);
        assert!(stationarity(&ar1(&mut rng, 2000, 0.0, 1.0)).stationary);
        assert!(stationarity(&ar1(&mut rng, 20_000, 0.8, 1.0)).stationary);
    }

    #[test]
    fn a_step_in_the_mean_is_not_stationary() {
        let x: Vec<f64> = (0..900)
            .map(|k| if k < 450 { 10.0 } else { 10.5 } + 0.01 * ((k * 7 % 13) as f64 - 6.0))
            .collect();
        assert!(!stationarity(&x).stationary);
    }

    #[test]
    fn short_and_empty_series() {
        assert_eq!(standard_error(&[]), 0.0);
        assert_eq!(standard_error(&[1.0]), 0.0);
        assert_eq!(rms_about_mean(&[]), 0.0);
        // Fewer than 20 samples: s/√n. x = (1, 3): s = √2, SE = 1.
        assert!((standard_error(&[1.0, 3.0]) - 1.0).abs() < 1e-15);
        assert!(stationarity(&[1.0, 2.0, 3.0]).stationary);
        // 45 samples: batches of 2, the 5 oldest left out.
        assert_eq!(batch_means(&[0.0; 45]).len(), BATCHES);
    }
}
