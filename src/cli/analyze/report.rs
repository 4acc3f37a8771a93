//! `chaindrive analyze`'s report (Markdown): the run, a table per segment
//! and per sprocket, the chosen link and roller, what was left out, and the
//! figures drawn beside it.

use std::fmt::Write as _;

use crate::analysis::recorded::RecordedAnalysis;
use crate::analysis::units::si;

fn opt(v: Option<f64>, digits: usize) -> String {
    v.filter(|v| v.is_finite())
        .map_or_else(|| "—".to_owned(), |v| format!("{v:.digits$}"))
}

/// The report (Markdown): the run, a table per segment and per sprocket, the
/// chosen link and roller, what was left out, and the figures (file stem and
/// caption, drawn beside the report).
pub(super) fn report_markdown(a: &RecordedAnalysis, figures: &[(String, String)]) -> String {
    let mut md = String::new();
    run_section(&mut md, a);
    mesh_section(&mut md, a);
    segments_section(&mut md, a);
    sprockets_section(&mut md, a);
    link_roller_section(&mut md, a);
    figures_section(&mut md, figures);
    md
}

/// The title, the run and its windows.
fn run_section(md: &mut String, a: &RecordedAnalysis) {
    let _ = writeln!(md, "# Analysis of the recording `{}`\n", a.recording);
    let _ = writeln!(
        md,
        "Scene **{}**, {} profile, dt = {}, {} samples at {} Hz from {:.3} s to {:.3} s; \
         the run ended: {}. Channels: {}.\n",
        a.scene,
        a.profile,
        si(a.dt_s, "s"),
        a.samples,
        a.sample_rate_hz,
        a.run_s[0],
        a.run_s[1],
        a.end_status,
        a.channels.join(", ")
    );
    let _ = writeln!(
        md,
        "Statistics over [{:.3}, {:.3}] s, spectra over [{:.3}, {:.3}] s, contacts over \
         [{:.3}, {:.3}] s. Static tension of the rebuilt drive {:.1} N (rest length {:.7} m); \
         mean chain speed {:.3} m/s, centrifugal tension q_c = {:.1} N. Link force over the \
         window's samples: {} … {} N.\n",
        a.window_s[0],
        a.window_s[1],
        a.spectrum_window_s[0],
        a.spectrum_window_s[1],
        a.contact_window_s[0],
        a.contact_window_s[1],
        a.static_tension_n,
        a.rest_length_m,
        a.chain_speed_m_s,
        a.q_c_n,
        opt(a.link_force_min_sampled_n, 1),
        opt(a.link_force_max_sampled_n, 1)
    );
}

/// The run's tooth jumps and tip rides, as its detectors recorded them.
fn mesh_section(md: &mut String, a: &RecordedAnalysis) {
    let jumps = crate::analysis::warnings::tooth_jumps(&a.tooth_jumps);
    let rides = crate::analysis::warnings::tip_rides(&a.tip_rides);
    if jumps.is_none() && rides.is_none() {
        let _ = writeln!(
            md,
            "**Mesh:** the recording lists no tooth jump and no roller riding a tip.\n"
        );
        return;
    }
    for line in jumps.into_iter().chain(rides) {
        let _ = writeln!(md, "**Mesh:** {line}.\n");
    }
}

/// A table of the segments.
fn segments_section(md: &mut String, a: &RecordedAnalysis) {
    let _ = writeln!(md, "## Segments\n");
    let _ = writeln!(
        md,
        "Average link force over the free strand's links; transverse displacement of the \
         strand's middle. `moving string`: f₁ = (1/2l) c (1 − V²/c²), c² = F/μ, from the \
         segment's own mean force; `(52)`: the string at rest.\n"
    );
    let _ = writeln!(
        md,
        "| segment | length (m) | mean link force (N) | peak-to-peak (N) | amplitude (N) | transverse peak 1–50 Hz (Hz) | moving string (Hz) | peak vs string | (52) (Hz) | transverse amplitude | spectral peaks 1–200 Hz (amplitude) |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|---|");
    for s in &a.segments {
        let vs = if s.string_f1_hz > 0.0 && s.transverse_peak_hz > 0.0 {
            format!(
                "{:+.1} %",
                100.0 * (s.transverse_peak_hz - s.string_f1_hz) / s.string_f1_hz
            )
        } else {
            "—".to_owned()
        };
        let peaks: Vec<String> = s
            .peaks
            .iter()
            .take(4)
            .map(|(f, amp)| format!("{f:.1} Hz ({})", si(*amp, "m")))
            .collect();
        let _ = writeln!(
            md,
            "| {} | {:.4} | {} | {} | {} | {:.2} | {:.2} | {} | {:.2} | {} | {} |",
            s.segment,
            s.length_m,
            opt(s.mean_link_force_n, 1),
            opt(s.link_force_p2p_n, 1),
            opt(s.link_force_amplitude_n, 1),
            s.transverse_peak_hz,
            s.string_f1_hz,
            vs,
            s.string_52_hz,
            si(s.transverse_amplitude_m, "m"),
            if peaks.is_empty() {
                "none".to_owned()
            } else {
                peaks.join(", ")
            }
        );
    }
    md.push('\n');
}

