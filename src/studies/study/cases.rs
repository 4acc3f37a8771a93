//! Running a study's cases: each case is one run of its scene, written to
//! `DIR/cases/<k>/` in a directory beside it and renamed into place, so a
//! case is finished exactly when its `status.json` exists. Finished cases
//! are skipped (resume); failed ones are kept with their error and skipped
//! unless retried.
//!
//! With the plan's `checkpoint_every_s = S`, a running case keeps its
//! complete state in `DIR/cases/<k>/checkpoint.ckpt` (written aside and
//! renamed, [`crate::sim::checkpoint`]) at t = S, 2S, …, and when it is
//! stopped (Ctrl-C, SIGTERM). A case that is not finished and has a
//! checkpoint resumes from it, so a killed or preempted task loses at most S
//! simulated seconds; its summary is bit for bit the uninterrupted run's
//! (wall times aside). The finished case's directory replaces the one that
//! held the checkpoint. A checkpoint that cannot be taken up (written by
//! another version of chaindrive, damaged) is set aside: the case starts
//! over, and its status says why.

use std::panic::AssertUnwindSafe;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::{Study, StudyError};
use crate::analysis::{RunSummary, Signals, StatsWindow};
use crate::scene::{Role, Scene};
use crate::sim::checkpoint::{
    Checkpoint, next_checkpoint_s, read_checkpoint, run_is_done, write_checkpoint,
};
use crate::sim::{RunOutcome, SampleRate, Simulation};
use crate::studies::queue::WorkQueue;

/// Sampling rate of a case's signals, Hz (as `chaindrive run`'s default).
pub(crate) const RATE_HZ: f64 = 1000.0;

/// How a case samples its signals: at [`RATE_HZ`], or with `by_speed` (the
/// plan's `sample_by_speed`) as a sweep does at the driver's fastest speed
/// (its run-up's end if faster): at least 1 kHz and 16 samples per period of
/// twice the largest tooth count ([`crate::studies::sweep::sampling_for`]).
/// A scene without a driver takes [`RATE_HZ`].
pub(crate) fn case_sampling(scene: &Scene, by_speed: bool) -> Result<SampleRate, String> {
    let dt_s = scene.solver().dt_s;
    let driver_rad_s = scene
        .sprockets()
        .iter()
        .filter_map(|s| match s.role {
            Role::Driver(law) => Some(
                law.speed_rad_s
                    .abs()
                    .max(law.run_up.map_or(0.0, |r| r.to_rad_s.abs())),
            ),
            _ => None,
        })
        .fold(0.0, f64::max);
    if by_speed && driver_rad_s > 0.0 {
        let rpm = driver_rad_s * 60.0 / std::f64::consts::TAU;
        let max_order = f64::from(2 * crate::studies::sweep::largest_teeth(scene));
        crate::studies::sweep::sampling_for(rpm, max_order, dt_s).map_err(|e| e.to_string())
    } else {
        SampleRate::new(RATE_HZ, dt_s).map_err(|e| e.to_string())
    }
}

/// A running case's checkpoint, in its directory `DIR/cases/<k>/`.
pub(crate) const CHECKPOINT_FILE: &str = "checkpoint.ckpt";

/// How a finished case ended.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CaseStatus {
    /// The case.
    pub case: usize,
    /// Whether it ran to its end.
    pub ok: bool,
    /// Why not.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// Wall time of the case (layout, equilibrium and run), s.
    pub wall_s: f64,
    /// Factor values, `path = value` (paths as the plan wrote them).
    pub factors: String,
    /// Simulated time at which the case was resumed from its checkpoint, s
    /// (the last resume, if it was stopped more than once).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resumed_from_s: Option<f64>,
    /// Why a checkpoint found for the case was not taken up (it started over).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub checkpoint_discarded: Option<String>,
    /// The run summary's warnings, a sentence each (none for a failed case).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

/// What running one case of a [`StudyDir`] did.
#[derive(Clone, Debug, PartialEq)]
pub enum CaseOutcome {
    /// It was finished already (ok or failed): not run.
    Skipped(CaseStatus),
    /// It ran now.
    Ran(CaseStatus),
    /// It was stopped (Ctrl-C, SIGTERM): nothing written, it runs again next time.
    Interrupted,
}

