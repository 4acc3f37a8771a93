//! The run summary: the public contract of `chaindrive run --summary`
//! (`tests/data/run-summary.schema.json`). Field names stay; more may be added.
//!
//! - `window_s`: the statistics window ([`super::StatsWindow`]): by default the
//!   last [`super::DEFAULT_WINDOW_S`] of the run, not before the end of the
//!   scene's last ramp, or the last W seconds chosen; of what ran, where the
//!   run was interrupted.
//! - **Means** (`mean_link_force_n`, `mean_speed_rad_s`, `mean_torque_n_m`,
//!   `driver_mean_power_w`, the guides' and tensioners' means) are counted
//!   every step of the window (`means_every_step`, [`super::means`]), so
//!   they do not depend on the sample rate; a summary of samples alone (a
//!   recording) takes the samples' means and says so (`means_every_step`
//!   false). Extremes (`link_force_min_n`/`max_n`, `max_bearing_force_n`,
//!   the guides' maxima, the tensioners' ranges) follow every step too.
//! - **Sampled statistics**, at `sample_rate_hz`: `link_force_p2p_n`,
//!   `speed_p2p_rad_s`, `mean_link_force_se_n`, `link_force_rms_n`,
//!   `speed_rms_rad_s`, `stationary` (the estimators of [`super::stats`] over
//!   the window's samples: batch means with 20 batches; first against last
//!   third at 3 standard errors) and the spectra. A sample rate near a
//!   multiple of the tooth-passing frequency aliases them, which a warning
//!   says.
//! - `spectrum_window_s`: from the driver's ramp end + 0.5 s to the end (spectra);
//!   the whole run if that is empty. `transverse_peak_hz` is the main peak in
//!   1–50 Hz of the spectrum averaged over segments of
//!   [`super::spectrum::WELCH_SEGMENT`] samples (one spectrum over the whole
//!   window when it is no longer).
//! - `mean_torque_n_m`: mean moment of the chain's contact forces on the
//!   sprocket about its centre (CCW positive). The driver's motor supplies
//!   the opposite.
//! - `max_bearing_force_n`: largest resultant of the chain's contact forces
//!   on the sprocket over the window (every step), i.e. the bearing reaction
//!   without the sprocket's own weight.
//! - `guides[]`: per guide, the mean and the largest value over the window
//!   (every step) of the sum of the rollers' normal forces on the shoe and of
//!   the magnitudes of their friction forces.
//! - `driver_mean_power_w`: mean of −(chain moment on the driver) × ω_driver.
//! - `string_f1_hz`: the moving-string estimate from the segment's own mean
//!   link force, its nominal length, μ = m_r / P (P the worn pitch for a worn
//!   chain) and the mean chain speed
//!   |ω_driver| R_driver over the window.

use serde::{Deserialize, Serialize};

use crate::model::DriveModel;
use crate::scene::Scene;

fn stationary_by_default() -> bool {
    true
}

/// A free strand as laid out.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StrandSummary {
    /// 1-based segment number.
    pub segment: usize,
    /// 1-based sprocket it leaves.
    pub from: usize,
    /// 1-based sprocket it reaches.
    pub to: usize,
    /// Length, m.
    pub length_m: f64,
    /// Polar angle of the tangent point on `from`, [0, 2π).
    pub angle_on_from_rad: f64,
    /// Polar angle of the tangent point on `to`, [0, 2π).
    pub angle_on_to_rad: f64,
}

/// Statistics of one segment over the window.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SegmentSummary {
    /// 1-based segment number.
    pub segment: usize,
    /// Mean of the segment's average link force (every step with a free link), N.
    pub mean_link_force_n: f64,
    /// Peak-to-peak of the segment's average link force (samples), N.
    pub link_force_p2p_n: f64,
    /// Standard error of `mean_link_force_n` by batch means (20 batches), N.
    #[serde(default)]
    pub mean_link_force_se_n: f64,
    /// RMS of the segment's average link force about its mean (samples), N.
    #[serde(default)]
    pub link_force_rms_n: f64,
    /// Whether the first and last thirds of the window agree within three
    /// combined standard errors (see `super::stats`).
    #[serde(default = "stationary_by_default")]
    pub stationary: bool,
    /// Main peak of the transverse displacement's spectrum in 1–50 Hz, Hz (0 if none).
    pub transverse_peak_hz: f64,
    /// Moving-string estimate of the first transverse eigenfrequency, Hz.
    pub string_f1_hz: f64,
}

/// Statistics of one sprocket over the window.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SprocketSummary {
    /// 1-based sprocket number.
    pub sprocket: usize,
    /// Mean angular speed (every step), rad/s (CCW positive).
    pub mean_speed_rad_s: f64,
    /// Peak-to-peak angular speed (samples), rad/s.
    pub speed_p2p_rad_s: f64,
    /// RMS of the angular speed about its mean (samples), rad/s.
    #[serde(default)]
    pub speed_rms_rad_s: f64,
    /// Mean chain moment on the sprocket, N·m.
    pub mean_torque_n_m: f64,
    /// Largest chain force on the bearing, N.
    pub max_bearing_force_n: f64,
}

