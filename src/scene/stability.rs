//! The explicit schemes' stability estimates (docs/model.md, “Time scales and stability”),
//! from the validated chain and contact law alone; they also choose the step
//! of a scene whose `solver.dt_s` is `"auto"`, and say (one sentence for
//! `check` and `run` alike) how a scene's step stands against its
//! integrator's own estimate. Nothing here steps or measures a drive.

use super::periodic::{Harmonic, LoadTable};
use super::{Chain, Contact, Integrator, Role, Scene, Solver, Sprocket};

/// Safety factor of `dt_s = "auto"`: the step is this fraction of the
/// scheme's estimated largest stable step. The estimates are
/// linearisations (a link between two fixed neighbours, a contact carrying the
/// tight strand's tension at the approach-speed floor); on the paper's drive the largest
/// stable step measured 0.94 times the links' estimate and 2.4 times the
/// contact damping's (docs/model.md, “Time scales and stability”), so one
/// half keeps a margin below the worst case.
pub(crate) const AUTO_SAFETY: f64 = 0.5;

/// `dt_s = "auto"` takes at most this fraction of a roller's impact on
/// engagement, [`impact_duration_s`]: an impact rises and falls over t_c
/// roughly as a half sine, and a step of t_c / N misses its peak by at most
/// 1 − cos(π / (2N)), 0.5 % for N = 16. The convergence study
/// (docs/model.md, “Time scales and stability”; `benches/auto_dt.sh`): on
/// the motorcycle drive the cap takes the step from 12.8 to 6.67 µs and the
/// largest link force from 2.1 % to 0.2 % off the reference.
pub(crate) const AUTO_STEPS_PER_IMPACT: f64 = 16.0;

/// Safety factor of `dt_s = "speed"`: the step is at most this fraction of
/// the scheme's estimated largest stable step, with no cap for a roller's
/// impact. On the paper's drive the largest stable step measured 0.94 times
/// the links' estimate (the estimate that is not pessimistic), so nine tenths
/// stays below it; the statistics of the drive with joint friction converge
/// at that step with `verlet_implicit_damping` (docs/model.md, “Time scales
/// and stability”).
pub(crate) const SPEED_SAFETY: f64 = 0.9;

/// `dt_s = "auto"` chooses a whole fraction of the run's sample period; this
/// one, s (1 ms, the default 1 kHz), where no rate is given
/// ([`super::Overrides::sample_rate_hz`]).
pub(crate) const AUTO_GRID_S: f64 = 1e-3;

/// The largest force a roller's contact is expected to carry in steady
/// running, N: the tight strand's tension T₀ + ΔT (docs/model.md, “Time
/// scales and stability”).
///
/// Going round the loop the strand tension changes at each sprocket by its
/// torque over its pitch radius, M / R, and returns to where it began, so
/// the tightest strand exceeds the slackest by at most the sum of the rises,
/// ΔT ≤ Σ |M_i| / R_i over the sprockets that are not drivers (equal for
/// loads that all oppose the motion; larger than the truth where a load
/// assists it). A driver at a prescribed speed supplies whatever balances
/// them; a governed driver's own torque (its constant plus its series'
/// amplitudes or its table's largest value) over its pitch radius counts
/// where it is larger. A load's torque is its peak: the constant plus the
/// series' amplitudes and the table's largest value, plus a resisting
/// torque. The slackest strand is taken at the pretension T₀: a tensioner
/// holds its strand there, and on fixed centres the tight strand's stretch
/// draws the slack strand below it (the loaded conveyor: 13.44 kN measured
/// against T₀ + ΔT = 14.54 kN). Left out: the chain's weight (the rest
/// state's largest link force can exceed T₀ on a tall drive), the
/// centrifugal tension m v² (carried by the rollers' inertia on a sprocket,
/// not by their seats) and the sprockets' inertia under a changing speed.
/// The pretension where the sum is not a finite number (a scene already
/// reported invalid).
pub(crate) fn running_force_n(chain: &Chain, sprockets: &[Sprocket]) -> f64 {
    let loads: f64 = sprockets
        .iter()
        .filter(|s| !matches!(s.role, Role::Driver(_)))
        .map(|s| {
            let e = &s.excitation;
            let peak = peak_torque_n_m(
                s.load_torque_n_m(),
                &e.load_harmonics,
                e.load_table.as_ref(),
            ) + s.resisting_torque_n_m();
            peak / s.pitch_radius_m
        })
        .sum();
    let driven = sprockets
        .iter()
        .filter_map(|s| {
            let g = s.excitation.governor.as_ref()?;
            let peak = peak_torque_n_m(
                g.drive_torque_n_m,
                &g.drive_harmonics,
                g.drive_table.as_ref(),
            );
            Some(peak / s.pitch_radius_m)
        })
        .fold(0.0, f64::max);
    let force = chain.pretension_n + loads.max(driven);
    if force.is_finite() {
        force
    } else {
        chain.pretension_n
    }
}

