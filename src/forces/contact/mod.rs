//! The roller–tooth contact (docs/model.md, “Contact law” and “Contact
//! memory”) and its reactions on the sprockets, in two passes per
//! evaluation:
//!
//! 1. **Reach** ([`reach`], per roller): each roller's set of sprockets
//!    within reach, kept between measurements ([`Culling`]); consecutive
//!    rollers with the same set form a run.
//! 2. **Contact** ([`pass`], per run): the sprocket's frame, speed and
//!    profile kind are fixed for the whole run and its reactions summed in
//!    registers; the loop is compiled once per profile kind.
//!
//! Rollers within reach of several sprockets (where reach circles overlap)
//! sum their contacts over their runs and are finished last. Every sum runs
//! in roller order within a sprocket, whatever was kept or measured, so
//! culling changes no bit (the oracle test `culling_changes_nothing`).
//!
//! Contact state: each contact patch remembers the approach speed δ̇⁻ at its
//! onset, keyed by (sprocket, patch id), until it separates. An evaluation
//! writes the advanced memory aside; [`ForceElement::commit`] adopts it.

mod kept;
mod pass;
mod reach;
mod scratch;
mod seats;

pub(crate) use reach::Culling;

use kept::Kept;
use pass::{ContactPass, Frame};
use reach::{Reach, shared_stretches};
use scratch::SeatScratch;

use super::rows::DampingRows;
use super::{
    ContactLawParams, ForceElement, Forces, History, HistoryError, HistoryReader, cpu_has_avx2,
};
use crate::geometry::{MAX_PATCHES, Patch, ToothProfile};
use crate::model::{DriveModel, DriveState};
use crate::scene::MAX_SPROCKETS;

/// Remembered onset of one contact patch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Memory {
    /// (sprocket << 32) | patch id; `EMPTY` when unused.
    pub(super) key: u64,
    /// χ / δ̇⁻ (δ̇⁻ floored), s/m.
    pub(super) damping_per_speed: f64,
}

pub(super) const EMPTY: u64 = u64::MAX;

pub(super) const FREE: Memory = Memory {
    key: EMPTY,
    damping_per_speed: 0.0,
};

/// The contact damping factor χ used while relaxing to static equilibrium,
/// whatever the run's law and restitution: Lankarani–Nikravesh at e = 0. The
/// static equilibrium does not depend on it; without it a stiff elastic
/// contact (K_g = 1e10, e = 1) rings through the first tensioning until the
/// stretch guard trips.
const RELAXATION_CHI: f64 = 0.75;

/// The roller–tooth contact element.
#[derive(Clone, Debug)]
pub(crate) struct ToothContact {
    law: ContactLawParams,
    /// The run's law and whether it recorded damping rows, kept aside while
    /// the static equilibrium uses its own.
    run_settings: Option<(ContactLawParams, bool)>,
    memory: Vec<[Memory; MAX_PATCHES]>,
    /// The memory as the last evaluation left it (swapped in on commit).
    pending_memory: Vec<[Memory; MAX_PATCHES]>,
    /// Linear forms of the contact damping, when enabled.
    damping_rows: Option<DampingRows>,
    /// Last gap each roller touched: where the O(1) gap search starts.
    gap_hint: Vec<u32>,
    /// Reach caching settings; `None` checks every roller against every
    /// sprocket at each evaluation.
    pub culling: Option<Culling>,
    reach: Reach,
    /// Scratch: each sprocket's pose and speed.
    frames: Vec<Frame>,
    /// Scratch: contact force on each roller of a shared stretch, N.
    contact_sum: Vec<[f64; 2]>,
    /// Scratch: patches found for each roller of a shared stretch.
    patches_used: Vec<u8>,
    /// Scratch of the circular seats' pass.
    seat_scratch: SeatScratch,
    /// Whether each evaluation keeps what depends on the positions alone
    /// ([`Self::keep_positions`]).
    keep: bool,
    /// What the last evaluation kept of it.
    kept: Kept,
    /// Use the AVX2 build of the pass where the CPU has it (off: the
    /// baseline build, for the test that compares the two).
    pub(crate) avx2: bool,
}

