//! The catalogue rating of a chain drive (docs/design-checks.md, “Rating”).
//!
//! **What it computes.** At the smallest sprocket's teeth N₁ and speed n₁
//! (rpm), with the pitch p in inches, the two limits of the ANSI
//! horsepower tables (ASME B29.1 ratings, in the form machine-design texts
//! give them):
//!
//! - link-plate fatigue: H₁ = K N₁^1.08 n₁^0.9 p^(3.0 − 0.07 p) hp, K = 0.004
//!   (0.0022 for the lightweight No. 41);
//! - roller–bushing impact: H₂ = 1000 K_r N₁^1.5 p^0.8 / n₁^1.5 hp, K_r = 29
//!   for the bush chains Nos. 25 and 35, 3.4 for No. 41, 17 for Nos. 40–240;
//!
//! the rated power min(H₁, H₂) (one strand, service factor 1), the power
//! the drive may transmit after the multiple-strand factor (1.7, 2.5, 3.3
//! for 2, 3, 4 strands) and a service factor, the lubrication type the
//! tables assume at the chain speed, the chain speed, each sprocket's
//! tooth-passing frequency, the rigid-chain polygonal speed variation
//! 1 − cos(π/N₁), and for a run the static safety factors of its link
//! forces against the chain's tensile strength.
//!
//! **What it does not.** It knows no galling limit (the tables' blank
//! cells at the highest speeds), no life other than the tables' ~15,000 h,
//! and nothing of the run's dynamics beyond its mean power, mean speeds and
//! largest and mean link forces: fatigue from the computed force history is
//! a separate check. ISO 606 B-series chains and chains without a
//! designation are rated with the standard-series constants at their own
//! pitch, and [`Rating::basis`] says so.

use serde::{Deserialize, Serialize};

use crate::analysis::RunSummary;
use crate::scene::designations::{self, Designation};
use crate::scene::{Role, Scene};

/// Watts per (mechanical) horsepower, 550 ft·lbf/s.
pub(crate) const HP_W: f64 = 745.699_871_582_270_2;
/// Metres per inch.
const INCH_M: f64 = 0.0254;
/// m/s per ft/min.
const FT_MIN_M_S: f64 = 0.3048 / 60.0;

/// Largest link force, as a fraction of the tensile strength, above which a
/// run is flagged: the working-load limit of one sixth of the minimum
/// ultimate tensile strength that chain makers give for a chain in service
/// (Diamond Chain, "Technical Engineering" guide; docs/design-checks.md).
pub(crate) const WORKING_LOAD_FRACTION: f64 = 1.0 / 6.0;

/// The chain speed, as a multiple of the oil-bath (type B) limit, above
/// which a run is flagged. This is chaindrive's own threshold, not a
/// catalogue's: beyond type B the tables assume an oil stream (type C), which
/// engine drives have, so type C alone is reported (`lubrication`), not
/// flagged; three times the bath limit is far above the speeds the
/// horsepower tables read here cover (No. 40's reach about 17 m/s,
/// 45 teeth at 1800 rpm) and catches a speed typed ten times too high.
pub(crate) const LUBRICATION_WARNING_FACTOR: f64 = 3.0;

/// Lubrication limits by chain size: (ANSI number, pitch in inches, type A
/// limit, type B limit), chain speeds in ft/min, from McGuire Bearing's
/// "guidelines for better chain performance" table. Type C (oil stream)
/// beyond type B's limit.
const LUBRICATION_FT_MIN: [(u32, f64, f64, f64); 8] = [
    (40, 0.5, 300.0, 2300.0),
    (50, 0.625, 250.0, 2000.0),
    (60, 0.75, 220.0, 1800.0),
    (80, 1.0, 170.0, 1500.0),
    (100, 1.25, 150.0, 1300.0),
    (120, 1.5, 130.0, 1200.0),
    (140, 1.75, 115.0, 1100.0),
    (160, 2.0, 100.0, 1000.0),
];

/// The constants the rating formulas take for a chain.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ChainClass {
    /// Standard roller chains, ANSI 40–240: K = 0.004, K_r = 17.
    Standard,
    /// The rollerless bush chains ANSI 25 and 35: K = 0.004, K_r = 29.
    BushChain,
    /// The lightweight ANSI 41: K = 0.0022, K_r = 3.4.
    Lightweight,
}

