//! Guides: roller contact with a shoe's working face — a fixed guide bar,
//! or a shoe carried by a further body (a tensioner arm) — with the scene's
//! contact law at the guide's own stiffness and restitution and regularised
//! Coulomb friction (docs/model.md, “Guides”).
//!
//! It does not model the rollers' rotation (a roller slides on the shoe: a
//! low μ stands for rolling), wear, or contact between the shoe and the
//! link plates.

mod bar;
mod near;

use std::any::Any;

use bar::{Bar, BarScratch, Rollers, Totals};
use near::Near;

use super::{
    ContactLawParams, ForceElement, Forces, History, HistoryError, HistoryReader, cpu_has_avx2,
};
use crate::geometry::shoe::{Face, FacePoint, Straight};
use crate::model::{DriveModel, DriveState};

/// χ of the guide contact during the static equilibrium's relaxation (the
/// roller–tooth contact's value: a well damped settling).
const RELAXATION_CHI: f64 = 0.75;

/// A further body that carries a shoe: the shoe's pose is its scene pose
/// turned by the body's coordinate `q[body]` about `pivot_m`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Carrier {
    /// Index of the carrying body's coordinate in [`DriveState::q`].
    pub body: usize,
    /// The pivot, m (world).
    pub pivot_m: [f64; 2],
}

/// What a [`GuideElement`] is built from.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct GuideParams {
    /// Name, for outputs.
    pub name: String,
    /// The working face in its scene pose (at q = 0 for a carried shoe).
    pub face: Face,
    /// The normal law: the scene's law with the guide's stiffness and χ.
    pub law: ContactLawParams,
    /// Coulomb coefficient μ (≥ 0).
    pub friction: f64,
    /// Regularisation speed v_s of the friction, m/s (> 0).
    pub slip_speed_m_s: f64,
    /// The carrying body, or `None` for a fixed guide.
    pub carrier: Option<Carrier>,
}

/// The forces of one evaluation on one shoe.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct ShoeForces {
    /// Σ f_n over the rollers in contact, N.
    pub normal_n: f64,
    /// Σ |f_t| over the rollers in contact, N.
    pub friction_n: f64,
    /// Resultant of the rollers' forces on the shoe, N (world).
    pub force_n: [f64; 2],
    /// Their moment on the shoe about its carrier's pivot, N·m (zero for a
    /// fixed guide).
    pub moment_n_m: f64,
    /// Rollers in contact.
    pub contacts: usize,
    /// Deepest penetration, m.
    pub max_penetration_m: f64,
}

/// Roller–shoe contact.
///
/// A roller of radius R_r centred at c meets the face at signed distance s
/// (positive on the working side; [`Face::query`]) with penetration
/// δ = R_r − s > 0, as long as the centre is less than R_r behind the face
/// (deeper, the roller is taken to be on the face's back and ignored). With
/// n̂ the face normal at the closest point and v the roller's velocity
/// relative to the shoe there:
///
/// ```text
/// f_n = K δⁿ (1 + χ δ̇ / δ̇⁻),   δ̇ = −v·n̂,   δ̇⁻ remembered at onset
/// f_t = −μ f_n v_t / √(v_t² + v_s²),   v_t = v·t̂,  t̂ = (−n̂_y, n̂_x)
/// ```
///
/// The friction reaches ±μ f_n smoothly over a few v_s and vanishes at zero
/// slip (no stick: a roller at rest on a sloping shoe creeps).
#[derive(Clone, Debug)]
pub(crate) struct GuideElement {
    params: GuideParams,
    /// The law of the run, kept while the relaxation uses its own.
    run_law: Option<ContactLawParams>,
    roller_radius_m: f64,
    /// Per roller: the remembered χ/δ̇⁻ of a contact, or < 0 for none.
    onset: Vec<f64>,
    /// The same, advanced by the last evaluation (adopted at commit).
    pending: Vec<f64>,
    last: ShoeForces,
    /// The face's fast query, for a straight face without ramps.
    straight: Option<Straight>,
    /// The rollers near a fixed guide (`None` for a carried shoe: every
    /// roller is tested).
    near: Option<Near>,
    /// Scratch of the fixed straight guide's kernel ([`bar`]), sized where
    /// it applies.
    bar: BarScratch,
    /// Steps between the contact's evaluations in a run (1: every step; see
    /// [`GuideElement::every_steps`]).
    configured: u32,
    /// Steps between the evaluations now: `configured` from a run's start
    /// ([`ForceElement::begin_run`]), 1 before it and from a relaxation on.
    every: u32,
    /// Committed steps before the next evaluation is due (0: the next one).
    due: u32,
    /// The time of the last committed evaluation: an evaluation at that
    /// time again (the same state) is one too.
    evaluated_t_s: f64,
    /// The time of the last evaluation that computed the contact, if the
    /// last evaluation did (adopted at commit).
    computed_t_s: Option<f64>,
    /// The elastic energy of the last evaluation, J (held between them).
    held_energy_j: f64,
    /// The largest normal force on one roller at the last evaluation, N.
    largest_normal_n: f64,
}

