//! The summary's means, counted every step, against closed forms and
//! across sample rates; the statistics window after the scene's ramps.

use chaindrive::analysis::{RunSummary, StatsWindow};
use chaindrive::scene::Scene;
use chaindrive::sim::{PowerMeans, SampleRate, Simulation};

/// ISO 606 10B-1, 15T at 4000 rpm → 44T against 560 N·m: its tooth-passing
/// frequency is 1000 Hz.
const MOTO: &str = include_str!("../data/moto_10b_15_44_560nm.toml");

/// Runs `scene` sampled at `rate_hz` and summarises it over its default
/// window, through the library's one entry point; also the ledger's means.
fn summary_at(scene: &Scene, rate_hz: f64) -> (RunSummary, PowerMeans) {
    let mut sim = Simulation::new(scene).expect("a static equilibrium");
    let window = StatsWindow::of(scene, None).expect("the default window");
    let sampling = SampleRate::new(rate_hz, scene.solver().dt_s).expect("a whole number of steps");
    let mut signals = window.observe(&mut sim, sampling.rate_hz);
    let outcome = sim
        .run(
            scene.solver().duration_s,
            sampling.every,
            &mut signals,
            None,
        )
        .expect("no blow-up");
    let flow = sim.power.as_ref().and_then(|p| p.means()).expect("counted");
    let summary = RunSummary::of_run_in(&sim, &outcome, &signals, 0.0, &window);
    (summary, flow)
}

/// The summary's window is `[from, to]`, s (to the clock's rounding).
fn assert_window(s: &RunSummary, [from, to]: [f64; 2]) {
    let [a, b] = s.window_s;
    assert!(
        (a - from).abs() < 1e-9 && (b - to).abs() < 1e-9,
        "{:?}",
        s.window_s
    );
}

#[test]
fn mean_torques_meet_the_closed_form_at_a_rate_equal_to_the_tooth_frequency() {
    // Closed form, steady state over the window (after the 0.2 s ramps):
    // - the wheel (free, J dω/dt = M_chain + τ_load): its mean chain moment
    //   is −τ_load = 560 N·m, less J Δω / T over the window (J = 0.05 kg·m²,
    //   the speed swings 4 rad/s peak to peak: under 0.2 N·m, 0.04 %);
    // - the engine (speed imposed): the chain takes from it what the wheel's
    //   load and the chain's losses take, −M₁ ω₁ = 560 ω₂ + P_loss + dE/dt,
    //   and ω₂ / ω₁ = z₁ / z₂ on average (no chain slips): −M₁ = 560 · 15/44
    //   + P_loss / ω₁ = 190.91 N·m + about 1.6 N·m. The losses (link and
    //   contact damping, 0.8 % of the 80 kW) do not fit within 0.5 %; they
    //   are the ledger's, counted from the dampers' forces and speeds, not
    //   from the sprockets' moments; dE/dt and the step's own energy error
    //   (the balance residual, 0.4 % at this step) are what is left.
    // Before the means were counted every step, 1 kHz sampling met the
    // same phase of every tooth and gave −178.4 / 551.7 N·m.
    let scene = Scene::from_toml(MOTO).expect("a valid scene");
    let ratio = 15.0 / 44.0;
    let mut means = Vec::new();
    for rate in [1000.0, 5000.0] {
        let (s, flow) = summary_at(&scene, rate);
        assert_window(&s, [0.5, 1.5]);
        assert!(s.means_every_step);
        let [engine, wheel] = [&s.sprockets[0], &s.sprockets[1]];
        approx::assert_relative_eq!(wheel.mean_torque_n_m, 560.0, max_relative = 5e-3);
        let losses_w = flow.mean.link_damping_w + flow.mean.contact_damping_w;
        let closed = 560.0 * ratio + losses_w / engine.mean_speed_rad_s;
        approx::assert_relative_eq!(-engine.mean_torque_n_m, closed, max_relative = 5e-3);
        // The engine supplies at least the load: never less than 560 · 15/44.
        assert!(
            -engine.mean_torque_n_m > 560.0 * ratio,
            "{rate} Hz: {engine:?}"
        );
        approx::assert_relative_eq!(
            wheel.mean_speed_rad_s,
            engine.mean_speed_rad_s * ratio,
            max_relative = 1e-4
        );
        means.push([
            engine.mean_torque_n_m,
            wheel.mean_torque_n_m,
            s.driver_mean_power_w,
            s.segments[0].mean_link_force_n,
            s.segments[1].mean_link_force_n,
        ]);
    }
    // Counted every step, the means are those of the same steps whatever
    // the rate: equal but for the order of the additions.
    for (a, b) in means[0].iter().zip(&means[1]) {
        approx::assert_relative_eq!(*a, *b, max_relative = 1e-10);
    }
}

