//! A worn chain (`chain.elongation_pct`; docs/model.md, "A worn chain"):
//! its static seating on the real tooth form against a closed form of the
//! ASA geometry, the slack it gains on fixed centres, its take-up by a
//! tensioner, and an arm drive lengthened by Newton alone.

use crate::scene::Scene;
use crate::sim::Simulation;

/// A 30T/30T ANSI 80 drive on the real profile, no gravity, the chain
/// `elongation_pct` worn, at 1 kN by `rule`: under "tensioner" the driven
/// sprocket is moved along the centre line to the pretension; under
/// "rest_length" it stands where 111 links fit. A 200 N·m load ramps in
/// over a second from the start, so at rest the strands carry the
/// pretension alone.
fn drive_30(elongation_pct: f64, rule: &str) -> String {
    format!(
        r#"
name = "worn 30/30 ANSI 80"
gravity_m_s2 = [0.0, 0.0]
profile = "real"

[chain]
designation = "ANSI 80"
rollers = 111
damping_n_s_m = 50.0
pretension_n = 1000.0
pretension_by = "{rule}"
elongation_pct = {elongation_pct}

[contact]
stiffness = 1e9
restitution = 0.5
min_approach_speed_m_s = 0.1

[[sprockets]]
name = "driver"
center_m = [0.0, 0.0]
teeth = 30
mass_kg = 2.0
inertia_kg_m2 = 0.02
wrap = "ccw"
role = "driver"
speed_rpm = 100.0

[[sprockets]]
name = "driven"
center_m = [{centre}, 0.0]
teeth = 30
mass_kg = 2.0
inertia_kg_m2 = 0.02
wrap = "ccw"
role = "{role}"
{adjust}
load_torque_n_m = 200.0
load_ramp_s = 1.0

[solver]
duration_s = 0.01
"#,
        role = if rule == "tensioner" {
            "tensioner"
        } else {
            "free"
        },
        centre = 1.0291,
        adjust = if rule == "tensioner" {
            "adjust_direction = [1.0, 0.0]"
        } else {
            ""
        },
    )
}

/// ASA B29.1 working curve of a sprocket of `z` teeth for a chain of pitch
/// `p` and roller diameter `dr` (docs/tooth-profile.md, “Constants”, in SI):
/// A = 35° + 60°/N, the working-curve centre c at (∓M, T) from the seating
/// centre, M = 0.8 Dr cos A, T = 0.8 Dr sin A, radius RE = 1.3025 Dr +
/// 0.0015 in; and the pitch radius P / (2 sin(π/N)).
struct Asa {
    m: f64,
    t: f64,
    re: f64,
    rs: f64,
}

fn asa(z: f64, p: f64, dr: f64) -> Asa {
    let a = (35.0 + 60.0 / z).to_radians();
    Asa {
        m: 0.8 * dr * a.cos(),
        t: 0.8 * dr * a.sin(),
        re: 1.3025 * dr + 0.0015 * 0.0254,
        rs: p / (2.0 * (std::f64::consts::PI / z).sin()),
    }
}

/// The intersection of the circles (a, ra) and (b, rb) nearer `near`.
fn meet(a: [f64; 2], ra: f64, b: [f64; 2], rb: f64, near: [f64; 2]) -> [f64; 2] {
    let d = [b[0] - a[0], b[1] - a[1]];
    let dist = d[0].hypot(d[1]);
    let along = (ra * ra - rb * rb + dist * dist) / (2.0 * dist);
    let h = (ra * ra - along * along).max(0.0).sqrt();
    let u = [d[0] / dist, d[1] / dist];
    let foot = [a[0] + along * u[0], a[1] + along * u[1]];
    let p1 = [foot[0] - h * u[1], foot[1] + h * u[0]];
    let p2 = [foot[0] + h * u[1], foot[1] - h * u[0]];
    let dist_to = |p: [f64; 2]| (p[0] - near[0]).hypot(p[1] - near[1]);
    if dist_to(p1) < dist_to(p2) { p1 } else { p2 }
}

