//! Link-plate fatigue from the computed link forces (docs/design-checks.md,
//! "Fatigue"): an S–N curve per chain, the mean-stress correction, Miner's
//! damage per hour and the life, and the summary's `fatigue` block.
//!
//! **The S–N curve** of pulsating cycles ([`super::sn_curve`], with its
//! mean-stress correction): unless the scene
//! gives its own (`[checks]` `fatigue_limit_n`, `sn_slope`), it is derived
//! from the link-plate limited rating of the ANSI tables
//! ([`super::rating::link_plate_limited_hp`]), which at the smallest
//! sprocket's N₁ teeth and speed n₁ allows the chain tension
//! F₁ = H₁ / v ∝ N₁^0.08 n₁^−0.1 for the tables' 15,000 h on a chain of
//! 120 pitches, that is C = 15,000 · 60 · N₁ n₁ / 120 pulsating cycles per
//! link: F₁ ∝ C^−0.1 at fixed N₁, an S–N slope m = 10; the fatigue limit is
//! that line's force at the knee N_D = 5·10⁶ cycles, the count at which
//! chain makers determine a chain's fatigue limit (its "maximum allowable
//! load", after JIS B 1801).
//!
//! It does not count cycles (the streaming count is
//! [`super::link_cycles`]) and knows no wear, no corrosion, no fretting at
//! the pin holes, no scatter (the curve is the rating's, a design curve,
//! not a probability of failure).

use serde::{Deserialize, Serialize};

use super::life::Life;
use super::link_cycles::{LinkCycles, unpack};
use super::rating::{ChainClass, HP_W, link_plate_limited_hp};
use super::sn_curve::SnCurve;
use crate::analysis::{RunSummary, StrandSummary};
use crate::scene::Scene;
use crate::scene::designations;

/// The life the ANSI ratings are set for, h.
pub const RATING_LIFE_H: f64 = 15_000.0;
/// The chain length, in pitches, of the drives the ratings were tested on.
pub const RATING_CHAIN_PITCHES: f64 = 120.0;
/// Cycles at the knee of the S–N curve, where its fatigue limit is taken.
pub const KNEE_CYCLES: f64 = 5e6;
/// The S–N slope of the link-plate rating: H₁ ∝ n₁^0.9, so the tension
/// F₁ = H₁ / v ∝ n₁^−0.1 ∝ C^−0.1, and m = 1 / 0.1.
pub const RATING_SN_SLOPE: f64 = 10.0;
/// Cycles below which the S–N line is not a chain's: the high-cycle
/// region of steels' S–N curves begins at about 10³ cycles, and the
/// rating's line, extended below it, reaches half the tensile strength at
/// a few cycles. A cycle that lasts fewer on the curve gets a note.
pub const LOW_CYCLE_LIMIT: f64 = 1e3;

/// Metres per inch.
const INCH_M: f64 = 0.0254;

/// The chain tension at which the ANSI link-plate rating is reached, N,
/// for a chain of `class` and `pitch_m` on a smallest sprocket of `teeth`
/// whose links see `cycles` pulsating cycles in the rating's life:
/// F = H₁ / v with n₁ = C · 120 / (15,000 · 60 · N₁).
pub fn rated_tension_n(class: ChainClass, pitch_m: f64, teeth: f64, cycles: f64) -> f64 {
    let speed_rpm = cycles * RATING_CHAIN_PITCHES / (RATING_LIFE_H * 60.0 * teeth);
    let power_w = HP_W * link_plate_limited_hp(class, teeth, speed_rpm, pitch_m / INCH_M);
    let chain_speed_m_s = teeth * pitch_m * speed_rpm / 60.0;
    power_w / chain_speed_m_s
}

/// The S–N curve derived from the link-plate rating ([module docs](self)).
pub fn curve_from_rating(
    class: ChainClass,
    pitch_m: f64,
    teeth: f64,
    tensile_strength_n: f64,
) -> SnCurve {
    SnCurve {
        slope: RATING_SN_SLOPE,
        fatigue_limit_n: rated_tension_n(class, pitch_m, teeth, KNEE_CYCLES),
        knee_cycles: KNEE_CYCLES,
        tensile_strength_n,
    }
}

