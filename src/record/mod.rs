//! Recording: a run written as an [MCAP](https://mcap.dev) file that opens in
//! Foxglove and in Rerun.
//!
//! A [`Recorder`] is an [`Observer`] of the stepping loop: at every sample of
//! the run (the run's sample rate, `chaindrive run --rate`, independent of
//! the solver's dt) it writes one message on each requested [`Channel`]. Log
//! and publish times are the simulated time (t = 0 after static equilibrium),
//! so two identical runs give byte-identical recordings.
//!
//! | channel | topic | schema | what |
//! |---|---|---|---|
//! | `scene` | `/scene/static` | `foxglove.SceneUpdate` | once: each sprocket's tooth outline (circular or real profile), pitch circle, a spoke and its name, in its own frame `sprocketN`, frame-locked |
//! | `scene` | `/scene` | `foxglove.SceneUpdate` | rollers (spheres) and links (lines coloured by force, blue = slack … red ≥ 2 × pretension, 16 bins) in frame `world` |
//! | `transforms` | `/tf` | `foxglove.FrameTransforms` | `world` → `sprocketN`: centre and rotation θ about z; `world` → `tensionerN`: the arm's pivot and angle; `world` → a name of the user's: a body of a co-simulated world given to [`Recorder::body_frame`] |
//! | `outlines` | `/outlines/sprocketN` | `foxglove.PointCloud` | once: sprocket N's tooth outline as points 0.5 mm apart, in its frame `sprocketN`, one colour per sprocket (what Rerun draws) |
//! | `rollers` | `/rollers` | `foxglove.PointCloud` | roller centres, f32 x, y, z = 0, frame `world`, coloured (u8 red, green, blue, alpha) by the mean force of the roller's two links on the links' scale |
//! | `links` | `/links` | `ChainLinkForces` | every link's force, N, and every joint's friction moment, N·m |
//! | `contacts` | `/contacts` | `ChainContactForces` | every roller's contact force, N |
//! | `sprockets` | `/sprockets` | `SprocketSignals` | angles, speeds, chain torques |
//! | `segments` | `/segments` | `SegmentSignals` | each free strand's mean link force and transverse displacement ([`crate::analysis`]'s definitions) |
//! | `guides` | `/guides` | `GuideSignals` | each guide's summed normal and friction forces, resultant and contacts (none without guides); the guides' faces are drawn in `/scene/static`, frame `world` |
//! | `tensioners` | `/tensioners` | `TensionerSignals` | each tensioner arm's plunger travel, speed, chamber pressure, check-valve state, arm angle, shoe force and push (none without tensioner arms); the arms are drawn in `/scene/static`, each in its frame `tensionerN` (pivot, turned by the arm's angle), which `/tf` moves |
//!
//! Every file also holds a metadata record `chaindrive` (scene name, profile,
//! contact law, integrator, stepping, dt, sample rate, crate version), the
//! scene file as an attachment with the tables it read (a load table's
//! CSV, attached under the name the scene gives it, media type
//! `text/csv`), at the end a metadata record `chaindrive.end` saying how
//! the run ended, where the chain jumped teeth a record
//! `chaindrive.tooth_jumps` listing every jump, and where its rollers rode
//! the teeth's tips a record `chaindrive.tip_rides` listing every ride.
//! Channels not requested are neither computed nor written.
//!
//! Cost: the stepping loop only copies the arrays the requested channels
//! need (and computes the segment signals when asked); a writer thread of
//! the recorder builds the messages, encodes them, compresses them (zstd
//! chunks of at most 1 MiB) and writes them, in order. The simulation itself
//! stays single-threaded and deterministic.
//!
//! A recording is finished by [`Recorder::finish`]; dropping a recorder
//! finishes it too (the writer thread drains its queue and the MCAP writer
//! writes its summary and footer), so a file is readable up to its last
//! frame however the run ends: normal end, blow-up, interruption, or a panic
//! that unwinds. A process killed outright (SIGKILL, an out-of-memory kill)
//! loses the open chunk, the summary and the footer: so that the open chunk
//! never holds much, it is closed and written to the file whenever it is
//! full or `FLUSH_INTERVAL_NS` (0.1 s) of simulated time has passed since
//! the last one. Such a file streams up to its last chunk, but seeking
//! readers (Foxglove, Rerun) need the index: `recover` rewrites it whole
//! (`chaindrive recover`).
//!
//! A run resumed from a checkpoint continues its recording
//! ([`Recorder::continued`]): an MCAP file cannot be appended to once it
//! has its footer, so the resumed run writes a new file that starts with
//! every message the earlier file holds up to the checkpoint
//! ([`RecordMark`], taken by [`Recorder::mark`], which also writes the open
//! chunk out so that a process killed after the checkpoint still leaves
//! those messages in the file) and goes on from there. The result holds the
//! same messages as a recording of the run that never stopped.
//!
//! Reading a recording back is `read`'s job.
//!
//! What it does not do: decimate on its own (it records every sample the run
//! hands it) or stream to a live viewer.

