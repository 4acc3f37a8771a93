//! The native `check`, `sweep`, `study`, `life`, `rate` and `chains`: what the
//! command line's subcommands of the same names compute, returned as
//! plain data and NumPy columns. The Python package wraps `sweep`,
//! `study` and `life` (tables with `to_pandas()`, `KeyboardInterrupt`).

use std::path::PathBuf;
use std::time::Duration;

use numpy::IntoPyArray;
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::bridge_studies::{self, Column, LifeRequest, Plan, StudyFailure, SweepRequest, Table};
use crate::convert::{json_to_py, vector};
use crate::run::SimError;
use crate::scene::PyScene;
use crate::watch::Watch;

pyo3::create_exception!(
    chaindrive,
    StudyError,
    PyValueError,
    "A study's plan, or a case's scene, is invalid: one `path: message` line\n\
     per problem (paths in the plan, or the case's factor values)."
);

/// A table as a dict of columns: numbers as NumPy arrays (no copy), text
/// and booleans with gaps as lists.
fn table_to_py<'py>(py: Python<'py>, table: Table) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (name, column) in table.columns {
        match column {
            Column::Float(v) => d.set_item(name, vector(py, v))?,
            Column::Int(v) => d.set_item(name, v.into_pyarray(py))?,
            Column::Bool(v) => d.set_item(name, v)?,
            Column::Text(v) => d.set_item(name, v)?,
        }
    }
    Ok(d)
}

/// `chaindrive check`: the scene laid out and at static equilibrium.
#[pyfunction]
fn check<'py>(py: Python<'py>, scene: &Bound<'py, PyScene>) -> PyResult<Bound<'py, PyAny>> {
    let scene = &scene.get().inner;
    let report = py
        .detach(|| bridge_studies::check(scene))
        .map_err(SimError::new_err)?;
    json_to_py(py, &report)
}

/// The speed sweep (wrapped by `chaindrive.sweep`).
#[pyfunction]
#[pyo3(signature = (scene, rpm, *, settle=1.0, window=1.0, jobs=None, max_order=None, order_step=1.0, progress=None))]
#[allow(clippy::too_many_arguments)]
fn sweep<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyScene>,
    rpm: &Bound<'py, PyAny>,
    settle: f64,
    window: f64,
    jobs: Option<usize>,
    max_order: Option<f64>,
    order_step: f64,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    // The command line's `FROM:TO:STEP`, or the speeds themselves.
    let rpm = match rpm.extract::<String>() {
        Ok(text) => bridge_studies::rpm_range(&text).map_err(PyValueError::new_err)?,
        Err(_) => rpm.extract::<Vec<f64>>().map_err(|_| {
            PyValueError::new_err(
                "rpm: the driver speeds, a sequence of numbers or \"FROM:TO:STEP\" (e.g. \"60:180:30\")",
            )
        })?,
    };
    let request = SweepRequest {
        rpm,
        settle_s: settle,
        window_s: window,
        jobs: jobs.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get())),
        max_order,
        order_step,
    };
    let scene = &scene.get().inner;
    let mut watch = Watch::new(progress, Duration::from_millis(100));
    let out = py.detach(|| bridge_studies::sweep(scene, &request, &mut watch));
    watch.raised(py)?;
    let out = out.map_err(PyValueError::new_err)?;
    let d = PyDict::new(py);
    d.set_item("scalars", table_to_py(py, out.scalars)?)?;
    d.set_item("cases", table_to_py(py, out.cases)?)?;
    d.set_item("orders", table_to_py(py, out.orders)?)?;
    d.set_item("spans", table_to_py(py, out.spans)?)?;
    let summaries = PyList::empty(py);
    for (rpm, s) in &out.summaries {
        summaries.append((rpm, json_to_py(py, s)?))?;
    }
    d.set_item("summaries", summaries)?;
    d.set_item("interrupted", out.interrupted)?;
    Ok(d)
}

/// A design study (wrapped by `chaindrive.study`): `plan` is a file, or
/// `plan_toml` with `scene_toml`.
#[pyfunction]
#[pyo3(signature = (dir, *, plan=None, plan_toml=None, scene_toml=None, jobs=1, retry_failed=false, progress=None))]
#[allow(clippy::too_many_arguments)]
fn study<'py>(
    py: Python<'py>,
    dir: PathBuf,
    plan: Option<PathBuf>,
    plan_toml: Option<String>,
    scene_toml: Option<String>,
    jobs: usize,
    retry_failed: bool,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let plan = match (plan, plan_toml, scene_toml) {
        (Some(p), None, None) => Plan::File(p),
        (None, Some(plan_toml), Some(scene_toml)) => Plan::Texts {
            plan_toml,
            scene_toml,
        },
        _ => {
            return Err(PyValueError::new_err(
                "a study needs a plan file, or a plan's TOML with its scene's",
            ));
        }
    };
    let mut watch = Watch::new(progress, Duration::from_millis(100));
    let out = py.detach(|| bridge_studies::study(plan, &dir, jobs, retry_failed, &mut watch));
    watch.raised(py)?;
    let out = match out {
        Ok(o) => o,
        Err(StudyFailure::Plan(m)) => return Err(StudyError::new_err(m)),
        Err(StudyFailure::Other(m)) => return Err(PyOSError::new_err(m)),
    };
    let d = PyDict::new(py);
    d.set_item("table", table_to_py(py, out.table)?)?;
    d.set_item("interrupted", out.interrupted)?;
    d.set_item("cases", out.cases)?;
    d.set_item("pending", out.pending)?;
    Ok(d)
}

