//! The contact pass: one loop per [`Run`] of rollers within reach of one
//! sprocket, with the sprocket's frame in registers, compiled once per
//! profile kind ([`Outline`]).

use super::super::rows::DampingRows;
use super::kept::{Kept, Touch};
use super::reach::Run;
use super::scratch::SeatScratch;
use super::{EMPTY, FREE, Memory};
use crate::forces::ContactLawParams;
use crate::geometry::{MAX_PATCHES, Outline, Patch};
use crate::model::{DriveState, SprocketModel};

/// One sprocket's pose and speed, fixed for its contact pass.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Frame {
    pub(super) index: usize,
    pub(super) center: [f64; 2],
    /// Velocity of the centre (a moving mount), m/s.
    pub(super) velocity: [f64; 2],
    pub(super) sin: f64,
    pub(super) cos: f64,
    pub(super) omega: f64,
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
    /// What an evaluation at the same positions reads again (written only
    /// by the loops compiled to keep it, `KEEP`).
    pub(super) kept: &'a mut Kept,
    /// Scratch of the circular seats' pass ([`super::seats`]).
    pub(super) seat_scratch: &'a mut SeatScratch,
    /// Whether the CPU has AVX2 and the pass may use it.
    pub(super) avx2: bool,
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
    ///
    /// The patches are taken by constant index (the first, then a rare
    /// second), so that a profile which writes its one patch by constant
    /// index (the circular seat) keeps it in registers; the sums run in the
    /// same order as a loop over the patches would.
    #[inline(always)]
    pub(super) fn run<
        const ROWS: bool,
        const SHARED: bool,
        const MOVING: bool,
        const KEEP: bool,
        const HERTZ: bool,
        P: Outline,
    >(
        &mut self,
        profile: &P,
        frame: &Frame,
        run: &Run,
    ) -> ([f64; 2], f64) {
        let law = self.law;
        let energy_factor = 1.0 / (law.exponent + 1.0);
        let (sin, cos, omega) = (frame.sin, frame.cos, frame.omega);
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
        let mut sprocket = Sums {
            force: [0.0; 2],
            torque: 0.0,
            energy: 0.0,
            damping_power: 0.0,
            max_pen: self.max_penetration_m,
        };
        let ctx = PatchContext {
            law,
            energy_factor,
            sin,
            cos,
            omega,
            velocity: frame.velocity,
            index: frame.index,
        };
        for k in 0..b - a {
            let rx = xs[k] - frame.center[0];
            let ry = ys[k] - frame.center[1];
            // World → sprocket frame: rotate by −θ.
            let local = [cos * rx + sin * ry, -sin * rx + cos * ry];
            let mut patches = [Patch::default(); MAX_PATCHES];
            let count = profile.contacts(local, &mut gap_hint[k], &mut patches);
            if count == 0 {
                if !SHARED {
                    pending_memory[k] = [FREE; MAX_PATCHES];
                }
                continue;
            }
            // Velocity of the roller relative to the sprocket point under it
            // (16)–(18), v − v_c − ω × r (v_c: a moving mount's centre).
            let v_rel = if MOVING {
                [
                    vxs[k] - frame.velocity[0] + omega * ry,
                    vys[k] - frame.velocity[1] - omega * rx,
                ]
            } else {
                [vxs[k] + omega * ry, vys[k] - omega * rx]
            };
            // A roller that was within no reach circle at the committed
            // evaluation left its memory behind there.
            let onsets = if remembered[k] != 0 {
                &memory[k]
            } else {
                &[FREE; MAX_PATCHES]
            };
            let mut roller = if SHARED {
                Roller {
                    next: pending_memory[k],
                    used: usize::from(used_by[k]),
                    total: sums[k],
                    row: Row::default(),
                    last_force: 0.0,
                }
            } else {
                Roller {
                    next: [FREE; MAX_PATCHES],
                    used: 0,
                    total: [0.0; 2],
                    row: Row::default(),
                    last_force: 0.0,
                }
            };
            let lever = [rx, ry];
            let i = a + k;
            let both = u8::from(count > 1) + 1;
            let first = ctx.patch::<ROWS, MOVING, HERTZ, P>(
                profile,
                &patches[0],
                lever,
                v_rel,
                onsets,
                &mut roller,
                &mut sprocket,
            );
            if KEEP {
                self.kept.touches.push(first.touch(i, both, lever));
            }
            if count > 1 {
                let second = ctx.patch::<ROWS, MOVING, HERTZ, P>(
                    profile,
                    &patches[1],
                    lever,
                    v_rel,
                    onsets,
                    &mut roller,
                    &mut sprocket,
                );
                if KEEP {
                    self.kept.touches.push(second.touch(i, both, lever));
                }
            }
            pending_memory[k] = roller.next;
            let total = roller.total;
            if SHARED {
                used_by[k] = roller.used as u8;
                sums[k] = total;
            } else {
                fx_out[k] += total[0];
                fy_out[k] += total[1];
                touching[k] = true;
                // One patch (the rule): its force is the magnitude, no square root.
                contact_force[k] = if count == 1 {
                    roller.last_force
                } else {
                    (total[0] * total[0] + total[1] * total[1]).sqrt()
                };
            }
            // A roller's implicit row holds the first sprocket it touches;
            // contacts on a second one (overlapping reach) stay explicit.
            if ROWS
                && let Some(rows) = &mut self.rows
                && rows.sprocket[i] == u32::MAX
            {
                let row = roller.row;
                rows.sprocket[i] = frame.index as u32;
                rows.c[i] = row.c;
                rows.c_v_sprocket[i] = row.c_v_sprocket;
                rows.elastic[i] = row.elastic;
                rows.explicit[i] = row.explicit;
                rows.lever[i] = lever;
                rows.surface_velocity[i] = if MOVING {
                    [
                        frame.velocity[0] - omega * ry,
                        frame.velocity[1] + omega * rx,
                    ]
                } else {
                    [-omega * ry, omega * rx]
                };
            }
        }
        self.energy_j += sprocket.energy;
        self.damping_power_w += sprocket.damping_power;
        self.max_penetration_m = sprocket.max_pen;
        (sprocket.force, sprocket.torque)
    }
}

