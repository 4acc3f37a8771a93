//! The static equilibrium's equations for Newton's method (`newton`): the
//! unknowns (rollers, free sprockets, tensioner arms), the residual, the
//! potential energy the line search descends and the tangent stiffness
//! K = −∂r/∂q. The solve itself, its line search and its fallbacks are in
//! `newton`.
//!
//! # The tangent stiffness K = −∂r/∂q
//!
//! - **Links**, exact: a link of length ℓ along u with force f = k(ℓ − ℓ₀)
//!   adds to its two rollers' blocks ±(k u uᵀ + (f/ℓ)(I − u uᵀ)): the axial
//!   stiffness k along u, and the geometric stiffness f/ℓ across it (turning
//!   the link by a small angle φ = δ⊥/ℓ turns its force f u by φ, a force
//!   f δ⊥/ℓ across it).
//! - **Contact**, by differences: a roller's contact force depends on its own
//!   position and its sprockets' angles only, and the links' forces do not
//!   change when every roller moves alike. Moving all rollers by h along x,
//!   then along y, gives every roller's 2×2 contact block (n K δⁿ⁻¹ along the
//!   normal and whatever the tooth's curvature adds) from two evaluations.
//!   Turning one free sprocket by h/R gives its column (the forces on the
//!   rollers it touches and its own torque's change); its row is the column's
//!   transpose (the contact is elastic at rest: K is symmetric).
//! - **Gravity and the loads at rest** are constant: no stiffness.

use rapier2d_f64::na::{DMatrix, Matrix2};

use super::hold::RimHold;
use crate::forces::{ArmAtRest, ForceGenerator, TensionerArm};
use crate::model::{DriveModel, DriveState};

/// Regularising stiffness on a free sprocket's rotation, times k R².
const ROTATION_REGULARISATION: f64 = 1e-9;
/// Difference step for the contact's stiffness, times the rest length.
const DIFFERENCE_STEP: f64 = 1e-7;

/// The unknowns beyond the rollers: the free sprockets' angles, then the
/// tensioner arms' angles (the plunger's travel follows from its arm's).
pub(super) struct Free {
    /// Index of each free sprocket in the model.
    pub(super) sprockets: Vec<usize>,
    /// Each tensioner arm, with its potential at rest.
    pub(super) arms: Vec<ArmAtRest>,
    /// Rollers held on their circular seating arcs (`hold`): their
    /// springs join the residual and the energy.
    pub(super) holds: Vec<RimHold>,
}

impl Free {
    pub(super) fn of(model: &DriveModel, forces: &ForceGenerator) -> Self {
        Self {
            sprockets: model
                .sprockets
                .iter()
                .enumerate()
                .filter(|(_, s)| !s.still_in_statics())
                .map(|(j, _)| j)
                .collect(),
            arms: forces
                .elements_of::<TensionerArm>()
                .map(TensionerArm::at_rest)
                .collect(),
            holds: Vec::new(),
        }
    }

    /// Unknowns beyond the rollers.
    pub(super) fn len(&self) -> usize {
        self.sprockets.len() + self.arms.len()
    }

    /// Length scale of unknown `k` beyond the rollers, m: a sprocket's
    /// pitch radius, an arm's reach. Its residual over this is a force,
    /// its step times this a displacement.
    pub(super) fn scale_m(&self, model: &DriveModel, k: usize) -> f64 {
        match self.sprockets.get(k) {
            Some(&s) => model.sprockets[s].pitch_radius_m,
            None => self.arms[k - self.sprockets.len()].reach_m(),
        }
    }

    /// The coordinate of unknown `k` beyond the rollers in `state`.
    pub(super) fn coordinate<'a>(&self, state: &'a mut DriveState, k: usize) -> &'a mut f64 {
        match self.sprockets.get(k) {
            Some(&s) => &mut state.theta[s],
            None => &mut state.q[self.arms[k - self.sprockets.len()].body()],
        }
    }
}

