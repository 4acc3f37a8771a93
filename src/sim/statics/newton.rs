//! Newton's method on the static equilibrium equations at a fixed rest
//! length (docs/model.md, “Pretension and static equilibrium”).
//!
//! The unknowns are the rollers' positions and the free sprockets' angles
//! (the driver and any sprocket without inertia are held); the equations are
//! the rollers' force balances (links, contact, gravity) and the free
//! sprockets' torque balances (chain plus load at rest). The drive is
//! conservative at rest, so the tangent stiffness is symmetric and each step
//! is taken along the Newton direction with a line search on the potential
//! energy (and on the residual where the energy's rounding hides the
//! decrease), a Levenberg–Marquardt shift μ where the tangent is not positive
//! definite. Where Newton stalls from a start whose free strands are
//! compressed (a chain laid longer than its path), it settles the drive
//! from taut (`taut`: the links' rest length lengthened from short); where
//! it stalls with a roller on a circular seating arc's rim, it solves again
//! with that roller held on its arc (`hold`); where it still stalls, the
//! dynamic relaxation takes over and Newton is tried again. What this module does not do: choose the rest length (the
//! pretension iteration does).
//!
//! # The tangent stiffness
//!
//! Assembled in `tangent` (the unknowns, the residual, the potential and
//! K = −∂r/∂q, exact for the links and by differences for the contact).
//!
//! # The linear solve, O(N)
//!
//! The chain is a closed loop: K is block tridiagonal in the rollers (2×2
//! blocks) with two corner blocks from the closing link, bordered by a row and
//! a column per free sprocket. Roller 0 joins the border, which leaves rollers
//! 1 … N−1 block tridiagonal: a block LU (Thomas) sweep solves them for the
//! right-hand side and each border column, and the border's Schur complement
//! (2 + free sprockets unknowns) is solved dense with `nalgebra`.
//!
//! # The free sprockets' rotation
//!
//! An unloaded free sprocket whose teeth barely touch the chain (the real
//! profile's seating clearance) turns at almost no stiffness. Its diagonal
//! gets a regularising stiffness 10⁻⁹ k R² (k the link stiffness, R its pitch
//! radius) at all times: it changes nothing where the chain holds the sprocket
//! (the contact's stiffness times R² is orders above) and keeps a sprocket
//! that nothing holds where it is instead of sending it anywhere.

use rapier2d_f64::na::{DMatrix, DVector, Matrix2, Vector2};

use super::error::EquilibriumError;
use super::feasibility::rim_roller_except;
use super::hold::RimHold;
use super::relax::{RelaxSettings, relax_until};
use super::tangent::{Free, Tangent, assemble, energy, residual};
use crate::forces::{ForceGenerator, TensionerArm};
use crate::model::{DriveModel, DriveState};

/// How a Newton solve ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct NewtonEnd {
    /// Largest force out of balance at the end (a sprocket's torque counted
    /// as torque / pitch radius), N.
    pub(crate) residual_n: f64,
    /// Newton iterations taken.
    pub(crate) iterations: usize,
    /// Whether the residual reached the tolerance.
    pub(crate) converged: bool,
    /// The residual at the start, N.
    pub(crate) start_residual_n: f64,
    /// Whether the last step still needed the stabilising shift μ (the
    /// tangent not positive definite there: a saddle or a ridge, not a
    /// valley, near the point reached).
    pub(crate) shifted: bool,
}

/// First bound on a step's largest roller (or pitch-circle) displacement,
/// times the rest length: the trust radius, which grows fourfold after each
/// full step that it cut and shrinks to what the line search accepted.
const FIRST_RADIUS: f64 = 0.25;
/// Largest trust radius, times the rest length.
const MAX_RADIUS: f64 = 1e4;
/// Line search halvings before the shift μ grows.
const HALVINGS: usize = 10;

