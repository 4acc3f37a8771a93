//! The soak study (`chaindrive bench soak`): a long run summed in windows of
//! simulated time, to show there is no drift — driven speed ratios exact on
//! average, strand tension steady, penetration not growing.
//!
//! [`Soak`] is the observer; it keeps per-window sums, not samples, so an
//! hour of simulated time costs a few numbers per window. Printing the table
//! is the command-line tool's job.

use crate::sim::{Observer, Sample};

/// Per-window sums.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SoakWindow {
    /// Samples in the window.
    pub samples: usize,
    /// Sum of each sprocket's angular speed over the samples, rad/s.
    pub omega_sum: Vec<f64>,
    /// Sum of each segment's mean link force over the samples with a free link, N.
    pub force_sum: Vec<f64>,
    /// Samples with a free link, per segment.
    pub force_count: Vec<usize>,
    /// Largest penetration over every step of the window, m.
    pub max_penetration_m: f64,
}

impl SoakWindow {
    /// Mean angular speed of each sprocket over the window, rad/s.
    pub fn mean_omega_rad_s(&self) -> Vec<f64> {
        let n = self.samples.max(1) as f64;
        self.omega_sum.iter().map(|s| s / n).collect()
    }

    /// Mean link force of each segment over its samples with a free link, N
    /// (0 when there was none).
    pub fn mean_force_n(&self) -> Vec<f64> {
        self.force_sum
            .iter()
            .zip(&self.force_count)
            .map(|(sum, count)| if *count > 0 { sum / *count as f64 } else { 0.0 })
            .collect()
    }
}

/// Sums a run's samples in windows of `window_s` of simulated time.
pub struct Soak {
    window_s: f64,
    /// The windows, in time order.
    pub windows: Vec<SoakWindow>,
    scratch: Vec<Option<f64>>,
}

impl Soak {
    /// An observer summing in windows of `window_s` for a drive of `segments` segments.
    pub fn new(window_s: f64, segments: usize) -> Self {
        Self {
            window_s,
            windows: Vec::new(),
            scratch: vec![None; segments],
        }
    }

    fn current(&mut self, t_s: f64, sprockets: usize, segments: usize) -> &mut SoakWindow {
        let k = ((t_s - 1e-12) / self.window_s).floor().max(0.0) as usize;
        while self.windows.len() <= k {
            self.windows.push(SoakWindow {
                omega_sum: vec![0.0; sprockets],
                force_sum: vec![0.0; segments],
                force_count: vec![0; segments],
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
        let w = self.current(st.t_s, st.omega.len(), scratch.len());
        w.samples += 1;
        for (sum, omega) in w.omega_sum.iter_mut().zip(&st.omega) {
            *sum += omega;
        }
        for (k, f) in scratch.iter().enumerate() {
            if let Some(f) = f {
                w.force_sum[k] += f;
                w.force_count[k] += 1;
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
