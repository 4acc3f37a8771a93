//! A chain as laid round its path, and why a chain cannot be laid: the
//! layout's result ([`Layout`], with where it put each tensioner arm), its
//! errors and the arms' reach named in them. Data only: the laying is
//! [`super::layout`]'s (and the walk's, and the arms' in [`super::arms`]).

/// Where every roller starts and how the sprockets are turned to receive them.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Layout {
    /// Roller centres, m, in chain order (roller i linked to i + 1, cyclic).
    pub rollers_m: Vec<[f64; 2]>,
    /// Initial angle of each sprocket (gap 0 under its first seated roller), rad.
    pub sprocket_angles_rad: Vec<f64>,
    /// For each roller seated on a wrap: (sprocket, gap).
    pub seats: Vec<Option<(usize, u32)>>,
    /// Number of links in each free strand.
    pub strand_links: Vec<usize>,
    /// Length of each strand link, m.
    pub strand_link_m: f64,
    /// Length of the closed polygon through the rollers, m.
    pub polygon_length_m: f64,
    /// Pitches of chain the path through the seated rollers needs, less the
    /// chain's links: positive when the chain is short (its strand links are
    /// laid longer than the pitch), negative when it is long. At most 0.5
    /// in magnitude, unless the chain hangs ([`Self::hanging`]).
    pub misfit_pitches: f64,
    /// The chain is longer than its path by more than half a pitch and its
    /// excess hangs in the strands' sag ([`super::layout_hanging`]): the strand
    /// links are one pitch long, laid on parabolas.
    pub hanging: bool,
    /// Where each tensioner arm stands, in scene order, when the arms'
    /// shoes take up the chain's excess ([`super::layout_with_arms`]);
    /// empty when the arms stand at the scene's pose.
    pub arms: Vec<ArmPose>,
}

impl Layout {
    /// Relative stretch of the strand links as laid out, λ/P − 1: the
    /// misfit shared among the free links.
    pub(crate) fn strand_stretch(&self, pitch_m: f64) -> f64 {
        self.strand_link_m / pitch_m - 1.0
    }
}

/// Why the rollers do not fit the path.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LayoutError {
    /// The chain's length and the path's differ by more than half a pitch.
    #[error(
        "the path through the seated rollers needs {needed:.2} pitches of chain but the chain has {rollers} links ({which} by {:.2} pitches, more than the half pitch its free links take up){}",
        (needed - *rollers as f64).abs(),
        arms.as_ref().map(ToString::to_string).unwrap_or_default()
    )]
    ChainLength {
        /// Pitches the path needs.
        needed: f64,
        /// Links the chain has.
        rollers: usize,
        /// "too short" or "too long".
        which: &'static str,
        /// Nearest roller count: the layout accepts it. The message does not
        /// offer it: the equilibrium may still find its misfit too large for
        /// the pretension, and only the counts `chaindrive check` lists
        /// (`sim::count_verdicts`) are offered.
        suggest: usize,
        /// What the tensioner arms' shoes take up over their travel, where
        /// the drive has arms.
        arms: Option<ArmReach>,
    },
    /// A wrap holds no roller.
    #[error(
        "sprocket {sprocket} is wrapped by {wrap_deg:.2} degrees: the chain does not engage it"
    )]
    NoEngagement {
        /// 1-based index.
        sprocket: usize,
        /// Wrap angle, degrees.
        wrap_deg: f64,
    },
    /// A strand cannot reach the next sprocket with a whole number of links.
    #[error("the strand from sprocket {from} cannot be laid onto sprocket {to}")]
    NoLanding {
        /// 1-based index.
        from: usize,
        /// 1-based index.
        to: usize,
    },
}

/// The chain the tensioner arms take up, beside a chain they do not fit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArmReach {
    /// Take-up with the arms as far back as they go, m.
    pub min_m: f64,
    /// With the arms as far in as they go, m.
    pub max_m: f64,
    /// The chain's length less the straight path's, m.
    pub excess_m: f64,
    /// What bounds `max_m` (named in the message).
    pub(crate) bound: TakeUpBound,
}

impl std::fmt::Display for ArmReach {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "; over their travel the tensioner arms' shoes take up {:.2} to {:.2} mm of chain ({}), and the chain is {:.2} mm {} than the path with straight strands",
            self.min_m * 1e3,
            self.max_m * 1e3,
            self.bound,
            self.excess_m.abs() * 1e3,
            if self.excess_m > 0.0 {
                "longer"
            } else {
                "shorter"
            }
        )
    }
}

/// Largest mismatch, in pitches, between the chain and the path: half a
/// pitch, so that the nearest roller count always lays out.
pub(super) const MAX_LENGTH_MISMATCH_PITCHES: f64 = 0.5;

/// Where the layout put an arm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArmPose {
    /// The arm's angle from the scene's pose, rad (counter-clockwise).
    pub angle_rad: f64,
    /// The tensioner's travel there, m.
    pub travel_m: f64,
    /// The strand its shoe bends (strand k leaves sprocket k); `None`: the
    /// shoe is clear of the chain.
    pub strand: Option<usize>,
}

/// What bounds the arms' take-up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TakeUpBound {
    /// The tensioners' upper stops.
    Stops,
    /// Further in, the chain would run over the end of this arm's shoe
    /// (0-based, scene order).
    ShoeEnd(usize),
    /// Further in, no path or layout passes the shoes (a shoe's circle
    /// meets a sprocket's).
    Path,
}

impl std::fmt::Display for TakeUpBound {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Stops => write!(f, "from stop to stop"),
            Self::ShoeEnd(j) => write!(
                f,
                "further in, the chain would run over the end of the shoe of tensioners[{j}]"
            ),
            Self::Path => write!(
                f,
                "further in, the chain could not be laid between a shoe and a sprocket"
            ),
        }
    }
}

pub(super) fn length_error(needed: f64, rollers: usize) -> LayoutError {
    LayoutError::ChainLength {
        needed,
        rollers,
        which: if needed > rollers as f64 {
            "too short"
        } else {
            "too long"
        },
        suggest: needed.round().max(1.0) as usize,
        arms: None,
    }
}