/// A table of the sprockets.
fn sprockets_section(md: &mut String, a: &RecordedAnalysis) {
    let _ = writeln!(md, "## Sprockets\n");
    let _ = writeln!(
        md,
        "Contact forces against Binder's (49) (consistent form; q_a, q_b, q_c, nb, t_s, t_e \
         from each complete contact, see `crate::analysis::paper_probes::binder_comparison`). \
         Polygonal action: the strand-speed variation 1 − cos(π/nt) at constant ω.\n"
    );
    let _ = writeln!(
        md,
        "| sprocket | teeth | mean speed (rad/s) | speed p2p (rad/s) | mean chain moment | polygonal 1 − cos(π/nt) | contacts | RMS vs (49) (N) | RMS of (49) (N) | relative | RMS vs printed (49) (N) | example nb, q_a, q_b, q_c (N) |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|---|---|");
    for s in &a.sprockets {
        let tail = match (&s.binder, &s.binder_note) {
            (Some(b), _) => format!(
                "{} | {:.1} | {:.1} | {:.0} % | {:.1} | {}, {:.0}, {:.0}, {:.0}",
                b.contacts,
                b.rms_n,
                b.binder_rms_n,
                100.0 * b.rms_n / b.binder_rms_n.max(1e-9),
                b.printed_rms_n,
                b.bedded,
                b.q_a_n,
                b.q_b_n,
                b.q_c_n
            ),
            (None, note) => format!(
                "— | {} | | | | ",
                note.as_deref().unwrap_or("no comparison")
            ),
        };
        let _ = writeln!(
            md,
            "| {} | {} | {:.4} | {:.4} | {} | {:.5} | {tail} |",
            s.sprocket,
            s.teeth,
            s.mean_speed_rad_s,
            s.speed_p2p_rad_s,
            si(s.mean_torque_n_m, "N·m"),
            s.polygonal_variation
        );
    }
    md.push('\n');
}

/// The chosen link and roller, what was left out, and what a recording
/// cannot report.
fn link_roller_section(md: &mut String, a: &RecordedAnalysis) {
    if let Some(l) = &a.link {
        let _ = writeln!(
            md,
            "Link {} (roller {} to {}): mean {:.1} N, {:.1} … {:.1} N over the statistics window.\n",
            l.link,
            l.link,
            l.link + 1,
            l.mean_n,
            l.min_n,
            l.max_n
        );
    }
    if let Some(r) = &a.roller {
        let on: Vec<String> = r.sprockets.iter().map(ToString::to_string).collect();
        let _ = writeln!(
            md,
            "Roller {} over [{:.3}, {:.3}] s: largest contact force {:.1} N, in contact {:.0} % \
             of the samples, sprockets touched: {}.\n",
            r.roller,
            r.window_s[0],
            r.window_s[1],
            r.max_n,
            100.0 * r.in_contact,
            if on.is_empty() {
                "none".to_owned()
            } else {
                on.join(", ")
            }
        );
    }
    if !a.notes.is_empty() {
        let _ = writeln!(md, "## Left out\n");
        for n in &a.notes {
            let _ = writeln!(md, "- {n}");
        }
        md.push('\n');
    }
    let _ = writeln!(
        md,
        "Not in a recording, so not reported: wall times, step counts, the largest \
         penetration, bearing forces (they need every step; a recording holds samples).\n"
    );
}

/// The figures drawn beside the report.
fn figures_section(md: &mut String, figures: &[(String, String)]) {
    if !figures.is_empty() {
        let _ = writeln!(md, "## Figures\n");
        for (stem, caption) in figures {
            let _ = writeln!(md, "**{stem}**: {caption}\n\n![{caption}]({stem}.png)\n");
        }
    }
}
