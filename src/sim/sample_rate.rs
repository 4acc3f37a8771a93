//! The sample rate of a run's outputs: stated once, in Hz, and taken every
//! whole number of integration steps. A rate the step does not divide is
//! refused, never rounded to a neighbouring one.

/// A sample rate that a whole number of steps of `dt_s` makes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampleRate {
    /// Samples per second, Hz: 1/(`every` · dt), the rate asked for to
    /// within rounding.
    pub rate_hz: f64,
    /// Integration steps from one sample to the next (≥ 1), as
    /// [`super::Simulation::run`] takes it.
    pub every: u64,
}

/// Why a sample rate cannot be taken with a step.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SampleRateError {
    /// Not a finite rate above zero.
    #[error("the sample rate must be a finite number > 0 Hz, got {rate_hz}")]
    NotPositive {
        /// The rate asked for, Hz.
        rate_hz: f64,
    },
    /// 1/(rate · dt) is no whole number of steps (to within 1e-9).
    #[error(
        "a sample rate of {rate_hz} Hz is not a whole number of steps of dt = {dt_s:e} s \
         (1/(rate · dt) = {steps:.4} steps); choose a rate for which it is one"
    )]
    NotWholeSteps {
        /// The rate asked for, Hz.
        rate_hz: f64,
        /// The integration step, s.
        dt_s: f64,
        /// Steps per sample, 1/(rate · dt).
        steps: f64,
    },
}

impl SampleRate {
    /// Sampling at `rate_hz` with steps of `dt_s`: every 1/(rate · dt) steps,
    /// if that is a whole number (within 1e-9) of at least one.
    pub fn new(rate_hz: f64, dt_s: f64) -> Result<Self, SampleRateError> {
        if !(rate_hz.is_finite() && rate_hz > 0.0) {
            return Err(SampleRateError::NotPositive { rate_hz });
        }
        let steps = 1.0 / (rate_hz * dt_s);
        let every = steps.round();
        // Negated: a NaN (dt not a positive number) is refused too.
        if !((steps - every).abs() <= 1e-9 && every >= 1.0) {
            return Err(SampleRateError::NotWholeSteps {
                rate_hz,
                dt_s,
                steps,
            });
        }
        Ok(Self {
            rate_hz: 1.0 / (every * dt_s),
            every: every as u64,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rate_the_step_divides_is_taken_every_whole_number_of_steps() {
        let r = SampleRate::new(1000.0, 1e-5).expect("100 steps");
        assert_eq!(r.every, 100);
        approx::assert_relative_eq!(r.rate_hz, 1000.0, max_relative = 1e-12);
        assert_eq!(SampleRate::new(1e5, 1e-5).expect("every step").every, 1);
    }

    #[test]
    fn a_rate_the_step_does_not_divide_is_refused() {
        let e = SampleRate::new(3000.0, 1e-5).expect_err("33.3 steps");
        assert!(matches!(e, SampleRateError::NotWholeSteps { .. }), "{e}");
        assert!(e.to_string().contains("dt = 1e-5 s"), "{e}");
        // Faster than the steps, and nonsense.
        assert!(SampleRate::new(2e5, 1e-5).is_err());
        assert!(SampleRate::new(0.0, 1e-5).is_err());
        assert!(SampleRate::new(f64::NAN, 1e-5).is_err());
        assert!(SampleRate::new(1000.0, 0.0).is_err());
    }
}
