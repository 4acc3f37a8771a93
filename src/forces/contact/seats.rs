//! The contact pass of a run of rollers on a circular-profile sprocket
//! (without damping rows, tips or shared rollers), in two loops:
//!
//! 1. **Geometry**, branch-free over the whole run, which the compiler
//!    vectorises: each roller in the sprocket frame, the cone test of its
//!    hinted gap, its seat's depth and normal, and its approach speed.
//! 2. **Law**, in roller order: the contact memory, the force and the sums
//!    — the same operations in the same order as the general pass
//!    ([`super::pass`]), so the same bits. A roller that has left its hinted
//!    gap's cone (a few per revolution) takes the full query there.
//!
//! Not for the real profile (its query branches by area) nor for rollers
//! within reach of two sprockets.

use super::FREE;
use super::pass::{ContactPass, Frame, PatchContext, Roller, Row, Sums, WorldPatch};
use super::reach::Run;
use super::scratch::{NO_DIRECTION, SeatScratch};
use crate::geometry::{MAX_PATCHES, Patch, Seats};

const IN_CONE: u8 = 1;
const TOUCHING: u8 = 2;

impl ContactPass<'_> {
    /// Contacts of one unshared run on a circular-profile sprocket; returns
    /// the chain's resultant force and moment on the sprocket, as
    /// [`ContactPass::run`] does.
    #[inline(always)]
    pub(super) fn run_seats<const MOVING: bool, const KEEP: bool>(
        &mut self,
        seats: &Seats<'_>,
        frame: &Frame,
        run: &Run,
    ) -> ([f64; 2], f64) {
        let (a, b) = (run.start, run.end);
        // The full queries' loop only where a roller has left its hinted
        // gap's cone (a few times per revolution).
        if !self.seat_geometry::<MOVING>(seats, frame, a, b) {
            self.seat_queries::<MOVING>(seats, frame, a, b);
        }
        // One loop per law shape: `powf` (any exponent but 3/2) is a call,
        // which would keep the loop's sums out of registers.
        let law = self.law;
        if law.hertz() {
            let stiffness = law.stiffness;
            self.seat_law::<MOVING, KEEP>(seats, frame, a, b, |d| stiffness * d * d.sqrt())
        } else {
            self.seat_law::<MOVING, KEEP>(seats, frame, a, b, |d| law.elastic(d))
        }
    }

    /// The law's loop of [`Self::run_seats`], in roller order, with the
    /// elastic part `elastic_of(δ)` = K δⁿ.
    #[inline(always)]
    fn seat_law<const MOVING: bool, const KEEP: bool>(
        &mut self,
        seats: &Seats<'_>,
        frame: &Frame,
        a: usize,
        b: usize,
        elastic_of: impl Fn(f64) -> f64,
    ) -> ([f64; 2], f64) {
        let law = self.law;
        let ctx = PatchContext {
            law,
            energy_factor: 1.0 / (law.exponent + 1.0),
            sin: frame.sin,
            cos: frame.cos,
            omega: frame.omega,
            velocity: frame.velocity,
            index: frame.index,
        };
        let sc = &*self.seat_scratch;
        let (rxs, rys, status) = (&sc.rx[a..b], &sc.ry[a..b], &sc.status[a..b]);
        let (depth, nxs, nys, rate) = (&sc.depth[a..b], &sc.nx[a..b], &sc.ny[a..b], &sc.rate[a..b]);
        let memory = &self.memory[a..b];
        let remembered = &self.remembered[a..b];
        let pending_memory = &mut self.pending_memory[a..b];
        let gap_hint = &self.gap_hint[a..b];
        let (fx_out, fy_out) = (&mut self.fx[a..b], &mut self.fy[a..b]);
        let touching = &mut self.touching[a..b];
        let contact_force = &mut self.contact_force[a..b];
        let mut sums = Sums {
            force: [0.0; 2],
            torque: 0.0,
            energy: 0.0,
            damping_power: 0.0,
            max_pen: self.max_penetration_m,
        };
        for k in 0..b - a {
            if status[k] != IN_CONE | TOUCHING {
                pending_memory[k] = [FREE; MAX_PATCHES];
                continue;
            }
            let (rx, ry) = (rxs[k], rys[k]);
            let contact = WorldPatch {
                depth_m: depth[k],
                patch_id: gap_hint[k],
                normal: [nxs[k], nys[k]],
                depth_rate: rate[k],
            };
            let onsets = if remembered[k] != 0 {
                &memory[k]
            } else {
                &[FREE; MAX_PATCHES]
            };
            let mut roller = Roller {
                next: [FREE; MAX_PATCHES],
                used: 0,
                total: [0.0; 2],
                row: Row::default(),
                last_force: 0.0,
            };
            let elastic = elastic_of(contact.depth_m);
            let onset = ctx.world_patch::<false, MOVING, _>(
                seats,
                &contact,
                elastic,
                [rx, ry],
                onsets,
                &mut roller,
                &mut sums,
            );
            if KEEP {
                let touch = onset.touch(a + k, 1, [rx, ry], contact.normal, elastic);
                self.kept.touches.push(touch);
            }
            pending_memory[k] = roller.next;
            fx_out[k] += roller.total[0];
            fy_out[k] += roller.total[1];
            touching[k] = true;
            // One patch: its force is the magnitude.
            contact_force[k] = roller.last_force;
        }
        self.energy_j += sums.energy;
        self.damping_power_w += sums.damping_power;
        self.max_penetration_m = sums.max_pen;
        (sums.force, sums.torque)
    }

    /// The full query, as the general pass makes it, for each roller of
    /// `a..b` that the geometry found out of its hinted gap's cone (a few
    /// per revolution), into the scratch: kept out of the law's loop, whose
    /// sums then stay in registers (a call would clobber them).
    #[inline(always)]
    fn seat_queries<const MOVING: bool>(
        &mut self,
        seats: &Seats<'_>,
        frame: &Frame,
        a: usize,
        b: usize,
    ) {
        let (sin, cos, omega) = (frame.sin, frame.cos, frame.omega);
        let s = self.state;
        let (vxs, vys) = (&s.vx[a..b], &s.vy[a..b]);
        let sc = &mut *self.seat_scratch;
        let (rxs, rys) = (&sc.rx[a..b], &sc.ry[a..b]);
        let (status, depth) = (&mut sc.status[a..b], &mut sc.depth[a..b]);
        let (nxs, nys, rate) = (&mut sc.nx[a..b], &mut sc.ny[a..b], &mut sc.rate[a..b]);
        let gap_hint = &mut self.gap_hint[a..b];
        for k in 0..b - a {
            if status[k] & IN_CONE != 0 {
                continue;
            }
            let (rx, ry) = (rxs[k], rys[k]);
            let local = [cos * rx + sin * ry, -sin * rx + cos * ry];
            let mut patches = [Patch::default(); MAX_PATCHES];
            status[k] = IN_CONE;
            if seats.contacts(local, &mut gap_hint[k], &mut patches) == 0 {
                continue;
            }
            let p = &patches[0];
            let v_rel = if MOVING {
                [
                    vxs[k] - frame.velocity[0] + omega * ry,
                    vys[k] - frame.velocity[1] - omega * rx,
                ]
            } else {
                [vxs[k] + omega * ry, vys[k] - omega * rx]
            };
            // Normal back to the world frame.
            let nx = cos * p.normal[0] - sin * p.normal[1];
            let ny = sin * p.normal[0] + cos * p.normal[1];
            (depth[k], nxs[k], nys[k]) = (p.depth_m, nx, ny);
            rate[k] = -(v_rel[0] * nx + v_rel[1] * ny);
            status[k] = IN_CONE | TOUCHING;
        }
    }

    /// The geometry of rollers `a..b` against their hinted gaps, into the
    /// scratch (see [`seat_geometry`]); returns whether every roller of
    /// `a..b` is inside its hinted gap's cone.
    #[inline(always)]
    fn seat_geometry<const MOVING: bool>(
        &mut self,
        seats: &Seats<'_>,
        frame: &Frame,
        a: usize,
        b: usize,
    ) -> bool {
        let sc = &mut *self.seat_scratch;
        hinted_directions(seats, frame.index, &self.gap_hint[a..b], sc, a);
        // A whole number of four-roller chunks where the chain has the
        // rollers (the vector loop then leaves no roller to a scalar
        // remainder): the rollers past `b` are computed, from whatever
        // directions their slots hold, into scratch slots no one reads
        // before their own run computes them again.
        let end = b;
        let padded = a + (b - a).div_ceil(4) * 4;
        let b = if padded <= self.gap_hint.len() {
            padded
        } else {
            b
        };
        let s = self.state;
        let c = Consts {
            center: frame.center,
            velocity: frame.velocity,
            sin: frame.sin,
            cos: frame.cos,
            omega: frame.omega,
            tan_half_pitch: seats.tan_half_pitch,
            seat_radius_m: seats.seat_radius_m,
            clearance_m: seats.clearance_m,
            clearance_sq_m2: seats.clearance_sq_m2,
        };
        let args = (
            &s.x[a..b],
            &s.y[a..b],
            &s.vx[a..b],
            &s.vy[a..b],
            &sc.ux[a..b],
            &sc.uy[a..b],
        );
        let outs = (
            &mut sc.rx[a..b],
            &mut sc.ry[a..b],
            &mut sc.depth[a..b],
            &mut sc.nx[a..b],
            &mut sc.ny[a..b],
            &mut sc.rate[a..b],
            &mut sc.status[a..b],
        );
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            // SAFETY: `avx2` is set only where the CPU has AVX2.
            unsafe {
                seat_geometry_avx2::<MOVING>(
                    &c, args.0, args.1, args.2, args.3, args.4, args.5, outs.0, outs.1, outs.2,
                    outs.3, outs.4, outs.5, outs.6,
                );
            }
        } else {
            seat_geometry::<MOVING>(
                &c, args.0, args.1, args.2, args.3, args.4, args.5, outs.0, outs.1, outs.2, outs.3,
                outs.4, outs.5, outs.6,
            );
        }
        #[cfg(not(target_arch = "x86_64"))]
        seat_geometry::<MOVING>(
            &c, args.0, args.1, args.2, args.3, args.4, args.5, outs.0, outs.1, outs.2, outs.3,
            outs.4, outs.5, outs.6,
        );
        // A plain fold (no early exit), which the compiler vectorises.
        sc.status[a..end].iter().fold(IN_CONE, |all, s| all & s) == IN_CONE
    }
}

