//! The rollers' symplectic Euler update fused with the links' evaluation at
//! the new state: one pass over the rollers per step instead of two, and on
//! two threads one fork and one join per step instead of two.
//!
//! Each chunk of rollers (`CHUNKS` of them, as in [`Links::evaluate_split`])
//! is updated, v ← (v + h·f)·scale then x ← x + dt·v, and its links are
//! evaluated at once, while the chunk is in the core's cache. A chunk's
//! last link reaches the next chunk's first roller, and the link before its
//! first roller starts at the previous chunk's last: those rollers' new
//! states are computed once before the chunks start, with the update's own
//! operations (no fused multiply-add, so the same bits as the packed
//! update), and read from there, never from a chunk that may be writing
//! them. The results are the bits of the update followed by
//! [`Links::evaluate`] (test `fused_step_matches_the_update_then_the_links`).
//!
//! It does not step the sprockets, the further bodies or the clock (the
//! caller's, `sim::stepper`), and does not relax (no velocity scale other
//! than the caller's).

use super::{Ends, LinkLaw, Links, Rates, Slots, open_links, rates, roller_sums};
use crate::forces::{CHUNKS, Forces, Fork, Halves, chunk};
use crate::model::{DriveModel, DriveState};

/// The update's constants: v ← (v + h·f)·scale, x ← x + dt·v.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Kick {
    /// dt / roller mass, s/kg.
    pub h: f64,
    /// The step, s.
    pub dt_s: f64,
    /// The velocity factor (1 in a run).
    pub scale: f64,
}

impl Kick {
    /// Roller `i`'s new (x, y, vx, vy), as the packed update computes it.
    #[inline(always)]
    fn roller(self, s: &DriveState, out: &Forces, i: usize) -> [f64; 4] {
        let vx = (s.vx[i] + self.h * out.fx[i]) * self.scale;
        let vy = (s.vy[i] + self.h * out.fy[i]) * self.scale;
        [s.x[i] + self.dt_s * vx, s.y[i] + self.dt_s * vy, vx, vy]
    }
}

/// One coordinate of the rollers' update: v ← (v + h·f)·scale, x ← x + dt·v.
/// Slices as arguments tell the compiler they do not overlap, so it
/// vectorises the loop: four lanes where the CPU has AVX2 (chosen at run
/// time, as the links' kernel is), two otherwise. Each roller's update is
/// its own, so the width changes no bit.
#[inline(never)]
pub(crate) fn kick_drift(v: &mut [f64], x: &mut [f64], f: &[f64], h: f64, dt_s: f64, scale: f64) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2, checked on the line above.
        return unsafe { kick_drift_avx2(v, x, f, h, dt_s, scale) };
    }
    kick_drift_body(v, x, f, h, dt_s, scale);
}

/// [`kick_drift_body`] compiled with AVX2 (no FMA: the same roundings).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn kick_drift_avx2(v: &mut [f64], x: &mut [f64], f: &[f64], h: f64, dt_s: f64, scale: f64) {
    kick_drift_body(v, x, f, h, dt_s, scale);
}

#[inline(always)]
fn kick_drift_body(v: &mut [f64], x: &mut [f64], f: &[f64], h: f64, dt_s: f64, scale: f64) {
    for ((v, x), f) in v.iter_mut().zip(x).zip(f) {
        *v = (*v + h * f) * scale;
        *x += dt_s * *v;
    }
}

