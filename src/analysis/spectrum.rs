//! Amplitude spectra and peak picking.
//!
//! Normalisation: the signal's mean is removed, a Hann window applied, and
//! the one-sided amplitude spectrum scaled by 2 / Σw so that a sine of
//! amplitude A sampled over many periods shows a peak of height ≈ A.
//! The peak frequency is refined by fitting a parabola through the log
//! amplitudes of the highest bin and its neighbours (Gaussian interpolation),
//! which for a Hann window is accurate to a few percent of a bin.
//!
//! # Averaged segments (Welch)
//!
//! A signal longer than [`WELCH_SEGMENT`] samples is cut into segments of
//! that length overlapping by half, each with its own mean removed and its
//! own Hann window; the amplitude is the root of the mean of the segments'
//! squared amplitudes (Welch 1967), so a sine still peaks at its amplitude
//! and the noise's spread shrinks with the number of segments. The samples
//! after the last whole segment are left out. A signal of at most one
//! segment is one spectrum over all of it, as above. [`Welch`] does this as
//! the samples arrive, holding at most one segment ([`welch_spectrum`] is
//! the same over a slice, bit for bit): a run's memory does not grow with
//! its length.

use rustfft::FftPlanner;
use rustfft::num_complex::Complex;
use serde::{Deserialize, Serialize};

/// Length of a segment of the averaged spectrum, samples (16.4 s at 1 kHz:
/// a resolution of 0.06 Hz).
pub const WELCH_SEGMENT: usize = 16_384;

/// One-sided amplitude spectrum of `signal` sampled at `rate_hz`:
/// (frequencies, amplitudes). Empty for fewer than 4 samples.
pub fn amplitude_spectrum(signal: &[f64], rate_hz: f64) -> (Vec<f64>, Vec<f64>) {
    let n = signal.len();
    if n < 4 {
        return (Vec::new(), Vec::new());
    }
    let mean = signal.iter().sum::<f64>() / n as f64;
    let window: Vec<f64> = (0..n)
        .map(|i| 0.5 - 0.5 * (std::f64::consts::TAU * i as f64 / (n - 1) as f64).cos())
        .collect();
    let wsum: f64 = window.iter().sum();
    let mut buf: Vec<Complex<f64>> = signal
        .iter()
        .zip(&window)
        .map(|(x, w)| Complex::new((x - mean) * w, 0.0))
        .collect();
    FftPlanner::new().plan_fft_forward(n).process(&mut buf);
    let half = n / 2 + 1;
    let freqs = (0..half).map(|k| k as f64 * rate_hz / n as f64).collect();
    let amps = buf[..half].iter().map(|c| 2.0 * c.norm() / wsum).collect();
    (freqs, amps)
}

/// An averaged amplitude spectrum built as the samples arrive (module docs,
/// “Averaged segments”).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Welch {
    rate_hz: f64,
    segment: usize,
    /// Samples not yet in a finished segment (at most one segment).
    pending: Vec<f64>,
    /// Sum over the finished segments of each bin's squared amplitude.
    power_sum: Vec<f64>,
    /// Finished segments.
    segments: u64,
}

impl Welch {
    /// An empty spectrum of samples at `rate_hz`, in segments of `segment`
    /// samples (at least 4).
    pub fn new(rate_hz: f64, segment: usize) -> Self {
        Self {
            rate_hz,
            segment: segment.max(4),
            pending: Vec::new(),
            power_sum: Vec::new(),
            segments: 0,
        }
    }

    /// Adds the next sample.
    pub fn push(&mut self, x: f64) {
        self.pending.push(x);
        if self.pending.len() < self.segment {
            return;
        }
        let (_, amps) = amplitude_spectrum(&self.pending, self.rate_hz);
        if self.power_sum.is_empty() {
            self.power_sum = vec![0.0; amps.len()];
        }
        for (p, a) in self.power_sum.iter_mut().zip(&amps) {
            *p += a * a;
        }
        self.segments += 1;
        self.pending.drain(..self.segment / 2);
    }