impl ChainClass {
    /// The class of a designation (the table's name); a chain without one
    /// is rated as a standard roller chain.
    pub(crate) fn of(designation: Option<&str>) -> Self {
        match designation {
            Some("ANSI 25" | "ANSI 35") => Self::BushChain,
            Some("ANSI 41") => Self::Lightweight,
            _ => Self::Standard,
        }
    }

    /// K of the link-plate formula.
    pub(crate) fn link_plate_k(self) -> f64 {
        match self {
            Self::Lightweight => 0.0022,
            Self::Standard | Self::BushChain => 0.004,
        }
    }

    /// K_r of the roller–bushing formula.
    pub(crate) fn roller_bushing_kr(self) -> f64 {
        match self {
            Self::Standard => 17.0,
            Self::BushChain => 29.0,
            Self::Lightweight => 3.4,
        }
    }
}

/// Link-plate fatigue limited rating H₁ = K N₁^1.08 n₁^0.9 p^(3.0 − 0.07 p),
/// hp, one strand (`pitch_in` in inches, `speed_rpm` of the sprocket with
/// `teeth`).
pub(crate) fn link_plate_limited_hp(
    class: ChainClass,
    teeth: f64,
    speed_rpm: f64,
    pitch_in: f64,
) -> f64 {
    class.link_plate_k()
        * teeth.powf(1.08)
        * speed_rpm.powf(0.9)
        * pitch_in.powf(3.0 - 0.07 * pitch_in)
}

/// Roller–bushing impact limited rating H₂ = 1000 K_r N₁^1.5 p^0.8 / n₁^1.5,
/// hp, one strand; infinite at rest (the caller refuses a speed of zero).
pub(crate) fn roller_bushing_limited_hp(
    class: ChainClass,
    teeth: f64,
    speed_rpm: f64,
    pitch_in: f64,
) -> f64 {
    1000.0 * class.roller_bushing_kr() * teeth.powf(1.5) * pitch_in.powf(0.8) / speed_rpm.powf(1.5)
}

/// The multiple-strand factor of the ANSI tables (1, 1.7, 2.5, 3.3 for
/// 1–4 strands); `None` beyond four, which the tables do not give.
pub(crate) fn strand_factor(strands: u32) -> Option<f64> {
    match strands {
        1 => Some(1.0),
        2 => Some(1.7),
        3 => Some(2.5),
        4 => Some(3.3),
        _ => None,
    }
}

/// The lubrication the ratings assume at a chain speed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Lubrication {
    /// Type A: manual or drip.
    A,
    /// Type B: oil bath or slinger disc.
    B,
    /// Type C: oil stream (pump and nozzles).
    C,
}

impl Lubrication {
    /// What the type means, for people.
    pub(crate) fn description(self) -> &'static str {
        match self {
            Self::A => "type A: manual or drip",
            Self::B => "type B: oil bath or disc",
            Self::C => "type C: oil stream",
        }
    }
}

/// The chain speeds up to which type A and type B lubrication serve a chain
/// of `pitch_m`, m/s, with the ANSI number whose row gives them: the row of
/// nearest pitch (below No. 40 and above No. 160 the table has none, and
/// the nearest row's limits are used).
pub(crate) fn lubrication_limits_m_s(pitch_m: f64) -> (f64, f64, u32) {
    let pitch_in = pitch_m / INCH_M;
    let mut best = LUBRICATION_FT_MIN[0];
    for row in LUBRICATION_FT_MIN {
        if (row.1 - pitch_in).abs() < (best.1 - pitch_in).abs() {
            best = row;
        }
    }
    (best.2 * FT_MIN_M_S, best.3 * FT_MIN_M_S, best.0)
}

/// What a rating is computed with besides the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RatingSettings {
    /// Service factor (≥ 1 for a load rougher than the tables' smooth one).
    pub service_factor: f64,
}

impl Default for RatingSettings {
    fn default() -> Self {
        Self {
            service_factor: 1.0,
        }
    }
}

/// Why a rating cannot be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RatingError {
    /// The service factor is not a finite number > 0.
    #[error("the service factor must be a finite number > 0, got {0}")]
    ServiceFactor(f64),
    /// The tables have no multiple-strand factor for this many strands.
    #[error("the rating tables give strand factors for 1 to 4 strands, not {0}")]
    Strands(u32),
    /// No sprocket is prescribed a speed.
    #[error(
        "the scene has no driver, so its speeds are unknown before a run: rate a run's summary instead"
    )]
    NoDriver,
    /// The smallest sprocket does not turn.
    #[error(
        "sprocket {sprocket} (the smallest, {teeth} teeth) does not turn: a rating needs a speed > 0"
    )]
    NotTurning {
        /// 1-based sprocket number.
        sprocket: usize,
        /// Its teeth.
        teeth: u32,
    },
}

