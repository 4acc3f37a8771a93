//! A roller held on the edge of its circular seating arc while Newton
//! solves (`newton`): the rest state of a drive that the circular profile
//! cannot hold (`feasibility::rim_roller`).
//!
//! The circular profile pushes a roller only while its centre lies on the
//! inner side of its seating circle's diameter across the gap (e · u ≤ 0,
//! e the offset from the seating centre, u the gap's radial direction):
//! there the force is K δⁿ along −e/|e|, beyond it nothing. A roller pulled
//! outward (F · u > 0 for the pull F of its links and its weight) rides on
//! that diameter's end, the rim, where the force jumps: its contact pushes
//! along the pitch circle only and nothing of the profile balances the
//! outward pull. No state is at rest there, and the potential energy has
//! no minimum: it falls as the roller leaves the gap.
//!
//! What Newton solves for instead is the minimum of the energy over the
//! states that keep the roller on its seating arc: e · u ≤ −ε, ε a
//! thousandth of the clearance ΔR inside the edge, where the contact's
//! force is smooth. The bound is a one-sided spring of stiffness 10 k
//! (k the link stiffness) on e · u + ε, so the roller stays on the arc
//! within F · u / (10 k), nanometres, of the bound (stiffer, its force's
//! rounding at metres from the origin would exceed Newton's tolerance). At that state every
//! other roller and every free sprocket is in balance (to Newton's
//! tolerance), the held roller's contact balances its pull along the pitch
//! circle (K δⁿ = F_along at the depth δ it takes), and the force out of
//! balance is the spring's: the held roller's outward pull F · u, which no
//! contact force of the profile can give. That is the residual the rest
//! state reports, with the roller named.

use super::feasibility::RimRoller;
use crate::geometry::ToothProfile;
use crate::model::{DriveModel, DriveState};

/// Where the roller is held, inside the seating arc's edge, times the
/// clearance ΔR.
const INSET: f64 = 1e-3;
/// The hold's stiffness, times the link stiffness.
const STIFFNESS: f64 = 10.0;

/// One roller held on its seating arc (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct RimHold {
    /// The roller's index.
    pub(super) roller: usize,
    /// The sprocket whose gap holds it.
    pub(super) sprocket: usize,
    /// The gap's radial direction, sprocket frame.
    direction: [f64; 2],
    /// Distance of the gap's seating centre from the sprocket's centre, m.
    seat_m: f64,
    /// How far inside the edge the roller is held, m.
    inset_m: f64,
    /// The one-sided spring's stiffness, N/m.
    stiffness_n_m: f64,
}

impl RimHold {
    /// A hold on `rim`'s roller in its gap; `None` unless the sprocket has
    /// the circular profile.
    pub(super) fn new(model: &DriveModel, rim: &RimRoller) -> Option<Self> {
        let ToothProfile::Circular(c) = &model.sprockets.get(rim.sprocket)?.profile else {
            return None;
        };
        let seat = c.seat_center(rim.gap);
        let seat_m = seat[0].hypot(seat[1]);
        if !(seat_m > 0.0) {
            return None;
        }
        Some(Self {
            roller: rim.roller,
            sprocket: rim.sprocket,
            direction: [seat[0] / seat_m, seat[1] / seat_m],
            seat_m,
            inset_m: INSET * c.clearance_m,
            stiffness_n_m: STIFFNESS * model.stiffness_n_m,
        })
    }

    /// How far the roller's centre lies beyond the bound e · u = −ε
    /// (> 0: the spring pushes it back), with the gap's radial direction u
    /// (world frame) and the centre's offset from the sprocket's centre
    /// along the pitch circle, u × r, m.
    fn beyond(&self, model: &DriveModel, state: &DriveState) -> (f64, [f64; 2], f64) {
        let centre = model.sprockets[self.sprocket].center_m;
        let (sin, cos) = state.theta[self.sprocket].sin_cos();
        let [a, b] = self.direction;
        let u = [cos * a - sin * b, sin * a + cos * b];
        let r = [
            state.x[self.roller] - centre[0],
            state.y[self.roller] - centre[1],
        ];
        let radial = r[0] * u[0] + r[1] * u[1];
        let along = u[0] * r[1] - u[1] * r[0];
        (radial - self.seat_m + self.inset_m, u, along)
    }

