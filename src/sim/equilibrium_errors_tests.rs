//! Infeasible static equilibria end with their cause, and the numbers in the
//! message are the ones that make the drive feasible: each error is checked
//! against a closed form derived here, or against a relaxation run at the
//! suggested value (the relaxation knows nothing of the closed forms).

use crate::scene::Scene;
use crate::sim::{EquilibriumError, SimError, Simulation};

fn data(file: &str) -> String {
    let path = format!("{}/tests/data/{file}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).expect("the scene file exists")
}

fn equilibrium_error(scene: &Scene) -> EquilibriumError {
    match Simulation::new(scene) {
        Err(SimError::Equilibrium(e)) => e,
        Err(e) => panic!("expected an equilibrium error, got {e}"),
        Ok(sim) => panic!("expected no equilibrium, got {:?}", sim.equilibrium),
    }
}

/// The 30/30 drive of `flat_30_30_real.toml` moved closer, by a fifth of a
/// pitch of chain,
/// and the given gravity; no load.
fn long_30_30(gravity: &str) -> Scene {
    let text = data("flat_30_30_real.toml")
        .replace(
            "center_m = [1.7780250000, 0.0]",
            &format!("center_m = [{C}, 0.0]"),
        )
        .replace("gravity_m_s2 = [0.0, 0.0]", gravity)
        .replace("load_torque_n_m = -2126.215129", "load_torque_n_m = 0.0");
    Scene::from_toml(&text).expect("a valid scene")
}

const P: f64 = 0.0889;

const C: f64 = 1.76911;

const Z: f64 = 30.0;

/// Two equal sprockets C apart: the strands are straight and C long, and each
/// half wrap seats z/2 rollers a pitch apart, so the path through the seated
/// rollers is z P + 2 C. A chain of N rollers is longer by N − z − 2 C / P
/// pitches: 0.2 for 70 rollers at C = 19.9 P, within the quarter pitch the
/// layout absorbs, but far beyond what 3 kN can take up.
fn excess_pitches(rollers: f64) -> f64 {
    rollers - Z - 2.0 * C / P
}

#[test]
fn a_chain_too_long_without_gravity_is_named_with_its_excess() {
    let scene = long_30_30("gravity_m_s2 = [0.0, 0.0]");
    let err = equilibrium_error(&scene);
    let message = err.to_string();
    let EquilibriumError::ChainTooLong {
        long_pitches,
        sag_m,
        sag_tension_n,
        ..
    } = err
    else {
        panic!("expected ChainTooLong, got {message}");
    };
    approx::assert_abs_diff_eq!(long_pitches, excess_pitches(70.0), epsilon = 0.02);
    assert_eq!(sag_m, 0.0, "nothing sags without gravity");
    assert_eq!(sag_tension_n, None, "{message}");
    assert!(message.contains("without gravity"), "{message}");
    assert!(message.contains("remove rollers"), "{message}");
}

/// Under gravity a too-long chain can hang its excess in the strands' sag at
/// a lower tension. A shallow strand of span L under the weight q per length
/// across it is a parabola y = 4 d x (L − x) / L² with d = q L² / (8 T); its
/// arc length is L + 8 d² / (3 L) = L + q² L³ / (24 T²). Two horizontal
/// strands take up ΔL = q² L³ / (12 T²), so T = √(q² L³ / (12 ΔL)).
#[test]
fn a_chain_too_long_under_gravity_suggests_the_pretension_at_which_it_sags() {
    let scene = long_30_30("gravity_m_s2 = [0.0, -9.81]");
    let err = equilibrium_error(&scene);
    let message = err.to_string();
    let EquilibriumError::ChainTooLong {
        long_m,
        sag_tension_n,
        ..
    } = err
    else {
        panic!("expected ChainTooLong, got {message}");
    };
    approx::assert_abs_diff_eq!(long_m / P, excess_pitches(70.0), epsilon = 0.02);
    let q = 0.3 / P * 9.81;
    // The strands span the tangent length between the pitch circles: C.
    let expected = (q * q * C.powi(3) / (12.0 * long_m)).sqrt();
    let suggested = sag_tension_n.expect("a pretension to suggest under gravity");
    approx::assert_relative_eq!(suggested, expected, max_relative = 0.01);
    assert!(message.contains(&format!("{suggested:.0} N")), "{message}");
}

/// The paper's drive without gravity, with opposite loads on its two
/// counterweight sprockets (the scene has no loads of its own).
fn paper_loaded(pretension_n: f64, right_n_m: f64, left_n_m: f64) -> Scene {
    let mut text = data("../../assets/l60mc.toml")
        .replace("gravity_m_s2 = [0.0, -9.81]", "gravity_m_s2 = [0.0, 0.0]")
        .replace(
            "pretension_n = 21000.0",
            &format!("pretension_n = {pretension_n:.3}"),
        );
    for (name, load) in [
        ("name = \"counterweight (right)\"", right_n_m),
        ("name = \"counterweight (left)\"", left_n_m),
    ] {
        let at = text.find(name).expect("the sprocket is in the scene") + name.len();
        text.insert_str(at, &format!("\nload_torque_n_m = {load:.3}"));
    }
    Scene::from_toml(&text).expect("a valid scene")
}

/// Static link force of every free strand, from the relaxed chain.
fn strand_forces(sim: &Simulation) -> Vec<f64> {
    crate::test_support::strand_means(&sim.model, &sim.state, sim.forces.output())
        .into_iter()
        .map(|m| m.expect("a free strand"))
        .collect()
}

/// Loads on two sprockets that would leave a strand in compression are
/// named with the least pretension that holds them. The check: the strands'
/// tensions are the pretension plus terms linear in the loads, so at a
/// pretension T′ above the named threshold T* the weakest strand of the
/// *relaxed* chain carries T′ − T* (the relaxation balances forces on every
/// roller and torques on every sprocket and knows nothing of the threshold).
#[test]
fn loads_that_leave_a_strand_in_compression_are_named_with_the_pretension_that_holds_them() {
    let (right, left) = (9000.0, -9000.0);
    let err = equilibrium_error(&paper_loaded(21000.0, right, left));
    let message = err.to_string();
    let needed_n = match err {
        EquilibriumError::StrandCompression {
            needed_n,
            tension_n,
            ..
        } => {
            assert!(tension_n < 0.0, "{message}");
            needed_n
        }
        other => panic!("expected StrandCompression, got {other}"),
    };
    assert!(message.contains("compression"), "{message}");
    // 1.5 T* used to end with a residual torque of about 950 N·m on a
    // counterweight after 30 relaxations; Newton settles it, and 3 T*.
    for factor in [1.5, 3.0] {
        let raised = factor * needed_n;
        let sim = Simulation::new(&paper_loaded(raised, right, left)).expect("feasible above T*");
        assert!(
            sim.equilibrium.force_residual <= 1e-6,
            "{factor} T*: {:?}",
            sim.equilibrium
        );
        let weakest = strand_forces(&sim)
            .into_iter()
            .fold(f64::INFINITY, f64::min);
        approx::assert_relative_eq!(weakest, raised - needed_n, max_relative = 0.03);
    }
}
