//! Geometry: tooth profiles in a sprocket's own frame, the chain's path
//! around the sprockets, and the initial layout of the rollers.
//!
//! Everything here is plain arithmetic on `[f64; 2]` points in metres and
//! radians (counter-clockwise positive). It is the lowest layer of the crate
//! and imports nothing else of it: it knows nothing of scenes, of rapier
//! bodies or of time stepping. [`crate::scene`] uses it for pitch radii and
//! generated drives, [`crate::model`] builds bodies from it and
//! [`crate::forces`] queries the profiles.
//!
//! Sprocket frame: origin at the sprocket centre, gap 0's seating centre on
//! the +x axis, gaps numbered counter-clockwise; gap j's centre at polar angle
//! j·2π/N.

mod arms;
pub mod asa;
mod circular;
mod laid;
mod layout;
mod path;
#[cfg(test)]
mod profile_tests;
pub(crate) mod shoe;
pub(crate) mod v2;
mod walk;

pub(crate) use arms::{ArmShoe, ArmTakeUp, arm_take_up, layout_with_arms};
pub use circular::CircularProfile;
pub(crate) use circular::Seats;
pub(crate) use laid::Layout;
pub use laid::{ArmReach, LayoutError};
pub(crate) use layout::{hang_excess, layout_hanging, layout_rollers, needed_pitches};
pub use path::PathError;
pub(crate) use path::{ChainPath, PathCircle, Strand, chain_path};

/// Pitch radius of a sprocket: P / (2 sin(π/N)), so that the chord between two
/// seated roller centres is exactly the pitch.
pub(crate) fn pitch_radius(pitch_m: f64, teeth: u32) -> f64 {
    pitch_m / (2.0 * (std::f64::consts::PI / f64::from(teeth)).sin())
}

/// Seating-curve radius R_t = (1.005 D_r + 0.003 in) / 2 (ASA B29.1;
/// docs/tooth-profile.md, “Constants”).
pub(crate) fn seating_radius(roller_radius_m: f64) -> f64 {
    const INCH_0_003_M: f64 = 7.62e-5;
    (1.005 * 2.0 * roller_radius_m + INCH_0_003_M) / 2.0
}

/// Which tooth profile a sprocket uses. Its names (`circular`, `real`) are
/// those of [`ProfileKind::name`]; the command line's are derived from the
/// same variants.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum ProfileKind {
    /// One seating arc per gap (the paper's §2.3).
    Circular,
    /// The ASA B29.1 tooth form (the paper's §2.4).
    Real,
}

impl ProfileKind {
    /// The name used in scene files and outputs.
    pub fn name(self) -> &'static str {
        match self {
            Self::Circular => "circular",
            Self::Real => "real",
        }
    }

    /// Parses a scene-file name.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "circular" => Some(Self::Circular),
            "real" => Some(Self::Real),
            _ => None,
        }
    }
}

/// One sample of a sprocket outline, in the sprocket frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct OutlinePoint {
    /// x in metres.
    pub x_m: f64,
    /// y in metres.
    pub y_m: f64,
    /// Gap (0..N) the sampled piece belongs to.
    pub gap: i64,
    /// Tooth-profile area of the sampled piece: 1–7 for the real profile; 4 (seating
    /// arc) or 0 (the segment across a tooth, not a contact surface) for the circular one.
    pub area: u8,
}

/// One contact patch between a roller and a tooth outline, in the sprocket frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Patch {
    /// Penetration depth δ > 0, m.
    pub depth_m: f64,
    /// Unit normal from the closest outline point towards the roller centre
    /// (when the centre is in free space): the direction of the force on the
    /// roller.
    pub normal: [f64; 2],
    /// Tooth-profile area of the piece that holds the closest point (1–7 for
    /// the real profile, 4 for the circular seat).
    pub area: u8,
    /// Gap (0..N) whose piece holds the closest point.
    pub gap: u32,
    /// Identity of the contact patch: constant while a roller slides along
    /// tangent-continuous pieces, different for separate places (the real
    /// profile's ids are described in [`asa`]).
    pub patch_id: u32,
}

/// The most patches one roller can have on one sprocket.
pub(crate) const MAX_PATCHES: usize = 2;

/// What the contact generator asks of one kind of tooth outline. The contact
/// loop is compiled once per kind ([`ToothProfile`] dispatches once per
/// sprocket, not once per roller).
pub(crate) trait Outline {
    /// Contact patches of a roller centred at `p` (sprocket frame); returns
    /// the count. `hint` is a gap the roller was recently in (any value
    /// works); it is updated to the gap found.
    fn contacts(&self, p: [f64; 2], hint: &mut u32, out: &mut [Patch; MAX_PATCHES]) -> usize;

