//! `chaindrive chains`: the table of chains by designation
//! (`chaindrive::scene::designations`), with each value's source.

use std::process::ExitCode;

use chaindrive::scene::designations::{DESIGNATIONS, Designation};

/// Arguments of `chaindrive chains`.
#[derive(clap::Args)]
pub struct ChainsArgs {
    /// Print one designation only (any spelling: "16B", "ANSI 80").
    name: Option<String>,
}

pub fn chains(args: ChainsArgs) -> anyhow::Result<ExitCode> {
    let rows: Vec<&Designation> = match &args.name {
        Some(name) => match chaindrive::scene::designations::find(name) {
            Some(d) => vec![d],
            None => {
                eprintln!(
                    "unknown designation \"{name}\"; nearest: {}",
                    chaindrive::scene::designations::nearest(name, 3).join(", ")
                );
                return Ok(ExitCode::FAILURE);
            }
        },
        None => DESIGNATIONS.iter().collect(),
    };
    println!(
        "designation    pitch_mm  roller_d_mm  pin_d_mm  plate_h_mm  plate_t_mm  mass_kg_m  roller_mass_kg  stiffness_n_m"
    );
    for d in &rows {
        println!(
            "{:<13}  {:>8.3}  {:>11.2}  {:>8.2}  {:>10.2}  {:>10.2}  {:>9.2}  {:>14.5}  {:>13.3e}",
            d.name,
            d.pitch_m * 1e3,
            d.roller_diameter_m * 1e3,
            d.pin_diameter_m * 1e3,
            d.plate_depth_m * 1e3,
            d.plate_thickness_m * 1e3,
            d.mass_per_m_kg,
            d.roller_mass_kg(),
            d.stiffness_n_m()
        );
    }
    println!();
    println!("sources:");
    let mut seen: Vec<(&str, &str)> = Vec::new();
    for d in &rows {
        if !seen.contains(&(d.dimension_source, d.mass_source)) {
            seen.push((d.dimension_source, d.mass_source));
        }
    }
    for (dims, mass) in seen {
        println!("  pitch, roller, pin diameters, plate depth: {dims}");
        println!("  mass per metre, plate thickness: {mass}");
    }
    println!("  stiffness: {}", Designation::stiffness_source());
    println!(
        "  ANSI 25 and 35 are bush chains: their roller diameter is the bush's. In a scene, chain.designation fills pitch_m, roller_radius_m, roller_mass_kg (mass per metre x pitch), stiffness_n_m and pin_radius_m; a field written in the scene overrides it."
    );
    Ok(ExitCode::SUCCESS)
}
