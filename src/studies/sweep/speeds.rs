//! The text forms of driver speeds that the front ends read (the command
//! line's `sweep --rpm` and `--run-up`, the Python bindings' `rpm`): a
//! stepped range `FROM:TO:STEP` and a run-up `FROM:TO`, in rpm. Errors name
//! the option they came from, so each front end can say it in its own terms.

use super::SweepError;

/// Most speeds a stepped range may hold.
pub const MAX_CASES: usize = 100_000;

/// Speeds `FROM:TO:STEP` in rpm (both ends included when STEP divides the
/// span; a last point beyond TO is not added). `what` names the option in errors.
///
/// # Errors
///
/// Not three numbers, not finite, not 0 < FROM ≤ TO and STEP > 0, or more
/// than [`MAX_CASES`] speeds; the error names `what`.
pub fn parse_rpm_range(what: &'static str, text: &str) -> Result<Vec<f64>, SweepError> {
    let bad = |why: &str| SweepError::BadRange {
        what,
        text: text.to_owned(),
        why: format!(
            "{why}; write FROM:TO:STEP in rpm with 0 < FROM ≤ TO and STEP > 0, e.g. 300:3000:100"
        ),
    };
    let parts: Vec<&str> = text.split(':').collect();
    if parts.len() != 3 {
        return Err(bad("three numbers separated by ':' are needed"));
    }
    let nums: Vec<f64> = parts
        .iter()
        .map(|p| p.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| bad("not a number"))?;
    let (from, to, step) = (nums[0], nums[1], nums[2]);
    if !(from.is_finite() && to.is_finite() && step.is_finite()) {
        return Err(bad("not finite"));
    }
    if !(from > 0.0) {
        return Err(bad("FROM must be > 0"));
    }
    if !(to >= from) {
        return Err(bad("TO must not be below FROM"));
    }
    if !(step > 0.0) {
        return Err(bad("STEP must be > 0"));
    }
    let count = ((to - from) / step * (1.0 + 1e-12) + 1e-9).floor() + 1.0;
    if count > MAX_CASES as f64 {
        return Err(bad(&format!("more than {MAX_CASES} speeds")));
    }
    Ok((0..count as usize)
        .map(|i| from + i as f64 * step)
        .collect())
}

/// Two speeds `FROM:TO` in rpm with 0 < FROM < TO (a run-up).
///
/// # Errors
///
/// Not two numbers, or not 0 < FROM < TO.
pub fn parse_run_up(text: &str) -> Result<(f64, f64), SweepError> {
    let bad = |why: &str| SweepError::BadRange {
        what: "--run-up",
        text: text.to_owned(),
        why: format!("{why}; write FROM:TO in rpm with 0 < FROM < TO, e.g. 300:3000"),
    };
    let parts: Vec<&str> = text.split(':').collect();
    if parts.len() != 2 {
        return Err(bad("two numbers separated by ':' are needed"));
    }
    let from: f64 = parts[0].trim().parse().map_err(|_| bad("not a number"))?;
    let to: f64 = parts[1].trim().parse().map_err(|_| bad("not a number"))?;
    if !(from.is_finite() && to.is_finite() && from > 0.0 && to > from) {
        return Err(bad("out of range"));
    }
    Ok((from, to))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_speed_range_includes_both_ends() {
        // 300 to 3000 by 100: (3000 − 300) / 100 + 1 = 28 speeds.
        let rpm = parse_rpm_range("--rpm", "300:3000:100").expect("valid");
        assert_eq!(rpm.len(), 28);
        assert_eq!(rpm[0], 300.0);
        assert_eq!(rpm[27], 3000.0);
        assert_eq!(parse_rpm_range("--rpm", "100:100:5").expect("one").len(), 1);
    }

    #[test]
    fn bad_speed_ranges_are_errors_naming_the_option() {
        for (text, why) in [
            ("300:3000", "three numbers"),
            ("0:3000:100", "FROM must be > 0"),
            ("3000:300:100", "TO must not be below FROM"),
            ("300:3000:0", "STEP must be > 0"),
            ("300:3000:-5", "STEP must be > 0"),
            ("a:3000:100", "not a number"),
            ("1:1e9:1e-3", "more than"),
        ] {
            let e = parse_rpm_range("--rpm", text).expect_err(text);
            let msg = e.to_string();
            assert!(msg.starts_with("--rpm"), "{msg}");
            assert!(msg.contains(why), "{text}: {msg}");
        }
    }

    #[test]
    fn a_run_up_goes_up() {
        assert_eq!(parse_run_up("300:3000").expect("valid"), (300.0, 3000.0));
        for text in ["3000:300", "300", "0:300", "a:300"] {
            let e = parse_run_up(text).expect_err(text);
            assert!(e.to_string().starts_with("--run-up"), "{e}");
        }
    }
}
