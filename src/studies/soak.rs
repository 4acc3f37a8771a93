//! The soak study (`chaindrive bench soak`): a long run summed in windows of
//! simulated time, to show there is no drift — driven speed ratios exact on
//! average, strand tension steady, penetration not growing.
//!
//! [`Soak`] is the observer; it keeps per-window sums, not samples, so an
//! hour of simulated time costs a few numbers per window. Printing the table
//! is the command-line tool's job.
//!
//! # Standard errors and the steady state
//!
//! Each window's segment means carry a standard error by batch means: the
//! window is cut into [`BATCHES`] equal spans of time, each span's mean is a
//! batch mean, SE = sd(batch means) / √(batches with a sample)
//! ([`crate::analysis::stats`]).
//!
//! The run is *steady from* the earliest window start after which every
//! window's mean of every segment lies within ±[`STEADY_FRACTION`] of that
//! segment's overall mean over those windows, or within [`STEADY_SE`] of the
//! window's own standard errors ([`steady_from`]). The steady part must span
//! at least half of the windows and at least [`STEADY_MIN_WINDOWS`] of them:
//! a run that settles only in its last windows is not steady.

use crate::analysis::stats::BATCHES;
use crate::sim::{Observer, Sample};

/// Relative band of the steady state about the overall mean.
pub(crate) const STEADY_FRACTION: f64 = 0.02;

/// Standard errors of the steady state's band.
pub(crate) const STEADY_SE: f64 = 2.0;

/// Fewest windows a steady state spans.
pub(crate) const STEADY_MIN_WINDOWS: usize = 3;

/// Per-window sums.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct SoakWindow {
    /// Samples in the window.
    pub samples: usize,
    /// Sum of each sprocket's angular speed over the samples, rad/s.
    pub omega_sum: Vec<f64>,
    /// Sum of each segment's mean link force over the samples with a free link, N.
    pub force_sum: Vec<f64>,
    /// Samples with a free link, per segment.
    pub force_count: Vec<usize>,
    /// Per segment, the sums of its link force over each of the window's
    /// [`BATCHES`] time batches, N.
    pub batch_sum: Vec<[f64; BATCHES]>,
    /// Per segment, the samples with a free link in each batch.
    pub batch_count: Vec<[usize; BATCHES]>,
    /// Largest penetration over every step of the window, m.
    pub max_penetration_m: f64,
}

impl SoakWindow {
    /// Mean angular speed of each sprocket over the window, rad/s.
    pub(crate) fn mean_omega_rad_s(&self) -> Vec<f64> {
        let n = self.samples.max(1) as f64;
        self.omega_sum.iter().map(|s| s / n).collect()
    }

    /// Mean link force of each segment over its samples with a free link, N
    /// (0 when there was none).
    pub(crate) fn mean_force_n(&self) -> Vec<f64> {
        self.force_sum
            .iter()
            .zip(&self.force_count)
            .map(|(sum, count)| if *count > 0 { sum / *count as f64 } else { 0.0 })
            .collect()
    }

    /// Standard error of each segment's mean force by batch means, N (0 with
    /// fewer than two batches holding a sample).
    pub(crate) fn force_se_n(&self) -> Vec<f64> {
        self.batch_sum
            .iter()
            .zip(&self.batch_count)
            .map(|(sums, counts)| {
                let means: Vec<f64> = sums
                    .iter()
                    .zip(counts)
                    .filter(|(_, c)| **c > 0)
                    .map(|(s, c)| s / *c as f64)
                    .collect();
                let k = means.len();
                if k < 2 {
                    return 0.0;
                }
                let m = means.iter().sum::<f64>() / k as f64;
                let var = means.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / (k - 1) as f64;
                (var / k as f64).sqrt()
            })
            .collect()
    }
}

/// The index of the earliest window from which the run is steady (module
/// docs), or `None`. `means[i][k]` and `ses[i][k]` are window i's mean of
/// segment k and its standard error.
pub(crate) fn steady_from(means: &[Vec<f64>], ses: &[Vec<f64>]) -> Option<usize> {
    let n = means.len();
    let segments = means.first().map_or(0, Vec::len);
    let needed = STEADY_MIN_WINDOWS.max(n.div_ceil(2));
    (0..n)
        .take_while(|&start| n - start >= needed)
        .find(|&start| {
            (0..segments).all(|k| {
                let overall = means[start..].iter().map(|m| m[k]).sum::<f64>() / (n - start) as f64;
                (start..n).all(|i| {
                    let d = (means[i][k] - overall).abs();
                    d <= STEADY_FRACTION * overall.abs() || d <= STEADY_SE * ses[i][k]
                })
            })
        })
}

/// Sums a run's samples in windows of `window_s` of simulated time.
pub(crate) struct Soak {
    window_s: f64,
    /// The windows, in time order.
    pub windows: Vec<SoakWindow>,
    scratch: Vec<Option<f64>>,
}

impl Soak {
    /// An observer summing in windows of `window_s` for a drive of `segments` segments.
    pub(crate) fn new(window_s: f64, segments: usize) -> Self {
        Self {
            window_s,
            windows: Vec::new(),
            scratch: vec![None; segments],
        }
    }

