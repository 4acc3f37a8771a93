//! What can go wrong when a drive lives in a user's world.

use crate::sim::SimError;

/// An error of a co-simulated drive: the scene's own (it cannot be built,
/// no equilibrium, a blow-up), or a use of the drive its world does not
/// allow (a bad mount, a bad step, a world stepped without the drive).
#[derive(Debug, thiserror::Error)]
pub enum CosimError {
    /// The scene cannot be built, has no equilibrium, or the chain blew up
    /// (a co-simulation's blow-up names the coupling's limit in its detail).
    #[error(transparent)]
    Sim(#[from] SimError),
    /// An argument the drive cannot use: `field` names it (`mounts[1]`,
    /// `dt_s`, a scene field such as `sprockets[1].center_m`), `message` what
    /// it was and what is allowed.
    #[error("{field}: {message}")]
    Input {
        /// The argument or scene field.
        field: String,
        /// What it was and what is allowed.
        message: String,
    },
    /// The world's step did not do what the drive set it up for.
    #[error("the world's step and the drive disagree: {0}")]
    World(String),
}

impl CosimError {
    pub(super) fn input(field: impl Into<String>, message: impl Into<String>) -> Self {
        Self::Input {
            field: field.into(),
            message: message.into(),
        }
    }
}

/// What limits a co-simulation when its chain blows up. A smaller
/// `solver.dt_s` does not lift it: the chain's substeps already resolve the
/// chain; what they do not resolve is what acts once per world frame.
pub(super) fn coupling_causes(frame_dt_s: f64) -> String {
    format!(
        "the coupling's limit, which a smaller solver.dt_s does not lift: a mounted body's \
         joints, the user's force on it (held over the frame) and carried bodies' contacts with \
         each other act once per world frame (here {frame_dt_s:.3e} s) against the chain's \
         stiffness, so a mount tied by a joint to a light body (a hub on a carriage), a stiff \
         spring force set each frame or a stack of carried bodies can blow up; make that body \
         heavier, step the world \
         at a smaller dt, or let one body touch the chain; if the scene blows up on its own too \
         (`chaindrive run`), its own step or contact is the cause"
    )
}

/// `e` with its possible causes replaced by the coupling's limit (a blow-up's
/// history, if any, is kept).
pub(super) fn at_coupling_limit(e: SimError, frame_dt_s: f64) -> CosimError {
    match e {
        SimError::BlowUp {
            t_s,
            detector,
            body,
            value,
            limit,
            detail,
        } => {
            let history = detail
                .split_once("; possible causes:")
                .map_or(detail.as_str(), |(h, _)| h);
            CosimError::Sim(SimError::BlowUp {
                t_s,
                detector,
                body,
                value,
                limit,
                detail: format!(
                    "{history}; possible causes: {}",
                    coupling_causes(frame_dt_s)
                ),
            })
        }
        other => CosimError::Sim(other),
    }
}
