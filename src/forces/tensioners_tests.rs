//! Tensioner arms and their tensioners (docs/model.md, “Tensioner arms”):
//! the hydraulic chamber's leak-down and refill against closed forms, the
//! spring-damper arm's static moment balance from the links' forces, the
//! timing drive's short run, and bad input.

use crate::forces::{ForceElement, Forces, TensionerArm};
use crate::model::{DriveModel, DriveState};
use crate::scene::Scene;
use crate::sim::Simulation;
use std::any::Any;
use std::f64::consts::PI;

const FLAT: &str = include_str!("../../tests/data/flat_20_40_1000rpm.toml");

const TIMING: &str = include_str!("../../assets/timing-drive.toml");

/// The hydraulic tensioner of the chamber tests: d = 14 mm, c = 15 µm,
/// L = 15 mm, η = 0.01 Pa·s, no air, a 1 mm valve, no return spring (so the
/// plunger's push is p A alone), travel ±50 mm.
const HYDRAULIC: &str = r#"
[tensioners.hydraulic]
bore_m = 0.014
clearance_m = 15e-6
leak_length_m = 0.015
viscosity_pa_s = 0.010
bulk_modulus_pa = 1.5e9
air_fraction = 0.0
oil_density_kg_m3 = 850.0
chamber_volume_m3 = 1e-5
supply_pressure_pa = 3e5
cracking_pressure_pa = 1.5e4
valve_diameter_m = 1e-3
valve_cd = 0.7
spring_preload_n = 0.0
spring_stiffness_n_m = 0.0
min_travel_m = -0.05
max_travel_m = 0.05
"#;

/// An arm far from the chain (its shoe touches nothing): pivot (1, 1), the
/// tensioner pushing at (1.1, 1) along +y, a lever of ℓ = 0.1 m.
const FAR_ARM: &str = r#"
[[tensioners]]
name = "test arm"
pivot_m = [1.0, 1.0]
inertia_kg_m2 = 1e-3
shoe_center_m = [1.05, 1.2]
shoe_radius_m = 0.05
shoe_start_deg = 60.0
shoe_end_deg = 120.0
point_m = [1.1, 1.0]
direction = [0.0, 1.0]
"#;

const LEVER_M: f64 = 0.1;

const AREA_M2: f64 = PI * 0.014 * 0.014 / 4.0;

/// A moment M₀ − c u on the arm (body 0): a load on the plunger of the
/// test's choosing.
#[derive(Clone, Debug)]
struct ArmLoad {
    moment_n_m: f64,
    damping_n_m_s: f64,
}

impl ForceElement for ArmLoad {
    fn name(&self) -> &'static str {
        "arm load"
    }

    fn evaluate(&mut self, _model: &DriveModel, state: &DriveState, out: &mut Forces) {
        out.body_force[0] += self.moment_n_m - self.damping_n_m_s * state.u[0];
    }

    fn clone_box(&self) -> Box<dyn ForceElement> {
        Box::new(self.clone())
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}

fn far_hydraulic_drive() -> Simulation {
    let text = format!("{FLAT}\n{FAR_ARM}\n{HYDRAULIC}");
    let scene = Scene::from_toml(&text).expect("a valid scene");
    Simulation::new(&scene).expect("the drive settles")
}

fn arm(sim: &Simulation) -> &TensionerArm {
    sim.forces
        .element::<TensionerArm>()
        .expect("the drive has a tensioner arm")
}

/// Travel x at the present state, from the arm's angle q: the point
/// a₀ − P = (ℓ, 0) turned by q, along ê = (0, 1): x = ℓ sin q.
fn travel(sim: &Simulation) -> f64 {
    LEVER_M * sim.state.q[0].sin()
}

/// Puts the arm at angle `q` at rest with the chamber at `p_pa` and
/// evaluates the forces there.
fn start_at(sim: &mut Simulation, q: f64, p_pa: f64) {
    sim.state.q[0] = q;
    sim.state.u[0] = 0.0;
    sim.state.z[0] = arm(sim)
        .chamber_state_for(p_pa, q)
        .expect("a hydraulic tensioner");
    sim.forces.evaluate(&sim.model, &sim.state);
}

fn run_for(sim: &mut Simulation, seconds: f64) {
    let dt = sim.scene.solver().dt_s;
    let steps = (seconds / dt).round() as usize;
    for _ in 0..steps {
        sim.step(dt).expect("the step succeeds");
    }
}