/// Residual r = (roller forces, free sprockets' torques, arms' moments) at
/// `state`, into `r`, the held rollers' springs included; returns its
/// largest entry (torques over the pitch radius, moments over the reach), N.
pub(super) fn residual(
    model: &DriveModel,
    state: &DriveState,
    forces: &mut ForceGenerator,
    free: &Free,
    r: &mut [f64],
) -> f64 {
    forces.forget_reach();
    forces.evaluate(model, state);
    let out = forces.output();
    let n = state.x.len();
    for i in 0..n {
        r[2 * i] = out.fx[i];
        r[2 * i + 1] = out.fy[i];
    }
    for (k, &s) in free.sprockets.iter().enumerate() {
        r[2 * n + k] = out.chain_torque[s] + model.sprockets[s].load_at_rest_n_m();
    }
    for hold in &free.holds {
        if let Some((f, torque)) = hold.push(model, state) {
            r[2 * hold.roller] += f[0];
            r[2 * hold.roller + 1] += f[1];
            if let Some(k) = free.sprockets.iter().position(|&s| s == hold.sprocket) {
                r[2 * n + k] += torque;
            }
        }
    }
    let mut largest: f64 = 0.0;
    for i in 0..n {
        largest = largest.max(r[2 * i].hypot(r[2 * i + 1]));
    }
    for (k, &s) in free.sprockets.iter().enumerate() {
        largest = largest.max(r[2 * n + k].abs() / model.sprockets[s].pitch_radius_m);
    }
    let m = free.sprockets.len();
    for (k, arm) in free.arms.iter().enumerate() {
        let moment = out.body_force[arm.body()];
        r[2 * n + m + k] = moment;
        largest = largest.max(moment.abs() / arm.reach_m());
    }
    if largest.is_finite() {
        largest
    } else {
        f64::INFINITY
    }
}

/// Potential energy at `state` relative to `reference` (links, contact,
/// gravity, loads at rest, the holds' springs), J, and a bound on its
/// rounding error; infinite where a held roller is off its arc. `forces`
/// evaluated at `state`.
pub(super) fn energy(
    model: &DriveModel,
    state: &DriveState,
    reference: &DriveState,
    forces: &ForceGenerator,
    free: &Free,
) -> (f64, f64) {
    // A held roller off its arc is outside the states the solve ranges
    // over (`hold`).
    if free.holds.iter().any(|h| !h.on_arc(model, state)) {
        return (f64::INFINITY, 0.0);
    }
    let n = state.x.len();
    let k = model.stiffness_n_m;
    let mut links = 0.0;
    for i in 0..n {
        let j = if i + 1 == n { 0 } else { i + 1 };
        let s = (state.x[j] - state.x[i]).hypot(state.y[j] - state.y[i]) - model.rest_length_m;
        links += 0.5 * k * s * s;
    }
    let m = model.roller_mass_kg;
    let [gx, gy] = model.gravity_m_s2;
    let mut weight = 0.0;
    let mut weight_size = 0.0;
    for i in 0..n {
        let w = m * (gx * (state.x[i] - reference.x[i]) + gy * (state.y[i] - reference.y[i]));
        weight -= w;
        weight_size += w.abs();
    }
    let mut loads = 0.0;
    for &s in &free.sprockets {
        loads -= model.sprockets[s].load_at_rest_n_m() * (state.theta[s] - reference.theta[s]);
    }
    for arm in &free.arms {
        let b = arm.body();
        loads += arm.potential_j(model.gravity_m_s2, state.q[b])
            - arm.potential_j(model.gravity_m_s2, reference.q[b]);
    }
    let contact = forces.output().contact_energy_j;
    let held: f64 = free.holds.iter().map(|h| h.energy_j(model, state)).sum();
    let total = links + contact + weight + loads + held;
    let size = links + contact.abs() + weight_size + loads.abs() + held;
    (total, 1e-12 * size)
}