/// The rating of a drive: the `rating` block of the run summary and the
/// output of `chaindrive rate --json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Rating {
    /// The designation rated (absent: the scene names none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub designation: Option<String>,
    /// How the chain is rated: which table's constants, and why.
    pub basis: String,
    /// The constants' class.
    pub chain_class: ChainClass,
    /// Mean chain speed N₁ P n₁ / 60 at the smallest sprocket, m/s.
    pub chain_speed_m_s: f64,
    /// 1-based number of the sprocket with the fewest teeth (the first of equals).
    pub smallest_sprocket: usize,
    /// Its teeth N₁.
    pub smallest_teeth: u32,
    /// Its speed n₁, rpm (magnitude).
    pub smallest_speed_rpm: f64,
    /// Each sprocket's tooth-passing frequency N |n| / 60, Hz.
    pub tooth_frequency_hz: Vec<f64>,
    /// Rigid-chain polygonal speed variation of the smallest sprocket,
    /// 1 − cos(π/N₁): (v_max − v_min) / v_max of a chain on a sprocket
    /// turning steadily.
    pub polygonal_speed_variation: f64,
    /// Link-plate fatigue limited rating H₁, one strand, W.
    pub link_plate_limited_power_w: f64,
    /// Roller–bushing impact limited rating H₂, one strand, W.
    pub roller_bushing_limited_power_w: f64,
    /// The governing limit min(H₁, H₂), one strand, service factor 1, W.
    pub rated_power_w: f64,
    /// `link_plate` or `roller_bushing`: which limit governs.
    pub limited_by: String,
    /// Strands.
    pub strands: u32,
    /// Multiple-strand factor.
    pub strand_factor: f64,
    /// Service factor.
    pub service_factor: f64,
    /// The power the drive may transmit: rated × strand factor / service
    /// factor, W.
    pub design_power_w: f64,
    /// The lubrication the ratings assume at this chain speed.
    pub lubrication: Lubrication,
    /// Chain speed up to which type A serves, m/s.
    pub lubrication_a_max_m_s: f64,
    /// Chain speed up to which type B serves, m/s.
    pub lubrication_b_max_m_s: f64,
    /// The power transmitted, W (absent where unknown).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transmitted_power_w: Option<f64>,
    /// Where the transmitted power comes from.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transmitted_power_from: Option<String>,
    /// design_power_w / transmitted_power_w (below 1: the chain is
    /// overloaded by the catalogue's measure).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub margin: Option<f64>,
    /// Minimum tensile strength of the chain (all strands), N.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tensile_strength_n: Option<f64>,
    /// Tensile strength over the largest link force in the window.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub static_safety_factor: Option<f64>,
    /// Tensile strength over the largest segment's mean link force.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mean_static_safety_factor: Option<f64>,
    /// What could not be computed and which field would enable it.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
}

/// How a chain is rated, in a sentence, and its constants.
fn basis_of(designation: Option<&Designation>, pitch_m: f64) -> (ChainClass, String) {
    let class = ChainClass::of(designation.map(|d| d.name));
    let pitch_in = pitch_m / INCH_M;
    let beyond = if pitch_in > 3.0 + 1e-9 {
        format!(
            "; the pitch, {pitch_in:.3} in, is above the largest ANSI chain's (No. 240, 3 in): the formulas are extrapolated"
        )
    } else {
        String::new()
    };
    let text = match designation {
        Some(d) if d.name.starts_with("ANSI") => format!(
            "{}: the ANSI horsepower-table formulas with K = {}, K_r = {}{}{beyond}",
            d.name,
            class.link_plate_k(),
            class.roller_bushing_kr(),
            if d.name.ends_with('H') {
                " of the standard chain of its pitch (no separate rating read for the heavy series; its thicker plates are not credited)"
            } else {
                ""
            }
        ),
        Some(d) if d.is_motorcycle() => format!(
            "{}: no published rating method read for motorcycle chains; rated by the ANSI formulas with the standard roller chains' constants (K = 0.004, K_r = 17) at its pitch ({pitch_in:.3} in): the ANSI 50's rating. The formulas know pitch, teeth and speed only: an inner width of {:.2} mm (the ANSI 50's 9.53) is not credited or debited, nor are the thicker plates and the seals",
            d.name,
            d.inner_width_m * 1e3
        ),
        Some(d) => format!(
            "{}: no published rating method read for ISO 606 B-series chains; rated by the ANSI formulas at its own pitch ({pitch_in:.3} in) with the standard roller chains' constants (K = 0.004, K_r = 17), as the ANSI chain of that pitch, since both are bush-and-roller chains of the same construction{beyond}",
            d.name
        ),
        None => format!(
            "no chain.designation: rated by the ANSI formulas at the scene's pitch ({pitch_in:.3} in) as a standard roller chain (K = 0.004, K_r = 17){beyond}"
        ),
    };
    (class, text)
}

