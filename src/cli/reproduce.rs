//! `chaindrive reproduce`: the paper's study (five runs of the L60MC drive),
//! its report, summaries and figures.

use std::path::PathBuf;
use std::process::ExitCode;

use crate::analysis::figures::{FigureChoice, paper_figures};
use crate::studies::reproduce::{
    Findings, StudySettings, report_markdown, run_paper_study, summaries_json,
};
use anyhow::Context;

/// Arguments of `chaindrive reproduce`.
#[derive(clap::Args)]
pub(super) struct ReproduceArgs {
    /// Output directory (created if missing).
    #[arg(long, default_value = "reproduce")]
    out: PathBuf,
    /// Simulated time of each run, s (the paper's: 10).
    #[arg(long, default_value_t = 10.0)]
    duration: f64,
    /// Sample rate, Hz.
    #[arg(long, default_value_t = 1000.0)]
    rate: f64,
    /// Link whose force Fig. 16 shows (0-based).
    #[arg(long, default_value_t = 0)]
    link: usize,
    /// Roller whose contact force Fig. 22 shows (0-based).
    #[arg(long, default_value_t = 0)]
    roller: usize,
    /// Run the five runs one after the other instead of in parallel threads.
    #[arg(long)]
    sequential: bool,
}

pub(super) fn reproduce(args: ReproduceArgs) -> anyhow::Result<ExitCode> {
    anyhow::ensure!(
        args.duration > 0.0 && args.duration.is_finite(),
        "--duration must be a positive number of seconds, got {}",
        args.duration
    );
    // The paper's drive: reject a bad rate or index before minutes of simulation.
    let paper = crate::scene::Scene::l60mc();
    crate::sim::SampleRate::new(args.rate, paper.solver().dt_s)
        .map_err(|e| anyhow::anyhow!("--rate {}: {e}", args.rate))?;
    let rollers = paper.chain().rollers;
    anyhow::ensure!(
        args.link < rollers,
        "unknown link {}: the chain has links 0 to {}",
        args.link,
        rollers - 1
    );
    anyhow::ensure!(
        args.roller < rollers,
        "unknown roller {}: the chain has rollers 0 to {}",
        args.roller,
        rollers - 1
    );
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    eprintln!(
        "running the paper's drive five times ({} s each: circular, real, real with the circular rest length, circular and real with joint friction){}",
        args.duration,
        if args.sequential { "" } else { " in parallel" }
    );
    let study = run_paper_study(&StudySettings {
        duration_s: args.duration,
        rate_hz: args.rate,
        parallel: !args.sequential,
    })?;
    eprintln!("runs done in {:.1} s; measuring and drawing", study.wall_s);
    let findings = Findings::measure(&study)?;
    let runs: Vec<_> = study.runs.iter().collect();
    let figures = paper_figures(
        &runs,
        FigureChoice {
            link: args.link,
            roller: args.roller,
        },
        &args.out,
    )?;
    let summary_path = args.out.join("summary.json");
    std::fs::write(
        &summary_path,
        serde_json::to_string_pretty(&summaries_json(&study))?,
    )
    .with_context(|| format!("cannot write {}", summary_path.display()))?;
    let report_path = args.out.join("report.md");
    std::fs::write(&report_path, report_markdown(&study, &findings, &figures))
        .with_context(|| format!("cannot write {}", report_path.display()))?;
    println!(
        "wrote {}, {} and {} figures (PNG + SVG) in {}",
        report_path.display(),
        summary_path.display(),
        figures.len(),
        args.out.display()
    );
    Ok(ExitCode::SUCCESS)
}
