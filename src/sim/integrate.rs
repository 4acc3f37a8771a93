//! The chain's integrators, on the structure-of-arrays state.
//!
//! | scheme | order | force evaluations per step | largest stable step, paper's drive (measured) |
//! |---|---|---|---|
//! | `symplectic_euler` | 1 | 1 | 57 µs (the links) |
//! | `velocity_verlet` | 2 | 2 | 57 µs |
//! | `rk4` | 4 | 4 | 85 µs |
//! | `dormand_prince45` | 5(4) | 6 per trial step + located events | chosen by the error estimate (stable at every cap up to 128 µs) |
//! | `implicit_damping` | 1 | 1 | 57 µs, and still 57 µs where the contact damping limits symplectic Euler (17 µs on a 10-sprocket drive) |
//! | `verlet_implicit_damping` | 2 | 1 | the links' 57 µs; with joint friction half its explicit limit (module `verlet`) |
//!
//! (`chaindrive bench stress` measures these; the estimates of docs/model.md,
//! “Time scales and stability”, are 60 µs for the links and 19 µs for the
//! contact damping at the approach-speed floor, the latter far too pessimistic
//! over real runs.)
//!
//! Every scheme leaves the force generator holding the forces at the step's
//! end state with the contact memory advanced to it (the invariant
//! [`super::Simulation::step`] relies on). Inner stages use
//! [`ForceGenerator::evaluate_trial`]. Nothing is allocated per step: the
//! stage buffers live in [`Integration`].
//!
//! # The driver
//!
//! The driver's angle integrates its speed law dθ/dt = ω(t, θ) (θ enters
//! through the speed harmonics); its speed is set to the law's value at
//! every stage's time and angle, so the Runge–Kutta schemes integrate it at
//! their own order. Symplectic Euler, implicit damping and velocity Verlet
//! take the explicit midpoint rule (second order); without harmonics it
//! samples the law at the step's midpoint, so a linear ramp is integrated
//! exactly.
//!
//! # Implicit damping
//!
//! The Lankarani–Nikravesh damping coefficient of a contact is
//! c = χ K δⁿ / δ̇⁻; a contact begun at the approach-speed floor makes c so
//! large that explicit schemes need dt < 2 m_r / c (docs/model.md,
//! “Guards” and “Time scales and stability”).
//! `implicit_damping` is symplectic Euler with the contact damping force
//! evaluated at the *new* velocity: per roller the 2×2 system
//! `(m I + h C) v' = m v + h (F_rest + C v_sp)` (see
//! [`crate::forces::DampingRows`]), which backward Euler makes unconditionally
//! stable for any c. The ≥ 0 clamp of the contact force is applied to the
//! solved force. The sprockets see the implicit damping force's reaction;
//! their speeds in v_sp are the step's start values (a sprocket is ≥ 5
//! roller masses heavier than a roller here; its coupling stays explicit).
//! The links' damping stays explicit: at up to 1 % of the single-link critical
//! damping its explicit limit (≈ m_r / (2 D) ≥ 1.5 ms) is far above the links'
//! own stiffness limit.
//!
//! # The adaptive scheme
//!
//! Dormand–Prince 5(4) (FSAL, local extrapolation) with a step controller on
//! the max-norm of the embedded error estimate. The error of each component
//! is measured against `tolerance` times a scale chosen for what matters in a
//! chain: positions against the static link stretch T₀/K (a position error
//! of the stretch's size is a 100 % force error, even though it is 1e-5 of
//! the coordinates), velocities against that stretch times √(K/m_r), sprocket
//! angles and speeds against the same divided by the pitch radius.
//! `solver.dt_s` caps the step and is the sample step.
//!
//! Contact events are located: when the set of rollers touching a sprocket
//! changes across a trial step, the earliest change is found by bisection on
//! the cubic Hermite interpolant of the roller's and sprockets' positions
//! (to 0.1 % of the step), and the step is retaken to end just after it. The
//! onset's approach speed δ̇⁻ is then sampled where the contact begins, not up
//! to a step later. Separation by the force clamp (damping cancelling the
//! elastic force while δ > 0) is not located.

mod verlet;

use super::stepper::{advance_extras, driver_speed};
use super::{Relaxation, SimError};
use crate::forces::ForceGenerator;
use crate::model::{DriveModel, DriveState};
use crate::scene::Integrator;

