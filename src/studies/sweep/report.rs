//! What a sweep's cases are judged by: the resonance crossings (where an
//! excitation order meets a span's predicted natural frequency, and whether
//! the response peaks there), order cuts, the worst-case speeds, every
//! scalar of a case for `sweep.csv`, and whether a case's run doubts its own
//! numbers ([`CaseFlags`]: its summary's warnings, segments that are not
//! stationary). Pure functions of the cases: nothing here runs a simulation
//! or writes a file.

use std::fmt::Write as _;

use super::{CaseOutcome, CaseResult, SpanFrequencies, TRANSVERSE_MODES, driver_of};
use crate::analysis::orders::OrderSet;
use crate::scene::Scene;

/// Which natural frequency of a span.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SpanMode {
    /// The moving string's transverse mode n (1-based).
    Transverse(u32),
    /// The first axial mode.
    Axial,
}

impl SpanMode {
    /// `transverse n` or `axial`.
    pub(crate) fn name(&self) -> String {
        match self {
            Self::Transverse(n) => format!("transverse {n}"),
            Self::Axial => "axial".to_owned(),
        }
    }

    /// The signal that responds to this mode in segment `segment` (1-based).
    pub(crate) fn response_signal(&self, segment: usize) -> String {
        match self {
            Self::Transverse(_) => format!("seg{segment}_transverse_m"),
            Self::Axial => format!("seg{segment}_link_force_n"),
        }
    }

    fn of(&self, span: &SpanFrequencies) -> f64 {
        match self {
            Self::Transverse(n) => span
                .transverse_hz
                .get(*n as usize - 1)
                .copied()
                .unwrap_or(0.0),
            Self::Axial => span.axial_hz,
        }
    }
}

/// Where an excitation order's frequency meets a span's predicted natural
/// frequency between two swept speeds.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Crossing {
    /// 1-based segment.
    pub segment: usize,
    /// The mode.
    pub mode: SpanMode,
    /// The excitation order.
    pub order: f64,
    /// The crossing's speed, linearly interpolated between the two cases, rpm.
    pub rpm: f64,
    /// The frequency there, Hz.
    pub frequency_hz: f64,
    /// The signal whose order amplitude is the response.
    pub signal: String,
    /// The case of largest response among the two around the crossing and
    /// their neighbours, rpm.
    pub peak_rpm: f64,
    /// Its amplitude.
    pub peak_amplitude: f64,
    /// Whether the response peaks there ([`judge_peak`]).
    pub verdict: PeakVerdict,
    /// `verdict` is [`PeakVerdict::Peaks`].
    pub response_peaks: bool,
}

/// How far the response at a crossing must exceed the median of the
/// order's response over the sweep for a resonance.
pub(crate) const PEAK_MEDIAN_FACTOR: f64 = 1.5;

/// The coarsest grid that resolves a crossing: the speeds on either side of
/// it at most this fraction of its rpm apart.
pub(crate) const GRID_RESOLUTION: f64 = 0.05;

/// Whether the response peaks at a crossing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PeakVerdict {
    /// A resonance: the larger response of the two speeds around the
    /// crossing is a local maximum over its neighbours and at least
    /// [`PEAK_MEDIAN_FACTOR`] × the median response over the sweep.
    Peaks,
    /// The grid resolves the crossing, and the response does not peak there.
    NoPeak,
    /// The speeds around the crossing are more than [`GRID_RESOLUTION`] of
    /// its rpm apart, or one of them has no neighbour beyond it (the edge of
    /// the sweep): the grid cannot tell.
    NotResolved,
}

impl PeakVerdict {
    /// As written in the report.
    pub(crate) fn describe(&self) -> &'static str {
        match self {
            Self::Peaks => "yes",
            Self::NoPeak => "no",
            Self::NotResolved => "not resolved by the grid",
        }
    }
}

