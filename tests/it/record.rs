//! MCAP recordings read back through the `mcap` crate's reader: in memory
//! through the library API, and from files written by the real binary,
//! including runs that blow up or are interrupted with SIGINT.

use std::collections::BTreeMap;
use std::io::Cursor;
#[cfg(feature = "cli")]
use std::path::Path;
#[cfg(feature = "cli")]
use std::time::{Duration, Instant};

use approx::abs_diff_eq;

use chaindrive::analysis::{RunSummary, Signals, SummaryInputs};
use chaindrive::record::{Channels, RecordOptions, Recorder, RunEnd};
use chaindrive::scene::{L60MC_TOML, Scene};
use chaindrive::sim::{Observer, Sample, SampleRate, Simulation};
use foxglove::schemas::{FrameTransforms, PointCloud, SceneUpdate};
use prost::Message as _;

use crate::common::l60mc;
#[cfg(feature = "cli")]
use crate::common::{command, stderr};

// Mirrors of the derived schemas (field numbers in declaration order); the
// test `derived_schemas_name_their_fields` checks them against the file's
// own descriptors.
#[derive(Clone, PartialEq, prost::Message)]
struct ForcesPb {
    #[prost(double, tag = "1")]
    t_s: f64,
    #[prost(double, repeated, tag = "2")]
    force_n: Vec<f64>,
}

#[derive(Clone, PartialEq, prost::Message)]
struct SprocketsPb {
    #[prost(double, tag = "1")]
    t_s: f64,
    #[prost(double, repeated, tag = "2")]
    angle_rad: Vec<f64>,
    #[prost(double, repeated, tag = "3")]
    speed_rad_s: Vec<f64>,
    #[prost(double, repeated, tag = "4")]
    chain_torque_n_m: Vec<f64>,
}

#[derive(Clone, PartialEq, prost::Message)]
struct SegmentPb {
    #[prost(uint32, tag = "1")]
    segment: u32,
    #[prost(double, optional, tag = "2")]
    link_force_n: Option<f64>,
    #[prost(double, tag = "3")]
    transverse_m: f64,
}

#[derive(Clone, PartialEq, prost::Message)]
struct SegmentsPb {
    #[prost(double, tag = "1")]
    t_s: f64,
    #[prost(message, repeated, tag = "2")]
    segments: Vec<SegmentPb>,
}

/// A recording as read back: messages per topic, schema per topic, metadata
/// and attachments.
struct Recording {
    messages: BTreeMap<String, Vec<(u64, Vec<u8>)>>,
    schemas: BTreeMap<String, (String, String, Vec<u8>)>,
    metadata: BTreeMap<String, BTreeMap<String, String>>,
    attachments: BTreeMap<String, Vec<u8>>,
}

impl Recording {
    fn read(bytes: &[u8]) -> Self {
        let summary = mcap::Summary::read(bytes)
            .expect("summary readable")
            .expect("file has a summary section (it was finished)");
        let mut schemas = BTreeMap::new();
        for c in summary.channels.values() {
            let s = c.schema.as_ref().expect("every channel has a schema");
            schemas.insert(
                c.topic.clone(),
                (s.name.clone(), s.encoding.clone(), s.data.to_vec()),
            );
            assert_eq!(c.message_encoding, "protobuf", "{}", c.topic);
        }
        let mut messages: BTreeMap<String, Vec<(u64, Vec<u8>)>> = BTreeMap::new();
        for m in mcap::MessageStream::new(bytes).expect("stream") {
            let m = m.expect("message readable");
            messages
                .entry(m.channel.topic.clone())
                .or_default()
                .push((m.log_time, m.data.to_vec()));
        }
        let metadata = summary
            .metadata_indexes
            .iter()
            .map(|i| {
                let m = mcap::read::metadata(bytes, i).expect("metadata");
                (m.name, m.metadata)
            })
            .collect();
        let attachments = summary
            .attachment_indexes
            .iter()
            .map(|i| {
                let a = mcap::read::attachment(bytes, i).expect("attachment");
                (a.name, a.data.to_vec())
            })
            .collect();
        Self {
            messages,
            schemas,
            metadata,
            attachments,
        }
    }

