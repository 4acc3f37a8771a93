//! The 3D scene in Foxglove's schemas: the static sprocket geometry (sent
//! once, each sprocket in its own frame), the frames' motion, and the chain
//! (rollers and links coloured by force) at every sample.
//!
//! Messages are kept between samples and updated in place, so a frame
//! allocates only the point cloud's byte buffer.

use foxglove::bytes::Bytes;
use foxglove::schemas::{
    Color, FrameTransform, FrameTransforms, LinePrimitive, PackedElementField, Point3, PointCloud,
    Pose, Quaternion, SceneEntity, SceneUpdate, SpherePrimitive, TextPrimitive, Timestamp, Vector3,
    line_primitive, packed_element_field,
};

use crate::geometry::ToothProfile;
use crate::model::DriveModel;
use crate::scene::Scene;

/// The fixed frame of the world.
pub(crate) const WORLD_FRAME: &str = "world";

/// Number of colour bins of the link-force colour map.
pub(crate) const FORCE_BINS: usize = 16;

/// Outline sampling step of the real tooth profile, rad.
const OUTLINE_STEP_RAD: f64 = 2.0 * std::f64::consts::PI / 180.0;

/// Angular step of the fine outline that [`outline_points`] walks along, rad
/// (0.1°: chords of at most 0.2 µm sag on a 10 mm arc).
const FINE_OUTLINE_STEP_RAD: f64 = 0.1 * std::f64::consts::PI / 180.0;

/// Spacing of the points of an outline cloud (`/outlines/sprocketN`) along
/// the outline, m: dense enough to read as a line.
pub(crate) const OUTLINE_SPACING_M: f64 = 0.5e-3;

/// Topic prefix of the outline clouds: sprocket `i` (0-based) is on
/// `/outlines/sprocket{i + 1}`.
pub(crate) const OUTLINES_TOPIC: &str = "/outlines";

/// Topic of sprocket `i`'s outline cloud (0-based): `/outlines/sprocket1`, ….
pub(crate) fn outline_topic(i: usize) -> String {
    format!("{OUTLINES_TOPIC}/{}", sprocket_frame(i))
}

/// Frame name of sprocket `i` (0-based): `sprocket1`, `sprocket2`, ….
pub(crate) fn sprocket_frame(i: usize) -> String {
    format!("sprocket{}", i + 1)
}

/// Simulated time as a protobuf timestamp.
pub(super) fn timestamp(t_ns: u64) -> Timestamp {
    let sec = u32::try_from(t_ns / 1_000_000_000).unwrap_or(u32::MAX);
    let nsec = (t_ns % 1_000_000_000) as u32;
    Timestamp::new_checked(sec, nsec).unwrap_or(Timestamp::MAX)
}

fn identity_pose() -> Pose {
    Pose {
        position: Some(Vector3::default()),
        orientation: Some(Quaternion {
            w: 1.0,
            ..Quaternion::default()
        }),
    }
}

fn grey(level: f64) -> Color {
    Color {
        r: level,
        g: level,
        b: level,
        a: 1.0,
    }
}

/// Colour of force bin `b` of [`FORCE_BINS`]: blue (slack) through cyan,
/// green and yellow to red (the top of the scale).
pub(crate) fn bin_color(b: usize) -> Color {
    let s = b as f64 / (FORCE_BINS - 1) as f64;
    // Piecewise-linear "jet": four ramps over [0, 1].
    let ramp = |x: f64| x.clamp(0.0, 1.0);
    Color {
        r: ramp(4.0 * s - 2.0),
        g: ramp(if s < 0.5 { 4.0 * s } else { 4.0 - 4.0 * s }),
        b: ramp(2.0 - 4.0 * s),
        a: 1.0,
    }
}