impl GuideElement {
    /// The element for a chain of `rollers` rollers of radius `roller_radius_m`.
    pub(crate) fn new(params: GuideParams, rollers: usize, roller_radius_m: f64) -> Self {
        Self {
            straight: params.face.straight(),
            near: params.carrier.is_none().then(|| Near::new(rollers)),
            bar: if params.carrier.is_none() && params.face.straight().is_some() {
                BarScratch::new(rollers)
            } else {
                BarScratch::default()
            },
            params,
            run_law: None,
            roller_radius_m,
            onset: vec![-1.0; rollers],
            pending: vec![-1.0; rollers],
            last: ShoeForces::default(),
            configured: 1,
            every: 1,
            due: 0,
            evaluated_t_s: f64::NAN,
            computed_t_s: None,
            held_energy_j: 0.0,
            largest_normal_n: 0.0,
        }
    }

    /// Evaluates the contact at every `every`-th step only, applying its
    /// force as an impulse of `every` steps (`every` times the force at that
    /// step; in between the guide adds nothing, its reported sums and
    /// elastic energy held): the impulse, or r-RESPA, multiple time step
    /// scheme (docs/model.md, “Guides”). From a run's start only
    /// ([`ForceElement::begin_run`], for a scheme that evaluates the forces
    /// once a step, at its end); the static equilibrium evaluates at every
    /// step.
    pub(crate) fn every_steps(mut self, every: u32) -> Self {
        self.configured = every.max(1);
        self
    }

    /// Tests every roller at every evaluation (no kept candidates): the
    /// oracle of the culling test.
    #[cfg(test)]
    pub(crate) fn without_culling(mut self) -> Self {
        self.near = None;
        self
    }

    /// A fixed guide of the scene, on `chain`'s rollers.
    pub(crate) fn fixed(guide: &crate::scene::Guide, chain: &crate::scene::Chain) -> Self {
        Self::new(
            GuideParams {
                name: guide.name.clone(),
                face: guide.face,
                law: ContactLawParams::new(&guide.contact),
                friction: guide.friction,
                slip_speed_m_s: guide.slip_speed_m_s,
                carrier: None,
            },
            chain.rollers,
            chain.roller_radius_m,
        )
        .every_steps(guide.every_steps)
    }

    /// The guide's name.
    pub(crate) fn name(&self) -> &str {
        &self.params.name
    }

    /// Steps between the contact's evaluations in a run.
    pub(crate) fn configured_every(&self) -> u32 {
        self.configured
    }

    /// The largest normal force on one roller at the last evaluation, N.
    pub(crate) fn largest_normal_n(&self) -> f64 {
        self.largest_normal_n
    }

    /// The contact's largest stable interval between evaluations for a
    /// roller of mass `mass_kg` carrying `load_n`, s: the smaller of the
    /// linearised contact's 2/ω, with ω² = k_lin / m and
    /// k_lin = dF/dδ = n F / δ at δ = (F/K)^(1/n), and of m / c, the
    /// damping's c = χ F / δ̇⁻ at the approach-speed floor (taken, as the
    /// explicit damping of `verlet_implicit_damping`, at predicted
    /// velocities: stable for h c / m < 1). ∞ at no load.
    pub(crate) fn stable_interval_s(&self, mass_kg: f64, load_n: f64) -> f64 {
        let law = self.run_law.unwrap_or(self.params.law);
        if !(load_n > 0.0 && mass_kg > 0.0) {
            return f64::INFINITY;
        }
        let depth = (load_n / law.stiffness).powf(1.0 / law.exponent);
        let k_lin = law.exponent * load_n / depth;
        let oscillation = 2.0 / (k_lin / mass_kg).sqrt();
        let c = law.damping_per_speed(0.0) * load_n;
        let damping = if c > 0.0 { mass_kg / c } else { f64::INFINITY };
        oscillation.min(damping)
    }

    /// The forces of the last evaluation.
    #[cfg(test)]
    pub(crate) fn forces(&self) -> &ShoeForces {
        &self.last
    }

    fn expire_near(&mut self) {
        if let Some(near) = &mut self.near {
            near.expire();
        }
    }

