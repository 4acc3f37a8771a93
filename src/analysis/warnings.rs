//! Warnings where a run's result is suspect (the summary's `warnings`, a line
//! each on `run`'s stderr). Each criterion and its threshold is documented in
//! docs/model.md, "Warnings"; none fires on the paper's drive at 120 rpm
//! but the power balance, which its frictionless form misses by about 2 % at
//! the default step.
//!
//! They judge the summary and the statistics window's samples only: no
//! warning stops a run (the blow-up detectors do, [`crate::sim`]).

use super::stats::{STATIONARITY_SE, stationarity as test_stationarity};
use super::summary::{Judged, segment_series};
use crate::scene::Role;

/// Deepest penetration, as a fraction of the roller radius, above which a run
/// is flagged (the paper's drive: 3 % at 120 rpm, 18 % at 600 rpm).
pub const PENETRATION_FRACTION: f64 = 0.1;

/// Tolerance of the energy balance, as a fraction of the power that flows
/// through the drive.
pub const ENERGY_BALANCE_TOLERANCE: f64 = 0.01;

/// The slackest strand's mean force above this multiple of static + m v² is
/// flagged: an excess of 15 %, beyond what the tooth-passing geometry alone
/// gives at a crawl (under 2 % on the flat 20T/40T drive at 20 rpm) and
/// what the paper's drive gives at 120 rpm (1 %); docs/model.md, "Running
/// tension".
pub const RUNNING_TENSION_RATIO: f64 = 1.15;

/// Largest roller force imbalance at the static equilibrium, as a fraction
/// of the pretension, above which a run is flagged: the relaxation stops at
/// 10⁻⁶ when it settles; a thousand times that is a start that is not at
/// rest, whose release the window may still hold.
pub const STATIC_RESIDUAL_TOLERANCE: f64 = 1e-3;

/// The warnings of a run, one sentence each.
pub(crate) fn of_run(j: &Judged<'_>) -> Vec<String> {
    [
        unsettled_start(j),
        penetration(j),
        energy_balance(j),
        power_balance(j),
        compression(j),
        running_tension(j),
        stationarity(j),
    ]
    .into_iter()
    .flatten()
    .chain(
        j.summary
            .rating
            .iter()
            .flat_map(|r| super::design::rating::warnings(j.scene, r, j.summary.link_force_max_n)),
    )
    .collect()
}

fn unsettled_start(j: &Judged<'_>) -> Option<String> {
    let residual = j.summary.static_force_residual?;
    (residual > STATIC_RESIDUAL_TOLERANCE || residual.is_nan()).then(|| {
        format!(
            "unsettled start: the static equilibrium left a roller force imbalance of {:.1e} of the pretension ({:.0} N; warning above {:.0e}), so the run starts from a state that is not at rest and its first transients are partly the release of that imbalance: run `chaindrive check` to see it, raise equilibrium.max_relax_s, or choose a later window (--window)",
            residual,
            residual * j.scene.chain.pretension_n,
            STATIC_RESIDUAL_TOLERANCE
        ) + &j.unsettled_cause.map(|c| format!("; the cause: {c}")).unwrap_or_default()
    })
}

fn penetration(j: &Judged<'_>) -> Option<String> {
    let r = j.scene.chain.roller_radius_m;
    let depth = j.summary.max_penetration_m;
    (depth > PENETRATION_FRACTION * r).then(|| {
        format!(
            "penetration: a roller sank {:.2} mm into a tooth, {:.0} % of the roller radius (warning above {:.0} %); the contact law is fitted to small depths, so forces this deep are an extrapolation: consider a stiffer contact (contact.stiffness) or check the load",
            depth * 1e3,
            100.0 * depth / r,
            100.0 * PENETRATION_FRACTION
        )
    })
}