/// The static geometry: per sprocket an entity in its own frame, locked to
/// it, with the tooth outline, the pitch circle, a spoke to gap 0 (so that
/// rotation shows) and the sprocket's name.
pub(super) fn static_scene(scene: &Scene, model: &DriveModel, t_ns: u64) -> SceneUpdate {
    let entities = model
        .sprockets
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let outline: Vec<Point3> = s
                .profile
                .outline(OUTLINE_STEP_RAD)
                .iter()
                .map(|p| Point3 {
                    x: p.x_m,
                    y: p.y_m,
                    z: 0.0,
                })
                .collect();
            let circle: Vec<Point3> = (0..360)
                .map(|k| {
                    let a = f64::from(k) * std::f64::consts::TAU / 360.0;
                    Point3 {
                        x: s.pitch_radius_m * a.cos(),
                        y: s.pitch_radius_m * a.sin(),
                        z: 0.0,
                    }
                })
                .collect();
            let name = scene
                .sprockets
                .get(i)
                .map_or_else(String::new, |sp| sp.name.clone());
            SceneEntity {
                timestamp: Some(timestamp(t_ns)),
                frame_id: sprocket_frame(i),
                id: format!("sprocket{}", i + 1),
                frame_locked: true,
                lines: vec![
                    LinePrimitive {
                        r#type: line_primitive::Type::LineLoop as i32,
                        pose: Some(identity_pose()),
                        thickness: 2.0,
                        scale_invariant: true,
                        points: outline,
                        color: Some(grey(0.85)),
                        ..LinePrimitive::default()
                    },
                    LinePrimitive {
                        r#type: line_primitive::Type::LineLoop as i32,
                        pose: Some(identity_pose()),
                        thickness: 1.0,
                        scale_invariant: true,
                        points: circle,
                        color: Some(grey(0.5)),
                        ..LinePrimitive::default()
                    },
                    LinePrimitive {
                        r#type: line_primitive::Type::LineStrip as i32,
                        pose: Some(identity_pose()),
                        thickness: 2.0,
                        scale_invariant: true,
                        points: vec![
                            Point3::default(),
                            Point3 {
                                x: s.pitch_radius_m,
                                y: 0.0,
                                z: 0.0,
                            },
                        ],
                        color: Some(grey(0.85)),
                        ..LinePrimitive::default()
                    },
                ],
                texts: vec![TextPrimitive {
                    pose: Some(identity_pose()),
                    billboard: true,
                    font_size: 14.0,
                    scale_invariant: true,
                    color: Some(grey(1.0)),
                    text: format!("{} {name}", i + 1),
                }],
                ..SceneEntity::default()
            }
        })
        .collect::<Vec<_>>();
    let guides = scene.guides.iter().enumerate().map(|(k, g)| {
        let face = &g.face;
        let piece = |p: &crate::geometry::shoe::Piece| -> Vec<Point3> {
            let n = match p {
                crate::geometry::shoe::Piece::Segment { .. } => 1,
                crate::geometry::shoe::Piece::Arc { sweep_rad, .. } => {
                    ((sweep_rad / OUTLINE_STEP_RAD).ceil() as usize).clamp(1, 720)
                }
            };
            (0..=n)
                .map(|i| {
                    let q = p.point_at(i as f64 / n as f64);
                    Point3 {
                        x: q[0],
                        y: q[1],
                        z: 0.0,
                    }
                })
                .collect()
        };
        let mut points = face.start_ramp.as_ref().map(piece).unwrap_or_default();
        points.extend(piece(&face.body));
        if let Some(r) = &face.end_ramp {
            points.extend(piece(r));
        }
        let label = face.middle_m();
        SceneEntity {
            timestamp: Some(timestamp(t_ns)),
            frame_id: WORLD_FRAME.to_owned(),
            id: format!("guide{}", k + 1),
            frame_locked: true,
            lines: vec![LinePrimitive {
                r#type: line_primitive::Type::LineStrip as i32,
                pose: Some(identity_pose()),
                thickness: 3.0,
                scale_invariant: true,
                points,
                color: Some(grey(0.85)),
                ..LinePrimitive::default()
            }],
            texts: vec![TextPrimitive {
                pose: Some(Pose {
                    position: Some(Vector3 {
                        x: label[0],
                        y: label[1],
                        z: 0.0,
                    }),
                    ..identity_pose()
                }),
                billboard: true,
                font_size: 14.0,
                scale_invariant: true,
                color: Some(grey(1.0)),
                text: format!("guide {} {}", k + 1, g.name),
            }],
            ..SceneEntity::default()
        }
    });
    SceneUpdate {
        deletions: Vec::new(),
        entities: entities
            .into_iter()
            .chain(guides)
            .chain(tensioner_arms(scene, t_ns))
            .collect(),
    }
}

