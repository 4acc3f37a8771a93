//! Setting a simulation up, before its first step: the force elements a
//! scene asks for, the layout and the static equilibrium by the scene's
//! pretension rule (rest length, tensioner, tensioner preload), sprockets
//! held for the solve where a co-simulation asks, and a worn chain's links
//! lengthened after it settled new. What this module does not do: step the
//! drive, or build the rapier world (`Simulation::assemble`).

use super::statics::{
    self, EquilibriumError, RelaxSettings, fit_sprocket, force_residual, free_strand_tension,
    settle_rest_length,
};
use super::{BlowUpLimits, SimError, StaticEquilibrium, parallel, worn};
use crate::forces::{
    ContactLawParams, ForceGenerator, GuideElement, JointFrictionElement, TensionerArm,
};
use crate::geometry::Layout;
use crate::model::{DriveModel, DriveState};
use crate::scene::{PretensionRule, Role, Scene, StepLimits, TensionerKind};

/// Lays out `scene`'s drive and brings it to static equilibrium by its
/// pretension rule, the sprockets k with `held[k]` held at rest for the
/// solve ([`super::Simulation::new_holding`]); a worn chain settles new
/// first and is then lengthened. Returns the settled drive and the blow-up
/// limits its run keeps.
pub(super) fn settle(scene: &Scene, held: &[bool]) -> Result<(Settled, BlowUpLimits), SimError> {
    let limits = BlowUpLimits::for_scene(scene);
    // The relaxation steps symplectic Euler with the contact damping
    // implicit: only the links limit its step, whatever step the run's
    // integrator takes.
    let settings = RelaxSettings {
        dt_s: scene.solver.dt_s.min(0.8 * StepLimits::of(scene).links_s),
        max_time_s: scene.equilibrium.max_relax_s,
        rate_per_s: 60.0,
        rest_speed_m_s: 1e-6,
        max_stretch_m: limits.max_stretch_m,
    };
    // A worn chain: the drive with the chain new first, at its
    // pretension; its links are then lengthened (`worn`).
    let worn = scene;
    let new_chain = worn.as_new_chain();
    let scene = new_chain.as_ref().unwrap_or(worn);
    let settled = match scene.chain.pretension_by {
        PretensionRule::RestLength => {
            let (mut model, mut state, layout) = DriveModel::build(scene)?;
            statics::check_chain_length(scene, &layout, &model.path)?;
            statics::check_load(scene, &layout)?;
            let mut forces = new_forces(scene, &model);
            let freed = hold(&mut model, held);
            let eq = settle_rest_length(
                &mut model,
                &mut state,
                &mut forces,
                &settings,
                scene.chain.pretension_n,
                scene.equilibrium.tension_tolerance,
                &scene
                    .sprockets
                    .iter()
                    .map(|s| s.name.as_str())
                    .collect::<Vec<_>>(),
            )?;
            release(&mut model, &freed);
            (scene.clone(), model, state, forces, layout, eq)
        }
        PretensionRule::Tensioner => settle_tensioner(scene, &settings)?,
        PretensionRule::TensionerPreload => {
            let (mut model, mut state, layout) = DriveModel::build(scene)?;
            let mut forces = new_forces(scene, &model);
            let freed = hold(&mut model, held);
            let mut eq = statics::settle_preload(
                &model,
                &mut state,
                &mut forces,
                &settings,
                scene.chain.pretension_n,
            )?;
            release(&mut model, &freed);
            eq.misfit = statics::misfit_tension(scene, &layout, &forces, eq.tension_n);
            (scene.clone(), model, state, forces, layout, eq)
        }
    };
    let settled = if new_chain.is_some() {
        wear_settled(worn, settled, &settings)?
    } else {
        settled
    };
    Ok((settled, limits))
}

