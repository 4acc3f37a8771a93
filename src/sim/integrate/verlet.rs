//! The two velocity Verlet schemes: `velocity_verlet` (two force evaluations
//! per step, every force explicit) and `verlet_implicit_damping` (one
//! evaluation per step, the contact damping taken by the trapezoidal rule).
//!
//! Both kick half a step, drift, and evaluate the forces at the new positions
//! with the velocities predicted at the step's end, v + h a(xₙ, vₙ) (with the
//! half-step ones the damping would lag half a step and the scheme fall to
//! first order). Then:
//!
//! - `velocity_verlet` kicks the second half with those forces and evaluates
//!   them once more at the corrected velocities: the committed forces.
//! - `verlet_implicit_damping` commits that one evaluation and kicks the
//!   second half with the contact damping at the *new* velocity: per roller
//!   in contact the 2×2 system `(m I + h/2 C) v' = m v½ + h/2 (F_rest + C v_sp)`
//!   ([`crate::forces::DampingRows`]). With the first half kick explicit at the
//!   step's start, the damping is integrated by the trapezoidal rule, stable
//!   for any damping coefficient, so the contact damping does not bound the
//!   step. The force with the solved damping (and its reaction on the
//!   sprocket) replaces the evaluated one as the next step's start force. The
//!   links' damping and the joint friction stay explicit, at the predicted
//!   velocities: for a damping rate λ that is stable for h λ < 1 (half of the
//!   explicit schemes' 2), which [`crate::scene::stability`] accounts for.
//!
//! What this does not do: solve the links' stiffness implicitly (the links
//! bound both schemes' step), or locate contact onsets.

use super::Integration;
use super::{damped_roller, set_driver_speed};
use crate::forces::{ForceGenerator, Forces};
use crate::model::{DriveModel, DriveState};
use crate::sim::stepper::driver_speed;

impl Integration {
    /// Velocity Verlet: half kick, drift, forces at the new positions, half
    /// kick, then the committed evaluation — at the same positions, where
    /// the links and the contact compute again only what depends on the
    /// velocities ([`ForceGenerator::evaluate_again`]; the same numbers).
    pub(super) fn velocity_verlet(
        &mut self,
        model: &DriveModel,
        state: &mut DriveState,
        forces: &mut ForceGenerator,
        h: f64,
    ) {
        self.verlet_first_half(model, state, forces.output(), h);
        self.trial(model, state, forces);
        self.verlet_second_kick(model, state, forces.output(), h);
        self.verlet_second_half_others(model, state, forces.output(), h);
        forces.evaluate_again(model, state);
        self.stats.evaluations += 1;
        self.stats.steps += 1;
    }