/// What a chain without a tensile strength lacks, and the field that gives
/// it: a designation whose row has none (a motorcycle chain) or none at all.
pub(crate) fn missing_strength_note(designation: Option<&Designation>) -> String {
    match designation {
        Some(d) => format!(
            "no tensile strength: the {} row has none (each maker's and grade's own; `chaindrive chains {}`); give chain.tensile_strength_n, the maker's minimum, and with it the static safety factors and the fatigue check",
            d.name, d.name
        ),
        None => "no tensile strength: chain.tensile_strength_n or chain.designation (`chaindrive chains` lists them) gives it, and with it the static safety factors and the fatigue check".to_owned(),
    }
}

/// Inputs of [`rate`] that differ between a scene and a run.
struct Operating {
    /// Each sprocket's speed, rad/s.
    speeds_rad_s: Vec<f64>,
    /// The power transmitted and where it comes from.
    transmitted: Result<(f64, String), String>,
}

/// The rating of `scene` turning at `op`'s speeds.
fn rate(scene: &Scene, op: Operating, settings: RatingSettings) -> Result<Rating, RatingError> {
    let sf = settings.service_factor;
    if !(sf.is_finite() && sf > 0.0) {
        return Err(RatingError::ServiceFactor(sf));
    }
    // The strand count comes from the designation ("ANSI 80-2"), which the
    // scene has checked against the factors' range.
    let strands = scene.chain.strands;
    let strand_factor = strand_factor(strands).ok_or(RatingError::Strands(strands))?;
    let sprockets = &scene.sprockets;
    let smallest = (0..sprockets.len())
        .min_by_key(|&s| sprockets[s].teeth)
        .ok_or(RatingError::NoDriver)?;
    let teeth = sprockets[smallest].teeth;
    let speed_rpm = op.speeds_rad_s[smallest].abs() * 60.0 / std::f64::consts::TAU;
    if !(speed_rpm.is_finite() && speed_rpm > 0.0) {
        return Err(RatingError::NotTurning {
            sprocket: smallest + 1,
            teeth,
        });
    }
    let pitch_m = scene.chain.pitch_m;
    let pitch_in = pitch_m / INCH_M;
    let designation = scene.chain.designation.and_then(designations::find);
    let (class, basis) = basis_of(designation, pitch_m);
    let z = f64::from(teeth);
    let h1_w = HP_W * link_plate_limited_hp(class, z, speed_rpm, pitch_in);
    let h2_w = HP_W * roller_bushing_limited_hp(class, z, speed_rpm, pitch_in);
    let rated_w = h1_w.min(h2_w);
    let design_w = rated_w * strand_factor / sf;
    let chain_speed = z * pitch_m * speed_rpm / 60.0;
    let (a_max, b_max, _) = lubrication_limits_m_s(pitch_m);
    let lubrication = if chain_speed <= a_max {
        Lubrication::A
    } else if chain_speed <= b_max {
        Lubrication::B
    } else {
        Lubrication::C
    };
    let mut notes = Vec::new();
    let (transmitted, from) = match op.transmitted {
        Ok((p, from)) => (Some(p), Some(from)),
        Err(missing) => {
            notes.push(missing);
            (None, None)
        }
    };
    // The scene's, or the designation's n strands (n times one's, not the
    // rating's strand factor: designations::Stranded).
    let tensile = scene.chain.tensile_strength_n;
    if tensile.is_none() {
        notes.push(missing_strength_note(designation));
    }
    Ok(Rating {
        designation: designation.map(|d| designations::Stranded { single: d, strands }.name()),
        basis,
        chain_class: class,
        chain_speed_m_s: chain_speed,
        smallest_sprocket: smallest + 1,
        smallest_teeth: teeth,
        smallest_speed_rpm: speed_rpm,
        tooth_frequency_hz: sprockets
            .iter()
            .zip(&op.speeds_rad_s)
            .map(|(s, w)| f64::from(s.teeth) * w.abs() / std::f64::consts::TAU)
            .collect(),
        polygonal_speed_variation: 1.0 - (std::f64::consts::PI / z).cos(),
        link_plate_limited_power_w: h1_w,
        roller_bushing_limited_power_w: h2_w,
        rated_power_w: rated_w,
        limited_by: if h1_w <= h2_w {
            "link_plate"
        } else {
            "roller_bushing"
        }
        .to_owned(),
        strands,
        strand_factor,
        service_factor: sf,
        design_power_w: design_w,
        lubrication,
        lubrication_a_max_m_s: a_max,
        lubrication_b_max_m_s: b_max,
        transmitted_power_w: transmitted,
        transmitted_power_from: from,
        margin: transmitted.filter(|p| *p > 0.0).map(|p| design_w / p),
        tensile_strength_n: tensile,
        static_safety_factor: None,
        mean_static_safety_factor: None,
        notes,
    })
}

