//! The slow reference implementation of the contact query (one `atan2` per arc piece, no
//! skipping, no direct rules), kept as the oracle of the fast one.

use super::pieces::{Hit, nearest_hit};
use super::{AsaProfile, CONSISTENCY_TOL_M, LocatedPatch, Patch, TIE_M};

/// Closest owned point of a patch, from the hits of its pieces: `None` when the nearest
/// point of the run lies beyond one of its shared joints (it then belongs to the
/// neighbouring patch). On a tie (within [`TIE_M`], e.g. both toppings at the tip) the
/// earlier piece wins.
pub(super) fn patch_hit(hits: &[Hit]) -> Option<Hit> {
    let mut best: Option<Hit> = None;
    for &h in hits {
        match best {
            Some(b) if b.dist_m <= h.dist_m + TIE_M => {}
            _ => best = Some(h),
        }
    }
    best.filter(|h| h.owned)
}

/// Keeps the two deepest (largest r − sd, i.e. smallest sd) candidates, deepest first.
pub(super) fn insert_deepest(best: &mut [Option<(Hit, u32)>; 2], c: (Hit, u32)) {
    let deeper = |a: &(Hit, u32), b: &Option<(Hit, u32)>| b.is_none_or(|b| a.0.sd_m < b.0.sd_m);
    if deeper(&c, &best[0]) {
        best[1] = best[0];
        best[0] = Some(c);
    } else if deeper(&c, &best[1]) {
        best[1] = Some(c);
    }
}

impl AsaProfile {
    /// The previous implementation of [`AsaProfile::contacts`] (one `atan2` for the gap and
    /// one per arc piece, no skipping), kept as the oracle of the fast one.
    pub(super) fn contacts_reference(
        &self,
        p: [f64; 2],
        roller_radius_m: f64,
        out: &mut [LocatedPatch; 2],
    ) -> usize {
        if !(p[0].is_finite() && p[1].is_finite() && roller_radius_m.is_finite())
            || roller_radius_m < 0.0
        {
            return 0;
        }
        let gap = self.gap_index(p);
        let q = self.to_local(gap, p);
        let n = self.dims.teeth;
        let g = gap as u32;
        let prev_tooth = (g + n - 1) % n;
        let own = self.own.map(|piece| piece.closest(q));
        // Own piece first, so a roller over a tip is labelled with the area on its side.
        let cw_tooth = [own[0], self.prev_area1.closest(q)];
        let ccw_tooth = [own[7], self.next_area7.closest(q)];
        // The nearest point of the whole outline lies in p's sector (own pieces). No genuine
        // local minimum can be nearer, or on the other side of the surface; this rejects the
        // insides of the neighbouring topping circles, which reach into this gap.
        let nearest = nearest_hit(&own).sd_m;
        let consistent = |sd: f64| {
            if nearest >= 0.0 {
                sd >= nearest - CONSISTENCY_TOL_M
            } else {
                sd <= nearest + CONSISTENCY_TOL_M
            }
        };
        let in_contact = |h: Option<Hit>| {
            h.filter(|h| h.sd_m.is_finite() && roller_radius_m - h.sd_m > 0.0 && consistent(h.sd_m))
        };
        let right = in_contact(patch_hit(&own[1..4]));
        let left = in_contact(patch_hit(&own[4..7]));
        let left_id = if right.is_some() { 2 * n + g } else { 2 * g };
        let candidates = [
            (right, 2 * g),
            (left, left_id),
            (in_contact(patch_hit(&ccw_tooth)), 2 * g + 1),
            (in_contact(patch_hit(&cw_tooth)), 2 * prev_tooth + 1),
        ];
        let mut best: [Option<(Hit, u32)>; 2] = [None, None];
        for (hit, id) in candidates {
            let Some(h) = hit else { continue };
            insert_deepest(&mut best, (h, id));
        }
        let mut written = 0;
        for (h, id) in best.into_iter().flatten() {
            if let Some(slot) = out.get_mut(written) {
                *slot = LocatedPatch {
                    patch: Patch {
                        depth_m: roller_radius_m - h.sd_m,
                        normal: self.to_global_vec(gap, h.normal),
                        area: h.area,
                        gap: self.wrap_gap(gap, h.gap_offset) as u32,
                        patch_id: id,
                    },
                    point: self.to_global_point(gap, h.point),
                };
                written += 1;
            }
        }
        written
    }
}