impl ToothContact {
    /// Buffers for `rollers` rollers and `sprockets` sprockets (at most
    /// [`MAX_SPROCKETS`]: a roller's set of sprockets within reach is a
    /// 64-bit mask; the scene's validator holds every drive to it).
    pub(crate) fn new(law: ContactLawParams, rollers: usize, sprockets: usize) -> Self {
        debug_assert!(
            sprockets <= MAX_SPROCKETS,
            "a drive has at most 64 sprockets"
        );
        Self {
            law,
            run_settings: None,
            memory: vec![[FREE; MAX_PATCHES]; rollers],
            pending_memory: vec![[FREE; MAX_PATCHES]; rollers],
            damping_rows: None,
            gap_hint: vec![0; rollers],
            culling: Some(Culling::default()),
            reach: Reach::new(rollers, sprockets),
            frames: vec![Frame::default(); sprockets],
            contact_sum: vec![[0.0; 2]; rollers],
            patches_used: vec![0; rollers],
            seat_scratch: SeatScratch::new(rollers),
            keep: false,
            kept: Kept::default(),
            avx2: true,
        }
    }

    /// Forgets every kept reach set ([`Culling`]): the next evaluation
    /// measures every roller again. Call when a sprocket centre has moved
    /// other than at its `center_velocity_m_s` (a co-simulation frame's new
    /// mount position and velocity).
    pub(crate) fn forget_reach(&mut self) {
        self.reach.expire();
        self.kept.valid = false;
    }

    /// From now on each evaluation (without damping rows) keeps what
    /// depends on the positions alone, for [`Self::evaluate_again`] (velocity
    /// Verlet evaluates twice at one set of positions).
    pub(crate) fn keep_positions(&mut self, keep: bool) {
        self.keep = keep;
        if keep {
            self.kept.reserve(self.gap_hint.len());
        }
        self.kept.valid = false;
    }

    /// Forgets the circular seats' kept gap directions: the next evaluation
    /// reads every roller's from its sprocket's table (tests of the kept ones).
    #[cfg(test)]
    pub(crate) fn forget_gap_directions(&mut self) {
        self.seat_scratch.direction_of.fill(scratch::NO_DIRECTION);
    }

    /// Records [`DampingRows`] from now on (for the implicit-damping scheme).
    pub(crate) fn enable_damping_rows(&mut self) {
        if self.damping_rows.is_none() {
            self.damping_rows = Some(DampingRows::new(self.gap_hint.len()));
        }
    }

    /// Stops recording [`DampingRows`].
    pub(crate) fn disable_damping_rows(&mut self) {
        self.damping_rows = None;
    }

    /// The damping rows of the last evaluation, if enabled.
    pub(crate) fn damping_rows(&self) -> Option<&DampingRows> {
        self.damping_rows.as_ref()
    }

    /// Whether a roller centred at (`x`, `y`) touches any sprocket, the
    /// sprockets at angles `theta` (for locating contact events; the roller's
    /// gap hint is read, not updated). Stops at the first sprocket touched.
    pub(crate) fn touches(
        &self,
        model: &DriveModel,
        roller: usize,
        x: f64,
        y: f64,
        theta: &[f64],
    ) -> bool {
        let mut patches = [Patch::default(); MAX_PATCHES];
        (0..model.sprockets.len())
            .any(|j| self.patches_on(model, j, roller, [x, y], theta[j], &mut patches) > 0)
    }

    /// The roller of `state` that penetrates a tooth deepest, with its
    /// depth, m (a slow search of every roller against every sprocket, for
    /// reports).
    pub(crate) fn deepest_roller(
        &self,
        model: &DriveModel,
        state: &DriveState,
    ) -> Option<(usize, f64)> {
        let mut patches = [Patch::default(); MAX_PATCHES];
        let mut deepest: Option<(usize, f64)> = None;
        for i in 0..state.rollers() {
            for j in 0..model.sprockets.len() {
                let at = [state.x[i], state.y[i]];
                let count = self.patches_on(model, j, i, at, state.theta[j], &mut patches);
                for p in &patches[..count] {
                    if deepest.is_none_or(|(_, d)| p.depth_m > d) {
                        deepest = Some((i, p.depth_m));
                    }
                }
            }
        }
        deepest
    }