/// The largest magnitude of a torque given as a constant, a harmonic series
/// and a table (its nodes), N·m: |constant| + Σ |amplitude| + max |node|.
fn peak_torque_n_m(constant: f64, harmonics: &[Harmonic], table: Option<&LoadTable>) -> f64 {
    let series: f64 = harmonics.iter().map(|h| h.amplitude.abs()).sum();
    let tabled = table.map_or(0.0, |t| {
        t.torques_n_m.iter().fold(0.0, |m: f64, x| m.max(x.abs()))
    });
    constant.abs() + series + tabled
}

/// Estimated largest stable steps of the explicit schemes (docs/model.md), s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct StepLimits {
    /// Links: 2 / ω_max with ω_max = 2 √(K / m_r) (symplectic Euler, velocity Verlet).
    pub links_s: f64,
    /// Contact damping at the approach-speed floor: 2 m_r / c with
    /// c = χ F / δ̇⁻_min, F the tight strand's tension in steady running
    /// ([`running_force_n`]): a roller carrying it, its contact begun slower
    /// than the floor.
    pub contact_damping_s: f64,
    /// Joint friction and damping (∞ without): 2 m_r ℓ² / (16 c_θ,eff) with
    /// c_θ,eff = μ r_pin F / ω_s + c_θ, the regularised law's slope in ω_rel
    /// at a pin load F, the tight strand's tension as above, and 16 / ℓ² the
    /// largest eigenvalue of the joints' damping matrix on the rollers'
    /// transverse speeds (the zig-zag mode, docs/model.md, “Joint friction”).
    pub joint_friction_s: f64,
}

impl StepLimits {
    /// The limits of a chain, its contact law and the sprockets whose
    /// torques load it ([`running_force_n`]).
    pub(crate) fn of_parts(chain: &Chain, contact: &Contact, sprockets: &[Sprocket]) -> Self {
        Self::at_force(chain, contact, running_force_n(chain, sprockets))
    }

    /// The limits of a chain and its contact law with a roller's contact and
    /// a pin carrying `force_n`, N.
    pub(crate) fn at_force(chain: &Chain, contact: &Contact, force_n: f64) -> Self {
        let m = chain.roller_mass_kg;
        let chi = contact.law.chi(contact.restitution);
        let c = chi * force_n / contact.min_approach_speed_m_s;
        let joint_friction_s = chain.joint_friction.map_or(f64::INFINITY, |j| {
            let slope = j.friction * j.pin_radius_m * force_n / j.speed_rad_s + j.damping_n_m_s_rad;
            if slope > 0.0 && slope.is_finite() {
                2.0 * m * chain.pitch_m * chain.pitch_m / (16.0 * slope)
            } else {
                f64::INFINITY
            }
        });
        Self {
            joint_friction_s,
            links_s: (m / chain.stiffness_n_m).sqrt(),
            contact_damping_s: if c > 0.0 && c.is_finite() {
                2.0 * m / c
            } else {
                f64::INFINITY
            },
        }
    }

    /// The smallest of them.
    pub(crate) fn min_s(&self) -> f64 {
        self.links_s
            .min(self.contact_damping_s)
            .min(self.joint_friction_s)
    }

    /// The estimated largest stable step of `scheme`, s (∞ for the adaptive
    /// scheme, which chooses its own): the smallest of [`Self::bounds_for`].
    pub(crate) fn for_integrator(&self, scheme: Integrator) -> f64 {
        self.bounds_for(scheme)
            .iter()
            .map(|b| b.1)
            .fold(f64::INFINITY, f64::min)
    }