/// Judges the `response` at speeds `rpm` (ascending, one each) at a crossing
/// at `crossing_rpm` ([`PeakVerdict`]); returns the verdict and the index
/// of the larger response of the two speeds around the crossing.
pub(crate) fn judge_peak(rpm: &[f64], response: &[f64], crossing_rpm: f64) -> (PeakVerdict, usize) {
    let n = rpm.len().min(response.len());
    if n < 2 {
        return (PeakVerdict::NotResolved, 0);
    }
    // The two speeds around the crossing.
    let i = rpm[..n]
        .partition_point(|&r| r < crossing_rpm)
        .clamp(1, n - 1);
    let j = if response[i] >= response[i - 1] {
        i
    } else {
        i - 1
    };
    let step = rpm[i] - rpm[i - 1];
    if j == 0 || j + 1 >= n || step > GRID_RESOLUTION * crossing_rpm.abs() {
        return (PeakVerdict::NotResolved, j);
    }
    let mut sorted: Vec<f64> = response[..n].to_vec();
    sorted.sort_by(f64::total_cmp);
    let median = if n % 2 == 1 {
        sorted[n / 2]
    } else {
        0.5 * (sorted[n / 2 - 1] + sorted[n / 2])
    };
    let peaks = response[j] >= response[j - 1]
        && response[j] >= response[j + 1]
        && response[j] > PEAK_MEDIAN_FACTOR * median;
    (
        if peaks {
            PeakVerdict::Peaks
        } else {
            PeakVerdict::NoPeak
        },
        j,
    )
}

/// The completed cases, in speed order.
pub fn completed(cases: &[CaseOutcome]) -> Vec<&CaseResult> {
    let mut done: Vec<&CaseResult> = cases
        .iter()
        .filter_map(|c| match c {
            CaseOutcome::Done(r) => Some(r.as_ref()),
            CaseOutcome::Failed { .. } => None,
        })
        .collect();
    done.sort_by(|a, b| a.rpm.total_cmp(&b.rpm));
    done
}

/// The amplitude of `order` in `signal` of each case (0 where absent).
pub(crate) fn order_cut(cases: &[&CaseResult], signal: &str, order: f64) -> Vec<f64> {
    cases
        .iter()
        .map(|c| {
            c.signal(signal)
                .and_then(|s| s.at(order))
                .map_or(0.0, |o| o.amplitude)
        })
        .collect()
}

/// Every crossing of an order in `orders` with a span's predicted natural
/// frequency (transverse modes 1..=[`TRANSVERSE_MODES`] and axial) between
/// consecutive completed cases, and whether the response peaks there.
pub(crate) fn resonance_crossings(cases: &[CaseOutcome], orders: &[f64]) -> Vec<Crossing> {
    let done = completed(cases);
    let spans = done.first().map_or(0, |c| c.spans.len());
    let modes: Vec<SpanMode> = (1..=TRANSVERSE_MODES)
        .map(SpanMode::Transverse)
        .chain([SpanMode::Axial])
        .collect();
    let mut found = Vec::new();
    for k in 0..spans {
        for mode in &modes {
            for &order in orders {
                let gap = |c: &CaseResult| {
                    let f = c.spans.get(k).map_or(0.0, |s| mode.of(s));
                    (f > 0.0).then_some(order * c.rev_per_s - f)
                };
                for i in 1..done.len() {
                    let (a, b) = (done[i - 1], done[i]);
                    let (Some(ga), Some(gb)) = (gap(a), gap(b)) else {
                        continue;
                    };
                    if ga.signum() == gb.signum() && ga != 0.0 {
                        continue;
                    }
                    let w = if ga == gb { 0.0 } else { ga / (ga - gb) };
                    let rpm = a.rpm + w * (b.rpm - a.rpm);
                    let rev = a.rev_per_s + w * (b.rev_per_s - a.rev_per_s);
                    let segment = k + 1;
                    let signal = mode.response_signal(segment);
                    let cut = order_cut(&done, &signal, order);
                    let speeds: Vec<f64> = done.iter().map(|c| c.rpm).collect();
                    let (verdict, j) = judge_peak(&speeds, &cut, rpm);
                    found.push(Crossing {
                        segment,
                        mode: *mode,
                        order,
                        rpm,
                        frequency_hz: order * rev,
                        signal,
                        peak_rpm: done[j].rpm,
                        peak_amplitude: cut[j],
                        verdict,
                        response_peaks: verdict == PeakVerdict::Peaks,
                    });
                }
            }
        }
    }
    found
}