mod channels;
mod decode;
mod files;
mod messages;
mod opening;
pub(crate) mod read;
#[cfg(all(test, feature = "record"))]
mod record_tests;
#[cfg(all(test, feature = "record"))]
mod recorded_settings_tests;
pub(crate) mod recover;
#[cfg(all(test, feature = "cli"))]
mod recover_tests;
#[cfg(all(test, feature = "record"))]
mod rerun_view_tests;
mod visual;
mod writer;

pub(crate) use channels::STATIC_SCENE_TOPIC;
pub use channels::{Channel, Channels};

/// The media type of a table a scene read, attached beside it.
pub(crate) const TABLE_MEDIA_TYPE: &str = "text/csv";
use opening::{attach_scene, copy_messages, header_metadata, open_channels};
pub(crate) use writer::CHUNK_BYTES;
use writer::{Frame, Job, QUEUE_FRAMES, Sink, Writer};

pub(crate) use messages::{
    ChainContactForces, ChainLinkForces, GuideSignals, SegmentSignal, SegmentSignals,
    SprocketSignals, TensionerSignal, TensionerSignals,
};
#[cfg(test)]
pub(crate) use visual::OUTLINE_SPACING_M;
#[cfg(test)]
pub(crate) use writer::FLUSH_INTERVAL_NS;

use std::collections::BTreeMap;
use std::io::{Seek, Write};

use foxglove::schemas::FrameTransforms;

use crate::scene::Scene;
use crate::sim::{Observer, Sample};

/// What the recorder is told besides the scene.
#[derive(Clone, Debug, Default)]
pub struct RecordOptions {
    /// Channels to record.
    pub channels: Channels,
    /// The scene file attached to the recording: (file name, contents);
    /// `None` attaches nothing.
    pub scene_file: Option<(String, Vec<u8>)>,
    /// The run's sample rate, Hz, written into the metadata.
    pub rate_hz: f64,
}

/// Name of the metadata record that lists a run's tooth jumps (written at
/// its end, only when it had any): `count`, and `jump NNNN` per jump,
/// `t_s=… sprocket=… roller=… gaps=… ahead|behind` (sprocket 1-based,
/// roller 0-based, gaps counter-clockwise positive).
pub(crate) const JUMPS_RECORD: &str = "chaindrive.tooth_jumps";

/// The entries of the `chaindrive.tooth_jumps` metadata record.
fn jump_entries(jumps: &[crate::sim::ToothJump]) -> BTreeMap<String, String> {
    let mut m: BTreeMap<String, String> = jumps
        .iter()
        .enumerate()
        .map(|(k, j)| {
            (
                format!("jump {:04}", k + 1),
                format!(
                    "t_s={} sprocket={} roller={} gaps={} {}",
                    j.t_s,
                    j.sprocket + 1,
                    j.roller,
                    j.gaps,
                    if j.ahead { "ahead" } else { "behind" }
                ),
            )
        })
        .collect();
    m.insert("count".to_owned(), jumps.len().to_string());
    m
}

/// Name of the metadata record that lists the tip rides of a run's rollers
/// (written at its end, only when it had any): `count`, and `ride NNNN`
/// per ride, `t_s=… sprocket=… roller=…` (sprocket 1-based, roller 0-based),
/// as the detector saw them (docs/model.md, "Riding a tip").
pub(crate) const RIDES_RECORD: &str = "chaindrive.tip_rides";

