//! Forces: the links' spring-dampers and the roller–tooth contact, with their
//! reactions on the sprockets.
//!
//! [`ForceGenerator::evaluate`] is the one force routine shared by every way
//! of stepping (the plugin's own substepping and rapier's integration). It
//! reads a [`DriveState`] and writes forces into its own reused buffers —
//! nothing is allocated per call. Gravity on the rollers is included in the
//! roller forces.
//!
//! Contact state: each contact patch remembers the approach speed δ̇⁻ at its
//! onset (MODEL.md §3), keyed by (sprocket, patch id), until it separates.
//! The memory is advanced by every call, so call `evaluate` once per step.

mod contact_law;

pub use contact_law::ContactLawParams;

use crate::geometry::{MAX_PATCHES, Patch};
use crate::model::{DriveModel, DriveState};

/// Remembered onset of one contact patch.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Memory {
    /// (sprocket << 32) | patch id; `EMPTY` when unused.
    key: u64,
    /// δ̇⁻, floored, m/s.
    onset_m_s: f64,
}

const EMPTY: u64 = u64::MAX;
const FREE: Memory = Memory {
    key: EMPTY,
    onset_m_s: 0.0,
};

/// Computes link and contact forces into reused buffers.
#[derive(Clone, Debug)]
pub struct ForceGenerator {
    law: ContactLawParams,
    memory: Vec<[Memory; MAX_PATCHES]>,
    /// Force on each roller (links, contacts, gravity), N.
    pub fx: Vec<f64>,
    /// Force on each roller, y, N.
    pub fy: Vec<f64>,
    /// Link force F_link of link i (roller i to i + 1), N, tension positive.
    pub link_force: Vec<f64>,
    /// Whether roller i touches any sprocket.
    pub touching: Vec<bool>,
    /// Moment of the chain's contact forces on each sprocket about its centre, N·m.
    pub chain_torque: Vec<f64>,
    /// Resultant of the chain's contact forces on each sprocket, N.
    pub chain_force: Vec<[f64; 2]>,
    /// Total contact force magnitude on each roller, N.
    pub contact_force: Vec<f64>,
    /// Largest penetration in this evaluation, m.
    pub max_penetration_m: f64,
    /// Largest |l − rest length| of any link in this evaluation, m (NaN propagates).
    pub max_stretch_m: f64,
}

impl ForceGenerator {
    /// Buffers for `rollers` rollers and `sprockets` sprockets.
    pub fn new(law: ContactLawParams, rollers: usize, sprockets: usize) -> Self {
        Self {
            law,
            memory: vec![[FREE; MAX_PATCHES]; rollers],
            fx: vec![0.0; rollers],
            fy: vec![0.0; rollers],
            link_force: vec![0.0; rollers],
            touching: vec![false; rollers],
            chain_torque: vec![0.0; sprockets],
            chain_force: vec![[0.0; 2]; sprockets],
            contact_force: vec![0.0; rollers],
            max_penetration_m: 0.0,
            max_stretch_m: 0.0,
        }
    }

    /// The contact law in use.
    pub fn law(&self) -> &ContactLawParams {
        &self.law
    }

    /// Forgets every remembered contact onset.
    pub fn reset_memory(&mut self) {
        self.memory.fill([FREE; MAX_PATCHES]);
    }

    /// Evaluates all forces at `state`.
    pub fn evaluate(&mut self, model: &DriveModel, state: &DriveState) {
        let m = model.roller_mass_kg;
        let (gx, gy) = (m * model.gravity_m_s2[0], m * model.gravity_m_s2[1]);
        self.fx.fill(gx);
        self.fy.fill(gy);
        self.chain_torque.fill(0.0);
        self.chain_force.fill([0.0; 2]);
        self.links(model, state);
        self.contacts(model, state);
    }

