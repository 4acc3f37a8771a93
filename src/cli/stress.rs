//! `chaindrive bench stress`: the stress matrix of [`crate::studies::stress`].
//!
//! Progress goes to stderr, one line per ladder and per cell; the tables and
//! findings to stdout; `DIR/stress.csv` (one row per run),
//! `DIR/stress_limits.csv` (largest stable step per cell and integrator) and
//! `DIR/stress_blowups.csv` (detector, time and body of every unstable run)
//! are written cell by cell, so an interrupted matrix leaves what it did.

use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use crate::studies::queue::WorkQueue;
use crate::studies::stress::{
    BLOWUPS_CSV_HEADER, CSV_HEADER, CaseResult, LIMITS_CSV_HEADER, Ladder, Progress,
    blowup_csv_rows, csv_rows, default_matrix, first_failure, limits_csv_rows, quick_matrix,
    roller_costs, run_case,
};
use anyhow::Context;

/// Arguments of `bench stress`.
#[derive(clap::Args)]
pub(super) struct StressArgs {
    /// Output directory for the CSV files.
    #[arg(long, default_value = "stress-out")]
    out: PathBuf,
    /// A small subset (one cell, two integrators, short horizon), for tests.
    #[arg(long)]
    quick: bool,
    /// Cells run at once, one thread each (wall times are measured per run,
    /// on whatever core it gets).
    #[arg(long, default_value_t = 2)]
    jobs: usize,
    /// Only the cells with these names (comma-separated, e.g. `baseline,rpm-1200`).
    #[arg(long, value_delimiter = ',')]
    cases: Vec<String>,
}

struct Outputs {
    runs: csv::Writer<File>,
    limits: csv::Writer<File>,
    blowups: csv::Writer<File>,
}

impl Outputs {
    fn create(dir: &Path) -> anyhow::Result<Self> {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        // The header first, even for a file that gets no row.
        let open = |name: &str, header: &str| -> anyhow::Result<csv::Writer<File>> {
            let path = dir.join(name);
            let file =
                File::create(&path).with_context(|| format!("cannot create {}", path.display()))?;
            let mut w = csv::WriterBuilder::new()
                .has_headers(false)
                .from_writer(file);
            w.write_record(header.split(','))?;
            Ok(w)
        };
        Ok(Self {
            runs: open("stress.csv", CSV_HEADER)?,
            limits: open("stress_limits.csv", LIMITS_CSV_HEADER)?,
            blowups: open("stress_blowups.csv", BLOWUPS_CSV_HEADER)?,
        })
    }

    /// Appends a cell's rows and flushes, so an interrupted matrix leaves what it did.
    fn append(&mut self, r: &CaseResult) -> anyhow::Result<()> {
        fn rows<T: serde::Serialize>(
            w: &mut csv::Writer<File>,
            rows: Vec<T>,
        ) -> anyhow::Result<()> {
            for row in rows {
                w.serialize(row)?;
            }
            w.flush()?;
            Ok(())
        }
        rows(&mut self.runs, csv_rows(r))?;
        rows(&mut self.limits, limits_csv_rows(r))?;
        rows(&mut self.blowups, blowup_csv_rows(r))
    }
}

/// One progress line on stderr (cell `k` of `n`).
fn progress(k: usize, n: usize, started: Instant, p: Progress<'_>) {
    match p {
        Progress::Settled {
            info,
            wall_s,
            error: None,
        } => eprintln!(
            "[{}/{n}] {}: settled in {wall_s:.1} s ({} rollers, {} sprockets, {} profile)",
            k + 1,
            info.name,
            info.rollers,
            info.sprockets,
            info.profile
        ),
        Progress::Settled {
            info,
            error: Some(e),
            ..
        } => eprintln!("[{}/{n}] {}: cannot settle: {e}", k + 1, info.name),
        Progress::Run { .. } => {}
        Progress::Ladder { info, limit } => eprintln!(
            "[{}/{n}] {} {:<17} stable to {:>7} µs, first failure {:>7} µs  ({:.0} s elapsed)",
            k + 1,
            info.name,
            limit.integrator.name(),
            us(limit.largest_stable_dt_s),
            us(limit.first_unstable_dt_s),
            started.elapsed().as_secs_f64()
        ),
    }
}

fn us(x: Option<f64>) -> String {
    x.map_or_else(|| "-".to_owned(), |v| format!("{:.1}", v * 1e6))
}