#[test]
fn a_worn_chains_rollers_seat_further_out_as_the_asa_working_curve_and_statics_give() {
    // Closed form (docs/model.md, "A worn chain"). On the driven sprocket
    // at rest (the pretension alone) the strand pulls each roller of the
    // wrap back towards the roller before it; a worn chain's rollers, P (1 + e) apart where the
    // gaps are P apart, cannot all sit in their seats: from the first roller
    // of the wrap on, each next one lies on the working curve of its gap on
    // the side of the roller before, i.e. on the circle of radius
    // RE − R_r + δ about that curve's centre c, and at the link's length
    // l₀ + F/K from the roller before. Each roller's balance, with the link
    // forces along the links and the tooth's push N along (c − r)/|c − r|,
    // gives the next link's force and N from the one before: two equations,
    // two unknowns. δ = (N / K_g)^(2/3) (the contact law's spring) and the
    // links' stretch F/K are put in by three fixed-point passes. From the
    // first roller of the wrap (the run's own, and its link force), this
    // predicts every further roller on a working curve: its distance from
    // the sprocket's centre (growing round the wrap) and its share N / F₀.
    let scene = Scene::from_toml(&drive_30(2.0, "tensioner")).expect("valid");
    let sim = Simulation::new(&scene).expect("equilibrium");
    let chain = scene.chain();
    let (p, dr) = (chain.pitch_m, 2.0 * chain.roller_radius_m);
    let geo = asa(30.0, p, dr);
    let (k_link, k_contact) = (chain.stiffness_n_m, scene.contact().stiffness);
    let rest = sim.model.rest_length_m;
    approx::assert_relative_eq!(rest, p * 1.02, max_relative = 1e-12);
    let sp = &sim.model.sprockets[1];
    let centre = sp.center_m;
    let theta = sim.state.theta[1];
    let pitch_angle = std::f64::consts::TAU / 30.0;
    let n = sim.state.rollers();
    let at = |i: usize| [sim.state.x[i % n], sim.state.y[i % n]];
    let radius = |q: [f64; 2]| (q[0] - centre[0]).hypot(q[1] - centre[1]);
    let gap_of = |q: [f64; 2]| ((q[1] - centre[1]).atan2(q[0] - centre[0]) - theta) / pitch_angle;
    let out = sim.forces.output();
    // The wrap's first roller from the tight strand (segment 1 arrives here).
    let touching: Vec<usize> = (0..n)
        .filter(|&i| out.touching[i] && radius(at(i)) < sp.reach_m)
        .collect();
    let first = *touching
        .iter()
        .find(|&&i| !touching.contains(&((i + n - 1) % n)))
        .expect("a wrap");
    // Rollers in gaps: their polar angles are whole gaps from θ to within
    // the play of a worn chain (a quarter pitch).
    let gap = |i: usize| gap_of(at(i)).round();
    assert!((gap_of(at(first)) - gap(first)).abs() < 0.25);
    // Up to eight rollers round the wrap from the first.
    let count = 8;
    let mut pos: Vec<[f64; 2]> = (0..=count).map(|k| at(first + k)).collect();
    let mut force = vec![out.link_force[first]; count + 1];
    let mut push = vec![0.0; count + 1];
    let gap_frame = |g: f64| {
        let psi = theta + g * pitch_angle;
        let (s, c) = psi.sin_cos();
        let o = [centre[0] + geo.rs * c, centre[1] + geo.rs * s];
        // ξ clockwise tangential, η radially outward.
        (o, [s, -c], [c, s])
    };
    let flank_centre = |g: f64, towards: [f64; 2]| {
        let (o, xi, eta) = gap_frame(g);
        let side = ((towards[0] - o[0]) * xi[0] + (towards[1] - o[1]) * xi[1]).signum();
        // The flank on side σ of the gap is the arc about (−σ M, T).
        [
            o[0] - side * geo.m * xi[0] + geo.t * eta[0],
            o[1] - side * geo.m * xi[1] + geo.t * eta[1],
        ]
    };
    for _pass in 0..3 {
        for k in 1..=count {
            let g = gap(first + k);
            let c = flank_centre(g, pos[k - 1]);
            let depth = (push[k] / k_contact).max(0.0).powf(2.0 / 3.0);
            let link = rest + force[k - 1] / k_link;
            let (o, _, _) = gap_frame(g);
            pos[k] = meet(pos[k - 1], link, c, geo.re - dr / 2.0 + depth, o);
        }
        // The balances, roller by roller: F_k u_back + F_{k+1} u_fwd + N n = 0.
        for k in 1..count {
            let c = flank_centre(gap(first + k), pos[k - 1]);
            let unit = |a: [f64; 2], b: [f64; 2]| {
                let d = [b[0] - a[0], b[1] - a[1]];
                let l = d[0].hypot(d[1]);
                [d[0] / l, d[1] / l]
            };
            let (back, fwd, nrm) = (
                unit(pos[k], pos[k - 1]),
                unit(pos[k], pos[k + 1]),
                unit(pos[k], c),
            );
            let rhs = [-force[k - 1] * back[0], -force[k - 1] * back[1]];
            let det = fwd[0] * nrm[1] - fwd[1] * nrm[0];
            force[k] = (rhs[0] * nrm[1] - rhs[1] * nrm[0]) / det;
            push[k] = (fwd[0] * rhs[1] - fwd[1] * rhs[0]) / det;
        }
    }
    let f0 = out.link_force[first];
    for k in 1..count {
        let i = (first + k) % n;
        let predicted = radius(pos[k]);
        let simulated = radius(at(i));
        assert!(
            (predicted - simulated).abs() < 5e-6,
            "roller {k} of the wrap: radius {simulated} m, closed form {predicted} m"
        );
        let share = out.contact_force[i] / f0;
        assert!(
            (share - push[k] / f0).abs() < 0.01,
            "roller {k}: load share {share}, closed form {}",
            push[k] / f0
        );
    }
    // The limit of the climb, in closed form: rollers that have climbed as
    // far as they go each sit the same way in their gaps, so they lie on one
    // circle, successive ones 2π/z apart round it and P (1 + e) apart: the
    // chord 2 R sin(π/z) = P (1 + e) gives R∞ = R_p (1 + e). It lies on the
    // working curve while e is below where that curve ends (2.56 % for 30
    // teeth, docs/model.md), so no roller of the wrap lies further out than
    // R∞ (pressed into its flank, a little less), and the climb reaches a
    // good part of e R_p before the wrap ends.
    let r_inf = geo.rs * 1.02;
    let radii: Vec<f64> = touching.iter().map(|&i| radius(at(i))).collect();
    let highest = radii.iter().copied().fold(0.0, f64::max);
    assert!(
        highest <= r_inf + 1e-6,
        "highest roller at {highest} m, beyond R∞ = {r_inf} m: {radii:?}"
    );
    assert!(
        highest - geo.rs > 0.5 * (r_inf - geo.rs),
        "highest roller {highest} m climbs less than half of e R_p above {} m: {radii:?}",
        geo.rs
    );
}