/// A scene's S–N curve and where it comes from; `Err` names the field that
/// would enable the check.
pub fn curve_of_scene(scene: &Scene) -> Result<(SnCurve, String), String> {
    let designation = scene.chain.designation.and_then(designations::find);
    // n strands: n times one's minimum tensile strength, and the fatigue
    // limit of the rating it derives from times the rating's strand factor
    // (1.7, 2.5, 3.3: less than n, as the strands share the load unevenly).
    let strands = scene.chain.strands;
    let strand_factor = super::rating::strand_factor(strands).unwrap_or(1.0);
    let Some(strength) = scene.chain.tensile_strength_n else {
        return Err(format!(
            "no fatigue check (the mean-stress correction needs the tensile strength): {}",
            super::rating::missing_strength_note(designation)
        ));
    };
    let Some(teeth) = scene.sprockets.iter().map(|s| s.teeth).min() else {
        return Err("no fatigue check: the scene has no sprocket".to_owned());
    };
    let class = ChainClass::of(designation.map(|d| d.name));
    let pitch_m = scene.chain.pitch_m;
    let mut derived = curve_from_rating(class, pitch_m, f64::from(teeth), strength);
    derived.fatigue_limit_n *= strand_factor;
    let checks = &scene.checks;
    let curve = SnCurve {
        slope: checks.sn_slope.unwrap_or(derived.slope),
        fatigue_limit_n: checks.fatigue_limit_n.unwrap_or(derived.fatigue_limit_n),
        ..derived
    };
    let limit = match checks.fatigue_limit_n {
        Some(f) => format!("fatigue limit {:.3} kN (checks.fatigue_limit_n)", f * 1e-3),
        None => format!(
            "fatigue limit {:.3} kN: the tension of the ANSI link-plate rating (K = {}) on the {teeth}-tooth smallest sprocket at {KNEE_CYCLES:.0e} pulsating cycles, its {RATING_LIFE_H:.0} h on a chain of {RATING_CHAIN_PITCHES:.0} pitches{}",
            curve.fatigue_limit_n * 1e-3,
            class.link_plate_k(),
            if strands > 1 {
                format!(
                    ", times the rating's multiple-strand factor {strand_factor} for {strands} strands"
                )
            } else {
                String::new()
            }
        ),
    };
    let slope = match checks.sn_slope {
        Some(m) => format!("slope {m} (checks.sn_slope)"),
        None => "slope 10 (the rating's n1^0.9: tension ∝ cycles^-0.1)".to_owned(),
    };
    let basis = format!(
        "pulsating S-N curve, {limit}, {slope}, knee at {:.0e} cycles; Goodman's mean-stress correction to the tensile strength {:.1} kN; Miner's rule, no damage below the limit",
        curve.knee_cycles,
        strength * 1e-3
    );
    Ok((curve, basis))
}

/// Where the fatigue damage is largest: a free strand or a sprocket's wrap,
/// and how many pitches into it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Place {
    /// 1-based segment (free strand), if the place is one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub segment: Option<usize>,
    /// 1-based sprocket whose wrap it is, if the place is one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sprocket: Option<usize>,
    /// Pitches from the place's start (a strand's: leaving its first
    /// sprocket; a wrap's: engaging), counted at the link.
    pub pitches: usize,
    /// Share of the window's damage there (0 when there is none: then the
    /// place of the largest cycle).
    pub damage_share: f64,
    /// In words.
    pub text: String,
}