pub(crate) fn new_forces(scene: &Scene, model: &DriveModel) -> ForceGenerator {
    let mut forces = ForceGenerator::new(
        ContactLawParams::new(&scene.contact),
        model,
        scene.chain.rollers,
    );
    // The roller loops on two threads where the setting and size say so.
    forces.set_fork(Some(Box::new(parallel::Split::new(scene.solver.threads))));
    if let Some(joints) = scene.chain.joint_friction {
        forces.add(Box::new(JointFrictionElement::new(
            joints,
            scene.chain.rollers,
        )));
    }
    let mut scalar = 0;
    for (k, t) in scene.tensioners.iter().enumerate() {
        let chamber = matches!(t.kind, TensionerKind::Hydraulic(_)).then(|| {
            scalar += 1;
            scalar - 1
        });
        forces.add(Box::new(TensionerArm::new(
            t,
            k,
            chamber,
            ContactLawParams::new(&scene.contact),
            scene.chain.rollers,
            scene.chain.roller_radius_m,
        )));
    }
    for guide in &scene.guides {
        forces.add(Box::new(GuideElement::fixed(guide, &scene.chain)));
    }
    forces
}

pub(super) type Settled = (
    Scene,
    DriveModel,
    DriveState,
    ForceGenerator,
    Layout,
    StaticEquilibrium,
);

/// The tensioner rule: links keep their rest length P; the tensioner's
/// centre first moves along its adjustment direction until the unstretched
/// chain fits the path through the seated rollers ([`fit_sprocket`]; refused
/// only when its travel cannot close the gap), then on from there, by a
/// secant iteration on the static tension, until the pretension is reached.
/// Each iterate lays the chain out anew and settles it (Newton's method, the
/// relaxation where it stalls). The returned scene holds
/// the tensioner's final centre, so every output describes the drive simulated
/// (docs/model.md, “Pretension and static equilibrium”).
fn settle_tensioner(scene: &Scene, settings: &RelaxSettings) -> Result<Settled, SimError> {
    const MAX_ITERATIONS: usize = 20;
    let Some(t) = scene.tensioner() else {
        return Err(SimError::Equilibrium(EquilibriumError::NoTensioner));
    };
    let Role::Tensioner { direction, .. } = scene.sprockets[t].role else {
        return Err(SimError::Equilibrium(EquilibriumError::NoTensioner));
    };
    let target = scene.chain.pretension_n;
    let tension_at = |offset: f64| -> Result<(Settled, f64), SimError> {
        let mut moved = scene.clone();
        let c = &mut moved.sprockets[t].center_m;
        c[0] += offset * direction[0];
        c[1] += offset * direction[1];
        let (model, mut state, layout) = DriveModel::build(&moved)?;
        let mut forces = new_forces(&moved, &model);
        // Newton at this offset, the relaxation only where it stalls.
        let residual = statics::settle(
            &model,
            &mut state,
            &mut forces,
            settings,
            statics::REST_FORCE * target.abs(),
            0.5 * statics::REST_FORCE * target.abs(),
            true,
        )?;
        let tension =
            free_strand_tension(&model, &state, &forces).ok_or(EquilibriumError::NoFreeLinks)?;
        let eq = StaticEquilibrium {
            tension_n: tension,
            rest_length_m: model.rest_length_m,
            iterations: 0,
            residual_speed_m_s: residual,
            force_residual: force_residual(&forces, target),
            beyond_seating_arc: None,
            misfit: None,
        };
        Ok(((moved, model, state, forces, layout, eq), tension))
    };
    // Where the unstretched chain fits; from there, the first step is the
    // move that stretches every link by T₀/K (the path grows by
    // slope · P per metre of move).
    let fit = fit_sprocket(scene, t, direction, scene.chain.rollers).map_err(|reason| {
        EquilibriumError::TensionerFit {
            sprocket: scene.sprockets[t].name.clone(),
            reason: Box::new(reason),
        }
    })?;
    let first_step_m = (target / scene.chain.stiffness_n_m) * scene.chain.rollers as f64
        / (fit.slope_per_m * scene.chain.pitch_m);
    // At the fit the unstretched chain carries no tension (nothing to relax:
    // no roller presses on a tooth, so no strand could be told from a wrap).
    let (mut s0, mut t0) = (fit.offset_m, 0.0);
    let mut s1 = s0 + first_step_m;
    for iteration in 1..=MAX_ITERATIONS {
        let (mut settled, t1) = tension_at(s1)?;
        if ((t1 - target) / target).abs() <= scene.equilibrium.tension_tolerance {
            settled.5.iterations = iteration;
            return Ok(settled);
        }
        let slope = (t1 - t0) / (s1 - s0);
        if !(slope.abs() > 0.0) || !slope.is_finite() {
            break;
        }
        (s0, t0, s1) = (s1, t1, s1 + (target - t1) / slope);
    }
    Err(SimError::Equilibrium(EquilibriumError::NotConverged {
        tension_n: t0,
        target_n: target,
        iterations: MAX_ITERATIONS,
    }))
}