/// Whether the Newton solve handles this drive: rollers, sprockets and
/// tensioner arms (any other further body or scalar state is left to the
/// relaxation), at least one sprocket held (a driver, a governed driver, or
/// a sprocket the co-simulation holds for the solve:
/// [`super::Simulation::new_holding`]).
pub(crate) fn applies(model: &DriveModel, state: &DriveState, forces: &ForceGenerator) -> bool {
    // Without a held sprocket (a co-simulation whose motor is a body not
    // held for the solve) every sprocket turns freely and a load has no
    // reaction: no rest state to solve for; the relaxation handles it.
    // The further bodies must be the arms, one each, and the scalar states
    // their chambers (held at their supply pressure at rest).
    let arms = forces.elements_of::<TensionerArm>().count();
    let arm_bodies = model.bodies.len() == arms
        && forces
            .elements_of::<TensionerArm>()
            .map(|a| a.at_rest().body())
            .eq(0..arms);
    arm_bodies
        && model.scalars.len() <= arms
        && state.x.len() >= 3
        && model.sprockets.iter().any(|s| s.still_in_statics())
}

/// Block LU of the tridiagonal part (rollers 1 … N−1) with the shift μ,
/// applied to right-hand sides.
struct Banded {
    /// Inverse of each pivot block (index 0 is roller 1).
    inv: Vec<Matrix2<f64>>,
}

impl Banded {
    /// Factors; `None` when a pivot block is singular.
    fn factor(t: &Tangent, mu: f64) -> Option<Self> {
        let n = t.diag.len();
        let mut inv = Vec::with_capacity(n - 1);
        let shift = Matrix2::identity() * mu;
        let mut previous: Option<Matrix2<f64>> = None;
        for i in 1..n {
            let mut pivot = t.diag[i] + shift;
            if let Some(g) = previous {
                // L_i G_{i-1} U_{i-1}, L_i = U_{i-1}ᵀ.
                let u = t.upper[i - 1];
                pivot -= u.transpose() * g * u;
            }
            // Positive definite pivots only: the shifted tangent must be, for
            // the step to descend the energy (the Schur complement's Cholesky
            // checks the rest).
            let det = pivot[(0, 0)] * pivot[(1, 1)] - pivot[(0, 1)] * pivot[(1, 0)];
            if !(pivot[(0, 0)] > 0.0 && det > 0.0) {
                return None;
            }
            let g = pivot.try_inverse()?;
            if !g.iter().all(|v| v.is_finite()) {
                return None;
            }
            inv.push(g);
            previous = Some(g);
        }
        Some(Self { inv })
    }

    /// Solves in place: `b` holds rollers 1 … N−1 (2 entries each).
    fn solve(&self, t: &Tangent, b: &mut [f64]) {
        let n = self.inv.len();
        // Forward: y_i = b_i − L_i G_{i−1} y_{i−1}.
        for i in 1..n {
            let prev = Vector2::new(b[2 * (i - 1)], b[2 * (i - 1) + 1]);
            let l = t.upper[i].transpose(); // K(roller i+1, roller i)
            let y = l * (self.inv[i - 1] * prev);
            b[2 * i] -= y[0];
            b[2 * i + 1] -= y[1];
        }
        // Back: x_i = G_i (y_i − U_i x_{i+1}).
        let mut next: Option<Vector2<f64>> = None;
        for i in (0..n).rev() {
            let mut y = Vector2::new(b[2 * i], b[2 * i + 1]);
            if let Some(x) = next {
                y -= t.upper[i + 1] * x;
            }
            let x = self.inv[i] * y;
            b[2 * i] = x[0];
            b[2 * i + 1] = x[1];
            next = Some(x);
        }
    }
}

