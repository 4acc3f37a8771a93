//! `chaindrive check`: validate a scene and print its layout.

use std::path::PathBuf;
use std::process::ExitCode;

use crate::geometry::{Layout, LayoutError};
use crate::model::{BuildError, DriveModel};
use crate::scene::{PretensionRule, Role, Scene};
use crate::sim::{
    EquilibriumError, SimError, Simulation, count_verdicts, default_direction, fit_sprocket,
    needed_pitches_of,
};

/// Arguments of `chaindrive check`.
#[derive(clap::Args)]
pub(super) struct CheckArgs {
    /// Scene file (TOML). Default: the embedded paper drive.
    scene: Option<PathBuf>,
    /// The chain's integration step, s, `auto` or `speed` (overrides the scene).
    #[arg(long, value_name = "SECONDS|auto|speed")]
    dt: Option<crate::cli::DtArg>,
    /// The sample rate `run --rate` would use, Hz: an automatic step is a
    /// whole fraction of its period.
    #[arg(long, default_value_t = 1000.0)]
    rate: f64,
}

pub(super) fn check(args: CheckArgs) -> anyhow::Result<ExitCode> {
    let (dt_s, dt_auto, dt_speed) = crate::cli::DtArg::overrides(args.dt);
    let overrides = crate::scene::Overrides {
        dt_s,
        dt_auto,
        dt_speed,
        sample_rate_hz: Some(args.rate),
        ..Default::default()
    };
    let Some(scene) = crate::cli::load_scene_or_report(args.scene.as_deref(), &overrides)? else {
        return Ok(ExitCode::FAILURE);
    };
    let name = args.scene.as_ref().map_or_else(
        || "<embedded l60mc.toml>".to_owned(),
        |p| p.display().to_string(),
    );
    let tensioner_rule = scene.chain().pretension_by == PretensionRule::Tensioner;
    println!(
        "scene: {} ({} rollers, {} sprockets)",
        scene.name(),
        scene.chain().rollers,
        scene.sprockets().len()
    );
    // Under the tensioner rule the chain need not fit where the tensioner is
    // written: the tensioner takes it up, and the layout is printed where it ends.
    match DriveModel::build(&scene) {
        Ok((model, _, layout)) => print_layout(&scene, &model, &layout, layout.polygon_length_m),
        Err(BuildError::Layout(LayoutError::ChainLength { needed, .. })) if tensioner_rule => {
            println!(
                "as written, the path through the seated rollers needs {needed:.3} pitches of chain for {} links: the tensioner moves to take it up",
                scene.chain().rollers
            );
        }
        Err(e) => {
            eprintln!("{name}: {e}");
            if let BuildError::Layout(LayoutError::ChainLength { .. }) = e {
                suggest_fit(&scene, &name);
            }
            return Ok(ExitCode::FAILURE);
        }
    }
    println!("{}", crate::scene::step_note(&scene));
    for w in scene.warnings() {
        eprintln!("{name}: warning: {w}");
    }
    let started = std::time::Instant::now();
    match super::run::note_slow_setup(false, || Simulation::new(&scene)) {
        Ok(sim) => {
            if let Some(t) = scene.tensioner().filter(|_| tensioner_rule) {
                let (from, to) = (
                    scene.sprockets()[t].center_m,
                    sim.scene.sprockets()[t].center_m,
                );
                println!("at the tensioner's final position:");
                // A worn chain's wear moved the tensioner on after the
                // layout: the polygon is the one where it ends.
                let polygon_m = crate::sim::needed_pitches_of(&sim.scene)
                    .map_or(sim.layout.polygon_length_m, |n| n * scene.chain().pitch_m);
                print_layout(&sim.scene, &sim.model, &sim.layout, polygon_m);
                println!(
                    "tensioner \"{}\": centre [{:.6}, {:.6}] m, moved {:.6} m from [{}, {}] along its adjust_direction",
                    scene.sprockets()[t].name,
                    to[0],
                    to[1],
                    (to[0] - from[0]).hypot(to[1] - from[1])
                        * if (to[0] - from[0]) * direction(&scene, t)[0]
                            + (to[1] - from[1]) * direction(&scene, t)[1]
                            < 0.0
                        {
                            -1.0
                        } else {
                            1.0
                        },
                    from[0],
                    from[1]
                );
            }
            // A tensioner moved until the pretension is reached leaves a
            // path longer than the unstretched chain by the links' elastic
            // stretch: that is the pretension, not a misfit to fit away.
            // Where the misfit, not the tensioner arms, sets the tension, it is a warning.
            if let Some(misfit) = &sim.equilibrium.misfit {
                eprintln!("{name}: warning: {misfit}");
                suggest_fit(&scene, &name);
            } else if !tensioner_rule {
                misfit_notice(&name, &sim.scene, &sim.layout);
            }
            println!(
                "static equilibrium: tension {:.1} N (target {:.1} N), link rest length {:.7} m, {} iteration(s), residual {:.1e} of the pretension, {:.2} s",
                sim.equilibrium.tension_n,
                scene.chain().pretension_n,
                sim.model.rest_length_m,
                sim.equilibrium.iterations,
                sim.equilibrium.force_residual,
                started.elapsed().as_secs_f64()
            );
            guide_rates(&name, &sim);
            if sim.equilibrium.misfit.is_none() {
                idle_tensioners(&name, &sim);
            }
            if let Some(w) = sim.unmeshed_warning() {
                eprintln!("{name}: warning: {w}");
            }
            if let Some(unbalanced) = &sim.equilibrium.unbalanced {
                eprintln!("{name}: warning: {unbalanced}");
            }
            if let Some(slack) = &sim.equilibrium.worn_slack {
                eprintln!("{name}: warning: {slack}");
            }
            let residual = sim.equilibrium.force_residual;
            if residual > crate::analysis::STATIC_RESIDUAL_TOLERANCE || residual.is_nan() {
                eprintln!(
                    "{name}: warning: not settled: a roller force imbalance of {residual:.1e} of the pretension is left (above {:.0e}); a run starts from a state that is not at rest",
                    crate::analysis::STATIC_RESIDUAL_TOLERANCE
                );
                if let Some(cause) = &sim.equilibrium.beyond_seating_arc {
                    eprintln!("{name}: the cause: {cause}");
                }
            }
        }
        Err(e) => {
            eprintln!("{name}: {e}");
            match e {
                // Short only by what the strands' sag holds: the chain fits
                // the straight path already, and no move of the straight
                // layout (which accepts a chain within a quarter pitch of
                // it) makes room for a sag of more.
                SimError::Equilibrium(EquilibriumError::ChainTooShort {
                    short_m,
                    sag_m,
                    needed_tension_n,
                    ..
                }) if sag_m > 0.0 && short_m <= sag_m + 1e-6 * scene.chain().pitch_m => {
                    eprintln!(
                        "{name}: the chain fits the path through the seated rollers; what it lacks is the {:.1} mm its strands' sag holds at chain.pretension_n, which straight strands cannot give: set chain.pretension_n to about {needed_tension_n:.0} N, the tension this chain carries when it hangs",
                        sag_m * 1e3
                    );
                }
                SimError::Equilibrium(
                    EquilibriumError::ChainTooShort { .. } | EquilibriumError::ChainTooLong { .. },
                ) => suggest_fit(&scene, &name),
                _ => {}
            }
            return Ok(ExitCode::FAILURE);
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// The tensioner's unit adjustment direction.
fn direction(scene: &Scene, t: usize) -> [f64; 2] {
    match scene.sprockets()[t].role {
        Role::Tensioner { direction, .. } => direction,
        _ => [0.0, 0.0],
    }
}

/// The strands and wraps of a laid-out drive, with the length of the
/// polygon through its seated rollers, `polygon_m`.
fn print_layout(scene: &Scene, model: &DriveModel, layout: &Layout, polygon_m: f64) {
    println!("segment  from  to   length_m   angle_on_from_rad  angle_on_to_rad  links");
    for (k, s) in model.path.strands.iter().enumerate() {
        println!(
            "{:>7}  {:>4}  {:>2}  {:>9.4}  {:>17.4}  {:>15.4}  {:>5}",
            k + 1,
            s.from + 1,
            s.to + 1,
            s.length_m,
            s.angle_on_from_rad,
            s.angle_on_to_rad,
            layout.strand_links[k]
        );
    }
    println!("sprocket  teeth  pitch_radius_m  wrap_rad  wrap_pitches");
    for (k, (sp, w)) in scene.sprockets().iter().zip(&model.path.wraps).enumerate() {
        println!(
            "{:>8}  {:>5}  {:>14.6}  {:>8.4}  {:>12.2}",
            k + 1,
            sp.teeth,
            sp.pitch_radius_m,
            w.wrap_rad,
            w.wrap_rad * f64::from(sp.teeth) / std::f64::consts::TAU
        );
    }
    let chain = scene.chain();
    let new_m = chain.rollers as f64 * chain.pitch_m;
    let worn = if chain.elongation > 0.0 {
        format!(
            " new, {:.4} m worn (pitch {:.6} m)",
            chain.rollers as f64 * chain.worn_pitch_m(),
            chain.worn_pitch_m()
        )
    } else {
        String::new()
    };
    println!(
        "polygon through the seated rollers: {polygon_m:.4} m; unstretched chain: {new_m:.4} m{worn}"
    );
    if let Some(t) = crate::sim::arm_take_up_of(scene) {
        println!(
            "tensioner arms: their shoes take up {:.2} mm of chain at the scene's pose, {:.2} to {:.2} mm over their travel ({})",
            t.pose_m * 1e3,
            t.min_m * 1e3,
            t.max_m * 1e3,
            t.bound
        );
    }
    for (t, arm) in scene.tensioners().iter().zip(&layout.arms) {
        println!(
            "tensioner \"{}\": laid turned by {:.3}° (travel {:.2} mm) to take up the chain's length",
            t.name,
            arm.angle_rad.to_degrees(),
            arm.travel_m * 1e3
        );
    }
}

/// A notice when the layout took up a misfit by laying the strand links
/// longer (a short chain) or shorter (a long one) than the pitch.
fn misfit_notice(name: &str, scene: &Scene, layout: &Layout) {
    let pitch = scene.chain().pitch_m;
    let misfit_m = layout.misfit_pitches * pitch;
    if misfit_m.abs() <= 1e-6 {
        return;
    }
    let free: usize = layout.strand_links.iter().sum();
    if layout.hanging {
        eprintln!(
            "{name}: notice: the chain is {:.3} pitches ({:.3} mm) longer than the path through the seated rollers; it is laid hanging in its strands' sag, its {free} free links one pitch long",
            layout.misfit_pitches.abs(),
            misfit_m.abs() * 1e3,
        );
        return;
    }
    eprintln!(
        "{name}: notice: the chain is {:.3} pitches ({:.3} mm) {} than the path through the seated rollers; its {free} free links are laid {:.4} % {} than the pitch to take this up (`chaindrive fit` moves a sprocket so that it fits exactly)",
        layout.misfit_pitches.abs(),
        misfit_m.abs() * 1e3,
        if misfit_m > 0.0 { "shorter" } else { "longer" },
        layout.strand_stretch(pitch).abs() * 100.0,
        if misfit_m > 0.0 { "longer" } else { "shorter" },
    );
}

/// Arms whose tensioner holds no chain at rest: the push is spent (the
/// plunger at its free length) or no roller touches the shoe. The strands'
/// tension is then not what the tensioner gives, whatever its preload.
fn idle_tensioners(name: &str, sim: &Simulation) {
    for (t, r) in sim
        .scene
        .tensioners()
        .iter()
        .zip(&sim.forces.output().tensioners)
    {
        if r.plunger_force_n <= 0.0 || r.shoe_rollers == 0 {
            eprintln!(
                "{name}: warning: tensioner \"{}\" holds no chain at rest: it pushes {:.1} N at travel {:.2} mm and {} roller(s) touch its shoe ({:.1} N); the arm hangs free, so the strands' tension is not set by it: raise its preload, or shorten the chain",
                t.name,
                r.plunger_force_n,
                r.travel_m * 1e3,
                r.shoe_rollers,
                r.shoe_force_n
            );
        }
    }
}

/// After a chain that does not fit: the roller counts `check` accepts as
/// the drive stands, and the move of one sprocket (`chaindrive fit`) that
/// makes the nearest count fit exactly.
fn suggest_fit(scene: &Scene, name: &str) {
    let verdicts = count_verdicts(scene);
    let counts: Vec<usize> = verdicts
        .iter()
        .filter(|v| v.refused.is_none())
        .map(|v| v.rollers)
        .collect();
    let needed = needed_pitches_of(scene).ok();
    match (&counts[..], needed) {
        ([], Some(n)) => {
            eprintln!(
                "{name}: no roller count fits as the sprockets stand (the path needs {n:.3} pitches):"
            );
            for v in &verdicts {
                if let Some(why) = &v.refused {
                    eprintln!("{name}:   {} rollers: {why}", v.rollers);
                }
            }
            eprintln!("{name}: move a sprocket instead:");
        }
        ([], None) => {}
        (c, _) => eprintln!(
            "{name}: a chain of {} rollers fits as the sprockets stand (chain.rollers); or move a sprocket:",
            c.iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join(" or ")
        ),
    }
    let Some(k) = mover(scene) else {
        return;
    };
    let Some(dir) = default_direction(scene, k) else {
        return;
    };
    let target = needed.map_or(scene.chain().rollers, |n| n.round().max(4.0) as usize);
    for rollers in [scene.chain().rollers, target] {
        match fit_sprocket(scene, k, dir, rollers) {
            Ok(fit) => eprintln!(
                "{name}:   with {rollers} rollers, sprocket \"{}\" moved by [{:+.6}, {:+.6}] m to [{:.6}, {:.6}] fits: chaindrive fit {name} --move \"{}\"{}",
                scene.sprockets()[k].name,
                fit.offset_m * fit.direction[0],
                fit.offset_m * fit.direction[1],
                fit.center_m[0],
                fit.center_m[1],
                scene.sprockets()[k].name,
                if rollers == scene.chain().rollers {
                    String::new()
                } else {
                    format!(" --rollers {rollers}")
                }
            ),
            Err(e) => eprintln!("{name}:   with {rollers} rollers: {e}"),
        }
        if target == scene.chain().rollers {
            break;
        }
    }
}

/// The sprocket a suggested fit moves: the tensioner, else the last
/// sprocket that is not the driver.
fn mover(scene: &Scene) -> Option<usize> {
    scene.tensioner().or_else(|| {
        (0..scene.sprockets().len())
            .rev()
            .find(|&k| k != scene.driver())
    })
}

/// Each fixed guide's evaluation interval against its contact's largest
/// stable one at the most loaded roller at rest (a warning above half of it
/// where the guide is evaluated every k > 1 steps).
fn guide_rates(name: &str, sim: &Simulation) {
    for (line, warning) in super::guide_intervals::guide_intervals(sim) {
        println!("{line}");
        if let Some(w) = warning {
            eprintln!("{name}: warning: {w}");
        }
    }
}
