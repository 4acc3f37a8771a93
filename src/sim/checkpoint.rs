//! Checkpoints: a running [`Simulation`]'s complete state at a step's end,
//! written to a file and read back, so that a run continued from it gives
//! the same bits as a run that never stopped.
//!
//! What is kept ([`Snapshot`]): the state (rollers, sprockets, further
//! bodies' coordinates and scalar states, the clock), the forces of the last
//! evaluation (the integrators start each step from them: the adaptive
//! scheme's first stage is their rates, FSAL), every force element's history
//! ([`crate::forces::ForceElement::save_history`]: the contact's remembered
//! onsets, gap hints and kept reach sets, its damping rows), the integrator's
//! carried state (the adaptive step's proposal, the counters), the growth
//! detector's history and the power ledger (and the ledger a window starting
//! at the last step would hold, for a run continued to another end). The
//! caller adds what its observers accumulated ([`Checkpoint::run`]).
//!
//! What is rebuilt, not kept: the drive itself (its layout and static
//! equilibrium are computed again from the scene, deterministically), the
//! rapier world (written from the state), the integrators' stage buffers (set
//! at every step's start), and the contact's runs of rollers within reach,
//! a function of the kept reach sets (the culling changes no bit:
//! `culling_changes_nothing`).
//!
//! # Continuing to another end
//!
//! The run's planned end (`solver.duration_s`) is not part of the state: a
//! checkpoint read with [`read_checkpoint_to_continue`] goes on to any end
//! not before its own time, and the result is the run of that duration
//! done at once. What was planned from the end is the statistics window
//! (`crate::analysis::StatsWindow` of the new end: the last second after
//! the ramps, or the length chosen). Its accumulators (the power ledger, an
//! observer's integrals and extremes over every step)
//! either go on, when the window starts where the run's did, or start anew,
//! when the window now starts after the step before the checkpoint's last
//! one ([`Snapshot::window_restarts`], [`Simulation::restart_power`]). A
//! window that would hold earlier steps of the checkpoint's run, after the
//! start of the one that run counted, is refused: sums over it cannot be
//! taken apart again.
//!
//! # The file
//!
//! `chaindrive-ckpt\n`, then a header and the body, each a CBOR item (RFC
//! 8949, by `ciborium`) after its length as 8 bytes little-endian. CBOR
//! keeps every `f64` bit for bit, infinities included (JSON has no
//! infinity, and the contact's reach expiry and the adaptive step's first
//! proposal are infinite). The header holds the format number
//! ([`FORMAT`]), the crate version, a hash of the scene without its duration
//! ([`scene_hash`]), the scene's fields as its file form writes them (to
//! name what differs) and the planned duration; a checkpoint of another
//! scene, version or format is refused before its body is read, naming the
//! fields that differ.
//!
//! Files are written beside their place (`PATH.partial.<process id>`),
//! synced, renamed over it, and the directory synced: a process killed at
//! any moment leaves the previous checkpoint whole (and perhaps the
//! partial file of the one it was writing, which nothing reads).
//!
//! Only the substepped stepping is checkpointed: rapier keeps solver state
//! of its own.

use std::io::Write;
use std::path::{Path, PathBuf};

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use super::{Clock, GrowthWatch, IntegrationStats, PowerLedger, Simulation};
use crate::forces::{Forces, History};
use crate::model::DriveState;
use crate::scene::{Scene, Stepping};
use std::collections::BTreeMap;

/// The checkpoint file format's number; a change of what is kept raises it
/// (2: the header names the scene's fields and its end; 3: the observers'
/// signals carry their integrals over every step and the links' fatigue
/// count).
pub(crate) const FORMAT: u32 = 3;

const MAGIC: &[u8; 16] = b"chaindrive-ckpt\n";

