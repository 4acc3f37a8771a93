//! `chaindrive bench convergence`: the summary statistics of every
//! integrator over a ladder of steps against a fine reference (see
//! `crate::studies::convergence` for the measure).

use std::io::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;

use crate::analysis::figures::{FigureError, Mark, Plot, Trace, save};
use crate::studies::convergence::{Convergence, REL_TOLERANCE, Run, SE_TOLERANCE, Settings, study};
use crate::studies::ladder::{Ladder, Rung, Setting};

/// Arguments of `chaindrive bench convergence`.
#[derive(clap::Args)]
pub(super) struct ConvergenceArgs {
    #[command(flatten)]
    start: crate::cli::WarmStartArgs,
    /// Simulated time of each run after the warm-up, s.
    #[arg(long, default_value_t = 10.0)]
    duration: f64,
    /// Output directory: convergence.csv, convergence.png/.svg.
    #[arg(long, default_value = "convergence")]
    out: PathBuf,
    /// Runs in parallel.
    #[arg(long, default_value_t = 2)]
    jobs: usize,
    /// Two settings of symplectic Euler only, against a 5 µs reference (for tests).
    #[arg(long)]
    quick: bool,
    /// Only these integrators (repeat the option for more; default: every one).
    #[arg(long = "integrator", value_enum)]
    integrators: Vec<crate::scene::Integrator>,
    /// The fixed-step schemes' steps, s (repeat the option for more; default:
    /// 5, 10, 20, 40 and 50 µs). Each should divide the 1 ms sample period.
    #[arg(long = "dt")]
    steps_s: Vec<f64>,
}

pub(super) fn convergence(args: ConvergenceArgs) -> anyhow::Result<ExitCode> {
    let Some(scene) = args.start.scene()? else {
        return Ok(ExitCode::FAILURE);
    };
    crate::cli::ensure_positive("--duration", args.duration)?;
    anyhow::ensure!(args.jobs >= 1, "--jobs must be at least 1");
    let mut settings = Settings::default_for(args.duration);
    settings.warmup_s = args.start.warmup_s;
    settings.threads = args.jobs;
    for &dt in &args.steps_s {
        crate::cli::ensure_positive("--dt", dt)?;
    }
    narrow(&mut settings.ladder, &args.integrators, &args.steps_s);
    if args.quick {
        let euler = crate::scene::Integrator::SymplecticEuler;
        settings.ladder = Ladder {
            methods: vec![(euler, vec![Setting::Step(1e-5), Setting::Step(2e-5)])],
        };
        settings.reference = Rung {
            integrator: euler,
            setting: Setting::Step(5e-6),
        };
    }
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    eprintln!(
        "convergence on {} ({} profile): warm-up {} s, {} s per run, reference {} {}",
        scene.name(),
        scene.profile_name(),
        settings.warmup_s,
        settings.duration_s,
        settings.reference.integrator.name(),
        settings.reference.setting.label()
    );
    let result = study(&scene, &settings, |run| {
        eprintln!(
            "  {:<18} {:<10} {:>8.1} s wall{}",
            run.integrator.name(),
            run.setting.label(),
            run.wall_s,
            run.outcome
                .as_ref()
                .err()
                .map_or(String::new(), |e| format!("  ({e})"))
        );
    })
    .context("convergence study")?;
    let csv = args.out.join("convergence.csv");
    std::fs::write(&csv, to_csv(&result)?)
        .with_context(|| format!("cannot write {}", csv.display()))?;
    // Every run failed: no points to draw, the CSV and the table still say why.
    let figures = match save(&plot(&result), &args.out, "convergence") {
        Ok(paths) => paths,
        Err(FigureError::Empty(_)) => Vec::new(),
        Err(e) => anyhow::bail!("figure: {e}"),
    };
    let mut out = std::io::stdout().lock();
    write!(out, "{}", table(&result))?;
    writeln!(out, "{}", verdict(&result))?;
    writeln!(
        out,
        "wrote {}{}{}",
        csv.display(),
        if figures.is_empty() { "" } else { " and " },
        figures
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    )?;
    Ok(ExitCode::SUCCESS)
}

/// Keeps the ladder's `integrators` (all if empty) and gives its fixed-step
/// schemes the steps `steps_s`, fine to coarse (theirs if empty).
fn narrow(ladder: &mut Ladder, integrators: &[crate::scene::Integrator], steps_s: &[f64]) {
    if !integrators.is_empty() {
        ladder.methods.retain(|(i, _)| integrators.contains(i));
    }
    if !steps_s.is_empty() {
        let mut steps = steps_s.to_vec();
        steps.sort_by(f64::total_cmp);
        steps.dedup();
        for (integrator, settings) in &mut ladder.methods {
            if !integrator.is_adaptive() {
                *settings = steps.iter().map(|&dt| Setting::Step(dt)).collect();
            }
        }
    }
}

