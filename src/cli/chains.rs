//! `chaindrive chains`: the table of chains by designation
//! (`crate::scene::designations`), with each value's source.

use std::io::Write;
use std::process::ExitCode;

use crate::scene::designations::{DESIGNATIONS, Designation};

/// Arguments of `chaindrive chains`.
#[derive(clap::Args)]
pub(super) struct ChainsArgs {
    /// Print one designation only (any spelling: "16B", "ANSI 80").
    name: Option<String>,
}

pub(super) fn chains(args: ChainsArgs) -> anyhow::Result<ExitCode> {
    let rows: Vec<&Designation> = match &args.name {
        Some(name) => match crate::scene::designations::find(name) {
            Some(d) => vec![d],
            None => {
                eprintln!(
                    "unknown designation \"{name}\"; nearest: {}",
                    crate::scene::designations::nearest(name, 3).join(", ")
                );
                return Ok(ExitCode::FAILURE);
            }
        },
        None => DESIGNATIONS.iter().collect(),
    };
    quiet_on_closed_pipe(print_rows(&rows))?;
    Ok(ExitCode::SUCCESS)
}

/// Writes the table and, row by row, where its values come from.
fn print_rows(rows: &[&Designation]) -> std::io::Result<()> {
    let mut out = std::io::stdout().lock();
    writeln!(
        out,
        "designation    pitch_mm  roller_d_mm  inner_w_mm  pin_d_mm  plate_h_mm  plate_t_mm  mass_kg_m  tensile_kn  roller_mass_kg  stiffness_n_m"
    )?;
    for d in rows {
        writeln!(
            out,
            "{:<13}  {:>8.3}  {:>11.2}  {:>10.2}  {:>8.2}  {:>10.2}  {:>10.2}  {:>9.3}  {:>10.1}  {:>14.5}  {:>13.3e}",
            d.name,
            d.pitch_m * 1e3,
            d.roller_diameter_m * 1e3,
            d.inner_width_m * 1e3,
            d.pin_diameter_m * 1e3,
            d.plate_depth_m * 1e3,
            d.plate_thickness_m * 1e3,
            d.mass_per_m_kg,
            d.tensile_strength_n * 1e-3,
            d.roller_mass_kg(),
            d.stiffness_n_m()
        )?;
    }
    writeln!(out)?;
    writeln!(out, "sources:")?;
    for d in rows {
        let s = &d.sources;
        writeln!(out, "  {}:", d.name)?;
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
        writeln!(out, "    mass per metre: {}", s.mass)?;
        writeln!(out, "    tensile strength: {}", s.strength)?;
    }
    writeln!(
        out,
        "  stiffness (every row): {}",
        Designation::stiffness_source()
    )?;
    writeln!(
        out,
        "  ANSI 25 and 35 are bush chains: their roller diameter is the bush's. In a scene, chain.designation fills pitch_m, roller_radius_m, roller_mass_kg (mass per metre x pitch), stiffness_n_m and pin_radius_m; a field written in the scene overrides it."
    )?;
    Ok(())
}

/// A closed pipe on stdout (`chaindrive chains | head`) ends the listing
/// cleanly: the reader has what it wanted. Any other write error stands.
pub(crate) fn quiet_on_closed_pipe(written: std::io::Result<()>) -> std::io::Result<()> {
    match written {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        other => other,
    }
}
