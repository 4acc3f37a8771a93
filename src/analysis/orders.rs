//! Order analysis: signals resampled to the driver's angle and their spectra
//! over whole revolutions, so that a component locked to the driver's
//! rotation stays in one bin however the speed varies.
//!
//! # Method
//!
//! 1. **Rotation angle.** φ = s (θ − θ₀) with θ the driver's angle as
//!    sampled and s the sign of its net turn, so φ grows whichever way the
//!    driver turns; an order is a number of cycles per revolution in that
//!    sense. Phases are measured from θ = 0 of the angles given, not from
//!    the window's start (the sweep gives the angle turned since t = 0).
//! 2. **Whole revolutions.** The window is the last N whole revolutions
//!    turned by the samples (N a multiple of the order step's denominator
//!    D, so every order asked for falls on a bin), ending at the last
//!    sample.
//! 3. **Resampling** to M points per revolution, uniform in φ, by cubic
//!    Lagrange interpolation through the four samples around each point
//!    (non-uniform in φ: the driver's speed varies). The error of a
//!    component with h radians of its own phase between samples is of order
//!    h⁴/24 of its amplitude (4·10⁻⁴ at 20 samples per period); linear
//!    interpolation would lose h²/8 (1.2 %). M = 8 × the largest order
//!    (at least 16), so the resampled grid aliases nothing asked for.
//! 4. **Spectrum**: the DFT of the N M points, no window (the record holds
//!    whole revolutions, so an order that is a multiple of 1/N is exactly
//!    periodic in it and does not leak). Order k sits in bin k N. With
//!    x(φ) = x̄ + Σ A_k cos(k φ + ψ_k), A_k = 2 |X| / (N M) and
//!    ψ_k = arg X − k φ_start (radians, wrapped to (−π, π]).
//!
//! The frequency reported with an order is k × the mean revolutions per
//! second over the window (N revolutions over its duration).
//!
//! What this module does not do: choose the signals (the sweep study does)
//! or run anything.

use std::f64::consts::{PI, TAU};

use rustfft::FftPlanner;
use rustfft::num_complex::Complex;

/// Largest denominator of an order step (1/D).
pub(crate) const MAX_ORDER_DENOMINATOR: u32 = 16;

/// Why an order spectrum could not be taken.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum OrderError {
    /// No order is asked for.
    #[error(
        "the order set is empty: the largest order must be ≥ the order step (got largest {max_order}, step {step})"
    )]
    EmptyOrderSet {
        /// Largest order asked for.
        max_order: f64,
        /// The step between orders.
        step: f64,
    },
    /// The order step is not 1/D for a whole D in 1..=16.
    #[error(
        "the order step must be 1/D for a whole number D from 1 to {MAX_ORDER_DENOMINATOR} (1, 0.5, 0.25, …), got {0}"
    )]
    BadStep(f64),
    /// The samples turn the driver through too few revolutions.
    #[error(
        "the window turns the driver through {revolutions:.2} revolutions; order analysis needs at least {needed} whole ones"
    )]
    TooFewRevolutions {
        /// Revolutions turned.
        revolutions: f64,
        /// Whole revolutions needed.
        needed: u32,
    },
    /// The driver's angle does not advance steadily one way, or a series
    /// has not one value per angle sample, or holds a non-finite value.
    #[error("order analysis: {0}")]
    BadInput(String),
}

/// The orders analysed: `step`, 2 `step`, … up to `max_order`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrderSet {
    max_order: f64,
    denominator: u32,
}

impl OrderSet {
    /// Orders `1/D, 2/D, …, max_order` for `step` = 1/D; an error names what is wrong.
    pub fn new(max_order: f64, step: f64) -> Result<Self, OrderError> {
        let d = (1.0 / step).round();
        let whole = step.is_finite()
            && step > 0.0
            && (1.0..=f64::from(MAX_ORDER_DENOMINATOR)).contains(&d)
            && (1.0 / step - d).abs() <= 1e-9 * d;
        if !whole {
            return Err(OrderError::BadStep(step));
        }
        if !(max_order.is_finite() && max_order >= step * (1.0 - 1e-12)) {
            return Err(OrderError::EmptyOrderSet { max_order, step });
        }
        Ok(Self {
            max_order,
            denominator: d as u32,
        })
    }

    /// Largest order, cycles per revolution of the driver.
    pub fn max_order(&self) -> f64 {
        self.max_order
    }

    /// Denominator D of the step 1/D.
    pub(crate) fn denominator(&self) -> u32 {
        self.denominator
    }

    /// The step between orders, 1/D.
    pub(crate) fn step(&self) -> f64 {
        1.0 / f64::from(self.denominator)
    }

    /// Number of orders in the set.
    pub(crate) fn len(&self) -> usize {
        (self.max_order * f64::from(self.denominator) + 1e-9).floor() as usize
    }