    fn count(&self, topic: &str) -> usize {
        self.messages.get(topic).map_or(0, Vec::len)
    }

    fn decode<T: prost::Message + Default>(&self, topic: &str) -> Vec<(u64, T)> {
        self.messages
            .get(topic)
            .map(|v| {
                v.iter()
                    .map(|(t, d)| (*t, T::decode(&d[..]).expect("decodes")))
                    .collect()
            })
            .unwrap_or_default()
    }

    fn end_status(&self) -> &str {
        &self.metadata["chaindrive.end"]["status"]
    }
}

/// Two observers at once: the signals for the summary and the recorder.
struct Both<'a, W: std::io::Write + std::io::Seek + Send + 'static> {
    signals: &'a mut Signals,
    recorder: &'a mut Recorder<W>,
}

impl<W: std::io::Write + std::io::Seek + Send + 'static> Observer for Both<'_, W> {
    fn sample(&mut self, s: &Sample<'_>) {
        self.signals.sample(s);
        self.recorder.sample(s);
    }
    fn step(&mut self, s: &Sample<'_>) {
        self.signals.step(s);
    }
    fn per_step_from_s(&self) -> f64 {
        self.signals.per_step_from_s()
    }
}

/// Runs `scene` at `rate_hz`, recording `channels` in memory; returns the
/// file's bytes and the summary of the run's samples (a recording holds
/// samples: its means are theirs, not the steps', `means_every_step`).
fn record_in_memory(scene: &Scene, rate_hz: f64, channels: Channels) -> (Vec<u8>, RunSummary) {
    let mut sim = Simulation::new(scene).expect("sim");
    let sampling = SampleRate::new(rate_hz, scene.solver().dt_s).expect("a whole number of steps");
    let mut signals = Signals::new(&sim.model, sampling.rate_hz, 0.0);
    let options = RecordOptions {
        channels,
        scene_file: Some(("l60mc.toml".to_owned(), L60MC_TOML.as_bytes().to_vec())),
        rate_hz: sampling.rate_hz,
    };
    let mut recorder = Recorder::new(Cursor::new(Vec::new()), scene, &options).expect("recorder");
    let outcome = sim
        .run(
            scene.solver().duration_s,
            sampling.every,
            &mut Both {
                signals: &mut signals,
                recorder: &mut recorder,
            },
            None,
        )
        .expect("run");
    let bytes = recorder
        .finish(RunEnd::Completed)
        .expect("finish")
        .into_inner();
    for row in &mut signals.rows {
        row.step_sums = Default::default();
    }
    let summary = RunSummary::compute(
        &SummaryInputs {
            scene,
            model: &sim.model,
            static_tension_n: sim.equilibrium.tension_n,
            static_force_residual: None,
            static_unsettled_cause: None,
            steps: outcome.steps,
            wall_s: outcome.wall_s,
            setup_wall_s: 0.0,
            interrupted: outcome.interrupted,
            max_penetration_m: outcome.max_penetration_m,
        },
        &signals,
    );
    (bytes, summary)
}

const PER_SAMPLE_TOPICS: [&str; 7] = [
    "/scene",
    "/tf",
    "/rollers",
    "/links",
    "/contacts",
    "/sprockets",
    "/segments",
];

