//! The bindings' one door into the chaindrive library for scenes and runs
//! (the other is [`crate::bridge_studies`]): every `chaindrive::` path the
//! bindings use for a scene, a run, a checkpoint or a recording is named in
//! this file, and what leaves it is plain Rust data (strings, `Vec<f64>`,
//! JSON and TOML values) or the opaque [`Scene`].
//!
//! It does what `chaindrive run` does around [`Simulation::run`] (the
//! statistics window, the sampling, checkpoints, the recording, the
//! summary) and adds no physics. It knows nothing of Python: the caller's
//! [`RunHooks`] are asked at every sample whether to stop.

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use chaindrive::analysis::{RunSummary, SampleRow, Signals, StatsWindow};
use chaindrive::lab::{
    Checkpoint, next_checkpoint_s, read_checkpoint, run_is_done, write_checkpoint,
};
use chaindrive::record::{Channels, RecordMark, RecordOptions, Recorder, RunEnd};
use chaindrive::scene::{Assignment, Overrides, ProfileKind, SceneError, ScenePath};
use chaindrive::sim::{Observer, RunOutcome, Sample, SampleRate, Simulation};
use serde::{Deserialize, Serialize};

pub(crate) use chaindrive::scene::Scene;

/// One problem with one field of a scene.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Problem {
    /// The field's path (`sprockets[2].teeth`); empty for a TOML syntax error.
    pub path: String,
    /// What is wrong and what is allowed.
    pub message: String,
    /// 1-based line and column of the value in the text, when known.
    pub location: Option<(usize, usize)>,
}

/// Why a scene was rejected: the message the command line prints (one
/// line per problem, the file's name first) and the problems.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct SceneFailure {
    pub message: String,
    pub problems: Vec<Problem>,
}

impl SceneFailure {
    /// `file:line:col: path: message` lines, as `chaindrive check` prints
    /// them (`source`: the file's name, or `None` for text).
    fn of(e: &SceneError, source: Option<&str>) -> Self {
        let problems = match e {
            SceneError::Invalid(errors) => errors
                .iter()
                .map(|f| Problem {
                    path: f.path.clone(),
                    message: f.message.clone(),
                    location: f.location,
                })
                .collect(),
            SceneError::Syntax(s) => vec![Problem {
                path: String::new(),
                message: s.replace('\n', " "),
                location: None,
            }],
        };
        let lines: Vec<String> = e
            .lines()
            .iter()
            .map(|l| match source {
                Some(name) if l.starts_with(|c: char| c.is_ascii_digit()) => {
                    format!("{name}:{l}")
                }
                Some(name) => format!("{name}: {l}"),
                None => l.clone(),
            })
            .collect();
        Self {
            message: lines.join("\n"),
            problems,
        }
    }
}

/// Why a scene file could not be loaded.
#[derive(Debug)]
pub(crate) enum LoadError {
    /// The file cannot be read.
    Io(String),
    /// It is not a valid scene.
    Scene(SceneFailure),
}

/// Reads and validates the scene file at `path` (relative file names in it
/// are read beside it).
pub(crate) fn scene_from_file(path: &Path) -> Result<Scene, LoadError> {
    match Scene::from_path_with(path, &Overrides::default()) {
        Err(e) => Err(LoadError::Io(format!(
            "cannot read scene {}: {e}",
            path.display()
        ))),
        Ok(Err(e)) => Err(LoadError::Scene(SceneFailure::of(
            &e,
            Some(&path.display().to_string()),
        ))),
        Ok(Ok(scene)) => Ok(scene),
    }
}

/// Parses and validates a scene's TOML text.
pub(crate) fn scene_from_toml(text: &str) -> Result<Scene, SceneFailure> {
    Scene::from_toml(text).map_err(|e| SceneFailure::of(&e, None))
}

/// The paper's drive (the embedded `assets/l60mc.toml`).
pub(crate) fn paper() -> Scene {
    Scene::l60mc()
}

/// `scene` with each `(dotted path, value)` written into its file form in
/// order, validated again (the paths a study plan's factors use).
pub(crate) fn scene_with(
    scene: &Scene,
    values: &[(String, toml::Value)],
) -> Result<Scene, SceneFailure> {
    let assignments = values
        .iter()
        .map(|(path, value)| {
            let path: ScenePath = path.trim().parse()?;
            Ok(Assignment {
                path,
                value: value.clone(),
            })
        })
        .collect::<Result<Vec<_>, SceneError>>()
        .map_err(|e| SceneFailure::of(&e, None))?;
    scene
        .with_set(&assignments)
        .map_err(|e| SceneFailure::of(&e, None))
}

