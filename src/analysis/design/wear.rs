//! The wear check (docs/design-checks.md, "Wear"): how fast the chain
//! lengthens by pin–bushing wear, and in how many hours it reaches its
//! allowable elongation.
//!
//! **What it computes.** Archard's law, V = k F s / H, at every joint: the
//! pin slides on the bushing by s = r_pin |Δφ| under the pin load F (the
//! joints' sliding as counted every step, [`crate::sim::JointSliding`]), and
//! the worn volume spread over the bearing area A = d_pin L_bush (pin
//! diameter × bushing length) is the depth h = k Σ(F s) / (H A) by which the
//! pin and the bushing together wear (the joint's clearance grows by h).
//! Each joint lengthens the chain by its h (a joint lies between two pitches
//! and counts once), so the chain's elongation is the mean h over its
//! joints divided by the pitch. Over a window of T seconds at a steady
//! operating point that is a rate, % per 1000 h; the life is the hours to
//! the elongation limit, by default the smaller of 3 % and 200/z % of the
//! largest sprocket's z teeth.
//!
//! **What it does not.** It assumes steady, mild wear (after running-in,
//! before the hardened case is worn through: the straight middle of a
//! chain's wear curve) with one coefficient k; it knows no lubrication
//! regime, temperature, dirt or corrosion other than through k, no wear of
//! rollers, bushings' outsides or sprocket teeth, and no change of the
//! dynamics as the chain wears (run the worn chain with
//! `chain.elongation_pct` for that).

use serde::{Deserialize, Serialize};

use super::Life;
use crate::scene::{ELONGATION_LIMIT_CAP_PCT, Scene};
use crate::sim::JointSliding;

/// Seconds in 1000 hours.
const SECONDS_PER_1000_H: f64 = 3.6e6;

/// The wear model of a chain: Archard's constants, the bearing, the pitch
/// and the elongation limit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WearModel {
    /// Archard's wear coefficient k, dimensionless.
    pub coefficient: f64,
    /// Hardness H of the worn surfaces, Pa.
    pub hardness_pa: f64,
    /// Pin radius r_pin, m.
    pub pin_radius_m: f64,
    /// Length of the bushing the pin bears on, m.
    pub bushing_length_m: f64,
    /// The chain's pitch as new, m.
    pub pitch_m: f64,
    /// The elongation that ends the chain's life, %.
    pub elongation_limit_pct: f64,
}

impl WearModel {
    /// The model of `scene`'s chain, where the scene asks for the wear check
    /// (`checks.wear = true`, which needs the pin and bushing dimensions).
    pub fn of_scene(scene: &Scene) -> Option<Self> {
        let settings = scene.checks.wear?;
        let chain = &scene.chain;
        Some(Self {
            coefficient: settings.coefficient,
            hardness_pa: settings.hardness_pa,
            pin_radius_m: chain.pin_radius_m?,
            bushing_length_m: chain.bushing_length_m?,
            pitch_m: chain.pitch_m,
            elongation_limit_pct: settings
                .elongation_limit_pct
                .unwrap_or_else(|| default_elongation_limit_pct(scene)),
        })
    }

    /// The bearing area A = 2 r_pin L_bush, m².
    pub fn bearing_area_m2(&self) -> f64 {
        2.0 * self.pin_radius_m * self.bushing_length_m
    }

    /// The wear depth of a joint (pin and bushing together) after it slid
    /// through `load_angle_n_rad` = Σ F |Δφ| (N·rad): h = k r_pin Σ F |Δφ| /
    /// (H A), m.
    pub fn depth_m(&self, load_angle_n_rad: f64) -> f64 {
        self.coefficient * self.pin_radius_m * load_angle_n_rad
            / (self.hardness_pa * self.bearing_area_m2())
    }

    /// The chain's elongation rate, % per 1000 h, when its joints slide
    /// through `mean_load_angle_n_rad` = Σ F |Δφ| each, on average, in
    /// `duration_s` seconds.
    pub fn elongation_pct_per_1000h(&self, mean_load_angle_n_rad: f64, duration_s: f64) -> f64 {
        let depth_m = self.depth_m(mean_load_angle_n_rad);
        100.0 * depth_m / self.pitch_m * SECONDS_PER_1000_H / duration_s
    }

    /// The hours to the elongation limit at `rate_pct_per_1000h`.
    pub fn life(&self, rate_pct_per_1000h: f64) -> Life {
        Life::of_rate_per_hour(rate_pct_per_1000h / (1000.0 * self.elongation_limit_pct))
    }
}

