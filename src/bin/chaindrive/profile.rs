//! `chaindrive profile`: a sprocket's tooth outline (CSV) or its dimension table.
//!
//! Public contract: the outline of a whole sprocket in its own frame, gap 0's
//! seating centre at (R_s, 0), gaps numbered counter-clockwise; CSV columns
//! `x_m,y_m,gap,area`, every piece sampled, arcs at ≤ 0.5° steps; areas 1–7 as
//! in docs/tooth-profile.md, “Construction”, for the real profile, 4 (seating
//! arcs) and 0 (the segments joining them) for the circular one.

use std::io::Write;
use std::process::ExitCode;

use chaindrive::geometry::asa::AsaProfile;
use chaindrive::geometry::{CircularProfile, OutlinePoint, ProfileKind};

/// Arguments of `chaindrive profile`.
#[derive(clap::Args)]
pub struct ProfileArgs {
    /// Number of teeth.
    #[arg(long)]
    teeth: u32,
    /// Chain pitch, m.
    #[arg(long)]
    pitch: f64,
    /// Roller diameter, m.
    #[arg(long)]
    roller_diameter: f64,
    /// Tooth profile.
    #[arg(long, value_enum, default_value_t = ProfileKind::Real)]
    profile: ProfileKind,
    /// Print the outline as CSV instead of the dimension table.
    #[arg(long)]
    csv: bool,
}

/// Arc sampling of the CSV outline.
const STEP_RAD: f64 = 0.5 * std::f64::consts::PI / 180.0;

pub fn profile(args: ProfileArgs) -> anyhow::Result<ExitCode> {
    crate::ensure_positive("--pitch", args.pitch)?;
    crate::ensure_positive("--roller-diameter", args.roller_diameter)?;
    anyhow::ensure!(
        (3..=10_000).contains(&args.teeth),
        "--teeth must lie in 3..=10000, got {}",
        args.teeth
    );
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    if args.profile == ProfileKind::Circular {
        anyhow::ensure!(
            args.roller_diameter < args.pitch,
            "--roller-diameter {} must be smaller than --pitch {}",
            args.roller_diameter,
            args.pitch
        );
        let c = CircularProfile::new(args.teeth, args.pitch, args.roller_diameter / 2.0);
        if args.csv {
            write_outline(&mut out, &c.outline(STEP_RAD))?;
        } else {
            writeln!(
                out,
                "circular profile, N = {}, P = {} m, Dr = {} m",
                args.teeth, args.pitch, args.roller_diameter
            )?;
            let mm = |v: f64| v * 1e3;
            writeln!(out, "{:<16} {:>12}  unit", "quantity", "value")?;
            writeln!(out, "{:<16} {:>12.4}  mm", "Rs", mm(c.pitch_radius_m))?;
            writeln!(out, "{:<16} {:>12.4}  mm", "R_t", mm(c.seating_radius_m))?;
            writeln!(out, "{:<16} {:>12.4}  mm", "delta_R", mm(c.clearance_m))?;
            writeln!(
                out,
                "{:<16} {:>12.4}  mm",
                "root radius",
                mm(c.pitch_radius_m - c.roller_radius_m)
            )?;
        }
        out.flush()?;
        return Ok(ExitCode::SUCCESS);
    }
    let asa = AsaProfile::new(args.teeth, args.pitch, args.roller_diameter)
        .map_err(|e| anyhow::anyhow!("no ASA B29.1 profile for these dimensions: {e}"))?;
    if args.csv {
        write_outline(&mut out, &asa.outline(STEP_RAD))?;
    } else {
        let d = asa.dimensions();
        let (mm, deg) = (|v: f64| v * 1e3, |v: f64| v.to_degrees());
        writeln!(
            out,
            "ASA B29.1 (Type II) profile, N = {}, P = {} m, Dr = {} m",
            args.teeth, args.pitch, args.roller_diameter
        )?;
        writeln!(out, "{:<16} {:>12}  unit", "quantity", "value")?;
        let rows: [(&str, f64, &str); 18] = [
            ("A", deg(d.a_rad), "deg"),
            ("B", deg(d.b_rad), "deg"),
            ("C", deg(d.c_rad), "deg"),
            ("alpha", deg(d.pressure_angle_rad), "deg"),
            ("Rs", mm(d.pitch_radius_m), "mm"),
            ("R_t", mm(d.seating_radius_m), "mm"),
            ("delta_R", mm(d.clearance_m), "mm"),
            ("M", mm(d.m_m), "mm"),
            ("T", mm(d.t_m), "mm"),
            ("R_E", mm(d.working_radius_m), "mm"),
            ("W", mm(d.w_m), "mm"),
            ("V", mm(d.v_m), "mm"),
            ("R_F", mm(d.topping_radius_m), "mm"),
            ("H", mm(d.h_m), "mm"),
            ("S", mm(d.s_m), "mm"),
            ("straight length", mm(d.straight_length_m), "mm"),
            ("tip radius", mm(d.tip_radius_m), "mm"),
            ("root radius", mm(d.root_radius_m), "mm"),
        ];
        for (name, value, unit) in rows {
            writeln!(out, "{name:<16} {value:>12.4}  {unit}")?;
        }
    }
    out.flush()?;
    Ok(ExitCode::SUCCESS)
}

/// The outline as CSV, `x_m,y_m,gap,area`.
fn write_outline(out: impl Write, points: &[OutlinePoint]) -> anyhow::Result<()> {
    let mut w = csv::Writer::from_writer(out);
    w.write_record(["x_m", "y_m", "gap", "area"])?;
    for p in points {
        w.write_record([
            p.x_m.to_string(),
            p.y_m.to_string(),
            p.gap.to_string(),
            p.area.to_string(),
        ])?;
    }
    w.flush()?;
    Ok(())
}
