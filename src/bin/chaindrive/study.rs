//! `chaindrive study`: a design study from a plan (factors × levels of a
//! scene), run here in parallel or on a Slurm cluster as a job array, and
//! merged into one table.
//!
//! - `study PLAN --out DIR [--jobs N] [--retry-failed]`: runs the cases
//!   here; finished cases are skipped, so the same command resumes.
//! - `study slurm PLAN --out DIR [...] [--submit]`: writes `DIR/study.sbatch`
//!   whose array task k runs `chaindrive study run-case DIR k`.
//! - `study run-case DIR K`: one case (what each array task runs).
//! - `study collect DIR`: `results.parquet`, `results.csv`, main-effects figures.
//!
//! The study itself lives in `chaindrive::studies::study`.

use std::fmt::Write as _;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicUsize, Ordering};

use anyhow::Context;
use chaindrive::studies::study::cases::CHECKPOINT_FILE;
use chaindrive::studies::study::{CaseOutcome, CaseStatus, RowStatus, Study, StudyDir, Table};

/// Arguments of `chaindrive study`.
#[derive(clap::Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct StudyArgs {
    #[command(subcommand)]
    command: Option<StudyCommand>,
    #[command(flatten)]
    run: RunArgs,
}

/// `study PLAN --out DIR`.
#[derive(clap::Args)]
struct RunArgs {
    /// The plan (TOML).
    #[arg(required = true)]
    plan: Option<PathBuf>,
    /// The study's directory (created; an existing one with the same plan resumes).
    #[arg(long, required = true)]
    out: Option<PathBuf>,
    /// Cases run at once.
    #[arg(long, default_value_t = 1)]
    jobs: usize,
    /// Run the failed cases again.
    #[arg(long)]
    retry_failed: bool,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
}

#[derive(clap::Subcommand)]
enum StudyCommand {
    /// Write a Slurm job-array script for the study (and submit it with --submit).
    Slurm(SlurmArgs),
    /// Run one case of a study prepared in DIR (an array task's work).
    RunCase {
        /// The study's directory.
        dir: PathBuf,
        /// The case, from 0.
        k: usize,
        /// Run it again if it failed.
        #[arg(long)]
        retry_failed: bool,
    },
    /// Merge the cases into results.parquet, results.csv and main-effects figures.
    Collect {
        /// The study's directory.
        dir: PathBuf,
    },
}

/// `study slurm`.
#[derive(clap::Args)]
struct SlurmArgs {
    /// The plan (TOML).
    plan: PathBuf,
    /// The study's directory, on a file system every node sees.
    #[arg(long)]
    out: PathBuf,
    /// Slurm partition.
    #[arg(long)]
    partition: Option<String>,
    /// Time limit of one task (Slurm's format, e.g. 00:10:00).
    #[arg(long)]
    time: Option<String>,
    /// CPUs per task.
    #[arg(long, default_value_t = 1)]
    cpus_per_task: u32,
    /// Most tasks running at once (`--array=…%K`).
    #[arg(long)]
    array_limit: Option<u32>,
    /// Submit the script with sbatch and print the job id.
    #[arg(long)]
    submit: bool,
}

/// Runs `chaindrive study`.
pub fn study(args: StudyArgs) -> anyhow::Result<ExitCode> {
    match args.command {
        Some(StudyCommand::Slurm(a)) => slurm(&a),
        Some(StudyCommand::RunCase {
            dir,
            k,
            retry_failed,
        }) => run_case(&dir, k, retry_failed),
        Some(StudyCommand::Collect { dir }) => collect(&dir),
        None => {
            let (Some(plan), Some(out)) = (args.run.plan.as_deref(), args.run.out.as_deref())
            else {
                anyhow::bail!("usage: chaindrive study PLAN --out DIR");
            };
            run_here(plan, out, &args.run)
        }
    }
}

/// Reads and checks the plan and puts it into `out`.
fn prepare(plan: &Path, out: &Path) -> anyhow::Result<StudyDir> {
    let study =
        Study::from_plan_path(plan).map_err(|e| anyhow::anyhow!("{}: {e}", plan.display()))?;
    Ok(StudyDir::prepare(out, study)?)
}