#[test]
fn a_worn_chain_on_fixed_centres_gains_its_slack_and_loses_tension() {
    // Fixed centres (the rest-length rule): the new chain settles at the
    // pretension with rest length l₀; worn by e, its links are l₀ (1 + e)
    // and the chain N l₀ e longer, which the summary reports; the static
    // tension falls.
    let new = Simulation::new(&Scene::from_toml(&drive_30(0.0, "rest_length")).expect("valid"))
        .expect("equilibrium");
    let scene = Scene::from_toml(&drive_30(0.5, "rest_length")).expect("valid");
    let worn = Simulation::new(&scene).expect("equilibrium");
    approx::assert_relative_eq!(
        worn.model.rest_length_m,
        new.model.rest_length_m * 1.005,
        max_relative = 1e-12
    );
    assert!(
        worn.equilibrium.tension_n < 0.5 * new.equilibrium.tension_n,
        "{} N against {} N new",
        worn.equilibrium.tension_n,
        new.equilibrium.tension_n
    );
}

#[test]
fn a_tensioner_takes_a_worn_chain_up_to_the_pretension() {
    // The tensioner rule: the sprocket moves on until the worn chain has the
    // pretension again (within the scene's 0.1 %), further out than for the
    // new chain: at least by the strands' share of the gained length, half
    // of it for two strands along the centre line (80 % of that allowed:
    // the strands' ends ride up with the wraps).
    let new = Simulation::new(&Scene::from_toml(&drive_30(0.0, "tensioner")).expect("valid"))
        .expect("equilibrium");
    let worn = Simulation::new(&Scene::from_toml(&drive_30(2.0, "tensioner")).expect("valid"))
        .expect("equilibrium");
    approx::assert_relative_eq!(worn.equilibrium.tension_n, 1000.0, max_relative = 1e-3);
    let moved = worn.scene.sprockets()[1].center_m[0] - new.scene.sprockets()[1].center_m[0];
    let strand_links = 2.0 * 40.0;
    let at_least = 0.8 * 0.5 * strand_links * 0.02 * 0.0254;
    assert!(moved > at_least, "moved {moved} m, at least {at_least} m");
}