#[test]
fn a_rate_equal_to_the_tooth_frequency_warns_of_the_sampled_statistics() {
    let scene = Scene::from_toml(&MOTO.replace("duration_s = 1.5", "duration_s = 0.3"))
        .expect("a valid scene");
    let warned = |rate| {
        let (s, _) = summary_at(&scene, rate);
        s.warnings
            .into_iter()
            .find(|w| w.starts_with("sample rate"))
    };
    let w = warned(1000.0).expect("a warning at 1 kHz");
    assert!(
        w.contains("engine") && w.contains("0.0 Hz from 1 × the sample rate"),
        "{w}"
    );
    assert!(w.contains("the means are counted every step"), "{w}");
    // 5 kHz: the harmonics 1–3 (1, 2, 3 kHz) keep away from its multiples.
    assert_eq!(warned(5000.0), None);
}

#[test]
fn the_tension_difference_of_a_short_run_is_the_loads_after_its_ramps() {
    // 1 s runs with 0.3 s ramps: the default window is 0.3–1.0 s, after
    // them. Moment balance on the wheel: the tight strand's mean force less
    // the slack one's carries the 560 N·m on the pitch radius
    // R₂ = P / (2 sin(π/44)) = 111.26 mm, 5033 N (the polygon's lever
    // R₂ cos(π/44) is 0.26 % shorter at its shortest). The last second,
    // ramps included, gave about 11 % less.
    let text = MOTO
        .replace("duration_s = 1.5", "duration_s = 1.0")
        .replace("ramp_s = 0.2", "ramp_s = 0.3");
    let scene = Scene::from_toml(&text).expect("a valid scene");
    let (s, _) = summary_at(&scene, 1000.0);
    assert_window(&s, [0.3, 1.0]);
    assert!(!s.warnings.iter().any(|w| w.starts_with("ramp in window")));
    let r2 = 0.015875 / (2.0 * (std::f64::consts::PI / 44.0).sin());
    let difference = s.segments[1].mean_link_force_n - s.segments[0].mean_link_force_n;
    approx::assert_relative_eq!(difference, 560.0 / r2, max_relative = 0.01);
}

#[test]
fn the_default_window_starts_after_the_paper_drives_ramp() {
    // 1.5 s with a 1 s ramp: the last second would start at 0.5 s.
    let (s, _) = summary_at(&crate::common::l60mc(1.5), 1000.0);
    assert_window(&s, [1.0, 1.5]);
    assert!(!s.warnings.iter().any(|w| w.starts_with("ramp in window")));
}

#[test]
fn a_run_that_ends_with_its_ramp_warns_naming_it() {
    // `run --duration 1` on the paper's drive: nothing after the ramp; the
    // summary keeps the whole run and says what it holds (its driver's
    // torque, −12.6 kN·m, is the ramp's).
    let (s, _) = summary_at(&crate::common::l60mc(1.0), 1000.0);
    assert_window(&s, [0.0, 1.0]);
    let w = s
        .warnings
        .iter()
        .find(|w| w.starts_with("ramp in window"))
        .unwrap_or_else(|| panic!("{:?}", s.warnings));
    assert!(w.contains("speed ramp of sprocket 1 (crankshaft)"), "{w}");
    assert!(w.contains("the run ends before it does"), "{w}");
}

#[test]
fn a_chosen_window_that_reaches_into_a_ramp_warns() {
    let scene = crate::common::l60mc(1.2);
    let mut sim = Simulation::new(&scene).expect("a static equilibrium");
    let window = StatsWindow::of(&scene, Some(0.5)).expect("a window");
    approx::assert_relative_eq!(window.start_s(), 0.7, max_relative = 1e-12);
    let sampling = SampleRate::new(1000.0, scene.solver().dt_s).expect("a sample step");
    let mut signals = window.observe(&mut sim, sampling.rate_hz);
    let outcome = sim
        .run(1.2, sampling.every, &mut signals, None)
        .expect("no blow-up");
    let s = RunSummary::of_run_in(&sim, &outcome, &signals, 0.0, &window);
    let w = s
        .warnings
        .iter()
        .find(|w| w.starts_with("ramp in window"))
        .unwrap_or_else(|| panic!("{:?}", s.warnings));
    assert!(w.contains("0.70–1.20 s"), "{w}");
    assert!(w.contains("at most 0.200 s"), "{w}");
}