#[test]
fn hydraulic_leak_down_speed_is_the_gap_leak_over_the_plunger_area() {
    // Closed form: with the check valve closed (p far above p_s) and a
    // constant force F pressing the plunger in, the chamber settles at
    // Δp = F / A (no return spring) and the plunger retracts at the speed
    // that the annular gap's leak carries away:
    //   v = −Q_leak / A = −π d c³ Δp / (12 η L A).
    // Assumptions: the gap's laminar flow (c ≪ d), the chamber's
    // compressibility transient (period ~0.4 ms here) averaged out over
    // 0.1 s, the lever's change over the 80 µm travelled negligible.
    let force_n = 200.0;
    let dp = force_n / AREA_M2;
    let leak = PI * 0.014 * 15e-6_f64.powi(3) * dp / (12.0 * 0.010 * 0.015);
    let expected = -leak / AREA_M2;
    let mut sim = far_hydraulic_drive();
    sim.add_force_element(Box::new(ArmLoad {
        moment_n_m: -force_n * LEVER_M,
        damping_n_m_s: 0.0,
    }));
    start_at(&mut sim, 0.0, dp);
    run_for(&mut sim, 0.01);
    let (x0, t0) = (travel(&sim), sim.state.t_s);
    run_for(&mut sim, 0.1);
    let speed = (travel(&sim) - x0) / (sim.state.t_s - t0);
    assert!(!arm(&sim).reading().valve_open, "the valve stays closed");
    assert!(
        (speed / expected - 1.0).abs() < 0.02,
        "leak-down speed {speed:e} m/s, closed form {expected:e} m/s"
    );
}

#[test]
fn check_valve_refill_flow_matches_the_orifice_formula_as_the_plunger_extends() {
    // The arm is pulled so that the plunger extends against a viscous load
    // (M = M₀ − c u), drawing oil in through the check valve. Once the
    // speed is steady the flow in equals the volume swept plus the leak:
    //   Q_in = A v + π d c³ p / (12 η L),
    // with v from the arm's speed (v = ℓ u) and p the chamber's pressure,
    // and the orifice formula gives it from the pressure alone:
    //   Q_in = C_d (π d_v²/4) √(2 (p_s − p_crack − p) / ρ).
    // Assumptions: turbulent orifice flow (Δp far above the 10 kPa laminar
    // joint: about 0.1 MPa here), a steady state (the chamber's time
    // constant is well below a millisecond), 5 % for what is left of it.
    let mut sim = far_hydraulic_drive();
    sim.add_force_element(Box::new(ArmLoad {
        moment_n_m: 2.0,
        damping_n_m_s: 10.0,
    }));
    start_at(&mut sim, -0.3, 3e5);
    run_for(&mut sim, 0.02);
    let reading = *arm(&sim).reading();
    let p = reading.pressure_pa;
    // v = d(ℓ sin q)/dt = ℓ cos q · u.
    let v = LEVER_M * sim.state.q[0].cos() * sim.state.u[0];
    let swept = AREA_M2 * v + PI * 0.014 * 15e-6_f64.powi(3) * p / (12.0 * 0.010 * 0.015);
    let orifice = 0.7 * PI * 1e-3 * 1e-3 / 4.0 * (2.0 * (3e5 - 1.5e4 - p) / 850.0).sqrt();
    assert!(reading.valve_open, "the valve is open while refilling");
    assert!(
        v > 0.0 && travel(&sim) < 0.05,
        "the plunger extends: {v} m/s"
    );
    assert!(
        (3e5 - 1.5e4 - p) > 5e4,
        "the orifice runs turbulent: Δp = {} Pa",
        3e5 - 1.5e4 - p
    );
    assert!(
        (swept / orifice - 1.0).abs() < 0.05,
        "flow swept {swept:e} m³/s, orifice formula {orifice:e} m³/s"
    );
}

/// The spring-damper arm above the flat drive's upper strand: a 200 mm
/// shoe held 1 mm above the strand at the scene's pose, the spring pushing
/// down at 200 mm from the pivot.
const SPRING_ARM: &str = r#"
[[tensioners]]
name = "upper arm"
pivot_m = [0.05, 0.2]
inertia_kg_m2 = 2e-3
shoe_center_m = [0.215754, 0.264404]
shoe_radius_m = 0.2
shoe_start_deg = -111.12
shoe_end_deg = -81.12
point_m = [0.25, 0.2]
direction = [0.0, -1.0]

