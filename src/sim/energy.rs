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
