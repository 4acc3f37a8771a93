//! `chaindrive rate`: the catalogue rating of a scene's chain at its
//! driver's speed, without a run (`crate::analysis::design::rating`).

use std::path::PathBuf;
use std::process::ExitCode;

use crate::analysis::design::rating::{self, HP_W, Rating, RatingSettings};

/// Arguments of `chaindrive rate`.
#[derive(clap::Args)]
pub(super) struct RateArgs {
    /// Scene file (TOML). Default: the embedded paper drive.
    scene: Option<PathBuf>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
    /// Service factor: the rating is divided by it (1: the tables' smooth load).
    #[arg(long, default_value_t = 1.0, value_name = "F")]
    service_factor: f64,
    /// The transmitted power, W (default: the scene's load torques at the
    /// driver's speed).
    #[arg(long, value_name = "W")]
    power_w: Option<f64>,
}

pub(super) fn rate(args: RateArgs) -> anyhow::Result<ExitCode> {
    crate::cli::ensure_positive("--service-factor", args.service_factor)?;
    if let Some(p) = args.power_w {
        crate::cli::ensure_positive("--power-w", p)?;
    }
    let Some(scene) = crate::cli::load_scene_or_report(args.scene.as_deref(), &Default::default())?
    else {
        return Ok(ExitCode::FAILURE);
    };
    let settings = RatingSettings {
        service_factor: args.service_factor,
    };
    let r = match rating::of_scene(&scene, settings, args.power_w) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("cannot rate {}: {e}", scene.name());
            return Ok(ExitCode::FAILURE);
        }
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&r)?);
    } else {
        print_text(scene.name(), &r);
    }
    Ok(ExitCode::SUCCESS)
}

/// kW and hp of a power in W.
fn kw_hp(w: f64) -> String {
    format!("{:.3} kW ({:.2} hp)", w * 1e-3, w / HP_W)
}

fn print_text(name: &str, r: &Rating) {
    println!("scene: {name}");
    println!("basis: {}", r.basis);
    println!(
        "smallest sprocket: {} ({} teeth) at {:.1} rpm; chain speed {:.3} m/s ({:.0} ft/min)",
        r.smallest_sprocket,
        r.smallest_teeth,
        r.smallest_speed_rpm,
        r.chain_speed_m_s,
        r.chain_speed_m_s * 60.0 / 0.3048
    );
    let freqs: Vec<String> = r
        .tooth_frequency_hz
        .iter()
        .enumerate()
        .map(|(k, f)| format!("{}: {f:.2} Hz", k + 1))
        .collect();
    println!("tooth-passing frequency: {}", freqs.join(", "));
    println!(
        "polygonal speed variation of the rigid chain on {} teeth, 1 - cos(pi/N): {:.3} %",
        r.smallest_teeth,
        100.0 * r.polygonal_speed_variation
    );
    println!(
        "link-plate fatigue limit:    {}",
        kw_hp(r.link_plate_limited_power_w)
    );
    println!(
        "roller-bushing impact limit: {}",
        kw_hp(r.roller_bushing_limited_power_w)
    );
    println!(
        "rated power (one strand, service factor 1): {}, {} limited",
        kw_hp(r.rated_power_w),
        r.limited_by.replace('_', "-")
    );
    println!(
        "design power: x {} ({} strand{}) / {} (service factor) = {}",
        r.strand_factor,
        r.strands,
        if r.strands == 1 { "" } else { "s" },
        r.service_factor,
        kw_hp(r.design_power_w)
    );
    println!(
        "lubrication the rating assumes: {} (type A up to {:.2} m/s, type B up to {:.2} m/s)",
        r.lubrication.description(),
        r.lubrication_a_max_m_s,
        r.lubrication_b_max_m_s
    );
    if let Some(strength) = r.tensile_strength_n {
        println!("tensile strength: {:.1} kN", strength * 1e-3);
    }
    if let (Some(p), Some(from)) = (r.transmitted_power_w, &r.transmitted_power_from) {
        println!("transmitted power: {} ({from})", kw_hp(p));
    }
    if let Some(m) = r.margin {
        println!(
            "margin (design power / transmitted): {m:.2}{}",
            if m < 1.0 { "  OVERLOADED" } else { "" }
        );
    }
    for note in &r.notes {
        println!("note: {note}");
    }
}
