//! `chaindrive run`: simulate a scene and report its summary.

use std::fs::File;
use std::io::{BufWriter, IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use crate::analysis::{RunSummary, Signals, StatsWindow};
use crate::record::{Channels, RecordOptions, Recorder, RunEnd};
use crate::scene::{ContactLaw, Integrator, Overrides, ProfileKind, Stepping};
use crate::sim::checkpoint::{Checkpoint, next_checkpoint_s, run_is_done};
use crate::sim::{Observer, RunOutcome, Sample, SampleRate, Simulation, StageTimes};
use anyhow::Context;

mod resume;
use resume::{CliRun, Resume, continue_series, take_up, write_run_checkpoint};

/// Arguments of `chaindrive run`.
#[derive(clap::Args)]
pub(super) struct RunArgs {
    /// Scene file (TOML). Default: the paper's drive (embedded `assets/l60mc.toml`).
    scene: Option<PathBuf>,
    /// Tooth profile of every sprocket.
    #[arg(long, value_enum)]
    profile: Option<ProfileKind>,
    /// Simulated time, s (overrides the scene).
    #[arg(long)]
    duration: Option<f64>,
    /// The chain's integration step, s, `auto` or `speed` (overrides the scene).
    #[arg(long, value_name = "SECONDS|auto|speed")]
    dt: Option<crate::cli::DtArg>,
    /// How the chain is stepped (overrides the scene).
    #[arg(long, value_enum)]
    stepping: Option<Stepping>,
    /// The chain's integrator (overrides the scene).
    #[arg(long, value_enum)]
    integrator: Option<Integrator>,
    /// Error tolerance of the adaptive integrator (overrides the scene).
    #[arg(long)]
    tolerance: Option<f64>,
    /// Contact law (overrides the scene).
    #[arg(long, value_enum)]
    contact_law: Option<ContactLaw>,
    /// Write the run summary (JSON) here.
    #[arg(long)]
    summary: Option<PathBuf>,
    /// Write the sampled signals (CSV) here.
    #[arg(long)]
    series: Option<PathBuf>,
    /// Record the run to this MCAP file (opens in Foxglove and Rerun), at --rate.
    #[arg(long, value_name = "PATH.mcap")]
    record: Option<PathBuf>,
    /// Channels to record, comma-separated: scene, transforms, rollers,
    /// outlines, links, contacts, sprockets, segments, guides, tensioners,
    /// or all.
    #[arg(long, value_name = "LIST", default_value = "all")]
    record_channels: String,
    /// Statistics window: the last S seconds of the run (default: the last
    /// 1 s after the scene's ramps, or the whole run if shorter). Longer than
    /// --duration or not > 0 is an error; a window that reaches into a ramp
    /// is a warning.
    #[arg(long, value_name = "S", allow_negative_numbers = true)]
    window: Option<f64>,
    /// Sampling rate of every sampled output, Hz.
    #[arg(long, default_value_t = 1000.0)]
    rate: f64,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
    /// Time every stage of the stepping loop and print where the time went.
    #[arg(long)]
    timings: bool,
    /// Write the run's complete state here every --checkpoint-every
    /// simulated seconds, when it is interrupted and at its end (written
    /// aside and renamed: the file is always a whole checkpoint).
    #[arg(long, value_name = "PATH", requires = "checkpoint_every")]
    checkpoint: Option<PathBuf>,
    /// Simulated seconds between checkpoints (rounded to whole steps).
    #[arg(long, value_name = "S", requires = "checkpoint")]
    checkpoint_every: Option<f64>,
    /// Continue the run from this checkpoint. Give the scene and the options
    /// the run was started with; --duration may differ (a longer one
    /// extends the run), not end before the checkpoint. --series continues
    /// that file (cut back to the checkpoint's last row), --record continues
    /// that recording (a new file with its messages up to the checkpoint),
    /// --summary is of the whole run.
    #[arg(long, value_name = "PATH")]
    resume: Option<PathBuf>,
}

/// Streams each sample to the CSV as it is taken, so an interrupted or failed
/// run keeps every row already computed.
struct CliObserver {
    signals: Signals,
    csv: Option<csv::Writer<File>>,
    csv_error: Option<std::io::Error>,
    progress: Option<indicatif::ProgressBar>,
    recorder: Option<Recorder<BufWriter<File>>>,
    /// The scene's guides: the first shoes of every row.
    guides: usize,
}

impl CliObserver {
    /// The latest sample as a series row; numbers as Rust prints them
    /// (shortest round-trip), an absent segment force as an empty field.
    fn write_row(&mut self) -> csv::Result<()> {
        let (Some(csv), Some(row)) = (self.csv.as_mut(), self.signals.rows.last()) else {
            return Ok(());
        };
        csv.write_field(row.t_s.to_string())?;
        for w in &row.omega_rad_s {
            csv.write_field(w.to_string())?;
        }
        for f in &row.segment_force_n {
            csv.write_field(f.map(|f| f.to_string()).unwrap_or_default())?;
        }
        for d in &row.transverse_m {
            csv.write_field(d.to_string())?;
        }
        for t in &row.tensioners {
            for v in [
                t.angle_rad,
                t.travel_m,
                t.plunger_speed_m_s,
                t.pressure_pa,
                f64::from(u8::from(t.valve_open)),
                t.shoe_force_n,
            ] {
                csv.write_field(v.to_string())?;
            }
        }
        for g in row.shoes.iter().take(self.guides) {
            csv.write_field(g.normal_n.to_string())?;
            csv.write_field(g.friction_n.to_string())?;
        }
        csv.write_record(None::<&[u8]>)
    }
}

impl Observer for CliObserver {
    fn sample(&mut self, s: &Sample<'_>) {
        self.signals.sample(s);
        if let Some(r) = self.recorder.as_mut() {
            r.sample(s);
        }
        if self.csv_error.is_none()
            && let Err(e) = self.write_row()
        {
            self.csv_error = Some(io_error(e));
        }
        if let Some(p) = &self.progress {
            p.set_position((s.state.t_s * 1000.0) as u64);
        }
    }
    fn step(&mut self, s: &Sample<'_>) {
        self.signals.step(s);
    }
    fn per_step_from_s(&self) -> f64 {
        self.signals.per_step_from_s()
    }
}

fn create_file(path: &PathBuf, what: &str) -> anyhow::Result<File> {
    File::create(path).with_context(|| format!("cannot write the {what} to {}", path.display()))
}

fn create(path: &PathBuf, what: &str) -> anyhow::Result<BufWriter<File>> {
    create_file(path, what).map(BufWriter::new)
}

/// The I/O error under a CSV writer's error (the only kind writing text fields can meet).
fn io_error(e: csv::Error) -> std::io::Error {
    match e.into_kind() {
        csv::ErrorKind::Io(e) => e,
        other => std::io::Error::other(format!("{other:?}")),
    }
}

pub(super) fn run(args: RunArgs) -> anyhow::Result<ExitCode> {
    crate::cli::outputs::check_distinct(
        &[("scene file", args.scene.as_deref())],
        &[
            ("--summary", args.summary.as_deref()),
            ("--series", args.series.as_deref()),
            ("--record", args.record.as_deref()),
            ("--checkpoint", args.checkpoint.as_deref()),
        ],
    )?;
    if let Some(every) = args.checkpoint_every {
        anyhow::ensure!(
            every.is_finite() && every > 0.0,
            "--checkpoint-every {every}: the time between checkpoints must be a number of simulated seconds > 0"
        );
    }
    let (dt_s, dt_auto, dt_speed) = crate::cli::DtArg::overrides(args.dt);
    let overrides = Overrides {
        profile: args.profile,
        duration_s: args.duration,
        dt_s,
        dt_auto,
        dt_speed,
        stepping: args.stepping,
        integrator: args.integrator,
        tolerance: args.tolerance,
        contact_law: args.contact_law,
        max_relax_s: None,
        sample_rate_hz: Some(args.rate),
    };
    let scene = match crate::cli::load_scene(args.scene.as_deref(), &overrides)? {
        Ok(s) => s,
        Err(lines) => {
            eprintln!("{lines}");
            return Ok(ExitCode::FAILURE);
        }
    };
    let sampling = Sampling {
        rate: SampleRate::new(args.rate, scene.solver().dt_s)
            .map_err(|e| anyhow::anyhow!("--rate {}: {e}", args.rate))?,
        window: StatsWindow::of(&scene, args.window)
            .map_err(|e| anyhow::anyhow!("--window: {e}"))?,
        window_option: args.window,
    };
    // A checkpoint of another scene, version or set of options fails now,
    // before the static equilibrium.
    let resume = args
        .resume
        .as_ref()
        .map(|p| take_up(p, &scene, &sampling))
        .transpose()?;
    // Outputs are opened before anything is simulated: an unwritable path fails now.
    let summary_file = args
        .summary
        .as_ref()
        .map(|p| create(p, "summary"))
        .transpose()?;
    // Numbers are written as text: csv's own float formatting (ryu) would
    // print `1.0` and `1e-5` where the series has always had `1` and `0.00001`.
    let csv = match (&args.series, &resume) {
        (None, _) => None,
        (Some(p), None) => Some(create_file(p, "series")?),
        (Some(p), Some(r)) => Some(continue_series(p, r.checkpoint.run.series_bytes)?),
    }
    .map(csv::Writer::from_writer);
    let recorder = args
        .record
        .as_ref()
        .map(|p| {
            let ck = resume.as_ref().map(|r| &r.checkpoint);
            start_recording(p, &args, &scene, sampling.rate, ck)
        })
        .transpose()?;
    let result = simulate(&args, scene, sampling, summary_file, csv, recorder, resume);
    if result.is_err()
        && let Some(p) = &args.summary
    {
        // A failed run has no summary: leave no empty file that looks like one.
        let _ = std::fs::remove_file(p);
    }
    result
}

/// Opens the recording before anything is simulated (an unwritable path fails
/// now) and attaches the scene file to it.
fn start_recording(
    path: &PathBuf,
    args: &RunArgs,
    scene: &crate::scene::Scene,
    sampling: SampleRate,
    resume: Option<&Checkpoint<CliRun>>,
) -> anyhow::Result<Recorder<BufWriter<File>>> {
    let channels = Channels::parse(&args.record_channels)?;
    let scene_file = match &args.scene {
        Some(p) => (
            p.file_name()
                .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into()),
            std::fs::read(p).with_context(|| format!("cannot read scene {}", p.display()))?,
        ),
        None => (
            "l60mc.toml".to_owned(),
            crate::scene::L60MC_TOML.as_bytes().to_vec(),
        ),
    };
    let options = RecordOptions {
        channels,
        scene_file: Some(scene_file),
        rate_hz: sampling.rate_hz,
    };
    let Some(ck) = resume else {
        let file = create(path, "recording")?;
        return Recorder::new(file, scene, &options)
            .with_context(|| format!("cannot write the recording to {}", path.display()));
    };
    let Some(mark) = ck.run.record else {
        anyhow::bail!(
            "--record {}: the run being resumed was not recorded, so its recording cannot be continued; resume without --record",
            path.display()
        );
    };
    Recorder::continue_file(path, scene, &options, &mark)
        .with_context(|| format!("--record {}", path.display()))
}

