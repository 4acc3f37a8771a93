//! Generated drives: a closed chain of any length around 2 to
//! `MAX_GENERATED_SPROCKETS` sprockets, placed so that the chain's path closes with
//! exactly the requested roller count. Used by `chaindrive bench stress` and
//! by tests that need a drive the paper does not have (1,000 or 10,000
//! rollers, ten sprockets).
//!
//! A generated drive is put together with a [`SceneBuilder`] and goes
//! through the same validation as a hand-written scene
//! ([`DriveSpec::scene`]), so it is a scene like any other;
//! [`DriveSpec::toml`] gives its text.
//!
//! # Placement
//!
//! - **Two sprockets**: a conveyor along +x, driver at the origin, the other
//!   sprocket at (d, 0), both wrapped counter-clockwise.
//! - **Three or more**: the centres on a regular polygon of circumradius ρ,
//!   driver at the bottom, visited counter-clockwise, every sprocket wrapped
//!   counter-clockwise (the chain runs round the outside of a convex loop).
//!
//! The scale (d or ρ) is solved so that the path needs `rollers` pitches:
//! the free strands' tangent lengths over P plus each wrap's angle over its
//! pitch angle 2π/N. That continuous estimate is then checked against the
//! roller layout of `crate::geometry` (the walk that seats the rollers),
//! and the scale corrected by the walk's own count of needed pitches until
//! it lays out. Every sprocket keeps its full tooth count; no sprocket
//! overlaps another (else the chain is too short for the sprocket count, and
//! [`GenerateError::TooShort`] says how many rollers are needed).
//!
//! # Defaults
//!
//! The chain and the contact law are the paper's (docs/model.md, “The paper's drive”, read from
//! the embedded `l60mc.toml`): P = 88.9 mm, m_r = 3.01 kg, K = 815 MN/m,
//! D = 250 N·s/m, 21 kN pretension by rest length, K_g = 1 GN/m^1.5, e = 0.
//! The driver has 60 teeth, every other sprocket 30 (the paper's crankshaft
//! and counterweights); masses and inertias scale from the paper's 30-tooth
//! counterweight (759 kg, 82 kg·m²) as a disc does: m ∝ R², J ∝ R⁴.
//! **Gravity is off** by default: a 10,000-roller conveyor's 440 m strands
//! would sag some 34 m at 21 kN (w L²/8T); the paper's equations have no
//! gravity either. With gravity set, the placement counts the chain the
//! strands' sag holds at the pretension, q⊥² L³ / (24 T₀²) per strand
//! (shallow cable, q⊥ the weight per length across it), so the chain is
//! that much longer than its straight path and hangs
//! (`crate::geometry::layout_hanging`): the drive is feasible at its
//! pretension. Only while every strand sags by at most
//! `MAX_SAG_OVER_SPAN` of its span: a deeper one leaves its wraps too
//! steeply for the laid parabola to be a good start, and the chain is
//! closed on the straight path as without gravity (too short for its sag
//! at the pretension, which the static equilibrium names).
//!
//! This module only writes scene data; it uses `crate::geometry`'s path and
//! layout arithmetic to check the fit and knows nothing of the model or of
//! stepping.

use std::f64::consts::{PI, TAU};

use super::{
    L60MC_TOML, ProfileKind, RoleKind, Scene, SceneBuilder, SceneError, SceneFile, SolverFile,
    SprocketFile, TEETH_RANGE, Wrap,
};
use crate::geometry::{
    LayoutError, PathCircle, chain_path, layout_hanging, layout_rollers, needed_pitches,
    pitch_radius,
};

/// Most sprockets a generated drive may have (the placement's own limit,
/// well below the [`super::MAX_SPROCKETS`] any scene may have).
pub(crate) const MAX_GENERATED_SPROCKETS: usize = 16;

