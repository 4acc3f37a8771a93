//! Why the static equilibrium or a fit fails: the errors of the statics,
//! in one file that every other file of the statics may name and that
//! names none of them.

/// A roller on the rim of the circular profile's seating arc, where no
/// force of that profile holds it (see the feasibility module): pulled
/// beyond the arc, or held on its edge where the contact force jumps to
/// zero. The drive has no smooth rest state with this profile.
#[derive(Clone, Debug, PartialEq)]
pub struct BeyondSeatingArc {
    /// The roller.
    pub roller: usize,
    /// The sprocket's name.
    pub sprocket: String,
    /// The gap, as the profile numbers it.
    pub gap: u32,
    /// Pulled beyond the arc: the angle between the roller's pull and the
    /// arc's edge; held on the edge: how far beyond the edge the roller's
    /// offset from its seating centre points; degrees.
    pub beyond_deg: f64,
    /// The pull's component radially outward (negative: inward), N.
    pub outward_n: f64,
    /// Its component along the pitch circle, N.
    pub along_n: f64,
    /// Held on the edge (pulled back towards the gap, not beyond it): how
    /// far the roller's centre lies outside the seating circle, m. `None`:
    /// pulled beyond the arc.
    pub edge_depth_m: Option<f64>,
    /// Largest roller force at the rest state reached, relative to the pretension.
    pub residual: f64,
}

impl std::fmt::Display for BeyondSeatingArc {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let Self {
            roller,
            sprocket,
            gap,
            beyond_deg,
            outward_n,
            along_n,
            residual,
            ..
        } = self;
        match self.edge_depth_m {
            None => write!(
                f,
                "roller {roller} is pulled {beyond_deg:.1}° beyond the seating arc of gap {gap} on sprocket \"{sprocket}\" ({outward_n:.3} N outward, {along_n:.3} N along the pitch circle)"
            )?,
            Some(depth_m) => write!(
                f,
                "roller {roller} is held on the edge of the seating arc of gap {gap} on sprocket \"{sprocket}\", {:.1} µm outside its seating circle and {beyond_deg:.2}° beyond the edge ({:.3} N inward, {along_n:.3} N along the pitch circle): one step inwards the seat pushes it with the contact's full force at that depth, one step out nothing does",
                depth_m * 1e6,
                -outward_n
            )?,
        }
        write!(
            f,
            ": the circular profile holds a roller only on the half of its seating circle facing the sprocket's centre, so this drive has no smooth rest state with it (the rest state reached leaves {residual:.2e} of the pretension out of balance); the real tooth form holds it (profile = \"real\"), or another load moves the roller off the rim"
        )
    }
}

impl std::error::Error for BeyondSeatingArc {}