/// The excitation orders searched for crossings and drawn on a Campbell
/// diagram, in cycles per driver revolution, ascending: 1, 2, the driver's
/// tooth count (the meshing order) and twice it, and the scene's own
/// excitation. The driver's speed harmonics and a governed driver's torque
/// harmonics are orders of the driver as they stand; a load harmonic of
/// order k on sprocket i is order k·z_d/z_i of the driver (the sprocket turns
/// z_d/z_i times per driver revolution); a load table (or a governed
/// driver's torque table) adds its largest harmonic among the first
/// [`TABLE_HARMONICS`] and every other one at least half as large, so scaled.
pub(crate) fn excitation_orders(scene: &Scene) -> Vec<f64> {
    let sprockets = scene.sprockets();
    let driver_teeth = driver_of(scene)
        .map(|(i, _)| f64::from(sprockets[i].teeth))
        .unwrap_or(1.0);
    let mut orders = vec![1.0, 2.0, driver_teeth, 2.0 * driver_teeth];
    for s in sprockets {
        let ratio = driver_teeth / f64::from(s.teeth.max(1));
        let e = &s.excitation;
        let mut own: Vec<f64> = e
            .speed_harmonics
            .iter()
            .chain(&e.load_harmonics)
            .map(|h| f64::from(h.order))
            .collect();
        own.extend(e.load_table.as_ref().map_or_else(Vec::new, table_orders));
        if let Some(g) = &e.governor {
            own.extend(g.drive_harmonics.iter().map(|h| f64::from(h.order)));
            own.extend(g.drive_table.as_ref().map_or_else(Vec::new, table_orders));
        }
        orders.extend(own.into_iter().map(|k| k * ratio));
    }
    orders.retain(|k| k.is_finite() && *k > 0.0);
    orders.sort_by(f64::total_cmp);
    orders.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * b.abs().max(1.0));
    orders
}

/// Harmonics of a load table weighed by [`excitation_orders`].
pub(crate) const TABLE_HARMONICS: u32 = 12;

/// The orders (per revolution of its sprocket) of a periodic table's
/// largest harmonic among the first [`TABLE_HARMONICS`] and of every other
/// one at least half as large: amplitudes |c_k| of the table's piecewise
/// linear interpolation over its 360°, integrated exactly segment by
/// segment. A constant table has none.
fn table_orders(table: &crate::scene::LoadTable) -> Vec<f64> {
    let (a, t) = (&table.angles_rad, &table.torques_n_m);
    let amplitude = |k: f64| {
        // ∫ T(θ) e^{-ikθ} dθ over each linear piece [θ0, θ1], T = T0 + s (θ − θ0).
        let (mut re, mut im) = (0.0, 0.0);
        for j in 1..a.len().min(t.len()) {
            let (x0, x1, y0, y1) = (a[j - 1], a[j], t[j - 1], t[j]);
            let h = x1 - x0;
            if h <= 0.0 {
                continue;
            }
            let s = (y1 - y0) / h;
            // F(x) = ∫ (y0 + s (x − x0)) e^{-ikx} dx = e^{-ikx} [ i (y0 + s (x − x0))/k + s/k² ]
            let f = |x: f64| {
                let y = y0 + s * (x - x0);
                let (c, sn) = ((k * x).cos(), (k * x).sin());
                // e^{-ikx} = c − i sn; times (s/k² + i y/k)
                let (pr, pi) = (s / (k * k), y / k);
                (c * pr + sn * pi, c * pi - sn * pr)
            };
            let (r1, i1) = f(x1);
            let (r0, i0) = f(x0);
            re += r1 - r0;
            im += i1 - i0;
        }
        re.hypot(im) / std::f64::consts::PI
    };
    let amps: Vec<(f64, f64)> = (1..=TABLE_HARMONICS)
        .map(|k| (f64::from(k), amplitude(f64::from(k))))
        .collect();
    let largest = amps.iter().map(|&(_, c)| c).fold(0.0, f64::max);
    if !(largest > 0.0 && largest.is_finite()) {
        return Vec::new();
    }
    amps.into_iter()
        .filter(|&(_, c)| c >= 0.5 * largest)
        .map(|(k, _)| k)
        .collect()
}

/// `orders` split into those on `set`'s grid (a multiple of its step, up to
/// its largest order), whose amplitudes the analysis gives, and the others.
pub(crate) fn on_order_grid(orders: &[f64], set: &OrderSet) -> (Vec<f64>, Vec<f64>) {
    let d = f64::from(set.denominator());
    orders.iter().partition(|&&k| {
        let n = k * d;
        (n - n.round()).abs() <= 1e-6 && k <= set.max_order() * (1.0 + 1e-12)
    })
}

/// A worst case: where a statistic of the sweep is at its extreme.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct WorstCase {
    /// What.
    pub statistic: String,
    /// The case's speed, rpm.
    pub rpm: f64,
    /// The value, in `unit`.
    pub value: f64,
    /// Its SI unit: `N`, `m`, `rad/s`.
    pub unit: &'static str,
}

