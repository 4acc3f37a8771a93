//! Guides in a scene (`[[guides]]`): the file form, the validated form and
//! their checks (docs/model.md, “Guides”).
//!
//! A guide is a fixed shoe — straight, or a circular arc given by a radius or
//! a centre — with optional lead-in ramps at its ends. The side its face
//! works on follows from the chain's nominal path: the face pushes towards
//! the path. A guide the path does not reach gets a warning
//! ([`super::Scene::warnings`]).

use serde::{Deserialize, Serialize};

use super::checker::Checker;
use super::{Chain, Contact, Integrator, Solver, Sprocket, Stepping};
use crate::geometry::shoe::{Face, Piece, Ramp, ShoeError, body_from_centre, body_from_radius};
use crate::geometry::v2::segment_distance;
use crate::geometry::{ChainPath, PathCircle, chain_path};

/// Regularisation speed v_s of the guides' friction when the scene gives
/// none, m/s: small beside the chain's speed along a guide (0.4 m/s at the
/// paper's drive's 120 rpm on its 36-tooth crankshaft sprocket… metres per
/// second on faster drives), so a sliding roller feels very nearly μ f_n.
pub(crate) const DEFAULT_GUIDE_SLIP_SPEED_M_S: f64 = 0.01;

/// One guide as written (`[[guides]]`).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct GuideFile {
    /// Name, for outputs.
    pub name: String,
    /// First end of the shoe's working face, m.
    pub start_m: [f64; 2],
    /// Second end, m.
    pub end_m: [f64; 2],
    /// An arc shoe: its radius, m; positive if the arc bends to the left of
    /// start → end (its centre on the left), negative to the right.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius_m: Option<f64>,
    /// An arc shoe: its centre, m (instead of `radius_m`; the shorter arc).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub center_m: Option<[f64; 2]>,
    /// Lead-in ramp at `start_m`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) start_ramp: Option<RampFile>,
    /// Lead-in ramp at `end_m`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) end_ramp: Option<RampFile>,
    /// Contact stiffness K_g, N/m^n (n the scene's `contact.exponent`;
    /// default: the scene's `contact.stiffness`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness: Option<f64>,
    /// Coefficient of restitution e in [0, 1] (default: the scene's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restitution: Option<f64>,
    /// Coulomb friction coefficient μ between rollers and shoe, in [0, 1]
    /// (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<f64>,
    /// Regularisation speed v_s of the friction, m/s (default 0.01).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slip_speed_m_s: Option<f64>,
    /// The guide's contact is evaluated at every this many steps and its
    /// force applied as an impulse of that many steps (default 1: every
    /// step; docs/model.md, “Guides”, “A guide evaluated every k steps”).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub every_steps: Option<f64>,
}

/// A lead-in ramp as written.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RampFile {
    /// Length along the ramp, m.
    pub length_m: f64,
    /// Angle away from the face's end tangent, degrees, in (0, 45].
    pub angle_deg: f64,
}

/// A validated guide.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Guide {
    /// Name.
    pub name: String,
    /// The working face, its side fixed by the chain path.
    pub face: Face,
    /// The contact law: the scene's, at this stiffness and restitution.
    pub contact: Contact,
    /// Coulomb coefficient μ.
    pub friction: f64,
    /// Regularisation speed v_s, m/s.
    pub slip_speed_m_s: f64,
    /// The nominal path's clearance from the face, m: its smallest distance
    /// from the face less the roller radius (≤ 0: the rollers press on it).
    pub clearance_m: f64,
    /// Steps between the contact's evaluations (1: every step).
    pub every_steps: u32,
}

/// The largest `every_steps` accepted.
const MAX_EVERY_STEPS: f64 = 1000.0;

/// The rollers' largest reach beyond a sprocket's pitch circle where a shoe
/// must not be: a seated roller's outside edge.
fn sprocket_reach_m(s: &Sprocket, chain: &Chain) -> f64 {
    s.pitch_radius_m + chain.roller_radius_m
}

