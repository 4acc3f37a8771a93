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
//! [`ForceGenerator::evaluate`] advances that memory: call it once per step,
//! at the step's end state. The inner stages of a multi-stage integrator use
//! [`ForceGenerator::evaluate_trial`], which reads the memory but keeps its
//! update aside ([`ForceGenerator::commit_trial`] adopts it when the trial
//! state becomes the step's end, as the adaptive scheme's last stage does).
//!
//! For the implicit-damping integrator the generator also records, per
//! roller, the linear form of its contact damping ([`DampingRows`]); nothing
//! of it is computed unless [`ForceGenerator::enable_damping_rows`] was called.
//!
//! # The contact laws' effective restitution
//!
//! All four laws have the form `K δⁿ (1 + χ(e) δ̇/δ̇⁻)`. For one Hertzian
//! impact (n = 3/2) the rebound ratio depends on χ alone; the test
//! `effective_restitution_table` integrates single impacts and checks:
//!
//! | e | Lankarani–Nikravesh | Hunt–Crossley | Flores | Gonthier |
//! |---|---|---|---|---|
//! | 0.0 | 0.66 | 0.49 | — (needs e > 0) | — (needs e > 0) |
//! | 0.1 | 0.67 | 0.52 | 0.07 | 0.10 |
//! | 0.3 | 0.68 | 0.58 | 0.26 | 0.30 |
//! | 0.5 | 0.72 | 0.66 | 0.47 | 0.49 |
//! | 0.7 | 0.80 | 0.77 | 0.68 | 0.67 |
//! | 0.9 | 0.91 | 0.91 | 0.89 | 0.88 |
//!
//! (With the ≥ 0 clamp, which every law here applies; the test checks the
//! e = 0, e = 0.9 and Gonthier columns and the monotony of every column.)
//!
//! Lankarani–Nikravesh and Hunt–Crossley were derived for e near 1 and cannot
//! model a plastic impact; Gonthier et al.'s χ gives very nearly e over the
//! whole range, Flores et al.'s a little less than e at small e. For a truly
//! plastic chain contact choose `gonthier` with a small e.

mod contact_law;

pub use contact_law::ContactLawParams;

use crate::geometry::{MAX_PATCHES, Patch};
use crate::model::{DriveModel, DriveState};

/// Remembered onset of one contact patch.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Memory {
    /// (sprocket << 32) | patch id; `EMPTY` when unused.
    key: u64,
    /// χ / δ̇⁻ (δ̇⁻ floored), s/m.
    damping_per_speed: f64,
}

const EMPTY: u64 = u64::MAX;

/// Contact culling: a roller whose centre is outside every sprocket's reach
/// circle by a clearance c is skipped for
/// τ = min(c / (speed_factor · v_max + speed_floor), max_skip_s),
/// v_max the chain's fastest roller at that moment. Within τ a roller could
/// only reach a tooth by more than doubling its speed plus the floor (5 m/s)
/// within ≤ 1 ms — an acceleration beyond 5000 m/s², i.e. a blow-up. The
/// oracle test `culling_changes_nothing` checks the bitwise equality of runs
/// with and without culling.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Culling {
    /// Factor on the fastest roller speed.
    pub speed_factor: f64,
    /// Speed added to the bound, m/s (covers rollers starting from rest).
    pub speed_floor_m_s: f64,
    /// Longest skip, s.
    pub max_skip_s: f64,
}

impl Default for Culling {
    fn default() -> Self {
        Self {
            speed_factor: 2.0,
            speed_floor_m_s: 5.0,
            max_skip_s: 1e-3,
        }
    }
}
const FREE: Memory = Memory {
    key: EMPTY,
    damping_per_speed: 0.0,
};

/// Wall time spent in the force stages, when timing is on
/// ([`ForceGenerator::timing`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ForceTimes {
    /// Force evaluations timed.
    pub evaluations: u64,
    /// Clearing the buffers, gravity, links, s.
    pub links_s: f64,
    /// Contact search, contact law and reactions, s.
    pub contacts_s: f64,
}