    /// The shoe's pose at `state`: its rotation (cos, sin) about the pivot,
    /// and the pivot (the origin for a fixed guide, with no rotation).
    fn pose(&self, state: &DriveState) -> (f64, f64, [f64; 2], f64) {
        match self.params.carrier {
            Some(c) => {
                let q = state.q.get(c.body).copied().unwrap_or(0.0);
                let u = state.u.get(c.body).copied().unwrap_or(0.0);
                let (s, co) = q.sin_cos();
                (co, s, c.pivot_m, u)
            }
            None => (1.0, 0.0, [0.0, 0.0], 0.0),
        }
    }
}

impl ForceElement for GuideElement {
    fn name(&self) -> &'static str {
        "guides"
    }

    fn evaluate(&mut self, _model: &DriveModel, s: &DriveState, out: &mut Forces) {
        if self.every > 1 && self.due > 0 && s.t_s != self.evaluated_t_s {
            // Between evaluations: nothing added, the sums held.
            self.computed_t_s = None;
            out.contact_energy_j += self.held_energy_j;
            out.max_penetration_m = out.max_penetration_m.max(self.last.max_penetration_m);
            out.shoes.push(self.last);
            return;
        }
        self.computed_t_s = Some(s.t_s);
        let sums = self.contact(s, out);
        out.shoes.push(sums);
    }

    fn commit(&mut self) {
        let Some(t_s) = self.computed_t_s else {
            self.due = self.due.saturating_sub(1);
            return;
        };
        self.due = self.every - 1;
        self.evaluated_t_s = t_s;
        self.onset.copy_from_slice(&self.pending);
        if let Some(near) = &mut self.near {
            near.commit();
        }
    }

    fn save_history(&self, history: &mut History) {
        history.push_floats(self.onset.iter().copied());
        history.push_floats(self.pending.iter().copied());
        if self.configured > 1 {
            // The schedule and what is held between evaluations.
            history.push_words([u64::from(self.due)]);
            history.push_floats([self.evaluated_t_s, self.held_energy_j]);
            history.push_floats(self.held_sums());
        }
    }

    fn restore_history(&mut self, history: &mut HistoryReader<'_>) -> Result<(), HistoryError> {
        let onset = history.floats(self.onset.len())?;
        self.onset.copy_from_slice(onset);
        let pending = history.floats(self.pending.len())?;
        self.pending.copy_from_slice(pending);
        if self.configured > 1 {
            self.due = history.words(1)?[0].min(u64::from(self.configured - 1)) as u32;
            let [t_s, energy_j] = history.floats(2)?.try_into().unwrap_or([f64::NAN, 0.0]);
            (self.evaluated_t_s, self.held_energy_j) = (t_s, energy_j);
            let sums = history.floats(HELD_SUMS)?;
            self.hold_sums(sums);
        }
        self.expire_near();
        Ok(())
    }

    fn reset(&mut self) {
        self.onset.fill(-1.0);
        self.pending.fill(-1.0);
        self.due = 0;
        self.evaluated_t_s = f64::NAN;
        self.expire_near();
    }

    fn forget_kept(&mut self) {
        self.expire_near();
    }

    fn begin_equilibrium(&mut self) {
        let run = *self.run_law.get_or_insert(self.params.law);
        self.params.law = run.with_chi(RELAXATION_CHI);
        (self.every, self.due) = (1, 0);
        self.expire_near();
    }

    fn end_equilibrium(&mut self) {
        if let Some(law) = self.run_law.take() {
            self.params.law = law;
        }
        self.expire_near();
    }

    fn begin_run(&mut self) {
        (self.every, self.due) = (self.configured, 0);
        self.evaluated_t_s = f64::NAN;
    }

    fn clone_box(&self) -> Box<dyn ForceElement> {
        Box::new(self.clone())
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}