/// `chaindrive rate`: the chain's catalogue rating at the scene's speeds.
///
/// `service_factor` divides the rating (1: the tables' smooth load);
/// `power_w` is the transmitted power (default: the scene's load torques at
/// the driver's speed). Returns the rating as a dict (the summary's
/// `rating` block). Raises `ValueError` when the scene cannot be rated (no
/// driver, the smallest sprocket not turning, a bad service factor).
#[pyfunction]
#[pyo3(signature = (scene, *, service_factor=1.0, power_w=None))]
fn rate<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyScene>,
    service_factor: f64,
    power_w: Option<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    if let Some(p) = power_w
        && !(p.is_finite() && p > 0.0)
    {
        return Err(PyValueError::new_err(format!(
            "power_w must be a finite number > 0, got {p}"
        )));
    }
    let scene = &scene.get().inner;
    let r = bridge_studies::rate(scene, service_factor, power_w).map_err(|e| {
        PyValueError::new_err(format!(
            "cannot rate {}: {e}",
            crate::bridge::scene_name(scene)
        ))
    })?;
    json_to_py(py, &r)
}

/// The chains known by designation (ISO 606 B series, ANSI), each a dict of
/// its dimensions, mass, strength, stiffness estimate and the source of
/// each value; with `name` (any spelling: "16B", "ANSI 80") that one only.
/// Raises `ValueError` naming the nearest designations for an unknown name.
#[pyfunction]
#[pyo3(signature = (name=None))]
fn chains<'py>(py: Python<'py>, name: Option<&str>) -> PyResult<Bound<'py, PyList>> {
    let rows = bridge_studies::chains(name).map_err(PyValueError::new_err)?;
    let list = PyList::empty(py);
    for r in &rows {
        list.append(json_to_py(py, r)?)?;
    }
    Ok(list)
}

/// A dict as TOML text (a study plan given as data).
#[pyfunction]
fn _to_toml(value: &Bound<'_, PyDict>) -> PyResult<String> {
    match crate::convert::py_to_toml(value.as_any(), "plan")? {
        toml::Value::Table(t) => {
            toml::to_string(&t).map_err(|e| PyValueError::new_err(format!("plan: {e}")))
        }
        _ => Err(PyValueError::new_err("plan: a dict")),
    }
}

/// A duty cycle's life (wrapped by `chaindrive.life`): the points of
/// `duty_toml` (`[[duty]]` tables; `None`: the scene's own) run as a study
/// in `dir` and combined by hours.
#[pyfunction]
#[pyo3(signature = (scene, dir, *, duty_toml=None, jobs=1, duration=None, window=None, checkpoint_every=None, retry_failed=false, progress=None))]
#[allow(clippy::too_many_arguments)]
fn life<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyScene>,
    dir: PathBuf,
    duty_toml: Option<String>,
    jobs: usize,
    duration: Option<f64>,
    window: Option<f64>,
    checkpoint_every: Option<f64>,
    retry_failed: bool,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    for (name, v) in [
        ("duration", duration),
        ("window", window),
        ("checkpoint_every", checkpoint_every),
    ] {
        if let Some(v) = v
            && !(v.is_finite() && v > 0.0)
        {
            return Err(PyValueError::new_err(format!(
                "{name} must be a finite number of seconds > 0, got {v}"
            )));
        }
    }
    let request = LifeRequest {
        duty_toml,
        jobs,
        retry_failed,
        settings: chaindrive::lab::LifeSettings {
            duration_s: duration,
            window_s: window,
            checkpoint_every_s: checkpoint_every,
        },
    };
    let scene = &scene.get().inner;
    let mut watch = Watch::new(progress, Duration::from_millis(100));
    let out = py.detach(|| bridge_studies::life(scene, &request, &dir, &mut watch));
    watch.raised(py)?;
    let out = match out {
        Ok(o) => o,
        Err(StudyFailure::Plan(m)) => return Err(StudyError::new_err(m)),
        Err(StudyFailure::Other(m)) => return Err(PyOSError::new_err(m)),
    };
    let d = PyDict::new(py);
    match &out.life {
        Some(v) => d.set_item("life", json_to_py(py, v)?)?,
        None => d.set_item("life", py.None())?,
    }
    d.set_item("interrupted", out.interrupted)?;
    d.set_item("points", out.points)?;
    d.set_item("pending", out.pending)?;
    Ok(d)
}

/// Adds this module's functions and exception.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(study, m)?)?;
    m.add_function(wrap_pyfunction!(life, m)?)?;
    m.add_function(wrap_pyfunction!(rate, m)?)?;
    m.add_function(wrap_pyfunction!(chains, m)?)?;
    m.add_function(wrap_pyfunction!(_to_toml, m)?)?;
    Ok(())
}
