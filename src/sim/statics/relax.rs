//! The relaxation: the chain stepped under extra viscous damping until it is
//! at rest (or a time limit), and the checks of "at rest". It knows nothing
//! of the pretension rule or of Newton's settling, which call it.

use crate::forces::ForceGenerator;
use crate::model::{DriveModel, DriveState};
use crate::sim::integrate::implicit_damping_step;
use crate::sim::stepper::Relaxation;

use super::error::EquilibriumError;

/// Settings of the relaxation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct RelaxSettings {
    /// Integration step, s.
    pub dt_s: f64,
    /// Largest relaxation time, s.
    pub max_time_s: f64,
    /// Damping rate, 1/s.
    pub rate_per_s: f64,
    /// Stop when every roller is slower than this, m/s.
    pub rest_speed_m_s: f64,
    /// Blow-up bound on the link stretch, m.
    pub max_stretch_m: f64,
}

#[cfg(test)]
thread_local! {
    /// Relaxations started on this thread ([`relax_until`]): tests count
    /// where a solve fell back on the relaxation.
    pub(crate) static RELAXATIONS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// Relaxes `state` to rest with the driver held. Returns the residual speed.
///
/// Steps symplectic Euler with the contact damping implicit
/// ([`super::integrate`]), so the contact damping puts no limit on the step;
/// the relaxation's own damping (`rate_per_s`) brings everything to rest.
pub(crate) fn relax(
    model: &DriveModel,
    state: &mut DriveState,
    forces: &mut ForceGenerator,
    settings: &RelaxSettings,
) -> Result<f64, EquilibriumError> {
    relax_until(model, state, forces, settings, None)
}

/// [`relax`], stopping as well once the drive is in equilibrium within
/// `rest_force_n`: every roller's force and its damping force m·rate·|v|
/// below it, and every free sprocket's torque (chain plus load at rest)
/// below it times the pitch radius.
pub(crate) fn relax_until(
    model: &DriveModel,
    state: &mut DriveState,
    forces: &mut ForceGenerator,
    settings: &RelaxSettings,
    rest_force_n: Option<f64>,
) -> Result<f64, EquilibriumError> {
    #[cfg(test)]
    RELAXATIONS.with(|n| n.set(n.get() + 1));
    let relax = Some(Relaxation {
        rate_per_s: settings.rate_per_s,
    });
    // The elements switch to what relaxing needs (the contact: a dissipative
    // law and damping rows for the implicit step).
    forces.begin_equilibrium();
    let mut torque = vec![0.0; model.sprockets.len()];
    let t0 = state.t_s;
    let steps = (settings.max_time_s / settings.dt_s).ceil() as usize;
    let check_every = ((0.01 / settings.dt_s).ceil() as usize).max(1);
    let mut residual = f64::INFINITY;
    let mut blown = None;
    for step in 1..=steps {
        forces.evaluate(model, state);
        if !(forces.output().max_stretch_m <= settings.max_stretch_m) {
            blown = Some(forces.output().max_stretch_m);
            break;
        }
        implicit_damping_step(model, state, forces, settings.dt_s, &mut torque, relax);
        if step % check_every == 0 {
            residual = max_speed(state);
            // The forces are those before the step just taken: the final
            // residual is evaluated anew below.
            if residual < settings.rest_speed_m_s
                || rest_force_n.is_some_and(|f| {
                    model.roller_mass_kg * settings.rate_per_s * residual <= f
                        && at_rest(model, forces, f)
                })
            {
                break;
            }
        }
    }
    forces.end_equilibrium();
    if let Some(stretch_m) = blown {
        return Err(EquilibriumError::BlowUp { stretch_m });
    }
    state.t_s = t0;
    state.vx.fill(0.0);
    state.vy.fill(0.0);
    state.omega.fill(0.0);
    state.u.fill(0.0);
    forces.reset_memory();
    forces.evaluate(model, state);
    Ok(residual)
}

/// Every roller's force below `force_n` and every free sprocket's torque
/// below `force_n` times its pitch radius. `forces` evaluated at the state.
fn at_rest(model: &DriveModel, forces: &ForceGenerator, force_n: f64) -> bool {
    let out = forces.output();
    let rollers = out
        .fx
        .iter()
        .zip(&out.fy)
        .all(|(x, y)| x.hypot(*y) <= force_n);
    rollers
        && worst_sprocket(model, forces)
            .is_none_or(|(s, m)| m.abs() <= force_n * model.sprockets[s].pitch_radius_m)
}

/// The free sprocket with the largest torque out of balance (chain plus load
/// at rest) relative to its pitch radius, and that torque, N·m.
pub(super) fn worst_sprocket(model: &DriveModel, forces: &ForceGenerator) -> Option<(usize, f64)> {
    let out = forces.output();
    model
        .sprockets
        .iter()
        .enumerate()
        .filter(|(_, sp)| !sp.still_in_statics())
        .map(|(s, sp)| (s, out.chain_torque[s] + sp.load_at_rest_n_m()))
        .max_by(|a, b| {
            let ra = a.1.abs() / model.sprockets[a.0].pitch_radius_m;
            let rb = b.1.abs() / model.sprockets[b.0].pitch_radius_m;
            ra.total_cmp(&rb)
        })
}

/// The body furthest from equilibrium, for a message: a free sprocket's
/// torque or a roller's force, whichever is larger against the pretension
/// (a torque counted as torque / pitch radius).
pub(super) fn unsettled_body(
    model: &DriveModel,
    forces: &ForceGenerator,
    names: &[&str],
) -> (String, f64) {
    let out = forces.output();
    let (roller, force) = out
        .fx
        .iter()
        .zip(&out.fy)
        .map(|(x, y)| x.hypot(*y))
        .enumerate()
        .fold((0, 0.0), |a, (i, f)| if f > a.1 { (i, f) } else { a });
    let roller_text = format!("roller {roller} did not settle: residual force {force:.3e} N");
    match worst_sprocket(model, forces) {
        Some((s, m)) if m.abs() / model.sprockets[s].pitch_radius_m > force => {
            let name = names
                .get(s)
                .map_or_else(|| format!("{}", s + 1), |n| (*n).to_owned());
            (
                format!("sprocket \"{name}\" did not settle: residual torque {m:.3e} N·m"),
                m.abs() / model.sprockets[s].pitch_radius_m,
            )
        }
        _ => (roller_text, force),
    }
}

fn max_speed(state: &DriveState) -> f64 {
    state
        .vx
        .iter()
        .zip(&state.vy)
        .map(|(x, y)| x.hypot(*y))
        .fold(0.0, f64::max)
}
