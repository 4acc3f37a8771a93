//! The caller's side of long work done with the GIL released: Ctrl-C (the
//! Python-level signal handlers) and the progress callback, looked at with
//! the GIL taken back at most every `every` of wall time. Runs, sweeps and
//! studies all use it.

use std::time::{Duration, Instant};

use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;

use crate::bridge::RunHooks;

pub(crate) struct Watch {
    progress: Option<Py<PyAny>>,
    every: Duration,
    last: Instant,
    /// What stopped the work: a `KeyboardInterrupt` (or whatever a signal
    /// handler raised), or the callback's exception.
    pub(crate) error: Option<PyErr>,
}

impl Watch {
    pub(crate) fn new(progress: Option<Py<PyAny>>, every: Duration) -> Self {
        Self {
            progress,
            every,
            last: Instant::now(),
            error: None,
        }
    }

    /// The callback's (or a signal handler's) exception, unless it is a
    /// `KeyboardInterrupt`: that one stops the work and the caller reports it.
    pub(crate) fn raised(self, py: Python<'_>) -> PyResult<()> {
        match self.error {
            Some(e) if !e.is_instance_of::<PyKeyboardInterrupt>(py) => Err(e),
            _ => Ok(()),
        }
    }
}

impl RunHooks for Watch {
    fn poll(&mut self, done: f64, total: f64) -> bool {
        if self.error.is_some() {
            return true;
        }
        if self.last.elapsed() < self.every {
            return false;
        }
        self.last = Instant::now();
        let result = Python::attach(|py| -> PyResult<()> {
            // Runs the Python-level signal handlers (SIGINT's raises
            // KeyboardInterrupt); only the main thread has any.
            py.check_signals()?;
            if let Some(callback) = &self.progress {
                callback.call1(py, (done, total))?;
            }
            Ok(())
        });
        result.map_err(|e| self.error = Some(e)).is_err()
    }
}