    /// Resampled points per revolution: 8 × the largest order, at least 16.
    pub(crate) fn points_per_revolution(&self) -> usize {
        ((8.0 * self.max_order).ceil() as usize).max(16)
    }
}

/// One order's amplitude and phase.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrderComponent {
    /// Order, cycles per revolution of the driver.
    pub order: f64,
    /// Its frequency at the window's mean speed, Hz.
    pub frequency_hz: f64,
    /// Amplitude A, in the signal's unit.
    pub amplitude: f64,
    /// Phase ψ in x̄ + A cos(k φ + ψ), rad, in (−π, π].
    pub phase_rad: f64,
}

/// The order spectrum of one signal over a window.
#[derive(Clone, Debug, PartialEq)]
pub struct OrderSpectrum {
    /// Mean of the resampled signal.
    pub mean: f64,
    /// The orders asked for, ascending.
    pub components: Vec<OrderComponent>,
}

impl OrderSpectrum {
    /// The component of `order` (to within 10⁻⁹), if it was asked for.
    pub(crate) fn at(&self, order: f64) -> Option<&OrderComponent> {
        self.components
            .iter()
            .find(|c| (c.order - order).abs() < 1e-9)
    }
}

/// The driver's rotation over a window of samples, cut to whole revolutions
/// (module docs, steps 1–2): the common part of every signal's analysis.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct AngleWindow {
    /// Time of each sample, s.
    t_s: Vec<f64>,
    /// Rotation angle φ of each sample, rad, increasing.
    phi: Vec<f64>,
    /// φ at the start of the whole revolutions.
    phi_start: f64,
    /// Whole revolutions N.
    revolutions: usize,
    /// The sign s that makes φ increase.
    sign: f64,
    /// Mean revolutions per second over the whole revolutions.
    rev_per_s: f64,
    orders: OrderSet,
}

impl AngleWindow {
    /// The whole revolutions of the driver's angle `theta_rad` sampled at
    /// `t_s` (module docs), for the orders in `orders`.
    pub(crate) fn new(
        t_s: &[f64],
        theta_rad: &[f64],
        orders: OrderSet,
    ) -> Result<Self, OrderError> {
        if t_s.len() != theta_rad.len() || t_s.len() < 4 {
            return Err(OrderError::BadInput(format!(
                "{} times and {} angles (at least 4 of each, as many of one as of the other)",
                t_s.len(),
                theta_rad.len()
            )));
        }
        if t_s.iter().chain(theta_rad).any(|v| !v.is_finite()) {
            return Err(OrderError::BadInput(
                "a time or driver angle is not finite".to_owned(),
            ));
        }
        let turn = theta_rad[theta_rad.len() - 1] - theta_rad[0];
        let sign = if turn < 0.0 { -1.0 } else { 1.0 };
        let phi: Vec<f64> = theta_rad.iter().map(|th| sign * th).collect();
        if phi.windows(2).any(|w| !(w[1] > w[0])) {
            return Err(OrderError::BadInput(
                "the driver's angle must advance one way at every sample (the driver stood still or turned back)"
                    .to_owned(),
            ));
        }
        let d = orders.denominator as usize;
        let span = phi[phi.len() - 1] - phi[0];
        let whole = (span / TAU + 1e-9).floor() as usize;
        let revolutions = whole - whole % d;
        if revolutions == 0 {
            return Err(OrderError::TooFewRevolutions {
                revolutions: span / TAU,
                needed: orders.denominator,
            });
        }
        let phi_end = phi[phi.len() - 1];
        let phi_start = phi_end - revolutions as f64 * TAU;
        let t_start = interpolate(&phi, t_s, phi_start);
        let duration = t_s[t_s.len() - 1] - t_start;
        Ok(Self {
            t_s: t_s.to_vec(),
            phi,
            phi_start,
            revolutions,
            sign,
            rev_per_s: revolutions as f64 / duration.max(f64::MIN_POSITIVE),
            orders,
        })
    }

    /// Whole revolutions analysed.
    pub(crate) fn revolutions(&self) -> usize {
        self.revolutions
    }

    /// Mean revolutions per second of the driver over them.
    pub(crate) fn rev_per_s(&self) -> f64 {
        self.rev_per_s
    }

    /// Time at which the whole revolutions start, s.
    pub(crate) fn start_s(&self) -> f64 {
        interpolate(&self.phi, &self.t_s, self.phi_start)
    }

    /// `x` (one value per sample) resampled uniformly in φ over the whole
    /// revolutions, M points per revolution (module docs, step 3).
    pub(crate) fn resample(&self, x: &[f64]) -> Result<Vec<f64>, OrderError> {
        if x.len() != self.phi.len() {
            return Err(OrderError::BadInput(format!(
                "{} values against {} driver angles",
                x.len(),
                self.phi.len()
            )));
        }
        if x.iter().any(|v| !v.is_finite()) {
            return Err(OrderError::BadInput("a value is not finite".to_owned()));
        }
        let m = self.orders.points_per_revolution();
        let n = m * self.revolutions;
        let dphi = TAU / m as f64;
        Ok((0..n)
            .map(|j| interpolate(&self.phi, x, self.phi_start + j as f64 * dphi))
            .collect())
    }

