//! Static equilibrium before t = 0 (docs/model.md, “Pretension and static
//! equilibrium”): the driver is held, gravity
//! acts as set, and the chain relaxes under extra viscous damping until it is
//! at rest. The pretension rule then iterates: with `rest_length`, the links'
//! rest length is corrected by a secant iteration until the mean link force of
//! all free strands equals the pretension.

use crate::forces::ForceGenerator;
use crate::model::{DriveModel, DriveState};

use super::error::{BeyondSeatingArc, EquilibriumError};
use super::relax::{RelaxSettings, unsettled_body, worst_sprocket};
use super::tension::free_strand_tension;

/// Outcome of the static equilibrium.
#[derive(Clone, Debug, PartialEq)]
pub struct StaticEquilibrium {
    /// Mean link force over the links of all free strands, N.
    pub tension_n: f64,
    /// Links' rest length, m.
    pub rest_length_m: f64,
    /// Pretension iterations used.
    pub iterations: usize,
    /// Largest roller speed left at the end of the last relaxation, m/s.
    pub residual_speed_m_s: f64,
    /// Largest force on a roller at the equilibrium (links, contact and
    /// gravity), relative to the pretension.
    pub force_residual: f64,
    /// Why the state reached is not at rest, where the cause is known: a
    /// roller pulled beyond a circular seating arc. A run starts from it and
    /// warns (the summary's `warnings`); `check` names it.
    pub(crate) beyond_seating_arc: Option<BeyondSeatingArc>,
    /// Where the chain's fit to its path, not the tensioner arms, sets the
    /// static tension of a drive whose arms should set it (tensioner-preload
    /// rule; `sim::statics::misfit`). A run warns.
    pub(crate) misfit: Option<super::misfit::MisfitTension>,
    /// Where no sprocket is driven and the sprockets' loads do not balance
    /// around the loop: the torque the sprocket held for the solve took
    /// (`sim::statics::free`). No rest state exists; a run warns.
    pub(crate) unbalanced: Option<super::error::Unbalanced>,
    /// Where a worn chain is longer than the tensioner arms take up: every
    /// arm on a stop or clear of the chain, the chain slack
    /// (`sim::statics::misfit`). A run warns.
    pub(crate) worn_slack: Option<super::misfit::WornSlack>,
}

impl StaticEquilibrium {
    /// What sets the static tension, as the summary's
    /// `static_tension_set_by` names it: the pretension rule of `scene`
    /// (`rest_length`, `tensioner`, `tensioner_preload`), or `chain_misfit`
    /// where the chain's fit to its path sets it ([`Self::warnings`] says so).
    pub fn tension_set_by(&self, scene: &crate::scene::Scene) -> &'static str {
        if self.misfit.is_some() {
            "chain_misfit"
        } else {
            scene.chain.pretension_by.name()
        }
    }

    /// What a run warns of about this rest state, a sentence each: a
    /// roller held on or pulled beyond a circular seating arc (the drive
    /// has no smooth rest state with that profile), a static tension
    /// that the chain's fit to its path sets where tensioner arms should,
    /// loads that do not balance around a loop with no driver, or a worn
    /// chain longer than the tensioner arms take up. Empty for a clean
    /// rest state.
    pub fn warnings(&self) -> Vec<String> {
        let rim = self.beyond_seating_arc.as_ref().map(ToString::to_string);
        let misfit = self.misfit.as_ref().map(ToString::to_string);
        let unbalanced = self.unbalanced.as_ref().map(ToString::to_string);
        let slack = self.worn_slack.as_ref().map(ToString::to_string);
        rim.into_iter()
            .chain(misfit)
            .chain(unbalanced)
            .chain(slack)
            .collect()
    }
}

/// Largest force on a roller at `state`, relative to `scale_n`: the
/// equilibrium's residual. `forces` must have been evaluated at `state`.
pub(crate) fn force_residual(forces: &ForceGenerator, scale_n: f64) -> f64 {
    let out = forces.output();
    let largest = out
        .fx
        .iter()
        .zip(&out.fy)
        .map(|(x, y)| x.hypot(*y))
        .fold(0.0, f64::max);
    largest / scale_n.abs().max(f64::MIN_POSITIVE)
}