impl GuideElement {
    /// The contact kernel: adds each touching roller's force to `out`, the
    /// contacts' energy and damping power, the moment on a carrier's body
    /// coordinate and the deepest penetration, and returns the shoe's sums
    /// (without listing them in [`Forces::shoes`]: a [`GuideElement`] element does
    /// that, a tensioner arm reports its shoe itself).
    pub(crate) fn contact(&mut self, s: &DriveState, out: &mut Forces) -> ShoeForces {
        let (cos_q, sin_q, pivot, omega) = self.pose(s);
        let face = &self.params.face;
        let law = self.params.law;
        let (mu, v_s) = (self.params.friction, self.params.slip_speed_m_s);
        let r = self.roller_radius_m;
        let [x0, y0, x1, y1] = face.bounds_m;
        // The impulse's weight: the force of `every` steps (1.0 × f = f).
        let weight = f64::from(self.every);
        let mut largest_normal = 0.0f64;
        let mut sums = ShoeForces::default();
        let (mut energy, mut damping_power) = (0.0, 0.0);
        let n = [
            s.y.len(),
            s.vx.len(),
            s.vy.len(),
            out.fx.len(),
            out.fy.len(),
        ]
        .into_iter()
        .fold(s.x.len().min(self.onset.len()), usize::min);
        // Slices of one length: no bounds checks in the loop.
        let (xs, ys, vxs, vys) = (&s.x[..n], &s.y[..n], &s.vx[..n], &s.vy[..n]);
        let (onset, pending) = (&self.onset[..n], &mut self.pending[..n]);
        let (fxs, fys) = (&mut out.fx[..n], &mut out.fy[..n]);
        // A fixed guide looks at the rollers near it only, in roller order.
        let candidates = match &mut self.near {
            Some(near) => {
                let bounds = [x0 - r, y0 - r, x1 + r, y1 + r];
                let v_max = out.max_roller_speed_m_s;
                Some(near.candidates(s.t_s, xs, ys, bounds, r, v_max, pending))
            }
            None => None,
        };
        // A fixed straight guide: the branch-free kernel, run by run.
        if let (Some(runs), Some(face)) = (candidates, self.straight)
            && self.bar.hit.len() == n
        {
            let bar = Bar {
                face,
                law,
                friction: (mu, v_s),
                radius_m: r,
                bounds_m: [x0, y0, x1, y1],
                weight,
            };
            let avx2 = cpu_has_avx2();
            for &[a, b] in runs {
                let rollers = Rollers {
                    x: &xs[a..b],
                    y: &ys[a..b],
                    vx: &vxs[a..b],
                    vy: &vys[a..b],
                    onset: &onset[a..b],
                    pending: &mut pending[a..b],
                    fx: &mut fxs[a..b],
                    fy: &mut fys[a..b],
                };
                let totals = Totals {
                    sums: &mut sums,
                    energy: &mut energy,
                    damping_power: &mut damping_power,
                    largest_normal: &mut largest_normal,
                };
                bar::run(&bar, rollers, &mut self.bar, avx2, totals);
            }
            self.largest_normal_n = largest_normal;
            return self.finish(out, sums, energy, damping_power);
        }
        let straight = self.straight;
        let query = |p: [f64; 2]| -> Option<FacePoint> {
            match &straight {
                Some(f) => f.query(p),
                None => face.query(p),
            }
        };
        let mut roller = |i: usize| {
            pending[i] = -1.0;
            // Into the shoe's frame: p_l = pivot + R(−q)(p − pivot).
            let (dx, dy) = (xs[i] - pivot[0], ys[i] - pivot[1]);
            let px = pivot[0] + cos_q * dx + sin_q * dy;
            let py = pivot[1] - sin_q * dx + cos_q * dy;
            if px < x0 - r || px > x1 + r || py < y0 - r || py > y1 + r {
                return;
            }
            let Some(hit) = query([px, py]) else {
                return;
            };
            let depth = r - hit.distance_m;
            if !(depth > 0.0) || depth >= 2.0 * r {
                return;
            }
            // The roller's velocity relative to the shoe, in the shoe's frame:
            // R(−q)(v − ω × (p − pivot)).
            let (vwx, vwy) = (vxs[i] + omega * dy, vys[i] - omega * dx);
            let vx = cos_q * vwx + sin_q * vwy;
            let vy = -sin_q * vwx + cos_q * vwy;
            let [nx, ny] = hit.normal;
            let rate = -(vx * nx + vy * ny);
            let damping = if onset[i] >= 0.0 {
                onset[i]
            } else {
                law.damping_per_speed(rate)
            };
            pending[i] = damping;
            // The law's `force_with`, its elastic part kept for the energy.
            let elastic = law.elastic(depth);
            let f_n = (elastic * (1.0 + damping * rate)).max(0.0);
            let v_t = -vx * ny + vy * nx;
            let f_t = -mu * f_n * v_t / (v_t * v_t + v_s * v_s).sqrt();
            // Force on the roller in the shoe's frame, then in the world.
            let (flx, fly) = (f_n * nx - f_t * ny, f_n * ny + f_t * nx);
            let fx = cos_q * flx - sin_q * fly;
            let fy = sin_q * flx + cos_q * fly;
            fxs[i] += weight * fx;
            fys[i] += weight * fy;
            // Its reaction on the shoe at the contact point (world).
            let (cx, cy) = (hit.point_m[0] - pivot[0], hit.point_m[1] - pivot[1]);
            let (cwx, cwy) = (cos_q * cx - sin_q * cy, sin_q * cx + cos_q * cy);
            sums.moment_n_m -= cwx * fy - cwy * fx;
            sums.force_n[0] -= fx;
            sums.force_n[1] -= fy;
            sums.normal_n += f_n;
            largest_normal = largest_normal.max(f_n);
            sums.friction_n += f_t.abs();
            sums.contacts += 1;
            sums.max_penetration_m = sums.max_penetration_m.max(depth);
            energy += elastic * depth / (law.exponent + 1.0);
            damping_power += (f_n - elastic) * -rate + f_t * v_t;
        };
        match candidates {
            Some(runs) => runs.iter().flat_map(|&[a, b]| a..b).for_each(roller),
            None => (0..n).for_each(&mut roller),
        }
        self.largest_normal_n = largest_normal;
        self.finish(out, sums, energy, damping_power)
    }

