//! Unit tests of the ASA profile: the standard's tables, the construction, the exact
//! distance against a brute-force polyline; the contact query in [`contacts`].

use super::pieces::{Piece, Shape};
use super::query::SKIP_MARGIN_M;
use super::*;
use crate::geometry::v2::{add, dot, mirror, norm, polar, scale, sub, unit_or};
use crate::rng::SeededRng;

mod contacts;

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
    let mut rng = SeededRng::new(12345);
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

/// The radius at which a roller rides a tip, against a closed form in the frame of the
/// tooth: origin at the midpoint M of the chord between two seating centres (R_s cos φ
/// from the sprocket centre on the tooth's centreline), u along the chord, v outward
/// along the centreline. The topping centre b lies on the chord a = 1.4 D_r − P/2 past
/// M, the tip f on the centreline H above M, so f − b = (−a, H) with |f − b| = R_F. The
/// roller centre touching f on the topping's normal is b + (1 + R_r/R_F)(f − b) =
/// (−a R_r/R_F, H (1 + R_r/R_F)), at a radius
///
///     r_tip² = (R_s cos φ + H (1 + R_r/R_F))² + (a R_r / R_F)².
///
/// That centre lies R_r from the outline with f its nearest point, and every centre
/// touching the topping curve lower down lies nearer the sprocket centre.
#[test]
fn tip_ride_radius_matches_its_closed_form_and_bounds_the_flank() {
    // ANSI 80 (D_r = 0.625 P; the standard's additive constants in inches make
    // the rise in pitches depend a little on the pitch) and the paper's chain.
    let ansi = |n: u32, p: f64| (n, p, 0.625 * p);
    for (n, p, dr) in [
        ansi(12, 0.0254),
        ansi(19, 0.0254),
        ansi(45, 0.0254),
        ansi(120, 0.0254),
        (30, P, DR),
    ] {
        let prof = AsaProfile::new(n, p, dr).expect("profile");
        let d = prof.dimensions();
        let (rr, rf) = (0.5 * dr, d.topping_radius_m);
        let phi = std::f64::consts::PI / f64::from(n);
        let a = 1.4 * dr - 0.5 * p;
        let h = (rf * rf - a * a).sqrt();
        let want = ((d.pitch_radius_m * phi.cos() + h * (1.0 + rr / rf)).powi(2)
            + (a * rr / rf).powi(2))
        .sqrt();
        let got = prof.tip_ride_radius_m();
        assert!((got - want).abs() < 1e-12, "N = {n}: {got} against {want}");
        // The quasi-static ride-over of docs/design-checks.md on the ANSI
        // proportions: a rise of 0.535 P.
        let rise = (got - d.pitch_radius_m) / p;
        if dr == 0.625 * p {
            assert!((rise - 0.535).abs() < 0.004, "N = {n}: rise {rise} P");
        }
        // The centre found by walking out from b through the tip: R_r from the
        // outline, f its nearest point (in the sprocket frame, gap 0 at (R_s, 0)).
        let pts = prof.gap_points();
        let local = |q: V2| [d.pitch_radius_m + q[1], -q[0]];
        let u = scale(sub(pts.f_m, pts.b_m), 1.0 / rf);
        let centre = add(pts.b_m, scale(u, rf + rr));
        let (sd, near, _, _) = prof.signed_distance(local(centre));
        assert!((sd - rr).abs() < 1e-12, "N = {n}: {sd} against {rr}");
        let f = local(pts.f_m);
        assert!(
            norm(sub(near, f)) < 1e-12,
            "N = {n}: nearest {near:?}, tip {f:?}"
        );
        // Lower on the topping curve (towards z) the touching centre is nearer in.
        let (zb, fb) = (sub(pts.z_m, pts.b_m), sub(pts.f_m, pts.b_m));
        let (t0, t1) = (zb[1].atan2(zb[0]), fb[1].atan2(fb[0]));
        for k in 0..20 {
            let t = t0 + (t1 - t0) * f64::from(k) / 20.0;
            let c = add(pts.b_m, scale(polar(t), rf + rr));
            let r = norm(local(c));
            assert!(
                r < got,
                "N = {n}: {r} at {k}/20 of the topping, tip ride at {got}"
            );
        }
    }
}
