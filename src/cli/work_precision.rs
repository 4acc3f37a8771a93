//! `chaindrive bench work-precision`: wall time against error for every
//! integrator (see `crate::studies::work_precision` for the measure).

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use crate::analysis::figures::{Mark, Plot, Trace, save};
use crate::studies::work_precision::{Settings, WorkPrecision, study};
use anyhow::Context;

/// Arguments of `chaindrive bench work-precision`.
#[derive(clap::Args)]
pub(super) struct WorkPrecisionArgs {
    #[command(flatten)]
    start: crate::cli::WarmStartArgs,
    /// Horizon after the warm-up, s.
    #[arg(long, default_value_t = 0.02)]
    horizon: f64,
    /// Output directory: work_precision.csv, work_precision.md, work_precision.png/.svg.
    #[arg(long, default_value = "work-precision")]
    out: PathBuf,
    /// A short ladder per method (for tests).
    #[arg(long)]
    quick: bool,
}

pub(super) fn work_precision(args: WorkPrecisionArgs) -> anyhow::Result<ExitCode> {
    let Some(scene) = args.start.scene()? else {
        return Ok(ExitCode::FAILURE);
    };
    crate::cli::ensure_positive("--horizon", args.horizon)?;
    let mut settings = Settings::default_for(args.horizon);
    settings.warmup_s = args.start.warmup_s;
    anyhow::ensure!(
        args.horizon >= settings.grid_s,
        "--horizon must be at least the sample grid step {} s",
        settings.grid_s
    );
    if args.quick {
        for (_, ladder) in &mut settings.ladder.methods {
            ladder.truncate(3);
            ladder.drain(..ladder.len().saturating_sub(2));
        }
        settings.reference_tolerance = 1e-5;
        settings.reference_rk4_step_s = 1e-6;
    }
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    eprintln!(
        "work-precision on {}: warm-up {} s, horizon {} s",
        scene.name(),
        settings.warmup_s,
        settings.horizon_s
    );
    let result = study(&scene, &settings, |run, [speeds, link, contact]| {
        eprintln!(
            "  {:<18} {:<12} {:>9.3} s wall  error: speeds {:.2e}, link {:.2e}, contact {:.2e}{}",
            run.integrator.name(),
            run.setting.label(),
            run.wall_s,
            speeds,
            link,
            contact,
            run.outcome
                .as_ref()
                .err()
                .map_or(String::new(), |e| format!("  ({e})"))
        );
    })
    .context("work-precision study")?;
    let csv = args.out.join("work_precision.csv");
    std::fs::write(&csv, to_csv(&result)?)
        .with_context(|| format!("cannot write {}", csv.display()))?;
    let md = args.out.join("work_precision.md");
    let report = to_markdown(&result);
    std::fs::write(&md, &report).with_context(|| format!("cannot write {}", md.display()))?;
    let figures = save(&plot(&result), &args.out, "work_precision")
        .map_err(|e| anyhow::anyhow!("figure: {e}"))?;
    let mut out = std::io::stdout().lock();
    writeln!(out, "{report}")?;
    writeln!(
        out,
        "wrote {}, {} and {}",
        csv.display(),
        md.display(),
        figures
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    )?;
    Ok(ExitCode::SUCCESS)
}

fn fmt_order(order: Option<f64>) -> String {
    order.map_or(String::new(), |o| format!("{o:.2}"))
}

/// The columns of `work_precision.csv`.
const CSV_HEADER: [&str; 7] = [
    "integrator",
    "setting",
    "dt_s",
    "wall_s",
    "horizon_s",
    "error",
    "order",
];

/// One row of `work_precision.csv`; numbers formatted as the file has them
/// (`{:e}` for steps, wall times and errors, `inf` for a failed run).
#[derive(serde::Serialize)]
struct CsvRow {
    integrator: &'static str,
    setting: String,
    dt_s: String,
    wall_s: String,
    horizon_s: String,
    error: String,
    order: String,
}

