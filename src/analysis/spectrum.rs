//! Amplitude spectra and peak picking.
//!
//! Normalisation: the signal's mean is removed, a Hann window applied, and
//! the one-sided amplitude spectrum scaled by 2 / Σw so that a sine of
//! amplitude A sampled over many periods shows a peak of height ≈ A.
//! The peak frequency is refined by fitting a parabola through the log
//! amplitudes of the highest bin and its neighbours (Gaussian interpolation),
//! which for a Hann window is accurate to a few percent of a bin.

use rustfft::FftPlanner;
use rustfft::num_complex::Complex;

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

/// The highest spectral peak of `signal` with frequency in [lo_hz, hi_hz],
/// refined between bins: (frequency, amplitude). `None` if no bin lies in the band.
pub fn main_peak(signal: &[f64], rate_hz: f64, lo_hz: f64, hi_hz: f64) -> Option<(f64, f64)> {
    let (freqs, amps) = amplitude_spectrum(signal, rate_hz);
    let k = (1..freqs.len().saturating_sub(1))
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

    #[test]
    fn too_short_has_no_peak() {
        assert!(main_peak(&[1.0, 2.0], 100.0, 1.0, 50.0).is_none());
    }
}