/// `scene` with its chain named by `designation` (`"ISO 606 16B-1"`,
/// `"ANSI 80"`): the pitch, roller radius, roller mass, stiffness and pin
/// radius written in the scene are dropped, so that the table's values
/// apply; everything else stays (sprockets laid out for another pitch are
/// the validator's to report).
pub(crate) fn scene_with_designation(
    scene: &Scene,
    designation: &str,
) -> Result<Scene, SceneFailure> {
    let mut file = scene.file().clone();
    let chain = &mut file.chain;
    chain.designation = Some(designation.to_owned());
    chain.pitch_m = None;
    chain.roller_radius_m = None;
    chain.roller_mass_kg = None;
    chain.stiffness_n_m = None;
    chain.pin_radius_m = None;
    Scene::from_file_with(file, &Overrides::default()).map_err(|e| SceneFailure::of(&e, None))
}

/// The scene's file form as TOML (overrides included).
pub(crate) fn scene_toml(scene: &Scene) -> Result<String, String> {
    toml::to_string(scene.file()).map_err(|e| e.to_string())
}

/// The scene's file form as JSON (for a dict).
pub(crate) fn scene_json(scene: &Scene) -> Result<serde_json::Value, String> {
    serde_json::to_value(scene.file()).map_err(|e| e.to_string())
}

/// Whether two scenes have the same file form (the same scene to run).
pub(crate) fn same_scene(a: &Scene, b: &Scene) -> bool {
    a.file() == b.file()
}

/// The scene's name.
pub(crate) fn scene_name(scene: &Scene) -> &str {
    scene.name()
}

/// What is valid but likely unintended in the scene, a sentence each.
pub(crate) fn scene_warnings(scene: &Scene) -> Vec<String> {
    scene.warnings()
}

/// The run's settings beside the scene, as `chaindrive run`'s options.
#[derive(Clone, Debug, Default)]
pub(crate) struct RunSettings {
    pub duration_s: Option<f64>,
    pub window_s: Option<f64>,
    pub rate_hz: f64,
    /// An integrator's name (`velocity_verlet`, `rk4`, …).
    pub integrator: Option<String>,
    /// Every sprocket's tooth profile: `circular` or `real`.
    pub profile: Option<String>,
    /// The step, s, or `None` with `dt_auto`.
    pub dt_s: Option<f64>,
    pub dt_auto: bool,
    /// `"speed"`: the step chosen for speed.
    pub dt_speed: bool,
    /// `substepped` or `rapier`.
    pub stepping: Option<String>,
    /// Keep every sample of the series (else only the summary's window).
    pub keep_series: bool,
    pub record: Option<PathBuf>,
    pub record_channels: String,
    pub checkpoint: Option<PathBuf>,
    pub checkpoint_every_s: Option<f64>,
    pub resume: Option<PathBuf>,
}

/// Why a run could not be made.
#[derive(Debug)]
pub(crate) enum RunError {
    /// The scene with the run's settings is invalid.
    Scene(SceneFailure),
    /// A setting of the run is invalid (the message names it).
    Setting(String),
    /// A file could not be read or written.
    Io(String),
    /// The simulation could not start, or blew up.
    Sim(String),
}

/// What the caller is asked during a run.
pub(crate) trait RunHooks {
    /// Called at every sample with the simulated time; `true` stops the run
    /// there (it then ends as interrupted).
    fn poll(&mut self, t_s: f64, duration_s: f64) -> bool;
}

/// The sampled series, one row per sample, each quantity a row-major
/// `samples × width` block in one contiguous vector.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub(crate) struct Series {
    pub t_s: Vec<f64>,
    /// Angular speed of each sprocket, rad/s.
    pub omega_rad_s: Vec<f64>,
    /// Moment of the chain on each sprocket, N·m.
    pub chain_torque_n_m: Vec<f64>,
    /// Mean link force of each segment's free strand, N (NaN: no free link).
    pub segment_force_n: Vec<f64>,
    /// Transverse displacement of each segment's middle, m.
    pub transverse_m: Vec<f64>,
    pub sprockets: usize,
    pub segments: usize,
}

impl Series {
    fn with_capacity(samples: usize, sprockets: usize, segments: usize) -> Self {
        Self {
            t_s: Vec::with_capacity(samples),
            omega_rad_s: Vec::with_capacity(samples * sprockets),
            chain_torque_n_m: Vec::with_capacity(samples * sprockets),
            segment_force_n: Vec::with_capacity(samples * segments),
            transverse_m: Vec::with_capacity(samples * segments),
            sprockets,
            segments,
        }
    }