    /// The spring's force on the roller (world frame, N) and its torque on
    /// the sprocket (N·m, the derivative of [`Self::energy_j`] in the
    /// sprocket's angle, negated); `None` where the roller is inside the
    /// bound.
    pub(super) fn push(&self, model: &DriveModel, state: &DriveState) -> Option<([f64; 2], f64)> {
        let (beyond, u, along) = self.beyond(model, state);
        if !(beyond > 0.0) {
            return None;
        }
        let f = self.stiffness_n_m * beyond;
        Some(([-f * u[0], -f * u[1]], -f * along))
    }

    /// The spring's potential energy, J.
    pub(super) fn energy_j(&self, model: &DriveModel, state: &DriveState) -> f64 {
        let (beyond, _, _) = self.beyond(model, state);
        if beyond > 0.0 {
            0.5 * self.stiffness_n_m * beyond * beyond
        } else {
            0.0
        }
    }

    /// Puts the roller on its seating arc, twice the hold's inset inside
    /// the edge, at its distance from the seating centre (at least a
    /// thousandth of the clearance beyond ΔR, at most 2 ΔR), on the side of
    /// the gap it is on: a start inside the held states. Beyond the edge the
    /// energy is lower by the seat's whole contact energy, so Newton's
    /// descent could not bring a roller there back onto its arc.
    pub(super) fn place(&self, model: &DriveModel, state: &mut DriveState) {
        let ToothProfile::Circular(c) = &model.sprockets[self.sprocket].profile else {
            return;
        };
        let (_, u, _) = self.beyond(model, state);
        let t = [-u[1], u[0]];
        let centre = model.sprockets[self.sprocket].center_m;
        let seat = [
            centre[0] + self.seat_m * u[0],
            centre[1] + self.seat_m * u[1],
        ];
        let e = [
            state.x[self.roller] - seat[0],
            state.y[self.roller] - seat[1],
        ];
        let side = if e[0] * t[0] + e[1] * t[1] >= 0.0 {
            1.0
        } else {
            -1.0
        };
        let clearance = c.clearance_m;
        let len = e[0]
            .hypot(e[1])
            .clamp((1.0 + INSET) * clearance, 2.0 * clearance);
        let across = -2.0 * self.inset_m;
        let along = side * (len * len - across * across).max(0.0).sqrt();
        state.x[self.roller] = seat[0] + across * u[0] + along * t[0];
        state.y[self.roller] = seat[1] + across * u[1] + along * t[1];
    }

    /// Whether the roller's centre lies on the held side of the seating
    /// circle's diameter across the gap (e · u < 0), where the profile
    /// pushes it.
    pub(super) fn on_arc(&self, model: &DriveModel, state: &DriveState) -> bool {
        let (beyond, _, _) = self.beyond(model, state);
        beyond < self.inset_m
    }
}

#[cfg(test)]
mod tests {
    use crate::geometry::ToothProfile;
    use crate::scene::Scene;
    use crate::sim::Simulation;