[tensioners.spring]
preload_n = 10.0
stiffness_n_m = 500.0
damping_n_s_m = 20.0
min_travel_m = -0.01
max_travel_m = 0.03
"#;

#[test]
fn spring_arm_static_angle_balances_moments_about_the_pivot() {
    // At rest the chain's moment on the arm about the pivot balances the
    // spring's: M_chain + F(x) ℓ(q) = 0, with F = F₀ − k x (between the
    // stops) and, for the pivot P, the point a(q) = P + R(q)(a₀ − P) and
    // the line's direction ê,
    //   x = (a(q) − a₀)·ê,  ℓ = (a(q) − P) × ê.
    // The chain's moment comes from the links alone: a roller on the shoe
    // is at rest, so the shoe pushes it with minus its links' forces and
    // weight, along the normal through its centre (no friction), whose
    // moment about P is (c − P) × (F_links + m g). Assumption: the drive at
    // static equilibrium (its residual is 1e-5 of the pretension); 1 %.
    let text = format!("{FLAT}\n{SPRING_ARM}");
    let scene = Scene::from_toml(&text).expect("a valid scene");
    let sim = Simulation::new(&scene).expect("the drive settles");
    let q = sim.state.q[0];
    let pivot = [0.05, 0.2];
    let a0 = [0.25, 0.2];
    let e = [0.0, -1.0];
    let (s, c) = q.sin_cos();
    let r = [c * (a0[0] - pivot[0]), s * (a0[0] - pivot[0])];
    let x = (pivot[0] + r[0] - a0[0]) * e[0] + (pivot[1] + r[1] - a0[1]) * e[1];
    let lever = r[0] * e[1] - r[1] * e[0];
    let spring_moment = (10.0 - 500.0 * x) * lever;
    // Rollers on the shoe: within R + R_r (plus a micrometre) of its centre.
    let centre = [
        pivot[0] + c * (0.215754 - pivot[0]) - s * (0.264404 - pivot[1]),
        pivot[1] + s * (0.215754 - pivot[0]) + c * (0.264404 - pivot[1]),
    ];
    let out = sim.forces.output();
    let n = sim.state.rollers();
    let (m, g) = (0.00775, -9.81);
    let mut chain_moment = 0.0;
    let mut on_shoe = 0;
    for i in 0..n {
        let (x_i, y_i) = (sim.state.x[i], sim.state.y[i]);
        if (x_i - centre[0]).hypot(y_i - centre[1]) > 0.2 + 0.00396 + 1e-6 {
            continue;
        }
        on_shoe += 1;
        let pull = |j: usize, tension: f64| {
            let (dx, dy) = (sim.state.x[j] - x_i, sim.state.y[j] - y_i);
            let l = dx.hypot(dy);
            [tension * dx / l, tension * dy / l]
        };
        let next = pull((i + 1) % n, out.link_force[i]);
        let prev = pull((i + n - 1) % n, out.link_force[(i + n - 1) % n]);
        let f = [next[0] + prev[0], next[1] + prev[1] + m * g];
        // The shoe pushes with −f; the roller pushes the shoe with +f.
        chain_moment += (x_i - pivot[0]) * f[1] - (y_i - pivot[1]) * f[0];
    }
    assert!(
        on_shoe >= 2,
        "the strand rides on the shoe: {on_shoe} rollers"
    );
    assert!(
        x > 0.0 && x < 0.03,
        "the spring between its stops: x = {x} m"
    );
    assert!(
        ((chain_moment + spring_moment) / spring_moment).abs() < 0.01,
        "chain moment {chain_moment} N·m, spring moment {spring_moment} N·m"
    );
}

fn timing_scene() -> Scene {
    Scene::from_toml(TIMING).expect("the timing drive is valid")
}

#[test]
fn timing_drive_runs_and_its_tensioner_works() {
    // A short run of the timing drive (the README's 2 s run is measured, not
    // tested): no blow-up, the arm and plunger move, the pressure stays
    // finite and above the cavitation floor, the plunger inside its stops.
    let mut sim = Simulation::new(&timing_scene()).expect("the timing drive settles");
    let eq = arm(&sim).reading().plunger_force_n;
    assert!(eq > 0.0, "the tensioner pushes at rest: {eq} N");
    run_for(&mut sim, 0.02);
    let r = *arm(&sim).reading();
    assert!(r.pressure_pa.is_finite() && r.pressure_pa > -101_325.0);
    assert!(r.travel_m > -0.0045 && r.travel_m < 0.0305, "{r:?}");
    assert!(r.shoe_force_n > 0.0, "the strand rides on the shoe: {r:?}");
}