/// The entries of the `chaindrive.tip_rides` metadata record.
fn ride_entries(rides: &[crate::sim::TipRide]) -> BTreeMap<String, String> {
    let mut m: BTreeMap<String, String> = rides
        .iter()
        .enumerate()
        .map(|(k, r)| {
            (
                format!("ride {:04}", k + 1),
                format!(
                    "t_s={} sprocket={} roller={}",
                    r.t_s,
                    r.sprocket + 1,
                    r.roller
                ),
            )
        })
        .collect();
    m.insert("count".to_owned(), rides.len().to_string());
    m
}

/// How a run ended, written into the `chaindrive.end` metadata record.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RunEnd<'a> {
    /// It reached its planned duration.
    Completed,
    /// It was stopped early (Ctrl-C).
    Interrupted,
    /// It failed (e.g. blew up), with the error message.
    Failed(&'a str),
}

/// Where a recording stood when a checkpoint was taken
/// ([`Recorder::mark`]): what [`Recorder::continued`] copies from the
/// earlier file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct RecordMark {
    /// Samples recorded.
    pub frames: u64,
    /// Log time of the last one, ns.
    pub last_t_ns: u64,
    /// Messages written (the last message's sequence number).
    pub messages: u32,
    /// The channels recorded ([`Channels::bits`]).
    pub channels: u16,
}

/// Why a recording could not be written.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    /// A name in the channel list is not a channel.
    #[error(
        "unknown recording channel {0:?}; channels: scene, transforms, rollers, outlines, links, contacts, sprockets, segments, guides, tensioners, all"
    )]
    UnknownChannel(String),
    /// The file could not be created.
    #[error("cannot create {path}: {source}")]
    Create {
        /// The path.
        path: String,
        /// Why.
        source: std::io::Error,
    },
    /// Writing failed.
    #[error("writing the recording: {0}")]
    Mcap(#[from] mcap::McapError),
    /// Flushing the finished file failed.
    #[error("writing the recording: {0}")]
    Io(#[from] std::io::Error),
    /// The writer thread could not be started.
    #[error("starting the recording's writer thread: {0}")]
    Thread(String),
    /// The writer thread stopped before the run ended.
    #[error("the recording's writer thread stopped unexpectedly")]
    WriterStopped,
    /// The earlier recording of a resumed run cannot be continued.
    #[error("cannot continue the recording: {0}")]
    Continue(String),
    /// A message could not be encoded.
    #[error("encoding a {topic} message: {message}")]
    Encode {
        /// The topic.
        topic: &'static str,
        /// The encoder's error.
        message: String,
    },
}

/// What the writer thread hands back: the sink and its first error.
type Joined<W> = (Sink<W>, Option<RecordError>);

/// Writes a run to an MCAP file; see the module documentation.
///
/// The stepping loop only copies the arrays the requested channels need
/// (and computes the segment signals if asked); a writer thread builds,
/// encodes, compresses (zstd) and writes the messages, in order.
pub struct Recorder<W: Write + Seek + Send + 'static> {
    channels: Channels,
    tx: Option<std::sync::mpsc::SyncSender<Job>>,
    thread: Option<std::thread::JoinHandle<Joined<W>>>,
    frames: u64,
    last_t_ns: u64,
    started: bool,
    scene: Scene,
    segment_force: Vec<Option<f64>>,
    /// A failure to hand a job over (the writer thread stopped).
    lost: bool,
    /// It continues an earlier file, whose static scene and outlines it
    /// copied: the first sample writes none.
    continued: bool,
    /// A co-simulated run's metadata, written again at its end with the
    /// run's duration; `None` for a standalone run.
    cosim: Option<BTreeMap<String, String>>,
    /// Every tooth jump the run saw, as its samples listed them.
    jumps: Vec<crate::sim::ToothJump>,
    /// Every tip ride the run saw, as its samples listed them.
    rides: Vec<crate::sim::TipRide>,
    /// Time of the first sample, ns.
    first_t_ns: u64,
    /// The user's frames ([`Recorder::body_frame`]), their latest poses.
    bodies: Vec<(String, [f64; 2], f64)>,
}

