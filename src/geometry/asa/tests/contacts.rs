//! The contact query: seated rollers, symmetries, continuity of the force
//! and the depth, patches, and the fast query against the reference.

use super::*;

fn contacts(pr: &AsaProfile, p: V2, r: f64) -> Vec<LocatedPatch> {
    let mut out = [LocatedPatch::default(); 2];
    let k = pr.contacts(p, r, &mut out);
    out[..k].to_vec()
}

#[test]
fn seated_roller() {
    for n in [60, 30, 28] {
        let pr = profile(n);
        let d = pr.dimensions();
        let rs = d.pitch_radius_m;
        // Centred on the seating centre: clearance all round, no contact.
        assert!(contacts(&pr, [rs, 0.0], RR).is_empty());
        let (sd, _, area, gap) = pr.signed_distance([rs, 0.0]);
        check("sd at O", sd, d.seating_radius_m, 1e-15);
        // O is equidistant from the whole seat and from x, x* on the working curves.
        assert!((3..=5).contains(&area) && gap == 0);
        // Just touching after moving by ΔR, depth d after ΔR + d.
        for depth in [1e-6, 1e-4, 1e-3] {
            let c = contacts(&pr, [rs - d.clearance_m - depth, 0.0], RR);
            assert_eq!(c.len(), 1);
            check("depth", c[0].patch.depth_m, depth, 1e-14);
            check("nx", c[0].patch.normal[0], 1.0, 1e-15);
            check("ny", c[0].patch.normal[1], 0.0, 1e-15);
            check("px", c[0].point[0], d.root_radius_m, 1e-14);
            check("py", c[0].point[1], 0.0, 1e-15);
            assert_eq!(
                (c[0].patch.area, c[0].patch.gap, c[0].patch.patch_id),
                (4, 0, 0)
            );
        }
        // Same in gap 5, rotated.
        let psi = 5.0 * pr.pitch_angle_rad();
        let r = rs - d.clearance_m - 1e-4;
        let c = contacts(&pr, [r * psi.cos(), r * psi.sin()], RR);
        assert_eq!(c.len(), 1);
        check("depth gap 5", c[0].patch.depth_m, 1e-4, 1e-13);
        check(
            "n gap 5",
            dot(c[0].patch.normal, [psi.cos(), psi.sin()]),
            1.0,
            1e-14,
        );
        assert_eq!((c[0].patch.gap, c[0].patch.patch_id), (5, 10));
    }
}

fn rotate(v: V2, a: f64) -> V2 {
    let (s, c) = a.sin_cos();
    [c * v[0] - s * v[1], s * v[0] + c * v[1]]
}

fn random_point(rng: &mut SeededRng, d: &AsaDimensions) -> V2 {
    let r = rng.range(d.root_radius_m - 0.01, d.tip_radius_m + 0.03);
    let a = rng.range(-PI, PI);
    [r * a.cos(), r * a.sin()]
}

#[test]
fn rotational_symmetry() {
    let pr = profile(30);
    let n = 30_i64;
    let phi_p = pr.pitch_angle_rad();
    let d = pr.dimensions().clone();
    let mut rng = SeededRng::new(7);
    let mut seen = 0;
    for _ in 0..4000 {
        let p = random_point(&mut rng, &d);
        let a = contacts(&pr, p, RR);
        let b = contacts(&pr, rotate(p, phi_p), RR);
        assert_eq!(a.len(), b.len(), "at {p:?}");
        seen += a.len();
        for (x, y) in a.iter().zip(&b) {
            check("depth", y.patch.depth_m, x.patch.depth_m, 1e-12);
            check(
                "n",
                norm(sub(y.patch.normal, rotate(x.patch.normal, phi_p))),
                0.0,
                1e-12,
            );
            check("q", norm(sub(y.point, rotate(x.point, phi_p))), 0.0, 1e-12);
            assert_eq!(y.patch.area, x.patch.area);
            assert_eq!(y.patch.gap, (x.patch.gap + 1) % n as u32);
            assert_eq!(y.patch.patch_id, (x.patch.patch_id + 2) % (2 * n as u32));
        }
        let (sa, qa, aa, ga) = pr.signed_distance(p);
        let (sb, qb, ab, gb) = pr.signed_distance(rotate(p, phi_p));
        check("sd", sb, sa, 1e-12);
        check("sd q", norm(sub(qb, rotate(qa, phi_p))), 0.0, 1e-12);
        assert_eq!((ab, gb), (aa, (ga + 1).rem_euclid(n)));
    }
    assert!(seen > 100, "too few contacts sampled: {seen}");
}