/// Each tensioner arm in its frame `tensionerN` (origin at the pivot, at
/// the scene's pose for angle 0), frame-locked: the shoe's arc, the arm from
/// the pivot to the shoe's ends and to the point the tensioner pushes, and
/// its name.
fn tensioner_arms(scene: &Scene, t_ns: u64) -> impl Iterator<Item = SceneEntity> + '_ {
    scene.tensioners.iter().enumerate().map(move |(k, t)| {
        let local = |p: [f64; 2]| Point3 {
            x: p[0] - t.pivot_m[0],
            y: p[1] - t.pivot_m[1],
            z: 0.0,
        };
        let n = ((t.shoe_span_rad / OUTLINE_STEP_RAD).ceil() as usize).clamp(1, 720);
        let arc: Vec<Point3> = (0..=n)
            .map(|i| {
                let a = t.shoe_start_rad + t.shoe_span_rad * i as f64 / n as f64;
                local([
                    t.shoe_center_m[0] + t.shoe_radius_m * a.cos(),
                    t.shoe_center_m[1] + t.shoe_radius_m * a.sin(),
                ])
            })
            .collect();
        let pivot = Point3::default();
        let (first, last) = (arc[0], arc[arc.len() - 1]);
        let arm = vec![pivot, first, pivot, last, pivot, local(t.point_m)];
        let line =
            |kind: line_primitive::Type, points: Vec<Point3>, thickness: f64| LinePrimitive {
                r#type: kind as i32,
                pose: Some(identity_pose()),
                thickness,
                scale_invariant: true,
                points,
                color: Some(grey(0.85)),
                ..LinePrimitive::default()
            };
        SceneEntity {
            timestamp: Some(timestamp(t_ns)),
            frame_id: tensioner_frame(k),
            id: tensioner_frame(k),
            frame_locked: true,
            lines: vec![
                line(line_primitive::Type::LineStrip, arc, 3.0),
                line(line_primitive::Type::LineList, arm, 1.5),
            ],
            texts: vec![TextPrimitive {
                pose: Some(identity_pose()),
                billboard: true,
                font_size: 14.0,
                scale_invariant: true,
                color: Some(grey(1.0)),
                text: format!("tensioner {} {}", k + 1, t.name),
            }],
            ..SceneEntity::default()
        }
    })
}

/// The chain entity of `/scene`, updated in place at every sample.
pub(super) struct ChainScene {
    update: SceneUpdate,
    /// Link force at the top of the colour scale, N.
    full_scale_n: f64,
}

impl ChainScene {
    /// The chain of `rollers` rollers of radius `roller_radius_m`; link
    /// colours span 0 … `full_scale_n` in [`FORCE_BINS`] bins.
    pub(super) fn new(rollers: usize, roller_radius_m: f64, full_scale_n: f64) -> Self {
        let d = 2.0 * roller_radius_m;
        let sphere = SpherePrimitive {
            pose: Some(identity_pose()),
            size: Some(Vector3 { x: d, y: d, z: d }),
            color: Some(grey(0.35)),
        };
        let lines = (0..FORCE_BINS)
            .map(|b| LinePrimitive {
                r#type: line_primitive::Type::LineList as i32,
                pose: Some(identity_pose()),
                thickness: 4.0,
                scale_invariant: true,
                color: Some(bin_color(b)),
                ..LinePrimitive::default()
            })
            .collect();
        let entity = SceneEntity {
            frame_id: WORLD_FRAME.to_owned(),
            id: "chain".to_owned(),
            spheres: vec![sphere; rollers],
            lines,
            ..SceneEntity::default()
        };
        Self {
            update: SceneUpdate {
                deletions: Vec::new(),
                entities: vec![entity],
            },
            full_scale_n: full_scale(full_scale_n),
        }
    }

