//! `chaindrive._chaindrive`: the native part of the `chaindrive` Python
//! package. Thin: it mirrors the Rust names and adds no physics. Every call
//! into the chaindrive library goes through [`bridge`] (scenes, runs,
//! checkpoints, recordings) or [`bridge_studies`] (check, sweep, study,
//! rating); the rest converts to and from Python.

mod bridge;
mod bridge_studies;
mod convert;
mod run;
mod scene;
mod studies;
mod watch;

use pyo3::prelude::*;

#[pymodule]
fn _chaindrive(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<scene::PyScene>()?;
    m.add("SceneError", py.get_type::<scene::SceneError>())?;
    m.add("SimError", py.get_type::<run::SimError>())?;
    m.add("StudyError", py.get_type::<studies::StudyError>())?;
    m.add_function(wrap_pyfunction!(run::run, m)?)?;
    studies::register(m)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
