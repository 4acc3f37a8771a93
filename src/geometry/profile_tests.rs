//! The tooth profiles through their public faces: the `profile` command's
//! table and CSV (a public contract), the exact contact against parry's
//! projection on a fine tessellation, the sprocket colliders in the rapier
//! world, and the real profile running the paper's drive.

use crate::geometry::ToothProfile;
use crate::rng::SeededRng;
use crate::scene::{Overrides, ProfileKind, Scene};
use approx::{abs_diff_eq, assert_abs_diff_eq};
use parry2d_f64::math::Vector;
use parry2d_f64::query::PointQuery;
use parry2d_f64::shape::Polyline;

#[test]
fn exact_distance_agrees_with_parry_on_a_fine_tessellation() {
    // Oracle: the exact arcs-and-segments distance against parry's projection
    // onto the outline tessellated at 0.02° (chord error < 70 mm · (1 − cos 0.01°) ≈ 1.1 nm).
    let profile = crate::geometry::asa::AsaProfile::new(30, 0.0889, 0.054).expect("profile");
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
    let (model, mut state, _) = crate::model::DriveModel::build(&scene).expect("layout");
    let mut forces = crate::forces::ForceGenerator::new(
        crate::forces::ContactLawParams::new(scene.contact()),
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
    let sim = crate::sim::Simulation::new(&Scene::l60mc()).expect("sim");
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
        crate::geometry::asa::AsaProfile::new(28, 0.0889, 0.054).expect("profile"),
    ));
    let shape = crate::model::rapier::sprocket_shape(&profile);
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
