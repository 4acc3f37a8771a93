//! `chaindrive.Scene` and `chaindrive.SceneError`.

use std::path::PathBuf;

use pyo3::exceptions::{PyOSError, PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::bridge::{self, LoadError, Scene, SceneFailure};
use crate::convert::{json_to_py, py_to_toml};

pyo3::create_exception!(
    chaindrive,
    SceneError,
    PyValueError,
    "A scene (or a run's setting of one) is invalid.\n\n\
     The message is the command line's: one line per problem, each naming the\n\
     field's path in the scene file (with the file's name, line and column where\n\
     known) and what is allowed. Attributes: `path` (the first problem's field\n\
     path, e.g. 'sprockets[2].teeth'; '' for a TOML syntax error), `paths` (every\n\
     problem's), `problems` (a list of dicts: path, message, line, column)."
);

/// A [`SceneFailure`] as a `SceneError` carrying its paths.
pub(crate) fn scene_error(py: Python<'_>, failure: SceneFailure) -> PyErr {
    let err = SceneError::new_err(failure.message.clone());
    let attach = || -> PyResult<()> {
        let value = err.value(py);
        let first = failure
            .problems
            .first()
            .map_or(String::new(), |p| p.path.clone());
        value.setattr("path", first)?;
        let paths: Vec<String> = failure.problems.iter().map(|p| p.path.clone()).collect();
        value.setattr("paths", paths)?;
        let problems = PyList::empty(py);
        for p in &failure.problems {
            let d = PyDict::new(py);
            d.set_item("path", &p.path)?;
            d.set_item("message", &p.message)?;
            d.set_item("line", p.location.map(|l| l.0))?;
            d.set_item("column", p.location.map(|l| l.1))?;
            problems.append(d)?;
        }
        value.setattr("problems", problems)
    };
    match attach() {
        Ok(()) => err,
        Err(e) => e,
    }
}

/// A chain drive, valid by construction (the Rust `chaindrive::scene::Scene`).
///
/// Build one with `Scene.from_file(path)`, `Scene.from_toml(text)` or
/// `Scene.l60mc()` (the paper's drive); derive others with
/// `scene.with_({"sprockets.0.speed_rpm": 600})`. Every constructor
/// validates: a bad scene raises `SceneError`. A scene is immutable.
#[pyclass(frozen, name = "Scene", module = "chaindrive")]
pub(crate) struct PyScene {
    pub(crate) inner: Scene,
}

#[pymethods]
impl PyScene {
    /// Reads and validates the TOML scene file at `path` (files it names,
    /// such as a load table, are read beside it).
    ///
    /// Raises `SceneError` (with the file's name, line and column) for an
    /// invalid scene, `OSError` for a file that cannot be read.
    #[staticmethod]
    fn from_file(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        match bridge::scene_from_file(&path) {
            Ok(inner) => Ok(Self { inner }),
            Err(LoadError::Io(m)) => Err(PyOSError::new_err(m)),
            Err(LoadError::Scene(f)) => Err(scene_error(py, f)),
        }
    }

    /// Parses and validates a TOML scene given as text (relative file names
    /// in it are read from the working directory).
    ///
    /// Raises `SceneError` (with line and column) for an invalid scene.
    #[staticmethod]
    fn from_toml(py: Python<'_>, text: &str) -> PyResult<Self> {
        bridge::scene_from_toml(text)
            .map(|inner| Self { inner })
            .map_err(|f| scene_error(py, f))
    }

    /// The paper's drive: the MAN B&W L60MC camshaft chain of Pedersen (2005),
    /// four sprockets, 122 rollers, 21 kN pretension, 120 rpm after a 1 s
    /// ramp, 10 s (the embedded `assets/l60mc.toml`).
    #[staticmethod]
    fn l60mc() -> Self {
        Self {
            inner: bridge::paper(),
        }
    }

    /// This scene with values changed by their dotted paths in the scene
    /// file, as a study plan's factors and the command line's `--set` name
    /// them: `scene.with_({"sprockets.0.speed_rpm": 600})` or
    /// `scene.with_(**{"chain.pretension_n": 18e3})`. Indices count from 0
    /// (`sprockets.2.teeth` or `sprockets[2].teeth`); values are bool, int,
    /// float, str or lists of them. The result is validated like a file.
    ///
    /// Raises `SceneError` naming the path for an unknown field, a value of
    /// the wrong type or an invalid value.
    #[pyo3(signature = (values=None, /, **more))]
    fn with_(
        &self,
        py: Python<'_>,
        values: Option<&Bound<'_, PyDict>>,
        more: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let mut assignments = Vec::new();
        for dict in [values, more].into_iter().flatten() {
            for (k, v) in dict.iter() {
                let path: String = k.extract().map_err(|_| {
                    PyTypeError::new_err(format!("a path {k} that is not a string"))
                })?;
                let value = py_to_toml(&v, &path)?;
                assignments.push((path, value));
            }
        }
        bridge::scene_with(&self.inner, &assignments)
            .map(|inner| Self { inner })
            .map_err(|f| scene_error(py, f))
    }

    /// This scene with its chain named by a designation (`"ISO 606 16B-1"`,
    /// `"ANSI 80"`, any spelling; `chaindrive.chains()` lists them): the
    /// table's pitch, roller radius, roller mass, stiffness and pin radius
    /// replace those written in the scene. Meant for a drive laid out for a
    /// chain of that pitch (ISO 606 16B and ANSI 80 share 25.4 mm).
    ///
    /// Raises `SceneError` (`chain.designation`) for an unknown name.
    fn with_designation(&self, py: Python<'_>, designation: &str) -> PyResult<Self> {
        bridge::scene_with_designation(&self.inner, designation)
            .map(|inner| Self { inner })
            .map_err(|f| scene_error(py, f))
    }

    /// The scene file as TOML, every value that was changed included; it
    /// reads back as the same scene (`Scene.from_toml(scene.to_toml())`).
    fn to_toml(&self) -> PyResult<String> {
        bridge::scene_toml(&self.inner).map_err(PyRuntimeError::new_err)
    }

    /// The scene file as a dict (the same fields as `to_toml()`).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let json = bridge::scene_json(&self.inner).map_err(PyRuntimeError::new_err)?;
        json_to_py(py, &json)
    }

    /// What is valid but likely unintended (a step above the integrator's
    /// stability limit, guides the chain does not reach), a sentence each.
    fn warnings(&self) -> Vec<String> {
        bridge::scene_warnings(&self.inner)
    }

    /// The scene's name.
    #[getter]
    fn name(&self) -> String {
        bridge::scene_name(&self.inner).to_owned()
    }

    fn __repr__(&self) -> String {
        format!("Scene({:?})", bridge::scene_name(&self.inner))
    }

    /// Scenes are equal when their scene files are (`to_dict()` equal, and
    /// the same directory for the files they name).
    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<PyScene>()
            .is_ok_and(|o| bridge::same_scene(&o.get().inner, &self.inner))
    }
}