/// Solves (K + μ M) Δ = r for the step Δ (M: I on the rollers, R² on the
/// sprockets); `None` when the shifted tangent is singular.
fn step(t: &Tangent, free: &Free, model: &DriveModel, mu: f64, r: &[f64]) -> Option<Vec<f64>> {
    let n = t.diag.len();
    let m = free.len();
    let banded = Banded::factor(t, mu)?;
    let inner = 2 * (n - 1);
    // Border columns over rollers 1 … N−1: roller 0's two, then the sprockets'.
    let border = 2 + m;
    let mut columns: Vec<Vec<f64>> = Vec::with_capacity(border + 1);
    for c in 0..2 {
        let mut col = vec![0.0; inner];
        // K(roller 1, roller 0) = upper[0]ᵀ; K(roller N−1, roller 0) = upper[N−1].
        let a = t.upper[0].transpose();
        col[0] += a[(0, c)];
        col[1] += a[(1, c)];
        let b = t.upper[n - 1];
        col[inner - 2] += b[(0, c)];
        col[inner - 1] += b[(1, c)];
        columns.push(col);
    }
    for col in &t.columns {
        columns.push(col[2..].to_vec());
    }
    let solved: Vec<Vec<f64>> = columns
        .iter()
        .map(|c| {
            let mut x = c.clone();
            banded.solve(t, &mut x);
            x
        })
        .collect();
    let mut x_r = r[2..2 * n].to_vec();
    banded.solve(t, &mut x_r);
    // Border block E and its Schur complement S = E − Bᵀ A⁻¹ B.
    let mut e = DMatrix::zeros(border, border);
    let d0 = t.diag[0] + Matrix2::identity() * mu;
    for a in 0..2 {
        for b in 0..2 {
            e[(a, b)] = d0[(a, b)];
        }
    }
    for (c, col) in t.columns.iter().enumerate() {
        for a in 0..2 {
            e[(a, 2 + c)] = col[a];
            e[(2 + c, a)] = col[a];
        }
    }
    for a in 0..m {
        for b in 0..m {
            e[(2 + a, 2 + b)] = t.sprockets[(a, b)];
        }
        let radius = free.scale_m(model, a);
        e[(2 + a, 2 + a)] += mu * radius * radius;
    }
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let mut s = e;
    let mut rhs = DVector::zeros(border);
    rhs[0] = r[0];
    rhs[1] = r[1];
    for a in 0..m {
        rhs[2 + a] = r[2 * n + a];
    }
    for a in 0..border {
        for b in 0..border {
            s[(a, b)] -= dot(&columns[a], &solved[b]);
        }
        rhs[a] -= dot(&columns[a], &x_r);
    }
    let s = 0.5 * (&s + s.transpose());
    let y = s.cholesky()?.solve(&rhs);
    if !y.iter().all(|v| v.is_finite()) {
        return None;
    }
    let mut delta = vec![0.0; 2 * n + m];
    delta[0] = y[0];
    delta[1] = y[1];
    for (i, v) in x_r.iter().enumerate() {
        let mut d = *v;
        for b in 0..border {
            d -= solved[b][i] * y[b];
        }
        delta[2 + i] = d;
    }
    for a in 0..m {
        delta[2 * n + a] = y[2 + a];
    }
    Some(delta)
}

/// `base` moved by α Δ into `trial`.
fn moved(base: &DriveState, free: &Free, delta: &[f64], alpha: f64, trial: &mut DriveState) {
    trial.clone_from(base);
    let n = base.x.len();
    for i in 0..n {
        trial.x[i] += alpha * delta[2 * i];
        trial.y[i] += alpha * delta[2 * i + 1];
    }
    for k in 0..free.len() {
        *free.coordinate(trial, k) += alpha * delta[2 * n + k];
    }
}

/// Newton's method with a line search on the equilibrium at the model's rest
/// length, from `state`, until every force is within `tolerance_n` or
/// `max_iterations` Newton steps. The state keeps the best point reached
/// (its velocities zeroed); `forces` are left evaluated at it.
pub(crate) fn solve(
    model: &DriveModel,
    state: &mut DriveState,
    forces: &mut ForceGenerator,
    tolerance_n: f64,
    max_iterations: usize,
) -> NewtonEnd {
    solve_held(model, state, forces, tolerance_n, max_iterations, &[])
}

