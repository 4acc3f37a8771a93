//! The drive's mechanical energy, for balances and conservation checks.

use crate::forces::ForceGenerator;
use crate::model::{DriveModel, DriveState};

/// Mechanical energy of a drive state, J.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energy {
    /// Rollers' and sprockets' kinetic energy.
    pub kinetic_j: f64,
    /// The links' elastic energy Σ ½ K (l − l₀)².
    pub links_j: f64,
    /// The contacts' elastic energy Σ K_g δⁿ⁺¹ / (n + 1) (from the last evaluation).
    pub contacts_j: f64,
    /// The rollers' potential energy in gravity, −Σ m g · q.
    pub gravity_j: f64,
}

impl Energy {
    /// Of `state`, with `forces` evaluated at it.
    pub fn of(model: &DriveModel, state: &DriveState, forces: &ForceGenerator) -> Self {
        let m = model.roller_mass_kg;
        let n = state.rollers();
        let mut kinetic = 0.0;
        let mut gravity = 0.0;
        let mut links = 0.0;
        let [gx, gy] = model.gravity_m_s2;
        for i in 0..n {
            kinetic += 0.5 * m * (state.vx[i] * state.vx[i] + state.vy[i] * state.vy[i]);
            gravity -= m * (gx * state.x[i] + gy * state.y[i]);
            let j = (i + 1) % n;
            let l = (state.x[j] - state.x[i]).hypot(state.y[j] - state.y[i]);
            let s = l - model.rest_length_m;
            links += 0.5 * model.stiffness_n_m * s * s;
        }
        for (sp, omega) in model.sprockets.iter().zip(&state.omega) {
            if sp.inv_inertia > 0.0 {
                kinetic += 0.5 * omega * omega / sp.inv_inertia;
            }
        }
        Self {
            kinetic_j: kinetic,
            links_j: links,
            contacts_j: forces.output().contact_energy_j,
            gravity_j: gravity,
        }
    }

    /// The sum.
    pub fn total_j(&self) -> f64 {
        self.kinetic_j + self.links_j + self.contacts_j + self.gravity_j
    }
}

/// The power of each kind of force at one state, W. Losses are counted as
/// the power they dissipate (≥ 0), the driver's as the power it delivers,
/// the loads' as the power they absorb (positive for a braking load).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Powers {
    /// Delivered by the speed-controlled sprockets, Σ −(chain moment) ω,
    /// and by a torque-driven driver's torque, T ω.
    pub driver_w: f64,
    /// Absorbed by the load torques: Σ −τ_load ω over the free sprockets.
    pub load_w: f64,
    /// Dissipated by the joint friction: −Σ M_i ω_rel,i.
    pub joint_friction_w: f64,
    /// Dissipated by the links' dampers: Σ (F − K s)² / D.
    pub link_damping_w: f64,
    /// Dissipated by the contacts' damping: Σ (f − K δⁿ) δ̇.
    pub contact_damping_w: f64,
}

/// Σ (F − K s)² / D over the links, `inv_damping` = 1/D, summed in link
/// order from −0 as `Iterator::sum` does; the terms four at a time, which
/// the compiler computes in packed form (the sum itself stays in order, so
/// its bits are those of the plain fold).
fn damping_sum(force: &[f64], stretch: &[f64], stiffness: f64, inv_damping: f64) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2, checked on the line above.
        return unsafe { damping_sum_avx2(force, stretch, stiffness, inv_damping) };
    }
    damping_sum_body(force, stretch, stiffness, inv_damping)
}

/// [`damping_sum_body`] compiled with AVX2 (no FMA: the same roundings).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn damping_sum_avx2(force: &[f64], stretch: &[f64], stiffness: f64, inv_damping: f64) -> f64 {
    damping_sum_body(force, stretch, stiffness, inv_damping)
}

#[inline(always)]
fn damping_sum_body(force: &[f64], stretch: &[f64], stiffness: f64, inv_damping: f64) -> f64 {
    let term = |f: f64, s: f64| {
        let d = f - stiffness * s;
        d * d * inv_damping
    };
    let n = force.len().min(stretch.len());
    let (force, stretch) = (&force[..n], &stretch[..n]);
    let mut total = -0.0;
    let (fc, sc) = (force.chunks_exact(4), stretch.chunks_exact(4));
    let (f_rest, s_rest) = (fc.remainder(), sc.remainder());
    for (f, s) in fc.zip(sc) {
        let t = [
            term(f[0], s[0]),
            term(f[1], s[1]),
            term(f[2], s[2]),
            term(f[3], s[3]),
        ];
        total += t[0];
        total += t[1];
        total += t[2];
        total += t[3];
    }
    for (f, s) in f_rest.iter().zip(s_rest) {
        total += term(*f, *s);
    }
    total
}