pub(super) fn stress(args: StressArgs) -> anyhow::Result<ExitCode> {
    let mut cases = if args.quick {
        quick_matrix()?
    } else {
        default_matrix()?
    };
    if !args.cases.is_empty() {
        let known: Vec<String> = cases.iter().map(|c| c.name.clone()).collect();
        if let Some(unknown) = args.cases.iter().find(|n| !known.contains(n)) {
            anyhow::bail!(
                "--cases: no cell named {unknown:?}; cells: {}",
                known.join(", ")
            );
        }
        cases.retain(|c| args.cases.contains(&c.name));
    }
    let ladder = Ladder::default();
    let mut out = Outputs::create(&args.out)?;
    let started = Instant::now();
    eprintln!(
        "stress: {} cells, dt from {:e} s ×{} to {:e} s, {} rungs past the first failure",
        cases.len(),
        ladder.first_dt_s,
        ladder.factor,
        ladder.max_dt_s,
        ladder.past_failure
    );
    let n = cases.len();
    // Each cell's rows are written as it finishes.
    let results: Vec<CaseResult> = WorkQueue::new(&cases)
        .threads(args.jobs)
        .try_run(
            |k, case| {
                Some(run_case(case, &ladder, &mut |p| {
                    progress(k, n, started, p);
                }))
            },
            |_, r| out.append(r),
        )?
        .into_iter()
        .flatten()
        .collect();
    let broken = report(&results);
    println!(
        "\nwall time of the matrix: {:.1} s; outputs in {}",
        started.elapsed().as_secs_f64(),
        args.out.display()
    );
    Ok(if broken {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}

/// Prints the tables and findings; true if a promise was broken (a NaN in
/// the output of a run reported stable).
fn report(results: &[CaseResult]) -> bool {
    limits_table(results);
    roller_cost_table(results);
    let broken = blow_up_section(results);
    false_alarms_section(results);
    profile_pairs_table(results);
    broken
}

/// The largest stable step per cell and integrator.
fn limits_table(results: &[CaseResult]) {
    println!("\n== largest stable dt per cell and integrator (µs) ==");
    println!(
        "{:<16} {:>6} {:>3} {:>6} {:>4} {:>7} {:>8} {:<8} {:<17} {:>7} {:>8} {:>8}  {:<28} {:>9}",
        "case",
        "roller",
        "spr",
        "rpm",
        "e",
        "ζ %",
        "K_g",
        "profile",
        "integrator",
        "est.",
        "stable",
        "fails",
        "detector @ t",
        "wall/sim"
    );
    for r in results {
        let i = &r.info;
        if let Some(e) = &r.build_error {
            println!("{:<16} cannot settle: {e}", i.name);
            continue;
        }
        for l in &r.limits {
            let fail = first_failure(r, l);
            let at = fail.map_or_else(String::new, |f| {
                format!(
                    "{} @ {:.4} s",
                    f.verdict.detector(),
                    f.verdict.stop_t_s().unwrap_or(f64::NAN)
                )
            });
            println!(
                "{:<16} {:>6} {:>3} {:>6} {:>4} {:>7.3} {:>8.0e} {:<8} {:<17} {:>7} {:>8} {:>8}  {:<28} {:>9}{}",
                i.name,
                i.rollers,
                i.sprockets,
                i.rpm,
                i.restitution,
                i.damping_ratio * 100.0,
                i.contact_stiffness,
                i.profile,
                l.integrator.name(),
                us(l.estimated_dt_s.is_finite().then_some(l.estimated_dt_s)),
                us(l.largest_stable_dt_s),
                us(l.first_unstable_dt_s),
                at,
                l.wall_per_sim_s_at_limit
                    .map_or_else(|| "-".to_owned(), |w| format!("{w:.3}")),
                if l.cap_not_binding {
                    "  (cap not binding)"
                } else {
                    ""
                }
            );
        }
    }
}

/// The cost per roller-step over the roller-count series.
fn roller_cost_table(results: &[CaseResult]) {
    println!("\n== per-roller cost (ns per roller-step) over the roller-count series ==");
    let costs = roller_costs(results);
    if costs.is_empty() {
        println!("(no roller-count series in this matrix)");
    }
    for c in &costs {
        let pts: Vec<String> = c
            .points
            .iter()
            .map(|(_, n, ns)| format!("{n}: {ns:.1}"))
            .collect();
        println!(
            "{:<17} dt {:>6.2} µs  {}  spread ×{:.2} (target ≤ 1.5)",
            c.integrator.name(),
            c.dt_s * 1e6,
            pts.join("  "),
            c.spread()
        );
    }
}

/// Which detectors caught the blow-ups, and whether a NaN got out first;
/// true if a run reported stable had a NaN in an output.
fn blow_up_section(results: &[CaseResult]) -> bool {
    println!("\n== blow-up detectors ==");
    let runs = || {
        results
            .iter()
            .flat_map(|r| r.runs.iter().map(move |x| (r, x)))
    };
    let total = runs().count();
    let unstable: Vec<_> = runs().filter(|(_, x)| !x.verdict.is_stable()).collect();
    let mut by_detector: Vec<(&str, usize)> = Vec::new();
    for (_, x) in &unstable {
        let d = x.verdict.detector();
        match by_detector.iter_mut().find(|(n, _)| *n == d) {
            Some(e) => e.1 += 1,
            None => by_detector.push((d, 1)),
        }
    }
    println!(
        "{total} runs, {} unstable; detectors: {}",
        unstable.len(),
        by_detector
            .iter()
            .map(|(d, c)| format!("{d} {c}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let non_finite: Vec<_> = unstable
        .iter()
        .filter(|(_, x)| x.verdict.detector() == "non-finite")
        .collect();
    if non_finite.is_empty() {
        println!(
            "no blow-up reached a NaN: the penetration/stretch detectors caught every one first"
        );
    } else {
        println!(
            "{} blow-ups reached a NaN before the stretch/penetration detectors fired:",
            non_finite.len()
        );
        for (r, x) in &non_finite {
            println!(
                "  {} {} dt {:.2} µs",
                r.info.name,
                x.integrator.name(),
                x.dt_s * 1e6
            );
        }
    }
    let nan_unstable = unstable
        .iter()
        .filter(|(_, x)| x.nan_in_output_t_s.is_some())
        .count();
    println!(
        "unstable runs whose sampled outputs held a NaN before the detector fired: {nan_unstable}"
    );
    let broken: Vec<_> = runs()
        .filter(|(_, x)| x.verdict.is_stable() && x.nan_in_output_t_s.is_some())
        .collect();
    if broken.is_empty() {
        println!(
            "stable runs with a NaN in any output: 0 of {}",
            total - unstable.len()
        );
    } else {
        println!("BROKEN: stable runs with a NaN in an output:");
        for (r, x) in &broken {
            println!(
                "  {} {} dt {:.2} µs at t = {:?}",
                r.info.name,
                x.integrator.name(),
                x.dt_s * 1e6,
                x.nan_in_output_t_s
            );
        }
    }
    !broken.is_empty()
}

/// The steps flagged unstable although a larger one was stable.
fn false_alarms_section(results: &[CaseResult]) {
    let alarms: Vec<String> = results
        .iter()
        .flat_map(|r| {
            r.limits
                .iter()
                .filter(|l| !l.false_alarms_dt_s.is_empty())
                .map(move |l| {
                    format!(
                        "  {} {}: flagged at {} µs, stable at a larger dt",
                        r.info.name,
                        l.integrator.name(),
                        l.false_alarms_dt_s
                            .iter()
                            .map(|d| format!("{:.2}", d * 1e6))
                            .collect::<Vec<_>>()
                            .join(", ")
                    )
                })
        })
        .collect();
    if alarms.is_empty() {
        println!("possible false alarms (flagged, yet stable at a larger dt): none");
    } else {
        println!("possible false alarms (flagged, yet stable at a larger dt):");
        for a in &alarms {
            println!("{a}");
        }
    }
}

/// Each cell's circular profile beside its real one.
fn profile_pairs_table(results: &[CaseResult]) {
    println!("\n== circular vs real (same cell) ==");
    let mut any = false;
    for real in results.iter().filter(|r| r.info.profile == "real") {
        let Some(base) = real.info.name.strip_suffix("-real") else {
            continue;
        };
        let Some(circ) = results.iter().find(|r| r.info.name == base) else {
            continue;
        };
        any = true;
        for l in &real.limits {
            let Some(c) = circ.limits.iter().find(|c| c.integrator == l.integrator) else {
                continue;
            };
            // Peaks at the smallest step, where both ran (if both were stable there).
            let peak = |r: &CaseResult| {
                r.runs
                    .iter()
                    .filter(|x| x.integrator == l.integrator)
                    .min_by(|a, b| a.dt_s.total_cmp(&b.dt_s))
                    .map_or_else(
                        || "-".to_owned(),
                        |x| {
                            format!(
                                "{}{:.0} kN, δ {:.0} µm",
                                if x.verdict.is_stable() {
                                    ""
                                } else {
                                    "UNSTABLE "
                                },
                                x.max_link_force_n / 1e3,
                                x.max_penetration_m * 1e6
                            )
                        },
                    )
            };
            println!(
                "{:<12} {:<17} circular {:>7} µs [{}]   real {:>7} µs [{}]",
                base,
                l.integrator.name(),
                us(c.largest_stable_dt_s),
                peak(circ),
                us(l.largest_stable_dt_s),
                peak(real)
            );
        }
    }
    if !any {
        println!("(no circular/real pair in this matrix)");
    }
}