/// Simulated time in integer nanoseconds (negative and NaN clamp to 0).
fn time_ns(t_s: f64) -> u64 {
    (t_s * 1e9).round() as u64
}

/// The refusal of a resumed recording with other channels.
fn other_channels(mark: &RecordMark, options: &RecordOptions) -> RecordError {
    RecordError::Continue(format!(
        "the run was recorded with other channels ({:?}, now {:?}): resume with the same --record-channels",
        Channels::from_bits_truncate(mark.channels),
        options.channels
    ))
}

impl<W: Write + Seek + Send + 'static> Recorder<W> {
    /// Starts a recording into `writer`: header, metadata, the scene file as
    /// an attachment, schemas and channels. Messages follow at every sample.
    pub fn new(writer: W, scene: &Scene, options: &RecordOptions) -> Result<Self, RecordError> {
        Self::start(writer, scene, options, None, None)
    }

    /// Starts a recording into `writer` that continues `earlier`, the MCAP
    /// file (complete, or cut short by a killed process) of the same run up
    /// to a checkpoint taken at `mark`: header, metadata, attachment and
    /// channels as [`Recorder::new`] writes them, then every message of
    /// `earlier` up to the mark, then the resumed run's samples. Fails if
    /// `earlier` lacks messages up to the mark or was recorded with other
    /// channels.
    pub fn continued(
        writer: W,
        scene: &Scene,
        options: &RecordOptions,
        earlier: &[u8],
        mark: &RecordMark,
    ) -> Result<Self, RecordError> {
        if mark.channels != options.channels.bits() {
            return Err(other_channels(mark, options));
        }
        Self::start(writer, scene, options, Some((earlier, mark)), None)
    }

    /// Starts the recording of a co-simulated run (a drive in a rapier world
    /// stepped at `frame_dt_s`, sampled once per frame): its metadata gives
    /// the frame step (`frame_dt_s`) and, written again when the recording
    /// is finished, the run's real duration (`duration_s`, from the first
    /// sample to the last) instead of the scene's planned one; the sprocket
    /// centres are recorded at every sample (a mounted sprocket moves with
    /// its body).
    pub fn co_simulated(
        writer: W,
        scene: &Scene,
        options: &RecordOptions,
        frame_dt_s: f64,
    ) -> Result<Self, RecordError> {
        Self::start(writer, scene, options, None, Some(frame_dt_s))
    }

    fn start(
        writer: W,
        scene: &Scene,
        options: &RecordOptions,
        earlier: Option<(&[u8], &RecordMark)>,
        frame_dt_s: Option<f64>,
    ) -> Result<Self, RecordError> {
        let mut topics = BTreeMap::new();
        let mut w = mcap::WriteOptions::new()
            .compression(Some(mcap::Compression::Zstd))
            .compression_level(3)
            .compression_threads(0)
            .chunk_size(Some(CHUNK_BYTES))
            .library(format!("chaindrive {}", env!("CARGO_PKG_VERSION")))
            .create(writer)?;
        let metadata = header_metadata(scene, options, frame_dt_s);
        w.write_metadata(&mcap::records::Metadata {
            name: "chaindrive".to_owned(),
            metadata: metadata.clone(),
        })?;
        attach_scene(&mut w, scene, options)?;
        let channels = options.channels;
        let ids = open_channels(&mut w, &mut topics, scene, channels)?;
        let mut sequence = 0;
        if let Some((bytes, mark)) = earlier {
            copy_messages(&mut w, &topics, bytes, mark)?;
            sequence = mark.messages;
            // The copy is on disk before the earlier file may go.
            w.flush()?;
        }
        // Top of the force colour scale, shared by the links and the rollers.
        let full_scale_n = visual::full_scale(2.0 * scene.chain.pretension_n);
        let writer = Writer {
            sink: Sink {
                writer: w,
                buf: Vec::with_capacity(64 << 10),
                sequence,
            },
            ids,
            chain: visual::ChainScene::new(
                scene.chain.rollers,
                scene.chain.roller_radius_m,
                full_scale_n,
            ),
            full_scale_n,
            centers_m: Vec::new(),
            tf: FrameTransforms::default(),
            links: ChainLinkForces::default(),
            contacts: ChainContactForces::default(),
            sprockets: SprocketSignals::default(),
            segments: SegmentSignals::default(),
            guides: GuideSignals::default(),
            tensioners: TensionerSignals::default(),
            pivots_m: Vec::new(),
            flushed_ns: 0,
        };
        let (tx, rx) = std::sync::mpsc::sync_channel::<Job>(QUEUE_FRAMES);
        let thread = std::thread::Builder::new()
            .name("chaindrive-record".to_owned())
            .spawn(move || {
                let mut writer = writer;
                let mut error = None;
                for job in rx {
                    // After an error the queue is drained and nothing more is written.
                    if error.is_none()
                        && let Err(e) = writer.job(job)
                    {
                        error = Some(e);
                    }
                }
                (writer.sink, error)
            })
            .map_err(|e| RecordError::Thread(e.to_string()))?;
        Ok(Self {
            channels,
            tx: Some(tx),
            thread: Some(thread),
            frames: earlier.map_or(0, |(_, m)| m.frames),
            last_t_ns: earlier.map_or(0, |(_, m)| m.last_t_ns),
            started: false,
            scene: scene.clone(),
            segment_force: Vec::new(),
            lost: false,
            continued: earlier.is_some_and(|(_, m)| m.frames > 0),
            cosim: frame_dt_s.map(|_| metadata),
            first_t_ns: 0,
            jumps: Vec::new(),
            rides: Vec::new(),
            bodies: Vec::new(),
        })
    }

    /// Sets the pose of one of the user's own bodies (a box, a carriage, a
    /// motor), recorded with every later sample as the frame transform
    /// `world` → `name` on `/tf` (channel `transforms`) until set again: in
    /// Foxglove's 3D panel the body is the frame `name`, beside the chain.
    /// Call it before each frame is sampled, with the body's pose then, e.g.
    /// `recorder.body_frame("box", b.translation(), b.rotation().angle())`.
    /// A name of the drive's own frames (`world`, `sprocketN`,
    /// `tensionerN`) or a non-finite pose is ignored: nothing a user passes
    /// can corrupt the chain's own frames or write a NaN.
    pub fn body_frame(
        &mut self,
        name: &str,
        position: rapier2d_f64::prelude::Vector,
        angle_rad: f64,
    ) {
        let own = name == visual::WORLD_FRAME
            || ["sprocket", "tensioner"].iter().any(|p| {
                name.strip_prefix(p)
                    .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
            });
        if own || !(position.x.is_finite() && position.y.is_finite() && angle_rad.is_finite()) {
            return;
        }
        let pose = ([position.x, position.y], angle_rad);
        match self.bodies.iter_mut().find(|b| b.0 == name) {
            Some(b) => (b.1, b.2) = pose,
            None => self.bodies.push((name.to_owned(), pose.0, pose.1)),
        }
    }

    /// Samples recorded so far.
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// The channels being recorded.
    pub fn channels(&self) -> Channels {
        self.channels
    }

    /// Writes everything recorded so far to the file (the open chunk
    /// included) and says where the recording stands, for a checkpoint.
    pub fn mark(&mut self) -> Result<RecordMark, RecordError> {
        let (done, answer) = std::sync::mpsc::sync_channel(1);
        self.send(Job::Flush(done));
        let messages = answer.recv().map_err(|_| RecordError::WriterStopped)?;
        Ok(RecordMark {
            frames: self.frames,
            last_t_ns: self.last_t_ns,
            messages,
            channels: self.channels.bits(),
        })
    }

    fn send(&mut self, job: Job) {
        let sent = self.tx.as_ref().is_some_and(|tx| tx.send(job).is_ok());
        self.lost |= !sent;
    }

    /// Stops the writer thread and takes back its sink.
    fn join(&mut self) -> Result<Joined<W>, RecordError> {
        self.tx = None;
        match self.thread.take().map(std::thread::JoinHandle::join) {
            Some(Ok(joined)) => Ok(joined),
            Some(Err(_)) => Err(RecordError::WriterStopped),
            None => Err(RecordError::WriterStopped),
        }
    }

    /// Writes the end record, the summary and the footer, flushes, and
    /// returns the writer. Returns the first error met while recording, if
    /// any (the file is still finished as far as it can be).
    pub fn finish(mut self, end: RunEnd<'_>) -> Result<W, RecordError> {
        let (mut sink, error) = self.join()?;
        // A co-simulated run's metadata again, now with its duration (a
        // reader keeps the last record of a name).
        let run_written = match self.cosim.take() {
            Some(mut metadata) => {
                let span_ns = self.last_t_ns.saturating_sub(self.first_t_ns);
                metadata.insert(
                    "duration_s".to_owned(),
                    format!("{}", span_ns as f64 * 1e-9),
                );
                sink.writer.write_metadata(&mcap::records::Metadata {
                    name: "chaindrive".to_owned(),
                    metadata,
                })
            }
            None => Ok(()),
        };
        let (status, message) = match end {
            RunEnd::Completed => ("completed", ""),
            RunEnd::Interrupted => ("interrupted", ""),
            RunEnd::Failed(m) => ("failed", m),
        };
        let metadata: BTreeMap<String, String> = [
            ("status", status.to_owned()),
            ("message", message.to_owned()),
            ("frames", self.frames.to_string()),
            ("last_t_s", format!("{}", self.last_t_ns as f64 * 1e-9)),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_owned(), v))
        .collect();
        let end_written = sink.writer.write_metadata(&mcap::records::Metadata {
            name: "chaindrive.end".to_owned(),
            metadata,
        });
        // The tooth jumps, one entry each (no record without any).
        let jumps_written = if self.jumps.is_empty() {
            Ok(())
        } else {
            sink.writer.write_metadata(&mcap::records::Metadata {
                name: JUMPS_RECORD.to_owned(),
                metadata: jump_entries(&self.jumps),
            })
        };
        // The tip rides likewise.
        let rides_written = if self.rides.is_empty() {
            Ok(())
        } else {
            sink.writer.write_metadata(&mcap::records::Metadata {
                name: RIDES_RECORD.to_owned(),
                metadata: ride_entries(&self.rides),
            })
        };
        let finished = sink.writer.finish();
        let mut inner = sink.writer.into_inner();
        let flushed = inner.flush();
        if let Some(e) = error {
            return Err(e);
        }
        if self.lost {
            return Err(RecordError::WriterStopped);
        }
        run_written?;
        end_written?;
        jumps_written?;
        rides_written?;
        finished?;
        flushed?;
        Ok(inner)
    }
}

