//! Tensioner arms take up the chain: a chain longer than its straight path
//! lays out with the arm turned into its strand (layout, `check`, the
//! counts `check` offers), the static tension of such a drive is the arm's
//! torque balance, and a chain the arm cannot tension (short of its path)
//! is named: a warning and the summary's `static_tension_set_by`. The
//! command line's side is in the integration tests (`tests/it/arms.rs`).

use crate::geometry::LayoutError;
use crate::model::{BuildError, DriveModel};
use crate::scene::Scene;
use crate::sim::{Simulation, fitting_counts, needed_pitches_of};

fn path(file: &str) -> String {
    format!("{}/{file}", env!("CARGO_MANIFEST_DIR"))
}

fn text(file: &str) -> String {
    std::fs::read_to_string(path(file)).expect("the scene file exists")
}

/// The timing drive of `tests/data/user_timing_06b_arm.toml`: 101 rollers
/// (06B-1, P = 9.525 mm) on a path that needs 100 with straight strands,
/// a hydraulic arm with 25 mm of travel on the slack strand.
const ONE_LINK_LONG: &str = "tests/data/user_timing_06b_arm.toml";

/// `assets/timing-drive.toml` with both cams 2.3 mm higher: the 112
/// rollers (08B-1, P = 12.7 mm, K = 1e8 N/m) are 4.26 mm short of the path
/// with straight strands, within the half pitch the free links take up.
fn short_timing_drive() -> String {
    let t = text("assets/timing-drive.toml");
    assert_eq!(t.matches("0.370638]").count(), 2);
    t.replace("0.370638]", "0.372938]")
}

/// Regression: the straight layout refused a chain one link longer than
/// its path ("too long"), though the arm's 25 mm of travel takes that link
/// up. It lays out now with the arm turned into the strand, every link one
/// pitch long, and `check` offers that count.
#[test]
fn an_arm_takes_up_a_link_the_straight_path_refuses() {
    let scene = Scene::from_toml(&text(ONE_LINK_LONG)).expect("valid");
    let pitch_m = scene.chain().pitch_m;
    let needed = needed_pitches_of(&scene).expect("a path");
    assert!((needed - 100.0).abs() < 1e-3, "{needed}");
    let (_, _, layout) = match DriveModel::build(&scene) {
        Ok(built) => built,
        Err(e) => panic!("the arm takes the link up: {e}"),
    };
    assert_eq!(layout.rollers_m.len(), 101);
    let arm = layout.arms.first().expect("the arm's pose");
    assert!(
        arm.travel_m > 0.0 && arm.travel_m < 0.025,
        "travel {} m",
        arm.travel_m
    );
    // The chain's length is the path's: every free link (on the strands and
    // round the shoe) a pitch long. Wrap links are chords of the seated
    // rollers' circle, inside the pitch circle on the real profile.
    assert!(layout.strand_stretch(pitch_m).abs() < 1e-9);
    assert!(
        (layout.polygon_length_m - 101.0 * pitch_m).abs() < 1e-6,
        "{}",
        layout.polygon_length_m
    );
    let n = layout.rollers_m.len();
    let on_wrap = |i: usize| match (layout.seats[i], layout.seats[(i + 1) % n]) {
        (Some((j, _)), Some((k, _))) => j == k,
        _ => false,
    };
    for i in (0..n).filter(|&i| !on_wrap(i)) {
        let (a, b) = (layout.rollers_m[i], layout.rollers_m[(i + 1) % n]);
        let l = (b[0] - a[0]).hypot(b[1] - a[1]);
        assert!((l / pitch_m - 1.0).abs() < 1e-6, "link {i}: {l} m");
    }
    assert!(
        fitting_counts(&scene).contains(&101),
        "{:?}",
        fitting_counts(&scene)
    );
}

/// A chain longer than the arm's whole travel takes up is refused, and the
/// message says what the arm takes up instead of naming a count.
#[test]
fn a_chain_beyond_the_arms_reach_is_refused_with_their_reach() {
    let t = text(ONE_LINK_LONG).replace("rollers = 101", "rollers = 102");
    let scene = Scene::from_toml(&t).expect("valid");
    match DriveModel::build(&scene) {
        Err(BuildError::Layout(e @ LayoutError::ChainLength { arms: Some(_), .. })) => {
            let message = e.to_string();
            assert!(
                message.contains("tensioner arms' shoes take up"),
                "{message}"
            );
            assert!(!message.contains("nearest count"), "{message}");
        }
        Err(e) => panic!("expected ChainLength with the arms' reach, got {e}"),
        Ok(_) => panic!("two links are more than the arm takes up"),
    }
}

