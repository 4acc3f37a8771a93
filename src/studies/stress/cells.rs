//! The matrix's cells: one factor at a time around the paper's drive, the
//! generated drives, and the integrators each cell runs (see [`super`]).

use super::{Case, StressError};
use crate::scene::DriveSpec;
use crate::scene::{Integrator, L60MC_TOML, ProfileKind, Scene, SceneFile};
/// Every integrator.
pub(crate) fn all_integrators() -> Vec<Integrator> {
    Integrator::ALL.to_vec()
}

/// The schemes run on the 10,000-roller drives: the one- and two-evaluation
/// ones (RK4's and Dormand–Prince's per-roller cost is read from the
/// 1,000-roller cells; on 10,000 rollers their ladders alone would take
/// several minutes).
pub(crate) fn big_chain_integrators() -> Vec<Integrator> {
    vec![
        Integrator::SymplecticEuler,
        Integrator::VelocityVerlet,
        Integrator::ImplicitDamping,
    ]
}

/// The schemes run on the costliest circular-profile cells (the 2.75 s and
/// 5.25 s horizons of 600 and 1200 rpm, 500 rollers; the real profile at
/// 1200 rpm keeps all five for the comparison): velocity Verlet's limit equals symplectic
/// Euler's on every cheaper cell, and the adaptive scheme costs some 1.7 s
/// per simulated second on the baseline already.
pub(crate) fn core_integrators() -> Vec<Integrator> {
    vec![
        Integrator::SymplecticEuler,
        Integrator::Rk4,
        Integrator::ImplicitDamping,
    ]
}

/// The baseline's scene file (the paper's drive).
fn paper_file(case: &str) -> Result<SceneFile, StressError> {
    toml::from_str(L60MC_TOML).map_err(|e| StressError::Toml {
        case: case.to_owned(),
        message: e.to_string(),
    })
}

/// Driver speed, ramp and horizon (see the module docs).
fn set_speed(file: &mut SceneFile, rpm: f64, ramp_s: f64, hold_s: f64) {
    for s in &mut file.sprockets {
        if s.role == "driver" {
            s.speed_rpm = Some(rpm);
            s.ramp_s = Some(ramp_s);
        }
    }
    file.solver.duration_s = ramp_s + hold_s;
}

/// The ramp at 25 rad/s² (0.5 s to 120 rpm), never shorter than 0.5 s.
fn ramp_for(rpm: f64) -> f64 {
    0.5 * (rpm.abs() / 120.0).max(1.0)
}

/// Hold time at speed, s.
const HOLD_S: f64 = 0.25;

/// A cell from a scene file, through TOML and validation.
fn cell(
    name: &str,
    mut file: SceneFile,
    integrators: Vec<Integrator>,
    cost_series: bool,
) -> Result<Case, StressError> {
    file.name = format!("stress: {name}");
    file.solver.dt_s = crate::scene::StepFile::Seconds(1e-5);
    file.solver.integrator = "symplectic_euler".to_owned();
    let text = toml::to_string(&file).map_err(|e| StressError::Toml {
        case: name.to_owned(),
        message: e.to_string(),
    })?;
    let scene = Scene::from_toml(&text).map_err(|source| StressError::Scene {
        case: name.to_owned(),
        source,
    })?;
    Ok(Case {
        name: name.to_owned(),
        scene,
        integrators,
        cost_series,
    })
}

/// The baseline with `edit` applied, at `rpm`, run by every integrator.
fn paper_cell(
    name: &str,
    rpm: f64,
    edit: impl FnOnce(&mut SceneFile),
) -> Result<Case, StressError> {
    paper_cell_with(name, rpm, all_integrators(), edit)
}

/// The baseline with `edit` applied, at `rpm`, run by `integrators`.
fn paper_cell_with(
    name: &str,
    rpm: f64,
    integrators: Vec<Integrator>,
    edit: impl FnOnce(&mut SceneFile),
) -> Result<Case, StressError> {
    let mut file = paper_file(name)?;
    set_speed(&mut file, rpm, ramp_for(rpm), HOLD_S);
    edit(&mut file);
    cell(name, file, integrators, false)
}

/// How a generated drive is driven.
#[derive(Clone, Copy)]
enum Drive {
    /// 120 rpm, the standard ramp and hold.
    Standard,
    /// 12 rpm, ramp 0.05 s, hold 0.05 s (the 10,000-roller drive and its
    /// cost series).
    Slow,
}

