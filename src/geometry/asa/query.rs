//! The contact query: the direct rules for the bottom and the free space of a gap, and
//! the general path that examines every piece within reach.

#[cfg(doc)]
use super::TIE_M;
use super::dimensions::{AsaDimensions, GapPoints};
use super::fast::{
    FAR, FastPiece, Found, NONE, Near, insert_deepest_near, nearest_near, patch_near,
};
use super::{AsaProfile, CONSISTENCY_TOL_M};
use crate::geometry::v2::{V2, add, dot, mirror, neg, norm, scale, sub, unit_or};

/// Smallest distance |s| of `q` from the line c–O–x (or its mirror c*–O–x*) for which the
/// bottom-of-gap rules of [`Shortcuts`] decide between the seat and a working curve, as a
/// fraction of Rt. The losing piece is then farther by at least s²/(2(|c| + R_L)) ≈ 3·10⁻¹²
/// m for the paper's rollers (≫ [`TIE_M`] and the rounding); closer to the line the general
/// path decides.
pub(super) const JOINT_LINE_MARGIN: f64 = 2e-5;

/// Margin by which a working curve's foot must be nearer than the seat bottom before the
/// bottom-of-gap rule reports it (≫ [`TIE_M`] and the rounding).
pub(super) const BOTTOM_MARGIN_M: f64 = 1e-12;

/// The two direct rules of [`AsaProfile::contacts_hinted`], for the places where almost
/// every query of a running drive falls. Radius-independent part; [`Reach`] holds the rest.
///
/// **Bottom of the gap** (seated rollers, and rollers rocked onto a working curve just past
/// x or x*): for `min_r ≤ |q| < R_L`, with s = cos A·η + sin A·|ξ| the signed distance of `q`
/// from the joint line c–O–x (its mirror when ξ ≤ 0), the answer is the owning seat half's
/// foot when s ≤ −s_min, the working curve's foot when s ≥ s_min and the seat bottom is
/// farther, else the general path (proof: docs/tooth-profile.md, section “Direct rule: bottom
/// of the gap”).
///
/// **Free space of the gap** (a roller lifted out or coming in): `q` outside the seat's
/// wedge and, on both sides, farther than the reach from the straight portion's line, the
/// topping circle and the working circle (unless beyond its y end) has no contact (proof:
/// docs/tooth-profile.md, section “Direct rule: free space of the gap”; the free side is told
/// by [`SideGraph`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Shortcuts {
    /// (cos A, sin A): s = cos A·η + sin A·|ξ|.
    pub(super) cos_sin_a: V2,
    /// s_min, m.
    pub(super) s_min_m: f64,
    /// Smallest |q|², (Rt·10⁻⁶)².
    pub(super) min_r2: f64,
    /// Lower bound of the distance from O to pieces 0, 1, 6, 7, 8, 9 (0 disables the
    /// bottom-of-gap rules).
    pub(super) far_m: f64,
    /// Upper bound of R_L: Rt(1 − 10⁻³) (q well inside the seat circle, where the foot on
    /// the seat is well conditioned: at the seat bottom, where the owning half's window ends,
    /// foot and end point then give the same normal to ~10⁻¹³), the distance from O to the
    /// line c–y, and 2|c| sin A.
    pub(super) free_m: f64,
    /// The seat bottom (0, −Rt).
    pub(super) bottom: V2,
    /// Unit direction from c to y: the working curve's y edge.
    pub(super) c_to_y: V2,
    /// Whether the free-space rule holds for this construction (checked at construction).
    pub(super) free_rule: bool,
}

