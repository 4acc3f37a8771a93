//! The hydraulic tensioner's chamber (docs/model.md, “Hydraulic
//! tensioner”): the pressure's rate, the leak through the plunger's annular
//! gap, the check valve from the supply, and the force on the plunger.
//! Pressures are gauge (relative to the ambient); the entrained air's
//! stiffness uses the absolute pressure.
//!
//! **The state is the fluid's volume, not its pressure.** The chamber holds
//! a fluid (oil with a fraction α of air, both measured at the ambient
//! pressure) of volume V_ref at the ambient pressure; at gauge pressure p it
//! fills V_ref φ(p), φ(p) = (1 − α)(1 − p/β) + α p_a/(p + p_a) (the oil
//! linearly compressible, the air isothermal). The chamber's volume V(x)
//! fixes the pressure: V_ref φ(p) = V(x), a quadratic in p. Only the flows
//! change V_ref, dV_ref/dt = (Q_in − Q_leak)/φ(p). Differentiating the
//! constraint gives the chamber equation dp/dt = β_eff/V (Q_in − Q_leak − A v)
//! with 1/β_eff = −φ'(p)/φ(p). Written this way the oil's stiffness
//! β_eff A²/V is a position-dependent force, which symplectic Euler keeps
//! stable as it keeps a spring; integrating dp/dt itself explicitly beside
//! the plunger's motion makes that stiff oscillator grow by e^(ω² h t/2).
//!
//! Nothing here knows the arm: [`super::TensionerArm`] gives the plunger's
//! travel and speed and takes its force.

use std::f64::consts::PI;

use crate::scene::HydraulicTensioner;

/// Below this pressure difference across the check valve, Pa, its flow is
/// taken as laminar, proportional to the difference and joined to the
/// turbulent orifice law √Δp with equal value at the joint: the orifice law's
/// infinite slope at Δp = 0 would otherwise make the chamber's equation
/// infinitely stiff as the valve opens.
pub(crate) const VALVE_TRANSITION_PA: f64 = 1e4;

/// The chamber's constants, derived once from the tensioner's parameters.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Chamber {
    /// The parameters.
    pub params: HydraulicTensioner,
    /// Plunger area A = π d²/4, m².
    pub area_m2: f64,
    /// Leak conductance G = π d c³ / (12 η L), m³/(s·Pa).
    pub leak_conductance: f64,
    /// C_d A_v √(2/ρ), the orifice's flow per √Pa, m³/(s·√Pa).
    pub valve_coefficient: f64,
}

impl Chamber {
    /// The chamber of `params`.
    pub(crate) fn new(params: &HydraulicTensioner) -> Self {
        let h = params;
        let valve_area = PI * h.valve_diameter_m * h.valve_diameter_m / 4.0;
        Self {
            params: *h,
            area_m2: PI * h.bore_m * h.bore_m / 4.0,
            leak_conductance: PI * h.bore_m * h.clearance_m.powi(3)
                / (12.0 * h.viscosity_pa_s * h.leak_length_m),
            valve_coefficient: h.valve_cd * valve_area * (2.0 / h.oil_density_kg_m3).sqrt(),
        }
    }

    /// The lowest gauge pressure the oil holds, Pa: absolute zero (it
    /// cavitates below).
    pub(crate) fn floor_pa(&self) -> f64 {
        -self.params.ambient_pressure_pa
    }

    /// Chamber volume V(x) = V₀ + A x at travel `x_m`, m³ (never below a
    /// thousandth of V₀, so that a plunger driven past its bottom stop
    /// leaves a finite stiffness).
    pub(crate) fn volume_m3(&self, x_m: f64) -> f64 {
        let v0 = self.params.chamber_volume_m3;
        (v0 + self.area_m2 * x_m).max(1e-3 * v0)
    }

    /// φ(p): the volume that fluid of unit volume at the ambient pressure
    /// fills at gauge pressure `p_pa`.
    pub(crate) fn fill_ratio(&self, p_pa: f64) -> f64 {
        let h = &self.params;
        let pa = h.ambient_pressure_pa;
        (1.0 - h.air_fraction) * (1.0 - p_pa / h.bulk_modulus_pa)
            + h.air_fraction * pa / (p_pa + pa)
    }

    /// The gauge pressure at which fluid of volume `reference_m3` (at the
    /// ambient pressure) fills `volume_m3`, Pa: the root above −p_a of
    /// V_ref φ(p) = V, i.e. with r = V / V_ref and a = 1 − α,
    /// (a/β) p² − (a − a p_a/β − r) p − p_a (1 − r) = 0
    /// (or, without air, p = β (1 − r)). Floored at the cavitation floor.
    pub(crate) fn pressure_pa(&self, reference_m3: f64, volume_m3: f64) -> f64 {
        let h = &self.params;
        let pa = h.ambient_pressure_pa;
        let r = volume_m3 / reference_m3;
        let p = if h.air_fraction == 0.0 {
            h.bulk_modulus_pa * (1.0 - r)
        } else {
            let a = 1.0 - h.air_fraction;
            let qa = a / h.bulk_modulus_pa;
            let qb = -(a - a * pa / h.bulk_modulus_pa - r);
            let qc = -pa * (1.0 - r);
            // qa > 0 and the product of the roots qc/qa: the larger root is
            // the physical one (the other lies below −p_a).
            let disc = (qb * qb - 4.0 * qa * qc).max(0.0);
            (-qb + disc.sqrt()) / (2.0 * qa)
        };
        if p.is_finite() {
            p.max(self.floor_pa())
        } else {
            self.floor_pa()
        }
    }