/// Lengthens the links of a drive `settled` with its chain new to `worn`'s
/// elongation ([`worn::wear_in`]); the tensioner rule's sprocket moves on
/// to keep the pretension. Returns the worn drive, its scene `worn`'s with
/// the tensioner where it ended.
fn wear_settled(
    worn: &Scene,
    settled: Settled,
    settings: &RelaxSettings,
) -> Result<Settled, SimError> {
    let (mut scene, mut model, mut state, mut forces, layout, _) = settled;
    let e = worn.chain.elongation;
    let chain = &worn.chain;
    let take_up = match (chain.pretension_by, scene.tensioner()) {
        (PretensionRule::Tensioner, Some(t)) => {
            let Role::Tensioner { direction, .. } = scene.sprockets[t].role else {
                return Err(SimError::Equilibrium(EquilibriumError::NoTensioner));
            };
            // The path's gain per metre the sprocket moves, from the fit's
            // slope (pitches per metre) where the new chain sits.
            let fit = fit_sprocket(&scene, t, direction, chain.rollers).map_err(|reason| {
                EquilibriumError::TensionerFit {
                    sprocket: scene.sprockets[t].name.clone(),
                    reason: Box::new(reason),
                }
            })?;
            let norm = direction[0].hypot(direction[1]);
            Some((
                t,
                [direction[0] / norm, direction[1] / norm],
                1.0 / (fit.slope_per_m * chain.pitch_m),
            ))
        }
        _ => None,
    };
    let mut taken = scene.clone();
    let eq = worn::wear_in(
        &mut model,
        &mut state,
        &mut forces,
        settings,
        e,
        chain.pretension_n,
        take_up.map(|(sprocket, direction, travel_per_length)| worn::TakeUp {
            scene: &mut taken,
            sprocket,
            direction,
            travel_per_length,
            tolerance: worn.equilibrium.tension_tolerance,
        }),
    )?;
    scene = taken;
    scene.chain.elongation = e;
    Ok((scene, model, state, forces, layout, eq))
}

/// Holds the sprockets k with `held[k]` for the static equilibrium (no
/// inverse inertia: the solve keeps them still); returns what [`release`]
/// gives back.
fn hold(model: &mut DriveModel, held: &[bool]) -> Vec<(usize, f64)> {
    let mut freed = Vec::new();
    for (k, sp) in model.sprockets.iter_mut().enumerate() {
        if held.get(k).copied().unwrap_or(false) {
            freed.push((k, sp.inv_inertia));
            sp.inv_inertia = 0.0;
        }
    }
    freed
}

/// Gives the sprockets [`hold`] held their inverse inertia back.
fn release(model: &mut DriveModel, freed: &[(usize, f64)]) {
    for &(k, inv_inertia) in freed {
        model.sprockets[k].inv_inertia = inv_inertia;
    }
}