impl<W: Write + Seek + Send + 'static> Drop for Recorder<W> {
    /// A recorder dropped without [`Recorder::finish`] (an early return, a
    /// panic) still finishes its file: the writer thread drains its queue and
    /// the MCAP writer writes its summary and footer when dropped.
    fn drop(&mut self) {
        if self.thread.is_some() {
            let _ = self.join();
        }
    }
}

impl<W: Write + Seek + Send + 'static> Observer for Recorder<W> {
    fn sample(&mut self, s: &Sample<'_>) {
        if self.lost {
            return;
        }
        if s.jumps.len() != self.jumps.len() {
            self.jumps = s.jumps.to_vec();
        }
        if s.rides.len() != self.rides.len() {
            self.rides = s.rides.to_vec();
        }
        let st = s.state;
        let f = s.forces;
        // No NaN is ever written: a non-finite state (a run about to be
        // stopped by the blow-up detectors) is not recorded.
        let check: f64 = [
            &st.x,
            &st.y,
            &st.theta,
            &st.omega,
            &f.link_force,
            &f.contact_force,
            &f.joint_moment_n_m,
        ]
        .iter()
        .flat_map(|v| v.iter())
        .sum();
        if !check.is_finite() {
            return;
        }
        let t_ns = time_ns(st.t_s);
        let ch = self.channels;
        if !self.started {
            self.started = true;
            self.first_t_ns = t_ns;
            // A continued recording has them from the earlier file.
            let once = !self.continued;
            let static_scene = (once && ch.contains(Channels::SCENE))
                .then(|| Box::new(visual::static_scene(&self.scene, s.model, t_ns)));
            let outlines = if once && ch.contains(Channels::OUTLINES) {
                s.model
                    .sprockets
                    .iter()
                    .enumerate()
                    .map(|(i, sp)| visual::outline_cloud(&sp.profile, i, t_ns))
                    .collect()
            } else {
                Vec::new()
            };
            let centers_m = s.model.sprockets.iter().map(|s| s.center_m).collect();
            let pivots_m = self.scene.tensioners.iter().map(|t| t.pivot_m).collect();
            self.send(Job::Start {
                t_ns,
                static_scene,
                outlines,
                centers_m,
                pivots_m,
            });
        }
        let wants = |c: &[Channel]| c.iter().any(|&c| ch.contains(c.into()));
        let copy = |yes: bool, v: &[f64]| if yes { v.to_vec() } else { Vec::new() };
        let positions = wants(&[Channel::Scene, Channel::Rollers]);
        let mut frame = Frame {
            t_s: st.t_s,
            t_ns,
            x: copy(positions, &st.x),
            y: copy(positions, &st.y),
            theta: copy(wants(&[Channel::Transforms, Channel::Sprockets]), &st.theta),
            omega: copy(wants(&[Channel::Sprockets]), &st.omega),
            link_force: copy(
                wants(&[Channel::Scene, Channel::Rollers, Channel::Links]),
                &f.link_force,
            ),
            joint_moment: copy(wants(&[Channel::Links]), &f.joint_moment_n_m),
            contact_force: copy(wants(&[Channel::Contacts]), &f.contact_force),
            chain_torque: copy(wants(&[Channel::Sprockets]), &f.chain_torque),
            segments: Vec::new(),
            centers_m: if self.cosim.is_some() {
                s.model.sprockets.iter().map(|s| s.center_m).collect()
            } else {
                Vec::new()
            },
            // The scene's guides are the first shoes; no NaN is written.
            shoes: if ch.contains(Channels::GUIDES) {
                f.shoes
                    .iter()
                    .take(self.scene.guides.len())
                    .copied()
                    .filter(|s| s.normal_n.is_finite() && s.friction_n.is_finite())
                    .collect()
            } else {
                Vec::new()
            },
            // Every arm's reading, or none if one is not finite.
            bodies: if ch.contains(Channels::TRANSFORMS) {
                self.bodies.clone()
            } else {
                Vec::new()
            },
            tensioners: if wants(&[Channel::Transforms, Channel::Tensioners])
                && f.tensioners.iter().all(|r| {
                    [
                        r.angle_rad,
                        r.travel_m,
                        r.plunger_speed_m_s,
                        r.pressure_pa,
                        r.shoe_force_n,
                        r.plunger_force_n,
                    ]
                    .iter()
                    .all(|v| v.is_finite())
                }) {
                f.tensioners.clone()
            } else {
                Vec::new()
            },
        };
        if ch.contains(Channels::SEGMENTS) {
            let segments = &s.model.segments;
            self.segment_force.resize(segments.len(), None);
            let runs = segments.runs(&s.model.sprockets, &st.x, &st.y, &f.touching);
            segments.mean_forces(&runs, &f.link_force, &mut self.segment_force);
            frame.segments = self
                .segment_force
                .iter()
                .enumerate()
                .map(|(k, force)| SegmentSignal {
                    segment: (k + 1) as u32,
                    link_force_n: force.filter(|v| v.is_finite()),
                    transverse_m: segments.transverse(k, &runs, &st.x, &st.y),
                })
                .collect();
        }
        self.send(Job::Frame(Box::new(frame)));
        if !self.lost {
            self.frames += 1;
            self.last_t_ns = t_ns;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_channel_has_its_own_flag_and_all_holds_them() {
        let union = Channel::ALL
            .iter()
            .fold(Channels::empty(), |s, &c| s | Channels::from(c));
        assert_eq!(union, Channels::all());
        let bits: u32 = Channel::ALL
            .iter()
            .map(|&c| Channels::from(c).bits().count_ones())
            .sum();
        assert_eq!(bits, Channel::ALL.len() as u32);
        assert_eq!(
            Channels::parse("segments, sprockets").ok(),
            Some(Channels::SEGMENTS | Channels::SPROCKETS)
        );
        assert_eq!(Channels::parse("all").ok(), Some(Channels::all()));
    }
}
