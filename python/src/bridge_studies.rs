//! The bindings' second door into the chaindrive library (the first is
//! [`crate::bridge`]): `check`, the speed sweep, design studies, the
//! catalogue rating and the table of chains. Every `chaindrive::` path they
//! use is named here; what leaves is plain Rust data: JSON values and
//! [`Table`]s of columns.
//!
//! Sweeps and studies run on their own threads while the calling thread
//! asks the caller's [`RunHooks`] every few milliseconds whether to stop
//! (Ctrl-C): a stopped sweep keeps its finished speeds, a stopped study
//! its finished cases (it resumes from its directory).

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Duration;

use chaindrive::lab::{
    CaseFlags, CaseOutcome, CaseResult, ColumnData, DESIGNATIONS, Designation, DutyCycle,
    DutyError, LifeSettings, OrderSet, RatingSettings, Study, StudyDir, StudyError, StudyTable,
    SweepError, SweepSettings, TRANSVERSE_MODES, combine_duty, completed, default_orders,
    lookup_designation, run_sweep, summary_scalars,
};
use serde_json::{Value, json};

use crate::bridge::{RunHooks, Scene};

/// One column of a table.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Column {
    /// Numbers; NaN where a value is missing.
    Float(Vec<f64>),
    /// Integers, never missing.
    Int(Vec<i64>),
    /// Booleans; `None` where missing.
    Bool(Vec<Option<bool>>),
    /// Text; `None` where missing.
    Text(Vec<Option<String>>),
}

/// Named columns of equal length (a long table: one row per observation).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Table {
    pub columns: Vec<(String, Column)>,
}

/// `scene` laid out and brought to static equilibrium, as `chaindrive
/// check` reports it: strands, wraps, the chain's length, the static
/// tension, the step; `Err` with the message if it cannot be.
pub(crate) fn check(scene: &Scene) -> Result<Value, String> {
    chaindrive::lab::check_report(scene).map_err(|e| e.to_string())
}

/// What a sweep is asked for (as `chaindrive sweep`'s options).
#[derive(Clone, Debug)]
pub(crate) struct SweepRequest {
    pub rpm: Vec<f64>,
    pub settle_s: f64,
    pub window_s: f64,
    pub jobs: usize,
    /// Largest order (`None`: twice the largest tooth count).
    pub max_order: Option<f64>,
    pub order_step: f64,
}

/// A sweep's results: the long tables `chaindrive sweep` writes as CSV
/// (`sweep.csv` as `scalars`, `cases.csv`, `orders.csv`, `spans.csv`) and
/// each finished speed's run summary.
#[derive(Debug, Default)]
pub(crate) struct SweepOutput {
    pub scalars: Table,
    pub cases: Table,
    pub orders: Table,
    pub spans: Table,
    pub summaries: Vec<(f64, Value)>,
    pub interrupted: bool,
}

/// Runs the sweep on its own threads; `hooks` sees (speeds done, speeds)
/// and may stop it.
pub(crate) fn sweep(
    scene: &Scene,
    request: &SweepRequest,
    hooks: &mut dyn RunHooks,
) -> Result<SweepOutput, String> {
    let orders = match request.max_order {
        Some(k) => OrderSet::new(k, request.order_step)
            .map_err(|e| format!("max_order {k}, order_step {}: {e}", request.order_step))?,
        None => {
            let d = default_orders(scene).map_err(|e| e.to_string())?;
            OrderSet::new(d.max_order(), request.order_step)
                .map_err(|e| format!("order_step {}: {e}", request.order_step))?
        }
    };
    let settings = SweepSettings {
        rpm: request.rpm.clone(),
        settle_s: request.settle_s,
        window_s: request.window_s,
        jobs: request.jobs.max(1),
        orders,
    };
    let total = settings.rpm.len();
    let done = AtomicUsize::new(0);
    let stop = AtomicBool::new(false);
    let cases = watched(hooks, &stop, &done, total, || {
        run_sweep(scene, &settings, Some(&stop), &|_| {
            done.fetch_add(1, Ordering::Relaxed);
        })
        .map_err(sweep_error)
    })?;
    let mut out = sweep_tables(&cases);
    out.interrupted = stop.load(Ordering::Relaxed) && cases.len() < total;
    Ok(out)
}