    /// Adds the shoe's sums to `out` and keeps them as the last forces.
    fn finish(
        &mut self,
        out: &mut Forces,
        mut sums: ShoeForces,
        energy: f64,
        damping_power: f64,
    ) -> ShoeForces {
        out.contact_energy_j += energy;
        // The damping's work over the impulse's steps (1.0 × p = p).
        out.contact_damping_power_w += f64::from(self.every) * damping_power;
        self.held_energy_j = energy;
        match self.params.carrier {
            Some(c) => {
                if let Some(q) = out.body_force.get_mut(c.body) {
                    *q += sums.moment_n_m;
                }
            }
            None => sums.moment_n_m = 0.0,
        }
        out.max_penetration_m = out.max_penetration_m.max(sums.max_penetration_m);
        self.last = sums;
        sums
    }

    /// The held sums as floats, for a checkpoint.
    fn held_sums(&self) -> [f64; HELD_SUMS] {
        let l = &self.last;
        [
            l.normal_n,
            l.friction_n,
            l.force_n[0],
            l.force_n[1],
            l.moment_n_m,
            l.contacts as f64,
            l.max_penetration_m,
        ]
    }

    /// Takes back [`Self::held_sums`]' output.
    fn hold_sums(&mut self, v: &[f64]) {
        if let [
            normal_n,
            friction_n,
            fx,
            fy,
            moment_n_m,
            contacts,
            max_penetration_m,
        ] = *v
        {
            self.last = ShoeForces {
                normal_n,
                friction_n,
                force_n: [fx, fy],
                moment_n_m,
                contacts: contacts as usize,
                max_penetration_m,
            };
        }
    }
}

