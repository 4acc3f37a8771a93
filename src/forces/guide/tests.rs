//! The guide element's tests: against closed forms (the elastic force along
//! the normal, Coulomb's saturation, the carried shoe's moment, Hertz's depth,
//! an elastic bounce's energy) and against itself (every k-th step, culling).

use super::*;
use crate::geometry::shoe::{Ramp, body_from_radius};
use crate::model::DriveModel;
use crate::scene::{Contact, ContactLaw, Scene};

fn law(k: f64, e: f64) -> ContactLawParams {
    ContactLawParams::new(&Contact {
        law: ContactLaw::HuntCrossley,
        stiffness: k,
        exponent: 1.5,
        restitution: e,
        min_approach_speed_m_s: 0.05,
    })
}

/// A model and a state of `n` rollers, all at the origin at rest, except
/// those the test places.
fn drive(n: usize) -> (DriveModel, DriveState) {
    let scene = Scene::l60mc();
    let (model, mut state, _) = DriveModel::build(&scene).unwrap();
    state.x.truncate(n);
    state.y.truncate(n);
    state.vx.truncate(n);
    state.vy.truncate(n);
    state.x.fill(10.0);
    state.y.fill(10.0);
    state.vx.fill(0.0);
    state.vy.fill(0.0);
    (model, state)
}

fn flat(carrier: Option<Carrier>, mu: f64) -> GuideElement {
    // Face y = 0, x ∈ [0, 1], working side above, ramps of 5 cm at 0.1 rad.
    let body = body_from_radius([0.0, 0.0], [1.0, 0.0], None).unwrap();
    let ramp = Ramp {
        length_m: 0.05,
        angle_rad: 0.1,
    };
    let face = Face::new(body, 1.0, Some(ramp), Some(ramp));
    GuideElement::new(
        GuideParams {
            name: "g".into(),
            face,
            law: law(1e9, 1.0),
            friction: mu,
            slip_speed_m_s: 0.01,
            carrier,
        },
        3,
        0.01,
    )
}

#[test]
fn a_resting_roller_gets_the_elastic_force_along_the_normal() {
    // Roller of R_r = 10 mm, centre 9 mm above the face: δ = 1 mm,
    // f = K δ^1.5 = 1e9 · (1e-3)^1.5 = 31 622.8 N, straight up, e = 1.
    let (model, mut state) = drive(3);
    state.x[1] = 0.5;
    state.y[1] = 0.009;
    let mut out = Forces::new(3, 0, 0, 0);
    let mut g = flat(None, 0.3);
    g.evaluate(&model, &state, &mut out);
    let f = 1e9 * 1e-3f64.powf(1.5);
    assert!((out.fy[1] - f).abs() < 1e-6 * f, "{}", out.fy[1]);
    assert!(out.fx[1].abs() < 1e-9, "no slip, no friction");
    assert_eq!(g.forces().contacts, 1);
    assert!((g.forces().force_n[1] + f).abs() < 1e-6 * f);
    assert_eq!(out.fy[0], 0.0);
}

#[test]
fn friction_saturates_at_mu_times_the_normal_force() {
    // Sliding at 1 m/s ≫ v_s = 0.01: |f_t| = μ f_n / √(1 + 1e-4) ≈ μ f_n
    // (within 5e-5), against the sliding direction.
    let (model, mut state) = drive(3);
    state.x[1] = 0.5;
    state.y[1] = 0.009;
    state.vx[1] = 1.0;
    let mut out = Forces::new(3, 0, 0, 0);
    let mut g = flat(None, 0.3);
    g.evaluate(&model, &state, &mut out);
    let f = 1e9 * 1e-3f64.powf(1.5);
    assert!(
        (out.fx[1] + 0.3 * f).abs() < 5e-5 * 0.3 * f,
        "{}",
        out.fx[1]
    );
    assert!((g.forces().friction_n - 0.3 * f).abs() < 5e-5 * 0.3 * f);
}