    /// Spring-damper links (MODEL.md §2).
    fn links(&mut self, model: &DriveModel, s: &DriveState) {
        let n = s.x.len();
        let (k, d, rest) = (
            model.stiffness_n_m,
            model.damping_n_s_m,
            model.rest_length_m,
        );
        let mut max_stretch = 0.0f64;
        for i in 0..n {
            let j = if i + 1 == n { 0 } else { i + 1 };
            let dx = s.x[j] - s.x[i];
            let dy = s.y[j] - s.y[i];
            let l = (dx * dx + dy * dy).sqrt();
            // Coincident rollers have no direction: the blow-up detector stops the
            // run (the stretch is a full pitch); no force rather than NaN.
            let inv = if l > 0.0 { 1.0 / l } else { 0.0 };
            let (ux, uy) = (dx * inv, dy * inv);
            let rate = (s.vx[j] - s.vx[i]) * ux + (s.vy[j] - s.vy[i]) * uy;
            let stretch = l - rest;
            let f = k * stretch + d * rate;
            self.link_force[i] = f;
            // `max` would drop a NaN; keep it visible to the blow-up check.
            let a = stretch.abs();
            if !(a <= max_stretch) {
                max_stretch = a;
            }
            self.fx[i] += f * ux;
            self.fy[i] += f * uy;
            self.fx[j] -= f * ux;
            self.fy[j] -= f * uy;
        }
        self.max_stretch_m = max_stretch;
    }

    /// Roller–tooth contacts (MODEL.md §3–5) and their reactions.
    fn contacts(&mut self, model: &DriveModel, s: &DriveState) {
        let law = self.law;
        let mut max_pen = 0.0f64;
        let mut patches = [Patch::default(); MAX_PATCHES];
        for i in 0..s.x.len() {
            let mut next = [FREE; MAX_PATCHES];
            let mut used = 0;
            let mut total = [0.0f64; 2];
            for (sp_index, sp) in model.sprockets.iter().enumerate() {
                let rx = s.x[i] - sp.center_m[0];
                let ry = s.y[i] - sp.center_m[1];
                if rx * rx + ry * ry > sp.reach_sq_m2 {
                    continue;
                }
                let (sin, cos) = s.theta[sp_index].sin_cos();
                // World → sprocket frame: rotate by −θ.
                let local = [cos * rx + sin * ry, -sin * rx + cos * ry];
                let count = sp.profile.contacts(local, &mut patches);
                let omega = s.omega[sp_index];
                for p in &patches[..count] {
                    // Normal back to the world frame.
                    let nx = cos * p.normal[0] - sin * p.normal[1];
                    let ny = sin * p.normal[0] + cos * p.normal[1];
                    // Velocity of the roller relative to the sprocket point under it (16)–(18).
                    let vrx = s.vx[i] + omega * ry;
                    let vry = s.vy[i] - omega * rx;
                    let depth_rate = -(vrx * nx + vry * ny);
                    let key = ((sp_index as u64) << 32) | u64::from(p.patch_id);
                    let onset = self.memory[i]
                        .iter()
                        .find(|mem| mem.key == key)
                        .map_or_else(|| law.onset_speed(depth_rate), |mem| mem.onset_m_s);
                    if used < MAX_PATCHES {
                        next[used] = Memory {
                            key,
                            onset_m_s: onset,
                        };
                        used += 1;
                    }
                    let f = law.force(p.depth_m, depth_rate, onset);
                    let (fx, fy) = (f * nx, f * ny);
                    total[0] += fx;
                    total[1] += fy;
                    // Reaction −f on the sprocket, moment (r_r − r_s) × (−f) (19).
                    self.chain_force[sp_index][0] -= fx;
                    self.chain_force[sp_index][1] -= fy;
                    self.chain_torque[sp_index] -= rx * fy - ry * fx;
                    if !(p.depth_m <= max_pen) {
                        max_pen = p.depth_m;
                    }
                }
            }
            self.memory[i] = next;
            self.touching[i] = used > 0;
            self.fx[i] += total[0];
            self.fy[i] += total[1];
            self.contact_force[i] = total[0].hypot(total[1]);
        }
        self.max_penetration_m = max_pen;
    }
}
