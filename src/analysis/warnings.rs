//! Warnings where a run's result is suspect (the summary's `warnings`, a line
//! each on `run`'s stderr). Each criterion and its threshold is documented in
//! docs/model.md, "Warnings"; none fires on the paper's drive as it comes
//! (`chaindrive run`).
//!
//! They judge the summary and the statistics window's samples only: no
//! warning stops a run (the blow-up detectors do, [`crate::sim`]).

use super::stats::{STATIONARITY_SE, stationarity as test_stationarity};
use super::window::{DEFAULT_WINDOW_S, holds, last_ramp};
use super::{RunSummary, SampleRow, segment_series};
use crate::scene::stability::running_force_n;
use crate::scene::{Integrator, ProfileKind, Scene, StepLimits, micro};
use crate::sim::PowerMeans;

/// Deepest penetration, as a fraction of the roller radius, above which a run
/// is flagged (the paper's drive: 3 % at 120 rpm, 18 % at 600 rpm).
pub(crate) const PENETRATION_FRACTION: f64 = 0.1;

/// Tolerance of the energy balance, as a fraction of the power that flows
/// through the drive.
pub(crate) const ENERGY_BALANCE_TOLERANCE: f64 = 0.01;

/// The slackest strand's mean force above this multiple of static + m v² is
/// flagged: an excess of 15 %, beyond what the tooth-passing geometry alone
/// gives at a crawl (under 2 % on the flat 20T/40T drive at 20 rpm) and
/// what the paper's drive gives at 120 rpm (1 %); docs/model.md, "Running
/// tension".
pub(crate) const RUNNING_TENSION_RATIO: f64 = 1.15;

/// Largest roller force imbalance at the static equilibrium, as a fraction
/// of the pretension, above which a run is flagged: the relaxation stops at
/// 10⁻⁶ when it settles; a thousand times that is a start that is not at
/// rest, whose release the window may still hold.
pub(crate) const STATIC_RESIDUAL_TOLERANCE: f64 = 1e-3;

/// Harmonics of the tooth-passing frequency judged for aliasing: the
/// polygonal action's speed and force swings are strongest in the first
/// few (the impacts' sharp peaks reach higher, and the means, which they
/// would bias most, are counted every step).
pub(crate) const ALIAS_HARMONICS: u32 = 3;

/// An alias (a harmonic's distance to the nearest multiple of the sample
/// rate) below this is flagged, Hz: it falls among the slow swings the
/// sampled statistics read (the 1–50 Hz transverse peak, 20 batches of a
/// 1 s window at 20 Hz, the thirds of the stationarity test).
pub(crate) const ALIAS_BAND_HZ: f64 = 50.0;

/// What the warnings judge: the summary and the window's rows.
pub(crate) struct Judged<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// The summary, warnings not yet filled in.
    pub summary: &'a RunSummary,
    /// The samples of the statistics window.
    pub window_rows: &'a [&'a SampleRow],
    /// The mean chain speed over the window, m/s.
    pub chain_speed_m_s: f64,
    /// Why the static equilibrium's state is not at rest, where known.
    pub unsettled_cause: Option<&'a str>,
    /// The window's counted power flow, where it was counted.
    pub power_flow: Option<PowerMeans>,
}