/// The default elongation limit of `scene`'s chain, %: the smaller of 3 %
/// and 200/z % of its largest sprocket's z teeth (the catalogues' rule: a
/// larger sprocket's rollers ride out of their gaps at a smaller
/// elongation).
pub fn default_elongation_limit_pct(scene: &Scene) -> f64 {
    let z_max = scene.sprockets.iter().map(|s| s.teeth).max().unwrap_or(1);
    (200.0 / f64::from(z_max)).min(ELONGATION_LIMIT_CAP_PCT)
}

/// The summary's `wear` block (docs/design-checks.md, "Wear").
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Wear {
    /// The chain's wear elongation rate at the run's operating point, % per 1000 h.
    pub elongation_pct_per_1000h: f64,
    /// The elongation that ends the chain's life, %.
    pub elongation_limit_pct: f64,
    /// Hours to the limit at this rate.
    pub life_h: Life,
    /// Archard's k used, dimensionless.
    pub wear_coefficient: f64,
    /// The hardness H used, Pa.
    pub hardness_pa: f64,
    /// Bearing area d_pin × L_bush of one joint, m².
    pub bearing_area_m2: f64,
    /// Mean articulation of a joint, Σ|Δφ| per second, rad/s.
    pub articulation_rad_s: f64,
    /// Mean pin load while articulating, Σ F |Δφ| / Σ |Δφ|, N.
    pub mean_pin_load_n: f64,
    /// The time counted (the statistics window), s.
    pub counted_s: f64,
    /// The largest joint's rate over the counted time against the mean: a
    /// window shorter than a circuit of the chain leaves joints that passed
    /// no sprocket, so only the mean is the chain's.
    pub largest_joint_rate_ratio: f64,
    /// The quasi-static articulation of a joint, rad/s: 2π/z where it
    /// enters and again where it leaves each wrap of z teeth, Σ 4π/z_k per
    /// circuit of the chain, at the run's mean chain speed (absent where
    /// no sprocket turned). The run's `articulation_rad_s` exceeds it by
    /// what the strands' vibration adds.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub quasi_static_articulation_rad_s: Option<f64>,
}

/// Articulation beyond which a run's joints are taken to be turned mostly
/// by vibration rather than by the wraps, as a multiple of the quasi-static
/// one (a drive with joint friction runs about 1.2 times it).
pub const VIBRATION_ARTICULATION_RATIO: f64 = 2.0;

/// The quasi-static articulation of a joint of `scene`'s chain, rad/s, at
/// the sprockets' mean speeds `speeds_rad_s` (as the summary lists them):
/// Σ_k 4π/z_k per circuit, circuits per second |ω_k| z_k / (2π N) (the
/// largest over the sprockets: a tensioner's idler may stand); `None`
/// where none turned.
pub fn quasi_static_articulation_rad_s(scene: &Scene, speeds_rad_s: &[f64]) -> Option<f64> {
    let rollers = scene.chain.rollers as f64;
    let circuits_per_s = scene
        .sprockets
        .iter()
        .zip(speeds_rad_s)
        .map(|(s, w)| w.abs() * f64::from(s.teeth) / (std::f64::consts::TAU * rollers))
        .fold(0.0, f64::max);
    let per_circuit: f64 = scene
        .sprockets
        .iter()
        .map(|s| 2.0 * std::f64::consts::TAU / f64::from(s.teeth))
        .sum();
    (circuits_per_s > 0.0).then_some(per_circuit * circuits_per_s)
}

impl Wear {
    /// The wear of a run of `scene` whose joints slid as `sliding` counted,
    /// its sprockets turning at `speeds_rad_s` on average; `None` where the
    /// scene did not ask for the check or nothing was counted.
    pub fn of_run(scene: &Scene, sliding: &JointSliding, speeds_rad_s: &[f64]) -> Option<Self> {
        let model = WearModel::of_scene(scene)?;
        let duration_s = sliding.duration_s();
        let joints = sliding.load_angle_n_rad();
        if !(duration_s > 0.0) || joints.is_empty() {
            return None;
        }
        let n = joints.len() as f64;
        let mean_load_angle = joints.iter().sum::<f64>() / n;
        let mean_angle = sliding.angle_rad().iter().sum::<f64>() / n;
        let largest = joints.iter().copied().fold(0.0, f64::max);
        let rate = model.elongation_pct_per_1000h(mean_load_angle, duration_s);
        Some(Self {
            elongation_pct_per_1000h: rate,
            elongation_limit_pct: model.elongation_limit_pct,
            life_h: model.life(rate),
            wear_coefficient: model.coefficient,
            hardness_pa: model.hardness_pa,
            bearing_area_m2: model.bearing_area_m2(),
            articulation_rad_s: mean_angle / duration_s,
            mean_pin_load_n: if mean_angle > 0.0 {
                mean_load_angle / mean_angle
            } else {
                0.0
            },
            counted_s: duration_s,
            largest_joint_rate_ratio: if mean_load_angle > 0.0 {
                largest / mean_load_angle
            } else {
                0.0
            },
            quasi_static_articulation_rad_s: quasi_static_articulation_rad_s(scene, speeds_rad_s),
        })
    }