    /// The window holding time `t_s` (a sample at a window's end belongs to it).
    fn window_of(t_s: f64, window_s: f64) -> usize {
        ((t_s - 1e-12) / window_s).floor().max(0.0) as usize
    }

    /// The batch of its window holding time `t_s`.
    fn batch_of(t_s: f64, window_s: f64) -> usize {
        let start = Self::window_of(t_s, window_s) as f64 * window_s;
        let b = ((t_s - 1e-12 - start) / window_s * BATCHES as f64).floor();
        (b.max(0.0) as usize).min(BATCHES - 1)
    }

    /// Each window's segment means and their standard errors, N.
    pub(crate) fn means_and_ses(&self) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
        (
            self.windows.iter().map(SoakWindow::mean_force_n).collect(),
            self.windows.iter().map(SoakWindow::force_se_n).collect(),
        )
    }

    fn current(&mut self, t_s: f64, sprockets: usize, segments: usize) -> &mut SoakWindow {
        let k = Self::window_of(t_s, self.window_s);
        while self.windows.len() <= k {
            self.windows.push(SoakWindow {
                omega_sum: vec![0.0; sprockets],
                force_sum: vec![0.0; segments],
                force_count: vec![0; segments],
                batch_sum: vec![[0.0; BATCHES]; segments],
                batch_count: vec![[0; BATCHES]; segments],
                ..SoakWindow::default()
            });
        }
        &mut self.windows[k]
    }
}

impl Observer for Soak {
    fn sample(&mut self, s: &Sample<'_>) {
        let st = s.state;
        let mut scratch = std::mem::take(&mut self.scratch);
        let segments = &s.model.segments;
        let runs = segments.runs(&s.model.sprockets, &st.x, &st.y, &s.forces.touching);
        segments.mean_forces(&runs, &s.forces.link_force, &mut scratch);
        let b = Self::batch_of(st.t_s, self.window_s);
        let w = self.current(st.t_s, st.omega.len(), scratch.len());
        w.samples += 1;
        for (sum, omega) in w.omega_sum.iter_mut().zip(&st.omega) {
            *sum += omega;
        }
        for (k, f) in scratch.iter().enumerate() {
            if let Some(f) = f {
                w.force_sum[k] += f;
                w.force_count[k] += 1;
                w.batch_sum[k][b] += f;
                w.batch_count[k][b] += 1;
            }
        }
        self.scratch = scratch;
    }

    fn step(&mut self, s: &Sample<'_>) {
        let pen = s.forces.max_penetration_m;
        let w = self.current(s.state.t_s, s.state.omega.len(), s.model.segments.len());
        w.max_penetration_m = w.max_penetration_m.max(pen);
    }

    fn per_step_from_s(&self) -> f64 {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_run_that_settles_is_steady_from_its_settling() {
        // Two segments; segment 1 climbs for three windows, then holds within
        // 1 % of 100 (band ±2 %), SE 0.1.
        let seg1 = [
            80.0, 90.0, 96.0, 100.0, 101.0, 99.0, 100.5, 99.5, 100.0, 100.0,
        ];
        let means: Vec<Vec<f64>> = seg1.iter().map(|&m| vec![m, 50.0]).collect();
        let ses = vec![vec![0.1, 0.1]; means.len()];
        assert_eq!(steady_from(&means, &ses), Some(3));
    }

    #[test]
    fn a_run_that_drifts_is_not_steady() {
        // +1.5 % per window: no tail of ≥ 5 windows stays within ±2 % of its
        // mean (the ends lie 3 % away).
        let means: Vec<Vec<f64>> = (0..10)
            .map(|i| vec![100.0 * (1.0 + 0.015 * i as f64)])
            .collect();
        let ses = vec![vec![0.1]; 10];
        assert_eq!(steady_from(&means, &ses), None);
        // Unless the windows are that uncertain: 2 SE = 8 N covers the largest
        // deviation, 6.75 N from the mean 106.75 N.
        let wide = vec![vec![4.0]; 10];
        assert_eq!(steady_from(&means, &wide), Some(0));
    }

    #[test]
    fn batches_split_a_window_evenly() {
        // Windows of 5 s: batches of 0.25 s; a sample at a window's end is in its last batch.
        assert_eq!(Soak::batch_of(0.001, 5.0), 0);
        assert_eq!(Soak::batch_of(0.26, 5.0), 1);
        assert_eq!(Soak::batch_of(5.0, 5.0), BATCHES - 1);
        assert_eq!(Soak::batch_of(5.001, 5.0), 0);
        // Mean 2 of batches (1, 3) repeated: SE = sd / √k with sd = √(20/19).
        let w = SoakWindow {
            batch_sum: vec![std::array::from_fn(|b| if b % 2 == 0 { 2.0 } else { 6.0 })],
            batch_count: vec![[2; BATCHES]],
            ..SoakWindow::default()
        };
        let expected = (20.0f64 / 19.0).sqrt() / 20f64.sqrt();
        assert!((w.force_se_n()[0] - expected).abs() < 1e-12);
    }
}