/// The next rest length of the pretension iteration: a secant step on
/// T(l₀), safeguarded.
///
/// T falls as l₀ grows, with a slope between −K (every link stretched
/// alike) and 0. The slope is near 0 wherever the chain is slack: without
/// gravity a strand at no tension holds no length, and the real profile's
/// seating clearance lets the rollers on a wrap give up length as well, so
/// after the first relaxation the static tension may be about zero whatever
/// l₀ is near. A plain secant step there is huge (millimetres per link) and
/// the next relaxation blows up. The step is therefore at most
/// `step_factor` elastic steps (target − T)/K; the factor starts at 8 and
/// doubles each time it limits the step (where the slope is truly shallow,
/// e.g. the real profile's wraps under gravity give up length at about K/50),
/// and once the target is bracketed the step stays inside the bracket
/// (bisection when the secant leaves it).
fn next_rest_length(
    k: f64,
    (rest, tension): (f64, f64),
    previous: Option<(f64, f64)>,
    bracket: (Option<f64>, Option<f64>),
    target_n: f64,
    step_factor: &mut f64,
) -> f64 {
    let slope = match previous {
        Some((r0, t0)) if (rest - r0).abs() > 0.0 => (tension - t0) / (rest - r0),
        _ => -k,
    };
    // Within [−K, −K / step_factor]: a secant with the wrong sign or a flat
    // one (a slack chain) takes the longest step allowed.
    let limit = -k / *step_factor;
    let (slope, clamped) = if !slope.is_finite() {
        (-k, true)
    } else if slope > limit {
        *step_factor *= 2.0;
        (limit, true)
    } else if slope < -k {
        (-k, true)
    } else {
        (slope, false)
    };
    let proposal = rest + (target_n - tension) / slope;
    match bracket {
        // `low`: a rest length whose tension is above the target; `high`:
        // below. Only a clamped step is held to the bracket: a relaxation
        // cut short by `max_relax_s` leaves T(rest length) depending on the
        // iterations before, and a plain secant step then converges where a
        // stale bracket would not.
        (Some(low), Some(high))
            if clamped && !(proposal > low.min(high) && proposal < low.max(high)) =>
        {
            0.5 * (low + high)
        }
        _ => proposal,
    }
}

/// Force residual, relative to the pretension, above which a rest state
/// counts as not settled when a roller pulled beyond a circular seating arc
/// explains it.
const UNSETTLED_RESIDUAL: f64 = 1e-6;

/// The roller pulled beyond a circular profile's seating arc, when the
/// drive has a rest state to solve for (`newton::applies`), the rest state
/// reached leaves more than [`UNSETTLED_RESIDUAL`] of the pretension out of
/// balance and such a roller explains it
/// ([`super::feasibility::rim_roller`]): no rest state exists there, and the
/// cause is named beside the residual. `forces` evaluated at `state`.
fn beyond_seating_arc(
    model: &DriveModel,
    state: &DriveState,
    forces: &ForceGenerator,
    target_n: f64,
    names: &[&str],
) -> Option<BeyondSeatingArc> {
    // Only where a rest state is defined (a held sprocket, rollers and
    // sprockets only: see the newton module); elsewhere the relaxation's
    // end is only a start.
    let residual = force_residual(forces, target_n);
    if !(residual > UNSETTLED_RESIDUAL) || !super::newton::applies(model, state, forces) {
        return None;
    }
    let rim = super::feasibility::rim_roller(model, state, forces)?;
    let sprocket = names
        .get(rim.sprocket)
        .map_or_else(|| format!("{}", rim.sprocket + 1), |n| (*n).to_owned());
    Some(BeyondSeatingArc {
        roller: rim.roller,
        sprocket,
        gap: rim.gap,
        beyond_deg: rim.beyond_deg,
        outward_n: rim.outward_n,
        along_n: rim.along_n,
        edge_depth_m: rim.edge_depth_m,
        residual,
    })
}

/// Force residual, relative to the pretension, at which a relaxation stops
/// while the pretension iteration is still looking for the rest length: the
/// static tension is then known well within the tolerance on it.
pub(crate) const SEARCH_FORCE: f64 = 1e-5;
/// Force residual, relative to the pretension, at which the final relaxation
/// stops: the equilibrium's residual is below it.
pub(crate) const REST_FORCE: f64 = 1e-7;
/// Least relaxation damping rate, 1/s.
const MIN_RATE_PER_S: f64 = 2.0;

