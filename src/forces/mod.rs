//! Forces: the links' spring-dampers, the roller–tooth contact with its
//! reactions on the sprockets, and whatever further force elements a drive
//! holds — each a [`ForceElement`], composed by one [`ForceGenerator`].
//!
//! [`ForceGenerator::evaluate`] is the one force routine shared by every way
//! of stepping (the plugin's own substepping and rapier's integration). It
//! reads a [`DriveState`] and writes the [`Forces`] — nothing is allocated
//! per call. Gravity on the rollers is included in the roller forces.
//!
//! # The seam: force elements
//!
//! A force element reads the state and adds forces to the outputs: on the
//! rollers, on the sprockets (moments and resultants), on further bodies'
//! coordinates, and rates of scalar states ([`crate::model::BodyModel`],
//! [`crate::model::ScalarModel`]). The links come first and *set* the roller
//! forces (weight plus links); the roller–tooth contact and every further
//! element add to them, in the order they were added. An element with
//! history (the contact's remembered onset speeds) writes its advanced
//! history aside in [`ForceElement::evaluate`] and adopts it in
//! [`ForceElement::commit`], called when the evaluated state has become a
//! step's end: the inner stages of a multi-stage integrator evaluate trial
//! states without committing ([`ForceGenerator::evaluate_trial`],
//! [`ForceGenerator::commit_trial`]). The static equilibrium brackets its
//! relaxation with [`ForceElement::begin_equilibrium`] and
//! [`ForceElement::end_equilibrium`] (the contact switches to a dissipative
//! law there). With timing on, each element's evaluation is timed under its
//! [`ForceElement::name`].
//!
//! A checkpoint keeps each element's history through
//! [`ForceElement::save_history`] and [`ForceElement::restore_history`]
//! (no-ops by default: an element without history needs neither).
//!
//! Adding an element touches its own file, the scene schema and the docs:
//! integrators and observers see only [`Forces`]. See docs/architecture.md,
//! “Adding a force element or a body”.
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

mod buffer;
mod contact;
mod contact_law;
#[cfg(test)]
mod friction_tests;
mod guide;
#[cfg(test)]
mod guides_tests;
pub(crate) mod hydraulic;
mod joint_friction;
mod links;
mod output;
mod rows;
#[cfg(test)]
mod seam_tests;
mod split;
mod tensioner;
#[cfg(test)]
mod tensioners_tests;

pub(crate) use contact::Culling;
pub(crate) use contact::ToothContact;
pub use contact_law::ContactLawParams;
pub(crate) use guide::{GuideElement, ShoeForces};
pub(crate) use joint_friction::JointFrictionElement;
pub(crate) use links::{Kick, Links, kick_drift};
pub use output::Forces;

pub(crate) use rows::DampingRows;
pub(crate) use split::Fork;
pub(crate) use split::{CHUNKS, Halves, chunk};
pub(crate) use tensioner::{ArmAtRest, TensionerArm, TensionerReading};

use std::any::Any;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::model::{DriveModel, DriveState};

/// Whether the CPU has AVX2, where the kernels built for it may run (the
/// check is cached by the standard library).
pub(crate) fn cpu_has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// A force element: one kind of force acting in the drive.
///
/// Implementations write into [`Forces`] only what they add; they keep
/// their own history and outputs as fields, reached through
/// `ForceGenerator::element`. Nothing may be allocated per evaluation.
pub trait ForceElement: std::fmt::Debug + Send + Sync {
    /// Short name, for stage timings (`links`, `contacts`, …).
    fn name(&self) -> &'static str;

    /// Adds the element's forces at `state` to `out`. History advanced by
    /// this evaluation is kept aside until [`Self::commit`].
    fn evaluate(&mut self, model: &DriveModel, state: &DriveState, out: &mut Forces);

    /// Adopts the history of the last evaluation, whose state has become the
    /// step's end state.
    fn commit(&mut self) {}

    /// Forgets all history (the static equilibrium's end, a restart).
    fn reset(&mut self) {}

    /// Forgets what the element keeps only to skip work (a guide's rollers
    /// kept far from it): the next evaluation looks at everything. Called
    /// when the state may have moved other than in time (a Newton iterate,
    /// a co-simulation frame's new mount positions). History stays.
    fn forget_kept(&mut self) {}

    /// The static equilibrium's relaxation begins: switch to what it needs.
    fn begin_equilibrium(&mut self) {}

