//! The fatigue check on whole runs: the summary's `fatigue` block where the
//! chain has a designation, none where it has not, and its numbers against
//! bounds from the run's own link-force extremes and the rating's formula
//! (docs/design-checks.md, "Fatigue"). The blocks are read as a user reads
//! them: in the summary's JSON.

use serde_json::Value;

use chaindrive::analysis::{RunSummary, StatsWindow};
use chaindrive::scene::{L60MC_TOML, Overrides, Scene};
use chaindrive::sim::{SampleRate, Simulation};

/// The summary of `text` run for `duration_s`, statistics (and the
/// fatigue count) over its last `window_s`, as its JSON.
fn run(text: &str, duration_s: f64, window_s: f64) -> Value {
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
    let summary = RunSummary::of_run_in(&sim, &out, &signals, 0.0, &window);
    serde_json::to_value(&summary).expect("a summary is JSON")
}

/// A number of the summary's JSON at `path` ("fatigue/life_h").
fn num(v: &Value, path: &str) -> f64 {
    v.pointer(&format!("/{path}"))
        .and_then(Value::as_f64)
        .unwrap_or_else(|| panic!("{path} is a number in {v}"))
}

/// The summary's warnings.
fn warnings(v: &Value) -> Vec<String> {
    v["warnings"]
        .as_array()
        .map(|w| {
            w.iter()
                .filter_map(|x| x.as_str().map(str::to_owned))
                .collect()
        })
        .unwrap_or_default()
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
    assert_eq!(s["fatigue"]["life_h"], "infinite");
    assert_eq!(num(&s, "fatigue/damage_per_hour"), 0.0);
    assert_eq!(num(&s, "fatigue/links"), 122.0);
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
    let limit = num(&s, "fatigue/fatigue_limit_n");
    approx::assert_relative_eq!(limit, h1_w / v_m_s, max_relative = 1e-9);
    approx::assert_relative_eq!(limit, 60_370.0, max_relative = 1e-3);
    approx::assert_relative_eq!(num(&s, "fatigue/counted_s"), 0.5, max_relative = 1e-3);
    let (lo, hi) = (
        num(&s, "link_force_min_n").max(0.0),
        num(&s, "link_force_max_n"),
    );
    let fu = num(&s, "fatigue/tensile_strength_n");
    let reversed = 0.5 * (hi - lo) / (1.0 - 0.5 * (hi + lo) / fu);
    let bound = 2.0 * reversed / (1.0 + reversed / fu);
    let largest = num(&s, "fatigue/largest_cycle_n");
    assert!(
        largest > 0.0 && largest <= bound * (1.0 + 1e-12),
        "{largest} against {bound}"
    );
    assert!(num(&s, "fatigue/fatigue_safety_factor") > 1.0);
    assert!(warnings(&s).iter().all(|w| !w.starts_with("fatigue")));
}