/// Speeds `FROM:TO:STEP` in rpm, as `chaindrive sweep --rpm` reads them.
pub(crate) fn rpm_range(text: &str) -> Result<Vec<f64>, String> {
    let bad = |why: &str| {
        format!(
            "rpm = {text:?}: {why} (allowed: FROM:TO:STEP in rpm with 0 < FROM ≤ TO and STEP > 0, e.g. 300:3000:100)"
        )
    };
    let nums = text
        .split(':')
        .map(|p| p.trim().parse::<f64>().map_err(|_| bad("not a number")))
        .collect::<Result<Vec<f64>, String>>()?;
    let [from, to, step] = nums[..] else {
        return Err(bad("three numbers separated by ':' are needed"));
    };
    if !(from.is_finite() && to.is_finite() && step.is_finite()) {
        return Err(bad("not finite"));
    }
    if !(from > 0.0 && to >= from && step > 0.0) {
        return Err(bad("FROM must be > 0, TO not below FROM, STEP > 0"));
    }
    let count = ((to - from) / step * (1.0 + 1e-12) + 1e-9).floor() + 1.0;
    if count > 100_000.0 {
        return Err(bad("more than 100000 speeds"));
    }
    Ok((0..count as usize)
        .map(|i| from + i as f64 * step)
        .collect())
}

/// A sweep's error, its settings named as the Python keywords (`window`,
/// not `--window`).
fn sweep_error(e: SweepError) -> String {
    let keyword = |what: &str| what.trim_start_matches('-').replace('-', "_");
    match e {
        SweepError::BadTime { what, value, why } => format!("{} {value}: {why}", keyword(what)),
        SweepError::BadRange { what, text, why } => {
            format!(
                "{} {text:?}: {}",
                keyword(what),
                why.split("; write").next().unwrap_or(&why)
            )
        }
        other => other.to_string(),
    }
}

/// Runs `work` on a thread of its own while this one polls `hooks` with
/// (`done`, `total`) every 20 ms, setting `stop` when they ask.
fn watched<T: Send>(
    hooks: &mut dyn RunHooks,
    stop: &AtomicBool,
    done: &AtomicUsize,
    total: usize,
    work: impl FnOnce() -> T + Send,
) -> T {
    std::thread::scope(|s| {
        let worker = s.spawn(work);
        while !worker.is_finished() {
            std::thread::sleep(Duration::from_millis(20));
            if hooks.poll(done.load(Ordering::Relaxed) as f64, total as f64) {
                stop.store(true, Ordering::Relaxed);
            }
        }
        match worker.join() {
            Ok(v) => v,
            Err(panic) => std::panic::resume_unwind(panic),
        }
    })
}

/// The sweep's outcomes as `chaindrive sweep`'s four tables.
fn sweep_tables(cases: &[CaseOutcome]) -> SweepOutput {
    let mut out = SweepOutput::default();
    let (mut rpm, mut name, mut value) = (Vec::new(), Vec::new(), Vec::new());
    let mut push = |r: f64, n: String, v: f64| {
        rpm.push(r);
        name.push(Some(n));
        value.push(v);
    };
    for case in cases {
        match case {
            CaseOutcome::Done(r) => {
                push(r.rpm, "failed".to_owned(), 0.0);
                for (n, v) in summary_scalars(r) {
                    push(r.rpm, n, v);
                }
                if let Some(s) = &r.summary
                    && let Ok(v) = serde_json::to_value(s)
                {
                    out.summaries.push((r.rpm, v));
                }
            }
            CaseOutcome::Failed { rpm: r, .. } => push(*r, "failed".to_owned(), 1.0),
        }
    }
    out.scalars = Table {
        columns: vec![
            ("rpm".into(), Column::Float(rpm)),
            ("statistic".into(), Column::Text(name)),
            ("value".into(), Column::Float(value)),
        ],
    };
    out.cases = case_flags(cases);
    let done = completed(cases);
    let mut o: [Vec<f64>; 5] = Default::default();
    let mut signal = Vec::new();
    for r in &done {
        for s in &r.orders {
            for c in &s.spectrum.components {
                for (col, v) in
                    o.iter_mut()
                        .zip([r.rpm, c.order, c.frequency_hz, c.amplitude, c.phase_rad])
                {
                    col.push(v);
                }
                signal.push(Some(s.signal.clone()));
            }
        }
    }
    let [o_rpm, order, frequency, amplitude, phase] = o;
    out.orders = Table {
        columns: vec![
            ("rpm".into(), Column::Float(o_rpm)),
            ("signal".into(), Column::Text(signal)),
            ("order".into(), Column::Float(order)),
            ("frequency_hz".into(), Column::Float(frequency)),
            ("amplitude".into(), Column::Float(amplitude)),
            ("phase_rad".into(), Column::Float(phase)),
        ],
    };
    out.spans = spans_table(&done);
    out
}