fn to_csv(r: &WorkPrecision) -> anyhow::Result<Vec<u8>> {
    let mut w = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(Vec::new());
    w.write_record(CSV_HEADER)?;
    for row in &r.rows {
        let error = if row.error.is_finite() {
            format!("{:e}", row.error)
        } else {
            "inf".to_owned()
        };
        w.serialize(CsvRow {
            integrator: row.run.integrator.name(),
            setting: row.run.setting.label(),
            dt_s: format!("{:e}", row.run.dt_s),
            wall_s: format!("{:e}", row.run.wall_s),
            horizon_s: r.horizon_s.to_string(),
            error,
            order: fmt_order(row.order),
        })?;
    }
    Ok(w.into_inner()?)
}

fn to_markdown(r: &WorkPrecision) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Work-precision, horizon {} s (link {}, roller {})\n",
        r.horizon_s, r.probe.link, r.probe.roller
    );
    let _ = writeln!(
        s,
        "Reference: Dormand–Prince 5(4); RK4 check agrees to {:.2e}; one roller moved by 1 nm changes the reference by {:.2e} over the horizon.\n",
        r.reference_agreement, r.perturbation_growth
    );
    let _ = writeln!(
        s,
        "| integrator | setting | dt (s) | steps | evals | wall (s) | error | order | Pareto |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|");
    for row in &r.rows {
        let error = match &row.run.outcome {
            Ok(_) => format!("{:.2e}", row.error),
            Err(e) => format!("failed: {}", e.split(':').next().unwrap_or("")),
        };
        let _ = writeln!(
            s,
            "| {} | {} | {:.2e} | {} | {} | {:.4} | {} | {} | {} |",
            row.run.integrator.name(),
            row.run.setting.label(),
            row.run.dt_s,
            row.run.stats.steps,
            row.run.stats.evaluations,
            row.run.wall_s,
            error,
            fmt_order(row.order),
            if row.pareto { "yes" } else { "" }
        );
    }
    let _ = writeln!(
        s,
        "\n10 simulated seconds at ≤ 1 % error, extrapolated from the cheapest such run of each method:\n"
    );
    let mut methods: Vec<_> = r.rows.iter().map(|row| row.run.integrator).collect();
    methods.dedup();
    for m in methods {
        let best = r
            .rows
            .iter()
            .filter(|row| row.run.integrator == m && row.error <= 0.01)
            .min_by(|a, b| a.run.wall_s.total_cmp(&b.run.wall_s));
        let _ = match best {
            Some(row) => writeln!(
                s,
                "- {}: {} → {:.2} s wall",
                m.name(),
                row.run.setting.label(),
                row.run.wall_s * 10.0 / r.horizon_s
            ),
            None => writeln!(s, "- {}: no run reached 1 %", m.name()),
        };
    }
    s
}

fn plot(r: &WorkPrecision) -> Plot {
    let mut methods: Vec<_> = r.rows.iter().map(|row| row.run.integrator).collect();
    methods.dedup();
    let mut traces: Vec<Trace> = methods
        .iter()
        .enumerate()
        .map(|(i, m)| Trace {
            label: m.name().to_owned(),
            points: r
                .rows
                .iter()
                .filter(|row| row.run.integrator == *m && row.error.is_finite())
                .map(|row| (row.error.log10(), row.run.wall_s.log10()))
                .collect(),
            mark: Mark::LineDots,
            color: i,
        })
        .collect();
    let mut front: Vec<(f64, f64)> = r
        .rows
        .iter()
        .filter(|row| row.pareto)
        .map(|row| (row.error.log10(), row.run.wall_s.log10()))
        .collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    traces.push(Trace {
        label: "Pareto front".to_owned(),
        points: front,
        mark: Mark::Crosses,
        color: 5,
    });
    Plot {
        title: format!("Work-precision, horizon {} s", r.horizon_s),
        x_label: "log10 relative RMS error".to_owned(),
        y_label: "log10 wall time (s)".to_owned(),
        traces,
        notes: Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_row_fields_are_the_header() {
        let mut w = csv::Writer::from_writer(Vec::new());
        w.serialize(CsvRow {
            integrator: "rk4",
            setting: "dt=1e-5".into(),
            dt_s: "1e-5".into(),
            wall_s: "1e0".into(),
            horizon_s: "0.05".into(),
            error: "inf".into(),
            order: String::new(),
        })
        .expect("serializes");
        let text = String::from_utf8(w.into_inner().expect("flushes")).expect("UTF-8");
        assert_eq!(text.lines().next(), Some(CSV_HEADER.join(",").as_str()));
    }
}