/// Mean, smallest and largest value of a quantity over the window.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Range {
    /// Mean.
    pub mean: f64,
    /// Smallest.
    pub min: f64,
    /// Largest.
    pub max: f64,
}

/// One tensioner arm over the statistics window (docs/model.md, “Tensioner
/// arms”).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TensionerSummary {
    /// The arm's name.
    pub tensioner: String,
    /// Arm angle from the scene's pose, rad.
    pub arm_angle_rad: Range,
    /// Plunger travel from the scene's pose, m.
    pub travel_m: Range,
    /// Plunger speed, m/s.
    pub plunger_speed_m_s: Range,
    /// The tensioner's push, N.
    pub plunger_force_n: Range,
    /// Chamber pressure (gauge), Pa (zeros for a spring tensioner).
    pub pressure_pa: Range,
    /// Fraction of the window with the check valve open (every step).
    pub valve_open_fraction: f64,
    /// Times the check valve opened within the window (every step).
    pub valve_openings: u64,
    /// The chain's resultant force on the shoe, N.
    pub shoe_force_n: Range,
}

/// Forces on one guide over the window (docs/model.md, “Guides”).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GuideSummary {
    /// 1-based guide number (`guides[k]` is guide k + 1).
    pub guide: usize,
    /// Its name.
    pub name: String,
    /// Mean of Σ f_n, the rollers' normal forces on the shoe (every step), N.
    pub normal_mean_n: f64,
    /// Largest Σ f_n (every step), N.
    pub normal_max_n: f64,
    /// Mean of Σ |f_t|, the rollers' friction forces on the shoe (every step), N.
    pub friction_mean_n: f64,
    /// Largest Σ |f_t| (every step), N.
    pub friction_max_n: f64,
}

/// The run summary.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunSummary {
    /// Scene name.
    pub scene: String,
    /// `circular`, `real` or `mixed`.
    pub profile: String,
    /// Contact law name.
    pub contact_law: String,
    /// Integrator name.
    pub integrator: String,
    /// How the chain was stepped (`substepped` or `rapier`).
    pub stepping: String,
    /// Gravity, m/s².
    pub gravity_m_s2: [f64; 2],
    /// Chain step, s.
    pub dt_s: f64,
    /// Whether the step was chosen automatically (`solver.dt_s = "auto"`).
    #[serde(default)]
    pub dt_auto: bool,
    /// Simulated time reached, s.
    pub duration_s: f64,
    /// Whether the run stopped before its planned end.
    pub interrupted: bool,
    /// Statistics window, s.
    pub window_s: [f64; 2],
    /// Whether the window's means were counted every step (false: the
    /// means of the samples, as in a summary of a recording).
    #[serde(default)]
    pub means_every_step: bool,
    /// Spectrum window, s.
    pub spectrum_window_s: [f64; 2],
    /// Sample rate of the signals (and of the sampled statistics), Hz.
    pub sample_rate_hz: f64,
    /// Wall time of the stepping loop, s.
    pub wall_s: f64,
    /// Wall time of layout and static equilibrium, s.
    pub setup_wall_s: f64,
    /// Chain integration steps.
    pub steps: u64,
    /// Wall time per step, ns.
    pub ns_per_step: f64,
    /// Mean free-strand link force at static equilibrium, N.
    pub static_tension_n: f64,
    /// Largest roller force imbalance left at the static equilibrium, as a
    /// fraction of the pretension (absent where unknown: a summary of a
    /// recording). Above `super::STATIC_RESIDUAL_TOLERANCE` the
    /// run starts from a state that is not at rest, and says so in
    /// `warnings`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub static_force_residual: Option<f64>,
    /// What sets the static tension: the pretension rule (`rest_length`,
    /// `tensioner`, `tensioner_preload`, as `chain.pretension_by`), or
    /// `chain_misfit` where the tensioner arms meant to set it hold no chain
    /// and the chain's fit to its path does (a warning says how). Absent
    /// where unknown (a summary of a recording).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub static_tension_set_by: Option<String>,
    /// Links' rest length after the pretension rule, m.
    pub rest_length_m: f64,
    /// Smallest link force over the window, N.
    pub link_force_min_n: f64,
    /// Largest link force over the window, N.
    pub link_force_max_n: f64,
    /// Strands as laid out.
    pub strands: Vec<StrandSummary>,
    /// Segment statistics.
    pub segments: Vec<SegmentSummary>,
    /// Sprocket statistics.
    pub sprockets: Vec<SprocketSummary>,
    /// Guide statistics (absent from the JSON without guides).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub guides: Vec<GuideSummary>,
    /// Mean power the driver delivers, W.
    pub driver_mean_power_w: f64,
    /// Largest roller penetration over the run, m.
    pub max_penetration_m: f64,
    /// Mean power dissipated by the joint friction over the window, W
    /// (integrated every step; absent where the run did not count powers).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joint_friction_power_w: Option<f64>,
    /// Mean power dissipated by the links' dampers over the window, W.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub link_damping_power_w: Option<f64>,
    /// Mean power dissipated by the contacts' damping over the window, W.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_damping_power_w: Option<f64>,
    /// Mean power absorbed by the load torques over the window, W (positive
    /// for braking loads).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub load_power_w: Option<f64>,
    /// Load power over driver power (absent without a driver delivering power).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub chain_efficiency: Option<f64>,
    /// Relative residual of driver power = losses + load power + dE/dt over
    /// the window, against the power flowing through.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub energy_balance_error: Option<f64>,
    /// Tensioner arms (absent from scenes without them).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub tensioners: Vec<TensionerSummary>,
    /// The catalogue rating and static safety factors
    /// ([`super::design::rating`]; absent where the smallest sprocket did
    /// not turn).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) rating: Option<super::design::Rating>,
    /// Link-plate fatigue from every link's force over the window
    /// ([`super::design::fatigue`]; absent where the chain has no tensile
    /// strength, or the steps were not counted).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) fatigue: Option<super::design::Fatigue>,
    /// The wear check ([`super::design::wear`]; absent where the scene
    /// does not ask for it, `checks.wear = true`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) wear: Option<super::design::Wear>,
    /// A worn chain (`chain.elongation_pct` > 0; absent for a new chain).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) worn_chain: Option<WornChain>,
    /// Every tooth jump of the run, in order (absent without any).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(crate) tooth_jumps: Vec<ToothJumpSummary>,
    /// Per sprocket whose tips rollers rode, how often and the first ride
    /// (docs/model.md, "Riding a tip"; absent without any).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(crate) tip_rides: Vec<TipRideSummary>,
    /// Where a result is suspect, one sentence each (docs/model.md, "Warnings").
    #[serde(default)]
    pub warnings: Vec<String>,
}