    /// Whether no sample was taken.
    pub fn is_empty(&self) -> bool {
        self.segments == 0 && self.pending.is_empty()
    }

    /// The spectrum of the samples so far: (frequencies, amplitudes).
    pub fn spectrum(&self) -> (Vec<f64>, Vec<f64>) {
        if self.segments == 0 {
            return amplitude_spectrum(&self.pending, self.rate_hz);
        }
        let n = self.segments as f64;
        let freqs = (0..self.power_sum.len())
            .map(|k| k as f64 * self.rate_hz / self.segment as f64)
            .collect();
        let amps = self.power_sum.iter().map(|p| (p / n).sqrt()).collect();
        (freqs, amps)
    }
}

/// The averaged amplitude spectrum of `signal` in segments of `segment`
/// samples (module docs): what [`Welch`] gives fed the same samples.
pub fn welch_spectrum(signal: &[f64], rate_hz: f64, segment: usize) -> (Vec<f64>, Vec<f64>) {
    let mut w = Welch::new(rate_hz, segment);
    for &x in signal {
        w.push(x);
    }
    w.spectrum()
}

/// The highest spectral peak of `signal` with frequency in [lo_hz, hi_hz],
/// refined between bins: (frequency, amplitude). `None` if no bin lies in the band.
pub fn main_peak(signal: &[f64], rate_hz: f64, lo_hz: f64, hi_hz: f64) -> Option<(f64, f64)> {
    let (freqs, amps) = amplitude_spectrum(signal, rate_hz);
    peak_in(&freqs, &amps, lo_hz, hi_hz)
}

