//! The analysis: spectra of synthetic signals, Binder's formulas against
//! values computed by hand, and `chaindrive reproduce` end to end.

use crate::analysis::binder::{
    BinderInputs, beta, centrifugal_tension_n, placement_times_s, pressure_angle_rad,
    printed_contact_forces, printed_link_forces,
};
use crate::analysis::paper_probes::{Series, spectrum_with_peaks};
use approx::{abs_diff_eq, assert_abs_diff_eq};
use std::f64::consts::PI;

#[test]
fn spectrum_finds_a_known_sines_frequency_and_amplitude() {
    // 5.5 Hz at 2 mm and 83 Hz at 0.5 mm, 8 s at 1 kHz, on an offset.
    let rate = 1000.0;
    let t: Vec<f64> = (0..8000).map(|i| f64::from(i) / rate).collect();
    let s = Series {
        value: t
            .iter()
            .map(|t| {
                2e-3 * (2.0 * PI * 5.5 * t).sin() + 0.5e-3 * (2.0 * PI * 83.0 * t).cos() + 0.01
            })
            .collect(),
        t_s: t,
    };
    let p = spectrum_with_peaks(&s, rate, [1.0, 200.0], 2, 2.0);
    assert_eq!(p.peaks.len(), 2);
    let (f1, a1) = p.peaks[0];
    let (f2, a2) = p.peaks[1];
    // Bin width 0.125 Hz; Hann window: the peak bin holds the amplitude within a few percent.
    assert_abs_diff_eq!(f1, 5.5, epsilon = 0.125);
    assert_abs_diff_eq!(a1, 2e-3, epsilon = 0.05 * 2e-3);
    assert_abs_diff_eq!(f2, 83.0, epsilon = 0.125);
    assert_abs_diff_eq!(a2, 0.5e-3, epsilon = 0.05 * 0.5e-3);
    assert!(
        p.amplitude.iter().all(|a| a.is_finite()),
        "no NaN in the spectrum"
    );
}

/// β computed independently: α = 35° − 120°/nt in degrees, φ = 360°/nt.
fn beta_by_hand(nt: f64) -> (f64, f64, f64) {
    let alpha = (35.0 - 120.0 / nt) * PI / 180.0;
    let phi = 2.0 * PI / nt;
    (alpha.sin() / (alpha + phi).sin(), alpha, phi)
}

#[test]
fn binder_formulas_match_hand_computed_values() {
    // nt = 60: α = 33°, φ = 6°, β = sin 33° / sin 39° = 0.544639 / 0.629320 = 0.865440.
    assert_abs_diff_eq!(pressure_angle_rad(60), 33f64.to_radians(), epsilon = 1e-15);
    assert_abs_diff_eq!(beta(60), 0.865_440, epsilon = 1e-6);
    // nt = 30: α = 31°, φ = 12°: sin 31° / sin 43° = 0.515038 / 0.681998 = 0.755190.
    assert_abs_diff_eq!(beta(30), 0.755_190, epsilon = 1e-6);
    // nt = 28: α = 30.714286°, φ = 12.857143°: sin / sin = 0.510757 / 0.689258 = 0.741024.
    assert_abs_diff_eq!(beta(28), 0.741_024, epsilon = 1e-6);
    // q_c = m_r V²/P: 3.01 × (12.566 × 0.849325)² / 0.0889 = 3.86 kN
    // (docs/model.md, “Binder's quasi-static contact forces”).
    let v = 4.0 * PI * 0.849_325;
    assert_abs_diff_eq!(
        centrifugal_tension_n(3.01, v, 0.0889),
        3857.0,
        epsilon = 10.0
    );

    for (nt, nb) in [(60u32, 33usize), (30, 6), (28, 15)] {
        let (b, alpha, phi) = beta_by_hand(f64::from(nt));
        let (qa, qb, qc) = (25_000.0, 19_000.0, 3_860.0);
        let inputs = BinderInputs {
            teeth: nt,
            bedded: nb,
            q_a_n: qa,
            q_b_n: qb,
            q_c_n: qc,
        };
        // Explicit products β·β·…·β, not powi.
        let pow = |k: usize| (0..k).fold(1.0, |acc, _| acc * b);
        let ratio = phi.sin() / (alpha + phi).sin();
        let fc = inputs.contact_forces();
        assert_eq!(fc.len(), nb);
        for i in 1..=nb {
            let expect = ((qa - qc) * pow(i - 1) + (qb - qc) * pow(nb - i)) * ratio;
            assert!(
                abs_diff_eq!(fc[i - 1], expect, epsilon = 1e-9 * expect.abs().max(1.0)),
                "nt {nt} i {i}: {} vs {expect}",
                fc[i - 1]
            );
            let printed =
                (qa * pow(i - 1) + qb * pow(nb - i)) * ratio + 2.0 * qc * (phi / 2.0).sin();
            let p = printed_contact_forces(&inputs)[i - 1];
            assert!(
                abs_diff_eq!(p, printed, epsilon = 1e-9 * printed),
                "nt {nt} i {i}: {p} vs {printed}"
            );
        }
        let fl = inputs.link_forces();
        assert_eq!(fl.len(), nb + 1);
        for (i, f) in fl.iter().enumerate() {
            let expect = (qa - qc) * pow(i) + (qb - qc) * pow(nb - i) + qc;
            assert!(
                abs_diff_eq!(*f, expect, epsilon = 1e-9 * expect),
                "nt {nt} link {i}: {f} vs {expect}"
            );
        }
        // Boundary links carry the strand tensions (to within the other side's decayed share).
        assert_abs_diff_eq!(fl[0] - qa, (qb - qc) * pow(nb), epsilon = 1e-6);
        let pl = printed_link_forces(&inputs);
        assert_eq!(pl.len(), nb);
        assert_abs_diff_eq!(pl[0], qa * b + qb * pow(nb) + qc, epsilon = 1e-6);
        // Equilibrium of a bedded roller (consistent form): consecutive links differ by
        // the tangential share of its contact force; with q_b = q_c the link force
        // above q_c decays by exactly β per roller from the entering side.
        let one_sided = BinderInputs {
            q_b_n: qc,
            ..inputs
        }
        .link_forces();
        for i in 1..=nb {
            let r = (one_sided[i] - qc) / (one_sided[i - 1] - qc);
            assert!(abs_diff_eq!(r, b, epsilon = 1e-12), "nt {nt} link {i}: {r}");
        }
    }
    // (51): t_i = t_s + (i − 1)(t_e − t_s)/(nb − 1).
    let t = placement_times_s(9.3, 9.6, 4);
    for (i, ti) in t.iter().enumerate() {
        assert_abs_diff_eq!(*ti, 9.3 + i as f64 * 0.1, epsilon = 1e-12);
    }
}