/// Teeth, mass and inertia of the paper's 30-tooth counterweight, the
/// reference the generated sprockets scale from.
const REFERENCE_TEETH: u32 = 30;
const REFERENCE_MASS_KG: f64 = 759.0;
const REFERENCE_INERTIA_KG_M2: f64 = 82.0;

/// Why a drive cannot be generated.
#[derive(Debug, thiserror::Error)]
pub enum GenerateError {
    /// The sprocket count is outside 2..=MAX_GENERATED_SPROCKETS.
    #[error("a generated drive has 2 to {MAX_GENERATED_SPROCKETS} sprockets, asked for {0}")]
    SprocketCount(usize),
    /// The tooth list does not match the sprocket count, or a count is out of range.
    #[error("teeth: {0}")]
    Teeth(String),
    /// The chain is too short to go round the sprockets without overlap.
    #[error(
        "{rollers} rollers cannot go round {sprockets} sprockets of these sizes without them overlapping: at least {min_rollers} are needed"
    )]
    TooShort {
        /// Rollers asked for.
        rollers: usize,
        /// Sprockets asked for.
        sprockets: usize,
        /// Fewest rollers that fit.
        min_rollers: usize,
    },
    /// The scale search did not make the roller layout fit.
    #[error("no placement lays out {rollers} rollers: {reason}")]
    NoFit {
        /// Rollers asked for.
        rollers: usize,
        /// The layout's last complaint.
        reason: String,
    },
    /// The embedded paper scene (the default chain) does not parse.
    #[error("embedded l60mc.toml: {0}")]
    Reference(String),
    /// The generated scene could not be written as TOML.
    #[error("writing the generated scene as TOML: {0}")]
    Toml(String),
    /// The generated scene failed validation (a bug in the generator).
    #[error("the generated scene is invalid: {0}")]
    Invalid(#[from] SceneError),
}

/// What to generate. [`DriveSpec::new`] gives the paper's chain and contact
/// law; change any public field before calling [`DriveSpec::scene_file`].
#[derive(Clone, Debug)]
pub struct DriveSpec {
    /// Scene name (default: `generated N rollers, k sprockets`).
    pub name: String,
    /// Number of rollers.
    pub rollers: usize,
    /// Teeth of each sprocket, driver first; its length is the sprocket count.
    pub teeth: Vec<u32>,
    /// The chain (default: the paper's); `rollers` is overwritten by [`Self::rollers`].
    pub chain: super::ChainFile,
    /// The contact law (default: the paper's).
    pub contact: super::ContactFile,
    /// Tooth profile of every sprocket.
    pub profile: ProfileKind,
    /// Driver speed, rpm, counter-clockwise positive.
    pub speed_rpm: f64,
    /// Driver ramp from rest, s.
    pub ramp_s: f64,
    /// Gravity, m/s² (default off, see the module docs).
    pub gravity_m_s2: [f64; 2],
    /// Solver settings.
    pub solver: SolverFile,
    /// Static-equilibrium settings.
    pub equilibrium: super::EquilibriumFile,
}

impl DriveSpec {
    /// The paper's chain, `rollers` long, round `sprockets` sprockets (the
    /// driver with 60 teeth, the others with 30), 120 rpm after a 0.1 s ramp.
    pub fn new(rollers: usize, sprockets: usize) -> Result<Self, GenerateError> {
        if !(2..=MAX_GENERATED_SPROCKETS).contains(&sprockets) {
            return Err(GenerateError::SprocketCount(sprockets));
        }
        let paper: SceneFile =
            toml::from_str(L60MC_TOML).map_err(|e| GenerateError::Reference(e.to_string()))?;
        let mut teeth = vec![REFERENCE_TEETH; sprockets];
        teeth[0] = 60;
        Ok(Self {
            name: format!("generated {rollers} rollers, {sprockets} sprockets"),
            rollers,
            teeth,
            chain: paper.chain,
            contact: paper.contact,
            profile: ProfileKind::Circular,
            speed_rpm: 120.0,
            ramp_s: 0.1,
            gravity_m_s2: [0.0, 0.0],
            solver: SolverFile {
                duration_s: 0.35,
                ..SolverFile::default()
            },
            equilibrium: super::EquilibriumFile::default(),
        })
    }

