//! Static equilibrium before t = 0 (docs/model.md, “Pretension and static
//! equilibrium”): the driver is held, gravity
//! acts as set, and the chain relaxes under extra viscous damping until it is
//! at rest. The pretension rule then iterates: with `rest_length`, the links'
//! rest length is corrected by a secant iteration until the mean link force of
//! all free strands equals the pretension.

use super::integrate::implicit_damping_step;
use super::stepper::Relaxation;
use crate::forces::ForceGenerator;
use crate::model::{DriveModel, DriveState};

/// A roller on the rim of the circular profile's seating arc, where no
/// force of that profile holds it (see the feasibility module): pulled
/// beyond the arc, or held on its edge where the contact force jumps to
/// zero. The drive has no smooth rest state with this profile.
#[derive(Clone, Debug, PartialEq)]
pub struct BeyondSeatingArc {
    /// The roller.
    pub roller: usize,
    /// The sprocket's name.
    pub sprocket: String,
    /// The gap, as the profile numbers it.
    pub gap: u32,
    /// Pulled beyond the arc: the angle between the roller's pull and the
    /// arc's edge; held on the edge: how far beyond the edge the roller's
    /// offset from its seating centre points; degrees.
    pub beyond_deg: f64,
    /// The pull's component radially outward (negative: inward), N.
    pub outward_n: f64,
    /// Its component along the pitch circle, N.
    pub along_n: f64,
    /// Held on the edge (pulled back towards the gap, not beyond it): how
    /// far the roller's centre lies outside the seating circle, m. `None`:
    /// pulled beyond the arc.
    pub edge_depth_m: Option<f64>,
    /// Largest roller force at the rest state reached, relative to the pretension.
    pub residual: f64,
}

impl std::fmt::Display for BeyondSeatingArc {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let Self {
            roller,
            sprocket,
            gap,
            beyond_deg,
            outward_n,
            along_n,
            residual,
            ..
        } = self;
        match self.edge_depth_m {
            None => write!(
                f,
                "roller {roller} is pulled {beyond_deg:.1}° beyond the seating arc of gap {gap} on sprocket \"{sprocket}\" ({outward_n:.3} N outward, {along_n:.3} N along the pitch circle)"
            )?,
            Some(depth_m) => write!(
                f,
                "roller {roller} is held on the edge of the seating arc of gap {gap} on sprocket \"{sprocket}\", {:.1} µm outside its seating circle and {beyond_deg:.2}° beyond the edge ({:.3} N inward, {along_n:.3} N along the pitch circle): one step inwards the seat pushes it with the contact's full force at that depth, one step out nothing does",
                depth_m * 1e6,
                -outward_n
            )?,
        }
        write!(
            f,
            ": the circular profile holds a roller only on the half of its seating circle facing the sprocket's centre, so this drive has no smooth rest state with it (the rest state reached leaves {residual:.2e} of the pretension out of balance); the real tooth form holds it (profile = \"real\"), or another load moves the roller off the rim"
        )
    }
}

impl std::error::Error for BeyondSeatingArc {}

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
    pub beyond_seating_arc: Option<BeyondSeatingArc>,
    /// Where the chain's fit to its path, not the tensioner arms, sets the
    /// static tension of a drive whose arms should set it (tensioner-preload
    /// rule; `sim::misfit`). A run warns.
    pub misfit: Option<super::misfit::MisfitTension>,
}

