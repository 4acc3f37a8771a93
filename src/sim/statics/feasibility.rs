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
//!   Under gravity each free strand also sags at T₀ and holds
//!   q⊥² L³ / (24 T₀²) more chain than its straight span (shallow parabolic
//!   cable, q⊥ the weight per length across it): that much is missing too.
//! - **Chain too long** (rest-length rule). A chain longer than its seated
//!   path must hold the excess in the strands' sag at T₀. Without gravity
//!   nothing sags, and a too-long chain has no equilibrium at the
//!   pretension: the wrap links would carry K·excess/n_free more than the
//!   strands. The same margin applies. Tensioner arms turned into their
//!   strands take up as much more as their shoes add to the path over
//!   their travel ([`crate::geometry::arm_take_up`]).
//! - **Load beyond the pretension** (any number of sprockets). With the
//!   driver held, a free sprocket's torque balance (chain torque
//!   w R (T_out − T_in), w = +1 for a counter-clockwise wrap, plus its load
//!   M) fixes the tension jump across it, T_out − T_in = −w M / R. Strand k
//!   leaves sprocket k; from the strand leaving the driver the jumps add up
//!   to c_k. The rest-length rule holds the pooled mean over the free links
//!   at T₀, so T_k = T₀ + c_k − Σ n_j c_j / Σ n_j. A strand with T_k < 0
//!   would carry compression: one loaded sprocket is named with the largest
//!   load T₀ holds (two equal strands: |M| ≤ 2 R T₀), several with the
//!   strand. Exact for a weightless chain, a guide under gravity.

use super::error::EquilibriumError;
use crate::forces::ForceGenerator;
use crate::geometry::{ChainPath, Layout, ToothProfile};
use crate::model::{DriveModel, DriveState};
use crate::scene::{Role, Scene};

/// Factor on the length the pretension can take up beyond which a chain is
/// reported too short.
const SHORT_MARGIN: f64 = 2.0;
/// Further missing length tolerated, in pitches.
const SHORT_MARGIN_PITCHES: f64 = 0.1;

/// The chain is neither too short nor too long for the pretension
/// (rest-length rule; module docs).
pub(crate) fn check_chain_length(
    scene: &Scene,
    layout: &Layout,
    path: &ChainPath,
) -> Result<(), EquilibriumError> {
    let chain = &scene.chain;
    let chain_m = chain.rollers as f64 * chain.pitch_m;
    let free_links: usize = layout.strand_links.iter().sum();
    if free_links == 0 {
        return Ok(());
    }
    // Under gravity the strands sag at the pretension and hold that much more chain.
    let sag_m = sag_take_up_m(scene, path, chain.pretension_n);
    let short_m = layout.polygon_length_m + sag_m - chain_m;
    let allowed_m = free_links as f64 * chain.pretension_n / chain.stiffness_n_m;
    let margin_m = SHORT_MARGIN * allowed_m + SHORT_MARGIN_PITCHES * chain.pitch_m;
    if short_m > margin_m {
        return Err(EquilibriumError::ChainTooShort {
            short_m,
            sag_m,
            short_pitches: short_m / chain.pitch_m,
            free_links,
            allowed_m,
            needed_tension_n: hanging_tension_n(
                layout.polygon_length_m - chain_m,
                sag_take_up_m(scene, path, 1.0),
                free_links as f64 / chain.stiffness_n_m,
                chain.pretension_n,
            ),
        });
    }
    let long_m = chain_m - layout.polygon_length_m;
    if long_m > sag_m + margin_m {
        // Tensioner arms turned into their strands take up what their
        // shoes add to the path (asked only here: no cost where the chain fits).
        let arms_m = super::fit::arm_take_up_of(scene).map(|t| t.max_m);
        if long_m <= sag_m + arms_m.unwrap_or(0.0) + margin_m {
            return Ok(());
        }
        // The pretension at which the sag takes up the excess: Σ q⊥² L³ / (24 T²) = excess.
        let sag_at_1n = sag_take_up_m(scene, path, 1.0);
        return Err(EquilibriumError::ChainTooLong {
            long_m,
            long_pitches: long_m / chain.pitch_m,
            sag_m,
            pretension_n: chain.pretension_n,
            sag_tension_n: (sag_at_1n > 0.0).then(|| (sag_at_1n / long_m).sqrt()),
            arms_m,
        });
    }
    Ok(())
}