    /// The relaxation has ended: switch back to the run's settings.
    fn end_equilibrium(&mut self) {}

    /// A run of a scheme that evaluates the forces once a step, at the
    /// step's end, begins (a guide evaluated every k steps starts to).
    fn begin_run(&mut self) {}

    /// Writes what a checkpoint must keep of the element: the history
    /// [`Self::commit`] adopted, and whatever of the last evaluation the next
    /// one reads. The default writes nothing (an element without history).
    fn save_history(&self, _history: &mut History) {}

    /// Takes back, in the same order, what [`Self::save_history`] wrote, so
    /// that the element evaluates as if the run had never stopped (the
    /// [`Forces`] of the last evaluation are restored beside it).
    fn restore_history(&mut self, _history: &mut HistoryReader<'_>) -> Result<(), HistoryError> {
        Ok(())
    }

    /// Whether the element reads each link's angular rate and normal
    /// ([`Forces`]' `link_omega`, `link_normal_x`, `link_normal_y`): when it
    /// does, the links' pass computes them before it from the first
    /// evaluation on. The default asks for nothing (nothing is computed).
    fn wants_link_rates(&self) -> bool {
        false
    }

    /// A boxed copy (a generator is cloned to fork a settled drive).
    fn clone_box(&self) -> Box<dyn ForceElement>;

    /// The element as [`Any`], to reach its own outputs.
    fn as_any(&self) -> &dyn Any;
}

/// A force element's history as a checkpoint keeps it: arrays of numbers,
/// read back in the order they were written ([`ForceElement::save_history`]).
/// Floats are kept bit for bit.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct History {
    floats: Vec<Vec<f64>>,
    words: Vec<Vec<u64>>,
}

impl History {
    /// Appends an array of floats.
    pub fn push_floats(&mut self, values: impl IntoIterator<Item = f64>) {
        self.floats.push(values.into_iter().collect());
    }

    /// Appends an array of integers.
    pub fn push_words(&mut self, values: impl IntoIterator<Item = u64>) {
        self.words.push(values.into_iter().collect());
    }

    /// Reads the arrays back from the first.
    pub fn reader(&self) -> HistoryReader<'_> {
        HistoryReader {
            history: self,
            floats: 0,
            words: 0,
        }
    }
}

/// Reads a [`History`]'s arrays in the order they were written.
#[derive(Debug)]
pub struct HistoryReader<'a> {
    history: &'a History,
    floats: usize,
    words: usize,
}

impl<'a> HistoryReader<'a> {
    /// The next array of floats, which must hold `len` values.
    pub fn floats(&mut self, len: usize) -> Result<&'a [f64], HistoryError> {
        let found = self
            .history
            .floats
            .get(self.floats)
            .ok_or(HistoryError::Missing("float"))?;
        self.floats += 1;
        check_length(found, len)
    }

    /// The next array of integers, which must hold `len` values.
    pub fn words(&mut self, len: usize) -> Result<&'a [u64], HistoryError> {
        let found = self
            .history
            .words
            .get(self.words)
            .ok_or(HistoryError::Missing("integer"))?;
        self.words += 1;
        check_length(found, len)
    }
}

fn check_length<T>(found: &[T], expected: usize) -> Result<&[T], HistoryError> {
    if found.len() == expected {
        Ok(found)
    } else {
        Err(HistoryError::Length {
            found: found.len(),
            expected,
        })
    }
}

/// Why a saved history does not fit an element.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HistoryError {
    /// Fewer arrays than the element reads.
    #[error("it holds fewer {0} arrays than the element reads")]
    Missing(&'static str),
    /// An array of another length (another drive).
    #[error("an array of {found} values where the drive has {expected}")]
    Length {
        /// Values held.
        found: usize,
        /// Values the element needs.
        expected: usize,
    },
}

/// Wall time spent in each force element, when timing is on
/// (`ForceGenerator::timing`).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct ForceTimes {
    /// Force evaluations timed.
    pub evaluations: u64,
    /// Each element's name and its total time, s, in evaluation order.
    pub elements: Vec<(&'static str, f64)>,
}

impl ForceTimes {
    fn add(&mut self, k: usize, name: &'static str, seconds: f64) {
        if let Some(entry) = self.elements.get_mut(k) {
            entry.1 += seconds;
        } else {
            self.elements.push((name, seconds));
        }
    }
}

/// Rollers from which [`ForceGenerator::step_rollers_and_links`] fuses the
/// rollers' update with the links on one thread: below, the two plain
/// passes fit the cache anyway.
pub(crate) const FUSED_MIN_ROLLERS: usize = 1024;