/// A worn chain as laid out (docs/model.md, "A worn chain").
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WornChain {
    /// Wear elongation of every pitch, %.
    pub elongation_pct: f64,
    /// The worn pitch P (1 + e), m.
    pub worn_pitch_m: f64,
    /// On fixed centres (the rest-length rule): the length the chain gained
    /// over the new chain that had the pretension, N l₀ e, m; absent where a
    /// tensioner takes it up.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub extra_slack_m: Option<f64>,
}

/// One tooth jump (docs/model.md, "Tooth jump").
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ToothJumpSummary {
    /// When it was seen, s (to a sample period).
    pub t_s: f64,
    /// 1-based sprocket number.
    pub sprocket: usize,
    /// The roller, 0-based.
    pub roller: usize,
    /// Gaps moved, counter-clockwise positive.
    pub gaps: i32,
    /// `"ahead"` (in the sprocket's sense of rotation: the chain slipped
    /// forward on it) or `"behind"`.
    pub direction: String,
}

impl From<&crate::sim::ToothJump> for ToothJumpSummary {
    fn from(j: &crate::sim::ToothJump) -> Self {
        Self {
            t_s: j.t_s,
            sprocket: j.sprocket + 1,
            roller: j.roller,
            gaps: j.gaps,
            direction: if j.ahead { "ahead" } else { "behind" }.to_owned(),
        }
    }
}

/// The rollers that rode one sprocket's tips (docs/model.md, "Riding a tip").
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TipRideSummary {
    /// 1-based sprocket number.
    pub sprocket: usize,
    /// Rides counted: a roller coming to rest on a tip, once until it lies
    /// deep in a gap again or leaves the sprocket.
    pub count: usize,
    /// When the first was seen, s (to a sample period).
    pub first_t_s: f64,
    /// The first one's roller, 0-based.
    pub first_roller: usize,
}

impl TipRideSummary {
    /// The rides of `rides` (in time order) gathered per sprocket, in the
    /// order of the sprockets.
    pub(crate) fn per_sprocket(rides: &[crate::sim::TipRide]) -> Vec<Self> {
        let mut out: Vec<Self> = Vec::new();
        for r in rides {
            match out.iter_mut().find(|s| s.sprocket == r.sprocket + 1) {
                Some(s) => s.count += 1,
                None => out.push(Self {
                    sprocket: r.sprocket + 1,
                    count: 1,
                    first_t_s: r.t_s,
                    first_roller: r.roller,
                }),
            }
        }
        out.sort_by_key(|s| s.sprocket);
        out
    }
}

/// What the summary needs besides the signals.
pub(crate) struct SummaryInputs<'a> {
    /// The scene (names, settings).
    pub scene: &'a Scene,
    /// The model (strands, driver radius).
    pub model: &'a DriveModel,
    /// Static tension, N.
    pub static_tension_n: f64,
    /// The static equilibrium's force residual (relative to the pretension),
    /// where known.
    pub static_force_residual: Option<f64>,
    /// Why the static equilibrium's state is not at rest, where known (a
    /// sentence, for the unsettled-start warning).
    pub static_unsettled_cause: Option<String>,
    /// Steps taken.
    pub steps: u64,
    /// Wall time of the loop, s.
    pub wall_s: f64,
    /// Wall time of setup, s.
    pub setup_wall_s: f64,
    /// Interrupted?
    pub interrupted: bool,
    /// Largest penetration over the run, m.
    pub max_penetration_m: f64,
}