impl Links {
    /// Advances the rollers of `s` by one step under the forces in `out`
    /// (as the links and every element left them), then sets `out`'s roller
    /// forces, link forces, largest stretch and speed to the links' at the
    /// new state, in chunks: on two threads through `fork`, else one after
    /// the other here. Needs at least `2·CHUNKS` rollers.
    pub(crate) fn step_and_evaluate(
        &mut self,
        model: &DriveModel,
        s: &mut DriveState,
        out: &mut Forces,
        fork: Option<&dyn Fork>,
        kick: Kick,
    ) {
        self.forget_positions();
        let n = s.x.len();
        // The new state of each chunk's first roller and of the roller
        // before it (the last, for the first chunk), before any chunk moves.
        let mut first = [[0.0; 4]; CHUNKS];
        let mut before = [[0.0; 4]; CHUNKS];
        for k in 0..CHUNKS {
            let lo = chunk(n, k).0;
            first[k] = kick.roller(s, out, lo);
            before[k] = kick.roller(s, out, if lo == 0 { n - 1 } else { lo - 1 });
        }
        let law = LinkLaw::of(model);
        let with_rates = self.rates_fit(out, n);
        let (x, y) = (Halves::new(&mut s.x[..n]), Halves::new(&mut s.y[..n]));
        let (vx, vy) = (Halves::new(&mut s.vx[..n]), Halves::new(&mut s.vy[..n]));
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
        let mut partial = [0.0f64; 3 * CHUNKS];
        let parts = Halves::new(&mut partial);
        let mass = model.roller_mass_kg;
        let (gx, gy) = (mass * model.gravity_m_s2[0], mass * model.gravity_m_s2[1]);
        let job = |k: usize| {
            let (lo, hi) = chunk(n, k);
            // SAFETY: chunk k takes the disjoint range lo..hi of every
            // array (its links lo..hi too: link hi − 1 joins its last roller
            // to the next chunk's first, the last chunk's being the closing
            // link n − 1 → 0), and the borrows behind the views outlive the
            // chunks. The other chunks' rollers are read from `first` and
            // `before`, never from the arrays.
            unsafe {
                let (x, y) = (x.range(lo, hi), y.range(lo, hi));
                let (vx, vy) = (vx.range(lo, hi), vy.range(lo, hi));
                let (fx, fy) = (fx.range(lo, hi), fy.range(lo, hi));
                kick_drift(vx, x, fx, kick.h, kick.dt_s, kick.scale);
                kick_drift(vy, y, fy, kick.h, kick.dt_s, kick.scale);
                let m = hi - lo;
                let slots = Slots {
                    force: force.range(lo, hi - 1),
                    fx: lfx.range(lo, hi - 1),
                    fy: lfy.range(lo, hi - 1),
                    stretch: stretch.range(lo, hi - 1),
                };
                let rates_k = rate_views.map(|(w, gx, gy)| Rates {
                    omega: w.range(lo, hi - 1),
                    normal_x: gx.range(lo, hi - 1),
                    normal_y: gy.range(lo, hi - 1),
                });
                let ends = Ends {
                    x: &*x,
                    y: &*y,
                    vx: &*vx,
                    vy: &*vy,
                };
                open_links(law, ends, slots, rates_k);
                // Link hi − 1, to the next chunk's first roller.
                let next = first[(k + 1) % CHUNKS];
                let (dvx, dvy) = (next[2] - vx[m - 1], next[3] - vy[m - 1]);
                let (f, ux, uy, st, inv) =
                    law.eval(next[0] - x[m - 1], next[1] - y[m - 1], dvx, dvy);
                force.range(hi - 1, hi)[0] = f;
                lfx.range(hi - 1, hi)[0] = f * ux;
                lfy.range(hi - 1, hi)[0] = f * uy;
                stretch.range(hi - 1, hi)[0] = st;
                if let Some((w, nx, ny)) = rate_views {
                    (
                        w.range(hi - 1, hi)[0],
                        nx.range(hi - 1, hi)[0],
                        ny.range(hi - 1, hi)[0],
                    ) = rates(ux, uy, inv, dvx, dvy);
                }
                // The link before roller lo, from the previous chunk's last.
                let prev = before[k];
                let (dvx, dvy) = (vx[0] - prev[2], vy[0] - prev[3]);
                let (f, ux, uy, _, _) = law.eval(x[0] - prev[0], y[0] - prev[1], dvx, dvy);
                let (prev_x, prev_y) = (f * ux, f * uy);
                let (nan, max_stretch, max_speed_sq) = roller_sums(
                    [gx, gy],
                    [&*lfx.range(lo, hi), &*lfy.range(lo, hi)],
                    [prev_x, prev_y],
                    [fx, fy],
                    &*stretch.range(lo, hi),
                    [&*vx, &*vy],
                );
                let p = parts.range(3 * k, 3 * k + 3);
                p[0] = if nan { 1.0 } else { 0.0 };
                p[1] = max_stretch;
                p[2] = max_speed_sq;
            }
        };
        match fork {
            Some(f) => f.both(&job),
            None => (0..CHUNKS).for_each(&job),
        }
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

#[cfg(test)]
mod tests {
    use super::{Kick, kick_drift};
    use crate::forces::CHUNKS;
    use crate::forces::{ForceElement, Forces, Fork, Links};
    use crate::model::{DriveModel, DriveState};

    /// Two threads claiming the chunks from a shared counter: the forces
    /// stage's own stand-in for the simulation's worker.
    #[derive(Debug)]
    struct TwoThreads;

    impl Fork for TwoThreads {
        fn splits(&self, _rollers: usize) -> bool {
            true
        }

        fn both(&self, job: &(dyn Fn(usize) + Sync)) {
            let next = std::sync::atomic::AtomicUsize::new(0);
            let claim = || loop {
                let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                if k >= CHUNKS {
                    break;
                }
                job(k);
            };
            std::thread::scope(|s| {
                s.spawn(claim);
                claim();
            });
        }

        fn clone_box(&self) -> Box<dyn Fork> {
            Box::new(TwoThreads)
        }
    }

    /// The bits of every output the update and the links write.
    fn bits(s: &DriveState, out: &Forces, links: &Links) -> Vec<u64> {
        [
            &s.x,
            &s.y,
            &s.vx,
            &s.vy,
            &out.fx,
            &out.fy,
            &out.link_force,
            &out.link_omega,
            &out.link_normal_x,
            &out.link_normal_y,
        ]
        .into_iter()
        .flat_map(|v| v.iter().copied())
        .chain(links.stretch().iter().copied())
        .chain([out.max_stretch_m, out.max_roller_speed_m_s])
        .map(f64::to_bits)
        .collect()
    }

    #[test]
    fn fused_step_matches_the_update_then_the_links() {
        // Oracle: the plain update (each roller's v ← (v + h·f)·scale,
        // x ← x + dt·v over the whole chain) followed by the links' plain
        // pass: the fused pass, on one thread and on two, with and without
        // the links' rates, gives the same bits. The paper's drive with a
        // disturbed state and forces, so that every link differs.
        let scene = crate::scene::Scene::l60mc();
        let (model, mut s, _) = DriveModel::build(&scene).expect("paper's drive lays out");
        let n = s.rollers();
        assert!(n >= 2 * crate::forces::CHUNKS);
        for i in 0..n {
            s.x[i] += ((i * 3 % 7) as f64 - 3.0) * 1e-4;
            s.vx[i] += ((i * 7 % 11) as f64 - 5.0) * 0.3;
            s.vy[i] += ((i * 5 % 13) as f64 - 6.0) * 0.2;
        }
        let kick = Kick {
            h: 50e-6 / model.roller_mass_kg,
            dt_s: 50e-6,
            scale: 0.999,
        };
        for with_rates in [false, true] {
            let mut out = Forces::new(n, model.sprockets.len(), 0, 0);
            let mut links = Links::new(n);
            if with_rates {
                links.request_rates(&mut out);
            }
            links.evaluate(&model, &s, &mut out);
            for i in 0..n {
                out.fx[i] += ((i * 13 % 17) as f64 - 8.0) * 3.0;
            }
            let (s0, out0, links0) = (s.clone(), out.clone(), links.clone());
            let (mut s1, mut out1, mut links1) = (s0.clone(), out0.clone(), links0.clone());
            kick_drift(
                &mut s1.vx, &mut s1.x, &out1.fx, kick.h, kick.dt_s, kick.scale,
            );
            kick_drift(
                &mut s1.vy, &mut s1.y, &out1.fy, kick.h, kick.dt_s, kick.scale,
            );
            links1.evaluate(&model, &s1, &mut out1);
            let expected = bits(&s1, &out1, &links1);
            assert_ne!(
                bits(&s0, &out0, &links0),
                expected,
                "the step moves the chain"
            );
            for fork in [None, Some(&TwoThreads as &dyn Fork)] {
                let (mut s2, mut out2, mut links2) = (s0.clone(), out0.clone(), links0.clone());
                links2.step_and_evaluate(&model, &mut s2, &mut out2, fork, kick);
                assert_eq!(
                    bits(&s2, &out2, &links2),
                    expected,
                    "rates {with_rates}, two threads {}",
                    fork.is_some()
                );
            }
        }
    }
}