/// How the run is sampled and which window its statistics cover.
struct Sampling {
    rate: SampleRate,
    window: StatsWindow,
    /// `--window` as given (`None`: the default window).
    window_option: Option<f64>,
}

fn simulate(
    args: &RunArgs,
    scene: crate::scene::Scene,
    sampling: Sampling,
    mut summary_file: Option<BufWriter<File>>,
    mut csv: Option<csv::Writer<File>>,
    recorder: Option<Recorder<BufWriter<File>>>,
    resume: Option<Resume>,
) -> anyhow::Result<ExitCode> {
    let stop = stop_on_signal();
    if !args.quiet {
        eprintln!("{}", crate::scene::step_note(&scene));
    }
    for w in scene.warnings() {
        eprintln!("warning: {w}");
    }
    let setup = Instant::now();
    // The error's own message holds its causes: printed once, not again as
    // a chain of sources.
    let mut sim = note_slow_setup(args.quiet, || Simulation::new(&scene))
        .map_err(|e| anyhow::anyhow!("cannot start the simulation: {e}"))?;
    let setup_wall_s = setup.elapsed().as_secs_f64();
    // A guide evaluated too seldom for its load at rest: said before the
    // run steps (it may blow up with causes that do not name the guide).
    let guide_warnings: Vec<String> = super::guide_intervals::guide_intervals(&sim)
        .into_iter()
        .filter_map(|(_, w)| w)
        .collect();
    for w in &guide_warnings {
        eprintln!("warning: {w}");
    }
    let duration = scene.solver().duration_s;
    if let Some(csv) = csv.as_mut().filter(|_| resume.is_none()) {
        csv.write_record(series_header(&sim, &scene))
            .map_err(io_error)?;
    }
    let progress = progress_bar(args.quiet, duration);
    // Where the power goes and the means, counted every step of the
    // summary's window. Memory flat whatever the duration: the series goes
    // to disk as it is taken, the summary needs the window's rows and the
    // running spectra.
    let mut signals = sampling.window.observe(&mut sim, sampling.rate.rate_hz);
    let mut so_far = RunOutcome {
        steps: 0,
        wall_s: 0.0,
        interrupted: false,
        max_penetration_m: 0.0,
        stage_times: None,
    };
    if let Some(Resume {
        checkpoint: ck,
        window_restarts,
    }) = resume
    {
        signals = resume_run(&mut sim, ck, window_restarts, &sampling, &mut so_far)?;
    }
    let mut observer = CliObserver {
        signals,
        csv,
        csv_error: None,
        progress,
        recorder,
        guides: scene.guides().len(),
    };
    sim.timings = args.timings;
    let checkpoints = args.checkpoint.as_deref().zip(args.checkpoint_every);
    let outcome = run_with_checkpoints(
        &mut sim,
        &scene,
        &mut observer,
        so_far,
        checkpoints,
        &sampling,
        &stop,
    );
    if let Some(p) = &observer.progress {
        p.finish_and_clear();
    }
    finish_series_and_recording(&mut observer, &outcome)?;
    let outcome = outcome?;
    let mut summary = RunSummary::of_run_in(
        &sim,
        &outcome,
        &observer.signals,
        setup_wall_s,
        &sampling.window,
    );
    let guide_warnings_count = guide_warnings.len();
    summary.warnings.extend(guide_warnings);
    if let Some(f) = summary_file.as_mut() {
        serde_json::to_writer_pretty(&mut *f, &summary)?;
        writeln!(f)?;
        f.flush().context("writing the summary failed")?;
    }
    print_summary(&summary, sim.scene.solver().dt_speed);
    // The guides' warnings were said before the run stepped.
    let guides_said = summary.warnings.len() - guide_warnings_count;
    for w in &summary.warnings[..guides_said] {
        eprintln!("warning: {w}");
    }
    if let Some(times) = &outcome.stage_times {
        print_stage_times(times, sim.integration.stats.evaluations);
    }
    Ok(if outcome.interrupted {
        ExitCode::from(130)
    } else {
        ExitCode::SUCCESS
    })
}