/// The warnings of a run, one sentence each.
pub(crate) fn of_run(j: &Judged<'_>) -> Vec<String> {
    [
        unsettled_start(j),
        ramp_in_window(j),
        penetration(j),
        power_balance(j),
        aliasing(j),
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
    .chain(
        j.summary
            .fatigue
            .iter()
            .flat_map(super::design::fatigue::warnings),
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

/// The counted power flow ([`crate::sim::PowerLedger`]): driver power =
/// losses + load power + dE/dt to [`ENERGY_BALANCE_TOLERANCE`] of the power
/// flowing through. The one balance the summary judges, on the number it
/// reports (`energy_balance_error`): a negative residual is energy the
/// integration made (more dissipated and stored than the driver and the
/// loads put in), a positive one energy it lost.
///
/// What it advises depends on what the window shows. Where the drive's
/// stored energy changed faster than power flowed through it (a drive that
/// carries almost nothing, still giving up the energy of its start), the
/// residual is a fraction of a small number and the window is not steady:
/// it says so rather than blame the step. A second-order integrator is
/// advised only where a first-order one ran.
fn power_balance(j: &Judged<'_>) -> Option<String> {
    let error = j.summary.energy_balance_error?;
    if !(error.abs() > ENERGY_BALANCE_TOLERANCE || error.is_nan()) {
        return None;
    }
    let made = if error < 0.0 {
        "more energy dissipated and stored than the driver and the loads put in: the integration made it"
    } else {
        "less energy dissipated and stored than the driver and the loads put in: the integration lost it"
    };
    let head = format!(
        "power balance: driver power = losses + load power + dE/dt holds to {:.1} % of the power flowing through over the window (tolerance {:.0} %); {made}",
        100.0 * error,
        100.0 * ENERGY_BALANCE_TOLERANCE
    );
    let unsteady = j.power_flow.and_then(|p| {
        let through = p.mean.driver_w.abs().max(p.mean.load_w.abs());
        let stored = p.energy_change_j / p.duration_s;
        (stored.abs() > through).then_some((stored, through))
    });
    if let Some((stored, through)) = unsteady {
        let way = if stored < 0.0 { "gave up" } else { "took up" };
        return Some(format!(
            "{head}, but the drive's stored energy {way} {:.3} W over the window, more than the {:.3} W flowing through it: the window is not steady (the drive still settling from its start, or carrying almost nothing), so this residual is a fraction of a small flow: choose a later or longer window (--window), or load the drive, before judging the step by it (docs/model.md, \"Where the power goes\")",
            stored.abs(),
            through
        ));
    }
    if let Some(bound) = loaded_contact_damping(j) {
        return Some(format!(
            "{head}; {bound} (docs/model.md, \"Time scales and stability\")"
        ));
    }
    let remedy = match j.scene.solver().integrator {
        Integrator::SymplecticEuler | Integrator::ImplicitDamping => {
            "reduce solver.dt_s, or take a second-order integrator (solver.integrator = \"velocity_verlet\")"
        }
        _ => "reduce solver.dt_s",
    };
    // The circular seat cuts a loaded roller's force at once where it
    // leaves the seat's arc (and starts it at once where it enters): work
    // that neither the law's damping nor its stored energy counts, whatever
    // the step. One run cannot tell that from the step's error; the real
    // profile, whose force is continuous, can.
    let circular = j
        .scene
        .sprockets
        .iter()
        .any(|s| s.profile == ProfileKind::Circular);
    if error < 0.0 && circular {
        return Some(format!(
            "{head}: either the step is too large for this drive's energy flows ({remedy}), or, on the circular profile, a loaded roller's force jumps where it crosses the edge of a seat's arc, which the power count does not see and no step removes: run the drive with profile = \"real\" (or `--profile real`), whose force is continuous; a balance that closes there is the seats' edge (docs/model.md, \"Where the power goes\")"
        ));
    }
    Some(format!(
        "{head}, so the step is too large for this drive's energy flows: {remedy} (docs/model.md, \"Where the power goes\")"
    ))
}

/// Where the run's step exceeds the explicit contact damping's bound at the
/// tension the drive ran at: a roller engaging the tightest strand at the
/// approach-speed floor has a damping coefficient χ F / δ̇⁻_min, F that
/// strand's mean force. The stability estimate takes F from the pretension
/// and the load torques ([`crate::scene::stability::running_force_n`]), so
/// this names a step given above the estimate's limit, or a drive that ran
/// tighter than the scene's torques say. A smaller step or a scheme that
/// takes the contact damping implicitly cures it; a second-order explicit
/// scheme has the same bound. `None` where the scheme is not bound by the
/// contact damping or the step is within the bound.
fn loaded_contact_damping(j: &Judged<'_>) -> Option<String> {
    let scheme = j.scene.solver().integrator;
    let (chain, contact) = (j.scene.chain(), j.scene.contact());
    let expected = running_force_n(chain, j.scene.sprockets());
    let force = j
        .summary
        .segments
        .iter()
        .map(|s| s.mean_link_force_n)
        .fold(f64::NEG_INFINITY, f64::max);
    if !(force > 0.0) {
        return None;
    }
    let bound_at =
        |tension: f64| StepLimits::at_force(chain, contact, tension).contact_damping_for(scheme);
    let (loaded, estimated) = (bound_at(force)?, bound_at(expected)?);
    let dt = j.summary.dt_s;
    (dt > loaded).then(|| {
        format!(
            "the contact damping bounds this step: the tightest strand ran at {:.2} kN ({:.2} times the {:.2} kN that the stability estimate takes from the pretension and the load torques), and a roller engaging at the approach-speed floor (contact.min_approach_speed_m_s = {}) under that force allows an explicit step of {} against this run's {} (the estimate: {}): take solver.integrator = \"verlet_implicit_damping\" or \"implicit_damping\" (the contact damping taken implicitly; velocity_verlet has the same bound), or solver.dt_s below {}, or a larger contact.min_approach_speed_m_s",
            force / 1e3,
            force / expected,
            expected / 1e3,
            contact.min_approach_speed_m_s,
            micro(loaded),
            micro(dt),
            micro(estimated),
            micro(loaded)
        )
    })
}

/// A window that begins before the scene's last ramp ends
/// ([`super::window::last_ramp`]): its means mix the run-up with the steady
/// state. The default window starts after the ramps; it holds one only when
/// the run ends before them, a chosen window (`--window`) when it reaches
/// back into them, and an interrupted run's when it stopped early.
fn ramp_in_window(j: &Judged<'_>) -> Option<String> {
    let ramp = last_ramp(j.scene)?;
    let [start, end] = j.summary.window_s;
    holds(start, &ramp).then(|| {
        let after = if end > ramp.end_s {
            format!("choose a window that starts after it (at most {:.3} s)", end - ramp.end_s)
        } else {
            "the run ends before it does".to_owned()
        };
        format!(
            "ramp in window: the statistics window {start:.2}–{end:.2} s begins before the end of {} at {:.2} s, so its means and ranges mix the run-up with the steady state ({after}); run {:.2} s or longer for a whole {DEFAULT_WINDOW_S} s window after the ramps",
            ramp.what,
            ramp.end_s,
            ramp.end_s + DEFAULT_WINDOW_S
        )
    })
}

/// A harmonic of a tooth-passing frequency that the samples alias.
struct Alias<'a> {
    sprocket: &'a str,
    teeth: u32,
    tooth_hz: f64,
    harmonic: u32,
    multiple: f64,
    alias_hz: f64,
}

/// The first harmonic (1 to [`ALIAS_HARMONICS`]) of a sprocket's
/// tooth-passing frequency z |ω̄| / 2π above the Nyquist frequency whose
/// alias, its distance to the nearest multiple of the sample rate, falls
/// below [`ALIAS_BAND_HZ`].
fn find_alias<'a>(j: &'a Judged<'_>, rate_hz: f64) -> Option<Alias<'a>> {
    j.scene
        .sprockets
        .iter()
        .zip(&j.summary.sprockets)
        .find_map(|(sp, summary)| {
            let tooth_hz =
                f64::from(sp.teeth) * summary.mean_speed_rad_s.abs() / std::f64::consts::TAU;
            (1..=ALIAS_HARMONICS).find_map(|harmonic| {
                let f = f64::from(harmonic) * tooth_hz;
                let multiple = (f / rate_hz).round();
                let alias_hz = (f - multiple * rate_hz).abs();
                (multiple >= 1.0 && alias_hz < ALIAS_BAND_HZ).then_some(Alias {
                    sprocket: &sp.name,
                    teeth: sp.teeth,
                    tooth_hz,
                    harmonic,
                    multiple,
                    alias_hz,
                })
            })
        })
}

/// A sample rate that aliases a tooth-passing harmonic ([`find_alias`]):
/// the samples see it as a slow swing that is not there.
fn aliasing(j: &Judged<'_>) -> Option<String> {
    let rate = j.summary.sample_rate_hz;
    if !(rate > 0.0) {
        return None;
    }
    let a = find_alias(j, rate)?;
    let harmonic = if a.harmonic == 1 {
        String::new()
    } else {
        format!(
            ", its harmonic {} at {:.1} Hz",
            a.harmonic,
            f64::from(a.harmonic) * a.tooth_hz
        )
    };
    let means = if j.summary.means_every_step {
        "the means are counted every step and are not affected"
    } else {
        "the means, taken from the samples here, are too"
    };
    Some(format!(
        "sample rate: the tooth-passing frequency of sprocket \"{}\" ({} teeth) is {:.1} Hz{harmonic}, {:.1} Hz from {:.0} × the sample rate {rate} Hz (warning below {ALIAS_BAND_HZ} Hz): the samples see it as a swing at {:.1} Hz that is not there, so the sampled statistics (peaks-to-peak, RMS, standard errors, stationarity, spectra) are aliased; {means}: choose a sample rate (--rate) whose multiples keep away from it",
        a.sprocket, a.teeth, a.tooth_hz, a.alias_hz, a.multiple, a.alias_hz
    ))
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
    let centrifugal = chain.mass_per_length_kg_m() * j.chain_speed_m_s.powi(2);
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
/// Rollers that rode the teeth's tips: how often on which sprocket, and
/// the first (docs/model.md, "Riding a tip"); `None` without any.
pub(crate) fn tip_rides(rides: &[super::summary::TipRideSummary]) -> Option<String> {
    let first = rides
        .iter()
        .min_by(|a, b| a.first_t_s.total_cmp(&b.first_t_s))?;
    let total: usize = rides.iter().map(|r| r.count).sum();
    let places = rides
        .iter()
        .map(|r| format!("{} on sprocket {}", r.count, r.sprocket))
        .collect::<Vec<_>>()
        .join(", ");
    Some(format!(
        "tip ride: rollers rode the teeth's tips {total} time(s) ({places}), first at t = {:.4} s, roller {} on sprocket {}: the chain is all but out of mesh there and one disturbance from jumping a tooth; a worn chain's rollers climb the flanks to the tips at about 336/z % elongation, sooner under a fluctuating load (docs/model.md, \"Riding a tip\")",
        first.first_t_s, first.first_roller, first.sprocket
    ))
}

/// A chain that jumped teeth: how often, the first jump, and where it
/// happened most (docs/model.md, "Tooth jump"); `None` without any.
pub(crate) fn tooth_jumps(jumps: &[super::ToothJumpSummary]) -> Option<String> {
    let first = jumps.first()?;
    let mut per_sprocket: Vec<(usize, usize)> = Vec::new();
    for j in jumps {
        match per_sprocket.iter_mut().find(|(s, _)| *s == j.sprocket) {
            Some((_, n)) => *n += 1,
            None => per_sprocket.push((j.sprocket, 1)),
        }
    }
    let places = per_sprocket
        .iter()
        .map(|(s, n)| format!("{n} on sprocket {s}"))
        .collect::<Vec<_>>()
        .join(", ");
    Some(format!(
        "tooth jump: the chain jumped {} time(s) ({places}), first at t = {:.4} s, roller {} {} gap(s) {} on sprocket {}; the forces after it are those of a chain out of mesh (checks.tooth_jump = \"stop\" ends a run there)",
        jumps.len(),
        first.t_s,
        first.roller,
        first.gaps.abs(),
        first.direction,
        first.sprocket
    ))
}