/// One contact patch in the world frame.
pub(super) struct WorldPatch {
    pub(super) depth_m: f64,
    pub(super) patch_id: u32,
    /// Unit normal, the direction of the force on the roller.
    pub(super) normal: [f64; 2],
    /// δ̇, m/s (positive while approaching).
    pub(super) depth_rate: f64,
}

/// What a run's loop sums over its contacts.
pub(super) struct Sums {
    /// Reaction on the sprocket, N.
    pub(super) force: [f64; 2],
    /// Its moment about the sprocket's centre, N·m.
    pub(super) torque: f64,
    pub(super) energy: f64,
    pub(super) damping_power: f64,
    pub(super) max_pen: f64,
}

/// Implicit damping row of one roller: C, C v_sp, elastic, explicit damping.
#[derive(Clone, Copy, Default)]
pub(super) struct Row {
    c: [f64; 3],
    c_v_sprocket: [f64; 2],
    elastic: [f64; 2],
    explicit: [f64; 2],
}

/// One roller's state while its patches are added.
pub(super) struct Roller {
    /// Its advanced contact memory.
    pub(super) next: [Memory; MAX_PATCHES],
    /// Entries of `next` in use.
    pub(super) used: usize,
    /// Contact force on the roller, N.
    pub(super) total: [f64; 2],
    pub(super) row: Row,
    /// Force of the last patch, N.
    pub(super) last_force: f64,
}

/// What every patch of a run reads: the law and the sprocket's frame.
pub(super) struct PatchContext {
    pub(super) law: ContactLawParams,
    pub(super) energy_factor: f64,
    pub(super) sin: f64,
    pub(super) cos: f64,
    pub(super) omega: f64,
    pub(super) velocity: [f64; 2],
    pub(super) index: usize,
}

