//! Which roller counts a drive accepts as it stands: the counts nearest the
//! path's need, each tried through the layout and the feasibility checks
//! (rest-length and tensioner-preload rules) or the tensioner's fit
//! (tensioner rule). `chaindrive check` lists them; nothing here steps the
//! chain or changes the scene.

use super::fit::{arm_take_up_of, default_direction, fit_sprocket, needed_pitches_of};
use crate::scene::Scene;

/// Whether a roller count fits the drive as it stands, and if not, why.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct CountVerdict {
    /// The roller count.
    pub rollers: usize,
    /// `None`: it fits; else why not (a sentence).
    pub refused: Option<String>,
}

/// The roller counts nearest the path's need, each with whether the drive
/// accepts it as it stands, nearest the need first: a count is accepted
/// when the layout lays it out and, under the rest-length and the
/// tensioner-preload rules, the pretension, the strands' sag or the
/// tensioner arms take up its misfit (`feasibility::check_chain_length`);
/// under the tensioner rule, when the tensioner's travel makes it fit.
/// Tried: the two counts either side of the need, and those the arms'
/// take-up reaches. Empty when the path has no need (no layout).
pub(crate) fn count_verdicts(scene: &Scene) -> Vec<CountVerdict> {
    let Ok(needed) = needed_pitches_of(scene) else {
        return Vec::new();
    };
    let pitch = scene.chain.pitch_m;
    let reach = arm_take_up_of(scene).map_or(0.0, |t| t.max_m / pitch);
    let mut candidates: Vec<usize> =
        (needed.floor().max(4.0) as usize..=(needed + reach).ceil().max(4.0) as usize).collect();
    candidates.sort_by(|a, b| {
        (*a as f64 - needed)
            .abs()
            .total_cmp(&(*b as f64 - needed).abs())
    });
    candidates
        .into_iter()
        .map(|n| CountVerdict {
            rollers: n,
            refused: count_refused(scene, n).err(),
        })
        .collect()
}

/// Why `scene` with `n` rollers does not fit as it stands (see
/// [`count_verdicts`]).
fn count_refused(scene: &Scene, n: usize) -> Result<(), String> {
    let mut s = scene.clone();
    s.chain.rollers = n;
    match s.chain.pretension_by {
        crate::scene::PretensionRule::Tensioner => {
            let t = s.tensioner().ok_or("no sprocket is a tensioner")?;
            let d = default_direction(&s, t).ok_or("the tensioner has no direction to move in")?;
            fit_sprocket(&s, t, d, n)
                .map(|_| ())
                .map_err(|e| e.to_string())
        }
        // The arms' preload: links at their rest length, as the rest-length rule lays them.
        crate::scene::PretensionRule::RestLength
        | crate::scene::PretensionRule::TensionerPreload => {
            let (model, _, layout) = crate::model::DriveModel::build(&s).map_err(|e| match e {
                crate::model::BuildError::Layout(crate::geometry::LayoutError::ChainLength {
                    needed,
                    which,
                    arms,
                    ..
                }) => format!(
                    "{which} by {:.2} pitches, more than the half pitch its free links take up{}",
                    (needed - n as f64).abs(),
                    arms.map(|a| a.to_string()).unwrap_or_default()
                ),
                e => e.to_string(),
            })?;
            super::feasibility::check_chain_length(&s, &layout, &model.path)
                .map_err(|e| e.to_string())
        }
    }
}

/// The roller counts the drive accepts as it stands, nearest the path's
/// need first ([`count_verdicts`]). Empty when none is accepted (then only
/// a move fits).
#[cfg(test)]
pub(crate) fn fitting_counts(scene: &Scene) -> Vec<usize> {
    count_verdicts(scene)
        .into_iter()
        .filter(|v| v.refused.is_none())
        .map(|v| v.rollers)
        .collect()
}
