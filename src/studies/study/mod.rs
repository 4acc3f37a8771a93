//! Design studies: many runs of one scene with some of its values changed,
//! laid out by a plan ([`plan`]), run here or as a Slurm job array
//! ([`cases`]), and merged into one table ([`table`]).
//!
//! The files in the study's directory are the only coordination between
//! the runs, so a study runs the same on one machine and on a cluster with
//! a shared file system:
//!
//! ```text
//! DIR/plan.toml         the plan, as given
//! DIR/scene.toml        the base scene, as read
//! DIR/cases/<k>/        one per finished case (k from 0), written aside and
//!                       renamed into place: scene.toml, summary.json
//!                       (when the run finished), status.json (with the
//!                       summary's warnings); while a checkpointed case
//!                       runs, only checkpoint.ckpt
//! DIR/results.parquet   `collect`: one row per case (factors, responses,
//!                       flags, status: ok, warned, failed or missing)
//! DIR/results.csv
//! DIR/main_effects/     `collect`: a main-effects figure per response
//! ```
//!
//! A case whose `status.json` exists is finished (ok or failed) and is not
//! run again, except a failed one when asked; an interrupted case runs
//! again, from its checkpoint when the plan asks for checkpoints
//! (`checkpoint_every_s`), else from the start. This module does not schedule anything across
//! machines: that is Slurm's job (`chaindrive study slurm`).

pub(crate) mod cases;
mod design;
mod file;
pub(crate) mod plan;
pub(crate) mod table;

pub(crate) use cases::{CaseOutcome, CaseStatus, StudyDir};
pub(crate) use plan::{Responses, Study};
#[cfg(test)]
pub(crate) use table::ColumnData;
pub(crate) use table::{RowStatus, Table};

/// Why a study could not be prepared, run or collected.
#[derive(Clone, Debug, thiserror::Error)]
pub enum StudyError {
    /// The plan is invalid: one `path: message` line per problem.
    #[error("invalid plan:\n{}", .0.join("\n"))]
    Plan(Vec<String>),
    /// Cases whose scene is invalid, each with its factor values.
    #[error("cases that cannot be built (nothing was run):\n{}", .0.join("\n"))]
    Cases(Vec<String>),
    /// No such case.
    #[error("no case {k}: the study has {count} cases (0 to {})", .count.saturating_sub(1))]
    NoCase {
        /// The case asked for.
        k: usize,
        /// Cases in the study.
        count: usize,
    },
    /// The directory holds another study.
    #[error("{dir} holds another study ({what} differs); use another directory or remove it")]
    Another {
        /// The directory.
        dir: String,
        /// Which file differs.
        what: String,
    },
    /// A response no finished case has.
    #[error("responses[{index}]: no finished case has `{name}`; allowed: {allowed}")]
    UnknownResponse {
        /// Position in the plan's list.
        index: usize,
        /// The field.
        name: String,
        /// The summary's numeric fields.
        allowed: String,
    },
    /// The results table could not be written as CSV.
    #[error("writing CSV: {0}")]
    Csv(String),
    /// Reading or writing a file failed.
    #[error("{path}: {message}")]
    Io {
        /// The file.
        path: String,
        /// Why.
        message: String,
    },
}

impl StudyError {
    pub(crate) fn io(path: &std::path::Path, e: impl std::fmt::Display) -> Self {
        Self::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        }
    }
}
