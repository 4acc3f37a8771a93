//! Analytical references (docs/model.md, “Analytical references”).

/// Transverse eigenfrequency n of a pretensioned string (52):
/// f_n = n √(F / (4 l m)), F tension (N), l length (m), m the strand's mass (kg).
pub(crate) fn string_frequency_hz(n: u32, tension_n: f64, length_m: f64, mass_kg: f64) -> f64 {
    f64::from(n) * (tension_n / (4.0 * length_m * mass_kg)).sqrt()
}

/// Eigenfrequency n of an axially moving string:
/// f_n = (n / 2l) c (1 − V²/c²), c² = F / μ, μ the mass per length (kg/m).
/// Zero when the string moves at or above its wave speed (no standing wave).
pub(crate) fn moving_string_frequency_hz(
    n: u32,
    tension_n: f64,
    length_m: f64,
    mass_per_length_kg_m: f64,
    speed_m_s: f64,
) -> f64 {
    if !(tension_n > 0.0 && length_m > 0.0 && mass_per_length_kg_m > 0.0) {
        return 0.0;
    }
    let c2 = tension_n / mass_per_length_kg_m;
    let factor = 1.0 - speed_m_s * speed_m_s / c2;
    if factor <= 0.0 {
        return 0.0;
    }
    f64::from(n) / (2.0 * length_m) * c2.sqrt() * factor
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn string_forms_agree_at_rest() {
        // (52) with m = μ l equals the moving form at V = 0.
        let (f, l, mu) = (21e3, 1.8797, 3.01 / 0.0889);
        let a = string_frequency_hz(1, f, l, mu * l);
        let b = moving_string_frequency_hz(1, f, l, mu, 0.0);
        assert!((a - b).abs() < 1e-12);
    }

    #[test]
    fn moving_string_gives_segment1_frequencies_at_25_and_19_kn() {
        // docs/model.md, “Transverse vibration of a free strand”: segment 1 at 120 rpm
        // (V = 10.67 m/s, μ = 33.86 kg/m): 25 kN → 6.1 Hz, 19 kN → 5.0 Hz.
        let mu = 3.01 / 0.0889;
        let f25 = moving_string_frequency_hz(1, 25e3, 1.8797, mu, 10.67);
        let f19 = moving_string_frequency_hz(1, 19e3, 1.8797, mu, 10.67);
        assert!((f25 - 6.1).abs() < 0.05, "{f25}");
        assert!((f19 - 5.0).abs() < 0.05, "{f19}");
    }
}