/// The drive's force elements and their outputs: the links, the
/// roller–tooth contact, then any further elements.
#[derive(Debug)]
pub(crate) struct ForceGenerator {
    /// The chain's links (and the rollers' weight).
    pub links: Links,
    /// The roller–tooth contact.
    pub contact: ToothContact,
    /// Further elements, evaluated in this order after the contact.
    elements: Vec<Box<dyn ForceElement>>,
    output: Forces,
    /// Stage timers; `None` (the default) times nothing.
    pub timing: Option<ForceTimes>,
    /// Runs the roller loops on two threads (`None`: one thread).
    fork: Option<Box<dyn Fork>>,
}

impl Clone for ForceGenerator {
    fn clone(&self) -> Self {
        Self {
            links: self.links.clone(),
            contact: self.contact.clone(),
            elements: self.elements.iter().map(|e| e.clone_box()).collect(),
            output: self.output.clone(),
            timing: self.timing.clone(),
            fork: self.fork.as_ref().map(|f| f.clone_box()),
        }
    }
}

impl ForceGenerator {
    /// The links and the contact for `model`'s drive of `rollers` rollers.
    pub(crate) fn new(law: ContactLawParams, model: &DriveModel, rollers: usize) -> Self {
        let sprockets = model.sprockets.len();
        Self {
            links: Links::new(rollers),
            contact: ToothContact::new(law, rollers, sprockets),
            elements: Vec::new(),
            output: Forces::new(rollers, sprockets, model.bodies.len(), model.scalars.len()),
            timing: None,
            fork: None,
        }
    }

    /// Splits the roller loops over two threads where `fork` says so (the
    /// simulation's `sim::parallel::Split`); `None` steps on one thread.
    /// The results are the same bits either way.
    pub(crate) fn set_fork(&mut self, fork: Option<Box<dyn Fork>>) {
        self.fork = fork;
    }

    /// The fork, where it splits a drive of `rollers` rollers.
    pub(crate) fn fork_for(&self, rollers: usize) -> Option<&dyn Fork> {
        self.fork.as_deref().filter(|f| f.splits(rollers))
    }

    /// Adds a further element, evaluated after those already present.
    pub(crate) fn add(&mut self, element: Box<dyn ForceElement>) {
        if element.wants_link_rates() {
            self.links.request_rates(&mut self.output);
        }
        self.elements.push(element);
    }

    /// Sizes the outputs of further bodies and scalar states to `model`'s.
    pub(crate) fn fit(&mut self, model: &DriveModel) {
        self.output.body_force.resize(model.bodies.len(), 0.0);
        self.output.scalar_rate.resize(model.scalars.len(), 0.0);
    }