    /// The contact patches of roller `roller` centred at `at` on sprocket
    /// `j` turned to `theta`, written to `patches`; returns their count (0
    /// outside the sprocket's reach). The roller's gap hint is read, not
    /// updated.
    fn patches_on(
        &self,
        model: &DriveModel,
        j: usize,
        roller: usize,
        at: [f64; 2],
        theta: f64,
        patches: &mut [Patch; MAX_PATCHES],
    ) -> usize {
        let sp = &model.sprockets[j];
        let (rx, ry) = (at[0] - sp.center_m[0], at[1] - sp.center_m[1]);
        if rx * rx + ry * ry > sp.reach_sq_m2 {
            return 0;
        }
        let (sin, cos) = theta.sin_cos();
        let local = [cos * rx + sin * ry, -sin * rx + cos * ry];
        let mut hint = self.gap_hint[roller];
        sp.profile.contacts(local, &mut hint, patches)
    }

    /// The contact pass for the CPU: built for AVX2 where the CPU has it
    /// (three-operand instructions, fewer register copies), for the
    /// baseline target otherwise. The same operations in the same order and
    /// no FMA, so the same bits (test `avx2_and_baseline_contacts_agree_to_the_bit`).
    fn contacts_on_cpu<const ROWS: bool, const MOVING: bool, const KEEP: bool>(
        &mut self,
        model: &DriveModel,
        s: &DriveState,
        out: &mut Forces,
        centre_speed: f64,
    ) {
        #[cfg(target_arch = "x86_64")]
        if self.avx2 && cpu_has_avx2() {
            // SAFETY: the CPU has AVX2, checked on the line above.
            return unsafe {
                self.contacts_avx2::<ROWS, MOVING, KEEP>(model, s, out, centre_speed)
            };
        }
        self.contacts::<ROWS, MOVING, KEEP>(model, s, out, centre_speed);
    }

