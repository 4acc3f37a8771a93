//! Tensioner arms and their tensioners (`[[tensioners]]`): the file form,
//! the validated form and the checks, each error with its field path.
//!
//! An arm turns about a fixed pivot and carries a circular-arc shoe that the
//! chain's rollers ride on (outside the arc). A tensioner pushes the arm at
//! one of its points along a fixed line: a spring-damper with end stops, or
//! a hydraulic tensioner (docs/model.md, “Tensioner arms”). Angles are
//! written in degrees and converted to radians here; every other quantity is
//! SI.

use serde::{Deserialize, Serialize};

use super::checker::Checker;
use crate::geometry::v2::{norm, segment_distance, sub};

/// One tensioner arm with its tensioner, as written.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct TensionerFile {
    /// Name, for outputs.
    pub name: String,
    /// The arm's fixed pivot, m.
    pub pivot_m: [f64; 2],
    /// The arm's moment of inertia about the pivot, kg·m².
    pub inertia_kg_m2: f64,
    /// The arm's mass, kg (with `center_of_mass_m`: its weight's moment;
    /// absent: no weight).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass_kg: Option<f64>,
    /// The arm's centre of mass at the scene's pose, m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub center_of_mass_m: Option<[f64; 2]>,
    /// Centre of the shoe's arc at the scene's pose, m.
    pub shoe_center_m: [f64; 2],
    /// Radius of the shoe's arc, m (the rollers ride on its outside).
    pub shoe_radius_m: f64,
    /// Where the arc starts, degrees, measured at its centre from +x,
    /// counter-clockwise, at the scene's pose.
    pub shoe_start_deg: f64,
    /// Where it ends (counter-clockwise from the start, less than 180° on).
    pub shoe_end_deg: f64,
    /// Coulomb friction coefficient between rollers and shoe (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shoe_friction: Option<f64>,
    /// Regularisation speed of the shoe's friction, m/s (default 0.05).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shoe_friction_speed_m_s: Option<f64>,
    /// The point of the arm the tensioner pushes, at the scene's pose, m.
    pub point_m: [f64; 2],
    /// The direction the tensioner pushes that point in (fixed in the world).
    pub direction: [f64; 2],
    /// A spring-damper tensioner (exactly one of `spring`, `hydraulic`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spring: Option<SpringFile>,
    /// A hydraulic tensioner.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hydraulic: Option<HydraulicFile>,
}

/// A spring-damper tensioner, as written. Travel x is measured along the
/// tensioner's line from the scene's pose, positive as it pushes out.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SpringFile {
    /// Force at the scene's pose (x = 0), N.
    pub preload_n: f64,
    /// Stiffness, N/m (the force falls as it extends: F = F₀ − k x).
    pub stiffness_n_m: f64,
    /// Damping, N·s/m.
    #[serde(default)]
    pub damping_n_s_m: f64,
    /// Travel at which it bottoms out (≤ 0), m.
    pub min_travel_m: f64,
    /// Travel at which it tops out (≥ 0), m.
    pub max_travel_m: f64,
    /// Stiffness of the end stops, N/m (default 1e7).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stop_stiffness_n_m: Option<f64>,
}

