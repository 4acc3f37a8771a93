//! A life: a number of hours, or infinite (docs/design-checks.md, "The
//! shared types"). In JSON a number or the string `"infinite"`, never null
//! nor NaN. Fatigue reports one from its damage per hour; a duty cycle the
//! shortest of its checks'.
//!
//! It computes nothing but the inverse of a rate.

use serde::{Deserialize, Serialize};

/// Hours of operation until a limit is reached, or never.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Life {
    /// This many hours (finite, ≥ 0).
    Hours(f64),
    /// The limit is never reached (nothing accumulates).
    Infinite,
}

impl Life {
    /// The life of a rate per hour that reaches its limit at 1: 1 / rate,
    /// infinite for a rate that is zero or negative (or not a number: a
    /// rate nothing was counted for).
    pub fn of_rate_per_hour(rate: f64) -> Self {
        if rate > 0.0 && rate.is_finite() {
            Self::Hours(1.0 / rate)
        } else if rate == f64::INFINITY {
            Self::Hours(0.0)
        } else {
            Self::Infinite
        }
    }

    /// The hours, `None` when infinite.
    pub fn hours(self) -> Option<f64> {
        match self {
            Self::Hours(h) => Some(h),
            Self::Infinite => None,
        }
    }

    /// Whether `self` is shorter than `other`.
    pub fn is_shorter_than(self, other: Self) -> bool {
        match (self, other) {
            (Self::Hours(a), Self::Hours(b)) => a < b,
            (Self::Hours(_), Self::Infinite) => true,
            (Self::Infinite, _) => false,
        }
    }
}

impl std::fmt::Display for Life {
    /// `12345 h`, `2.500 h`, `2.335e-4 h` (four significant digits at least), or `infinite`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Infinite => f.write_str("infinite"),
            Self::Hours(h) if *h >= 1e7 => write!(f, "{h:.3e} h"),
            Self::Hours(h) if *h >= 100.0 => write!(f, "{h:.0} h"),
            Self::Hours(h) if *h >= 0.01 => write!(f, "{h:.3} h"),
            Self::Hours(h) => write!(f, "{h:.3e} h"),
        }
    }
}

impl Serialize for Life {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Self::Hours(h) => s.serialize_f64(*h),
            Self::Infinite => s.serialize_str("infinite"),
        }
    }
}

impl<'de> Deserialize<'de> for Life {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Written {
            Hours(f64),
            Text(String),
        }
        match Written::deserialize(d)? {
            Written::Hours(h) if h.is_finite() && h >= 0.0 => Ok(Self::Hours(h)),
            Written::Text(t) if t == "infinite" => Ok(Self::Infinite),
            Written::Hours(h) => Err(serde::de::Error::custom(format!(
                "a life is a number of hours >= 0 or \"infinite\", got {h}"
            ))),
            Written::Text(t) => Err(serde::de::Error::custom(format!(
                "a life is a number of hours >= 0 or \"infinite\", got \"{t}\""
            ))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_life_is_a_number_or_the_string_infinite_in_json() {
        assert_eq!(
            serde_json::to_string(&Life::Hours(1500.0)).ok().as_deref(),
            Some("1500.0")
        );
        assert_eq!(
            serde_json::to_string(&Life::Infinite).ok().as_deref(),
            Some("\"infinite\"")
        );
        for life in [Life::Hours(2.5), Life::Infinite] {
            let text = serde_json::to_string(&life).unwrap_or_default();
            assert_eq!(serde_json::from_str::<Life>(&text).ok(), Some(life));
        }
        assert!(serde_json::from_str::<Life>("\"forever\"").is_err());
        assert!(serde_json::from_str::<Life>("-1.0").is_err());
    }

    #[test]
    fn a_rate_gives_its_inverse_and_none_is_infinite() {
        assert_eq!(Life::of_rate_per_hour(1e-4), Life::Hours(1e4));
        assert_eq!(Life::of_rate_per_hour(0.0), Life::Infinite);
        assert_eq!(Life::of_rate_per_hour(f64::NAN), Life::Infinite);
        assert_eq!(Life::of_rate_per_hour(f64::INFINITY), Life::Hours(0.0));
        assert!(Life::Hours(3.0).is_shorter_than(Life::Infinite));
        assert!(!Life::Infinite.is_shorter_than(Life::Hours(3.0)));
    }
}