/// The linear form of each roller's contact damping, for an implicit solve.
///
/// With the elastic parts E_k = K δ_kⁿ and remembered factors κ_k = χ/δ̇⁻_k of
/// the roller's patches on one sprocket, the damping force on the roller is
/// `Σ E_k κ_k n_k n_kᵀ (v_sp − v)` (v_sp the sprocket's surface velocity under
/// the roller): `C v_sp − C v` with `C = Σ E_k κ_k n_k n_kᵀ`. Patches on a
/// second sprocket (only where reach circles overlap) stay explicit.
#[derive(Clone, Debug, Default)]
pub struct DampingRows {
    /// The sprocket of roller i's implicit contacts; `u32::MAX` for none.
    pub sprocket: Vec<u32>,
    /// C as (c_xx, c_xy, c_yy), N·s/m.
    pub c: Vec<[f64; 3]>,
    /// `C v_sp`, N.
    pub c_v_sprocket: Vec<[f64; 2]>,
    /// The elastic force `Σ E_k n_k`, N.
    pub elastic: Vec<[f64; 2]>,
    /// The damping force included in [`ForceGenerator::fx`]/`fy` (after the ≥ 0 clamp), N.
    pub explicit: Vec<[f64; 2]>,
    /// Roller centre relative to that sprocket's centre, m.
    pub lever: Vec<[f64; 2]>,
}

impl DampingRows {
    fn new(rollers: usize) -> Self {
        Self {
            sprocket: vec![u32::MAX; rollers],
            c: vec![[0.0; 3]; rollers],
            c_v_sprocket: vec![[0.0; 2]; rollers],
            elastic: vec![[0.0; 2]; rollers],
            explicit: vec![[0.0; 2]; rollers],
            lever: vec![[0.0; 2]; rollers],
        }
    }

    fn clear(&mut self, i: usize) {
        self.sprocket[i] = u32::MAX;
    }
}

/// The link law of MODEL.md §2 for one link.
#[derive(Clone, Copy)]
struct LinkLaw {
    stiffness: f64,
    damping: f64,
    rest: f64,
}

impl LinkLaw {
    /// From the link vector d = q_j − q_i and the velocity difference:
    /// (F_link, u_x, u_y, l − rest).
    #[inline(always)]
    fn eval(&self, dx: f64, dy: f64, dvx: f64, dvy: f64) -> (f64, f64, f64, f64) {
        let l = (dx * dx + dy * dy).sqrt();
        // Coincident rollers have no direction: no force rather than NaN (the
        // blow-up detector stops the run, the stretch being a whole pitch).
        let inv = if l > 0.0 { 1.0 / l } else { 0.0 };
        let (ux, uy) = (dx * inv, dy * inv);
        let stretch = l - self.rest;
        let f = self.stiffness * stretch + self.damping * (dvx * ux + dvy * uy);
        (f, ux, uy, stretch)
    }
}

/// Computes link and contact forces into reused buffers.
#[derive(Clone, Debug)]
pub struct ForceGenerator {
    law: ContactLawParams,
    memory: Vec<[Memory; MAX_PATCHES]>,
    /// The memory as the last evaluation left it (swapped in on commit).
    pending_memory: Vec<[Memory; MAX_PATCHES]>,
    /// Culling times as the last evaluation left them (swapped in on commit).
    pending_free_until_s: Vec<f64>,
    /// Linear forms of the contact damping, when enabled.
    damping_rows: Option<DampingRows>,
    /// Stage timers; `None` (the default) times nothing.
    pub timing: Option<ForceTimes>,
    /// Last gap each roller touched: where the O(1) gap search starts.
    gap_hint: Vec<u32>,
    /// Last sprocket each roller was within reach of: checked first.
    sprocket_hint: Vec<u32>,
    /// Contact culling settings; `None` checks every roller against every sprocket each call.
    pub culling: Option<Culling>,
    /// Time before which roller i touches no sprocket (see [`Culling`]).
    free_until_s: Vec<f64>,
    /// Scratch: (sin θ, cos θ) of each sprocket.
    rotations: Vec<(f64, f64)>,
    /// Largest roller speed at the last evaluation, m/s.
    max_speed_m_s: f64,
    /// Force on each roller (links, contacts, gravity), N.
    pub fx: Vec<f64>,
    /// Force on each roller, y, N.
    pub fy: Vec<f64>,
    /// Scratch: force vector of link i on roller i, N.
    link_fx: Vec<f64>,
    /// Scratch: its y component, N.
    link_fy: Vec<f64>,
    /// Scratch: l − rest length of link i, m.
    link_stretch: Vec<f64>,
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
    /// Elastic energy stored in the contacts, Σ K δⁿ⁺¹/(n + 1), J.
    pub contact_energy_j: f64,
}