/// Each sprocket's speed in a scene before any run, rad/s: the driver's top
/// speed, and the others turning with the chain, ω_s = ω_d N_d / N_s (the
/// sign does not matter to the rating).
fn scene_speeds_rad_s(scene: &Scene) -> Result<Vec<f64>, RatingError> {
    let driver = scene
        .sprockets
        .iter()
        .find_map(|s| match s.role {
            Role::Driver(law) => Some((law.top_speed_rad_s(), s.teeth)),
            _ => None,
        })
        .ok_or(RatingError::NoDriver)?;
    Ok(scene
        .sprockets
        .iter()
        .map(|s| driver.0 * f64::from(driver.1) / f64::from(s.teeth))
        .collect())
}

/// The power the scene's load torques absorb at `speeds`,
/// Σ (|τ_s| + T_s) |ω_s|, W, each load taken as braking and each resisting
/// load T_s at its full size (the speeds are above its creep speed); an
/// error naming what would give a power when they absorb none.
fn load_power(scene: &Scene, speeds: &[f64]) -> Result<(f64, String), String> {
    let power: f64 = scene
        .sprockets
        .iter()
        .zip(speeds)
        .map(|(s, w)| (s.load_torque_n_m().abs() + s.resisting_torque_n_m()) * w.abs())
        .sum();
    if power > 0.0 {
        Ok((
            power,
            "the scene's load torques at the driver's speed, sum of (|load torque| + resisting torque) x speed"
                .to_owned(),
        ))
    } else {
        Err("no transmitted power: the scene has no load torque (sprockets.N.load_torque_n_m or resisting_torque_n_m); give the power (--power-w) or run the scene (its summary's rating uses the run's driver power)".to_owned())
    }
}

/// The rating of a scene before any run, at the driver's top speed; the
/// transmitted power is `power_w` if given, else that of the scene's load
/// torques.
///
/// # Errors
/// A service factor that is not a positive number, a scene without a
/// driver or whose smallest sprocket does not turn.
pub fn of_scene(
    scene: &Scene,
    settings: RatingSettings,
    power_w: Option<f64>,
) -> Result<Rating, RatingError> {
    let speeds = scene_speeds_rad_s(scene)?;
    let transmitted = match power_w {
        Some(p) => Ok((p, "given (--power-w)".to_owned())),
        None => load_power(scene, &speeds),
    };
    rate(
        scene,
        Operating {
            speeds_rad_s: speeds,
            transmitted,
        },
        settings,
    )
}

/// The rating of a run from its summary (mean speeds, driver power, link
/// forces over the window), service factor 1, the scene's strands; `None` when the
/// smallest sprocket did not turn in the window.
pub(crate) fn of_run(scene: &Scene, summary: &RunSummary) -> Option<Rating> {
    let speeds: Vec<f64> = summary
        .sprockets
        .iter()
        .map(|s| s.mean_speed_rad_s)
        .collect();
    if speeds.len() != scene.sprockets.len() {
        return None;
    }
    let power = summary.driver_mean_power_w;
    let transmitted = if power > 0.0 && power.is_finite() {
        Ok((
            power,
            "the run's mean driver power over the window".to_owned(),
        ))
    } else {
        Err("no transmitted power: the driver delivered none over the window".to_owned())
    };
    let mut rating = rate(
        scene,
        Operating {
            speeds_rad_s: speeds,
            transmitted,
        },
        RatingSettings::default(),
    )
    .ok()?;
    if let Some(strength) = rating.tensile_strength_n {
        let largest_mean = summary
            .segments
            .iter()
            .map(|s| s.mean_link_force_n)
            .fold(0.0, f64::max);
        let factor = |force: f64| (force > 0.0 && force.is_finite()).then(|| strength / force);
        rating.static_safety_factor = factor(summary.link_force_max_n);
        rating.mean_static_safety_factor = factor(largest_mean);
    }
    Some(rating)
}