impl Shortcuts {
    /// The rules of a gap, each disabled when its preconditions do not hold.
    pub(super) fn new(
        d: &AsaDimensions,
        g: &GapPoints,
        fast: &[FastPiece; 10],
        graph: Option<&SideGraph>,
    ) -> Shortcuts {
        let rt = d.seating_radius_m;
        let (sin_a, cos_a) = d.a_rad.sin_cos();
        let c_to_y = unit_or(sub(g.y_m, g.c_m), [1.0, 0.0]);
        let far = [0, 1, 6, 7, 8, 9]
            .iter()
            .filter_map(|&k| fast.get(k))
            .map(|f| f.near([0.0, 0.0], 0).dist_m)
            .fold(f64::INFINITY, f64::min)
            * (1.0 - 1e-12);
        // R_L must stay clear of the working curve's y edge (the line c–y), and below
        // 2|c| sin A (the other side's working foot is then farther than Rt).
        let c_len = norm(g.c_m);
        let o_from_c = neg(g.c_m);
        let y_edge_m = (c_to_y[0] * o_from_c[1] - c_to_y[1] * o_from_c[0]).abs();
        let x_on_line = {
            // c, O and x are collinear (x on the ray from c through O).
            let u = unit_or(g.x_m, [1.0, 0.0]);
            (u[0] * o_from_c[1] - u[1] * o_from_c[0]).abs() < 1e-12 * c_len
                && dot(u, o_from_c) > 0.0
        };
        let ok = far.is_finite()
            && g.x_m[0] > 0.0
            && g.x_m[1] < 0.0
            && cos_a > 0.0
            && sin_a > 0.0
            && x_on_line;
        Shortcuts {
            cos_sin_a: [cos_a, sin_a],
            s_min_m: JOINT_LINE_MARGIN * rt,
            min_r2: (1e-6 * rt) * (1e-6 * rt),
            far_m: if ok { far } else { 0.0 },
            free_m: (rt * (1.0 - 1e-3))
                .min(y_edge_m * (1.0 - 1e-9))
                .min(2.0 * c_len * sin_a * (1.0 - 1e-9)),
            bottom: [0.0, -rt],
            c_to_y,
            // The graph shape, a rising straight portion (so that it passes above the topping
            // circle's lower branch beyond z) and the topping circle reaching left of z.
            free_rule: graph.is_some()
                && g.z_m[1] > g.y_m[1]
                && g.b_m[0] - d.topping_radius_m < g.z_m[0],
        }
    }
}

/// The radius-dependent constants of the fast paths (see [`Shortcuts`]), computed once for
/// the profile's own roller and on the fly for any other radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Reach {
    /// Roller radius r.
    pub(super) r: f64,
    /// r + [`SKIP_MARGIN_M`].
    pub(super) reach: f64,
    /// (tip reach + reach)²: beyond it nothing is within reach.
    pub(super) outer2: f64,
    /// (seat clearance − reach)², negative when the roller does not fit the seat.
    pub(super) clear2: f64,
    /// R_L², 0 when the bottom-of-gap rules are off.
    pub(super) low2: f64,
    /// (RE − reach)², negative when the free-space rule is off.
    pub(super) re_in2: f64,
    /// (RF + reach)².
    pub(super) rf_out2: f64,
}

impl Reach {
    /// The constants for a roller of radius `r` (finite, ≥ 0).
    #[inline]
    pub(super) fn new(pr: &AsaProfile, r: f64) -> Reach {
        let reach = r + SKIP_MARGIN_M;
        let outer = pr.reach_radius_m + reach;
        let clear = pr.seat_clear_m - reach;
        let cut = &pr.cuts;
        let low = (cut.far_m - reach).min(cut.free_m);
        let rt = pr.dims.seating_radius_m;
        let re_in = pr.dims.working_radius_m - reach;
        let rf_out = pr.dims.topping_radius_m + reach;
        Reach {
            r,
            reach,
            outer2: outer * outer,
            clear2: if clear > 0.0 { clear * clear } else { -1.0 },
            low2: if low > 0.0 && reach < rt {
                low * low
            } else {
                0.0
            },
            re_in2: if cut.free_rule && re_in > 0.0 {
                re_in * re_in
            } else {
                -1.0
            },
            rf_out2: rf_out * rf_out,
        }
    }
}