#[test]
fn elongation_out_of_range_is_refused_with_its_path() {
    for bad in ["-1.0", "40.0"] {
        let text = drive_30(0.0, "tensioner")
            .replace("elongation_pct = 0", &format!("elongation_pct = {bad}"));
        let msg = Scene::from_toml(&text).expect_err(bad).to_string();
        assert!(msg.contains("chain.elongation_pct"), "{bad}: {msg}");
    }
}

/// Regression: each lengthening step of a worn arm drive lengthened every
/// link on the rest state before, compressing the chain by K times the step
/// (about 100 N against a static tension of 10–17 N): Newton met an
/// indefinite tangent, stalled in 40 iterations at steps 6, 8, 9 and 10,
/// and the relaxation ran 0.4–0.6 s each (2.1–2.4 s in all). Started
/// from the two rest states before, extrapolated, Newton settles every
/// step: no relaxation is started (the new chain's settling needs none
/// either).
///
/// `user_timing_06b_arm.toml` worn 0.5 %, its hydraulic tensioner at rest
/// held at the 3 bar supply: the plunger pushes p A + max(0, F₀ − k x) with
/// A = π/4 · (14 mm)² = 1.5394 · 10⁻⁴ m², F₀ = 15 N, k = 2000 N/m, x its
/// travel (46.18 + max(0, 15 − 2000 x) N: 46.18 N at rest beyond the
/// return spring's free length, 7.5 mm), and the arm's moment is balanced.
#[test]
fn a_worn_arm_drive_is_lengthened_by_newton_alone() {
    let scene = timing_drive_worn_half_a_percent();
    let before = crate::sim::statics::RELAXATIONS.with(std::cell::Cell::get);
    let sim = Simulation::new(&scene).expect("equilibrium");
    let relaxations = crate::sim::statics::RELAXATIONS.with(std::cell::Cell::get) - before;
    assert_eq!(relaxations, 0, "{:?}", sim.equilibrium);
    assert!(
        sim.equilibrium.force_residual <= 1e-7,
        "{:?}",
        sim.equilibrium
    );
    let arm = sim.forces.output().tensioners[0];
    let area_m2 = std::f64::consts::FRAC_PI_4 * 0.014f64.powi(2);
    let push_n = 3e5 * area_m2 + (15.0 - 2000.0 * arm.travel_m).max(0.0);
    approx::assert_relative_eq!(arm.plunger_force_n, push_n, max_relative = 1e-6);
    // The arm's moment over its reach, against the pretension scale.
    let reach_m = 0.25_f64.max((0.3007f64 - 0.09).hypot(0.163 - 0.33));
    let moment = sim.forces.output().body_force[0];
    assert!(
        moment.abs() / reach_m <= 1e-7 * 150.0,
        "arm moment {moment} N·m out of balance"
    );
}

