//! A sprocket's excitation evaluated: the load torque in its angle (a
//! harmonic series plus a periodic cubic spline through a table) and the
//! driver's speed factor 1 + Σ a_k sin(k θ + φ_k) (docs/model.md,
//! “Excitation”). Angles are measured from the sprocket's angle origin
//! ([`super::SprocketModel::angle_origin_rad`]); the caller subtracts it.
//!
//! This module knows nothing of time or stepping.

use std::f64::consts::TAU;

use crate::scene::{Harmonic, LoadTable};

/// The periodic cubic spline through one revolution of nodes: C² and
/// 2π-periodic, cubic between nodes, through every node exactly. Its error
/// on a smooth periodic f is at most (5/384) h⁴ max|f⁗| for the largest node
/// spacing h (Hall & Meyer's bound, as for the clamped spline).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct PeriodicSpline {
    /// Node angles, rad, strictly increasing within [x₀, x₀ + 2π).
    x: Vec<f64>,
    /// Values at the nodes.
    y: Vec<f64>,
    /// Second derivatives at the nodes.
    m: Vec<f64>,
}

impl PeriodicSpline {
    /// The spline through `(angles_rad[i], values[i])`, one period with the
    /// closing node left out. `None` with fewer than three nodes, lengths
    /// that differ or angles not strictly increasing within 2π.
    pub(crate) fn new(angles_rad: &[f64], values: &[f64]) -> Option<Self> {
        let n = angles_rad.len();
        if n < 3 || values.len() != n {
            return None;
        }
        let step = |i: usize| {
            if i + 1 < n {
                angles_rad[i + 1] - angles_rad[i]
            } else {
                angles_rad[0] + TAU - angles_rad[n - 1]
            }
        };
        let h: Vec<f64> = (0..n).map(step).collect();
        if !h.iter().all(|&h| h > 0.0 && h.is_finite()) {
            return None;
        }
        let slope = |i: usize| (values[(i + 1) % n] - values[i]) / h[i];
        // Row i: h[i−1] M[i−1] + 2 (h[i−1] + h[i]) M[i] + h[i] M[i+1]
        //        = 6 (slope[i] − slope[i−1]), indices modulo n.
        let prev = |i: usize| (i + n - 1) % n;
        let sub: Vec<f64> = (0..n).map(|i| h[prev(i)]).collect();
        let diag: Vec<f64> = (0..n).map(|i| 2.0 * (h[prev(i)] + h[i])).collect();
        let sup: Vec<f64> = h.clone();
        let rhs: Vec<f64> = (0..n).map(|i| 6.0 * (slope(i) - slope(prev(i)))).collect();
        let m = solve_cyclic(&sub, &diag, &sup, &rhs)?;
        Some(Self {
            x: angles_rad.to_vec(),
            y: values.to_vec(),
            m,
        })
    }

    /// The spline at `theta_rad` (any angle; taken modulo 2π).
    pub(crate) fn at(&self, theta_rad: f64) -> f64 {
        let n = self.x.len();
        let x0 = self.x[0];
        let x = x0 + (theta_rad - x0).rem_euclid(TAU);
        // The interval [x_i, x_{i+1}) holding x; i = n − 1 wraps to x₀ + 2π.
        let i = self.x.partition_point(|&a| a <= x).saturating_sub(1);
        let (x1, j) = if i + 1 < n {
            (self.x[i + 1], i + 1)
        } else {
            (x0 + TAU, 0)
        };
        let h = x1 - self.x[i];
        let (a, b) = (x1 - x, x - self.x[i]);
        (self.m[i] * a * a * a + self.m[j] * b * b * b) / (6.0 * h)
            + (self.y[i] / h - self.m[i] * h / 6.0) * a
            + (self.y[j] / h - self.m[j] * h / 6.0) * b
    }
}

/// Solves the cyclic tridiagonal system with `sub[i]` left of the diagonal
/// in row i (row 0's at column n − 1), `sup[i]` right of it (row n − 1's at
/// column 0): Sherman–Morrison around the Thomas algorithm. `None` if a
/// pivot vanishes.
fn solve_cyclic(sub: &[f64], diag: &[f64], sup: &[f64], rhs: &[f64]) -> Option<Vec<f64>> {
    let n = diag.len();
    let (alpha, beta) = (sup[n - 1], sub[0]);
    let gamma = -diag[0];
    let mut b = diag.to_vec();
    b[0] -= gamma;
    b[n - 1] -= alpha * beta / gamma;
    let x = solve_tridiagonal(sub, &b, sup, rhs)?;
    let mut u = vec![0.0; n];
    u[0] = gamma;
    u[n - 1] = alpha;
    let z = solve_tridiagonal(sub, &b, sup, &u)?;
    let fact = (x[0] + beta * x[n - 1] / gamma) / (1.0 + z[0] + beta * z[n - 1] / gamma);
    let out: Vec<f64> = x.iter().zip(&z).map(|(x, z)| x - fact * z).collect();
    out.iter().all(|v| v.is_finite()).then_some(out)
}

