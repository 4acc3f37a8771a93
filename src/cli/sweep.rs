//! `chaindrive sweep`: one steady run per driver speed, in parallel, and
//! what a speed range is judged by: `sweep.csv` (every summary scalar per
//! speed), `cases.csv` (each speed's status, stationarity and warnings),
//! `verdict.csv` (each speed's static safety factor, rating margin and
//! fatigue damage per hour and life),
//! `orders.csv` (order spectra), `spans.csv` (each span's predicted
//! natural frequencies), a Campbell diagram, order cuts, envelopes and
//! `report.md` (speeds whose runs warned, the design checks per speed and
//! the weakest speed, resonance crossings, worst-case speeds). With `--run-up`,
//! one run whose driver speed ramps slowly, analysed in short windows, gives
//! the same outputs at each window's mean speed.

use std::fmt::Write as _;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::Ordering;
use std::time::Instant;

use crate::analysis::orders::{MAX_ORDER_DENOMINATOR, OrderSet};
use crate::analysis::units::si;
use crate::scene::{Assignment, Overrides, Scene};
use crate::studies::sweep::campbell::describe_signal;
use crate::studies::sweep::report::GRID_RESOLUTION;
use anyhow::Context;

use crate::cli::sweep_figures::{FigureSettings, draw_figures};
use crate::studies::sweep::{
    CaseFlags, CaseOutcome, DEFAULT_WINDOW_SPEED_CHANGE, PEAK_MEDIAN_FACTOR, RunUpSettings,
    SweepSettings, TRANSVERSE_MODES, completed, default_orders, doubt_section, excitation_orders,
    held_sprockets, on_order_grid, parse_rpm_range, parse_run_up, resonance_crossings, run_sweep,
    run_up, summary_scalars, verdicts, weakest, worst_cases,
};

/// Arguments of `chaindrive sweep`.
#[derive(clap::Args)]
pub(super) struct SweepArgs {
    /// Scene file (TOML). Default: the paper's drive (embedded `assets/l60mc.toml`).
    scene: Option<PathBuf>,
    /// Driver speeds FROM:TO:STEP, rpm (e.g. 300:3000:100): one steady run each.
    #[arg(
        long,
        value_name = "FROM:TO:STEP",
        required_unless_present = "run_up",
        conflicts_with = "run_up"
    )]
    rpm: Option<String>,
    /// One run whose driver speed rises linearly from FROM to TO rpm over
    /// --duration seconds (after the ramp and --settle), analysed in windows
    /// of whole revolutions.
    #[arg(long, value_name = "FROM:TO", requires = "duration")]
    run_up: Option<String>,
    /// Length of the run-up, s.
    #[arg(
        long,
        value_name = "S",
        allow_negative_numbers = true,
        requires = "run_up"
    )]
    duration: Option<f64>,
    /// Run-up: largest change of the driver's speed over one window, as a
    /// fraction of its speed.
    #[arg(long, value_name = "FRACTION", default_value_t = DEFAULT_WINDOW_SPEED_CHANGE, allow_negative_numbers = true)]
    window_change: f64,
    /// Time after the driver's ramp before the window, s.
    #[arg(
        long,
        value_name = "S",
        default_value_t = 1.0,
        allow_negative_numbers = true
    )]
    settle: f64,
    /// Statistics and order window at the end of each run, s.
    #[arg(
        long,
        value_name = "S",
        default_value_t = 1.0,
        allow_negative_numbers = true
    )]
    window: f64,
    /// Runs at once (default: the machine's cores).
    #[arg(long, value_name = "N")]
    jobs: Option<usize>,
    /// Folder of the outputs (created if missing).
    #[arg(long, value_name = "DIR", default_value = "sweep")]
    out: PathBuf,
    /// Largest order analysed, cycles per driver revolution (default: twice
    /// the largest tooth count).
    #[arg(long, value_name = "K", allow_negative_numbers = true)]
    max_order: Option<f64>,
    /// Step between orders, 1/D (1, 0.5, 0.25, …).
    #[arg(
        long,
        value_name = "STEP",
        default_value_t = 1.0,
        allow_negative_numbers = true
    )]
    order_step: f64,
    /// Signal of the Campbell diagram and the order cuts: segK_link_force_n,
    /// segK_transverse_m, omega_I_rad_s or max_contact_force_n.
    #[arg(long, default_value = "seg1_transverse_m")]
    signal: String,
    /// Upper end of the Campbell diagram's frequency axis, Hz (default: a
    /// little above the highest non-meshing order at the top speed and the
    /// spans' transverse modes).
    #[arg(long, value_name = "HZ", allow_negative_numbers = true)]
    max_freq: Option<f64>,
    /// Any other scene value, the same in every case: PATH=VALUE by the
    /// scene file's path (repeatable), e.g. `--set chain.pretension_n=25000`.
    #[arg(long = "set", value_name = "PATH=VALUE")]
    set: Vec<String>,
    /// The chain's integration step, s, `auto` or `speed` (overrides the scene).
    #[arg(long, value_name = "SECONDS|auto|speed")]
    dt: Option<crate::cli::DtArg>,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
}

