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
mod tests;
