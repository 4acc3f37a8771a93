//! The fatigue check on whole runs: the summary's `fatigue` block where the
//! chain has a designation, none where it has not, and its numbers against
//! bounds from the run's own link-force extremes and the rating's formula
//! (docs/design-checks.md, "Fatigue").

use chaindrive::analysis::design::Life;
use chaindrive::analysis::{RunSummary, StatsWindow};
use chaindrive::scene::{L60MC_TOML, Overrides, Scene};
use chaindrive::sim::{SampleRate, Simulation};

/// The summary of `text` run for `duration_s`, statistics (and the
/// fatigue count) over its last `window_s`.
fn run(text: &str, duration_s: f64, window_s: f64) -> RunSummary {
    let scene = Scene::from_toml_with(
        text,
        &Overrides {
            duration_s: Some(duration_s),
            ..Overrides::default()
        },
    )
    .expect("valid scene");
    let mut sim = Simulation::new(&scene).expect("equilibrium");
    let sampling = SampleRate::new(1000.0, scene.solver().dt_s).expect("a whole number of steps");
    let window = StatsWindow::of(&scene, Some(window_s)).expect("window");
    let mut signals = window.observe(&mut sim, sampling.rate_hz);
    let out = sim
        .run(duration_s, sampling.every, &mut signals, None)
        .expect("run");
    RunSummary::of_run_in(&sim, &out, &signals, 0.0, &window)
}

/// The paper's drive with the ISO 606 56B-1 chain its dimensions match
/// (88.9 mm pitch, 54 mm rollers).
fn paper_56b() -> String {
    L60MC_TOML.replace(
        "rollers = 122\n",
        "rollers = 122\ndesignation = \"ISO 606 56B-1\"\n",
    )
}

/// The paper's drive at 120 rpm: link forces of 8–42 kN, far below the
/// 56B's fatigue limit of 60.4 kN (the rating's tension at 5·10⁶ cycles on
/// its 28-tooth tightener): infinite life. The largest counted cycle can be
/// no larger than the window's whole force range taken as one cycle,
/// F_max − F_min about their middle, mapped by Goodman onto the pulsating
/// line: F_ar = (ΔF/2) / (1 − F_m/F_u), F₀ = 2 F_ar / (1 + F_ar/F_u).
#[test]
fn the_papers_drive_at_120_rpm_has_an_infinite_fatigue_life() {
    let s = run(&paper_56b(), 1.6, 0.5);
    let f = s.fatigue.as_ref().expect("a fatigue block");
    assert_eq!(f.life_h, Life::Infinite);
    assert_eq!(f.damage_per_hour, 0.0);
    assert_eq!(f.links, 122);
    // The fatigue limit by hand: the link-plate rating H₁ = 0.004 N₁^1.08
    // n₁^0.9 p^(3 − 0.07 p) hp (p = 3.5 in) on the 28-tooth tightener at
    // the speed n₁ = 5·10⁶ · 120 / (15,000 · 60 · 28) = 23.8 rpm that gives
    // a link 5·10⁶ pulsating cycles in 15,000 h, over the chain speed
    // v = N₁ p n₁ / 60: 59.6 kW / 0.988 m/s = 60.4 kN.
    let n1: f64 = 5e6 * 120.0 / (15_000.0 * 60.0 * 28.0);
    let h1_w = 745.699_871_582_270_2
        * 0.004
        * 28f64.powf(1.08)
        * n1.powf(0.9)
        * 3.5f64.powf(3.0 - 0.07 * 3.5);
    let v_m_s = 28.0 * 0.0889 * n1 / 60.0;
    approx::assert_relative_eq!(f.fatigue_limit_n, h1_w / v_m_s, max_relative = 1e-9);
    approx::assert_relative_eq!(f.fatigue_limit_n, 60_370.0, max_relative = 1e-3);
    approx::assert_relative_eq!(f.counted_s, 0.5, max_relative = 1e-3);
    let (lo, hi) = (s.link_force_min_n.max(0.0), s.link_force_max_n);
    let fu = f.tensile_strength_n;
    let reversed = 0.5 * (hi - lo) / (1.0 - 0.5 * (hi + lo) / fu);
    let bound = 2.0 * reversed / (1.0 + reversed / fu);
    assert!(
        f.largest_cycle_n > 0.0 && f.largest_cycle_n <= bound * (1.0 + 1e-12),
        "{} against {bound}",
        f.largest_cycle_n
    );
    assert!(f.fatigue_safety_factor.expect("cycles") > 1.0);
    let json = serde_json::to_value(&s).expect("json");
    assert_eq!(json["fatigue"]["life_h"], "infinite");
    assert!(s.warnings.iter().all(|w| !w.starts_with("fatigue")));
}

