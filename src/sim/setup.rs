//! Setting a simulation up, before its first step: the layout and the static equilibrium by the scene's
//! pretension rule (rest length, tensioner, tensioner preload), sprockets
//! held for the solve where a co-simulation asks, and a worn chain's links
//! lengthened after it settled new. Each thread's setup says what it is
//! solving ([`super::setup_stage`]), so that a slow setup can tell its
//! user. What this module does not do: step the drive, or build the rapier
//! world (`Simulation::assemble`).

use super::settled::{Settled, new_forces};
use super::setup_stage::{Staged, note_stage};
use super::statics::{self, EquilibriumError, RelaxSettings, settle_rest_length};
use super::take_up::{settle_tensioner, wear_settled};
use super::worn::WearStep;
use super::{BlowUpLimits, SimError, guide_entry};
use crate::forces::ForceGenerator;
use crate::model::{DriveModel, DriveState};
use crate::scene::{PretensionRule, Scene, StepLimits};

/// Lays out `scene`'s drive and brings it to static equilibrium by its
/// pretension rule, the sprockets k with `held[k]` held at rest for the
/// solve ([`super::Simulation::new_holding`]); a worn chain settles new
/// first and is then lengthened. Returns the settled drive and the blow-up
/// limits its run keeps.
pub(super) fn settle(scene: &Scene, held: &[bool]) -> Result<(Settled, BlowUpLimits), SimError> {
    let _stage = Staged;
    let limits = BlowUpLimits::for_scene(scene);
    let settings = relax_settings(scene, limits.max_stretch_m);
    // A worn chain: the drive with the chain new first, at its
    // pretension; its links are then lengthened (`worn`).
    let worn = scene;
    let new_chain = worn.as_new_chain();
    let scene = new_chain.as_ref().unwrap_or(worn);
    note_stage(|| {
        let new = if new_chain.is_some() { " new" } else { "" };
        format!(
            "the chain{new} at its pretension by the rule \"{}\"",
            scene.chain.pretension_by.name()
        )
    });
    let (settled, held) = match scene.chain.pretension_by {
        PretensionRule::RestLength => {
            let (mut model, mut state, layout) = DriveModel::build(scene)?;
            statics::check_chain_length(scene, &layout, &model.path)?;
            statics::check_load(scene, &layout)?;
            let mut forces = new_forces(scene, &model);
            let (freed, auto) = hold(&mut model, held);
            let pitch_m = model.rest_length_m;
            let mut eq = settle_rest_length(
                &mut model,
                &mut state,
                &mut forces,
                &settings,
                scene.chain.pretension_n,
                scene.equilibrium.tension_tolerance,
                &names(scene),
            )?;
            if let Some(k) = auto {
                note_let_go(scene, k);
                let (s, f) = (&mut state, &mut forces);
                eq = statics::let_go(scene, &mut model, s, f, &settings, k, Some(pitch_m), eq)?;
            }
            let held = Held { freed, auto };
            ((scene.clone(), model, state, forces, layout, eq), held)
        }
        PretensionRule::Tensioner => (settle_tensioner(scene, &settings)?, Held::default()),
        PretensionRule::TensionerPreload => {
            let (mut model, mut state, layout) = DriveModel::build(scene)?;
            let mut forces = new_forces(scene, &model);
            let (freed, auto) = hold(&mut model, held);
            let mut eq = statics::settle_preload(
                &model,
                &mut state,
                &mut forces,
                &settings,
                scene.chain.pretension_n,
            )?;
            if let Some(k) = auto {
                note_let_go(scene, k);
                let (s, f) = (&mut state, &mut forces);
                eq = statics::let_go(scene, &mut model, s, f, &settings, k, None, eq)?;
            }
            eq.misfit = statics::misfit_tension(scene, &layout, &forces, eq.tension_n);
            let held = Held { freed, auto };
            ((scene.clone(), model, state, forces, layout, eq), held)
        }
    };
    // The chain is worn with the held sprockets still held: a drive with no
    // driver has a neutral circulation, and each step of the wear would
    // otherwise fall back to the relaxation.
    let mut settled = if new_chain.is_some() {
        // A rest state that runs over an arm shoe's end at one wear step
        // does so at the scene's wear as well (the arms turn further in as
        // the chain gains length): refused at the first such step.
        let mut shoe_ends =
            |at: WearStep, model: &DriveModel, state: &DriveState, forces: &ForceGenerator| {
                check_shoe_ends(worn, model, state, forces, &limits, Some(at))
            };
        let mut settled = wear_settled(worn, settled, &settings, &mut shoe_ends)?;
        // A worn chain longer than the arms take up hangs slack with every
        // arm on a stop: said, not refused.
        let (scene, _, _, forces, _, eq) = &mut settled;
        let take_up_m = statics::arm_take_up_of(scene).map(|t| t.max_m);
        eq.worn_slack = statics::worn_slack(scene, forces, eq.tension_n, take_up_m);
        if let Some(k) = held.auto {
            note_let_go(worn, k);
            let (scene, model, state, forces, _, eq) = &mut settled;
            *eq = statics::let_go(scene, model, state, forces, &settings, k, None, eq.clone())?;
        }
        settled
    } else {
        settled
    };
    release(&mut settled.1, &held.freed);
    check_guide_entries(&settled.0, &settled.1, &settled.2, &limits)?;
    check_shoe_ends(
        &settled.0, &settled.1, &settled.2, &settled.3, &limits, None,
    )?;
    Ok((settled, limits))
}