#[test]
fn a_carried_shoe_turns_with_its_body_and_feels_the_moment() {
    // The flat shoe on a body turned by +90° about the origin: its face
    // is then x = 0 for y ∈ [0, 1] with the working side at x < 0. A
    // roller at (−9 mm, 0.5) presses it with f = K δ^1.5 in −x; the
    // moment of the reaction (+f in x at (0, 0.5)) about the origin is
    // −0.5 f.
    let (model, mut state) = drive(3);
    state.q = vec![std::f64::consts::FRAC_PI_2];
    state.u = vec![0.0];
    state.x[1] = -0.009;
    state.y[1] = 0.5;
    let mut out = Forces::new(3, 0, 1, 0);
    let mut g = flat(
        Some(Carrier {
            body: 0,
            pivot_m: [0.0, 0.0],
        }),
        0.0,
    );
    g.evaluate(&model, &state, &mut out);
    let f = 1e9 * 1e-3f64.powf(1.5);
    assert!((out.fx[1] + f).abs() < 1e-6 * f, "{}", out.fx[1]);
    assert!(out.fy[1].abs() < 1e-6 * f);
    assert!(
        (out.body_force[0] + 0.5 * f).abs() < 1e-6 * f,
        "{}",
        out.body_force[0]
    );
}

#[test]
fn the_onset_speed_is_remembered_until_separation() {
    // Approach at 0.5 m/s at δ = 1 mm: f = K δ^1.5 (1 + χ) with
    // Hunt–Crossley χ = 1.5 (1 − e) = 0.75 at e = 0.5. Committed, a later
    // evaluation at 0.25 m/s damps with the remembered 0.5 m/s:
    // f = K δ^1.5 (1 + 0.75 · 0.5).
    let (model, mut state) = drive(3);
    state.x[1] = 0.5;
    state.y[1] = 0.009;
    state.vy[1] = -0.5;
    let mut out = Forces::new(3, 0, 0, 0);
    let mut g = flat(None, 0.0);
    g.params.law = law(1e9, 0.5);
    g.evaluate(&model, &state, &mut out);
    let k = 1e9 * 1e-3f64.powf(1.5);
    assert!((out.fy[1] - k * 1.75).abs() < 1e-6 * k);
    g.commit();
    state.vy[1] = -0.25;
    let mut out = Forces::new(3, 0, 0, 0);
    g.evaluate(&model, &state, &mut out);
    assert!((out.fy[1] - k * 1.375).abs() < 1e-6 * k, "{}", out.fy[1]);
    // Apart: forgotten.
    state.y[1] = 0.02;
    g.evaluate(&model, &state, &mut out);
    g.commit();
    assert!(g.onset[1] < 0.0);
}

/// One roller of mass `m` (roller 1 of [`drive`]) stepped by symplectic
/// Euler at `h` under gravity `g` (downwards) and the flat guide `g_el`
/// from height `y0` at vertical speed `v0`, for `steps` steps; `each`
/// sees the state after every step (penetration, vertical speed).
#[allow(clippy::too_many_arguments)]
fn drop_on(
    g_el: &mut GuideElement,
    m: f64,
    g: f64,
    h: f64,
    y0: f64,
    v0: f64,
    steps: usize,
    mut each: impl FnMut(f64, f64),
) {
    let (model, mut state) = drive(3);
    state.x[1] = 0.5;
    state.y[1] = y0;
    state.vy[1] = v0;
    state.t_s = 0.0;
    g_el.begin_run();
    let mut out = Forces::new(3, 0, 0, 0);
    g_el.evaluate(&model, &state, &mut out);
    g_el.commit();
    for step in 1..=steps {
        state.vy[1] += h * (out.fy[1] / m - g);
        state.y[1] += h * state.vy[1];
        state.t_s = step as f64 * h;
        out = Forces::new(3, 0, 0, 0);
        g_el.evaluate(&model, &state, &mut out);
        g_el.commit();
        each(0.01 - state.y[1], state.vy[1]);
    }
}