/// The relaxation's damping rate: twice the lowest natural frequency of the
/// held drive, at most `cap_per_s`. Viscous damping c brings a mode of
/// frequency ω ≥ c/2 to rest at the rate c/2 but an overdamped one (ω < c/2)
/// only at ω²/c, so c = 2 ω_min is the fastest for the slowest mode. The
/// modes estimated, for each free strand of length L (ρ = m_r/P):
/// - the strand's longitudinal fundamental between its held ends, π P √(K/m_r) / L;
/// - with gravity across it, its lateral (string) fundamental π √(T₀/ρ) / L;
/// - each free sprocket turning against the strands on either side, √(R² K (1/n_in + 1/n_out) / J),
///   n the strands' link counts.
fn damping_rate(model: &DriveModel, target_n: f64, cap_per_s: f64) -> f64 {
    let p = model.rest_length_m;
    let m = model.roller_mass_kg;
    let k = model.stiffness_n_m;
    let rho = m / p;
    let [gx, gy] = model.gravity_m_s2;
    let g = gx.hypot(gy);
    let strands = &model.path.strands;
    let mut omega = f64::INFINITY;
    for s in strands {
        let l = s.length_m.max(p);
        omega = omega.min(std::f64::consts::PI * p * (k / m).sqrt() / l);
        let [dx, dy] = s.direction();
        if g > 0.0 && (dx * gy - dy * gx).abs() > 0.1 * g {
            omega = omega.min(std::f64::consts::PI * (target_n.abs() / rho).sqrt() / l);
        }
    }
    let n = strands.len();
    for (j, sp) in model.sprockets.iter().enumerate() {
        if sp.held_at_rest() || !(sp.inv_inertia > 0.0) || n == 0 {
            continue;
        }
        // Strand j leaves sprocket j, strand j − 1 reaches it.
        let links = |s: &crate::geometry::Strand| (s.length_m / p).max(1.0);
        let compliance = 1.0 / links(&strands[j % n]) + 1.0 / links(&strands[(j + n - 1) % n]);
        let r = sp.pitch_radius_m;
        omega = omega.min((r * r * k * compliance * sp.inv_inertia).sqrt());
    }
    if omega.is_finite() {
        (2.0 * omega).clamp(MIN_RATE_PER_S.min(cap_per_s), cap_per_s)
    } else {
        cap_per_s
    }
}

/// The tensioner-preload rule (`pretension_by = "tensioner_preload"`): the
/// links keep their rest length, the pitch; the drive relaxes with its
/// tensioner arms free (a hydraulic chamber held at its supply pressure),
/// and the static tension is what the tensioners' pushes hold. Relaxes
/// until the force residual relative to `scale_n` (the scene's pretension,
/// only a scale here) is below the final threshold, or stops falling.
pub(crate) fn settle_preload(
    model: &DriveModel,
    state: &mut DriveState,
    forces: &mut ForceGenerator,
    settings: &RelaxSettings,
    scale_n: f64,
) -> Result<StaticEquilibrium, EquilibriumError> {
    const MAX_RELAXATIONS: usize = 20;
    let settings = RelaxSettings {
        rate_per_s: damping_rate(model, scale_n, settings.rate_per_s),
        ..*settings
    };
    let mut previous = f64::INFINITY;
    let mut iterations = 0;
    let mut residual = f64::INFINITY;
    while iterations < MAX_RELAXATIONS {
        iterations += 1;
        // Newton first, the relaxation where it stalls (see the newton
        // module).
        residual = super::newton::settle(
            model,
            state,
            forces,
            &settings,
            REST_FORCE * scale_n,
            0.5 * REST_FORCE * scale_n,
            false,
        )?;
        let now = force_residual(forces, scale_n);
        if now <= REST_FORCE || residual < settings.rest_speed_m_s || !(now < 0.9 * previous) {
            break;
        }
        previous = now;
    }
    Ok(StaticEquilibrium {
        tension_n: free_strand_tension(model, state, forces)
            .ok_or(EquilibriumError::NoFreeLinks)?,
        rest_length_m: model.rest_length_m,
        iterations,
        residual_speed_m_s: residual,
        force_residual: force_residual(forces, scale_n),
        beyond_seating_arc: None,
        misfit: None,
        unbalanced: None,
        worn_slack: None,
    })
}