/// Why a checkpoint cannot be written or taken up.
#[derive(Debug, thiserror::Error)]
pub enum CheckpointError {
    /// Reading or writing the file failed.
    #[error("checkpoint {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The file is not a checkpoint, or is damaged.
    #[error("{path} is not a chaindrive checkpoint, or is damaged ({reason})")]
    NotACheckpoint {
        /// The file.
        path: PathBuf,
        /// What was wrong.
        reason: String,
    },
    /// Written by another version of chaindrive or another file format.
    #[error(
        "checkpoint {path} was written by chaindrive {found_version} (checkpoint format {found_format}); \
         this is chaindrive {version} (format {format}): a checkpoint is only taken up by the version that wrote it"
    )]
    OtherVersion {
        /// The file.
        path: PathBuf,
        /// Version that wrote it.
        found_version: String,
        /// Its format.
        found_format: u32,
        /// This version.
        version: String,
        /// This format.
        format: u32,
    },
    /// Written for another scene (or the same with other overrides).
    #[error(
        "checkpoint {path} was written for another scene ({}): resume with the scene file and the options that started the run",
        differences.join("; ")
    )]
    OtherScene {
        /// The file.
        path: PathBuf,
        /// What differs, field by field (`path: value there, value here`).
        differences: Vec<String>,
    },
    /// The run would end before the checkpoint's time.
    #[error(
        "checkpoint {path} was taken at t = {t_s} s, after the end of this run (solver.duration_s = {duration_s} s): continue it to a duration of at least {t_s} s"
    )]
    EndsBefore {
        /// The file.
        path: PathBuf,
        /// The checkpoint's time, s.
        t_s: f64,
        /// This run's duration, s.
        duration_s: f64,
    },
    /// The statistics window of the run continued to another end would
    /// hold steps the checkpoint's run counted in another window.
    #[error(
        "the statistics window would start at {from_s} s, not where the checkpoint's run counted it from ({was_from_s} s) and not after its steps up to t = {step_s} s: what was summed over them cannot be taken apart; continue to an end whose window starts after the checkpoint's time"
    )]
    WindowMoved {
        /// Where the window would start, s.
        from_s: f64,
        /// Where the checkpoint's run counted it from, s.
        was_from_s: f64,
        /// The step before the checkpoint's last, s.
        step_s: f64,
    },
    /// The saved state does not fit the drive (another make-up).
    #[error("checkpoint does not fit the drive: {what}")]
    Mismatch {
        /// What differs.
        what: String,
    },
    /// The scene steps with rapier.
    #[error(
        "checkpoints need solver.stepping = \"substepped\" (rapier keeps solver state of its own that a checkpoint does not hold)"
    )]
    Stepping,
}

/// A [`Simulation`]'s state at a step's end (module docs).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Snapshot {
    clock: Clock,
    state: DriveState,
    forces: Forces,
    histories: Vec<(String, History)>,
    next_step_s: f64,
    stats: IntegrationStats,
    growth: GrowthWatch,
    power: Option<PowerLedger>,
    /// The power ledger of a window that starts at the last step (`None`
    /// without power tracking, or before the first step).
    power_from_last_step: Option<PowerLedger>,
    rest_length_m: f64,
    /// The joints' sliding (absent from checkpoints written before it).
    #[serde(default)]
    sliding: Option<super::JointSliding>,
    /// The tooth-jump detector's state (absent from older checkpoints: a
    /// resumed run then starts watching afresh).
    #[serde(default)]
    jumps: Option<super::JumpWatch>,
}

impl Snapshot {
    /// Simulated time, s.
    pub(crate) fn t_s(&self) -> f64 {
        self.state.t_s
    }

    /// The time of the step before the last one, as the run computed it
    /// (−∞ if fewer than two steps were taken since the clock started).
    fn step_before_last_s(&self) -> f64 {
        match self.clock.steps.checked_sub(1) {
            Some(k) if k > 0 => self.clock.origin_s + k as f64 * self.clock.dt_s,
            _ => f64::NEG_INFINITY,
        }
    }

    /// Whether a run continued from here to another end, whose statistics
    /// window now starts at `from_s`, starts its window accumulators anew
    /// (`true`) or goes on with those the checkpoint's run counted from
    /// `was_from_s` (`false`: the same start, bit for bit). Anew is right
    /// when the window starts after the step before the last one: a run with
    /// this window from the start has counted at most the last step
    /// ([`Simulation::restart_power`] and the observers take it up again).
    /// Otherwise the window would hold steps that were counted in another
    /// window: [`CheckpointError::WindowMoved`].
    pub(crate) fn window_restarts(
        &self,
        was_from_s: f64,
        from_s: f64,
    ) -> Result<bool, CheckpointError> {
        if from_s.to_bits() == was_from_s.to_bits() {
            return Ok(false);
        }
        let step_s = self.step_before_last_s();
        if step_s < from_s {
            Ok(true)
        } else {
            Err(CheckpointError::WindowMoved {
                from_s,
                was_from_s,
                step_s,
            })
        }
    }
}