/// Ends the run cleanly on Ctrl-C/SIGTERM from here on (also during the
/// static equilibrium: the run then stops at t = 0 with everything
/// written): the flag the run watches.
fn stop_on_signal() -> Arc<AtomicBool> {
    let stop = Arc::new(AtomicBool::new(false));
    {
        let stop = Arc::clone(&stop);
        // A second handler cannot be installed (e.g. in tests calling run twice): ignore.
        let _ = ctrlc::set_handler(move || stop.store(true, Ordering::Relaxed));
    }
    stop
}

/// The series' CSV header: time, each sprocket's speed, each segment's
/// link force and transverse displacement, each tensioner's and guide's
/// outputs.
fn series_header(sim: &Simulation, scene: &crate::scene::Scene) -> Vec<String> {
    let segments = 1..=sim.model.segments.len();
    let header = std::iter::once("t_s".to_owned())
        .chain((1..=scene.sprockets().len()).map(|i| format!("omega_{i}_rad_s")))
        .chain(segments.clone().map(|k| format!("seg{k}_link_force_n")))
        .chain(segments.map(|k| format!("seg{k}_transverse_m")))
        .chain((1..=scene.tensioners().len()).flat_map(|k| {
            [
                "arm_angle_rad",
                "travel_m",
                "plunger_speed_m_s",
                "pressure_pa",
                "valve_open",
                "shoe_force_n",
            ]
            .map(|q| format!("tensioner{k}_{q}"))
        }))
        .chain(
            (1..=scene.guides().len())
                .flat_map(|k| [format!("guide{k}_normal_n"), format!("guide{k}_friction_n")]),
        );
    header.collect()
}

