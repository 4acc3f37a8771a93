//! The study plan (TOML) and its cases.
//!
//! ```toml
//! scene = "../assets/l60mc.toml"        # relative to the plan
//! set = { "solver.duration_s" = 2.0 }   # the same in every case (optional)
//! responses = ["max_penetration_m", "segments.0.mean_link_force_n"]   # or "all"
//! checkpoint_every_s = 1.0              # optional: checkpoint each case every 1 s simulated
//! window_s = 0.5                        # optional: statistics over each run's last 0.5 s
//! sample_by_speed = true                # optional: each case's sample rate from its driver speed
//!
//! [[factors]]
//! path = "chain.pretension_n"
//! levels = [15000, 21000]
//!
//! [[factors]]
//! path = "sprockets.0.speed_rpm"
//! range = { from = 60, to = 120, steps = 4 }
//!
//! [design]
//! kind = "full_factorial"               # or "latin_hypercube" (seed, count), "explicit" (cases)
//! ```
//!
//! A factor's levels are TOML values of its field's type; a range is
//! `from`, `to` and (for a full factorial) `steps` evenly spaced levels.
//! A Latin hypercube of `count` cases cuts each factor's range (or its list
//! of levels) into `count` strata and visits each once, in an order and at a
//! point within the stratum drawn from `seed`. An explicit design lists its
//! cases as rows of values, one per factor (`cases = [[15000, 60], …]`).
//! With `checkpoint_every_s`, each case writes its complete state
//! ([`crate::sim::checkpoint`]) into its directory every so many simulated
//! seconds, and a case that was stopped (a preempted or killed task)
//! resumes from it: it loses at most that much simulated time.
//! With `window_s`, each case's summary takes its statistics over the run's
//! last `window_s` seconds, as `chaindrive run --window` does (the default
//! window otherwise); a window longer than a case's run is an error of that
//! case, reported before anything runs.
//! With `sample_by_speed = true`, each case samples its signals as a sweep
//! does at its driver's speed (at least 1 kHz and 16 samples per period of
//! twice the largest tooth count), not at 1 kHz: a fast drive's
//! tooth-passing frequency then stays clear of the sample rate.
//! (`scene`, `set`, `responses`, `checkpoint_every_s`, `window_s` and `sample_by_speed` come
//! before the first `[[factors]]` table: in TOML, a key after a table
//! header belongs to that table.)

use std::collections::BTreeSet;
use std::path::Path;

use super::StudyError;
use super::design::{design_rows, range_levels};
use super::file::{PlanFile, Problems};
use crate::scene::{Assignment, Scene, ScenePath, Stepping, set_in_table};

/// Which summary fields a study reports.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) enum Responses {
    /// Every numeric field of the summary.
    All,
    /// These fields, as dotted paths into the summary (`max_penetration_m`,
    /// `segments.0.mean_link_force_n`; indices from 0).
    Fields(Vec<String>),
}

/// One case: its factor values and everything written into the base scene.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Case {
    /// 0-based case number (the job array's task id).
    pub k: usize,
    /// One value per factor, in the plan's order.
    pub values: Vec<toml::Value>,
    /// The plan's `set` values followed by the factor values.
    pub assignments: Vec<Assignment>,
}