/// A generated cell: name prefix, rollers, sprockets, profile, how it is
/// driven, whether it is in the roller-count series.
type GeneratedRow = (&'static str, usize, usize, ProfileKind, Drive, bool);

/// A generated drive, run by every scheme when driven at the standard
/// speed, by the cheaper ones when slow (the large drives).
fn generated_cell(
    (prefix, rollers, sprockets, profile, drive, cost_series): GeneratedRow,
) -> Result<Case, StressError> {
    let name = match profile {
        ProfileKind::Circular => format!("{prefix}-{rollers}x{sprockets}"),
        ProfileKind::Real => format!("{prefix}-{rollers}x{sprockets}-real"),
    };
    let generate = |source| StressError::Generate {
        case: name.clone(),
        source,
    };
    let mut spec = DriveSpec::new(rollers, sprockets).map_err(generate)?;
    spec.profile = profile;
    let big = rollers >= 5000;
    // A 10,000-roller chain's slowest mode outlasts any affordable relaxation;
    // 0.5 s leaves it within 1e-3 of the pretension (measured).
    if big {
        spec.equilibrium.max_relax_s = 0.5;
    }
    let mut file = spec.scene_file().map_err(generate)?;
    let integrators = match drive {
        Drive::Standard => {
            set_speed(&mut file, 120.0, ramp_for(120.0), HOLD_S);
            all_integrators()
        }
        Drive::Slow => {
            set_speed(&mut file, 12.0, 0.05, 0.05);
            big_chain_integrators()
        }
    };
    cell(&name, file, integrators, cost_series)
}

fn set_profile(file: &mut SceneFile, profile: ProfileKind) {
    file.profile = profile.name().to_owned();
    for s in &mut file.sprockets {
        s.profile = None;
    }
}

/// Link damping at `ratio` of the single-link critical damping 2√(m_r K).
fn set_damping_ratio(file: &mut SceneFile, ratio: f64) {
    let c = &mut file.chain;
    if let (Some(m), Some(k)) = (c.roller_mass_kg, c.stiffness_n_m) {
        c.damping_n_s_m = ratio * 2.0 * (m * k).sqrt();
    }
}

/// The full matrix (see the module docs).
pub(crate) fn default_matrix() -> Result<Vec<Case>, StressError> {
    use ProfileKind::{Circular, Real};
    let mut cases = vec![
        paper_cell("baseline", 120.0, |_| {})?,
        paper_cell("baseline-real", 120.0, |f| set_profile(f, Real))?,
    ];
    for rpm in [30.0, 240.0] {
        cases.push(paper_cell(&format!("rpm-{rpm}"), rpm, |_| {})?);
    }
    // 2.75 s and 5.25 s horizons: the core schemes only.
    for rpm in [600.0, 1200.0] {
        cases.push(paper_cell_with(
            &format!("rpm-{rpm}"),
            rpm,
            core_integrators(),
            |_| {},
        )?);
    }
    for e in [0.5, 1.0] {
        cases.push(paper_cell(&format!("e-{e}"), 120.0, |f| {
            f.contact.restitution = e;
        })?);
    }
    for (label, ratio) in [("0", 0.0), ("0.1pct", 0.001), ("1pct", 0.01)] {
        cases.push(paper_cell(&format!("damping-{label}"), 120.0, |f| {
            set_damping_ratio(f, ratio);
        })?);
    }
    for kg in [1e8, 1e10] {
        cases.push(paper_cell(&format!("kg-{kg:e}"), 120.0, |f| {
            f.contact.stiffness = kg;
        })?);
    }
    // Combinations: the fastest drive on the real profile; no dissipation
    // at all; stiff, perfectly elastic impacts.
    cases.push(paper_cell("rpm-1200-real", 1200.0, |f| {
        set_profile(f, Real)
    })?);
    cases.push(paper_cell("undamped-e1-d0", 120.0, |f| {
        f.contact.restitution = 1.0;
        set_damping_ratio(f, 0.0);
    })?);
    cases.push(paper_cell("kg-1e10-e1", 120.0, |f| {
        f.contact.stiffness = 1e10;
        f.contact.restitution = 1.0;
    })?);
    // A 0.1 s ramp to 120 rpm: a physical overload (see the module docs).
    for (name, profile) in [("ramp-0.1", Circular), ("ramp-0.1-real", Real)] {
        cases.push(paper_cell(name, 120.0, |f| {
            set_speed(f, 120.0, 0.1, HOLD_S);
            set_profile(f, profile);
        })?);
    }
    // Generated drives: name prefix, rollers, sprockets, profile, how it is
    // driven, whether it is in the roller-count series (the same conveyor
    // driven the same way).
    #[rustfmt::skip]
    let generated: [GeneratedRow; 11] = [
        ("gen", 122, 2, Circular, Drive::Standard, false),
        ("gen", 1000, 2, Circular, Drive::Standard, false),
        ("gen", 1000, 2, Real, Drive::Standard, false),
        ("gen", 500, 3, Circular, Drive::Standard, false),
        ("gen", 500, 6, Circular, Drive::Standard, false),
        ("gen", 500, 10, Circular, Drive::Standard, false),
        ("gen", 500, 10, Real, Drive::Standard, false),
        ("cost", 122, 2, Circular, Drive::Slow, true),
        ("cost", 1000, 2, Circular, Drive::Slow, true),
        ("gen", 10_000, 2, Circular, Drive::Slow, true),
        ("gen", 10_000, 2, Real, Drive::Slow, false),
    ];
    for row in generated {
        cases.push(generated_cell(row)?);
    }
    Ok(cases)
}

/// A small subset for tests: the baseline at 30 rpm with a short horizon
/// (ramp 0.1 s, hold 0.02 s), symplectic Euler and implicit damping.
pub(crate) fn quick_matrix() -> Result<Vec<Case>, StressError> {
    let mut file = paper_file("quick-baseline")?;
    set_speed(&mut file, 30.0, 0.1, 0.02);
    Ok(vec![cell(
        "quick-baseline",
        file,
        vec![Integrator::SymplecticEuler, Integrator::ImplicitDamping],
        false,
    )?])
}
