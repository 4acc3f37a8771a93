//! Validation: a [`SceneFile`] becomes a [`Scene`] only through
//! [`TryFrom`], which checks every field, converts units (rpm → rad/s) and
//! reports *every* problem with its field's path.

use super::checker::Checker;
use super::designations;
use super::excitation::check_excitation;
use super::file::{AUTO, LimitsFile, SPEED};
use super::periodic::TableFiles;
use super::types::{DEFAULT_JOINT_FRICTION_SPEED_RAD_S, JointFriction, Limits};
use super::{
    Chain, ChainFile, Contact, ContactFile, ContactLaw, Equilibrium, Integrator, MAX_SPROCKETS,
    PITCH_RADIUS_TOLERANCE, PretensionRule, ProfileKind, Role, RoleKind, Scene, SceneError,
    SceneFile, Solver, SolverFile, SpeedLaw, Sprocket, SprocketFile, StepFile, StepLimits,
    Stepping, TEETH_RANGE, Wrap,
};
use crate::geometry::asa::IN_0_003_M;
use crate::geometry::{pitch_radius, seating_radius};

impl TryFrom<SceneFile> for Scene {
    type Error = SceneError;

    fn try_from(file: SceneFile) -> Result<Self, SceneError> {
        let mut c = Checker::new();
        for (i, g) in file.gravity_m_s2.iter().enumerate() {
            c.finite(&format!("gravity_m_s2[{i}]"), *g);
        }
        let default_profile = c.one_of::<ProfileKind>("profile", &file.profile);
        let chain = check_chain(&mut c, &file.chain);
        let contact = check_contact(&mut c, &file.contact);
        let mut sprockets = check_sprockets(
            &mut c,
            &file.sprockets,
            &chain,
            default_profile.unwrap_or(ProfileKind::Circular),
            TableFiles {
                base_dir: file.base_dir.as_deref(),
                given: &file.given_tables,
            },
        );
        check_seating(&mut c, &chain, &sprockets);
        let solver = check_solver(&mut c, &file.solver, &chain, &contact, &sprockets);
        super::resisting::set_default_speeds(&mut sprockets, solver.dt_s);
        let equilibrium = Equilibrium {
            tension_tolerance: c.positive(
                "equilibrium.tension_tolerance",
                file.equilibrium.tension_tolerance,
            ),
            max_relax_s: c.positive("equilibrium.max_relax_s", file.equilibrium.max_relax_s),
        };
        let tensioners = super::tensioners::check_tensioners(&mut c, &file.tensioners);
        super::duty::check_duty(&mut c, &file.duty);
        if chain.pretension_by == PretensionRule::TensionerPreload && tensioners.is_empty() {
            c.fail(
                "chain.pretension_by",
                "is \"tensioner_preload\" but the scene has no [[tensioners]]",
            );
        }
        if chain.pretension_by == PretensionRule::Tensioner
            && !sprockets
                .iter()
                .any(|s| matches!(s.role, Role::Tensioner { .. }))
        {
            c.fail(
                "chain.pretension_by",
                "is \"tensioner\" but no sprocket has role = \"tensioner\"",
            );
        }
        let bearing = chain.pin_radius_m.is_some() && chain.bushing_length_m.is_some();
        let checks =
            super::checks::check_checks(&mut c, &file.checks, bearing, chain.tensile_strength_n);
        let guides = if c.errors.is_empty() {
            super::guides::check_guides(&mut c, &file.guides, &chain, &contact, &sprockets, &solver)
        } else {
            Vec::new()
        };
        if !c.errors.is_empty() {
            return Err(SceneError::Invalid(c.errors));
        }
        Ok(Scene {
            guides,
            checks,
            name: file.name.clone(),
            gravity_m_s2: file.gravity_m_s2,
            chain,
            contact,
            sprockets,
            solver,
            equilibrium,
            tensioners,
            file,
            source_toml: None,
        })
    }
}

