//! The links: linear spring-dampers between consecutive rollers
//! (docs/model.md, “Links”), and the rollers' weight.

use super::{ForceElement, Forces, Halves, History, HistoryError, HistoryReader};

mod kernels;
mod step;
use crate::model::{DriveModel, DriveState};
#[cfg(test)]
pub(crate) use kernels::link_rates;
use kernels::{
    Ends, KeptShape, LinkLaw, Rates, Shape, Slots, largest, link_geometry, link_velocities,
    open_links, rates, roller_sums,
};
pub(crate) use step::{Kick, kick_drift};

/// The chain's links and the rollers' weight: the first force element of
/// every drive. It *sets* each roller's force to its weight plus its two
/// links (every later element adds to it), the links' forces, the largest
/// stretch and the largest roller speed.
#[derive(Clone, Debug)]
pub(crate) struct Links {
    /// Scratch: force vector of link i on roller i, N.
    link_fx: Vec<f64>,
    /// Scratch: its y component, N.
    link_fy: Vec<f64>,
    /// l − rest length of link i at the last evaluation, m.
    stretch: Vec<f64>,
    /// Whether the pass writes each link's ω and n/ℓ into
    /// [`Forces::link_omega`] and its normals: set by
    /// [`Links::request_rates`], which an element asks for through
    /// [`super::ForceElement::wants_link_rates`].
    rates: bool,
    /// What each evaluation keeps for one at the same positions
    /// ([`Links::keep_positions`]); `None`: nothing kept.
    kept: Option<Kept>,
}

/// What depends on the rollers' positions alone, one slot per link, kept
/// from an evaluation for [`Links::evaluate_again`].
#[derive(Clone, Debug)]
struct Kept {
    /// Unit vector u, x and y.
    ux: Vec<f64>,
    uy: Vec<f64>,
    /// Spring force K (l − rest), N.
    spring: Vec<f64>,
    /// 1/l, 1/m.
    inv: Vec<f64>,
    /// Whether the last evaluation kept them at its positions.
    valid: bool,
}

impl Links {
    /// Buffers for a chain of `rollers` rollers (and as many links).
    pub(crate) fn new(rollers: usize) -> Self {
        Self {
            link_fx: vec![0.0; rollers],
            link_fy: vec![0.0; rollers],
            stretch: vec![0.0; rollers],
            rates: false,
            kept: None,
        }
    }

    /// From now on (`keep`) each evaluation on one thread keeps what depends
    /// on the positions alone, for [`Self::evaluate_again`]; `false` keeps
    /// nothing.
    pub(crate) fn keep_positions(&mut self, keep: bool) {
        let n = self.stretch.len();
        self.kept = keep.then(|| Kept {
            ux: vec![0.0; n],
            uy: vec![0.0; n],
            spring: vec![0.0; n],
            inv: vec![0.0; n],
            valid: false,
        });
    }

    /// From now on, write each link's ω and n/ℓ into `out`'s
    /// [`Forces::link_omega`] and normals, sized here (once, not per step).
    pub(crate) fn request_rates(&mut self, out: &mut Forces) {
        let n = self.stretch.len();
        self.rates = true;
        out.link_omega.resize(n, 0.0);
        out.link_normal_x.resize(n, 0.0);
        out.link_normal_y.resize(n, 0.0);
    }

    /// l − rest length of each link at the last evaluation, m.
    pub(crate) fn stretch(&self) -> &[f64] {
        &self.stretch
    }

    /// Whether a pass over `n` links writes their rates: asked for, and
    /// `out`'s rate buffers sized for them.
    fn rates_fit(&self, out: &Forces, n: usize) -> bool {
        self.rates
            && out.link_omega.len() == n
            && out.link_normal_x.len() == n
            && out.link_normal_y.len() == n
    }
}

