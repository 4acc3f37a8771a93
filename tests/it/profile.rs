//! The tooth profiles through their public faces: the `profile` command's
//! table and CSV (a public contract), the exact contact against parry's
//! projection on a fine tessellation, the sprocket colliders in the rapier
//! world, and the real profile running the paper's drive.

use approx::{abs_diff_eq, assert_abs_diff_eq};
use chaindrive::geometry::ToothProfile;
use chaindrive::rng::SeededRng;
use chaindrive::scene::{Overrides, ProfileKind, Scene};
use parry2d_f64::math::Vector;
use parry2d_f64::query::PointQuery;
use parry2d_f64::shape::Polyline;

#[cfg(feature = "cli")]
use crate::common::chaindrive_stdout;

/// docs/tooth-profile.md, “Dimensions of the paper's sprockets” (P = 0.0889 m,
/// Dr = 0.054 m), mm and degrees:
/// (N, A, B, C, Rs, R_t, M, T, R_E, W, V, R_F, H, S, yz, tip radius).
#[cfg(feature = "cli")]
const TABLE: [(u32, [f64; 15]); 3] = [
    (
        60,
        [
            36.0000, 17.0667, 15.9333, 849.3205, 27.1731, 34.9495, 25.3923, 70.3731, 75.4964,
            3.9566, 43.6201, 30.5351, 45.9872, 8.0751, 878.6916,
        ],
    ),
    (
        30,
        [
            37.0000, 16.1333, 14.8667, 425.2430, 27.1731, 34.5011, 25.9984, 70.3731, 75.1859,
            7.9024, 44.1949, 31.3507, 47.4835, 7.3926, 454.2642,
        ],
    ),
    (
        28,
        [
            37.1429, 16.0000, 14.7143, 397.0009, 27.1731, 34.4361, 26.0844, 70.3731, 75.1246,
            8.4645, 44.2741, 31.4622, 47.6932, 7.2948, 425.9669,
        ],
    ),
];
#[cfg(feature = "cli")]
const NAMES: [&str; 15] = [
    "A",
    "B",
    "C",
    "Rs",
    "R_t",
    "M",
    "T",
    "R_E",
    "W",
    "V",
    "R_F",
    "H",
    "S",
    "straight length",
    "tip radius",
];

#[cfg(feature = "cli")]
#[test]
fn profile_prints_the_dimension_table_of_the_papers_sprockets() {
    for (teeth, expected) in TABLE {
        let text = chaindrive_stdout(&[
            "profile",
            "--teeth",
            &teeth.to_string(),
            "--pitch",
            "0.0889",
            "--roller-diameter",
            "0.054",
        ]);
        for (name, value) in NAMES.iter().zip(expected) {
            let line = text
                .lines()
                .find(|l| l.starts_with(&format!("{name:<16} ")))
                .unwrap_or_else(|| panic!("{name} missing in\n{text}"));
            let got: f64 = line[16..]
                .split_whitespace()
                .next()
                .and_then(|v| v.parse().ok())
                .expect("number");
            // Printed to 4 decimals: within half a unit of the last digit.
            assert!(
                abs_diff_eq!(got, value, epsilon = 0.5e-4 + 1e-9),
                "N = {teeth}, {name}: {got} vs {value}"
            );
        }
    }
}

#[cfg(feature = "cli")]
fn csv_points(args: &[&str]) -> Vec<(f64, f64, i64, u8)> {
    let text = chaindrive_stdout(args);
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("x_m,y_m,gap,area"));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (
                f[0].parse().expect("x"),
                f[1].parse().expect("y"),
                f[2].parse().expect("gap"),
                f[3].parse().expect("area"),
            )
        })
        .collect()
}

#[cfg(feature = "cli")]
#[test]
fn outline_csv_contract() {
    let pts = csv_points(&[
        "profile",
        "--teeth",
        "28",
        "--pitch",
        "0.0889",
        "--roller-diameter",
        "0.054",
        "--csv",
    ]);
    // Every gap has all seven areas, met in the order 7, 6, …, 1 going counter-clockwise.
    for gap in 0..28 {
        let mut areas: Vec<u8> = pts.iter().filter(|p| p.2 == gap).map(|p| p.3).collect();
        areas.dedup();
        assert_eq!(areas, vec![7, 6, 5, 4, 3, 2, 1], "gap {gap}");
    }
    // Arcs at ≤ 0.5° steps: consecutive points on one arc are at most one 0.5° chord of the
    // largest radius (R_E = 70.3731 mm) apart.
    let max_chord = 2.0 * 70.3731e-3 * 0.25f64.to_radians().sin() + 1e-9;
    for w in pts.windows(2) {
        if w[0].3 == w[1].3 && w[0].3 != 2 && w[0].3 != 6 {
            let d = (w[0].0 - w[1].0).hypot(w[0].1 - w[1].1);
            assert!(d <= max_chord, "{d} between {:?} and {:?}", w[0], w[1]);
        }
    }
    // Gap 0's seating centre at (R_s, 0): its root (area 4) at R_s − R_t on the +x axis.
    let root = pts
        .iter()
        .filter(|p| p.2 == 0 && p.3 == 4)
        .map(|p| p.0.hypot(p.1))
        .fold(f64::INFINITY, f64::min);
    assert_abs_diff_eq!(root, 369.8278e-3, epsilon = 1e-7);
    let circular = csv_points(&[
        "profile",
        "--teeth",
        "30",
        "--pitch",
        "0.0889",
        "--roller-diameter",
        "0.054",
        "--profile",
        "circular",
        "--csv",
    ]);
    let areas: std::collections::BTreeSet<u8> = circular.iter().map(|p| p.3).collect();
    assert_eq!(areas.into_iter().collect::<Vec<_>>(), vec![0, 4]);
}