/// The relaxation's settings for `scene`, links stretched beyond
/// `max_stretch_m` counting as a blow-up. It steps symplectic Euler with
/// the contact damping implicit: only the links limit its step, whatever
/// step the run's integrator takes.
pub(super) fn relax_settings(scene: &Scene, max_stretch_m: f64) -> RelaxSettings {
    RelaxSettings {
        dt_s: scene.solver.dt_s.min(0.8 * StepLimits::of(scene).links_s),
        max_time_s: scene.equilibrium.max_relax_s,
        rate_per_s: 60.0,
        rest_speed_m_s: 1e-6,
        max_stretch_m,
    }
}

/// Refuses a rest state with a roller behind a guide's entry
/// ([`guide_entry::behind_entry`]).
fn check_guide_entries(
    scene: &Scene,
    model: &DriveModel,
    state: &DriveState,
    limits: &BlowUpLimits,
) -> Result<(), SimError> {
    let faces: Vec<_> = scene.guides.iter().map(|g| g.face).collect();
    let Some(found) = guide_entry::behind_entry(
        &faces,
        &state.x,
        &state.y,
        model.rest_length_m,
        scene.chain.roller_radius_m,
        limits.max_penetration_m,
    ) else {
        return Ok(());
    };
    let e = scene.chain.elongation;
    let slack = if e > 0.0 {
        format!(
            " (worn by {:.3} %, the chain gained {:.1} mm)",
            100.0 * e,
            1e3 * scene.chain.wear_gain_m()
        )
    } else {
        String::new()
    };
    let index = found.guide;
    Err(SimError::Equilibrium(EquilibriumError::BehindGuideEntry(
        format!(
            "roller {} rests behind the entry of guide \"{}\" (guides.{index}, {} at its {end}): running onto it, it would meet the face {:.2} mm deep, beyond the blow-up limit of {:.2} mm (solver.limits.max_penetration_m), so the run would blow up there; the strand sags below the guide's entry{slack}: give that end a longer or steeper ramp (guides.{index}.{end}_ramp), or take the slack up (a tensioner, fewer rollers)",
            found.roller,
            scene.guides[index].name,
            if found.ramp {
                "the ramp"
            } else {
                "the face's end"
            },
            1e3 * found.depth_m,
            1e3 * limits.max_penetration_m,
            end = found.end,
        ),
    )))
}

