//! Free strands found in chain order: sagging conveyors at rest, with the
//! driver held and a load on the tail, against the tail's moment balance.
//!
//! Two 20T sprockets, ANSI 80 chain, both wrapped counter-clockwise, the tail
//! to the left of the driver: the chain runs along the upper strand (segment
//! 1, −x) to the tail and back along the lower strand (segment 2, +x). Both
//! strands pull the tail towards the driver (+x), the upper one at its top,
//! the lower one at its bottom, so a clockwise load torque M < 0 on the tail
//! is carried by the lower strand's extra tension:
//!
//!   a (T₂ − T₁) + 2 w R² + M = 0,
//!
//! with a the strands' lever arm about the tail's centre and the middle term
//! the moment of the weight of the chain wrapped on the tail's outer (left)
//! half (weight per metre w = m g / P, lever arm R cos φ over φ ∈ [−π/2,
//! π/2]: ∫ w R cos φ · R dφ = 2 w R², counter-clockwise). The pitch radius is
//! R = P / (2 sin(π/N)); the arm a lies between the pitch polygon's
//! R cos(π/N) and R, as the tail's angle decides how a strand leaves its last
//! seated roller (polygonal action): the expected difference is taken at the
//! middle of that band, ±0.6 %. Along a sagging strand the link force grows
//! with height, T(y) = H + w (y − y_low) (a catenary with horizontal tension
//! H); on a parabola of sag s the mean over the strand's length is
//! H + (2/3) w s and the value at the tangent points H + w s, so a strand's
//! mean sits w s / 3 below its end values. The measured quantity is the
//! difference of the two segments' mean link forces:
//!
//!   T̄₂ − T̄₁ = (|M| − 2 w R²) / a + w (s₁ − s₂) / 3,
//!
//! with s₁, s₂ the strands' sags (the magnitudes of their transverse
//! displacements). Assumptions: the tail at rest (the real tooth form:
//! with the circular one the drives have no rest state), sags small against the span (parabola), rollers evenly spaced along
//! a strand. Tolerance 1 % of |M| / R (the polygon band's half-width within).

use crate::scene::Scene;
use crate::sim::Simulation;
use std::f64::consts::PI;

const SAG_6M: &str = include_str!("../../tests/data/conveyor_sag_6m.toml");

const SAG_10M: &str = include_str!("../../tests/data/conveyor_sag_10m.toml");

/// ANSI 80 pitch, m; 20 teeth; roller mass, kg; load on the tail, N·m.
const P: f64 = 0.0254;

const TEETH: f64 = 20.0;

const M_ROLLER: f64 = 0.066;

const LOAD: f64 = -100.0;

const G: f64 = 9.81;

/// The settled drive's two segments: mean link forces, transverse
/// displacements and free-link counts.
struct AtRest {
    mean_n: [f64; 2],
    transverse_m: [f64; 2],
    links: [usize; 2],
}

fn settle(toml: &str, gravity: bool) -> AtRest {
    // The real tooth form: with the circular profile the roller leaving the
    // tail is pulled beyond its seating arc and the drive has no rest state
    // (docs/model.md, “Pretension and static equilibrium”).
    let real = toml.replace(
        "gravity_m_s2 = [0.0, -9.81]",
        "gravity_m_s2 = [0.0, -9.81]\nprofile = \"real\"",
    );
    assert_ne!(real, toml, "the scene states its gravity");
    let toml = real.as_str();
    let text = if gravity {
        toml.to_owned()
    } else {
        let t = toml.replace("gravity_m_s2 = [0.0, -9.81]", "gravity_m_s2 = [0.0, 0.0]");
        assert_ne!(t, toml, "the scene states its gravity");
        t
    };
    let scene = Scene::from_toml(&text).expect("valid scene");
    let sim = Simulation::new(&scene).expect("equilibrium");
    let out = sim.forces.output();
    let segments = &sim.model.segments;
    let runs = segments.runs(
        &sim.model.sprockets,
        &sim.state.x,
        &sim.state.y,
        &out.touching,
    );
    let mut mean = [None; 2];
    segments.mean_forces(&runs, &out.link_force, &mut mean);
    let transverse = [0, 1].map(|k| segments.transverse(k, &runs, &sim.state.x, &sim.state.y));
    AtRest {
        mean_n: mean.map(|m| m.expect("a free strand")),
        transverse_m: transverse,
        links: [0, 1].map(|k| runs.links(k).count()),
    }
}

