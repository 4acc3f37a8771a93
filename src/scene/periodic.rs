//! Quantities periodic in a sprocket's angle, as a scene writes them and as
//! checked: a series of harmonics (a driver's relative speed, a load or
//! drive torque) and a torque tabled over one revolution in a CSV file,
//! read from a file or from a copy given with the scene. Shared by the
//! excitation ([`super::excitation`]) and the governor's drive torque
//! ([`super::governor`]); it knows neither. Evaluating them is the model's.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::checker::Checker;

/// One term of a driver's speed profile, as written
/// (`[[sprockets.speed_harmonics]]`): ω(θ) = ω̄ (1 + Σ a_k sin(k θ + φ_k)).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SpeedHarmonicFile {
    /// Order k: cycles per revolution of the driver, an integer ≥ 1.
    pub order: i64,
    /// Relative amplitude a_k (of the mean speed); Σ |a_k| < 1.
    pub amplitude: f64,
    /// Phase φ_k, degrees (default 0).
    #[serde(default)]
    pub phase_deg: f64,
}

/// One term of a load torque in the sprocket's angle, as written
/// (`[[sprockets.load_harmonics]]`): M(θ) = Σ M_k sin(k θ + φ_k).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct LoadHarmonicFile {
    /// Order k: cycles per revolution of the sprocket, an integer ≥ 1.
    pub order: i64,
    /// Amplitude M_k, N·m.
    pub amplitude_n_m: f64,
    /// Phase φ_k, degrees (default 0).
    #[serde(default)]
    pub phase_deg: f64,
}

/// A load torque tabled over one revolution of the sprocket, as written
/// (`sprockets.load_table`).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct LoadTableFile {
    /// CSV file of rows `angle_deg,torque_n_m`, relative to the scene file's
    /// directory. A first line that is not two numbers is a header; lines
    /// starting with `#` are comments. The angles increase strictly and span
    /// exactly 360°: the last row repeats the first one's torque at the first
    /// angle + 360°.
    pub file: String,
    /// Factor on the tabled torque (default 1; −1 turns a table of the
    /// torque that resists a counter-clockwise turn into the crate's
    /// counter-clockwise-positive load).
    #[serde(default = "one")]
    pub scale: f64,
}

fn one() -> f64 {
    1.0
}

/// One validated term of a series in a sprocket's angle θ:
/// `amplitude · sin(order · θ + phase_rad)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Harmonic {
    /// Order k (cycles per revolution).
    pub order: u32,
    /// Amplitude: relative (a speed harmonic) or N·m (a load harmonic).
    pub amplitude: f64,
    /// Phase, rad.
    pub phase_rad: f64,
}

impl Harmonic {
    /// The term at angle `theta_rad`.
    #[inline]
    pub(crate) fn at(&self, theta_rad: f64) -> f64 {
        self.amplitude * (f64::from(self.order) * theta_rad + self.phase_rad).sin()
    }
}

/// A validated load table: one period of nodes (the closing row at +360°
/// dropped), angles in radians from the first, scale applied.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct LoadTable {
    /// The file as the scene names it (`load_table.file`), wherever it was
    /// read from: the same table is the same scene from any folder.
    pub file: String,
    /// The file's text as read: what a recording keeps of it, so that the
    /// scene is rebuilt without the file.
    pub text: String,
    /// Node angles, rad, strictly increasing, within [first, first + 2π).
    pub angles_rad: Vec<f64>,
    /// Torques at the nodes, N·m (counter-clockwise positive).
    pub torques_n_m: Vec<f64>,
}

/// Largest harmonic order accepted (a tooth count's multiple is far below).
pub(crate) const MAX_ORDER: i64 = 1000;

/// Rows a load table needs at least (three nodes and the closing row).
pub(crate) const MIN_TABLE_ROWS: usize = 4;

/// Where a scene's tables are read from: the texts given with it, by the
/// name the scene writes (a recording's copies), else the files, relative
/// to `base_dir` (the working directory if `None`).
#[derive(Clone, Copy)]
pub(super) struct TableFiles<'a> {
    pub(super) base_dir: Option<&'a Path>,
    pub(super) given: &'a BTreeMap<String, String>,
}

/// A harmonic's order at `path`: an integer in 1..=[`MAX_ORDER`] (1 where
/// it is not, after the failure).
pub(super) fn check_order(c: &mut Checker, path: &str, order: i64) -> u32 {
    if !(1..=MAX_ORDER).contains(&order) {
        c.fail(
            path,
            format!("must be an integer in 1..={MAX_ORDER} (cycles per revolution), got {order}"),
        );
        return 1;
    }
    u32::try_from(order).unwrap_or(1)
}

/// The torque harmonics written at `path` (`path[k].order`, …).
pub(super) fn check_torque_harmonics(
    c: &mut Checker,
    path: &str,
    harmonics: &[LoadHarmonicFile],
) -> Vec<Harmonic> {
    harmonics
        .iter()
        .enumerate()
        .map(|(k, h)| {
            let at = |field: &str| format!("{path}[{k}].{field}");
            Harmonic {
                order: check_order(c, &at("order"), h.order),
                amplitude: c.finite(&at("amplitude_n_m"), h.amplitude_n_m),
                phase_rad: c.finite(&at("phase_deg"), h.phase_deg).to_radians(),
            }
        })
        .collect()
}

