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

use crate::geometry::{MAX_PATCHES, Outline, Patch, ToothProfile};
use crate::model::{DriveModel, DriveState, SprocketModel};
use crate::scene::MAX_SPROCKETS;

/// Remembered onset of one contact patch.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Memory {
    /// (sprocket << 32) | patch id; `EMPTY` when unused.
    key: u64,
    /// χ / δ̇⁻ (δ̇⁻ floored), s/m.
    damping_per_speed: f64,
}

const EMPTY: u64 = u64::MAX;

/// Reach caching ("culling"): a roller's set of sprockets within reach is
/// measured, then kept for
/// τ = min(c / (speed_factor · v_max + speed_floor), max_skip_s),
/// c the distance from the roller's centre to the nearest reach circle's
/// edge, v_max the chain's fastest roller at that moment. Within τ a roller
/// could only cross that edge by more than doubling its speed plus the floor
/// (5 m/s) within ≤ 1 ms — an acceleration beyond 5000 m/s², i.e. a blow-up.
/// A roller within no reach circle costs nothing more until then; one within
/// reach goes straight to its sprockets' contact loops. The oracle test
/// `culling_changes_nothing` checks the bitwise equality of runs with and
/// without it (without: every roller measured against every sprocket at
/// every evaluation).
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
    /// Linear forms of the contact damping, when enabled.
    damping_rows: Option<DampingRows>,
    /// Stage timers; `None` (the default) times nothing.
    pub timing: Option<ForceTimes>,
    /// Last gap each roller touched: where the O(1) gap search starts.
    gap_hint: Vec<u32>,
    /// Contact culling settings; `None` checks every roller against every sprocket each call.
    pub culling: Option<Culling>,
    /// Time before which roller i's set of sprockets within reach is kept (see [`Culling`]).
    reach_until_s: Vec<f64>,
    /// That set, bit j for sprocket j. It is also the set in effect at the
    /// last committed evaluation, so `memory[i]` is current only where it is
    /// not empty.
    reach_mask: Vec<u64>,
    /// Rollers whose set the last evaluation measured again, with the new
    /// set and time in `pending_reach_*` (adopted on commit).
    remeasured: Buffer<u32>,
    /// See `remeasured`.
    pending_reach_until_s: Vec<f64>,
    /// See `remeasured`.
    pending_reach_mask: Vec<u64>,
    /// Scratch: each sprocket's pose and speed.
    frames: Vec<Frame>,
    /// The last evaluation's stretches of rollers within reach.
    runs: Buffer<Run>,
    /// The runs of the committed sets (`reach_mask`).
    committed_runs: Buffer<Run>,
    /// Scratch: contact force on each roller of a shared stretch, N.
    contact_sum: Vec<[f64; 2]>,
    /// Scratch: patches found for each roller of a shared stretch.
    patches_used: Vec<u8>,
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
            damping_rows: None,
            timing: None,
            gap_hint: vec![0; rollers],
            culling: Some(Culling::default()),
            reach_until_s: vec![f64::NEG_INFINITY; rollers],
            reach_mask: vec![0; rollers],
            remeasured: Buffer::with_capacity(rollers),
            pending_reach_until_s: vec![f64::NEG_INFINITY; rollers],
            pending_reach_mask: vec![0; rollers],
            // Room for a run per roller and sprocket pair in reach twice over:
            // the step loop does not allocate.
            frames: vec![Frame::default(); sprockets],
            runs: Buffer::with_capacity(2 * rollers + sprockets),
            committed_runs: Buffer::with_capacity(2 * rollers + sprockets),
            contact_sum: vec![[0.0; 2]; rollers],
            patches_used: vec![0; rollers],
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
        self.reach_until_s.fill(f64::NEG_INFINITY);
        self.reach_mask.fill(0);
        self.remeasured.clear();
        self.committed_runs.clear();
    }

    /// Forgets every kept reach set ([`Culling`]): the next evaluation
    /// measures every roller again. Call when a sprocket centre has moved
    /// other than at its `center_velocity_m_s` (a co-simulation frame's new
    /// mount position and velocity).
    pub fn forget_reach(&mut self) {
        self.reach_until_s.fill(f64::NEG_INFINITY);
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
        for &i in self.remeasured.iter() {
            let i = i as usize;
            self.reach_until_s[i] = self.pending_reach_until_s[i];
            self.reach_mask[i] = self.pending_reach_mask[i];
        }
        self.remeasured.clear();
        self.committed_runs.clone_from(&self.runs);
    }

    /// Evaluates all forces at `state` without advancing the contact memory
    /// (an integrator's inner stage). The outputs are overwritten as by
    /// [`Self::evaluate`].
    pub fn evaluate_trial(&mut self, model: &DriveModel, state: &DriveState) {
        let started = self.timing.map(|_| std::time::Instant::now());
        self.chain_torque.fill(0.0);
        self.chain_force.fill([0.0; 2]);
        self.links(model, state);
        let links_done = started.map(|_| std::time::Instant::now());
        // Copies of the contact loop: without damping rows (every scheme but
        // implicit damping) the rows' accumulators compile away, and without
        // moving sprocket centres (mounts in a co-simulation) their velocity.
        let centres = model.moving_centres_speed_m_s();
        let centre_speed = centres.unwrap_or(0.0);
        match (self.damping_rows.is_some(), centres.is_some()) {
            (true, true) => self.contacts::<true, true>(model, state, centre_speed),
            (true, false) => self.contacts::<true, false>(model, state, centre_speed),
            (false, true) => self.contacts::<false, true>(model, state, centre_speed),
            (false, false) => self.contacts::<false, false>(model, state, centre_speed),
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

    /// Gravity and the spring-damper links (MODEL.md §2): sets each roller's
    /// force to its weight plus its two links.
    ///
    /// Two passes: the links' force vectors first (independent iterations,
    /// which the compiler pipelines and vectorises), then each roller's sum
    /// of its two links, so no iteration waits on the previous one's store.
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
        let (f, ux, uy, last) = law.eval(
            x[0] - x[n - 1],
            y[0] - y[n - 1],
            vx[0] - vx[n - 1],
            vy[0] - vy[n - 1],
        );
        force[n - 1] = f;
        lfx[n - 1] = f * ux;
        lfy[n - 1] = f * uy;
        stretch[n - 1] = last;
        // `max` drops a NaN: keep it visible to the blow-up check.
        let nan = stretch.iter().fold(false, |b, s| b | s.is_nan());
        let max_stretch = largest(stretch, stretch, |s, _| s.abs());
        let max_speed_sq = largest(vx, vy, |a, b| a * a + b * b);
        let m = model.roller_mass_kg;
        let (gx, gy) = (m * model.gravity_m_s2[0], m * model.gravity_m_s2[1]);
        let (fx, fy) = (&mut self.fx[..n], &mut self.fy[..n]);
        fx[0] = gx + (lfx[0] - lfx[n - 1]);
        fy[0] = gy + (lfy[0] - lfy[n - 1]);
        for i in 1..n {
            fx[i] = gx + (lfx[i] - lfx[i - 1]);
            fy[i] = gy + (lfy[i] - lfy[i - 1]);
        }
        self.max_stretch_m = if nan { f64::NAN } else { max_stretch };
        self.max_speed_m_s = max_speed_sq.sqrt();
    }

    /// Roller–tooth contacts (MODEL.md §3–5) and their reactions, in two passes.
    ///
    /// 1. **Reach** ([`Self::reach`], per roller): each roller's set of
    ///    sprockets within reach, kept between measurements ([`Culling`]);
    ///    consecutive rollers with the same set form a [`Run`].
    /// 2. **Contact** (per run): the sprocket's frame, speed and profile kind
    ///    are fixed for the whole run and its reactions summed in registers;
    ///    the loop is compiled once per profile kind ([`Outline`]).
    ///
    /// Rollers within reach of several sprockets (where reach circles
    /// overlap) sum their contacts over their runs and are finished last.
    /// Every sum runs in roller order within a sprocket, whatever was kept or
    /// measured, so culling changes no bit (the oracle test `culling_changes_nothing`).
    /// `centre_speed` is the fastest sprocket centre's speed (moving mounts), m/s.
    fn contacts<const ROWS: bool, const MOVING: bool>(
        &mut self,
        model: &DriveModel,
        s: &DriveState,
        centre_speed: f64,
    ) {
        // The last evaluation's contact outputs are cleared where it wrote them.
        for run in self.runs.iter() {
            let (a, b) = (run.start, run.end);
            self.touching[a..b].fill(false);
            self.contact_force[a..b].fill(0.0);
            if let Some(rows) = &mut self.damping_rows {
                rows.sprocket[a..b].fill(u32::MAX);
            }
        }
        self.reach(model, s, centre_speed);
        for range in shared_stretches(&self.runs) {
            let (a, b) = (range.start, range.end);
            self.contact_sum[a..b].fill([0.0; 2]);
            self.patches_used[a..b].fill(0);
            self.pending_memory[a..b].fill([FREE; MAX_PATCHES]);
        }
        let mut pass = ContactPass {
            law: self.law,
            state: s,
            memory: &self.memory,
            remembered: &self.reach_mask,
            pending_memory: &mut self.pending_memory,
            gap_hint: &mut self.gap_hint,
            fx: &mut self.fx,
            fy: &mut self.fy,
            touching: &mut self.touching,
            contact_force: &mut self.contact_force,
            sum: &mut self.contact_sum,
            used: &mut self.patches_used,
            rows: if ROWS {
                self.damping_rows.as_mut()
            } else {
                None
            },
            energy_j: 0.0,
            max_penetration_m: 0.0,
        };
        // Each sprocket's frame once, for the sprockets with rollers within reach.
        let mut framed = 0u64;
        for run in self.runs.iter() {
            if framed >> run.sprocket & 1 == 0 {
                framed |= 1 << run.sprocket;
                let j = run.sprocket;
                self.frames[j] = Frame::of(&model.sprockets[j], s.theta[j], s.omega[j], j);
            }
        }
        for run in self.runs.iter() {
            let sp = &model.sprockets[run.sprocket];
            let frame = self.frames[run.sprocket];
            let (force, torque) = match (&sp.profile, run.shared) {
                (ToothProfile::Circular(c), false) => {
                    pass.run::<ROWS, false, MOVING, _>(c, &frame, run)
                }
                (ToothProfile::Circular(c), true) => {
                    pass.run::<ROWS, true, MOVING, _>(c, &frame, run)
                }
                (ToothProfile::Real(r), false) => {
                    pass.run::<ROWS, false, MOVING, _>(&**r, &frame, run)
                }
                (ToothProfile::Real(r), true) => {
                    pass.run::<ROWS, true, MOVING, _>(&**r, &frame, run)
                }
            };
            let total = &mut self.chain_force[run.sprocket];
            total[0] += force[0];
            total[1] += force[1];
            self.chain_torque[run.sprocket] += torque;
        }
        self.max_penetration_m = pass.max_penetration_m;
        self.contact_energy_j = pass.energy_j;
        for range in shared_stretches(&self.runs) {
            for i in range {
                let [sx, sy] = self.contact_sum[i];
                let touching = self.patches_used[i] > 0;
                self.fx[i] += sx;
                self.fy[i] += sy;
                self.touching[i] = touching;
                self.contact_force[i] = if touching {
                    (sx * sx + sy * sy).sqrt()
                } else {
                    0.0
                };
            }
        }
    }

    /// The reach pass of [`Self::contacts`]: each roller's set of sprockets
    /// within reach, kept while [`Culling`] proves it unchanged and measured
    /// against every sprocket otherwise, gathered into [`Run`]s.
    fn reach(&mut self, model: &DriveModel, s: &DriveState, centre_speed: f64) {
        // Rollers and moving sprocket centres (mounted sprockets) approach
        // each other at most at the sum of their speeds.
        let cull = self.culling.map(|c| {
            (
                c.speed_factor * self.max_speed_m_s + c.speed_floor_m_s + centre_speed,
                c.max_skip_s,
            )
        });
        self.remeasured.clear();
        // Slices of one length: the compiler drops the bounds checks on `[i]`.
        let n = s.x.len();
        let (xs, ys) = (&s.x[..n], &s.y[..n]);
        let (until, kept) = (&self.reach_until_s[..n], &self.reach_mask[..n]);
        let pending_until = &mut self.pending_reach_until_s[..n];
        let pending_mask = &mut self.pending_reach_mask[..n];
        // Measure the rollers whose kept set has expired (a few per step).
        let mut changed = false;
        for i in 0..n {
            if s.t_s < until[i] {
                continue;
            }
            let mut mask = 0u64;
            let mut clearance = f64::INFINITY;
            // One bit per sprocket: the validator admits no more than the mask holds.
            for (j, sp) in model.sprockets.iter().enumerate().take(MAX_SPROCKETS) {
                let rx = xs[i] - sp.center_m[0];
                let ry = ys[i] - sp.center_m[1];
                let d_sq = rx * rx + ry * ry;
                if d_sq <= sp.reach_sq_m2 {
                    mask |= 1 << j;
                }
                if cull.is_some() {
                    clearance = clearance.min((d_sq.sqrt() - sp.reach_m).abs());
                }
            }
            pending_mask[i] = mask;
            pending_until[i] = match cull {
                Some((speed_bound, max_skip)) => s.t_s + (clearance / speed_bound).min(max_skip),
                None => f64::NEG_INFINITY,
            };
            self.remeasured.push(i as u32);
            changed |= mask != kept[i];
        }
        // Runs are a function of the sets alone: with no set changed they
        // are the committed ones.
        if !changed {
            self.runs.clone_from(&self.committed_runs);
            return;
        }
        self.runs.clear();
        let mut stretch = Stretch::default();
        for i in 0..n {
            let mask = if s.t_s < until[i] {
                kept[i]
            } else {
                pending_mask[i]
            };
            if mask != stretch.mask {
                stretch.close(i, &mut self.runs);
                stretch = Stretch { mask, start: i };
            }
        }
        stretch.close(n, &mut self.runs);
    }
}