impl Links {
    /// [`ForceElement::evaluate`] with the rollers split in two halves, run
    /// by `fork` (module `sim::parallel`) in chunks: each chunk evaluates its
    /// own links and sums its own rollers' forces. The link before a chunk's
    /// first roller belongs to the chunk before; the chunk evaluates it
    /// again, with the same operations, so each roller's sum is the same
    /// bits as on one thread without waiting for the other chunk.
    pub(crate) fn evaluate_split(
        &mut self,
        model: &DriveModel,
        s: &DriveState,
        out: &mut Forces,
        fork: &dyn super::Fork,
    ) {
        self.forget_positions();
        let n = s.x.len();
        let law = LinkLaw::of(model);
        let (x, y, vx, vy) = (&s.x[..n], &s.y[..n], &s.vx[..n], &s.vy[..n]);
        let with_rates = self.rates_fit(out, n);
        let force = Halves::new(&mut out.link_force[..n]);
        let (lfx, lfy) = (
            Halves::new(&mut self.link_fx[..n]),
            Halves::new(&mut self.link_fy[..n]),
        );
        let stretch = Halves::new(&mut self.stretch[..n]);
        let (fx, fy) = (Halves::new(&mut out.fx[..n]), Halves::new(&mut out.fy[..n]));
        let rate_views = with_rates.then(|| {
            (
                Halves::new(&mut out.link_omega[..n]),
                Halves::new(&mut out.link_normal_x[..n]),
                Halves::new(&mut out.link_normal_y[..n]),
            )
        });
        // Per chunk: NaN stretch seen, largest |stretch|, largest speed².
        let mut partial = [0.0f64; 3 * super::CHUNKS];
        let parts = Halves::new(&mut partial);
        let mass = model.roller_mass_kg;
        let (gx, gy) = (mass * model.gravity_m_s2[0], mass * model.gravity_m_s2[1]);
        let half = |h: usize| {
            // Rollers lo..hi; links lo..hi too, the last chunk's last being
            // the closing link n−1 → 0.
            let (lo, hi) = super::chunk(n, h);
            let last = hi == n;
            let open_hi = if last { n - 1 } else { hi };
            // SAFETY: the two halves take disjoint ranges lo..hi of every
            // output, and the borrows behind the views outlive `fork.both`.
            unsafe {
                let slots = Slots {
                    force: force.range(lo, open_hi),
                    fx: lfx.range(lo, open_hi),
                    fy: lfy.range(lo, open_hi),
                    stretch: stretch.range(lo, open_hi),
                };
                let rates_h = rate_views.map(|(w, gx, gy)| Rates {
                    omega: w.range(lo, open_hi),
                    normal_x: gx.range(lo, open_hi),
                    normal_y: gy.range(lo, open_hi),
                });
                let ends = Ends {
                    x: &x[lo..=open_hi],
                    y: &y[lo..=open_hi],
                    vx: &vx[lo..=open_hi],
                    vy: &vy[lo..=open_hi],
                };
                open_links(law, ends, slots, rates_h);
                // The link before roller lo: j → lo, with j = lo − 1 (or the
                // closing link n − 1 for roller 0). The last chunk writes
                // the closing link; the first only reads it.
                let j = if lo == 0 { n - 1 } else { lo - 1 };
                let (dvx, dvy) = (vx[lo] - vx[j], vy[lo] - vy[j]);
                let (f, ux, uy, _, _) = law.eval(x[lo] - x[j], y[lo] - y[j], dvx, dvy);
                let (prev_x, prev_y) = (f * ux, f * uy);
                if last {
                    let k = n - 1;
                    let (dvx, dvy) = (vx[0] - vx[k], vy[0] - vy[k]);
                    let (f, ux, uy, last, inv) = law.eval(x[0] - x[k], y[0] - y[k], dvx, dvy);
                    force.range(k, n)[0] = f;
                    lfx.range(k, n)[0] = f * ux;
                    lfy.range(k, n)[0] = f * uy;
                    stretch.range(k, n)[0] = last;
                    if let Some((w, nx, ny)) = rate_views {
                        (w.range(k, n)[0], nx.range(k, n)[0], ny.range(k, n)[0]) =
                            rates(ux, uy, inv, dvx, dvy);
                    }
                }
                let st_h = &*stretch.range(lo, hi);
                let nan = st_h.iter().fold(false, |b, s| b | s.is_nan());
                let max_stretch = largest(st_h, st_h, |s, _| s.abs());
                let max_speed_sq = largest(&vx[lo..hi], &vy[lo..hi], |a, b| a * a + b * b);
                let (lx, ly) = (&*lfx.range(lo, hi), &*lfy.range(lo, hi));
                let (fx_h, fy_h) = (fx.range(lo, hi), fy.range(lo, hi));
                fx_h[0] = gx + (lx[0] - prev_x);
                fy_h[0] = gy + (ly[0] - prev_y);
                for i in 1..hi - lo {
                    fx_h[i] = gx + (lx[i] - lx[i - 1]);
                    fy_h[i] = gy + (ly[i] - ly[i - 1]);
                }
                let p = parts.range(3 * h, 3 * h + 3);
                p[0] = if nan { 1.0 } else { 0.0 };
                p[1] = max_stretch;
                p[2] = max_speed_sq;
            }
        };
        fork.both(&half);
        // Maxima do not depend on the order in which they are taken.
        let larger = |a: f64, b: f64| if b > a { b } else { a };
        let mut nan = false;
        let (mut max_stretch, mut max_speed_sq) = (0.0f64, 0.0f64);
        for p in partial.chunks_exact(3) {
            nan |= p[0] != 0.0;
            max_stretch = larger(max_stretch, p[1]);
            max_speed_sq = larger(max_speed_sq, p[2]);
        }
        out.max_stretch_m = if nan { f64::NAN } else { max_stretch };
        out.max_roller_speed_m_s = max_speed_sq.sqrt();
    }
}