/// A hydraulic tensioner, as written (pressures relative to the ambient).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct HydraulicFile {
    /// Plunger diameter d, m.
    pub bore_m: f64,
    /// Radial clearance c of the plunger in its bore, m.
    pub clearance_m: f64,
    /// Length L of the leak gap, m.
    pub leak_length_m: f64,
    /// Dynamic viscosity η of the oil, Pa·s.
    pub viscosity_pa_s: f64,
    /// Bulk modulus β of the oil, Pa.
    pub bulk_modulus_pa: f64,
    /// Volume fraction of entrained air, in [0, 1).
    #[serde(default)]
    pub air_fraction: f64,
    /// Oil density ρ, kg/m³.
    pub oil_density_kg_m3: f64,
    /// Chamber volume at the scene's pose, m³.
    pub chamber_volume_m3: f64,
    /// Supply pressure p_s (gauge), Pa.
    pub supply_pressure_pa: f64,
    /// Check valve's cracking pressure, Pa.
    pub cracking_pressure_pa: f64,
    /// Check valve's orifice diameter, m.
    pub valve_diameter_m: f64,
    /// Check valve's discharge coefficient C_d, in (0, 1].
    pub valve_cd: f64,
    /// Return spring's force at the scene's pose, N.
    pub spring_preload_n: f64,
    /// Return spring's stiffness, N/m.
    pub spring_stiffness_n_m: f64,
    /// Travel at which the plunger bottoms out (≤ 0), m.
    pub min_travel_m: f64,
    /// Travel at which it tops out (≥ 0), m.
    pub max_travel_m: f64,
    /// Backlash of a ratchet that stops the plunger retracting further than
    /// this below its furthest extension, m (absent: no ratchet).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ratchet_backlash_m: Option<f64>,
    /// Stiffness of the end stops and the ratchet, N/m (default 1e7).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stop_stiffness_n_m: Option<f64>,
    /// Ambient pressure, absolute, Pa (default 101 325): the entrained
    /// air's stiffness and the cavitation floor.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ambient_pressure_pa: Option<f64>,
}

/// Default stiffness of end stops and ratchets, N/m.
pub(crate) const DEFAULT_STOP_STIFFNESS_N_M: f64 = 1e7;
/// Default regularisation speed of the shoe's friction, m/s.
pub(crate) const DEFAULT_SHOE_FRICTION_SPEED_M_S: f64 = 0.05;
/// Standard atmosphere, Pa.
pub(crate) const STANDARD_ATMOSPHERE_PA: f64 = 101_325.0;

/// A validated tensioner arm and its tensioner (SI, radians).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Tensioner {
    /// Name.
    pub name: String,
    /// Pivot, m.
    pub pivot_m: [f64; 2],
    /// Moment of inertia about the pivot, kg·m².
    pub inertia_kg_m2: f64,
    /// Mass, kg (0: no weight).
    pub mass_kg: f64,
    /// Centre of mass at the scene's pose, m.
    pub center_of_mass_m: [f64; 2],
    /// Shoe arc's centre at the scene's pose, m.
    pub shoe_center_m: [f64; 2],
    /// Shoe radius, m.
    pub shoe_radius_m: f64,
    /// Arc start angle at the scene's pose, rad.
    pub shoe_start_rad: f64,
    /// Arc's angular extent, rad, in (0, π).
    pub shoe_span_rad: f64,
    /// Roller–shoe friction coefficient.
    pub shoe_friction: f64,
    /// Its regularisation speed, m/s.
    pub shoe_friction_speed_m_s: f64,
    /// The point pushed, at the scene's pose, m.
    pub point_m: [f64; 2],
    /// Unit direction of the push.
    pub direction: [f64; 2],
    /// The tensioner.
    pub kind: TensionerKind,
}

/// What pushes the arm.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum TensionerKind {
    /// A spring-damper with end stops.
    Spring(SpringTensioner),
    /// A hydraulic tensioner.
    Hydraulic(HydraulicTensioner),
}

/// A validated spring-damper tensioner.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SpringTensioner {
    /// Force at x = 0, N.
    pub preload_n: f64,
    /// Stiffness, N/m.
    pub stiffness_n_m: f64,
    /// Damping, N·s/m.
    pub damping_n_s_m: f64,
    /// Bottom stop, m (≤ 0).
    pub min_travel_m: f64,
    /// Top stop, m (≥ 0).
    pub max_travel_m: f64,
    /// Stops' stiffness, N/m.
    pub stop_stiffness_n_m: f64,
}