#[test]
fn library_round_trip_matches_the_run_summary() {
    // 1.5 s at 1 kHz: the statistics window (the last second) is fully recorded.
    let scene = l60mc(1.5);
    let rate = 1000.0;
    let (bytes, summary) = record_in_memory(&scene, rate, Channels::all());
    let rec = Recording::read(&bytes);

    // Schemas: Foxglove's well-known ones where one fits, derived protobuf otherwise.
    let schema = |t: &str| rec.schemas[t].0.as_str();
    assert_eq!(schema("/scene/static"), "foxglove.SceneUpdate");
    assert_eq!(schema("/scene"), "foxglove.SceneUpdate");
    assert_eq!(schema("/tf"), "foxglove.FrameTransforms");
    assert_eq!(schema("/rollers"), "foxglove.PointCloud");
    assert!(schema("/links").ends_with(".ChainLinkForces"));
    assert!(schema("/contacts").ends_with(".ChainContactForces"));
    assert!(schema("/sprockets").ends_with(".SprocketSignals"));
    assert!(schema("/segments").ends_with(".SegmentSignals"));
    for (topic, (_, encoding, data)) in &rec.schemas {
        assert_eq!(encoding, "protobuf", "{topic}");
        assert!(!data.is_empty(), "{topic}: descriptor set");
    }

    // Counts: duration × rate, ±1 (the sample at t = 0 is the +1).
    let expected = scene.solver().duration_s * rate;
    for topic in PER_SAMPLE_TOPICS {
        let n = rec.count(topic) as f64;
        assert!((n - expected).abs() <= 1.0, "{topic}: {n} messages");
    }
    assert_eq!(rec.count("/scene/static"), 1);

    // Log times are simulated time, at the sample rate.
    let times: Vec<u64> = rec.messages["/sprockets"].iter().map(|m| m.0).collect();
    assert_eq!(times[0], 0);
    assert_eq!(times[1], 1_000_000);
    assert_eq!(*times.last().expect("frames"), 1_500_000_000);

    // 122 rollers per frame, in the point cloud and in the scene.
    for (_, cloud) in rec.decode::<PointCloud>("/rollers") {
        assert_eq!(cloud.data.len() / cloud.point_stride as usize, 122);
        assert_eq!(cloud.frame_id, "world");
    }
    for (_, update) in rec.decode::<SceneUpdate>("/scene") {
        assert_eq!(update.entities[0].spheres.len(), 122);
        let link_points: usize = update.entities[0]
            .lines
            .iter()
            .map(|l| l.points.len())
            .sum();
        assert_eq!(link_points, 2 * 122);
    }
    let static_scene = &rec.decode::<SceneUpdate>("/scene/static")[0].1;
    assert_eq!(static_scene.entities.len(), 4);
    assert_eq!(static_scene.entities[0].frame_id, "sprocket1");
    assert!(static_scene.entities[0].lines[0].points.len() > 60);
    let tf = &rec.decode::<FrameTransforms>("/tf")[0].1;
    assert_eq!(tf.transforms.len(), 4);
    assert_eq!(tf.transforms[1].child_frame_id, "sprocket2");

    // Decoded values reproduce the summary over its window (t_end − 1 s, t_end].
    let [w0, w1] = summary.window_s;
    let in_window = |t: u64| {
        let t = t as f64 * 1e-9;
        t > w0 + 1e-12 && t <= w1 + 1e-12
    };
    let segments = rec.decode::<SegmentsPb>("/segments");
    for (k, seg) in summary.segments.iter().enumerate() {
        let forces: Vec<f64> = segments
            .iter()
            .filter(|(t, _)| in_window(*t))
            .filter_map(|(_, m)| m.segments[k].link_force_n)
            .collect();
        assert!(!forces.is_empty(), "segment {}", k + 1);
        let mean = forces.iter().sum::<f64>() / forces.len() as f64;
        assert!(
            abs_diff_eq!(
                mean,
                seg.mean_link_force_n,
                epsilon = 1e-9 * seg.mean_link_force_n.abs()
            ),
            "segment {}: recorded mean {mean} vs summary {}",
            k + 1,
            seg.mean_link_force_n
        );
    }
    let sprockets = rec.decode::<SprocketsPb>("/sprockets");
    for (i, sp) in summary.sprockets.iter().enumerate() {
        let speeds: Vec<f64> = sprockets
            .iter()
            .filter(|(t, _)| in_window(*t))
            .map(|(_, m)| m.speed_rad_s[i])
            .collect();
        let mean = speeds.iter().sum::<f64>() / speeds.len() as f64;
        assert!(
            abs_diff_eq!(
                mean,
                sp.mean_speed_rad_s,
                epsilon = 1e-9 * sp.mean_speed_rad_s.abs().max(1e-9)
            ),
            "sprocket {}: {mean} vs {}",
            i + 1,
            sp.mean_speed_rad_s
        );
    }
    // Link forces: the extremes over the window's samples lie within the
    // summary's per-step extremes.
    let links = rec.decode::<ForcesPb>("/links");
    for (t, m) in &links {
        assert_eq!(m.force_n.len(), 122);
        if in_window(*t) {
            for &f in &m.force_n {
                assert!(f >= summary.link_force_min_n && f <= summary.link_force_max_n);
            }
        }
    }
    let contacts = rec.decode::<ForcesPb>("/contacts");
    assert!(contacts.iter().all(|(_, m)| m.force_n.len() == 122));
    assert!(
        contacts
            .last()
            .is_some_and(|(_, m)| m.force_n.iter().any(|&f| f > 0.0))
    );

    // Metadata and the scene file.
    let meta = &rec.metadata["chaindrive"];
    assert_eq!(meta["scene"], scene.name());
    assert_eq!(meta["profile"], "circular");
    assert_eq!(meta["contact_law"], summary.contact_law);
    assert_eq!(meta["integrator"], summary.integrator);
    assert_eq!(meta["dt_s"].parse::<f64>().expect("dt"), 1e-5);
    assert_eq!(meta["version"], env!("CARGO_PKG_VERSION"));
    assert_eq!(rec.attachments["l60mc.toml"], L60MC_TOML.as_bytes());
    assert_eq!(rec.end_status(), "completed");
}

