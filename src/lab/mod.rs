//! The lab (feature `lab`): what a front end other than the command line
//! needs to run the tool's experiments and design checks itself — the
//! Python bindings are one.
//!
//! The prelude's names run one drive; these drive many runs and read them
//! as a designer does:
//!
//! - **A scene changed by dotted path**, as a study plan's factors change
//!   it ([`Scene::with_set`](crate::scene::Scene::with_set) with
//!   [`crate::scene::Assignment`]s); the step's one-line report ([`step_note`]).
//! - **A scene checked**: laid out and brought to static equilibrium, as
//!   `chaindrive check` reports it ([`check_report`]).
//! - **Checkpoints**: a [`Simulation`](crate::sim::Simulation)'s
//!   [`Snapshot`](crate::sim::Snapshot) (`snapshot`, `restore`) in a [`Checkpoint`] file with the
//!   caller's own part ([`write_checkpoint`], [`read_checkpoint`]), and where
//!   the next one falls ([`next_checkpoint_s`], [`run_is_done`]).
//! - **The catalogue rating** of a scene's chain ([`rate`], [`Rating`]) and
//!   the table of chains ([`DESIGNATIONS`], [`find_designation`]).
//! - **The speed sweep** ([`run_sweep`]: one steady run per speed, in
//!   parallel, with order spectra and each span's natural frequencies) and
//!   what its tables are made of ([`summary_scalars`], [`CaseFlags`]).
//! - **Design studies** ([`Study`] from a plan, run in a [`StudyDir`],
//!   collected into a [`StudyTable`]), and the chain's life over a duty
//!   cycle ([`DutyCycle`]: its points run as a study, [`combine_duty`]
//!   combines them by hours into a [`DutyLife`]).
//!
//! What the lab does not do: write the command line's files, draw its
//! figures or parse its option syntax; a front end formats what it gets.
//! Every item here is also what `chaindrive` itself calls, so the two front
//! ends cannot drift apart.

mod check;

pub use check::check_report;

pub use crate::analysis::design::life::Life;
pub use crate::analysis::design::rating::{
    ChainClass, Lubrication, Rating, RatingError, RatingSettings, of_scene as rate,
};
pub use crate::analysis::orders::{OrderComponent, OrderError, OrderSet, OrderSpectrum};
pub use crate::scene::designations::{
    DESIGNATIONS, Designation, Sources as DesignationSources, Stranded as StrandedDesignation,
    find as find_designation, lookup as lookup_designation, nearest as nearest_designations,
};
pub use crate::scene::stability::step_note;
pub use crate::sim::checkpoint::{
    Checkpoint, next_checkpoint_s, read_checkpoint, run_is_done, write_checkpoint,
};
pub use crate::studies::duty::combine::{
    DutyLife, LimitLife, PointResult, combine as combine_duty,
};
pub use crate::studies::duty::{DutyCycle, DutyError, DutyPoint, LifeSettings};
pub use crate::studies::study::StudyError;
pub use crate::studies::study::cases::{CaseOutcome as StudyCaseOutcome, CaseStatus, StudyDir};
pub use crate::studies::study::plan::Study;
pub use crate::studies::study::table::{Column as TableColumn, ColumnData, Table as StudyTable};
pub use crate::studies::sweep::report::{CaseFlags, completed, summary_scalars};
pub use crate::studies::sweep::{
    CaseOutcome, CaseResult, SignalOrders, SpanFrequencies, SweepError, SweepSettings,
    TRANSVERSE_MODES, default_orders, run_sweep,
};
