//! A sweep's Campbell diagram as data: one signal's order amplitudes at each
//! speed, the excitation orders' lines (the meshing ones marked), and each
//! span's predicted natural frequencies named by the sprockets it joins.
//! Drawing is [`crate::analysis::figures::save_campbell`]'s; this module only
//! gathers what it draws, and names the sweep's signals in words and units.

use super::{CaseResult, driver_of};
use crate::analysis::figures::{Campbell, OrderLine, SpanLines};
use crate::scene::Scene;

/// A sweep signal in words and its SI unit: `seg1_link_force_n` is
/// ("segment 1 link force", "N"), `seg2_transverse_m` ("segment 2
/// transverse displacement", "m"), `omega_3_rad_s` ("sprocket 3 speed",
/// "rad/s"), `max_contact_force_n` ("largest contact force", "N"). Another
/// name is kept as it is, with no unit.
pub fn describe_signal(signal: &str) -> (String, &'static str) {
    let numbered = |prefix: &str, suffix: &str| {
        signal
            .strip_prefix(prefix)
            .and_then(|rest| rest.strip_suffix(suffix))
            .filter(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
    };
    if let Some(k) = numbered("seg", "_link_force_n") {
        (format!("segment {k} link force"), "N")
    } else if let Some(k) = numbered("seg", "_transverse_m") {
        (format!("segment {k} transverse displacement"), "m")
    } else if let Some(i) = numbered("omega_", "_rad_s") {
        (format!("sprocket {i} speed"), "rad/s")
    } else if signal == "max_contact_force_n" {
        ("largest contact force".to_owned(), "N")
    } else {
        (signal.to_owned(), "")
    }
}

/// Whether `order` is a meshing order: a whole multiple of the driver's
/// tooth count `teeth`.
fn is_meshing(order: f64, teeth: f64) -> bool {
    let m = order / teeth;
    teeth > 0.0 && m >= 1.0 - 1e-9 && (m - m.round()).abs() <= 1e-9 * m.max(1.0)
}

/// The Campbell diagram of `signal` over the completed `cases` (in speed
/// order): its order amplitudes as markers, the `excitation` orders' lines
/// and each span's transverse and axial frequencies; `max_hz` ends the
/// frequency axis (`None`: [`Campbell::default_max_hz`]).
pub fn campbell(
    scene: &Scene,
    cases: &[&CaseResult],
    signal: &str,
    excitation: &[f64],
    max_hz: Option<f64>,
) -> Campbell {
    let (response, unit) = describe_signal(signal);
    let sprockets = scene.sprockets();
    let teeth = driver_of(scene).map_or(0.0, |(i, _)| f64::from(sprockets[i].teeth));
    let orders = excitation
        .iter()
        .map(|&k| OrderLine {
            order: k,
            meshing: is_meshing(k, teeth),
            points: cases.iter().map(|c| (c.rpm, k * c.rev_per_s)).collect(),
        })
        .collect();
    // The strands' ends, from the first run summary (a run-up's windows have none).
    let strands = cases
        .iter()
        .find_map(|c| c.summary.as_ref())
        .map(|s| s.strands.clone())
        .unwrap_or_default();
    let name = |i: usize| {
        sprockets
            .get(i.wrapping_sub(1))
            .map_or_else(|| format!("sprocket {i}"), |s| s.name.clone())
    };
    let spans = cases.first().map_or(0, |c| c.spans.len());
    let spans = (0..spans)
        .map(|k| {
            let label = strands.iter().find(|s| s.segment == k + 1).map_or_else(
                || format!("span {}", k + 1),
                |s| format!("span {}: {} → {}", k + 1, name(s.from), name(s.to)),
            );
            let modes = cases.first().map_or(0, |c| c.spans[k].transverse_hz.len());
            let along = |f: &dyn Fn(&CaseResult) -> Option<f64>| -> Vec<(f64, f64)> {
                cases
                    .iter()
                    .map(|c| (c.rpm, f(c).unwrap_or(f64::NAN)))
                    .collect()
            };
            SpanLines {
                label,
                transverse: (0..modes)
                    .map(|n| along(&|c| c.spans.get(k)?.transverse_hz.get(n).copied()))
                    .collect(),
                axial: along(&|c| c.spans.get(k).map(|s| s.axial_hz)),
            }
        })
        .collect();
    Campbell {
        title: format!("Campbell diagram: {response}"),
        points: cases
            .iter()
            .filter_map(|c| c.signal(signal).map(|s| (c.rpm, s)))
            .flat_map(|(rpm, s)| {
                s.components
                    .iter()
                    .map(move |o| (rpm, o.frequency_hz, o.amplitude))
            })
            .collect(),
        response,
        unit: unit.to_owned(),
        orders,
        spans,
        max_hz,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signals_are_named_in_words_with_their_unit() {
        assert_eq!(
            describe_signal("seg12_link_force_n"),
            ("segment 12 link force".to_owned(), "N")
        );
        assert_eq!(
            describe_signal("seg1_transverse_m"),
            ("segment 1 transverse displacement".to_owned(), "m")
        );
        assert_eq!(
            describe_signal("omega_2_rad_s"),
            ("sprocket 2 speed".to_owned(), "rad/s")
        );
        assert_eq!(describe_signal("segx_link_force_n").1, "");
    }

    #[test]
    fn meshing_orders_are_whole_multiples_of_the_drivers_teeth() {
        assert!(is_meshing(20.0, 20.0));
        assert!(is_meshing(40.0, 20.0));
        assert!(!is_meshing(4.0, 20.0));
        assert!(!is_meshing(30.0, 20.0));
        assert!(!is_meshing(20.0, 0.0));
    }
}