fn errors_of(text: &str) -> String {
    match Scene::from_toml(text) {
        Ok(_) => panic!("the scene should be rejected"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn a_tensioner_line_that_misses_the_arm_is_rejected_with_its_path() {
    let text = TIMING.replace("point_m = [0.180131, 0.227981]", "point_m = [0.9, 0.9]");
    let e = errors_of(&text);
    assert!(
        e.contains("tensioners[0].point_m") && e.contains("misses the arm"),
        "{e}"
    );
}

#[test]
fn a_line_through_the_pivot_is_rejected() {
    // The line from point_m along direction passes through the pivot.
    let text = format!("{FLAT}\n{FAR_ARM}\n{HYDRAULIC}")
        .replace("direction = [0.0, 1.0]", "direction = [-1.0, 0.0]");
    let e = errors_of(&text);
    assert!(e.contains("tensioners[0].direction"), "{e}");
}

#[test]
fn negative_and_nan_hydraulic_fields_are_rejected_with_their_paths() {
    let text = TIMING
        .replace("clearance_m = 15e-6", "clearance_m = -15e-6")
        .replace("viscosity_pa_s = 0.010", "viscosity_pa_s = nan")
        .replace("air_fraction = 0.02", "air_fraction = 1.5");
    let e = errors_of(&text);
    for path in [
        "tensioners[0].hydraulic.clearance_m",
        "tensioners[0].hydraulic.viscosity_pa_s",
        "tensioners[0].hydraulic.air_fraction",
    ] {
        assert!(e.contains(path), "{path} missing from:\n{e}");
    }
}

#[test]
fn a_shoe_arc_of_half_a_turn_or_more_is_rejected() {
    let text = TIMING.replace("shoe_end_deg = 174.37", "shoe_end_deg = 340.0");
    let e = errors_of(&text);
    assert!(e.contains("tensioners[0].shoe_end_deg"), "{e}");
}

#[test]
fn a_tensioner_with_both_kinds_or_none_is_rejected() {
    let none = format!("{FLAT}\n{FAR_ARM}");
    assert!(errors_of(&none).contains("tensioners[0]: has no tensioner"));
    let both = format!(
        "{FLAT}\n{FAR_ARM}\n{HYDRAULIC}\n[tensioners.spring]\npreload_n = 1.0\nstiffness_n_m = 1.0\nmin_travel_m = 0.0\nmax_travel_m = 0.0\n"
    );
    assert!(errors_of(&both).contains("exactly one"));
}

#[test]
fn a_chamber_emptied_inside_the_travel_is_rejected() {
    let text = format!("{FLAT}\n{FAR_ARM}\n{HYDRAULIC}")
        .replace("chamber_volume_m3 = 1e-5", "chamber_volume_m3 = 1e-6");
    let e = errors_of(&text);
    assert!(
        e.contains("tensioners[0].hydraulic.chamber_volume_m3"),
        "{e}"
    );
}

#[test]
fn tensioner_preload_without_tensioners_is_rejected() {
    let text = FLAT.replace(
        "pretension_n = 300.0",
        "pretension_n = 300.0\npretension_by = \"tensioner_preload\"",
    );
    let e = errors_of(&text);
    assert!(e.contains("chain.pretension_by"), "{e}");
}

/// `TensionerSignal`, mirrored for decoding (field numbers in declaration
/// order; the arm number read as any varint).
#[cfg(feature = "record")]
#[derive(Clone, PartialEq, prost::Message)]
struct TensionerPb {
    #[prost(uint64, tag = "1")]
    tensioner: u64,
    #[prost(double, tag = "2")]
    travel_m: f64,
    #[prost(double, tag = "3")]
    speed_m_s: f64,
    #[prost(double, tag = "4")]
    pressure_pa: f64,
    #[prost(bool, tag = "5")]
    valve_open: bool,
    #[prost(double, tag = "6")]
    arm_angle_rad: f64,
    #[prost(double, tag = "7")]
    shoe_force_n: f64,
    #[prost(double, tag = "8")]
    plunger_force_n: f64,
}

/// `TensionerSignals`.
#[cfg(feature = "record")]
#[derive(Clone, PartialEq, prost::Message)]
struct TensionersPb {
    #[prost(double, tag = "1")]
    t_s: f64,
    #[prost(message, repeated, tag = "2")]
    tensioners: Vec<TensionerPb>,
}

/// A recording of the timing drive holds a `/tensioners` message at every
/// sample, the arm drawn in `/scene/static` in its own frame, and that frame
/// in `/tf`; a drive without arms gets no `/tensioners` channel.
///
/// Read back, every sample's travel agrees with its arm angle by the
/// kinematics of the scene's arm (pivot P, pushed point a₀, line ê):
/// x = (R(q)(a₀ − P) − (a₀ − P))·ê (ê made unit), to 1e-12 m; the pressure is finite
/// and above the cavitation floor, the shoe carries the strand.
#[cfg(feature = "record")]
#[test]
fn tensioners_are_recorded_drawn_and_read_back() {
    use crate::record::{Channels, RecordOptions, Recorder, RunEnd};
    use crate::sim::SampleRate;
    use prost::Message as _;
    use std::io::Cursor;
    let record = |scene: &Scene| {
        let mut sim = Simulation::new(scene).expect("a static equilibrium");
        let sampling = SampleRate::new(1000.0, scene.solver().dt_s).expect("a sample step");
        let options = RecordOptions {
            channels: Channels::all(),
            // The scene attached, as `run --record` does, so that
            // `record::read` can read the file back.
            scene_file: scene
                .source_toml()
                .map(|t| ("timing-drive.toml".to_owned(), t.as_bytes().to_vec())),
            rate_hz: sampling.rate_hz,
        };
        let mut recorder =
            Recorder::new(Cursor::new(Vec::new()), scene, &options).expect("a recorder");
        sim.run(0.01, sampling.every, &mut recorder, None)
            .expect("no blow-up");
        let bytes = recorder
            .finish(RunEnd::Completed)
            .expect("finished")
            .into_inner();
        let mut samples = Vec::new();
        let (mut drawn, mut framed) = (false, false);
        for m in mcap::MessageStream::new(&bytes).expect("an MCAP file") {
            let m = m.expect("a message");
            match m.channel.topic.as_str() {
                "/tensioners" => {
                    samples.push(TensionersPb::decode(&*m.data).expect("a TensionerSignals"))
                }
                // Entity ids, frame names and labels are plain strings.
                "/scene/static" => drawn |= m.data.windows(10).any(|w| w == b"tensioner1"),
                "/tf" => framed |= m.data.windows(10).any(|w| w == b"tensioner1"),
                _ => {}
            }
        }
        // The same file read back by the library.
        let read = crate::record::read::read_recording_bytes("timing.mcap", &bytes)
            .unwrap_or_else(|e| panic!("a readable recording: {e}"));
        (samples, drawn, framed, read.tensioners)
    };
    let scene = timing_scene();
    let (samples, drawn, framed, read) = record(&scene);
    // t = 0 and every 1 ms to 10 ms: 11 samples.
    assert_eq!(samples.len(), 11);
    // `record::read` gives back every message as written, field by field.
    assert_eq!(read.len(), samples.len());
    for (r, s) in read.iter().zip(&samples) {
        assert_eq!(r.t_s, s.t_s);
        assert_eq!(r.tensioners.len(), 1);
        let (r, s) = (&r.tensioners[0], &s.tensioners[0]);
        assert_eq!(u64::from(r.tensioner), s.tensioner);
        assert_eq!(
            [
                r.travel_m,
                r.speed_m_s,
                r.pressure_pa,
                r.arm_angle_rad,
                r.shoe_force_n,
                r.plunger_force_n
            ],
            [
                s.travel_m,
                s.speed_m_s,
                s.pressure_pa,
                s.arm_angle_rad,
                s.shoe_force_n,
                s.plunger_force_n
            ]
        );
        assert_eq!(r.valve_open, s.valve_open);
    }
    assert!(drawn && framed, "drawn {drawn}, in /tf {framed}");
    let (pivot, a0, e) = (
        [0.090923, 0.015986],
        [0.180131, 0.227981],
        [-0.921718, 0.387861],
    );
    // The scene's line direction, made unit as the scene does.
    let norm: f64 = e[0] * e[0] + e[1] * e[1];
    let e = [e[0] / norm.sqrt(), e[1] / norm.sqrt()];
    let r0 = [a0[0] - pivot[0], a0[1] - pivot[1]];
    let mut on_shoe = 0;
    for s in &samples {
        assert_eq!(s.tensioners.len(), 1);
        let t = &s.tensioners[0];
        assert_eq!(t.tensioner, 1);
        let (sn, c) = t.arm_angle_rad.sin_cos();
        let r = [c * r0[0] - sn * r0[1], sn * r0[0] + c * r0[1]];
        let x = (r[0] - r0[0]) * e[0] + (r[1] - r0[1]) * e[1];
        assert!((t.travel_m - x).abs() < 1e-12, "{t:?} against x = {x}");
        assert!(
            t.pressure_pa.is_finite() && t.pressure_pa > -101_325.0,
            "{t:?}"
        );
        assert!(t.speed_m_s.is_finite() && t.plunger_force_n.is_finite());
        on_shoe += usize::from(t.shoe_force_n > 0.0);
    }
    assert!(
        on_shoe > 5,
        "the strand rides on the shoe in {on_shoe} of 11"
    );
    // Without arms: no channel, nothing drawn.
    let plain = &TIMING[..TIMING.find("[[tensioners]]").expect("an arm")];
    let plain = plain.replace("pretension_by = \"tensioner_preload\"", "");
    let plain = Scene::from_toml(&format!("{plain}[solver]\nduration_s = 0.01\n"))
        .expect("the drive without its arm");
    let (samples, drawn, framed, read) = record(&plain);
    assert!(samples.is_empty() && !drawn && !framed && read.is_empty());
}

/// A shoe the chain path does not reach gets a warning naming the arm, as a
/// guide does; the timing drive's shoe and guide both touch the strands at
/// rest, so it has no warnings. The far arm's shoe (centre (1.05, 1.2),
/// radius 0.05 m) lies about a metre from the flat drive's strands.
#[test]
fn a_shoe_the_chain_never_touches_is_warned_about() {
    let far = Scene::from_toml(&format!("{FLAT}\n{FAR_ARM}\n{HYDRAULIC}")).expect("a valid scene");
    let w = far.warnings();
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("tensioners[0]") && w[0].contains("\"test arm\""),
        "{w:?}"
    );
    assert!(
        timing_scene().warnings().is_empty(),
        "{:?}",
        timing_scene().warnings()
    );
}

/// The far arm's hydraulic tensioner with a return spring F₀ = 10 N,
/// k = 1000 N/m (free length x_f = 10 mm), at supply pressure
/// p_s = 3e5 Pa: on both sides of x_f the plunger's push is the closed
/// form p_s A + max(0, F₀ − k x), and the static potential's derivative
/// dU/dq (central differences) is minus its moment F ℓ cos q about the
/// pivot (the point at (ℓ cos q, ℓ sin q) from the pivot, pushed along +y).
#[test]
fn the_return_spring_pushes_only_while_compressed_and_the_potential_agrees() {
    let spring = HYDRAULIC
        .replace("spring_preload_n = 0.0", "spring_preload_n = 10.0")
        .replace(
            "spring_stiffness_n_m = 0.0",
            "spring_stiffness_n_m = 1000.0",
        );
    let text = format!("{FLAT}\n{FAR_ARM}\n{spring}");
    let scene = Scene::from_toml(&text).expect("a valid scene");
    let mut sim = Simulation::new(&scene).expect("the drive settles");
    let p_s = 3e5;
    let at_rest = arm(&sim).at_rest();
    // x = ℓ sin q: 4 mm (compressed) and 30 mm (off its seat).
    for x in [0.004, 0.03] {
        let q = (x / LEVER_M).asin();
        let push = p_s * AREA_M2 + (10.0 - 1000.0 * x).max(0.0);
        start_at(&mut sim, q, p_s);
        let read = arm(&sim).reading().plunger_force_n;
        assert!(
            (read - push).abs() < 1e-6 * push,
            "x = {x}: push {read} N, closed form {push} N"
        );
        let h = 1e-6;
        let du = (at_rest.potential_j([0.0, 0.0], q + h) - at_rest.potential_j([0.0, 0.0], q - h))
            / (2.0 * h);
        let moment = push * LEVER_M * q.cos();
        assert!(
            (du + moment).abs() < 1e-6 * moment,
            "x = {x}: dU/dq {du} N·m, minus the moment {} N·m",
            -moment
        );
    }
}
