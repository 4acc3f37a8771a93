//! `chaindrive check`: validate a scene and print its layout.

use std::path::PathBuf;
use std::process::ExitCode;

use chaindrive::model::DriveModel;
use chaindrive::sim::{Simulation, StepLimits};

/// Arguments of `chaindrive check`.
#[derive(clap::Args)]
pub struct CheckArgs {
    /// Scene file (TOML). Default: the embedded paper drive.
    scene: Option<PathBuf>,
    /// The chain's integration step, s, or `auto` (overrides the scene).
    #[arg(long, value_name = "SECONDS|auto")]
    dt: Option<crate::DtArg>,
}

pub fn check(args: CheckArgs) -> anyhow::Result<ExitCode> {
    let (dt_s, dt_auto) = crate::DtArg::overrides(args.dt);
    let overrides = chaindrive::scene::Overrides {
        dt_s,
        dt_auto,
        ..Default::default()
    };
    let scene = match crate::load_scene(args.scene.as_deref(), &overrides)? {
        Ok(s) => s,
        Err(lines) => {
            eprintln!("{lines}");
            return Ok(ExitCode::FAILURE);
        }
    };
    let name = args.scene.as_ref().map_or_else(
        || "<embedded l60mc.toml>".to_owned(),
        |p| p.display().to_string(),
    );
    let (model, _, layout) = match DriveModel::build(&scene) {
        Ok(x) => x,
        Err(e) => {
            eprintln!("{name}: {e}");
            return Ok(ExitCode::FAILURE);
        }
    };
    println!(
        "scene: {} ({} rollers, {} sprockets)",
        scene.name(),
        scene.chain().rollers,
        scene.sprockets().len()
    );
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
    println!(
        "polygon through the seated rollers: {:.4} m; unstretched chain: {:.4} m",
        layout.polygon_length_m,
        scene.chain().rollers as f64 * scene.chain().pitch_m
    );
    let limits = StepLimits::of(&scene);
    println!(
        "explicit step limits: links {:.1} µs, contact damping {:.1} µs; dt = {:.2} µs{}",
        limits.links_s * 1e6,
        limits.contact_damping_s * 1e6,
        scene.solver().dt_s * 1e6,
        if scene.solver().dt_auto {
            format!(
                " (auto: {} x the integrator's limit, at most 1/{} of a roller's impact)",
                chaindrive::scene::AUTO_SAFETY,
                chaindrive::scene::AUTO_STEPS_PER_IMPACT
            )
        } else {
            String::new()
        }
    );
    if scene.solver().dt_s > limits.min_s() {
        eprintln!(
            "{name}: warning: solver.dt_s = {:e} s exceeds the estimated stability limit {:.2e} s",
            scene.solver().dt_s,
            limits.min_s()
        );
    }
    for w in scene.warnings() {
        eprintln!("{name}: warning: {w}");
    }
    let started = std::time::Instant::now();
    match Simulation::new(&scene) {
        Ok(sim) => {
            println!(
                "static equilibrium: tension {:.1} N (target {:.1} N), link rest length {:.7} m, {} iteration(s), residual {:.1e} of the pretension, {:.2} s",
                sim.equilibrium.tension_n,
                scene.chain().pretension_n,
                sim.model.rest_length_m,
                sim.equilibrium.iterations,
                sim.equilibrium.force_residual,
                started.elapsed().as_secs_f64()
            );
            let residual = sim.equilibrium.force_residual;
            if residual > chaindrive::analysis::STATIC_RESIDUAL_TOLERANCE || residual.is_nan() {
                eprintln!(
                    "{name}: warning: not settled: a roller force imbalance of {residual:.1e} of the pretension is left (above {:.0e}); a run starts from a state that is not at rest",
                    chaindrive::analysis::STATIC_RESIDUAL_TOLERANCE
                );
            }
        }
        Err(e) => {
            eprintln!("{name}: {e}");
            return Ok(ExitCode::FAILURE);
        }
    }
    Ok(ExitCode::SUCCESS)
}