/// The chain's tension at rest is the arm's torque balance. Without gravity
/// and friction at rest, the chain on the shoe is held by the strands'
/// tension T at both ends, pulling along ê_a and ê_b (away from the shoe),
/// so the chain pushes the shoe with T (ê_a + ê_b), through the shoe's
/// centre C (a circular arc's normal forces all point through it). About
/// the pivot P: T (C − P) × (ê_a + ê_b) + F ℓ = 0, ℓ = (a − P) × ê, with the
/// tensioner's push F = p_s π d²/4 + max(0, F₀ − k x) at rest (the chamber
/// held at its supply pressure during the static equilibrium, the return
/// spring pushing only while compressed; docs/model.md).
#[test]
fn the_static_tension_of_a_laid_arm_is_its_torque_balance() {
    let t = text(ONE_LINK_LONG).replace("gravity_m_s2 = [0.0, -9.81]", "gravity_m_s2 = [0.0, 0.0]");
    let scene = Scene::from_toml(&t).expect("valid");
    let sim = Simulation::new(&scene).expect("settles");
    assert!(sim.equilibrium.misfit.is_none());
    assert_eq!(
        sim.equilibrium.tension_set_by(&sim.scene),
        "tensioner_preload"
    );
    let arm = &scene.tensioners()[0];
    let q = sim.state.q[0];
    let turn = |p: [f64; 2]| {
        let r = [p[0] - arm.pivot_m[0], p[1] - arm.pivot_m[1]];
        let (s, c) = q.sin_cos();
        [
            arm.pivot_m[0] + c * r[0] - s * r[1],
            arm.pivot_m[1] + s * r[0] + c * r[1],
        ]
    };
    let cross = |a: [f64; 2], b: [f64; 2]| a[0] * b[1] - a[1] * b[0];
    let sub = |a: [f64; 2], b: [f64; 2]| [a[0] - b[0], a[1] - b[1]];
    let (center, point) = (turn(arm.shoe_center_m), turn(arm.point_m));
    let e = arm.direction;
    let x = sub(point, arm.point_m)[0] * e[0] + sub(point, arm.point_m)[1] * e[1];
    // The scene's hydraulic tensioner: d = 14 mm, p_s = 3 bar, F₀ = 15 N,
    // k = 2 N/mm. Laid beyond the return spring's free length F₀/k = 7.5 mm,
    // the spring is off its seat: the push is p_s A alone.
    assert!(x > 0.0075, "travel {x} m");
    let push_n = 3e5 * std::f64::consts::PI * 0.014f64.powi(2) / 4.0 + (15.0 - 2000.0 * x).max(0.0);
    let lever_m = cross(sub(point, arm.pivot_m), e);
    // The rollers on the shoe, in chain order, and the strands off its ends.
    let reach = arm.shoe_radius_m + scene.chain().roller_radius_m + 1e-6;
    let r = |i: usize| [sim.state.x[i], sim.state.y[i]];
    let n = sim.state.x.len();
    let on: Vec<usize> = (0..n)
        .filter(|&i| {
            let d = sub(r(i), center);
            d[0].hypot(d[1]) < reach
        })
        .collect();
    assert!(on.len() > 3, "{on:?}");
    let (first, last) = (on[0], on[on.len() - 1]);
    assert_eq!(
        last - first + 1,
        on.len(),
        "the shoe's rollers in one run: {on:?}"
    );
    let unit = |a: [f64; 2], b: [f64; 2]| {
        let d = sub(b, a);
        let l = d[0].hypot(d[1]);
        [d[0] / l, d[1] / l]
    };
    let e_a = unit(r(first - 2), r(first - 4));
    let e_b = unit(r(last + 2), r(last + 4));
    let pull = [e_a[0] + e_b[0], e_a[1] + e_b[1]];
    let tension_n = (push_n * lever_m / cross(sub(center, arm.pivot_m), pull)).abs();
    assert!(
        (sim.equilibrium.tension_n / tension_n - 1.0).abs() < 0.02,
        "static tension {} N, the arm's balance {tension_n} N (push {push_n} N at travel {x} m)",
        sim.equilibrium.tension_n
    );
}

/// Regression: a chain 4.26 mm short of its path lays out with its free
/// links stretched and settles at several kN against the 471 N the
/// tensioner holds on the fitted drive, and `check` said only "notice".
/// A shoe only lengthens the path, so the chain's own stretch sets that
/// tension: by hand, with the shortfall e shared by all N links or only by
/// the n_free free links, K e / N ≤ T ≤ K e / n_free. It is a warning now,
/// and the run's summary says what set the tension.
#[test]
fn a_chain_short_of_its_path_sets_the_tension_not_the_arm() {
    let scene = Scene::from_toml(&short_timing_drive()).expect("valid");
    let sim = Simulation::new(&scene).expect("settles");
    let (k, pitch_m) = (scene.chain().stiffness_n_m, scene.chain().pitch_m);
    let short_m = sim.layout.misfit_pitches * pitch_m;
    assert!((short_m - 4.26e-3).abs() < 0.01e-3, "{short_m}");
    let n_free: usize = sim.layout.strand_links.iter().sum();
    let t = sim.equilibrium.tension_n;
    assert!(
        t >= k * short_m / 112.0 && t <= k * short_m / n_free as f64,
        "{t} N outside [{}, {}] N",
        k * short_m / 112.0,
        k * short_m / n_free as f64
    );
    let misfit = sim
        .equilibrium
        .misfit
        .as_ref()
        .expect("the misfit is named");
    assert_eq!(sim.equilibrium.tension_set_by(&sim.scene), "chain_misfit");
    let message = misfit.to_string();
    assert!(message.contains("4.26 mm shorter"), "{message}");
    assert!(
        message.contains("tensioner \"slack-side arm\" pushes"),
        "{message}"
    );
    // The drive as fitted: the tensioner sets its 471 N (`chaindrive check
    // assets/timing-drive.toml`; its push p_s A = 46.2 N, the return spring
    // off its seat), and nothing is said.
    let fitted = Scene::from_toml(&text("assets/timing-drive.toml")).expect("valid");
    let sim = Simulation::new(&fitted).expect("settles");
    assert!(
        sim.equilibrium.misfit.is_none(),
        "{:?}",
        sim.equilibrium.misfit
    );
    assert!((sim.equilibrium.tension_n - 471.0).abs() < 5.0);
}
