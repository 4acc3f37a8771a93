//! The circular tooth profile (the paper's §2.3; docs/tooth-profile.md,
//! “The circular profile”).
//!
//! Each gap j is a seating circle of radius R_t centred at (R_s + ΔR) e_r(jφ),
//! ΔR = R_t − R_r, so that a seated roller rests on the pitch circle. Only the
//! half of the circle facing the sprocket centre is a tooth surface: a roller
//! whose centre lies radially outside the seating centre is free, so it can
//! leave the gap. The gap is found in O(1) from the roller's polar angle.

use super::{MAX_PATCHES, OutlinePoint, Patch, pitch_radius, seating_radius};

/// One seating arc per gap.
#[derive(Clone, Debug)]
pub struct CircularProfile {
    /// Tooth count N.
    pub teeth: u32,
    /// Pitch radius R_s, m.
    pub pitch_radius_m: f64,
    /// Seating-circle radius R_t, m.
    pub seating_radius_m: f64,
    /// Clearance ΔR = R_t − R_r, m.
    pub clearance_m: f64,
    /// Roller radius, m.
    pub roller_radius_m: f64,
    /// N / 2π, to turn a polar angle into a gap index.
    gaps_per_rad: f64,
    /// tan(φ/2): a point is nearest gap j when |u_j × p| ≤ tan(φ/2) (u_j · p).
    tan_half_pitch: f64,
    /// Unit radial direction of each gap centre, (cos jφ, sin jφ).
    gap_dirs: Vec<[f64; 2]>,
    /// Whether a roller radially outside its seat's centre meets the seating
    /// arc's ends, the tooth tips (off: it is free there, the paper's form).
    pub tips: bool,
}

impl CircularProfile {
    /// The profile of a sprocket with `teeth` teeth for a chain of pitch
    /// `pitch_m` and roller radius `roller_radius_m`.
    pub fn new(teeth: u32, pitch_m: f64, roller_radius_m: f64) -> Self {
        let pitch_angle = std::f64::consts::TAU / f64::from(teeth);
        let seating_radius_m = seating_radius(roller_radius_m);
        Self {
            teeth,
            pitch_radius_m: pitch_radius(pitch_m, teeth),
            seating_radius_m,
            clearance_m: seating_radius_m - roller_radius_m,
            roller_radius_m,
            gaps_per_rad: 1.0 / pitch_angle,
            tan_half_pitch: (0.5 * pitch_angle).tan(),
            gap_dirs: (0..teeth)
                .map(|j| {
                    let a = f64::from(j) * pitch_angle;
                    [a.cos(), a.sin()]
                })
                .collect(),
            tips: false,
        }
    }

    /// Index of the gap nearest in polar angle to `p`.
    #[inline]
    pub fn gap_of(&self, p: [f64; 2]) -> u32 {
        let k = (p[1].atan2(p[0]) * self.gaps_per_rad).round() as i64;
        k.rem_euclid(i64::from(self.teeth)) as u32
    }

    /// Index of the gap nearest to `p`, trying `hint` and its neighbours
    /// before falling back to [`Self::gap_of`]: a roller stays in a gap for
    /// many steps, and two products are much cheaper than an `atan2`.
    #[inline(always)]
    pub fn gap_near(&self, p: [f64; 2], hint: u32) -> u32 {
        // The roller is almost always still in its hinted gap: one cone test, inline.
        if let Some(&u) = self.gap_dirs.get(hint as usize) {
            let along = u[0] * p[0] + u[1] * p[1];
            let across = u[0] * p[1] - u[1] * p[0];
            if along > 0.0 && across.abs() <= self.tan_half_pitch * along {
                return hint;
            }
        }
        self.gap_search(p, hint)
    }