    /// Whether a roller sliding from patch `a` onto patch `b` stays in one
    /// continuous contact (the real profile's flank → topping joint), so its
    /// remembered onset carries over.
    fn continues(&self, a: u32, b: u32) -> bool;

    /// Whether [`Self::continues`] can ever be true (false: no patch
    /// continues another, and the contact loop need not ask).
    const SLIDES: bool = true;
}

impl Outline for CircularProfile {
    #[inline(always)]
    fn contacts(&self, p: [f64; 2], hint: &mut u32, out: &mut [Patch; MAX_PATCHES]) -> usize {
        CircularProfile::contacts(self, p, hint, out)
    }

    #[inline(always)]
    fn continues(&self, _: u32, _: u32) -> bool {
        false
    }

    const SLIDES: bool = false;
}

impl Outline for asa::AsaProfile {
    #[inline(always)]
    fn contacts(&self, p: [f64; 2], hint: &mut u32, out: &mut [Patch; MAX_PATCHES]) -> usize {
        self.contacts_nominal(p, hint, out)
    }

    #[inline(always)]
    fn continues(&self, a: u32, b: u32) -> bool {
        self.patches_are_neighbours(a, b)
    }
}

/// A sprocket's tooth outline, as used by the contact generator.
#[derive(Clone, Debug)]
pub(crate) enum ToothProfile {
    /// One seating arc per gap.
    Circular(CircularProfile),
    /// ASA B29.1 Type II.
    Real(Box<asa::AsaProfile>),
}

impl ToothProfile {
    /// Builds the profile of kind `kind` for a sprocket with `teeth` teeth and
    /// a chain of pitch `pitch_m` and roller radius `roller_radius_m`.
    ///
    /// # Errors
    /// [`asa::AsaError`] when the real profile cannot be built for these inputs.
    pub(crate) fn new(
        kind: ProfileKind,
        teeth: u32,
        pitch_m: f64,
        roller_radius_m: f64,
    ) -> Result<Self, asa::AsaError> {
        Ok(match kind {
            ProfileKind::Circular => {
                Self::Circular(CircularProfile::new(teeth, pitch_m, roller_radius_m))
            }
            ProfileKind::Real => Self::Real(Box::new(asa::AsaProfile::new(
                teeth,
                pitch_m,
                2.0 * roller_radius_m,
            )?)),
        })
    }

    /// Contact patches of a roller centred at `p` (sprocket frame). Returns
    /// the count. `hint` is a gap the roller was recently in (any value
    /// works); it is updated to the gap found.
    #[inline]
    pub(crate) fn contacts(
        &self,
        p: [f64; 2],
        hint: &mut u32,
        out: &mut [Patch; MAX_PATCHES],
    ) -> usize {
        match self {
            Self::Circular(c) => Outline::contacts(c, p, hint, out),
            Self::Real(r) => Outline::contacts(&**r, p, hint, out),
        }
    }

    /// The whole outline in the sprocket frame, counter-clockwise, arcs
    /// sampled at ≤ `max_step_rad` (for drawing, colliders and the outline CSV).
    pub(crate) fn outline(&self, max_step_rad: f64) -> Vec<OutlinePoint> {
        match self {
            Self::Circular(c) => c.outline(max_step_rad),
            Self::Real(r) => r.outline(max_step_rad),
        }
    }

    /// The radius beyond which no roller centre can touch this sprocket.
    pub(crate) fn reach_m(&self) -> f64 {
        match self {
            Self::Circular(c) => c.reach_m(),
            Self::Real(r) => r.dimensions().tip_radius_m + r.dimensions().roller_diameter_m / 2.0,
        }
    }

    /// Turns the circular form's tooth-tip contact on or off
    /// ([`CircularProfile::tips`]); the real form has its tips already.
    pub(crate) fn set_tips(&mut self, on: bool) {
        if let Self::Circular(c) = self {
            c.tips = on;
        }
    }

    /// The radius at which a seated roller's centre sits on this profile.
    pub(crate) fn seated_radius_m(&self) -> f64 {
        match self {
            Self::Circular(c) => c.pitch_radius_m,
            Self::Real(r) => {
                let d = r.dimensions();
                d.pitch_radius_m - d.clearance_m
            }
        }
    }
}