/// A study in its directory.
#[derive(Clone, Debug)]
pub struct StudyDir {
    /// The directory.
    pub dir: PathBuf,
    /// The study.
    pub study: Study,
}

/// Writes `bytes` to `path` through a file beside it and a rename.
fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), StudyError> {
    let tmp = path.with_extension(format!("tmp.{}", std::process::id()));
    std::fs::write(&tmp, bytes).map_err(|e| StudyError::io(&tmp, e))?;
    std::fs::rename(&tmp, path).map_err(|e| StudyError::io(path, e))
}

fn read(path: &Path) -> Result<String, StudyError> {
    std::fs::read_to_string(path).map_err(|e| StudyError::io(path, e))
}

impl StudyDir {
    /// Puts `study` into `dir` (its plan and base scene), or checks that
    /// `dir` already holds this same study.
    pub fn prepare(dir: &Path, study: Study) -> Result<Self, StudyError> {
        let cases = dir.join("cases");
        std::fs::create_dir_all(&cases).map_err(|e| StudyError::io(&cases, e))?;
        for (name, text) in [
            ("plan.toml", &study.plan_toml),
            ("scene.toml", &study.scene_toml),
        ] {
            let path = dir.join(name);
            if path.exists() {
                if &read(&path)? != text {
                    return Err(StudyError::Another {
                        dir: dir.display().to_string(),
                        what: name.to_owned(),
                    });
                }
            } else {
                write_atomic(&path, text.as_bytes())?;
            }
        }
        Ok(Self {
            dir: dir.to_owned(),
            study,
        })
    }

    /// Opens the study prepared in `dir`.
    pub(crate) fn open(dir: &Path) -> Result<Self, StudyError> {
        let plan = read(&dir.join("plan.toml"))?;
        let scene = read(&dir.join("scene.toml"))?;
        Ok(Self {
            dir: dir.to_owned(),
            study: Study::from_texts(&plan, &scene)?,
        })
    }

    /// `DIR/cases/<k>`.
    pub(crate) fn case_dir(&self, k: usize) -> PathBuf {
        self.dir.join("cases").join(k.to_string())
    }

    /// The status of case `k`, if it finished.
    pub(crate) fn status(&self, k: usize) -> Result<Option<CaseStatus>, StudyError> {
        let path = self.case_dir(k).join("status.json");
        if !path.exists() {
            return Ok(None);
        }
        serde_json::from_str(&read(&path)?)
            .map(Some)
            .map_err(|e| StudyError::io(&path, e))
    }

    /// The summary of case `k`, if it finished ok.
    pub(crate) fn summary(&self, k: usize) -> Result<Option<serde_json::Value>, StudyError> {
        let path = self.case_dir(k).join("summary.json");
        if !path.exists() {
            return Ok(None);
        }
        serde_json::from_str(&read(&path)?)
            .map(Some)
            .map_err(|e| StudyError::io(&path, e))
    }

    /// The cases not finished, and with `retry_failed` the failed ones.
    pub fn pending(&self, retry_failed: bool) -> Result<Vec<usize>, StudyError> {
        let mut left = Vec::new();
        for k in 0..self.study.cases.len() {
            match self.status(k)? {
                None => left.push(k),
                Some(s) if retry_failed && !s.ok => left.push(k),
                Some(_) => {}
            }
        }
        Ok(left)
    }