/// The largest `f(a_i, b_i)`, at least 0, in four independent lanes of plain
/// comparisons, which the compiler turns into packed `max` instructions. A
/// NaN is dropped, as by `f64::max` (the links report NaN stretches apart; a
/// NaN speed comes with a NaN position, which the blow-up check stops on).
#[inline(always)]
fn largest(a: &[f64], b: &[f64], f: impl Fn(f64, f64) -> f64) -> f64 {
    let larger = |m: f64, v: f64| if v > m { v } else { m };
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut lanes = [0.0f64; 4];
    for (ca, cb) in a.chunks_exact(4).zip(b.chunks_exact(4)) {
        for k in 0..4 {
            lanes[k] = larger(lanes[k], f(ca[k], cb[k]));
        }
    }
    let tail = n - n % 4;
    let rest = a[tail..]
        .iter()
        .zip(&b[tail..])
        .fold(0.0f64, |m, (&x, &y)| larger(m, f(x, y)));
    lanes.into_iter().fold(rest, larger)
}

/// A reused scratch list whose clone keeps the capacity (a derived `Vec`
/// clone shrinks it to the length, and a cloned generator's step loop would
/// allocate again).
#[derive(Debug)]
struct Buffer<T>(Vec<T>);

impl<T> Buffer<T> {
    fn with_capacity(capacity: usize) -> Self {
        Self(Vec::with_capacity(capacity))
    }
}