/// A validated hydraulic tensioner (pressures gauge, SI).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct HydraulicTensioner {
    /// Plunger diameter d, m.
    pub bore_m: f64,
    /// Radial clearance c, m.
    pub clearance_m: f64,
    /// Leak length L, m.
    pub leak_length_m: f64,
    /// Viscosity η, Pa·s.
    pub viscosity_pa_s: f64,
    /// Oil bulk modulus β, Pa.
    pub bulk_modulus_pa: f64,
    /// Entrained air's volume fraction α.
    pub air_fraction: f64,
    /// Oil density ρ, kg/m³.
    pub oil_density_kg_m3: f64,
    /// Chamber volume at x = 0, m³.
    pub chamber_volume_m3: f64,
    /// Supply pressure p_s, Pa (gauge).
    pub supply_pressure_pa: f64,
    /// Cracking pressure, Pa.
    pub cracking_pressure_pa: f64,
    /// Valve orifice diameter, m.
    pub valve_diameter_m: f64,
    /// Discharge coefficient.
    pub valve_cd: f64,
    /// Return spring at x = 0, N.
    pub spring_preload_n: f64,
    /// Return spring's stiffness, N/m.
    pub spring_stiffness_n_m: f64,
    /// Bottom stop, m (≤ 0).
    pub min_travel_m: f64,
    /// Top stop, m (≥ 0).
    pub max_travel_m: f64,
    /// Ratchet backlash, m (`None`: no ratchet).
    pub ratchet_backlash_m: Option<f64>,
    /// Stops' and ratchet's stiffness, N/m.
    pub stop_stiffness_n_m: f64,
    /// Ambient pressure, absolute, Pa.
    pub ambient_pressure_pa: f64,
}

impl Tensioner {
    /// The travel at the tensioner's lower and upper stops, m.
    pub fn travel_limits_m(&self) -> (f64, f64) {
        match &self.kind {
            TensionerKind::Spring(s) => (s.min_travel_m, s.max_travel_m),
            TensionerKind::Hydraulic(h) => (h.min_travel_m, h.max_travel_m),
        }
    }

    /// The arm as the layout sees it, with rollers of `roller_radius_m`
    /// riding on its shoe.
    pub fn arm_shoe(&self, roller_radius_m: f64) -> crate::geometry::ArmShoe {
        let (min_travel_m, max_travel_m) = self.travel_limits_m();
        crate::geometry::ArmShoe {
            pivot_m: self.pivot_m,
            center_m: self.shoe_center_m,
            radius_m: self.shoe_radius_m + roller_radius_m,
            start_rad: self.shoe_start_rad,
            span_rad: self.shoe_span_rad,
            point_m: self.point_m,
            direction: self.direction,
            min_travel_m,
            max_travel_m,
        }
    }
}

fn finite_point(c: &mut Checker, path: &str, p: [f64; 2]) -> [f64; 2] {
    for (i, v) in p.iter().enumerate() {
        c.finite(&format!("{path}[{i}]"), *v);
    }
    p
}

fn travel_limits(c: &mut Checker, path: &str, min: f64, max: f64) -> (f64, f64) {
    let min = c.finite(&format!("{path}.min_travel_m"), min);
    let max = c.finite(&format!("{path}.max_travel_m"), max);
    if min > 0.0 {
        c.fail(
            format!("{path}.min_travel_m"),
            format!("must be <= 0 (travel is measured from the scene's pose), got {min}"),
        );
    }
    if max < 0.0 {
        c.fail(
            format!("{path}.max_travel_m"),
            format!("must be >= 0 (travel is measured from the scene's pose), got {max}"),
        );
    }
    (min, max)
}

/// Checks every `[[tensioners]]` entry.
pub(crate) fn check_tensioners(c: &mut Checker, files: &[TensionerFile]) -> Vec<Tensioner> {
    files
        .iter()
        .enumerate()
        .map(|(i, f)| check_tensioner(c, &format!("tensioners[{i}]"), f))
        .collect()
}