/// The half outline of one gap (ξ ≥ 0: seat half, working curve, straight, topping) as a
/// graph η = h(ξ) over 0 ≤ ξ ≤ ξ_f, mirrored for ξ < 0. Within the gap's sector a vertical
/// line meets the outline once, so a point is in the material exactly when it lies below
/// the graph (points with |ξ| > ξ_f in the sector are above the tip, in free space;
/// docs/tooth-profile.md, section “The outline as a graph”).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct SideGraph {
    /// ξ of x, y, z and f.
    pub(super) xi: [f64; 4],
    /// Rt².
    pub(super) rt2: f64,
    /// Working-curve centre c (lower branch).
    pub(super) c: V2,
    /// RE².
    pub(super) re2: f64,
    /// y (start of the straight portion).
    pub(super) y: V2,
    /// dη/dξ of the straight portion.
    pub(super) slope: f64,
    /// Topping centre b (upper branch).
    pub(super) b: V2,
    /// RF².
    pub(super) rf2: f64,
}

/// Vertical distance from the graph below which [`SideGraph::is_free`] does not decide.
pub(super) const GRAPH_TOL_M: f64 = 1e-9;

impl SideGraph {
    /// The graph of a gap, when the construction has the graph shape (checked, not
    /// assumed): ξ increasing through 0 < x < y < z < f, the seat and working arcs below
    /// their centres, the topping arc above its centre.
    pub(super) fn new(d: &AsaDimensions, g: &GapPoints) -> Option<SideGraph> {
        let xi = [g.x_m[0], g.y_m[0], g.z_m[0], g.f_m[0]];
        let ordered = 0.0 < xi[0] && xi[0] < xi[1] && xi[1] < xi[2] && xi[2] < xi[3];
        let arcs_on_branch = g.x_m[1] < 0.0
            && g.x_m[1] < g.c_m[1]
            && g.y_m[1] < g.c_m[1]
            && g.z_m[1] > g.b_m[1]
            && g.f_m[1] > g.b_m[1];
        (ordered && arcs_on_branch).then(|| SideGraph {
            xi,
            rt2: d.seating_radius_m * d.seating_radius_m,
            c: g.c_m,
            re2: d.working_radius_m * d.working_radius_m,
            y: g.y_m,
            slope: (g.z_m[1] - g.y_m[1]) / (g.z_m[0] - g.y_m[0]),
            b: g.b_m,
            rf2: d.topping_radius_m * d.topping_radius_m,
        })
    }

    /// Some(true) in free space, Some(false) in the material, None within
    /// [`GRAPH_TOL_M`] of the outline. `q` is gap-local and in the gap's sector.
    #[inline]
    pub(super) fn is_free(&self, q: V2) -> Option<bool> {
        let a = q[0].abs();
        if a > self.xi[3] {
            return Some(true);
        }
        let h = if a <= self.xi[0] {
            -(self.rt2 - a * a).max(0.0).sqrt()
        } else if a <= self.xi[1] {
            let u = a - self.c[0];
            self.c[1] - (self.re2 - u * u).max(0.0).sqrt()
        } else if a <= self.xi[2] {
            self.y[1] + (a - self.y[0]) * self.slope
        } else {
            let u = a - self.b[0];
            self.b[1] + (self.rf2 - u * u).max(0.0).sqrt()
        };
        if q[1] > h + GRAPH_TOL_M {
            Some(true)
        } else if q[1] < h - GRAPH_TOL_M {
            Some(false)
        } else {
            None
        }
    }
}

/// Margin added to the roller radius when a piece is skipped as far away. Much larger than
/// every rounding error and than [`CONSISTENCY_TOL_M`], so skipping never changes a result.
pub(super) const SKIP_MARGIN_M: f64 = 1e-7;

