//! `chaindrive analyze`: the paper-reproduction analysis for any recorded run.

use std::path::PathBuf;
use std::process::ExitCode;

use chaindrive::analysis::recorded::{AnalyzeOptions, write_analysis};

/// Arguments of `chaindrive analyze`.
#[derive(clap::Args)]
pub struct AnalyzeArgs {
    /// Recording written by `chaindrive run --record` (needs /segments and
    /// /sprockets; /links, /contacts and /rollers for the link and contact analyses).
    recording: PathBuf,
    /// Output directory (created if missing): report.md, analysis.json, figures.
    #[arg(long, default_value = "analysis")]
    out: PathBuf,
    /// Link whose force is shown (0-based; default 0 when /links was recorded).
    #[arg(long)]
    link: Option<usize>,
    /// Roller whose contact force is shown (0-based; default 0 when /contacts was recorded).
    #[arg(long)]
    roller: Option<usize>,
    /// Draw only this segment's figures (1-based; default every segment).
    #[arg(long)]
    segment: Option<usize>,
    /// One window for every statistic, spectrum and figure, s (default: the run summary's windows).
    #[arg(long, value_name = "T0,T1", value_parser = parse_window)]
    window: Option<Window>,
}

/// `T0,T1` in seconds.
#[derive(Clone, Copy, Debug)]
pub struct Window([f64; 2]);

fn parse_window(s: &str) -> Result<Window, String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let [a, b] = parts.as_slice() else {
        return Err(format!("expected T0,T1 (two times in s), got {s:?}"));
    };
    let parse = |v: &str| {
        v.parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("{v:?} is not a finite time in s"))
    };
    let (t0, t1) = (parse(a)?, parse(b)?);
    if !(t0 < t1) {
        return Err(format!(
            "the window's start {t0} must be before its end {t1}"
        ));
    }
    Ok(Window([t0, t1]))
}

pub fn analyze(args: AnalyzeArgs) -> anyhow::Result<ExitCode> {
    let options = AnalyzeOptions {
        link: args.link,
        roller: args.roller,
        segment: args.segment,
        window_s: args.window.map(|w| w.0),
    };
    let (analysis, written) = write_analysis(&args.recording, &options, &args.out)?;
    for note in &analysis.notes {
        eprintln!("note: {note}");
    }
    println!(
        "analysed {} ({} samples, {} segments, {} sprockets): wrote {}, {} and {} figures (PNG + SVG) in {}",
        args.recording.display(),
        analysis.samples,
        analysis.segments.len(),
        analysis.sprockets.len(),
        written.report.display(),
        written.json.display(),
        written.figures.len(),
        args.out.display()
    );
    Ok(ExitCode::SUCCESS)
}
