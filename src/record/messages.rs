//! The recording's own typed messages: the run's signals, one struct per
//! channel, encoded as protobuf with schemas derived by `foxglove::Encode`.
//!
//! Field numbers follow declaration order (1, 2, …); the schema's package is
//! the lower-cased struct name (e.g. `chainlinkforces.ChainLinkForces`).
//! Foxglove's Plot panel addresses fields by path
//! (`/sprockets.speed_rad_s[0]`, `/segments.segments[1].link_force_n`); Rerun
//! decodes them through the schema into one struct component per topic
//! (`segmentsignals.SegmentSignals:message`, …) whose fields a time-series
//! view plots through a selector (`.segments[1].link_force_n`,
//! `.speed_rad_s[0]`). No field is ever NaN: a value that does not exist is
//! left out (an `Option` that is `None`).

/// `/links`: the force of every link, tension positive.
#[derive(Clone, Debug, Default, PartialEq, foxglove::Encode)]
pub(crate) struct ChainLinkForces {
    /// Simulated time, s (the message's log time too).
    pub t_s: f64,
    /// F_link of link i (roller i to roller i + 1, the last closing the loop), N.
    pub force_n: Vec<f64>,
    /// Joint friction moment at roller i (the moment of link i − 1 on link
    /// i, CCW positive), N·m; empty without joint friction.
    pub joint_friction_moment_n_m: Vec<f64>,
}

/// `/contacts`: the total contact force on every roller.
#[derive(Clone, Debug, Default, PartialEq, foxglove::Encode)]
pub(crate) struct ChainContactForces {
    /// Simulated time, s.
    pub t_s: f64,
    /// Magnitude of the vector sum of the contact forces on roller i over
    /// all its patches, N (0: free); two patches' forces at an angle give
    /// less than the sum of their magnitudes.
    pub force_n: Vec<f64>,
}

/// `/sprockets`: the sprockets' rotation, in scene order (index 0 = sprocket 1).
#[derive(Clone, Debug, Default, PartialEq, foxglove::Encode)]
pub(crate) struct SprocketSignals {
    /// Simulated time, s.
    pub t_s: f64,
    /// Angle, rad (counter-clockwise positive, not wrapped).
    pub angle_rad: Vec<f64>,
    /// Angular speed, rad/s (counter-clockwise positive).
    pub speed_rad_s: Vec<f64>,
    /// Moment of the chain's contact forces about the centre, N·m (CCW positive).
    pub chain_torque_n_m: Vec<f64>,
}

/// One segment (free strand) at one sample.
#[derive(Clone, Debug, Default, PartialEq, foxglove::Encode)]
pub(crate) struct SegmentSignal {
    /// 1-based segment number: the strand from sprocket k to the next.
    pub segment: u32,
    /// Mean link force over the strand's free links, N; absent when no link is free.
    pub link_force_n: Option<f64>,
    /// Transverse displacement of the strand's middle, m (left of the strand positive).
    pub transverse_m: f64,
}

/// `/segments`: every segment's average link force and transverse displacement,
/// as defined in [`crate::analysis`].
#[derive(Clone, Debug, Default, PartialEq, foxglove::Encode)]
pub(crate) struct SegmentSignals {
    /// Simulated time, s.
    pub t_s: f64,
    /// Segments in order (index 0 = segment 1).
    pub segments: Vec<SegmentSignal>,
}

/// One guide at one sample (docs/model.md, “Guides”).
#[derive(Clone, Debug, Default, PartialEq, foxglove::Encode)]
pub(crate) struct GuideSignal {
    /// 1-based guide number (`guides[k]` of the scene is guide k + 1).
    pub guide: u32,
    /// Σ f_n, the rollers' normal forces on the shoe, N.
    pub normal_n: f64,
    /// Σ |f_t|, the magnitudes of their friction forces, N.
    pub friction_n: f64,
    /// Resultant of the rollers' forces on the shoe, x, N.
    pub force_x_n: f64,
    /// Its y component, N.
    pub force_y_n: f64,
    /// Rollers in contact.
    pub contacts: u32,
}

/// `/guides`: every guide's forces, in scene order.
#[derive(Clone, Debug, Default, PartialEq, foxglove::Encode)]
pub(crate) struct GuideSignals {
    /// Simulated time, s.
    pub t_s: f64,
    /// Guides in order (index 0 = guide 1).
    pub guides: Vec<GuideSignal>,
}

/// One tensioner arm at one sample (docs/model.md, “Tensioner arms”).
#[derive(Clone, Debug, Default, PartialEq, foxglove::Encode)]
pub(crate) struct TensionerSignal {
    /// 1-based arm number (`tensioners[k]` of the scene is arm k + 1).
    pub tensioner: u32,
    /// Tensioner (plunger) travel x from the scene's pose, m.
    pub travel_m: f64,
    /// Plunger speed v, m/s.
    pub speed_m_s: f64,
    /// Chamber pressure (gauge), Pa; 0 for a spring tensioner.
    pub pressure_pa: f64,
    /// Whether the check valve is open (false for a spring tensioner).
    pub valve_open: bool,
    /// Arm angle from the scene's pose, rad (counter-clockwise).
    pub arm_angle_rad: f64,
    /// Magnitude of the chain's resultant force on the shoe, N.
    pub shoe_force_n: f64,
    /// The tensioner's push on the arm, N.
    pub plunger_force_n: f64,
}

/// `/tensioners`: every tensioner arm's state, in scene order.
#[derive(Clone, Debug, Default, PartialEq, foxglove::Encode)]
pub(crate) struct TensionerSignals {
    /// Simulated time, s.
    pub t_s: f64,
    /// Arms in order (index 0 = arm 1).
    pub tensioners: Vec<TensionerSignal>,
}