#[test]
fn derived_schemas_name_their_fields() {
    // The test's prost mirrors rely on these names and numbers.
    let (bytes, _) = record_in_memory(&l60mc(0.01), 1000.0, Channels::all());
    let rec = Recording::read(&bytes);
    let fields = |topic: &str| -> Vec<(String, i32)> {
        let set = prost_types::FileDescriptorSet::decode(&rec.schemas[topic].2[..])
            .expect("descriptor set");
        let name = rec.schemas[topic]
            .0
            .rsplit('.')
            .next()
            .expect("name")
            .to_owned();
        set.file
            .iter()
            .flat_map(|f| &f.message_type)
            .find(|m| m.name() == name)
            .expect("message in its descriptor set")
            .field
            .iter()
            .map(|f| (f.name().to_owned(), f.number()))
            .collect()
    };
    let named = |v: &[(&str, i32)]| -> Vec<(String, i32)> {
        v.iter().map(|(n, i)| ((*n).to_owned(), *i)).collect()
    };
    assert_eq!(
        fields("/links"),
        named(&[("t_s", 1), ("force_n", 2), ("joint_friction_moment_n_m", 3)])
    );
    assert_eq!(
        fields("/sprockets"),
        named(&[
            ("t_s", 1),
            ("angle_rad", 2),
            ("speed_rad_s", 3),
            ("chain_torque_n_m", 4)
        ])
    );
    assert_eq!(fields("/segments"), named(&[("t_s", 1), ("segments", 2)]));
}

#[test]
fn identical_runs_give_identical_recordings_and_unrequested_channels_are_absent() {
    let scene = l60mc(0.05);
    let (a, _) = record_in_memory(&scene, 1000.0, Channels::all());
    let (b, _) = record_in_memory(&scene, 1000.0, Channels::all());
    assert!(a == b, "two identical runs differ");

    let only = Channels::parse("sprockets, segments").expect("valid list");
    let (c, _) = record_in_memory(&scene, 1000.0, only);
    let rec = Recording::read(&c);
    let topics: Vec<&str> = rec.schemas.keys().map(String::as_str).collect();
    assert_eq!(topics, ["/segments", "/sprockets"]);
    assert_eq!(rec.count("/sprockets"), 51);
    assert!(Channels::parse("scene,bogus").is_err());
    assert!(Channels::parse("").is_err());
}

