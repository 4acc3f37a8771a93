//! `chaindrive analyze`: the paper-reproduction analysis for any recorded run.
//!
//! The library reads the recording (`crate::record::read`) and measures
//! it (`crate::analysis::recorded`); this command writes the results:
//! `DIR/report.md` ([`report`]), `DIR/analysis.json` and the figures
//! ([`figures`]).

mod figures;
mod report;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use crate::analysis::recorded::{AnalyzeOptions, RecordedAnalysis, RecordedRun};

use figures::{FigureList, recorded_figures};
use report::report_markdown;

/// Arguments of `chaindrive analyze`.
#[derive(clap::Args)]
pub(super) struct AnalyzeArgs {
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
pub(super) struct Window([f64; 2]);

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

pub(super) fn analyze(args: AnalyzeArgs) -> anyhow::Result<ExitCode> {
    let options = AnalyzeOptions {
        link: args.link,
        roller: args.roller,
        segment: args.segment,
        window_s: args.window.map(|w| w.0),
    };
    // A recording whose run was killed outright streams up to its last
    // chunk but has no index: analyse it, and say how to make it whole.
    let unfinished = unfinished_mcap(&args.recording).then(|| {
        format!(
            "{} has no summary or index (the run was killed before it finished?): viewers will not open it; `chaindrive recover {} FIXED.mcap` writes a complete copy",
            args.recording.display(),
            args.recording.display()
        )
    });
    let (analysis, written) = match write_analysis(&args.recording, &options, &args.out) {
        Ok(done) => done,
        Err(e) => match &unfinished {
            Some(hint) => anyhow::bail!("{e:#}\n{hint}"),
            None => return Err(e),
        },
    };
    if let Some(hint) = &unfinished {
        eprintln!("warning: {hint}");
    }
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

/// Whether `path` starts like an MCAP file but lacks its summary and footer.
fn unfinished_mcap(path: &Path) -> bool {
    use std::io::Read;
    let mut head = [0_u8; 8];
    let starts_like_mcap = std::fs::File::open(path)
        .and_then(|mut f| f.read_exact(&mut head))
        .is_ok()
        && head == *b"\x89MCAP0\r\n";
    starts_like_mcap && matches!(crate::record::read::is_complete_mcap_file(path), Ok(false))
}

/// A file that could not be written.
#[derive(Debug, thiserror::Error)]
#[error("cannot write {path}: {source}")]
struct WriteError {
    path: String,
    source: std::io::Error,
}

/// What [`write_analysis`] wrote.
#[derive(Clone, Debug, PartialEq)]
struct Written {
    /// `DIR/report.md`.
    report: PathBuf,
    /// `DIR/analysis.json`.
    json: PathBuf,
    /// Figures: (stem, caption); each as PNG and SVG.
    figures: Vec<(String, String)>,
}

/// Reads the recording at `path`, checks `options`, measures, and writes
/// `dir/report.md`, `dir/analysis.json` and the figures. Nothing is written
/// (not even `dir`) before the recording and the options have passed every
/// check. Everything is drawn and written aside first (a hidden directory in
/// `dir`, removed afterwards) and moved into `dir` only once all of it has
/// been: a failed analysis leaves the outputs of an earlier one as they were.
fn write_analysis(
    path: &Path,
    options: &AnalyzeOptions,
    dir: &Path,
) -> anyhow::Result<(RecordedAnalysis, Written)> {
    let run = RecordedRun::read(path)?;
    let analysis = run.analyze(options)?;
    std::fs::create_dir_all(dir).map_err(write_err(dir))?;
    let staging = dir.join(format!(".analysis-{}.tmp", std::process::id()));
    std::fs::create_dir_all(&staging).map_err(write_err(&staging))?;
    let result = stage(&run, &analysis, options, &staging, dir)
        .and_then(|(figures, names)| commit(&staging, dir, &names).map(|()| figures));
    // Whatever happened, nothing staged stays behind (moved files are gone from it).
    let _ = std::fs::remove_dir_all(&staging);
    let figures = result?;
    Ok((
        analysis,
        Written {
            report: dir.join("report.md"),
            json: dir.join("analysis.json"),
            figures,
        },
    ))
}

/// The error of a failed write to `p`.
fn write_err(p: &Path) -> impl FnOnce(std::io::Error) -> WriteError {
    let path = p.display().to_string();
    move |source| WriteError { path, source }
}

/// Draws the figures and writes the JSON and the report into `staging`;
/// returns the figures and the names of the files written. Errors name the
/// files' places in `dir`.
fn stage(
    run: &RecordedRun,
    analysis: &RecordedAnalysis,
    options: &AnalyzeOptions,
    staging: &Path,
    dir: &Path,
) -> anyhow::Result<(FigureList, Vec<std::ffi::OsString>)> {
    let (figures, paths) = recorded_figures(run, analysis, options, staging)?;
    let text = serde_json::to_string_pretty(analysis).map_err(|e| WriteError {
        path: dir.join("analysis.json").display().to_string(),
        source: std::io::Error::other(e),
    })?;
    std::fs::write(staging.join("analysis.json"), text + "\n")
        .map_err(write_err(&dir.join("analysis.json")))?;
    std::fs::write(
        staging.join("report.md"),
        report_markdown(analysis, &figures),
    )
    .map_err(write_err(&dir.join("report.md")))?;
    let mut names: Vec<std::ffi::OsString> = paths
        .iter()
        .filter_map(|p| p.file_name())
        .map(Into::into)
        .collect();
    names.extend(["analysis.json".into(), "report.md".into()]);
    Ok((figures, names))
}

/// Moves the files `names` from `staging` into `dir`, replacing earlier
/// ones. A directory where a file goes is refused before anything moves.
fn commit(staging: &Path, dir: &Path, names: &[std::ffi::OsString]) -> anyhow::Result<()> {
    for name in names {
        let target = dir.join(name);
        if target.symlink_metadata().is_ok_and(|m| m.is_dir()) {
            return Err(
                write_err(&target)(std::io::Error::other("a directory is in the way")).into(),
            );
        }
    }
    for name in names {
        let target = dir.join(name);
        std::fs::rename(staging.join(name), &target).map_err(write_err(&target))?;
    }
    Ok(())
}
