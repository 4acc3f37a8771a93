//! A second evaluation of the contact at the positions of the last one, with
//! other velocities (velocity Verlet evaluates the forces at the new
//! positions with predicted velocities, then again with the corrected
//! ones).
//!
//! What depends on the positions alone is kept from the first ([`Kept`]):
//! the runs, each touching roller's lever, each patch's world normal and
//! elastic part K δⁿ, its onset in the contact memory (remembered χ/δ̇⁻, or
//! a new onset, whose χ/δ̇⁻ follows the approach speed), the stored energy
//! and the deepest penetration. The second evaluation computes again only
//! the approach speeds, the new onsets' χ/δ̇⁻ (in the advanced memory), the
//! forces and their sums — the same operations in the same order as the
//! passes ([`super::pass`], [`super::seats`]), so the same bits (test
//! `second_evaluation_at_the_same_positions_changes_no_bit`). The reach sets are measured again: the masks, and
//! so the runs, are a function of the positions and the committed sets, but
//! the kept sets' expiry follows the fastest roller's speed.
//!
//! Not for damping rows (the implicit schemes evaluate once per step).

use super::ToothContact;
use super::reach::shared_stretches;
use crate::forces::{ForceElement, Forces};
use crate::model::{DriveModel, DriveState};

/// One patch as an evaluation found it, in the order it was added.
#[derive(Clone, Copy, Debug)]
pub(super) struct Touch {
    pub(super) roller: u32,
    /// The roller's patches on this sprocket (1 or 2; the same on each).
    pub(super) patches: u8,
    /// Its entry in the roller's advanced memory (`MAX_PATCHES`: none).
    pub(super) slot: u8,
    /// A new onset: χ/δ̇⁻ follows the approach speed.
    pub(super) new: bool,
    /// Roller centre from the sprocket's centre, m.
    pub(super) lever: [f64; 2],
    /// World unit normal, the direction of the force on the roller.
    pub(super) normal: [f64; 2],
    /// K δⁿ, N.
    pub(super) elastic: f64,
    /// χ/δ̇⁻ remembered (read where `new` is false), s/m.
    pub(super) damping: f64,
}

/// What the last evaluation kept for one at the same positions.
#[derive(Clone, Debug, Default)]
pub(super) struct Kept {
    /// Every patch, run by run, roller by roller.
    pub(super) touches: Vec<Touch>,
    /// Where each run's patches end in `touches`.
    pub(super) run_ends: Vec<u32>,
    /// The contact's stored energy, J, and deepest penetration, m.
    pub(super) energy_j: f64,
    pub(super) max_penetration_m: f64,
    /// Whether the last evaluation kept them (else another evaluation, or
    /// a forgotten or restored history, came after).
    pub(super) valid: bool,
}

impl Kept {
    /// Room for a chain of `rollers` rollers, two patches each on two
    /// sprockets: the step loop does not allocate.
    pub(super) fn reserve(&mut self, rollers: usize) {
        self.touches
            .reserve((4 * rollers).saturating_sub(self.touches.len()));
        self.run_ends
            .reserve((2 * rollers + 64).saturating_sub(self.run_ends.len()));
    }
}

impl ToothContact {
    /// The contact at `state`, whose positions (rollers and sprocket angles)
    /// are those of the last evaluation: only what depends on the
    /// velocities is computed again (module docs). Without a kept
    /// evaluation, the whole one.
    pub(crate) fn evaluate_again(
        &mut self,
        model: &DriveModel,
        state: &DriveState,
        out: &mut Forces,
    ) {
        if !self.kept.valid || self.damping_rows.is_some() {
            return self.evaluate(model, state, out);
        }
        let centres = model.moving_centres_speed_m_s();
        let cull = self.culling.map(|c| {
            (
                c.speed_factor * out.max_roller_speed_m_s
                    + c.speed_floor_m_s
                    + centres.unwrap_or(0.0),
                c.max_skip_s,
            )
        });
        self.reach.measure(model, state, cull);
        debug_assert_eq!(self.reach.runs.len(), self.kept.run_ends.len());
        if centres.is_some() {
            self.replay::<true>(model, state, out);
        } else {
            self.replay::<false>(model, state, out);
        }
    }

