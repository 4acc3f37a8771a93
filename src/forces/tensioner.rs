//! [`TensionerArm`]: a rigid arm on a fixed pivot whose circular-arc shoe
//! the rollers ride on, pushed by a spring-damper or a hydraulic tensioner
//! (docs/model.md, “Tensioner arms”).
//!
//! The arm's angle q (from the scene's pose, counter-clockwise) and speed u
//! are a further body's coordinate ([`crate::model::BodyModel`]); a hydraulic
//! chamber's pressure is a scalar state ([`crate::model::ScalarModel`]). The
//! tensioner acts at a point of the arm along a line fixed in the world:
//! its travel x and speed v follow from the arm's angle (the plunger is tied
//! to the arm kinematically, its mass is in the arm's inertia), so that
//! x = (a(q) − a(0))·ê and v = u (r × ê), r = a − pivot.
//!
//! Roller–shoe contact is a guide's ([`GuideElement`]): the shoe is a carried
//! guide face (a circular arc working on its outside) turned with the arm,
//! meeting the rollers with the scene's contact law and regularised Coulomb
//! friction; its moment about the pivot goes into the arm's body force.

use std::any::Any;

use super::contact_law::ContactLawParams;
use super::guide::{Carrier, GuideElement, GuideParams};
use super::hydraulic::{Chamber, return_spring_j, stops_n};
use super::{ForceElement, Forces, History, HistoryError, HistoryReader};
use crate::geometry::shoe::{Face, Piece};
use crate::model::{DriveModel, DriveState};
use crate::scene::{Tensioner, TensionerKind};

/// What a tensioner arm reports at its last evaluation.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct TensionerReading {
    /// Arm angle from the scene's pose, rad (counter-clockwise).
    pub angle_rad: f64,
    /// Arm angular speed, rad/s.
    pub speed_rad_s: f64,
    /// Tensioner travel x from the scene's pose, m (positive pushing out).
    pub travel_m: f64,
    /// Tensioner (plunger) speed v, m/s.
    pub plunger_speed_m_s: f64,
    /// The tensioner's push on the arm, N.
    pub plunger_force_n: f64,
    /// Chamber pressure (gauge), Pa; 0 for a spring tensioner.
    pub pressure_pa: f64,
    /// Whether the check valve is open (always false for a spring tensioner).
    pub valve_open: bool,
    /// Flow in through the check valve, m³/s.
    pub valve_flow_m3_s: f64,
    /// Leak flow out through the plunger's gap, m³/s.
    pub leak_flow_m3_s: f64,
    /// Magnitude of the chain's resultant force on the shoe, N.
    pub shoe_force_n: f64,
    /// Rollers touching the shoe.
    pub shoe_rollers: usize,
}

/// A tensioner arm with its tensioner: one force element per arm.
#[derive(Clone, Debug)]
pub(crate) struct TensionerArm {
    params: Tensioner,
    /// The arm's body coordinate in [`DriveState::q`].
    body: usize,
    /// The chamber's pressure in [`DriveState::z`] (hydraulic only).
    scalar: Option<usize>,
    chamber: Option<Chamber>,
    /// The shoe: a guide carried by the arm's body coordinate.
    shoe: GuideElement,
    /// The ratchet's furthest travel, committed (NaN: not yet known).
    peak_m: f64,
    /// What the chamber's state z adds up to with: V_ref = z + offset, m³
    /// (NaN: to be set at the next evaluation so that the chamber is at
    /// its supply pressure there, as the static equilibrium leaves it).
    offset_m3: f64,
    /// Travel at the last evaluation.
    travel_next_m: f64,
    relaxing: bool,
    reading: TensionerReading,
}