/// Each roller's hinted gap direction on sprocket `sprocket` into the
/// scratch slots from `first` on, `hints` the rollers' gap hints: read from
/// the sprocket's table only where the slot holds another sprocket's or
/// another gap's direction (a roller entering the wrap or moving on a gap),
/// a hint that is no gap of this sprocket giving NaN, which fails the cone
/// test. The directions are the table's, so kept or read again, the same
/// bits.
#[inline(always)]
fn hinted_directions(
    seats: &Seats<'_>,
    sprocket: usize,
    hints: &[u32],
    sc: &mut SeatScratch,
    first: usize,
) {
    let table = (seats.dirs.as_ptr() as usize, seats.dirs.len());
    if let Some(kept) = sc.tables.get_mut(sprocket)
        && *kept != table
    {
        // Another table than the kept directions were read from (another
        // drive's model). A table's directions are a function of its length
        // (gap j at j 2π/z), so even a new table at a freed one's address
        // cannot hold other directions under the same key.
        *kept = table;
        sc.direction_of.fill(NO_DIRECTION);
    }
    let n = hints.len();
    let tag = (sprocket as u64) << 32;
    let of = &mut sc.direction_of[first..first + n];
    // A plain fold (no early exit), which the compiler vectorises.
    let stale = hints
        .iter()
        .zip(of.iter())
        .fold(false, |stale, (h, k)| stale | (tag | u64::from(*h) != *k));
    if !stale {
        return;
    }
    let (ux, uy) = (&mut sc.ux[first..first + n], &mut sc.uy[first..first + n]);
    for (((h, k), ux), uy) in hints.iter().zip(of).zip(ux).zip(uy) {
        let key = tag | u64::from(*h);
        if *k != key {
            *k = key;
            let u = seats
                .dirs
                .get(*h as usize)
                .copied()
                .unwrap_or([f64::NAN; 2]);
            (*ux, *uy) = (u[0], u[1]);
        }
    }
}