    /// The fluid volume at the ambient pressure that is at gauge pressure
    /// `p_pa` in the chamber at travel `x_m`, m³.
    pub(crate) fn reference_volume_m3(&self, p_pa: f64, x_m: f64) -> f64 {
        self.volume_m3(x_m) / self.fill_ratio(p_pa)
    }

    /// Effective bulk modulus at gauge pressure `p_pa`, Pa:
    /// 1/β_eff = −φ'(p)/φ(p), φ'(p) = −(1 − α)/β − α p_a/(p + p_a)².
    #[cfg(test)]
    pub(crate) fn bulk_modulus_pa(&self, p_pa: f64) -> f64 {
        let h = &self.params;
        let pa = h.ambient_pressure_pa;
        let absolute = (p_pa + pa).max(1e-3 * pa);
        let slope = (1.0 - h.air_fraction) / h.bulk_modulus_pa
            + h.air_fraction * pa / (absolute * absolute);
        self.fill_ratio(p_pa) / slope
    }

    /// Leak out through the annular gap, Q = G p, m³/s.
    pub(crate) fn leak_flow_m3_s(&self, p_pa: f64) -> f64 {
        self.leak_conductance * p_pa
    }

    /// The pressure difference that drives the check valve, p_s − p_crack − p,
    /// Pa: it is open while this is positive.
    pub(crate) fn valve_drive_pa(&self, p_pa: f64) -> f64 {
        self.params.supply_pressure_pa - self.params.cracking_pressure_pa - p_pa
    }

    /// Flow in through the check valve, m³/s: C_d A_v √(2 Δp / ρ) with
    /// Δp = [`Self::valve_drive_pa`] when open (laminar below
    /// [`VALVE_TRANSITION_PA`]), zero when closed.
    pub(crate) fn valve_flow_m3_s(&self, p_pa: f64) -> f64 {
        let dp = self.valve_drive_pa(p_pa);
        if dp <= 0.0 {
            0.0
        } else if dp < VALVE_TRANSITION_PA {
            self.valve_coefficient * dp / VALVE_TRANSITION_PA.sqrt()
        } else {
            self.valve_coefficient * dp.sqrt()
        }
    }

    /// dV_ref/dt = (Q_in − Q_leak)/φ(p), m³/s, at gauge pressure `p_pa`.
    pub(crate) fn reference_rate(&self, p_pa: f64) -> f64 {
        (self.valve_flow_m3_s(p_pa) - self.leak_flow_m3_s(p_pa)) / self.fill_ratio(p_pa)
    }

    /// The plunger's push at gauge pressure `p_pa` and travel `x_m`, N:
    /// p A plus the return spring F₀ − k x, plus the end stops, plus the
    /// ratchet's stop at `ratchet_floor_m` (`None`: no ratchet).
    pub(crate) fn force_n(&self, p_pa: f64, x_m: f64, ratchet_floor_m: Option<f64>) -> f64 {
        let h = &self.params;
        let mut f = p_pa.max(self.floor_pa()) * self.area_m2
            + return_spring_n(h.spring_preload_n, h.spring_stiffness_n_m, x_m)
            + stops_n(x_m, h.min_travel_m, h.max_travel_m, h.stop_stiffness_n_m);
        if let Some(floor) = ratchet_floor_m
            && x_m < floor
        {
            f += h.stop_stiffness_n_m * (floor - x_m);
        }
        f
    }
}

/// The return spring's push on a plunger at travel `x_m`, N: F₀ − k x while
/// compressed, nothing beyond its free length x_f = F₀/k (a compression
/// spring seated in the chamber pushes, never pulls); F₀ always when k = 0.
fn return_spring_n(preload_n: f64, k_n_m: f64, x_m: f64) -> f64 {
    (preload_n - k_n_m * x_m).max(0.0)
}

/// The return spring's potential at travel `x_m`, J: minus
/// [`return_spring_n`]'s integral from 0, −F₀ x + ½ k x² up to the free
/// length x_f = F₀/k and −F₀²/(2k) beyond it.
pub(crate) fn return_spring_j(preload_n: f64, k_n_m: f64, x_m: f64) -> f64 {
    if k_n_m > 0.0 && x_m > preload_n / k_n_m {
        -0.5 * preload_n * preload_n / k_n_m
    } else {
        -preload_n * x_m + 0.5 * k_n_m * x_m * x_m
    }
}