/// The paper's drive as written has no designation, hence no tensile
/// strength: no count, no block, and the rating's note names the field.
#[test]
fn a_chain_without_designation_gets_no_fatigue_block() {
    let s = run(L60MC_TOML, 1.2, 0.1);
    assert!(
        s.get("fatigue").is_none_or(Value::is_null),
        "{}",
        s["fatigue"]
    );
    let notes = s["rating"]["notes"].as_array().expect("the rating's notes");
    assert!(
        notes
            .iter()
            .filter_map(Value::as_str)
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
    let hours = num(&s, "fatigue/life_h");
    assert!(hours > 0.0 && hours < 15_000.0, "{hours}");
    approx::assert_relative_eq!(
        hours * num(&s, "fatigue/damage_per_hour"),
        1.0,
        max_relative = 1e-12
    );
    let (largest, limit) = (
        num(&s, "fatigue/largest_cycle_n"),
        num(&s, "fatigue/fatigue_limit_n"),
    );
    assert!(largest > limit);
    let lasts =
        num(&s, "fatigue/knee_cycles") * (limit / largest).powf(num(&s, "fatigue/sn_slope"));
    assert!(lasts < 1e3, "{lasts}");
    let notes = &s["fatigue"]["notes"];
    assert_eq!(
        lasts < 1e3,
        notes.as_array().is_some_and(|n| n
            .iter()
            .filter_map(Value::as_str)
            .any(|n| n.contains("far overloaded"))),
        "{lasts} cycles: {notes}"
    );
    let at = &s["fatigue"]["least_life_at"];
    let share = num(at, "damage_share");
    assert!(share > 0.0 && share <= 1.0);
    assert!(
        at.get("segment").is_some() != at.get("sprocket").is_some(),
        "{at}"
    );
    let text = at["text"].as_str().expect("in words");
    assert!(
        warnings(&s)
            .iter()
            .any(|w| w.starts_with("fatigue") && w.contains(text)),
        "{:?}",
        warnings(&s)
    );
}

/// A scene's own S–N curve replaces the derived one, and a slope outside
/// what steels have is refused with its path, as is a fatigue limit at or
/// above the chain's tensile strength (the 10B's 22.2 kN): a pulsating load
/// of that peak breaks the chain at once.
#[test]
fn the_scenes_checks_give_their_own_curve_or_a_clear_error() {
    let own = format!("{MOTO}\n[checks]\nfatigue_limit_n = 20000.0\nsn_slope = 5.0\n");
    let s = run(&own, 0.3, 0.05);
    assert_eq!(
        (
            num(&s, "fatigue/fatigue_limit_n"),
            num(&s, "fatigue/sn_slope")
        ),
        (20_000.0, 5.0)
    );
    let above = format!("{MOTO}\n[checks]\nfatigue_limit_n = 50000.0\n");
    let e = Scene::from_toml(&above).expect_err("refused").to_string();
    assert!(
        e.contains("checks.fatigue_limit_n") && e.contains("tensile strength of 22.2 kN"),
        "{e}"
    );
    let basis = s["fatigue"]["basis"].as_str().expect("a basis");
    assert!(basis.contains("checks.fatigue_limit_n"), "{basis}");
    assert_eq!(s["fatigue"]["life_h"], "infinite");
    let bad = format!("{MOTO}\n[checks]\nsn_slope = 50.0\n");
    let e = Scene::from_toml(&bad).expect_err("refused").to_string();
    assert!(
        e.contains("checks.sn_slope") && e.contains("2 to 30"),
        "{e}"
    );
}

const HEAVY_80H: &str = include_str!("../data/designation_80h.toml");

/// An ANSI 80H drive (Donghua's heavy duty table: 56.7 kN) run as a user
/// would, its rating and safety factors against hand values. The 19-tooth
/// driver at 300 rpm, p = 1 in: H₁ = 0.004 · 19^1.08 · 300^0.9 hp =
/// 0.004 · 24.048 · 169.59 = 16.314 hp = 12.165 kW, the standard 80's (the
/// heavy plates are not credited); H₂ = 17,000 · 19^1.5 / 300^1.5 = 271 hp.
/// Transmitted: 600 N·m at 150 rpm (15.708 rad/s) = 9.425 kW, margin
/// 12.165 / 9.425 = 1.291. The tight strand carries the load over the
/// 38-tooth pitch radius 25.4 mm / (2 sin(π/38)) = 153.79 mm, 3,901 N, on
/// top of the slack strand's tension; the largest link force is at least
/// that, so the static safety factor is at most 56.7 / 3.901 = 14.5.
#[test]
fn a_heavy_chain_drive_is_rated_and_checked_by_hand() {
    let s = run(HEAVY_80H, 0.6, 0.3);
    let r = &s["rating"];
    assert_eq!(r["designation"], "ANSI 80H");
    let basis = r["basis"].as_str().expect("a basis");
    assert!(basis.contains("heavy"), "{basis}");
    approx::assert_relative_eq!(
        num(r, "link_plate_limited_power_w"),
        12_165.0,
        max_relative = 1e-3
    );
    approx::assert_relative_eq!(num(r, "rated_power_w"), 12_165.0, max_relative = 1e-3);
    approx::assert_relative_eq!(num(r, "margin"), 1.291, max_relative = 0.01);
    assert_eq!(num(r, "tensile_strength_n"), 56_700.0);
    let sf = num(r, "static_safety_factor");
    approx::assert_relative_eq!(
        sf,
        56_700.0 / num(&s, "link_force_max_n"),
        max_relative = 1e-9
    );
    assert!(sf > 1.0 && sf <= 56_700.0 / 3_901.0, "{sf}");
    // The strands' mean forces: tight minus slack is the load over the
    // pitch radius, 3,901 N, within 1 %.
    let means: Vec<f64> = (0..2)
        .map(|i| num(&s, &format!("segments/{i}/mean_link_force_n")))
        .collect();
    let (slack, tight) = (means[0].min(means[1]), means[0].max(means[1]));
    approx::assert_relative_eq!(tight - slack, 3_901.0, max_relative = 0.01);
}

const MOTO_520: &str = include_str!("../data/moto_520_15_45.toml");

/// A 520 motorcycle drive named by its designation builds and runs, with
/// the mass, stiffness and strength its scene writes (the 520 row has the
/// pitch and roller only). Rated as the ANSI 50: the 15-tooth engine
/// sprocket at 2653 rpm, p = 0.625 in: H₁ = 0.004 · 15^1.08 · 2653^0.9 ·
/// 0.625^(3 − 0.04375) hp = 0.004 · 18.630 · 1205.6 · 0.24923 = 22.39 hp
/// = 16.70 kW; H₂ = 17,000 · 15^1.5 · 0.625^0.8 / 2653^1.5 =
/// 17,000 · 58.095 · 0.68659 / 136,649 = 4.962 hp = 3.700 kW, which
/// governs. The 78 N·m on the wheel over the 45-tooth pitch radius
/// 15.875 mm / (2 sin(π/45)) = 113.75 mm is 685.7 N between the strands'
/// mean forces; the static safety factor is the written 36.5 kN over the
/// largest link force.
#[test]
fn a_520_drive_by_designation_runs_and_is_checked_on_its_written_strength() {
    let s = run(MOTO_520, 0.8, 0.4);
    let r = &s["rating"];
    assert_eq!(r["designation"], "520");
    let basis = r["basis"].as_str().expect("a basis");
    assert!(
        basis.contains("motorcycle") && basis.contains("ANSI 50"),
        "{basis}"
    );
    approx::assert_relative_eq!(
        num(r, "link_plate_limited_power_w"),
        16_697.0,
        max_relative = 2e-3
    );
    approx::assert_relative_eq!(num(r, "rated_power_w"), 3_700.3, max_relative = 3e-3);
    assert_eq!(num(r, "tensile_strength_n"), 36_500.0);
    approx::assert_relative_eq!(
        num(r, "static_safety_factor"),
        36_500.0 / num(&s, "link_force_max_n"),
        max_relative = 1e-9
    );
    assert_eq!(num(&s, "fatigue/tensile_strength_n"), 36_500.0);
    let means: Vec<f64> = (0..2)
        .map(|i| num(&s, &format!("segments/{i}/mean_link_force_n")))
        .collect();
    let (slack, tight) = (means[0].min(means[1]), means[0].max(means[1]));
    approx::assert_relative_eq!(tight - slack, 685.7, max_relative = 0.02);
}
