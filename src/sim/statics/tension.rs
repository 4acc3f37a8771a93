//! The static tension: the mean link force of the free strands, which the
//! pretension rules aim at and the continuations measure.

use crate::forces::ForceGenerator;
use crate::model::{DriveModel, DriveState};

/// Mean link force over the links of all free strands, pooled; `None` if
/// there is no free link. `forces` must have been evaluated at `state`.
pub(crate) fn free_strand_tension(
    model: &DriveModel,
    state: &DriveState,
    forces: &ForceGenerator,
) -> Option<f64> {
    let out = forces.output();
    let runs = model
        .segments
        .runs(&model.sprockets, &state.x, &state.y, &out.touching);
    let (mut sum, mut count) = (0.0, 0usize);
    for k in 0..model.segments.len() {
        for i in runs.links(k) {
            sum += out.link_force[i];
            count += 1;
        }
    }
    (count > 0).then(|| sum / count as f64)
}