    /// The update at a sample: roller centres and link forces.
    pub(super) fn update(
        &mut self,
        t_ns: u64,
        x: &[f64],
        y: &[f64],
        link_force_n: &[f64],
    ) -> &SceneUpdate {
        let full_scale_n = self.full_scale_n;
        if let Some(e) = self.update.entities.first_mut() {
            e.timestamp = Some(timestamp(t_ns));
            for ((s, &xi), &yi) in e.spheres.iter_mut().zip(x).zip(y) {
                if let Some(p) = s.pose.as_mut().and_then(|p| p.position.as_mut()) {
                    p.x = xi;
                    p.y = yi;
                }
            }
            for l in &mut e.lines {
                l.points.clear();
            }
            let n = x.len();
            for (i, &f) in link_force_n.iter().enumerate().take(n) {
                let b = force_bin(f, full_scale_n);
                let j = if i + 1 == n { 0 } else { i + 1 };
                if let Some(l) = e.lines.get_mut(b) {
                    l.points.push(Point3 {
                        x: x[i],
                        y: y[i],
                        z: 0.0,
                    });
                    l.points.push(Point3 {
                        x: x[j],
                        y: y[j],
                        z: 0.0,
                    });
                }
            }
        }
        &self.update
    }
}

/// The top of a force colour scale, N: `full_scale_n` if positive and
/// finite, otherwise 1 N.
pub(crate) fn full_scale(full_scale_n: f64) -> f64 {
    if full_scale_n.is_finite() && full_scale_n > 0.0 {
        full_scale_n
    } else {
        1.0
    }
}

/// Force bin of a link force (slack and compressed links in bin 0).
fn force_bin(force_n: f64, full_scale_n: f64) -> usize {
    let s = force_n / full_scale_n * FORCE_BINS as f64;
    if s.is_finite() {
        (s.max(0.0) as usize).min(FORCE_BINS - 1)
    } else {
        0
    }
}

/// The frame of tensioner arm `k` (0-based): `tensioner{k+1}`.
pub(super) fn tensioner_frame(k: usize) -> String {
    format!("tensioner{}", k + 1)
}

/// `world` → `sprocketN` (centre, rotation θ) for every sprocket, then
/// `world` → `tensionerN` (pivot, the arm's angle) for every arm. An arm
/// without an angle in `arm_angles_rad` (a sample whose readings were not
/// finite) keeps its last pose.
pub(super) fn transforms(
    centers_m: &[[f64; 2]],
    theta: &[f64],
    pivots_m: &[[f64; 2]],
    arm_angles_rad: &[f64],
    t_ns: u64,
    out: &mut FrameTransforms,
) {
    let n = centers_m.len();
    if out.transforms.len() != n + pivots_m.len() {
        out.transforms = (0..n)
            .map(sprocket_frame)
            .chain((0..pivots_m.len()).map(tensioner_frame))
            .map(|child| FrameTransform {
                parent_frame_id: WORLD_FRAME.to_owned(),
                child_frame_id: child,
                ..FrameTransform::default()
            })
            .collect();
    }
    let place = |tf: &mut FrameTransform, c: [f64; 2], th: Option<f64>| {
        tf.timestamp = Some(timestamp(t_ns));
        tf.translation = Some(Vector3 {
            x: c[0],
            y: c[1],
            z: 0.0,
        });
        if let Some(th) = th {
            let half = 0.5 * if th.is_finite() { th } else { 0.0 };
            tf.rotation = Some(Quaternion {
                x: 0.0,
                y: 0.0,
                z: half.sin(),
                w: half.cos(),
            });
        } else if tf.rotation.is_none() {
            tf.rotation = Some(Quaternion {
                x: 0.0,
                y: 0.0,
                z: 0.0,
                w: 1.0,
            });
        }
    };
    let (sprockets, arms) = out.transforms.split_at_mut(n);
    for ((tf, c), &th) in sprockets.iter_mut().zip(centers_m).zip(theta) {
        place(tf, *c, Some(th));
    }
    for (k, (tf, c)) in arms.iter_mut().zip(pivots_m).enumerate() {
        place(tf, *c, arm_angles_rad.get(k).copied());
    }
}

/// `world` → `name` for one of the user's bodies: its position and angle.
pub(super) fn body_transform(name: &str, c: [f64; 2], th: f64, t_ns: u64) -> FrameTransform {
    let half = 0.5 * th;
    FrameTransform {
        timestamp: Some(timestamp(t_ns)),
        parent_frame_id: WORLD_FRAME.to_owned(),
        child_frame_id: name.to_owned(),
        translation: Some(Vector3 {
            x: c[0],
            y: c[1],
            z: 0.0,
        }),
        rotation: Some(Quaternion {
            x: 0.0,
            y: 0.0,
            z: half.sin(),
            w: half.cos(),
        }),
    }
}