/// The rating's warnings for a run whose largest link force is
/// `largest_link_force_n` (docs/design-checks.md, “Warnings”).
pub(crate) fn warnings(scene: &Scene, rating: &Rating, largest_link_force_n: f64) -> Vec<String> {
    let v = rating.chain_speed_m_s;
    let mut found = Vec::new();
    if v > LUBRICATION_WARNING_FACTOR * rating.lubrication_b_max_m_s {
        found.push(format!(
            "chain speed: {v:.1} m/s ({:.0} rpm on the {}-tooth sprocket {}) is {:.1} times the {:.1} m/s to which oil-bath lubrication serves a chain of this pitch (warning above {LUBRICATION_WARNING_FACTOR}); beyond it the ratings assume a forced oil stream, and this far beyond it no rating table reaches: check the speed (a typo in speed_rpm?) and the lubrication (docs/design-checks.md, \"Rating\")",
            rating.smallest_speed_rpm,
            rating.smallest_teeth,
            rating.smallest_sprocket,
            v / rating.lubrication_b_max_m_s,
            rating.lubrication_b_max_m_s,
        ));
    }
    if let Some(strength) = rating.tensile_strength_n
        && largest_link_force_n > WORKING_LOAD_FRACTION * strength
    {
        let centrifugal = scene.chain.mass_per_length_kg_m() * v * v;
        found.push(format!(
            "link force: the largest link force, {:.1} kN, is {:.0} % of the chain's tensile strength of {:.1} kN (static safety factor {:.2}; warning above 1/6 of the strength, the working-load limit chain makers give; above 1/2 a single load damages the chain) at a chain speed of {v:.1} m/s, whose centrifugal tension m v² alone is {:.1} kN: a larger chain, a lower speed or load, or check the scene for a typo",
            largest_link_force_n * 1e-3,
            100.0 * largest_link_force_n / strength,
            strength * 1e-3,
            strength / largest_link_force_n,
            centrifugal * 1e-3
        ));
    }
    // A chain without a designation is rated by its pitch alone, as a guide:
    // nothing says it is a catalogue chain, so its margin is reported, not
    // flagged.
    if let (Some(p), Some(margin), Some(_)) = (
        rating.transmitted_power_w,
        rating.margin,
        &rating.designation,
    ) && margin < 1.0
    {
        found.push(format!(
            "rating: the drive transmits {:.2} kW, above the chain's catalogue rating of {:.2} kW ({} limited, {} teeth at {:.0} rpm, strand factor {}, service factor {}; margin {margin:.2}); {}",
            p * 1e-3,
            rating.design_power_w * 1e-3,
            rating.limited_by.replace('_', "-"),
            rating.smallest_teeth,
            rating.smallest_speed_rpm,
            rating.strand_factor,
            rating.service_factor,
            rating.basis
        ));
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lubrication row of nearest pitch: 12.7 mm is No. 40's, 25.4 mm
    /// No. 80's, 8 mm and 88.9 mm the ends' (300 and 100 ft/min for type A).
    #[test]
    fn lubrication_rows_are_chosen_by_nearest_pitch() {
        assert_eq!(lubrication_limits_m_s(0.0127).2, 40);
        assert_eq!(lubrication_limits_m_s(0.0254).2, 80);
        assert_eq!(lubrication_limits_m_s(0.008).2, 40);
        assert_eq!(lubrication_limits_m_s(0.0889).2, 160);
        approx::assert_relative_eq!(lubrication_limits_m_s(0.0127).0, 1.524, epsilon = 1e-12);
    }

    #[test]
    fn strand_factors_stop_at_four() {
        assert_eq!(strand_factor(2), Some(1.7));
        assert_eq!(strand_factor(5), None);
    }
}