/// Why no equilibrium was found.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EquilibriumError {
    /// No free strand link exists to measure the tension on.
    #[error("no free strand link to measure the static tension on")]
    NoFreeLinks,
    /// A roller at rest lies so far behind a fixed guide's entry, or behind
    /// the end of a tensioner arm's shoe as the arm stands at rest, that,
    /// carried onto it, it would meet the face beyond the blow-up limit
    /// (the sentence names the guide or shoe, the roller, the depth and the
    /// remedy).
    #[error("{0}")]
    BehindGuideEntry(String),
    /// The tensioner rule needs a sprocket with role = "tensioner".
    #[error("pretension_by = \"tensioner\" but no sprocket is a tensioner")]
    NoTensioner,
    /// The tensioner's travel along its adjustment direction cannot make
    /// the chain fit (the sprocket's move is in the message).
    #[error("the tensioner \"{sprocket}\" cannot take up the chain: {reason}")]
    TensionerFit {
        /// The tensioner's name.
        sprocket: String,
        /// Why no position along its direction fits (boxed: it is large).
        reason: Box<FitError>,
    },
    /// The pretension iteration did not converge.
    #[error(
        "static tension {tension_n:.1} N after {iterations} iterations, target {target_n:.1} N"
    )]
    NotConverged {
        /// Reached tension, N.
        tension_n: f64,
        /// Target, N.
        target_n: f64,
        /// Iterations used.
        iterations: usize,
    },
    /// The pretension iteration ran out of iterations with a body not at rest.
    #[error(
        "static tension {tension_n:.1} N after {iterations} iterations, target {target_n:.1} N: {body}"
    )]
    Unsettled {
        /// Reached tension, N.
        tension_n: f64,
        /// Target, N.
        target_n: f64,
        /// Iterations used.
        iterations: usize,
        /// The body furthest from equilibrium and its residual.
        body: String,
    },
    /// The chain is too short for the pretension (see the feasibility module).
    #[error(
        "the chain is {short_m:.4} m ({short_pitches:.2} pitches) shorter than the path through the seated rollers{}, but at chain.pretension_n its {free_links} free links stretch {allowed_m:.2e} m in all; it would carry about {needed_tension_n:.0} N: add rollers or move the sprockets closer",
        if *sag_m > 0.0 { format!(" plus the {sag_m:.2e} m its strands' sag holds at chain.pretension_n") } else { String::new() }
    )]
    ChainTooShort {
        /// Missing length (the seated path plus the sag at the pretension, less the chain), m.
        short_m: f64,
        /// Length the strands' sag holds at the pretension (gravity), m.
        sag_m: f64,
        /// Missing length, pitches.
        short_pitches: f64,
        /// Links of the free strands.
        free_links: usize,
        /// Length the pretension takes up, m.
        allowed_m: f64,
        /// Static tension the short chain would carry (its links' stretch
        /// taking up what it lacks, the strands' sag at that tension
        /// included), N.
        needed_tension_n: f64,
    },
    /// The chain is longer than its path by more than the strands' sag at
    /// the pretension takes up (see the feasibility module).
    #[error(
        "the chain is {long_m:.4} m ({long_pitches:.2} pitches) longer than the path through the seated rollers, but at chain.pretension_n = {pretension_n:.1} N the strands' sag takes up only {sag_m:.2e} m{}: a chain longer than its path has no equilibrium at the pretension; remove rollers or move the sprockets apart{}",
        arms_m.map(|a| format!(" and the tensioner arms' shoes at most {a:.2e} m over their travel")).unwrap_or_default(),
        match sag_tension_n {
            Some(t) => format!(", or lower chain.pretension_n to about {t:.0} N, where the strands sag by that much"),
            None => " (without gravity the strands cannot sag)".to_owned(),
        }
    )]
    ChainTooLong {
        /// Excess length, m.
        long_m: f64,
        /// Excess length, pitches.
        long_pitches: f64,
        /// Length the strands' sag takes up at the pretension, m.
        sag_m: f64,
        /// Pretension, N.
        pretension_n: f64,
        /// Pretension at which the sag takes up the excess, N (none without gravity).
        sag_tension_n: Option<f64>,
        /// What the tensioner arms' shoes take up at most over their
        /// travel, m (none without arms).
        arms_m: Option<f64>,
    },
    /// The loads on several sprockets leave a free strand in compression.
    #[error(
        "at chain.pretension_n = {pretension_n:.1} N the load torques leave strand {strand} ({context}) carrying {tension_n:.1} N: a strand cannot carry compression; raise chain.pretension_n to at least {needed_n:.1} N or reduce the loads"
    )]
    StrandCompression {
        /// The strand, 1-based (strand k leaves sprocket k).
        strand: usize,
        /// Its static tension, N (negative).
        tension_n: f64,
        /// Pretension, N.
        pretension_n: f64,
        /// Least pretension that keeps every strand in tension, N.
        needed_n: f64,
        /// The sprockets the strand runs between and the loads at rest, for the message.
        context: String,
    },
    /// A load torque needs more pretension than the scene has.
    #[error(
        "load torque {load_n_m} N·m on sprocket \"{sprocket}\" exceeds the {limit_n_m:.1} N·m the slack strand can hold at chain.pretension_n = {pretension_n:.1} N (it would need compression); raise chain.pretension_n to at least {needed_n:.1} N"
    )]
    LoadBeyondPretension {
        /// The loaded sprocket's name.
        sprocket: String,
        /// Its load torque, N·m.
        load_n_m: f64,
        /// Largest load the pretension holds, N·m.
        limit_n_m: f64,
        /// Pretension, N.
        pretension_n: f64,
        /// Least pretension that holds the load, N.
        needed_n: f64,
    },
    /// The relaxation itself blew up (dt too large for the scene).
    #[error(
        "the chain blew up while relaxing to static equilibrium (largest link stretch {stretch_m:.3e} m)"
    )]
    BlowUp {
        /// Largest link stretch seen, m.
        stretch_m: f64,
    },
}