/// [`solve`] with `holds` keeping rollers on their seating arcs (`hold`):
/// the residual and the energy include their springs; the forces left
/// evaluated at the end do not.
fn solve_held(
    model: &DriveModel,
    state: &mut DriveState,
    forces: &mut ForceGenerator,
    tolerance_n: f64,
    max_iterations: usize,
    holds: &[RimHold],
) -> NewtonEnd {
    let free = Free {
        holds: holds.to_vec(),
        ..Free::of(model, forces)
    };
    let n = state.x.len();
    let m = free.len();
    state.vx.fill(0.0);
    state.vy.fill(0.0);
    state.omega.fill(0.0);
    state.u.fill(0.0);
    // Arms are solved at rest as the relaxation sees them: a hydraulic
    // chamber at its supply pressure, no ratchet.
    let arms = !free.arms.is_empty();
    if arms {
        forces.begin_equilibrium();
    }
    forces.reset_memory();
    let reference = state.clone();
    let mut trial = state.clone();
    let mut r0 = vec![0.0; 2 * n + m];
    let mut r = vec![0.0; 2 * n + m];
    let mut tangent = Tangent::new(n, m);
    let mut now = residual(model, state, forces, &free, &mut r0);
    let start_residual_n = now;
    let (mut u0, _) = energy(model, state, &reference, forces, &free);
    let k = model.stiffness_n_m;
    let mu_min = 1e-8 * k;
    let mut mu = 0.0;
    let mut radius = FIRST_RADIUS * model.rest_length_m;
    let mut iterations = 0;
    while now > tolerance_n && iterations < max_iterations {
        iterations += 1;
        assemble(
            model,
            state,
            forces,
            &free,
            &r0,
            &mut trial,
            &mut r,
            &mut tangent,
        );
        let mut accepted = false;
        while !accepted && mu <= 1e3 * k {
            let Some(mut delta) = step(&tangent, &free, model, mu, &r0) else {
                mu = (10.0 * mu).max(mu_min);
                continue;
            };
            // Bound the step (a trust region on displacement).
            let mut largest: f64 = 0.0;
            for i in 0..n {
                largest = largest.max(delta[2 * i].hypot(delta[2 * i + 1]));
            }
            for a in 0..m {
                largest = largest.max(delta[2 * n + a].abs() * free.scale_m(model, a));
            }
            if !largest.is_finite() {
                mu = (10.0 * mu).max(mu_min);
                continue;
            }
            let cut = largest > radius;
            if cut {
                let scale = radius / largest;
                delta.iter_mut().for_each(|d| *d *= scale);
            }
            // The energy's slope along Δ is −Δ·r: a descent direction has Δ·r > 0.
            let slope: f64 = delta.iter().zip(&r0).map(|(d, f)| d * f).sum();
            if slope > 0.0 {
                let mut alpha = 1.0;
                for _ in 0..HALVINGS {
                    moved(state, &free, &delta, alpha, &mut trial);
                    let trial_residual = residual(model, &trial, forces, &free, &mut r);
                    let (u, rounding) = energy(model, &trial, &reference, forces, &free);
                    let descends = u <= u0 - 1e-4 * alpha * slope;
                    let flat = u <= u0 + rounding && trial_residual < now;
                    if trial_residual.is_finite() && (descends || flat) {
                        std::mem::swap(state, &mut trial);
                        std::mem::swap(&mut r0, &mut r);
                        now = trial_residual;
                        u0 = u;
                        accepted = true;
                        break;
                    }
                    alpha *= 0.5;
                }
                if accepted {
                    if alpha == 1.0 {
                        mu = if mu <= mu_min { 0.0 } else { 0.1 * mu };
                        if cut {
                            radius = (4.0 * radius).min(MAX_RADIUS * model.rest_length_m);
                        }
                    } else {
                        // A cut step: the quadratic model was poor this far
                        // out; shift towards steepest descent as well.
                        radius = alpha * largest.min(radius);
                        mu = (10.0 * mu).max(mu_min);
                    }
                    break;
                }
            }
            mu = (10.0 * mu).max(mu_min);
        }
        if !accepted {
            break;
        }
    }
    // Leave the forces evaluated at the state reached.
    if arms {
        forces.end_equilibrium();
    }
    forces.reset_memory();
    forces.evaluate(model, state);
    NewtonEnd {
        residual_n: now,
        iterations,
        converged: now <= tolerance_n,
        start_residual_n,
        shifted: mu > 0.0,
    }
}

