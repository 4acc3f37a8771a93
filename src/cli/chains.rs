//! `chaindrive chains`: the table of chains by designation
//! (`crate::scene::designations`), with each value's source.

use std::io::Write;
use std::process::ExitCode;

use crate::scene::designations::{
    self, DESIGNATIONS, Designation, MAX_STRANDS, Stranded, transverse_pitch_m,
};

/// Arguments of `chaindrive chains`.
#[derive(clap::Args)]
pub(super) struct ChainsArgs {
    /// Print one designation only (any spelling: "16B", "ANSI 80", "80-2").
    name: Option<String>,
}

pub(super) fn chains(args: ChainsArgs) -> anyhow::Result<ExitCode> {
    let rows: Vec<Stranded> = match &args.name {
        Some(name) => match designations::lookup(name) {
            Ok(d) => vec![d],
            Err(e) => {
                eprintln!("{e}");
                return Ok(ExitCode::FAILURE);
            }
        },
        None => DESIGNATIONS
            .iter()
            .map(|single| Stranded { single, strands: 1 })
            .collect(),
    };
    quiet_on_closed_pipe(print_rows(&rows))?;
    Ok(ExitCode::SUCCESS)
}

/// Writes the table and, row by row, where its values come from.
fn print_rows(rows: &[Stranded]) -> std::io::Result<()> {
    let mut out = std::io::stdout().lock();
    writeln!(
        out,
        "designation      pitch_mm  roller_d_mm  inner_w_mm  pin_d_mm  plate_h_mm  plate_t_mm  mass_kg_m  tensile_kn  roller_mass_kg  stiffness_n_m"
    )?;
    for c in rows {
        let d = c.single;
        let mm = |v: Option<f64>| known(v.map(|m| format!("{:.2}", m * 1e3)));
        writeln!(
            out,
            "{:<15}  {:>8.3}  {:>11.2}  {:>10.2}  {:>8}  {:>10}  {:>10}  {:>9}  {:>10}  {:>14}  {:>13}",
            c.name(),
            d.pitch_m * 1e3,
            d.roller_diameter_m * 1e3,
            d.inner_width_m * 1e3,
            mm(d.pin_diameter_m),
            mm(d.plate_depth_m),
            mm(d.plate_thickness_m),
            known(c.mass_per_m_kg().map(|q| format!("{q:.3}"))),
            known(c.tensile_strength_n().map(|f| format!("{:.1}", f * 1e-3))),
            known(c.roller_mass_kg().map(|m| format!("{m:.5}"))),
            known(c.stiffness_n_m().map(|k| format!("{k:.3e}")))
        )?;
    }
    writeln!(
        out,
        "(-: no published value read; a scene naming the chain gives the field it would fill)"
    )?;
    writeln!(out)?;
    writeln!(out, "sources:")?;
    for c in rows {
        let s = &c.single.sources;
        writeln!(out, "  {}:", c.name())?;
        writeln!(
            out,
            "    pitch, roller diameter, inner width: {}",
            s.dimensions
        )?;
        writeln!(
            out,
            "    pin diameter, plate depth: {}",
            s.pin_and_plate_depth
        )?;
        writeln!(out, "    plate thickness: {}", s.plate_thickness)?;
        writeln!(out, "    mass per metre: {}", c.derived(s.mass))?;
        writeln!(
            out,
            "    tensile strength: {}",
            if c.strands == 1 {
                s.strength.to_owned()
            } else {
                format!(
                    "{}, as the minimum strengths of multiple-strand chains are printed in the U.S. Tsubaki RS catalogue (RS50-2 to -6: n x 4,880 lbs) and the Mecha ISO/ASA catalogue (16A-2, 16A-3: n x 56,700 N)",
                    c.derived(s.strength)
                )
            }
        )?;
        if c.strands > 1 {
            writeln!(
                out,
                "    stiffness: n x the single strand's estimate (strands in parallel on common pins)"
            )?;
            writeln!(
                out,
                "    rating: the single strand's times the multiple-strand factor {} (not {}); the derived fatigue limit likewise",
                crate::analysis::design::rating::strand_factor(c.strands).unwrap_or(1.0),
                c.strands
            )?;
            match transverse_pitch_m(c.single) {
                Some(pt) => writeln!(
                    out,
                    "    transverse pitch (strand spacing): {:.2} mm (PEER ANSI double-strand table; listed only, the planar model does not use it)",
                    pt * 1e3
                )?,
                None => writeln!(out, "    transverse pitch: no table read for this size")?,
            }
        }
    }
    writeln!(
        out,
        "  stiffness (every row): {}",
        Designation::stiffness_source()
    )?;
    writeln!(
        out,
        "  ANSI 25 and 35 are bush chains: their roller diameter is the bush's. In a scene, chain.designation fills pitch_m, roller_radius_m, roller_mass_kg (mass per metre x pitch), stiffness_n_m, pin_radius_m and tensile_strength_n where its row has them; a field written in the scene overrides it."
    )?;
    writeln!(
        out,
        "  Motorcycle chains 520, 525, 530: single strand only; rated as the ANSI 50 (the same pitch and roller; docs/design-checks.md, \"Chain data\"). Their rows hold pitch, roller, inner width (and the 520's plate depth): a scene gives roller_mass_kg, stiffness_n_m and tensile_strength_n from its maker's data."
    )?;
    writeln!(
        out,
        "  Multiple strands: add -2 to -{MAX_STRANDS} to a name (\"ANSI 80-2\", \"16B-3\"; not ANSI 41): mass, stiffness and tensile strength n times the single strand's, the rating times 1.7, 2.5 or 3.3 (`chaindrive chains 80-2` shows one)."
    )?;
    Ok(())
}

/// A value as printed, or "-" where the row has none.
fn known(value: Option<String>) -> String {
    value.unwrap_or_else(|| "-".to_owned())
}

/// A closed pipe on stdout (`chaindrive chains | head`) ends the listing
/// cleanly: the reader has what it wanted. Any other write error stands.
pub(crate) fn quiet_on_closed_pipe(written: std::io::Result<()>) -> std::io::Result<()> {
    match written {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        other => other,
    }
}