    /// Runs case `k` unless it is finished (a failed one runs again with
    /// `retry_failed`). `stop` ends the run early without writing the case.
    pub(crate) fn run_case(
        &self,
        k: usize,
        retry_failed: bool,
        stop: Option<&AtomicBool>,
    ) -> Result<CaseOutcome, StudyError> {
        let case = self.study.cases.get(k).ok_or(StudyError::NoCase {
            k,
            count: self.study.cases.len(),
        })?;
        let final_dir = self.case_dir(k);
        if let Some(s) = self.status(k)? {
            if s.ok || !retry_failed {
                return Ok(CaseOutcome::Skipped(s));
            }
        }
        let started = Instant::now();
        let factors = case.describe(&self.study.factor_names);
        let scene = self.study.scene(k)?;
        let checkpoint = self
            .study
            .checkpoint_every_s
            .map(|every| (final_dir.join(CHECKPOINT_FILE), every));
        let window_s = self.study.statistics_window_s();
        if checkpoint.is_some() {
            std::fs::create_dir_all(&final_dir).map_err(|e| StudyError::io(&final_dir, e))?;
        }
        let mut resume = Resume::default();
        // A panic in a run is this case's failure, not the study's.
        let result = std::panic::catch_unwind(AssertUnwindSafe(|| {
            let checkpoint = checkpoint.as_ref().map(|(p, s)| (p.as_path(), *s));
            let sampling = case_sampling(&scene, self.study.sample_by_speed)?;
            simulate(&scene, sampling, window_s, stop, checkpoint, &mut resume)
        }))
        .unwrap_or_else(|panic| {
            let what = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| (*s).to_owned()))
                .unwrap_or_else(|| "unknown".to_owned());
            Err(format!("the run panicked: {what}"))
        });
        let (summary, error) = match result {
            Ok(None) => return Ok(CaseOutcome::Interrupted),
            Ok(Some(summary)) => (Some(summary), None),
            Err(e) => (None, Some(e)),
        };
        let status = CaseStatus {
            case: k,
            ok: summary.is_some(),
            error,
            wall_s: resume.earlier_wall_s + started.elapsed().as_secs_f64(),
            factors,
            resumed_from_s: resume.from_s,
            checkpoint_discarded: resume.discarded,
            warnings: summary
                .as_ref()
                .map(|s| s.warnings.clone())
                .unwrap_or_default(),
        };
        // Written aside, then renamed into place.
        let cases = self.dir.join("cases");
        let tmp = cases.join(format!(".{k}.tmp.{}", std::process::id()));
        if tmp.exists() {
            std::fs::remove_dir_all(&tmp).map_err(|e| StudyError::io(&tmp, e))?;
        }
        std::fs::create_dir_all(&tmp).map_err(|e| StudyError::io(&tmp, e))?;
        let scene_text = toml::to_string(scene.file()).map_err(|e| StudyError::io(&tmp, e))?;
        let write = |name: &str, text: String| {
            let p = tmp.join(name);
            std::fs::write(&p, text).map_err(|e| StudyError::io(&p, e))
        };
        write("scene.toml", scene_text)?;
        if let Some(s) = &summary {
            write(
                "summary.json",
                serde_json::to_string_pretty(s).map_err(|e| StudyError::io(&tmp, e))?,
            )?;
        }
        write(
            "status.json",
            serde_json::to_string_pretty(&status).map_err(|e| StudyError::io(&tmp, e))?,
        )?;
        if final_dir.exists() {
            // A failed case run again, or the directory holding the case's
            // checkpoint: the finished case replaces it.
            std::fs::remove_dir_all(&final_dir).map_err(|e| StudyError::io(&final_dir, e))?;
        }
        if let Err(e) = std::fs::rename(&tmp, &final_dir) {
            // Another task finished the same case meanwhile: keep its result.
            let _ = std::fs::remove_dir_all(&tmp);
            if !final_dir.exists() {
                return Err(StudyError::io(&final_dir, e));
            }
        }
        Ok(CaseOutcome::Ran(status))
    }

    /// Runs every pending case on `jobs` threads; `on_done` is called after
    /// each case (on the calling thread). Stops taking cases when `stop` is
    /// set, or after the first case that could not be written.
    ///
    /// # Errors
    ///
    /// The study's files cannot be read, or a case's cannot be written.
    pub fn run_all(
        &self,
        jobs: usize,
        retry_failed: bool,
        stop: Option<&AtomicBool>,
        on_done: &(dyn Fn(&CaseOutcome) + Sync),
    ) -> Result<(), StudyError> {
        let pending = self.pending(retry_failed)?;
        WorkQueue::new(&pending)
            .threads(jobs)
            .stop(stop)
            .try_run(
                |_, &k| Some(self.run_case(k, retry_failed, stop)),
                |_, outcome| match outcome {
                    Ok(outcome) => {
                        on_done(outcome);
                        Ok(())
                    }
                    Err(e) => Err(e.clone()),
                },
            )
            .map(|_| ())
    }
}