/// The highest peak of a spectrum (frequencies, amplitudes) with frequency
/// in [lo_hz, hi_hz], refined between bins as [`main_peak`] does.
pub fn peak_in(freqs: &[f64], amps: &[f64], lo_hz: f64, hi_hz: f64) -> Option<(f64, f64)> {
    let k = (1..freqs.len().min(amps.len()).saturating_sub(1))
        .filter(|&k| freqs[k] >= lo_hz && freqs[k] <= hi_hz)
        .max_by(|&a, &b| amps[a].total_cmp(&amps[b]))?;
    let df = freqs[1] - freqs[0];
    let (a, b, c) = (amps[k - 1], amps[k], amps[k + 1]);
    let shift = if a > 0.0 && b > 0.0 && c > 0.0 {
        let (la, lb, lc) = (a.ln(), b.ln(), c.ln());
        let denom = la - 2.0 * lb + lc;
        if denom < 0.0 {
            (0.5 * (la - lc) / denom).clamp(-0.5, 0.5)
        } else {
            0.0
        }
    } else {
        0.0
    };
    Some((freqs[k] + shift * df, b))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sine_frequency_and_amplitude() {
        // 6.1 Hz, amplitude 3 mm, plus a 120 Hz sawtooth-like tone that must not win in 1–50 Hz.
        let rate = 1000.0;
        let signal: Vec<f64> = (0..8500)
            .map(|i| {
                let t = i as f64 / rate;
                3e-3 * (std::f64::consts::TAU * 6.1 * t).sin()
                    + 5e-3 * (std::f64::consts::TAU * 120.0 * t).sin()
                    + 1e-2
            })
            .collect();
        let (f, a) = main_peak(&signal, rate, 1.0, 50.0).expect("peak");
        assert!((f - 6.1).abs() < 0.01, "{f}");
        assert!((a - 3e-3).abs() < 0.1 * 3e-3, "{a}");
    }

    /// Reproducible Gaussian noise of standard deviation `sigma`.
    fn noise(seed: u64, n: usize, sigma: f64) -> Vec<f64> {
        let mut rng = crate::rng::SeededRng::new(seed);
        (0..n).map(|_| sigma * rng.normal()).collect()
    }

    #[test]
    fn welch_finds_a_sine_in_noise_and_averages_the_noise_down() {
        // 60 s at 1 kHz of a 6.1 Hz sine of amplitude A = 3 mm on an offset,
        // in white noise of σ = 1 cm: 6 whole segments of N = 16384.
        let (rate, n, a, sigma) = (1000.0, 60_000, 3e-3, 1e-2);
        let signal: Vec<f64> = noise(11, n, sigma)
            .iter()
            .enumerate()
            .map(|(i, e)| 0.2 + a * (std::f64::consts::TAU * 6.1 * i as f64 / rate).sin() + e)
            .collect();
        let (freqs, amps) = welch_spectrum(&signal, rate, WELCH_SEGMENT);
        let df = rate / WELCH_SEGMENT as f64;
        assert_eq!(freqs.len(), WELCH_SEGMENT / 2 + 1);
        let (f, peak) = peak_in(&freqs, &amps, 1.0, 50.0).expect("peak");
        // The peak within a tenth of a bin, its height within 5 % of A (6.1 Hz
        // is 0.06 bin from a bin centre: no scalloping loss to speak of).
        assert!((f - 6.1).abs() < 0.1 * df, "{f}");
        assert!((peak - a).abs() < 0.05 * a, "{peak}");
        // Noise floor: for white noise of variance σ² a Hann-windowed bin
        // scaled by 2/Σw has E[a²] = 4σ² Σw²/(Σw)² = 6σ²/(N − 1) (Σw = (N−1)/2,
        // Σw² = 3(N−1)/8). Over ~4900 bins in 100–400 Hz the mean is within
        // a few percent; tolerance 5 %.
        let band: Vec<f64> = freqs
            .iter()
            .zip(&amps)
            .filter(|(f, _)| (100.0..400.0).contains(*f))
            .map(|(_, a)| a * a)
            .collect();
        let mean = band.iter().sum::<f64>() / band.len() as f64;
        let expected = 6.0 * sigma * sigma / (WELCH_SEGMENT - 1) as f64;
        assert!((mean / expected - 1.0).abs() < 0.05, "{mean} vs {expected}");
        // A single segment's power in a noise bin is exponential (relative
        // spread 1); the mean of K = 6 half-overlapping Hann segments has
        // relative spread √((1 + 2 · 0.167²)/K) ≈ 0.42 (Welch 1967, the
        // overlap correlation of a Hann window at 50 %). Between 0.3 and 0.55.
        let spread = (band.iter().map(|p| (p - mean).powi(2)).sum::<f64>() / band.len() as f64)
            .sqrt()
            / mean;
        assert!((0.3..0.55).contains(&spread), "{spread}");
    }

    #[test]
    fn welch_as_the_samples_arrive_is_the_batch_and_one_segment_is_one_spectrum() {
        let signal = noise(12, 3000, 1.0);
        // At most one segment: the plain spectrum, bit for bit.
        assert_eq!(
            welch_spectrum(&signal, 500.0, 4096),
            amplitude_spectrum(&signal, 500.0)
        );
        assert_eq!(
            welch_spectrum(&signal[..1024], 500.0, 1024),
            amplitude_spectrum(&signal[..1024], 500.0)
        );
        // Streamed with a pause (a copy of the accumulator, as a checkpoint
        // would keep it) and continued: the same bits as the batch.
        let mut w = Welch::new(500.0, 512);
        for &x in &signal[..1700] {
            w.push(x);
        }
        let mut resumed = w.clone();
        for &x in &signal[1700..] {
            resumed.push(x);
        }
        assert_eq!(resumed.spectrum(), welch_spectrum(&signal, 500.0, 512));
        assert!(Welch::new(500.0, 512).is_empty());
    }

    #[test]
    fn too_short_has_no_peak() {
        assert!(main_peak(&[1.0, 2.0], 100.0, 1.0, 50.0).is_none());
    }
}
