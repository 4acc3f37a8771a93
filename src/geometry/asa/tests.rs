//! Unit tests of the ASA profile: the standard's tables, the construction, the exact
//! distance against a brute-force polyline, and the fast query against the reference.

use super::pieces::{Piece, Shape};
use super::query::SKIP_MARGIN_M;
use super::v2::{add, dot, mirror, norm, polar, scale, sub, unit_or};
use super::*;
use crate::geometry::testing::Lcg;

const P: f64 = 0.0889;
const DR: f64 = 0.054;
const RR: f64 = 0.027;
/// Half a unit in the 4th printed decimal (plus rounding slack).
const HALF_E4: f64 = 0.5e-4 + 1e-9;

fn profile(n: u32) -> AsaProfile {
    match AsaProfile::new(n, P, DR) {
        Ok(p) => p,
        Err(e) => panic!("profile N={n}: {e}"),
    }
}

fn check(what: &str, got: f64, want: f64, tol: f64) {
    assert!(
        (got - want).abs() <= tol,
        "{what}: got {got}, want {want} (tol {tol}, diff {})",
        got - want
    );
}
fn mm(what: &str, got_m: f64, want_mm: f64) {
    check(what, got_m * 1e3, want_mm, HALF_E4);
}
fn mm2(what: &str, got_m: V2, want_mm: [f64; 2]) {
    mm(&format!("{what}.ξ"), got_m[0], want_mm[0]);
    mm(&format!("{what}.η"), got_m[1], want_mm[1]);
}
fn deg(what: &str, got_rad: f64, want_deg: f64) {
    check(what, got_rad.to_degrees(), want_deg, HALF_E4);
}

/// One column of the table in docs/tooth-profile.md, “Dimensions of the paper's
/// sprockets” (lengths mm, angles deg).
struct Column {
    n: u32,
    abc: [f64; 3],
    alpha: f64,
    rs: f64,
    rt: f64,
    dr_clear: f64,
    mt: [f64; 2],
    re: f64,
    wv: [f64; 2],
    rf: f64,
    hs: [f64; 2],
    xy_yz: [f64; 2],
    x: [f64; 2],
    y: [f64; 2],
    z: [f64; 2],
    f: [f64; 2],
    th_a: [f64; 2],
    th_c: [f64; 2],
    th_c_star: [f64; 2],
    th_b: [f64; 2],
    th_b_star: [f64; 2],
    sweep: f64,
    root: f64,
    tip: f64,
}

fn table() -> [Column; 3] {
    [
        Column {
            n: 60,
            abc: [36.0, 17.0667, 15.9333],
            alpha: 33.0,
            rs: 849.3205,
            rt: 27.1731,
            dr_clear: 0.1731,
            mt: [34.9495, 25.3923],
            re: 70.3731,
            wv: [75.4964, 3.9566],
            rf: 43.6201,
            hs: [30.5351, 45.9872],
            xy_yz: [20.8846, 8.0751],
            x: [21.9835, -15.9719],
            y: [31.6162, 2.5585],
            z: [34.2363, 10.1967],
            f: [45.9872, 28.1669],
            th_a: [216.0, 324.0],
            th_c: [324.0, 341.0667],
            th_c_star: [198.9333, 216.0],
            th_b: [132.5711, 161.0667],
            th_b_star: [18.9333, 47.4289],
            sweep: 28.4955,
            root: 822.1474,
            tip: 878.6916,
        },
        Column {
            n: 30,
            abc: [37.0, 16.1333, 14.8667],
            alpha: 31.0,
            rs: 425.2430,
            rt: 27.1731,
            dr_clear: 0.1731,
            mt: [34.5011, 25.9984],
            re: 70.3731,
            wv: [75.1859, 7.9024],
            rf: 44.1949,
            hs: [31.3507, 47.4835],
            xy_yz: [19.7502, 7.3926],
            x: [21.7014, -16.3532],
            y: [31.2564, 0.9319],
            z: [33.8896, 7.8396],
            f: [47.4835, 26.5327],
            th_a: [217.0, 323.0],
            th_c: [323.0, 339.1333],
            th_c_star: [200.8667, 217.0],
            th_b: [128.8160, 159.1333],
            th_b_star: [20.8667, 51.1840],
            sweep: 30.3173,
            root: 398.0699,
            tip: 454.2642,
        },
        Column {
            n: 28,
            abc: [37.1429, 16.0, 14.7143],
            alpha: 30.7143,
            rs: 397.0009,
            rt: 27.1731,
            dr_clear: 0.1731,
            mt: [34.4361, 26.0844],
            re: 70.3731,
            wv: [75.1246, 8.4645],
            rf: 44.2741,
            hs: [31.4622, 47.6932],
            xy_yz: [19.5881, 7.2948],
            x: [21.6606, -16.4072],
            y: [31.1997, 0.7012],
            z: [33.8309, 7.5049],
            f: [47.6932, 26.2876],
            th_a: [217.1429, 322.8571],
            th_c: [322.8571, 338.8571],
            th_c_star: [201.1429, 217.1429],
            th_b: [128.2857, 158.8571],
            th_b_star: [21.1429, 51.7143],
            sweep: 30.5714,
            root: 369.8278,
            tip: 425.9669,
        },
    ]
}

