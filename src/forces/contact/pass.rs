//! The contact pass: one loop per [`Run`] of rollers within reach of one
//! sprocket, with the sprocket's frame in registers, compiled once per
//! profile kind ([`Outline`]).

use super::super::rows::DampingRows;
use super::reach::Run;
use super::{EMPTY, FREE, Memory};
use crate::forces::ContactLawParams;
use crate::geometry::{MAX_PATCHES, Outline, Patch};
use crate::model::{DriveState, SprocketModel};

/// One sprocket's pose and speed, fixed for its contact pass.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Frame {
    index: usize,
    center: [f64; 2],
    /// Velocity of the centre (a moving mount), m/s.
    velocity: [f64; 2],
    sin: f64,
    cos: f64,
    omega: f64,
}

impl Frame {
    pub(super) fn of(sprocket: &SprocketModel, theta: f64, omega: f64, index: usize) -> Self {
        let (sin, cos) = theta.sin_cos();
        Self {
            index,
            center: sprocket.center_m,
            velocity: sprocket.center_velocity_m_s,
            sin,
            cos,
            omega,
        }
    }
}

/// The contact pass of one evaluation: what it reads and the per-roller
/// outputs it writes, shared by the runs' loops.
pub(super) struct ContactPass<'a> {
    pub(super) law: ContactLawParams,
    pub(super) state: &'a DriveState,
    /// The committed contact memory, current where `remembered` is not empty.
    pub(super) memory: &'a [[Memory; MAX_PATCHES]],
    /// Each roller's set of sprockets within reach at the committed evaluation.
    pub(super) remembered: &'a [u64],
    pub(super) pending_memory: &'a mut [[Memory; MAX_PATCHES]],
    pub(super) gap_hint: &'a mut [u32],
    pub(super) fx: &'a mut [f64],
    pub(super) fy: &'a mut [f64],
    pub(super) touching: &'a mut [bool],
    pub(super) contact_force: &'a mut [f64],
    /// Contact force on each roller of a shared run, summed over its runs, N.
    pub(super) sum: &'a mut [[f64; 2]],
    /// Patches found for each roller of a shared run (its entries in `pending_memory`).
    pub(super) used: &'a mut [u8],
    pub(super) rows: Option<&'a mut DampingRows>,
    pub(super) energy_j: f64,
    /// Power of the contact forces' damping parts, −Σ (f − K δⁿ) δ̇, W (≤ 0
    /// but for the ≥ 0 clamp, which only lowers it).
    pub(super) damping_power_w: f64,
    pub(super) max_penetration_m: f64,
}