/// What a case's checkpoint keeps besides the simulation.
#[derive(Clone, Serialize, Deserialize)]
struct CaseRun {
    signals: Signals,
    steps: u64,
    /// Wall time of the stepping so far, s.
    run_wall_s: f64,
    /// Wall time of the case so far (setup and stepping, every attempt), s.
    case_wall_s: f64,
    setup_wall_s: f64,
    max_penetration_m: f64,
}

/// Whether a case was resumed, and how long its earlier attempts took.
#[derive(Clone, Debug, Default)]
struct Resume {
    from_s: Option<f64>,
    discarded: Option<String>,
    earlier_wall_s: f64,
}

/// Runs `scene` to its end, sampled at `sampling`, its statistics over the
/// last `window_s` (`None`: the default window after the ramps);
/// `Ok(None)` when stopped. With `checkpoint = (path, S)` it resumes from
/// `path` when the file exists, and writes it at every multiple of S and
/// when stopped.
fn simulate(
    scene: &Scene,
    sampling: SampleRate,
    window_s: Option<f64>,
    stop: Option<&AtomicBool>,
    checkpoint: Option<(&Path, f64)>,
    resume: &mut Resume,
) -> Result<Option<RunSummary>, String> {
    let started = Instant::now();
    let mut sim = Simulation::new(scene).map_err(|e| e.to_string())?;
    let mut setup_wall_s = started.elapsed().as_secs_f64();
    let dt = scene.solver().dt_s;
    let duration = scene.solver().duration_s;
    // The plan's statistics window, or the default after the scene's ramps;
    // only its rows are kept (and in a checkpoint).
    let window = StatsWindow::of(scene, window_s).map_err(|e| e.to_string())?;
    let mut signals = window.observe(&mut sim, sampling.rate_hz);
    let mut so_far = RunOutcome {
        steps: 0,
        wall_s: 0.0,
        interrupted: false,
        max_penetration_m: 0.0,
        stage_times: None,
    };
    if let Some((path, _)) = checkpoint.filter(|(p, _)| p.exists()) {
        let taken = read_checkpoint::<CaseRun>(path, scene)
            .and_then(|ck| sim.restore(&ck.sim).map(|()| ck.run));
        match taken {
            Ok(run) => {
                resume.from_s = Some(sim.state.t_s);
                resume.earlier_wall_s = run.case_wall_s;
                signals = run.signals;
                so_far.steps = run.steps;
                so_far.wall_s = run.run_wall_s;
                so_far.max_penetration_m = run.max_penetration_m;
                setup_wall_s = run.setup_wall_s;
            }
            Err(e) => {
                // The checkpoint only saves time: start over from the
                // scene (a fresh simulation, the restore may have begun).
                resume.discarded = Some(e.to_string());
                sim = Simulation::new(scene).map_err(|e| e.to_string())?;
                signals = window.observe(&mut sim, sampling.rate_hz);
            }
        }
    }
    loop {
        let until = match checkpoint {
            Some((_, every)) => next_checkpoint_s(sim.state.t_s, dt, every, duration),
            None => duration,
        };
        let piece = sim
            .run(until, sampling.every, &mut signals, stop)
            .map_err(|e| e.to_string())?;
        so_far.steps += piece.steps;
        so_far.wall_s += piece.wall_s;
        so_far.max_penetration_m = so_far.max_penetration_m.max(piece.max_penetration_m);
        so_far.interrupted = piece.interrupted;
        let done = piece.interrupted || run_is_done(sim.state.t_s, dt, duration);
        if let Some((path, _)) = checkpoint
            && (piece.interrupted || !done)
        {
            let ck = Checkpoint {
                sim: sim.snapshot().map_err(|e| e.to_string())?,
                run: CaseRun {
                    signals: signals.clone(),
                    steps: so_far.steps,
                    run_wall_s: so_far.wall_s,
                    case_wall_s: resume.earlier_wall_s + started.elapsed().as_secs_f64(),
                    setup_wall_s,
                    max_penetration_m: so_far.max_penetration_m,
                },
            };
            write_checkpoint(path, scene, &ck).map_err(|e| e.to_string())?;
        }
        if done {
            break;
        }
    }
    if so_far.interrupted {
        return Ok(None);
    }
    Ok(Some(RunSummary::of_run_in(
        &sim,
        &so_far,
        &signals,
        setup_wall_s,
        &window,
    )))
}