/// Why no equilibrium was found.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EquilibriumError {
    /// No free strand link exists to measure the tension on.
    #[error("no free strand link to measure the static tension on")]
    NoFreeLinks,
    /// The tensioner rule needs a sprocket with role = "tensioner".
    #[error("pretension_by = \"tensioner\" but no sprocket is a tensioner")]
    NoTensioner,
    /// The tensioner's travel along its adjustment direction cannot make
    /// the chain fit (the sprocket's move is in the message).
    #[error("the tensioner \"{sprocket}\" cannot take up the chain: {reason}")]
    TensionerFit {
        /// The tensioner's name.
        sprocket: String,
        /// Why no position along its direction fits (boxed: it is large).
        reason: Box<super::fit::FitError>,
    },
    /// The pretension iteration did not converge.
    #[error(
        "static tension {tension_n:.1} N after {iterations} iterations, target {target_n:.1} N"
    )]
    NotConverged {
        /// Reached tension, N.
        tension_n: f64,
        /// Target, N.
        target_n: f64,
        /// Iterations used.
        iterations: usize,
    },
    /// The pretension iteration ran out of iterations with a body not at rest.
    #[error(
        "static tension {tension_n:.1} N after {iterations} iterations, target {target_n:.1} N: {body}"
    )]
    Unsettled {
        /// Reached tension, N.
        tension_n: f64,
        /// Target, N.
        target_n: f64,
        /// Iterations used.
        iterations: usize,
        /// The body furthest from equilibrium and its residual.
        body: String,
    },
    /// The chain is too short for the pretension (see the feasibility module).
    #[error(
        "the chain is {short_m:.4} m ({short_pitches:.2} pitches) shorter than the path through the seated rollers{}, but at chain.pretension_n its {free_links} free links stretch {allowed_m:.2e} m in all; it would carry about {needed_tension_n:.0} N: add rollers or move the sprockets closer",
        if *sag_m > 0.0 { format!(" plus the {sag_m:.2e} m its strands' sag holds at chain.pretension_n") } else { String::new() }
    )]
    ChainTooShort {
        /// Missing length (the seated path plus the sag at the pretension, less the chain), m.
        short_m: f64,
        /// Length the strands' sag holds at the pretension (gravity), m.
        sag_m: f64,
        /// Missing length, pitches.
        short_pitches: f64,
        /// Links of the free strands.
        free_links: usize,
        /// Length the pretension takes up, m.
        allowed_m: f64,
        /// Static tension the short chain would carry (its links' stretch
        /// taking up what it lacks, the strands' sag at that tension
        /// included), N.
        needed_tension_n: f64,
    },
    /// The chain is longer than its path by more than the strands' sag at
    /// the pretension takes up (see the feasibility module).
    #[error(
        "the chain is {long_m:.4} m ({long_pitches:.2} pitches) longer than the path through the seated rollers, but at chain.pretension_n = {pretension_n:.1} N the strands' sag takes up only {sag_m:.2e} m{}: a chain longer than its path has no equilibrium at the pretension; remove rollers or move the sprockets apart{}",
        arms_m.map(|a| format!(" and the tensioner arms' shoes at most {a:.2e} m over their travel")).unwrap_or_default(),
        match sag_tension_n {
            Some(t) => format!(", or lower chain.pretension_n to about {t:.0} N, where the strands sag by that much"),
            None => " (without gravity the strands cannot sag)".to_owned(),
        }
    )]
    ChainTooLong {
        /// Excess length, m.
        long_m: f64,
        /// Excess length, pitches.
        long_pitches: f64,
        /// Length the strands' sag takes up at the pretension, m.
        sag_m: f64,
        /// Pretension, N.
        pretension_n: f64,
        /// Pretension at which the sag takes up the excess, N (none without gravity).
        sag_tension_n: Option<f64>,
        /// What the tensioner arms' shoes take up at most over their
        /// travel, m (none without arms).
        arms_m: Option<f64>,
    },
    /// The loads on several sprockets leave a free strand in compression.
    #[error(
        "at chain.pretension_n = {pretension_n:.1} N the load torques leave strand {strand} ({context}) carrying {tension_n:.1} N: a strand cannot carry compression; raise chain.pretension_n to at least {needed_n:.1} N or reduce the loads"
    )]
    StrandCompression {
        /// The strand, 1-based (strand k leaves sprocket k).
        strand: usize,
        /// Its static tension, N (negative).
        tension_n: f64,
        /// Pretension, N.
        pretension_n: f64,
        /// Least pretension that keeps every strand in tension, N.
        needed_n: f64,
        /// The sprockets the strand runs between and the loads at rest, for the message.
        context: String,
    },
    /// A load torque needs more pretension than the scene has.
    #[error(
        "load torque {load_n_m} N·m on sprocket \"{sprocket}\" exceeds the {limit_n_m:.1} N·m the slack strand can hold at chain.pretension_n = {pretension_n:.1} N (it would need compression); raise chain.pretension_n to at least {needed_n:.1} N"
    )]
    LoadBeyondPretension {
        /// The loaded sprocket's name.
        sprocket: String,
        /// Its load torque, N·m.
        load_n_m: f64,
        /// Largest load the pretension holds, N·m.
        limit_n_m: f64,
        /// Pretension, N.
        pretension_n: f64,
        /// Least pretension that holds the load, N.
        needed_n: f64,
    },
    /// The relaxation itself blew up (dt too large for the scene).
    #[error(
        "the chain blew up while relaxing to static equilibrium (largest link stretch {stretch_m:.3e} m)"
    )]
    BlowUp {
        /// Largest link stretch seen, m.
        stretch_m: f64,
    },
}

/// Settings of the relaxation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RelaxSettings {
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

/// Relaxes `state` to rest with the driver held. Returns the residual speed.
///
/// Steps symplectic Euler with the contact damping implicit
/// ([`super::integrate`]), so the contact damping puts no limit on the step;
/// the relaxation's own damping (`rate_per_s`) brings everything to rest.
pub fn relax(
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
fn worst_sprocket(model: &DriveModel, forces: &ForceGenerator) -> Option<(usize, f64)> {
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
fn unsettled_body(model: &DriveModel, forces: &ForceGenerator, names: &[&str]) -> (String, f64) {
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

/// Mean link force over the links of all free strands, pooled; `None` if
/// there is no free link. `forces` must have been evaluated at `state`.
pub fn free_strand_tension(
    model: &DriveModel,
    state: &DriveState,
    forces: &ForceGenerator,
) -> Option<f64> {
    let out = forces.output();
    let runs = model
        .segments
        .runs(&model.sprockets, &state.x, &state.y, &out.touching);
    let (mut sum, mut count) = (0.0, 0usize);
    for k in 0..model.segments.len() {
        for i in runs.links(k) {
            sum += out.link_force[i];
            count += 1;
        }
    }
    (count > 0).then(|| sum / count as f64)
}

/// Largest force on a roller at `state`, relative to `scale_n`: the
/// equilibrium's residual. `forces` must have been evaluated at `state`.
pub fn force_residual(forces: &ForceGenerator, scale_n: f64) -> f64 {
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
    if !(residual > UNSETTLED_RESIDUAL) || !super::newton::applies(model, state) {
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
        residual = relax_until(model, state, forces, &settings, Some(REST_FORCE * scale_n))?;
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
pub fn settle_rest_length(
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