impl PatchContext {
    /// Adds one patch of a roller at `lever` from the sprocket's centre,
    /// moving at `v_rel` relative to the sprocket's surface under it;
    /// returns what of it depends on the positions alone.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(super) fn patch<const ROWS: bool, const MOVING: bool, const HERTZ: bool, P: Outline>(
        &self,
        profile: &P,
        p: &Patch,
        lever: [f64; 2],
        v_rel: [f64; 2],
        onsets: &[Memory; MAX_PATCHES],
        roller: &mut Roller,
        sums: &mut Sums,
    ) -> Placed {
        let (sin, cos) = (self.sin, self.cos);
        // Normal back to the world frame.
        let nx = cos * p.normal[0] - sin * p.normal[1];
        let ny = sin * p.normal[0] + cos * p.normal[1];
        let depth_rate = -(v_rel[0] * nx + v_rel[1] * ny);
        let contact = WorldPatch {
            depth_m: p.depth_m,
            patch_id: p.patch_id,
            normal: [nx, ny],
            depth_rate,
        };
        let law = self.law;
        // Hertz's K δ √δ chosen before the loop (the same operations as
        // `elastic`'s), so that no call to `powf` stands in it.
        let elastic = if HERTZ {
            law.stiffness * contact.depth_m * contact.depth_m.sqrt()
        } else {
            law.elastic(contact.depth_m)
        };
        let onset = self.world_patch::<ROWS, MOVING, P>(
            profile, &contact, elastic, lever, onsets, roller, sums,
        );
        Placed {
            normal: [nx, ny],
            elastic,
            onset,
        }
    }

    /// [`Self::patch`] once the normal is in the world frame, the approach
    /// speed known and the elastic part K δⁿ computed; returns the patch's
    /// onset in the advanced memory.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(super) fn world_patch<const ROWS: bool, const MOVING: bool, P: Outline>(
        &self,
        profile: &P,
        p: &WorldPatch,
        elastic: f64,
        lever: [f64; 2],
        onsets: &[Memory; MAX_PATCHES],
        roller: &mut Roller,
        sums: &mut Sums,
    ) -> Onset {
        let (omega, law) = (self.omega, self.law);
        let [rx, ry] = lever;
        let [nx, ny] = p.normal;
        let depth_rate = p.depth_rate;
        let key = ((self.index as u64) << 32) | u64::from(p.patch_id);
        // The same patch, or (real profile) the one it slid over from.
        let remembered = match onsets.iter().find(|mem| mem.key == key) {
            Some(mem) => Some(mem.damping_per_speed),
            None if !P::SLIDES => None,
            None => slid_from(profile, onsets, self.index, p.patch_id),
        };
        let damping = remembered.unwrap_or_else(|| law.damping_per_speed(depth_rate));
        let slot = roller.used;
        if roller.used < MAX_PATCHES {
            roller.next[roller.used] = Memory {
                key,
                damping_per_speed: damping,
            };
            roller.used += 1;
        }
        let f = (elastic * (1.0 + damping * depth_rate)).max(0.0);
        sums.energy += elastic * p.depth_m * self.energy_factor;
        sums.damping_power -= (f - elastic) * depth_rate;
        if ROWS {
            let c = elastic * damping;
            // Surface velocity of the sprocket under the roller: v_c + ω × r.
            let v_sp_n = if MOVING {
                (self.velocity[0] - omega * ry) * nx + (self.velocity[1] + omega * rx) * ny
            } else {
                -omega * ry * nx + omega * rx * ny
            };
            let row = &mut roller.row;
            row.c[0] += c * nx * nx;
            row.c[1] += c * nx * ny;
            row.c[2] += c * ny * ny;
            row.c_v_sprocket[0] += c * v_sp_n * nx;
            row.c_v_sprocket[1] += c * v_sp_n * ny;
            row.elastic[0] += elastic * nx;
            row.elastic[1] += elastic * ny;
            row.explicit[0] += (f - elastic) * nx;
            row.explicit[1] += (f - elastic) * ny;
        }
        roller.last_force = f;
        let (fx, fy) = (f * nx, f * ny);
        roller.total[0] += fx;
        roller.total[1] += fy;
        // Reaction −f on the sprocket, moment (r_r − r_s) × (−f) (19).
        sums.force[0] -= fx;
        sums.force[1] -= fy;
        sums.torque -= rx * fy - ry * fx;
        if !(p.depth_m <= sums.max_pen) {
            sums.max_pen = p.depth_m;
        }
        Onset {
            damping,
            new: remembered.is_none(),
            slot: slot.min(MAX_PATCHES) as u8,
        }
    }
}

/// A patch's onset as [`PatchContext::world_patch`] found it.
#[derive(Clone, Copy)]
pub(super) struct Onset {
    /// χ / δ̇⁻: remembered, or from this evaluation's approach speed.
    pub(super) damping: f64,
    /// Not remembered: a new onset, whose χ / δ̇⁻ follows the approach speed.
    pub(super) new: bool,
    /// Its entry in the roller's advanced memory (`MAX_PATCHES`: none).
    pub(super) slot: u8,
}

impl Onset {
    /// The patch as kept for an evaluation at the same positions, with its
    /// world normal and elastic part.
    #[inline(always)]
    pub(super) fn touch(
        self,
        roller: usize,
        patches: u8,
        lever: [f64; 2],
        normal: [f64; 2],
        elastic: f64,
    ) -> Touch {
        Touch {
            roller: roller as u32,
            patches,
            slot: self.slot,
            new: self.new,
            lever,
            normal,
            elastic,
            damping: self.damping,
        }
    }
}

/// What [`PatchContext::patch`] found of a patch that depends on the
/// positions alone: its world normal, elastic part and onset.
#[derive(Clone, Copy)]
pub(super) struct Placed {
    normal: [f64; 2],
    elastic: f64,
    onset: Onset,
}

impl Placed {
    /// The patch as kept for an evaluation at the same positions.
    #[inline(always)]
    fn touch(self, roller: usize, patches: u8, lever: [f64; 2]) -> Touch {
        self.onset
            .touch(roller, patches, lever, self.normal, self.elastic)
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