    /// Velocity Verlet with one evaluation per step and the contact damping
    /// by the trapezoidal rule (module docs).
    pub(super) fn verlet_implicit_damping(
        &mut self,
        model: &DriveModel,
        state: &mut DriveState,
        forces: &mut ForceGenerator,
        h: f64,
    ) {
        self.verlet_first_half(model, state, forces.output(), h);
        forces.evaluate(model, state);
        self.stats.evaluations += 1;
        self.stats.steps += 1;
        let m = model.roller_mass_kg;
        let half_h = 0.5 * h;
        self.predicted_vx.copy_from_slice(&state.vx);
        self.predicted_vy.copy_from_slice(&state.vy);
        // The explicit second half kick of every roller; those in contact
        // are solved again below.
        self.verlet_second_kick(model, state, forces.output(), h);
        let Some(rows) = forces.damping_rows() else {
            // Nothing implicit to do.
            self.verlet_second_half_others(model, state, forces.output(), h);
            return;
        };
        // The damping force changes of the rollers in contact: roller,
        // sprocket, lever, Δf; and the change of the damping's power.
        let changes = &mut self.damping_changes;
        changes.clear();
        let mut power_change_w = 0.0;
        let out = forces.output();
        for (i, &s) in rows.sprocket.iter().enumerate() {
            if s != u32::MAX {
                let (fx, fy) = (out.fx[i], out.fy[i]);
                let (vx, vy) = (self.start.vx[i], self.start.vy[i]);
                let (u, change) = damped_roller(rows, i, m, half_h, [vx, vy], [fx, fy]);
                // Power of the damping on the roller's motion relative to
                // the sprocket: the solved force at the new velocity
                // replaces the evaluated one at the predicted velocity.
                let [ex, ey] = rows.explicit[i];
                let [wx, wy] = rows.surface_velocity[i];
                let (sx, sy) = (ex + change[0], ey + change[1]);
                let (px, py) = (self.predicted_vx[i], self.predicted_vy[i]);
                power_change_w +=
                    sx * (u[0] - wx) + sy * (u[1] - wy) - (ex * (px - wx) + ey * (py - wy));
                state.vx[i] = u[0];
                state.vy[i] = u[1];
                changes.push((i, s as usize, rows.lever[i], change));
            }
        }
        // The solved damping replaces the evaluated one in the forces the
        // next step starts from, with its reaction on the sprocket.
        let out = forces.output_mut();
        out.contact_damping_power_w += power_change_w;
        for &(i, s, [lx, ly], [ddx, ddy]) in changes.iter() {
            out.fx[i] += ddx;
            out.fy[i] += ddy;
            out.chain_torque[s] -= lx * ddy - ly * ddx;
            out.chain_force[s][0] -= ddx;
            out.chain_force[s][1] -= ddy;
        }
        // The joint friction's moments act while the rollers move at their
        // new velocities: its power at them.
        let (dvx, dvy) = (&mut self.predicted_vx, &mut self.predicted_vy);
        for ((d, v), (e, u)) in dvx
            .iter_mut()
            .zip(&state.vx)
            .zip(dvy.iter_mut().zip(&state.vy))
        {
            *d = v - *d;
            *e = u - *e;
        }
        let out = forces.output_mut();
        if let Some(power_w) = friction_power_w(out, dvx, dvy) {
            out.joint_friction_power_w = power_w;
        }
        self.verlet_second_half_others(model, state, forces.output(), h);
    }

    /// The first half kick and the drift of every coordinate (the rollers'
    /// half-step velocities kept in `start.vx/vy`, the sprockets' in
    /// `torque_scratch`), the scalar states' Euler predictor; the time and
    /// the driver's speed set to the step's end.
    fn verlet_first_half(
        &mut self,
        model: &DriveModel,
        state: &mut DriveState,
        f: &Forces,
        h: f64,
    ) {
        let half = 0.5 * h / model.roller_mass_kg;
        let n = state.rollers();
        let (vhx, vhy) = (&mut self.start.vx[..n], &mut self.start.vy[..n]);
        kick_drift_kick(vhx, &mut state.vx, &mut state.x, &f.fx[..n], half, h);
        kick_drift_kick(vhy, &mut state.vy, &mut state.y, &f.fy[..n], half, h);
        let omega_half = &mut self.torque_scratch;
        for (s, sp) in model.sprockets.iter().enumerate() {
            if sp.speed_law.is_some() {
                state.theta[s] += h * driver_speed(model, s, state.t_s, state.theta[s], h);
            } else {
                let kick = 0.5
                    * h
                    * (f.chain_torque[s] + sp.torque_at(state.t_s, state.theta[s], state.omega[s]))
                    * sp.inv_inertia;
                omega_half[s] = state.omega[s] + kick;
                state.theta[s] += h * omega_half[s];
                state.omega[s] = omega_half[s] + kick;
            }
        }
        // Further bodies as the sprockets; scalar states by Heun's rule
        // (an Euler predictor here, the trapezoid after the new forces).
        for (k, body) in model.bodies.iter().enumerate() {
            let kick = 0.5 * h * f.body_force[k] * body.inv_mass;
            self.start.u[k] = state.u[k] + kick;
            state.q[k] += h * self.start.u[k];
            state.u[k] = self.start.u[k] + kick;
        }
        self.start.z.copy_from_slice(&state.z);
        self.rate_scratch.copy_from_slice(&f.scalar_rate);
        for (z, rate) in state.z.iter_mut().zip(&f.scalar_rate) {
            *z += h * rate;
        }
        state.t_s += h;
        set_driver_speed(model, state);
    }

    /// The rollers' second half kick, explicit: v = v½ + h/2 · f/m.
    fn verlet_second_kick(&self, model: &DriveModel, state: &mut DriveState, f: &Forces, h: f64) {
        let half = 0.5 * h / model.roller_mass_kg;
        let n = state.rollers();
        kick(&mut state.vx, &self.start.vx[..n], &f.fx[..n], half);
        kick(&mut state.vy, &self.start.vy[..n], &f.fy[..n], half);
    }