fn check_chain(c: &mut Checker, f: &ChainFile) -> Chain {
    if f.rollers < 4 {
        c.fail(
            "chain.rollers",
            format!("must be at least 4, got {}", f.rollers),
        );
    }
    let designation = f
        .designation
        .as_deref()
        .and_then(|name| match designations::lookup(name) {
            Ok(found) => Some(found),
            Err(e) => {
                c.fail("chain.designation", e);
                None
            }
        });
    // An unknown designation is its own error: the fields it would have
    // filled are not reported missing as well.
    let unknown = f.designation.is_some() && designation.is_none();
    let row = designation.map(|d| d.name());
    // A field written in the file overrides the designation's value.
    let field = |c: &mut Checker, name: &str, value: Option<f64>, from: Option<f64>| {
        let path = format!("chain.{name}");
        match value.or(from) {
            Some(v) => c.positive(&path, v),
            None if unknown => f64::NAN,
            None => {
                let why = match &row {
                    // A row without the value (a motorcycle chain's mass).
                    Some(r) => format!(
                        "is required: the designation \"{r}\" has no published value for it (`chaindrive chains {r}` shows what its row holds and where from)"
                    ),
                    None => "is required (or give chain.designation, e.g. \"ISO 606 16B-1\" or \"ANSI 80\")".to_owned(),
                };
                c.fail(path, why);
                f64::NAN
            }
        }
    };
    let pitch_m = field(
        c,
        "pitch_m",
        f.pitch_m,
        designation.map(|d| d.single.pitch_m),
    );
    let roller_radius_m = field(
        c,
        "roller_radius_m",
        f.roller_radius_m,
        designation.map(|d| d.single.roller_radius_m()),
    );
    let roller_mass_kg = field(
        c,
        "roller_mass_kg",
        f.roller_mass_kg,
        designation.and_then(|d| d.roller_mass_kg()),
    );
    let stiffness_n_m = field(
        c,
        "stiffness_n_m",
        f.stiffness_n_m,
        designation.and_then(|d| d.stiffness_n_m()),
    );
    let tensile_strength_n = f
        .tensile_strength_n
        .map(|t| c.positive("chain.tensile_strength_n", t))
        .or(designation.and_then(|d| d.tensile_strength_n()));
    if pitch_m.is_finite() && roller_radius_m.is_finite() && 2.0 * roller_radius_m >= pitch_m {
        c.fail(
            "chain.roller_radius_m",
            format!(
                "rollers of diameter {} m overlap at pitch {pitch_m} m",
                2.0 * roller_radius_m
            ),
        );
    }
    let pin_radius_m = f
        .pin_radius_m
        .or(designation.and_then(|d| d.single.pin_radius_m()));
    let bushing_length_m = f
        .bushing_length_m
        .map(|l| c.positive("chain.bushing_length_m", l))
        .or(designation.and_then(|d| d.bushing_length_m()));
    let elongation_pct = f
        .elongation_pct
        .map(|e| c.non_negative("chain.elongation_pct", e))
        .unwrap_or(0.0);
    if elongation_pct.is_finite() && elongation_pct > MAX_ELONGATION_PCT {
        c.fail(
            "chain.elongation_pct",
            format!(
                "must lie in [0, {MAX_ELONGATION_PCT}] % (catalogues replace a chain at 1.5 to 3 %), got {elongation_pct}"
            ),
        );
    }
    Chain {
        rollers: f.rollers.max(0) as usize,
        pitch_m,
        roller_radius_m,
        roller_mass_kg,
        stiffness_n_m,
        damping_n_s_m: c.non_negative("chain.damping_n_s_m", f.damping_n_s_m),
        pretension_n: c.positive("chain.pretension_n", f.pretension_n),
        pretension_by: c
            .one_of("chain.pretension_by", &f.pretension_by)
            .unwrap_or(PretensionRule::RestLength),
        joint_friction: check_joint_friction(c, f, pin_radius_m, roller_radius_m),
        designation: designation.map(|d| d.single.name),
        strands: designation.map_or(1, |d| d.strands),
        pin_radius_m: pin_radius_m.filter(|r| r.is_finite() && *r > 0.0),
        tensile_strength_n: tensile_strength_n.filter(|t| t.is_finite() && *t > 0.0),
        bushing_length_m,
        elongation: elongation_pct / 100.0,
    }
}

/// The largest wear elongation a scene may give, %: far beyond any chain's
/// service limit (3 %), where the rollers of a worn chain already ride on
/// the teeth's tips of a 20-tooth sprocket.
pub(crate) const MAX_ELONGATION_PCT: f64 = 15.0;

