//! A chain set moving with a mount that already turns when the drive is
//! inserted.
//!
//! The equilibrium leaves the chain at rest. When a mount turns at ω, the
//! chain is given the belt motion it would have at that speed: every roller
//! moves along the chain's path at the belt speed s, every free sprocket
//! turns at the speed its seated rollers give it. The path's tangent at
//! roller i is taken along the chord from roller i − 1 to i + 1 (exact on a
//! wrap of equal pitches, where that chord is perpendicular to the radius at
//! roller i; exact on a straight span).

use crate::model::{DriveModel, DriveState};

/// The unit tangents of the chain's path at each roller, along increasing
/// roller index; `None` where two neighbours coincide.
fn tangents(state: &DriveState) -> Vec<Option<[f64; 2]>> {
    let n = state.rollers();
    (0..n)
        .map(|i| {
            let (a, b) = ((i + n - 1) % n, (i + 1) % n);
            let d = [state.x[b] - state.x[a], state.y[b] - state.y[a]];
            let len = d[0].hypot(d[1]);
            (len > 0.0).then(|| [d[0] / len, d[1] / len])
        })
        .collect()
}

/// A roller seated mid-wrap on sprocket `k`: of the rollers within a
/// fifth of a pitch of its pitch circle, the one whose path tangent is most
/// nearly perpendicular to its radius (at a wrap's ends the chord to the
/// span's roller is not).
fn seated_roller(model: &DriveModel, state: &DriveState, k: usize) -> Option<usize> {
    let sp = &model.sprockets[k];
    let t = tangents(state);
    let band = 0.2 * model.rest_length_m;
    (0..state.rollers())
        .filter_map(|i| {
            let r = [state.x[i] - sp.center_m[0], state.y[i] - sp.center_m[1]];
            let len = r[0].hypot(r[1]);
            let t = t[i]?;
            ((len - sp.pitch_radius_m).abs() < band && len > 0.0)
                .then(|| (i, (r[0] * t[1] - r[1] * t[0]).abs() / len))
        })
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(i, _)| i)
}

/// The belt speed (along increasing roller index) at which sprocket `k`
/// turning at `omega_rad_s` moves the chain, m/s.
pub(super) fn belt_speed(
    model: &DriveModel,
    state: &DriveState,
    k: usize,
    omega_rad_s: f64,
) -> Option<f64> {
    let t = tangents(state);
    let i = seated_roller(model, state, k)?;
    let c = model.sprockets[k].center_m;
    let lever = [state.x[i] - c[0], state.y[i] - c[1]];
    // v = ω ẑ × r
    let v = [-omega_rad_s * lever[1], omega_rad_s * lever[0]];
    t[i].map(|t| v[0] * t[0] + v[1] * t[1])
}

/// Sprocket `k`'s speed when the chain moves at belt speed `s`, rad/s.
pub(super) fn sprocket_speed(model: &DriveModel, state: &DriveState, k: usize, s: f64) -> f64 {
    let t = tangents(state);
    let Some(i) = seated_roller(model, state, k) else {
        return 0.0;
    };
    let Some(t) = t[i] else { return 0.0 };
    let c = model.sprockets[k].center_m;
    let lever = [state.x[i] - c[0], state.y[i] - c[1]];
    let r2 = lever[0] * lever[0] + lever[1] * lever[1];
    if r2 > 0.0 {
        // ω = (r × v) / |r|²
        (lever[0] * s * t[1] - lever[1] * s * t[0]) / r2
    } else {
        0.0
    }
}

/// Sets every roller moving at belt speed `s` along the path and every
/// sprocket at the speed that gives.
pub(super) fn set_belt_motion(model: &DriveModel, state: &mut DriveState, s: f64) {
    let t = tangents(state);
    for (i, t) in t.iter().enumerate() {
        let [tx, ty] = t.unwrap_or([0.0; 2]);
        state.vx[i] = s * tx;
        state.vy[i] = s * ty;
    }
    for k in 0..model.sprocket_count() {
        state.omega[k] = sprocket_speed(model, state, k, s);
    }
}
