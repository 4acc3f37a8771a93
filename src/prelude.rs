//! The front door: what a user of the library needs, in one `use`.
//!
//! ```
//! use chaindrive::prelude::*;
//! ```
//!
//! brings in a scene and the ways to change it ([`Scene`], [`SceneBuilder`],
//! [`Overrides`]), a run of the drive on its own ([`Simulation`] with its
//! [`SampleRate`], the [`Observer`]s that watch it, the [`Signals`] they
//! collect, the [`StatsWindow`] and the [`RunSummary`] of the run), the drive
//! inside your own rapier world ([`ChainDrive`], its [`ChainDriveBuilder`]
//! and [`Coupling`]), the recorder ([`Recorder`], feature `record`) and the
//! errors each of these returns.
//!
//! The second group is the extension seam: a force element of your own
//! ([`ForceElement`]) reads the [`DriveModel`] and the [`DriveState`] and adds
//! to the [`Forces`]; further bodies and scalar states ([`BodyModel`],
//! [`ScalarModel`]) join a [`Simulation`] through [`Simulation::add_body`],
//! [`Simulation::add_scalar`] and [`Simulation::add_force_element`]; an element with history keeps it across a
//! checkpoint through [`History`] and [`HistoryReader`].
//!
//! What is not here lives in the module that owns it: the scene's parts
//! ([`crate::scene`]), the observers' and the run's data ([`crate::sim`],
//! [`crate::analysis`]), the co-simulation's details ([`crate::cosim`]) and
//! the recording's options ([`crate::record`]).

pub use crate::analysis::{RunSummary, Signals, StatsWindow, WindowError};
pub use crate::cosim::{ChainDrive, ChainDriveBuilder, CosimError, Coupling, SprocketId};
#[cfg(feature = "record")]
pub use crate::record::{Channels, RecordError, RecordOptions, Recorder, RunEnd};
pub use crate::scene::{Overrides, Scene, SceneBuilder, SceneError};
pub use crate::sim::{
    Observer, RunOutcome, Sample, SampleRate, SampleRateError, SimError, Simulation,
};

// The extension seam.
pub use crate::forces::{ForceElement, Forces, History, HistoryError, HistoryReader};
pub use crate::model::{BodyModel, DriveModel, DriveState, ScalarModel, SprocketModel};