    /// The placed drive as a scene file.
    pub fn scene_file(&self) -> Result<SceneFile, GenerateError> {
        Ok(self.builder()?.file()?)
    }

    /// The placed drive's parts, ready to build.
    fn builder(&self) -> Result<SceneBuilder, GenerateError> {
        let k = self.teeth.len();
        if !(2..=MAX_GENERATED_SPROCKETS).contains(&k) {
            return Err(GenerateError::SprocketCount(k));
        }
        if let Some(t) = self
            .teeth
            .iter()
            .find(|&&t| !TEETH_RANGE.contains(&i64::from(t)))
        {
            return Err(GenerateError::Teeth(format!(
                "{t} teeth is outside {}..={}",
                TEETH_RANGE.start(),
                TEETH_RANGE.end()
            )));
        }
        let pitch = self.chain.pitch_m.unwrap_or(f64::NAN);
        if !(pitch > 0.0 && pitch.is_finite()) {
            return Err(GenerateError::NoFit {
                rollers: self.rollers,
                reason: format!("chain.pitch_m = {pitch} is not a positive length"),
            });
        }
        let placement = Placement {
            radii_m: self.teeth.iter().map(|&t| pitch_radius(pitch, t)).collect(),
            teeth: self.teeth.clone(),
            pitch_m: pitch,
            clearance_m: 2.0 * self.chain.roller_radius_m.unwrap_or(0.0),
            sag: (self.gravity_m_s2 != [0.0, 0.0] && self.chain.pretension_n > 0.0).then(|| Sag {
                gravity_m_s2: self.gravity_m_s2,
                mass_per_m_per_n: self.chain.roller_mass_kg.unwrap_or(0.0)
                    / pitch
                    / self.chain.pretension_n,
            }),
        };
        let centres = placement.solve(self.rollers)?;
        let sprockets = centres
            .iter()
            .zip(&self.teeth)
            .enumerate()
            .map(|(i, (c, &teeth))| {
                let scale =
                    (pitch_radius(pitch, teeth) / pitch_radius(pitch, REFERENCE_TEETH)).powi(2);
                let driver = i == 0;
                SprocketFile {
                    name: if driver {
                        "driver".to_owned()
                    } else {
                        format!("sprocket {}", i + 1)
                    },
                    center_m: *c,
                    teeth: i64::from(teeth),
                    pitch_radius_m: None,
                    mass_kg: REFERENCE_MASS_KG * scale,
                    inertia_kg_m2: REFERENCE_INERTIA_KG_M2 * scale * scale,
                    wrap: Wrap::Ccw.name().to_owned(),
                    role: if driver {
                        RoleKind::Driver
                    } else {
                        RoleKind::Free
                    }
                    .name()
                    .to_owned(),
                    speed_rpm: driver.then_some(self.speed_rpm),
                    ramp_s: driver.then_some(self.ramp_s),
                    run_up: None,
                    load_torque_n_m: None,
                    load_ramp_s: None,
                    resisting_torque_n_m: None,
                    resisting_speed_rad_s: None,
                    adjust_direction: None,
                    profile: None,
                    speed_harmonics: Vec::new(),
                    load_harmonics: Vec::new(),
                    load_table: None,
                    governor: None,
                }
            })
            .collect::<Vec<_>>();
        let mut chain = self.chain.clone();
        chain.rollers = i64::try_from(self.rollers).unwrap_or(i64::MAX);
        Ok(Scene::builder(self.name.clone())
            .gravity_m_s2(self.gravity_m_s2)
            .profile(self.profile)
            .chain(chain)
            .contact(self.contact.clone())
            .sprockets(sprockets)
            .solver(self.solver.clone())
            .equilibrium(self.equilibrium.clone()))
    }