/// A speed RMS at or below this fraction of the driver's speed is the
/// rounding of a speed held constant, not a fluctuation (a driver at a
/// prescribed speed: ~10⁻¹⁷ of it).
const HELD_SPEED_RMS: f64 = 1e-9;

/// The 0-based sprockets whose speed RMS is rounding at every completed
/// case ([`HELD_SPEED_RMS`] of the driver's speed): held at a prescribed
/// speed, so they have no worst case.
pub(crate) fn held_sprockets(cases: &[CaseOutcome]) -> Vec<usize> {
    let done = completed(cases);
    let sprockets = done.first().map_or(0, |c| c.speed_rms_rad_s.len());
    (0..sprockets)
        .filter(|&s| {
            done.iter().all(|c| {
                let omega = c.rpm.abs() * std::f64::consts::TAU / 60.0;
                c.speed_rms_rad_s
                    .get(s)
                    .is_some_and(|rms| *rms <= HELD_SPEED_RMS * omega)
            })
        })
        .collect()
}

/// The speeds of the largest link force, the smallest link force, the
/// largest contact force, the largest penetration and each sprocket's
/// largest speed fluctuation (RMS), but for the sprockets held at a
/// prescribed speed ([`held_sprockets`]).
pub(crate) fn worst_cases(cases: &[CaseOutcome]) -> Vec<WorstCase> {
    let done = completed(cases);
    let pick =
        |statistic: &str, unit: &'static str, value: &dyn Fn(&CaseResult) -> f64, largest: bool| {
            done.iter()
                .map(|c| (c.rpm, value(c)))
                .filter(|(_, v)| v.is_finite())
                .reduce(|a, b| {
                    let better = if largest { b.1 > a.1 } else { b.1 < a.1 };
                    if better { b } else { a }
                })
                .map(|(rpm, value)| WorstCase {
                    statistic: statistic.to_owned(),
                    rpm,
                    value,
                    unit,
                })
        };
    let mut out = vec![
        pick("largest link force", "N", &|c| c.link_force_max_n, true),
        pick("smallest link force", "N", &|c| c.link_force_min_n, false),
        pick(
            "largest contact force",
            "N",
            &|c| c.max_contact_force_n,
            true,
        ),
        pick("largest penetration", "m", &|c| c.max_penetration_m, true),
    ];
    let sprockets = done.first().map_or(0, |c| c.speed_rms_rad_s.len());
    let held = held_sprockets(cases);
    for s in (0..sprockets).filter(|s| !held.contains(s)) {
        out.push(pick(
            &format!("sprocket {} speed RMS", s + 1),
            "rad/s",
            &|c| c.speed_rms_rad_s.get(s).copied().unwrap_or(f64::NAN),
            true,
        ));
    }
    out.into_iter().flatten().collect()
}

/// What a case's run says of its own numbers.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseFlags {
    /// The case's speed, rpm.
    pub rpm: f64,
    /// `ok`: its run finished with no warning and every segment
    /// stationary; `warned`: a warning or a segment that is not stationary
    /// (its numbers are in doubt); `failed`: it did not finish;
    /// `not judged`: a run-up's window, which has no run summary.
    pub status: &'static str,
    /// Whether every segment's statistics are stationary (`None` without a
    /// run summary).
    pub stationary: Option<bool>,
    /// The 1-based segments that are not stationary.
    pub not_stationary: Vec<usize>,
    /// The run summary's warnings (`None` without a run summary).
    pub warnings: Option<Vec<String>>,
    /// Why a failed case failed.
    pub error: Option<String>,
}

impl CaseFlags {
    /// The flags of `case`.
    pub fn of(case: &CaseOutcome) -> Self {
        match case {
            CaseOutcome::Failed { rpm, message } => Self {
                rpm: *rpm,
                status: "failed",
                stationary: None,
                not_stationary: Vec::new(),
                warnings: None,
                error: Some(message.clone()),
            },
            CaseOutcome::Done(r) => Self::of_result(r),
        }
    }