impl Links {
    /// The kept positions no longer hold: an evaluation that keeps none
    /// came after.
    fn forget_positions(&mut self) {
        if let Some(kept) = &mut self.kept {
            kept.valid = false;
        }
    }

    /// Each link's geometry at `s` into the kept slots (and its n/ℓ into
    /// `out` where the rates are asked for), and the stretches.
    fn keep_geometry(&mut self, model: &DriveModel, s: &DriveState, out: &mut Forces) {
        let n = s.x.len();
        let with_rates = self.rates_fit(out, n);
        let Some(kept) = &mut self.kept else {
            return;
        };
        let law = LinkLaw::of(model);
        let shape = Shape {
            ux: &mut kept.ux[..n],
            uy: &mut kept.uy[..n],
            spring: &mut kept.spring[..n],
            inv: &mut kept.inv[..n],
            stretch: &mut self.stretch[..n],
        };
        let normals =
            with_rates.then(|| (&mut out.link_normal_x[..n], &mut out.link_normal_y[..n]));
        link_geometry(law, &s.x[..n], &s.y[..n], shape, normals);
        kept.valid = true;
    }

    /// The links at `s`, whose roller positions are those of the last
    /// evaluation (kept, [`Self::keep_positions`]): only what depends on the
    /// velocities is computed again — the forces (the damping's part), each
    /// roller's sum, the rates' ω and the largest speed; the stretches and
    /// the normals stay. The same numbers as [`ForceElement::evaluate`].
    /// Without kept positions, the whole evaluation.
    pub(crate) fn evaluate_again(&mut self, model: &DriveModel, s: &DriveState, out: &mut Forces) {
        let n = s.x.len();
        let with_rates = self.rates_fit(out, n);
        let Some(kept) = self.kept.as_ref().filter(|k| k.valid) else {
            return self.evaluate(model, s, out);
        };
        let lfx = &mut self.link_fx[..n];
        let lfy = &mut self.link_fy[..n];
        let shape = KeptShape {
            ux: &kept.ux[..n],
            uy: &kept.uy[..n],
            spring: &kept.spring[..n],
            inv: &kept.inv[..n],
        };
        let slots = Slots {
            force: &mut out.link_force[..n],
            fx: &mut *lfx,
            fy: &mut *lfy,
            stretch: &mut [],
        };
        let omega = with_rates.then(|| &mut out.link_omega[..n]);
        link_velocities(
            model.damping_n_s_m,
            [&s.vx[..n], &s.vy[..n]],
            shape,
            slots,
            omega,
        );
        let m = model.roller_mass_kg;
        let weight = [m * model.gravity_m_s2[0], m * model.gravity_m_s2[1]];
        let (fx, fy) = (&mut out.fx[..n], &mut out.fy[..n]);
        let prev = [lfx[n - 1], lfy[n - 1]];
        let v = [&s.vx[..n], &s.vy[..n]];
        let (nan, max_stretch, max_speed_sq) = roller_sums(
            weight,
            [&*lfx, &*lfy],
            prev,
            [fx, fy],
            &self.stretch[..n],
            v,
        );
        out.max_stretch_m = if nan { f64::NAN } else { max_stretch };
        out.max_roller_speed_m_s = max_speed_sq.sqrt();
    }
}