/// The joint friction's fields: absent (or μ = c_θ = 0) means off. A pin
/// radius is needed by μ > 0 and must be smaller than the roller's.
fn check_joint_friction(
    c: &mut Checker,
    f: &ChainFile,
    pin_radius_m: Option<f64>,
    roller_radius_m: f64,
) -> Option<JointFriction> {
    let friction = f
        .joint_friction
        .map(|mu| c.non_negative("chain.joint_friction", mu));
    if let Some(mu) = friction
        && mu > 1.0
    {
        c.fail(
            "chain.joint_friction",
            format!("must lie in [0, 1] (lubricated steel: 0.05 to 0.15), got {mu}"),
        );
    }
    let speed = f
        .joint_friction_speed_rad_s
        .map(|w| c.positive("chain.joint_friction_speed_rad_s", w));
    let damping = f
        .joint_damping_n_m_s_rad
        .map(|d| c.non_negative("chain.joint_damping_n_m_s_rad", d));
    let pin = pin_radius_m.map(|r| c.positive("chain.pin_radius_m", r));
    if let Some(r) = pin
        && r.is_finite()
        && roller_radius_m.is_finite()
        && r >= roller_radius_m
    {
        c.fail(
            "chain.pin_radius_m",
            format!(
                "must be smaller than chain.roller_radius_m = {roller_radius_m} m (the pin sits inside the bushing and roller), got {r}"
            ),
        );
    }
    let mu = friction.unwrap_or(0.0);
    let damping = damping.unwrap_or(0.0);
    if mu > 0.0 && pin.is_none() {
        c.fail(
            "chain.pin_radius_m",
            "is needed by chain.joint_friction > 0 (the friction moment is μ r_pin F_pin); allowed: 0 < pin_radius_m < roller_radius_m",
        );
    }
    (mu > 0.0 || damping > 0.0).then(|| JointFriction {
        pin_radius_m: pin.unwrap_or(0.0),
        friction: mu,
        speed_rad_s: speed.unwrap_or(DEFAULT_JOINT_FRICTION_SPEED_RAD_S),
        damping_n_m_s_rad: damping,
    })
}

fn check_contact(c: &mut Checker, f: &ContactFile) -> Contact {
    let law = c
        .one_of("contact.law", &f.law)
        .unwrap_or(ContactLaw::LankaraniNikravesh);
    let restitution = c.finite("contact.restitution", f.restitution);
    if !(0.0..=1.0).contains(&restitution) {
        c.fail(
            "contact.restitution",
            format!("must lie in [0, 1], got {restitution}"),
        );
    } else if restitution == 0.0 && law.needs_positive_restitution() {
        c.fail(
            "contact.restitution",
            format!(
                "must be > 0 with law \"{}\" (its damping factor is infinite at e = 0)",
                law.name()
            ),
        );
    }
    let exponent = c.positive("contact.exponent", f.exponent);
    if exponent.is_finite() && exponent < 1.0 {
        c.fail(
            "contact.exponent",
            format!("must be >= 1 (a stiffening contact), got {exponent}"),
        );
    }
    Contact {
        law,
        stiffness: c.positive("contact.stiffness", f.stiffness),
        exponent,
        restitution,
        min_approach_speed_m_s: c
            .positive("contact.min_approach_speed_m_s", f.min_approach_speed_m_s),
    }
}

