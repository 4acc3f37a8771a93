//! What a viewer that draws only point clouds and frames (Rerun) sees in a
//! recording: the sprocket outlines, sent once in their own frames, turned
//! by `/tf`, with the rollers of `/rollers` seated in their teeth, and the
//! rollers coloured by link force.

use crate::record::{Channels, OUTLINE_SPACING_M, RecordOptions, Recorder, RunEnd};
use crate::scene::{Overrides, ProfileKind, Scene};
use crate::sim::{SampleRate, Simulation};
use crate::test_support::l60mc;
use foxglove::schemas::{FrameTransforms, PointCloud};
use std::collections::BTreeMap;
use std::io::Cursor;

/// Messages per topic (log time, bytes) and schema name per topic.
struct Messages {
    by_topic: BTreeMap<String, Vec<(u64, Vec<u8>)>>,
    schema: BTreeMap<String, String>,
}

impl Messages {
    fn decode<T: prost::Message + Default>(&self, topic: &str) -> Vec<(u64, T)> {
        self.by_topic
            .get(topic)
            .map(|v| {
                v.iter()
                    .map(|(t, d)| (*t, T::decode(&d[..]).expect("decodes")))
                    .collect()
            })
            .unwrap_or_default()
    }
}

/// Runs `scene` for its duration at 1 kHz, recording `channels` in memory.
fn record(scene: &Scene, channels: Channels) -> Messages {
    let mut sim = Simulation::new(scene).expect("sim");
    let sampling = SampleRate::new(1000.0, scene.solver().dt_s).expect("whole steps");
    let options = RecordOptions {
        channels,
        scene_file: None,
        rate_hz: sampling.rate_hz,
    };
    let mut recorder = Recorder::new(Cursor::new(Vec::new()), scene, &options).expect("recorder");
    sim.run(
        scene.solver().duration_s,
        sampling.every,
        &mut recorder,
        None,
    )
    .expect("run");
    let bytes = recorder
        .finish(RunEnd::Completed)
        .expect("finish")
        .into_inner();
    let mut by_topic: BTreeMap<String, Vec<(u64, Vec<u8>)>> = BTreeMap::new();
    let mut schema = BTreeMap::new();
    for m in mcap::MessageStream::new(&bytes).expect("mcap") {
        let m = m.expect("message");
        let name = m.channel.schema.as_ref().map(|s| s.name.clone());
        schema.insert(m.channel.topic.clone(), name.unwrap_or_default());
        by_topic
            .entry(m.channel.topic.clone())
            .or_default()
            .push((m.log_time, m.data.to_vec()));
    }
    Messages { by_topic, schema }
}

/// A cloud's points: (x, y) and, where the cloud has them, (red, green, blue, alpha).
fn points(cloud: &PointCloud) -> Vec<([f64; 2], Option<[u8; 4]>)> {
    let offset = |name: &str| {
        cloud
            .fields
            .iter()
            .find(|f| f.name == name)
            .map(|f| f.offset as usize)
    };
    let (ox, oy) = (offset("x").expect("x"), offset("y").expect("y"));
    let rgba = ["red", "green", "blue", "alpha"].map(offset);
    let f = |c: &[u8], o: usize| f64::from(f32::from_le_bytes(c[o..o + 4].try_into().expect("4")));
    cloud
        .data
        .chunks_exact(cloud.point_stride as usize)
        .map(|c| {
            let colour = match rgba {
                [Some(r), Some(g), Some(b), Some(a)] => Some([c[r], c[g], c[b], c[a]]),
                _ => None,
            };
            ([f(c, ox), f(c, oy)], colour)
        })
        .collect()
}

fn scene_with(profile: ProfileKind, duration_s: f64) -> Scene {
    l60mc(duration_s)
        .with(&Overrides {
            profile: Some(profile),
            ..Overrides::default()
        })
        .expect("valid overrides")
}

