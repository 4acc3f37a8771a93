//! Guides: a guide pressing a tensioned strand against the balance of the
//! strand's tensions, the settled drive, the example scene and bad input.

use crate::scene::{Scene, SceneError};
use crate::sim::Simulation;

fn text(file: &str) -> String {
    let path = format!("{}/tests/data/{file}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).expect("the scene file exists")
}

/// The guide under the upper strand of `guide_30_30.toml`: its face
/// y = R_p − R_r + d for x ∈ [0.689, 1.089] m, d = 10 mm.
const FACE_Y_M: f64 = 0.408243;

const FACE_X_M: [f64; 2] = [0.689, 1.089];

/// A straight guide pressing a tensioned straight strand in by d.
///
/// Assumptions: no gravity, no load, μ = 0, the chain at rest (static
/// equilibrium). The rollers on the guide are then held by the two links
/// that leave the guide's ends and by the guide alone, so the guide's force
/// on the chain balances the two links' pulls: |F| = |T₁ û₁ + T₂ û₂|, and
/// with the strand symmetric about the guide's middle (T₁ = T₂ = T, both
/// links at θ to the face) |F| = 2 T sin θ. θ and T are measured on those
/// two links; F is the sum of the guide's contact forces. Tolerance 1 %.
///
/// The tension: the free sprocket carries no load and turns without
/// friction, so its two strands pull equally, and the frictionless guide
/// does not change the tension along its strand: both strands are at the
/// pretension that the rest-length rule sets for their mean. Tolerance
/// 0.5 %.
#[test]
fn a_guide_pressing_a_strand_carries_two_t_sin_theta() {
    let scene = Scene::from_toml(&text("guide_30_30.toml")).expect("a valid scene");
    assert!(scene.warnings().is_empty(), "{:?}", scene.warnings());
    let mut sim = Simulation::new(&scene).expect("a static equilibrium");
    sim.forces.evaluate(&sim.model, &sim.state);
    let out = sim.forces.output();
    let s = &sim.state;
    let r = scene.chain().roller_radius_m;
    let n = s.x.len();
    // Rollers on the guide (closer than R_r to the face segment), ordered
    // along x.
    let mut on: Vec<usize> = (0..n)
        .filter(|&i| {
            let dx = (FACE_X_M[0] - s.x[i]).max(s.x[i] - FACE_X_M[1]).max(0.0);
            s.y[i] > 0.0 && dx.hypot(s.y[i] - FACE_Y_M) < r
        })
        .collect();
    assert!(on.len() >= 3, "rollers on the guide: {on:?}");
    on.sort_by(|&a, &b| s.x[a].total_cmp(&s.x[b]));
    let shoe = out.shoes[0];
    assert_eq!(shoe.contacts, on.len());
    // The link leaving each end roller away from the guide: its pull on the
    // end roller, T û (û from the end roller to its outer neighbour).
    let pull = |end: usize, outward_x: f64| {
        let (prev, next) = ((end + n - 1) % n, (end + 1) % n);
        let (nb, link) = if (s.x[next] - s.x[end]) * outward_x > 0.0 {
            (next, end)
        } else {
            (prev, prev)
        };
        let (dx, dy) = (s.x[nb] - s.x[end], s.y[nb] - s.y[end]);
        let l = dx.hypot(dy);
        (out.link_force[link], [dx / l, dy / l])
    };
    let (t1, u1) = pull(on[0], -1.0);
    let (t2, u2) = pull(on[on.len() - 1], 1.0);
    let theta = 0.5 * (u1[1].abs().asin() + u2[1].abs().asin());
    let t = 0.5 * (t1 + t2);
    let expected = 2.0 * t * theta.sin();
    let force = shoe.force_n[0].hypot(shoe.force_n[1]);
    eprintln!(
        "guide force {force:.3} N, 2 T sin θ = {expected:.3} N (T = {t:.2} N, θ = {theta:.6} rad), links {t1:.2} N and {t2:.2} N, {} rollers on the guide",
        on.len()
    );
    assert!(
        (force - expected).abs() < 0.01 * expected,
        "guide force {force} N, 2 T sin θ = {expected} N (T = {t} N, θ = {theta} rad)"
    );
    // The press is real: θ within a factor of the straight-line estimate
    // d / a (a = 0.689 m from the tangent point to the guide's end).
    assert!(
        theta > 0.5 * 0.01 / 0.689 && theta < 2.0 * 0.01 / 0.689,
        "θ = {theta}"
    );
    let target = scene.chain().pretension_n;
    for (name, tension) in [("left", t1), ("right", t2)] {
        assert!(
            (tension - target).abs() < 0.005 * target,
            "{name} link {tension} N against the pretension {target} N"
        );
    }
    // The lower strand: every link with both rollers below the centres'
    // line and off the sprockets.
    let lower: Vec<f64> = (0..n)
        .filter(|&i| {
            let j = (i + 1) % n;
            s.y[i] < 0.0
                && s.y[j] < 0.0
                && !out.touching[i]
                && !out.touching[j]
                && s.x[i] > 0.0
                && s.x[i] < 1.778
        })
        .map(|i| out.link_force[i])
        .collect();
    assert!(!lower.is_empty());
    let lower_mean = lower.iter().sum::<f64>() / lower.len() as f64;
    assert!(
        (lower_mean - target).abs() < 0.005 * target,
        "lower strand {lower_mean} N against the pretension {target} N"
    );
}

/// The drive with a guide settles (force residual below 10⁻³ of the
/// pretension) and then runs 0.2 s, its ramp beginning, without a blow-up;
/// the guide's summary entry exists and is finite.
#[test]
fn a_drive_with_a_guide_settles_and_runs() {
    use crate::analysis::{RunSummary, Signals};
    use crate::sim::SampleRate;
    let scene = Scene::from_toml(&text("guide_30_30.toml")).expect("a valid scene");
    let mut sim = Simulation::new(&scene).expect("a static equilibrium");
    assert!(
        sim.equilibrium.force_residual < 1e-3,
        "{:?}",
        sim.equilibrium
    );
    let sampling = SampleRate::new(1000.0, scene.solver().dt_s).expect("a sample step");
    let mut signals = Signals::new(&sim.model, sampling.rate_hz, 0.0);
    let outcome = sim
        .run(0.2, sampling.every, &mut signals, None)
        .expect("no blow-up");
    let summary = RunSummary::of_run(&sim, &outcome, &signals, 0.0);
    assert_eq!(summary.guides.len(), 1);
    let g = &summary.guides[0];
    assert_eq!(g.name, "upper");
    assert!(
        g.normal_mean_n > 0.0 && g.normal_max_n >= g.normal_mean_n,
        "{g:?}"
    );
    assert!(
        g.friction_mean_n == 0.0 && g.friction_max_n == 0.0,
        "μ = 0: {g:?}"
    );
}

/// `assets/l60mc-guides.toml`, the paper's drive with guide bars on its
/// long strands, runs 0.05 s and both guides carry the chain.
#[test]
fn the_paper_drive_with_guides_runs() {
    use crate::analysis::{RunSummary, Signals};
    use crate::sim::SampleRate;
    let path = format!("{}/assets/l60mc-guides.toml", env!("CARGO_MANIFEST_DIR"));
    let scene = Scene::from_toml(&std::fs::read_to_string(path).expect("the asset"))
        .expect("a valid scene");
    assert!(scene.warnings().is_empty(), "{:?}", scene.warnings());
    let mut sim = Simulation::new(&scene).expect("a static equilibrium");
    let sampling = SampleRate::new(1000.0, scene.solver().dt_s).expect("a sample step");
    let mut signals = Signals::new(&sim.model, sampling.rate_hz, 0.0);
    let outcome = sim
        .run(0.05, sampling.every, &mut signals, None)
        .expect("no blow-up");
    let summary = RunSummary::of_run(&sim, &outcome, &signals, 0.0);
    assert_eq!(summary.guides.len(), 2);
    for g in &summary.guides {
        assert!(g.normal_mean_n > 0.0 && g.normal_max_n.is_finite(), "{g:?}");
    }
}

/// Field errors of `[[guides]]` entries: every one named with its path.
fn errors(guide: &str) -> Vec<(String, String)> {
    let scene = text("guide_30_30.toml");
    let head = &scene[..scene.find("[[guides]]").expect("a guide")];
    let tail = &scene[scene.find("[solver]").expect("a solver")..];
    let toml = format!("{head}[[guides]]\n{guide}\n{tail}");
    match Scene::from_toml(&toml) {
        Err(SceneError::Invalid(e)) => e.into_iter().map(|e| (e.path, e.message)).collect(),
        Err(e) => panic!("expected field errors, got {e}"),
        Ok(_) => panic!("expected field errors for\n{guide}"),
    }
}

fn has(errors: &[(String, String)], path: &str, words: &str) {
    assert!(
        errors.iter().any(|(p, m)| p == path && m.contains(words)),
        "no error at {path} saying \"{words}\": {errors:?}"
    );
}

#[test]
fn bad_guides_are_named_by_their_field() {
    let ok = "name = \"g\"\nstart_m = [0.689, 0.408243]\nend_m = [1.089, 0.408243]\n";
    has(
        &errors("name = \"g\"\nstart_m = [0.5, 0.4]\nend_m = [0.5, 0.4]"),
        "guides[0].end_m",
        "coincide",
    );
    has(
        &errors("name = \"g\"\nstart_m = [nan, 0.4]\nend_m = [0.5, 0.4]"),
        "guides[0].start_m[0]",
        "finite",
    );
    has(
        &errors(&format!("{ok}stiffness = -1e9")),
        "guides[0].stiffness",
        "> 0",
    );
    has(
        &errors(&format!("{ok}restitution = 1.5")),
        "guides[0].restitution",
        "[0, 1]",
    );
    has(
        &errors(&format!("{ok}friction = -0.1")),
        "guides[0].friction",
        ">= 0",
    );
    has(
        &errors(&format!("{ok}friction = nan")),
        "guides[0].friction",
        "finite",
    );
    has(
        &errors(&format!("{ok}radius_m = 0.1")),
        "guides[0].radius_m",
        "shorter than half",
    );
    has(
        &errors(&format!("{ok}center_m = [0.8, 0.0]")),
        "guides[0].center_m",
        "from the start",
    );
    has(
        &errors(&format!("{ok}radius_m = 1.0\ncenter_m = [0.8, 0.0]")),
        "guides[0].center_m",
        "not both",
    );
    has(
        &errors(&format!(
            "{ok}start_ramp = {{ length_m = -0.01, angle_deg = 5.0 }}"
        )),
        "guides[0].start_ramp.length_m",
        "> 0",
    );
    has(
        &errors(&format!(
            "{ok}end_ramp = {{ length_m = 0.01, angle_deg = 60.0 }}"
        )),
        "guides[0].end_ramp.angle_deg",
        "(0, 45]",
    );
    // A shoe across the driven sprocket's teeth.
    has(
        &errors("name = \"g\"\nstart_m = [-0.1, 0.3]\nend_m = [0.3, 0.3]"),
        "guides[0].start_m",
        "sprocket \"driven\"",
    );
}

#[test]
fn a_bad_every_steps_is_named() {
    let ok = "name = \"g\"\nstart_m = [0.689, 0.408243]\nend_m = [1.089, 0.408243]\n";
    for bad in ["0", "2.5", "-3", "nan", "1e6"] {
        has(
            &errors(&format!("{ok}every_steps = {bad}")),
            "guides[0].every_steps",
            "whole number of steps from 1 to 1000",
        );
    }
    // Above 1 with an integrator that evaluates inner stages: refused.
    let scene = text("guide_30_30.toml").replace(
        "end_m = [1.089, 0.408243]\n",
        "end_m = [1.089, 0.408243]\nevery_steps = 4\n",
    );
    assert!(Scene::from_toml(&scene).is_ok());
    for integrator in ["rk4", "velocity_verlet", "dormand_prince45"] {
        let toml = scene.replace(
            "[solver]\n",
            &format!("[solver]\nintegrator = \"{integrator}\"\n"),
        );
        match Scene::from_toml(&toml) {
            Err(SceneError::Invalid(e)) => assert!(
                e.iter().any(|e| e.path == "guides[0].every_steps"
                    && e.message.contains("one evaluation of the forces a step")),
                "{e:?}"
            ),
            other => panic!("{integrator}: expected a field error, got {other:?}"),
        }
    }
}

/// The guide pressing a strand (`guide_30_30.toml`, 10 mm in, about 100 N
/// on four rollers) evaluated every 4 steps of 10 µs against every step,
/// from the same state at rest (the static equilibrium evaluates it at
/// every step, so the two start from the same bits):
/// over 0.2 s of run-up the guide's mean normal force, the largest link
/// force and the free sprocket's final speed agree within 1 %.
#[test]
fn a_guide_every_four_steps_runs_as_one_every_step() {
    use crate::analysis::{RunSummary, Signals};
    use crate::sim::SampleRate;
    let run = |every: u32| {
        let toml = text("guide_30_30.toml").replace(
            "end_m = [1.089, 0.408243]\n",
            &format!("end_m = [1.089, 0.408243]\nevery_steps = {every}\n"),
        );
        let scene = Scene::from_toml(&toml).expect("a valid scene");
        let mut sim = Simulation::new(&scene).expect("a static equilibrium");
        let at_rest = sim.state.clone();
        let sampling = SampleRate::new(1000.0, scene.solver().dt_s).expect("a sample step");
        let mut signals = Signals::new(&sim.model, sampling.rate_hz, 0.0);
        let outcome = sim
            .run(0.2, sampling.every, &mut signals, None)
            .expect("no blow-up");
        let summary = RunSummary::of_run(&sim, &outcome, &signals, 0.0);
        (at_rest, sim.state.clone(), summary)
    };
    let (rest1, s1, a) = run(1);
    let (rest4, s4, b) = run(4);
    // The same state at rest, bit for bit: the static equilibrium evaluates
    // the guide at every step whatever the setting.
    assert_eq!(rest1.y, rest4.y);
    assert_eq!(rest1.x, rest4.x);
    let close = |x: f64, y: f64, what: &str| {
        assert!((x - y).abs() <= 1e-2 * x.abs(), "{what}: {x} against {y}");
    };
    close(
        a.guides[0].normal_mean_n,
        b.guides[0].normal_mean_n,
        "guide's mean normal force",
    );
    assert!(a.guides[0].normal_mean_n > 10.0, "{:?}", a.guides[0]);
    close(a.link_force_max_n, b.link_force_max_n, "largest link force");
    close(s1.omega[1], s4.omega[1], "free sprocket's speed");
    // Not the same bits: the impulses are applied.
    assert_ne!(s1.y, s4.y);
}

/// A guide the chain path passes clear of is valid, with a warning that
/// names it and the clearance.
#[test]
fn a_guide_clear_of_the_chain_gets_a_warning() {
    let scene = text("guide_30_30.toml").replace("0.408243", "0.35");
    let scene = Scene::from_toml(&scene).expect("a valid scene");
    let w = scene.warnings();
    assert_eq!(w.len(), 1, "{w:?}");
    // Clearance: R_p − 0.35 − R_r = 0.425243 − 0.35 − 0.027 = 48.24 mm.
    assert!(
        w[0].contains("guides[0]") && w[0].contains("48.24 mm"),
        "{w:?}"
    );
}

/// A recording of a drive with a guide holds a `/guides` message at every
/// sample and the guide's face in the static scene; a drive without guides
/// gets no `/guides` channel.
#[cfg(feature = "record")]
#[test]
fn guides_are_recorded_and_drawn() {
    use crate::record::{Channels, RecordOptions, Recorder, RunEnd};
    use crate::sim::SampleRate;
    use std::io::Cursor;
    let record = |scene: &Scene| {
        let mut sim = Simulation::new(scene).expect("a static equilibrium");
        let sampling = SampleRate::new(1000.0, scene.solver().dt_s).expect("a sample step");
        let options = RecordOptions {
            channels: Channels::all(),
            scene_file: None,
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
        let mut guides = 0;
        let mut drawn = false;
        for m in mcap::MessageStream::new(&bytes).expect("an MCAP file") {
            let m = m.expect("a message");
            match m.channel.topic.as_str() {
                "/guides" => guides += 1,
                // The entity id and the label are plain strings in the message.
                "/scene/static" => {
                    drawn |= m.data.windows(6).any(|w| w == b"guide1");
                }
                _ => {}
            }
        }
        (guides, drawn)
    };
    let scene = Scene::from_toml(&text("guide_30_30.toml")).expect("a valid scene");
    // t = 0 and every 1 ms to 10 ms: 11 samples.
    assert_eq!(record(&scene), (11, true));
    let plain = text("guide_30_30.toml");
    let plain = &plain[..plain.find("[[guides]]").expect("a guide")];
    let plain = Scene::from_toml(&format!("{plain}[solver]\ndt_s = 1e-5\n")).expect("a scene");
    assert_eq!(record(&plain), (0, false));
}
