//! Numbers for people: a value in an SI unit written with the prefix and the
//! digits that keep it readable (2.0e-5 m is "20.0 µm", never "0.00 mm"),
//! for reports, tables and figure axes.
//!
//! Only decimal SI prefixes in steps of 1000 (n, µ, m, k, M, G): no centi-
//! or deci-. What this module does not do: convert between unit systems
//! (rpm, degrees and inches are converted at the scene's boundary) or parse.

/// An SI prefix in a step of 1000 and its power of ten.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Prefix {
    /// `"µ"`, `"m"`, `""`, `"k"`, …
    pub symbol: &'static str,
    /// The power of ten it stands for (−9 … 9, a multiple of 3).
    pub exponent: i32,
}

const PREFIXES: [Prefix; 7] = [
    Prefix {
        symbol: "n",
        exponent: -9,
    },
    Prefix {
        symbol: "µ",
        exponent: -6,
    },
    Prefix {
        symbol: "m",
        exponent: -3,
    },
    Prefix {
        symbol: "",
        exponent: 0,
    },
    Prefix {
        symbol: "k",
        exponent: 3,
    },
    Prefix {
        symbol: "M",
        exponent: 6,
    },
    Prefix {
        symbol: "G",
        exponent: 9,
    },
];

const NONE: Prefix = PREFIXES[3];

impl Prefix {
    /// The prefix that puts |`value`| in [1, 1000) (clamped to n … G); none
    /// for 0 and for a non-finite value.
    pub fn of(value: f64) -> Self {
        let a = value.abs();
        if !(a > 0.0 && a.is_finite()) {
            return NONE;
        }
        let e = (a.log10().floor() as i32).div_euclid(3) * 3;
        // log10 can land a hair below an exact power of ten.
        let e = if a / 10f64.powi(e) >= 1000.0 - 1e-9 {
            e + 3
        } else {
            e
        };
        PREFIXES
            .iter()
            .copied()
            .find(|p| p.exponent == e.clamp(-9, 9))
            .unwrap_or(NONE)
    }

    /// `value` (in the base unit) in this prefix's unit.
    pub fn scale(&self, value: f64) -> f64 {
        value / 10f64.powi(self.exponent)
    }

    /// The prefixed unit: `Prefix::of(2e-5).unit("m")` is `"µm"`.
    pub fn unit(&self, unit: &str) -> String {
        format!("{}{unit}", self.symbol)
    }
}

/// `value`, in `unit` (a base or derived SI unit: "m", "N", "Hz", "N·m",
/// "s", "W"), with the prefix that puts it in [1, 1000) and three
/// significant digits: 2.0e-5 m → "20.0 µm", 1234.5 N → "1.23 kN",
/// 0.5 Hz → "500 mHz", 0 → "0 N". A non-finite value is "—".
pub fn si(value: f64, unit: &str) -> String {
    if !value.is_finite() {
        return "—".to_owned();
    }
    if value == 0.0 {
        return format!("0 {unit}");
    }
    // Round to three significant digits first: 999.7 µm is "1.00 mm".
    let digits = value.abs().log10().floor() as i32;
    let step = 10f64.powi(digits - 2);
    let rounded = (value / step).round() * step;
    let prefix = Prefix::of(rounded);
    let m = prefix.scale(rounded);
    let decimals = (2 - m.abs().log10().floor() as i32).clamp(0, 2) as usize;
    format!("{m:.decimals$} {}", prefix.unit(unit))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fiftieth_of_a_millimetre_is_twenty_micrometres() {
        assert_eq!(si(2.0e-5, "m"), "20.0 µm");
        assert_eq!(si(2.03e-5, "m"), "20.3 µm");
    }

    #[test]
    fn si_keeps_three_significant_digits_and_the_sign() {
        assert_eq!(si(1234.5, "N"), "1.23 kN");
        assert_eq!(si(-0.04, "N·m"), "-40.0 mN·m");
        assert_eq!(si(123.4, "Hz"), "123 Hz");
        assert_eq!(si(4.587155963302753e-6, "s"), "4.59 µs");
        assert_eq!(si(1.0, "m"), "1.00 m");
    }

    #[test]
    fn rounding_up_to_a_thousand_moves_to_the_next_prefix() {
        assert_eq!(si(9.997e-4, "m"), "1.00 mm");
        assert_eq!(si(999.96, "N"), "1.00 kN");
    }

    #[test]
    fn zero_and_non_finite_values_are_written_plainly() {
        assert_eq!(si(0.0, "N"), "0 N");
        assert_eq!(si(f64::NAN, "N"), "—");
        assert_eq!(si(f64::INFINITY, "N"), "—");
    }

    #[test]
    fn the_prefix_puts_the_value_between_one_and_a_thousand() {
        for (v, symbol) in [
            (2e-5, "µ"),
            (1e-3, "m"),
            (0.999, "m"),
            (1.0, ""),
            (999.0, ""),
            (1000.0, "k"),
            (3.2e7, "M"),
            (0.0, ""),
            (1e-15, "n"),
            (1e15, "G"),
        ] {
            assert_eq!(Prefix::of(v).symbol, symbol, "{v}");
        }
        assert!((Prefix::of(2e-5).scale(2e-5) - 20.0).abs() < 1e-12);
        assert_eq!(Prefix::of(2e-5).unit("m"), "µm");
    }
}