impl TensionerArm {
    /// The arm of `params` on body coordinate `body` (and the chamber's
    /// pressure on scalar `scalar`, hydraulic only) in a drive of `rollers`
    /// rollers of radius `roller_radius_m`, meeting the shoe with `law`.
    pub(crate) fn new(
        params: &Tensioner,
        body: usize,
        scalar: Option<usize>,
        law: ContactLawParams,
        rollers: usize,
        roller_radius_m: f64,
    ) -> Self {
        let chamber = match &params.kind {
            TensionerKind::Hydraulic(h) => Some(Chamber::new(h)),
            TensionerKind::Spring(_) => None,
        };
        // The arc from its counter-clockwise start: its left is the centre's
        // side, so the rollers ride on the right (side −1).
        let face = Face::new(
            Piece::Arc {
                center_m: params.shoe_center_m,
                radius_m: params.shoe_radius_m,
                start_rad: params.shoe_start_rad,
                sweep_rad: params.shoe_span_rad,
            },
            -1.0,
            None,
            None,
        );
        let shoe = GuideElement::new(
            GuideParams {
                name: params.name.clone(),
                face,
                law,
                friction: params.shoe_friction,
                slip_speed_m_s: params.shoe_friction_speed_m_s,
                carrier: Some(Carrier {
                    body,
                    pivot_m: params.pivot_m,
                }),
            },
            rollers,
            roller_radius_m,
        );
        Self {
            params: params.clone(),
            body,
            scalar,
            chamber,
            shoe,
            peak_m: f64::NAN,
            offset_m3: f64::NAN,
            travel_next_m: 0.0,
            relaxing: false,
            reading: TensionerReading::default(),
        }
    }

    /// What the last evaluation found.
    #[cfg(test)]
    pub(crate) fn reading(&self) -> &TensionerReading {
        &self.reading
    }

    /// The chamber state z that holds gauge pressure `p_pa` at arm angle
    /// `q` (hydraulic only; `None` for a spring tensioner).
    #[cfg(test)]
    pub(crate) fn chamber_state_for(&self, p_pa: f64, q: f64) -> Option<f64> {
        let ch = self.chamber.as_ref()?;
        let (_, x) = self.lever_and_travel(q);
        Some(ch.reference_volume_m3(p_pa, x) - self.offset_m3)
    }

    /// The lever of the tensioner's line about the pivot at arm angle `q`,
    /// ℓ = r × ê, m, and the travel x = (a(q) − a(0))·ê, m.
    pub(crate) fn lever_and_travel(&self, q: f64) -> (f64, f64) {
        lever_and_travel(&self.params, q)
    }

    /// What the static equilibrium needs of the arm at rest: its body
    /// coordinate, its length scale and its potential energy.
    pub(crate) fn at_rest(&self) -> ArmAtRest {
        ArmAtRest {
            params: self.params.clone(),
            body: self.body,
            chamber: self.chamber,
        }
    }
}

/// A tensioner arm at rest, as the static equilibrium sees it: the
/// hydraulic chamber held at its supply pressure (as while relaxing), no
/// ratchet, no damping. The tensioner's push and the arm's weight are then
/// conservative, with the potential [`ArmAtRest::potential_j`].
#[derive(Clone, Debug)]
pub(crate) struct ArmAtRest {
    params: Tensioner,
    body: usize,
    chamber: Option<Chamber>,
}

impl ArmAtRest {
    /// The arm's body coordinate in [`DriveState::q`].
    pub(crate) fn body(&self) -> usize {
        self.body
    }

    /// The arm's length scale, m: its shoe's distance from the pivot (at
    /// least the shoe's radius). Turning the arm by δ moves the shoe by
    /// about δ times this.
    pub(crate) fn reach_m(&self) -> f64 {
        let p = &self.params;
        (p.shoe_center_m[0] - p.pivot_m[0])
            .hypot(p.shoe_center_m[1] - p.pivot_m[1])
            .max(p.shoe_radius_m)
    }