fn check_tensioner(c: &mut Checker, path: &str, f: &TensionerFile) -> Tensioner {
    let p = |field: &str| format!("{path}.{field}");
    let pivot = finite_point(c, &p("pivot_m"), f.pivot_m);
    let inertia = c.positive(&p("inertia_kg_m2"), f.inertia_kg_m2);
    let mass = f.mass_kg.map_or(0.0, |m| c.non_negative(&p("mass_kg"), m));
    let com = match f.center_of_mass_m {
        Some(com) => finite_point(c, &p("center_of_mass_m"), com),
        None => {
            if mass > 0.0 {
                c.fail(
                    p("center_of_mass_m"),
                    "is needed with mass_kg > 0 (the weight acts there)",
                );
            }
            pivot
        }
    };
    let shoe_center = finite_point(c, &p("shoe_center_m"), f.shoe_center_m);
    let shoe_radius = c.positive(&p("shoe_radius_m"), f.shoe_radius_m);
    let start = c.finite(&p("shoe_start_deg"), f.shoe_start_deg);
    let end = c.finite(&p("shoe_end_deg"), f.shoe_end_deg);
    let span_deg = (end - start).rem_euclid(360.0);
    if start.is_finite() && end.is_finite() && !(span_deg > 0.0 && span_deg < 180.0) {
        c.fail(
            p("shoe_end_deg"),
            format!(
                "the arc from shoe_start_deg = {start} to shoe_end_deg = {end} (counter-clockwise) spans {span_deg}°; allowed: more than 0° and less than 180°"
            ),
        );
    }
    let friction = f
        .shoe_friction
        .map_or(0.0, |mu| c.non_negative(&p("shoe_friction"), mu));
    if friction > 1.0 {
        c.fail(
            p("shoe_friction"),
            format!(
                "must lie in [0, 1] (lubricated polymer on steel: 0.05 to 0.15), got {friction}"
            ),
        );
    }
    let friction_speed = f
        .shoe_friction_speed_m_s
        .map_or(DEFAULT_SHOE_FRICTION_SPEED_M_S, |v| {
            c.positive(&p("shoe_friction_speed_m_s"), v)
        });
    let point = finite_point(c, &p("point_m"), f.point_m);
    let dir = finite_point(c, &p("direction"), f.direction);
    let dir_len = norm(dir);
    let direction = if dir_len > 0.0 && dir_len.is_finite() {
        [dir[0] / dir_len, dir[1] / dir_len]
    } else {
        c.fail(
            p("direction"),
            format!("must be a non-zero vector, got {dir:?}"),
        );
        [1.0, 0.0]
    };
    // The arm reaches from its pivot to its shoe's far end (and its centre of
    // mass); the point pushed must lie on it.
    let start_rad = start.to_radians();
    let span_rad = span_deg.to_radians();
    let reach = [0.0, 0.5, 1.0]
        .iter()
        .map(|s| {
            let a = start_rad + s * span_rad;
            let q = [
                shoe_center[0] + shoe_radius * a.cos(),
                shoe_center[1] + shoe_radius * a.sin(),
            ];
            norm(sub(q, pivot))
        })
        .fold(norm(sub(com, pivot)), f64::max);
    let r = sub(point, pivot);
    let arm = norm(r);
    if reach.is_finite() && arm.is_finite() {
        if arm > 1.05 * reach {
            c.fail(
                p("point_m"),
                format!(
                    "misses the arm: it is {arm:.4} m from the pivot, but the arm (to its shoe) reaches {reach:.4} m"
                ),
            );
        } else if (r[0] * direction[1] - r[1] * direction[0]).abs() < 0.05 * arm.max(1e-3 * reach) {
            c.fail(
                p("direction"),
                format!(
                    "the tensioner's line through point_m passes within {:.2e} m of the pivot: it would push the arm without turning it; allowed: a line at least 5 % of the point's distance {arm:.4} m from the pivot",
                    (r[0] * direction[1] - r[1] * direction[0]).abs()
                ),
            );
        }
    }
    let kind = match (&f.spring, &f.hydraulic) {
        (Some(s), None) => TensionerKind::Spring(check_spring(c, &p("spring"), s)),
        (None, Some(h)) => TensionerKind::Hydraulic(check_hydraulic(c, &p("hydraulic"), h)),
        (Some(s), Some(_)) => {
            c.fail(
                path,
                "has both [spring] and [hydraulic]; allowed: exactly one",
            );
            TensionerKind::Spring(check_spring(c, &p("spring"), s))
        }
        (None, None) => {
            c.fail(
                path,
                "has no tensioner; allowed: a [tensioners.spring] or a [tensioners.hydraulic] table",
            );
            TensionerKind::Spring(SpringTensioner {
                preload_n: 0.0,
                stiffness_n_m: 0.0,
                damping_n_s_m: 0.0,
                min_travel_m: 0.0,
                max_travel_m: 0.0,
                stop_stiffness_n_m: DEFAULT_STOP_STIFFNESS_N_M,
            })
        }
    };
    Tensioner {
        name: f.name.clone(),
        pivot_m: pivot,
        inertia_kg_m2: inertia,
        mass_kg: mass,
        center_of_mass_m: com,
        shoe_center_m: shoe_center,
        shoe_radius_m: shoe_radius,
        shoe_start_rad: start_rad,
        shoe_span_rad: span_rad,
        shoe_friction: friction,
        shoe_friction_speed_m_s: friction_speed,
        point_m: point,
        direction,
        kind,
    }
}