fn pitch_radius() -> f64 {
    P / (2.0 * (PI / TEETH).sin())
}

/// Checks the tail's moment balance on the segments' means (module docs).
fn check_balance(name: &str, r: &AtRest, g: f64) {
    let radius = pitch_radius();
    // Middle of the polygonal band R cos(π/N) … R of the lever arm, as 1/a.
    let inv_arm = 0.5 * (1.0 + 1.0 / (PI / TEETH).cos()) / radius;
    let w = M_ROLLER * g / P;
    let sag = r.transverse_m.map(f64::abs);
    let expected = (LOAD.abs() - 2.0 * w * radius * radius) * inv_arm + w * (sag[0] - sag[1]) / 3.0;
    let measured = r.mean_n[1] - r.mean_n[0];
    let tolerance = 0.01 * LOAD.abs() / radius;
    assert!(
        (measured - expected).abs() < tolerance,
        "{name}: T̄₂ − T̄₁ = {measured:.1} N (means {:.1} / {:.1} N, sags {:.4} / {:.4} m, \
         free links {:?}); the tail's balance needs {expected:.1} ± {tolerance:.1} N",
        r.mean_n[0],
        r.mean_n[1],
        sag[0],
        sag[1],
        r.links,
    );
}

/// Checks the sign and size of each sagging strand's transverse displacement.
///
/// Segment 1 runs in −x (left normal −y), segment 2 in +x (left normal +y):
/// a sag below the chord is positive on segment 1 and negative on segment 2.
/// Its size is the parabola's w L² / (8 H), with L the span between the
/// tangent points (the centre distance: equal sprockets) and H the horizontal
/// tension, H = T̄ − (2/3) w s from the strand's own mean (a fixed-point
/// iteration). Tolerance 3 %: the roller nearest the middle lies up to half a
/// pitch from it; the strand's stretch and the catenary's departure from the
/// parabola are far smaller.
fn check_sag(name: &str, r: &AtRest, span_m: f64) {
    let w = M_ROLLER * G / P;
    for (k, sign) in [(0, 1.0), (1, -1.0)] {
        let mut sag = 0.0;
        for _ in 0..50 {
            sag = w * span_m * span_m / (8.0 * (r.mean_n[k] - 2.0 / 3.0 * w * sag));
        }
        let measured = r.transverse_m[k];
        assert!(
            measured * sign > 0.0 && (measured.abs() - sag).abs() < 0.03 * sag,
            "{name}: segment {} transverse {measured:.4} m, a sag of {:.4} m expected",
            k + 1,
            sign * sag,
        );
    }
}

/// The reproducer: 6.35 m, gravity on. With links given to the nearest nominal
/// strand line, the slack upper strand, sagging below the lower strand's line,
/// was partly counted in the lower strand: the means differed by about 740 N
/// against the 1232 N the tail needs, and segment 2's transverse value was a
/// roller of the upper strand, 16 mm above the line.
#[test]
fn sagging_conveyor_6m_carries_the_tail_torque() {
    let r = settle(SAG_6M, true);
    check_balance("6.35 m", &r, G);
    check_sag("6.35 m", &r, 6.35);
}

#[test]
fn sagging_conveyor_10m_carries_the_tail_torque() {
    let r = settle(SAG_10M, true);
    check_balance("10 m", &r, G);
    check_sag("10 m", &r, 10.0066);
}

#[test]
fn conveyors_without_gravity_carry_the_tail_torque() {
    for (name, toml) in [("6.35 m", SAG_6M), ("10 m", SAG_10M)] {
        let r = settle(toml, false);
        check_balance(name, &r, 0.0);
        // Straight strands between seated rollers: a strand's ends sit on the
        // pitch polygons, at most R (1 − cos(π/N)) (the chordal rise, 1.0 mm)
        // inside the pitch circles' tangent line.
        // The strand's end roller is pressed into its seat by the strand's
        // tension T, inside the pitch circle by up to its penetration
        // δ = (T/K)^(1/n) (contact stiffness K = 2e8, n = 1.5), T at most
        // the largest mean strand force.
        let chordal = pitch_radius() * (1.0 - (PI / TEETH).cos());
        let tension = r.mean_n[0].max(r.mean_n[1]);
        let penetration = (tension / 2e8).powf(1.0 / 1.5);
        for t in r.transverse_m {
            assert!(
                t.abs() <= chordal + penetration,
                "{name}: transverse {t} m without gravity; the chordal rise is {chordal} m"
            );
        }
    }
}