/// The summary's `fatigue` block.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Fatigue {
    /// The S–N curve's source, the mean-stress correction and the damage rule.
    pub basis: String,
    /// The S–N curve.
    pub sn_slope: f64,
    /// Its fatigue limit: the peak of the pulsating cycle endured for
    /// ever, N.
    pub fatigue_limit_n: f64,
    /// Its knee, cycles.
    pub knee_cycles: f64,
    /// The tensile strength of the mean-stress correction, N.
    pub tensile_strength_n: f64,
    /// Miner's damage per hour of operation at this point, per link (the
    /// mean over the chain's links: each runs through the whole loop).
    pub damage_per_hour: f64,
    /// Hours to a damage of 1: a number, or `"infinite"`.
    pub life_h: Life,
    /// The largest counted cycle as its pulsating equivalent, N (0: none).
    pub largest_cycle_n: f64,
    /// Fatigue limit over the largest cycle (absent without cycles).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fatigue_safety_factor: Option<f64>,
    /// Where the damage is largest (or the largest cycle was).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub least_life_at: Option<Place>,
    /// Links counted.
    pub links: usize,
    /// Time counted (the statistics window), s.
    pub counted_s: f64,
    /// Cycles counted, over all links (half cycles as ½).
    pub cycles: f64,
    /// Passes of the chain round its loop in the counted time.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub chain_circuits: Option<f64>,
    /// What limits these numbers.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
}

/// The place packed by [`super::link_cycles`] in words, with the strands
/// `strands` (1-based sprockets).
fn place_of(packed: u32, strands: &[StrandSummary], damage_share: f64) -> Option<Place> {
    let (index, pitches) = unpack(packed)?;
    let strand = strands.get(index / 2)?;
    let after = |n: usize, what: &str| match n {
        0 => format!("at {what}"),
        1 => format!("1 pitch after {what}"),
        n => format!("{n} pitches after {what}"),
    };
    Some(if index % 2 == 0 {
        Place {
            segment: Some(strand.segment),
            sprocket: None,
            pitches,
            damage_share,
            text: format!(
                "segment {} (sprocket {} to {}), {}",
                strand.segment,
                strand.from,
                strand.to,
                after(pitches, &format!("leaving sprocket {}", strand.from))
            ),
        }
    } else {
        Place {
            segment: None,
            sprocket: Some(strand.to),
            pitches,
            damage_share,
            text: format!("on sprocket {}, {}", strand.to, after(pitches, "engaging")),
        }
    })
}

/// The `fatigue` block of a run whose links `cycles` counted, with the
/// summary's strands and rating (its chain speed); `None` where the scene
/// has no S–N curve.
pub(crate) fn of_run(scene: &Scene, summary: &RunSummary, cycles: &LinkCycles) -> Option<Fatigue> {
    let (_, basis) = curve_of_scene(scene).ok()?;
    let curve = *cycles.curve();
    let sums = cycles.sums();
    let mut notes = Vec::new();
    let hours = sums.counted_s / 3600.0;
    let damage_per_hour = if hours > 0.0 && sums.links > 0 {
        sums.damage / (sums.links as f64 * hours)
    } else {
        notes.push(
            "no step was counted: the window holds no step with the chain on its sprockets"
                .to_owned(),
        );
        0.0
    };
    let total = sums.damage;
    let most = sums
        .by_place
        .iter()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .map(|(&p, &d)| (p, d / total));
    let least_life_at = match most {
        Some((p, share)) => place_of(p, &summary.strands, share),
        None => place_of(sums.largest_at, &summary.strands, 0.0),
    };
    let pitch_m = scene.chain.pitch_m;
    let chain_circuits = summary
        .rating
        .as_ref()
        .map(|r| r.chain_speed_m_s * sums.counted_s / (sums.links.max(1) as f64 * pitch_m));
    if let Some(c) = chain_circuits.filter(|&c| c < 1.0) {
        notes.push(format!(
            "the window holds {c:.2} circuits of the chain: each link's largest cycle (slack to tight strand and back) is counted from its halves, and the damage per hour is the mean over the links of what each saw; a window of a few circuits (--window) estimates it better"
        ));
    }
    let largest_lasts = curve.cycles_to_failure(sums.largest_n);
    if largest_lasts < LOW_CYCLE_LIMIT {
        notes.push(format!(
            "the largest cycle, {:.2} kN as a pulsating one ({:.0} % of the tensile strength), lasts {largest_lasts:.3} cycles on the S-N line: below {LOW_CYCLE_LIMIT:.0} cycles the line is the rating's extended beyond what a chain's fatigue tests cover (it reaches half the tensile strength at a few cycles), so the life says the chain is far overloaded, not how long it lasts",
            sums.largest_n * 1e-3,
            100.0 * sums.largest_n / curve.tensile_strength_n
        ));
    }
    if sums.overflows > 0 {
        notes.push(format!(
            "{} times a link's open turning points filled its stack ({} points): its oldest range was counted as half a cycle early",
            sums.overflows,
            super::rainflow::DEFAULT_CAPACITY
        ));
    }
    Some(Fatigue {
        basis,
        sn_slope: curve.slope,
        fatigue_limit_n: curve.fatigue_limit_n,
        knee_cycles: curve.knee_cycles,
        tensile_strength_n: curve.tensile_strength_n,
        damage_per_hour,
        life_h: Life::of_rate_per_hour(damage_per_hour),
        largest_cycle_n: sums.largest_n,
        fatigue_safety_factor: (sums.largest_n > 0.0)
            .then(|| curve.fatigue_limit_n / sums.largest_n),
        least_life_at,
        links: sums.links,
        counted_s: sums.counted_s,
        cycles: sums.cycles,
        chain_circuits,
        notes,
    })
}