fn run_here(plan: &Path, out: &Path, args: &RunArgs) -> anyhow::Result<ExitCode> {
    let dir = prepare(plan, out)?;
    let total = dir.study.cases.len();
    let pending = dir.pending(args.retry_failed)?;
    let before = total - pending.len();
    let failed_before = (0..total)
        .filter_map(|k| dir.status(k).ok().flatten())
        .filter(|s| !s.ok && !args.retry_failed)
        .count();
    eprintln!(
        "study: {total} cases, {before} finished before ({failed_before} failed), {} to run on {} jobs",
        pending.len(),
        args.jobs.max(1)
    );
    let stop = crate::stop_on_ctrl_c();
    let ran = AtomicUsize::new(0);
    let failed = AtomicUsize::new(0);
    let left = pending.len();
    let bar = (!args.quiet && std::io::stderr().is_terminal()).then(|| {
        let b = indicatif::ProgressBar::new(left as u64);
        b.set_style(
            indicatif::ProgressStyle::with_template("{bar:40} {msg}, eta {eta}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b.set_message(format!("done 0, failed 0, left {left}"));
        b
    });
    let on_done = |outcome: &CaseOutcome| {
        let CaseOutcome::Ran(status) = outcome else {
            return;
        };
        let done = ran.fetch_add(1, Ordering::Relaxed) + 1;
        if !status.ok {
            failed.fetch_add(1, Ordering::Relaxed);
        }
        let f = failed.load(Ordering::Relaxed);
        let resumed = status
            .resumed_from_s
            .map(|t| format!(", resumed at t = {t} s"))
            .unwrap_or_default();
        let line = format!("done {done}, failed {f}, left {}{resumed}", left - done);
        match &bar {
            Some(b) => {
                b.set_message(line);
                b.inc(1);
            }
            None if !args.quiet => eprintln!(
                "case {} {} in {:.1} s ({line})",
                status.case,
                ended(status),
                status.wall_s
            ),
            None => {}
        }
    };
    dir.run_all(args.jobs, args.retry_failed, Some(&stop), &on_done)?;
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    let still = dir.pending(false)?.len();
    let (ran, failed) = (ran.into_inner(), failed.into_inner());
    eprintln!(
        "study: ran {ran} cases now ({failed} failed), {} finished, {still} left",
        total - still
    );
    if stop.load(Ordering::Relaxed) {
        eprintln!(
            "study: interrupted; the same command resumes{}",
            if dir.study.checkpoint_every_s.is_some() {
                " (the cases stopped resume from their checkpoints)"
            } else {
                ""
            }
        );
        return Ok(ExitCode::from(130));
    }
    eprintln!("next: chaindrive study collect {}", out.display());
    Ok(if failed > 0 {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}

fn run_case(dir: &Path, k: usize, retry_failed: bool) -> anyhow::Result<ExitCode> {
    let study = StudyDir::open(dir)?;
    let stop = crate::stop_on_ctrl_c();
    let checkpoint = study.case_dir(k).join(CHECKPOINT_FILE);
    if study.status(k)?.is_none() && checkpoint.exists() {
        eprintln!("case {k}: resuming from {}", checkpoint.display());
    }
    let outcome = study.run_case(k, retry_failed, Some(&stop))?;
    if let CaseOutcome::Ran(s) = &outcome {
        if let Some(t) = s.resumed_from_s {
            eprintln!("case {k}: resumed at t = {t} s");
        }
        if let Some(why) = &s.checkpoint_discarded {
            eprintln!("case {k}: its checkpoint was not taken up, it started over: {why}");
        }
    }
    match outcome {
        CaseOutcome::Skipped(s) => {
            eprintln!("case {k}: finished before ({})", ended(&s));
            Ok(ExitCode::SUCCESS)
        }
        CaseOutcome::Ran(s) if s.ok => {
            eprintln!(
                "case {k} {} in {:.1} s ({})",
                ended(&s),
                s.wall_s,
                s.factors
            );
            for w in &s.warnings {
                eprintln!("case {k}: warning: {w}");
            }
            Ok(ExitCode::SUCCESS)
        }
        CaseOutcome::Ran(s) => {
            eprintln!(
                "case {k} failed ({}): {}",
                s.factors,
                s.error.as_deref().unwrap_or("")
            );
            Ok(ExitCode::FAILURE)
        }
        CaseOutcome::Interrupted if study.study.checkpoint_every_s.is_some() => {
            eprintln!(
                "case {k}: interrupted; it resumes from {} when resubmitted",
                checkpoint.display()
            );
            Ok(ExitCode::from(130))
        }
        CaseOutcome::Interrupted => {
            eprintln!("case {k}: interrupted, nothing written; it runs again when resubmitted");
            Ok(ExitCode::from(130))
        }
    }
}

/// How a case ended: `ok`, `ok with N warnings` or `failed`.
fn ended(s: &CaseStatus) -> String {
    match (s.ok, s.warnings.len()) {
        (false, _) => "failed".to_owned(),
        (true, 0) => "ok".to_owned(),
        (true, 1) => "ok with 1 warning".to_owned(),
        (true, n) => format!("ok with {n} warnings"),
    }
}

/// `0-3,5,7-9` from sorted case numbers.
fn ranges(ks: &[usize]) -> String {
    let mut out = String::new();
    let mut i = 0;
    while i < ks.len() {
        let mut j = i;
        while j + 1 < ks.len() && ks[j + 1] == ks[j] + 1 {
            j += 1;
        }
        if !out.is_empty() {
            out.push(',');
        }
        let _ = if j > i {
            write!(out, "{}-{}", ks[i], ks[j])
        } else {
            write!(out, "{}", ks[i])
        };
        i = j + 1;
    }
    out
}

/// The sbatch script: an array over the cases not finished yet.
fn sbatch_script(exe: &Path, dir: &Path, pending: &[usize], a: &SlurmArgs) -> String {
    let mut s = String::from("#!/bin/bash\n");
    let _ = writeln!(s, "#SBATCH --job-name=chaindrive-study");
    let limit = a.array_limit.map(|k| format!("%{k}")).unwrap_or_default();
    let _ = writeln!(s, "#SBATCH --array={}{limit}", ranges(pending));
    let _ = writeln!(s, "#SBATCH --cpus-per-task={}", a.cpus_per_task);
    if let Some(p) = &a.partition {
        let _ = writeln!(s, "#SBATCH --partition={p}");
    }
    if let Some(t) = &a.time {
        let _ = writeln!(s, "#SBATCH --time={t}");
    }
    let _ = writeln!(s, "#SBATCH --output={}/slurm/%A_%a.out", dir.display());
    let _ = writeln!(
        s,
        "# Each task runs one case; finished cases are skipped, so resubmitting\n# this script after a failure finishes the rest. With the plan's\n# checkpoint_every_s, a case that was stopped (preempted, requeued, killed)\n# resumes from DIR/cases/<k>/checkpoint.ckpt."
    );
    let _ = writeln!(
        s,
        "exec '{}' study run-case '{}' \"$SLURM_ARRAY_TASK_ID\"",
        exe.display(),
        dir.display()
    );
    s
}

fn slurm(a: &SlurmArgs) -> anyhow::Result<ExitCode> {
    std::fs::create_dir_all(&a.out)
        .with_context(|| format!("cannot create {}", a.out.display()))?;
    let out = a
        .out
        .canonicalize()
        .with_context(|| format!("cannot resolve {}", a.out.display()))?;
    let dir = prepare(&a.plan, &out)?;
    let pending = dir.pending(false)?;
    if pending.is_empty() {
        eprintln!(
            "study: all {} cases finished; next: chaindrive study collect {}",
            dir.study.cases.len(),
            out.display()
        );
        return Ok(ExitCode::SUCCESS);
    }
    std::fs::create_dir_all(out.join("slurm")).context("cannot create the log directory")?;
    let exe = std::env::current_exe().context("cannot find the chaindrive executable")?;
    let script = out.join("study.sbatch");
    std::fs::write(&script, sbatch_script(&exe, &out, &pending, a))
        .with_context(|| format!("cannot write {}", script.display()))?;
    eprintln!(
        "wrote {} ({} of {} cases)",
        script.display(),
        pending.len(),
        dir.study.cases.len()
    );
    if a.submit {
        let output = std::process::Command::new("sbatch")
            .arg("--parsable")
            .arg(&script)
            .output()
            .context("cannot run sbatch (is Slurm installed and on PATH?)")?;
        anyhow::ensure!(
            output.status.success(),
            "sbatch failed: {}",
            String::from_utf8_lossy(&output.stderr).trim()
        );
        let id = String::from_utf8_lossy(&output.stdout);
        let id = id.trim().split(';').next().unwrap_or_default();
        println!("{id}");
    }
    Ok(ExitCode::SUCCESS)
}

fn collect(dir: &Path) -> anyhow::Result<ExitCode> {
    let study = StudyDir::open(dir)?;
    let table = Table::collect(&study)?;
    let csv = dir.join("results.csv");
    std::fs::write(&csv, table.to_csv()?)
        .with_context(|| format!("cannot write {}", csv.display()))?;
    let parquet = dir.join("results.parquet");
    table.write_parquet(&parquet)?;
    let figures = table.main_effects_figures(&dir.join("main_effects"))?;
    let statuses = table.statuses();
    let counts: Vec<String> = [
        RowStatus::Ok,
        RowStatus::Warned,
        RowStatus::Failed,
        RowStatus::Missing,
    ]
    .iter()
    .map(|s| {
        let n = statuses.iter().filter(|&&x| x == Some(s.name())).count();
        format!("{n} {}", s.name())
    })
    .collect();
    eprintln!(
        "{} rows ({}) x {} columns: {}, {}; {figures} main-effects figures in {}",
        table.rows(),
        counts.join(", "),
        table.columns.len(),
        parquet.display(),
        csv.display(),
        dir.join("main_effects").display()
    );
    let warned: Vec<String> = statuses
        .iter()
        .enumerate()
        .filter(|(_, s)| **s == Some(RowStatus::Warned.name()))
        .map(|(k, _)| k.to_string())
        .collect();
    if !warned.is_empty() {
        eprintln!(
            "warned: case {} (their numbers are in doubt: see the columns warnings and segments.<k>.stationary)",
            warned.join(", ")
        );
    }
    Ok(ExitCode::SUCCESS)
}

#[cfg(test)]
mod tests {
    use super::ranges;

    #[test]
    fn array_ranges() {
        assert_eq!(ranges(&[0, 1, 2, 3, 5, 7, 8]), "0-3,5,7-8");
        assert_eq!(ranges(&[4]), "4");
    }
}