fn check_spring(c: &mut Checker, path: &str, f: &SpringFile) -> SpringTensioner {
    let p = |field: &str| format!("{path}.{field}");
    let (min, max) = travel_limits(c, path, f.min_travel_m, f.max_travel_m);
    SpringTensioner {
        preload_n: c.non_negative(&p("preload_n"), f.preload_n),
        stiffness_n_m: c.non_negative(&p("stiffness_n_m"), f.stiffness_n_m),
        damping_n_s_m: c.non_negative(&p("damping_n_s_m"), f.damping_n_s_m),
        min_travel_m: min,
        max_travel_m: max,
        stop_stiffness_n_m: f
            .stop_stiffness_n_m
            .map_or(DEFAULT_STOP_STIFFNESS_N_M, |k| {
                c.positive(&p("stop_stiffness_n_m"), k)
            }),
    }
}

fn check_hydraulic(c: &mut Checker, path: &str, f: &HydraulicFile) -> HydraulicTensioner {
    let p = |field: &str| format!("{path}.{field}");
    let bore = c.positive(&p("bore_m"), f.bore_m);
    let clearance = c.positive(&p("clearance_m"), f.clearance_m);
    if clearance.is_finite() && bore.is_finite() && clearance > 0.0 && clearance >= 0.05 * bore {
        c.fail(
            p("clearance_m"),
            format!(
                "{clearance} m is not a narrow gap around a {bore} m plunger (the leak law needs c much smaller than d; automotive: 10 to 30 µm)"
            ),
        );
    }
    let air = c.non_negative(&p("air_fraction"), f.air_fraction);
    if air >= 1.0 {
        c.fail(
            p("air_fraction"),
            format!("must lie in [0, 1) (a volume fraction), got {air}"),
        );
    }
    let cd = c.positive(&p("valve_cd"), f.valve_cd);
    if cd > 1.0 {
        c.fail(p("valve_cd"), format!("must lie in (0, 1], got {cd}"));
    }
    let (min, max) = travel_limits(c, path, f.min_travel_m, f.max_travel_m);
    let volume = c.positive(&p("chamber_volume_m3"), f.chamber_volume_m3);
    let area = std::f64::consts::PI * bore * bore / 4.0;
    if volume.is_finite() && area.is_finite() && min.is_finite() && volume + area * min <= 0.0 {
        c.fail(
            p("chamber_volume_m3"),
            format!(
                "{volume} m³ is emptied before min_travel_m = {min} m (the plunger sweeps {area:.3e} m³ per m); allowed: more than {:.3e} m³",
                -area * min
            ),
        );
    }
    let ratchet = f
        .ratchet_backlash_m
        .map(|b| c.positive(&p("ratchet_backlash_m"), b));
    HydraulicTensioner {
        bore_m: bore,
        clearance_m: clearance,
        leak_length_m: c.positive(&p("leak_length_m"), f.leak_length_m),
        viscosity_pa_s: c.positive(&p("viscosity_pa_s"), f.viscosity_pa_s),
        bulk_modulus_pa: c.positive(&p("bulk_modulus_pa"), f.bulk_modulus_pa),
        air_fraction: air,
        oil_density_kg_m3: c.positive(&p("oil_density_kg_m3"), f.oil_density_kg_m3),
        chamber_volume_m3: volume,
        supply_pressure_pa: c.non_negative(&p("supply_pressure_pa"), f.supply_pressure_pa),
        cracking_pressure_pa: c.non_negative(&p("cracking_pressure_pa"), f.cracking_pressure_pa),
        valve_diameter_m: c.positive(&p("valve_diameter_m"), f.valve_diameter_m),
        valve_cd: cd,
        spring_preload_n: c.non_negative(&p("spring_preload_n"), f.spring_preload_n),
        spring_stiffness_n_m: c.non_negative(&p("spring_stiffness_n_m"), f.spring_stiffness_n_m),
        min_travel_m: min,
        max_travel_m: max,
        ratchet_backlash_m: ratchet,
        stop_stiffness_n_m: f
            .stop_stiffness_n_m
            .map_or(DEFAULT_STOP_STIFFNESS_N_M, |k| {
                c.positive(&p("stop_stiffness_n_m"), k)
            }),
        ambient_pressure_pa: f.ambient_pressure_pa.map_or(STANDARD_ATMOSPHERE_PA, |a| {
            c.positive(&p("ambient_pressure_pa"), a)
        }),
    }
}