    /// The estimates that bound `scheme`'s step, each scaled to its
    /// stability region, s. RK4's region reaches 2√2 on the imaginary axis
    /// (oscillating links) and 2.785 on the negative real axis (damping),
    /// against 2 and 2 for symplectic Euler and velocity Verlet. The implicit
    /// scheme is not bound by the contact damping; its joint friction stays
    /// explicit (its limit is far from binding at the default ω_s,
    /// docs/model.md, “Joint friction”). `verlet_implicit_damping` takes the
    /// contact damping by the trapezoidal rule (no bound) and the joint
    /// friction at velocities predicted from the step's start forces, which
    /// halves the explicit damping bound: a damping rate λ whose force is
    /// taken at p = v + h a is stable for h λ < 1 (the recursion
    /// (v, p) → ((1 − z/2) v + (z² − z) p / 2, v − z p), z = h λ, has
    /// trace 1 − 3z/2 and determinant −z/2; Jury's condition
    /// 1 + trace + det > 0 holds only for z < 1). The adaptive scheme has none.
    pub(crate) fn bounds_for(&self, scheme: Integrator) -> Vec<(&'static str, f64)> {
        let Some((links, damping, contact)) = Self::factors(scheme) else {
            return Vec::new();
        };
        let mut bounds = vec![("links", self.links_s * links)];
        if contact {
            bounds.push(("contact damping", self.contact_damping_s * damping));
        }
        bounds.push(("joint friction", self.joint_friction_s * damping));
        bounds
    }

    /// The contact damping's bound on `scheme`'s step, scaled to its
    /// stability region as in [`Self::bounds_for`], s; `None` for a scheme
    /// that the contact damping does not bound.
    pub(crate) fn contact_damping_for(&self, scheme: Integrator) -> Option<f64> {
        let (_, damping, contact) = Self::factors(scheme)?;
        contact.then_some(self.contact_damping_s * damping)
    }

    /// `scheme`'s stability region against the estimates: the factors on
    /// the links' and the damping estimates, and whether the contact damping
    /// is explicit; `None` for the adaptive scheme ([`Self::bounds_for`]).
    fn factors(scheme: Integrator) -> Option<(f64, f64, bool)> {
        match scheme {
            Integrator::SymplecticEuler | Integrator::VelocityVerlet => Some((1.0, 1.0, true)),
            Integrator::Rk4 => Some((std::f64::consts::SQRT_2, 1.3925, true)),
            Integrator::ImplicitDamping => Some((1.0, 1.0, false)),
            Integrator::VerletImplicitDamping => Some((1.0, 0.5, false)),
            Integrator::DormandPrince45 => None,
        }
    }

    /// The step `dt_s = "auto"` chooses for `scheme`: [`AUTO_SAFETY`] times
    /// its estimated limit, rounded down to a whole fraction of
    /// `sample_period_s` (so that the run's samples fall on whole numbers of
    /// steps, whatever its rate). The adaptive scheme, which needs no limit,
    /// gets the symplectic schemes' step as its largest (and sample) step.
    ///
    /// `impact_s` (∞ for none) caps it at 1/[`AUTO_STEPS_PER_IMPACT`] of a
    /// roller's impact on engagement, where stability alone leaves the
    /// deepest penetration unresolved.
    pub(crate) fn auto_step_s(
        &self,
        scheme: Integrator,
        impact_s: f64,
        sample_period_s: f64,
    ) -> f64 {
        let limit = match scheme {
            Integrator::DormandPrince45 => self.min_s(),
            other => self.for_integrator(other),
        };
        let raw = (AUTO_SAFETY * limit).min(impact_s / AUTO_STEPS_PER_IMPACT);
        whole_fraction(raw, sample_period_s)
    }

    /// The step `dt_s = "speed"` chooses for `scheme`: [`SPEED_SAFETY`]
    /// times its estimated limit (the adaptive scheme's: the smallest
    /// estimate), rounded down to a whole fraction of `sample_period_s`.
    pub(crate) fn speed_step_s(&self, scheme: Integrator, sample_period_s: f64) -> f64 {
        let limit = match scheme {
            Integrator::DormandPrince45 => self.min_s(),
            other => self.for_integrator(other),
        };
        whole_fraction(SPEED_SAFETY * limit, sample_period_s)
    }
}