/// A progress bar of the simulated milliseconds, on a terminal unless
/// `quiet`.
fn progress_bar(quiet: bool, duration_s: f64) -> Option<indicatif::ProgressBar> {
    (!quiet && std::io::stderr().is_terminal()).then(|| {
        let p = indicatif::ProgressBar::new((duration_s * 1000.0) as u64);
        p.set_style(
            indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} ms simulated, eta {eta}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        p
    })
}

/// Restores the run of checkpoint `ck` into `sim`, its counts into
/// `so_far`: its signals, their window moved to the run's end.
fn resume_run(
    sim: &mut Simulation,
    ck: Checkpoint<CliRun>,
    window_restarts: bool,
    sampling: &Sampling,
    so_far: &mut RunOutcome,
) -> anyhow::Result<Signals> {
    sim.restore(&ck.sim)
        .context("cannot resume from the checkpoint")?;
    let mut signals = ck.run.signals;
    // The run may now end elsewhere: its window moves with the end.
    let last = sim
        .last_step_sampled(sampling.rate.every)
        .map(|sampled| (sim.sample(), sampled));
    let last = last.as_ref().map(|(s, sampled)| (s, *sampled));
    signals.continue_window(
        &sim.model,
        sampling.window.start_s(),
        sampling.window.length_s(),
        last,
    );
    if window_restarts {
        sim.restart_power(&ck.sim, sampling.window.start_s());
    }
    so_far.steps = ck.run.steps;
    so_far.wall_s = ck.run.wall_s;
    so_far.max_penetration_m = ck.run.max_penetration_m;
    Ok(signals)
}

