//! A duty cycle (`chaindrive life`): one steady run per operating point,
//! combined by hours into the chain's life (docs/design-checks.md, "Duty
//! cycle").
//!
//! A point is the scene with some values set (`[[duty]]`'s `set`, dotted
//! scene paths) and a weight in hours: a study case with a weight. So the
//! points run as a study ([`crate::studies::study`]): an explicit design,
//! one case per point, in the study's directory, on its worker threads,
//! resumable (finished cases are kept), on one machine or as a Slurm job
//! array (`chaindrive study slurm DIR/plan.toml --out DIR`). This module
//! writes that plan ([`DutyCycle::plan_toml`]) and combines the finished
//! cases' summaries ([`combine`]); it schedules nothing itself.
//!
//! Each check with a rate per hour gives a life: a point's rate rᵢ (Miner's
//! damage per hour for fatigue) for hᵢ hours adds rᵢ hᵢ per block of
//! H = Σ hᵢ hours, so the block's mean rate is Σ rᵢ hᵢ / H and the life is
//! the limit (a damage of 1) over it; the point with the largest rᵢ hᵢ
//! dominates. The duty cycle's life is the shortest of its checks'.

pub(crate) mod combine;

pub(crate) use combine::{DutyLife, combine};

use crate::scene::{Assignment, DutyPointFile, PathPart, Scene, ScenePath, check_points};
use crate::studies::study::plan::flatten_set;
use crate::studies::study::{Study, StudyDir, StudyError};

/// Why a duty cycle cannot be run.
#[derive(Debug, thiserror::Error)]
pub enum DutyError {
    /// The points are invalid: one `path: message` line per problem.
    #[error("invalid duty cycle:\n{}", .0.join("\n"))]
    Points(Vec<String>),
    /// The study could not be prepared, run or read.
    #[error(transparent)]
    Study(#[from] StudyError),
}

/// One operating point.
#[derive(Clone, Debug, PartialEq)]
pub struct DutyPoint {
    /// Its name (`point N` unless given).
    pub name: String,
    /// Its weight: hours of operation (or its fraction of the time).
    pub hours: f64,
    /// The values set, by path as written.
    pub set: Vec<(String, toml::Value)>,
}

/// A checked duty cycle.
#[derive(Clone, Debug, PartialEq)]
pub struct DutyCycle {
    /// The points, in the order written.
    pub points: Vec<DutyPoint>,
    /// Whether the weights are fractions of the time (else hours).
    pub by_fraction: bool,
}

/// How each point is run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LifeSettings {
    /// Simulated time of each point, s (`None`: the scene's).
    pub duration_s: Option<f64>,
    /// Statistics window of each point, s (`None`: the default after the ramps).
    pub window_s: Option<f64>,
    /// Simulated seconds between a point's checkpoints (`None`: none).
    pub checkpoint_every_s: Option<f64>,
}

/// The value at `path` in a TOML table, if there is one.
fn get_in_table<'a>(table: &'a toml::Table, path: &ScenePath) -> Option<&'a toml::Value> {
    let mut parts = path.parts().iter();
    let mut here = match parts.next()? {
        PathPart::Key(k) => table.get(k)?,
        PathPart::Index(_) => return None,
    };
    for part in parts {
        here = match (part, here) {
            (PathPart::Key(k), toml::Value::Table(t)) => t.get(k)?,
            (PathPart::Index(i), toml::Value::Array(a)) => a.get(*i)?,
            _ => return None,
        };
    }
    Some(here)
}

impl DutyCycle {
    /// Checks `points` against the base scene `scene_toml`: their weights
    /// (`check_points`), then each point's scene (its values set), every
    /// problem with its path (`duty[1].set."sprockets.0.speed_rpm"`).
    ///
    /// # Errors
    /// Every problem found.
    pub fn new(points: &[DutyPointFile], scene_toml: &str) -> Result<Self, DutyError> {
        if let Err(e) = check_points(points) {
            return Err(DutyError::Points(e.lines()));
        }
        let mut problems = Vec::new();
        let mut out = Vec::with_capacity(points.len());
        for (i, p) in points.iter().enumerate() {
            let mut set = Vec::new();
            flatten_set(&p.set, "", &mut set);
            let mut assignments = Vec::new();
            for (path, value) in &set {
                match path.parse::<ScenePath>() {
                    Ok(path) => assignments.push(Assignment {
                        path,
                        value: value.clone(),
                    }),
                    Err(e) => problems.push(format!("duty[{i}].set.\"{path}\": {e}")),
                }
            }
            if let Err(e) = Scene::from_toml_set(scene_toml, &assignments) {
                problems.extend(e.lines().iter().map(|l| format!("duty[{i}].set: {l}")));
            }
            out.push(DutyPoint {
                name: p.name.clone().unwrap_or_else(|| format!("point {}", i + 1)),
                hours: p.hours.or(p.fraction).unwrap_or(0.0),
                set,
            });
        }
        if !problems.is_empty() {
            return Err(DutyError::Points(problems));
        }
        Ok(Self {
            points: out,
            by_fraction: points.iter().all(|p| p.fraction.is_some()),
        })
    }

