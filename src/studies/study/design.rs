//! A study's design: the rows of factor levels its cases take (a full
//! factorial, a Latin hypercube or explicit rows), and a range's levels.
//! It does not read the plan file or check the factors' paths (`plan`).

use super::file::{FactorFile, PlanFile, Problems, RangeFile};
use crate::rng::SeededRng;

/// The design's rows of levels, one per case, over the factors' `levels`.
pub(super) fn design_rows(
    file: &PlanFile,
    levels: &[Vec<toml::Value>],
    p: &mut Problems,
) -> Vec<Vec<toml::Value>> {
    let kind = file.design.kind.as_str();
    let design = &file.design;
    match kind {
        "full_factorial" => {
            if file.factors.is_empty() {
                p.add("factors", "a full factorial needs at least one factor");
            }
            no_field(p, "design.seed", design.seed.is_some(), kind);
            no_field(p, "design.count", design.count.is_some(), kind);
            no_field(p, "design.cases", design.cases.is_some(), kind);
            full_factorial(levels)
        }
        "latin_hypercube" => {
            if file.factors.is_empty() {
                p.add("factors", "a Latin hypercube needs at least one factor");
            }
            no_field(p, "design.cases", design.cases.is_some(), kind);
            if design.seed.is_none() {
                p.add("design.seed", "missing; a Latin hypercube needs a seed");
            }
            let count = match design.count {
                Some(n) if n >= 1 => n as usize,
                Some(n) => {
                    p.add("design.count", format!("must be >= 1, got {n}"));
                    0
                }
                None => {
                    p.add("design.count", "missing; allowed: a number of cases >= 1");
                    0
                }
            };
            latin_hypercube(&file.factors, levels, count, design.seed.unwrap_or(0))
        }
        "explicit" => {
            no_field(p, "design.seed", design.seed.is_some(), kind);
            no_field(p, "design.count", design.count.is_some(), kind);
            let rows = design.cases.clone().unwrap_or_default();
            if rows.is_empty() {
                p.add(
                    "design.cases",
                    "is empty; allowed: at least one row of values",
                );
            }
            for (k, row) in rows.iter().enumerate() {
                if row.len() != file.factors.len() {
                    p.add(
                        format!("design.cases[{k}]"),
                        format!(
                            "has {} values; allowed: one per factor ({})",
                            row.len(),
                            file.factors.len()
                        ),
                    );
                }
            }
            rows
        }
        other => {
            p.add(
                "design.kind",
                format!(
                    "unknown design `{other}`; allowed: full_factorial, latin_hypercube, explicit"
                ),
            );
            Vec::new()
        }
    }
}

fn no_field(p: &mut Problems, path: &str, given: bool, kind: &str) {
    if given {
        p.add(path, format!("is not used by design `{kind}`"));
    }
}

/// Levels of a range: `steps` evenly spaced for a full factorial, the two
/// ends for a Latin hypercube (which draws within them).
pub(super) fn range_levels(kind: &str, r: &RangeFile) -> Result<Vec<toml::Value>, String> {
    if !(r.from.is_finite() && r.to.is_finite()) {
        return Err(format!(
            "from = {} and to = {} must be finite numbers",
            r.from, r.to
        ));
    }
    match (kind, r.steps) {
        ("latin_hypercube", Some(_)) => {
            Err("steps is not used by a Latin hypercube (it draws within from..to)".to_owned())
        }
        ("latin_hypercube", None) => Ok(vec![toml::Value::Float(r.from), toml::Value::Float(r.to)]),
        (_, None) => Err("missing steps; allowed: an integer >= 1".to_owned()),
        (_, Some(n)) if n < 1 => Err(format!("steps must be >= 1, got {n}")),
        (_, Some(1)) => Ok(vec![toml::Value::Float(r.from)]),
        (_, Some(n)) => Ok((0..n)
            .map(|i| toml::Value::Float(r.from + (r.to - r.from) * i as f64 / (n - 1) as f64))
            .collect()),
    }
}

/// Every combination; the last factor varies fastest.
fn full_factorial(levels: &[Vec<toml::Value>]) -> Vec<Vec<toml::Value>> {
    if levels.is_empty() || levels.iter().any(Vec::is_empty) {
        return Vec::new();
    }
    let mut rows = vec![Vec::new()];
    for factor in levels {
        rows = rows
            .into_iter()
            .flat_map(|row| {
                factor.iter().map(move |v| {
                    let mut r = row.clone();
                    r.push(v.clone());
                    r
                })
            })
            .collect();
    }
    rows
}

/// `count` cases: for each factor a random permutation of the strata
/// 0..count; case i takes stratum s = perm[i] and the point (s + u)/count
/// of the unit interval, u uniform in [0, 1), mapped onto the range
/// (from + x (to − from)) or onto the list of levels (level ⌊x · len⌋).
fn latin_hypercube(
    factors: &[FactorFile],
    levels: &[Vec<toml::Value>],
    count: usize,
    seed: u64,
) -> Vec<Vec<toml::Value>> {
    if count == 0 || levels.iter().any(Vec::is_empty) {
        return Vec::new();
    }
    // A fixed generator, so a plan's cases are the same on every machine and version.
    let mut rng = SeededRng::new(seed);
    let mut rows = vec![Vec::with_capacity(factors.len()); count];
    for (f, values) in factors.iter().zip(levels) {
        let mut perm: Vec<usize> = (0..count).collect();
        // Fisher–Yates.
        for i in (1..count).rev() {
            perm.swap(i, rng.below(i + 1));
        }
        for (row, s) in rows.iter_mut().zip(perm) {
            let x = (s as f64 + rng.unit()) / count as f64;
            let v = match (&f.range, values.len()) {
                (Some(r), _) => toml::Value::Float(r.from + x * (r.to - r.from)),
                (None, n) => values[((x * n as f64) as usize).min(n - 1)].clone(),
            };
            row.push(v);
        }
    }
    rows
}