#[test]
fn every_kth_step_adds_k_times_the_force_and_nothing_between() {
    // A roller held at δ = 1 mm: over any k consecutive steps the guide
    // adds k·f once (the impulse k h f of k steps) and nothing at the
    // others, while its reported sums stay f.
    let (model, mut state) = drive(3);
    state.x[1] = 0.5;
    state.y[1] = 0.009;
    let f = 1e9 * 1e-3f64.powf(1.5);
    let k = 7;
    let mut g = flat(None, 0.3).every_steps(k);
    g.begin_run();
    let mut added = Vec::new();
    for step in 0..3 * k {
        state.t_s = f64::from(step) * 1e-6;
        let mut out = Forces::new(3, 0, 0, 0);
        g.evaluate(&model, &state, &mut out);
        // Evaluated again at the same state: the same forces.
        let mut again = Forces::new(3, 0, 0, 0);
        g.evaluate(&model, &state, &mut again);
        assert_eq!(out.fy, again.fy);
        g.commit();
        added.push(out.fy[1]);
        assert!((out.shoes[0].normal_n - f).abs() < 1e-6 * f);
    }
    for window in added.windows(k as usize) {
        let sum: f64 = window.iter().sum();
        assert!((sum - f64::from(k) * f).abs() < 1e-9 * f, "{window:?}");
        assert_eq!(window.iter().filter(|&&v| v == 0.0).count(), k as usize - 1);
    }
}

#[test]
fn an_elastic_bounce_every_tenth_step_keeps_its_energy_and_hertz_depth() {
    // e = 1 (no damping): a roller of m = 50 g meeting the face at
    // v₀ = 0.1 m/s rebounds at v₀ and reaches the Hertz depth
    // δ_max = (5 m v₀² / (4 K))^(2/5) (½ m v₀² = 2/5 K δ^(5/2)), with the
    // guide evaluated every 10 steps of 1 µs (10 µs, about a 47th of the
    // contact's 0.47 ms). Tolerances: speed 0.5 %, depth 1 %.
    let (m, v0, k) = (0.05f64, 0.1, 1e9);
    let expected = (5.0 * m * v0 * v0 / (4.0 * k)).powf(0.4);
    for every in [1, 10] {
        let mut g = flat(None, 0.0).every_steps(every);
        let (mut deepest, mut last_v) = (0.0f64, 0.0);
        drop_on(&mut g, m, 0.0, 1e-6, 0.0101, -v0, 2000, |d, v| {
            deepest = deepest.max(d);
            last_v = v;
        });
        assert!(
            (last_v - v0).abs() < 5e-3 * v0,
            "every {every}: rebound {last_v} m/s"
        );
        assert!(
            (deepest - expected).abs() < 1e-2 * expected,
            "every {every}: depth {deepest} m, Hertz {expected} m"
        );
    }
}

#[test]
fn a_roller_resting_under_load_settles_to_the_hertz_depth() {
    // m g = 0.4905 N on the face (K = 1e9, e = 0.1): at rest δ = (m g /
    // K)^(2/3) = 0.622 µm, with the guide evaluated every 10 µs (a
    // 130th of the contact's period at that load). Mean over the last
    // 10 ms of 0.3 s, within 0.5 %.
    let (m, grav) = (0.05f64, 9.81);
    let expected = (m * grav / 1e9).powf(2.0 / 3.0);
    let mut g = flat(None, 0.0).every_steps(10);
    g.params.law = law(1e9, 0.1);
    let (mut sum, mut count) = (0.0, 0);
    let steps = 300_000;
    let mut step = 0;
    drop_on(&mut g, m, grav, 1e-6, 0.01, 0.0, steps, |d, _| {
        step += 1;
        if step > steps - 10_000 {
            sum += d;
            count += 1;
        }
    });
    let mean = sum / f64::from(count);
    assert!(
        (mean - expected).abs() < 5e-3 * expected,
        "mean depth {mean} m, Hertz {expected} m"
    );
}