#[test]
fn exact_distance_agrees_with_parry_on_a_fine_tessellation() {
    // Oracle: the exact arcs-and-segments distance against parry's projection
    // onto the outline tessellated at 0.02° (chord error < 70 mm · (1 − cos 0.01°) ≈ 1.1 nm).
    let profile = chaindrive::geometry::asa::AsaProfile::new(30, 0.0889, 0.054).expect("profile");
    let pts: Vec<Vector> = profile
        .outline(0.02f64.to_radians())
        .iter()
        .map(|p| Vector::new(p.x_m, p.y_m))
        .collect();
    let n = pts.len() as u32;
    let polyline = Polyline::new(pts, Some((0..n).map(|i| [i, (i + 1) % n]).collect()));
    let mut rng = SeededRng::new(7);
    let mut next = || rng.unit();
    for _ in 0..2000 {
        let a = next() * std::f64::consts::TAU;
        let r = 0.395 + next() * 0.065; // root 398 mm to tip 454 mm, and beyond
        let p = [r * a.cos(), r * a.sin()];
        let (sd, _, _, _) = profile.signed_distance(p);
        let proj = polyline.project_local_point(Vector::new(p[0], p[1]), false);
        let d = (proj.point.x - p[0]).hypot(proj.point.y - p[1]);
        assert!(
            abs_diff_eq!(sd.abs(), d, epsilon = 5e-9),
            "at {p:?}: exact {sd}, parry {d}"
        );
    }
}

#[test]
fn real_profile_seated_contact_is_hertzian() {
    // A roller pressed radially into the seating curve by δ: force K_g δ^1.5 along +e_r.
    let scene = Scene::l60mc()
        .with(&Overrides {
            profile: Some(ProfileKind::Real),
            ..Overrides::default()
        })
        .expect("valid scene");
    let (model, mut state, _) = chaindrive::model::DriveModel::build(&scene).expect("layout");
    let mut forces = chaindrive::forces::ForceGenerator::new(
        chaindrive::forces::ContactLawParams::new(scene.contact()),
        &model,
        state.rollers(),
    );
    let ToothProfile::Real(asa) = &model.sprockets[0].profile else {
        panic!("real profile")
    };
    let d = asa.dimensions();
    let delta = 1e-4;
    // Roller 0 is seated in gap 0 of sprocket 1 (the driver, at the origin).
    let theta = state.theta[0];
    let r = d.pitch_radius_m - d.clearance_m - delta;
    state.x[0] = r * theta.cos();
    state.y[0] = r * theta.sin();
    forces.evaluate(&model, &state);
    let expected = 1e9 * delta.powf(1.5);
    assert_abs_diff_eq!(
        forces.output().contact_force[0],
        expected,
        epsilon = 1e-9 * expected
    );
}

#[test]
fn sprocket_colliders_are_seen_by_ray_casts() {
    let sim = chaindrive::sim::Simulation::new(&Scene::l60mc()).expect("sim");
    let mut world = sim.world;
    world.step();
    // A ray from the left towards sprocket 1's centre along +x, at y = 0: it meets the
    // sprocket between its root and tip radius (the rollers' own colliders are filtered out).
    let ray = rapier2d_f64::prelude::Ray::new(Vector::new(-2.0, 0.0), Vector::new(1.0, 0.0));
    let is_sprocket = |h: rapier2d_f64::prelude::ColliderHandle,
                       _: &rapier2d_f64::prelude::Collider| {
        sim.bodies
            .sprockets
            .iter()
            .any(|s| world.colliders[h].parent() == Some(*s))
    };
    let filter = rapier2d_f64::prelude::QueryFilter::default().predicate(&is_sprocket);
    let (_, toi) = world.cast_ray(&ray, 10.0, true, filter).expect("hit");
    let hit_radius = 2.0 - toi;
    assert!(
        hit_radius > 0.849 - 0.028 && hit_radius < 0.8787,
        "{hit_radius}"
    );
}

#[test]
fn parry_projection_on_the_sprocket_collider_agrees_to_its_tessellation() {
    // The collider is the outline tessellated at 2° (model::rapier::COLLIDER_ARC_STEP_RAD):
    // chord error ≤ R (1 − cos 1°) for the largest arc radius R_E = 70.37 mm, 10.7 µm.
    let profile = ToothProfile::Real(Box::new(
        chaindrive::geometry::asa::AsaProfile::new(28, 0.0889, 0.054).expect("profile"),
    ));
    let shape = chaindrive::model::rapier::sprocket_shape(&profile);
    let ToothProfile::Real(asa) = &profile else {
        unreachable!()
    };
    let tolerance = 70.3731e-3 * (1.0 - 1f64.to_radians().cos()) + 1e-9;
    let mut rng = SeededRng::new(11);
    let mut next = || rng.unit();
    for _ in 0..2000 {
        let a = next() * std::f64::consts::TAU;
        let r = 0.367 + next() * 0.065;
        let p = [r * a.cos(), r * a.sin()];
        let (sd, _, _, _) = asa.signed_distance(p);
        let proj = shape.project_local_point(Vector::new(p[0], p[1]), false);
        let d = (proj.point.x - p[0]).hypot(proj.point.y - p[1]);
        assert!(
            abs_diff_eq!(sd.abs(), d, epsilon = tolerance),
            "at {p:?}: exact {sd}, collider {d}"
        );
    }
}