impl<T: Clone> Clone for Buffer<T> {
    fn clone(&self) -> Self {
        let mut copy = Vec::with_capacity(self.0.capacity());
        copy.extend_from_slice(&self.0);
        Self(copy)
    }

    fn clone_from(&mut self, source: &Self) {
        self.0.clear();
        self.0.extend_from_slice(&source.0);
    }
}

impl<T> std::ops::Deref for Buffer<T> {
    type Target = Vec<T>;

    fn deref(&self) -> &Vec<T> {
        &self.0
    }
}

impl<T> std::ops::DerefMut for Buffer<T> {
    fn deref_mut(&mut self) -> &mut Vec<T> {
        &mut self.0
    }
}

/// Consecutive rollers within reach of one sprocket.
#[derive(Clone, Copy, Debug)]
struct Run {
    sprocket: usize,
    start: usize,
    end: usize,
    /// Its rollers are within reach of other sprockets too.
    shared: bool,
}

/// The stretches of rollers within reach of several sprockets, each once:
/// a stretch's runs (one per sprocket) follow each other and share its range.
fn shared_stretches(runs: &[Run]) -> impl Iterator<Item = std::ops::Range<usize>> + '_ {
    runs.iter()
        .enumerate()
        .filter(|&(k, run)| run.shared && (k == 0 || runs[k - 1].start != run.start))
        .map(|(_, run)| run.start..run.end)
}