/// What the geometry loop reads besides the rollers: the sprocket's frame
/// and its seats.
struct Consts {
    center: [f64; 2],
    velocity: [f64; 2],
    sin: f64,
    cos: f64,
    omega: f64,
    tan_half_pitch: f64,
    seat_radius_m: f64,
    clearance_m: f64,
    clearance_sq_m2: f64,
}

/// [`seat_geometry`] compiled with AVX2 (no FMA: the same roundings).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[allow(clippy::too_many_arguments)]
fn seat_geometry_avx2<const MOVING: bool>(
    c: &Consts,
    xs: &[f64],
    ys: &[f64],
    vxs: &[f64],
    vys: &[f64],
    ux: &[f64],
    uy: &[f64],
    rxs: &mut [f64],
    rys: &mut [f64],
    depth: &mut [f64],
    nxs: &mut [f64],
    nys: &mut [f64],
    rate: &mut [f64],
    status: &mut [u8],
) {
    seat_geometry::<MOVING>(
        c, xs, ys, vxs, vys, ux, uy, rxs, rys, depth, nxs, nys, rate, status,
    );
}

/// Each roller against its hinted gap, without branches: the same
/// expressions as [`Seats::contacts`] and the general pass. Slices as
/// arguments tell the compiler they do not overlap, so it vectorises the
/// loop.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn seat_geometry<const MOVING: bool>(
    c: &Consts,
    xs: &[f64],
    ys: &[f64],
    vxs: &[f64],
    vys: &[f64],
    ux: &[f64],
    uy: &[f64],
    rxs: &mut [f64],
    rys: &mut [f64],
    depth: &mut [f64],
    nxs: &mut [f64],
    nys: &mut [f64],
    rate: &mut [f64],
    status: &mut [u8],
) {
    let n = xs.len();
    let (ys, vxs, vys, ux, uy) = (&ys[..n], &vxs[..n], &vys[..n], &ux[..n], &uy[..n]);
    let (rxs, rys, depth) = (&mut rxs[..n], &mut rys[..n], &mut depth[..n]);
    let (nxs, nys, rate, status) = (
        &mut nxs[..n],
        &mut nys[..n],
        &mut rate[..n],
        &mut status[..n],
    );
    let (sin, cos, omega) = (c.sin, c.cos, c.omega);
    let (rc, clearance) = (c.seat_radius_m, c.clearance_m);
    for k in 0..n {
        let rx = xs[k] - c.center[0];
        let ry = ys[k] - c.center[1];
        // World → sprocket frame: rotate by −θ.
        let p = [cos * rx + sin * ry, -sin * rx + cos * ry];
        let u = [ux[k], uy[k]];
        let along = u[0] * p[0] + u[1] * p[1];
        let across = u[0] * p[1] - u[1] * p[0];
        let in_cone = (along > 0.0) & (across.abs() <= c.tan_half_pitch * along);
        let e = [p[0] - rc * u[0], p[1] - rc * u[1]];
        // Only the half facing the sprocket centre holds the roller, and
        // only beyond the clearance.
        let facing = !(e[0] * u[0] + e[1] * u[1] > 0.0);
        let len_sq = e[0] * e[0] + e[1] * e[1];
        let touch = facing & (len_sq > c.clearance_sq_m2);
        let len = len_sq.sqrt();
        let inv_len = 1.0 / len;
        let normal = [-e[0] * inv_len, -e[1] * inv_len];
        // Normal back to the world frame.
        let nx = cos * normal[0] - sin * normal[1];
        let ny = sin * normal[0] + cos * normal[1];
        // Velocity relative to the sprocket point under the roller.
        let v_rel = if MOVING {
            [
                vxs[k] - c.velocity[0] + omega * ry,
                vys[k] - c.velocity[1] - omega * rx,
            ]
        } else {
            [vxs[k] + omega * ry, vys[k] - omega * rx]
        };
        rxs[k] = rx;
        rys[k] = ry;
        depth[k] = len - clearance;
        nxs[k] = nx;
        nys[k] = ny;
        rate[k] = -(v_rel[0] * nx + v_rel[1] * ny);
        status[k] = u8::from(in_cone) | (u8::from(touch) << 1);
    }
}