impl ForceGenerator {
    /// Buffers for `rollers` rollers and `sprockets` sprockets.
    pub fn new(law: ContactLawParams, rollers: usize, sprockets: usize) -> Self {
        Self {
            law,
            memory: vec![[FREE; MAX_PATCHES]; rollers],
            pending_memory: vec![[FREE; MAX_PATCHES]; rollers],
            pending_free_until_s: vec![f64::NEG_INFINITY; rollers],
            damping_rows: None,
            timing: None,
            gap_hint: vec![0; rollers],
            sprocket_hint: vec![0; rollers],
            culling: Some(Culling::default()),
            free_until_s: vec![f64::NEG_INFINITY; rollers],
            rotations: vec![(0.0, 1.0); sprockets],
            max_speed_m_s: 0.0,
            fx: vec![0.0; rollers],
            fy: vec![0.0; rollers],
            link_force: vec![0.0; rollers],
            link_fx: vec![0.0; rollers],
            link_fy: vec![0.0; rollers],
            link_stretch: vec![0.0; rollers],
            touching: vec![false; rollers],
            chain_torque: vec![0.0; sprockets],
            chain_force: vec![[0.0; 2]; sprockets],
            contact_force: vec![0.0; rollers],
            max_penetration_m: 0.0,
            max_stretch_m: 0.0,
            contact_energy_j: 0.0,
        }
    }

    /// The contact law in use.
    pub fn law(&self) -> &ContactLawParams {
        &self.law
    }

    /// Forgets every remembered contact onset.
    pub fn reset_memory(&mut self) {
        self.memory.fill([FREE; MAX_PATCHES]);
        self.pending_memory.fill([FREE; MAX_PATCHES]);
        self.free_until_s.fill(f64::NEG_INFINITY);
        self.pending_free_until_s.fill(f64::NEG_INFINITY);
    }

    /// Replaces the contact law (the static relaxation uses a dissipative
    /// one whatever the run's restitution).
    pub fn set_law(&mut self, law: ContactLawParams) {
        self.law = law;
    }

    /// Records [`DampingRows`] from now on (for the implicit-damping scheme).
    pub fn enable_damping_rows(&mut self) {
        if self.damping_rows.is_none() {
            self.damping_rows = Some(DampingRows::new(self.fx.len()));
        }
    }

    /// Stops recording [`DampingRows`].
    pub fn disable_damping_rows(&mut self) {
        self.damping_rows = None;
    }

    /// The damping rows of the last evaluation, if enabled.
    pub fn damping_rows(&self) -> Option<&DampingRows> {
        self.damping_rows.as_ref()
    }

    /// Evaluates all forces at `state`, the end of a step, and advances the
    /// contact memory to it.
    pub fn evaluate(&mut self, model: &DriveModel, state: &DriveState) {
        self.evaluate_trial(model, state);
        self.commit_trial();
    }

    /// Adopts the contact memory of the last [`Self::evaluate_trial`], whose
    /// state has become the step's end state.
    pub fn commit_trial(&mut self) {
        std::mem::swap(&mut self.memory, &mut self.pending_memory);
        std::mem::swap(&mut self.free_until_s, &mut self.pending_free_until_s);
    }