#[cfg(all(feature = "figures", feature = "lab"))]
#[test]
fn bad_indices_and_windows_are_clear_errors_and_draw_nothing() {
    use crate::analysis::figures::{FigureChoice, Mark, Plot, Trace, paper_figures, save};
    use crate::analysis::paper_probes::{
        AnalysisError, link_force_series, roller_contact_series, segment_force_series,
    };
    use crate::studies::reproduce::run_scene;
    let data =
        run_scene("circular", &crate::test_support::l60mc(0.2), 1000.0, None).expect("short run");
    let e = segment_force_series(&data, 5, [0.0, 0.2]).expect_err("segment 5");
    assert_eq!(
        e,
        AnalysisError::UnknownSegment {
            segment: 5,
            count: 4
        }
    );
    assert!(e.to_string().contains("segments 1 to 4"));
    assert!(segment_force_series(&data, 0, [0.0, 0.2]).is_err());
    let e = roller_contact_series(&data, 122, [0.0, 0.2]).expect_err("roller 122");
    assert!(e.to_string().contains("unknown roller 122"), "{e}");
    let e = link_force_series(&data, 3, [0.1, 5.0]).expect_err("window");
    assert!(matches!(e, AnalysisError::Window { .. }), "{e}");
    assert!(link_force_series(&data, 3, [0.05, 0.15]).is_ok());

    let dir = tempfile::tempdir().expect("tmp");
    // An unknown roller: Fig. 22 fails with the index in the message and is not written.
    let e = paper_figures(
        &[&data],
        FigureChoice {
            link: 0,
            roller: 999,
        },
        dir.path(),
    )
    .expect_err("roller 999");
    assert!(
        e.to_string().contains("fig22") && e.to_string().contains("999"),
        "{e}"
    );
    assert!(!dir.path().join("fig22_roller_contact.png").exists());
    // A plot with nothing finite is an error, and no file appears.
    let empty = Plot {
        title: "nothing".into(),
        traces: vec![Trace {
            label: "nan".into(),
            points: vec![(f64::NAN, 1.0), (0.0, f64::INFINITY)],
            mark: Mark::Line,
            color: 0,
        }],
        ..Plot::default()
    };
    assert!(save(&empty, dir.path(), "empty").is_err());
    assert!(!dir.path().join("empty.png").exists() && !dir.path().join("empty.svg").exists());
}

#[test]
fn link_force_range_avx2_and_plain_agree_to_the_bit() {
    // The AVX2 build of the link-force range returns the plain four-lane
    // fold's bits, signed zeros and NaNs included, for every length 0–13
    // (whole chunks and each remainder), and both equal the smallest and
    // largest value picked by hand.
    #[cfg(target_arch = "x86_64")]
    {
        use super::{range_of_avx2, range_of_plain};
        if !std::arch::is_x86_feature_detected!("avx2") {
            return;
        }
        let values = [
            3.5,
            -0.0,
            f64::NAN,
            0.0,
            -7.25,
            12.0,
            f64::NAN,
            -0.0,
            1e300,
            -1e-300,
            0.0,
            -7.25,
            4.0,
        ];
        for n in 0..=values.len() {
            let v = &values[..n];
            // SAFETY: the CPU has AVX2, checked above.
            let (lo, hi) = unsafe { range_of_avx2(v) };
            let (plo, phi) = range_of_plain(v);
            assert_eq!(lo.to_bits(), plo.to_bits(), "low of {n}");
            assert_eq!(hi.to_bits(), phi.to_bits(), "high of {n}");
        }
        let (lo, hi) = range_of_plain(&values);
        assert_eq!((lo, hi), (-7.25, 1e300));
    }
}