    /// [`Self::gap_near`] when `p` has left the hinted gap's cone.
    #[inline(never)]
    fn gap_search(&self, p: [f64; 2], hint: u32) -> u32 {
        let n = self.teeth;
        let mut j = if hint < n { hint } else { 0 };
        for _ in 0..2 {
            let u = self.gap_dirs[j as usize];
            let along = u[0] * p[0] + u[1] * p[1];
            let across = u[0] * p[1] - u[1] * p[0];
            let limit = self.tan_half_pitch * along;
            if along > 0.0 && across.abs() <= limit {
                return j;
            }
            if along <= 0.0 || across.abs() > 3.0 * limit {
                break;
            }
            // Try the neighbour on the side the point lies.
            j = if across > 0.0 {
                (j + 1) % n
            } else {
                (j + n - 1) % n
            };
        }
        self.gap_of(p)
    }

    /// Centre of gap `gap`'s seating circle.
    #[inline]
    pub fn seat_center(&self, gap: u32) -> [f64; 2] {
        let u = self.gap_dirs[gap as usize];
        let r = self.pitch_radius_m + self.clearance_m;
        [r * u[0], r * u[1]]
    }

    /// Contact of a roller centred at `p` (sprocket frame): at most one patch.
    /// `hint` is a gap the roller was recently in (any value works); it is
    /// updated to the gap found.
    #[inline(always)]
    pub fn contacts(&self, p: [f64; 2], hint: &mut u32, out: &mut [Patch; MAX_PATCHES]) -> usize {
        self.seats().contacts(p, hint, out)
    }

    /// What a contact query reads, taken out of the profile once (for a
    /// loop over many rollers).
    #[inline(always)]
    pub(crate) fn seats(&self) -> Seats<'_> {
        Seats {
            profile: self,
            dirs: &self.gap_dirs,
            tan_half_pitch: self.tan_half_pitch,
            seat_radius_m: self.pitch_radius_m + self.clearance_m,
            clearance_m: self.clearance_m,
            clearance_sq_m2: self.clearance_m * self.clearance_m,
            tips: self.tips,
        }
    }

    /// With [`Self::tips`]: contact of a roller radially outside its seat's centre (`e`: from the
    /// seat's centre to the roller's, `u`: the gap's radial direction) with
    /// the nearer end of the seating arc, the tooth's tip corner: none for a
    /// roller leaving the gap radially, but a roller beside the seat at its
    /// centre's radius (a slack chain sliding over the teeth) meets the
    /// corner with the depth and normal the arc has there, so the contact
    /// does not appear at a depth (|e| − ΔR) as the roller crosses the
    /// seat's diameter.
    #[inline(never)]
    fn tip_contact(&self, e: [f64; 2], u: [f64; 2], gap: u32) -> Option<Patch> {
        let t = [-u[1], u[0]];
        let side = if e[0] * t[0] + e[1] * t[1] >= 0.0 {
            1.0
        } else {
            -1.0
        };
        let r = side * self.seating_radius_m;
        let d = [e[0] - r * t[0], e[1] - r * t[1]];
        let len_sq = d[0] * d[0] + d[1] * d[1];
        if !(len_sq < self.roller_radius_m * self.roller_radius_m) || len_sq == 0.0 {
            return None;
        }
        let len = len_sq.sqrt();
        let inv_len = 1.0 / len;
        Some(Patch {
            depth_m: self.roller_radius_m - len,
            normal: [d[0] * inv_len, d[1] * inv_len],
            area: 4,
            gap,
            patch_id: gap,
        })
    }

    /// The whole outline in the sprocket frame, counter-clockwise: each gap's
    /// active seating arc (area 4), sampled at ≤ `max_step_rad` about its
    /// centre, then the straight segment across the tooth to the next gap
    /// (area 0, not a contact surface; docs/tooth-profile.md, “The circular
    /// profile”). Each arc runs from the gap's clockwise side through its bottom to its
    /// counter-clockwise side.
    pub fn outline(&self, max_step_rad: f64) -> Vec<OutlinePoint> {
        use std::f64::consts::PI;
        let step = if max_step_rad.is_finite() && max_step_rad > 0.0 {
            max_step_rad.min(PI / 8.0)
        } else {
            1f64.to_radians()
        };
        let pieces = (PI / step).ceil() as usize;
        let mut out = Vec::with_capacity(self.teeth as usize * (pieces + 1));
        for gap in 0..self.teeth {
            let c = self.seat_center(gap);
            let psi = f64::from(gap) / self.gaps_per_rad;
            for k in 0..=pieces {
                // From ψ − π/2 (clockwise side) down to ψ − 3π/2 (counter-clockwise side).
                let a = psi - 0.5 * PI - PI * k as f64 / pieces as f64;
                out.push(OutlinePoint {
                    x_m: c[0] + self.seating_radius_m * a.cos(),
                    y_m: c[1] + self.seating_radius_m * a.sin(),
                    gap: i64::from(gap),
                    area: if k == pieces { 0 } else { 4 },
                });
            }
        }
        out
    }

    /// The radius beyond which no roller centre can touch this profile.
    pub fn reach_m(&self) -> f64 {
        let rc = self.pitch_radius_m + self.clearance_m;
        if self.tips {
            // A roller touching an arc's end (a tip) reaches a hair further.
            (rc + self.seating_radius_m).max(rc.hypot(self.seating_radius_m) + self.roller_radius_m)
        } else {
            rc + self.seating_radius_m
        }
    }
}