    /// The scene file's TOML text.
    pub fn toml(&self) -> Result<String, GenerateError> {
        toml::to_string(&self.scene_file()?).map_err(|e| GenerateError::Toml(e.to_string()))
    }

    /// The validated scene, checked like a user's file.
    pub fn scene(&self) -> Result<Scene, GenerateError> {
        Ok(self.builder()?.build()?)
    }
}

/// The sprockets' sizes; solves for their centres.
struct Placement {
    radii_m: Vec<f64>,
    teeth: Vec<u32>,
    pitch_m: f64,
    /// Gap kept between two sprockets' pitch circles (a roller diameter).
    clearance_m: f64,
    /// Under gravity, what the strands' sag holds.
    sag: Option<Sag>,
}

/// The chain's weight and tension that set its strands' sag.
struct Sag {
    /// Gravity, m/s².
    gravity_m_s2: [f64; 2],
    /// Chain mass per length over the pretension, kg/(m·N).
    mass_per_m_per_n: f64,
}

/// Deepest sag, over its span, that a generated drive's strands are laid
/// with: s / L = q⊥ L / (8 T₀). Deeper strands leave their wraps so steeply
/// (4 s / L, above 11°) that the laid parabola is a poor start.
pub(crate) const MAX_SAG_OVER_SPAN: f64 = 0.05;

impl Sag {
    /// Pitches of chain the strands of `path` hold in their sag beyond
    /// their spans: q⊥² L³ / (24 T₀²) each (shallow cable), q⊥ the weight
    /// per length across the strand; 0 where a strand would sag deeper
    /// than [`MAX_SAG_OVER_SPAN`] (the chain is then laid straight).
    fn pitches(&self, path: &crate::geometry::ChainPath, pitch_m: f64) -> f64 {
        let [gx, gy] = self.gravity_m_s2;
        let q_over_t = |st: &crate::geometry::Strand| {
            let [dx, dy] = st.direction();
            self.mass_per_m_per_n * (dx * gy - dy * gx).abs()
        };
        if path
            .strands
            .iter()
            .any(|st| q_over_t(st) * st.length_m / 8.0 > MAX_SAG_OVER_SPAN)
        {
            return 0.0;
        }
        path.sag_take_up_m(self.mass_per_m_per_n, self.gravity_m_s2, 1.0) / pitch_m
    }
}

impl Placement {
    /// Centres at scale `s` (centre distance for two, circumradius for more).
    fn centres(&self, s: f64) -> Vec<[f64; 2]> {
        let k = self.radii_m.len();
        if k == 2 {
            return vec![[0.0, 0.0], [s, 0.0]];
        }
        (0..k)
            .map(|j| {
                let a = -PI / 2.0 + TAU * j as f64 / k as f64;
                [s * a.cos(), s * a.sin() + s]
            })
            .collect()
    }

    fn circles(&self, s: f64) -> Vec<PathCircle> {
        self.centres(s)
            .into_iter()
            .zip(&self.radii_m)
            .map(|(center_m, &radius_m)| PathCircle {
                center_m,
                radius_m,
                sense: 1.0,
            })
            .collect()
    }

    /// Smallest scale at which no two pitch circles (plus clearance) overlap.
    fn min_scale(&self) -> f64 {
        let k = self.radii_m.len();
        let r = |i: usize| self.radii_m[i % k];
        let mut need: f64 = 0.0;
        for i in 0..k {
            for j in i + 1..k {
                // Distance between vertices i and j at unit scale.
                let unit = if k == 2 {
                    1.0
                } else {
                    2.0 * (PI * (j - i) as f64 / k as f64).sin()
                };
                need = need.max((r(i) + r(j) + self.clearance_m) / unit);
            }
        }
        need * (1.0 + 1e-9)
    }