/// Newton steps per solve (per round of [`solve_in_rounds`]).
const MAX_ITERATIONS: usize = 40;

/// Most rounds of [`solve_in_rounds`].
const MAX_ROUNDS: usize = 8;

/// Newton ([`solve`]) in rounds of [`MAX_ITERATIONS`] steps, each from
/// where the last one stopped, for as long as each round cuts the force
/// residual tenfold. A chain going slack (a worn chain on fixed centres, a
/// drive turned to where it takes no torque) sags further with each
/// change: Newton descends steadily but needs more than one round's steps,
/// and the relaxation it would otherwise fall back to takes far longer to
/// the same rest state. A roller on a circular seating arc's rim (no
/// smooth rest state) or a round that ends with the stabilising shift on
/// (a tangent that is not positive definite: Newton may be heading for a
/// saddle, which the relaxation would roll off; found on a worn timing
/// drive's slack arm, where going on reached another rest state than the
/// relaxation's) ends it after that round, a stall after the first round
/// that does not gain. Returns the last round's end, with the first
/// round's start residual.
fn solve_in_rounds(
    model: &DriveModel,
    state: &mut DriveState,
    forces: &mut ForceGenerator,
    tolerance_n: f64,
    holds: &[RimHold],
) -> NewtonEnd {
    let mut end = solve_held(model, state, forces, tolerance_n, MAX_ITERATIONS, holds);
    let start_residual_n = end.start_residual_n;
    let held: Vec<usize> = holds.iter().map(|h| h.roller).collect();
    for _ in 1..MAX_ROUNDS {
        let steady = end.residual_n < 0.1 * start_residual_n;
        if end.converged
            || end.iterations < MAX_ITERATIONS
            || !steady
            || end.shifted
            || rim_roller_except(model, state, forces, &held).is_some()
        {
            break;
        }
        let next = solve_held(model, state, forces, tolerance_n, MAX_ITERATIONS, holds);
        let gained = next.residual_n < 0.1 * end.residual_n;
        end = NewtonEnd {
            start_residual_n,
            ..next
        };
        if !gained {
            break;
        }
    }
    end
}
/// Most rollers held on their seating arcs ([`settle_on_rims`]).
const MAX_HOLDS: usize = 4;