/// Flushes the series and finishes the recording, however the run ended
/// (`outcome`), saying how.
fn finish_series_and_recording(
    observer: &mut CliObserver,
    outcome: &anyhow::Result<RunOutcome>,
) -> anyhow::Result<()> {
    let flushed = observer.csv.as_mut().map_or(Ok(()), |c| c.flush());
    if let Some(e) = observer.csv_error.take() {
        return Err(e).context("writing the series failed");
    }
    flushed.context("writing the series failed")?;
    // The recording is finished however the run ended, and says how.
    if let Some(r) = observer.recorder.take() {
        let failure = outcome.as_ref().err().map(ToString::to_string);
        let end = match (outcome, &failure) {
            (_, Some(m)) => RunEnd::Failed(m),
            (Ok(o), None) if o.interrupted => RunEnd::Interrupted,
            _ => RunEnd::Completed,
        };
        r.finish(end).context("writing the recording failed")?;
    }
    Ok(())
}

/// Runs to the scene's end, in pieces between checkpoints when asked: every
/// `S` simulated seconds (a whole number of steps, at least one), when
/// interrupted and at the end. The pieces step as one run would ([`Simulation::run`]'s
/// clock counts the steps from the start).
fn run_with_checkpoints(
    sim: &mut Simulation,
    scene: &crate::scene::Scene,
    observer: &mut CliObserver,
    mut so_far: RunOutcome,
    checkpoints: Option<(&Path, f64)>,
    sampling: &Sampling,
    stop: &AtomicBool,
) -> anyhow::Result<RunOutcome> {
    let dt = scene.solver().dt_s;
    let duration = scene.solver().duration_s;
    loop {
        let until = match checkpoints {
            Some((_, every)) => next_checkpoint_s(sim.state.t_s, dt, every, duration),
            None => duration,
        };
        let piece = sim.run(until, sampling.rate.every, observer, Some(stop))?;
        so_far.steps += piece.steps;
        so_far.wall_s += piece.wall_s;
        so_far.max_penetration_m = so_far.max_penetration_m.max(piece.max_penetration_m);
        so_far.interrupted = piece.interrupted;
        merge_stage_times(&mut so_far.stage_times, piece.stage_times);
        let done = piece.interrupted || run_is_done(sim.state.t_s, dt, duration);
        // At the end too: a finished run can be continued to a later end.
        if let Some((path, _)) = checkpoints {
            write_run_checkpoint(path, sim, scene, observer, &so_far, sampling)?;
        }
        if done {
            return Ok(so_far);
        }
    }
}