impl Case {
    /// `path = value, …` of the factors (their paths as the plan wrote
    /// them), for messages and `status.json`.
    pub(crate) fn describe(&self, factors: &[String]) -> String {
        factors
            .iter()
            .zip(&self.values)
            .map(|(p, v)| format!("{p} = {v}"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// A checked plan: the base scene's text, the factors and every case, each
/// case's scene already validated.
#[derive(Clone, Debug)]
pub struct Study {
    /// The plan's text.
    pub plan_toml: String,
    /// The base scene's text.
    pub scene_toml: String,
    /// Factor paths, in the plan's order.
    pub factors: Vec<ScenePath>,
    /// Factor paths as the plan wrote them (`sprockets.0.speed_rpm` stays
    /// so): the results' column names.
    pub factor_names: Vec<String>,
    /// The cases, case k at index k.
    pub(crate) cases: Vec<Case>,
    /// The responses.
    pub(crate) responses: Responses,
    /// Simulated seconds between a case's checkpoints (`None`: no checkpoints).
    pub checkpoint_every_s: Option<f64>,
    /// Length of each case's statistics window, s (`None`: the default).
    pub window_s: Option<f64>,
    /// Whether each case's sample rate follows its driver speed.
    pub(crate) sample_by_speed: bool,
}

impl Study {
    /// How many cases the plan has.
    pub fn case_count(&self) -> usize {
        self.cases.len()
    }

    /// Reads the plan at `path` and the scene it names, and checks both.
    pub fn from_plan_path(path: &Path) -> Result<Self, StudyError> {
        let plan_toml = std::fs::read_to_string(path).map_err(|e| StudyError::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        let file: PlanFile = toml::from_str(&plan_toml)
            .map_err(|e| StudyError::Plan(vec![e.to_string().trim_end().replace('\n', " ")]))?;
        let scene_path = path
            .parent()
            .unwrap_or_else(|| Path::new("."))
            .join(&file.scene);
        let scene_toml = std::fs::read_to_string(&scene_path).map_err(|e| {
            StudyError::Plan(vec![format!(
                "scene: cannot read {}: {e}",
                scene_path.display()
            )])
        })?;
        Self::from_texts(&plan_toml, &scene_toml)
    }

    /// Checks a plan against the base scene's text (the plan's `scene` path
    /// is not read). Every problem is reported, each with its path in the
    /// plan; then every case's scene is validated, and the cases that fail
    /// are reported with their factor values. Nothing is run.
    pub fn from_texts(plan_toml: &str, scene_toml: &str) -> Result<Self, StudyError> {
        let file: PlanFile = toml::from_str(plan_toml)
            .map_err(|e| StudyError::Plan(vec![e.to_string().trim_end().replace('\n', " ")]))?;
        if let Err(e) = Scene::from_toml(scene_toml) {
            return Err(StudyError::Plan(
                e.lines().iter().map(|l| format!("scene: {l}")).collect(),
            ));
        }
        let mut base: toml::Table = scene_toml
            .parse()
            .map_err(|e: toml::de::Error| StudyError::Plan(vec![format!("scene: {e}")]))?;
        let mut p = Problems(Vec::new());
        let set = fixed_assignments(&file.set, &mut base, &mut p);
        let factors = read_factors(&file, &base, &mut p);
        let rows = design_rows(&file, &factors.levels, &mut p);
        let responses = read_responses(file.responses.as_ref(), &mut p);
        let checkpoint_every_s = positive_seconds(
            &mut p,
            "checkpoint_every_s",
            file.checkpoint_every_s.as_ref(),
            "a number of simulated seconds > 0",
        );
        let window_s = positive_seconds(
            &mut p,
            "window_s",
            file.window_s.as_ref(),
            "a statistics window of simulated seconds > 0",
        );
        if !p.0.is_empty() {
            return Err(StudyError::Plan(p.0));
        }
        let cases: Vec<Case> = rows
            .into_iter()
            .enumerate()
            .map(|(k, values)| {
                let mut assignments = set.clone();
                assignments.extend(factors.paths.iter().zip(&values).map(|(path, value)| {
                    Assignment {
                        path: path.clone(),
                        value: value.clone(),
                    }
                }));
                Case {
                    k,
                    values,
                    assignments,
                }
            })
            .collect();
        let failed = case_problems(
            scene_toml,
            &cases,
            &factors.names,
            checkpoint_every_s,
            window_s,
        );
        if !failed.is_empty() {
            return Err(StudyError::Cases(failed));
        }
        Ok(Self {
            plan_toml: plan_toml.to_owned(),
            scene_toml: scene_toml.to_owned(),
            factors: factors.paths,
            factor_names: factors.names,
            cases,
            responses,
            checkpoint_every_s,
            window_s,
            sample_by_speed: file.sample_by_speed,
        })
    }

    /// The statistics window of a case's runs, s: the plan's `window_s`
    /// (checked against every case's run when the plan was read), or `None`
    /// for the default window after the scene's ramps
    /// ([`crate::analysis::StatsWindow`]).
    pub(crate) fn statistics_window_s(&self) -> Option<f64> {
        self.window_s
    }

    /// The validated scene of case `k`.
    pub(crate) fn scene(&self, k: usize) -> Result<Scene, StudyError> {
        let case = self.cases.get(k).ok_or(StudyError::NoCase {
            k,
            count: self.cases.len(),
        })?;
        Scene::from_toml_set(&self.scene_toml, &case.assignments).map_err(|e| {
            StudyError::Cases(vec![format!(
                "case {k} ({}): {}",
                case.describe(&self.factor_names),
                e.lines().join("; ")
            )])
        })
    }
}

/// The values the plan fixes in every case (`set`), each set on `base`.
fn fixed_assignments(
    set_table: &toml::Table,
    base: &mut toml::Table,
    p: &mut Problems,
) -> Vec<Assignment> {
    let mut fixed = Vec::new();
    flatten_set(set_table, "", &mut fixed);
    let mut set = Vec::new();
    for (path, value) in fixed {
        match path.parse::<ScenePath>() {
            Ok(path) => {
                let a = Assignment { path, value };
                match set_in_table(base, &a) {
                    Ok(()) => set.push(a),
                    Err(e) => p.add(format!("set.\"{}\"", a.path), e),
                }
            }
            Err(e) => p.add(format!("set.\"{path}\""), e),
        }
    }
    set
}

/// The plan's factors as read: their paths, their names as written and
/// each one's levels.
struct Factors {
    paths: Vec<ScenePath>,
    names: Vec<String>,
    levels: Vec<Vec<toml::Value>>,
}

/// The factors of `file`, each level tried on the `base` scene.
fn read_factors(file: &PlanFile, base: &toml::Table, p: &mut Problems) -> Factors {
    let kind = file.design.kind.as_str();
    let mut factors = Vec::new();
    let mut factor_names = Vec::new();
    let mut seen = BTreeSet::new();
    let mut levels: Vec<Vec<toml::Value>> = Vec::new();
    for (i, f) in file.factors.iter().enumerate() {
        let at = format!("factors[{i}]");
        let path = match f.path.parse::<ScenePath>() {
            Ok(path) => path,
            Err(e) => {
                p.add(format!("{at}.path"), e);
                continue;
            }
        };
        if !seen.insert(path.to_string()) {
            p.add(format!("{at}.path"), format!("{path} is already a factor"));
        }
        let mut values = Vec::new();
        match (kind, &f.levels, &f.range) {
            ("explicit", None, None) => {}
            ("explicit", _, _) => p.add(
                &at,
                "an explicit design takes its values from design.cases; allowed: path only",
            ),
            (_, Some(_), Some(_)) => p.add(&at, "has both levels and range; allowed: one"),
            (_, None, None) => p.add(&at, "has no levels; allowed: levels = [...] or range"),
            (_, Some(l), None) if l.is_empty() => p.add(
                format!("{at}.levels"),
                "is empty; allowed: at least one level",
            ),
            (_, Some(l), None) => values.clone_from(l),
            (_, None, Some(r)) => match range_levels(kind, r) {
                Ok(v) => values = v,
                Err(m) => p.add(format!("{at}.range"), m),
            },
        }
        for (j, v) in values.iter().enumerate() {
            let a = Assignment {
                path: path.clone(),
                value: v.clone(),
            };
            if let Err(e) = set_in_table(&mut base.clone(), &a) {
                let place = match &f.levels {
                    Some(_) => format!("{at}.levels[{j}]"),
                    None => format!("{at}.range"),
                };
                p.add(place, e);
                break;
            }
        }
        factors.push(path);
        factor_names.push(f.path.clone());
        levels.push(values);
    }
    Factors {
        paths: factors,
        names: factor_names,
        levels,
    }
}

/// Which summary fields the study reports, as `responses` says.
fn read_responses(responses: Option<&toml::Value>, p: &mut Problems) -> Responses {
    match responses {
        None => Responses::All,
        Some(toml::Value::String(s)) if s == "all" => Responses::All,
        Some(toml::Value::Array(items)) if !items.is_empty() => {
            let mut fields = Vec::new();
            for (i, item) in items.iter().enumerate() {
                match item.as_str() {
                    Some(s) if is_summary_path(s) => fields.push(s.to_owned()),
                    _ => p.add(
                        format!("responses[{i}]"),
                        format!(
                            "{item} is not a summary field; allowed: a dotted path such as max_penetration_m or segments.0.mean_link_force_n"
                        ),
                    ),
                }
            }
            Responses::Fields(fields)
        }
        Some(other) => {
            p.add(
                "responses",
                format!("{other}: allowed: \"all\" or a non-empty list of summary fields"),
            );
            Responses::All
        }
    }
}

/// Every case's scene, validated before anything runs: what is wrong with
/// each, by case.
fn case_problems(
    scene_toml: &str,
    cases: &[Case],
    factor_names: &[String],
    checkpoint_every_s: Option<f64>,
    window_s: Option<f64>,
) -> Vec<String> {
    let mut failed = Vec::new();
    for case in cases {
        let k = case.k;
        match Scene::from_toml_set(scene_toml, &case.assignments) {
            Err(e) => failed.push(format!(
                "case {k} ({}): {}",
                case.describe(factor_names),
                e.lines().join("; ")
            )),
            // Rapier keeps solver state a checkpoint does not hold.
            Ok(scene)
                if checkpoint_every_s.is_some()
                    && scene.solver().stepping != Stepping::Substepped =>
            {
                failed.push(format!(
                    "case {k} ({}): checkpoint_every_s needs solver.stepping = \"substepped\", the case steps with {}",
                    case.describe(factor_names),
                    scene.solver().stepping.name()
                ));
            }
            Ok(scene)
                if window_s.is_some_and(|w| w > scene.solver().duration_s * (1.0 + 1e-12)) =>
            {
                failed.push(format!(
                    "case {k} ({}): window_s = {} s is longer than the run (solver.duration_s = {} s); allowed: a window within the run",
                    case.describe(factor_names),
                    window_s.unwrap_or_default(),
                    scene.solver().duration_s
                ));
            }
            Ok(_) => {}
        }
    }
    failed
}

/// A plan key of simulated seconds: a finite number > 0, or absent.
fn positive_seconds(
    p: &mut Problems,
    key: &str,
    value: Option<&toml::Value>,
    allowed: &str,
) -> Option<f64> {
    let v = value?;
    match v.as_float().or_else(|| v.as_integer().map(|i| i as f64)) {
        Some(s) if s.is_finite() && s > 0.0 => Some(s),
        _ => {
            p.add(key, format!("{v}: allowed: {allowed}"));
            None
        }
    }
}

/// `a.b.c`: keys of letters, digits and `_`, or 0-based indices.
fn is_summary_path(s: &str) -> bool {
    !s.is_empty()
        && s.split('.').all(|part| {
            !part.is_empty() && part.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        })
}

/// The plan's `set` table as (dotted path, value) pairs; nested tables are
/// joined by dots (`[set.chain] pretension_n = 1` is `chain.pretension_n`).
pub(crate) fn flatten_set(table: &toml::Table, prefix: &str, out: &mut Vec<(String, toml::Value)>) {
    for (key, value) in table {
        let path = if prefix.is_empty() {
            key.clone()
        } else {
            format!("{prefix}.{key}")
        };
        match value {
            toml::Value::Table(t) => flatten_set(t, &path, out),
            v => out.push((path, v.clone())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::L60MC_TOML;

    const PLAN: &str = r#"
scene = "l60mc.toml"
set = { "solver.duration_s" = 0.5 }
[[factors]]
path = "chain.pretension_n"
levels = [15000, 21000]
[[factors]]
path = "sprockets.0.speed_rpm"
range = { from = 60, to = 120, steps = 3 }
[design]
kind = "full_factorial"
"#;

    fn lines(plan: &str) -> Vec<String> {
        match Study::from_texts(plan, L60MC_TOML) {
            Err(StudyError::Plan(l) | StudyError::Cases(l)) => l,
            other => panic!("expected errors, got {other:?}"),
        }
    }

    #[test]
    fn a_full_factorial_has_every_combination() {
        let s = Study::from_texts(PLAN, L60MC_TOML).expect("valid");
        assert_eq!(s.cases.len(), 6);
        // The last factor varies fastest.
        assert_eq!(s.cases[1].values[1], toml::Value::Float(90.0));
        assert_eq!(s.cases[3].values[0], toml::Value::Integer(21000));
        let scene = s.scene(5).expect("valid");
        assert_eq!(scene.chain().pretension_n, 21000.0);
        assert_eq!(scene.file().sprockets[0].speed_rpm, Some(120.0));
        assert_eq!(scene.solver().duration_s, 0.5);
    }

    #[test]
    fn a_latin_hypercube_visits_every_stratum_once() {
        let plan = r#"
scene = "x"
[[factors]]
path = "chain.pretension_n"
range = { from = 10000, to = 20000 }
[[factors]]
path = "sprockets.0.speed_rpm"
levels = [60, 80, 100, 120]
[design]
kind = "latin_hypercube"
seed = 7
count = 8
"#;
        let s = Study::from_texts(plan, L60MC_TOML).expect("valid");
        assert_eq!(s.cases.len(), 8);
        // Each of the 8 strata of [10000, 20000) holds exactly one case.
        let mut strata: Vec<usize> = s
            .cases
            .iter()
            .map(|c| ((c.values[0].as_float().expect("float") - 10000.0) / 1250.0) as usize)
            .collect();
        strata.sort_unstable();
        assert_eq!(strata, (0..8).collect::<Vec<_>>());
        // 8 strata over 4 levels: each level twice.
        for level in [60, 80, 100, 120] {
            let n = s
                .cases
                .iter()
                .filter(|c| c.values[1] == toml::Value::Integer(level))
                .count();
            assert_eq!(n, 2, "level {level}");
        }
        // The same seed gives the same cases.
        let again = Study::from_texts(plan, L60MC_TOML).expect("valid");
        assert_eq!(again.cases, s.cases);
    }

    #[test]
    fn bad_plans_name_their_paths() {
        let l = lines(&PLAN.replace("chain.pretension_n", "chain.colour"));
        assert!(
            l[0].starts_with("factors[0].levels[0]: chain.colour: no such field"),
            "{l:?}"
        );
        let l = lines(&PLAN.replace("[15000, 21000]", "[15000, \"high\"]"));
        assert!(
            l[0].starts_with("factors[0].levels[1]: chain.pretension_n: a string does not fit"),
            "{l:?}"
        );
        let l = lines("scene = \"x\"\n[design]\nkind = \"explicit\"\ncases = []\n");
        assert_eq!(
            l,
            ["design.cases: is empty; allowed: at least one row of values"]
        );
        let l = lines("scene = \"x\"\n[design]\nkind = \"full_factorial\"\n");
        assert_eq!(l, ["factors: a full factorial needs at least one factor"]);
        let l = lines(&PLAN.replace("full_factorial", "latin_hypercube"));
        assert!(l.iter().any(|m| m.starts_with("design.seed")), "{l:?}");
        assert!(l.iter().any(|m| m.starts_with("factors[1].range")), "{l:?}");
    }

    #[test]
    fn a_case_that_cannot_be_built_is_reported_with_its_values() {
        let l = lines(&PLAN.replace("[15000, 21000]", "[15000, -5]"));
        assert_eq!(l.len(), 3, "{l:?}");
        assert!(
            l[0].starts_with("case 3 (chain.pretension_n = -5, sprockets.0.speed_rpm = 60.0): "),
            "{l:?}"
        );
        assert!(l[0].contains("chain.pretension_n"), "{l:?}");
    }
}