/// The largest `period_s / n` not above `raw` (`raw` itself unless finite
/// and > 0); the small tolerance keeps a step that is already a whole
/// fraction from losing one.
fn whole_fraction(raw: f64, period_s: f64) -> f64 {
    if !(raw.is_finite() && raw > 0.0) {
        return raw;
    }
    let n = (period_s / raw * (1.0 - 1e-12)).ceil().max(1.0);
    period_s / n
}

impl StepLimits {
    /// The limits of a validated scene's chain, contact law and sprockets.
    pub(crate) fn of(scene: &Scene) -> Self {
        Self::of_parts(&scene.chain, &scene.contact, &scene.sprockets)
    }
}

/// How a validated scene's step was chosen, in one line for people (`check`
/// and `run` print the same): the step, its integrator's own estimated limit
/// and, for an automatic step, what bounded it.
pub fn step_note(scene: &Scene) -> String {
    let solver = &scene.solver;
    let scheme = solver.integrator.name();
    let limit_s = StepLimits::of(scene).for_integrator(solver.integrator);
    let how = if solver.dt_speed {
        let period_ms = (solver.sample_period_s * 1e12).round() / 1e9;
        format!(
            " (speed: at most {SPEED_SAFETY} x the estimated limit{}, a whole fraction of the {period_ms} ms sample period, no cap for a roller's impact)",
            if limit_s.is_finite() {
                ""
            } else {
                " of symplectic Euler"
            },
        )
    } else if solver.dt_auto {
        let impact_s = impact_duration_s(&scene.chain, &scene.contact, &scene.sprockets);
        // Nine digits: 1 ms, 0.2 ms, 0.333333333 ms.
        let period_ms = (solver.sample_period_s * 1e12).round() / 1e9;
        format!(
            " (auto: at most {AUTO_SAFETY} x the estimated limit{} and 1/{AUTO_STEPS_PER_IMPACT} of a roller's impact{}, a whole fraction of the {period_ms} ms sample period)",
            if limit_s.is_finite() {
                ""
            } else {
                " of symplectic Euler"
            },
            if impact_s.is_finite() {
                format!(" of {}", micro(impact_s))
            } else {
                String::new()
            },
        )
    } else {
        String::new()
    };
    let limit = if limit_s.is_finite() {
        format!("{scheme}'s estimated stability limit {}", micro(limit_s))
    } else {
        format!("{scheme} has no fixed stability limit: this is its largest step")
    };
    format!("dt = {}{how}; {limit}", micro(solver.dt_s))
}

/// A warning when `solver`'s step exceeds its integrator's own estimated
/// stability limit (the estimates that bound it listed), else `None`.
pub(super) fn step_warning(solver: &Solver, limits: &StepLimits) -> Option<String> {
    let limit_s = limits.for_integrator(solver.integrator);
    // Negated: a NaN step is reported too.
    if solver.dt_s <= limit_s {
        return None;
    }
    let bounds: Vec<String> = limits
        .bounds_for(solver.integrator)
        .iter()
        .filter(|b| b.1.is_finite())
        .map(|(what, s)| format!("{what} {}", micro(*s)))
        .collect();
    Some(format!(
        "solver.dt_s = {} exceeds {}'s estimated stability limit {} ({}; docs/model.md, “Time scales and stability”): a run may blow up; take a smaller step, or \"auto\"",
        micro(solver.dt_s),
        solver.integrator.name(),
        micro(limit_s),
        bounds.join(", ")
    ))
}

/// A time in µs for people (∞ kept as such).
pub(crate) fn micro(t_s: f64) -> String {
    if t_s.is_finite() {
        format!("{:.3} µs", t_s * 1e6)
    } else {
        format!("{t_s} s")
    }
}