impl AsaProfile {
    /// The patches of a roller centred at `p` (sprocket frame) in gap-local form, and the
    /// gap. The commonest cases first: beyond the tips, seated with clearance, the bottom of
    /// the gap, the free space of the gap ([`Shortcuts`]); then the general path.
    #[inline(always)]
    pub(super) fn query(
        &self,
        p: V2,
        k: &Reach,
        hint: &mut u32,
        emit: &mut impl FnMut(usize, usize, Found),
    ) -> usize {
        // Beyond every tip by more than the radius: free space, nothing within reach. This
        // also rejects a non-finite `p` (the comparison is false for NaN).
        if !(dot(p, p) <= k.outer2) {
            return 0;
        }
        let gap = self.gap_near(p, *hint);
        *hint = gap as u32;
        let q = self.to_local(gap, p);
        // Seated with clearance: every piece is at least seat_clear_m − |q| away, and the
        // disc about O is free space.
        let r2 = dot(q, q);
        if r2 < k.clear2 {
            return 0;
        }
        let cut = &self.cuts;
        let s = cut.cos_sin_a[0] * q[1] + cut.cos_sin_a[1] * q[0].abs();
        if r2 < k.low2 && r2 >= cut.min_r2 {
            if let Some(hit) = self.bottom_of_gap(q, r2, s, k, 2 * gap as u32) {
                return match hit {
                    Some(f) => {
                        emit(0, gap, f);
                        1
                    }
                    None => 0,
                };
            }
        } else if k.re_in2 > 0.0 && self.in_free_gap(q, s, k) {
            return 0;
        }
        let mut found = [NONE; 2];
        let count = self.contacts_general(gap, q, k.r, &mut found);
        for (slot, f) in found[..count.min(2)].iter().enumerate() {
            emit(slot, gap, *f);
        }
        count
    }

    /// The bottom-of-gap rule of [`Shortcuts`]: `Some(patch)` when it decides (`Some(None)`:
    /// no contact).
    #[inline(always)]
    pub(super) fn bottom_of_gap(
        &self,
        q: V2,
        r2: f64,
        s: f64,
        k: &Reach,
        patch_id: u32,
    ) -> Option<Option<Found>> {
        let cut = &self.cuts;
        // The seat-bottom joint gives ξ > 0 to pieces 2, 3, the rest to pieces 5, 4.
        let right = q[0] > 0.0;
        if s <= -cut.s_min_m {
            let seat = self.fast.get(if right { 3 } else { 4 })?;
            let len = r2.sqrt();
            let depth_m = k.r - (seat.radius_m - len);
            if !(depth_m > 0.0) {
                return Some(None);
            }
            let dir = [q[0] / len, q[1] / len];
            return Some(Some(Found {
                depth_m,
                normal: neg(dir),
                point: scale(dir, seat.radius_m),
                area: seat.area,
                gap_offset: 0,
                patch_id,
            }));
        }
        if s < cut.s_min_m {
            return None;
        }
        let arc = self.fast.get(if right { 2 } else { 5 })?;
        let d = sub(q, arc.centre);
        let len = dot(d, d).sqrt();
        let dist_m = arc.radius_m - len;
        // The seat bottom, the seat half's other end, must lose to the working foot (or be
        // out of reach when the foot is).
        let to_bottom = sub(q, cut.bottom);
        let lim = (dist_m + BOTTOM_MARGIN_M).min(k.reach);
        if !(dot(to_bottom, to_bottom) > lim * lim) {
            return None;
        }
        let depth_m = k.r - dist_m;
        if !(depth_m > 0.0) {
            return Some(None);
        }
        let dir = [d[0] / len, d[1] / len];
        Some(Some(Found {
            depth_m,
            normal: neg(dir),
            point: add(arc.centre, scale(dir, arc.radius_m)),
            area: arc.area,
            gap_offset: 0,
            patch_id,
        }))
    }