/// The fatigue check's warning: a life shorter than the ratings' 15,000 h.
pub(crate) fn warnings(f: &Fatigue) -> Vec<String> {
    match f.life_h {
        Life::Hours(h) if h < RATING_LIFE_H => vec![format!(
            "fatigue: the link plates' fatigue life at this operating point is {} (below the {RATING_LIFE_H:.0} h the catalogue ratings are set for): the largest cycle, {:.2} kN as a pulsating one, is {:.2} times the fatigue limit of {:.2} kN{}; a larger chain, a lower load, or a smoother drive",
            f.life_h,
            f.largest_cycle_n * 1e-3,
            f.largest_cycle_n / f.fatigue_limit_n,
            f.fatigue_limit_n * 1e-3,
            f.least_life_at
                .as_ref()
                .map(|p| format!(", most damage {}", p.text))
                .unwrap_or_default()
        )],
        _ => Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The derived curve reproduces the rating: at the knee, the tension
    /// F₁ = H₁ / v of the link-plate rating at n₁ = N_D · 120 / (15,000 ·
    /// 60 · N₁); ANSI 40 (K = 0.004, p = 0.5 in) on 17 teeth:
    /// n₁ = 5e6 · 120 / (9e5 · 17) = 39.2 rpm, H₁ = 0.004 · 17^1.08 ·
    /// 39.2^0.9 · 0.5^2.965 hp, v = 17 · 0.0127 · 39.2 / 60 m/s.
    #[test]
    fn the_derived_fatigue_limit_is_the_rated_tension_at_the_knee() {
        let n1: f64 = 5e6 * 120.0 / (15_000.0 * 60.0 * 17.0);
        let h1_w =
            745.699_871_582_270_2 * 0.004 * 17f64.powf(1.08) * n1.powf(0.9) * 0.5f64.powf(2.965);
        let v = 17.0 * 0.0127 * n1 / 60.0;
        let c = curve_from_rating(ChainClass::Standard, 0.0127, 17.0, 13_900.0);
        approx::assert_relative_eq!(c.fatigue_limit_n, h1_w / v, max_relative = 1e-12);
        assert_eq!(c.slope, 10.0);
        // The rating's own point 1000 rpm: 7500 · 17 · 1000 cycles in
        // 15,000 h at the tension H₁ / v = 5.475 hp / 3.598 m/s.
        let cycles = 7500.0 * 17.0 * 1000.0;
        let f = rated_tension_n(ChainClass::Standard, 0.0127, 17.0, cycles);
        let expected = 745.699_871_582_270_2 * 5.475 / (17.0 * 0.0127 * 1000.0 / 60.0);
        approx::assert_relative_eq!(f, expected, max_relative = 2e-4);
        // On the S-N line: N = N_D (F_D / F)^10.
        approx::assert_relative_eq!(
            c.knee_cycles * (c.fatigue_limit_n / f).powf(10.0),
            cycles,
            max_relative = 1e-9
        );
    }
}