#[cfg(feature = "cli")]
#[test]
fn binary_records_a_readable_file_at_the_series_rate() {
    let dir = tempfile::tempdir().expect("tmp");
    let path = dir.path().join("run.mcap");
    let out = command()
        .args([
            "run",
            "--duration",
            "0.3",
            "--rate",
            "200",
            "--quiet",
            "--record",
        ])
        .arg(&path)
        .output()
        .expect("binary runs");
    assert!(out.status.success(), "{}", stderr(&out));
    let rec = Recording::read(&std::fs::read(&path).expect("file"));
    for topic in PER_SAMPLE_TOPICS {
        assert_eq!(rec.count(topic), 61, "{topic}");
    }
    assert_eq!(rec.metadata["chaindrive"]["sample_rate_hz"], "200");
    assert_eq!(rec.attachments["l60mc.toml"], L60MC_TOML.as_bytes());
    assert_eq!(rec.end_status(), "completed");
}

#[cfg(feature = "cli")]
#[test]
fn unwritable_recording_path_fails_before_simulating() {
    let started = Instant::now();
    let out = command()
        .args(["run", "--record", "/nonexistent-dir/x.mcap"])
        .output()
        .expect("binary runs");
    assert!(!out.status.success());
    let err = stderr(&out);
    assert!(
        err.contains("recording") && err.contains("/nonexistent-dir/x.mcap"),
        "{err}"
    );
    assert!(
        started.elapsed() < Duration::from_secs(5),
        "it simulated first"
    );
    let out = command()
        .args([
            "run",
            "--record",
            "x.mcap",
            "--record-channels",
            "scene,nope",
        ])
        .current_dir(tempfile::tempdir().expect("tmp").path())
        .output()
        .expect("binary runs");
    assert!(!out.status.success());
    assert!(stderr(&out).contains("nope"));
}

/// The paper's drive with a driver speed it cannot take: it blows up ~20 ms
/// into the run (penetration detector), after static equilibrium.
#[cfg(feature = "cli")]
fn blow_up_scene(dir: &Path) -> std::path::PathBuf {
    let text = L60MC_TOML.replace("speed_rpm = 120.0", "speed_rpm = 2000.0");
    assert_ne!(text, L60MC_TOML);
    let path = dir.join("too_fast.toml");
    std::fs::write(&path, text).expect("write scene");
    path
}

#[cfg(feature = "cli")]
#[test]
fn a_run_that_blows_up_leaves_a_readable_recording() {
    let dir = tempfile::tempdir().expect("tmp");
    let scene = blow_up_scene(dir.path());
    let path = dir.path().join("blow-up.mcap");
    let out = command()
        .arg("run")
        .arg(&scene)
        .args(["--duration", "1", "--quiet", "--record"])
        .arg(&path)
        .output()
        .expect("binary runs");
    assert!(!out.status.success());
    assert!(stderr(&out).contains("blow-up"));
    let rec = Recording::read(&std::fs::read(&path).expect("file"));
    let frames = rec.count("/rollers");
    assert!(frames > 5 && frames < 1000, "{frames} frames");
    assert_eq!(rec.end_status(), "failed");
    assert!(rec.metadata["chaindrive.end"]["message"].contains("blow-up"));
    assert_eq!(
        rec.attachments["too_fast.toml"].len(),
        std::fs::read(&scene).expect("scene").len()
    );

    // A run that fails before t = 0 (the static equilibrium cannot meet a
    // tolerance below rounding: 1e-17 of the pretension is under half an
    // ulp, so only an exact hit would pass) still leaves a finished file:
    // metadata and channels, no messages.
    let unreachable = dir.path().join("unreachable.toml");
    std::fs::write(
        &unreachable,
        format!("{L60MC_TOML}\n[equilibrium]\ntension_tolerance = 1e-17\n"),
    )
    .expect("write scene");
    let path = dir.path().join("setup.mcap");
    let out = command()
        .arg("run")
        .arg(&unreachable)
        .args(["--quiet", "--record"])
        .arg(&path)
        .output()
        .expect("binary runs");
    assert!(!out.status.success());
    let rec = Recording::read(&std::fs::read(&path).expect("file"));
    assert_eq!(rec.count("/rollers"), 0);
    assert!(rec.metadata.contains_key("chaindrive"));
}