/// Checks `[[guides]]`. `sprockets` and `chain` are the validated ones (a
/// guide is not placed when they hold errors: its checks need their
/// geometry).
pub(super) fn check_guides(
    c: &mut Checker,
    files: &[GuideFile],
    chain: &Chain,
    contact: &Contact,
    sprockets: &[Sprocket],
    solver: &Solver,
) -> Vec<Guide> {
    let circles: Vec<PathCircle> = sprockets
        .iter()
        .map(|s| PathCircle {
            center_m: s.center_m,
            radius_m: s.pitch_radius_m,
            sense: s.wrap.sign(),
        })
        .collect();
    let drive = Drive {
        chain,
        contact,
        sprockets,
        solver,
        path: chain_path(&circles).ok(),
    };
    files
        .iter()
        .enumerate()
        .filter_map(|(k, f)| check_guide(c, k, f, &drive))
        .collect()
}

/// What a guide is checked against: the validated drive and its path
/// (`None` where the sprockets lay none).
struct Drive<'a> {
    chain: &'a Chain,
    contact: &'a Contact,
    sprockets: &'a [Sprocket],
    solver: &'a Solver,
    path: Option<ChainPath>,
}

/// A guide's fields as checked, before its shoe is placed.
struct GuideFields {
    start_ramp: Option<Ramp>,
    end_ramp: Option<Ramp>,
    stiffness: f64,
    restitution: f64,
    friction: f64,
    slip_speed_m_s: f64,
    every_steps: u32,
}

/// Guide `k` (`guides[k]`), or `None` where it fails a check.
fn check_guide(c: &mut Checker, k: usize, f: &GuideFile, drive: &Drive<'_>) -> Option<Guide> {
    let at = |field: &str| format!("guides[{k}].{field}");
    let errors_before = c.errors.len();
    let fields = check_fields(c, k, f, drive.contact, drive.solver);
    if c.errors.len() > errors_before {
        return None;
    }
    let body = match f.center_m {
        Some(centre) => body_from_centre(f.start_m, f.end_m, centre),
        None => body_from_radius(f.start_m, f.end_m, f.radius_m),
    };
    let body = match body {
        Ok(b) => b,
        Err(e) => {
            let field = match e {
                ShoeError::DegenerateEnds => "end_m",
                ShoeError::RadiusTooShort { .. } => "radius_m",
                ShoeError::CentreOff { .. } => "center_m",
            };
            c.fail(at(field), e.to_string());
            return None;
        }
    };
    let path = drive.path.as_ref()?;
    if inside_a_sprocket(c, k, &body, drive) {
        return None;
    }
    let nearest = nearest_on_strands(&body, path)?;
    let Some(side) = crate::geometry::shoe::side_of(&body, nearest) else {
        c.fail(
            at("start_m"),
            "the shoe's middle lies on the chain path, so the side it presses from is undefined: move it by the roller radius less the pressing depth to the side it should press from",
        );
        return None;
    };
    let face = Face::new(body, side, fields.start_ramp, fields.end_ramp);
    // Clearance: the path's smallest distance from the body, sampled
    // finely along the body, less the roller radius.
    const SAMPLES: usize = 64;
    let clearance_m = (0..=SAMPLES)
        .map(|i| {
            let p = body.point_at(i as f64 / SAMPLES as f64);
            path.strands
                .iter()
                .map(|s| segment_distance(p, s.start_m, s.end_m).0)
                .fold(f64::INFINITY, f64::min)
        })
        .fold(f64::INFINITY, f64::min)
        - drive.chain.roller_radius_m;
    Some(Guide {
        name: f.name.clone(),
        face,
        contact: Contact {
            stiffness: fields.stiffness,
            restitution: fields.restitution,
            ..*drive.contact
        },
        friction: fields.friction,
        slip_speed_m_s: fields.slip_speed_m_s,
        clearance_m,
        every_steps: fields.every_steps,
    })
}