impl Powers {
    /// At `state`, with `forces` evaluated at it.
    pub fn of(model: &DriveModel, state: &DriveState, forces: &ForceGenerator) -> Self {
        let out = forces.output();
        let (mut driver, mut load) = (0.0, 0.0);
        for (s, sp) in model.sprockets.iter().enumerate() {
            let omega = state.omega[s];
            if sp.speed_law.is_some() {
                driver -= out.chain_torque[s] * omega;
            } else if sp.governor.is_some() {
                // A torque-driven driver's torque (its inertia's kinetic
                // energy stays in the balance).
                driver += sp.torque_at(state.t_s, state.theta[s], omega) * omega;
            } else {
                load -= sp.torque_at(state.t_s, state.theta[s], state.omega[s]) * omega;
            }
        }
        // The link force is K s + D u·Δv: its damping part from the force and
        // the stretch, without another square root.
        let link_damping = if model.damping_n_s_m > 0.0 {
            damping_sum(
                &out.link_force,
                forces.links.stretch(),
                model.stiffness_n_m,
                1.0 / model.damping_n_s_m,
            )
        } else {
            0.0
        };
        Self {
            driver_w: driver,
            load_w: load,
            joint_friction_w: -out.joint_friction_power_w,
            link_damping_w: link_damping,
            contact_damping_w: -out.contact_damping_power_w,
        }
    }

    fn scaled_sum(&self, other: &Self, w: f64) -> Self {
        Self {
            driver_w: self.driver_w + w * other.driver_w,
            load_w: self.load_w + w * other.load_w,
            joint_friction_w: self.joint_friction_w + w * other.joint_friction_w,
            link_damping_w: self.link_damping_w + w * other.link_damping_w,
            contact_damping_w: self.contact_damping_w + w * other.contact_damping_w,
        }
    }

    /// The losses: joint friction, link and contact damping, W.
    pub fn losses_w(&self) -> f64 {
        self.joint_friction_w + self.link_damping_w + self.contact_damping_w
    }
}

/// The energy a balance counts: the drive's mechanical energy less the
/// kinetic energy of the speed-controlled sprockets (their speed is imposed,
/// so the driver's power is measured at the chain), J.
pub fn balance_energy_j(model: &DriveModel, state: &DriveState, forces: &ForceGenerator) -> f64 {
    let driven: f64 = model
        .sprockets
        .iter()
        .zip(&state.omega)
        .filter(|(sp, _)| sp.speed_law.is_some() && sp.inv_inertia > 0.0)
        .map(|(sp, w)| 0.5 * w * w / sp.inv_inertia)
        .sum();
    Energy::of(model, state, forces).total_j() - driven
}

/// Where the power goes over a window: every kind of force's power
/// integrated step by step (trapezoids) from `from_s` on, and the energy at
/// the window's ends (docs/model.md, “Where the power goes”).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PowerLedger {
    from_s: f64,
    start: Option<(f64, f64)>,
    last: Option<(f64, Powers)>,
    end: Option<(f64, f64)>,
    work: Powers,
}

/// A [`PowerLedger`]'s window means.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PowerMeans {
    /// Window length, s.
    pub duration_s: f64,
    /// Mean powers over the window, W.
    pub mean: Powers,
    /// Change of [`balance_energy_j`] over the window, J.
    pub energy_change_j: f64,
}

impl PowerMeans {
    /// Relative residual of driver power = losses + load power + dE/dt,
    /// against the mean |power| flowing through the drive (the driver's and
    /// the loads' powers); 0 when nothing flows.
    pub fn balance_error(&self) -> f64 {
        let m = &self.mean;
        let through = m.driver_w.abs().max(m.load_w.abs());
        if !(through > 0.0) || !(self.duration_s > 0.0) {
            return 0.0;
        }
        (m.driver_w - m.losses_w() - m.load_w - self.energy_change_j / self.duration_s) / through
    }
}

impl PowerLedger {
    /// A ledger that counts from `from_s` on.
    pub fn new(from_s: f64) -> Self {
        Self {
            from_s,
            start: None,
            last: None,
            end: None,
            work: Powers::default(),
        }
    }

    /// This ledger, counting from `from_s` on instead: for a ledger that
    /// started at a step that a later-starting window also holds (a run
    /// resumed to another end, [`crate::sim::checkpoint`]).
    pub(crate) fn counting_from(mut self, from_s: f64) -> Self {
        self.from_s = from_s;
        self
    }

    /// Counts the step that ended at `state` (forces evaluated at it).
    pub fn step(&mut self, model: &DriveModel, state: &DriveState, forces: &ForceGenerator) {
        let t = state.t_s;
        if t < self.from_s {
            return;
        }
        let now = Powers::of(model, state, forces);
        if let Some((t_prev, prev)) = self.last {
            let h = 0.5 * (t - t_prev);
            self.work = self.work.scaled_sum(&prev, h).scaled_sum(&now, h);
        } else {
            self.start = Some((t, balance_energy_j(model, state, forces)));
        }
        self.last = Some((t, now));
    }

    /// Marks the end of the counted steps at `state`, the last one counted
    /// (the energy is measured at the window's ends only).
    pub fn close(&mut self, model: &DriveModel, state: &DriveState, forces: &ForceGenerator) {
        if self.last.is_some_and(|(t, _)| t == state.t_s) {
            self.end = Some((state.t_s, balance_energy_j(model, state, forces)));
        }
    }

    /// The window's means; `None` before two steps were counted and closed.
    pub fn means(&self) -> Option<PowerMeans> {
        let ((t0, e0), (t1, _)) = (self.start?, self.last?);
        let (t_end, e1) = self.end?;
        if t_end != t1 {
            return None;
        }
        let duration = t1 - t0;
        (duration > 0.0).then(|| PowerMeans {
            duration_s: duration,
            mean: Powers::default().scaled_sum(&self.work, 1.0 / duration),
            energy_change_j: e1 - e0,
        })
    }
}