/// The columns of `convergence.csv`.
pub(super) const CSV_HEADER: [&str; 10] = [
    "integrator",
    "setting",
    "dt_s",
    "wall_s",
    "duration_s",
    "statistic",
    "value",
    "reference",
    "reference_se",
    "rel_error",
];

/// A number as the file has it: Rust's shortest round-trip, `inf`/`-inf`,
/// empty when absent.
fn num(x: Option<f64>) -> String {
    match x {
        Some(v) if v.is_finite() => v.to_string(),
        Some(v) if v.is_infinite() => if v > 0.0 { "inf" } else { "-inf" }.to_owned(),
        _ => String::new(),
    }
}

fn to_csv(c: &Convergence) -> anyhow::Result<Vec<u8>> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(CSV_HEADER)?;
    for run in std::iter::once(&c.reference).chain(&c.runs) {
        for s in c.compare(run) {
            w.write_record([
                run.integrator.name().to_owned(),
                run.setting.label(),
                num(Some(run.dt_s)),
                num(Some(run.wall_s)),
                num(Some(run.sim_s)),
                s.name.clone(),
                num(s.value),
                num(Some(s.reference)),
                num(s.reference_se),
                num(Some(s.rel_error)),
            ])?;
        }
    }
    Ok(w.into_inner()?)
}

/// The worst statistic of a run: its largest |relative error| and its
/// largest normalized error (converged when ≤ 1).
fn worst(c: &Convergence, run: &Run) -> (f64, f64) {
    c.compare(run)
        .iter()
        .fold((0.0f64, 0.0f64), |(rel, norm), s| {
            (rel.max(s.rel_error.abs()), norm.max(s.normalized_error()))
        })
}

fn table(c: &Convergence) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let reference = c.compare(&c.reference);
    let _ = writeln!(
        s,
        "reference: {} {}, {:.1} s wall for {} s",
        c.reference.integrator.name(),
        c.reference.setting.label(),
        c.reference.wall_s,
        c.reference.sim_s
    );
    let _ = writeln!(s, "{:<30} {:>14} {:>12}", "statistic", "reference", "±se");
    for r in &reference {
        let _ = writeln!(
            s,
            "{:<30} {:>14.6e} {:>12}",
            r.name,
            r.reference,
            r.reference_se
                .map_or("-".to_owned(), |v| format!("{v:.3e}"))
        );
    }
    let _ = writeln!(
        s,
        "\n{:<18} {:<10} {:>9} {:>10} {:>11} {:>11} {:>10}  {:<9}  not converged",
        "integrator",
        "setting",
        "dt_s",
        "wall_s/s",
        "worst_rel",
        "worst_se",
        "worst_norm",
        "converged"
    );
    for run in &c.runs {
        let compared = c.compare(run);
        let (rel, norm) = worst(c, run);
        let failing: Vec<&str> = compared
            .iter()
            .filter(|x| !x.converged)
            .map(|x| x.name.as_str())
            .collect();
        let failing = match failing.len() {
            0 => String::new(),
            1..=3 => failing.join(", "),
            n => format!("{} and {} more", failing[..3].join(", "), n - 3),
        };
        let worst_se = compared
            .iter()
            .filter_map(|x| x.se_error())
            .fold(0.0, f64::max);
        let _ = writeln!(
            s,
            "{:<18} {:<10} {:>9.2e} {:>10.2} {:>11.2e} {:>11.2} {:>10.2}  {:<9}  {}",
            run.integrator.name(),
            run.setting.label(),
            run.dt_s,
            run.wall_s / run.sim_s.max(f64::MIN_POSITIVE),
            rel,
            worst_se,
            norm,
            if run.outcome.is_err() {
                "failed"
            } else if c.converged(run) {
                "yes"
            } else {
                "no"
            },
            if run.outcome.is_err() { "" } else { &failing }
        );
    }
    s
}

fn verdict(c: &Convergence) -> String {
    let robust = match c.robust_verdict() {
        Some(run) => format!(
            "\nconverged with every finer setting of its method: {} at {}, {:.2} s wall per simulated second",
            run.integrator.name(),
            run.setting.label(),
            run.wall_s / run.sim_s.max(f64::MIN_POSITIVE)
        ),
        None => "\nno setting is converged with every finer setting of its method".to_owned(),
    };
    let first = match c.verdict() {
        Some(run) => format!(
            "verdict: {} at {} is the cheapest setting with every statistic within {:.0} % of the reference or {:.0} standard errors: {:.2} s wall per simulated second",
            run.integrator.name(),
            run.setting.label(),
            100.0 * REL_TOLERANCE,
            SE_TOLERANCE,
            run.wall_s / run.sim_s.max(f64::MIN_POSITIVE)
        ),
        None => format!(
            "verdict: no setting has every statistic within {:.0} % of the reference or {:.0} standard errors",
            100.0 * REL_TOLERANCE,
            SE_TOLERANCE
        ),
    };
    first + &robust
}