/// What a checkpoint file holds: the simulation and what the caller keeps
/// of the run (its observers' accumulated signals, counters).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Checkpoint<T> {
    /// The simulation.
    pub sim: Snapshot,
    /// The caller's part.
    pub run: T,
}

#[derive(Serialize, Deserialize)]
struct Header {
    format: u32,
    version: String,
    scene_hash: String,
    /// The scene's fields as its file form writes them, `(path, value)`.
    scene_fields: Vec<(String, String)>,
    /// The run's planned end, s.
    duration_s: f64,
}

impl Simulation {
    /// The simulation's state for a checkpoint. Call between runs
    /// ([`Simulation::run`] returns at a step's end).
    pub fn snapshot(&self) -> Result<Snapshot, CheckpointError> {
        if self.scene.solver.stepping != Stepping::Substepped {
            return Err(CheckpointError::Stepping);
        }
        let (next_step_s, stats) = self.integration.carried();
        // Counted here, where the links' stretches are those of the state
        // (a restored simulation has not evaluated its forces again).
        let power_from_last_step = self
            .power
            .as_ref()
            .filter(|_| self.clock.steps > 0)
            .map(|_| {
                let mut ledger = PowerLedger::new(self.state.t_s);
                ledger.step(&self.model, &self.state, &self.forces);
                ledger
            });
        Ok(Snapshot {
            clock: self.clock,
            state: self.state.clone(),
            forces: self.forces.output().clone(),
            histories: self.forces.save_histories(),
            next_step_s,
            stats,
            growth: self.growth.clone(),
            power: self.power.clone(),
            power_from_last_step,
            rest_length_m: self.model.rest_length_m,
            sliding: self.sliding.clone(),
            jumps: Some(self.jumps.clone()),
        })
    }

    /// Takes up a [`Snapshot`] of a simulation built from the same scene
    /// (by [`Simulation::new`], with the same elements added): the next
    /// [`Simulation::run`] goes on as the one that took the snapshot would
    /// have.
    pub fn restore(&mut self, snapshot: &Snapshot) -> Result<(), CheckpointError> {
        if self.scene.solver.stepping != Stepping::Substepped {
            return Err(CheckpointError::Stepping);
        }
        let mismatch = |what: String| CheckpointError::Mismatch { what };
        let (s, saved) = (&self.state, &snapshot.state);
        let sizes = |d: &DriveState| {
            [
                d.x.len(),
                d.y.len(),
                d.vx.len(),
                d.vy.len(),
                d.theta.len(),
                d.omega.len(),
                d.q.len(),
                d.u.len(),
                d.z.len(),
            ]
        };
        if sizes(s) != sizes(saved) {
            return Err(mismatch(format!(
                "state sizes (rollers, sprockets, bodies, scalars) {:?}, the drive's {:?}",
                sizes(saved),
                sizes(s)
            )));
        }
        if snapshot.rest_length_m.to_bits() != self.model.rest_length_m.to_bits() {
            return Err(mismatch(format!(
                "links' rest length {} m, the drive's {} m",
                snapshot.rest_length_m, self.model.rest_length_m
            )));
        }
        self.forces
            .restore_histories(&snapshot.histories)
            .map_err(|(element, e)| mismatch(format!("force element {element}: {e}")))?;
        self.forces.restore_output(snapshot.forces.clone());
        self.state.clone_from(&snapshot.state);
        self.clock = snapshot.clock;
        self.integration.carry(snapshot.next_step_s, snapshot.stats);
        self.growth = snapshot.growth.clone();
        self.power.clone_from(&snapshot.power);
        if snapshot.sliding.is_some() {
            self.sliding.clone_from(&snapshot.sliding);
        }
        if let Some(jumps) = &snapshot.jumps {
            self.jumps.clone_from(jumps);
        }
        self.sync_world();
        Ok(())
    }

    /// After [`Simulation::restore`], for a run continued to another end
    /// whose statistics window now starts at `from_s` (when
    /// [`Snapshot::window_restarts`] says so): the power ledger, if one is
    /// kept, starts anew there, holding the last step if the window does.
    pub(crate) fn restart_power(&mut self, snapshot: &Snapshot, from_s: f64) {
        if self.power.is_none() {
            return;
        }
        self.power = Some(match &snapshot.power_from_last_step {
            Some(ledger) if snapshot.state.t_s >= from_s => ledger.clone().counting_from(from_s),
            _ => PowerLedger::new(from_s),
        });
    }

