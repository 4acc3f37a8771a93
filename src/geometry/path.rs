//! The chain's path: tangent lines between consecutive sprockets (plain or
//! crossed, from the wrap senses) and the wrap arcs between them.
//!
//! A sprocket with wrap sense s (+1 counter-clockwise) is a circle the chain
//! follows with its centre on the left (s = +1) or right (s = −1) of the
//! direction of travel. For a strand leaving circle i along unit direction t,
//! with left normal n = (−t_y, t_x): c_i = p_i + s_i R_i n. Hence
//! c_j − c_i = L t + (s_j R_j − s_i R_i) n, which fixes t and L in closed form.

use std::f64::consts::TAU;

/// A free strand: the tangent line from sprocket `from` to sprocket `to`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Strand {
    /// Index of the sprocket the strand leaves (0-based).
    pub from: usize,
    /// Index of the sprocket the strand reaches.
    pub to: usize,
    /// Tangent point on `from`, m.
    pub start_m: [f64; 2],
    /// Tangent point on `to`, m.
    pub end_m: [f64; 2],
    /// Length, m.
    pub length_m: f64,
    /// Polar angle of the tangent point about `from`'s centre, in [0, 2π).
    pub angle_on_from_rad: f64,
    /// Polar angle of the tangent point about `to`'s centre, in [0, 2π).
    pub angle_on_to_rad: f64,
}

impl Strand {
    /// Unit direction from start to end.
    pub(crate) fn direction(&self) -> [f64; 2] {
        [
            (self.end_m[0] - self.start_m[0]) / self.length_m,
            (self.end_m[1] - self.start_m[1]) / self.length_m,
        ]
    }
}

/// The arc the chain wraps on one sprocket.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct WrapArc {
    /// Polar angle where the chain arrives, rad.
    pub arrive_rad: f64,
    /// Polar angle where the chain leaves, rad.
    pub leave_rad: f64,
    /// Wrapped angle in [0, 2π), rad, measured in the wrap sense.
    pub wrap_rad: f64,
}

/// Strands and wraps of a closed drive; strand k leaves sprocket k.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ChainPath {
    /// Free strands, strand k from sprocket k to k + 1 (cyclic).
    pub strands: Vec<Strand>,
    /// Wraps, one per sprocket.
    pub wraps: Vec<WrapArc>,
}

impl ChainPath {
    /// Length of chain the free strands hold in their sag beyond their
    /// spans at tension `tension_n`, m: a shallow cable of span L under the
    /// weight per length q⊥ across it holds q⊥² L³ / (24 T²) (parabolic
    /// sag s = q⊥ L² / (8 T), arc − span = 8 s² / (3 L)). `mass_per_m_kg`:
    /// the chain's mass per length.
    pub(crate) fn sag_take_up_m(
        &self,
        mass_per_m_kg: f64,
        gravity_m_s2: [f64; 2],
        tension_n: f64,
    ) -> f64 {
        let [gx, gy] = gravity_m_s2;
        self.strands
            .iter()
            .map(|s| {
                let [dx, dy] = s.direction();
                let q_perp = mass_per_m_kg * (dx * gy - dy * gx).abs();
                q_perp * q_perp * s.length_m.powi(3) / (24.0 * tension_n * tension_n)
            })
            .sum()
    }
}

/// Why no chain path exists.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PathError {
    /// No tangent line with the requested senses (e.g. a crossed strand between overlapping circles).
    #[error(
        "no {kind} tangent from sprocket {from} to sprocket {to}: the circles are too close for these wrap senses"
    )]
    NoTangent {
        /// "plain" or "crossed".
        kind: &'static str,
        /// 1-based index.
        from: usize,
        /// 1-based index.
        to: usize,
    },
}

/// A circle the chain follows: centre, radius, sense (+1 CCW).
#[derive(Clone, Copy, Debug)]
pub(crate) struct PathCircle {
    /// Centre, m.
    pub center_m: [f64; 2],
    /// Radius, m.
    pub radius_m: f64,
    /// +1 counter-clockwise, −1 clockwise.
    pub sense: f64,
}

