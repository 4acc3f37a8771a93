//! `chaindrive life SCENE --out DIR`: the chain's life over a duty cycle
//! (`crate::studies::duty`): each `[[duty]]` point (in the scene, or
//! `--duty FILE`) runs as a case of a study in DIR, in parallel and
//! resumably, and the finished points are combined by hours. Writes
//! `DIR/life.csv` (one row per point), `DIR/life.json` (the whole report)
//! and `DIR/damage.png` (each point's share of the damage and its fatigue
//! safety factor).
//!
//! With `--prepare-only` it writes the study and stops: run it as a Slurm
//! job array (`chaindrive study slurm DIR/plan.toml --out DIR --submit`),
//! then the same `life` command combines what the tasks wrote.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use crate::analysis::figures::{BarPanel, Bars, save_bars, value_label};
use crate::scene::{DutyFile, DutyPointFile};
use crate::studies::duty::{DutyCycle, DutyLife, LifeSettings, combine};
use crate::studies::study::CaseOutcome;
use anyhow::Context;

/// Arguments of `chaindrive life`.
#[derive(clap::Args)]
pub struct LifeArgs {
    /// Scene file (TOML) with the drive and, unless `--duty`, its `[[duty]]` points.
    scene: PathBuf,
    /// A file of `[[duty]]` points (instead of the scene's).
    #[arg(long, value_name = "FILE")]
    duty: Option<PathBuf>,
    /// The duty cycle's directory (created; an existing one with the same points resumes).
    #[arg(long)]
    out: PathBuf,
    /// Points run at once.
    #[arg(long, default_value_t = 1)]
    jobs: usize,
    /// Simulated time of each point, s (default: the scene's).
    #[arg(long)]
    duration: Option<f64>,
    /// Statistics window of each point, s (default: the last second after the ramps).
    #[arg(long)]
    window: Option<f64>,
    /// Simulated seconds between a point's checkpoints (a stopped point resumes from its last).
    #[arg(long, value_name = "S")]
    checkpoint_every: Option<f64>,
    /// Run the failed points again.
    #[arg(long)]
    retry_failed: bool,
    /// Write the study and stop (to run it as a Slurm job array).
    #[arg(long)]
    prepare_only: bool,
    /// Print the report as one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// The duty points: `--duty FILE`'s, else the scene's.
fn points(args: &LifeArgs, scene_toml: &str) -> anyhow::Result<Vec<DutyPointFile>> {
    if let Some(path) = &args.duty {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read {}", path.display()))?;
        let file: DutyFile = toml::from_str(&text)
            .map_err(|e| anyhow::anyhow!("{}: {}", path.display(), e.message()))?;
        return Ok(file.duty);
    }
    let file: crate::scene::SceneFile = toml::from_str(scene_toml)
        .map_err(|e| anyhow::anyhow!("{}: {}", args.scene.display(), e.message()))?;
    anyhow::ensure!(
        !file.duty.is_empty(),
        "{}: no [[duty]] points; give them in the scene or in a file (--duty FILE), e.g.\n[[duty]]\nhours = 800.0\nset = {{ \"sprockets.0.speed_rpm\" = 3000.0 }}",
        args.scene.display()
    );
    Ok(file.duty)
}

pub fn life(args: LifeArgs) -> anyhow::Result<ExitCode> {
    for (flag, v) in [
        ("--duration", args.duration),
        ("--window", args.window),
        ("--checkpoint-every", args.checkpoint_every),
    ] {
        if let Some(v) = v {
            crate::cli::ensure_positive(flag, v)?;
        }
    }
    // The scene itself first, its errors with its file name.
    if crate::cli::load_scene_or_report(Some(&args.scene), &Default::default())?.is_none() {
        return Ok(ExitCode::FAILURE);
    }
    let scene_toml = std::fs::read_to_string(&args.scene)
        .with_context(|| format!("cannot read {}", args.scene.display()))?;
    let points = points(&args, &scene_toml)?;
    let cycle = DutyCycle::new(&points, &scene_toml)?;
    let settings = LifeSettings {
        duration_s: args.duration,
        window_s: args.window,
        checkpoint_every_s: args.checkpoint_every,
    };
    let dir = cycle.prepare(&args.out, &scene_toml, settings)?;
    if args.prepare_only {
        eprintln!(
            "life: {} points written to {}; run them with `chaindrive study slurm {} --out {} --submit`, then this command again (without --prepare-only) to combine",
            cycle.points.len(),
            args.out.display(),
            args.out.join("plan.toml").display(),
            args.out.display()
        );
        return Ok(ExitCode::SUCCESS);
    }
    let pending = dir.pending(args.retry_failed)?;
    eprintln!(
        "life: {} points, {} to run on {} jobs",
        cycle.points.len(),
        pending.len(),
        args.jobs.max(1)
    );
    let stop = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&stop);
    let _ = ctrlc::set_handler(move || flag.store(true, Ordering::Relaxed));
    let names: Vec<&str> = cycle.points.iter().map(|p| p.name.as_str()).collect();
    let on_done = |outcome: &CaseOutcome| {
        if let CaseOutcome::Ran(s) = outcome {
            let name = names.get(s.case).copied().unwrap_or("?");
            match &s.error {
                None => eprintln!("point \"{name}\" finished in {:.1} s", s.wall_s),
                Some(e) => eprintln!("point \"{name}\" failed: {e}"),
            }
        }
    };
    dir.run_all(args.jobs, args.retry_failed, Some(&stop), &on_done)?;
    if stop.load(Ordering::Relaxed) {
        eprintln!("life: interrupted; the same command resumes");
        return Ok(ExitCode::from(130));
    }
    let report = combine(&cycle, &dir)?;
    write_outputs(&report, &args.out)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print_report(&report, &args.out);
    }
    Ok(if report.life_h.is_some() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

fn opt(v: Option<f64>, f: impl Fn(f64) -> String) -> String {
    v.map_or_else(|| "-".to_owned(), f)
}

fn print_report(r: &DutyLife, out: &Path) {
    let unit = if r.by_fraction { "fraction" } else { "hours" };
    println!(
        "{:<16} {:>10} {:>7} {:>10} {:>7} {:>9} {:>10} {:>12} {:>14} {:>8}  status",
        "point",
        unit,
        "time",
        "power_kW",
        "margin",
        "static_SF",
        "fatigue_SF",
        "damage_per_h",
        "life_alone_h",
        "damage"
    );
    for p in &r.points {
        println!(
            "{:<16} {:>10} {:>6.1}% {:>10} {:>7} {:>9} {:>10} {:>12} {:>14} {:>8}  {}",
            p.name,
            format!("{}", p.hours),
            100.0 * p.time_share,
            opt(p.driver_power_w, |w| format!("{:.2}", w * 1e-3)),
            opt(p.rating_margin, |m| format!("{m:.2}")),
            opt(p.static_safety_factor, |f| format!("{f:.2}")),
            opt(p.fatigue_safety_factor, |f| format!("{f:.2}")),
            opt(p.damage_per_hour, |d| format!("{d:.3e}")),
            p.fatigue_life_h
                .map_or_else(|| "-".to_owned(), |l| l.to_string()),
            opt(p.damage_share, |s| value_label(100.0 * s, 1, "%")),
            p.status
        );
    }
    for l in &r.limits {
        println!(
            "{} life: {} ({}: {:.3e} per hour of the cycle against a limit of {}){}",
            l.check,
            l.life_h,
            l.quantity,
            l.rate_per_hour,
            l.limit,
            l.dominated_by
                .as_ref()
                .map(|d| format!(", dominated by \"{d}\""))
                .unwrap_or_default()
        );
    }
    match (&r.life_h, &r.governed_by) {
        (Some(life), Some(check)) => println!("life: {life}, governed by {check}"),
        _ => println!("life: unknown"),
    }
    for n in &r.notes {
        println!("note: {n}");
    }
    println!(
        "wrote {0}/life.csv, {0}/life.json, {0}/damage.png",
        out.display()
    );
}

fn write_outputs(r: &DutyLife, out: &Path) -> anyhow::Result<()> {
    std::fs::write(out.join("life.json"), serde_json::to_string_pretty(r)?)?;
    let mut w = csv::Writer::from_path(out.join("life.csv"))?;
    w.write_record([
        "point",
        if r.by_fraction { "fraction" } else { "hours" },
        "time_share",
        "set",
        "status",
        "driver_power_w",
        "rating_margin",
        "static_safety_factor",
        "fatigue_safety_factor",
        "damage_per_hour",
        "fatigue_life_h",
        "damage_share",
        "elongation_pct_per_1000h",
        "wear_life_h",
    ])?;
    let num = |v: Option<f64>| v.map(|v| v.to_string()).unwrap_or_default();
    for p in &r.points {
        w.write_record([
            p.name.clone(),
            p.hours.to_string(),
            p.time_share.to_string(),
            p.set.clone(),
            p.status.clone(),
            num(p.driver_power_w),
            num(p.rating_margin),
            num(p.static_safety_factor),
            num(p.fatigue_safety_factor),
            num(p.damage_per_hour),
            // A number of hours (no unit: the column's name has it), or `infinite`.
            p.fatigue_life_h
                .map(|l| {
                    l.hours()
                        .map_or_else(|| "infinite".to_owned(), |h| h.to_string())
                })
                .unwrap_or_default(),
            num(p.damage_share),
            num(p.elongation_pct_per_1000h),
            p.wear_life_h
                .map(|l| {
                    l.hours()
                        .map_or_else(|| "infinite".to_owned(), |h| h.to_string())
                })
                .unwrap_or_default(),
        ])?;
    }
    w.flush()?;
    let life = r
        .life_h
        .map_or_else(|| "unknown".to_owned(), |l| l.to_string());
    let bars = Bars {
        title: format!("Fatigue damage per operating point; the cycle's life {life}"),
        // Each point with its share of the time: a point's share of the
        // damage is read against it.
        items: r
            .points
            .iter()
            .map(|p| {
                format!(
                    "{} ({} of the time)",
                    p.name,
                    value_label(100.0 * p.time_share, 0, " %")
                )
            })
            .collect(),
        panels: vec![
            BarPanel {
                y_label: "share of the cycle's damage (%)".to_owned(),
                values: r
                    .points
                    .iter()
                    .map(|p| p.damage_share.map(|s| 100.0 * s))
                    .collect(),
                decimals: 1,
                suffix: " %".to_owned(),
                reference: None,
                color: 1,
            },
            BarPanel {
                y_label: "fatigue limit / largest cycle (dashed: 1)".to_owned(),
                values: r.points.iter().map(|p| p.fatigue_safety_factor).collect(),
                decimals: 2,
                suffix: String::new(),
                reference: Some(1.0),
                color: 0,
            },
        ],
    };
    save_bars(&bars, out, "damage")?;
    Ok(())
}
