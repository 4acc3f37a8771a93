//! One step of the plugin's own integrator on the structure-of-arrays state.
//!
//! Symplectic (semi-implicit) Euler, the scheme rapier itself uses:
//! v ← v + dt·f(x, v)/m, then x ← x + dt·v. Free sprockets turn under the
//! chain's moment plus their load; the driver follows its speed law, sampled
//! at the step's midpoint so that a ramp's angle is integrated exactly.

use crate::forces::{ForceGenerator, Forces, Halves, Kick, chunk, kick_drift};
use crate::model::{DriveModel, DriveState};

/// Extra viscous damping used only while relaxing to static equilibrium:
/// velocities are scaled by 1 / (1 + dt·rate) each step (unconditionally stable).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Relaxation {
    /// Damping rate, 1/s.
    pub rate_per_s: f64,
}

/// The driver's angular speed over the step starting at `t_s` with the
/// driver at `theta_rad` (midpoint rule,
/// [`crate::model::SprocketModel::driver_step_speed`]).
#[inline]
pub(crate) fn driver_speed(
    model: &DriveModel,
    sprocket: usize,
    t_s: f64,
    theta_rad: f64,
    dt_s: f64,
) -> f64 {
    model.sprockets[sprocket].driver_step_speed(t_s, theta_rad, dt_s)
}

/// Advances `state` by `dt_s`. `forces` must hold the forces at `state`
/// (call [`ForceGenerator::evaluate`] first). With `relax`, the driver is held
/// and every velocity is damped.
pub(crate) fn symplectic_euler(
    model: &DriveModel,
    state: &mut DriveState,
    forces: &ForceGenerator,
    dt_s: f64,
    relax: Option<Relaxation>,
) {
    let h_kick = dt_s / model.roller_mass_kg;
    let scale = relax.map_or(1.0, |r| 1.0 / (1.0 + dt_s * r.rate_per_s));
    let n = state.rollers();
    let (fx, fy) = (&forces.output().fx, &forces.output().fy);
    if let Some(fork) = forces.fork_for(n) {
        // The rollers in two halves on two threads: each roller's update
        // is its own, so the bits are those of one thread.
        let (vx, x) = (Halves::new(&mut state.vx), Halves::new(&mut state.x));
        let (vy, y) = (Halves::new(&mut state.vy), Halves::new(&mut state.y));
        fork.both(&|h| {
            let (lo, hi) = chunk(n, h);
            // SAFETY: the halves take disjoint ranges of the state's
            // vectors, borrowed for the whole `both`.
            unsafe {
                kick_drift(
                    vx.range(lo, hi),
                    x.range(lo, hi),
                    &fx[lo..hi],
                    h_kick,
                    dt_s,
                    scale,
                );
                kick_drift(
                    vy.range(lo, hi),
                    y.range(lo, hi),
                    &fy[lo..hi],
                    h_kick,
                    dt_s,
                    scale,
                );
            }
        });
    } else {
        kick_drift(&mut state.vx, &mut state.x, fx, h_kick, dt_s, scale);
        kick_drift(&mut state.vy, &mut state.y, fy, h_kick, dt_s, scale);
    }
    advance_sprockets(model, state, forces, dt_s, relax, scale);
}

/// [`symplectic_euler`] in a run (no relaxation), with the links'
/// evaluation at the new state made in the same pass over the rollers
/// where the drive is large ([`ForceGenerator::step_rollers_and_links`]).
/// Returns whether it was: then finish the evaluation with
/// [`ForceGenerator::evaluate_after_links`], else with
/// [`ForceGenerator::evaluate`]. The same bits either way.
pub(crate) fn symplectic_euler_with_links(
    model: &DriveModel,
    state: &mut DriveState,
    forces: &mut ForceGenerator,
    dt_s: f64,
) -> bool {
    let kick = Kick {
        h: dt_s / model.roller_mass_kg,
        dt_s,
        scale: 1.0,
    };
    if !forces.step_rollers_and_links(model, state, kick) {
        symplectic_euler(model, state, forces, dt_s, None);
        return false;
    }
    advance_sprockets(model, state, forces, dt_s, None, 1.0);
    true
}

/// The sprockets', further bodies' and scalar states' part of
/// [`symplectic_euler`], and the clock; `scale` is the relaxation's
/// velocity factor (1 in a run).
fn advance_sprockets(
    model: &DriveModel,
    state: &mut DriveState,
    forces: &ForceGenerator,
    dt_s: f64,
    relax: Option<Relaxation>,
    scale: f64,
) {
    for (s, sp) in model.sprockets.iter().enumerate() {
        // A torque-driven driver is held as the kinematic one while the
        // drive relaxes.
        let omega = if sp.speed_law.is_some() || (relax.is_some() && sp.governor.is_some()) {
            if relax.is_some() {
                0.0
            } else {
                driver_speed(model, s, state.t_s, state.theta[s], dt_s)
            }
        } else {
            let load = if relax.is_some() {
                sp.load_at_rest_n_m()
            } else {
                sp.torque_at(state.t_s, state.theta[s], state.omega[s])
            };
            let torque = forces.output().chain_torque[s] + load;
            (state.omega[s] + dt_s * torque * sp.inv_inertia) * scale
        };
        state.omega[s] = omega;
        state.theta[s] += dt_s * omega;
    }
    advance_extras(model, state, forces.output(), dt_s, scale);
    state.t_s += dt_s;
}

/// Symplectic Euler for the further bodies' coordinates (u ← (u + dt·Q/m)·scale,
/// q ← q + dt·u) and explicit Euler for the scalar states (z ← z + dt·ż).
/// `scale` is the relaxation's velocity factor (1 in a run).
pub(crate) fn advance_extras(
    model: &DriveModel,
    state: &mut DriveState,
    forces: &Forces,
    dt_s: f64,
    scale: f64,
) {
    for (k, body) in model.bodies.iter().enumerate() {
        state.u[k] = (state.u[k] + dt_s * forces.body_force[k] * body.inv_mass) * scale;
        state.q[k] += dt_s * state.u[k];
    }
    for (z, rate) in state.z.iter_mut().zip(&forces.scalar_rate) {
        *z += dt_s * rate;
    }
}