/// A [`CircularProfile`]'s data for contact queries, read out of it once:
/// the gaps' directions and the seat's radii. Answers exactly as
/// [`CircularProfile::contacts`] (which goes through it).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Seats<'a> {
    profile: &'a CircularProfile,
    /// Unit radial direction of each gap centre.
    pub(crate) dirs: &'a [[f64; 2]],
    /// tan(φ/2), the gaps' cone test.
    pub(crate) tan_half_pitch: f64,
    /// R_s + ΔR: the seating circles' centres lie on it, m.
    pub(crate) seat_radius_m: f64,
    /// ΔR, m.
    pub(crate) clearance_m: f64,
    /// ΔR², m².
    pub(crate) clearance_sq_m2: f64,
    /// See [`CircularProfile::tips`].
    pub(crate) tips: bool,
}

impl Seats<'_> {
    /// See [`CircularProfile::contacts`].
    #[inline(always)]
    pub(crate) fn contacts(
        &self,
        p: [f64; 2],
        hint: &mut u32,
        out: &mut [Patch; MAX_PATCHES],
    ) -> usize {
        let (gap, u) = self.gap_near(p, *hint);
        *hint = gap;
        let rc = self.seat_radius_m;
        let e = [p[0] - rc * u[0], p[1] - rc * u[1]];
        // Only the half facing the sprocket centre holds the roller (e·u ≤ 0).
        if e[0] * u[0] + e[1] * u[1] > 0.0 {
            if !self.tips {
                return 0;
            }
            return match self.profile.tip_contact(e, u, gap) {
                Some(patch) => {
                    out[0] = patch;
                    1
                }
                None => 0,
            };
        }
        // Cheap rejection before the square root: |e| ≤ ΔR means no contact.
        let len_sq = e[0] * e[0] + e[1] * e[1];
        if !(len_sq > self.clearance_sq_m2) {
            return 0;
        }
        let len = len_sq.sqrt();
        let depth_m = len - self.clearance_m;
        // len > ΔR > 0 here, so the normalisation is safe (one division).
        let inv_len = 1.0 / len;
        out[0] = Patch {
            depth_m,
            normal: [-e[0] * inv_len, -e[1] * inv_len],
            area: 4,
            gap,
            patch_id: gap,
        };
        1
    }

    /// [`CircularProfile::gap_near`], with the gap's direction.
    #[inline(always)]
    fn gap_near(&self, p: [f64; 2], hint: u32) -> (u32, [f64; 2]) {
        if let Some(&u) = self.dirs.get(hint as usize) {
            let along = u[0] * p[0] + u[1] * p[1];
            let across = u[0] * p[1] - u[1] * p[0];
            if along > 0.0 && across.abs() <= self.tan_half_pitch * along {
                return (hint, u);
            }
        }
        let gap = self.profile.gap_search(p, hint);
        // The search answers a gap of this profile (0..N).
        (
            gap,
            self.dirs.get(gap as usize).copied().unwrap_or([1.0, 0.0]),
        )
    }
}

