//! The run's own messages (`super::messages`) mirrored for decoding with
//! `prost` (field numbers in declaration order), and Foxglove's point cloud
//! and frame transforms read back into plain numbers. Each decoder returns a
//! sentence on a message that does not decode; what to do with it is the
//! reader's (`super::read`).

use std::collections::BTreeMap;

use foxglove::schemas::{FrameTransforms, PointCloud};
use prost::Message as _;

/// `ChainLinkForces` / `ChainContactForces`.
#[derive(Clone, PartialEq, prost::Message)]
struct ForcesPb {
    #[prost(double, tag = "1")]
    t_s: f64,
    #[prost(double, repeated, tag = "2")]
    force_n: Vec<f64>,
}

/// `SprocketSignals`.
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

/// `SegmentSignal` (its segment read as any varint, as written: `uint32`).
#[derive(Clone, PartialEq, prost::Message)]
struct SegmentPb {
    #[prost(uint64, tag = "1")]
    segment: u64,
    #[prost(double, optional, tag = "2")]
    link_force_n: Option<f64>,
    #[prost(double, tag = "3")]
    transverse_m: f64,
}

/// `SegmentSignals`.
#[derive(Clone, PartialEq, prost::Message)]
struct SegmentsPb {
    #[prost(double, tag = "1")]
    t_s: f64,
    #[prost(message, repeated, tag = "2")]
    segments: Vec<SegmentPb>,
}

/// `TensionerSignal` (its arm number read as any varint, as written: `uint32`).
#[derive(Clone, PartialEq, prost::Message)]
struct TensionerPb {
    #[prost(uint64, tag = "1")]
    tensioner: u64,
    #[prost(double, tag = "2")]
    travel_m: f64,
    #[prost(double, tag = "3")]
    speed_m_s: f64,
    #[prost(double, tag = "4")]
    pressure_pa: f64,
    #[prost(bool, tag = "5")]
    valve_open: bool,
    #[prost(double, tag = "6")]
    arm_angle_rad: f64,
    #[prost(double, tag = "7")]
    shoe_force_n: f64,
    #[prost(double, tag = "8")]
    plunger_force_n: f64,
}

/// `TensionerSignals`.
#[derive(Clone, PartialEq, prost::Message)]
struct TensionersPb {
    #[prost(double, tag = "1")]
    t_s: f64,
    #[prost(message, repeated, tag = "2")]
    tensioners: Vec<TensionerPb>,
}

/// `TensionerSignals`, its arms in arm order.
pub(super) fn decode_tensioners(buf: &[u8]) -> Result<super::TensionerSignals, String> {
    let mut m = TensionersPb::decode(buf).map_err(|e| e.to_string())?;
    m.tensioners.sort_by_key(|t| t.tensioner);
    let tensioners = m
        .tensioners
        .into_iter()
        .map(|t| {
            Ok(super::TensionerSignal {
                tensioner: u32::try_from(t.tensioner)
                    .map_err(|_| format!("arm number {} out of range", t.tensioner))?,
                travel_m: t.travel_m,
                speed_m_s: t.speed_m_s,
                pressure_pa: t.pressure_pa,
                valve_open: t.valve_open,
                arm_angle_rad: t.arm_angle_rad,
                shoe_force_n: t.shoe_force_n,
                plunger_force_n: t.plunger_force_n,
            })
        })
        .collect::<Result<_, String>>()?;
    Ok(super::TensionerSignals {
        t_s: m.t_s,
        tensioners,
    })
}

/// `ChainLinkForces` / `ChainContactForces`: (t, values).
pub(super) fn decode_forces(buf: &[u8]) -> Result<(f64, Vec<f64>), String> {
    let m = ForcesPb::decode(buf).map_err(|e| e.to_string())?;
    Ok((m.t_s, m.force_n))
}

/// `SprocketSignals`: (t, speeds, chain moments).
pub(super) fn decode_sprockets(buf: &[u8]) -> Result<(f64, Vec<f64>, Vec<f64>), String> {
    let m = SprocketsPb::decode(buf).map_err(|e| e.to_string())?;
    Ok((m.t_s, m.speed_rad_s, m.chain_torque_n_m))
}

/// `SegmentSignals`: (t, forces, transverse displacements), in segment order.
type SegmentsMsg = (f64, Vec<Option<f64>>, Vec<f64>);

pub(super) fn decode_segments(buf: &[u8]) -> Result<SegmentsMsg, String> {
    let mut m = SegmentsPb::decode(buf).map_err(|e| e.to_string())?;
    m.segments.sort_by_key(|s| s.segment);
    Ok((
        m.t_s,
        m.segments.iter().map(|s| s.link_force_n).collect(),
        m.segments.iter().map(|s| s.transverse_m).collect(),
    ))
}