/// Bytes per point of `/rollers` and of the outline clouds: x, y, z as
/// little-endian f32, then red, green, blue, alpha as u8 (0–255).
pub(crate) const POINT_STRIDE: u32 = 16;

/// The fields of a [`POINT_STRIDE`] point: f32 x, y, z and u8 red, green,
/// blue, alpha, the names Foxglove's "RGBA (separate fields)" colour mode and
/// Rerun's point-cloud import read.
fn point_fields() -> Vec<PackedElementField> {
    use packed_element_field::NumericType;
    let field = |name: &str, offset: u32, ty: NumericType| PackedElementField {
        name: name.to_owned(),
        offset,
        r#type: ty as i32,
    };
    vec![
        field("x", 0, NumericType::Float32),
        field("y", 4, NumericType::Float32),
        field("z", 8, NumericType::Float32),
        field("red", 12, NumericType::Uint8),
        field("green", 13, NumericType::Uint8),
        field("blue", 14, NumericType::Uint8),
        field("alpha", 15, NumericType::Uint8),
    ]
}

/// A colour as four bytes (0–255).
fn rgba8(c: &Color) -> [u8; 4] {
    let byte = |v: f64| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    [byte(c.r), byte(c.g), byte(c.b), byte(c.a)]
}

/// Appends one point of [`POINT_STRIDE`] bytes.
fn push_point(data: &mut Vec<u8>, x: f64, y: f64, rgba: [u8; 4]) {
    data.extend_from_slice(&(x as f32).to_le_bytes());
    data.extend_from_slice(&(y as f32).to_le_bytes());
    data.extend_from_slice(&0.0f32.to_le_bytes());
    data.extend_from_slice(&rgba);
}

/// A point cloud of [`point_fields`] in `frame_id`.
fn cloud(frame_id: String, data: Vec<u8>, t_ns: u64) -> PointCloud {
    PointCloud {
        timestamp: Some(timestamp(t_ns)),
        frame_id,
        pose: Some(identity_pose()),
        point_stride: POINT_STRIDE,
        fields: point_fields(),
        data: Bytes::from(data),
    }
}

/// Force of roller `i` on the colour scale: the mean of its two links'
/// forces (link i − 1 ends at roller i, link i starts there), N.
fn roller_force_n(link_force_n: &[f64], i: usize) -> f64 {
    let n = link_force_n.len();
    if n == 0 {
        return 0.0;
    }
    let before = link_force_n[(i + n - 1) % n];
    let after = link_force_n[i % n];
    0.5 * (before + after)
}

/// `/rollers`: roller centres as a point cloud in the world frame (f32 x, y,
/// z = 0), each coloured by the mean force of its two links on the links'
/// scale ([`bin_color`] of 0 … `full_scale_n` in [`FORCE_BINS`] bins; grey
/// when the link forces are not given).
pub(super) fn roller_cloud(
    x: &[f64],
    y: &[f64],
    link_force_n: &[f64],
    full_scale_n: f64,
    t_ns: u64,
) -> PointCloud {
    let colors: Vec<[u8; 4]> = (0..FORCE_BINS).map(|b| rgba8(&bin_color(b))).collect();
    let mut data = Vec::with_capacity(x.len() * POINT_STRIDE as usize);
    for (i, (&xi, &yi)) in x.iter().zip(y).enumerate() {
        let rgba = if link_force_n.len() == x.len() {
            let b = force_bin(roller_force_n(link_force_n, i), full_scale_n);
            colors.get(b).copied().unwrap_or([255; 4])
        } else {
            rgba8(&grey(0.6))
        };
        push_point(&mut data, xi, yi, rgba);
    }
    cloud(WORLD_FRAME.to_owned(), data, t_ns)
}