#[test]
fn outline_clouds_are_sent_once_dense_and_in_their_frames() {
    let scene = scene_with(ProfileKind::Circular, 0.02);
    let rec = record(&scene, Channels::OUTLINES | Channels::TRANSFORMS);
    let chain = scene.chain();
    let mut colours = Vec::new();
    for (i, sprocket) in scene.sprockets().iter().enumerate() {
        let topic = format!("/outlines/sprocket{}", i + 1);
        assert_eq!(rec.schema[&topic], "foxglove.PointCloud", "{topic}");
        let clouds = rec.decode::<PointCloud>(&topic);
        // Sent once, at the first sample (t = 0 after static equilibrium).
        assert_eq!(clouds.len(), 1, "{topic}");
        assert_eq!(clouds[0].0, 0, "{topic}");
        let cloud = &clouds[0].1;
        assert_eq!(cloud.frame_id, format!("sprocket{}", i + 1));
        let pts = points(cloud);

        // About 0.5 mm apart along the outline, the closing gap included:
        // no gap wider than the spacing (+ f32 rounding), median within 10 %.
        let mut gaps: Vec<f64> = (0..pts.len())
            .map(|k| {
                let (a, b) = (pts[k].0, pts[(k + 1) % pts.len()].0);
                (b[0] - a[0]).hypot(b[1] - a[1])
            })
            .collect();
        gaps.sort_by(f64::total_cmp);
        let widest = gaps[gaps.len() - 1];
        assert!(widest <= OUTLINE_SPACING_M + 1e-6, "{topic}: gap {widest}");
        let median = gaps[gaps.len() / 2];
        assert!(
            (median - OUTLINE_SPACING_M).abs() < 0.1 * OUTLINE_SPACING_M,
            "{topic}: median gap {median}"
        );

        // Circular profile (docs/tooth-profile.md): seating arcs of radius
        // R_t centred at R_s + ΔR, ΔR = R_t − R_r, the half facing the centre.
        // The root lies at R_s − R_r, the arcs' ends at √((R_s + ΔR)² + R_t²).
        // R_s = P / (2 sin(π/N)); R_t = (1.005 D_r + 0.003 in) / 2 (ASA B29.1).
        let r_s = chain.pitch_m / (2.0 * (std::f64::consts::PI / f64::from(sprocket.teeth)).sin());
        let r_t = (1.005 * 2.0 * chain.roller_radius_m + 0.003 * 0.0254) / 2.0;
        let dr = r_t - chain.roller_radius_m;
        let radii: Vec<f64> = pts.iter().map(|(p, _)| p[0].hypot(p[1])).collect();
        let root = radii.iter().copied().fold(f64::INFINITY, f64::min);
        let tip = radii.iter().copied().fold(0.0, f64::max);
        // f32 coordinates: 1e-6 m covers their rounding at 0.2 m; the root
        // sample sits within 0.25 mm of the arc's lowest point (sag < 6 µm).
        assert!(
            (root - (r_s - chain.roller_radius_m)).abs() < 1e-5,
            "{topic}: root {root}"
        );
        assert!(
            (tip - (r_s + dr).hypot(r_t)).abs() < 1e-6,
            "{topic}: tip {tip}"
        );

        // One colour per sprocket.
        let colour = pts[0].1.expect("colour fields");
        assert!(pts.iter().all(|(_, c)| *c == Some(colour)), "{topic}");
        colours.push(colour);
    }
    colours.sort_unstable();
    colours.dedup();
    assert_eq!(colours.len(), scene.sprockets().len(), "distinct colours");
}

/// Distance from `p` (world) to the nearest point of an outline cloud in the
/// frame at `center` turned by the unit quaternion about z (z, w).
fn nearest_outline_m(p: [f64; 2], outline: &[[f64; 2]], center: [f64; 2], zw: [f64; 2]) -> f64 {
    let theta = 2.0 * zw[0].atan2(zw[1]);
    let (s, c) = theta.sin_cos();
    outline
        .iter()
        .map(|q| {
            let x = center[0] + c * q[0] - s * q[1];
            let y = center[1] + s * q[0] + c * q[1];
            (x - p[0]).hypot(y - p[1])
        })
        .fold(f64::INFINITY, f64::min)
}