    /// [`Self::contacts`] compiled with AVX2 (no FMA).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn contacts_avx2<const ROWS: bool, const MOVING: bool, const KEEP: bool>(
        &mut self,
        model: &DriveModel,
        s: &DriveState,
        out: &mut Forces,
        centre_speed: f64,
    ) {
        self.contacts::<ROWS, MOVING, KEEP>(model, s, out, centre_speed);
    }

    /// The contact pass, compiled per (damping rows, moving centres,
    /// keeping what depends on the positions alone).
    #[inline(always)]
    fn contacts<const ROWS: bool, const MOVING: bool, const KEEP: bool>(
        &mut self,
        model: &DriveModel,
        s: &DriveState,
        out: &mut Forces,
        centre_speed: f64,
    ) {
        // The last evaluation's contact outputs are cleared where it wrote them.
        for run in self.reach.runs.iter() {
            let (a, b) = (run.start, run.end);
            out.touching[a..b].fill(false);
            out.contact_force[a..b].fill(0.0);
            if let Some(rows) = &mut self.damping_rows {
                rows.sprocket[a..b].fill(u32::MAX);
            }
        }
        // Rollers and moving sprocket centres (mounted sprockets) approach
        // each other at most at the sum of their speeds.
        let cull = self.culling.map(|c| {
            (
                c.speed_factor * out.max_roller_speed_m_s + c.speed_floor_m_s + centre_speed,
                c.max_skip_s,
            )
        });
        self.reach.measure(model, s, cull);
        for range in shared_stretches(&self.reach.runs) {
            let (a, b) = (range.start, range.end);
            self.contact_sum[a..b].fill([0.0; 2]);
            self.patches_used[a..b].fill(0);
            self.pending_memory[a..b].fill([FREE; MAX_PATCHES]);
        }
        self.kept.valid = false;
        if KEEP {
            self.kept.touches.clear();
            self.kept.run_ends.clear();
        }
        let mut pass = ContactPass {
            law: self.law,
            state: s,
            memory: &self.memory,
            remembered: &self.reach.mask,
            pending_memory: &mut self.pending_memory,
            gap_hint: &mut self.gap_hint,
            fx: &mut out.fx,
            fy: &mut out.fy,
            touching: &mut out.touching,
            contact_force: &mut out.contact_force,
            sum: &mut self.contact_sum,
            used: &mut self.patches_used,
            rows: if ROWS {
                self.damping_rows.as_mut()
            } else {
                None
            },
            kept: &mut self.kept,
            seat_scratch: &mut self.seat_scratch,
            avx2: self.avx2 && cpu_has_avx2(),
            energy_j: 0.0,
            damping_power_w: 0.0,
            max_penetration_m: 0.0,
        };
        // Each sprocket's frame once, for the sprockets with rollers within reach.
        let mut framed = 0u64;
        for run in self.reach.runs.iter() {
            if framed >> run.sprocket & 1 == 0 {
                framed |= 1 << run.sprocket;
                let j = run.sprocket;
                self.frames[j] = Frame::of(&model.sprockets[j], s.theta[j], s.omega[j], j);
            }
        }
        let hertz = self.law.hertz();
        for run in self.reach.runs.iter() {
            let sp = &model.sprockets[run.sprocket];
            let frame = self.frames[run.sprocket];
            let (force, torque) = match (&sp.profile, run.shared) {
                // The branch-free seats' pass where it applies.
                (ToothProfile::Circular(c), false) if !ROWS && !c.tips => {
                    pass.run_seats::<MOVING, KEEP>(&c.seats(), &frame, run)
                }
                (ToothProfile::Circular(c), false) => {
                    pass.run::<ROWS, false, MOVING, KEEP, false, _>(&c.seats(), &frame, run)
                }
                (ToothProfile::Circular(c), true) => {
                    pass.run::<ROWS, true, MOVING, KEEP, false, _>(&c.seats(), &frame, run)
                }
                (ToothProfile::Real(r), false) if hertz => {
                    pass.run::<ROWS, false, MOVING, KEEP, true, _>(&**r, &frame, run)
                }
                (ToothProfile::Real(r), false) => {
                    pass.run::<ROWS, false, MOVING, KEEP, false, _>(&**r, &frame, run)
                }
                (ToothProfile::Real(r), true) => {
                    pass.run::<ROWS, true, MOVING, KEEP, false, _>(&**r, &frame, run)
                }
            };
            if KEEP {
                let end = pass.kept.touches.len() as u32;
                pass.kept.run_ends.push(end);
            }
            let total = &mut out.chain_force[run.sprocket];
            total[0] += force[0];
            total[1] += force[1];
            out.chain_torque[run.sprocket] += torque;
        }
        out.max_penetration_m = pass.max_penetration_m;
        out.contact_energy_j = pass.energy_j;
        out.contact_damping_power_w = pass.damping_power_w;
        if KEEP {
            self.kept.max_penetration_m = out.max_penetration_m;
            self.kept.energy_j = out.contact_energy_j;
            self.kept.valid = true;
        }
        for range in shared_stretches(&self.reach.runs) {
            for i in range {
                let [sx, sy] = self.contact_sum[i];
                let touching = self.patches_used[i] > 0;
                out.fx[i] += sx;
                out.fy[i] += sy;
                out.touching[i] = touching;
                out.contact_force[i] = if touching {
                    (sx * sx + sy * sy).sqrt()
                } else {
                    0.0
                };
            }
        }
    }
}