    /// Pitches of chain the path at scale `s` needs: strands over P plus
    /// each wrap over its pitch angle, plus what the strands' sag holds.
    fn needed(&self, s: f64) -> Option<f64> {
        let path = chain_path(&self.circles(s)).ok()?;
        let strands: f64 = path.strands.iter().map(|st| st.length_m).sum::<f64>() / self.pitch_m;
        let wraps: f64 = path
            .wraps
            .iter()
            .zip(&self.teeth)
            .map(|(w, &n)| w.wrap_rad * f64::from(n) / TAU)
            .sum();
        let sag = self
            .sag
            .as_ref()
            .map_or(0.0, |g| g.pitches(&path, self.pitch_m));
        Some(strands + wraps + sag)
    }

    /// The walk's verdict at scale `s`: `Ok` if the rollers lay out, else the
    /// walk's count of needed pitches (or the reason it failed).
    fn lays_out(&self, s: f64, rollers: usize) -> Result<(), Result<f64, String>> {
        let circles = self.circles(s);
        let path = chain_path(&circles).map_err(|e| Err(e.to_string()))?;
        if let Some(sag) = &self.sag {
            // The walk's own count plus the sag, within a tenth of a pitch
            // (what the model's layout lets the sag hold beyond its own);
            // the excess then hangs in the strands.
            let walk = needed_pitches(&path, &circles, &self.teeth, self.pitch_m)
                .map_err(|e| Err(e.to_string()))?;
            let needed = walk + sag.pitches(&path, self.pitch_m);
            if (needed - rollers as f64).abs() > 0.1 {
                return Err(Ok(needed));
            }
            return layout_hanging(
                &path,
                &circles,
                &self.teeth,
                rollers,
                self.pitch_m,
                sag.gravity_m_s2,
            )
            .map(|_| ())
            .map_err(|e| Err(e.to_string()));
        }
        match layout_rollers(&path, &circles, &self.teeth, rollers, self.pitch_m) {
            Ok(_) => Ok(()),
            Err(LayoutError::ChainLength { needed, .. }) => Err(Ok(needed)),
            Err(e) => Err(Err(e.to_string())),
        }
    }

    /// Centres for a chain of `rollers` pitches.
    fn solve(&self, rollers: usize) -> Result<Vec<[f64; 2]>, GenerateError> {
        let target = rollers as f64;
        let lo = self.min_scale();
        let no_fit = |reason: String| GenerateError::NoFit { rollers, reason };
        let at_lo = self
            .needed(lo)
            .ok_or_else(|| no_fit("no chain path at the smallest spacing".to_owned()))?;
        if at_lo > target - 0.5 {
            return Err(GenerateError::TooShort {
                rollers,
                sprockets: self.radii_m.len(),
                min_rollers: at_lo.ceil() as usize + 1,
            });
        }
        let mut hi = 2.0 * lo;
        while self.needed(hi).is_some_and(|n| n < target) {
            hi *= 2.0;
            if !hi.is_finite() {
                return Err(no_fit("the scale search diverged".to_owned()));
            }
        }
        // Bisection on the continuous estimate (monotone in the scale).
        let mut lo = lo;
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            match self.needed(mid) {
                Some(n) if n < target => lo = mid,
                _ => hi = mid,
            }
        }
        // Correct by the walk's own count: d(needed)/d(scale) from the estimate.
        let mut s = 0.5 * (lo + hi);
        let h = 1e-6 * s;
        let slope = match (self.needed(s + h), self.needed(s - h)) {
            (Some(a), Some(b)) if a > b => (a - b) / (2.0 * h),
            _ => {
                return Err(no_fit(
                    "the path length does not grow with the spacing".into(),
                ));
            }
        };
        let mut last = String::new();
        for _ in 0..8 {
            match self.lays_out(s, rollers) {
                Ok(()) => return Ok(self.centres(s)),
                Err(Ok(needed)) => {
                    last = format!("the path needs {needed:.3} pitches");
                    s += (target - needed) / slope;
                }
                Err(Err(reason)) => return Err(no_fit(reason)),
            }
        }
        Err(no_fit(last))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_sprockets_centre_distance_matches_the_closed_form() {
        // Equal sprockets: needed pitches = 2 d / P + N, so d = (n − N) P / 2.
        let mut spec = DriveSpec::new(200, 2).expect("spec");
        spec.teeth = vec![30, 30];
        let file = spec.scene_file().expect("placed");
        let d = file.sprockets[1].center_m[0];
        let expected = (200.0 - 30.0) * 0.0889 / 2.0;
        assert!((d - expected).abs() < 0.25 * 0.0889, "{d} vs {expected}");
    }