    /// The 6.35 m sagging conveyor (circular profile, −100 N·m on the
    /// tail): the sagging tight strand leaves the tail at an angle below
    /// the horizontal, and its first roller is pulled outward and along the
    /// pitch circle (no rest state of the profile holds it; see
    /// `sagging_conveyor_on_the_circular_rim_names_the_cause`). Newton
    /// alone reaches the rest state with that roller held on its arc: no
    /// relaxation. Checked by hand on the named roller, from the positions
    /// only: its links' forces k (ℓ − ℓ₀) and its weight pull it with F; it
    /// sits on its seating arc within 2·10⁻³ ΔR of the edge (e · u < 0); the
    /// seat's force at its depth, K δⁿ with δ = |e| − ΔR (the contact law
    /// at rest in closed form), balances F along the pitch circle to 10⁻³;
    /// and the force left out of balance, the residual, is F's outward
    /// component plus the seat's own outward push K δⁿ (−e · u)/|e|, to 10⁻³:
    /// every other roller and the tail are in balance.
    #[test]
    fn newton_holds_the_sagging_conveyors_rim_roller_without_relaxing() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/data/conveyor_sag_6m.toml"
        );
        let text = std::fs::read_to_string(path).expect("the scene file exists");
        let scene = Scene::from_toml(&text).expect("a valid scene");
        let before = super::super::RELAXATIONS.with(std::cell::Cell::get);
        let sim = Simulation::new(&scene).expect("a rest state");
        let relaxations = super::super::RELAXATIONS.with(std::cell::Cell::get) - before;
        let eq = &sim.equilibrium;
        assert_eq!(relaxations, 0, "{eq:?}");
        let rim = eq
            .beyond_seating_arc
            .as_ref()
            .expect("the rim roller named");
        assert!(rim.edge_depth_m.is_none(), "{rim}");
        let s = scene
            .sprockets
            .iter()
            .position(|sp| sp.name == rim.sprocket)
            .expect("a sprocket of the scene");
        let model = sim.model();
        let state = &sim.state;
        let n = state.x.len();
        let i = rim.roller;
        // The pull of the two links and the weight, from the positions.
        let [gx, gy] = model.gravity_m_s2;
        let m = model.roller_mass_kg;
        let mut f = [m * gx, m * gy];
        for j in [(i + 1) % n, (i + n - 1) % n] {
            let d = [state.x[j] - state.x[i], state.y[j] - state.y[i]];
            let l = d[0].hypot(d[1]);
            let t = model.stiffness_n_m * (l - model.rest_length_m);
            f[0] += t * d[0] / l;
            f[1] += t * d[1] / l;
        }
        // The roller's offset from its gap's seating centre.
        let sp = &model.sprockets[s];
        let ToothProfile::Circular(c) = &sp.profile else {
            panic!("circular profile");
        };
        let seat = c.seat_center(rim.gap);
        let (sin, cos) = state.theta[s].sin_cos();
        let seat_w = [
            sp.center_m[0] + cos * seat[0] - sin * seat[1],
            sp.center_m[1] + sin * seat[0] + cos * seat[1],
        ];
        let seat_len = seat[0].hypot(seat[1]);
        let u = [
            (cos * seat[0] - sin * seat[1]) / seat_len,
            (sin * seat[0] + cos * seat[1]) / seat_len,
        ];
        let e = [state.x[i] - seat_w[0], state.y[i] - seat_w[1]];
        let e_len = e[0].hypot(e[1]);
        let radial = e[0] * u[0] + e[1] * u[1];
        assert!(
            radial < 0.0 && radial > -2e-3 * c.clearance_m,
            "offset across the edge {radial:e} m, clearance {} m",
            c.clearance_m
        );
        let depth = e_len - c.clearance_m;
        let wall = scene.contact.stiffness * depth.powf(scene.contact.exponent);
        let outward = f[0] * u[0] + f[1] * u[1];
        let along = (f[0] * u[1] - f[1] * u[0]).abs();
        assert!(outward > 0.0, "{outward} N");
        assert!(
            (wall - along).abs() <= 1e-3 * along,
            "seat {wall} N against the pull along the pitch circle {along} N"
        );
        let left = outward + wall * (-radial) / e_len;
        let residual_n = eq.force_residual * scene.chain.pretension_n;
        assert!(
            (residual_n - left).abs() <= 1e-3 * left,
            "residual {residual_n} N against the held roller's {left} N ({outward} N outward)"
        );
    }

    /// The 3 m conveyor whose upper strand lies on a wear strip (circular
    /// profile, 2000 N): roller 6 on the head is pulled outward on its
    /// seating arc's rim. At the rest length after the first, Newton from
    /// where the unheld solve stalled meets a roller on the tail sitting on
    /// its own arc's rim (its contact block by differences spans the jump:
    /// indefinite, unsymmetric); the held solve continued from the rest
    /// state before reaches the rest state without any relaxation. Checked
    /// by hand from the positions only: on a flat frictionless strip the
    /// links lie level and the strip's push is normal, so every link on
    /// it carries the same force T, and every roller away from the strip's
    /// ends rests on it with its weight alone (its links' pull has no
    /// vertical part); the free tail with no load turns the same T into the
    /// lower strand, and the pretension rule sets the strands' mean link
    /// force: T within 0.5 % of the 2000 N pretension (the lower strand's
    /// sag changes its force along it by w × its sag, under 1 N).
    #[test]
    fn the_wear_strip_conveyor_settles_by_the_held_solve_with_its_strip_carrying_the_weight() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/data/user_conveyor_strips.toml"
        );
        let text = std::fs::read_to_string(path).expect("the scene file exists");
        let scene = Scene::from_toml(&text).expect("a valid scene");
        let before = super::super::RELAXATIONS.with(std::cell::Cell::get);
        let sim = Simulation::new(&scene).expect("a rest state");
        let relaxations = super::super::RELAXATIONS.with(std::cell::Cell::get) - before;
        let eq = &sim.equilibrium;
        assert_eq!(relaxations, 0, "{eq:?}");
        let rim = eq
            .beyond_seating_arc
            .as_ref()
            .expect("the rim roller named");
        // No worse than the relaxation's end (9.5e-3 of the pretension).
        assert!(eq.force_residual < 5e-3, "{eq:?}");
        let residual_n = eq.force_residual * scene.chain.pretension_n;
        assert!(
            rim.outward_n <= residual_n * (1.0 + 1e-6),
            "{rim}: {residual_n} N"
        );
        let model = sim.model();
        let state = &sim.state;
        let n = state.x.len();
        let k = model.stiffness_n_m;
        let link = |i: usize| {
            let j = (i + 1) % n;
            let d = [state.x[j] - state.x[i], state.y[j] - state.y[i]];
            let l = d[0].hypot(d[1]);
            (k * (l - model.rest_length_m), d, l)
        };
        // Rollers of the upper strand more than 0.1 m inside the strip's
        // ends (the scene's strip spans x = −2.7226 … −0.3 m).
        let (x0, x1) = (-2.7226 + 0.1, -0.3 - 0.1);
        let on_strip: Vec<usize> = (0..n)
            .filter(|&i| state.y[i] > 0.0 && state.x[i] > x0 && state.x[i] < x1)
            .collect();
        assert!(
            on_strip.len() > 50,
            "{} rollers on the strip",
            on_strip.len()
        );
        let weight = model.roller_mass_kg * model.gravity_m_s2[1].abs();
        let mut tensions = Vec::new();
        for &i in &on_strip {
            let (t_next, d_next, l_next) = link(i);
            let (t_prev, d_prev, l_prev) = link((i + n - 1) % n);
            let vertical = t_next * d_next[1] / l_next - t_prev * d_prev[1] / l_prev;
            assert!(
                vertical.abs() <= 1e-3 * weight,
                "roller {i}: links pull {vertical} N vertically against its weight {weight} N"
            );
            tensions.push(t_next);
        }
        let (low, high) = tensions
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &t| {
                (a.min(t), b.max(t))
            });
        assert!(
            high - low <= 1e-3,
            "link forces on the strip {low}..{high} N"
        );
        let target = scene.chain.pretension_n;
        assert!(
            (low - target).abs() <= 5e-3 * target,
            "the strip's strand at {low} N against the pretension {target} N"
        );
    }
}