    /// The further elements of type `T`, in the order they were added.
    pub(crate) fn elements_of<T: ForceElement + 'static>(&self) -> impl Iterator<Item = &T> {
        self.elements
            .iter()
            .filter_map(|e| e.as_any().downcast_ref::<T>())
    }

    /// The further element of type `T`, if the drive has one.
    #[cfg(test)]
    pub(crate) fn element<T: ForceElement + 'static>(&self) -> Option<&T> {
        self.elements
            .iter()
            .find_map(|e| e.as_any().downcast_ref::<T>())
    }

    /// The outputs of the last evaluation.
    pub(crate) fn output(&self) -> &Forces {
        &self.output
    }

    /// The outputs, to add forces from outside the elements (the
    /// co-simulation's user colliders act on the rollers between evaluations).
    pub(crate) fn output_mut(&mut self) -> &mut Forces {
        &mut self.output
    }

    /// Forgets all history of every element (the contact's remembered onsets
    /// and kept reach sets).
    pub(crate) fn reset_memory(&mut self) {
        self.contact.reset();
        for e in &mut self.elements {
            e.reset();
        }
    }

    /// See [`ToothContact::forget_reach`]; every further element forgets
    /// what it keeps to skip work too ([`ForceElement::forget_kept`]).
    pub(crate) fn forget_reach(&mut self) {
        self.contact.forget_reach();
        for e in &mut self.elements {
            e.forget_kept();
        }
    }

    /// Has the links' pass write each link's angular velocity and normal
    /// (`Forces::link_omega`) from the next evaluation on
    /// ([`Links::request_rates`]): what the wear check's sliding count reads
    /// (the joint friction asks for them itself, through
    /// [`ForceElement::wants_link_rates`]). The forces do not change.
    pub(crate) fn want_link_rates(&mut self) {
        self.links.request_rates(&mut self.output);
    }

    /// Records [`DampingRows`] from now on (for the implicit-damping scheme).
    pub(crate) fn enable_damping_rows(&mut self) {
        self.contact.enable_damping_rows();
    }

    /// The contact's damping rows of the last evaluation, if enabled.
    pub(crate) fn damping_rows(&self) -> Option<&DampingRows> {
        self.contact.damping_rows()
    }

    /// Every element switches to what the static equilibrium needs.
    pub(crate) fn begin_equilibrium(&mut self) {
        self.links.begin_equilibrium();
        self.contact.begin_equilibrium();
        for e in &mut self.elements {
            e.begin_equilibrium();
        }
    }

    /// Every element switches back to the run's settings.
    pub(crate) fn end_equilibrium(&mut self) {
        self.links.end_equilibrium();
        self.contact.end_equilibrium();
        for e in &mut self.elements {
            e.end_equilibrium();
        }
    }

    /// Every further element: a run of a scheme that evaluates the forces
    /// once a step, at its end, begins ([`ForceElement::begin_run`]).
    pub(crate) fn begin_run(&mut self) {
        for e in &mut self.elements {
            e.begin_run();
        }
    }

    /// Evaluates all forces at `state`, the end of a step, and advances every
    /// element's history to it.
    pub(crate) fn evaluate(&mut self, model: &DriveModel, state: &DriveState) {
        self.evaluate_trial(model, state);
        self.commit_trial();
    }

    /// Adopts the history of the last [`Self::evaluate_trial`], whose state
    /// has become the step's end state.
    pub(crate) fn commit_trial(&mut self) {
        self.links.commit();
        self.contact.commit();
        for e in &mut self.elements {
            e.commit();
        }
    }

    /// Advances the rollers of `state` by one step under the forces held
    /// (the kick `kick`) and evaluates the links at the new state in the
    /// same pass ([`Links::step_and_evaluate`]), on two threads where the
    /// drive is split, for drives of at least [`FUSED_MIN_ROLLERS`] rollers;
    /// `false`, with nothing done, for smaller ones. Finish the evaluation
    /// with [`Self::evaluate_after_links`]. The sprockets, further bodies
    /// and clock are the caller's.
    pub(crate) fn step_rollers_and_links(
        &mut self,
        model: &DriveModel,
        state: &mut DriveState,
        kick: Kick,
    ) -> bool {
        let n = state.rollers();
        let fork = self.fork.as_deref().filter(|f| f.splits(n));
        if fork.is_none() && n < FUSED_MIN_ROLLERS {
            return false;
        }
        let started = self.timing.is_some().then(Instant::now);
        self.links
            .step_and_evaluate(model, state, &mut self.output, fork, kick);
        if let (Some(times), Some(t0)) = (&mut self.timing, started) {
            times.add(0, self.links.name(), t0.elapsed().as_secs_f64());
        }
        true
    }

    /// The rest of [`Self::evaluate`] after
    /// [`Self::step_rollers_and_links`]: the contact and every further
    /// element at `state`, then every history advanced.
    pub(crate) fn evaluate_after_links(&mut self, model: &DriveModel, state: &DriveState) {
        let out = &mut self.output;
        out.begin();
        if let Some(times) = &mut self.timing {
            times.evaluations += 1;
            let mut lap = Instant::now();
            let mut timed = |k: usize, element: &mut dyn ForceElement| {
                element.evaluate(model, state, out);
                let now = Instant::now();
                times.add(k, element.name(), (now - lap).as_secs_f64());
                lap = now;
            };
            timed(1, &mut self.contact);
            for (k, e) in self.elements.iter_mut().enumerate() {
                timed(k + 2, e.as_mut());
            }
        } else {
            self.contact.evaluate(model, state, out);
            for e in &mut self.elements {
                e.evaluate(model, state, out);
            }
        }
        self.commit_trial();
    }

    /// Evaluates all forces at `state` without advancing any history (an
    /// integrator's inner stage). The outputs are overwritten as by
    /// [`Self::evaluate`].
    pub(crate) fn evaluate_trial(&mut self, model: &DriveModel, state: &DriveState) {
        self.evaluate_stages(model, state, false);
    }

    /// From now on (`keep`) the links and the contact keep, at each
    /// evaluation, what depends on the positions alone, for
    /// [`Self::evaluate_again`]; `false` keeps nothing (the default).
    pub(crate) fn keep_positions(&mut self, keep: bool) {
        self.links.keep_positions(keep);
        self.contact.keep_positions(keep);
    }

    /// [`Self::evaluate`] at `state`, whose positions (rollers, sprocket
    /// angles, further bodies, sprocket centres) are those of the last
    /// evaluation and only velocities (and scalar states) differ: the links
    /// and the contact compute again only what depends on the velocities
    /// ([`Self::keep_positions`]; without it, everything), every further
    /// element its whole evaluation. The same numbers as [`Self::evaluate`].
    pub(crate) fn evaluate_again(&mut self, model: &DriveModel, state: &DriveState) {
        self.evaluate_stages(model, state, true);
        self.commit_trial();
    }

    /// Every element at `state` in order, timed where timing is on; the
    /// links and the contact `again` at the last evaluation's positions.
    fn evaluate_stages(&mut self, model: &DriveModel, state: &DriveState, again: bool) {
        let out = &mut self.output;
        out.begin();
        let fork = self.fork.as_deref().filter(|f| f.splits(state.rollers()));
        let (links_name, contact_name) = (self.links.name(), self.contact.name());
        let links = &mut self.links;
        let mut chain = |out: &mut Forces| match fork {
            Some(f) => links.evaluate_split(model, state, out, f),
            None if again => links.evaluate_again(model, state, out),
            None => links.evaluate(model, state, out),
        };
        let contact = &mut self.contact;
        let mut contacts = |out: &mut Forces| {
            if again {
                contact.evaluate_again(model, state, out);
            } else {
                contact.evaluate(model, state, out);
            }
        };
        let Some(times) = &mut self.timing else {
            chain(out);
            contacts(out);
            for e in &mut self.elements {
                e.evaluate(model, state, out);
            }
            return;
        };
        times.evaluations += 1;
        let mut lap = Instant::now();
        chain(out);
        let now = Instant::now();
        times.add(0, links_name, (now - lap).as_secs_f64());
        lap = now;
        contacts(out);
        let now = Instant::now();
        times.add(1, contact_name, (now - lap).as_secs_f64());
        lap = now;
        for (k, e) in self.elements.iter_mut().enumerate() {
            e.evaluate(model, state, out);
            let now = Instant::now();
            times.add(k + 2, e.name(), (now - lap).as_secs_f64());
            lap = now;
        }
    }

    /// Every element's history (links, contact, then the further elements),
    /// named, for a checkpoint.
    pub(crate) fn save_histories(&self) -> Vec<(String, History)> {
        let elements = [&self.links as &dyn ForceElement, &self.contact]
            .into_iter()
            .chain(self.elements.iter().map(|e| e.as_ref()));
        elements
            .map(|e| {
                let mut h = History::default();
                e.save_history(&mut h);
                (e.name().to_owned(), h)
            })
            .collect()
    }

    /// Takes back [`Self::save_histories`]' output: the elements must be the
    /// same, in the same order. On error, names the element.
    pub(crate) fn restore_histories(
        &mut self,
        saved: &[(String, History)],
    ) -> Result<(), (String, HistoryError)> {
        let count = 2 + self.elements.len();
        if saved.len() != count {
            return Err((
                "force elements".to_owned(),
                HistoryError::Length {
                    found: saved.len(),
                    expected: count,
                },
            ));
        }
        let elements = [&mut self.links as &mut dyn ForceElement, &mut self.contact]
            .into_iter()
            .chain(self.elements.iter_mut().map(|e| e.as_mut()));
        for (e, (name, h)) in elements.zip(saved) {
            if e.name() != name {
                return Err((
                    format!("{name} (the drive has {} there)", e.name()),
                    HistoryError::Missing("element"),
                ));
            }
            e.restore_history(&mut h.reader())
                .map_err(|err| (name.clone(), err))?;
        }
        Ok(())
    }

    /// The outputs, to restore them from a checkpoint.
    pub(crate) fn restore_output(&mut self, output: Forces) {
        self.output = output;
    }

    /// Whether a roller centred at (`x`, `y`) touches any sprocket, the
    /// sprockets at angles `theta` (see [`ToothContact::touches`]).
    pub(crate) fn touches(
        &self,
        model: &DriveModel,
        roller: usize,
        x: f64,
        y: f64,
        theta: &[f64],
    ) -> bool {
        self.contact.touches(model, roller, x, y, theta)
    }
}