/// The torque table written at `path` (`path.file`, `path.scale`), read
/// from `tables` and scaled.
pub(super) fn check_torque_table(
    c: &mut Checker,
    path: &str,
    table: Option<&LoadTableFile>,
    tables: TableFiles<'_>,
) -> Option<LoadTable> {
    table.and_then(|t| {
        let scale = c.finite(&format!("{path}.scale"), t.scale);
        read_table(c, &format!("{path}.file"), &t.file, tables).map(|mut table| {
            for m in &mut table.torques_n_m {
                *m *= scale;
            }
            table
        })
    })
}

/// Reads and checks the load table the scene names `file` (its given text,
/// else the file); every problem is a failure at `path`.
fn read_table(
    c: &mut Checker,
    path: &str,
    file: &str,
    tables: TableFiles<'_>,
) -> Option<LoadTable> {
    let (text, shown) = if let Some(text) = tables.given.get(file) {
        (
            text.clone(),
            format!("{file} (the copy given with the scene)"),
        )
    } else {
        let resolved = match tables.base_dir {
            Some(dir) => dir.join(file),
            None => PathBuf::from(file),
        };
        match std::fs::read_to_string(&resolved) {
            Ok(t) => (t, resolved.display().to_string()),
            Err(e) => {
                c.fail(
                    path,
                    format!("cannot read the table {}: {e}", resolved.display()),
                );
                return None;
            }
        }
    };
    match parse_table(&text) {
        Ok((angles_deg, torques_n_m)) => Some(LoadTable {
            file: file.to_owned(),
            angles_rad: angles_deg.iter().map(|a| a.to_radians()).collect(),
            torques_n_m,
            text,
        }),
        Err(why) => {
            c.fail(path, format!("{shown}: {why}"));
            None
        }
    }
}

/// Parses a table's text into one period of (angle °, torque N·m) nodes,
/// the closing row dropped, angles made relative to nothing (as written).
/// The error names the line and what is allowed.
pub(crate) fn parse_table(text: &str) -> Result<(Vec<f64>, Vec<f64>), String> {
    let mut rows: Vec<(usize, f64, f64)> = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line_no = n + 1;
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        let numbers: Option<Vec<f64>> = fields.iter().map(|s| s.parse::<f64>().ok()).collect();
        let Some(numbers) = numbers else {
            if rows.is_empty() {
                // A header.
                continue;
            }
            return Err(format!(
                "line {line_no}: expected two numbers `angle_deg,torque_n_m`, got \"{line}\""
            ));
        };
        let [angle, torque] = numbers[..] else {
            return Err(format!(
                "line {line_no}: expected two numbers `angle_deg,torque_n_m`, got {} fields",
                numbers.len()
            ));
        };
        if !angle.is_finite() || !torque.is_finite() {
            return Err(format!(
                "line {line_no}: angle and torque must be finite numbers, got {angle}, {torque}"
            ));
        }
        if let Some(&(prev_line, prev, _)) = rows.last()
            && angle <= prev
        {
            return Err(format!(
                "line {line_no}: angles must increase strictly, got {angle}° after {prev}° (line {prev_line})"
            ));
        }
        rows.push((line_no, angle, torque));
    }
    if rows.len() < MIN_TABLE_ROWS {
        return Err(format!(
            "needs at least {MIN_TABLE_ROWS} rows (three nodes and the closing row at +360°), got {}",
            rows.len()
        ));
    }
    let (first, last) = (rows[0], rows[rows.len() - 1]);
    let period = last.1 - first.1;
    if (period - 360.0).abs() > 1e-9 * 360.0 {
        return Err(format!(
            "the angles span {period}° (from {}° to {}°); a table spans one revolution, 360°, its last row at the first angle + 360°",
            first.1, last.1
        ));
    }
    let scale = rows.iter().map(|r| r.2.abs()).fold(0.0, f64::max);
    if (last.2 - first.2).abs() > 1e-9 * scale {
        return Err(format!(
            "line {}: the torque at {}° ({} N·m) must equal the torque at {}° ({} N·m): the table is periodic",
            last.0, last.1, last.2, first.1, first.2
        ));
    }
    rows.pop();
    Ok((
        rows.iter().map(|r| r.1).collect(),
        rows.iter().map(|r| r.2).collect(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_table_with_a_header_and_comments_parses() {
        let text = "# cam\nangle_deg,torque_n_m\n0,1\n90,2\n180,3\n270,2\n360,1\n";
        let (a, m) = parse_table(text).expect("valid");
        assert_eq!(a, [0.0, 90.0, 180.0, 270.0]);
        assert_eq!(m, [1.0, 2.0, 3.0, 2.0]);
    }

    #[test]
    fn unsorted_angles_are_rejected_with_their_line() {
        let err = parse_table("0,1\n90,2\n80,3\n360,1\n").expect_err("unsorted");
        assert!(err.contains("line 3") && err.contains("increase"), "{err}");
    }

    #[test]
    fn nan_is_rejected() {
        let err = parse_table("0,1\n90,NaN\n180,3\n360,1\n").expect_err("NaN");
        assert!(err.contains("line 2") && err.contains("finite"), "{err}");
    }

    #[test]
    fn a_period_other_than_360_degrees_is_rejected() {
        let err = parse_table("0,1\n90,2\n180,3\n350,1\n").expect_err("period");
        assert!(err.contains("350°") && err.contains("360°"), "{err}");
    }

    #[test]
    fn an_open_period_is_rejected() {
        let err = parse_table("0,1\n90,2\n180,3\n360,2\n").expect_err("not periodic");
        assert!(err.contains("periodic"), "{err}");
    }
}