/// The static tension T of a chain `deficit_m` shorter than its straight
/// path whose free links stretch `stretch_m_per_n` per newton in all and
/// whose strands' sag holds `sag_at_1n_m` / T² (parabolic cable): the root
/// of stretch · T = deficit + sag₁ / T², which rises with T. Bracketed by
/// `low_n` (where the stretch is less than the need) and the linear estimate
/// that holds the sag at `low_n`'s value; bisected in log T.
fn hanging_tension_n(deficit_m: f64, sag_at_1n_m: f64, stretch_m_per_n: f64, low_n: f64) -> f64 {
    let excess = |t: f64| stretch_m_per_n * t - deficit_m - sag_at_1n_m / (t * t);
    let mut lo = low_n;
    let mut hi = (deficit_m + sag_at_1n_m / (low_n * low_n)) / stretch_m_per_n;
    if !(excess(lo) < 0.0 && excess(hi) > 0.0) {
        return hi;
    }
    for _ in 0..100 {
        let mid = (lo * hi).sqrt();
        if excess(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Length the free strands' sag takes up at tension `tension_n`
/// ([`ChainPath::sag_take_up_m`]).
fn sag_take_up_m(scene: &Scene, path: &ChainPath, tension_n: f64) -> f64 {
    let chain = &scene.chain;
    path.sag_take_up_m(
        chain.roller_mass_kg / chain.pitch_m,
        scene.gravity_m_s2,
        tension_n,
    )
}

/// No load torque leaves a free strand in compression (any number of sprockets).
///
/// With the driver held, each free sprocket's torque balance fixes the jump
/// of tension across it (module docs); the pooled mean over the free links is
/// the pretension, so every strand's tension follows. Gravity is left out:
/// the check is exact for a weightless chain and only a guide under gravity.
pub(crate) fn check_load(scene: &Scene, layout: &Layout) -> Result<(), EquilibriumError> {
    let n = scene.sprockets.len();
    let links = &layout.strand_links;
    let total: usize = links.iter().sum();
    if links.len() != n || total == 0 {
        return Ok(());
    }
    let t0 = scene.chain.pretension_n;
    // The tension jump T_out − T_in across each sprocket at rest; the driver
    // takes up whatever the others leave, so its jump is free and the
    // strands are numbered from the one leaving it.
    let jumps: Vec<f64> = scene
        .sprockets
        .iter()
        .map(|sp| {
            // A ramped load is not held at rest: the equilibrium carries none.
            let load = if matches!(sp.role, Role::Driver(_)) || sp.load_ramp_s() > 0.0 {
                0.0
            } else {
                sp.load_torque_n_m()
            };
            -sp.wrap.sign() * load / sp.pitch_radius_m
        })
        .collect();
    let loaded: Vec<usize> = (0..n).filter(|&s| jumps[s] != 0.0).collect();
    if loaded.is_empty() {
        return Ok(());
    }
    let tensions = strand_tensions(scene.driver(), &jumps, links, t0);
    let (weakest, lowest) =
        tensions
            .iter()
            .copied()
            .enumerate()
            .fold(
                (0, f64::INFINITY),
                |a, (k, t)| if t < a.1 { (k, t) } else { a },
            );
    if lowest >= 0.0 {
        return Ok(());
    }
    // Tensions are T₀ plus terms linear in the loads: T₀ − lowest more
    // pretension lifts the weakest strand to zero.
    let needed_n = t0 - lowest;
    if let [s] = loaded[..] {
        let sp = &scene.sprockets[s];
        let m = sp.load_torque_n_m();
        return Err(EquilibriumError::LoadBeyondPretension {
            sprocket: sp.name.clone(),
            load_n_m: m,
            // The weakest strand loses (needed_n / |M|) N per N·m.
            limit_n_m: t0 * m.abs() / needed_n,
            pretension_n: t0,
            needed_n,
        });
    }
    let (from, to) = strand_ends(scene, weakest);
    let loads = loaded
        .iter()
        .map(|&s| {
            format!(
                "\"{}\" {} N·m",
                scene.sprockets[s].name,
                scene.sprockets[s].load_torque_n_m()
            )
        })
        .collect::<Vec<_>>()
        .join(", ");
    Err(EquilibriumError::StrandCompression {
        strand: weakest + 1,
        tension_n: lowest,
        pretension_n: t0,
        needed_n,
        context: format!("from \"{from}\" to \"{to}\"; loads {loads}"),
    })
}

/// Names of the sprockets strand k runs between (strand k leaves sprocket k).
fn strand_ends(scene: &Scene, k: usize) -> (String, String) {
    let n = scene.sprockets.len();
    (
        scene.sprockets[k].name.clone(),
        scene.sprockets[(k + 1) % n].name.clone(),
    )
}

/// Static tension of each free strand of a weightless chain with the driver
/// (`driver`) held: strand k leaves sprocket k, so the tension steps by
/// `jumps[s]` from strand s − 1 to strand s; the link-weighted mean is `t0`.
fn strand_tensions(driver: usize, jumps: &[f64], links: &[usize], t0: f64) -> Vec<f64> {
    let n = jumps.len();
    let mut c = vec![0.0; n];
    // Strand `driver` is the reference; walk on from it.
    for step in 1..n {
        let s = (driver + step) % n;
        c[s] = c[(s + n - 1) % n] + jumps[s];
    }
    let total: usize = links.iter().sum();
    let mean = c.iter().zip(links).map(|(c, &l)| c * l as f64).sum::<f64>() / total as f64;
    c.iter().map(|c| t0 + c - mean).collect()
}

/// A roller the circular profile cannot hold: its links and its weight pull
/// it beyond the half of its seating circle that faces the sprocket's
/// centre (module docs of [`rim_roller`]).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct RimRoller {
    /// The roller's index.
    pub(crate) roller: usize,
    /// The sprocket whose gap it sits in.
    pub(crate) sprocket: usize,
    /// The gap, as the profile numbers it.
    pub(crate) gap: u32,
    /// Angle between the pull and the seating arc's edge, degrees (> 0:
    /// beyond the arc).
    pub(crate) beyond_deg: f64,
    /// The pull's component radially outward, N.
    pub(crate) outward_n: f64,
    /// Its component along the pitch circle, N (magnitude).
    pub(crate) along_n: f64,
    /// Where the roller sits on the arc's edge instead (pulled back towards
    /// the gap, not beyond it): how far its centre lies outside the
    /// seating circle, m.
    pub(crate) edge_depth_m: Option<f64>,
}

/// Least angle, from the gap's bottom, of a roller's offset from its seating
/// centre for the roller to count as on the seating arc's rim, rad (the rim
/// lies at 90°).
const RIM_OFFSET_RAD: f64 = 60.0 * std::f64::consts::PI / 180.0;

/// Largest angle beyond the seating arc's edge (90° from the gap's bottom) of
/// a roller's offset for the roller to count as held on the edge, rad.
const EDGE_OFFSET_RAD: f64 = 10.0 * std::f64::consts::PI / 180.0;

/// The roller on a circular-profile sprocket that is pulled hardest beyond
/// its seating arc, if any.
///
/// The circular profile holds a roller only on the half of its seating
/// circle that faces the sprocket's centre: the contact force pushes along
/// −e/|e|, e the roller centre's offset from the seating centre, and only
/// while e points inward (e·u ≤ 0, u the gap's radial direction). A roller at
/// rest is held against the pull F of its links and its weight by a contact
/// force −F, so it needs a contact point along F; where F points outward
/// (F·u > 0), that point lies beyond the arc by the angle between F and the
/// arc's edge, and no force of this profile can balance it: the roller rides
/// on the rim, where the force jumps from K δⁿ to zero, and the drive has no
/// smooth rest state. A roller counts when its offset has reached the wall
/// (|e| ≥ ΔR/2) at least [`RIM_OFFSET_RAD`] from the gap's bottom.
///
/// Where no roller is pulled beyond an arc, a roller held on an arc's edge
/// is named instead: its centre just beyond the edge (e·u ≥ 0, within
/// [`EDGE_OFFSET_RAD`] of it) and outside the seating circle (|e| > ΔR),
/// pulled back towards the gap. One step inwards the wall pushes it with
/// K (|e| − ΔR)ⁿ, one step out nothing does: the force it needs lies on the
/// jump, and the solve stalls there (found on a sagging conveyor whose
/// strand leaves the tail from such a roller). `forces` evaluated at
/// `state`.
pub(crate) fn rim_roller(
    model: &DriveModel,
    state: &DriveState,
    forces: &ForceGenerator,
) -> Option<RimRoller> {
    rim_roller_except(model, state, forces, &[])
}

/// [`rim_roller`] among the rollers not in `except` (rollers already held
/// on their arcs: `hold`).
pub(super) fn rim_roller_except(
    model: &DriveModel,
    state: &DriveState,
    forces: &ForceGenerator,
    except: &[usize],
) -> Option<RimRoller> {
    let out = forces.output();
    let n = state.x.len();
    if n < 3 || out.link_force.len() < n {
        return None;
    }
    let m = model.roller_mass_kg;
    let [gx, gy] = model.gravity_m_s2;
    // Rollers pulled beyond an arc, and rollers held on an arc's edge.
    let (mut pulled, mut edge): (Option<RimRoller>, Option<RimRoller>) = (None, None);
    for i in (0..n).filter(|i| !except.contains(i)) {
        let (prev, next) = ((i + n - 1) % n, (i + 1) % n);
        // The pull of the two links and the weight on roller i.
        let mut f = [m * gx, m * gy];
        for (j, force) in [(next, out.link_force[i]), (prev, out.link_force[prev])] {
            let (dx, dy) = (state.x[j] - state.x[i], state.y[j] - state.y[i]);
            let l = dx.hypot(dy);
            if l > 0.0 {
                f[0] += force * dx / l;
                f[1] += force * dy / l;
            }
        }
        for (s, sp) in model.sprockets.iter().enumerate() {
            let ToothProfile::Circular(c) = &sp.profile else {
                continue;
            };
            let (rx, ry) = (state.x[i] - sp.center_m[0], state.y[i] - sp.center_m[1]);
            if rx * rx + ry * ry > sp.reach_sq_m2 {
                continue;
            }
            let (sin, cos) = state.theta[s].sin_cos();
            let local = [cos * rx + sin * ry, -sin * rx + cos * ry];
            let gap = c.gap_of(local);
            let seat = c.seat_center(gap);
            let seat_r = seat[0].hypot(seat[1]);
            if !(seat_r > 0.0) {
                continue;
            }
            let u = [seat[0] / seat_r, seat[1] / seat_r];
            let e = [local[0] - seat[0], local[1] - seat[1]];
            let e_len = e[0].hypot(e[1]);
            if !(e_len >= 0.5 * c.clearance_m && e_len <= c.clearance_m + 0.5 * c.roller_radius_m) {
                continue;
            }
            // Angle of the offset from the gap's bottom (−u).
            let offset_angle = (e[0] * u[1] - e[1] * u[0])
                .abs()
                .atan2(-(e[0] * u[0] + e[1] * u[1]));
            if offset_angle < RIM_OFFSET_RAD {
                continue;
            }
            let f_local = [cos * f[0] + sin * f[1], -sin * f[0] + cos * f[1]];
            let outward = f_local[0] * u[0] + f_local[1] * u[1];
            let along = (f_local[0] * u[1] - f_local[1] * u[0]).abs();
            if outward > 0.0 {
                if pulled.as_ref().is_none_or(|w| outward > w.outward_n) {
                    pulled = Some(RimRoller {
                        roller: i,
                        sprocket: s,
                        gap,
                        beyond_deg: outward.atan2(along).to_degrees(),
                        outward_n: outward,
                        along_n: along,
                        edge_depth_m: None,
                    });
                }
                continue;
            }
            let beyond = offset_angle - 0.5 * std::f64::consts::PI;
            let depth = e_len - c.clearance_m;
            if (0.0..=EDGE_OFFSET_RAD).contains(&beyond)
                && depth > 0.0
                && edge.as_ref().is_none_or(|w| w.edge_depth_m < Some(depth))
            {
                edge = Some(RimRoller {
                    roller: i,
                    sprocket: s,
                    gap,
                    beyond_deg: beyond.to_degrees(),
                    outward_n: outward,
                    along_n: along,
                    edge_depth_m: Some(depth),
                });
            }
        }
    }
    pulled.or(edge)
}