/// Refuses a rest state with a roller behind the end of a tensioner arm's
/// shoe as the arm stands at rest ([`guide_entry::shoe_face`]): the chain
/// runs over the shoe's end, and the first roller carried onto it would
/// meet it beyond the blow-up limit. `forces` evaluated at `state`; `step`:
/// the wear step whose rest state this is, while a worn chain is lengthened.
fn check_shoe_ends(
    scene: &Scene,
    model: &DriveModel,
    state: &DriveState,
    forces: &ForceGenerator,
    limits: &BlowUpLimits,
    step: Option<WearStep>,
) -> Result<(), EquilibriumError> {
    for (j, arm) in scene.tensioners.iter().enumerate() {
        let angle_rad = state.q.get(j).copied().unwrap_or(0.0);
        let Some(found) = guide_entry::behind_entry(
            &[guide_entry::shoe_face(arm, angle_rad)],
            &state.x,
            &state.y,
            model.rest_length_m,
            scene.chain.roller_radius_m,
            limits.max_penetration_m,
        ) else {
            continue;
        };
        let travel_m = forces
            .output()
            .tensioners
            .get(j)
            .map_or(0.0, |r| r.travel_m);
        let reach = super::statics::arm_take_up_of(scene).map_or_else(String::new, |t| {
            format!(
                "; the arms' shoes take up at most {:.2} mm of chain ({})",
                1e3 * t.max_m,
                t.bound
            )
        });
        let e = scene.chain.elongation;
        let mut worn = if e > 0.0 {
            format!(
                ", the chain worn by {:.3} % (chain.elongation_pct) and {:.1} mm longer than new",
                100.0 * e,
                1e3 * scene.chain.wear_gain_m()
            )
        } else {
            String::new()
        };
        if let Some(at) = step.filter(|at| at.step < at.steps) {
            worn += &format!(
                "; lengthened towards it in {} steps, the chain ran over the shoe's end already at step {} (links {:.3} % longer than new, {:.1} mm), the arm's turn and travel given for that step: further wear turns the arm further in",
                at.steps,
                at.step,
                100.0 * at.elongation,
                1e3 * scene.chain.wear_gain_m() * at.elongation / e
            );
        }
        return Err(EquilibriumError::BehindGuideEntry(format!(
            "roller {} rests beyond the {end} of the shoe of tensioner \"{}\" (tensioners.{j}, shoe_{end}_deg), behind its arc: the chain runs over the shoe's end, and running onto it the roller would meet the shoe {:.2} mm deep, beyond the blow-up limit of {:.2} mm (solver.limits.max_penetration_m), so the run would blow up there. At rest the arm is turned by {:.2}° from the scene's pose (travel {:.2} mm){worn}{reach}: lengthen the shoe's arc (tensioners.{j}.shoe_start_deg, shoe_end_deg) or take the chain's slack up otherwise (fewer rollers, a sprocket moved)",
            found.roller,
            arm.name,
            1e3 * found.depth_m,
            1e3 * limits.max_penetration_m,
            angle_rad.to_degrees(),
            1e3 * travel_m,
            end = found.end,
        )));
    }
    Ok(())
}

/// Holds the sprockets k with `held[k]` for the static equilibrium (no
/// inverse inertia: the solve keeps them still); where that holds none and
/// no driver does either, one free sprocket
/// ([`statics::sprocket_to_hold`]: a drive with no driver has a neutral
/// circulation, which the solve must not look for). Returns what
/// [`release`] gives back, and the sprocket held for want of a driver.
fn hold(model: &mut DriveModel, held: &[bool]) -> (Vec<(usize, f64)>, Option<usize>) {
    let mut freed = Vec::new();
    for (k, sp) in model.sprockets.iter_mut().enumerate() {
        if held.get(k).copied().unwrap_or(false) {
            freed.push((k, sp.inv_inertia));
            sp.inv_inertia = 0.0;
        }
    }
    let auto = statics::sprocket_to_hold(model);
    if let Some(k) = auto {
        freed.push((k, model.sprockets[k].inv_inertia));
        model.sprockets[k].inv_inertia = 0.0;
    }
    (freed, auto)
}

/// The sprockets [`hold`] held: their inverse inertias to give back, and
/// the one held for want of a driver.
#[derive(Default)]
struct Held {
    freed: Vec<(usize, f64)>,
    auto: Option<usize>,
}

/// The sprockets' names, in order.
fn names(scene: &Scene) -> Vec<&str> {
    scene.sprockets.iter().map(|s| s.name.as_str()).collect()
}

/// Gives the sprockets [`hold`] held their inverse inertia back.
fn release(model: &mut DriveModel, freed: &[(usize, f64)]) {
    for &(k, inv_inertia) in freed {
        model.sprockets[k].inv_inertia = inv_inertia;
    }
}

/// Notes that the setup lets the sprocket `k`, held for want of a driver, go.
fn note_let_go(scene: &Scene, k: usize) {
    note_stage(|| {
        let name = scene.sprockets.get(k).map_or("", |s| s.name.as_str());
        format!("the drive with sprocket \"{name}\" let go (no driver holds it)")
    });
}