/// `cases.csv`: each speed's status, stationarity and warnings.
fn case_flags(cases: &[CaseOutcome]) -> Table {
    let flags: Vec<CaseFlags> = cases.iter().map(CaseFlags::of).collect();
    Table {
        columns: vec![
            (
                "rpm".into(),
                Column::Float(flags.iter().map(|f| f.rpm).collect()),
            ),
            (
                "status".into(),
                Column::Text(flags.iter().map(|f| Some(f.status.to_owned())).collect()),
            ),
            (
                "stationary".into(),
                Column::Bool(flags.iter().map(|f| f.stationary).collect()),
            ),
            (
                "warning_count".into(),
                Column::Float(
                    flags
                        .iter()
                        .map(|f| f.warnings.as_ref().map_or(f64::NAN, |w| w.len() as f64))
                        .collect(),
                ),
            ),
            (
                "warnings".into(),
                Column::Text(
                    flags
                        .iter()
                        .map(|f| f.warnings.as_ref().map(|w| w.join(" | ")))
                        .collect(),
                ),
            ),
            (
                "error".into(),
                Column::Text(flags.iter().map(|f| f.error.clone()).collect()),
            ),
        ],
    }
}

/// `spans.csv`: each span's tension and predicted natural frequencies per speed.
fn spans_table(done: &[&CaseResult]) -> Table {
    let modes = TRANSVERSE_MODES as usize;
    let (mut rpm, mut segment, mut tension, mut axial) = (vec![], vec![], vec![], vec![]);
    let mut transverse: Vec<Vec<f64>> = vec![Vec::new(); modes];
    for r in done {
        for s in &r.spans {
            rpm.push(r.rpm);
            segment.push(s.segment as i64);
            tension.push(s.tension_n);
            axial.push(s.axial_hz);
            for (n, col) in transverse.iter_mut().enumerate() {
                col.push(s.transverse_hz.get(n).copied().unwrap_or(f64::NAN));
            }
        }
    }
    let mut columns = vec![
        ("rpm".to_owned(), Column::Float(rpm)),
        ("segment".to_owned(), Column::Int(segment)),
        ("tension_n".to_owned(), Column::Float(tension)),
    ];
    for (n, col) in transverse.into_iter().enumerate() {
        columns.push((format!("transverse_{}_hz", n + 1), Column::Float(col)));
    }
    columns.push(("axial_hz".to_owned(), Column::Float(axial)));
    Table { columns }
}

/// Where a study's plan comes from.
pub(crate) enum Plan {
    /// A plan file (its `scene` is read relative to it).
    File(PathBuf),
    /// A plan's TOML text and its base scene's.
    Texts {
        plan_toml: String,
        scene_toml: String,
    },
}

/// A study's results table and whether it was stopped before its end.
pub(crate) struct StudyOutput {
    pub table: Table,
    pub interrupted: bool,
    pub cases: usize,
    /// Cases that were to run (not finished before).
    pub pending: usize,
}

/// Why a study could not run.
pub(crate) enum StudyFailure {
    /// The plan or a case's scene is invalid (every problem, one per line).
    Plan(String),
    /// Anything else: files, another study in the directory.
    Other(String),
}

impl StudyFailure {
    /// A plan's or a case's invalid values as `Plan`, anything else as `Other`.
    fn of(e: StudyError) -> Self {
        match e {
            StudyError::Plan(_) | StudyError::Cases(_) => Self::Plan(e.to_string()),
            other => Self::Other(other.to_string()),
        }
    }
}