#[cfg(test)]
mod tests {
    use super::{SeatScratch, hinted_directions};
    use crate::geometry::CircularProfile;

    #[test]
    fn kept_directions_follow_the_sprockets_table() {
        // Rollers 0–3 read their directions on sprocket 2 with 28 gaps,
        // then on a sprocket 2 of another drive with 27: the same keys
        // (sprocket, hint) but other directions, (cos jφ, sin jφ) with
        // φ = 2π/27, which must be read again. A hint past the gaps gives
        // NaN.
        let (pitch_m, roller_m) = (0.0889, 0.0254);
        let (old, new) = (
            CircularProfile::new(28, pitch_m, roller_m),
            CircularProfile::new(27, pitch_m, roller_m),
        );
        let hints = [0, 5, 13, 27];
        let mut sc = SeatScratch::new(4);
        hinted_directions(&old.seats(), 2, &hints, &mut sc, 0);
        let phi_old = std::f64::consts::TAU / 28.0;
        assert!((sc.ux[1] - (5.0 * phi_old).cos()).abs() < 1e-15);
        assert!((sc.uy[2] - (13.0 * phi_old).sin()).abs() < 1e-15);
        hinted_directions(&new.seats(), 2, &hints, &mut sc, 0);
        let phi = std::f64::consts::TAU / 27.0;
        for (k, &h) in hints.iter().enumerate().take(3) {
            let a = f64::from(h) * phi;
            assert!((sc.ux[k] - a.cos()).abs() < 1e-15, "roller {k}");
            assert!((sc.uy[k] - a.sin()).abs() < 1e-15, "roller {k}");
        }
        assert!(sc.ux[3].is_nan() && sc.uy[3].is_nan(), "hint 27 of 27 gaps");
    }
}