/// The rollers seated in the recorded outlines, placed by the recorded
/// frames: at t = 0 and at t = 0.1 s (after the sprockets have turned), for
/// both profiles. A roller touching an outline has its centre R_r from it,
/// less its penetration δ = (F / K_g)^(2/3): with the paper's K_g = 1 GN/m^1.5,
/// below 1.5 mm for any contact force under K_g (1.5 mm)^1.5 = 58 kN (the
/// deepest in a 2 s run of the paper's drive, whose strands carry 20–36 kN,
/// is 0.82 mm: `chaindrive run --duration 2`). A frame turned the wrong way would
/// put a tooth through a roller, up to R_r = 27 mm deep (12 mm when the
/// rotation's sign is flipped).
#[test]
fn rollers_sit_in_the_teeth_of_the_recorded_outlines() {
    for profile in [ProfileKind::Circular, ProfileKind::Real] {
        let scene = scene_with(profile, 0.1);
        let rec = record(
            &scene,
            Channels::OUTLINES | Channels::TRANSFORMS | Channels::ROLLERS,
        );
        let r_r = scene.chain().roller_radius_m;
        let outlines: Vec<Vec<[f64; 2]>> = (0..scene.sprockets().len())
            .map(|i| {
                let cloud = &rec.decode::<PointCloud>(&format!("/outlines/sprocket{}", i + 1))[0].1;
                points(cloud).into_iter().map(|(p, _)| p).collect()
            })
            .collect();
        let tfs = rec.decode::<FrameTransforms>("/tf");
        let rollers = rec.decode::<PointCloud>("/rollers");
        let mut turned = 0.0f64;
        for k in [0, rollers.len() - 1] {
            let (t_ns, cloud) = &rollers[k];
            let (tf_t, tf) = &tfs[k];
            assert_eq!(t_ns, tf_t);
            let mut seated = vec![0usize; outlines.len()];
            for (p, _) in points(cloud) {
                for (i, outline) in outlines.iter().enumerate() {
                    let frame = &tf.transforms[i];
                    assert_eq!(frame.child_frame_id, format!("sprocket{}", i + 1));
                    let tr = frame.translation.as_ref().expect("translation");
                    let q = frame.rotation.as_ref().expect("rotation");
                    turned = turned.max(2.0 * q.z.atan2(q.w).abs());
                    let d = nearest_outline_m(p, outline, [tr.x, tr.y], [q.z, q.w]);
                    assert!(
                        d > r_r - 1.5e-3,
                        "{profile:?}, t = {t_ns} ns: an outline of sprocket {} runs {:.3} mm inside a roller",
                        i + 1,
                        (r_r - d) * 1e3
                    );
                    if d < r_r + 0.05e-3 {
                        seated[i] += 1;
                    }
                }
            }
            // Every sprocket holds rollers in its teeth (the paper's drive
            // wraps each over several pitches).
            for (i, n) in seated.iter().enumerate() {
                assert!(
                    *n >= 3,
                    "{profile:?}, t = {t_ns} ns: sprocket {}: {n} seated",
                    i + 1
                );
            }
        }
        assert!(
            turned > 0.1,
            "{profile:?}: the sprockets turned {turned} rad"
        );
    }
}

/// The colour scale of `/rollers`: each roller takes the mean force of its
/// two links on the links' scale (blue at 0 or below, red at 2 × pretension
/// and above). Checked by order, not by formula: redder never means less force.
#[test]
fn roller_colours_follow_their_links_force() {
    let scene = l60mc(0.05);
    let rec = record(&scene, Channels::ROLLERS | Channels::LINKS);
    #[derive(Clone, PartialEq, prost::Message)]
    struct Links {
        #[prost(double, tag = "1")]
        t_s: f64,
        #[prost(double, repeated, tag = "2")]
        force_n: Vec<f64>,
    }
    let links = rec.decode::<Links>("/links");
    let rollers = rec.decode::<PointCloud>("/rollers");
    let full_scale_n = 2.0 * scene.chain().pretension_n;
    let mut pairs = Vec::new();
    for ((_, l), (_, cloud)) in links.iter().zip(&rollers) {
        let n = l.force_n.len();
        for (i, (_, colour)) in points(cloud).into_iter().enumerate() {
            let mean = 0.5 * (l.force_n[(i + n - 1) % n] + l.force_n[i]);
            pairs.push((mean, colour.expect("colour fields")));
        }
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    for w in pairs.windows(2) {
        let ([r0, _, b0, a0], [r1, _, b1, _]) = (w[0].1, w[1].1);
        assert_eq!(a0, 255);
        assert!(r1 >= r0 && b1 <= b0, "{:?} then {:?}", w[0], w[1]);
    }
    for (force, colour) in &pairs {
        if *force <= 0.0 {
            assert_eq!(*colour, [0, 0, 255, 255], "{force} N");
        }
        if *force >= full_scale_n {
            assert_eq!(*colour, [255, 0, 0, 255], "{force} N");
        }
    }
    // The drive's strands span the scale: tight ones red-ish, slack ones blue-ish.
    let reds = pairs.iter().filter(|(_, c)| c[0] > c[2]).count();
    let blues = pairs.iter().filter(|(_, c)| c[2] > c[0]).count();
    assert!(reds > 0 && blues > 0, "{reds} reddish, {blues} bluish");
}