/// Prepares the study in `dir` (or checks that `dir` holds this same
/// study), runs its pending cases on `jobs` threads, then merges the cases
/// into one table (also written to `dir` as `results.csv` and
/// `results.parquet`, as `chaindrive study collect` writes them).
pub(crate) fn study(
    plan: Plan,
    dir: &Path,
    jobs: usize,
    retry_failed: bool,
    hooks: &mut dyn RunHooks,
) -> Result<StudyOutput, StudyFailure> {
    let failure = StudyFailure::of;
    let study = match &plan {
        Plan::File(path) => Study::from_plan_path(path).map_err(|e| match e {
            StudyError::Plan(_) | StudyError::Cases(_) => {
                StudyFailure::Plan(format!("{}: {e}", path.display()))
            }
            other => StudyFailure::Other(format!("{}: {other}", path.display())),
        })?,
        Plan::Texts {
            plan_toml,
            scene_toml,
        } => Study::from_texts(plan_toml, scene_toml).map_err(failure)?,
    };
    let study_dir = StudyDir::prepare(dir, study).map_err(failure)?;
    let pending = study_dir.pending(retry_failed).map_err(failure)?.len();
    let done = AtomicUsize::new(0);
    let stop = AtomicBool::new(false);
    watched(hooks, &stop, &done, pending, || {
        study_dir.run_all(jobs, retry_failed, Some(&stop), &|_| {
            done.fetch_add(1, Ordering::Relaxed);
        })
    })
    .map_err(failure)?;
    let table = StudyTable::collect(&study_dir).map_err(failure)?;
    let csv = dir.join("results.csv");
    std::fs::write(&csv, table.to_csv().map_err(failure)?)
        .map_err(|e| StudyFailure::Other(format!("{}: {e}", csv.display())))?;
    table
        .write_parquet(&dir.join("results.parquet"))
        .map_err(failure)?;
    Ok(StudyOutput {
        table: study_table(&table),
        interrupted: stop.load(Ordering::Relaxed),
        cases: study_dir.study.case_count(),
        pending,
    })
}

/// A study's table as columns: counts and numbers with NaN for null.
fn study_table(t: &StudyTable) -> Table {
    let columns = t
        .columns
        .iter()
        .map(|c| {
            let data = match &c.data {
                ColumnData::Int(v) => Column::Int(v.clone()),
                ColumnData::Count(v) => {
                    Column::Float(v.iter().map(|x| x.map_or(f64::NAN, |n| n as f64)).collect())
                }
                ColumnData::Bool(v) => Column::Bool(v.clone()),
                ColumnData::Float(v) => {
                    Column::Float(v.iter().map(|x| x.unwrap_or(f64::NAN)).collect())
                }
                ColumnData::Text(v) => Column::Text(v.clone()),
            };
            (c.name.clone(), data)
        })
        .collect();
    Table { columns }
}

/// The chain's catalogue rating at the scene's speeds, as `chaindrive rate
/// --json` prints it.
pub(crate) fn rate(
    scene: &Scene,
    service_factor: f64,
    power_w: Option<f64>,
) -> Result<Value, String> {
    let settings = RatingSettings { service_factor };
    let r = chaindrive::lab::rate(scene, settings, power_w).map_err(|e| e.to_string())?;
    serde_json::to_value(&r).map_err(|e| e.to_string())
}

/// The table of chains by designation (`chaindrive chains`), or the one
/// row of `name` (any spelling); `Err` names the nearest designations.
pub(crate) fn chains(name: Option<&str>) -> Result<Vec<Value>, String> {
    let Some(n) = name else {
        return Ok(DESIGNATIONS.iter().map(designation_json).collect());
    };
    let chain = lookup_designation(n)?;
    let mut row = designation_json(chain.single);
    if chain.strands > 1 {
        let d = chain.single;
        row["designation"] = json!(chain.name());
        row["mass_per_m_kg"] = json!(chain.mass_per_m_kg());
        row["tensile_strength_n"] = json!(chain.tensile_strength_n());
        row["roller_mass_kg"] = json!(chain.roller_mass_kg());
        row["stiffness_n_m"] = json!(chain.stiffness_n_m());
        row["sources"]["mass"] = json!(chain.derived(d.sources.mass));
        row["sources"]["strength"] = json!(chain.derived(d.sources.strength));
        row["sources"]["stiffness"] = json!(chain.derived(Designation::stiffness_source()));
    }
    row["strands"] = json!(chain.strands);
    Ok(vec![row])
}