impl ContactPass<'_> {
    /// Contacts of one run's rollers; returns the chain's resultant force and
    /// moment on its sprocket. A shared run adds to the rollers' sums (the
    /// caller finishes them); any other writes each roller's outputs.
    #[inline(always)]
    pub(super) fn run<const ROWS: bool, const SHARED: bool, const MOVING: bool, P: Outline>(
        &mut self,
        profile: &P,
        frame: &Frame,
        run: &Run,
    ) -> ([f64; 2], f64) {
        let law = self.law;
        let energy_factor = 1.0 / (law.exponent + 1.0);
        let (sin, cos, omega) = (frame.sin, frame.cos, frame.omega);
        let sprocket_key = (frame.index as u64) << 32;
        let (a, b) = (run.start, run.end);
        let s = self.state;
        let (xs, ys, vxs, vys) = (&s.x[a..b], &s.y[a..b], &s.vx[a..b], &s.vy[a..b]);
        let memory = &self.memory[a..b];
        let remembered = &self.remembered[a..b];
        let pending_memory = &mut self.pending_memory[a..b];
        let gap_hint = &mut self.gap_hint[a..b];
        let (fx_out, fy_out) = (&mut self.fx[a..b], &mut self.fy[a..b]);
        let touching = &mut self.touching[a..b];
        let contact_force = &mut self.contact_force[a..b];
        let (sums, used_by) = (&mut self.sum[a..b], &mut self.used[a..b]);
        let mut patches = [Patch::default(); MAX_PATCHES];
        let (mut force, mut torque) = ([0.0f64; 2], 0.0f64);
        let (mut energy, mut max_pen) = (0.0, self.max_penetration_m);
        let mut damping_power = 0.0;
        for k in 0..b - a {
            let rx = xs[k] - frame.center[0];
            let ry = ys[k] - frame.center[1];
            // World → sprocket frame: rotate by −θ.
            let local = [cos * rx + sin * ry, -sin * rx + cos * ry];
            let count = profile.contacts(local, &mut gap_hint[k], &mut patches);
            if count == 0 {
                if !SHARED {
                    pending_memory[k] = [FREE; MAX_PATCHES];
                }
                continue;
            }
            // Velocity of the roller relative to the sprocket point under it
            // (16)–(18), v − v_c − ω × r (v_c: a moving mount's centre).
            let (vrx, vry) = if MOVING {
                (
                    vxs[k] - frame.velocity[0] + omega * ry,
                    vys[k] - frame.velocity[1] - omega * rx,
                )
            } else {
                (vxs[k] + omega * ry, vys[k] - omega * rx)
            };
            // A roller that was within no reach circle at the committed
            // evaluation left its memory behind there.
            let onsets = if remembered[k] != 0 {
                memory[k]
            } else {
                [FREE; MAX_PATCHES]
            };
            let (mut next, mut used, mut total) = if SHARED {
                (pending_memory[k], usize::from(used_by[k]), sums[k])
            } else {
                ([FREE; MAX_PATCHES], 0, [0.0; 2])
            };
            // Implicit damping row: (C, C v_sp, elastic, explicit damping).
            let mut row = ([0.0f64; 3], [0.0f64; 2], [0.0f64; 2], [0.0f64; 2]);
            let mut last_force = 0.0;
            for p in &patches[..count] {
                // Normal back to the world frame.
                let nx = cos * p.normal[0] - sin * p.normal[1];
                let ny = sin * p.normal[0] + cos * p.normal[1];
                let depth_rate = -(vrx * nx + vry * ny);
                let key = sprocket_key | u64::from(p.patch_id);
                // The same patch, or (real profile) the one it slid over from.
                let damping = match onsets.iter().find(|mem| mem.key == key) {
                    Some(mem) => mem.damping_per_speed,
                    None => slid_from(profile, &onsets, frame.index, p.patch_id)
                        .unwrap_or_else(|| law.damping_per_speed(depth_rate)),
                };
                if used < MAX_PATCHES {
                    next[used] = Memory {
                        key,
                        damping_per_speed: damping,
                    };
                    used += 1;
                }
                let elastic = law.elastic(p.depth_m);
                let f = (elastic * (1.0 + damping * depth_rate)).max(0.0);
                energy += elastic * p.depth_m * energy_factor;
                damping_power -= (f - elastic) * depth_rate;
                if ROWS {
                    let c = elastic * damping;
                    // Surface velocity of the sprocket under the roller: v_c + ω × r.
                    let v_sp_n = if MOVING {
                        (frame.velocity[0] - omega * ry) * nx
                            + (frame.velocity[1] + omega * rx) * ny
                    } else {
                        -omega * ry * nx + omega * rx * ny
                    };
                    row.0[0] += c * nx * nx;
                    row.0[1] += c * nx * ny;
                    row.0[2] += c * ny * ny;
                    row.1[0] += c * v_sp_n * nx;
                    row.1[1] += c * v_sp_n * ny;
                    row.2[0] += elastic * nx;
                    row.2[1] += elastic * ny;
                    row.3[0] += (f - elastic) * nx;
                    row.3[1] += (f - elastic) * ny;
                }
                last_force = f;
                let (fx, fy) = (f * nx, f * ny);
                total[0] += fx;
                total[1] += fy;
                // Reaction −f on the sprocket, moment (r_r − r_s) × (−f) (19).
                force[0] -= fx;
                force[1] -= fy;
                torque -= rx * fy - ry * fx;
                if !(p.depth_m <= max_pen) {
                    max_pen = p.depth_m;
                }
            }
            pending_memory[k] = next;
            if SHARED {
                used_by[k] = used as u8;
                sums[k] = total;
            } else {
                fx_out[k] += total[0];
                fy_out[k] += total[1];
                touching[k] = true;
                // One patch (the rule): its force is the magnitude, no square root.
                contact_force[k] = if count == 1 {
                    last_force
                } else {
                    (total[0] * total[0] + total[1] * total[1]).sqrt()
                };
            }
            // A roller's implicit row holds the first sprocket it touches;
            // contacts on a second one (overlapping reach) stay explicit.
            let i = a + k;
            if ROWS
                && let Some(rows) = &mut self.rows
                && rows.sprocket[i] == u32::MAX
            {
                rows.sprocket[i] = frame.index as u32;
                rows.c[i] = row.0;
                rows.c_v_sprocket[i] = row.1;
                rows.elastic[i] = row.2;
                rows.explicit[i] = row.3;
                rows.lever[i] = [rx, ry];
            }
        }
        self.energy_j += energy;
        self.damping_power_w += damping_power;
        self.max_penetration_m = max_pen;
        (force, torque)
    }
}

/// The remembered onset of a patch the roller slid over from onto `patch_id`
/// on the same sprocket (the real profile's flank → topping joint), if any.
/// Out of line: the exact-key match before it is the common case.
#[inline(never)]
fn slid_from<P: Outline>(
    profile: &P,
    onsets: &[Memory; MAX_PATCHES],
    sprocket: usize,
    patch_id: u32,
) -> Option<f64> {
    onsets
        .iter()
        .find(|mem| {
            mem.key != EMPTY
                && mem.key >> 32 == sprocket as u64
                && profile.continues(mem.key as u32, patch_id)
        })
        .map(|mem| mem.damping_per_speed)
}
