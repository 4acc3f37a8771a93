//! The `chaindrive` command-line tool (feature `cli`): one file per
//! subcommand, its argument parsing, progress bars, Ctrl-C and the files the
//! tool writes. It drives the library's stages and adds no physics of its
//! own; the binary is [`main`] and nothing else.

/// `eprintln!` for this tool: the line, newline included, goes to stderr in
/// one write (std's writes each piece of the format separately, so a line
/// can be split by whatever else writes to the same pipe or file: another
/// process, a progress bar). It shadows std's macro in every module of the
/// binary (they are declared below it); a failed write is ignored, as a
/// closed stderr leaves nowhere to report it.
macro_rules! eprintln {
    () => {
        $crate::cli::stderr_line(::std::format_args!(""))
    };
    ($($arg:tt)*) => {
        $crate::cli::stderr_line(::std::format_args!($($arg)*))
    };
}

mod analyze;
mod bench;
mod chains;
mod check;
mod convergence;
mod fit;
mod guide_intervals;
mod jump_margin;
mod life;
mod outputs;
mod profile;
mod rate;
mod recover;
mod reproduce;
mod run;
mod stress;
mod study;
mod sweep;
mod sweep_figures;
mod work_precision;

use clap::{Parser, Subcommand};

/// Dynamic simulation of roller-chain drives (Pedersen 2005) on rapier.
#[derive(Parser)]
#[command(name = "chaindrive", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene (default: the paper's four-sprocket drive) and report.
    Run(run::RunArgs),
    /// Long studies: soak (drift over a long run), work-precision (wall time
    /// against error per integrator), stress (stability matrix), fuzz
    /// (mutated scenes).
    Bench(bench::BenchArgs),
    /// Validate a scene without running it and print the derived layout.
    Check(check::CheckArgs),
    /// Move one sprocket until the chain fits its path exactly; print the
    /// position and write the fitted scene.
    Fit(fit::FitArgs),
    /// List the chains known by designation (ISO 606 B series, ANSI, ANSI heavy) with
    /// each value's source.
    Chains(chains::ChainsArgs),
    /// The chain's catalogue power rating at the scene's speeds (ANSI
    /// formulas), its lubrication, chain speed and the margin.
    Rate(rate::RateArgs),
    /// The chain's life over a duty cycle (`[[duty]]` points): each point run
    /// in parallel and resumably, fatigue damage combined by hours.
    Life(life::LifeArgs),
    /// Print a sprocket's tooth outline (CSV) or its dimension table.
    Profile(profile::ProfileArgs),
    /// Reproduce the paper's study: five runs (two with joint friction), report, summaries, figures.
    Reproduce(reproduce::ReproduceArgs),
    /// Sweep the driver's speed: one steady run per rpm in parallel; order
    /// spectra, Campbell diagram, envelopes, resonance crossings.
    Sweep(sweep::SweepArgs),
    /// Analyse a recording (`run --record`) of any scene: report, JSON, figures.
    Analyze(analyze::AnalyzeArgs),
    /// Rewrite a recording cut short (a killed run) as a complete, indexed
    /// MCAP file that every viewer opens.
    Recover(recover::RecoverArgs),
    /// A design study from a plan: run here (resumable), as a Slurm job array, collect.
    Study(study::StudyArgs),
    /// The least tensioner force (or pretension, or the largest elongation)
    /// at which a worn chain runs a given time without a tooth jump or a
    /// roller riding a tip: a bracketing search over runs in parallel.
    JumpMargin(jump_margin::JumpMarginArgs),
}

/// The `chaindrive` command: parses the process's arguments, runs the
/// subcommand and reports its error on stderr. A closed pipe on stdout
/// (`chaindrive profile --csv | head`) ends it with success.
pub fn main() -> std::process::ExitCode {
    let cli = Cli::parse();
    // `println!` panics where the reader closed stdout (`chaindrive run |
    // head`): that panic is the reader's choice too, so it says nothing
    // and ends the command as a closed pipe does below, after unwinding
    // (the files being written are flushed and closed on the way).
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if !closed_stdout(info.payload()) {
            default_hook(info);
        }
    }));
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| dispatch(cli))) {
        Ok(code) => code,
        Err(payload) if closed_stdout(payload.as_ref()) => std::process::ExitCode::SUCCESS,
        Err(payload) => std::panic::resume_unwind(payload),
    }
}

/// Whether a panic's payload is `println!`'s on a stdout whose reader has
/// gone (a broken pipe).
fn closed_stdout(payload: &(dyn std::any::Any + Send)) -> bool {
    let message = payload
        .downcast_ref::<String>()
        .map(String::as_str)
        .or_else(|| payload.downcast_ref::<&str>().copied())
        .unwrap_or("");
    message.starts_with("failed printing to stdout") && message.contains("Broken pipe")
}