    /// Hours in one block of the cycle (1 where the weights are fractions).
    pub fn block_hours(&self) -> f64 {
        self.points.iter().map(|p| p.hours).sum()
    }

    /// The study plan of the cycle: one case per point, the factors the
    /// paths any point sets (a point that does not set one takes the base
    /// scene's value), `scene = "scene.toml"`.
    ///
    /// # Errors
    /// A path one point sets that another leaves to a base scene without it.
    pub fn plan_toml(&self, scene_toml: &str, settings: LifeSettings) -> Result<String, DutyError> {
        let base: toml::Table = scene_toml
            .parse()
            .map_err(|e: toml::de::Error| DutyError::Points(vec![format!("scene: {e}")]))?;
        let mut paths: Vec<String> = Vec::new();
        for p in &self.points {
            for (path, _) in &p.set {
                if !paths.contains(path) {
                    paths.push(path.clone());
                }
            }
        }
        let mut problems = Vec::new();
        let mut rows = Vec::new();
        for (i, p) in self.points.iter().enumerate() {
            let mut row = Vec::new();
            for path in &paths {
                let given = p.set.iter().find(|(q, _)| q == path).map(|(_, v)| v);
                let from_base = || get_in_table(&base, &path.parse().ok()?);
                match given.or_else(from_base) {
                    Some(v) => row.push(v.clone()),
                    None => problems.push(format!(
                        "duty[{i}].set: `{path}` is set by another point and the scene has no value for it; give it here too"
                    )),
                }
            }
            rows.push(toml::Value::Array(row));
        }
        if !problems.is_empty() {
            return Err(DutyError::Points(problems));
        }
        let mut plan = toml::Table::new();
        plan.insert("scene".into(), "scene.toml".into());
        plan.insert("responses".into(), "all".into());
        // A point's sample rate follows its driver speed, as a sweep's
        // does: at 1 kHz a 15-tooth sprocket at 4000 rpm (1 kHz teeth)
        // would alias every sampled statistic.
        plan.insert("sample_by_speed".into(), true.into());
        if let Some(d) = settings.duration_s {
            let mut set = toml::Table::new();
            set.insert("solver.duration_s".into(), d.into());
            plan.insert("set".into(), set.into());
        }
        if let Some(w) = settings.window_s {
            plan.insert("window_s".into(), w.into());
        }
        if let Some(c) = settings.checkpoint_every_s {
            plan.insert("checkpoint_every_s".into(), c.into());
        }
        let factors: Vec<toml::Value> = paths
            .iter()
            .map(|p| {
                let mut f = toml::Table::new();
                f.insert("path".into(), p.clone().into());
                f.into()
            })
            .collect();
        plan.insert("factors".into(), factors.into());
        let mut design = toml::Table::new();
        design.insert("kind".into(), "explicit".into());
        design.insert("cases".into(), rows.into());
        plan.insert("design".into(), design.into());
        let text = toml::to_string(&plan)
            .map_err(|e| DutyError::Points(vec![format!("the plan: {e}")]))?;
        Ok(format!(
            "# A duty cycle's points as a study (`chaindrive life`): one case per point.\n{text}"
        ))
    }

    /// Puts the cycle's study into `dir` (or finds it there: the same
    /// command resumes).
    ///
    /// # Errors
    /// An invalid plan, or a directory holding another study.
    pub fn prepare(
        &self,
        dir: &std::path::Path,
        scene_toml: &str,
        settings: LifeSettings,
    ) -> Result<StudyDir, DutyError> {
        let plan = self.plan_toml(scene_toml, settings)?;
        let study = Study::from_texts(&plan, scene_toml)?;
        Ok(StudyDir::prepare(dir, study)?)
    }
}
