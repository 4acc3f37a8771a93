//! The `chaindrive` command-line tool: one file per subcommand.

mod analyze;
mod bench;
mod check;
mod profile;
mod reproduce;
mod run;
mod stress;
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
    /// Print a sprocket's tooth outline (CSV) or its dimension table.
    Profile(profile::ProfileArgs),
    /// Reproduce the paper's study: three runs, report, summaries, figures.
    Reproduce(reproduce::ReproduceArgs),
    /// Analyse a recording (`run --record`) of any scene: report, JSON, figures.
    Analyze(analyze::AnalyzeArgs),
}

fn main() -> std::process::ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run(args) => run::run(args),
        Command::Bench(args) => bench::bench(args),
        Command::Check(args) => check::check(args),
        Command::Profile(args) => profile::profile(args),
        Command::Reproduce(args) => reproduce::reproduce(args),
        Command::Analyze(args) => analyze::analyze(args),
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

/// Loads a scene file (or the embedded paper drive), reporting every error
/// prefixed with the file name, one per line.
pub(crate) fn load_scene(
    path: Option<&std::path::Path>,
) -> anyhow::Result<Result<chaindrive::scene::Scene, String>> {
    use chaindrive::scene::{L60MC_TOML, Scene};
    let (name, text) = match path {
        Some(p) => (
            p.display().to_string(),
            std::fs::read_to_string(p)
                .map_err(|e| anyhow::anyhow!("cannot read scene {}: {e}", p.display()))?,
        ),
        None => ("<embedded l60mc.toml>".to_owned(), L60MC_TOML.to_owned()),
    };
    Ok(Scene::from_toml(&text).map_err(|e| {
        e.lines()
            .iter()
            // `file:line:col: path: reason` when the field was located, else `file: path: reason`.
            .map(|l| {
                if l.starts_with(|c: char| c.is_ascii_digit()) {
                    format!("{name}:{l}")
                } else {
                    format!("{name}: {l}")
                }
            })
            .collect::<Vec<_>>()
            .join("\n")
    }))
}