impl super::Outline for Seats<'_> {
    #[inline(always)]
    fn contacts(&self, p: [f64; 2], hint: &mut u32, out: &mut [Patch; MAX_PATCHES]) -> usize {
        Seats::contacts(self, p, hint, out)
    }

    #[inline(always)]
    fn continues(&self, _: u32, _: u32) -> bool {
        false
    }

    const SLIDES: bool = false;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SeededRng;

    const P: f64 = 0.0889;
    const RR: f64 = 0.027;

    #[test]
    fn tip_contact_continues_the_arc_across_the_seat_diameter() {
        // A roller 1.2 mm beside its seat's centre, crossing the seat's
        // diameter outwards: on the arc side the depth is |e| − ΔR (closed
        // form of the arc); with the tips it goes on from that value and
        // normal, without them it drops to nothing (the jump that blew up a
        // slack chain).
        let mut c = CircularProfile::new(20, 0.0254, 0.00397);
        let rc = c.pitch_radius_m + c.clearance_m;
        let side = 1.2e-3;
        let depth = |c: &CircularProfile, radial: f64| {
            let mut out = [Patch::default(); MAX_PATCHES];
            let mut hint = 0;
            let n = c.contacts([rc + radial, side], &mut hint, &mut out);
            (n > 0).then_some((out[0].depth_m, out[0].normal))
        };
        let arc = side.hypot(1e-9) - c.clearance_m;
        let (inside, n_in) = depth(&c, -1e-9).expect("arc contact");
        assert!((inside - arc).abs() < 1e-9, "{inside} against {arc}");
        assert!(depth(&c, 1e-9).is_none());
        c.tips = true;
        let (outside, n_out) = depth(&c, 1e-9).expect("tip contact");
        assert!(
            (outside - inside).abs() < 1e-8,
            "{outside} against {inside}"
        );
        assert!((n_out[0] - n_in[0]).abs() < 1e-5 && (n_out[1] - n_in[1]).abs() < 1e-5);
        // Radially out of the seat, away from the tips: free.
        let mut out = [Patch::default(); MAX_PATCHES];
        assert_eq!(c.contacts([rc + 1e-3, 0.0], &mut 0, &mut out), 0);
    }

    #[test]
    fn clearance_matches_tooth_profile_table() {
        // docs/tooth-profile.md, “Dimensions of the paper's sprockets”:
        // R_t = 27.1731 mm, ΔR = 0.1731 mm.
        let c = CircularProfile::new(60, P, RR);
        assert!((c.seating_radius_m - 27.1731e-3).abs() < 5e-8);
        assert!((c.clearance_m - 0.1731e-3).abs() < 5e-8);
    }

    #[test]
    fn roller_on_pitch_circle_just_touches() {
        let c = CircularProfile::new(30, P, RR);
        let mut out = [Patch::default(); 2];
        // Slightly outside the pitch circle: free.
        assert_eq!(
            c.contacts([c.pitch_radius_m + 1e-9, 0.0], &mut 0, &mut out),
            0
        );
        // 1 mm inside the pitch circle at gap 0: depth 1 mm, normal radially out.
        let n = c.contacts([c.pitch_radius_m - 1e-3, 0.0], &mut 0, &mut out);
        assert_eq!(n, 1);
        assert!((out[0].depth_m - 1e-3).abs() < 1e-12);
        assert!((out[0].normal[0] - 1.0).abs() < 1e-12 && out[0].normal[1].abs() < 1e-12);
    }

    #[test]
    fn hand_computed_oblique_case() {
        // Gap 3 of a 28-tooth sprocket; roller displaced from the seating centre
        // by (dr, dt) = (-1.0 mm, 0.5 mm) in the gap's radial/tangential frame.
        let c = CircularProfile::new(28, P, RR);
        let phi = 3.0 * std::f64::consts::TAU / 28.0;
        let (ur, ut) = ([phi.cos(), phi.sin()], [-phi.sin(), phi.cos()]);
        let rc = c.pitch_radius_m + c.clearance_m;
        let (dr, dt) = (-1.0e-3, 0.5e-3);
        let p = [
            rc * ur[0] + dr * ur[0] + dt * ut[0],
            rc * ur[1] + dr * ur[1] + dt * ut[1],
        ];
        let mut out = [Patch::default(); 2];
        assert_eq!(c.contacts(p, &mut 0, &mut out), 1);
        let len = (1.0e-6f64 + 0.25e-6).sqrt();
        assert_eq!(out[0].gap, 3);
        assert!((out[0].depth_m - (len - 0.1731e-3)).abs() < 1e-7);
        // Normal = -(e)/|e|: radial +1.0/len, tangential -0.5/len.
        let n_r = out[0].normal[0] * ur[0] + out[0].normal[1] * ur[1];
        let n_t = out[0].normal[0] * ut[0] + out[0].normal[1] * ut[1];
        assert!((n_r - 1.0e-3 / len).abs() < 1e-12);
        assert!((n_t + 0.5e-3 / len).abs() < 1e-12);
    }

    #[test]
    fn outer_half_of_the_seat_is_free() {
        // A roller radially outside the seating centre may leave: no force.
        let c = CircularProfile::new(60, P, RR);
        let rc = c.pitch_radius_m + c.clearance_m;
        let mut out = [Patch::default(); 2];
        assert_eq!(c.contacts([rc + 1e-3, 0.0], &mut 0, &mut out), 0);
    }

    #[test]
    fn hinted_gap_equals_atan2_gap() {
        // Oracle: the hint path must agree with the plain atan2 rule everywhere.
        let c = CircularProfile::new(28, P, RR);
        let mut rng = SeededRng::new(12345);
        for _ in 0..20000 {
            let a = rng.range(0.0, std::f64::consts::TAU);
            let r = rng.range(0.3, 0.5);
            let p = [r * a.cos(), r * a.sin()];
            let hint = rng.range(0.0, 28.0) as u32;
            assert_eq!(c.gap_near(p, hint), c.gap_of(p));
        }
    }

    #[test]
    fn outline_arcs_sit_on_the_seating_circles() {
        let c = CircularProfile::new(30, P, RR);
        let pts = c.outline(0.5f64.to_radians());
        // Every point at distance R_t from its gap's seating centre; arcs at ≤ 0.5° steps.
        for p in &pts {
            let s = c.seat_center(p.gap as u32);
            let r = (p.x_m - s[0]).hypot(p.y_m - s[1]);
            assert!((r - c.seating_radius_m).abs() < 1e-12);
        }
        assert!(pts.len() >= 30 * 361);
        // The lowest point of gap 0's arc is the root, R_s + ΔR − R_t = R_s − R_r.
        let root = pts
            .iter()
            .filter(|p| p.gap == 0)
            .map(|p| p.x_m.hypot(p.y_m))
            .fold(f64::INFINITY, f64::min);
        assert!((root - (c.pitch_radius_m - RR)).abs() < 1e-9);
    }

    #[test]
    fn gap_index_wraps_around() {
        let c = CircularProfile::new(60, P, RR);
        let a = -0.4 * std::f64::consts::TAU / 60.0;
        assert_eq!(c.gap_of([a.cos(), a.sin()]), 0);
        let a = -0.6 * std::f64::consts::TAU / 60.0;
        assert_eq!(c.gap_of([a.cos(), a.sin()]), 59);
    }
}