    /// Whether the last step was sampled at one sample every `sample_every`
    /// steps (as [`Simulation::run`] samples); `None` before the first step.
    pub(crate) fn last_step_sampled(&self, sample_every: u64) -> Option<bool> {
        (self.clock.steps > 0).then(|| self.clock.steps % sample_every.max(1) == 0)
    }
}

/// Where the next piece of a run checkpointed every `every_s` simulated
/// seconds ends: the next whole multiple of the period (rounded to whole
/// steps of `dt_s`, at least one) after `t_s`, but not after the run's end
/// `duration_s`. A run stepped in these pieces checkpoints at t = k·S
/// whether it started at 0 or was resumed.
pub fn next_checkpoint_s(t_s: f64, dt_s: f64, every_s: f64, duration_s: f64) -> f64 {
    let last_step = (duration_s / dt_s).round();
    let per = (every_s / dt_s).round().max(1.0);
    let next = ((t_s / dt_s).round() / per).floor() * per + per;
    next.min(last_step) * dt_s
}

/// Whether a run at `t_s` has reached its end `duration_s` (in whole steps).
pub fn run_is_done(t_s: f64, dt_s: f64, duration_s: f64) -> bool {
    (t_s / dt_s).round() >= (duration_s / dt_s).round()
}

/// A hash of the validated scene (its every field, numbers bit for bit, its
/// tables' texts, its duration aside, and neither the scene file's text nor
/// its directory nor where its tables were read from: a comment or a path
/// changes no result): 16 hex digits of FNV-1a (64 bit)
/// over its debug form. Stable for one version of the crate, which is all a
/// checkpoint needs.
pub(crate) fn scene_hash(scene: &Scene) -> String {
    let mut scene = scene.clone();
    scene.solver.duration_s = 0.0;
    scene.file.solver.duration_s = 0.0;
    scene.file.base_dir = None;
    scene.file.given_tables.clear();
    scene.source_toml = None;
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in format!("{scene:?}").bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// The path of the planned end among [`scene_fields`].
const DURATION_FIELD: &str = "solver.duration_s";

/// The scene's fields as its file form writes them (the overrides written
/// in), flattened to `(path, value)`: `sprockets[0].speed_rpm`, `1000.0`.
fn scene_fields(scene: &Scene) -> Vec<(String, String)> {
    fn flatten(path: &str, value: &serde_json::Value, out: &mut Vec<(String, String)>) {
        match value {
            serde_json::Value::Object(fields) => {
                for (name, v) in fields {
                    let path = if path.is_empty() {
                        name.clone()
                    } else {
                        format!("{path}.{name}")
                    };
                    flatten(&path, v, out);
                }
            }
            serde_json::Value::Array(items) => {
                for (i, v) in items.iter().enumerate() {
                    flatten(&format!("{path}[{i}]"), v, out);
                }
            }
            serde_json::Value::Null => out.push((path.to_owned(), "not set".to_owned())),
            leaf => out.push((path.to_owned(), leaf.to_string())),
        }
    }
    let mut out = Vec::new();
    // A file form that cannot be written out names nothing (the hash still
    // tells scenes apart).
    if let Ok(value) = serde_json::to_value(&scene.file) {
        flatten("", &value, &mut out);
    }
    // Not a field of the file: the run's rate, which an automatic step divides.
    if let Some(period_s) = scene.file.solver.sample_period_s {
        // To the micro-hertz: 21800, not 21799.999999999996.
        let rate_hz = (1e6 / period_s).round() / 1e6;
        out.push((SAMPLE_RATE_FIELD.to_owned(), format!("{rate_hz} Hz")));
    }
    out
}

/// What [`scene_fields`] calls the sample rate an automatic step divides.
const SAMPLE_RATE_FIELD: &str = "sample rate (--rate, which the automatic step divides)";

/// What differs between the fields a checkpoint was written with (`there`)
/// and `here`'s, at most a few, with how many more; the duration left out
/// unless `with_duration`.
fn differences(
    there: &[(String, String)],
    here: &[(String, String)],
    with_duration: bool,
) -> Vec<String> {
    const SHOWN: usize = 6;
    let there: BTreeMap<_, _> = there
        .iter()
        .map(|(p, v)| (p.as_str(), v.as_str()))
        .collect();
    let here: BTreeMap<_, _> = here.iter().map(|(p, v)| (p.as_str(), v.as_str())).collect();
    let mut paths: Vec<&str> = there.keys().chain(here.keys()).copied().collect();
    paths.sort_unstable();
    paths.dedup();
    let mut found: Vec<String> = paths
        .into_iter()
        .filter(|p| with_duration || *p != DURATION_FIELD)
        .filter_map(|p| match (there.get(p), here.get(p)) {
            (Some(a), Some(b)) if a != b => Some(format!("{p}: {a} there, {b} here")),
            (Some(a), None) => Some(format!("{p}: {a} there, absent here")),
            (None, Some(b)) => Some(format!("{p}: absent there, {b} here")),
            _ => None,
        })
        .collect();
    if found.len() > SHOWN {
        let more = found.len() - SHOWN;
        found.truncate(SHOWN);
        found.push(format!("and {more} more"));
    }
    if found.is_empty() {
        // The same fields with other data behind them: a file the scene
        // reads (a load table), or a field the file form does not show.
        found.push(
            "the scene's fields are the same, but data it reads (a table file) differ".to_owned(),
        );
    }
    found
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> CheckpointError + '_ {
    move |source| CheckpointError::Io {
        path: path.to_owned(),
        source,
    }
}

fn cbor<T: Serialize>(value: &T, path: &Path) -> Result<Vec<u8>, CheckpointError> {
    let mut bytes = Vec::new();
    ciborium::into_writer(value, &mut bytes).map_err(|e| CheckpointError::Io {
        path: path.to_owned(),
        source: std::io::Error::other(e.to_string()),
    })?;
    Ok(bytes)
}

/// Writes `checkpoint` of a run of `scene` to `path`, atomically: to a file
/// beside it, synced, then renamed over `path` (module docs).
pub fn write_checkpoint<T: Serialize>(
    path: &Path,
    scene: &Scene,
    checkpoint: &Checkpoint<T>,
) -> Result<(), CheckpointError> {
    let header = cbor(
        &Header {
            format: FORMAT,
            version: env!("CARGO_PKG_VERSION").to_owned(),
            scene_hash: scene_hash(scene),
            scene_fields: scene_fields(scene),
            duration_s: scene.solver.duration_s,
        },
        path,
    )?;
    let body = cbor(checkpoint, path)?;
    write_parts(path, &header, &body)
}

/// Writes the marker, the header and the body to a file beside `path`,
/// syncs it and renames it over `path`.
fn write_parts(path: &Path, header: &[u8], body: &[u8]) -> Result<(), CheckpointError> {
    // The process id in the name: two processes writing the same
    // checkpoint (a task and its requeued copy) never share the aside file.
    let mut aside = path.as_os_str().to_owned();
    aside.push(format!(".partial.{}", std::process::id()));
    let aside = PathBuf::from(aside);
    let write = || -> std::io::Result<()> {
        let mut f = std::fs::File::create(&aside)?;
        f.write_all(MAGIC)?;
        for part in [header, body] {
            f.write_all(&(part.len() as u64).to_le_bytes())?;
            f.write_all(part)?;
        }
        f.sync_all()?;
        std::fs::rename(&aside, path)?;
        sync_directory(path)
    };
    write().map_err(io(path))
}

/// Syncs the directory holding `path`, so that a rename into it outlasts a
/// crash of the machine (the file's own sync keeps its bytes, not its name).
#[cfg(unix)]
fn sync_directory(path: &Path) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    std::fs::File::open(dir)?.sync_all()
}