    /// Evaluates all forces at `state` without advancing the contact memory
    /// (an integrator's inner stage). The outputs are overwritten as by
    /// [`Self::evaluate`].
    pub fn evaluate_trial(&mut self, model: &DriveModel, state: &DriveState) {
        let started = self.timing.map(|_| std::time::Instant::now());
        let m = model.roller_mass_kg;
        let (gx, gy) = (m * model.gravity_m_s2[0], m * model.gravity_m_s2[1]);
        self.fx.fill(gx);
        self.fy.fill(gy);
        self.chain_torque.fill(0.0);
        self.chain_force.fill([0.0; 2]);
        self.links(model, state);
        let links_done = started.map(|_| std::time::Instant::now());
        // Two copies of the contact loop: without damping rows (every scheme
        // but implicit damping) the rows' accumulators compile away.
        if self.damping_rows.is_some() {
            self.contacts::<true>(model, state);
        } else {
            self.contacts::<false>(model, state);
        }
        if let (Some(t), Some(start), Some(mid)) = (&mut self.timing, started, links_done) {
            t.evaluations += 1;
            t.links_s += (mid - start).as_secs_f64();
            t.contacts_s += mid.elapsed().as_secs_f64();
        }
    }

    /// Whether a roller centred at (`x`, `y`) touches any sprocket, the
    /// sprockets at angles `theta` (for locating contact events; the roller's
    /// gap hint is read, not updated).
    pub fn touches(
        &self,
        model: &DriveModel,
        roller: usize,
        x: f64,
        y: f64,
        theta: &[f64],
    ) -> bool {
        let mut patches = [Patch::default(); MAX_PATCHES];
        model.sprockets.iter().zip(theta).any(|(sp, &th)| {
            let (rx, ry) = (x - sp.center_m[0], y - sp.center_m[1]);
            if rx * rx + ry * ry > sp.reach_sq_m2 {
                return false;
            }
            let (sin, cos) = th.sin_cos();
            let local = [cos * rx + sin * ry, -sin * rx + cos * ry];
            let mut hint = self.gap_hint[roller];
            sp.profile.contacts(local, &mut hint, &mut patches) > 0
        })
    }

    /// Spring-damper links (MODEL.md §2).
    ///
    /// Two passes: the links' force vectors first (independent iterations,
    /// which the compiler pipelines and vectorises), then each roller's sum of
    /// its two links, so no iteration waits on the previous one's store.
    fn links(&mut self, model: &DriveModel, s: &DriveState) {
        let n = s.x.len();
        let law = LinkLaw {
            stiffness: model.stiffness_n_m,
            damping: model.damping_n_s_m,
            rest: model.rest_length_m,
        };
        let (x, y, vx, vy) = (&s.x[..n], &s.y[..n], &s.vx[..n], &s.vy[..n]);
        let force = &mut self.link_force[..n];
        let (lfx, lfy) = (&mut self.link_fx[..n], &mut self.link_fy[..n]);
        let stretch = &mut self.link_stretch[..n];
        // Links 0..n−1 join consecutive rollers: a branch-free loop over
        // zipped slices, which the compiler vectorises (square roots and
        // divisions two or four at a time). The closing link n−1 → 0 after it.
        let pairs = x[..n - 1]
            .iter()
            .zip(&x[1..])
            .zip(y[..n - 1].iter().zip(&y[1..]))
            .zip(vx[..n - 1].iter().zip(&vx[1..]))
            .zip(vy[..n - 1].iter().zip(&vy[1..]));
        let outs = force[..n - 1]
            .iter_mut()
            .zip(lfx[..n - 1].iter_mut())
            .zip(lfy[..n - 1].iter_mut())
            .zip(stretch[..n - 1].iter_mut());
        for (((((x0, x1), (y0, y1)), (vx0, vx1)), (vy0, vy1)), (((f, fx), fy), st)) in
            pairs.zip(outs)
        {
            let (force_n, ux, uy, s) = law.eval(x1 - x0, y1 - y0, vx1 - vx0, vy1 - vy0);
            *f = force_n;
            *fx = force_n * ux;
            *fy = force_n * uy;
            *st = s;
        }
        let (f, ux, uy, s) = law.eval(
            x[0] - x[n - 1],
            y[0] - y[n - 1],
            vx[0] - vx[n - 1],
            vy[0] - vy[n - 1],
        );
        force[n - 1] = f;
        lfx[n - 1] = f * ux;
        lfy[n - 1] = f * uy;
        stretch[n - 1] = s;
        // `max` drops a NaN: keep it visible to the blow-up check.
        let stretch_is_nan = stretch.iter().any(|s| s.is_nan());
        let max_stretch = stretch.iter().fold(0.0f64, |m, s| m.max(s.abs()));
        let (fx, fy) = (&mut self.fx[..n], &mut self.fy[..n]);
        fx[0] += lfx[0] - lfx[n - 1];
        fy[0] += lfy[0] - lfy[n - 1];
        for i in 1..n {
            fx[i] += lfx[i] - lfx[i - 1];
            fy[i] += lfy[i] - lfy[i - 1];
        }
        let max_speed_sq = vx
            .iter()
            .zip(vy)
            .fold(0.0f64, |m, (a, b)| m.max(a * a + b * b));
        self.max_stretch_m = if stretch_is_nan {
            f64::NAN
        } else {
            max_stretch
        };
        self.max_speed_m_s = max_speed_sq.sqrt();
    }