/// The tangent stiffness: the block tridiagonal part, the free sprockets'
/// columns and their own block.
pub(super) struct Tangent {
    /// Diagonal block of each roller.
    pub(super) diag: Vec<Matrix2<f64>>,
    /// K between roller i and i + 1 (mod N): the block of link i.
    pub(super) upper: Vec<Matrix2<f64>>,
    /// Column of each free sprocket: its entries on the rollers (2 N).
    pub(super) columns: Vec<Vec<f64>>,
    /// The free sprockets' own block.
    pub(super) sprockets: DMatrix<f64>,
}

impl Tangent {
    pub(super) fn new(n: usize, free: usize) -> Self {
        Self {
            diag: vec![Matrix2::zeros(); n],
            upper: vec![Matrix2::zeros(); n],
            columns: vec![vec![0.0; 2 * n]; free],
            sprockets: DMatrix::zeros(free, free),
        }
    }
}

/// Assembles the tangent at `state`, whose residual is `r0`. Uses
/// `trial` and `r` as scratch.
#[allow(clippy::too_many_arguments)]
pub(super) fn assemble(
    model: &DriveModel,
    state: &DriveState,
    forces: &mut ForceGenerator,
    free: &Free,
    r0: &[f64],
    trial: &mut DriveState,
    r: &mut [f64],
    t: &mut Tangent,
) {
    let n = state.x.len();
    let k = model.stiffness_n_m;
    for d in &mut t.diag {
        *d = Matrix2::zeros();
    }
    // Links: exact.
    for i in 0..n {
        let j = if i + 1 == n { 0 } else { i + 1 };
        let (dx, dy) = (state.x[j] - state.x[i], state.y[j] - state.y[i]);
        let l = dx.hypot(dy);
        let block = if l > 0.0 {
            let (ux, uy) = (dx / l, dy / l);
            let f = k * (l - model.rest_length_m);
            let g = f / l;
            Matrix2::new(
                k * ux * ux + g * (1.0 - ux * ux),
                (k - g) * ux * uy,
                (k - g) * ux * uy,
                k * uy * uy + g * (1.0 - uy * uy),
            )
        } else {
            Matrix2::identity() * k
        };
        t.diag[i] += block;
        t.diag[j] += block;
        t.upper[i] = -block;
    }
    // Contact: every roller moved alike along x, then y.
    let h = DIFFERENCE_STEP * model.rest_length_m;
    for axis in 0..2 {
        trial.clone_from(state);
        let coordinate = if axis == 0 {
            &mut trial.x
        } else {
            &mut trial.y
        };
        for c in coordinate.iter_mut() {
            *c += h;
        }
        residual(model, trial, forces, free, r);
        for i in 0..n {
            t.diag[i][(0, axis)] -= (r[2 * i] - r0[2 * i]) / h;
            t.diag[i][(1, axis)] -= (r[2 * i + 1] - r0[2 * i + 1]) / h;
        }
    }
    // Each free sprocket and arm turned.
    let m = free.len();
    for c in 0..m {
        let radius = free.scale_m(model, c);
        let h_theta = h / radius;
        trial.clone_from(state);
        *free.coordinate(trial, c) += h_theta;
        residual(model, trial, forces, free, r);
        for (e, (a, b)) in t.columns[c].iter_mut().zip(r.iter().zip(r0)).take(2 * n) {
            *e = -(a - b) / h_theta;
        }
        for row in 0..m {
            t.sprockets[(row, c)] = -(r[2 * n + row] - r0[2 * n + row]) / h_theta;
        }
        t.sprockets[(c, c)] += ROTATION_REGULARISATION * k * radius * radius;
    }
    // Symmetric: the sprockets' own block is averaged with its transpose.
    let sym = 0.5 * (&t.sprockets + t.sprockets.transpose());
    t.sprockets = sym;
}