/// Directories cannot be opened as files here: the rename is all there is.
#[cfg(not(unix))]
fn sync_directory(_path: &Path) -> std::io::Result<()> {
    Ok(())
}

/// Reads a checkpoint for a run of `scene` from `path`; refuses one of
/// another scene (its duration included), version or format.
pub fn read_checkpoint<T: DeserializeOwned>(
    path: &Path,
    scene: &Scene,
) -> Result<Checkpoint<T>, CheckpointError> {
    read(path, scene, false)
}

/// Reads a checkpoint to continue its run in a run of `scene`, which may
/// end elsewhere (module docs, “Continuing to another end”): refuses one of
/// another scene (the duration aside), version or format, or taken after
/// `scene`'s end.
pub(crate) fn read_checkpoint_to_continue<T: DeserializeOwned>(
    path: &Path,
    scene: &Scene,
) -> Result<Checkpoint<T>, CheckpointError> {
    read(path, scene, true)
}

fn read<T: DeserializeOwned>(
    path: &Path,
    scene: &Scene,
    other_end: bool,
) -> Result<Checkpoint<T>, CheckpointError> {
    let bytes = std::fs::read(path).map_err(io(path))?;
    let bad = |reason: &str| CheckpointError::NotACheckpoint {
        path: path.to_owned(),
        reason: reason.to_owned(),
    };
    let rest = bytes
        .strip_prefix(MAGIC.as_slice())
        .ok_or_else(|| bad("no checkpoint marker at its start"))?;
    let (header, rest) = split_part(rest).ok_or_else(|| bad("truncated header"))?;
    // The format and version first: another format's header may not parse.
    let version: Version = ciborium::from_reader(header).map_err(|e| bad(&e.to_string()))?;
    let this_version = env!("CARGO_PKG_VERSION");
    if version.format != FORMAT || version.version != this_version {
        return Err(CheckpointError::OtherVersion {
            path: path.to_owned(),
            found_version: version.version,
            found_format: version.format,
            version: this_version.to_owned(),
            format: FORMAT,
        });
    }
    let header: Header = ciborium::from_reader(header).map_err(|e| bad(&e.to_string()))?;
    let same_end = header.duration_s.to_bits() == scene.solver.duration_s.to_bits();
    if header.scene_hash != scene_hash(scene) || !(other_end || same_end) {
        return Err(CheckpointError::OtherScene {
            path: path.to_owned(),
            differences: differences(&header.scene_fields, &scene_fields(scene), !other_end),
        });
    }
    let (body, rest) = split_part(rest).ok_or_else(|| bad("truncated body"))?;
    if !rest.is_empty() {
        return Err(bad("bytes after the body"));
    }
    let checkpoint: Checkpoint<T> = ciborium::from_reader(body).map_err(|e| bad(&e.to_string()))?;
    let t_s = checkpoint.sim.t_s();
    let dt_s = scene.solver.dt_s;
    if !run_is_done(scene.solver.duration_s, dt_s, t_s) {
        return Err(CheckpointError::EndsBefore {
            path: path.to_owned(),
            t_s,
            duration_s: scene.solver.duration_s,
        });
    }
    Ok(checkpoint)
}