    fn push(&mut self, row: &SampleRow) {
        self.t_s.push(row.t_s);
        self.omega_rad_s.extend_from_slice(&row.omega_rad_s);
        self.chain_torque_n_m
            .extend_from_slice(&row.chain_torque_n_m);
        self.segment_force_n
            .extend(row.segment_force_n.iter().map(|f| f.unwrap_or(f64::NAN)));
        self.transverse_m.extend_from_slice(&row.transverse_m);
    }
}

/// A run's result.
#[derive(Debug)]
pub(crate) struct RunOutput {
    /// The run summary (the public summary schema).
    pub summary: serde_json::Value,
    pub series: Series,
    pub interrupted: bool,
}

/// What a checkpoint keeps besides the simulation: `chaindrive run`'s own
/// fields (so that either can resume the other's checkpoint) and the
/// series taken so far.
#[derive(Clone, Serialize, Deserialize)]
struct RunState {
    rate_hz: f64,
    /// The statistics window's length as given (`None`: the default), as
    /// `chaindrive run` keeps its `--window`.
    window: Option<f64>,
    /// Where the statistics window started, s.
    window_from_s: f64,
    signals: Signals,
    steps: u64,
    wall_s: f64,
    max_penetration_m: f64,
    /// `chaindrive run`'s series file length (not used here).
    #[serde(default)]
    series_bytes: Option<u64>,
    #[serde(default)]
    record: Option<RecordMark>,
    /// The series taken up to the checkpoint (`None`: a checkpoint of
    /// `chaindrive run`, whose series is in its file).
    #[serde(default)]
    series: Option<Series>,
}

/// Watches the run: the summary's signals, the series, the recording and
/// the caller's hooks.
struct RunObserver<'a> {
    signals: Signals,
    series: Series,
    keep_series: bool,
    recorder: Option<Recorder<BufWriter<File>>>,
    hooks: &'a mut dyn RunHooks,
    stop: &'a AtomicBool,
    duration_s: f64,
}

impl Observer for RunObserver<'_> {
    fn sample(&mut self, s: &Sample<'_>) {
        self.signals.sample(s);
        if let Some(r) = self.recorder.as_mut() {
            r.sample(s);
        }
        if self.keep_series
            && let Some(row) = self.signals.rows.last()
        {
            self.series.push(row);
        }
        if self.hooks.poll(s.state.t_s, self.duration_s) {
            self.stop.store(true, Ordering::Relaxed);
        }
    }
    fn step(&mut self, s: &Sample<'_>) {
        self.signals.step(s);
    }
    fn per_step_from_s(&self) -> f64 {
        self.signals.per_step_from_s()
    }
}

/// The scene with the run's overrides. A name that is not one of its
/// field's is written into the scene file as it is, so that the
/// validator's own message (path and allowed names) reports it.
fn with_settings(scene: &Scene, s: &RunSettings) -> Result<Scene, RunError> {
    let scene_error = |e: SceneError| RunError::Scene(SceneFailure::of(&e, None));
    let named = |path: &str, name: &Option<String>| -> Result<(), RunError> {
        if let Some(name) = name {
            let a = Assignment {
                path: path.parse().map_err(scene_error)?,
                value: toml::Value::String(name.clone()),
            };
            scene.with_set(&[a]).map_err(scene_error)?;
        }
        Ok(())
    };
    named("solver.integrator", &s.integrator)?;
    named("solver.stepping", &s.stepping)?;
    named("profile", &s.profile)?;
    let (integrator, stepping, profile) = (
        s.integrator.as_deref(),
        s.stepping.as_deref(),
        s.profile.as_deref(),
    );
    let overrides = Overrides {
        profile: profile.and_then(ProfileKind::parse),
        duration_s: s.duration_s,
        dt_s: s.dt_s,
        dt_auto: s.dt_auto,
        dt_speed: s.dt_speed,
        stepping: stepping.and_then(chaindrive::scene::Stepping::from_name),
        integrator: integrator.and_then(chaindrive::scene::Integrator::from_name),
        sample_rate_hz: Some(s.rate_hz),
        ..Overrides::default()
    };
    scene.with(&overrides).map_err(scene_error)
}

