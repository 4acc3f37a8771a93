//! `chaindrive bench`: long studies kept out of the test suite.
//!
//! - `soak`: the paper's drive for a long time (default 60 s), reported in
//!   windows, to show there is no drift — driven speed ratios exact on
//!   average, strand tension steady, penetration not growing.
//! - `fuzz`: thousands of mutated scene files through parse, layout,
//!   equilibrium and a short run (the property test runs a few hundred).
//! - `stress`: the stress matrix (`super::stress`).
//! - `convergence`: the summary statistics against a fine reference
//!   (`super::convergence`).
//! - `work-precision`: wall time against trajectory error (`super::work_precision`).
//!
//! The studies themselves live in `crate::studies`; this file parses the
//! arguments and prints.

use std::process::ExitCode;

use crate::scene::{L60MC_TOML, Overrides, ProfileKind};
use crate::sim::Simulation;
use crate::studies::fuzz::{FuzzOutcome, run_case};
use crate::studies::soak::{STEADY_FRACTION, STEADY_MIN_WINDOWS, STEADY_SE, Soak, steady_from};

/// Arguments of `chaindrive bench`.
#[derive(clap::Args)]
pub(super) struct BenchArgs {
    #[command(subcommand)]
    study: Study,
}

#[derive(clap::Subcommand)]
enum Study {
    /// A long run of a drive (the paper's by default), reported window by window.
    Soak {
        /// Scene file (default: the paper's drive).
        scene: Option<std::path::PathBuf>,
        /// Simulated time, s.
        #[arg(long, default_value_t = 60.0)]
        duration: f64,
        /// Report window, s.
        #[arg(long, default_value_t = 5.0)]
        window: f64,
        /// Tooth profile of every sprocket.
        #[arg(long, value_enum)]
        profile: Option<ProfileKind>,
        /// The chain's integration step, s, `auto` or `speed` (overrides the scene).
        #[arg(long, value_name = "SECONDS|auto|speed")]
        dt: Option<crate::cli::DtArg>,
    },
    /// The summary statistics of every integrator over a ladder of steps
    /// against a fine reference: table, CSV, figure, verdict.
    Convergence(crate::cli::convergence::ConvergenceArgs),
    /// Wall time against error for every integrator: table, CSV, figure.
    WorkPrecision(crate::cli::work_precision::WorkPrecisionArgs),
    /// Mutated scene files: no panic, every rejection explained, no NaN.
    Fuzz {
        /// Number of cases.
        #[arg(long, default_value_t = 5000)]
        cases: u64,
        /// First seed.
        #[arg(long, default_value_t = 0)]
        seed: u64,
    },
    /// Hard cases × integrators × a ladder of steps: stability limits,
    /// detectors, cost per simulated second.
    Stress(super::stress::StressArgs),
}

pub(super) fn bench(args: BenchArgs) -> anyhow::Result<ExitCode> {
    match args.study {
        Study::Soak {
            scene,
            duration,
            window,
            profile,
            dt,
        } => soak(scene.as_deref(), duration, window, profile, dt),
        Study::Fuzz { cases, seed } => fuzz(cases, seed),
        Study::Convergence(args) => crate::cli::convergence::convergence(args),
        Study::WorkPrecision(args) => crate::cli::work_precision::work_precision(args),
        Study::Stress(args) => super::stress::stress(args),
    }
}