/// The header's first fields, the same in every format.
#[derive(Deserialize)]
struct Version {
    format: u32,
    version: String,
}

/// A part after its 8-byte length, and what follows it.
fn split_part(bytes: &[u8]) -> Option<(&[u8], &[u8])> {
    let (len, rest) = bytes.split_first_chunk::<8>()?;
    let len = usize::try_from(u64::from_le_bytes(*len)).ok()?;
    (len <= rest.len()).then(|| rest.split_at(len))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file_with(dir: &Path, format: u32, version: &str, scene: &Scene) -> PathBuf {
        let path = dir.join(format!("{format}-{version}.ckpt"));
        let header = Header {
            format,
            version: version.to_owned(),
            scene_hash: scene_hash(scene),
            scene_fields: scene_fields(scene),
            duration_s: scene.solver.duration_s,
        };
        let (header, body) = (
            cbor(&header, &path).expect("header"),
            cbor(&(), &path).expect("body"),
        );
        write_parts(&path, &header, &body).expect("written");
        path
    }

    #[test]
    fn pieces_end_at_whole_multiples_of_the_period() {
        // dt = 1e-5 s, S = 0.05 s = 5000 steps, a 0.12 s run (12 000 steps).
        let next = |t: f64| next_checkpoint_s(t, 1e-5, 0.05, 0.12);
        let steps = |t: f64| (t / 1e-5).round() as u64;
        assert_eq!(steps(next(0.0)), 5000);
        assert_eq!(steps(next(0.05)), 10_000);
        // Resumed from a checkpoint taken when interrupted (step 7 345): the
        // next one is still at 2S.
        assert_eq!(steps(next(0.073_45)), 10_000);
        assert_eq!(steps(next(0.1)), 12_000, "not past the run's end");
        // A period shorter than a step is one step.
        assert_eq!(steps(next_checkpoint_s(0.0, 1e-5, 1e-7, 1.0)), 1);
        assert!(run_is_done(0.12, 1e-5, 0.12) && !run_is_done(0.119_99, 1e-5, 0.12));
    }

    #[test]
    fn another_version_or_format_is_refused() {
        let dir = tempfile::tempdir().expect("tmp");
        let scene = Scene::l60mc();
        let version = env!("CARGO_PKG_VERSION");
        // An earlier format (the signals without their step integrals) and a later one.
        let others = [
            (FORMAT, "0.0.1-other"),
            (FORMAT - 1, version),
            (FORMAT + 1, version),
        ];
        for (format, v) in others {
            let path = file_with(dir.path(), format, v, &scene);
            let err = read_checkpoint::<()>(&path, &scene).expect_err("refused");
            assert!(matches!(err, CheckpointError::OtherVersion { .. }), "{err}");
            assert!(
                err.to_string()
                    .contains("only taken up by the version that wrote it"),
                "{err}"
            );
        }
        // The same version and format get past the header (and fail on the
        // body here, which is not a checkpoint's).
        let path = file_with(dir.path(), FORMAT, version, &scene);
        let err = read_checkpoint::<()>(&path, &scene).expect_err("no body");
        assert!(
            matches!(err, CheckpointError::NotACheckpoint { .. }),
            "{err}"
        );
    }

    #[test]
    fn a_truncated_file_is_refused_and_the_write_leaves_nothing_aside() {
        let dir = tempfile::tempdir().expect("tmp");
        let scene = Scene::l60mc();
        let path = file_with(dir.path(), FORMAT, env!("CARGO_PKG_VERSION"), &scene);
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .expect("dir")
            .map(|e| e.expect("entry").file_name())
            .collect();
        assert_eq!(names.len(), 1, "{names:?}");
        let bytes = std::fs::read(&path).expect("read");
        std::fs::write(&path, &bytes[..bytes.len() - 1]).expect("write");
        let err = read_checkpoint::<()>(&path, &scene).expect_err("truncated");
        assert!(err.to_string().contains("truncated body"), "{err}");
    }

    /// A scene of another profile or duration is named field by field; the
    /// duration only where the end must be the same.
    #[test]
    fn another_scene_is_named_field_by_field() {
        let dir = tempfile::tempdir().expect("tmp");
        let scene = Scene::l60mc();
        let path = file_with(dir.path(), FORMAT, env!("CARGO_PKG_VERSION"), &scene);
        let with = |o: &crate::scene::Overrides| scene.with(o).expect("valid");
        let real = with(&crate::scene::Overrides {
            profile: Some(crate::scene::ProfileKind::Real),
            ..Default::default()
        });
        let err = read_checkpoint_to_continue::<()>(&path, &real).expect_err("another profile");
        let text = err.to_string();
        assert!(
            text.contains(r#"sprockets[0].profile: not set there, "real" here"#),
            "{text}"
        );
        let longer = with(&crate::scene::Overrides {
            duration_s: Some(2.0 * scene.solver.duration_s),
            ..Default::default()
        });
        assert_eq!(scene_hash(&longer), scene_hash(&scene));
        let err = read_checkpoint::<()>(&path, &longer).expect_err("another end");
        assert!(
            err.to_string()
                .contains("solver.duration_s: 10.0 there, 20.0 here"),
            "{err}"
        );
        // Continued, the header passes (the body here is not a checkpoint's).
        let err = read_checkpoint_to_continue::<()>(&path, &longer).expect_err("no body");
        assert!(
            matches!(err, CheckpointError::NotACheckpoint { .. }),
            "{err}"
        );
    }

    #[test]
    fn differences_are_listed_and_counted() {
        let field = |p: &str, v: &str| (p.to_owned(), v.to_owned());
        let there: Vec<_> = (0..9).map(|i| field(&format!("a[{i}]"), "1")).collect();
        let mut here = there.clone();
        here[0].1 = "2".to_owned();
        here.push(field("b", "true"));
        assert_eq!(
            differences(&there, &here, true),
            ["a[0]: 1 there, 2 here", "b: absent there, true here"]
        );
        let here: Vec<_> = there.iter().map(|(p, _)| field(p, "0")).collect();
        let found = differences(&there, &here, true);
        assert_eq!(found.len(), 7);
        assert_eq!(found[6], "and 3 more");
        let found = differences(&there, &there, true);
        assert!(found[0].contains("data it reads"), "{found:?}");
    }
}