/// Counters of the integration work done.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub(crate) struct IntegrationStats {
    /// Accepted integration steps (internal steps of the adaptive scheme).
    pub steps: u64,
    /// Rejected trial steps (error too large).
    pub rejected: u64,
    /// Steps shortened to end at a located contact event.
    pub events: u64,
    /// Force evaluations.
    pub evaluations: u64,
}

/// Dormand–Prince 5(4) tableau.
mod dp45 {
    pub(super) const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
    pub(super) const A: [[f64; 6]; 7] = [
        [0.0; 6],
        [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
        [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
        [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
        [
            19372.0 / 6561.0,
            -25360.0 / 2187.0,
            64448.0 / 6561.0,
            -212.0 / 729.0,
            0.0,
            0.0,
        ],
        [
            9017.0 / 3168.0,
            -355.0 / 33.0,
            46732.0 / 5247.0,
            49.0 / 176.0,
            -5103.0 / 18656.0,
            0.0,
        ],
        [
            35.0 / 384.0,
            0.0,
            500.0 / 1113.0,
            125.0 / 192.0,
            -2187.0 / 6784.0,
            11.0 / 84.0,
        ],
    ];
    /// Fifth-order weights (= the last row of A: FSAL; checked in the tests).
    #[cfg(test)]
    pub const B: [f64; 7] = [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
        0.0,
    ];
    /// B minus the fourth-order weights: the error estimate's weights.
    pub(super) const E: [f64; 7] = [
        35.0 / 384.0 - 5179.0 / 57600.0,
        0.0,
        500.0 / 1113.0 - 7571.0 / 16695.0,
        125.0 / 192.0 - 393.0 / 640.0,
        -2187.0 / 6784.0 + 92097.0 / 339200.0,
        11.0 / 84.0 - 187.0 / 2100.0,
        -1.0 / 40.0,
    ];
}

/// Smallest step the adaptive scheme may take, s, before it gives up.
const MIN_STEP_S: f64 = 1e-12;

/// An integrator with its reused buffers.
#[derive(Clone, Debug)]
pub(crate) struct Integration {
    scheme: Integrator,
    tolerance: f64,
    /// Stage rates k_j (a `DriveState` whose fields hold time derivatives).
    k: Vec<DriveState>,
    /// The step's start state.
    start: DriveState,
    /// Which rollers touched a sprocket at the step's start.
    touching_start: Vec<bool>,
    /// Scratch: sprocket angles at an interpolated time.
    theta_scratch: Vec<f64>,
    /// Scratch: chain torque on each sprocket (implicit damping).
    torque_scratch: Vec<f64>,
    /// Scratch: the scalar states' rates at the step's start (velocity Verlet).
    rate_scratch: Vec<f64>,
    /// Scratch: the solved contact damping's changes, (roller, sprocket,
    /// lever, Δf) (`verlet_implicit_damping`).
    damping_changes: Vec<(usize, usize, [f64; 2], [f64; 2])>,
    /// Scratch: the rollers' predicted velocities the forces were evaluated
    /// at (`verlet_implicit_damping`).
    predicted_vx: Vec<f64>,
    predicted_vy: Vec<f64>,
    /// Error scales per state field: x/y, vx/vy, and per sprocket θ, ω.
    scale_position_m: f64,
    scale_speed_m_s: f64,
    scale_theta: Vec<f64>,
    scale_omega: Vec<f64>,
    /// The adaptive scheme's proposed next step, s.
    next_step_s: f64,
    /// Work counters.
    pub stats: IntegrationStats,
}

impl Integration {
    /// Buffers for `model`'s drive. `forces` is switched to record what the
    /// scheme needs (damping rows for `implicit_damping`).
    pub(crate) fn new(
        scheme: Integrator,
        tolerance: f64,
        model: &DriveModel,
        state: &DriveState,
        forces: &mut ForceGenerator,
        static_stretch_m: f64,
    ) -> Self {
        let stages = match scheme {
            Integrator::SymplecticEuler
            | Integrator::ImplicitDamping
            | Integrator::VelocityVerlet
            | Integrator::VerletImplicitDamping => 0,
            Integrator::Rk4 => 4,
            Integrator::DormandPrince45 => 7,
        };
        if matches!(
            scheme,
            Integrator::SymplecticEuler
                | Integrator::ImplicitDamping
                | Integrator::VerletImplicitDamping
        ) {
            forces.begin_run();
        }
        if matches!(
            scheme,
            Integrator::ImplicitDamping | Integrator::VerletImplicitDamping
        ) {
            forces.enable_damping_rows();
            // Fill the rows for the first step (same state: the memory is kept).
            forces.evaluate(model, state);
        }
        // Velocity Verlet's second evaluation is at its first's positions.
        forces.keep_positions(scheme == Integrator::VelocityVerlet);
        let scale_position_m = static_stretch_m.abs().max(1e-12);
        let scale_speed_m_s =
            scale_position_m * (model.stiffness_n_m / model.roller_mass_kg).sqrt();
        Self {
            scheme,
            tolerance,
            k: vec![state.clone(); stages],
            start: state.clone(),
            touching_start: vec![false; state.rollers()],
            theta_scratch: vec![0.0; state.theta.len()],
            torque_scratch: vec![0.0; state.theta.len()],
            rate_scratch: vec![0.0; state.z.len()],
            damping_changes: Vec::with_capacity(state.rollers()),
            predicted_vx: vec![0.0; state.rollers()],
            predicted_vy: vec![0.0; state.rollers()],
            scale_position_m,
            scale_speed_m_s,
            scale_theta: model
                .sprockets
                .iter()
                .map(|s| scale_position_m / s.pitch_radius_m)
                .collect(),
            scale_omega: model
                .sprockets
                .iter()
                .map(|s| scale_speed_m_s / s.pitch_radius_m)
                .collect(),
            next_step_s: f64::INFINITY,
            stats: IntegrationStats::default(),
        }
    }

    /// What the scheme carries from one step to the next: the adaptive
    /// step's proposal (∞ before its first step) and the counters. Every
    /// other buffer is set at a step's start (the first stage of the
    /// adaptive scheme, FSAL, is the committed forces' rates).
    pub(crate) fn carried(&self) -> (f64, IntegrationStats) {
        (self.next_step_s, self.stats)
    }

    /// Takes back [`Self::carried`]' output (a checkpoint).
    pub(crate) fn carry(&mut self, next_step_s: f64, stats: IntegrationStats) {
        self.next_step_s = next_step_s;
        self.stats = stats;
    }

    /// The scheme.
    pub(crate) fn scheme(&self) -> Integrator {
        self.scheme
    }

    /// Advances `state` by `dt_s`; `forces` must hold the forces at `state`
    /// (committed) and holds those at the new state afterwards.
    pub(crate) fn advance(
        &mut self,
        model: &DriveModel,
        state: &mut DriveState,
        forces: &mut ForceGenerator,
        dt_s: f64,
    ) -> Result<(), SimError> {
        match self.scheme {
            Integrator::SymplecticEuler => {
                super::symplectic_euler(model, state, forces, dt_s, None);
                self.commit(model, state, forces);
            }
            Integrator::ImplicitDamping => {
                self.implicit_damping(model, state, forces, dt_s);
                self.commit(model, state, forces);
            }
            Integrator::VelocityVerlet => self.velocity_verlet(model, state, forces, dt_s),
            Integrator::VerletImplicitDamping => {
                self.verlet_implicit_damping(model, state, forces, dt_s);
            }
            Integrator::Rk4 => self.rk4(model, state, forces, dt_s),
            Integrator::DormandPrince45 => self.adaptive(model, state, forces, dt_s)?,
        }
        Ok(())
    }

    fn commit(&mut self, model: &DriveModel, state: &DriveState, forces: &mut ForceGenerator) {
        forces.evaluate(model, state);
        self.stats.evaluations += 1;
        self.stats.steps += 1;
    }

    fn trial(&mut self, model: &DriveModel, state: &DriveState, forces: &mut ForceGenerator) {
        forces.evaluate_trial(model, state);
        self.stats.evaluations += 1;
    }

    /// Symplectic Euler with implicit contact damping (see the module docs).
    fn implicit_damping(
        &mut self,
        model: &DriveModel,
        state: &mut DriveState,
        forces: &ForceGenerator,
        h: f64,
    ) {
        implicit_damping_step(model, state, forces, h, &mut self.torque_scratch, None);
    }

    /// Classical Runge–Kutta.
    fn rk4(
        &mut self,
        model: &DriveModel,
        state: &mut DriveState,
        forces: &mut ForceGenerator,
        h: f64,
    ) {
        const A: [[f64; 3]; 4] = [
            [0.0, 0.0, 0.0],
            [0.5, 0.0, 0.0],
            [0.0, 0.5, 0.0],
            [0.0, 0.0, 1.0],
        ];
        const C: [f64; 4] = [0.0, 0.5, 0.5, 1.0];
        const B: [f64; 4] = [1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0];
        self.start.clone_from(state);
        rate(model, state, forces, &mut self.k[0]);
        for j in 1..4 {
            combine(state, &self.start, h, &A[j][..j], &self.k[..j]);
            state.t_s = self.start.t_s + C[j] * h;
            set_driver_speed(model, state);
            self.trial(model, state, forces);
            rate(model, state, forces, &mut self.k[j]);
        }
        combine(state, &self.start, h, &B, &self.k[..4]);
        state.t_s = self.start.t_s + h;
        set_driver_speed(model, state);
        self.commit(model, state, forces);
    }

    /// Adaptive Dormand–Prince 5(4) over `dt_s`, with located contact events.
    fn adaptive(
        &mut self,
        model: &DriveModel,
        state: &mut DriveState,
        forces: &mut ForceGenerator,
        dt_s: f64,
    ) -> Result<(), SimError> {
        let t_end = state.t_s + dt_s;
        if !self.next_step_s.is_finite() {
            self.next_step_s = dt_s;
        }
        while state.t_s < t_end - 1e-3 * MIN_STEP_S.max(1e-9 * dt_s) {
            let remaining = t_end - state.t_s;
            let mut h = self.next_step_s.min(dt_s).min(remaining);
            // Avoid a sliver step at the end of the interval.
            if remaining - h < 1e-3 * h {
                h = remaining;
            }
            let proposed = self.next_step_s;
            // Cut short by the interval's end or an event rather than by the error.
            let mut cut_short = h < proposed;
            self.start.clone_from(state);
            self.touching_start
                .copy_from_slice(&forces.output().touching);
            rate(model, state, forces, &mut self.k[0]);
            loop {
                if !(h >= MIN_STEP_S) {
                    return Err(SimError::BlowUp {
                        t_s: state.t_s,
                        detector: super::Detector::StepSize.name(),
                        body: "the chain".to_owned(),
                        value: h,
                        limit: MIN_STEP_S,
                        detail: String::new(),
                    });
                }
                let err = self.dp45_trial(model, state, forces, h);
                if !(err <= 1.0) {
                    self.stats.rejected += 1;
                    let factor = if err.is_finite() {
                        (0.9 * err.powf(-0.2)).clamp(0.1, 0.9)
                    } else {
                        0.1
                    };
                    h *= factor;
                    state.clone_from(&self.start);
                    continue;
                }
                // Accepted by the error test: locate a contact event inside it.
                // (An event within the step's first or last 0.1 % is taken as is.)
                if let Some(t_event) = self.earliest_event(model, state, forces, h)
                    && t_event > self.start.t_s + 1e-3 * h
                    && t_event < self.start.t_s + h * (1.0 - 1e-3)
                {
                    self.stats.events += 1;
                    h = t_event - self.start.t_s;
                    cut_short = true;
                    state.clone_from(&self.start);
                    continue;
                }
                forces.commit_trial();
                self.stats.steps += 1;
                let grow = if err > 0.0 {
                    (0.9 * err.powf(-0.2)).clamp(0.2, 5.0)
                } else {
                    5.0
                };
                // After a step cut short (by an event or the interval's end), keep the old proposal.
                self.next_step_s = if cut_short {
                    (h * grow).max(proposed)
                } else {
                    h * grow
                };
                break;
            }
        }
        state.t_s = t_end;
        Ok(())
    }

    /// One Dormand–Prince trial step of `h` from `self.start` (stage 1 in
    /// `k[0]`); leaves the trial end state in `state`, the forces at it in
    /// `forces` (uncommitted) and returns the scaled error norm.
    fn dp45_trial(
        &mut self,
        model: &DriveModel,
        state: &mut DriveState,
        forces: &mut ForceGenerator,
        h: f64,
    ) -> f64 {
        for j in 1..7 {
            combine(state, &self.start, h, &dp45::A[j][..j], &self.k[..j]);
            state.t_s = self.start.t_s + dp45::C[j] * h;
            set_driver_speed(model, state);
            self.trial(model, state, forces);
            rate(model, state, forces, &mut self.k[j]);
        }
        // Stage 7 is at y₁ = y₀ + h Σ A₆ⱼ kⱼ = the fifth-order solution (FSAL).
        self.error_norm(model, h)
    }

    /// Max-norm of the embedded error estimate h Σ Eⱼ kⱼ against the scales.
    fn error_norm(&self, model: &DriveModel, h: f64) -> f64 {
        let k = &self.k;
        let tol = self.tolerance;
        let est = |field: fn(&DriveState) -> &Vec<f64>, i: usize| -> f64 {
            let mut e = 0.0;
            for (w, kj) in dp45::E.iter().zip(k) {
                e += w * field(kj)[i];
            }
            (h * e).abs()
        };
        let mut worst = 0.0f64;
        let (sp, sv) = (tol * self.scale_position_m, tol * self.scale_speed_m_s);
        for i in 0..self.start.rollers() {
            let e = (est(|s| &s.x, i).max(est(|s| &s.y, i)) / sp)
                .max(est(|s| &s.vx, i).max(est(|s| &s.vy, i)) / sv);
            // NaN must reject the step.
            if !(e <= worst) {
                worst = e;
            }
        }
        for (s, sprocket) in model.sprockets.iter().enumerate() {
            if sprocket.speed_law.is_some() {
                continue;
            }
            let e = (est(|st| &st.theta, s) / (tol * self.scale_theta[s]))
                .max(est(|st| &st.omega, s) / (tol * self.scale_omega[s]));
            if !(e <= worst) {
                worst = e;
            }
        }
        // Further bodies: a coordinate's scale is its own, its speed's the
        // same over the links' time scale, as for the rollers.
        let per_time = self.scale_speed_m_s / self.scale_position_m;
        for (k, body) in model.bodies.iter().enumerate() {
            let e = (est(|st| &st.q, k) / (tol * body.error_scale))
                .max(est(|st| &st.u, k) / (tol * body.error_scale * per_time));
            if !(e <= worst) {
                worst = e;
            }
        }
        for (k, scalar) in model.scalars.iter().enumerate() {
            let e = est(|st| &st.z, k) / (tol * scalar.error_scale);
            if !(e <= worst) {
                worst = e;
            }
        }
        worst
    }

    /// The earliest time in the trial step at which a roller's contact
    /// state changes, if it changes (bisection on the Hermite interpolant).
    fn earliest_event(
        &mut self,
        model: &DriveModel,
        end: &DriveState,
        forces: &ForceGenerator,
        h: f64,
    ) -> Option<f64> {
        let start = &self.start;
        let tolerance = 1e-3 * h;
        let mut earliest: Option<f64> = None;
        for i in 0..start.rollers() {
            let before = self.touching_start[i];
            if forces.output().touching[i] == before {
                continue;
            }
            let (mut lo, mut hi) = (0.0f64, 1.0f64);
            while (hi - lo) * h > tolerance {
                let mid = 0.5 * (lo + hi);
                let x = hermite(start.x[i], end.x[i], start.vx[i], end.vx[i], h, mid);
                let y = hermite(start.y[i], end.y[i], start.vy[i], end.vy[i], h, mid);
                for (s, th) in self.theta_scratch.iter_mut().enumerate() {
                    *th = hermite(
                        start.theta[s],
                        end.theta[s],
                        start.omega[s],
                        end.omega[s],
                        h,
                        mid,
                    );
                }
                if forces.touches(model, i, x, y, &self.theta_scratch) == before {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let t = start.t_s + hi * h;
            if earliest.is_none_or(|e| t < e) {
                earliest = Some(t);
            }
        }
        earliest
    }
}

/// One step of symplectic Euler with the contact damping implicit (see the
/// module docs); `forces` must hold damping rows. With `relax`, the driver is
/// held and every velocity damped, as in [`super::symplectic_euler`].
/// `torque` is scratch of one entry per sprocket.
pub(crate) fn implicit_damping_step(
    model: &DriveModel,
    state: &mut DriveState,
    forces: &ForceGenerator,
    h: f64,
    torque: &mut [f64],
    relax: Option<Relaxation>,
) {
    let m = model.roller_mass_kg;
    let scale = relax.map_or(1.0, |r| 1.0 / (1.0 + h * r.rate_per_s));
    torque.copy_from_slice(&forces.output().chain_torque);
    let Some(rows) = forces.damping_rows() else {
        // Without rows there is nothing implicit to do: the explicit step.
        super::symplectic_euler(model, state, forces, h, relax);
        return;
    };
    for i in 0..state.rollers() {
        let (fx, fy) = (forces.output().fx[i], forces.output().fy[i]);
        let (vx, vy) = (state.vx[i], state.vy[i]);
        let s = rows.sprocket[i];
        let (nvx, nvy) = if s == u32::MAX {
            (vx + h * fx / m, vy + h * fy / m)
        } else {
            let ([ux, uy], [ddx, ddy]) = damped_roller(rows, i, m, h, [vx, vy], [fx, fy]);
            let [lx, ly] = rows.lever[i];
            torque[s as usize] -= lx * ddy - ly * ddx;
            (ux, uy)
        };
        state.vx[i] = nvx * scale;
        state.vy[i] = nvy * scale;
        state.x[i] += h * state.vx[i];
        state.y[i] += h * state.vy[i];
    }
    for (s, sp) in model.sprockets.iter().enumerate() {
        // A torque-driven driver is held as the kinematic one while the
        // drive relaxes.
        let omega = if sp.speed_law.is_some() || (relax.is_some() && sp.governor.is_some()) {
            if relax.is_some() {
                0.0
            } else {
                driver_speed(model, s, state.t_s, state.theta[s], h)
            }
        } else {
            let load = if relax.is_some() {
                sp.load_at_rest_n_m()
            } else {
                sp.torque_at(state.t_s, state.theta[s], state.omega[s])
            };
            (state.omega[s] + h * (torque[s] + load) * sp.inv_inertia) * scale
        };
        state.omega[s] = omega;
        state.theta[s] += h * omega;
    }
    advance_extras(model, state, forces.output(), h, scale);
    state.t_s += h;
}

/// The velocity after a kick of `h` of roller `i` (in contact, with
/// damping row `i`) from velocity `v` under the evaluated force `f`, its
/// contact damping taken at the new velocity: the solution of
/// `(m I + h C) v' = m v + h (F_rest + C v_sp)`, and the change of the
/// damping force against the evaluated one. A damping force that would pull
/// clamps the contact force to zero.
#[inline(always)]
fn damped_roller(
    rows: &crate::forces::DampingRows,
    i: usize,
    m: f64,
    h: f64,
    v: [f64; 2],
    f: [f64; 2],
) -> ([f64; 2], [f64; 2]) {
    let ([vx, vy], [fx, fy]) = (v, f);
    let [cxx, cxy, cyy] = rows.c[i];
    let [ex, ey] = rows.explicit[i];
    let [dx, dy] = rows.c_v_sprocket[i];
    let [elx, ely] = rows.elastic[i];
    // The force without the contact damping.
    let (rest_x, rest_y) = (fx - ex, fy - ey);
    let (a, b, d) = (m + h * cxx, h * cxy, m + h * cyy);
    let (rx, ry) = (m * vx + h * (rest_x + dx), m * vy + h * (rest_y + dy));
    // A is symmetric positive definite (C ⪰ 0, m > 0): det > 0.
    let det = a * d - b * b;
    let (mut ux, mut uy) = ((d * rx - b * ry) / det, (a * ry - b * rx) / det);
    let (mut fdx, mut fdy) = (dx - (cxx * ux + cxy * uy), dy - (cxy * ux + cyy * uy));
    if (elx + fdx) * elx + (ely + fdy) * ely < 0.0 {
        // The damping would pull: the contact force is clamped to zero.
        (fdx, fdy) = (-elx, -ely);
        ux = vx + h * (rest_x + fdx) / m;
        uy = vy + h * (rest_y + fdy) / m;
    }
    ([ux, uy], [fdx - ex, fdy - ey])
}

/// Cubic Hermite interpolation at fraction `s` of a step `h` between values
/// `p0`, `p1` with derivatives `d0`, `d1`.
#[inline]
fn hermite(p0: f64, p1: f64, d0: f64, d1: f64, h: f64, s: f64) -> f64 {
    let s2 = s * s;
    let s3 = s2 * s;
    (2.0 * s3 - 3.0 * s2 + 1.0) * p0
        + (s3 - 2.0 * s2 + s) * h * d0
        + (-2.0 * s3 + 3.0 * s2) * p1
        + (s3 - s2) * h * d1
}

/// Sets the driver's speed to its law at the state's time and angle: within
/// a Runge–Kutta scheme the stage's θ rate is this speed, so the scheme
/// integrates dθ/dt = ω(t, θ) at its own order.
fn set_driver_speed(model: &DriveModel, state: &mut DriveState) {
    for (s, sp) in model.sprockets.iter().enumerate() {
        if sp.speed_law.is_some() {
            state.omega[s] = sp.driver_speed_at(state.t_s, state.theta[s]);
        }
    }
}

/// The time derivative of `state` given the forces at it, into `out`
/// (fields reused: `out.x` holds dx/dt, `out.vx` dvx/dt, and so on).
fn rate(model: &DriveModel, state: &DriveState, forces: &ForceGenerator, out: &mut DriveState) {
    let inv_m = 1.0 / model.roller_mass_kg;
    out.x.copy_from_slice(&state.vx);
    out.y.copy_from_slice(&state.vy);
    for (o, f) in out.vx.iter_mut().zip(&forces.output().fx) {
        *o = f * inv_m;
    }
    for (o, f) in out.vy.iter_mut().zip(&forces.output().fy) {
        *o = f * inv_m;
    }
    for (s, sp) in model.sprockets.iter().enumerate() {
        out.theta[s] = state.omega[s];
        out.omega[s] = if sp.speed_law.is_some() {
            0.0
        } else {
            (forces.output().chain_torque[s]
                + sp.torque_at(state.t_s, state.theta[s], state.omega[s]))
                * sp.inv_inertia
        };
    }
    let f = forces.output();
    out.q.copy_from_slice(&state.u);
    for ((o, q), body) in out.u.iter_mut().zip(&f.body_force).zip(&model.bodies) {
        *o = q * body.inv_mass;
    }
    out.z.copy_from_slice(&f.scalar_rate);
}

/// `out = start + h Σ a_j k_j` over every state field (time excluded).
fn combine(out: &mut DriveState, start: &DriveState, h: f64, a: &[f64], k: &[DriveState]) {
    fn field(
        out: &mut [f64],
        start: &[f64],
        h: f64,
        a: &[f64],
        k: &[DriveState],
        pick: fn(&DriveState) -> &[f64],
    ) {
        out.copy_from_slice(start);
        for (&w, kj) in a.iter().zip(k) {
            if w == 0.0 {
                continue;
            }
            let hw = h * w;
            for (o, r) in out.iter_mut().zip(pick(kj)) {
                *o += hw * r;
            }
        }
    }
    field(&mut out.x, &start.x, h, a, k, |s| &s.x);
    field(&mut out.y, &start.y, h, a, k, |s| &s.y);
    field(&mut out.vx, &start.vx, h, a, k, |s| &s.vx);
    field(&mut out.vy, &start.vy, h, a, k, |s| &s.vy);
    field(&mut out.theta, &start.theta, h, a, k, |s| &s.theta);
    field(&mut out.omega, &start.omega, h, a, k, |s| &s.omega);
    field(&mut out.q, &start.q, h, a, k, |s| &s.q);
    field(&mut out.u, &start.u, h, a, k, |s| &s.u);
    field(&mut out.z, &start.z, h, a, k, |s| &s.z);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dormand_prince_tableau_is_consistent() {
        // Row sums of A equal C; both weight sets sum to 1 (E sums to 0).
        for (row, c) in dp45::A.iter().zip(dp45::C) {
            assert!((row.iter().sum::<f64>() - c).abs() < 1e-14);
        }
        assert!((dp45::B.iter().sum::<f64>() - 1.0).abs() < 1e-14);
        assert!(dp45::E.iter().sum::<f64>().abs() < 1e-14);
        // FSAL: B equals the last row of A.
        for (b, a) in dp45::B.iter().zip(dp45::A[6]) {
            assert_eq!(*b, a);
        }
    }

    #[test]
    fn hermite_reproduces_a_cubic() {
        // p(t) = t³ − 2t + 1 on [0.5, 0.5 + h]: exact for cubics.
        let p = |t: f64| t * t * t - 2.0 * t + 1.0;
        let d = |t: f64| 3.0 * t * t - 2.0;
        let (t0, h) = (0.5, 0.3);
        for s in [0.0, 0.25, 0.6, 1.0] {
            let got = hermite(p(t0), p(t0 + h), d(t0), d(t0 + h), h, s);
            assert!((got - p(t0 + s * h)).abs() < 1e-14);
        }
    }
}
