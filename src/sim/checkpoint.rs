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
//! detector's history and the power ledger. The caller adds what its
//! observers accumulated ([`Checkpoint::run`]).
//!
//! What is rebuilt, not kept: the drive itself (its layout and static
//! equilibrium are computed again from the scene, deterministically), the
//! rapier world (written from the state), the integrators' stage buffers (set
//! at every step's start), and the contact's runs of rollers within reach,
//! a function of the kept reach sets (the culling changes no bit:
//! `culling_changes_nothing`).
//!
//! # The file
//!
//! `chaindrive-ckpt\n`, then a header and the body, each a CBOR item (RFC
//! 8949, by `ciborium`) after its length as 8 bytes little-endian. CBOR
//! keeps every `f64` bit for bit, infinities included (JSON has no
//! infinity, and the contact's reach expiry and the adaptive step's first
//! proposal are infinite). The header holds the format number
//! ([`FORMAT`]), the crate version and a hash of the scene; a checkpoint of
//! another scene, version or format is refused before its body is read.
//! Files are written aside and renamed into place: a checkpoint is whole or
//! absent, never half written.
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

/// The checkpoint file format's number; a change of what is kept raises it.
pub const FORMAT: u32 = 1;

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
        "checkpoint {path} was written for another scene (scene hash {found}, this one's is {expected}): \
         resume with the scene file and the options that started the run"
    )]
    OtherScene {
        /// The file.
        path: PathBuf,
        /// The checkpoint's scene hash.
        found: String,
        /// This scene's hash.
        expected: String,
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
    pub fn t_s(&self) -> f64 {
        self.state.t_s
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
}

impl Simulation {
    /// The simulation's state for a checkpoint. Call between runs
    /// ([`Simulation::run`] returns at a step's end).
    pub fn snapshot(&self) -> Result<Snapshot, CheckpointError> {
        if self.scene.solver.stepping != Stepping::Substepped {
            return Err(CheckpointError::Stepping);
        }
        let (next_step_s, stats) = self.integration.carried();
        Ok(Snapshot {
            clock: self.clock,
            state: self.state.clone(),
            forces: self.forces.output().clone(),
            histories: self.forces.save_histories(),
            next_step_s,
            stats,
            growth: self.growth.clone(),
            power: self.power.clone(),
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

/// A hash of the validated scene (its every field, numbers bit for bit):
/// 16 hex digits of FNV-1a (64 bit) over its debug form. Stable for one
/// version of the crate, which is all a checkpoint needs.
pub fn scene_hash(scene: &Scene) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in format!("{scene:?}").bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
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
/// beside it, synced, then renamed over `path`.
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
        std::fs::rename(&aside, path)
    };
    write().map_err(io(path))
}

/// Reads a checkpoint for a run of `scene` from `path`; refuses one of
/// another scene, version or format.
pub fn read_checkpoint<T: DeserializeOwned>(
    path: &Path,
    scene: &Scene,
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
    let header: Header = ciborium::from_reader(header).map_err(|e| bad(&e.to_string()))?;
    let version = env!("CARGO_PKG_VERSION");
    if header.format != FORMAT || header.version != version {
        return Err(CheckpointError::OtherVersion {
            path: path.to_owned(),
            found_version: header.version,
            found_format: header.format,
            version: version.to_owned(),
            format: FORMAT,
        });
    }
    let expected = scene_hash(scene);
    if header.scene_hash != expected {
        return Err(CheckpointError::OtherScene {
            path: path.to_owned(),
            found: header.scene_hash,
            expected,
        });
    }
    let (body, rest) = split_part(rest).ok_or_else(|| bad("truncated body"))?;
    if !rest.is_empty() {
        return Err(bad("bytes after the body"));
    }
    ciborium::from_reader(body).map_err(|e| bad(&e.to_string()))
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
        for (format, v) in [(FORMAT, "0.0.1-other"), (FORMAT + 1, version)] {
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
}