/// The paper's drive as written has no designation, hence no tensile
/// strength: no count, no block, and the rating's note names the field.
#[test]
fn a_chain_without_designation_gets_no_fatigue_block() {
    let s = run(L60MC_TOML, 1.2, 0.1);
    assert!(s.fatigue.is_none());
    let notes = &s.rating.as_ref().expect("a rating").notes;
    assert!(
        notes
            .iter()
            .any(|n| n.contains("chain.designation") && n.contains("fatigue")),
        "{notes:?}"
    );
}

const MOTO: &str = include_str!("../data/moto_10b_15_44_560nm.toml");

/// The motorcycle drive at 4000 rpm and 560 N·m (80 kW on a 22.2 kN
/// chain): tight-strand tension alone 560 N·m over the 44-tooth wheel's
/// pitch radius 0.015875 / (2 sin(π/44)) = 0.1113 m, 5.03 kN, twice the
/// 10B's derived fatigue limit of 2.39 kN, so a finite life, a warning,
/// and the place of the damage named. Its largest cycle (impacts on the
/// engine sprocket add to the tension) is far above the limit, where the
/// S–N line lasts fewer than 10³ cycles: a note says the life is a sign
/// of overload, not an estimate.
#[test]
fn the_overloaded_motorcycle_drive_has_a_finite_life_and_a_warning() {
    let s = run(MOTO, 0.45, 0.2);
    let f = s.fatigue.as_ref().expect("a fatigue block");
    let hours = f.life_h.hours().expect("finite");
    assert!(hours > 0.0 && hours < 15_000.0, "{hours}");
    approx::assert_relative_eq!(hours * f.damage_per_hour, 1.0, max_relative = 1e-12);
    assert!(f.largest_cycle_n > f.fatigue_limit_n);
    let lasts = f.knee_cycles * (f.fatigue_limit_n / f.largest_cycle_n).powf(f.sn_slope);
    assert!(lasts < 1e3, "{lasts}");
    assert_eq!(
        lasts < 1e3,
        f.notes.iter().any(|n| n.contains("far overloaded")),
        "{lasts} cycles: {:?}",
        f.notes
    );
    let at = f.least_life_at.as_ref().expect("a place");
    assert!(at.damage_share > 0.0 && at.damage_share <= 1.0);
    assert!(at.segment.is_some() != at.sprocket.is_some(), "{at:?}");
    assert!(
        s.warnings
            .iter()
            .any(|w| w.starts_with("fatigue") && w.contains(&at.text)),
        "{:?}",
        s.warnings
    );
}

/// A scene's own S–N curve replaces the derived one, and a slope outside
/// what steels have is refused with its path.
#[test]
fn the_scenes_checks_give_their_own_curve_or_a_clear_error() {
    let own = format!("{MOTO}\n[checks]\nfatigue_limit_n = 50000.0\nsn_slope = 5.0\n");
    let s = run(&own, 0.3, 0.05);
    let f = s.fatigue.as_ref().expect("a fatigue block");
    assert_eq!((f.fatigue_limit_n, f.sn_slope), (50_000.0, 5.0));
    assert!(f.basis.contains("checks.fatigue_limit_n"), "{}", f.basis);
    assert_eq!(f.life_h, Life::Infinite);
    let bad = format!("{MOTO}\n[checks]\nsn_slope = 50.0\n");
    let e = Scene::from_toml(&bad).expect_err("refused").to_string();
    assert!(
        e.contains("checks.sn_slope") && e.contains("2 to 30"),
        "{e}"
    );
}