/// Runs the command `cli` names.
fn dispatch(cli: Cli) -> std::process::ExitCode {
    let result = match cli.command {
        Command::Run(args) => run::run(args),
        Command::Bench(args) => bench::bench(args),
        Command::Check(args) => check::check(args),
        Command::Fit(args) => fit::fit(args),
        Command::Chains(args) => chains::chains(args),
        Command::Profile(args) => profile::profile(args),
        Command::Rate(args) => rate::rate(args),
        Command::Life(args) => life::life(args),
        Command::Reproduce(args) => reproduce::reproduce(args),
        Command::Analyze(args) => analyze::analyze(args),
        Command::Sweep(args) => sweep::sweep(args),
        Command::Recover(args) => recover::recover(args),
        Command::Study(args) => study::study(args),
        Command::JumpMargin(args) => jump_margin::jump_margin(args),
    };
    match result {
        Ok(code) => code,
        // A closed pipe (`chaindrive profile --csv | head`) is the reader's choice, not an error.
        Err(e)
            if e.downcast_ref::<std::io::Error>()
                .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe) =>
        {
            std::process::ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

/// Writes one line to stderr in a single write: [`eprintln!`]'s body.
pub(crate) fn stderr_line(args: std::fmt::Arguments<'_>) {
    let _ = write_line(&mut std::io::stderr().lock(), args);
}

/// `args` and a newline, formatted first and written with one `write_all`.
fn write_line(out: &mut impl std::io::Write, args: std::fmt::Arguments<'_>) -> std::io::Result<()> {
    let mut line = args.to_string();
    line.push('\n');
    out.write_all(line.as_bytes())
}

/// Loads a scene file (or the embedded paper drive) with the command line's
/// `overrides`, reporting every error prefixed with the file name, one per
/// line, or with the option for an overridden field.
pub(crate) fn load_scene(
    path: Option<&std::path::Path>,
    overrides: &crate::scene::Overrides,
) -> anyhow::Result<Result<crate::scene::Scene, String>> {
    use crate::scene::{L60MC_TOML, Scene, SceneError};
    let (name, text) = match path {
        Some(p) => (
            p.display().to_string(),
            std::fs::read_to_string(p)
                .map_err(|e| anyhow::anyhow!("cannot read scene {}: {e}", p.display()))?,
        ),
        None => ("<embedded l60mc.toml>".to_owned(), L60MC_TOML.to_owned()),
    };
    let overridden = overrides.paths();
    // A load table's file is read beside the scene file.
    let base_dir = path.and_then(std::path::Path::parent);
    Ok(
        Scene::from_toml_in(&text, base_dir, overrides).map_err(|e| {
            let lines = match &e {
                SceneError::Invalid(errors) => errors
                    .iter()
                    .map(|f| match option_for(&f.path) {
                        Some(option) if overridden.contains(&f.path.as_str()) => {
                            format!("{option} ({}): {}", f.path, f.message)
                        }
                        _ => with_file_name(&name, &f.to_string()),
                    })
                    .collect::<Vec<_>>(),
                SceneError::Syntax(_) => {
                    e.lines().iter().map(|l| with_file_name(&name, l)).collect()
                }
            };
            lines.join("\n")
        }),
    )
}

/// [`load_scene`], with an invalid scene's field errors printed on stderr
/// and `None` returned, for the command to exit with failure.
pub(crate) fn load_scene_or_report(
    path: Option<&std::path::Path>,
    overrides: &crate::scene::Overrides,
) -> anyhow::Result<Option<crate::scene::Scene>> {
    Ok(load_scene(path, overrides)?
        .map_err(|lines| eprintln!("{lines}"))
        .ok())
}

/// The warm start of the studies that compare integrators (`bench
/// convergence`, `bench work-precision`): the scene, its profile and the
/// warm-up every run starts after.
#[derive(clap::Args)]
pub(crate) struct WarmStartArgs {
    /// Scene file (TOML). Default: the paper's drive.
    scene: Option<std::path::PathBuf>,
    /// Tooth profile of every sprocket.
    #[arg(long, value_enum)]
    profile: Option<crate::scene::ProfileKind>,
    /// Warm-up with the scene's own settings before the runs, s.
    #[arg(long = "warmup", default_value_t = 1.2)]
    pub(crate) warmup_s: f64,
}

impl WarmStartArgs {
    /// The scene with the profile asked for (`None`: its field errors were
    /// printed), after checking the warm-up.
    pub(crate) fn scene(&self) -> anyhow::Result<Option<crate::scene::Scene>> {
        ensure_non_negative("--warmup", self.warmup_s)?;
        let overrides = crate::scene::Overrides {
            profile: self.profile,
            ..Default::default()
        };
        load_scene_or_report(self.scene.as_deref(), &overrides)
    }
}

/// A flag that Ctrl-C (or SIGTERM) sets, for a batch of runs to start no
/// more and stop the running ones at their next step.
pub(crate) fn stop_on_ctrl_c() -> std::sync::Arc<std::sync::atomic::AtomicBool> {
    use std::sync::atomic::{AtomicBool, Ordering};
    let stop = std::sync::Arc::new(AtomicBool::new(false));
    let flag = std::sync::Arc::clone(&stop);
    // A second handler cannot be installed (tests calling twice): ignore.
    let _ = ctrlc::set_handler(move || flag.store(true, Ordering::Relaxed));
    stop
}

/// An error unless the option `flag`'s value is a finite number > 0.
pub(crate) fn ensure_positive(flag: &str, value: f64) -> anyhow::Result<()> {
    anyhow::ensure!(
        value.is_finite() && value > 0.0,
        "{flag} must be a finite number > 0, got {value}"
    );
    Ok(())
}

/// An error unless the option `flag`'s value is a finite number >= 0.
pub(crate) fn ensure_non_negative(flag: &str, value: f64) -> anyhow::Result<()> {
    anyhow::ensure!(
        value.is_finite() && value >= 0.0,
        "{flag} must be a finite number >= 0, got {value}"
    );
    Ok(())
}

/// `file:line:col: path: reason` when the field was located, else `file: path: reason`.
fn with_file_name(name: &str, line: &str) -> String {
    if line.starts_with(|c: char| c.is_ascii_digit()) {
        format!("{name}:{line}")
    } else {
        format!("{name}: {line}")
    }
}

/// The command-line option that overrides a scene-file field.
fn option_for(path: &str) -> Option<&'static str> {
    Some(match path {
        "solver.duration_s" => "--duration",
        "solver.dt_s" => "--dt",
        "solver.stepping" => "--stepping",
        "solver.integrator" => "--integrator",
        "solver.tolerance" => "--tolerance",
        "contact.law" => "--contact-law",
        _ => return None,
    })
}

/// `--dt`: a step in seconds, `auto` for the step the scene's stiffnesses,
/// masses and damping allow (`solver.dt_s = "auto"`), or `speed` for the
/// largest such step (`solver.dt_s = "speed"`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum DtArg {
    /// A fixed step, s.
    Seconds(f64),
    /// `auto`.
    Auto,
    /// `speed`.
    Speed,
}