#[test]
fn dimension_tables_of_the_papers_sprockets() {
    for col in table() {
        let pr = profile(col.n);
        let d = pr.dimensions();
        let g = pr.gap_points();
        let tag = |s: &str| format!("N={} {s}", col.n);
        assert_eq!(d.teeth, col.n);
        deg(&tag("A"), d.a_rad, col.abc[0]);
        deg(&tag("B"), d.b_rad, col.abc[1]);
        deg(&tag("C"), d.c_rad, col.abc[2]);
        deg(&tag("alpha"), d.pressure_angle_rad, col.alpha);
        mm(&tag("Rs"), d.pitch_radius_m, col.rs);
        mm(&tag("Rt"), d.seating_radius_m, col.rt);
        mm(&tag("dR"), d.clearance_m, col.dr_clear);
        mm(&tag("M"), d.m_m, col.mt[0]);
        mm(&tag("T"), d.t_m, col.mt[1]);
        mm(&tag("RE"), d.working_radius_m, col.re);
        mm(&tag("W"), d.w_m, col.wv[0]);
        mm(&tag("V"), d.v_m, col.wv[1]);
        mm(&tag("RF"), d.topping_radius_m, col.rf);
        mm(&tag("H"), d.h_m, col.hs[0]);
        mm(&tag("S"), d.s_m, col.hs[1]);
        mm(&tag("xy"), d.working_chord_m, col.xy_yz[0]);
        mm(&tag("yz"), d.straight_length_m, col.xy_yz[1]);
        mm2(&tag("x"), g.x_m, col.x);
        mm2(&tag("y"), g.y_m, col.y);
        mm2(&tag("z"), g.z_m, col.z);
        mm2(&tag("f"), g.f_m, col.f);
        deg(&tag("th1a"), g.theta_1a_rad, col.th_a[0]);
        deg(&tag("th2a"), g.theta_2a_rad, col.th_a[1]);
        deg(&tag("th1c"), g.theta_1c_rad, col.th_c[0]);
        deg(&tag("th2c"), g.theta_2c_rad, col.th_c[1]);
        deg(&tag("th1c*"), g.theta_1c_star_rad, col.th_c_star[0]);
        deg(&tag("th2c*"), g.theta_2c_star_rad, col.th_c_star[1]);
        deg(&tag("th1b"), g.theta_1b_rad, col.th_b[0]);
        deg(&tag("th2b"), g.theta_2b_rad, col.th_b[1]);
        deg(&tag("th1b*"), g.theta_1b_star_rad, col.th_b_star[0]);
        deg(&tag("th2b*"), g.theta_2b_star_rad, col.th_b_star[1]);
        deg(&tag("sweep"), g.topping_sweep_rad, col.sweep);
        mm(&tag("root"), d.root_radius_m, col.root);
        mm(&tag("tip"), d.tip_radius_m, col.tip);
        // Derived identities of the constants (docs/tooth-profile.md, “Constants”).
        let phi = PI / f64::from(col.n);
        check(&tag("C=A-B-phi"), d.c_rad, d.a_rad - d.b_rad - phi, 1e-15);
        check(
            &tag("alpha=A-phi"),
            d.pressure_angle_rad,
            d.a_rad - phi,
            1e-15,
        );
        check(
            &tag("RE=0.8Dr+Rt"),
            d.working_radius_m,
            0.8 * DR + d.seating_radius_m,
            1e-15,
        );
        check(
            &tag("|x-y|=xy"),
            norm(sub(g.x_m, g.y_m)),
            d.working_chord_m,
            1e-14,
        );
        check(
            &tag("|y-z|=yz"),
            norm(sub(g.y_m, g.z_m)),
            d.straight_length_m,
            1e-14,
        );
        check(
            &tag("|f-b|=RF"),
            norm(sub(g.f_m, g.b_m)),
            d.topping_radius_m,
            1e-14,
        );
        // Truncated OD/2 of the table's last row is not used, but check the formula.
        let od2 = P * (0.6 + 1.0 / phi.tan()) / 2.0;
        let want = match col.n {
            60 => 874.8265,
            30 => 449.5835,
            _ => 421.1747,
        };
        mm(&tag("OD/2"), od2, want);
    }
}