/// The real (ASA) profile seats a roller of diameter Dr in a curve of
/// diameter Dt = 1.005 Dr + 0.003 in, which must be narrower than the pitch P
/// for two gaps to leave a tooth between them (the profile's construction,
/// `crate::geometry::asa`, refuses it too, but in its own terms). Blamed on
/// the fields the user wrote, with the largest roller allowed.
fn check_seating(c: &mut Checker, chain: &Chain, sprockets: &[Sprocket]) {
    let (pitch_m, r_m) = (chain.pitch_m, chain.roller_radius_m);
    let Some(i) = sprockets
        .iter()
        .position(|s| s.profile == ProfileKind::Real)
    else {
        return;
    };
    // Rollers that overlap at this pitch are already refused (check_chain).
    if !(pitch_m.is_finite() && r_m.is_finite() && 2.0 * r_m < pitch_m) {
        return;
    }
    let seating_diameter_m = 2.0 * seating_radius(r_m);
    if seating_diameter_m >= pitch_m {
        let max_radius_m = (pitch_m - IN_0_003_M) / 2.01;
        c.fail(
            "chain.roller_radius_m",
            format!(
                "{r_m} m is too large for the real tooth profile (sprockets[{i}]) at chain.pitch_m = {pitch_m} m: its seating diameter 1.005 × 2 × roller_radius_m + 0.003 in = {seating_diameter_m:.6} m must be below the pitch; allowed: roller_radius_m < {max_radius_m:.6} m, or profile = \"circular\""
            ),
        );
    }
}

fn check_sprockets(
    c: &mut Checker,
    files: &[SprocketFile],
    chain: &Chain,
    default_profile: ProfileKind,
    tables: TableFiles<'_>,
) -> Vec<Sprocket> {
    if files.len() < 2 {
        c.fail(
            "sprockets",
            format!("a drive needs at least 2 sprockets, got {}", files.len()),
        );
    }
    if files.len() > MAX_SPROCKETS {
        c.fail(
            "sprockets",
            format!(
                "a drive has at most {MAX_SPROCKETS} sprockets, got {}",
                files.len()
            ),
        );
    }
    let mut out = Vec::with_capacity(files.len());
    let mut drivers = 0;
    for (i, f) in files.iter().enumerate() {
        let p = |field: &str| format!("sprockets[{i}].{field}");
        let center_m = [
            c.finite(&p("center_m[0]"), f.center_m[0]),
            c.finite(&p("center_m[1]"), f.center_m[1]),
        ];
        let teeth_ok = TEETH_RANGE.contains(&f.teeth);
        if !teeth_ok {
            c.fail(
                p("teeth"),
                format!(
                    "must lie in {}..={}, got {}",
                    TEETH_RANGE.start(),
                    TEETH_RANGE.end(),
                    f.teeth
                ),
            );
        }
        let teeth = f.teeth.clamp(*TEETH_RANGE.start(), *TEETH_RANGE.end()) as u32;
        let radius = pitch_radius(chain.pitch_m, teeth);
        if let Some(stated) = f.pitch_radius_m {
            let stated = c.positive(&p("pitch_radius_m"), stated);
            if teeth_ok
                && radius.is_finite()
                && stated.is_finite()
                && ((stated - radius) / radius).abs() > PITCH_RADIUS_TOLERANCE
            {
                c.fail(
                    p("pitch_radius_m"),
                    format!(
                        "{stated} m disagrees with P / (2 sin(pi/N)) = {radius:.6} m for P = {} m, N = {teeth} (tolerance {PITCH_RADIUS_TOLERANCE:e} relative); omit it to use the computed value",
                        chain.pitch_m
                    ),
                );
            }
        }
        let wrap = c.one_of(&p("wrap"), &f.wrap).unwrap_or(Wrap::Ccw);
        let profile = match &f.profile {
            Some(name) => c.one_of(&p("profile"), name).unwrap_or(default_profile),
            None => default_profile,
        };
        let role = check_role(c, f, i);
        if matches!(role, Role::Driver(_)) {
            drivers += 1;
        }
        let kind = RoleKind::from_name(&f.role);
        let excitation = check_excitation(c, f.excitation(), i, kind, tables);
        let resisting = super::resisting::check(c, f, i, &role);
        out.push(Sprocket {
            name: f.name.clone(),
            center_m,
            teeth,
            pitch_radius_m: radius,
            mass_kg: c.positive(&p("mass_kg"), f.mass_kg),
            inertia_kg_m2: c.positive(&p("inertia_kg_m2"), f.inertia_kg_m2),
            wrap,
            role,
            profile,
            excitation,
            resisting,
        });
    }
    // No driver is allowed: a drive turned by torques on mounted bodies (crate::cosim).
    if drivers > 1 {
        c.fail(
            "sprockets",
            format!("at most one sprocket may have role = \"driver\", found {drivers}"),
        );
    }
    check_overlaps(c, &out, chain);
    out
}