/// Floats of the held sums in a checkpoint.
const HELD_SUMS: usize = 7;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::shoe::{Ramp, body_from_radius};
    use crate::model::DriveModel;
    use crate::scene::{Contact, ContactLaw, Scene};

    fn law(k: f64, e: f64) -> ContactLawParams {
        ContactLawParams::new(&Contact {
            law: ContactLaw::HuntCrossley,
            stiffness: k,
            exponent: 1.5,
            restitution: e,
            min_approach_speed_m_s: 0.05,
        })
    }

    /// A model and a state of `n` rollers, all at the origin at rest, except
    /// those the test places.
    fn drive(n: usize) -> (DriveModel, DriveState) {
        let scene = Scene::l60mc();
        let (model, mut state, _) = DriveModel::build(&scene).unwrap();
        state.x.truncate(n);
        state.y.truncate(n);
        state.vx.truncate(n);
        state.vy.truncate(n);
        state.x.fill(10.0);
        state.y.fill(10.0);
        state.vx.fill(0.0);
        state.vy.fill(0.0);
        (model, state)
    }

    fn flat(carrier: Option<Carrier>, mu: f64) -> GuideElement {
        // Face y = 0, x ∈ [0, 1], working side above, ramps of 5 cm at 0.1 rad.
        let body = body_from_radius([0.0, 0.0], [1.0, 0.0], None).unwrap();
        let ramp = Ramp {
            length_m: 0.05,
            angle_rad: 0.1,
        };
        let face = Face::new(body, 1.0, Some(ramp), Some(ramp));
        GuideElement::new(
            GuideParams {
                name: "g".into(),
                face,
                law: law(1e9, 1.0),
                friction: mu,
                slip_speed_m_s: 0.01,
                carrier,
            },
            3,
            0.01,
        )
    }

    #[test]
    fn a_resting_roller_gets_the_elastic_force_along_the_normal() {
        // Roller of R_r = 10 mm, centre 9 mm above the face: δ = 1 mm,
        // f = K δ^1.5 = 1e9 · (1e-3)^1.5 = 31 622.8 N, straight up, e = 1.
        let (model, mut state) = drive(3);
        state.x[1] = 0.5;
        state.y[1] = 0.009;
        let mut out = Forces::new(3, 0, 0, 0);
        let mut g = flat(None, 0.3);
        g.evaluate(&model, &state, &mut out);
        let f = 1e9 * 1e-3f64.powf(1.5);
        assert!((out.fy[1] - f).abs() < 1e-6 * f, "{}", out.fy[1]);
        assert!(out.fx[1].abs() < 1e-9, "no slip, no friction");
        assert_eq!(g.forces().contacts, 1);
        assert!((g.forces().force_n[1] + f).abs() < 1e-6 * f);
        assert_eq!(out.fy[0], 0.0);
    }

    #[test]
    fn friction_saturates_at_mu_times_the_normal_force() {
        // Sliding at 1 m/s ≫ v_s = 0.01: |f_t| = μ f_n / √(1 + 1e-4) ≈ μ f_n
        // (within 5e-5), against the sliding direction.
        let (model, mut state) = drive(3);
        state.x[1] = 0.5;
        state.y[1] = 0.009;
        state.vx[1] = 1.0;
        let mut out = Forces::new(3, 0, 0, 0);
        let mut g = flat(None, 0.3);
        g.evaluate(&model, &state, &mut out);
        let f = 1e9 * 1e-3f64.powf(1.5);
        assert!(
            (out.fx[1] + 0.3 * f).abs() < 5e-5 * 0.3 * f,
            "{}",
            out.fx[1]
        );
        assert!((g.forces().friction_n - 0.3 * f).abs() < 5e-5 * 0.3 * f);
    }

    #[test]
    fn a_carried_shoe_turns_with_its_body_and_feels_the_moment() {
        // The flat shoe on a body turned by +90° about the origin: its face
        // is then x = 0 for y ∈ [0, 1] with the working side at x < 0. A
        // roller at (−9 mm, 0.5) presses it with f = K δ^1.5 in −x; the
        // moment of the reaction (+f in x at (0, 0.5)) about the origin is
        // −0.5 f.
        let (model, mut state) = drive(3);
        state.q = vec![std::f64::consts::FRAC_PI_2];
        state.u = vec![0.0];
        state.x[1] = -0.009;
        state.y[1] = 0.5;
        let mut out = Forces::new(3, 0, 1, 0);
        let mut g = flat(
            Some(Carrier {
                body: 0,
                pivot_m: [0.0, 0.0],
            }),
            0.0,
        );
        g.evaluate(&model, &state, &mut out);
        let f = 1e9 * 1e-3f64.powf(1.5);
        assert!((out.fx[1] + f).abs() < 1e-6 * f, "{}", out.fx[1]);
        assert!(out.fy[1].abs() < 1e-6 * f);
        assert!(
            (out.body_force[0] + 0.5 * f).abs() < 1e-6 * f,
            "{}",
            out.body_force[0]
        );
    }

    #[test]
    fn the_onset_speed_is_remembered_until_separation() {
        // Approach at 0.5 m/s at δ = 1 mm: f = K δ^1.5 (1 + χ) with
        // Hunt–Crossley χ = 1.5 (1 − e) = 0.75 at e = 0.5. Committed, a later
        // evaluation at 0.25 m/s damps with the remembered 0.5 m/s:
        // f = K δ^1.5 (1 + 0.75 · 0.5).
        let (model, mut state) = drive(3);
        state.x[1] = 0.5;
        state.y[1] = 0.009;
        state.vy[1] = -0.5;
        let mut out = Forces::new(3, 0, 0, 0);
        let mut g = flat(None, 0.0);
        g.params.law = law(1e9, 0.5);
        g.evaluate(&model, &state, &mut out);
        let k = 1e9 * 1e-3f64.powf(1.5);
        assert!((out.fy[1] - k * 1.75).abs() < 1e-6 * k);
        g.commit();
        state.vy[1] = -0.25;
        let mut out = Forces::new(3, 0, 0, 0);
        g.evaluate(&model, &state, &mut out);
        assert!((out.fy[1] - k * 1.375).abs() < 1e-6 * k, "{}", out.fy[1]);
        // Apart: forgotten.
        state.y[1] = 0.02;
        g.evaluate(&model, &state, &mut out);
        g.commit();
        assert!(g.onset[1] < 0.0);
    }

    /// One roller of mass `m` (roller 1 of [`drive`]) stepped by symplectic
    /// Euler at `h` under gravity `g` (downwards) and the flat guide `g_el`
    /// from height `y0` at vertical speed `v0`, for `steps` steps; `each`
    /// sees the state after every step (penetration, vertical speed).
    #[allow(clippy::too_many_arguments)]
    fn drop_on(
        g_el: &mut GuideElement,
        m: f64,
        g: f64,
        h: f64,
        y0: f64,
        v0: f64,
        steps: usize,
        mut each: impl FnMut(f64, f64),
    ) {
        let (model, mut state) = drive(3);
        state.x[1] = 0.5;
        state.y[1] = y0;
        state.vy[1] = v0;
        state.t_s = 0.0;
        g_el.begin_run();
        let mut out = Forces::new(3, 0, 0, 0);
        g_el.evaluate(&model, &state, &mut out);
        g_el.commit();
        for step in 1..=steps {
            state.vy[1] += h * (out.fy[1] / m - g);
            state.y[1] += h * state.vy[1];
            state.t_s = step as f64 * h;
            out = Forces::new(3, 0, 0, 0);
            g_el.evaluate(&model, &state, &mut out);
            g_el.commit();
            each(0.01 - state.y[1], state.vy[1]);
        }
    }

    #[test]
    fn every_kth_step_adds_k_times_the_force_and_nothing_between() {
        // A roller held at δ = 1 mm: over any k consecutive steps the guide
        // adds k·f once (the impulse k h f of k steps) and nothing at the
        // others, while its reported sums stay f.
        let (model, mut state) = drive(3);
        state.x[1] = 0.5;
        state.y[1] = 0.009;
        let f = 1e9 * 1e-3f64.powf(1.5);
        let k = 7;
        let mut g = flat(None, 0.3).every_steps(k);
        g.begin_run();
        let mut added = Vec::new();
        for step in 0..3 * k {
            state.t_s = f64::from(step) * 1e-6;
            let mut out = Forces::new(3, 0, 0, 0);
            g.evaluate(&model, &state, &mut out);
            // Evaluated again at the same state: the same forces.
            let mut again = Forces::new(3, 0, 0, 0);
            g.evaluate(&model, &state, &mut again);
            assert_eq!(out.fy, again.fy);
            g.commit();
            added.push(out.fy[1]);
            assert!((out.shoes[0].normal_n - f).abs() < 1e-6 * f);
        }
        for window in added.windows(k as usize) {
            let sum: f64 = window.iter().sum();
            assert!((sum - f64::from(k) * f).abs() < 1e-9 * f, "{window:?}");
            assert_eq!(window.iter().filter(|&&v| v == 0.0).count(), k as usize - 1);
        }
    }

    #[test]
    fn an_elastic_bounce_every_tenth_step_keeps_its_energy_and_hertz_depth() {
        // e = 1 (no damping): a roller of m = 50 g meeting the face at
        // v₀ = 0.1 m/s rebounds at v₀ and reaches the Hertz depth
        // δ_max = (5 m v₀² / (4 K))^(2/5) (½ m v₀² = 2/5 K δ^(5/2)), with the
        // guide evaluated every 10 steps of 1 µs (10 µs, about a 47th of the
        // contact's 0.47 ms). Tolerances: speed 0.5 %, depth 1 %.
        let (m, v0, k) = (0.05f64, 0.1, 1e9);
        let expected = (5.0 * m * v0 * v0 / (4.0 * k)).powf(0.4);
        for every in [1, 10] {
            let mut g = flat(None, 0.0).every_steps(every);
            let (mut deepest, mut last_v) = (0.0f64, 0.0);
            drop_on(&mut g, m, 0.0, 1e-6, 0.0101, -v0, 2000, |d, v| {
                deepest = deepest.max(d);
                last_v = v;
            });
            assert!(
                (last_v - v0).abs() < 5e-3 * v0,
                "every {every}: rebound {last_v} m/s"
            );
            assert!(
                (deepest - expected).abs() < 1e-2 * expected,
                "every {every}: depth {deepest} m, Hertz {expected} m"
            );
        }
    }

    #[test]
    fn a_roller_resting_under_load_settles_to_the_hertz_depth() {
        // m g = 0.4905 N on the face (K = 1e9, e = 0.1): at rest δ = (m g /
        // K)^(2/3) = 0.622 µm, with the guide evaluated every 10 µs (a
        // 130th of the contact's period at that load). Mean over the last
        // 10 ms of 0.3 s, within 0.5 %.
        let (m, grav) = (0.05f64, 9.81);
        let expected = (m * grav / 1e9).powf(2.0 / 3.0);
        let mut g = flat(None, 0.0).every_steps(10);
        g.params.law = law(1e9, 0.1);
        let (mut sum, mut count) = (0.0, 0);
        let steps = 300_000;
        let mut step = 0;
        drop_on(&mut g, m, grav, 1e-6, 0.01, 0.0, steps, |d, _| {
            step += 1;
            if step > steps - 10_000 {
                sum += d;
                count += 1;
            }
        });
        let mean = sum / f64::from(count);
        assert!(
            (mean - expected).abs() < 5e-3 * expected,
            "mean depth {mean} m, Hertz {expected} m"
        );
    }

    #[test]
    fn guide_culling_changes_nothing() {
        // Oracle: a fixed guide that tests only the rollers kept near it
        // gives the bits of one that tests every roller, for a straight
        // face (its fast query) and one with ramps (the general query).
        // 300 rollers drift across the face's box and back at up to 3 m/s
        // (one in seven at up to 60 m/s),
        // some resting on it, with trial evaluations between the committed
        // ones; the fastest speed is the links' report, as in a run.
        let n = 300;
        let (model, mut state) = drive(3);
        for v in [&mut state.x, &mut state.y, &mut state.vx, &mut state.vy] {
            v.resize(n, 0.0);
        }
        let ramp = Ramp {
            length_m: 0.05,
            angle_rad: 0.1,
        };
        let bar = body_from_radius([0.0, 0.0], [1.0, 0.0], None).unwrap();
        for ramps in [None, Some(ramp)] {
            let face = Face::new(bar, 1.0, ramps, ramps);
            assert_eq!(face.straight().is_some(), ramps.is_none());
            let params = GuideParams {
                name: "g".into(),
                face,
                law: law(1e9, 0.5),
                friction: 0.3,
                slip_speed_m_s: 0.01,
                carrier: None,
            };
            let mut culled = GuideElement::new(params.clone(), n, 0.01);
            let mut every = GuideElement::new(params, n, 0.01).without_culling();
            // Deterministic scatter: x ∈ [−0.6, 1.6], y ∈ [−0.04, 0.06].
            let mut seed = 0x2545_f491_4f6c_dd1du64;
            let mut next = || {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                (seed >> 11) as f64 / (1u64 << 53) as f64
            };
            for i in 0..n {
                state.x[i] = -0.6 + 2.2 * next();
                state.y[i] = if i % 5 == 0 {
                    0.009
                } else {
                    -0.04 + 0.1 * next()
                };
                // Some fast enough to cross the kept margin within the
                // longest skip: the speed bound, not the margin, keeps them.
                let top = if i % 7 == 0 { 60.0 } else { 3.0 };
                let (speed, angle) = (top * next(), std::f64::consts::TAU * next());
                (state.vx[i], state.vy[i]) = (speed * angle.cos(), speed * angle.sin());
            }
            state.t_s = 0.0;
            let dt = 2e-5;
            let mut in_contact = 0;
            for step in 0..3000 {
                let v_max = (0..n)
                    .map(|i| state.vx[i].hypot(state.vy[i]))
                    .fold(0.0, f64::max);
                let evaluate = |g: &mut GuideElement, state: &DriveState| {
                    let mut out = Forces::new(n, 0, 0, 0);
                    out.max_roller_speed_m_s = v_max;
                    g.evaluate(&model, state, &mut out);
                    out
                };
                if step % 3 == 0 {
                    // A trial stage half a step on, not committed.
                    let mut trial = state.clone();
                    trial.t_s += 0.5 * dt;
                    for i in 0..n {
                        trial.x[i] += 0.5 * dt * trial.vx[i];
                        trial.y[i] += 0.5 * dt * trial.vy[i];
                    }
                    let (a, b) = (evaluate(&mut culled, &trial), evaluate(&mut every, &trial));
                    assert_eq!(a.fx, b.fx);
                    assert_eq!(a.fy, b.fy);
                }
                let (a, b) = (evaluate(&mut culled, &state), evaluate(&mut every, &state));
                assert_eq!(a.fx, b.fx, "step {step}");
                assert_eq!(a.fy, b.fy, "step {step}");
                assert_eq!(a.contact_energy_j, b.contact_energy_j);
                assert_eq!(a.contact_damping_power_w, b.contact_damping_power_w);
                assert_eq!(culled.forces(), every.forces());
                in_contact += culled.forces().contacts;
                culled.commit();
                every.commit();
                assert_eq!(culled.onset, every.onset);
                // Drift on; turn back at the scatter's edges.
                state.t_s += dt;
                for i in 0..n {
                    if !(-0.6..=1.6).contains(&state.x[i]) {
                        state.vx[i] = -state.vx[i];
                    }
                    if !(-0.04..=0.06).contains(&state.y[i]) {
                        state.vy[i] = -state.vy[i];
                    }
                    state.x[i] += dt * state.vx[i];
                    state.y[i] += dt * state.vy[i];
                }
            }
            assert!(in_contact > 10_000, "{in_contact} contacts seen");
        }
    }
}