#[test]
fn aca_gears_ids_number_80_n28_in_inches() {
    let inch = 0.0254;
    let pr = match AsaProfile::new(28, inch, 0.625 * inch) {
        Ok(p) => p,
        Err(e) => panic!("#80: {e}"),
    };
    let d = pr.dimensions();
    let tol = HALF_E4;
    let i = |x: f64| x / inch;
    check("B deg", d.b_rad.to_degrees(), 16.0, tol);
    check("ab", 1.4 * i(d.roller_diameter_m), 0.8750, tol);
    check("W", i(d.w_m), 0.8695, tol);
    check("V", i(d.v_m), 0.0980, tol);
    check("F", i(d.topping_radius_m), 0.5114, tol);
    check("H", i(d.h_m), 0.3477, tol);
    check("S", i(d.s_m), 0.5358, tol);
    check("yz", i(d.straight_length_m), 0.0844, tol);
    check("xy", i(d.working_chord_m), 0.2270, tol);
    check("M", i(d.m_m), 0.3986, tol);
    check("T", i(d.t_m), 0.3019, tol);
    check("E", i(d.working_radius_m), 0.8156, tol);
    check("Ds", 2.0 * i(d.seating_radius_m), 0.6311, tol);
    check("PD", 2.0 * i(d.pitch_radius_m), 8.9314, tol);
}

fn arc_point(piece: &Piece, at_end: bool) -> V2 {
    match piece.shape {
        Shape::Arc {
            centre,
            radius_m,
            start_rad,
            sweep_rad,
        } => {
            let a = if at_end {
                start_rad + sweep_rad
            } else {
                start_rad
            };
            add(centre, scale(polar(a), radius_m))
        }
        Shape::Segment => {
            if at_end {
                piece.end
            } else {
                piece.start
            }
        }
    }
}

#[test]
fn joints_continuous_and_tangent() {
    for n in [60, 30, 28, 17, 10] {
        let pr = profile(n);
        let own = &pr.own;
        for piece in own.iter().chain([&pr.next_area7, &pr.prev_area1]) {
            // Stored end points agree with the arc formula.
            check(
                "start",
                norm(sub(arc_point(piece, false), piece.start)),
                0.0,
                1e-14,
            );
            check(
                "end",
                norm(sub(arc_point(piece, true), piece.end)),
                0.0,
                1e-14,
            );
        }
        for w in own.windows(2) {
            let (a, b) = (&w[0], &w[1]);
            let tag = format!("N={n} areas {}->{}", a.area, b.area);
            check(&tag, norm(sub(a.end, b.start)), 0.0, 1e-14);
            let ta = a.tangent(true);
            let tb = b.tangent(false);
            check(
                &format!("{tag} tangent"),
                ta[0] * tb[1] - ta[1] * tb[0],
                0.0,
                1e-12,
            );
            assert!(dot(ta, tb) > 0.999_999, "{tag}: tangent reversed");
        }
        // Tip: area 1 of this gap ends where area 7 of the next gap starts.
        check(
            "tip",
            norm(sub(own[7].end, pr.next_area7.start)),
            0.0,
            1e-12,
        );
        check(
            "tip'",
            norm(sub(pr.prev_area1.end, own[0].start)),
            0.0,
            1e-12,
        );
        // The tip is a convex corner: the walk turns left there.
        let t1 = own[7].tangent(true);
        let t7 = pr.next_area7.tangent(false);
        assert!(t1[0] * t7[1] - t1[1] * t7[0] > 0.0, "N={n}: tip not convex");
        // The tip lies on the tooth centreline at the tip radius.
        let f_global = pr.to_global_point(0, own[0].start);
        let d = pr.dimensions();
        check("tip radius", norm(f_global), d.tip_radius_m, 1e-12);
        let want_angle = -PI / f64::from(n);
        check(
            "tip angle",
            f_global[1].atan2(f_global[0]),
            want_angle,
            1e-14,
        );
    }
}

#[test]
fn outline_is_closed_and_ordered() {
    let pr = profile(28);
    let step = 0.01;
    let pts = pr.outline(step);
    let max_gap = step * pr.dimensions().working_radius_m * 1.0001;
    let n = pts.len();
    let mut turning = 0.0;
    for k in 0..n {
        let a = pts[k];
        let b = pts[(k + 1) % n];
        let c = pts[(k + 2) % n];
        let ab = [b.x_m - a.x_m, b.y_m - a.y_m];
        let bc = [c.x_m - b.x_m, c.y_m - b.y_m];
        assert!(norm(ab) <= max_gap, "step {k} too long: {}", norm(ab));
        assert!(norm(ab) > 0.0, "repeated point at {k}");
        turning += (ab[0] * bc[1] - ab[1] * bc[0]).atan2(dot(ab, bc));
        assert!((1..=7).contains(&a.area) && (0..28).contains(&a.gap));
    }
    // One counter-clockwise turn.
    check("total turning", turning, 2.0 * PI, 1e-9);
    // Area order within each gap: 7, 6, 5, 4, 3, 2, 1.
    let mut last = (0_i64, 8_u8);
    for pt in &pts {
        if pt.gap == last.0 {
            assert!(pt.area <= last.1, "area order broken at gap {}", pt.gap);
        } else {
            assert_eq!(pt.gap, last.0 + 1);
            assert_eq!(pt.area, 7);
        }
        last = (pt.gap, pt.area);
    }
    // Non-finite and tiny steps are guarded.
    assert!(!pr.outline(f64::NAN).is_empty());
    assert!(!pr.outline(-1.0).is_empty());
}