/// Where Newton stalled (at `state`) with a roller on a circular seating
/// arc's rim ([`rim_roller_except`]), Newton again with that roller held on
/// its arc (`hold`), and with each further rim roller the state reached
/// names, up to [`MAX_HOLDS`]. With `from`, the held solve starts there
/// instead (the rest state of the rest length before: a continuation), its
/// rim rollers held where they already lie on their arcs. True when the
/// held solve's residual (the springs' included) is within `rest_force_n`
/// and every held roller lies on its arc: `state` is then that rest state
/// and `forces` are evaluated at it without the springs (the held rollers'
/// outward pulls are their residual). Otherwise `state` is left where
/// Newton stalled.
fn settle_on_rims(
    model: &DriveModel,
    state: &mut DriveState,
    forces: &mut ForceGenerator,
    (aim_n, rest_force_n): (f64, f64),
    from: Option<&DriveState>,
) -> bool {
    let stalled = state.clone();
    if let Some(from) = from {
        state.clone_from(from);
        forces.reset_memory();
        forces.evaluate(model, state);
    }
    let mut holds: Vec<RimHold> = Vec::new();
    while holds.len() < MAX_HOLDS {
        let held: Vec<usize> = holds.iter().map(|h| h.roller).collect();
        let Some(hold) = rim_roller_except(model, state, forces, &held)
            .and_then(|rim| RimHold::new(model, &rim))
        else {
            break;
        };
        if from.is_none() || !hold.on_arc(model, state) {
            hold.place(model, state);
        }
        holds.push(hold);
        let end = solve_in_rounds(model, state, forces, aim_n, &holds);
        if end.residual_n <= rest_force_n && holds.iter().all(|h| h.on_arc(model, state)) {
            return true;
        }
    }
    if !holds.is_empty() || from.is_some() {
        state.clone_from(&stalled);
        forces.reset_memory();
        forces.evaluate(model, state);
    }
    false
}

/// Share of the relaxation's time spent where Newton stalls on a roller at a
/// circular seating arc's rim.
const RIM_RELAX_SHARE: f64 = 0.1;

/// Brings the drive at its current rest length to equilibrium within
/// `rest_force_n`: Newton from `state` (aiming at `newton_force_n`, at most
/// `rest_force_n`); where Newton stalls, the dynamic relaxation
/// ([`relax_until`]) from the point it reached, then Newton again from the
/// relaxed state; first, where it stalls with a roller on a circular
/// seating arc's rim, Newton with that roller held on its arc
/// ([`settle_on_rims`]), which returns 0 where it converges. Where Newton
/// stalls with a roller on a circular seating
/// arc's rim ([`super::feasibility::rim_roller`]) while `searching` for the
/// rest length, the relaxation takes a tenth of its time: it cannot come to
/// rest there, and the search needs only its tension. Returns the residual roller speed of
/// the relaxation (0 when Newton alone converged).
pub(crate) fn settle(
    model: &DriveModel,
    state: &mut DriveState,
    forces: &mut ForceGenerator,
    settings: &RelaxSettings,
    rest_force_n: f64,
    newton_force_n: f64,
    searching: bool,
) -> Result<f64, EquilibriumError> {
    let forces_n = (rest_force_n, newton_force_n);
    settle_from(model, state, forces, settings, forces_n, searching, None)
}