/// Guide `k`'s own fields, the contact's where it gives none.
fn check_fields(
    c: &mut Checker,
    k: usize,
    f: &GuideFile,
    contact: &Contact,
    solver: &Solver,
) -> GuideFields {
    let at = |field: &str| format!("guides[{k}].{field}");
    if f.name.trim().is_empty() {
        c.fail(at("name"), "must not be empty");
    }
    for (i, v) in f.start_m.iter().enumerate() {
        c.finite(&format!("guides[{k}].start_m[{i}]"), *v);
    }
    for (i, v) in f.end_m.iter().enumerate() {
        c.finite(&format!("guides[{k}].end_m[{i}]"), *v);
    }
    let ramp = |c: &mut Checker, field: &str, r: &Option<RampFile>| {
        r.as_ref().map(|r| {
            let length_m = c.positive(&at(&format!("{field}.length_m")), r.length_m);
            let angle = c.positive(&at(&format!("{field}.angle_deg")), r.angle_deg);
            if angle.is_finite() && angle > 45.0 {
                c.fail(
                    at(&format!("{field}.angle_deg")),
                    format!("must lie in (0, 45] degrees, got {angle}"),
                );
            }
            Ramp {
                length_m,
                angle_rad: angle.to_radians(),
            }
        })
    };
    let start_ramp = ramp(c, "start_ramp", &f.start_ramp);
    let end_ramp = ramp(c, "end_ramp", &f.end_ramp);
    let stiffness = f
        .stiffness
        .map_or(contact.stiffness, |k| c.positive(&at("stiffness"), k));
    let restitution = match f.restitution {
        Some(e) => {
            let e = c.finite(&at("restitution"), e);
            if !(0.0..=1.0).contains(&e) {
                c.fail(at("restitution"), format!("must lie in [0, 1], got {e}"));
            } else if e == 0.0 && contact.law.needs_positive_restitution() {
                c.fail(
                    at("restitution"),
                    "must be > 0 with this contact law (its damping factor is infinite at e = 0)",
                );
            }
            e
        }
        None => contact.restitution,
    };
    let friction = f.friction.map_or(0.0, |mu| {
        let mu = c.non_negative(&at("friction"), mu);
        if mu > 1.0 {
            c.fail(at("friction"), format!("must lie in [0, 1], got {mu}"));
        }
        mu
    });
    let slip_speed_m_s = f.slip_speed_m_s.map_or(DEFAULT_GUIDE_SLIP_SPEED_M_S, |v| {
        c.positive(&at("slip_speed_m_s"), v)
    });
    if let Some(r) = f.radius_m {
        c.finite(&at("radius_m"), r);
        if r == 0.0 {
            c.fail(
                at("radius_m"),
                "must not be 0 (leave it out for a straight guide)",
            );
        }
    }
    if let Some(centre) = f.center_m {
        for (i, v) in centre.iter().enumerate() {
            c.finite(&format!("guides[{k}].center_m[{i}]"), *v);
        }
    }
    if f.radius_m.is_some() && f.center_m.is_some() {
        c.fail(
            at("center_m"),
            "give either radius_m or center_m for an arc, not both",
        );
    }
    GuideFields {
        start_ramp,
        end_ramp,
        stiffness,
        restitution,
        friction,
        slip_speed_m_s,
        every_steps: check_every_steps(c, k, f.every_steps, solver),
    }
}