/// Adds a piece's stage times to the run's.
fn merge_stage_times(total: &mut Option<StageTimes>, piece: Option<StageTimes>) {
    let Some(piece) = piece else {
        return;
    };
    let Some(t) = total else {
        *total = Some(piece);
        return;
    };
    t.add(piece);
}

fn print_stage_times(t: &StageTimes, evaluations: u64) {
    let steps = t.steps.max(1) as f64;
    let total = t.stepping_s + t.blow_up_checks_s + t.observers_s;
    println!(
        "stage timings ({} steps, {} force evaluations; the clock reads add ~25 ns per element and evaluation):",
        t.steps, evaluations
    );
    println!("stage              wall_s    ns/step  share");
    let stages = t.force_elements.iter().copied().chain([
        ("integrator", t.integrator_s()),
        ("blow-up checks", t.blow_up_checks_s),
        ("observers", t.observers_s),
    ]);
    for (name, secs) in stages {
        println!(
            "{name:<16} {secs:>8.3}  {:>9.0}  {:>4.1} %",
            secs * 1e9 / steps,
            100.0 * secs / total.max(f64::MIN_POSITIVE)
        );
    }
}

/// The run's headline; `dt_speed` names a step chosen by `dt_s = "speed"`,
/// which the summary counts with the automatic steps (`dt_auto`).
fn print_summary(s: &RunSummary, dt_speed: bool) {
    println!(
        "{} — {} profile, {}, {} ({}), dt {:e} s{}",
        s.scene,
        s.profile,
        s.contact_law,
        s.integrator,
        s.stepping,
        s.dt_s,
        match (s.dt_auto, dt_speed) {
            (true, true) => " (speed)",
            (true, false) => " (auto)",
            (false, _) => "",
        }
    );
    println!(
        "simulated {:.3} s{} in {:.2} s wall ({} steps, {:.0} ns/step; setup {:.2} s)",
        s.duration_s,
        if s.interrupted { " (interrupted)" } else { "" },
        s.wall_s,
        s.steps,
        s.ns_per_step,
        s.setup_wall_s
    );
    println!(
        "static tension {:.0} N (rest length {:.6} m); window {:.2}–{:.2} s: link force {:.0} … {:.0} N",
        s.static_tension_n,
        s.rest_length_m,
        s.window_s[0],
        s.window_s[1],
        s.link_force_min_n,
        s.link_force_max_n
    );
    println!(
        "segment  length_m  mean_force_n  ±se_n  rms_n  p2p_n  stationary  transverse_peak_hz  string_f1_hz"
    );
    for (seg, st) in s.segments.iter().zip(&s.strands) {
        println!(
            "{:>7}  {:>8.4}  {:>12.0}  {:>5.0}  {:>5.0}  {:>5.0}  {:>10}  {:>18.2}  {:>12.2}",
            seg.segment,
            st.length_m,
            seg.mean_link_force_n,
            seg.mean_link_force_se_n,
            seg.link_force_rms_n,
            seg.link_force_p2p_n,
            if seg.stationary { "yes" } else { "NO" },
            seg.transverse_peak_hz,
            seg.string_f1_hz
        );
    }
    println!(
        "sprocket  mean_speed_rad_s  speed_rms_rad_s  speed_p2p_rad_s  mean_torque_n_m  max_bearing_force_n"
    );
    for sp in &s.sprockets {
        println!(
            "{:>8}  {:>16.4}  {:>15.4}  {:>15.4}  {:>15.1}  {:>19.0}",
            sp.sprocket,
            sp.mean_speed_rad_s,
            sp.speed_rms_rad_s,
            sp.speed_p2p_rad_s,
            sp.mean_torque_n_m,
            sp.max_bearing_force_n
        );
    }
    println!(
        "driver mean power {:.0} W; max penetration {:.1} µm",
        s.driver_mean_power_w,
        s.max_penetration_m * 1e6
    );
    if let Some(c) = &s.worn_chain {
        let slack = c
            .extra_slack_m
            .map(|m| format!("; {:.1} mm of slack on fixed centres", m * 1e3))
            .unwrap_or_default();
        println!(
            "worn chain: elongation {} %, pitch {:.6} m{slack}",
            c.elongation_pct, c.worn_pitch_m
        );
    }
    if let Some(w) = &s.wear {
        println!(
            "wear: {:.4} % per 1000 h (k = {:e}, H = {:.2} GPa; pin load {:.0} N, articulation {:.3} rad/s per joint); life to {} %: {}",
            w.elongation_pct_per_1000h,
            w.wear_coefficient,
            w.hardness_pa * 1e-9,
            w.mean_pin_load_n,
            w.articulation_rad_s,
            w.elongation_limit_pct,
            w.life_h
        );
    }
    if let Some(f) = &s.fatigue {
        println!("{}", fatigue_line(f));
    }
}

