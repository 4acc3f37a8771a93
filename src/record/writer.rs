//! The writer thread: builds each sample's messages, encodes them and
//! writes them to the MCAP file, in order.

use std::io::{Seek, Write};

use foxglove::Encode;
use foxglove::schemas::{FrameTransforms, PointCloud, SceneUpdate};

use super::messages::{GuideSignal, SegmentSignal, TensionerSignal};
use super::visual::OUTLINES_TOPIC;
use super::{
    ChainContactForces, ChainLinkForces, Channel, GuideSignals, RecordError, STATIC_SCENE_TOPIC,
    SegmentSignals, SprocketSignals, TensionerSignals, visual,
};

/// Channel ids in the file, by [`Channel`] (and the static scene, and the
/// outlines: one channel per sprocket).
#[derive(Clone, Debug, Default)]
pub(super) struct ChannelIds {
    pub(super) static_scene: Option<u16>,
    pub(super) outlines: Vec<u16>,
    pub(super) per_sample: [Option<u16>; Channel::ALL.len()],
}

/// The MCAP writer with its encoding buffer.
pub(super) struct Sink<W: Write + Seek> {
    pub(super) writer: mcap::Writer<W>,
    pub(super) buf: Vec<u8>,
    pub(super) sequence: u32,
}

impl<W: Write + Seek> Sink<W> {
    /// Encodes `msg` and writes it on `id` (nothing if the channel is not recorded).
    fn write<T: Encode>(
        &mut self,
        id: Option<u16>,
        topic: &'static str,
        t_ns: u64,
        msg: &T,
    ) -> Result<(), RecordError> {
        let Some(channel_id) = id else {
            return Ok(());
        };
        self.buf.clear();
        msg.encode(&mut self.buf).map_err(|e| RecordError::Encode {
            topic,
            message: e.to_string(),
        })?;
        self.sequence = self.sequence.wrapping_add(1);
        self.writer.write_to_known_channel(
            &mcap::records::MessageHeader {
                channel_id,
                sequence: self.sequence,
                log_time: t_ns,
                publish_time: t_ns,
            },
            &self.buf,
        )?;
        Ok(())
    }
}

/// What the stepping loop hands the writer thread.
pub(super) enum Job {
    /// The first sample: the static scene, the outlines and the sprocket centres.
    Start {
        t_ns: u64,
        static_scene: Option<Box<SceneUpdate>>,
        outlines: Vec<PointCloud>,
        centers_m: Vec<[f64; 2]>,
        pivots_m: Vec<[f64; 2]>,
    },
    /// One sample, with only the arrays the requested channels need.
    Frame(Box<Frame>),
    /// Write the open chunk out and answer with the messages written so far.
    Flush(std::sync::mpsc::SyncSender<u32>),
}

/// A copy of one sample.
#[derive(Default)]
pub(super) struct Frame {
    pub(super) t_s: f64,
    pub(super) t_ns: u64,
    pub(super) x: Vec<f64>,
    pub(super) y: Vec<f64>,
    pub(super) theta: Vec<f64>,
    pub(super) omega: Vec<f64>,
    pub(super) link_force: Vec<f64>,
    pub(super) joint_moment: Vec<f64>,
    pub(super) contact_force: Vec<f64>,
    pub(super) chain_torque: Vec<f64>,
    pub(super) segments: Vec<SegmentSignal>,
    /// Sprocket centres, m (a co-simulated run's, at every sample; empty:
    /// the centres of the first sample hold).
    pub(super) centers_m: Vec<[f64; 2]>,
    pub(super) shoes: Vec<crate::forces::ShoeForces>,
    pub(super) tensioners: Vec<crate::forces::TensionerReading>,
    /// The user's frames at this sample ([`super::Recorder::body_frame`]):
    /// name, position (m) and angle (rad).
    pub(super) bodies: Vec<(String, [f64; 2], f64)>,
}

/// Samples queued for the writer thread before the stepping loop waits for it.
pub(super) const QUEUE_FRAMES: usize = 256;

/// Uncompressed size at which a chunk is closed and written, bytes.
pub(crate) const CHUNK_BYTES: u64 = 1 << 20;

/// Simulated time after which the open chunk is closed and written to the
/// file even if it is not full, ns: a process killed outright loses at most
/// this much of the run (or one chunk, if that is less).
pub(crate) const FLUSH_INTERVAL_NS: u64 = 100_000_000;

/// The writer thread's state: messages kept between frames, updated in place.
pub(super) struct Writer<W: Write + Seek> {
    pub(super) sink: Sink<W>,
    pub(super) ids: ChannelIds,
    pub(super) chain: visual::ChainScene,
    /// Link force at the top of the rollers' colour scale, N.
    pub(super) full_scale_n: f64,
    pub(super) centers_m: Vec<[f64; 2]>,
    pub(super) tf: FrameTransforms,
    pub(super) links: ChainLinkForces,
    pub(super) contacts: ChainContactForces,
    pub(super) sprockets: SprocketSignals,
    pub(super) segments: SegmentSignals,
    pub(super) guides: GuideSignals,
    pub(super) tensioners: TensionerSignals,
    /// Each tensioner arm's pivot, m.
    pub(super) pivots_m: Vec<[f64; 2]>,
    /// Simulated time of the last chunk closed by [`FLUSH_INTERVAL_NS`], ns.
    pub(super) flushed_ns: u64,
}