/// What a setup is solving is seen from another thread (the command line's
/// note of a slow setup reads it there) and is gone once the setup has
/// ended, however far it got.
#[test]
fn a_setups_stage_is_seen_from_another_thread_until_it_ends() {
    let scene = timing_drive_worn_half_a_percent();
    let (seen, watch) = std::sync::mpsc::channel();
    let (done, finished) = std::sync::mpsc::channel::<()>();
    let setting_up = std::thread::spawn(move || {
        super::setup_stage::note_stage(|| "a phrase".to_owned());
        // Seen from the test's thread before the setup starts.
        seen.send(()).expect("watched");
        finished.recv().expect("read");
        let sim = Simulation::new(&scene).expect("equilibrium");
        (sim.equilibrium.tension_n, std::thread::current().id())
    });
    watch.recv().expect("noted");
    let id = setting_up.thread().id();
    assert_eq!(super::setup_stage::stage(id).as_deref(), Some("a phrase"));
    done.send(()).expect("go");
    let (tension_n, ended_on) = setting_up.join().expect("set up");
    assert!(tension_n > 0.0);
    assert_eq!(ended_on, id);
    assert_eq!(super::setup_stage::stage(id), None, "left after the setup");
}

/// `user_timing_06b_arm.toml` with its chain worn 0.5 %.
fn timing_drive_worn_half_a_percent() -> Scene {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/user_timing_06b_arm.toml"
    );
    let text = std::fs::read_to_string(path).expect("scene").replace(
        "\npretension_by = \"tensioner_preload\"\n",
        "\npretension_by = \"tensioner_preload\"\nelongation_pct = 0.5\n",
    );
    Scene::from_toml(&text).expect("valid")
}

/// `assets/timing-drive.toml` with its chain worn `pct` %.
fn timing_drive_worn(pct: f64) -> Scene {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/timing-drive.toml");
    let text = std::fs::read_to_string(path).expect("scene").replace(
        "\npretension_by = \"tensioner_preload\"\n",
        &format!("\npretension_by = \"tensioner_preload\"\nelongation_pct = {pct}\n"),
    );
    Scene::from_toml(&text).expect("valid")
}

/// The timing drive worn 0.3 %: its 112 links of 12.7 mm gain
/// N P e = 112 × 12.7 mm × 0.003 = 4.267 mm, more than the 2.46 mm of
/// chain its arm's shoe takes up from stop to stop (`chaindrive check
/// assets/timing-drive.toml`), so the plunger ends on its upper stop
/// (30 mm) and the chain hangs slack, far below the new chain's 471 N:
/// said in the rest state's warnings with both lengths. The 06B arm drive
/// worn 0.5 % still holds its chain (20.5 N, the plunger inside its
/// travel): no such warning.
#[test]
fn a_worn_chain_longer_than_its_arm_takes_up_is_warned_of() {
    let sim = Simulation::new(&timing_drive_worn(0.3)).expect("equilibrium");
    let slack = sim.equilibrium.worn_slack.as_ref().expect("warned");
    approx::assert_relative_eq!(slack.gain_m, 112.0 * 0.0127 * 0.003, max_relative = 1e-12);
    let take_up_m = slack.take_up_m.expect("the arm's take-up");
    assert!((take_up_m - 2.46e-3).abs() < 0.01e-3, "{take_up_m}");
    let plunger = &sim.forces.output().tensioners[0];
    assert!(plunger.travel_m >= 0.030 - 1e-6, "{}", plunger.travel_m);
    assert!(
        sim.equilibrium.tension_n < 10.0,
        "{}",
        sim.equilibrium.tension_n
    );
    let warned = sim.equilibrium.warnings();
    assert!(
        warned
            .iter()
            .any(|w| w.contains("hangs slack") && w.contains("4.27 mm") && w.contains("2.46 mm")),
        "{warned:?}"
    );
    let holding = Simulation::new(&timing_drive_worn_half_a_percent()).expect("equilibrium");
    assert!(holding.equilibrium.worn_slack.is_none());
    assert!(holding.equilibrium.tension_n > 10.0);
}