    /// The flags of a complete case.
    pub(crate) fn of_result(r: &CaseResult) -> Self {
        let Some(summary) = &r.summary else {
            return Self {
                rpm: r.rpm,
                status: "not judged",
                stationary: None,
                not_stationary: Vec::new(),
                warnings: None,
                error: None,
            };
        };
        let not_stationary: Vec<usize> = summary
            .segments
            .iter()
            .filter(|s| !s.stationary)
            .map(|s| s.segment)
            .collect();
        let warned = !(summary.warnings.is_empty() && not_stationary.is_empty());
        Self {
            rpm: r.rpm,
            status: if warned { "warned" } else { "ok" },
            stationary: Some(not_stationary.is_empty()),
            not_stationary,
            warnings: Some(summary.warnings.clone()),
            error: None,
        }
    }

    /// Whether the case's numbers are in doubt (`warned`).
    pub(crate) fn warned(&self) -> bool {
        self.status == "warned"
    }
}

/// `## Runs to doubt` of a sweep's `report.md`: the speeds whose run warned
/// or has a segment that is not stationary ([`CaseFlags`]), each with its
/// warnings (Markdown); empty when no case has a run summary (a run-up).
pub(crate) fn doubt_section(cases: &[CaseOutcome]) -> String {
    let mut s = String::new();
    let flagged: Vec<CaseFlags> = cases
        .iter()
        .map(CaseFlags::of)
        .filter(CaseFlags::warned)
        .collect();
    if cases.iter().all(|c| CaseFlags::of(c).stationary.is_none()) {
        return s;
    }
    let _ = writeln!(s, "## Runs to doubt\n");
    if flagged.is_empty() {
        let _ = writeln!(
            s,
            "Every run finished without a warning, each segment's statistics stationary over its window.\n"
        );
        return s;
    }
    let _ = writeln!(
        s,
        "{} of {} speeds ran with a warning or with a segment whose mean drifts over the window (not stationary): their numbers below, in the tables and in the figures are in doubt.\n",
        flagged.len(),
        cases.len()
    );
    let _ = writeln!(s, "| rpm | not stationary | warnings |\n|---|---|---|");
    for f in &flagged {
        let segments = if f.not_stationary.is_empty() {
            "—".to_owned()
        } else {
            f.not_stationary
                .iter()
                .map(|k| format!("segment {k}"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let warnings = f
            .warnings
            .as_deref()
            .unwrap_or_default()
            .join("<br>")
            .replace('|', "\\|");
        let _ = writeln!(s, "| {} | {segments} | {warnings} |", f.rpm);
    }
    let _ = writeln!(s);
    s
}

/// Every scalar of a case's run summary as `(name, value)`: numbers as they
/// are, booleans as 0/1, per-segment and per-sprocket fields as
/// `segment{k}.field` / `sprocket{i}.field` (1-based), arrays of numbers as
/// `field[i]`; the tooth jumps as their number, `tooth_jump_count`, the
/// tip rides as theirs, `tip_ride_count`;
/// `warning_count` (the summary's warnings) and `warned` (1 when
/// the run warned or a segment is not stationary, [`CaseFlags`]); then the
/// sweep's own: `max_contact_force_n`, `rev_per_s`.
/// A run-up's window has no run summary: its own statistics take its place
/// (`link_force_min_n`, `link_force_max_n`, `max_penetration_m`,
/// `segment{k}.mean_link_force_n`, `.min_link_force_n`, `.max_link_force_n`,
/// `sprocket{i}.speed_rms_rad_s`, `speed_change`, `revolutions`).
/// Non-finite values are left out.
pub fn summary_scalars(case: &CaseResult) -> Vec<(String, f64)> {
    let mut out = Vec::new();
    match &case.summary {
        Some(summary) => {
            if let Ok(value) = serde_json::to_value(summary) {
                flatten("", &value, &mut out);
            }
            // One name per jump would repeat names (two jumps on one
            // sprocket): the count stands for the list.
            out.retain(|(name, _)| {
                !name.starts_with("tooth_jumps.") && !name.starts_with("tip_rides.")
            });
            let jumps = summary.tooth_jumps.len() as f64;
            out.push(("tooth_jump_count".to_owned(), jumps));
            let rides: usize = summary.tip_rides.iter().map(|r| r.count).sum();
            out.push(("tip_ride_count".to_owned(), rides as f64));
            out.push(("warning_count".to_owned(), summary.warnings.len() as f64));
            let warned = CaseFlags::of_result(case).warned();
            out.push(("warned".to_owned(), f64::from(u8::from(warned))));
        }
        None => {
            out.push(("link_force_min_n".to_owned(), case.link_force_min_n));
            out.push(("link_force_max_n".to_owned(), case.link_force_max_n));
            out.push(("max_penetration_m".to_owned(), case.max_penetration_m));
            for (k, (mean, range)) in case
                .segment_mean_n
                .iter()
                .zip(&case.segment_range_n)
                .enumerate()
            {
                let k = k + 1;
                out.push((format!("segment{k}.mean_link_force_n"), *mean));
                out.push((format!("segment{k}.min_link_force_n"), range.0));
                out.push((format!("segment{k}.max_link_force_n"), range.1));
            }
            for (i, rms) in case.speed_rms_rad_s.iter().enumerate() {
                out.push((format!("sprocket{}.speed_rms_rad_s", i + 1), *rms));
            }
            out.push(("speed_change".to_owned(), case.speed_change));
            out.push(("revolutions".to_owned(), case.revolutions as f64));
        }
    }
    out.push(("max_contact_force_n".to_owned(), case.max_contact_force_n));
    out.push(("rev_per_s".to_owned(), case.rev_per_s));
    out.retain(|(_, v)| v.is_finite());
    out
}

fn flatten(prefix: &str, value: &serde_json::Value, out: &mut Vec<(String, f64)>) {
    use serde_json::Value;
    match value {
        Value::Number(n) => {
            if let Some(v) = n.as_f64().filter(|v| v.is_finite()) {
                out.push((prefix.to_owned(), v));
            }
        }
        Value::Bool(b) => out.push((prefix.to_owned(), f64::from(u8::from(*b)))),
        Value::Object(map) => {
            for (k, v) in map {
                let name = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                flatten(&name, v, out);
            }
        }
        Value::Array(items) => {
            for (i, item) in items.iter().enumerate() {
                let numbered = ["segment", "sprocket"].iter().find_map(|key| {
                    item.get(*key)
                        .and_then(Value::as_u64)
                        .map(|n| format!("{key}{n}"))
                });
                let name = match numbered {
                    // `segments` → `segment3`, `strands` → `strand…` keep their own key.
                    Some(n) if prefix == "segments" || prefix == "sprockets" => n,
                    Some(n) => format!("{prefix}.{n}"),
                    None => format!("{prefix}[{i}]"),
                };
                flatten(&name, item, out);
            }
        }
        Value::String(_) | Value::Null => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A completed case at `rpm` whose sprockets' speed RMS are `rms`.
    fn case(rpm: f64, rms: &[f64]) -> CaseOutcome {
        CaseOutcome::Done(Box::new(CaseResult {
            rpm,
            summary: None,
            speed_change: 0.0,
            segment_mean_n: vec![1000.0],
            link_force_min_n: 500.0,
            link_force_max_n: 1500.0 + rpm,
            max_penetration_m: 1e-5,
            speed_rms_rad_s: rms.to_vec(),
            rev_per_s: rpm / 60.0,
            revolutions: 4,
            max_contact_force_n: 2000.0,
            segment_range_n: vec![(900.0, 1100.0)],
            orders: Vec::new(),
            spans: Vec::new(),
        }))
    }

    #[test]
    fn a_sprocket_at_a_prescribed_speed_has_no_speed_worst_case() {
        // Sprocket 1 is the driver at a prescribed speed: its RMS is the
        // rounding of a constant (1e-17 of 1000 rpm's 104.7 rad/s), a
        // governed driver's or a driven sprocket's a real fluctuation.
        let cases = [
            case(1000.0, &[1.0e-15, 0.02, 3.0e-7]),
            case(2000.0, &[2.0e-15, 0.05, 1.0e-7]),
        ];
        assert_eq!(held_sprockets(&cases), vec![0]);
        let names: Vec<String> = worst_cases(&cases)
            .into_iter()
            .map(|w| w.statistic)
            .collect();
        assert!(
            !names.iter().any(|n| n == "sprocket 1 speed RMS"),
            "{names:?}"
        );
        let two = worst_cases(&cases)
            .into_iter()
            .find(|w| w.statistic == "sprocket 2 speed RMS")
            .expect("sprocket 2 listed");
        assert_eq!((two.rpm, two.value), (2000.0, 0.05));
        // 3e-7 rad/s at 1000 rpm is 2.9e-9 of the driver's speed: a
        // fluctuation, however small, and listed.
        assert!(
            names.iter().any(|n| n == "sprocket 3 speed RMS"),
            "{names:?}"
        );
    }
}