/// The warnings of a scene's tensioner arms: each arm whose shoe, at the
/// scene's pose, the chain's nominal path (through the seated rollers)
/// passes clear of by more than the roller radius (as for guides).
pub(super) fn warnings(
    tensioners: &[Tensioner],
    sprockets: &[super::Sprocket],
    chain: &super::Chain,
) -> Vec<String> {
    use crate::geometry::{PathCircle, chain_path};
    if tensioners.is_empty() {
        return Vec::new();
    }
    let circles: Vec<PathCircle> = sprockets
        .iter()
        .map(|s| PathCircle {
            center_m: s.center_m,
            radius_m: s.pitch_radius_m,
            sense: s.wrap.sign(),
        })
        .collect();
    let Ok(path) = chain_path(&circles) else {
        return Vec::new();
    };
    const SAMPLES: usize = 64;
    tensioners
        .iter()
        .enumerate()
        .filter_map(|(k, t)| {
            let clearance_m = (0..=SAMPLES)
                .map(|i| {
                    let a = t.shoe_start_rad + t.shoe_span_rad * i as f64 / SAMPLES as f64;
                    let p = [
                        t.shoe_center_m[0] + t.shoe_radius_m * a.cos(),
                        t.shoe_center_m[1] + t.shoe_radius_m * a.sin(),
                    ];
                    path.strands
                        .iter()
                        .map(|s| segment_distance(p, s.start_m, s.end_m).0)
                        .fold(f64::INFINITY, f64::min)
                })
                .fold(f64::INFINITY, f64::min)
                - chain.roller_radius_m;
            (clearance_m > 0.0).then(|| {
                format!(
                    "tensioners[{k}] (\"{}\"): at the scene's pose the chain path passes {:.2} mm clear of the shoe, so the rollers do not touch it at rest unless the tensioner swings the arm onto the strand",
                    t.name,
                    clearance_m * 1e3
                )
            })
        })
        .collect()
}