fn check_role(c: &mut Checker, f: &SprocketFile, i: usize) -> Role {
    let p = |field: &str| format!("sprockets[{i}].{field}");
    let forbid = |c: &mut Checker, field: &str, present: bool, role: &str| {
        if present {
            c.fail(p(field), format!("is not allowed for role = \"{role}\""));
        }
    };
    let Some(kind) = c.one_of::<RoleKind>(&p("role"), &f.role) else {
        return Role::Free {
            load_torque_n_m: 0.0,
            load_ramp_s: 0.0,
        };
    };
    match kind {
        RoleKind::Driver => {
            forbid(c, "load_torque_n_m", f.load_torque_n_m.is_some(), "driver");
            forbid(c, "load_ramp_s", f.load_ramp_s.is_some(), "driver");
            forbid(
                c,
                "adjust_direction",
                f.adjust_direction.is_some(),
                "driver",
            );
            let speed_rpm = match f.speed_rpm {
                Some(v) => c.finite(&p("speed_rpm"), v),
                None => {
                    c.fail(p("speed_rpm"), "is required for role = \"driver\"");
                    0.0
                }
            };
            let ramp_s = c.non_negative(&p("ramp_s"), f.ramp_s.unwrap_or(0.0));
            let speed_rad_s = speed_rpm * std::f64::consts::TAU / 60.0;
            let run_up = super::run_up::check(c, f.run_up.as_ref(), i, ramp_s, speed_rad_s);
            Role::Driver(SpeedLaw {
                speed_rad_s,
                ramp_s,
                run_up,
            })
        }
        RoleKind::Free | RoleKind::Tensioner => {
            forbid(c, "speed_rpm", f.speed_rpm.is_some(), kind.name());
            forbid(c, "ramp_s", f.ramp_s.is_some(), kind.name());
            forbid(c, "run_up", f.run_up.is_some(), kind.name());
            let load_torque_n_m = c.finite(&p("load_torque_n_m"), f.load_torque_n_m.unwrap_or(0.0));
            let load_ramp_s = match f.load_ramp_s {
                Some(_) if f.load_torque_n_m.is_none() => {
                    c.fail(
                        p("load_ramp_s"),
                        "is allowed only on a sprocket with a load_torque_n_m",
                    );
                    0.0
                }
                Some(v) => c.non_negative(&p("load_ramp_s"), v),
                None => 0.0,
            };
            if kind == RoleKind::Free {
                forbid(c, "adjust_direction", f.adjust_direction.is_some(), "free");
                return Role::Free {
                    load_torque_n_m,
                    load_ramp_s,
                };
            }
            let direction = match f.adjust_direction {
                Some([x, y]) => {
                    let n = x.hypot(y);
                    if !n.is_finite() || n <= 0.0 {
                        c.fail(p("adjust_direction"), "must be a finite, non-zero vector");
                        [0.0, 1.0]
                    } else {
                        [x / n, y / n]
                    }
                }
                None => {
                    c.fail(
                        p("adjust_direction"),
                        "is required for role = \"tensioner\"",
                    );
                    [0.0, 1.0]
                }
            };
            Role::Tensioner {
                load_torque_n_m,
                load_ramp_s,
                direction,
            }
        }
    }
}

/// Two sprockets whose tip circles (pitch radius + roller radius) intersect cannot both turn.
fn check_overlaps(c: &mut Checker, sprockets: &[Sprocket], chain: &Chain) {
    for i in 0..sprockets.len() {
        for j in i + 1..sprockets.len() {
            let (a, b) = (&sprockets[i], &sprockets[j]);
            let d = (a.center_m[0] - b.center_m[0]).hypot(a.center_m[1] - b.center_m[1]);
            let reach = a.pitch_radius_m + b.pitch_radius_m + 2.0 * chain.roller_radius_m;
            if d.is_finite() && reach.is_finite() && d < reach {
                c.fail(
                    format!("sprockets[{j}].center_m"),
                    format!(
                        "sprocket \"{}\" overlaps sprocket {i} (\"{}\"): centres {d:.4} m apart, need at least {reach:.4} m",
                        b.name, a.name
                    ),
                );
            }
        }
    }
}

