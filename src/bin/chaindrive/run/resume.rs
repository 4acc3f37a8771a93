//! `chaindrive run`'s checkpoints: what they keep besides the simulation,
//! taking one up (the same scene and options, an end not before it, a
//! statistics window that can be continued), the series continued from it,
//! and writing one. The recording's continuation is `start_recording`'s.

use std::fs::File;
use std::path::Path;

use anyhow::Context;
use chaindrive::analysis::{DEFAULT_WINDOW_S, Signals};
use chaindrive::record::{RecordMark, Recorder};
use chaindrive::sim::checkpoint::{Checkpoint, read_checkpoint_to_continue, write_checkpoint};
use chaindrive::sim::{RunOutcome, Simulation};
use serde::{Deserialize, Serialize};

use super::{CliObserver, Sampling};

/// What a checkpoint keeps of `chaindrive run` besides the simulation.
#[derive(Clone, Serialize, Deserialize)]
pub(super) struct CliRun {
    pub(super) rate_hz: f64,
    /// `--window` as given (`None`: the default).
    pub(super) window: Option<f64>,
    /// Where the statistics window started, s (its accumulators count from there).
    pub(super) window_from_s: f64,
    pub(super) signals: Signals,
    /// Steps, wall time and largest penetration so far.
    pub(super) steps: u64,
    pub(super) wall_s: f64,
    pub(super) max_penetration_m: f64,
    /// Bytes of the series file written up to the checkpoint (`None`: no series).
    pub(super) series_bytes: Option<u64>,
    /// Where the recording stood at the checkpoint (`None`: no recording).
    #[serde(default)]
    pub(super) record: Option<RecordMark>,
}

/// A checkpoint taken up by a resumed run, and whether the statistics
/// window's accumulators start anew (the run now ends elsewhere).
pub(super) struct Resume {
    pub(super) checkpoint: Checkpoint<CliRun>,
    pub(super) window_restarts: bool,
}

/// Reads the checkpoint at `path` for a run of `scene` sampled as `sampling`: the
/// same scene and options, an end not before the checkpoint's time, and a
/// statistics window that can be continued.
pub(super) fn take_up(
    path: &Path,
    scene: &chaindrive::scene::Scene,
    sampling: &Sampling,
) -> anyhow::Result<Resume> {
    let ck: Checkpoint<CliRun> = read_checkpoint_to_continue(path, scene)?;
    let shown = |w: Option<f64>| {
        w.map_or_else(
            || "without --window".to_owned(),
            |w| format!("--window {w}"),
        )
    };
    anyhow::ensure!(
        ck.run.rate_hz.to_bits() == sampling.rate.rate_hz.to_bits()
            && ck.run.window.map(f64::to_bits) == sampling.window_option.map(f64::to_bits),
        "checkpoint {}: the run was started with --rate {} and {}, not --rate {} and {}: resume with the same options",
        path.display(),
        ck.run.rate_hz,
        shown(ck.run.window),
        sampling.rate.rate_hz,
        shown(sampling.window_option),
    );
    let t_s = ck.sim.t_s();
    let window_restarts = ck
        .sim
        .window_restarts(ck.run.window_from_s, sampling.window.start_s())
        .with_context(|| {
            // Any longer run's window, of this length, starts after the checkpoint.
            let length_s = sampling.window_option.unwrap_or(DEFAULT_WINDOW_S);
            format!(
                "--duration {}: the statistics window ({} to {} s) cannot be continued from checkpoint {} (t = {t_s} s); a --duration of at least {} s puts it after the checkpoint",
                scene.solver().duration_s,
                sampling.window.start_s(),
                scene.solver().duration_s,
                path.display(),
                // To the nanosecond: 0.6, not 0.6000000000000001.
                ((t_s + length_s) * 1e9).round() / 1e9
            )
        })?;
    Ok(Resume {
        checkpoint: ck,
        window_restarts,
    })
}

/// Opens the series of a run being resumed, cut back to its length at the
/// checkpoint, for the rows after it.
pub(super) fn continue_series(path: &Path, bytes: Option<u64>) -> anyhow::Result<File> {
    let Some(bytes) = bytes else {
        anyhow::bail!(
            "--series {}: the run being resumed wrote no series, so it cannot be continued; resume without --series",
            path.display()
        );
    };
    let file = std::fs::OpenOptions::new()
        .append(true)
        .open(path)
        .with_context(|| format!("cannot continue the series {}", path.display()))?;
    let len = file.metadata()?.len();
    anyhow::ensure!(
        len >= bytes,
        "--series {}: the file holds {len} bytes, fewer than the {bytes} written up to the checkpoint: give the series file the run was writing",
        path.display()
    );
    file.set_len(bytes)?;
    Ok(file)
}

/// Writes the run's checkpoint to `path`, the series synced first (the
/// checkpoint counts its bytes).
pub(super) fn write_run_checkpoint(
    path: &Path,
    sim: &Simulation,
    scene: &chaindrive::scene::Scene,
    observer: &mut CliObserver,
    so_far: &RunOutcome,
    sampling: &Sampling,
) -> anyhow::Result<()> {
    let series_bytes = match observer.csv.as_mut() {
        Some(csv) => {
            csv.flush().context("writing the series failed")?;
            let file = csv.get_ref();
            file.sync_data().context("writing the series failed")?;
            Some(file.metadata()?.len())
        }
        None => None,
    };
    let run = CliRun {
        rate_hz: sampling.rate.rate_hz,
        window: sampling.window_option,
        window_from_s: sampling.window.start_s(),
        signals: observer.signals.clone(),
        steps: so_far.steps,
        wall_s: so_far.wall_s,
        max_penetration_m: so_far.max_penetration_m,
        series_bytes,
        record: observer.recorder.as_mut().map(Recorder::mark).transpose()?,
    };
    let ck = Checkpoint {
        sim: sim.snapshot()?,
        run,
    };
    Ok(write_checkpoint(path, scene, &ck)?)
}