/// Thomas algorithm (`sub[0]` and `sup[n − 1]` ignored).
fn solve_tridiagonal(sub: &[f64], diag: &[f64], sup: &[f64], rhs: &[f64]) -> Option<Vec<f64>> {
    let n = diag.len();
    let mut gam = vec![0.0; n];
    let mut u = vec![0.0; n];
    let mut bet = diag[0];
    if bet == 0.0 {
        return None;
    }
    u[0] = rhs[0] / bet;
    for j in 1..n {
        gam[j] = sup[j - 1] / bet;
        bet = diag[j] - sub[j] * gam[j];
        if bet == 0.0 {
            return None;
        }
        u[j] = (rhs[j] - sub[j] * u[j - 1]) / bet;
    }
    for j in (0..n - 1).rev() {
        u[j] -= gam[j + 1] * u[j + 1];
    }
    Some(u)
}

/// A load torque in a sprocket's angle: a harmonic series plus a tabled
/// torque, N·m.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct AngleLoad {
    /// Σ M_k sin(k θ + φ_k).
    pub harmonics: Vec<Harmonic>,
    /// The table's periodic spline.
    pub table: Option<PeriodicSpline>,
}

impl AngleLoad {
    /// The load from a scene's harmonics and table; `None` when there is
    /// neither (a table too short or unordered for a spline is taken as
    /// absent: the scene's validation rejects those).
    pub(crate) fn new(harmonics: &[Harmonic], table: Option<&LoadTable>) -> Option<Self> {
        let table = table.and_then(|t| PeriodicSpline::new(&t.angles_rad, &t.torques_n_m));
        (!harmonics.is_empty() || table.is_some()).then(|| Self {
            harmonics: harmonics.to_vec(),
            table,
        })
    }

    /// The torque at `theta_rad` from the angle origin, N·m.
    #[inline]
    pub(crate) fn at(&self, theta_rad: f64) -> f64 {
        let series: f64 = self.harmonics.iter().map(|h| h.at(theta_rad)).sum();
        series + self.table.as_ref().map_or(0.0, |t| t.at(theta_rad))
    }
}

/// The driver's speed factor 1 + Σ a_k sin(k θ + φ_k) at `theta_rad` from
/// the angle origin.
#[inline]
pub(crate) fn speed_factor(harmonics: &[Harmonic], theta_rad: f64) -> f64 {
    1.0 + harmonics.iter().map(|h| h.at(theta_rad)).sum::<f64>()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Nodes of f every `step_deg` degrees over one revolution.
    fn nodes(step_deg: f64, f: impl Fn(f64) -> f64) -> (Vec<f64>, Vec<f64>) {
        let n = (360.0 / step_deg).round() as usize;
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * step_deg).to_radians()).collect();
        let y = x.iter().map(|&x| f(x)).collect();
        (x, y)
    }

    #[test]
    fn the_spline_is_exact_at_the_nodes() {
        let (x, y) = nodes(15.0, |t| (2.0 * t).cos() + 0.3 * (5.0 * t).sin());
        let s = PeriodicSpline::new(&x, &y).expect("spline");
        for (x, y) in x.iter().zip(&y) {
            approx::assert_abs_diff_eq!(s.at(*x), *y, epsilon = 1e-12);
            // One period on: periodic.
            approx::assert_abs_diff_eq!(s.at(*x + TAU), *y, epsilon = 1e-12);
            approx::assert_abs_diff_eq!(s.at(*x - 3.0 * TAU), *y, epsilon = 1e-12);
        }
    }

    #[test]
    fn the_spline_reproduces_a_sine_within_its_error_bound() {
        // sin θ at 10° nodes: |s − f| ≤ (5/384) h⁴ max|f⁗| = (5/384) h⁴ with
        // h = 10° = 0.1745 rad, i.e. 1.2e-5.
        let h = 10f64.to_radians();
        let bound = 5.0 / 384.0 * h.powi(4);
        let (x, y) = nodes(10.0, f64::sin);
        let s = PeriodicSpline::new(&x, &y).expect("spline");
        let worst = (0..3600)
            .map(|i| {
                let t = f64::from(i) * TAU / 3600.0;
                (s.at(t) - t.sin()).abs()
            })
            .fold(0.0, f64::max);
        assert!(worst <= bound, "max error {worst:e} > bound {bound:e}");
        // And the bound is not vacuous: the error is of its order.
        assert!(worst > 0.05 * bound, "max error {worst:e}");
    }

    #[test]
    fn the_spline_handles_uneven_nodes() {
        // A constant is reproduced exactly whatever the spacing.
        let x = [0.0, 0.1, 1.0, 2.5, 6.0];
        let s = PeriodicSpline::new(&x, &[3.0; 5]).expect("spline");
        for i in 0..100 {
            approx::assert_abs_diff_eq!(s.at(f64::from(i) * 0.07), 3.0, epsilon = 1e-12);
        }
    }

    #[test]
    fn too_few_or_unordered_nodes_build_no_spline() {
        assert!(PeriodicSpline::new(&[0.0, 1.0], &[1.0, 2.0]).is_none());
        assert!(PeriodicSpline::new(&[0.0, 2.0, 1.0], &[1.0, 2.0, 3.0]).is_none());
        assert!(PeriodicSpline::new(&[0.0, 1.0, 7.0], &[1.0, 2.0, 3.0]).is_none());
    }
}