    /// The order spectrum of `x` (one value per sample; module docs, step 4).
    pub(crate) fn spectrum(&self, x: &[f64]) -> Result<OrderSpectrum, OrderError> {
        let resampled = self.resample(x)?;
        Ok(self.spectrum_of(&resampled))
    }

    /// The order spectrum of `x` less its linear trend in φ over the window:
    /// the line through x at the window's two ends (one revolution apart by
    /// a whole number, so every order has the same value at both and the
    /// line holds the trend alone) is taken out before the DFT. A linear
    /// trend of rise Δ left in would leak Δ/(π k N) into order k of N
    /// revolutions; a signal that is a linear trend plus orders is analysed
    /// exactly. For a slowly changing speed (a run-up). The mean is the
    /// signal's own.
    pub(crate) fn spectrum_detrended(&self, x: &[f64]) -> Result<OrderSpectrum, OrderError> {
        let mut resampled = self.resample(x)?;
        let n = resampled.len();
        let mean = resampled.iter().sum::<f64>() / n as f64;
        let end = interpolate(&self.phi, x, self.phi_start + self.revolutions as f64 * TAU);
        let rise = end - resampled[0];
        for (j, v) in resampled.iter_mut().enumerate() {
            *v -= rise * j as f64 / n as f64;
        }
        let mut spectrum = self.spectrum_of(&resampled);
        spectrum.mean = mean;
        Ok(spectrum)
    }

    /// The spectrum of the resampled points (module docs, step 4).
    fn spectrum_of(&self, resampled: &[f64]) -> OrderSpectrum {
        let n = resampled.len();
        let mut buf: Vec<Complex<f64>> = resampled.iter().map(|&v| Complex::new(v, 0.0)).collect();
        FftPlanner::new().plan_fft_forward(n).process(&mut buf);
        let scale = 2.0 / n as f64;
        let per = self.revolutions / self.orders.denominator as usize;
        let components = (1..=self.orders.len())
            .map(|i| {
                let order = i as f64 / f64::from(self.orders.denominator);
                let c = buf[i * per];
                let phase = wrap(c.arg() - order * self.phi_start);
                OrderComponent {
                    order,
                    frequency_hz: order * self.rev_per_s,
                    amplitude: scale * c.norm(),
                    phase_rad: phase,
                }
            })
            .collect();
        OrderSpectrum {
            mean: buf[0].re / n as f64,
            components,
        }
    }
}

/// An angle wrapped to (−π, π].
fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(TAU);
    if w > PI { w - TAU } else { w }
}

/// `y` at `at` by cubic Lagrange interpolation through the four knots of the
/// increasing `x` around it (the nearest three or two at either end).
fn interpolate(x: &[f64], y: &[f64], at: f64) -> f64 {
    let n = x.len();
    // The knot interval [x[i], x[i + 1]] holding `at` (clamped to the ends).
    let i = x.partition_point(|&v| v <= at).clamp(1, n - 1) - 1;
    let lo = i.saturating_sub(1).min(n.saturating_sub(4));
    let hi = (lo + 4).min(n);
    let mut sum = 0.0;
    for a in lo..hi {
        let mut w = 1.0;
        for b in lo..hi {
            if a != b {
                w *= (at - x[b]) / (x[a] - x[b]);
            }
        }
        sum += w * y[a];
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cubic_interpolation_is_exact_on_a_cubic() {
        let x = [0.0, 0.3, 1.1, 1.5, 2.6, 3.0];
        let f = |v: f64| 2.0 - v + 0.5 * v * v - 0.25 * v * v * v;
        let y: Vec<f64> = x.iter().map(|&v| f(v)).collect();
        for at in [0.1, 0.7, 1.3, 2.0, 2.9] {
            assert!((interpolate(&x, &y, at) - f(at)).abs() < 1e-12, "{at}");
        }
    }

    #[test]
    fn an_order_step_that_is_not_one_over_a_whole_number_is_refused() {
        assert!(matches!(
            OrderSet::new(10.0, 0.3),
            Err(OrderError::BadStep(_))
        ));
        assert!(matches!(
            OrderSet::new(0.0, 1.0),
            Err(OrderError::EmptyOrderSet { .. })
        ));
        assert_eq!(OrderSet::new(3.0, 0.5).expect("valid").len(), 6);
    }

    #[test]
    fn wrap_keeps_angles_in_the_half_open_interval() {
        assert!((wrap(3.0 * PI) - PI).abs() < 1e-12);
        assert!((wrap(-PI) - PI).abs() < 1e-12);
        assert!((wrap(0.5) - 0.5).abs() < 1e-15);
    }
}