/// Energy balance over the window, at steady driver speed: the driver and
/// the load torques are the only sources; links' damping and contact
/// hysteresis only dissipate, gravity does no net work over a cycle. So the
/// net power in, P_driver + Σ τ_load ω̄, cannot be negative. A deficit beyond
/// [`ENERGY_BALANCE_TOLERANCE`] of the power flowing through (mean
/// |P_driver| + Σ |τ_load ω̄|) is energy the integration made.
fn energy_balance(j: &Judged<'_>) -> Option<String> {
    let rows = j.window_rows;
    let first = rows.first()?;
    let driver = j
        .scene
        .sprockets
        .iter()
        .position(|s| matches!(s.role, Role::Driver(_)))?;
    // Before the ramp's end the chain's kinetic energy is still growing; before
    // a load ramp's end the load is not the constant assumed below.
    if first.t_s < j.ramp_s
        || j.scene
            .sprockets
            .iter()
            .any(|s| first.t_s < s.load_ramp_s())
    {
        return None;
    }
    let n = rows.len() as f64;
    let mean_speed = |s: usize| rows.iter().map(|r| r.omega_rad_s[s]).sum::<f64>() / n;
    let abs_driver_power = rows
        .iter()
        .map(|r| (r.chain_torque_n_m[driver] * r.omega_rad_s[driver]).abs())
        .sum::<f64>()
        / n;
    let loads: Vec<f64> = j
        .scene
        .sprockets
        .iter()
        .enumerate()
        .map(|(s, sp)| sp.load_torque_n_m() * mean_speed(s))
        .collect();
    let net = j.summary.driver_mean_power_w + loads.iter().sum::<f64>();
    let through = abs_driver_power + loads.iter().map(|p| p.abs()).sum::<f64>();
    (through > 0.0 && net < -ENERGY_BALANCE_TOLERANCE * through).then(|| {
        format!(
            "energy balance: the driver and the loads put {net:.1} W net into the drive, below zero by {:.1} % of the {through:.1} W flowing through (tolerance {:.0} %); nothing in the model can supply it: the step is likely too large for the contacts (reduce solver.dt_s)",
            -100.0 * net / through,
            100.0 * ENERGY_BALANCE_TOLERANCE
        )
    })
}

/// The counted power flow ([`crate::sim::PowerLedger`]): driver power =
/// losses + load power + dE/dt to [`ENERGY_BALANCE_TOLERANCE`] of the power
/// flowing through. A larger residual is energy the integration made or lost.
fn power_balance(j: &Judged<'_>) -> Option<String> {
    let error = j.summary.energy_balance_error?;
    (error.abs() > ENERGY_BALANCE_TOLERANCE).then(|| {
        format!(
            "power balance: driver power = losses + load power + dE/dt holds to {:.1} % of the power flowing through over the window (tolerance {:.0} %); the integration is not conserving energy at this step: reduce solver.dt_s",
            100.0 * error,
            100.0 * ENERGY_BALANCE_TOLERANCE
        )
    })
}

fn compression(j: &Judged<'_>) -> Option<String> {
    let min = j.summary.link_force_min_n;
    (min < 0.0).then(|| {
        format!(
            "link compression: the smallest link force was {min:.1} N; the model's links push as well as pull (a spring-damper both ways), a real chain's do not, so results where slack strands or impacts matter are stiffer than the chain (docs/model.md, \"Link compression\")"
        )
    })
}

/// The slackest strand runs at about static + m v² (the centrifugal tension
/// of a moving string); far above it, the free strands' transverse vibration
/// (excited by polygonal action at the tooth frequency) takes up chain
/// length, which a closed chain of fixed length pays for by stretching
/// every link: measured, not assumed (docs/model.md, "Running tension").
fn running_tension(j: &Judged<'_>) -> Option<String> {
    let slack = j
        .summary
        .segments
        .iter()
        .map(|s| s.mean_link_force_n)
        .fold(f64::INFINITY, f64::min);
    if !slack.is_finite() {
        return None;
    }
    let chain = &j.scene.chain;
    let centrifugal = chain.roller_mass_kg / chain.pitch_m * j.chain_speed_m_s.powi(2);
    let expected = j.summary.static_tension_n + centrifugal;
    (expected > 0.0 && slack > RUNNING_TENSION_RATIO * expected).then(|| {
        format!(
            "running tension: the slackest strand's mean force is {slack:.0} N, {:.2} times static + m v² = {:.0} + {centrifugal:.0} N (warning above {RUNNING_TENSION_RATIO}); the cause is the free strands' transverse vibration, excited by polygonal action at the tooth frequency: bent strands take up chain length, which a closed chain of fixed length pays for by stretching every link; the strands' statistics describe that vibrating state, not the static design (see docs/model.md, \"Running tension\")",
            slack / expected,
            j.summary.static_tension_n
        )
    })
}

/// A segment whose mean link force is not steady over the window (first
/// against last third, [`super::stats`]): its mean, and everything derived
/// from it, depends on when the run stops.
fn stationarity(j: &Judged<'_>) -> Option<String> {
    let drifting: Vec<String> = j
        .summary
        .segments
        .iter()
        .filter(|s| !s.stationary)
        .map(|s| {
            let t = test_stationarity(&segment_series(j.window_rows, s.segment - 1));
            format!(
                "segment {} ({:.0} N in the first third, {:.0} N in the last, {:.1} standard errors apart)",
                s.segment,
                t.first_mean,
                t.last_mean,
                t.z()
            )
        })
        .collect();
    (!drifting.is_empty()).then(|| {
        format!(
            "not stationary: the mean link force drifts over the window {:.2}–{:.2} s in {} (allowed: {STATIONARITY_SE:.0}); the means depend on when the run stops and their standard errors understate the uncertainty: run longer, or choose a later or longer window (--window)",
            j.summary.window_s[0],
            j.summary.window_s[1],
            drifting.join(", ")
        )
    })
}