/// [`settle`] with a second start for Newton where it stalls from `state`,
/// tried before the relaxation: `guess`, a continuation's prediction of the
/// rest state (`sim::worn`'s lengthening extrapolates the two rest states
/// before). `(rest_force_n, newton_force_n)` as for [`settle`].
pub(crate) fn settle_from(
    model: &DriveModel,
    state: &mut DriveState,
    forces: &mut ForceGenerator,
    settings: &RelaxSettings,
    (rest_force_n, newton_force_n): (f64, f64),
    searching: bool,
    guess: Option<&DriveState>,
) -> Result<f64, EquilibriumError> {
    let aim = newton_force_n.min(rest_force_n);
    if !applies(model, state, forces) {
        return relax_until(model, state, forces, settings, Some(rest_force_n));
    }
    let start = state.clone();
    let first = solve_in_rounds(model, state, forces, aim, &[]);
    if first.residual_n <= rest_force_n {
        return Ok(0.0);
    }
    if let Some(guess) = guess {
        let stalled = state.clone();
        state.clone_from(guess);
        if solve(model, state, forces, aim, MAX_ITERATIONS).residual_n <= rest_force_n {
            return Ok(0.0);
        }
        state.clone_from(&stalled);
        forces.reset_memory();
        forces.evaluate(model, state);
    }
    // A start whose free strands are compressed (a chain laid longer than
    // its path, or links lengthened at once): the rest state from taut
    // (`taut`), where Newton from the start stalled.
    if !(first.residual_n <= rest_force_n) {
        let stalled = state.clone();
        state.clone_from(&start);
        if let Some(laid_n) = super::taut::laid_compression(model, state, forces)
            && super::taut::settle_from_taut(
                model,
                state,
                forces,
                laid_n,
                aim,
                |m, s, f, tol, most| solve(m, s, f, tol, most).converged,
            )
            && solve(model, state, forces, aim, MAX_ITERATIONS).residual_n <= rest_force_n
        {
            return Ok(0.0);
        }
        state.clone_from(&stalled);
        forces.reset_memory();
        forces.evaluate(model, state);
    }
    // A roller on a circular seating arc's rim: the rest state with it held
    // on its arc (`hold`), whose residual is the outward pull no contact
    // force of the profile gives.
    if settle_on_rims(model, state, forces, (aim, rest_force_n), None) {
        return Ok(0.0);
    }
    // The same from the state Newton started from (the rest state of the
    // rest length before, its rim rollers already on their arcs), where
    // the stall has moved other rollers onto their arcs' rims.
    if settle_on_rims(model, state, forces, (aim, rest_force_n), Some(&start)) {
        return Ok(0.0);
    }
    // A stall further from equilibrium than the start, or with a link
    // stretched beyond the relaxation's blow-up bound (Newton's energy
    // descent may trade the chain's weight for stretch far from the rest
    // state: found on a 2000-roller conveyor hanging 13 m), is no start for
    // the relaxation: it starts where Newton did.
    if !(first.residual_n <= first.start_residual_n)
        || !(forces.output().max_stretch_m <= settings.max_stretch_m)
    {
        state.clone_from(&start);
        forces.reset_memory();
        forces.evaluate(model, state);
    }
    // A roller on a circular seating arc's rim stalls Newton and keeps the
    // relaxation from ever coming to rest (no smooth rest state there):
    // while the rest length is searched for, the relaxation then only moves
    // the drive on, over a share of its time.
    let settings = if searching && super::feasibility::rim_roller(model, state, forces).is_some() {
        RelaxSettings {
            max_time_s: RIM_RELAX_SHARE * settings.max_time_s,
            ..*settings
        }
    } else {
        *settings
    };
    let speed = relax_until(model, state, forces, &settings, Some(rest_force_n))?;
    let again = solve(model, state, forces, aim, MAX_ITERATIONS);
    if again.residual_n <= rest_force_n {
        return Ok(0.0);
    }
    Ok(speed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::forces::ContactLawParams;
    use crate::scene::Scene;

    fn paper() -> (DriveModel, DriveState, ForceGenerator) {
        let scene = Scene::l60mc();
        let (mut model, state, _) = DriveModel::build(&scene).expect("lays out");
        let forces = ForceGenerator::new(
            ContactLawParams::new(&scene.contact),
            &model,
            scene.chain.rollers,
        );
        // Links stretched to the pretension, as the pretension iteration's first guess.
        model.rest_length_m -= scene.chain.pretension_n / model.stiffness_n_m;
        (model, state, forces)
    }

    /// Newton brings the paper's drive to rest within 10⁻⁸ of its 21 kN
    /// pretension in a few steps, from the laid-out chain.
    #[test]
    fn newton_settles_the_paper_drive() {
        let (model, mut state, mut forces) = paper();
        let end = solve(&model, &mut state, &mut forces, 21_000.0 * 1e-8, 40);
        assert!(end.converged, "{end:?}");
        assert!(end.iterations <= 25, "{end:?}");
    }

    /// The tangent against central differences of the residual at a settled
    /// state: the free sprocket's column (∂F/∂θ, assembled from a turned
    /// sprocket) equals its row (−∂τ/∂q, differences of the torque when one
    /// roller it touches moves), the symmetry the border solve assumes; and a
    /// link's block against moving one free-strand roller. Tolerance 1 % of
    /// the entry (difference steps 10⁻⁷ P on a contact of exponent 1.5).
    #[test]
    #[allow(clippy::needless_range_loop)]
    fn tangent_is_symmetric_and_matches_differences() {
        let (model, mut state, mut forces) = paper();
        let end = solve(&model, &mut state, &mut forces, 21_000.0 * 1e-6, 40);
        assert!(end.converged, "{end:?}");
        let free = Free::of(&model, &forces);
        assert!(!free.sprockets.is_empty());
        let n = state.x.len();
        let m = free.sprockets.len();
        let mut r0 = vec![0.0; 2 * n + m];
        let mut r = vec![0.0; 2 * n + m];
        let mut trial = state.clone();
        let mut t = Tangent::new(n, m);
        residual(&model, &state, &mut forces, &free, &mut r0);
        assemble(
            &model,
            &state,
            &mut forces,
            &free,
            &r0,
            &mut trial,
            &mut r,
            &mut t,
        );
        let h = 1e-7 * model.rest_length_m;
        // Rows: −∂τ/∂x_i by central differences for the rollers the sprocket pushes hardest.
        let column = &t.columns[0];
        let mut checked = 0;
        for i in 0..n {
            for axis in 0..2 {
                let entry = column[2 * i + axis];
                if entry.abs()
                    < 1e-3 * model.stiffness_n_m * model.sprockets[free.sprockets[0]].pitch_radius_m
                {
                    continue;
                }
                let mut torque = [0.0; 2];
                for (side, sign) in [(0, 1.0), (1, -1.0)] {
                    trial.clone_from(&state);
                    let c = if axis == 0 {
                        &mut trial.x
                    } else {
                        &mut trial.y
                    };
                    c[i] += sign * h;
                    residual(&model, &trial, &mut forces, &free, &mut r);
                    torque[side] = r[2 * n];
                }
                let row = -(torque[0] - torque[1]) / (2.0 * h);
                assert!(
                    (row - entry).abs() <= 0.01 * entry.abs(),
                    "roller {i} axis {axis}: row {row:e}, column {entry:e}"
                );
                checked += 1;
            }
        }
        assert!(checked >= 4, "only {checked} entries checked");
        // A roller in the middle of strand 1 (free): its diagonal block
        // against central differences of its own force.
        let strand = &model.path.strands[0];
        let [ax, ay] = strand.start_m;
        let [bx, by] = strand.end_m;
        let (mx, my) = (0.5 * (ax + bx), 0.5 * (ay + by));
        let i = (0..n)
            .min_by(|&a, &b| {
                let da = (state.x[a] - mx).hypot(state.y[a] - my);
                let db = (state.x[b] - mx).hypot(state.y[b] - my);
                da.total_cmp(&db)
            })
            .expect("rollers");
        for axis in 0..2 {
            let mut f = [[0.0; 2]; 2];
            for (side, sign) in [(0, 1.0), (1, -1.0)] {
                trial.clone_from(&state);
                let c = if axis == 0 {
                    &mut trial.x
                } else {
                    &mut trial.y
                };
                c[i] += sign * h;
                residual(&model, &trial, &mut forces, &free, &mut r);
                f[side] = [r[2 * i], r[2 * i + 1]];
            }
            for row in 0..2 {
                let expected = -(f[0][row] - f[1][row]) / (2.0 * h);
                let got = t.diag[i][(row, axis)];
                // The transverse entry is the geometric stiffness 2 T/ℓ, some
                // 10⁻³ of the axial one: a relative tolerance on each entry.
                assert!(
                    (got - expected).abs() <= 1e-3 * expected.abs() + 1e-7 * model.stiffness_n_m,
                    "roller {i} block ({row}, {axis}): {got:e} against {expected:e}"
                );
            }
        }
    }
}