    #[test]
    fn under_gravity_the_chain_holds_its_strands_sag() {
        // A 400-roller conveyor of the paper's chain (q = m_r g / P =
        // 3.01 · 9.81 / 0.0889 = 332 N/m) at 21 kN: two horizontal strands of
        // span L each hold q² L³ / (24 T²) beyond their spans (shallow
        // cable); with L ≈ 16.4 m, 46 mm each, about a pitch in all. The
        // chain is that much longer than its straight path, within the
        // tenth of a pitch the placement allows (laid straight, it would be
        // within half a pitch of the path instead), and the strands sag by
        // s / L = q L / (8 T) ≈ 0.03, under the twentieth a generated
        // strand may.
        let mut spec = DriveSpec::new(400, 2).expect("spec");
        spec.teeth = vec![30, 30];
        spec.gravity_m_s2 = [0.0, -9.81];
        let scene = spec.scene().expect("placed");
        let chain = scene.chain();
        let circles: Vec<PathCircle> = scene
            .sprockets()
            .iter()
            .map(|s| PathCircle {
                center_m: s.center_m,
                radius_m: s.pitch_radius_m,
                sense: 1.0,
            })
            .collect();
        let path = chain_path(&circles).expect("a path");
        let span = path.strands[0].length_m;
        let q = chain.roller_mass_kg * 9.81 / chain.pitch_m;
        let sag_m = 2.0 * q * q * span.powi(3) / (24.0 * chain.pretension_n.powi(2));
        let needed = needed_pitches(&path, &circles, &[30, 30], chain.pitch_m).expect("walks");
        let excess_m = (chain.rollers as f64 - needed) * chain.pitch_m;
        assert!(
            (excess_m - sag_m).abs() < 0.1 * chain.pitch_m,
            "the chain is {excess_m} m longer than its path, its sag holds {sag_m} m"
        );
        assert!(q * span / (8.0 * chain.pretension_n) < MAX_SAG_OVER_SPAN);
    }

    #[test]
    fn too_short_a_chain_says_how_many_rollers_fit() {
        let err = DriveSpec::new(40, 10)
            .and_then(|s| s.scene())
            .expect_err("too short");
        assert!(matches!(err, GenerateError::TooShort { .. }), "{err}");
        assert!(err.to_string().contains("at least"), "{err}");
    }

    #[test]
    fn sprocket_count_is_checked() {
        assert!(matches!(
            DriveSpec::new(100, 1),
            Err(GenerateError::SprocketCount(1))
        ));
    }

    #[test]
    fn generated_scene_round_trips_through_toml() {
        let spec = DriveSpec::new(300, 5).expect("spec");
        let scene = spec.scene().expect("valid");
        assert_eq!(scene.chain.rollers, 300);
        assert_eq!(scene.sprockets.len(), 5);
        // The same scene, bit for bit, when it is written out and read back.
        let mut parsed = Scene::from_toml(&spec.toml().expect("toml")).expect("valid");
        parsed.source_toml = None;
        assert_eq!(parsed, scene);
    }
}