pub(super) fn sweep(args: SweepArgs) -> anyhow::Result<ExitCode> {
    let (dt_s, dt_auto, dt_speed) = crate::cli::DtArg::overrides(args.dt);
    let overrides = Overrides {
        dt_s,
        dt_auto,
        dt_speed,
        ..Overrides::default()
    };
    let scene = match crate::cli::load_scene(args.scene.as_deref(), &overrides)? {
        Ok(s) => s,
        Err(lines) => {
            eprintln!("{lines}");
            return Ok(ExitCode::FAILURE);
        }
    };
    let assignments = args
        .set
        .iter()
        .map(|a| {
            let (path, value) = a.split_once('=').ok_or_else(|| {
                anyhow::anyhow!("--set {a}: write PATH=VALUE, e.g. chain.pretension_n=25000")
            })?;
            Assignment::parse(path.trim(), value.trim())
                .map_err(|e| anyhow::anyhow!("--set {a}: {e}"))
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    let scene = if assignments.is_empty() {
        scene
    } else {
        scene
            .with_set(&assignments)
            .map_err(|e| anyhow::anyhow!("--set: {e}"))?
    };
    let orders = match args.max_order {
        Some(k) => OrderSet::new(k, args.order_step).map_err(|e| {
            anyhow::anyhow!("--max-order {k} --order-step {}: {e}", args.order_step)
        })?,
        None => {
            let d = default_orders(&scene)?;
            OrderSet::new(d.max_order(), args.order_step)
                .map_err(|e| anyhow::anyhow!("--order-step {}: {e}", args.order_step))?
        }
    };
    check_signal(&args.signal, &scene)?;
    if let Some(hz) = args.max_freq {
        anyhow::ensure!(
            hz.is_finite() && hz > 0.0,
            "--max-freq {hz}: the frequency axis must end above 0 Hz; give a frequency in Hz, e.g. 2000"
        );
    }
    if let Some(text) = &args.run_up {
        return sweep_run_up(&args, &scene, text, orders);
    }
    let rpm = parse_rpm_range("--rpm", args.rpm.as_deref().unwrap_or(""))?;
    let jobs = args
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    anyhow::ensure!(jobs >= 1, "--jobs {jobs}: at least one run at a time");
    let settings = SweepSettings {
        rpm,
        settle_s: args.settle,
        window_s: args.window,
        jobs,
        orders,
    };
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create the output folder {}", args.out.display()))?;
    let stop = crate::cli::stop_on_ctrl_c();
    let progress = progress_bar(
        args.quiet,
        indicatif::ProgressBar::new(settings.rpm.len() as u64),
        "{bar:40} {pos}/{len} speeds, eta {eta} {msg}",
    );
    let started = Instant::now();
    let on_case = |c: &CaseOutcome| {
        if let Some(p) = &progress {
            p.inc(1);
            if let CaseOutcome::Failed { rpm, .. } = c {
                p.set_message(format!("(failed at {rpm} rpm)"));
            }
        }
    };
    let cases = run_sweep(&scene, &settings, Some(&stop), &on_case)?;
    let wall_s = started.elapsed().as_secs_f64();
    if let Some(p) = &progress {
        p.finish_and_clear();
    }
    let interrupted = stop.load(Ordering::Relaxed) && cases.len() < settings.rpm.len();
    let header = format!(
        "{} of {} speeds ({} … {} rpm), settle {} s after the ramp, window {} s; orders up to {} in steps of {}.",
        cases.len(),
        settings.rpm.len(),
        settings.rpm.first().copied().unwrap_or(0.0),
        settings.rpm.last().copied().unwrap_or(0.0),
        settings.settle_s,
        settings.window_s,
        settings.orders.max_order(),
        settings.orders.step()
    );
    write_outputs(&args, &scene, settings.orders, &header, &cases)?;
    let failed = cases
        .iter()
        .filter(|c| matches!(c, CaseOutcome::Failed { .. }))
        .count();
    let warned = cases.iter().filter(|c| CaseFlags::of(c).warned()).count();
    println!(
        "{} of {} speeds run in {:.1} s wall on {} thread(s) ({:.2} s per case){}{}{}; outputs in {}",
        cases.len(),
        settings.rpm.len(),
        wall_s,
        settings.jobs,
        wall_s / cases.len().max(1) as f64,
        if failed > 0 {
            format!(", {failed} failed (see report.md)")
        } else {
            String::new()
        },
        if warned > 0 {
            format!(", {warned} warned (see report.md, cases.csv)")
        } else {
            String::new()
        },
        if interrupted { " (interrupted)" } else { "" },
        args.out.display()
    );
    Ok(if interrupted {
        ExitCode::from(130)
    } else {
        ExitCode::SUCCESS
    })
}

/// `chaindrive sweep --run-up FROM:TO --duration S`.
fn sweep_run_up(
    args: &SweepArgs,
    scene: &Scene,
    text: &str,
    orders: OrderSet,
) -> anyhow::Result<ExitCode> {
    let (from_rpm, to_rpm) = parse_run_up(text)?;
    let settings = RunUpSettings {
        from_rpm,
        to_rpm,
        settle_s: args.settle,
        duration_s: args.duration.unwrap_or(f64::NAN),
        orders,
        max_speed_change: args.window_change,
    };
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create the output folder {}", args.out.display()))?;
    let stop = crate::cli::stop_on_ctrl_c();
    let progress = progress_bar(
        args.quiet,
        indicatif::ProgressBar::new_spinner(),
        "{spinner} {pos} windows, {msg}",
    );
    let started = Instant::now();
    let on_window = |c: &CaseOutcome| {
        if let Some(p) = &progress {
            p.inc(1);
            p.set_message(format!("{:.0} rpm", c.rpm()));
        }
    };
    let windows = run_up(scene, &settings, Some(&stop), &on_window)?;
    let wall_s = started.elapsed().as_secs_f64();
    if let Some(p) = &progress {
        p.finish_and_clear();
    }
    let interrupted = stop.load(Ordering::Relaxed);
    let header = format!(
        "A run-up from {from_rpm} to {to_rpm} rpm over {} s ({:.1} rpm/s) after the ramp and {} s of settling, analysed in {} windows of whole revolutions (each spanning at most {} % of its speed, or one revolution); orders up to {} in steps of {}, each window's linear trend taken out.",
        settings.duration_s,
        settings.rate_rpm_s(),
        settings.settle_s,
        windows.len(),
        100.0 * settings.max_speed_change,
        orders.max_order(),
        orders.step()
    );
    write_outputs(args, scene, orders, &header, &windows)?;
    let failed = windows
        .iter()
        .any(|c| matches!(c, CaseOutcome::Failed { .. }));
    println!(
        "run-up {from_rpm} → {to_rpm} rpm: {} windows in {wall_s:.1} s wall{}{}; outputs in {}",
        windows.len(),
        if failed {
            ", failed (see report.md)"
        } else {
            ""
        },
        if interrupted { " (interrupted)" } else { "" },
        args.out.display()
    );
    Ok(if interrupted {
        ExitCode::from(130)
    } else {
        ExitCode::SUCCESS
    })
}

/// `bar` with the style `template`, unless `quiet` or stderr is not a terminal.
fn progress_bar(
    quiet: bool,
    bar: indicatif::ProgressBar,
    template: &str,
) -> Option<indicatif::ProgressBar> {
    (!quiet && std::io::stderr().is_terminal()).then(|| {
        bar.set_style(
            indicatif::ProgressStyle::with_template(template)
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar
    })
}

/// The Campbell signal must be one the sweep analyses.
fn check_signal(signal: &str, scene: &Scene) -> anyhow::Result<()> {
    let segments = scene.sprockets().len();
    let sprockets = scene.sprockets().len();
    let mut known: Vec<String> = (1..=segments)
        .flat_map(|k| {
            [
                format!("seg{k}_link_force_n"),
                format!("seg{k}_transverse_m"),
            ]
        })
        .collect();
    known.extend((1..=sprockets).map(|i| format!("omega_{i}_rad_s")));
    known.push("max_contact_force_n".to_owned());
    anyhow::ensure!(
        known.iter().any(|k| k == signal),
        "--signal {signal}: not a signal of this drive; one of {}",
        known.join(", ")
    );
    Ok(())
}

fn create(dir: &Path, name: &str) -> anyhow::Result<std::io::BufWriter<std::fs::File>> {
    let path = dir.join(name);
    std::fs::File::create(&path)
        .map(std::io::BufWriter::new)
        .with_context(|| format!("cannot write {}", path.display()))
}

fn write_outputs(
    args: &SweepArgs,
    scene: &Scene,
    orders: OrderSet,
    header: &str,
    cases: &[CaseOutcome],
) -> anyhow::Result<()> {
    // The figures are drawn on a thread of their own while the tables are written.
    let (excitation, off_grid) = on_order_grid(&excitation_orders(scene), &orders);
    let settings = FigureSettings {
        dir: &args.out,
        signal: &args.signal,
        max_hz: args.max_freq,
    };
    let (figures, written) = std::thread::scope(|s| {
        let drawing = s.spawn(|| draw_figures(&settings, scene, &completed(cases), &excitation));
        let written = write_tables(&args.out, cases);
        let figures = drawing
            .join()
            .unwrap_or_else(|_| vec![Err("the figures' thread panicked".to_owned())]);
        (figures, written)
    });
    written?;
    let mut report = create(&args.out, "report.md")?;
    report.write_all(
        report_text(
            scene,
            header,
            cases,
            &excitation,
            &off_grid,
            orders,
            &figures,
        )
        .as_bytes(),
    )?;
    report.flush()?;
    Ok(())
}

/// `cases.csv`: one row per speed, `rpm,status,stationary,warning_count,warnings,error`
/// ([`CaseFlags`]; the warnings joined by ` | `, empty cells where unknown).
fn write_case_flags(dir: &Path, cases: &[CaseOutcome]) -> anyhow::Result<()> {
    let mut w = csv_writer(dir, "cases.csv")?;
    w.write_record([
        "rpm",
        "status",
        "stationary",
        "warning_count",
        "warnings",
        "error",
    ])?;
    for case in cases {
        let f = CaseFlags::of(case);
        w.write_record([
            f.rpm.to_string(),
            f.status.to_owned(),
            f.stationary.map_or_else(String::new, |s| s.to_string()),
            f.warnings
                .as_ref()
                .map_or_else(String::new, |w| w.len().to_string()),
            f.warnings
                .as_ref()
                .map_or_else(String::new, |w| w.join(" | ")),
            f.error.unwrap_or_default(),
        ])?;
    }
    w.flush()?;
    Ok(())
}

/// `verdict.csv`: one row per completed speed, `rpm,static_safety_factor,
/// mean_static_safety_factor,rating_margin,design_power_w,
/// transmitted_power_w,damage_per_hour,fatigue_life_h,
/// fatigue_safety_factor` (empty cells where a check has no data; an
/// infinite life `infinite`).
fn write_verdicts(dir: &Path, cases: &[CaseOutcome]) -> anyhow::Result<()> {
    let mut w = csv_writer(dir, "verdict.csv")?;
    w.write_record([
        "rpm",
        "static_safety_factor",
        "mean_static_safety_factor",
        "rating_margin",
        "design_power_w",
        "transmitted_power_w",
        "damage_per_hour",
        "fatigue_life_h",
        "fatigue_safety_factor",
    ])?;
    let cell = |x: Option<f64>| x.map_or_else(String::new, |x| x.to_string());
    for v in verdicts(cases) {
        w.write_record([
            v.rpm.to_string(),
            cell(v.static_safety_factor),
            cell(v.mean_static_safety_factor),
            cell(v.rating_margin),
            cell(v.design_power_w),
            cell(v.transmitted_power_w),
            cell(v.damage_per_hour),
            v.fatigue_life_h
                .map_or_else(String::new, |l| match l.hours() {
                    Some(h) => h.to_string(),
                    None => "infinite".to_owned(),
                }),
            cell(v.fatigue_safety_factor),
        ])?;
    }
    w.flush()?;
    Ok(())
}

/// The report's "Will it last?" section: the design checks per speed and
/// the weakest speed by each; empty where no speed has a check's data.
fn verdict_section(cases: &[CaseOutcome]) -> String {
    let v = verdicts(cases);
    let mut s = String::new();
    if v.iter().all(|v| {
        v.static_safety_factor.is_none() && v.rating_margin.is_none() && v.damage_per_hour.is_none()
    }) {
        return s;
    }
    let _ = writeln!(s, "## Will it last?\n");
    let _ = writeln!(
        s,
        "Each speed's design checks (docs/design-checks.md): the static safety factor (tensile strength over the largest link force), the catalogue rating's margin (design power over the run's transmitted power), and the link plates' fatigue damage per hour and life at that speed alone; — where the run has no data for a check.\n"
    );
    let _ = writeln!(
        s,
        "| rpm | static safety factor | rating margin | fatigue damage per hour | fatigue life |\n|---|---|---|---|---|"
    );
    let num =
        |x: Option<f64>, digits: usize| x.map_or("—".to_owned(), |x| format!("{x:.digits$}"));
    for r in &v {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} |",
            r.rpm,
            num(r.static_safety_factor, 2),
            num(r.rating_margin, 3),
            r.damage_per_hour
                .map_or("—".to_owned(), |d| format!("{d:.3e}")),
            r.fatigue_life_h.map_or("—".to_owned(), |l| l.to_string())
        );
    }
    let _ = writeln!(s, "\nThe weakest speed by each check:\n");
    for w in weakest(&v) {
        let value = if w.check.contains("damage") {
            format!("{:.3e} per hour", w.value)
        } else {
            format!("{:.3}", w.value)
        };
        let _ = writeln!(s, "- {}: {} at {} rpm", w.check, value, w.rpm);
    }
    let _ = writeln!(s);
    s
}

/// A CSV file in `dir`.
fn csv_writer(dir: &Path, name: &str) -> anyhow::Result<csv::Writer<std::fs::File>> {
    let path = dir.join(name);
    csv::Writer::from_path(&path).with_context(|| format!("cannot write {}", path.display()))
}

/// `sweep.csv`, `cases.csv`, `orders.csv` and `spans.csv` (numbers as Rust
/// writes them: the shortest text that reads back to the same bits).
fn write_tables(dir: &Path, cases: &[CaseOutcome]) -> anyhow::Result<()> {
    write_case_flags(dir, cases)?;
    write_verdicts(dir, cases)?;
    let mut sweep_csv = csv_writer(dir, "sweep.csv")?;
    sweep_csv.write_record(["rpm", "statistic", "value"])?;
    for case in cases {
        match case {
            CaseOutcome::Done(r) => {
                let rpm = r.rpm.to_string();
                sweep_csv.write_record([rpm.as_str(), "failed", "0"])?;
                for (name, value) in summary_scalars(r) {
                    sweep_csv.write_record([rpm.clone(), name, value.to_string()])?;
                }
            }
            CaseOutcome::Failed { rpm, .. } => {
                sweep_csv.write_record([rpm.to_string().as_str(), "failed", "1"])?;
            }
        }
    }
    sweep_csv.flush()?;
    let done = completed(cases);
    let mut orders_csv = csv_writer(dir, "orders.csv")?;
    orders_csv.write_record([
        "rpm",
        "signal",
        "order",
        "frequency_hz",
        "amplitude",
        "phase_rad",
    ])?;
    for r in &done {
        for s in &r.orders {
            for c in &s.spectrum.components {
                orders_csv.write_record([
                    r.rpm.to_string(),
                    s.signal.clone(),
                    c.order.to_string(),
                    c.frequency_hz.to_string(),
                    c.amplitude.to_string(),
                    c.phase_rad.to_string(),
                ])?;
            }
        }
    }
    orders_csv.flush()?;
    let mut spans_csv = csv_writer(dir, "spans.csv")?;
    let mut header = vec![
        "rpm".to_owned(),
        "segment".to_owned(),
        "tension_n".to_owned(),
    ];
    header.extend((1..=TRANSVERSE_MODES).map(|n| format!("transverse_{n}_hz")));
    header.push("axial_hz".to_owned());
    spans_csv.write_record(&header)?;
    for r in &done {
        for s in &r.spans {
            let mut row = vec![
                r.rpm.to_string(),
                s.segment.to_string(),
                s.tension_n.to_string(),
            ];
            row.extend(s.transverse_hz.iter().map(f64::to_string));
            row.push(s.axial_hz.to_string());
            spans_csv.write_record(&row)?;
        }
    }
    spans_csv.flush()?;
    Ok(())
}

fn report_text(
    scene: &Scene,
    header: &str,
    cases: &[CaseOutcome],
    excitation: &[f64],
    off_grid: &[f64],
    orders: OrderSet,
    figures: &[Result<String, String>],
) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# Speed sweep: {}\n", scene.name());
    let _ = writeln!(s, "{header}\n");
    let failed: Vec<(f64, &str)> = cases
        .iter()
        .filter_map(|c| match c {
            CaseOutcome::Failed { rpm, message } => Some((*rpm, message.as_str())),
            CaseOutcome::Done(_) => None,
        })
        .collect();
    if !failed.is_empty() {
        let _ = writeln!(s, "## Failed cases\n");
        for (rpm, m) in &failed {
            let _ = writeln!(s, "- {rpm} rpm: {m}");
        }
        let _ = writeln!(s);
    }
    s.push_str(&doubt_section(cases));
    s.push_str(&verdict_section(cases));
    let _ = writeln!(s, "## Resonance crossings\n");
    let _ = writeln!(
        s,
        "Where an excitation order ({}) meets a span's predicted natural frequency (moving string from the run's own mean tension and chain speed; axial rod K·P/μ), and whether that order's amplitude in the span's response peaks there: the larger response of the two speeds around the crossing is a local maximum over its neighbours and more than {} × the median of that order's response over the sweep. Where those two speeds are more than {} % of the crossing's rpm apart, or one has no neighbour beyond it, the grid cannot tell: \"not resolved by the grid\".\n",
        excitation
            .iter()
            .map(|k| k.to_string())
            .collect::<Vec<_>>()
            .join(", "),
        PEAK_MEDIAN_FACTOR,
        100.0 * GRID_RESOLUTION
    );
    if !off_grid.is_empty() {
        let listed = off_grid
            .iter()
            .map(|k| format!("{k:.4}"))
            .collect::<Vec<_>>()
            .join(", ");
        // The smallest step 1/D that puts every one of them on the grid.
        let step = (1..=MAX_ORDER_DENOMINATOR).find(|&d| {
            off_grid.iter().all(|k| {
                let n = k * f64::from(d);
                (n - n.round()).abs() <= 1e-6
            })
        });
        let hint = match step {
            Some(d) if off_grid.iter().all(|&k| k <= orders.max_order()) => {
                format!(
                    " (`--order-step {}`, a step of 1/{d}, puts them on it)",
                    1.0 / f64::from(d)
                )
            }
            _ => String::new(),
        };
        let _ = writeln!(
            s,
            "The scene also excites orders {listed} of the driver, off the analysed orders (steps of 1/{} up to {}): they are left out of the crossings and the figures{hint}.\n",
            orders.denominator(),
            orders.max_order()
        );
    }
    let crossings = resonance_crossings(cases, excitation);
    if crossings.is_empty() {
        let _ = writeln!(
            s,
            "No order line crosses a predicted natural frequency in this range.\n"
        );
    } else {
        let _ = writeln!(
            s,
            "| span | mode | order | crossing rpm | frequency Hz | response | peak at rpm | peak amplitude | peaks there |\n|---|---|---|---|---|---|---|---|---|"
        );
        for c in &crossings {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {:.1} | {:.2} | {} | {} | {} | {} |",
                c.segment,
                c.mode.name(),
                c.order,
                c.rpm,
                c.frequency_hz,
                c.signal,
                c.peak_rpm,
                si(c.peak_amplitude, describe_signal(&c.signal).1),
                c.verdict.describe()
            );
        }
        let _ = writeln!(s);
    }
    let _ = writeln!(s, "## Worst-case speeds\n");
    let _ = writeln!(s, "| statistic | rpm | value | run |\n|---|---|---|---|");
    let flags: Vec<CaseFlags> = cases.iter().map(CaseFlags::of).collect();
    for w in worst_cases(cases) {
        let run = flags
            .iter()
            .find(|f| f.rpm == w.rpm && f.status != "failed")
            .map_or("", |f| f.status);
        let _ = writeln!(
            s,
            "| {} | {} | {} | {run} |",
            w.statistic,
            w.rpm,
            si(w.value, w.unit)
        );
    }
    let held = held_sprockets(cases);
    if !held.is_empty() {
        let names: Vec<String> = held.iter().map(|k| format!("sprocket {}", k + 1)).collect();
        let _ = writeln!(
            s,
            "\n{} turns at a prescribed speed (its speed RMS is rounding, below 10⁻⁹ of the driver's speed): no speed worst case.",
            names.join(", ")
        );
    }
    let _ = writeln!(s, "\n## Files\n");
    let _ = writeln!(
        s,
        "- `sweep.csv`: `rpm,statistic,value`, every scalar of each run's summary (`failed` = 1 for a case that blew up; `warned` = 1 for a run that warned or has a segment that is not stationary, `warning_count`)"
    );
    let _ = writeln!(
        s,
        "- `cases.csv`: `rpm,status,stationary,warning_count,warnings,error`, one row per speed (status `ok`, `warned`, `failed`, or `not judged` for a run-up's window)"
    );
    let _ = writeln!(
        s,
        "- `verdict.csv`: `rpm,static_safety_factor,mean_static_safety_factor,rating_margin,design_power_w,transmitted_power_w,damage_per_hour,fatigue_life_h,fatigue_safety_factor`, one row per completed speed (empty where a check has no data; an infinite life `infinite`)"
    );
    let _ = writeln!(
        s,
        "- `orders.csv`: `rpm,signal,order,frequency_hz,amplitude,phase_rad` (phase ψ of A cos(k θ + ψ), θ the driver's angle turned since t = 0)"
    );
    let _ = writeln!(
        s,
        "- `spans.csv`: each span's tension and predicted frequencies per speed"
    );
    for f in figures {
        match f {
            Ok(stem) => {
                let _ = writeln!(s, "- `{stem}.png`, `{stem}.svg`");
            }
            Err(e) => {
                let _ = writeln!(s, "- not drawn: {e}");
            }
        }
    }
    s
}