impl ForceElement for Links {
    fn name(&self) -> &'static str {
        "links"
    }

    /// Two passes: the links' force vectors first (independent iterations,
    /// which the compiler pipelines and vectorises), then each roller's sum
    /// of its two links, so no iteration waits on the previous one's store.
    ///
    /// Keeping what depends on the positions alone
    /// ([`Links::keep_positions`]), the same numbers in two other passes:
    /// each link's geometry, then what depends on the velocities
    /// ([`Links::evaluate_again`]).
    fn evaluate(&mut self, model: &DriveModel, s: &DriveState, out: &mut Forces) {
        if self.kept.is_some() {
            self.keep_geometry(model, s, out);
            return self.evaluate_again(model, s, out);
        }
        let n = s.x.len();
        let law = LinkLaw::of(model);
        let with_rates = self.rates_fit(out, n);
        let (x, y, vx, vy) = (&s.x[..n], &s.y[..n], &s.vx[..n], &s.vy[..n]);
        let force = &mut out.link_force[..n];
        let (lfx, lfy) = (&mut self.link_fx[..n], &mut self.link_fy[..n]);
        let stretch = &mut self.stretch[..n];
        // Links 0..n−1 join consecutive rollers; the closing link n−1 → 0
        // after them.
        let link_rates = with_rates.then(|| Rates {
            omega: &mut out.link_omega[..n],
            normal_x: &mut out.link_normal_x[..n],
            normal_y: &mut out.link_normal_y[..n],
        });
        let slots = Slots {
            force: &mut *force,
            fx: &mut *lfx,
            fy: &mut *lfy,
            stretch: &mut *stretch,
        };
        open_links(law, Ends { x, y, vx, vy }, slots, link_rates);
        let (dvx, dvy) = (vx[0] - vx[n - 1], vy[0] - vy[n - 1]);
        let (f, ux, uy, last, inv) = law.eval(x[0] - x[n - 1], y[0] - y[n - 1], dvx, dvy);
        force[n - 1] = f;
        lfx[n - 1] = f * ux;
        lfy[n - 1] = f * uy;
        stretch[n - 1] = last;
        if with_rates {
            (
                out.link_omega[n - 1],
                out.link_normal_x[n - 1],
                out.link_normal_y[n - 1],
            ) = rates(ux, uy, inv, dvx, dvy);
        }
        let m = model.roller_mass_kg;
        let weight = [m * model.gravity_m_s2[0], m * model.gravity_m_s2[1]];
        let (fx, fy) = (&mut out.fx[..n], &mut out.fy[..n]);
        let prev = [lfx[n - 1], lfy[n - 1]];
        let (nan, max_stretch, max_speed_sq) =
            roller_sums(weight, [&*lfx, &*lfy], prev, [fx, fy], &*stretch, [vx, vy]);
        out.max_stretch_m = if nan { f64::NAN } else { max_stretch };
        out.max_roller_speed_m_s = max_speed_sq.sqrt();
    }

    /// No history; the last evaluation's stretches ([`Links::stretch`]).
    fn save_history(&self, history: &mut History) {
        history.push_floats(self.stretch.iter().copied());
    }

    fn restore_history(&mut self, history: &mut HistoryReader<'_>) -> Result<(), HistoryError> {
        let stretch = history.floats(self.stretch.len())?;
        self.stretch.copy_from_slice(stretch);
        Ok(())
    }

    fn clone_box(&self) -> Box<dyn ForceElement> {
        Box::new(self.clone())
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

#[cfg(test)]
mod tests {
    use crate::forces::{ForceElement, Forces, Links};
    use crate::model::DriveModel;

    #[test]
    fn links_pass_writes_each_links_angular_velocity_and_normal() {
        // Oracle: for link j from roller j to k = j + 1 (mod n), with d its
        // vector and ḋ its velocity difference, ω = (d × ḋ)/|d|² and
        // n/ℓ = (−d_y, d_x)/|d|²; relative tolerance 1e-12 of the largest.
        // The paper's drive as laid out, every roller given its own velocity.
        let scene = crate::scene::Scene::l60mc();
        let (model, mut s, _) = DriveModel::build(&scene).expect("paper's drive lays out");
        let n = s.rollers();
        for i in 0..n {
            s.vx[i] += ((i * 7 % 11) as f64 - 5.0) * 0.3;
            s.vy[i] += ((i * 5 % 13) as f64 - 6.0) * 0.2;
        }
        let mut out = Forces::new(n, model.sprockets.len(), 0, 0);
        // Not asked for: nothing written.
        let mut links = Links::new(n);
        links.evaluate(&model, &s, &mut out);
        assert!(out.link_omega.is_empty());
        links.request_rates(&mut out);
        out.link_omega.fill(f64::NAN);
        out.link_normal_x.fill(f64::NAN);
        out.link_normal_y.fill(f64::NAN);
        links.evaluate(&model, &s, &mut out);
        let mut worst = [0.0f64; 3];
        let mut largest_seen = [0.0f64; 3];
        for j in 0..n {
            let k = (j + 1) % n;
            let (dx, dy) = (s.x[k] - s.x[j], s.y[k] - s.y[j]);
            let (dvx, dvy) = (s.vx[k] - s.vx[j], s.vy[k] - s.vy[j]);
            let l2 = dx * dx + dy * dy;
            let expected = [(dx * dvy - dy * dvx) / l2, -dy / l2, dx / l2];
            let got = [
                out.link_omega[j],
                out.link_normal_x[j],
                out.link_normal_y[j],
            ];
            assert!(got.iter().all(|v| v.is_finite()), "link {j} not written");
            for c in 0..3 {
                worst[c] = worst[c].max((got[c] - expected[c]).abs());
                largest_seen[c] = largest_seen[c].max(expected[c].abs());
            }
        }
        for c in 0..3 {
            assert!(largest_seen[c] > 0.0);
            assert!(
                worst[c] <= 1e-12 * largest_seen[c],
                "component {c}: {worst:?}"
            );
        }
    }
}