/// Duration of the shortest roller impact on engagement, s (∞ where no
/// sprocket is driven at a speed).
///
/// A roller of mass m_r meets a tooth at v_i = v sin(2π/z) (the chain's
/// speed v = ω R of the fastest driver, at the peak of its speed harmonics,
/// turned through one tooth angle;
/// the smallest sprocket gives the fastest); against the contact law's
/// elastic part F = K δⁿ it penetrates δ_max = ((n+1) m_r v_i² / (2K))^(1/(n+1))
/// and leaves after t_c = 2 (δ_max / v_i) ∫₀¹ (1 − xⁿ⁺¹)^(−½) dx (Hertz's
/// impact, damping left out: it shortens the impact slightly).
pub(crate) fn impact_duration_s(chain: &Chain, contact: &Contact, sprockets: &[Sprocket]) -> f64 {
    let v = sprockets
        .iter()
        .filter_map(|s| match s.role {
            Role::Driver(law) => {
                // The speed harmonics' peak: ω̄ (1 + Σ |a_k|).
                let peak: f64 = 1.0
                    + s.excitation
                        .speed_harmonics
                        .iter()
                        .map(|h| h.amplitude.abs())
                        .sum::<f64>();
                Some(law.top_speed_rad_s() * peak * s.pitch_radius_m)
            }
            _ => None,
        })
        .fold(0.0, f64::max);
    let z = sprockets.iter().map(|s| s.teeth).min().unwrap_or(0);
    if !(v > 0.0 && v.is_finite()) || z < 3 {
        return f64::INFINITY;
    }
    let v_i = v * (std::f64::consts::TAU / f64::from(z)).sin();
    let (k, n, m) = (contact.stiffness, contact.exponent, chain.roller_mass_kg);
    if !(v_i > 0.0 && k > 0.0 && n > 0.0 && m > 0.0) {
        return f64::INFINITY;
    }
    let p = n + 1.0;
    let depth = (p * m * v_i * v_i / (2.0 * k)).powf(1.0 / p);
    let t = 2.0 * depth / v_i * rebound_integral(p);
    if t.is_finite() && t > 0.0 {
        t
    } else {
        f64::INFINITY
    }
}