    /// A warning where the joints turned more than
    /// [`VIBRATION_ARTICULATION_RATIO`] times the quasi-static articulation:
    /// the wear then counts the strands' vibration, which a chain without
    /// joint friction overstates (nothing damps its link-scale zig-zag).
    pub fn vibration_warning(&self, joint_friction: bool) -> Option<String> {
        let quasi = self.quasi_static_articulation_rad_s?;
        let ratio = self.articulation_rad_s / quasi;
        (ratio > VIBRATION_ARTICULATION_RATIO).then(|| {
            let why = if joint_friction {
                "the strands' vibration turns them back and forth"
            } else {
                "without joint friction nothing damps the strands' link-scale zig-zag, which turns them back and forth; give chain.joint_friction (lubricated steel: about 0.1) for a wear rate of a real chain"
            };
            format!(
                "wear from vibration: the joints articulated {:.2} rad/s, {ratio:.1} times the {quasi:.2} rad/s of passing the wraps alone (allowed: {VIBRATION_ARTICULATION_RATIO}); {why}; the wear rate {:.3} % per 1000 h counts it all",
                self.articulation_rad_s, self.elongation_pct_per_1000h
            )
        })
    }
}

/// The life of a duty cycle's wear: points at `rates_pct_per_1000h` run for
/// `hours` each (or fractions of the time) wear Σ eᵢ tᵢ / Σ tᵢ on average,
/// and the chain reaches `limit_pct` after limit / that many hours
/// (docs/design-checks.md, "The shared types").
#[cfg(test)]
pub(crate) fn duty_life(limit_pct: f64, points: &[(f64, f64)]) -> Life {
    let hours: f64 = points.iter().map(|(_, t)| t).sum();
    if !(hours > 0.0) {
        return Life::Infinite;
    }
    let mean_rate = points.iter().map(|(e, t)| e * t).sum::<f64>() / hours;
    Life::of_rate_per_hour(mean_rate / (1000.0 * limit_pct))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model() -> WearModel {
        WearModel {
            coefficient: 1e-6,
            hardness_pa: 7e9,
            pin_radius_m: 0.005,
            bushing_length_m: 0.02,
            pitch_m: 0.02,
            elongation_limit_pct: 2.0,
        }
    }

    #[test]
    fn archard_depth_rate_and_life_by_hand() {
        // A = 2 · 0.005 · 0.02 = 2e-4 m². Σ F |Δφ| = 1e6 N·rad is
        // Σ F s = 0.005 · 1e6 = 5000 N·m; V = 1e-6 · 5000 / 7e9 =
        // 7.142857e-13 m³; h = V / A = 3.5714286e-9 m.
        let m = model();
        approx::assert_relative_eq!(m.bearing_area_m2(), 2e-4, max_relative = 1e-15);
        approx::assert_relative_eq!(m.depth_m(1e6), 3.5714286e-9, max_relative = 1e-7);
        // In 10 s: h / P = 1.7857143e-7 per 10 s = 1.7857143e-5 % per 10 s,
        // × 360 000 (10 s → 1000 h) = 6.4285714 % per 1000 h; to 2 %:
        // 2 / 6.4285714 × 1000 h = 311.111 h.
        let rate = m.elongation_pct_per_1000h(1e6, 10.0);
        approx::assert_relative_eq!(rate, 6.4285714, max_relative = 1e-7);
        let hours = m.life(rate).hours().unwrap_or(f64::NAN);
        approx::assert_relative_eq!(hours, 311.1111, max_relative = 1e-6);
        assert_eq!(m.life(0.0), Life::Infinite);
    }

    #[test]
    fn a_duty_cycle_life_is_the_limit_over_the_hour_weighted_rate() {
        // 1 %/1000 h for 3 h, 3 %/1000 h for 1 h: mean 1.5 %/1000 h; to 3 %,
        // 2000 h. Nothing run: infinite.
        let life = duty_life(3.0, &[(1.0, 3.0), (3.0, 1.0)]);
        approx::assert_relative_eq!(life.hours().unwrap_or(0.0), 2000.0, max_relative = 1e-12);
        assert_eq!(duty_life(3.0, &[]), Life::Infinite);
    }
}