impl std::str::FromStr for DtArg {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        if s.eq_ignore_ascii_case("auto") {
            return Ok(Self::Auto);
        }
        if s.eq_ignore_ascii_case("speed") {
            return Ok(Self::Speed);
        }
        s.parse::<f64>().map(Self::Seconds).map_err(|_| {
            format!("a step in seconds (e.g. 1e-5), \"auto\" or \"speed\", got \"{s}\"")
        })
    }
}

impl DtArg {
    /// The overrides' `(dt_s, dt_auto, dt_speed)` for an optional `--dt`.
    pub(crate) fn overrides(dt: Option<Self>) -> (Option<f64>, bool, bool) {
        match dt {
            Some(Self::Seconds(s)) => (Some(s), false, false),
            Some(Self::Auto) => (None, true, false),
            Some(Self::Speed) => (None, false, true),
            None => (None, false, false),
        }
    }
}

#[cfg(test)]
mod tests {
    /// Counts the writes a line takes.
    #[derive(Default)]
    struct Writes(Vec<Vec<u8>>);

    impl std::io::Write for Writes {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            self.0.push(buf.to_vec());
            Ok(buf.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    /// A line with formatted numbers is one write ending in its newline;
    /// written as std's `eprintln!` writes it, it takes one per piece.
    #[test]
    fn a_stderr_line_is_one_write() {
        use std::io::Write;
        let args = |out: &mut Writes, one: bool| {
            let (name, depth) = ("x.toml", 337.0_f64);
            if one {
                super::write_line(out, format_args!("{name}: warning: depth {depth:.1} µm"))
            } else {
                writeln!(out, "{name}: warning: depth {depth:.1} µm")
            }
        };
        let mut one = Writes::default();
        args(&mut one, true).expect("write");
        assert_eq!(
            one.0,
            [b"x.toml: warning: depth 337.0 \xc2\xb5m\n".to_vec()]
        );
        let mut pieces = Writes::default();
        args(&mut pieces, false).expect("write");
        assert!(pieces.0.len() > 1, "{:?}", pieces.0);
    }
}