    /// The free-space rule of [`Shortcuts`]: true when no piece is within reach of `q`.
    #[inline(always)]
    pub(super) fn in_free_gap(&self, q: V2, s: f64, k: &Reach) -> bool {
        // Outside the seat's wedge: s > 0 on one side at least, and s (taken with |ξ|) is
        // the larger of the two sides' values.
        s > 0.0 && self.clear_of_side(q, k) && self.clear_of_side(mirror(q), k)
    }

    /// The lower bounds of the free-space rule against the right side's straight portion,
    /// topping and working curve (the left side is its mirror image).
    #[inline(always)]
    pub(super) fn clear_of_side(&self, q: V2, k: &Reach) -> bool {
        let [topping, straight, working] = [&self.fast[0], &self.fast[1], &self.fast[2]];
        if !(dot(sub(q, straight.start), straight.n_free[0]) > k.reach) {
            return false;
        }
        let b = sub(q, topping.centre);
        if !(dot(b, b) > k.rf_out2) {
            return false;
        }
        let c = sub(q, working.centre);
        let y = self.cuts.c_to_y;
        let beyond_y = dot(c, working.mid_dir) > 0.0 && y[0] * c[1] - y[1] * c[0] > 0.0;
        beyond_y || dot(c, c) < k.re_in2
    }

    /// The contacts of a roller centred at the gap-local point `q` of `gap`'s sector, with
    /// the pieces farther than the radius skipped (see [`AsaProfile::contacts`]).
    #[inline(never)]
    pub(super) fn contacts_general(
        &self,
        gap: usize,
        q: V2,
        roller_radius_m: f64,
        out: &mut [Found; 2],
    ) -> usize {
        let reach = roller_radius_m + SKIP_MARGIN_M;
        let f = &self.fast;
        let own = [
            f[0].eval(q, reach, 0),
            f[1].eval(q, reach, 1),
            f[2].eval(q, reach, 2),
            f[3].eval(q, reach, 3),
            f[4].eval(q, reach, 4),
            f[5].eval(q, reach, 5),
            f[6].eval(q, reach, 6),
            f[7].eval(q, reach, 7),
        ];
        let nearest = nearest_near(&own);
        // A skipped piece is farther than `reach`, so the nearest evaluated piece is the
        // nearest of all when it is within `reach`.
        if nearest.dist_m.is_nan() || nearest.dist_m > reach {
            // Every piece is farther than `reach`: no contact in free space.
            return match self.graph.and_then(|g| g.is_free(q)) {
                Some(true) => 0,
                _ => self.contacts_all(gap, q, roller_radius_m, out),
            };
        }
        // Inside the material a skipped piece could hide a deeper one: examine all.
        if nearest.sd_m < 0.0 {
            return self.contacts_all(gap, q, roller_radius_m, out);
        }
        // In free space a skipped piece is never a patch, and every run whose nearest piece
        // is skipped has no patch either (its nearest piece is farther than the radius).
        let prev_area1 = f[8].eval(q, reach, 8);
        let next_area7 = f[9].eval(q, reach, 9);
        self.finish(
            gap,
            q,
            &own,
            [prev_area1, next_area7],
            nearest.sd_m,
            roller_radius_m,
            out,
        )
    }

    /// The contacts with every piece examined (centre inside the material, or undecided).
    #[cold]
    #[inline(never)]
    pub(super) fn contacts_all(
        &self,
        gap: usize,
        q: V2,
        roller_radius_m: f64,
        out: &mut [Found; 2],
    ) -> usize {
        let mut all = [FAR; 10];
        for (k, (slot, f)) in all.iter_mut().zip(&self.fast).enumerate() {
            *slot = f.near(q, k as u8);
        }
        let own = [
            all[0], all[1], all[2], all[3], all[4], all[5], all[6], all[7],
        ];
        let nearest = nearest_near(&own).sd_m;
        self.finish(
            gap,
            q,
            &own,
            [all[8], all[9]],
            nearest,
            roller_radius_m,
            out,
        )
    }