#[test]
fn guide_culling_changes_nothing() {
    // Oracle: a fixed guide that tests only the rollers kept near it
    // gives the bits of one that tests every roller, for a straight
    // face (its fast query) and one with ramps (the general query).
    // 300 rollers drift across the face's box and back at up to 3 m/s
    // (one in seven at up to 60 m/s),
    // some resting on it, with trial evaluations between the committed
    // ones; the fastest speed is the links' report, as in a run.
    let n = 300;
    let (model, mut state) = drive(3);
    for v in [&mut state.x, &mut state.y, &mut state.vx, &mut state.vy] {
        v.resize(n, 0.0);
    }
    let ramp = Ramp {
        length_m: 0.05,
        angle_rad: 0.1,
    };
    let bar = body_from_radius([0.0, 0.0], [1.0, 0.0], None).unwrap();
    for ramps in [None, Some(ramp)] {
        let face = Face::new(bar, 1.0, ramps, ramps);
        assert_eq!(face.straight().is_some(), ramps.is_none());
        let params = GuideParams {
            name: "g".into(),
            face,
            law: law(1e9, 0.5),
            friction: 0.3,
            slip_speed_m_s: 0.01,
            carrier: None,
        };
        let mut culled = GuideElement::new(params.clone(), n, 0.01);
        let mut every = GuideElement::new(params, n, 0.01).without_culling();
        // Deterministic scatter: x ∈ [−0.6, 1.6], y ∈ [−0.04, 0.06].
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for i in 0..n {
            state.x[i] = -0.6 + 2.2 * next();
            state.y[i] = if i % 5 == 0 {
                0.009
            } else {
                -0.04 + 0.1 * next()
            };
            // Some fast enough to cross the kept margin within the
            // longest skip: the speed bound, not the margin, keeps them.
            let top = if i % 7 == 0 { 60.0 } else { 3.0 };
            let (speed, angle) = (top * next(), std::f64::consts::TAU * next());
            (state.vx[i], state.vy[i]) = (speed * angle.cos(), speed * angle.sin());
        }
        state.t_s = 0.0;
        let dt = 2e-5;
        let mut in_contact = 0;
        for step in 0..3000 {
            let v_max = (0..n)
                .map(|i| state.vx[i].hypot(state.vy[i]))
                .fold(0.0, f64::max);
            let evaluate = |g: &mut GuideElement, state: &DriveState| {
                let mut out = Forces::new(n, 0, 0, 0);
                out.max_roller_speed_m_s = v_max;
                g.evaluate(&model, state, &mut out);
                out
            };
            if step % 3 == 0 {
                // A trial stage half a step on, not committed.
                let mut trial = state.clone();
                trial.t_s += 0.5 * dt;
                for i in 0..n {
                    trial.x[i] += 0.5 * dt * trial.vx[i];
                    trial.y[i] += 0.5 * dt * trial.vy[i];
                }
                let (a, b) = (evaluate(&mut culled, &trial), evaluate(&mut every, &trial));
                assert_eq!(a.fx, b.fx);
                assert_eq!(a.fy, b.fy);
            }
            let (a, b) = (evaluate(&mut culled, &state), evaluate(&mut every, &state));
            assert_eq!(a.fx, b.fx, "step {step}");
            assert_eq!(a.fy, b.fy, "step {step}");
            assert_eq!(a.contact_energy_j, b.contact_energy_j);
            assert_eq!(a.contact_damping_power_w, b.contact_damping_power_w);
            assert_eq!(culled.forces(), every.forces());
            in_contact += culled.forces().contacts;
            culled.commit();
            every.commit();
            assert_eq!(culled.onset, every.onset);
            // Drift on; turn back at the scatter's edges.
            state.t_s += dt;
            for i in 0..n {
                if !(-0.6..=1.6).contains(&state.x[i]) {
                    state.vx[i] = -state.vx[i];
                }
                if !(-0.04..=0.06).contains(&state.y[i]) {
                    state.vy[i] = -state.vy[i];
                }
                state.x[i] += dt * state.vx[i];
                state.y[i] += dt * state.vy[i];
            }
        }
        assert!(in_contact > 10_000, "{in_contact} contacts seen");
    }
}