#[test]
fn mirror_symmetry() {
    let pr = profile(28);
    let n = 28_i64;
    let d = pr.dimensions().clone();
    let flip = |v: V2| [v[0], -v[1]];
    let mut rng = SeededRng::new(99);
    for _ in 0..4000 {
        let p = random_point(&mut rng, &d);
        let (sa, qa, aa, ga) = pr.signed_distance(p);
        let (sb, qb, ab, gb) = pr.signed_distance(flip(p));
        check("sd", sb, sa, 1e-12);
        check("q", norm(sub(qb, flip(qa))), 0.0, 1e-12);
        // Ties at the sector boundary may pick the mirror piece of the other gap.
        if (qa[1].atan2(qa[0]) / pr.pitch_angle_rad()).fract().abs() > 1e-9 {
            assert_eq!((ab, gb), (8 - aa, (-ga).rem_euclid(n)), "at {p:?}");
        }
        let a = contacts(&pr, p, RR);
        let b = contacts(&pr, flip(p), RR);
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(&b) {
            check("depth", y.patch.depth_m, x.patch.depth_m, 1e-12);
            check(
                "n",
                norm(sub(y.patch.normal, flip(x.patch.normal))),
                0.0,
                1e-12,
            );
        }
    }
    // Within a gap's local frame: pieces mirror onto pieces.
    for k in 0..8 {
        let a = &pr.own[k];
        let b = &pr.own[7 - k];
        assert_eq!(a.area, 8 - b.area);
        check(
            "mirror start",
            norm(sub(a.start, mirror(b.end))),
            0.0,
            1e-15,
        );
    }
}