/// Brings the drive to static equilibrium at `target_n` by shortening the
/// links' rest length (safeguarded secant iteration on T(rest length), see
/// `next_rest_length`).
///
/// Each relaxation stops once every force is below `SEARCH_FORCE` (10⁻⁵) of the
/// pretension (or at rest, or after `max_time_s`); when the static tension is
/// within `tolerance`, the drive relaxes on at that rest length until its
/// forces are below `REST_FORCE` (10⁻⁷) of the pretension (while each further
/// relaxation lowers the residual by a tenth at least; the residual returned says how
/// close it came). The damping rate is
/// chosen from the drive's own frequencies (`damping_rate`), at most
/// `settings.rate_per_s`. `sprocket_names` name the body that did not settle
/// when there is no equilibrium.
pub(crate) fn settle_rest_length(
    model: &mut DriveModel,
    state: &mut DriveState,
    forces: &mut ForceGenerator,
    settings: &RelaxSettings,
    target_n: f64,
    tolerance: f64,
    sprocket_names: &[&str],
) -> Result<StaticEquilibrium, EquilibriumError> {
    const MAX_ITERATIONS: usize = 30;
    let k = model.stiffness_n_m;
    let settings = RelaxSettings {
        rate_per_s: damping_rate(model, target_n, settings.rate_per_s),
        ..*settings
    };
    let scale = target_n.abs();
    // First guess: links on the wraps are exactly one pitch long; stretch them to the target.
    let mut rest = model.rest_length_m - target_n / k;
    let mut previous: Option<(f64, f64)> = None;
    // Rest lengths known to give a tension above (low) and below (high) the target.
    let (mut above, mut below): (Option<f64>, Option<f64>) = (None, None);
    let mut last = f64::NAN;
    let mut last_speed = 0.0;
    let mut step_factor = 8.0;
    let mut found = false;
    // Relaxations at the right tension beyond the first, and their limit.
    const MAX_FURTHER: usize = 20;
    let mut further = 0;
    let mut further_residual = f64::INFINITY;
    for iteration in 1..=MAX_ITERATIONS {
        model.rest_length_m = rest;
        let stop = if found { REST_FORCE } else { SEARCH_FORCE };
        // Newton first, the relaxation where it stalls (see the newton module).
        let residual = super::newton::settle(
            model,
            state,
            forces,
            &settings,
            stop * scale,
            0.5 * REST_FORCE * scale,
            !found,
        )?;
        last_speed = residual;
        let tension =
            free_strand_tension(model, state, forces).ok_or(EquilibriumError::NoFreeLinks)?;
        last = tension;
        if ((tension - target_n) / target_n).abs() <= tolerance {
            let now = force_residual(forces, target_n);
            let settled = now <= REST_FORCE
                && worst_sprocket(model, forces).is_none_or(|(s, m)| {
                    m.abs() <= REST_FORCE * scale * model.sprockets[s].pitch_radius_m
                });
            // A drive whose residual stops falling over further relaxations
            // (a roller chattering on a tooth) ends here too: its residual
            // says how far it is from equilibrium.
            // So does one whose relaxation at this rest length ran its
            // course with a roller on a circular seating arc's rim: no
            // further relaxation brings it to rest.
            let stalled = further > 0
                && (!(now < 0.9 * further_residual)
                    || super::feasibility::rim_roller(model, state, forces).is_some());
            if settled || residual < settings.rest_speed_m_s || stalled || further >= MAX_FURTHER {
                let beyond_seating_arc = if settled {
                    None
                } else {
                    beyond_seating_arc(model, state, forces, target_n, sprocket_names)
                };
                return Ok(StaticEquilibrium {
                    tension_n: tension,
                    rest_length_m: rest,
                    iterations: iteration,
                    residual_speed_m_s: residual,
                    force_residual: force_residual(forces, target_n),
                    beyond_seating_arc,
                    misfit: None,
                    unbalanced: None,
                    worn_slack: None,
                });
            }
            // Right tension, not yet at rest: relax on at this rest length.
            found = true;
            further += 1;
            further_residual = now;
            continue;
        }
        found = false;
        further = 0;
        if tension > target_n {
            above = Some(rest);
        } else {
            below = Some(rest);
        }
        let next = next_rest_length(
            k,
            (rest, tension),
            previous,
            (above, below),
            target_n,
            &mut step_factor,
        );
        previous = Some((rest, tension));
        rest = next;
    }
    // A roller beyond a circular seating arc explains why no rest state
    // was found: the run may start from the state reached, which names it.
    if let Some(rim) = beyond_seating_arc(model, state, forces, target_n, sprocket_names) {
        return Ok(StaticEquilibrium {
            tension_n: last,
            rest_length_m: model.rest_length_m,
            iterations: MAX_ITERATIONS,
            residual_speed_m_s: last_speed,
            force_residual: force_residual(forces, target_n),
            beyond_seating_arc: Some(rim),
            misfit: None,
            unbalanced: None,
            worn_slack: None,
        });
    }
    let (body, _) = unsettled_body(model, forces, sprocket_names);
    Err(EquilibriumError::Unsettled {
        tension_n: last,
        target_n,
        iterations: MAX_ITERATIONS,
        body,
    })
}