impl ForceElement for ToothContact {
    fn name(&self) -> &'static str {
        "contacts"
    }

    fn evaluate(&mut self, model: &DriveModel, state: &DriveState, out: &mut Forces) {
        // Copies of the contact loop: without damping rows (every scheme but
        // implicit damping) the rows' accumulators compile away, and without
        // moving sprocket centres (mounts in a co-simulation) their velocity.
        let centres = model.moving_centres_speed_m_s();
        let centre_speed = centres.unwrap_or(0.0);
        // Kept for a second evaluation at the same positions only without
        // damping rows (velocity Verlet records none).
        let keep = self.keep;
        match (self.damping_rows.is_some(), centres.is_some()) {
            (true, true) => {
                self.contacts_on_cpu::<true, true, false>(model, state, out, centre_speed)
            }
            (true, false) => {
                self.contacts_on_cpu::<true, false, false>(model, state, out, centre_speed)
            }
            (false, true) if keep => {
                self.contacts_on_cpu::<false, true, true>(model, state, out, centre_speed)
            }
            (false, true) => {
                self.contacts_on_cpu::<false, true, false>(model, state, out, centre_speed)
            }
            (false, false) if keep => {
                self.contacts_on_cpu::<false, false, true>(model, state, out, centre_speed)
            }
            (false, false) => {
                self.contacts_on_cpu::<false, false, false>(model, state, out, centre_speed)
            }
        }
    }

    fn commit(&mut self) {
        std::mem::swap(&mut self.memory, &mut self.pending_memory);
        self.reach.commit();
    }

    /// The remembered onsets (per roller and patch: key, χ/δ̇⁻), the gap
    /// hints, each roller's kept set of sprocket within reach with its
    /// expiry, and the damping rows where they are recorded. The runs are a
    /// function of the kept sets and are rebuilt from them.
    fn save_history(&self, history: &mut History) {
        let onsets = || self.memory.iter().flatten();
        history.push_words(onsets().map(|m| m.key));
        history.push_floats(onsets().map(|m| m.damping_per_speed));
        history.push_words(self.gap_hint.iter().map(|&h| u64::from(h)));
        let (mask, until_s) = self.reach.kept();
        history.push_words(mask.iter().copied());
        history.push_floats(until_s.iter().copied());
        if let Some(rows) = &self.damping_rows {
            history.push_words(rows.sprocket.iter().map(|&s| u64::from(s)));
            history.push_floats(
                [
                    &rows.c_v_sprocket,
                    &rows.elastic,
                    &rows.explicit,
                    &rows.lever,
                ]
                .into_iter()
                .flatten()
                .flatten()
                .copied()
                .chain(rows.c.iter().flatten().copied()),
            );
        }
    }

    fn restore_history(&mut self, history: &mut HistoryReader<'_>) -> Result<(), HistoryError> {
        let n = self.gap_hint.len();
        let keys = history.words(n * MAX_PATCHES)?;
        let damping = history.floats(n * MAX_PATCHES)?;
        for (k, (key, d)) in keys.iter().zip(damping).enumerate() {
            self.memory[k / MAX_PATCHES][k % MAX_PATCHES] = Memory {
                key: *key,
                damping_per_speed: *d,
            };
        }
        self.pending_memory.clone_from(&self.memory);
        self.kept.valid = false;
        for (h, w) in self.gap_hint.iter_mut().zip(history.words(n)?) {
            *h = u32::try_from(*w).unwrap_or(0);
        }
        let mask = history.words(n)?;
        let until_s = history.floats(n)?;
        self.reach.restore(mask, until_s);
        if let Some(rows) = &mut self.damping_rows {
            for (s, w) in rows.sprocket.iter_mut().zip(history.words(n)?) {
                *s = u32::try_from(*w).unwrap_or(u32::MAX);
            }
            let mut values = history.floats(11 * n)?.iter().copied();
            for pairs in [
                &mut rows.c_v_sprocket,
                &mut rows.elastic,
                &mut rows.explicit,
                &mut rows.lever,
            ] {
                for v in pairs.iter_mut().flatten() {
                    *v = values.next().unwrap_or(0.0);
                }
            }
            for v in rows.c.iter_mut().flatten() {
                *v = values.next().unwrap_or(0.0);
            }
        }
        Ok(())
    }

    fn reset(&mut self) {
        self.kept.valid = false;
        self.memory.fill([FREE; MAX_PATCHES]);
        self.pending_memory.fill([FREE; MAX_PATCHES]);
        self.reach.reset();
    }

    /// A dissipative law while relaxing, whatever the run's restitution, and
    /// damping rows: the relaxation steps with the contact damping implicit.
    fn begin_equilibrium(&mut self) {
        let had_rows = self.damping_rows.is_some();
        let (run_law, _) = *self.run_settings.get_or_insert((self.law, had_rows));
        self.law = run_law.with_chi(RELAXATION_CHI);
        self.enable_damping_rows();
    }

    fn end_equilibrium(&mut self) {
        if let Some((law, had_rows)) = self.run_settings.take() {
            self.law = law;
            if !had_rows {
                self.disable_damping_rows();
            }
        }
    }

    fn clone_box(&self) -> Box<dyn ForceElement> {
        Box::new(self.clone())
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}