    /// [`Self::evaluate_again`]'s forces, compiled per moving centres.
    fn replay<const MOVING: bool>(&mut self, model: &DriveModel, s: &DriveState, out: &mut Forces) {
        let law = self.law;
        let kept = &self.kept;
        for range in shared_stretches(&self.reach.runs) {
            self.contact_sum[range].fill([0.0; 2]);
        }
        let n = s.x.len();
        let (vxs, vys) = (&s.vx[..n], &s.vy[..n]);
        let (fx_out, fy_out) = (&mut out.fx[..n], &mut out.fy[..n]);
        let contact_force = &mut out.contact_force[..n];
        let pending = &mut self.pending_memory[..n];
        let sums = &mut self.contact_sum[..n];
        let mut damping_power_w = 0.0;
        let mut t = 0;
        for (run, &end) in self.reach.runs.iter().zip(&kept.run_ends) {
            let j = run.sprocket;
            let omega = s.omega[j];
            let velocity = model.sprockets[j].center_velocity_m_s;
            let mut force = [0.0; 2];
            let mut torque = 0.0;
            let mut damping_power = 0.0;
            let touches = &kept.touches[t..end as usize];
            t = end as usize;
            let mut k = 0;
            while let Some(first) = touches.get(k) {
                let i = first.roller as usize;
                let count = usize::from(first.patches);
                let [rx, ry] = first.lever;
                let v_rel = if MOVING {
                    [
                        vxs[i] - velocity[0] + omega * ry,
                        vys[i] - velocity[1] - omega * rx,
                    ]
                } else {
                    [vxs[i] + omega * ry, vys[i] - omega * rx]
                };
                let mut total = if run.shared { sums[i] } else { [0.0; 2] };
                let mut last_force = 0.0;
                for p in &touches[k..(k + count).min(touches.len())] {
                    let [nx, ny] = p.normal;
                    let depth_rate = -(v_rel[0] * nx + v_rel[1] * ny);
                    let damping = if p.new {
                        let d = law.damping_per_speed(depth_rate);
                        if let Some(m) = pending[i].get_mut(usize::from(p.slot)) {
                            m.damping_per_speed = d;
                        }
                        d
                    } else {
                        p.damping
                    };
                    let elastic = p.elastic;
                    let f = (elastic * (1.0 + damping * depth_rate)).max(0.0);
                    damping_power -= (f - elastic) * depth_rate;
                    last_force = f;
                    let (fx, fy) = (f * nx, f * ny);
                    total[0] += fx;
                    total[1] += fy;
                    force[0] -= fx;
                    force[1] -= fy;
                    torque -= rx * fy - ry * fx;
                }
                if run.shared {
                    sums[i] = total;
                } else {
                    fx_out[i] += total[0];
                    fy_out[i] += total[1];
                    contact_force[i] = if count == 1 {
                        last_force
                    } else {
                        (total[0] * total[0] + total[1] * total[1]).sqrt()
                    };
                }
                k += count.max(1);
            }
            damping_power_w += damping_power;
            let total = &mut out.chain_force[j];
            total[0] += force[0];
            total[1] += force[1];
            out.chain_torque[j] += torque;
        }
        out.max_penetration_m = kept.max_penetration_m;
        out.contact_energy_j = kept.energy_j;
        out.contact_damping_power_w = damping_power_w;
        // Rollers within reach of several sprockets, as the pass finishes
        // them (which of them touch is a matter of positions: kept).
        for range in shared_stretches(&self.reach.runs) {
            for i in range {
                let [sx, sy] = self.contact_sum[i];
                out.fx[i] += sx;
                out.fy[i] += sy;
                out.contact_force[i] = if self.patches_used[i] > 0 {
                    (sx * sx + sy * sy).sqrt()
                } else {
                    0.0
                };
            }
        }
    }
}