    /// Potential energy of the tensioner's push and the arm's weight at arm
    /// angle `q`, relative to the scene's pose, J: its derivative is minus
    /// the moment [`TensionerArm`] puts on the arm at rest (the shoe's
    /// contact energy is the contact's).
    pub(crate) fn potential_j(&self, gravity_m_s2: [f64; 2], q: f64) -> f64 {
        let p = &self.params;
        let (_, x) = lever_and_travel(p, q);
        // A spring tensioner's push F(x) = F₀ − k x + stops(x), tied to the
        // arm (it pulls beyond x = F₀/k): U = −F₀ x + ½ k x² + U_stops(x).
        // A hydraulic one's: p_s A + max(0, F₀ − k x) + stops(x), its return
        // spring pushing only while compressed.
        let mut u = match (&p.kind, &self.chamber) {
            (TensionerKind::Spring(sp), _) => {
                -sp.preload_n * x
                    + 0.5 * sp.stiffness_n_m * x * x
                    + stops_j(x, sp.min_travel_m, sp.max_travel_m, sp.stop_stiffness_n_m)
            }
            (TensionerKind::Hydraulic(h), Some(ch)) => {
                -h.supply_pressure_pa.max(ch.floor_pa()) * ch.area_m2 * x
                    + return_spring_j(h.spring_preload_n, h.spring_stiffness_n_m, x)
                    + stops_j(x, h.min_travel_m, h.max_travel_m, h.stop_stiffness_n_m)
            }
            (TensionerKind::Hydraulic(_), None) => 0.0,
        };
        if p.mass_kg > 0.0 {
            // U = −m g·(c(q) − c(0)), c the centre of mass.
            let r0 = [
                p.center_of_mass_m[0] - p.pivot_m[0],
                p.center_of_mass_m[1] - p.pivot_m[1],
            ];
            let (s, c) = q.sin_cos();
            let r = rotate(s, c, r0);
            let [gx, gy] = gravity_m_s2;
            u -= p.mass_kg * (gx * (r[0] - r0[0]) + gy * (r[1] - r0[1]));
        }
        u
    }
}

/// The end stops' potential at travel `x_m`, J: [`stops_n`]'s integral.
fn stops_j(x_m: f64, min_m: f64, max_m: f64, k_n_m: f64) -> f64 {
    if x_m < min_m {
        0.5 * k_n_m * (min_m - x_m).powi(2)
    } else if x_m > max_m {
        0.5 * k_n_m * (x_m - max_m).powi(2)
    } else {
        0.0
    }
}

/// The lever of `p`'s tensioner line about the pivot at arm angle `q`,
/// ℓ = r × ê, m, and the travel x = (a(q) − a(0))·ê, m.
fn lever_and_travel(p: &Tensioner, q: f64) -> (f64, f64) {
    let (s, c) = q.sin_cos();
    let r0 = [p.point_m[0] - p.pivot_m[0], p.point_m[1] - p.pivot_m[1]];
    let r = rotate(s, c, r0);
    let e = p.direction;
    let lever = r[0] * e[1] - r[1] * e[0];
    let travel = (r[0] - r0[0]) * e[0] + (r[1] - r0[1]) * e[1];
    (lever, travel)
}

#[inline]
fn rotate(s: f64, c: f64, v: [f64; 2]) -> [f64; 2] {
    [c * v[0] - s * v[1], s * v[0] + c * v[1]]
}