fn designation_json(d: &Designation) -> Value {
    json!({
        "designation": d.name,
        "pitch_m": d.pitch_m,
        "roller_diameter_m": d.roller_diameter_m,
        "inner_width_m": d.inner_width_m,
        "pin_diameter_m": d.pin_diameter_m,
        "plate_depth_m": d.plate_depth_m,
        "plate_thickness_m": d.plate_thickness_m,
        "mass_per_m_kg": d.mass_per_m_kg,
        "tensile_strength_n": d.tensile_strength_n,
        "roller_mass_kg": d.roller_mass_kg(),
        "stiffness_n_m": d.stiffness_n_m(),
        "sources": {
            "dimensions": d.sources.dimensions,
            "pin_and_plate_depth": d.sources.pin_and_plate_depth,
            "plate_thickness": d.sources.plate_thickness,
            "mass": d.sources.mass,
            "strength": d.sources.strength,
            "stiffness": Designation::stiffness_source(),
        },
    })
}

/// The `[[duty]]` points of a TOML text (a scene file or a file of points).
#[derive(serde::Deserialize)]
struct DutyForm {
    #[serde(default)]
    duty: Vec<chaindrive::scene::DutyPointFile>,
}

/// What a duty cycle is asked for (as `chaindrive life`'s options).
pub(crate) struct LifeRequest {
    /// `[[duty]]` points as TOML; `None`: the scene's own.
    pub duty_toml: Option<String>,
    pub jobs: usize,
    pub retry_failed: bool,
    pub settings: LifeSettings,
}

/// A duty cycle's outcome: the combined report (`chaindrive life --json`),
/// absent when stopped before every point ran.
pub(crate) struct LifeOutput {
    pub life: Option<Value>,
    pub interrupted: bool,
    pub points: usize,
    pub pending: usize,
}

/// Runs a duty cycle's points as a study in `dir` (resumable: finished
/// points are kept) and combines them by hours, as `chaindrive life` does.
pub(crate) fn life(
    scene: &Scene,
    request: &LifeRequest,
    dir: &Path,
    hooks: &mut dyn RunHooks,
) -> Result<LifeOutput, StudyFailure> {
    let failure = StudyFailure::of;
    let duty_failure = |e: DutyError| match e {
        DutyError::Points(_) => StudyFailure::Plan(e.to_string()),
        DutyError::Study(e) => failure(e),
    };
    let scene_toml = crate::bridge::scene_toml(scene).map_err(StudyFailure::Other)?;
    let text = request.duty_toml.as_deref().unwrap_or(&scene_toml);
    let form: DutyForm =
        toml::from_str(text).map_err(|e| StudyFailure::Plan(format!("duty: {}", e.message())))?;
    if form.duty.is_empty() {
        return Err(StudyFailure::Plan(
            "duty: no [[duty]] points; give them as a list of dicts, e.g. [{\"hours\": 800.0, \"set\": {\"sprockets.0.speed_rpm\": 3000.0}}], a file, or in the scene".to_owned(),
        ));
    }
    let cycle = DutyCycle::new(&form.duty, &scene_toml).map_err(duty_failure)?;
    let study_dir = cycle
        .prepare(dir, &scene_toml, request.settings)
        .map_err(duty_failure)?;
    let pending = study_dir
        .pending(request.retry_failed)
        .map_err(failure)?
        .len();
    let done = AtomicUsize::new(0);
    let stop = AtomicBool::new(false);
    watched(hooks, &stop, &done, pending, || {
        study_dir.run_all(
            request.jobs.max(1),
            request.retry_failed,
            Some(&stop),
            &|_| {
                done.fetch_add(1, Ordering::Relaxed);
            },
        )
    })
    .map_err(failure)?;
    let interrupted = stop.load(Ordering::Relaxed);
    let life = if interrupted {
        None
    } else {
        let report = combine_duty(&cycle, &study_dir).map_err(failure)?;
        Some(serde_json::to_value(&report).map_err(|e| StudyFailure::Other(e.to_string()))?)
    };
    Ok(LifeOutput {
        life,
        interrupted,
        points: cycle.points.len(),
        pending,
    })
}