/// ∫₀¹ (1 − xᵖ)^(−½) dx, by the midpoint rule after x = 1 − u² (which
/// removes the end singularity: the integrand becomes 2u (1 − (1 − u²)ᵖ)^(−½),
/// finite at u = 0); 10⁻⁴ relative for p in 1.5 … 3.
fn rebound_integral(p: f64) -> f64 {
    const N: u32 = 256;
    (0..N)
        .map(|i| {
            let u = (f64::from(i) + 0.5) / f64::from(N);
            2.0 * u / (1.0 - (1.0 - u * u).powf(p)).sqrt()
        })
        .sum::<f64>()
        / f64::from(N)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each scheme's limit, written out: symplectic Euler and velocity
    /// Verlet min(links, damping, joints); RK4 min(√2 links, 1.3925 damping,
    /// 1.3925 joints); the implicit scheme min(links, joints); the adaptive
    /// one none.
    #[test]
    fn each_scheme_is_bound_by_its_own_estimates() {
        let l = StepLimits {
            links_s: 10e-6,
            contact_damping_s: 3e-6,
            joint_friction_s: 20e-6,
        };
        assert_eq!(l.for_integrator(Integrator::SymplecticEuler), 3e-6);
        assert_eq!(l.for_integrator(Integrator::VelocityVerlet), 3e-6);
        assert_eq!(l.for_integrator(Integrator::Rk4), 3e-6 * 1.3925);
        assert_eq!(l.for_integrator(Integrator::ImplicitDamping), 10e-6);
        assert_eq!(l.for_integrator(Integrator::DormandPrince45), f64::INFINITY);
        let rk4_links = StepLimits {
            contact_damping_s: 1.0,
            ..l
        };
        assert_eq!(
            rk4_links.for_integrator(Integrator::Rk4),
            10e-6 * std::f64::consts::SQRT_2
        );
    }

    /// `verlet_implicit_damping`: no contact damping bound, the links' bound,
    /// half the joints' (10 µs links, 16 µs joints: 8 µs).
    #[test]
    fn the_implicit_verlet_is_bound_by_the_links_and_half_the_joints() {
        let l = StepLimits {
            links_s: 10e-6,
            contact_damping_s: 3e-6,
            joint_friction_s: 16e-6,
        };
        assert_eq!(l.for_integrator(Integrator::VerletImplicitDamping), 8e-6);
        let names: Vec<&str> = l
            .bounds_for(Integrator::VerletImplicitDamping)
            .iter()
            .map(|b| b.0)
            .collect();
        assert_eq!(names, ["links", "joint friction"]);
    }

    /// The bound's factor ½, checked on the scheme itself rather than on
    /// its matrix: a damper F = −c p, its force taken at the velocity p
    /// predicted from the step's start force, kicked half a step on each
    /// side. At h c/m = 0.95 a velocity decays; at 1.05 it grows.
    #[test]
    fn a_damper_at_predicted_velocities_is_stable_below_h_lambda_one() {
        let after = |z: f64| {
            // m = 1, c = 1, h = z.
            let (mut v, mut f) = (1.0_f64, -1.0_f64);
            for _ in 0..2000 {
                let half = v + 0.5 * z * f;
                let predicted = half + 0.5 * z * f;
                f = -predicted;
                v = half + 0.5 * z * f;
            }
            v.abs()
        };
        assert!(after(0.95) < 1e-6, "{}", after(0.95));
        assert!(after(1.05) > 1e6, "{}", after(1.05));
    }

    /// The drive with joint friction (`assets/l60mc-friction.toml`), real
    /// profile: its statistics converge with `verlet_implicit_damping` at
    /// 40 µs (benches/README.md), a step the scheme's estimate allows, so no
    /// stability warning; velocity Verlet, whose contact damping estimate is
    /// 19 µs, is warned at the same step. `dt_s = "speed"` takes 1/27 ms
    /// (nine tenths of the joints' 41.3 µs, rounded down to a whole fraction
    /// of 1 ms), also without a warning.
    #[test]
    fn the_converged_fast_setting_runs_without_a_stability_warning() {
        let text = include_str!("../../assets/l60mc-friction.toml");
        let with = |integrator, dt_s, dt_speed| {
            let overrides = super::super::Overrides {
                integrator: Some(integrator),
                dt_s,
                dt_speed,
                ..Default::default()
            };
            let scene = Scene::from_toml_with(text, &overrides).expect("valid scene");
            let warning = step_warning(&scene.solver, &StepLimits::of(&scene));
            (scene.solver.dt_s, warning)
        };
        let (_, warning) = with(Integrator::VerletImplicitDamping, Some(40e-6), false);
        assert_eq!(warning, None);
        let (_, warning) = with(Integrator::VelocityVerlet, Some(40e-6), false);
        assert!(warning.is_some_and(|w| w.contains("contact damping")));
        let (dt_s, warning) = with(Integrator::VerletImplicitDamping, None, true);
        approx::assert_relative_eq!(dt_s, 1e-3 / 27.0, max_relative = 1e-12);
        assert_eq!(warning, None);
    }

    /// The loaded conveyor (`tests/data/user_conveyor_loaded_100.toml`): ANSI
    /// 100, m_r = 2.49 lb/ft = 3.7055 kg/m × 0.03175 m = 0.117651 kg, T₀ = 1.5 kN, the
    /// tail braked by 800 N·m on R = 0.03175 / (2 sin 15°) = 0.0613363 m:
    /// F = 1500 + 13 042.9 = 14 542.9 N; χ = 0.5625 (e = 0.5), δ̇⁻_min = 0.05
    /// m/s: 2 m_r δ̇⁻_min / (χ F) = 1.43821 µs, below the 1.56 µs of the
    /// 13.44 kN its tight strand measured. The automatic step: half of it,
    /// 0.71910 µs, rounded down to 1 ms / 1391.
    #[test]
    fn the_loaded_conveyors_estimate_takes_its_brake() {
        let scene = Scene::from_toml(include_str!(
            "../../tests/data/user_conveyor_loaded_100.toml"
        ))
        .expect("valid scene");
        let radius = 0.03175 / (2.0 * 15f64.to_radians().sin());
        approx::assert_relative_eq!(radius, 0.0613363, max_relative = 1e-6);
        let force = 1500.0 + 800.0 / radius;
        approx::assert_relative_eq!(
            running_force_n(scene.chain(), scene.sprockets()),
            force,
            max_relative = 1e-9
        );
        let roller_kg = 2.49 * 0.453_592_37 / 0.3048 * 0.03175;
        let bound = 2.0 * roller_kg * 0.05 / (0.5625 * force);
        approx::assert_relative_eq!(bound, 1.43821e-6, max_relative = 1e-5);
        let limits = StepLimits::of(&scene);
        approx::assert_relative_eq!(limits.contact_damping_s, bound, max_relative = 1e-9);
        assert!(limits.for_integrator(Integrator::SymplecticEuler) <= 1.56e-6);
        approx::assert_relative_eq!(scene.solver().dt_s, 1e-3 / 1391.0, max_relative = 1e-12);
    }

    /// A drive with two loads (`tests/data/serpentine_08b_5.toml`): ISO 606
    /// 08B-1, m_r = 0.70 kg/m × 0.0127 m = 0.00889 kg, T₀ = 300 N, a pump
    /// braked by 5 N·m on 25 teeth (R = 0.0127 / (2 sin 7.2°) = 0.0506649
    /// m, 98.687 N) and a fan by 2 N·m on 21 (R = 0.0426054 m, 46.942 N):
    /// F = 445.63 N, 2 m_r δ̇⁻_min / (χ F) = 3.5465 µs at the default
    /// δ̇⁻_min = 0.05 m/s; the automatic step 1 ms / 564. The paper's drive,
    /// whose driven sprocket carries no load, keeps the pretension's
    /// estimate.
    #[test]
    fn two_loads_add_their_strand_tensions() {
        let scene = Scene::from_toml(include_str!("../../tests/data/serpentine_08b_5.toml"))
            .expect("valid scene");
        let radius = |teeth: f64| 0.0127 / (2.0 * (std::f64::consts::PI / teeth).sin());
        approx::assert_relative_eq!(radius(25.0), 0.0506649, max_relative = 1e-6);
        approx::assert_relative_eq!(radius(21.0), 0.0426054, max_relative = 1e-6);
        let force = 300.0 + 5.0 / radius(25.0) + 2.0 / radius(21.0);
        approx::assert_relative_eq!(force, 445.63, max_relative = 1e-5);
        let bound = 2.0 * 0.70 * 0.0127 * 0.05 / (0.5625 * force);
        approx::assert_relative_eq!(bound, 3.5465e-6, max_relative = 1e-4);
        approx::assert_relative_eq!(
            StepLimits::of(&scene).contact_damping_s,
            bound,
            max_relative = 1e-9
        );
        approx::assert_relative_eq!(scene.solver().dt_s, 1e-3 / 564.0, max_relative = 1e-12);
        let paper = Scene::l60mc();
        assert_eq!(
            running_force_n(paper.chain(), paper.sprockets()),
            paper.chain().pretension_n
        );
    }

    /// The contact damping's own bound on each scheme, by type rather than
    /// by its name in [`StepLimits::bounds_for`].
    #[test]
    fn the_contact_damping_bound_is_found_by_scheme() {
        let l = StepLimits {
            links_s: 10e-6,
            contact_damping_s: 3e-6,
            joint_friction_s: 20e-6,
        };
        assert_eq!(
            l.contact_damping_for(Integrator::SymplecticEuler),
            Some(3e-6)
        );
        assert_eq!(l.contact_damping_for(Integrator::Rk4), Some(3e-6 * 1.3925));
        assert_eq!(
            l.contact_damping_for(Integrator::VerletImplicitDamping),
            None
        );
        assert_eq!(l.contact_damping_for(Integrator::DormandPrince45), None);
    }

    /// Closed forms: p = 2 (linear spring), ∫₀¹ (1 − x²)^(−½) dx = π/2;
    /// p = 2.5 (Hertz), B(2/5, 1/2)/(5/2) = 1.4716 (Γ(0.4) = 2.21816,
    /// Γ(0.5) = √π, Γ(0.9) = 1.06863).
    #[test]
    fn rebound_integral_matches_closed_forms() {
        approx::assert_relative_eq!(
            rebound_integral(2.0),
            std::f64::consts::FRAC_PI_2,
            max_relative = 1e-4
        );
        let hertz = 2.21816 * std::f64::consts::PI.sqrt() / 1.06863 / 2.5;
        approx::assert_relative_eq!(rebound_integral(2.5), hertz, max_relative = 1e-4);
    }
}