/// Consecutive rollers with one set of sprockets within reach, while the reach pass grows it.
#[derive(Default)]
struct Stretch {
    mask: u64,
    start: usize,
}

impl Stretch {
    /// Ends the stretch before roller `end`: one run per sprocket of its set.
    fn close(&self, end: usize, runs: &mut Buffer<Run>) {
        if self.mask == 0 || end == self.start {
            return;
        }
        let several = !self.mask.is_power_of_two();
        let mut mask = self.mask;
        while mask != 0 {
            runs.push(Run {
                sprocket: mask.trailing_zeros() as usize,
                start: self.start,
                end,
                shared: several,
            });
            mask &= mask - 1;
        }
    }
}

/// One sprocket's pose and speed, fixed for its contact pass.
#[derive(Clone, Copy, Debug, Default)]
struct Frame {
    index: usize,
    center: [f64; 2],
    /// Velocity of the centre (a moving mount), m/s.
    velocity: [f64; 2],
    sin: f64,
    cos: f64,
    omega: f64,
}

impl Frame {
    fn of(sprocket: &SprocketModel, theta: f64, omega: f64, index: usize) -> Self {
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
struct ContactPass<'a> {
    law: ContactLawParams,
    state: &'a DriveState,
    /// The committed contact memory, current where `remembered` is not empty.
    memory: &'a [[Memory; MAX_PATCHES]],
    /// Each roller's set of sprockets within reach at the committed evaluation.
    remembered: &'a [u64],
    pending_memory: &'a mut [[Memory; MAX_PATCHES]],
    gap_hint: &'a mut [u32],
    fx: &'a mut [f64],
    fy: &'a mut [f64],
    touching: &'a mut [bool],
    contact_force: &'a mut [f64],
    /// Contact force on each roller of a shared run, summed over its runs, N.
    sum: &'a mut [[f64; 2]],
    /// Patches found for each roller of a shared run (its entries in `pending_memory`).
    used: &'a mut [u8],
    rows: Option<&'a mut DampingRows>,
    energy_j: f64,
    max_penetration_m: f64,
}

impl ContactPass<'_> {
    /// Contacts of one run's rollers; returns the chain's resultant force and
    /// moment on its sprocket. A shared run adds to the rollers' sums (the
    /// caller finishes them); any other writes each roller's outputs.
    #[inline(always)]
    fn run<const ROWS: bool, const SHARED: bool, const MOVING: bool, P: Outline>(
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

#[cfg(test)]
mod tests {
    use super::largest;

    #[test]
    fn largest_matches_the_plain_fold() {
        // Oracle: `f64::max` over the items (NaNs dropped), at least 0; every
        // length 0..12 (so every tail of the four lanes), mixed signs.
        let a: Vec<f64> = (0..12).map(|k| ((k * 7 % 5) as f64 - 2.0) * 0.3).collect();
        let b: Vec<f64> = (0..12).map(|k| ((k * 3 % 7) as f64 - 3.0) * 0.2).collect();
        for n in 0..=12 {
            let f = |x: f64, y: f64| x * y + x;
            let plain = a[..n]
                .iter()
                .zip(&b[..n])
                .fold(0.0f64, |m, (&x, &y)| m.max(f(x, y)));
            assert_eq!(largest(&a[..n], &b[..n], f), plain, "n = {n}");
        }
        let with_nan = [1.0, f64::NAN, 3.0, -4.0, 2.0];
        assert_eq!(largest(&with_nan, &with_nan, |x, _| x.abs()), 4.0);
    }
}