/// Why no position fits.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FitError {
    /// The direction is zero or not finite.
    #[error("the direction [{0}, {1}] is not a finite, non-zero vector")]
    Direction(f64, f64),
    /// The sprocket index is out of range.
    #[error("there is no sprocket {0}")]
    NoSprocket(usize),
    /// The drive as it stands has no chain path.
    #[error("the drive as written has no chain path: {0}")]
    NoPath(String),
    /// Moving along the direction does not change the path's length.
    #[error(
        "moving sprocket \"{sprocket}\" along [{dx:.4}, {dy:.4}] does not change the path's length (the direction is across it): choose another direction"
    )]
    Flat {
        /// The moved sprocket's name.
        sprocket: String,
        /// Direction, x.
        dx: f64,
        /// Direction, y.
        dy: f64,
    },
    /// The drive changes shape before the chain fits.
    #[error(
        "sprocket \"{sprocket}\" cannot move far enough along [{dx:.4}, {dy:.4}]: {reason} {offset_m:+.4} m from where it stands; there the path needs {reached:.3} pitches, and the chain's {rollers} are {:.3} pitches ({:.4} m) too {}",
        gap_pitches.abs(),
        gap_m.abs(),
        if *gap_pitches > 0.0 { "many" } else { "few" }
    )]
    Unreachable {
        /// The moved sprocket's name.
        sprocket: String,
        /// Direction, x.
        dx: f64,
        /// Direction, y.
        dy: f64,
        /// What stops the move.
        reason: String,
        /// How far it can move, m (signed along the direction).
        offset_m: f64,
        /// Pitches the path needs there.
        reached: f64,
        /// Pitches still missing (positive) or in excess (negative).
        gap_pitches: f64,
        /// The same as a length, m.
        gap_m: f64,
        /// The chain's roller count.
        rollers: usize,
    },
    /// The path's need of chain jumps across N (a roller changes from a wrap
    /// to a strand there): no position fits exactly.
    #[error(
        "the path's need of chain jumps from {below:.4} to {above:.4} pitches at {offset_m:.6} m along the direction, across the chain's {rollers}: no position of sprocket \"{sprocket}\" fits exactly"
    )]
    Jump {
        /// The moved sprocket's name.
        sprocket: String,
        /// Where, m.
        offset_m: f64,
        /// Need on one side.
        below: f64,
        /// Need on the other.
        above: f64,
        /// The chain's roller count.
        rollers: usize,
    },
}

/// Loads that do not balance around a loop with no driver: the torque the
/// sprocket held for the solve took at the rest state reached.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Unbalanced {
    /// The sprocket held for the solve.
    pub(crate) sprocket: String,
    /// The torque out of balance on it once it turns freely (its chain
    /// torque plus its load at rest), N·m.
    pub(crate) torque_n_m: f64,
    /// That torque over its pitch radius, relative to the pretension.
    pub(crate) relative: f64,
}

impl std::fmt::Display for Unbalanced {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let Self {
            sprocket,
            torque_n_m,
            relative,
        } = self;
        write!(
            f,
            "no sprocket is driven and the sprockets' loads do not balance around the loop: sprocket \"{sprocket}\", held at rest for the static equilibrium, takes {torque_n_m:.4} N·m ({relative:.1e} of the pretension at its pitch radius), so this drive has no rest state; a run starts from the state with it held, and the chain starts to move under the loads (drive a sprocket, role = \"driver\", or balance the loads, sprockets.N.load_torque_n_m)"
        )
    }
}