fn check_solver(
    c: &mut Checker,
    f: &SolverFile,
    chain: &Chain,
    contact: &Contact,
    sprockets: &[Sprocket],
) -> Solver {
    let stepping = c
        .one_of("solver.stepping", &f.stepping)
        .unwrap_or(Stepping::Substepped);
    let integrator = c
        .one_of("solver.integrator", &f.integrator)
        .unwrap_or(Integrator::SymplecticEuler);
    if stepping == Stepping::Rapier && integrator != Integrator::SymplecticEuler {
        c.fail(
            "solver.integrator",
            format!(
                "\"{}\" needs stepping = \"substepped\": rapier integrates with symplectic Euler",
                integrator.name()
            ),
        );
    }
    let tolerance = c.positive("solver.tolerance", f.tolerance);
    if tolerance.is_finite() && tolerance >= 1.0 {
        c.fail(
            "solver.tolerance",
            format!("must be below 1 (a relative error), got {tolerance}"),
        );
    }
    let sample_period_s = f.sample_period_s.unwrap_or(super::AUTO_GRID_S);
    if !(sample_period_s.is_finite() && sample_period_s > 0.0) {
        c.fail(
            "solver.dt_s",
            format!(
                "the sample period an automatic step divides must be > 0 s, got {sample_period_s}"
            ),
        );
    }
    let (dt_s, dt_auto, dt_speed) = match &f.dt_s {
        StepFile::Seconds(dt) => (c.positive("solver.dt_s", *dt), false, false),
        StepFile::Word(w) if w == AUTO || w == SPEED => {
            let speed = w == SPEED;
            let limits = StepLimits::of_parts(chain, contact, sprockets);
            let dt = if speed {
                limits.speed_step_s(integrator, sample_period_s)
            } else {
                let impact_s = super::stability::impact_duration_s(chain, contact, sprockets);
                limits.auto_step_s(integrator, impact_s, sample_period_s)
            };
            // Only a chain or contact already reported invalid lands here.
            if !(dt.is_finite() && dt > 0.0) && c.errors.is_empty() {
                c.fail(
                    "solver.dt_s",
                    format!("\"{w}\" found no finite step for this chain (got {dt}); give one in seconds"),
                );
            }
            (dt, true, speed)
        }
        StepFile::Word(w) => {
            c.fail(
                "solver.dt_s",
                format!("must be a step in seconds, \"auto\" or \"speed\", got \"{w}\""),
            );
            (f64::NAN, false, false)
        }
    };
    Solver {
        stepping,
        integrator,
        dt_s,
        dt_auto,
        dt_speed,
        sample_period_s,
        tolerance,
        duration_s: c.non_negative("solver.duration_s", f.duration_s),
        limits: check_limits(c, &f.limits, chain),
        threads: super::Threads::from_file(&f.threads).unwrap_or_else(|e| {
            c.fail("solver.threads", e);
            super::Threads::Auto
        }),
    }
}

/// `[solver.limits]`, defaults filled in from the chain (docs/model.md).
fn check_limits(c: &mut Checker, f: &LimitsFile, chain: &Chain) -> Limits {
    let path = |name: &str| format!("solver.limits.{name}");
    let mut positive_or = |name: &str, value: Option<f64>, default: f64| match value {
        Some(v) => c.positive(&path(name), v),
        None => default,
    };
    let max_penetration_m = positive_or(
        "max_penetration_m",
        f.max_penetration_m,
        chain.roller_radius_m,
    );
    let max_stretch_m = positive_or("max_stretch_m", f.max_stretch_m, 0.1 * chain.pitch_m);
    let growth_factor = positive_or("growth_factor", f.growth_factor, 100.0);
    if growth_factor.is_finite() && growth_factor <= 1.0 {
        c.fail(
            path("growth_factor"),
            format!("must be > 1 (a growth), got {growth_factor}"),
        );
    }
    let growth_steps = match f.growth_steps {
        None => 20,
        Some(n) if (1..=1000).contains(&n) => n as u32,
        Some(n) => {
            c.fail(
                path("growth_steps"),
                format!("must be an integer from 1 to 1000, got {n}"),
            );
            20
        }
    };
    Limits {
        max_penetration_m,
        max_stretch_m,
        growth_factor,
        growth_steps,
    }
}