impl ForceElement for TensionerArm {
    fn name(&self) -> &'static str {
        "tensioners"
    }

    fn evaluate(&mut self, model: &DriveModel, state: &DriveState, out: &mut Forces) {
        let p = &self.params;
        let (q, u) = (state.q[self.body], state.u[self.body]);
        let (s, c) = q.sin_cos();
        let pivot = p.pivot_m;
        let rel = |a: [f64; 2]| [a[0] - pivot[0], a[1] - pivot[1]];
        // The shoe's contact (its moment is in the body force already).
        let shoe = self.shoe.contact(state, out);
        let mut moment = 0.0;
        // The arm's weight.
        if p.mass_kg > 0.0 {
            let g = rotate(s, c, rel(p.center_of_mass_m));
            let [gx, gy] = model.gravity_m_s2;
            moment += p.mass_kg * (g[0] * gy - g[1] * gx);
        }
        // The tensioner.
        let (lever, x) = self.lever_and_travel(q);
        let v = u * lever;
        self.travel_next_m = x;
        let (mut pressure, mut valve_flow, mut leak_flow) = (0.0, 0.0, 0.0);
        let mut valve_open = false;
        let force = match (&p.kind, &self.chamber) {
            (TensionerKind::Spring(sp), _) => {
                sp.preload_n - sp.stiffness_n_m * x - sp.damping_n_s_m * v
                    + stops_n(x, sp.min_travel_m, sp.max_travel_m, sp.stop_stiffness_n_m)
            }
            (TensionerKind::Hydraulic(h), Some(ch)) => {
                let k = self.scalar.unwrap_or(0);
                if self.offset_m3.is_nan() {
                    self.offset_m3 = ch.reference_volume_m3(h.supply_pressure_pa, x) - state.z[k];
                }
                pressure = if self.relaxing {
                    h.supply_pressure_pa
                } else {
                    ch.pressure_pa(state.z[k] + self.offset_m3, ch.volume_m3(x))
                };
                valve_flow = ch.valve_flow_m3_s(pressure);
                leak_flow = ch.leak_flow_m3_s(pressure);
                valve_open = valve_flow > 0.0;
                out.scalar_rate[k] += if self.relaxing {
                    0.0
                } else {
                    ch.reference_rate(pressure)
                };
                let ratchet = match h.ratchet_backlash_m {
                    Some(b) if !self.relaxing => Some(self.peak_m.max(x) - b),
                    _ => None,
                };
                ch.force_n(pressure, x, ratchet)
            }
            (TensionerKind::Hydraulic(_), None) => 0.0,
        };
        moment += force * lever;
        out.body_force[self.body] += moment;
        if out.tensioners.len() <= self.body {
            out.tensioners
                .resize(self.body + 1, TensionerReading::default());
        }
        self.reading = TensionerReading {
            angle_rad: q,
            speed_rad_s: u,
            travel_m: x,
            plunger_speed_m_s: v,
            plunger_force_n: force,
            pressure_pa: pressure,
            valve_open,
            valve_flow_m3_s: valve_flow,
            leak_flow_m3_s: leak_flow,
            shoe_force_n: shoe.force_n[0].hypot(shoe.force_n[1]),
            shoe_rollers: shoe.contacts,
        };
        out.tensioners[self.body] = self.reading;
    }

    fn commit(&mut self) {
        self.shoe.commit();
        // f64::max drops the NaN of a ratchet not yet set.
        self.peak_m = self.peak_m.max(self.travel_next_m);
    }

    fn save_history(&self, history: &mut History) {
        self.shoe.save_history(history);
        history.push_floats([self.peak_m, self.offset_m3, self.travel_next_m]);
    }

    fn restore_history(&mut self, history: &mut HistoryReader<'_>) -> Result<(), HistoryError> {
        self.shoe.restore_history(history)?;
        let [peak, offset, travel] = history.floats(3)? else {
            return Err(HistoryError::Missing("float"));
        };
        (self.peak_m, self.offset_m3, self.travel_next_m) = (*peak, *offset, *travel);
        Ok(())
    }

    fn reset(&mut self) {
        self.shoe.reset();
        self.peak_m = f64::NAN;
        self.offset_m3 = f64::NAN;
    }

    fn begin_equilibrium(&mut self) {
        self.relaxing = true;
        self.shoe.begin_equilibrium();
    }

    fn end_equilibrium(&mut self) {
        self.relaxing = false;
        self.shoe.end_equilibrium();
    }

    fn clone_box(&self) -> Box<dyn ForceElement> {
        Box::new(self.clone())
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}