/// Guide `k`'s `every_steps`: a whole number in [1, 1000], above 1 only
/// where one evaluation of the forces ends each step (the impulse is then
/// applied at a step's end, where no inner stage reads the forces).
fn check_every_steps(c: &mut Checker, k: usize, every: Option<f64>, solver: &Solver) -> u32 {
    let field = format!("guides[{k}].every_steps");
    let Some(every) = every else {
        return 1;
    };
    if !(every.fract() == 0.0 && (1.0..=MAX_EVERY_STEPS).contains(&every)) {
        c.fail(
            &field,
            format!("must be a whole number of steps from 1 to {MAX_EVERY_STEPS}, got {every}"),
        );
        return 1;
    }
    let one_evaluation = matches!(
        solver.integrator,
        Integrator::SymplecticEuler
            | Integrator::ImplicitDamping
            | Integrator::VerletImplicitDamping
    );
    if every > 1.0 && !(one_evaluation && solver.stepping == Stepping::Substepped) {
        c.fail(
            &field,
            format!(
                "above 1 needs solver.integrator = \"symplectic_euler\", \"implicit_damping\" or \"verlet_implicit_damping\" and solver.stepping = \"substepped\" (one evaluation of the forces a step); the scene has \"{}\"",
                solver.integrator.name()
            ),
        );
        return 1;
    }
    every as u32
}

/// Whether guide `k`'s shoe `body` lies inside a sprocket's reach, where
/// the seated rollers would run into it (each such sprocket a failure).
fn inside_a_sprocket(c: &mut Checker, k: usize, body: &Piece, drive: &Drive<'_>) -> bool {
    let mut inside = false;
    for s in drive.sprockets {
        let d = shoe_distance(body, s.center_m);
        let reach = sprocket_reach_m(s, drive.chain);
        if d < reach {
            c.fail(
                format!("guides[{k}].start_m"),
                format!(
                    "the shoe passes {d:.4} m from sprocket \"{}\"'s centre, inside the {reach:.4} m its seated rollers reach (pitch radius + roller radius): a guide must lie beside the free strands",
                    s.name
                ),
            );
            inside = true;
        }
    }
    inside
}

/// The nearest point of the free strands from the shoe's middle: the side
/// it presses from is towards it.
fn nearest_on_strands(body: &Piece, path: &ChainPath) -> Option<[f64; 2]> {
    let middle = body.point_at(0.5);
    path.strands
        .iter()
        .map(|s| {
            let ab = [s.end_m[0] - s.start_m[0], s.end_m[1] - s.start_m[1]];
            let len2 = ab[0] * ab[0] + ab[1] * ab[1];
            let t = if len2 > 0.0 {
                (((middle[0] - s.start_m[0]) * ab[0] + (middle[1] - s.start_m[1]) * ab[1]) / len2)
                    .clamp(0.0, 1.0)
            } else {
                0.0
            };
            [s.start_m[0] + t * ab[0], s.start_m[1] + t * ab[1]]
        })
        .min_by(|a, b| {
            let da = (a[0] - middle[0]).hypot(a[1] - middle[1]);
            let db = (b[0] - middle[0]).hypot(b[1] - middle[1]);
            da.total_cmp(&db)
        })
}

/// Smallest distance from `p` to a shoe's body.
fn shoe_distance(body: &Piece, p: [f64; 2]) -> f64 {
    match *body {
        Piece::Segment { a, b } => segment_distance(p, a, b).0,
        Piece::Arc { .. } => {
            const SAMPLES: usize = 256;
            (0..=SAMPLES)
                .map(|i| {
                    let q = body.point_at(i as f64 / SAMPLES as f64);
                    (q[0] - p[0]).hypot(q[1] - p[1])
                })
                .fold(f64::INFINITY, f64::min)
        }
    }
}

/// The warnings of a scene's guides: each guide the nominal path does not
/// reach.
pub(super) fn warnings(guides: &[Guide]) -> Vec<String> {
    guides
        .iter()
        .enumerate()
        .filter(|(_, g)| g.clearance_m > 0.0)
        .map(|(k, g)| {
            format!(
                "guides[{k}] (\"{}\"): the chain path passes {:.2} mm clear of the shoe, so the rollers do not touch it at rest",
                g.name,
                g.clearance_m * 1e3
            )
        })
        .collect()
}