/// Runs `scene` with `settings` as `chaindrive run` does: the summary over
/// its statistics window and the series at `settings.rate_hz`; checkpoints,
/// a resume and a recording when asked. `hooks` may stop it (the result is
/// then the run so far, `interrupted`).
pub(crate) fn run(
    scene: &Scene,
    settings: &RunSettings,
    hooks: &mut dyn RunHooks,
) -> Result<RunOutput, RunError> {
    let scene = with_settings(scene, settings)?;
    let window = StatsWindow::of(&scene, settings.window_s)
        .map_err(|e| RunError::Setting(format!("window: {e}")))?;
    let rate = SampleRate::new(settings.rate_hz, scene.solver().dt_s)
        .map_err(|e| RunError::Setting(format!("rate {}: {e}", settings.rate_hz)))?;
    if let Some(every) = settings.checkpoint_every_s
        && !(every.is_finite() && every > 0.0)
    {
        return Err(RunError::Setting(format!(
            "checkpoint_every {every}: the time between checkpoints must be a number of simulated seconds > 0"
        )));
    }
    let resume = settings
        .resume
        .as_deref()
        .map(|p| read_resume(p, &scene, rate, settings.window_s))
        .transpose()?;
    let recorder = settings
        .record
        .as_deref()
        .map(|p| start_recording(p, settings, &scene, rate, resume.as_ref()))
        .transpose()?;
    let setup = Instant::now();
    let mut sim = Simulation::new(&scene)
        .map_err(|e| RunError::Sim(format!("cannot start the simulation: {e}")))?;
    let setup_wall_s = setup.elapsed().as_secs_f64();
    let duration_s = scene.solver().duration_s;
    let (sprockets, segments) = (scene.sprockets().len(), sim.model().segment_count());
    // Room for every sample up front (no reallocation while running), up
    // to ten million rows; a longer series grows as it goes.
    let samples = if settings.keep_series {
        (duration_s * rate.rate_hz).ceil().clamp(0.0, 1e7) as usize + 1
    } else {
        0
    };
    let stop = AtomicBool::new(false);
    let mut observer = RunObserver {
        signals: window.observe(&mut sim, rate.rate_hz),
        series: Series::with_capacity(samples, sprockets, segments),
        keep_series: settings.keep_series,
        recorder,
        hooks,
        stop: &stop,
        duration_s,
    };
    let mut so_far = RunOutcome {
        steps: 0,
        wall_s: 0.0,
        interrupted: false,
        max_penetration_m: 0.0,
        stage_times: None,
    };
    if let Some(ck) = resume {
        sim.restore(&ck.sim)
            .map_err(|e| RunError::Io(format!("cannot resume from the checkpoint: {e}")))?;
        observer.signals = ck.run.signals;
        so_far.steps = ck.run.steps;
        so_far.wall_s = ck.run.wall_s;
        so_far.max_penetration_m = ck.run.max_penetration_m;
        // The series up to the checkpoint; the resumed run samples after it.
        if let Some(series) = ck.run.series.filter(|_| settings.keep_series) {
            observer.series = series;
        }
    }
    let checkpoints = settings
        .checkpoint
        .as_deref()
        .zip(settings.checkpoint_every_s);
    let outcome = run_pieces(
        &mut sim,
        &mut observer,
        so_far,
        checkpoints,
        rate,
        (window, settings.window_s),
        &stop,
    );
    if let Some(r) = observer.recorder.take() {
        let failure = outcome.as_ref().err().map(ToString::to_string);
        let end = match (&outcome, &failure) {
            (_, Some(m)) => RunEnd::Failed(m),
            (Ok(o), None) if o.interrupted => RunEnd::Interrupted,
            _ => RunEnd::Completed,
        };
        r.finish(end)
            .map_err(|e| RunError::Io(format!("writing the recording failed: {e}")))?;
    }
    let outcome = outcome?;
    let summary = RunSummary::of_run_in(&sim, &outcome, &observer.signals, setup_wall_s, &window);
    Ok(RunOutput {
        summary: serde_json::to_value(&summary).map_err(|e| RunError::Io(e.to_string()))?,
        series: observer.series,
        interrupted: outcome.interrupted,
    })
}

/// Reads a checkpoint to resume, refusing one of another scene, rate or window.
fn read_resume(
    path: &Path,
    scene: &Scene,
    rate: SampleRate,
    window: Option<f64>,
) -> Result<Checkpoint<RunState>, RunError> {
    let ck: Checkpoint<RunState> =
        read_checkpoint(path, scene).map_err(|e| RunError::Io(e.to_string()))?;
    if ck.run.rate_hz.to_bits() != rate.rate_hz.to_bits()
        || ck.run.window.map(f64::to_bits) != window.map(f64::to_bits)
    {
        let shown =
            |w: Option<f64>| w.map_or_else(|| "the default".to_owned(), |w| format!("{w} s"));
        return Err(RunError::Setting(format!(
            "checkpoint {}: the run was started with rate {} Hz and a statistics window of {}, not {} Hz and {}: resume with the same settings",
            path.display(),
            ck.run.rate_hz,
            shown(ck.run.window),
            rate.rate_hz,
            shown(window)
        )));
    }
    Ok(ck)
}