/// The fatigue life in one line: the life, the largest cycle against the
/// limit, where the damage is largest.
fn fatigue_line(f: &crate::analysis::design::Fatigue) -> String {
    let rate = if f.damage_per_hour > 0.0 {
        format!(" ({:.3e} damage per hour)", f.damage_per_hour)
    } else {
        String::new()
    };
    let place = f.least_life_at.as_ref().map_or(String::new(), |p| {
        if p.damage_share > 0.0 {
            format!("; most damage {} ({:.0} %)", p.text, 100.0 * p.damage_share)
        } else {
            format!("; largest cycle {}", p.text)
        }
    });
    format!(
        "fatigue life {}{rate}: largest cycle {:.2} kN as a pulsating one, {:.2} of the fatigue limit {:.2} kN{place}",
        f.life_h,
        f.largest_cycle_n * 1e-3,
        f.largest_cycle_n / f.fatigue_limit_n,
        f.fatigue_limit_n * 1e-3
    )
}

/// Runs `setup` (building the drive and settling it to static equilibrium),
/// printing a line to stderr once it has taken a second, naming what it is
/// solving (the chain new at its pretension, a worn chain's wear step, a
/// sprocket let go), and another while it goes on, when that changed or
/// half a minute passed, so that a slow settle is not silent; nothing with
/// `quiet`.
pub(super) fn note_slow_setup<T>(quiet: bool, setup: impl FnOnce() -> T) -> T {
    use std::sync::mpsc::RecvTimeoutError;
    use std::time::Duration;
    if quiet {
        return setup();
    }
    let (done, wait) = std::sync::mpsc::channel::<()>();
    let setting_up = std::thread::current().id();
    std::thread::scope(|s| {
        s.spawn(move || {
            let started = Instant::now();
            let mut last: Option<(String, Instant)> = None;
            let mut tick = Duration::from_secs(1);
            while let Err(RecvTimeoutError::Timeout) = wait.recv_timeout(tick) {
                tick = Duration::from_millis(500);
                let stage = crate::sim::setup_stage::stage(setting_up).unwrap_or_default();
                let due = last.as_ref().is_none_or(|(said, at)| {
                    let quiet_for = at.elapsed().as_secs_f64();
                    (*said != stage && quiet_for >= 5.0) || quiet_for >= 30.0
                });
                if !due {
                    continue;
                }
                let solving = if stage.is_empty() {
                    String::new()
                } else {
                    format!(": {stage}")
                };
                eprintln!(
                    "settling the drive to static equilibrium{solving} (still at it after {:.1} s)…",
                    started.elapsed().as_secs_f64()
                );
                last = Some((stage, Instant::now()));
            }
        });
        let out = setup();
        // The note's thread may have ended already: nothing to tell it then.
        let _ = done.send(());
        out
    })
}