/// Colour of sprocket `i`'s outline (0-based), from a palette of eight that
/// stands out against the force colours' blue … red and a dark background.
pub(crate) fn sprocket_color(i: usize) -> [u8; 4] {
    const PALETTE: [[u8; 4]; 8] = [
        [255, 255, 255, 255], // white
        [255, 105, 180, 255], // pink
        [255, 165, 0, 255],   // orange
        [160, 120, 255, 255], // violet
        [170, 255, 170, 255], // pale green
        [120, 200, 255, 255], // sky blue
        [255, 230, 120, 255], // pale yellow
        [200, 200, 200, 255], // light grey
    ];
    PALETTE[i % PALETTE.len()]
}

/// A sprocket's outline, in its frame, as points about `spacing_m` apart
/// along it: the tooth profile sampled finely and walked at equal arc
/// length, the closing stretch back to the start included.
pub(crate) fn outline_points(profile: &ToothProfile, spacing_m: f64) -> Vec<[f64; 2]> {
    let fine: Vec<[f64; 2]> = profile
        .outline(FINE_OUTLINE_STEP_RAD)
        .iter()
        .map(|p| [p.x_m, p.y_m])
        .collect();
    resample_closed(&fine, spacing_m)
}

/// Points every `spacing_m` of arc length along the closed polyline `pts`
/// (the last point joins the first), starting at the first.
fn resample_closed(pts: &[[f64; 2]], spacing_m: f64) -> Vec<[f64; 2]> {
    let Some(&first) = pts.first() else {
        return Vec::new();
    };
    if !(spacing_m.is_finite() && spacing_m > 0.0) {
        return pts.to_vec();
    }
    let mut out = vec![first];
    // Arc length from the last point written to the start of the current piece.
    let mut since_m = 0.0;
    for (k, a) in pts.iter().enumerate() {
        let b = pts[(k + 1) % pts.len()];
        let len_m = (b[0] - a[0]).hypot(b[1] - a[1]);
        let mut s_m = spacing_m - since_m;
        while s_m < len_m {
            let u = s_m / len_m;
            out.push([a[0] + u * (b[0] - a[0]), a[1] + u * (b[1] - a[1])]);
            s_m += spacing_m;
        }
        since_m = len_m - (s_m - spacing_m);
    }
    // The walk ends back at the start: drop a last point closer to it than a
    // tenth of the spacing.
    if let Some(&last) = out.last()
        && out.len() > 1
        && (last[0] - first[0]).hypot(last[1] - first[1]) < 0.1 * spacing_m
    {
        out.pop();
    }
    out
}

/// `/outlines/sprocketN`: sprocket `i`'s outline ([`outline_points`] at
/// [`OUTLINE_SPACING_M`]) as a point cloud in its frame `sprocketN`, in its
/// colour ([`sprocket_color`]). Written once, at the first sample; the
/// frame's transform on `/tf` turns it.
pub(super) fn outline_cloud(profile: &ToothProfile, i: usize, t_ns: u64) -> PointCloud {
    let points = outline_points(profile, OUTLINE_SPACING_M);
    let rgba = sprocket_color(i);
    let mut data = Vec::with_capacity(points.len() * POINT_STRIDE as usize);
    for p in &points {
        push_point(&mut data, p[0], p[1], rgba);
    }
    cloud(sprocket_frame(i), data, t_ns)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resampling_walks_a_closed_polyline_at_equal_arc_length() {
        // A unit square walked every 0.3: arc lengths 0, 0.3, …, 3.9 (14
        // points; 4.0 is the start again). Point k lies at arc length 0.3 k.
        let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let pts = resample_closed(&square, 0.3);
        assert_eq!(pts.len(), 14);
        for (k, p) in pts.iter().enumerate() {
            let s = 0.3 * k as f64;
            let expected = match s {
                s if s <= 1.0 => [s, 0.0],
                s if s <= 2.0 => [1.0, s - 1.0],
                s if s <= 3.0 => [3.0 - s, 1.0],
                s => [0.0, 4.0 - s],
            };
            assert!(
                (p[0] - expected[0]).abs() < 1e-12 && (p[1] - expected[1]).abs() < 1e-12,
                "point {k}: {p:?} vs {expected:?}"
            );
        }
        // Nothing to walk, or no spacing: no panic, no NaN.
        assert!(resample_closed(&[], 0.3).is_empty());
        assert_eq!(resample_closed(&square, f64::NAN).len(), 4);
        assert_eq!(resample_closed(&square, 0.0).len(), 4);
    }
}