/// Roller centre on the curve where sd = Rr − depth, at polar angle `a` (bisection
/// along the ray).
fn pressed_centre(pr: &AsaProfile, a: f64, depth: f64) -> V2 {
    let d = pr.dimensions();
    let (mut lo, mut hi) = (d.root_radius_m - 0.01, d.tip_radius_m + 0.05);
    let at = |r: f64| [r * a.cos(), r * a.sin()];
    for _ in 0..64 {
        let mid = 0.5 * (lo + hi);
        if pr.signed_distance(at(mid)).0 < RR - depth {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    at(0.5 * (lo + hi))
}

#[test]
fn force_is_continuous_from_seat_over_tip_into_next_gap() {
    for n in [60, 28] {
        let pr = profile(n);
        let depth = 2e-4;
        let steps = 20_000;
        let phi_p = pr.pitch_angle_rad();
        let mut prev: Option<(V2, V2)> = None;
        let mut areas: Vec<u8> = Vec::new();
        let mut ids: Vec<u32> = Vec::new();
        let mut max_jump: f64 = 0.0;
        for k in 0..=steps {
            let a = phi_p * k as f64 / steps as f64;
            let c = pressed_centre(&pr, a, depth);
            let patches = contacts(&pr, c, RR);
            assert_eq!(patches.len(), 1, "N={n} step {k}: {patches:?}");
            let p = patches[0];
            check("depth", p.patch.depth_m, depth, 1e-9);
            check("|n|", norm(p.patch.normal), 1.0, 1e-12);
            // The normal points from the surface point to the centre.
            let to_c = sub(c, p.point);
            check(
                "n || q->c",
                norm(sub(scale(p.patch.normal, norm(to_c)), to_c)),
                0.0,
                1e-9,
            );
            let force = scale(p.patch.normal, p.patch.depth_m);
            if let Some((f0, c0)) = prev {
                assert!(
                    norm(sub(c, c0)) < 1e-4,
                    "path step too long at {k}: {} {c:?}",
                    norm(sub(c, c0))
                );
                max_jump = max_jump.max(norm(sub(force, f0)));
            }
            prev = Some((force, c));
            if areas.last() != Some(&p.patch.area) {
                areas.push(p.patch.area);
            }
            if ids.last() != Some(&p.patch.patch_id) {
                assert!(
                    ids.last()
                        .is_none_or(|&last| pr.patches_are_neighbours(last, p.patch.patch_id)),
                    "patch {p:?} after {ids:?}"
                );
                ids.push(p.patch.patch_id);
            }
        }
        // The path steps are < 100 µm (mostly ≈ 5 µm); the tightest turn of the normal is in the seat
        // (offset radius ΔR + depth ≈ 0.37 mm), ≈ 0.03 rad per step. A jump would be
        // of the order of the depth itself.
        assert!(
            max_jump < 0.05 * depth,
            "N={n}: largest force-proxy step {max_jump}"
        );
        assert_eq!(areas, vec![4, 3, 2, 1, 7, 6, 5, 4], "N={n}");
        assert_eq!(ids, vec![0, 1, 2], "N={n}");
    }
}

#[test]
fn depth_is_continuous_across_every_joint() {
    let pr = profile(30);
    let mut rng = SeededRng::new(3);
    // Straight lines through each joint, slightly on the free side.
    let own = pr.own;
    for (k, piece) in own.iter().enumerate() {
        let j = piece.start;
        let n_free = piece.free_normal(false);
        let base = pr.to_global_point(0, add(j, scale(n_free, RR - 1e-4)));
        for _ in 0..20 {
            let dir = polar(rng.range(0.0, 2.0 * PI));
            let mut last: Option<V2> = None;
            for s in -100..=100 {
                let p = add(base, scale(dir, 1e-7 * f64::from(s)));
                let c = contacts(&pr, p, RR);
                let f = c.iter().fold([0.0, 0.0], |acc, x| {
                    add(acc, scale(x.patch.normal, x.patch.depth_m))
                });
                if let Some(l) = last {
                    assert!(norm(sub(f, l)) < 1e-6, "jump at joint {k}: {c:?}");
                }
                last = Some(f);
            }
        }
    }
}

#[test]
fn two_separate_places_give_two_patches() {
    let pr = profile(28);
    let d = pr.dimensions().clone();
    // An oversized roller (radius 40 mm) on the gap axis touches both flanks.
    let r = 0.040;
    let p = [d.pitch_radius_m + 0.010, 0.0];
    let c = contacts(&pr, p, r);
    assert_eq!(c.len(), 2, "{c:?}");
    check(
        "equal depths",
        c[0].patch.depth_m,
        c[1].patch.depth_m,
        1e-12,
    );
    let mut ids = [c[0].patch.patch_id, c[1].patch.patch_id];
    ids.sort_unstable();
    assert_eq!(ids, [0, 56]);
    assert!(pr.patches_are_neighbours(0, 56));
    // Slightly off-axis: the clockwise side keeps id 0 in both orders of depth.
    for dy in [-1e-4, 1e-4] {
        let c = contacts(&pr, [p[0], dy], r);
        assert_eq!(c.len(), 2);
        for x in &c {
            let id = if x.patch.area >= 5 { 0 } else { 56 };
            assert_eq!(x.patch.patch_id, id, "{x:?}");
        }
    }
    // A 40 mm roller wedged between the topping of tooth 0 (area 1) and the opposite
    // straight flank (area 6): one tooth patch and the gap's concave patch.
    let p = pr.to_global_point(0, [-0.002, 0.020]);
    let c = contacts(&pr, p, r);
    assert_eq!(c.len(), 2, "{c:?}");
    let mut got: Vec<(u8, u32)> = c.iter().map(|x| (x.patch.area, x.patch.patch_id)).collect();
    got.sort_unstable();
    assert_eq!(got, vec![(1, 1), (6, 0)]);
    assert!(
        norm(sub(c[0].point, c[1].point)) > 0.05,
        "two separate places"
    );
    for x in &c {
        let v = sub(p, x.point);
        check("depth = r - |p-q|", x.patch.depth_m, r - norm(v), 1e-12);
        check(
            "normal",
            norm(sub(x.patch.normal, scale(v, 1.0 / norm(v)))),
            0.0,
            1e-12,
        );
    }
}

#[test]
fn neighbour_relation_of_patch_ids() {
    let pr = profile(10);
    assert!(pr.patches_are_neighbours(0, 1));
    assert!(pr.patches_are_neighbours(0, 19));
    assert!(pr.patches_are_neighbours(2, 1));
    assert!(pr.patches_are_neighbours(19, 18));
    assert!(!pr.patches_are_neighbours(0, 3));
    assert!(!pr.patches_are_neighbours(1, 3));
    assert!(!pr.patches_are_neighbours(0, 2));
    assert!(pr.patches_are_neighbours(4, 22));
    assert!(!pr.patches_are_neighbours(4, 4));
    assert!(!pr.patches_are_neighbours(0, 1000));
}

#[test]
fn no_panics_and_non_finite_input() {
    let pr = profile(17);
    let mut out = [LocatedPatch::default(); 2];
    for p in [
        [f64::NAN, 0.0],
        [0.0, f64::INFINITY],
        [f64::NEG_INFINITY, f64::NAN],
    ] {
        assert_eq!(pr.contacts(p, RR, &mut out), 0);
        assert!(pr.signed_distance(p).0.is_nan());
    }
    assert_eq!(pr.contacts([0.4, 0.0], f64::NAN, &mut out), 0);
    assert_eq!(pr.contacts([0.4, 0.0], -1.0, &mut out), 0);
    let mut rng = SeededRng::new(1);
    for k in 0..20_000 {
        let mag = 10f64.powf(rng.range(-310.0, 300.0));
        let p = [mag * rng.range(-1.0, 1.0), mag * rng.range(-1.0, 1.0)];
        let p = if k % 7 == 0 { [0.0, 0.0] } else { p };
        let n = pr.contacts(p, RR, &mut out);
        for x in &out[..n] {
            assert!(x.patch.depth_m > 0.0 && x.patch.depth_m.is_finite());
            assert!((norm(x.patch.normal) - 1.0).abs() < 1e-9, "{x:?} at {p:?}");
            assert!((0..17).contains(&x.patch.gap) && (1..=7).contains(&x.patch.area));
        }
        let _ = pr.signed_distance(p);
    }
}

/// Compares the fast `contacts` (and `contacts_hinted`) with the previous implementation.
fn assert_same_as_reference(pr: &AsaProfile, p: V2, r: f64, hint: &mut u32) {
    let mut want = [LocatedPatch::default(); 2];
    let mut got = [LocatedPatch::default(); 2];
    let mut got_h = [LocatedPatch::default(); 2];
    let kw = pr.contacts_reference(p, r, &mut want);
    let kg = pr.contacts(p, r, &mut got);
    let kh = pr.contacts_hinted(p, r, hint, &mut got_h);
    assert_eq!(
        kg,
        kw,
        "count at {p:?} r {r}: {:?} vs {:?}",
        &got[..kg],
        &want[..kw]
    );
    assert_eq!(kh, kg, "hinted count at {p:?} r {r}");
    assert_eq!(got_h[..kh], got[..kg], "hinted at {p:?} r {r}");
    if r == 0.5 * pr.dimensions().roller_diameter_m {
        let mut nominal = [Patch::default(); 2];
        let kn = pr.contacts_nominal(p, &mut 0, &mut nominal);
        assert_eq!(kn, kg, "nominal count at {p:?}");
        for (a, b) in nominal[..kn].iter().zip(&got[..kg]) {
            assert_eq!(*a, b.patch, "nominal at {p:?}");
        }
    }
    for (g, w) in got[..kg].iter().zip(&want[..kw]) {
        assert_eq!(
            (g.patch.area, g.patch.gap, g.patch.patch_id),
            (w.patch.area, w.patch.gap, w.patch.patch_id),
            "labels at {p:?} r {r}: {g:?} vs {w:?}"
        );
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12;
        assert!(
            close(g.patch.depth_m, w.patch.depth_m)
                && close(g.patch.normal[0], w.patch.normal[0])
                && close(g.patch.normal[1], w.patch.normal[1])
                && close(g.point[0], w.point[0])
                && close(g.point[1], w.point[1]),
            "values at {p:?} r {r}: {g:?} vs {w:?}"
        );
    }
}

#[test]
fn fast_contacts_match_the_reference_implementation() {
    let mut rng = SeededRng::new(4242);
    let mut touching = 0;
    let mut total = 0;
    for n in [60, 30, 28, 17, 9] {
        let pr = profile(n);
        let d = pr.dimensions().clone();
        let phi_p = pr.pitch_angle_rad();
        let mut hint = 0;
        // Random points near the outline, random radii (mostly the roller's).
        for k in 0..20_000 {
            let rad = rng.range(d.root_radius_m - 0.03, d.tip_radius_m + 0.03);
            let a = rng.range(-PI, PI);
            let p = [rad * a.cos(), rad * a.sin()];
            let r = match k % 4 {
                0 => rng.range(0.0, 0.045),
                1 => 0.0,
                _ => RR,
            };
            assert_same_as_reference(&pr, p, r, &mut hint);
            let mut out = [LocatedPatch::default(); 2];
            touching += usize::from(pr.contacts(p, r, &mut out) > 0);
            total += 1;
        }
        // Realistic rollers: pressed against the profile by −2..+1 mm, in the seat with
        // and without clearance, and hints that are right, neighbouring or stale.
        for k in 0..1_000 {
            let a = phi_p * (rng.range(-0.5, 0.5) + f64::from(k % n));
            let c = pressed_centre(&pr, a, rng.range(-2e-3, 1e-3));
            let mut h = [k % n, (k + 1) % n, 7 * k, u32::MAX][(k % 4) as usize];
            assert_same_as_reference(&pr, c, RR, &mut h);
            let b = rng.range(-1.2, 1.2);
            let s = rng.range(0.0, d.clearance_m + 1e-3);
            let seat = pr.to_global_point((k % n) as usize, [s * b.sin(), -s * b.cos()]);
            assert_same_as_reference(&pr, seat, RR, &mut h);
            touching += 1;
            total += 2;
        }
    }
    assert!(
        total >= 100_000 && touching > 30_000,
        "{touching} of {total}"
    );
}

/// The direct rules of [`Shortcuts`] against the reference: dense points in the bottom
/// of the gap (across the joint lines c–O–x and c*–O–x*, ξ = 0, the inner and outer
/// radius), rollers rocked onto a working curve just past x or x*, and the free space of
/// the gap, for several sprockets and roller radii; every rule must be exercised.
#[test]
fn direct_rules_match_the_reference_implementation() {
    let mut rng = SeededRng::new(2718);
    let sprockets = [
        (60, P, DR),
        (30, P, DR),
        (28, P, DR),
        (17, P, DR),
        (9, P, DR),
        (10, 0.0127, 0.00792),
        (17, 0.0127, 0.00792),
        (30, 0.0127, 0.00792),
    ];
    let mut by_rule = [0_usize; 4];
    let mut contacts_by_rule = [0_usize; 4];
    let mut total = 0;
    for (n, pitch, dr) in sprockets {
        let pr = match AsaProfile::new(n, pitch, dr) {
            Ok(p) => p,
            Err(e) => panic!("N={n}: {e}"),
        };
        let cut = pr.cuts;
        assert!(
            cut.far_m > 0.0 && cut.free_rule,
            "N={n} P={pitch}: rules enabled"
        );
        let d = pr.dimensions().clone();
        let g = pr.gap_points().clone();
        let rr = 0.5 * dr;
        let (rt, re) = (d.seating_radius_m, d.working_radius_m);
        // Unit directions of the joint line c–O–x and of its mirror.
        let ux = unit_or(g.x_m, [1.0, 0.0]);
        let ux_star = mirror(ux);
        let normal_of = |u: V2| [-u[1], u[0]];
        let mut hint = 0;
        for k in 0..30_000_u32 {
            let gap = (k % n) as usize;
            let r = match k % 8 {
                0 => rng.range(0.0, 1.2 * rt),
                1 => rr * rng.range(0.9, 1.1),
                2 => 0.0,
                _ => rr,
            };
            let reach = r + SKIP_MARGIN_M;
            let r_l = (cut.far_m - reach).min(cut.free_m).max(0.0);
            let q = match k % 6 {
                // Bottom of the gap: anywhere, and on and next to its radii.
                0 => {
                    let a = rng.range(-PI, PI);
                    let s = match k / 6 % 4 {
                        0 => r_l * (1.0 + rng.range(-1e-9, 1e-9)),
                        1 => cut.min_r2.sqrt() * (1.0 + rng.range(-1e-6, 1e-6)),
                        _ => rng.range(0.0, 1.3 * r_l),
                    };
                    [s * a.cos(), s * a.sin()]
                }
                // Across a joint line, at distances from 1e-12 m to 1 mm, and across ξ = 0.
                1 | 2 => {
                    let u = if k % 2 == 0 { ux } else { ux_star };
                    let along = rng.range(-1.0, 1.0) * r_l;
                    let off =
                        10f64.powf(rng.range(-12.0, -3.0)) * [1.0, -1.0][(k / 6 % 2) as usize];
                    let off = match k / 12 % 5 {
                        0 => cut.s_min_m * (1.0 + rng.range(-1e-6, 1e-6)) * off.signum(),
                        _ => off,
                    };
                    let q = add(scale(u, along), scale(normal_of(u), off));
                    if k / 6 % 7 == 0 {
                        [1e-300 * off.signum(), q[1]]
                    } else {
                        q
                    }
                }
                // A roller pressed onto a working curve just past x (or x*), or just off it.
                3 => {
                    let sigma =
                        10f64.powf(rng.range(-9.0, -1.0)) * [1.0, -1.0][(k / 6 % 2) as usize];
                    let depth = rng.range(-1e-3, 2e-3) * dr / DR;
                    let u = rotate(unit_or(sub(g.x_m, g.c_m), [1.0, 0.0]), sigma);
                    let q = add(g.c_m, scale(u, re - r + depth));
                    if k / 6 % 3 == 0 { mirror(q) } else { q }
                }
                // The free space of the gap and its surroundings.
                _ => [
                    rng.range(-1.1, 1.1) * g.f_m[0],
                    rng.range(-rt, g.f_m[1] + 2.0 * r + 1e-3),
                ],
            };
            let p = pr.to_global_point(gap, q);
            let rule = pr.rule_of(p, r);
            by_rule[rule] += 1;
            let mut h = [gap as u32, u32::MAX, hint][(k % 3) as usize];
            assert_same_as_reference(&pr, p, r, &mut h);
            hint = h;
            let mut out = [LocatedPatch::default(); 2];
            if pr.contacts(p, r, &mut out) > 0 {
                contacts_by_rule[rule] += 1;
            }
            total += 1;
        }
    }
    assert!(total >= 200_000, "{total} points");
    // Every rule decides many points, with and without contact.
    assert!(
        by_rule[1] > 40_000 && by_rule[2] > 10_000 && by_rule[3] > 10_000,
        "points by rule {by_rule:?}"
    );
    assert!(
        contacts_by_rule[1] > 20_000,
        "contacts by rule {contacts_by_rule:?}"
    );
}

#[test]
fn gap_search_matches_atan2() {
    let mut rng = SeededRng::new(77);
    for n in [5, 9, 28, 30, 60, 1000, 100_000] {
        let pr = match AsaProfile::new(n, 0.0127 * f64::from(n.min(1000)) / 50.0, 0.002) {
            Ok(p) => p,
            Err(_) => profile(n.min(60)),
        };
        let nn = pr.teeth();
        for k in 0..20_000_u32 {
            let a = rng.range(-PI, PI);
            let r = 10f64.powf(rng.range(-3.0, 1.0));
            let p = if k % 10 == 0 {
                // Exactly on or next to a sector boundary.
                let b = pr.pitch_angle_rad() * (f64::from(k % nn) + 0.5);
                let b = b + [0.0, 1e-13, -1e-13, 1e-7][(k / 10 % 4) as usize];
                [r * b.cos(), r * b.sin()]
            } else {
                [r * a.cos(), r * a.sin()]
            };
            let want = pr.gap_index(p);
            for hint in [u32::MAX, want as u32, (want as u32 + 1) % nn, k] {
                assert_eq!(pr.gap_near(p, hint), want, "N={nn} p {p:?} hint {hint}");
            }
        }
    }
}

#[test]
fn reach_and_seat_bounds_hold() {
    for n in [60, 30, 28, 9] {
        let pr = profile(n);
        let d = pr.dimensions();
        check("reach", pr.reach_radius_m, d.tip_radius_m, 1e-9);
        check("seat clearance", pr.seat_clear_m, d.seating_radius_m, 1e-9);
        let max_r = pr
            .outline(1e-3)
            .iter()
            .map(|q| q.x_m.hypot(q.y_m))
            .fold(0.0, f64::max);
        assert!(max_r <= pr.reach_radius_m, "{max_r} {}", pr.reach_radius_m);
        assert!(pr.graph.is_some(), "N={n}: the outline is a graph");
        // The graph agrees with the sign of the signed distance.
        let mut rng = SeededRng::new(5);
        for _ in 0..5_000 {
            let p = random_point(&mut rng, d);
            let gap = pr.gap_index(p);
            let q = pr.to_local(gap, p);
            let (sd, ..) = pr.signed_distance(p);
            if let Some(free) = pr.graph.and_then(|g| g.is_free(q)) {
                assert_eq!(free, sd > 0.0, "N={n} at {q:?}: sd {sd}");
            }
        }
    }
}

#[test]
fn invalid_inputs_are_errors() {
    assert_eq!(
        AsaProfile::new(3, P, DR).err(),
        Some(AsaError::TooFewTeeth { teeth: 3 })
    );
    assert!(matches!(
        AsaProfile::new(4, P, DR),
        Err(AsaError::DegenerateProfile { .. })
    ));
    assert!(matches!(
        AsaProfile::new(200_000, P, DR),
        Err(AsaError::TooManyTeeth { .. })
    ));
    for (p, dr) in [
        (0.0, DR),
        (-P, DR),
        (f64::NAN, DR),
        (P, 0.0),
        (P, f64::INFINITY),
    ] {
        assert!(matches!(
            AsaProfile::new(20, p, dr),
            Err(AsaError::NonPositive { .. })
        ));
    }
    assert!(matches!(
        AsaProfile::new(20, P, 0.09),
        Err(AsaError::RollerTooBig { .. })
    ));
    let e = AsaError::TooFewTeeth { teeth: 3 };
    assert_eq!(e.to_string(), "ASA sprocket needs at least 4 teeth, got 3");
    let e = AsaError::RollerTooBig {
        seating_diameter_m: 0.5,
        pitch_m: 0.25,
    };
    assert_eq!(
        e.to_string(),
        "seating diameter 0.5 m is not smaller than the pitch 0.25 m"
    );
}