/// Polar angle wrapped into [0, 2π).
pub(crate) fn wrap_angle(a: f64) -> f64 {
    let r = a.rem_euclid(TAU);
    if r >= TAU { 0.0 } else { r }
}

/// Computes strands and wraps for circles visited in order (closed loop).
pub(crate) fn chain_path(circles: &[PathCircle]) -> Result<ChainPath, PathError> {
    let n = circles.len();
    let mut strands = Vec::with_capacity(n);
    for i in 0..n {
        let j = (i + 1) % n;
        let (a, b) = (circles[i], circles[j]);
        let d = [b.center_m[0] - a.center_m[0], b.center_m[1] - a.center_m[1]];
        let dist = d[0].hypot(d[1]);
        let h = b.sense * b.radius_m - a.sense * a.radius_m;
        let kind = if a.sense == b.sense {
            "plain"
        } else {
            "crossed"
        };
        if !(dist > h.abs()) {
            return Err(PathError::NoTangent {
                kind,
                from: i + 1,
                to: j + 1,
            });
        }
        // sin(θ_d − ψ) = h / |d|
        let psi = d[1].atan2(d[0]) - (h / dist).asin();
        let t = [psi.cos(), psi.sin()];
        let nrm = [-t[1], t[0]];
        let start_m = [
            a.center_m[0] - a.sense * a.radius_m * nrm[0],
            a.center_m[1] - a.sense * a.radius_m * nrm[1],
        ];
        let end_m = [
            b.center_m[0] - b.sense * b.radius_m * nrm[0],
            b.center_m[1] - b.sense * b.radius_m * nrm[1],
        ];
        let polar = |c: &PathCircle, p: [f64; 2]| {
            wrap_angle((p[1] - c.center_m[1]).atan2(p[0] - c.center_m[0]))
        };
        strands.push(Strand {
            from: i,
            to: j,
            start_m,
            end_m,
            length_m: (dist * dist - h * h).sqrt(),
            angle_on_from_rad: polar(&a, start_m),
            angle_on_to_rad: polar(&b, end_m),
        });
    }
    let wraps = (0..n)
        .map(|k| {
            let arrive_rad = strands[(k + n - 1) % n].angle_on_to_rad;
            let leave_rad = strands[k].angle_on_from_rad;
            WrapArc {
                arrive_rad,
                leave_rad,
                wrap_rad: wrap_angle(circles[k].sense * (leave_rad - arrive_rad)),
            }
        })
        .collect();
    Ok(ChainPath { strands, wraps })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_equal_circles_plain_and_crossed() {
        // Plain: length = centre distance; crossed: sqrt(d² − (2R)²).
        let c = |x: f64, s: f64| PathCircle {
            center_m: [x, 0.0],
            radius_m: 1.0,
            sense: s,
        };
        let plain = chain_path(&[c(0.0, 1.0), c(5.0, 1.0)]).expect("path");
        assert!((plain.strands[0].length_m - 5.0).abs() < 1e-12);
        // Chain leaves the left circle at the bottom (CCW) and wraps half of each.
        assert!((plain.strands[0].angle_on_from_rad - 1.5 * std::f64::consts::PI).abs() < 1e-12);
        assert!((plain.wraps[0].wrap_rad - std::f64::consts::PI).abs() < 1e-12);
        let crossed = chain_path(&[c(0.0, 1.0), c(5.0, -1.0)]).expect("path");
        assert!((crossed.strands[0].length_m - 21.0f64.sqrt()).abs() < 1e-12);
        assert!((crossed.strands[1].length_m - 21.0f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn crossed_tangent_of_overlapping_circles_is_an_error() {
        let c = |x: f64, s: f64| PathCircle {
            center_m: [x, 0.0],
            radius_m: 1.0,
            sense: s,
        };
        assert!(chain_path(&[c(0.0, 1.0), c(1.5, -1.0)]).is_err());
    }
}