fn soak(
    path: Option<&std::path::Path>,
    duration: f64,
    window: f64,
    profile: Option<ProfileKind>,
    dt: Option<crate::cli::DtArg>,
) -> anyhow::Result<ExitCode> {
    crate::cli::ensure_positive("--duration", duration)?;
    crate::cli::ensure_positive("--window", window)?;
    let (dt_s, dt_auto, dt_speed) = crate::cli::DtArg::overrides(dt);
    let overrides = Overrides {
        profile,
        duration_s: Some(duration),
        dt_s,
        dt_auto,
        dt_speed,
        ..Overrides::default()
    };
    let Some(scene) = crate::cli::load_scene_or_report(path, &overrides)? else {
        return Ok(ExitCode::FAILURE);
    };
    let mut sim = Simulation::new(&scene)?;
    let mut obs = Soak::new(window, sim.model.segments.len());
    let every = (1e-3 / scene.solver().dt_s).round().max(1.0) as u64;
    let started = std::time::Instant::now();
    let outcome = sim.run(duration, every, &mut obs, None)?;
    // Speed ratios against the driver, or the first sprocket in a drive without one.
    let driver = sim.model.driver().unwrap_or(0);
    let teeth: Vec<f64> = scene
        .sprockets()
        .iter()
        .map(|s| f64::from(s.teeth))
        .collect();
    let sense: Vec<f64> = scene.sprockets().iter().map(|s| s.wrap.sign()).collect();
    println!(
        "soak: {} profile, {duration} s simulated in {:.1} s wall ({:.0} ns/step), windows of {window} s",
        scene.profile_name(),
        started.elapsed().as_secs_f64(),
        outcome.wall_s * 1e9 / outcome.steps.max(1) as f64
    );
    print!("{:>11}", "window_s");
    for j in (0..teeth.len()).filter(|&j| j != driver) {
        print!("  ratio{}_err_ppm", j + 1);
    }
    for k in 0..sim.model.segments.len() {
        print!("  seg{}_mean_n  ±se_n", k + 1);
    }
    println!("  max_penetration_um");
    let (means, ses) = obs.means_and_ses();
    for (i, w) in obs.windows.iter().enumerate() {
        let omega = w.mean_omega_rad_s();
        print!(
            "{:>5.0}–{:<5.0}",
            i as f64 * window,
            (i + 1) as f64 * window
        );
        for j in (0..teeth.len()).filter(|&j| j != driver) {
            // |ω_j / ω_1| = N_1 / N_j, the sign from the wrap senses.
            let expected = omega[driver] * teeth[driver] / teeth[j] * sense[j] * sense[driver];
            let err = if expected != 0.0 {
                (omega[j] - expected) / expected * 1e6
            } else {
                0.0
            };
            print!("  {err:>15.1}");
        }
        for (f, se) in means[i].iter().zip(&ses[i]) {
            print!("  {f:>11.0}  {se:>5.0}");
        }
        println!("  {:>18.1}", w.max_penetration_m * 1e6);
    }
    match steady_from(&means, &ses) {
        Some(k) => println!(
            "steady from {:.0} s: from there every window's segment means lie within ±{:.0} % of their overall mean or within {:.0} standard errors",
            k as f64 * window,
            100.0 * STEADY_FRACTION,
            STEADY_SE
        ),
        None => println!(
            "not steady: no window start leaves at least half of the run (and {STEADY_MIN_WINDOWS} windows) with every window's segment means within ±{:.0} % of their overall mean or within {:.0} standard errors",
            100.0 * STEADY_FRACTION,
            STEADY_SE
        ),
    }
    Ok(ExitCode::SUCCESS)
}

fn fuzz(cases: u64, seed: u64) -> anyhow::Result<ExitCode> {
    let (mut rejected, mut failed, mut blew_up, mut ran) = (0u64, 0u64, 0u64, 0u64);
    let mut broken = Vec::new();
    for s in seed..seed + cases {
        match std::panic::catch_unwind(|| run_case(L60MC_TOML, s)) {
            Ok(Ok(FuzzOutcome::Rejected)) => rejected += 1,
            Ok(Ok(FuzzOutcome::Failed)) => failed += 1,
            Ok(Ok(FuzzOutcome::BlewUp)) => blew_up += 1,
            Ok(Ok(FuzzOutcome::Ran)) => ran += 1,
            Ok(Err(e)) => broken.push(e),
            Err(_) => broken.push(format!("seed {s}: panic")),
        }
    }
    println!(
        "{cases} cases from seed {seed}: {rejected} rejected with explained errors, {failed} failed to settle with an error, {blew_up} blew up with an error, {ran} ran without NaN, {} broke a promise",
        broken.len()
    );
    for b in &broken {
        println!("  {b}");
    }
    Ok(if broken.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}