/// The end stops' force on a plunger at travel `x_m`, N: pushing out below
/// `min_m`, holding back beyond `max_m`, stiffness `k_n_m`.
pub(crate) fn stops_n(x_m: f64, min_m: f64, max_m: f64, k_n_m: f64) -> f64 {
    if x_m < min_m {
        k_n_m * (min_m - x_m)
    } else if x_m > max_m {
        -k_n_m * (x_m - max_m)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::STANDARD_ATMOSPHERE_PA;

    fn chamber() -> Chamber {
        Chamber::new(&params())
    }

    fn params() -> HydraulicTensioner {
        HydraulicTensioner {
            bore_m: 0.015,
            clearance_m: 20e-6,
            leak_length_m: 0.02,
            viscosity_pa_s: 0.01,
            bulk_modulus_pa: 1.5e9,
            air_fraction: 0.0,
            oil_density_kg_m3: 850.0,
            chamber_volume_m3: 2e-6,
            supply_pressure_pa: 3e5,
            cracking_pressure_pa: 2e4,
            valve_diameter_m: 2e-3,
            valve_cd: 0.7,
            spring_preload_n: 10.0,
            spring_stiffness_n_m: 1000.0,
            min_travel_m: -2e-3,
            max_travel_m: 5e-3,
            ratchet_backlash_m: None,
            stop_stiffness_n_m: 1e7,
            ambient_pressure_pa: STANDARD_ATMOSPHERE_PA,
        }
    }

    #[test]
    fn the_return_spring_pushes_only_while_compressed() {
        // F₀ = 10 N, k = 1000 N/m: free length x_f = 10 mm. Stops out of the
        // way (±50 mm). Oil: p A = 1e5 Pa · π (7.5 mm)² = 17.6715 N, by hand.
        let mut h = params();
        h.min_travel_m = -0.05;
        h.max_travel_m = 0.05;
        let oil_n = 1e5 * std::f64::consts::PI * 0.0075 * 0.0075;
        assert!((oil_n - 17.6715).abs() < 1e-4);
        let c = Chamber::new(&h);
        // Compressed (x = 4 mm): p A + F₀ − k x = p A + 6 N.
        assert!((c.force_n(1e5, 0.004, None) - (oil_n + 6.0)).abs() < 1e-9);
        // Short of the seat (x = −3 mm): p A + 13 N.
        assert!((c.force_n(1e5, -0.003, None) - (oil_n + 13.0)).abs() < 1e-9);
        // Beyond the free length (x = 20 mm): the oil alone, no pull.
        assert!((c.force_n(1e5, 0.02, None) - oil_n).abs() < 1e-9);
        // No stiffness: F₀ at any travel.
        h.spring_stiffness_n_m = 0.0;
        let c = Chamber::new(&h);
        assert!((c.force_n(1e5, 0.02, None) - (oil_n + 10.0)).abs() < 1e-9);
    }

    #[test]
    fn leak_conductance_is_the_annular_gap_formula() {
        // π d c³ / (12 η L) = π · 0.015 · 8e-15 / (12 · 0.01 · 0.02), by hand:
        // 3.7699e-16 / 2.4e-3 = 1.5708e-13 m³/(s·Pa).
        let c = chamber();
        assert!((c.leak_conductance / 1.5708e-13 - 1.0).abs() < 1e-4);
    }

    #[test]
    fn valve_flow_is_continuous_at_the_transition_and_closed_above_cracking() {
        let c = chamber();
        let p_open = 3e5 - 2e4;
        assert_eq!(c.valve_flow_m3_s(p_open + 1.0), 0.0);
        let p_joint = p_open - VALVE_TRANSITION_PA;
        let below = c.valve_flow_m3_s(p_joint - 1e-6);
        let above = c.valve_flow_m3_s(p_joint + 1e-6);
        assert!((below / above - 1.0).abs() < 1e-6);
    }

    #[test]
    fn air_softens_the_oil() {
        // α = 1 % at the ambient pressure (p = 0 gauge, φ = 1):
        // 1/β_eff = 0.99/1.5e9 + 0.01/101325, β_eff ≈ 9.95 MPa, far below
        // the oil's 1.5 GPa.
        let mut c = chamber();
        c.params.air_fraction = 0.01;
        let b = c.bulk_modulus_pa(0.0);
        let by_hand = 1.0 / (0.99 / 1.5e9 + 0.01 / STANDARD_ATMOSPHERE_PA);
        assert!((b / by_hand - 1.0).abs() < 1e-12 && b < 1.1e7);
    }

    #[test]
    fn the_pressure_of_a_reference_volume_round_trips() {
        for air in [0.0, 0.02] {
            let mut c = chamber();
            c.params.air_fraction = air;
            for p in [-5e4, 0.0, 3e5, 2e6] {
                let v_ref = c.reference_volume_m3(p, 1e-3);
                let back = c.pressure_pa(v_ref, c.volume_m3(1e-3));
                assert!(
                    (back - p).abs() < 1e-3 * (1.0 + p.abs()),
                    "{air} {p} {back}"
                );
            }
        }
    }

    #[test]
    fn the_pressure_does_not_fall_below_the_cavitation_floor() {
        let c = chamber();
        assert_eq!(c.pressure_pa(1e-6, 1.0), c.floor_pa());
    }
}