impl<W: Write + Seek> Writer<W> {
    pub(super) fn job(&mut self, job: Job) -> Result<(), RecordError> {
        match job {
            Job::Start {
                t_ns,
                static_scene,
                outlines,
                centers_m,
                pivots_m,
            } => {
                self.centers_m = centers_m;
                self.pivots_m = pivots_m;
                if let Some(update) = static_scene {
                    self.sink
                        .write(self.ids.static_scene, STATIC_SCENE_TOPIC, t_ns, &*update)?;
                }
                for (&id, cloud) in self.ids.outlines.iter().zip(&outlines) {
                    self.sink.write(Some(id), OUTLINES_TOPIC, t_ns, cloud)?;
                }
                Ok(())
            }
            Job::Frame(f) => {
                let t_ns = f.t_ns;
                self.frame(*f)?;
                // Simulated, not wall-clock, time: two identical runs still
                // give byte-identical files.
                if t_ns.saturating_sub(self.flushed_ns) >= FLUSH_INTERVAL_NS {
                    self.flushed_ns = t_ns;
                    self.sink.writer.flush()?;
                }
                Ok(())
            }
            Job::Flush(done) => {
                self.sink.writer.flush()?;
                // The caller waits for this answer; gone, it wants none.
                let _ = done.send(self.sink.sequence);
                Ok(())
            }
        }
    }

    fn frame(&mut self, mut f: Frame) -> Result<(), RecordError> {
        let t_ns = f.t_ns;
        let ids = self.ids.per_sample;
        let id = |c: Channel| ids[c as usize];
        let sink = &mut self.sink;
        if id(Channel::Scene).is_some() {
            let update = self.chain.update(t_ns, &f.x, &f.y, &f.link_force);
            sink.write(id(Channel::Scene), "/scene", t_ns, update)?;
        }
        if !f.centers_m.is_empty() {
            self.centers_m = std::mem::take(&mut f.centers_m);
        }
        if id(Channel::Transforms).is_some() {
            let arms: Vec<f64> = f.tensioners.iter().map(|r| r.angle_rad).collect();
            visual::transforms(
                &self.centers_m,
                &f.theta,
                &self.pivots_m,
                &arms,
                t_ns,
                &mut self.tf,
            );
            let own = self.tf.transforms.len();
            self.tf.transforms.extend(
                f.bodies
                    .iter()
                    .map(|(name, c, th)| visual::body_transform(name, *c, *th, t_ns)),
            );
            sink.write(id(Channel::Transforms), "/tf", t_ns, &self.tf)?;
            self.tf.transforms.truncate(own);
        }
        if id(Channel::Rollers).is_some() {
            let cloud = visual::roller_cloud(&f.x, &f.y, &f.link_force, self.full_scale_n, t_ns);
            sink.write(id(Channel::Rollers), "/rollers", t_ns, &cloud)?;
        }
        if id(Channel::Links).is_some() {
            self.links.t_s = f.t_s;
            std::mem::swap(&mut self.links.force_n, &mut f.link_force);
            std::mem::swap(
                &mut self.links.joint_friction_moment_n_m,
                &mut f.joint_moment,
            );
            sink.write(id(Channel::Links), "/links", t_ns, &self.links)?;
        }
        if id(Channel::Contacts).is_some() {
            self.contacts.t_s = f.t_s;
            std::mem::swap(&mut self.contacts.force_n, &mut f.contact_force);
            sink.write(id(Channel::Contacts), "/contacts", t_ns, &self.contacts)?;
        }
        if id(Channel::Sprockets).is_some() {
            let m = &mut self.sprockets;
            m.t_s = f.t_s;
            std::mem::swap(&mut m.angle_rad, &mut f.theta);
            std::mem::swap(&mut m.speed_rad_s, &mut f.omega);
            std::mem::swap(&mut m.chain_torque_n_m, &mut f.chain_torque);
            sink.write(id(Channel::Sprockets), "/sprockets", t_ns, m)?;
        }
        if id(Channel::Segments).is_some() {
            self.segments.t_s = f.t_s;
            std::mem::swap(&mut self.segments.segments, &mut f.segments);
            sink.write(id(Channel::Segments), "/segments", t_ns, &self.segments)?;
        }
        if id(Channel::Guides).is_some() {
            let m = &mut self.guides;
            m.t_s = f.t_s;
            m.guides.clear();
            m.guides
                .extend(f.shoes.iter().enumerate().map(|(k, s)| GuideSignal {
                    guide: (k + 1) as u32,
                    normal_n: s.normal_n,
                    friction_n: s.friction_n,
                    force_x_n: s.force_n[0],
                    force_y_n: s.force_n[1],
                    contacts: s.contacts as u32,
                }));
            sink.write(id(Channel::Guides), "/guides", t_ns, m)?;
        }
        if id(Channel::Tensioners).is_some() {
            let m = &mut self.tensioners;
            m.t_s = f.t_s;
            m.tensioners.clear();
            m.tensioners.extend(
                f.tensioners
                    .iter()
                    .enumerate()
                    .map(|(k, r)| TensionerSignal {
                        tensioner: (k + 1) as u32,
                        travel_m: r.travel_m,
                        speed_m_s: r.plunger_speed_m_s,
                        pressure_pa: r.pressure_pa,
                        valve_open: r.valve_open,
                        arm_angle_rad: r.angle_rad,
                        shoe_force_n: r.shoe_force_n,
                        plunger_force_n: r.plunger_force_n,
                    }),
            );
            sink.write(id(Channel::Tensioners), "/tensioners", t_ns, m)?;
        }
        Ok(())
    }
}