fn seg_dist(p: V2, a: V2, b: V2) -> f64 {
    let e = sub(b, a);
    let l2 = dot(e, e);
    let t = if l2 > 0.0 {
        (dot(sub(p, a), e) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    norm(sub(p, add(a, scale(e, t))))
}

/// Even-odd test against the polygon.
fn inside(p: V2, poly: &[V2]) -> bool {
    let mut c = false;
    let n = poly.len();
    for k in 0..n {
        let a = poly[k];
        let b = poly[(k + 1) % n];
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if p[0] < x {
                c = !c;
            }
        }
    }
    c
}

#[test]
fn signed_distance_matches_brute_force_oracle() {
    let pr = profile(28);
    let step = 2e-4;
    let poly: Vec<V2> = pr.outline(step).iter().map(|q| [q.x_m, q.y_m]).collect();
    // Chord sag of the coarsest arc (RE) bounds the polyline error.
    let tol = pr.dimensions().working_radius_m * step * step / 8.0 * 1.5 + 1e-12;
    let d = pr.dimensions();
    let mut rng = Lcg(12345);
    for _ in 0..300 {
        let r = rng.range(d.root_radius_m - 0.03, d.tip_radius_m + 0.03);
        let a = rng.range(-PI, PI);
        let p = [r * a.cos(), r * a.sin()];
        let (sd, q, area, gap) = pr.signed_distance(p);
        let brute = poly
            .iter()
            .zip(poly.iter().cycle().skip(1))
            .map(|(&a, &b)| seg_dist(p, a, b))
            .fold(f64::INFINITY, f64::min);
        check("|sd| vs brute", sd.abs(), brute, tol);
        check("|p-q| = |sd|", norm(sub(p, q)), sd.abs(), 1e-12);
        if sd.abs() > 10.0 * tol {
            let material = inside(p, &poly);
            assert_eq!(sd < 0.0, material, "sign at {p:?}: sd {sd}");
        }
        assert!((1..=7).contains(&area) && (0..28).contains(&gap));
        // The contact with a zero-radius probe is consistent with the distance.
        let mut out = [LocatedPatch::default(); 2];
        let k = pr.contacts(p, 0.0, &mut out);
        assert_eq!(k > 0, sd < 0.0, "probe at {p:?}");
        if k > 0 {
            check("probe depth", out[0].patch.depth_m, -sd, 1e-12);
        }
        // A roller of random size: the deepest patch is the nearest outline point, and
        // every patch is a local minimum of the distance to the (sampled) outline.
        let r = rng.range(0.0, 0.045);
        let k = pr.contacts(p, r, &mut out);
        assert_eq!(k > 0, sd < r, "roller at {p:?} r {r}");
        if k > 0 {
            check("deepest = nearest", out[0].patch.depth_m, r - sd, 1e-12);
        }
        for x in &out[..k] {
            let (sq, _, _, _) = pr.signed_distance(x.point);
            check("patch point on outline", sq, 0.0, 1e-12);
            let dq = norm(sub(p, x.point));
            if sd > 0.0 {
                check("depth = r - |p-q|", x.patch.depth_m, r - dq, 1e-12);
            }
            let near_closer = poly
                .iter()
                .zip(poly.iter().cycle().skip(1))
                .filter(|(a, _)| norm(sub(**a, x.point)) < 2e-3)
                .any(|(&a, &b)| seg_dist(p, a, b) < dq - tol);
            assert!(!near_closer, "patch {x:?} of {p:?} is no local minimum");
        }
    }
}

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

fn random_point(rng: &mut Lcg, d: &AsaDimensions) -> V2 {
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
    let mut rng = Lcg(7);
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
    let mut rng = Lcg(99);
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
    let mut rng = Lcg(3);
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
    let mut rng = Lcg(1);
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
    let mut rng = Lcg(4242);
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
    let mut rng = Lcg(2718);
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
    let mut rng = Lcg(77);
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
        let mut rng = Lcg(5);
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
