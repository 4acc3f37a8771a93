//! Checks, before relaxing, that a static equilibrium at the requested
//! pretension can exist, so that an infeasible request ends with its cause
//! and the numbers that would fix it rather than with a relaxation that
//! cannot converge. Closed forms only; nothing here steps the chain.
//!
//! - **Chain too short** (rest-length rule). The layout keeps the wrap links
//!   one pitch P long and lets the free links share the excess ΔL = (length of
//!   the path through the seated rollers) − N·P. At the pretension T₀ a free
//!   link is l₀ + T₀/K long, and a wrap link (P) must not be shorter than its
//!   rest length l₀, or it would carry compression. So ΔL / n_free ≤ T₀ / K:
//!   the pretension can take up at most n_free·T₀/K of missing length. The
//!   check fires only beyond twice that plus a tenth of a pitch: the rollers
//!   on the wraps give up some length in their gaps' clearance, and a chain
//!   a little too short settles with the wrap links slightly compressed
//!   (l₀ a few micrometres above P). A chain a quarter pitch short is far
//!   beyond: its free links would carry hundreds of kilonewtons.
//! - **Load beyond the pretension** (two-sprocket drives). With the driver
//!   held, a load torque M on the free sprocket (pitch radius R) makes the
//!   strands' tensions differ by |M|/R. The chain's length is fixed, so the
//!   strands' stretches change in opposite directions, and the pooled mean
//!   over the free links stays T₀: n_t ΔT_t = n_s ΔT_s with
//!   ΔT_t + ΔT_s = |M|/R, so the slack strand carries
//!   T₀ − |M| n_t / (R (n_t + n_s)). It would need compression unless
//!   T₀ ≥ |M| n_t / (R (n_t + n_s)); for equal strands T₀ ≥ |M| / (2R). The
//!   check takes the shorter strand as n_t (the lower bound of the two), so
//!   it never rejects a drive that could settle.

use super::equilibrium::EquilibriumError;
use crate::geometry::Layout;
use crate::scene::{Role, Scene};

/// Factor on the length the pretension can take up beyond which a chain is
/// reported too short.
const SHORT_MARGIN: f64 = 2.0;
/// Further missing length tolerated, in pitches.
const SHORT_MARGIN_PITCHES: f64 = 0.1;

/// The chain is not too short for the pretension (rest-length rule).
pub(crate) fn check_chain_length(scene: &Scene, layout: &Layout) -> Result<(), EquilibriumError> {
    let chain = &scene.chain;
    let chain_m = chain.rollers as f64 * chain.pitch_m;
    let short_m = layout.polygon_length_m - chain_m;
    let free_links: usize = layout.strand_links.iter().sum();
    let allowed_m = free_links as f64 * chain.pretension_n / chain.stiffness_n_m;
    if free_links > 0 && short_m > SHORT_MARGIN * allowed_m + SHORT_MARGIN_PITCHES * chain.pitch_m {
        return Err(EquilibriumError::ChainTooShort {
            short_m,
            short_pitches: short_m / chain.pitch_m,
            free_links,
            allowed_m,
            needed_tension_n: chain.stiffness_n_m * short_m / free_links as f64,
        });
    }
    Ok(())
}

/// No load torque needs the slack strand in compression (two-sprocket drives).
pub(crate) fn check_load(scene: &Scene, layout: &Layout) -> Result<(), EquilibriumError> {
    let [n1, n2] = layout.strand_links[..] else {
        return Ok(());
    };
    if scene.sprockets.len() != 2 || n1 + n2 == 0 {
        return Ok(());
    }
    let t0 = scene.chain.pretension_n;
    for sp in &scene.sprockets {
        // A ramped load is not held at rest: the equilibrium carries none.
        if matches!(sp.role, Role::Driver(_)) || sp.load_ramp_s() > 0.0 {
            continue;
        }
        let m = sp.load_torque_n_m().abs();
        // T₀ ≥ |M| n_t / (R (n_t + n_s)), n_t the shorter strand (module docs).
        let share = n1.min(n2) as f64 / (n1 + n2) as f64;
        let needed_n = m * share / sp.pitch_radius_m;
        if needed_n > t0 {
            return Err(EquilibriumError::LoadBeyondPretension {
                sprocket: sp.name.clone(),
                load_n_m: sp.load_torque_n_m(),
                limit_n_m: t0 * sp.pitch_radius_m / share,
                pretension_n: t0,
                needed_n,
            });
        }
    }
    Ok(())
}