    /// The second half kick of the sprockets, further bodies and scalar
    /// states with the forces `f` at the step's end.
    fn verlet_second_half_others(
        &mut self,
        model: &DriveModel,
        state: &mut DriveState,
        f: &Forces,
        h: f64,
    ) {
        for (s, sp) in model.sprockets.iter().enumerate() {
            if sp.speed_law.is_none() {
                state.omega[s] = self.torque_scratch[s]
                    + 0.5
                        * h
                        * (f.chain_torque[s]
                            + sp.torque_at(state.t_s, state.theta[s], state.omega[s]))
                        * sp.inv_inertia;
            }
        }
        for (k, body) in model.bodies.iter().enumerate() {
            state.u[k] = self.start.u[k] + 0.5 * h * f.body_force[k] * body.inv_mass;
        }
        for (k, rate) in f.scalar_rate.iter().enumerate() {
            state.z[k] = self.start.z[k] + 0.5 * h * (self.rate_scratch[k] + rate);
        }
    }
}

/// The joint friction's power Σ M ω_rel with the moments of `out` and the
/// links' angular velocities at the rollers' velocities moved by `dv` from
/// those `out` holds them at: ω = (u × Δv)/ℓ is linear in the velocities,
/// so each link's ω moves by n/ℓ · Δ(dv). Summed link by link as
/// Σ ω_j (M_j − M_{j+1}) (joint j lies between links j − 1 and j; joint 0
/// closes the loop). `None` without joint friction.
fn friction_power_w(out: &Forces, dvx: &[f64], dvy: &[f64]) -> Option<f64> {
    let n = dvx.len();
    let (m, w) = (&out.joint_moment_n_m, &out.link_omega);
    let (gx, gy) = (&out.link_normal_x, &out.link_normal_y);
    if n < 2 || [m.len(), w.len(), gx.len(), gy.len(), dvy.len()] != [n; 5] {
        return None;
    }
    let link = |j: usize, k: usize| w[j] + gx[j] * (dvx[k] - dvx[j]) + gy[j] * (dvy[k] - dvy[j]);
    let mut power_w = link(n - 1, 0) * (m[n - 1] - m[0]);
    let pairs = dvx[..n - 1]
        .iter()
        .zip(&dvx[1..])
        .zip(dvy[..n - 1].iter().zip(&dvy[1..]));
    let links = w[..n - 1].iter().zip(&gx[..n - 1]).zip(&gy[..n - 1]);
    let moments = m[..n - 1].iter().zip(&m[1..]);
    for ((((x0, x1), (y0, y1)), ((w, gx), gy)), (m0, m1)) in pairs.zip(links).zip(moments) {
        power_w += (w + gx * (x1 - x0) + gy * (y1 - y0)) * (m0 - m1);
    }
    Some(power_w)
}

/// One coordinate of the rollers' first half kick and drift:
/// v½ = v + k, x ← x + h v½, v ← v½ + k with k = `half` · f. Slices as
/// arguments let the compiler vectorise (with AVX2 where the CPU has it, as
/// `stepper::kick_drift`); each roller's update is its own, so the width
/// changes no bit.
#[inline(never)]
fn kick_drift_kick(vh: &mut [f64], v: &mut [f64], x: &mut [f64], f: &[f64], half: f64, h: f64) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2, checked on the line above.
        return unsafe { kick_drift_kick_avx2(vh, v, x, f, half, h) };
    }
    kick_drift_kick_body(vh, v, x, f, half, h);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn kick_drift_kick_avx2(
    vh: &mut [f64],
    v: &mut [f64],
    x: &mut [f64],
    f: &[f64],
    half: f64,
    h: f64,
) {
    kick_drift_kick_body(vh, v, x, f, half, h);
}

#[inline(always)]
fn kick_drift_kick_body(
    vh: &mut [f64],
    v: &mut [f64],
    x: &mut [f64],
    f: &[f64],
    half: f64,
    h: f64,
) {
    for (((vh, v), x), f) in vh.iter_mut().zip(v).zip(x).zip(f) {
        let k = half * f;
        *vh = *v + k;
        *x += h * *vh;
        *v = *vh + k;
    }
}

