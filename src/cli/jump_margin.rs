//! `chaindrive jump-margin`: the least value of one scene field (a
//! tensioner's preload, the pretension) at which a worn chain runs a given
//! time without a tooth jump or a roller riding a tip, or the largest
//! elongation that does; a bracketing search over runs
//! ([`crate::studies::jump_margin`]), each run ending at its first jump (a
//! run whose rollers ride a tip without jumping runs on: the ride is read
//! from the detector at its end).

use std::path::PathBuf;
use std::process::ExitCode;

use crate::scene::{Assignment, Overrides};
use crate::sim::{SampleRate, SimError, Simulation};
use crate::studies::jump_margin::{self, Outcome, Probe, Range};

/// Arguments of `chaindrive jump-margin`.
#[derive(clap::Args)]
pub(super) struct JumpMarginArgs {
    /// Scene file (TOML).
    scene: PathBuf,
    /// The scene value searched, by its path in the scene file: the
    /// pretension (default), a spring tensioner's `tensioners.0.spring.preload_n`,
    /// a hydraulic one's `tensioners.0.hydraulic.supply_pressure_pa`, or
    /// `chain.elongation_pct` itself.
    #[arg(long, default_value = "chain.pretension_n", value_name = "PATH")]
    path: String,
    /// The low end of the range searched.
    #[arg(long, value_name = "VALUE")]
    from: f64,
    /// The high end of the range searched.
    #[arg(long, value_name = "VALUE")]
    to: f64,
    /// Stop once the bracket is at most this wide (the value's unit).
    #[arg(long, value_name = "VALUE")]
    tolerance: f64,
    /// The chain's wear elongation, % (overrides the scene's `chain.elongation_pct`).
    #[arg(long, value_name = "PCT")]
    elongation: Option<f64>,
    /// Simulated time each run must go without a jump, s (overrides the scene).
    #[arg(long, value_name = "S")]
    duration: Option<f64>,
    /// Any other scene value, the same in every run: PATH=VALUE (repeatable).
    #[arg(long = "set", value_name = "PATH=VALUE")]
    set: Vec<String>,
    /// Runs at once, and values tried per round.
    #[arg(long, default_value_t = 2)]
    jobs: usize,
    /// Count only tooth jumps: a run whose rollers ride a tip without
    /// jumping runs clean (by default a ride counts as a jump).
    #[arg(long)]
    jumps_only: bool,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

pub(super) fn jump_margin(args: JumpMarginArgs) -> anyhow::Result<ExitCode> {
    if let Some(d) = args.duration {
        crate::cli::ensure_positive("--duration", d)?;
    }
    let range = Range {
        from: args.from,
        to: args.to,
        tolerance: args.tolerance,
        jobs: args.jobs.max(1),
    };
    range.check()?;
    if let Some(e) = args.elongation
        && args.path == "chain.elongation_pct"
    {
        anyhow::bail!(
            "--elongation {e} with --path chain.elongation_pct: the search sets the elongation from --from to --to; allowed: --elongation with another --path"
        );
    }
    let overrides = Overrides {
        duration_s: args.duration,
        ..Default::default()
    };
    let Some(base) = crate::cli::load_scene_or_report(Some(&args.scene), &overrides)? else {
        return Ok(ExitCode::FAILURE);
    };
    let mut fixed = vec![Assignment::parse("checks.tooth_jump", "\"stop\"")?];
    if let Some(e) = args.elongation {
        fixed.push(Assignment::parse("chain.elongation_pct", &e.to_string())?);
    }
    for a in &args.set {
        fixed.push(a.parse().map_err(|e| anyhow::anyhow!("--set {a}: {e}"))?);
    }
    let base = base.with_set(&fixed).map_err(|e| anyhow::anyhow!("{e}"))?;
    // The path and a value of the range checked once before anything runs.
    base.with_set(&[Assignment::parse(&args.path, &args.from.to_string())?])
        .map_err(|e| anyhow::anyhow!("--path {}: {e}", args.path))?;
    let duration_s = base.solver().duration_s;
    let run = |value: f64| -> Result<Outcome, String> {
        let a = Assignment::parse(&args.path, &value.to_string()).map_err(|e| e.to_string())?;
        let scene = base.with_set(&[a]).map_err(|e| e.to_string())?;
        let mut sim = Simulation::new(&scene).map_err(|e| e.to_string())?;
        let every = SampleRate::new(1000.0, scene.solver().dt_s)
            .map_err(|e| e.to_string())?
            .every;
        let first_jump_s = match sim.run(duration_s, every, &mut (), None) {
            Ok(_) => None,
            Err(SimError::ToothJump(jump)) => Some(jump.t_s),
            Err(e) => return Err(e.to_string()),
        };
        Ok(Outcome {
            first_jump_s,
            first_tip_ride_s: if args.jumps_only {
                None
            } else {
                sim.jumps.rides().first().map(|r| r.t_s)
            },
        })
    };
    let print_each = !args.json;
    let margin = jump_margin::search(range, run, |p: &Probe| {
        if print_each {
            eprintln!("{} = {}: {}", args.path, short(p.value), outcome(p));
        }
    })?;
    if args.json {
        let out = serde_json::json!({
            "path": args.path,
            "duration_s": duration_s,
            "elongation_pct": 100.0 * base.chain().elongation,
            "margin": margin,
        });
        println!("{}", serde_json::to_string_pretty(&out)?);
        return Ok(ExitCode::SUCCESS);
    }
    for p in &margin.probes {
        println!("{:>14} {}", short(p.value), outcome(p));
    }
    let (side, bound) = if margin.low_end_jumps {
        ("least", "at or above")
    } else {
        ("largest", "at or below")
    };
    let (without, failed) = if args.jumps_only {
        ("a tooth jump", "jumped")
    } else {
        ("a tooth jump or a tip ride", "jumped or rode")
    };
    println!(
        "{side} {} without {without} over {duration_s} s: between {} ({failed}) and {} (clean); every value tried {bound} {} ran clean",
        args.path,
        short(margin.jumping),
        short(margin.clean),
        short(margin.clean)
    );
    if !margin.monotone {
        println!(
            "note: a value on the jumping side ran clean too: the outcome is not monotone in {}",
            args.path
        );
    }
    Ok(ExitCode::SUCCESS)
}

fn outcome(p: &Probe) -> String {
    let Outcome {
        first_jump_s,
        first_tip_ride_s,
    } = p.outcome;
    let ride = first_tip_ride_s.map(|t| format!("rode a tip at t = {t:.4} s"));
    let jump = first_jump_s.map(|t| format!("jumped at t = {t:.4} s"));
    match (ride, jump) {
        (Some(r), Some(j)) => format!("{r}, {j}"),
        (Some(one), None) | (None, Some(one)) => one,
        (None, None) => "clean".to_owned(),
    }
}

/// A value tried, to 6 significant digits (the search's values are fractions
/// of the range).
fn short(value: f64) -> String {
    format!("{}", format!("{value:.5e}").parse::<f64>().unwrap_or(value))
}