fn plot(c: &Convergence) -> Plot {
    let mut methods: Vec<_> = c.runs.iter().map(|r| r.integrator).collect();
    methods.dedup();
    let point = |r: &Run| {
        let (_, norm) = worst(c, r);
        (
            (r.wall_s / r.sim_s.max(f64::MIN_POSITIVE)).log10(),
            norm.max(1e-6).log10(),
        )
    };
    // Each method's settings as dots on a line (a single setting is still
    // seen), each dot labelled with its setting; the settings that failed
    // have no point and are counted in the legend.
    let mut traces: Vec<Trace> = methods
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let failed = c
                .runs
                .iter()
                .filter(|r| r.integrator == *m && r.outcome.is_err())
                .count();
            Trace {
                label: match failed {
                    0 => m.name().to_owned(),
                    n => format!("{} ({n} failed: no point)", m.name()),
                },
                points: c
                    .runs
                    .iter()
                    .filter(|r| r.integrator == *m && r.outcome.is_ok())
                    .map(point)
                    .collect(),
                mark: Mark::LineDots,
                color: i,
            }
        })
        .collect();
    let notes = c
        .runs
        .iter()
        .filter(|r| r.outcome.is_ok())
        .map(|r| {
            let (x, y) = point(r);
            (x, y, r.setting.label())
        })
        .collect();
    let walls: Vec<f64> = c
        .runs
        .iter()
        .filter(|r| r.outcome.is_ok() && r.sim_s > 0.0)
        .map(|r| (r.wall_s / r.sim_s).log10())
        .filter(|v| v.is_finite())
        .collect();
    if let (Some(lo), Some(hi)) = (
        walls.iter().copied().reduce(f64::min),
        walls.iter().copied().reduce(f64::max),
    ) {
        traces.push(Trace {
            label: "converged below".to_owned(),
            points: vec![(lo, 0.0), (hi, 0.0)],
            mark: Mark::Line,
            color: 5,
        });
    }
    Plot {
        title: format!(
            "Convergence of the summary statistics, {} s per run",
            c.reference.sim_s
        ),
        x_label: "log10 wall time per simulated second (s)".to_owned(),
        y_label: format!(
            "log10 worst error / max({:.0} % of reference, {:.0} SE)",
            100.0 * REL_TOLERANCE,
            SE_TOLERANCE
        ),
        traces,
        notes,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Integrator;
    use crate::studies::convergence::Statistic;

    fn run(dt: f64, outcome: Result<f64, &str>) -> Run {
        Run {
            integrator: Integrator::VelocityVerlet,
            setting: Setting::Step(dt),
            dt_s: dt,
            wall_s: if outcome.is_ok() { 4.8 } else { 0.0 },
            sim_s: if outcome.is_ok() { 10.0 } else { 0.0 },
            stats: Default::default(),
            outcome: outcome
                .map(|value| {
                    vec![Statistic {
                        name: "a".to_owned(),
                        value,
                        se: None,
                    }]
                })
                .map_err(str::to_owned),
        }
    }

    /// One setting that ran and two that failed: the one is drawn as a
    /// labelled dot (a line alone draws nothing through one point), and
    /// the legend says that two settings have no point.
    #[test]
    fn a_single_setting_is_a_labelled_dot_and_failed_ones_are_counted() {
        let c = Convergence {
            reference: run(1e-6, Ok(100.0)),
            runs: vec![
                run(5e-5, Ok(100.4)),
                run(5.5e-5, Err("not a whole number of steps")),
                run(6e-5, Err("not a whole number of steps")),
            ],
        };
        let p = plot(&c);
        let method = &p.traces[0];
        assert_eq!(method.mark, Mark::LineDots);
        assert_eq!(method.points.len(), 1);
        assert!(method.label.contains("2 failed"), "{}", method.label);
        // 0.4 % against the 1 % allowance: log10(0.4) on y, 0.48 s/s on x.
        let (x, y) = method.points[0];
        assert!((x - 0.48f64.log10()).abs() < 1e-12, "{x}");
        assert!((y - 0.4f64.log10()).abs() < 1e-9, "{y}");
        assert_eq!(p.notes.len(), 1);
        assert_eq!(p.notes[0].2, Setting::Step(5e-5).label());
    }
}