/// `foxglove.PointCloud` of f32 x, y: the roller centres.
/// The sprocket frames' translations (`sprocket1`, ... in order), m.
pub(super) fn decode_centers(buf: &[u8], sprockets: usize) -> Result<Vec<[f64; 2]>, String> {
    let tf = FrameTransforms::decode(buf).map_err(|e| e.to_string())?;
    Ok((0..sprockets)
        .map(|k| {
            let frame = super::visual::sprocket_frame(k);
            tf.transforms
                .iter()
                .find(|t| t.child_frame_id == frame)
                .and_then(|t| t.translation.as_ref())
                .map_or([f64::NAN; 2], |v| [v.x, v.y])
        })
        .collect())
}

pub(super) fn decode_cloud(buf: &[u8]) -> Result<Vec<[f64; 2]>, String> {
    let cloud = PointCloud::decode(buf).map_err(|e| e.to_string())?;
    let stride = cloud.point_stride as usize;
    let offsets: BTreeMap<&str, usize> = cloud
        .fields
        .iter()
        .map(|f| (f.name.as_str(), f.offset as usize))
        .collect();
    let (ox, oy) = (
        offsets.get("x").copied().unwrap_or(0),
        offsets.get("y").copied().unwrap_or(4),
    );
    if stride < 8 || ox + 4 > stride || oy + 4 > stride {
        return Err(format!("unsupported point layout (stride {stride})"));
    }
    let f = |c: &[u8], o: usize| {
        c.get(o..o + 4)
            .and_then(|b| b.try_into().ok())
            .map_or(f64::NAN, |b| f64::from(f32::from_le_bytes(b)))
    };
    Ok(cloud
        .data
        .chunks_exact(stride)
        .map(|c| [f(c, ox), f(c, oy)])
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forces_decode_from_packed_and_unpacked_doubles() {
        // field 1 = 1.5 (fixed64), field 2 = [2.0] unpacked, field 2 = [3.0, 4.0] packed.
        let mut buf = vec![0x09];
        buf.extend(1.5f64.to_le_bytes());
        buf.push(0x11);
        buf.extend(2.0f64.to_le_bytes());
        buf.extend([0x12, 16]);
        buf.extend(3.0f64.to_le_bytes());
        buf.extend(4.0f64.to_le_bytes());
        let (t, v) = decode_forces(&buf).expect("decodes");
        assert_eq!(t, 1.5);
        assert_eq!(v, vec![2.0, 3.0, 4.0]);
        assert!(decode_forces(&buf[..5]).is_err());
    }

    #[test]
    fn derived_messages_decode() {
        use crate::record::{SegmentSignal, SegmentSignals, SprocketSignals};
        use foxglove::Encode;
        let msg = SegmentSignals {
            t_s: 0.25,
            segments: vec![
                SegmentSignal {
                    segment: 1,
                    link_force_n: Some(21e3),
                    transverse_m: -1e-3,
                },
                SegmentSignal {
                    segment: 2,
                    link_force_n: None,
                    transverse_m: 2e-3,
                },
            ],
        };
        let mut buf = Vec::new();
        msg.encode(&mut buf).expect("encodes");
        let (t, f, d) = decode_segments(&buf).expect("decodes");
        assert_eq!(t, 0.25);
        assert_eq!(f, vec![Some(21e3), None]);
        assert_eq!(d, vec![-1e-3, 2e-3]);
        let msg = SprocketSignals {
            t_s: 1.0,
            angle_rad: vec![0.1, 0.2],
            speed_rad_s: vec![12.0, -3.0],
            chain_torque_n_m: vec![5.0, 6.0],
        };
        buf.clear();
        msg.encode(&mut buf).expect("encodes");
        let (t, speed, torque) = decode_sprockets(&buf).expect("decodes");
        assert_eq!((t, speed, torque), (1.0, vec![12.0, -3.0], vec![5.0, 6.0]));
    }

    #[test]
    fn point_cloud_decodes() {
        use foxglove::Encode;
        use foxglove::schemas::{PackedElementField, PointCloud, packed_element_field};
        let mut data = Vec::new();
        for (x, y) in [(1.0f32, 0.5f32), (-2.5, 3.0)] {
            data.extend(x.to_le_bytes());
            data.extend(y.to_le_bytes());
            data.extend(0.0f32.to_le_bytes());
        }
        let field = |name: &str, offset: u32| PackedElementField {
            name: name.to_owned(),
            offset,
            r#type: packed_element_field::NumericType::Float32 as i32,
        };
        let cloud = PointCloud {
            // x, y, z only, as recordings made before the colour fields.
            point_stride: 12,
            fields: vec![field("x", 0), field("y", 4), field("z", 8)],
            data: foxglove::bytes::Bytes::from(data),
            ..PointCloud::default()
        };
        let mut buf = Vec::new();
        Encode::encode(&cloud, &mut buf).expect("encodes");
        let xy = decode_cloud(&buf).expect("decodes");
        assert_eq!(xy, vec![[1.0, 0.5], [-2.5, 3.0]]);
    }
}
