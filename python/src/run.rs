//! The native `run`: a scene simulated with the GIL released, the caller's
//! Ctrl-C and progress callback looked at every `poll_s` of wall time.
//! `chaindrive.run` (Python) wraps it: the result object, `KeyboardInterrupt`
//! with the partial result, a tqdm bar.

use std::path::PathBuf;
use std::time::Duration;

use pyo3::exceptions::{PyKeyboardInterrupt, PyOSError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::bridge::{self, RunError, RunOutput, RunSettings};
use crate::convert::{json_to_py, matrix, vector};
use crate::scene::{PyScene, scene_error};
use crate::watch::Watch;

pyo3::create_exception!(
    chaindrive,
    SimError,
    pyo3::exceptions::PyRuntimeError,
    "The simulation could not start (no layout, no static equilibrium) or\n\
     blew up; the message names the time, the body, the detector and the\n\
     possible causes, as the command line prints it."
);

/// A step in seconds, `"auto"` or `"speed"`: `(seconds, auto, speed)`.
fn dt_setting(dt: Option<&Bound<'_, PyAny>>) -> PyResult<(Option<f64>, bool, bool)> {
    const ALLOWED: &str = "a step in seconds (e.g. 1e-5), \"auto\" or \"speed\"";
    let Some(dt) = dt else {
        return Ok((None, false, false));
    };
    if let Ok(s) = dt.extract::<String>() {
        if s.eq_ignore_ascii_case("auto") {
            return Ok((None, true, false));
        }
        if s.eq_ignore_ascii_case("speed") {
            return Ok((None, false, true));
        }
        return Err(PyValueError::new_err(format!("dt {s:?}: {ALLOWED}")));
    }
    dt.extract::<f64>()
        .map(|s| (Some(s), false, false))
        .map_err(|_| PyTypeError::new_err(format!("dt: {ALLOWED}")))
}

/// Runs `scene` and returns `(summary, series, interrupted)` (the Python
/// wrapper's documentation is the user's).
#[pyfunction]
#[pyo3(signature = (
    scene, *, duration=None, window=None, rate=1000.0, integrator=None, profile=None,
    dt=None, stepping=None, series=true, record=None, record_channels="all",
    checkpoint=None, checkpoint_every=None, resume=None, progress=None, poll_s=0.1
))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn run<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyScene>,
    duration: Option<f64>,
    window: Option<f64>,
    rate: f64,
    integrator: Option<String>,
    profile: Option<String>,
    dt: Option<&Bound<'py, PyAny>>,
    stepping: Option<String>,
    series: bool,
    record: Option<PathBuf>,
    record_channels: &str,
    checkpoint: Option<PathBuf>,
    checkpoint_every: Option<f64>,
    resume: Option<PathBuf>,
    progress: Option<Py<PyAny>>,
    poll_s: f64,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyDict>, bool)> {
    let (dt_s, dt_auto, dt_speed) = dt_setting(dt)?;
    if checkpoint.is_some() != checkpoint_every.is_some() {
        return Err(PyValueError::new_err(
            "checkpoint and checkpoint_every go together: a file and the simulated seconds between checkpoints",
        ));
    }
    let settings = RunSettings {
        duration_s: duration,
        window_s: window,
        rate_hz: rate,
        integrator,
        profile,
        dt_s,
        dt_auto,
        dt_speed,
        stepping,
        keep_series: series,
        record,
        record_channels: record_channels.to_owned(),
        checkpoint,
        checkpoint_every_s: checkpoint_every,
        resume,
    };
    let every_s = if poll_s.is_finite() {
        poll_s.max(0.0)
    } else {
        0.1
    };
    let mut hooks = Watch::new(progress, Duration::from_secs_f64(every_s));
    let scene = &scene.get().inner;
    let result = py.detach(|| bridge::run(scene, &settings, &mut hooks));
    let mut output = result.map_err(|e| run_error(py, e))?;
    // A Ctrl-C after the last look: the run is whole, but the caller asked to stop.
    if hooks.error.is_none()
        && let Err(e) = py.check_signals()
    {
        hooks.error = Some(e);
    }
    match hooks.error {
        Some(e) if !e.is_instance_of::<PyKeyboardInterrupt>(py) => Err(e),
        Some(_) => {
            output.interrupted = true;
            output_to_py(py, output)
        }
        None => output_to_py(py, output),
    }
}

/// A run's error as its Python exception.
pub(crate) fn run_error(py: Python<'_>, e: RunError) -> PyErr {
    match e {
        RunError::Scene(f) => scene_error(py, f),
        RunError::Setting(m) => PyValueError::new_err(m),
        RunError::Io(m) => PyOSError::new_err(m),
        RunError::Sim(m) => SimError::new_err(m),
    }
}

/// The summary as plain data and the series as NumPy arrays (each owns
/// its vector: no copy).
fn output_to_py(
    py: Python<'_>,
    output: RunOutput,
) -> PyResult<(Bound<'_, PyAny>, Bound<'_, PyDict>, bool)> {
    let summary = json_to_py(py, &output.summary)?;
    let s = output.series;
    let series = PyDict::new(py);
    series.set_item("t_s", vector(py, s.t_s))?;
    series.set_item("omega_rad_s", matrix(py, s.omega_rad_s, s.sprockets)?)?;
    series.set_item(
        "chain_torque_n_m",
        matrix(py, s.chain_torque_n_m, s.sprockets)?,
    )?;
    series.set_item(
        "segment_force_n",
        matrix(py, s.segment_force_n, s.segments)?,
    )?;
    series.set_item("transverse_m", matrix(py, s.transverse_m, s.segments)?)?;
    Ok((summary, series, output.interrupted))
}