    /// Patch selection from the results of the own pieces and of the neighbouring
    /// toppings `[prev_area1, next_area7]`, the signed distance `nearest` of the nearest own
    /// piece, and the radius; writes the patches (gap-local).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(super) fn finish(
        &self,
        gap: usize,
        q: V2,
        own: &[Near; 8],
        neighbours: [Near; 2],
        nearest: f64,
        roller_radius_m: f64,
        out: &mut [Found; 2],
    ) -> usize {
        let n = self.dims.teeth;
        let g = gap as u32;
        let prev_tooth = if g == 0 { n - 1 } else { g - 1 };
        // Own piece first, so a roller over a tip is labelled with the area on its side.
        let cw_tooth = [own[0], neighbours[0]];
        let ccw_tooth = [own[7], neighbours[1]];
        // The nearest point of the whole outline lies in p's sector (own pieces). No genuine
        // local minimum can be nearer, or on the other side of the surface; this rejects the
        // insides of the neighbouring topping circles, which reach into this gap.
        let consistent = |sd: f64| {
            if nearest >= 0.0 {
                sd >= nearest - CONSISTENCY_TOL_M
            } else {
                sd <= nearest + CONSISTENCY_TOL_M
            }
        };
        let in_contact = |h: Option<Near>| {
            h.filter(|h| h.sd_m.is_finite() && roller_radius_m - h.sd_m > 0.0 && consistent(h.sd_m))
        };
        let right = in_contact(patch_near(&own[1..4]));
        let left = in_contact(patch_near(&own[4..7]));
        let left_id = if right.is_some() { 2 * n + g } else { 2 * g };
        let candidates = [
            (right, 2 * g),
            (left, left_id),
            (in_contact(patch_near(&ccw_tooth)), 2 * g + 1),
            (in_contact(patch_near(&cw_tooth)), 2 * prev_tooth + 1),
        ];
        let mut best: [Option<(Near, u32)>; 2] = [None, None];
        for (hit, id) in candidates {
            let Some(h) = hit else { continue };
            insert_deepest_near(&mut best, (h, id));
        }
        let mut written = 0;
        for (h, id) in best.into_iter().flatten() {
            let Some(piece) = self.fast.get(usize::from(h.piece)) else {
                continue;
            };
            let (point, normal) = piece.geometry(q, h.mode);
            if let Some(slot) = out.get_mut(written) {
                *slot = Found {
                    depth_m: roller_radius_m - h.sd_m,
                    normal,
                    point,
                    area: piece.area,
                    gap_offset: piece.gap_offset,
                    patch_id: id,
                };
                written += 1;
            }
        }
        written
    }

    /// Which step of [`AsaProfile::query`] decides `p`: 0 an early exit (beyond the tips,
    /// seated with clearance), 1 the bottom-of-gap rule, 2 the free-space rule, 3 the
    /// general path.
    #[cfg(test)]
    pub(super) fn rule_of(&self, p: [f64; 2], roller_radius_m: f64) -> usize {
        let k = Reach::new(self, roller_radius_m);
        if !(dot(p, p) <= k.outer2) {
            return 0;
        }
        let gap = self.gap_index(p);
        let q = self.to_local(gap, p);
        let r2 = dot(q, q);
        if r2 < k.clear2 {
            return 0;
        }
        let cut = &self.cuts;
        let s = cut.cos_sin_a[0] * q[1] + cut.cos_sin_a[1] * q[0].abs();
        if r2 < k.low2 && r2 >= cut.min_r2 {
            if self.bottom_of_gap(q, r2, s, &k, 0).is_some() {
                return 1;
            }
        } else if k.re_in2 > 0.0 && self.in_free_gap(q, s, &k) {
            return 2;
        }
        3
    }
}