/// One coordinate of the rollers' second half kick: v = v½ + `half` · f
/// (vectorised as [`kick_drift_kick`]).
#[inline(never)]
fn kick(v: &mut [f64], vh: &[f64], f: &[f64], half: f64) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2, checked on the line above.
        return unsafe { kick_avx2(v, vh, f, half) };
    }
    kick_body(v, vh, f, half);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn kick_avx2(v: &mut [f64], vh: &[f64], f: &[f64], half: f64) {
    kick_body(v, vh, f, half);
}

#[inline(always)]
fn kick_body(v: &mut [f64], vh: &[f64], f: &[f64], half: f64) {
    for ((v, vh), f) in v.iter_mut().zip(vh).zip(f) {
        *v = vh + half * f;
    }
}

#[cfg(test)]
mod tests {
    use crate::forces::Forces;
    use crate::model::DriveState;
    use crate::scene::{Integrator, L60MC_TOML, Overrides, ProfileKind, Scene};
    use crate::sim::Simulation;

    /// The paper's drive with pin–bushing friction (`assets/l60mc-friction.toml`).
    const FRICTION_TOML: &str = include_str!("../../../assets/l60mc-friction.toml");

    /// Every number of a state and of the forces at it, as bits.
    fn bits(s: &DriveState, f: &Forces) -> Vec<u64> {
        let state = [
            &s.x, &s.y, &s.vx, &s.vy, &s.theta, &s.omega, &s.q, &s.u, &s.z,
        ];
        let forces = [
            &f.fx,
            &f.fy,
            &f.link_force,
            &f.contact_force,
            &f.chain_torque,
            &f.joint_moment_n_m,
            &f.link_omega,
            &f.link_normal_x,
            &f.link_normal_y,
        ];
        let sums = [
            s.t_s,
            f.max_penetration_m,
            f.max_stretch_m,
            f.max_roller_speed_m_s,
            f.contact_energy_j,
            f.contact_damping_power_w,
            f.joint_friction_power_w,
        ];
        state
            .into_iter()
            .chain(forces)
            .flatten()
            .copied()
            .chain(f.chain_force.iter().flatten().copied())
            .chain(sums)
            .map(f64::to_bits)
            .chain(f.touching.iter().map(|&t| u64::from(t)))
            .collect()
    }

    #[test]
    fn second_evaluation_at_the_same_positions_changes_no_bit() {
        // Oracle: the same velocity Verlet steps with the second evaluation
        // of each step computed whole (nothing kept), every state and every
        // force compared bit for bit after each step; 0.15 s at 50 µs from
        // rest, so that rollers engage (new onsets, three or more in each
        // drive, whose remembered speed follows the corrected velocities)
        // and leave. Circular profile (the seats' pass) and the real one
        // with joint friction (the general pass, the links' rates).
        let steps = 3000;
        for (text, profile) in [
            (L60MC_TOML, ProfileKind::Circular),
            (FRICTION_TOML, ProfileKind::Real),
        ] {
            let overrides = Overrides {
                profile: Some(profile),
                integrator: Some(Integrator::VelocityVerlet),
                dt_s: Some(5e-5),
                ..Overrides::default()
            };
            let scene = Scene::from_toml_with(text, &overrides).expect("scene");
            let mut kept = Simulation::new(&scene).expect("settles");
            let mut whole = Simulation::new(&scene).expect("settles");
            whole.forces.keep_positions(false);
            let mut onsets = 0;
            for step in 0..steps {
                let before = kept.forces.output().touching.clone();
                kept.step(5e-5).expect("step");
                whole.step(5e-5).expect("step");
                let (a, b) = (
                    bits(&kept.state, kept.forces.output()),
                    bits(&whole.state, whole.forces.output()),
                );
                let first = a.iter().zip(&b).position(|(x, y)| x != y);
                assert_eq!(first, None, "{profile:?}: step {step}, number {first:?}");
                let now = &kept.forces.output().touching;
                onsets += now.iter().zip(&before).filter(|(n, b)| **n && !**b).count();
            }
            assert!(onsets >= 3, "{profile:?}: {onsets} onsets");
        }
    }
}