/// Opens the recording before anything is simulated (an unwritable path
/// fails now); a resumed run's recording continues the earlier file, as
/// `chaindrive run --resume --record` does.
fn start_recording(
    path: &Path,
    settings: &RunSettings,
    scene: &Scene,
    rate: SampleRate,
    resume: Option<&Checkpoint<RunState>>,
) -> Result<Recorder<BufWriter<File>>, RunError> {
    let io = |what: &str, e: &dyn std::fmt::Display| {
        RunError::Io(format!("record {}: {what}: {e}", path.display()))
    };
    let channels = Channels::parse(&settings.record_channels)
        .map_err(|e| RunError::Setting(format!("record_channels: {e}")))?;
    let text = scene_toml(scene).map_err(|e| io("cannot write the scene", &e))?;
    let options = RecordOptions {
        channels,
        scene_file: Some(("scene.toml".to_owned(), text.into_bytes())),
        rate_hz: rate.rate_hz,
    };
    let create = || File::create(path).map(BufWriter::new);
    let Some(ck) = resume else {
        let file = create().map_err(|e| io("cannot create", &e))?;
        return Recorder::new(file, scene, &options).map_err(|e| io("cannot record", &e));
    };
    let Some(mark) = ck.run.record else {
        return Err(RunError::Setting(format!(
            "record {}: the run being resumed was not recorded, so its recording cannot be continued; resume without record",
            path.display()
        )));
    };
    Recorder::continue_file(path, scene, &options, &mark).map_err(|e| io("cannot continue", &e))
}

impl std::fmt::Display for RunError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Scene(s) => write!(f, "{}", s.message),
            Self::Setting(m) | Self::Io(m) | Self::Sim(m) => write!(f, "{m}"),
        }
    }
}

/// Runs to the scene's end, in pieces between checkpoints when asked
/// (every `every` simulated seconds and when stopped), as `chaindrive run`.
fn run_pieces(
    sim: &mut Simulation,
    observer: &mut RunObserver<'_>,
    mut so_far: RunOutcome,
    checkpoints: Option<(&Path, f64)>,
    rate: SampleRate,
    (window, window_given): (StatsWindow, Option<f64>),
    stop: &AtomicBool,
) -> Result<RunOutcome, RunError> {
    let dt = sim.scene().solver().dt_s;
    let duration = sim.scene().solver().duration_s;
    loop {
        let until = match checkpoints {
            Some((_, every)) => next_checkpoint_s(sim.state().t_s, dt, every, duration),
            None => duration,
        };
        let piece = sim
            .run(until, rate.every, observer, Some(stop))
            .map_err(|e| RunError::Sim(e.to_string()))?;
        so_far.steps += piece.steps;
        so_far.wall_s += piece.wall_s;
        so_far.max_penetration_m = so_far.max_penetration_m.max(piece.max_penetration_m);
        so_far.interrupted = piece.interrupted;
        let done = piece.interrupted || run_is_done(sim.state().t_s, dt, duration);
        if let Some((path, _)) = checkpoints
            && (piece.interrupted || !done)
        {
            let record = match observer.recorder.as_mut() {
                Some(r) => Some(
                    r.mark()
                        .map_err(|e| RunError::Io(format!("recording: {e}")))?,
                ),
                None => None,
            };
            let ck = Checkpoint {
                sim: sim
                    .snapshot()
                    .map_err(|e| RunError::Setting(e.to_string()))?,
                run: RunState {
                    rate_hz: rate.rate_hz,
                    window: window_given,
                    window_from_s: window.start_s(),
                    signals: observer.signals.clone(),
                    steps: so_far.steps,
                    wall_s: so_far.wall_s,
                    max_penetration_m: so_far.max_penetration_m,
                    series_bytes: None,
                    record,
                    series: observer.keep_series.then(|| observer.series.clone()),
                },
            };
            write_checkpoint(path, sim.scene(), &ck).map_err(|e| RunError::Io(e.to_string()))?;
        }
        if done {
            return Ok(so_far);
        }
    }
}