#[cfg(feature = "cli")]
#[test]
fn a_run_interrupted_with_sigint_leaves_a_readable_recording() {
    let dir = tempfile::tempdir().expect("tmp");
    let path = dir.path().join("interrupted.mcap");
    let mut child = command()
        .args(["run", "--duration", "60", "--quiet", "--record"])
        .arg(&path)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("binary starts");
    // Wait until the stepping loop has written a few compressed chunks.
    let started = Instant::now();
    while std::fs::metadata(&path).map_or(0, |m| m.len()) < 400_000 {
        assert!(
            started.elapsed() < Duration::from_secs(60),
            "no data recorded in 60 s"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let killed = std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(killed.success());
    let status = child.wait().expect("binary ends");
    assert_eq!(status.code(), Some(130), "Ctrl-C exit code");
    let rec = Recording::read(&std::fs::read(&path).expect("file"));
    assert_eq!(rec.end_status(), "interrupted");
    let frames = rec.count("/rollers");
    assert!(frames > 10, "{frames} frames");
    for topic in PER_SAMPLE_TOPICS {
        assert!(rec.count(topic).abs_diff(frames) <= 1, "{topic}");
    }
    assert_eq!(rec.metadata["chaindrive.end"]["frames"], frames.to_string());
}

#[derive(Clone, PartialEq, prost::Message)]
struct LinksPb {
    #[prost(double, tag = "1")]
    t_s: f64,
    #[prost(double, repeated, tag = "2")]
    force_n: Vec<f64>,
    #[prost(double, repeated, tag = "3")]
    joint_friction_moment_n_m: Vec<f64>,
}

/// `/links` carries every joint's friction moment. Read back, each obeys the
/// Coulomb bound of the scene's law against the recorded link forces:
/// |M_i| ≤ μ r_pin F_pin with F_pin = max(0, (F_{i−1} + F_i) / 2), the mean
/// of the two links at roller i (no viscous term in this scene); and, at
/// full speed (after the 1 s ramp), the joints articulating where the chain
/// enters and leaves a wrap reach that bound (the cubic step saturated).
#[test]
fn links_channel_carries_joint_friction_moments_within_the_coulomb_bound() {
    let text = std::fs::read_to_string(format!(
        "{}/assets/l60mc-friction.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .expect("the friction scene");
    let scene = Scene::from_toml(&text)
        .expect("valid scene")
        .with(&chaindrive::scene::Overrides {
            duration_s: Some(1.1),
            ..Default::default()
        })
        .expect("override");
    let (mu, r_pin) = (0.10, 0.01715);
    let (bytes, _) = record_in_memory(&scene, 1000.0, Channels::all());
    let rec = Recording::read(&bytes);
    let links = rec.decode::<LinksPb>("/links");
    assert!(links.len() >= 1000, "{} samples", links.len());
    let (mut saturated, mut joints) = (0usize, 0usize);
    for (_, m) in &links {
        let n = m.force_n.len();
        let full_speed = m.t_s > 1.0;
        assert_eq!(m.joint_friction_moment_n_m.len(), n);
        for i in 0..n {
            let pin = (0.5 * (m.force_n[(i + n - 1) % n] + m.force_n[i])).max(0.0);
            let bound = mu * r_pin * pin;
            let moment = m.joint_friction_moment_n_m[i].abs();
            assert!(
                moment <= bound * (1.0 + 1e-9) + 1e-12,
                "joint {i}: |M| {moment} > {bound}"
            );
            joints += 1;
            if full_speed && moment > 0.9 * bound && bound > 0.0 {
                saturated += 1;
            }
        }
    }
    assert!(saturated > 0, "no joint slides: {saturated} of {joints}");
}
