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

use crate::model::DriveModel;
use crate::scene::Scene;

/// The fixed frame of the world.
pub const WORLD_FRAME: &str = "world";

/// Number of colour bins of the link-force colour map.
pub const FORCE_BINS: usize = 16;

/// Outline sampling step of the real tooth profile, rad.
const OUTLINE_STEP_RAD: f64 = 2.0 * std::f64::consts::PI / 180.0;

/// Frame name of sprocket `i` (0-based): `sprocket1`, `sprocket2`, ….
pub fn sprocket_frame(i: usize) -> String {
    format!("sprocket{}", i + 1)
}

/// Simulated time as a protobuf timestamp.
pub fn timestamp(t_ns: u64) -> Timestamp {
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
pub fn bin_color(b: usize) -> Color {
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
pub fn static_scene(scene: &Scene, model: &DriveModel, t_ns: u64) -> SceneUpdate {
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
        .collect();
    SceneUpdate {
        deletions: Vec::new(),
        entities,
    }
}

/// The chain entity of `/scene`, updated in place at every sample.
pub struct ChainScene {
    update: SceneUpdate,
    /// Link force at the top of the colour scale, N.
    full_scale_n: f64,
}

impl ChainScene {
    /// The chain of `rollers` rollers of radius `roller_radius_m`; link
    /// colours span 0 … `full_scale_n` in [`FORCE_BINS`] bins.
    pub fn new(rollers: usize, roller_radius_m: f64, full_scale_n: f64) -> Self {
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
            full_scale_n: if full_scale_n > 0.0 {
                full_scale_n
            } else {
                1.0
            },
        }
    }

    /// The update at a sample: roller centres and link forces.
    pub fn update(
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

/// Force bin of a link force (slack and compressed links in bin 0).
fn force_bin(force_n: f64, full_scale_n: f64) -> usize {
    let s = force_n / full_scale_n * FORCE_BINS as f64;
    if s.is_finite() {
        (s.max(0.0) as usize).min(FORCE_BINS - 1)
    } else {
        0
    }
}

/// `/tf`: world → sprocket frames (translation to the centre, rotation by θ about z).
pub fn transforms(centers_m: &[[f64; 2]], theta: &[f64], t_ns: u64, out: &mut FrameTransforms) {
    if out.transforms.len() != centers_m.len() {
        out.transforms = (0..centers_m.len())
            .map(|i| FrameTransform {
                parent_frame_id: WORLD_FRAME.to_owned(),
                child_frame_id: sprocket_frame(i),
                ..FrameTransform::default()
            })
            .collect();
    }
    for ((tf, c), &th) in out.transforms.iter_mut().zip(centers_m).zip(theta) {
        tf.timestamp = Some(timestamp(t_ns));
        tf.translation = Some(Vector3 {
            x: c[0],
            y: c[1],
            z: 0.0,
        });
        let half = 0.5 * if th.is_finite() { th } else { 0.0 };
        tf.rotation = Some(Quaternion {
            x: 0.0,
            y: 0.0,
            z: half.sin(),
            w: half.cos(),
        });
    }
}

/// Bytes per point of `/rollers`: x, y, z as little-endian f32.
pub const POINT_STRIDE: u32 = 12;

/// `/rollers`: roller centres as a point cloud in the world frame (f32 x, y, z = 0).
pub fn roller_cloud(x: &[f64], y: &[f64], t_ns: u64) -> PointCloud {
    let mut data = Vec::with_capacity(x.len() * POINT_STRIDE as usize);
    for (&xi, &yi) in x.iter().zip(y) {
        data.extend_from_slice(&(xi as f32).to_le_bytes());
        data.extend_from_slice(&(yi as f32).to_le_bytes());
        data.extend_from_slice(&0.0f32.to_le_bytes());
    }
    let field = |name: &str, offset: u32| PackedElementField {
        name: name.to_owned(),
        offset,
        r#type: packed_element_field::NumericType::Float32 as i32,
    };
    PointCloud {
        timestamp: Some(timestamp(t_ns)),
        frame_id: WORLD_FRAME.to_owned(),
        pose: Some(identity_pose()),
        point_stride: POINT_STRIDE,
        fields: vec![field("x", 0), field("y", 4), field("z", 8)],
        data: Bytes::from(data),
    }
}