    /// Roller–tooth contacts (MODEL.md §3–5) and their reactions.
    ///
    /// Rollers far from every sprocket are skipped for a while ([`Culling`]).
    /// Within reach, the gap search starts from the roller's last gap.
    fn contacts<const ROWS: bool>(&mut self, model: &DriveModel, s: &DriveState) {
        let law = self.law;
        let energy_factor = 1.0 / (law.exponent + 1.0);
        let mut energy = 0.0;
        let mut max_pen = 0.0f64;
        let mut patches = [Patch::default(); MAX_PATCHES];
        for (r, th) in self.rotations.iter_mut().zip(&s.theta) {
            *r = th.sin_cos();
        }
        let cull = self.culling.map(|c| {
            (
                c.speed_factor * self.max_speed_m_s + c.speed_floor_m_s,
                c.max_skip_s,
            )
        });
        // Slices of one length: the compiler drops the bounds checks on `[i]`.
        let n = s.x.len();
        let (xs, ys, vxs, vys) = (&s.x[..n], &s.y[..n], &s.vx[..n], &s.vy[..n]);
        let free_until = &self.free_until_s[..n];
        let pending_free_until = &mut self.pending_free_until_s[..n];
        let memory = &self.memory[..n];
        let pending_memory = &mut self.pending_memory[..n];
        let gap_hint = &mut self.gap_hint[..n];
        let sprocket_hint = &mut self.sprocket_hint[..n];
        let touching = &mut self.touching[..n];
        let contact_force = &mut self.contact_force[..n];
        let (fx_out, fy_out) = (&mut self.fx[..n], &mut self.fy[..n]);
        let rotations = &self.rotations;
        let chain_force = &mut self.chain_force;
        let chain_torque = &mut self.chain_torque;
        for i in 0..n {
            pending_free_until[i] = free_until[i];
            if s.t_s < free_until[i] {
                // Skipped rollers were found free: flags and force are already clear.
                pending_memory[i] = [FREE; MAX_PATCHES];
                if ROWS && let Some(rows) = &mut self.damping_rows {
                    rows.clear(i);
                }
                continue;
            }
            let mut next = [FREE; MAX_PATCHES];
            let mut used = 0;
            let mut total = [0.0f64; 2];
            let mut in_reach = false;
            // Implicit damping row of this roller: (C, C v_sp, elastic, explicit damping).
            let mut row_sprocket = u32::MAX;
            let mut row = (
                [0.0f64; 3],
                [0.0f64; 2],
                [0.0f64; 2],
                [0.0f64; 2],
                [0.0f64; 2],
            );
            let count_sprockets = model.sprockets.len();
            let first = sprocket_hint[i] as usize;
            // Sprockets still to be searched (bit j; 64 and above always are).
            let mut candidates = u64::MAX;
            for k in 0..count_sprockets {
                // Start with the sprocket the roller last touched.
                let sp_index = if k == 0 {
                    first
                } else if k <= first {
                    k - 1
                } else {
                    k
                };
                if sp_index < 64 && candidates >> sp_index & 1 == 0 {
                    continue;
                }
                let sp = &model.sprockets[sp_index];
                let rx = xs[i] - sp.center_m[0];
                let ry = ys[i] - sp.center_m[1];
                if rx * rx + ry * ry > sp.reach_sq_m2 {
                    continue;
                }
                in_reach = true;
                let (sin, cos) = rotations[sp_index];
                // World → sprocket frame: rotate by −θ.
                let local = [cos * rx + sin * ry, -sin * rx + cos * ry];
                let count = sp.profile.contacts(local, &mut gap_hint[i], &mut patches);
                let omega = s.omega[sp_index];
                for p in &patches[..count] {
                    // Normal back to the world frame.
                    let nx = cos * p.normal[0] - sin * p.normal[1];
                    let ny = sin * p.normal[0] + cos * p.normal[1];
                    // Velocity of the roller relative to the sprocket point under it (16)–(18).
                    let vrx = vxs[i] + omega * ry;
                    let vry = vys[i] - omega * rx;
                    let depth_rate = -(vrx * nx + vry * ny);
                    let key = ((sp_index as u64) << 32) | u64::from(p.patch_id);
                    // The same patch, or (real profile) the one it slid over from.
                    let damping = memory[i]
                        .iter()
                        .find(|mem| {
                            mem.key == key
                                || (mem.key != EMPTY
                                    && mem.key >> 32 == sp_index as u64
                                    && sp.profile.continues(mem.key as u32, p.patch_id))
                        })
                        .map_or_else(
                            || law.damping_per_speed(depth_rate),
                            |mem| mem.damping_per_speed,
                        );
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
                    if ROWS && (row_sprocket == u32::MAX || row_sprocket == sp_index as u32) {
                        row_sprocket = sp_index as u32;
                        let c = elastic * damping;
                        // Surface velocity of the sprocket under the roller: ω × r.
                        let v_sp_n = -omega * ry * nx + omega * rx * ny;
                        row.0[0] += c * nx * nx;
                        row.0[1] += c * nx * ny;
                        row.0[2] += c * ny * ny;
                        row.1[0] += c * v_sp_n * nx;
                        row.1[1] += c * v_sp_n * ny;
                        row.2[0] += elastic * nx;
                        row.2[1] += elastic * ny;
                        row.3[0] += (f - elastic) * nx;
                        row.3[1] += (f - elastic) * ny;
                        row.4 = [rx, ry];
                    }
                    let (fx, fy) = (f * nx, f * ny);
                    total[0] += fx;
                    total[1] += fy;
                    // Reaction −f on the sprocket, moment (r_r − r_s) × (−f) (19).
                    chain_force[sp_index][0] -= fx;
                    chain_force[sp_index][1] -= fy;
                    chain_torque[sp_index] -= rx * fy - ry * fx;
                    if !(p.depth_m <= max_pen) {
                        max_pen = p.depth_m;
                    }
                }
                sprocket_hint[i] = sp_index as u32;
                if model.disjoint_reach {
                    // No other sprocket can be within reach of this roller.
                    break;
                }
                // Only the sprockets whose reach overlaps this one's can be within reach too.
                candidates &= model
                    .reach_overlaps
                    .get(sp_index)
                    .copied()
                    .unwrap_or(u64::MAX);
                if candidates == 0 {
                    break;
                }
            }
            if let Some((speed_bound, max_skip)) = cull
                && !in_reach
            {
                let clearance = model
                    .sprockets
                    .iter()
                    .map(|sp| (xs[i] - sp.center_m[0]).hypot(ys[i] - sp.center_m[1]) - sp.reach_m)
                    .fold(f64::INFINITY, f64::min);
                pending_free_until[i] = s.t_s + (clearance / speed_bound).min(max_skip);
            }
            pending_memory[i] = next;
            if ROWS && let Some(rows) = &mut self.damping_rows {
                rows.sprocket[i] = row_sprocket;
                if row_sprocket != u32::MAX {
                    rows.c[i] = row.0;
                    rows.c_v_sprocket[i] = row.1;
                    rows.elastic[i] = row.2;
                    rows.explicit[i] = row.3;
                    rows.lever[i] = row.4;
                }
            }
            touching[i] = used > 0;
            fx_out[i] += total[0];
            fy_out[i] += total[1];
            contact_force[i] = if used > 0 {
                (total[0] * total[0] + total[1] * total[1]).sqrt()
            } else {
                0.0
            };
        }
        self.max_penetration_m = max_pen;
        self.contact_energy_j = energy;
    }
}
