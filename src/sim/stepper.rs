//! One step of the plugin's own integrator on the structure-of-arrays state.
//!
//! Symplectic (semi-implicit) Euler, the scheme rapier itself uses:
//! v ← v + dt·f(x, v)/m, then x ← x + dt·v. Free sprockets turn under the
//! chain's moment plus their load; the driver follows its speed law, sampled
//! at the step's midpoint so that a ramp's angle is integrated exactly.

use crate::forces::ForceGenerator;
use crate::model::{DriveModel, DriveState};

/// Extra viscous damping used only while relaxing to static equilibrium:
/// velocities are scaled by 1 / (1 + dt·rate) each step (unconditionally stable).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Relaxation {
    /// Damping rate, 1/s.
    pub rate_per_s: f64,
}

/// The driver's angular speed over the step starting at `t_s` (midpoint rule).
#[inline]
pub fn driver_speed(model: &DriveModel, sprocket: usize, t_s: f64, dt_s: f64) -> f64 {
    model.sprockets[sprocket]
        .speed_law
        .map_or(0.0, |law| law.speed_at(t_s + 0.5 * dt_s))
}

/// Advances `state` by `dt_s`. `forces` must hold the forces at `state`
/// (call [`ForceGenerator::evaluate`] first). With `relax`, the driver is held
/// and every velocity is damped.
pub fn symplectic_euler(
    model: &DriveModel,
    state: &mut DriveState,
    forces: &ForceGenerator,
    dt_s: f64,
    relax: Option<Relaxation>,
) {
    let h = dt_s / model.roller_mass_kg;
    let scale = relax.map_or(1.0, |r| 1.0 / (1.0 + dt_s * r.rate_per_s));
    kick_drift(&mut state.vx, &mut state.x, &forces.fx, h, dt_s, scale);
    kick_drift(&mut state.vy, &mut state.y, &forces.fy, h, dt_s, scale);
    for (s, sp) in model.sprockets.iter().enumerate() {
        let omega = if sp.speed_law.is_some() {
            if relax.is_some() {
                0.0
            } else {
                driver_speed(model, s, state.t_s, dt_s)
            }
        } else {
            let torque = forces.chain_torque[s] + sp.load_torque_n_m;
            (state.omega[s] + dt_s * torque * sp.inv_inertia) * scale
        };
        state.omega[s] = omega;
        state.theta[s] += dt_s * omega;
    }
    state.t_s += dt_s;
}

/// One coordinate of the rollers' update: v ← (v + h·f)·scale, x ← x + dt·v.
/// Slices as arguments tell the compiler they do not overlap, so it
/// vectorises the loop.
#[inline(never)]
fn kick_drift(v: &mut [f64], x: &mut [f64], f: &[f64], h: f64, dt_s: f64, scale: f64) {
    for ((v, x), f) in v.iter_mut().zip(x).zip(f) {
        *v = (*v + h * f) * scale;
        *x += dt_s * *v;
    }
}
