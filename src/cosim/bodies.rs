//! The user's colliders inside the chain's substeps.
//!
//! rapier exchanges no contact forces between the drive's kinematic roller
//! bodies and fixed or kinematic bodies, and treats the rollers as infinitely
//! heavy against dynamic ones. So the drive handles the rollers' contacts with
//! the user's colliders itself, inside its substeps at the scene's `dt_s`:
//!
//! - **fixed** colliders (and colliders without a body) push the rollers:
//!   guides, rails, stops;
//! - **kinematic** bodies' colliders push them too, moved over the frame at
//!   the body's velocity (velocity-based) or towards its next kinematic
//!   position (position-based);
//! - **dynamic** bodies near the chain are *carried*: integrated beside the
//!   chain at the small dt for the frame (a rigid body under its gravity, its
//!   user force and torque, and the rollers' contacts), then handed to rapier
//!   at their frame-start pose with the frame's mean velocity and no gravity,
//!   user force or damping (the substeps applied them), so rapier's step lands them where the substeps did while
//!   its other contacts and joints act on them as usual. What rapier's step
//!   changed in their velocity is added to the substeps' end velocity, less
//!   the part of the substeps' late change that points into a contact rapier
//!   pushed them with. The
//!   chain and a heavy box therefore meet at the substeps' dt, not with a
//!   frame's lag — the explicit lag pumps energy into a light roller under a
//!   heavy body (100 roller masses blow it up).
//!
//! Which pairs: once per frame, every collider that is not the drive's, not a
//! sensor, enabled, not on a mounted sprocket's body, and whose collision
//! groups accept the roller's, is tested against the chain's bounding box;
//! the rollers within its reach for the frame (the same bound as the
//! sprocket contact culling: twice the fastest speed plus a floor, over the
//! frame) form the pair list. Per substep, a pair costs a point-in-box test
//! and, when the roller is inside the collider's box grown by the roller
//! radius, one point projection; a pair found apart by a gap g is skipped
//! for g / (the same speed bounds). No pair, no work. The user's pair-filter
//! hooks are not consulted for these contacts (use collision groups).
//!
//! # Contact law
//!
//! A roller is a disc of radius R_r about its point mass at c. With p the
//! closest point of the collider's boundary (parry's point projection):
//!
//! ```text
//! δ = R_r − |c − p|  (c outside the shape)      n̂ = (c − p) / |c − p|
//! δ = R_r + |c − p|  (c inside a solid shape)   n̂ = (p − c) / |c − p|
//! f_n = K δⁿ (1 + χ δ̇ / δ̇⁻) ≥ 0                  (Hunt–Crossley family)
//! |f_t| = min(μ f_n, m_eff |v_t| / dt)           against the relative tangential speed v_t
//! ```
//!
//! The normal law (docs/model.md, “Contact law”) is the drive's roller–tooth
//! law by default (its K_g, n, e, δ̇⁻ floor; [`Coupling::new`] with another
//! [`Contact`](crate::scene::Contact) to change it),
//! δ̇⁻ remembered per (roller, collider) from onset to separation. μ combines
//! the roller collider's and the other collider's friction coefficients by
//! rapier's combine rules. Friction below the Coulomb limit removes the pair's
//! relative tangential speed in one substep for the pair's effective mass (the
//! roller's mass in series with the body's translational and rotational mass at
//! p, the body's share divided among its roller contacts): sticking without a
//! regularisation speed, and unconditionally stable. The force acts at the
//! roller's centre on the roller, its reaction at p on a carried body.
//!
//! Not modelled: roller rotation (rollers slide, they do not roll, on a
//! guide: give the guide a low friction to stand for rolling), contacts of
//! the user's bodies with the drive's own sprockets (rapier's, one-way).
//! What rapier's step does to a carried body (its other contacts, joints)
//! moves it by dt · Δv from where the substeps left it: the chain meets that
//! a frame later, as it would an impulse.

use rapier2d_f64::parry::bounding_volume::Aabb;
use rapier2d_f64::parry::query::{DefaultQueryDispatcher, PersistentQueryDispatcher};
use rapier2d_f64::prelude::*;

mod shared;
mod touches;
use touches::Touch;

use crate::forces::{ContactLawParams, Forces};
use crate::model::DriveState;
use crate::scene::Contact;

/// How the drive treats the user's colliders near its rollers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coupling {
    /// Fixed colliders (and colliders with no body) push the rollers.
    pub fixed: bool,
    /// Kinematic bodies' colliders push the rollers.
    pub kinematic: bool,
    /// Dynamic bodies near the chain are carried in the substeps; `false`
    /// leaves them to rapier's contact with the kinematic rollers, whose
    /// impulses reach the chain a frame later (stable only for bodies not
    /// much heavier than a roller).
    pub carry_dynamic: bool,
    /// Normal law between a roller and a user's collider.
    pub(crate) law: ContactLawParams,
    /// Speed floor of the once-per-frame pair search, m/s: a roller or body
    /// is assumed to travel at most (2 v + this) · dt over the frame.
    pub search_speed_m_s: f64,
    /// With the circular tooth form, a roller beside its seat (radially
    /// outside the seat's centre) meets the tooth's tip, the seating arc's
    /// end, instead of nothing: needed where the chain can go slack (a
    /// released carriage), whose rollers slide over the teeth and would
    /// otherwise meet the arc at a depth at once and blow up. Off by
    /// default (the paper's form, whose runs it would change); the real
    /// tooth form has its tips regardless.
    pub tooth_tips: bool,
}

impl Coupling {
    /// Everything coupled, with `contact`'s law between a roller and a
    /// user's collider: the scene's own `contact` gives the roller–tooth
    /// law; another (a softer stiffness for a rubber-faced box, a lower
    /// restitution) changes it for the user's colliders only.
    pub fn new(contact: &Contact) -> Self {
        Self {
            fixed: true,
            kinematic: true,
            carry_dynamic: true,
            law: ContactLawParams::new(contact),
            search_speed_m_s: 5.0,
            tooth_tips: false,
        }
    }
}

/// How an obstacle moves over the frame.
#[derive(Clone, Copy, Debug)]
enum Motion {
    Fixed,
    /// Moved at constant velocity about its body's centre of mass.
    Kinematic {
        v: Vector,
        w: f64,
    },
    /// Integrated in the substeps: index into `carried`.
    Carried(usize),
}

/// One of the user's colliders near the chain, for this frame.
#[derive(Clone, Debug)]
struct Obstacle {
    collider: ColliderHandle,
    shape: SharedShape,
    /// Collider pose at the frame's start.
    pose0: Pose,
    /// Its body's centre of mass at the frame's start (what it turns about).
    com0: Vector,
    motion: Motion,
    /// Pose at the current substep.
    pose: Pose,
    /// Centre of mass at the current substep.
    com: Vector,
    /// Bounding box at the current substep grown by the roller radius.
    reach: Aabb,
    /// Bound on the speed at which a roller and it can close, m/s.
    closing_m_s: f64,
}

/// A dynamic body integrated in the substeps for this frame.
#[derive(Clone, Copy, Debug)]
struct Carried {
    body: RigidBodyHandle,
    inv_mass: Vector,
    inv_inertia: f64,
    /// Centre-of-mass displacement and rotation since the frame's start.
    dx: Vector,
    dtheta: f64,
    v: Vector,
    w: f64,
    /// Gravity and user force (constant over the frame), N; user torque, N·m.
    force_ext: Vector,
    torque_ext: f64,
    /// The rollers' force and torque on it in this substep.
    force: Vector,
    torque: f64,
    /// Roller contacts in the last substep (≥ 1) and in this one.
    contacts_last: u32,
    contacts_now: u32,
    /// Stashed for rapier's step.
    user_force: Vector,
    user_torque: f64,
    gravity_scale: f64,
    /// rapier's linear and angular damping, 1/s (applied in the substeps).
    damping: [f64; 2],
    /// Velocities given to rapier for its step.
    mean_v: Vector,
    mean_w: f64,
    /// The rollers' force on it summed over the substeps, then their mean, N.
    chain_force: Vector,
    /// Whether other drives of a set carry it too in this frame (each
    /// integrates it with the sum of all their forces, [`Self::total`]).
    shared: bool,
    /// Whether this drive hands it to rapier's step and reads it back
    /// (the one drive of a set that keeps it; always, when not shared).
    keeper: bool,
    /// The force and torque of every drive carrying it in this substep,
    /// N and N·m (when shared).
    total: (Vector, f64),
}

#[derive(Clone, Copy, Debug)]
struct Pair {
    roller: usize,
    obstacle: usize,
    friction: f64,
    /// Time into the frame before which the pair cannot touch, s: its last
    /// gap over the bound on its closing speed.
    free_until_s: f64,
}

/// Remembered contact onset of a roller with one collider.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Onset {
    collider: Option<ColliderHandle>,
    damping_per_speed: f64,
}

const NO_ONSET: Onset = Onset {
    collider: None,
    damping_per_speed: 0.0,
};

/// Onsets remembered per roller (a roller touching more colliders at once
/// reuses the last slot).
const ONSETS: usize = 2;

/// What the drive needs to know about itself to find pairs.
pub(super) struct DriveView<'a> {
    pub owns: &'a dyn Fn(ColliderHandle) -> bool,
    pub mounted: &'a dyn Fn(RigidBodyHandle) -> bool,
    pub roller_colliders: &'a [ColliderHandle],
    pub state: &'a DriveState,
}

/// Per-frame state of the coupling to the user's colliders, buffers reused.
#[derive(Clone, Debug, Default)]
pub(super) struct BodyContacts {
    obstacles: Vec<Obstacle>,
    carried: Vec<Carried>,
    pairs: Vec<Pair>,
    touches: Vec<Touch>,
    onsets: Vec<[Onset; ONSETS]>,
    /// Sum over the frame's substeps of each roller's force from the user's colliders, N.
    roller_force_sum: Vec<[f64; 2]>,
    /// Its mean over the last frame, N.
    pub roller_force_mean: Vec<Vector>,
    /// Deepest roller penetration into a user's collider this frame, m.
    pub max_depth_m: f64,
    /// Point projections done, summed over frames.
    pub projections: u64,
    /// Whether some moving obstacle needs its pose recomputed per substep.
    moving: bool,
    roller_mass_kg: f64,
    roller_radius_m: f64,
}

impl BodyContacts {
    pub(super) fn new(rollers: usize, roller_mass_kg: f64, roller_radius_m: f64) -> Self {
        Self {
            roller_mass_kg,
            roller_radius_m,
            onsets: vec![[NO_ONSET; ONSETS]; rollers],
            roller_force_sum: vec![[0.0; 2]; rollers],
            roller_force_mean: vec![Vector::ZERO; rollers],
            ..Self::default()
        }
    }

    /// Whether any pair is active this frame.
    pub(super) fn is_empty(&self) -> bool {
        self.pairs.is_empty() && self.touches.is_empty() && self.carried.is_empty()
    }

    /// Whether `body` is carried this frame.
    pub(super) fn carries(&self, body: RigidBodyHandle) -> bool {
        self.carried.iter().any(|c| c.body == body)
    }

    /// Bodies carried this frame, with their roller pairs.
    pub(super) fn carried_pairs(&self) -> impl Iterator<Item = (RigidBodyHandle, usize)> + '_ {
        self.carried.iter().enumerate().map(|(k, c)| {
            let pairs = self
                .pairs
                .iter()
                .filter(|p| {
                    self.obstacles
                        .get(p.obstacle)
                        .is_some_and(|o| matches!(o.motion, Motion::Carried(j) if j == k))
                })
                .count();
            (c.body, pairs)
        })
    }

    /// Leaves `body` to another drive for this frame: it is no longer
    /// carried here, and its colliders touch neither the rollers nor the
    /// bodies carried here (the drive that carries it meets them).
    pub(super) fn release(&mut self, body: RigidBodyHandle) {
        let Some(k) = self.carried.iter().position(|c| c.body == body) else {
            return;
        };
        self.carried.remove(k);
        // The released body's obstacles become fixed and lose their pairs.
        let moved = |m: &mut Motion| match *m {
            Motion::Carried(j) if j == k => {
                *m = Motion::Fixed;
                false
            }
            Motion::Carried(j) if j > k => {
                *m = Motion::Carried(j - 1);
                true
            }
            _ => true,
        };
        let kept: Vec<bool> = self
            .obstacles
            .iter_mut()
            .map(|ob| moved(&mut ob.motion))
            .collect();
        self.pairs
            .retain(|p| kept.get(p.obstacle).copied().unwrap_or(false));
        self.touches
            .retain_mut(|t| moved(&mut t.a.motion) & moved(&mut t.b.motion));
    }

    /// The rollers' mean force on a carried body over the frame, N.
    pub(super) fn chain_force_on(&self, body: RigidBodyHandle) -> Option<Vector> {
        self.carried
            .iter()
            .find(|c| c.body == body)
            .map(|c| c.chain_force)
    }

    /// Finds this frame's obstacles and pairs; stashes carried bodies'
    /// gravity and user forces. Call once at the frame's start.
    pub(super) fn prepare(
        &mut self,
        coupling: &Coupling,
        drive: &DriveView<'_>,
        bodies: &mut RigidBodySet,
        colliders: &ColliderSet,
        gravity: Vector,
        frame_dt_s: f64,
    ) {
        self.obstacles.clear();
        self.carried.clear();
        self.pairs.clear();
        self.touches.clear();
        self.roller_force_sum.fill([0.0; 2]);
        self.max_depth_m = 0.0;
        self.moving = false;
        let s = drive.state;
        if !(coupling.fixed || coupling.kinematic || coupling.carry_dynamic) || s.x.is_empty() {
            return;
        }
        let r = self.roller_radius_m;
        let floor = coupling.search_speed_m_s.max(0.0);
        let mut chain = Aabb::new_invalid();
        let mut v_max_sq = 0.0f64;
        for i in 0..s.x.len() {
            chain.take_point(Vector::new(s.x[i], s.y[i]));
            v_max_sq = v_max_sq.max(s.vx[i] * s.vx[i] + s.vy[i] * s.vy[i]);
        }
        let roller_travel = (2.0 * v_max_sq.sqrt() + floor) * frame_dt_s;
        let chain = chain.loosened(r + roller_travel);
        if !chain.mins.is_finite() || !chain.maxs.is_finite() {
            return;
        }
        for (handle, co) in colliders.iter() {
            if (drive.owns)(handle) || co.is_sensor() || !co.is_enabled() {
                continue;
            }
            let (motion, pose0, com0, travel) = match co
                .parent()
                .and_then(|b| bodies.get(b).map(|rb| (b, rb)))
            {
                None if co.parent().is_some() => continue,
                None => (Motion::Fixed, *co.position(), Vector::ZERO, 0.0),
                Some((b, rb)) => {
                    if (drive.mounted)(b) {
                        continue;
                    }
                    let pose0 = co
                        .position_wrt_parent()
                        .map_or(*co.position(), |local| *rb.position() * *local);
                    // From the pose, which a user's teleport updates at once.
                    let com = rb.position().transform_point(rb.local_center_of_mass());
                    let extent =
                        co.compute_aabb().extents().length() + (pose0.translation - com).length();
                    match rb.body_type() {
                        RigidBodyType::Fixed if coupling.fixed => (Motion::Fixed, pose0, com, 0.0),
                        RigidBodyType::KinematicVelocityBased if coupling.kinematic => {
                            let (v, w) = (rb.linvel(), rb.angvel());
                            let travel = (v.length() + w.abs() * extent) * frame_dt_s;
                            (Motion::Kinematic { v, w }, pose0, com, travel)
                        }
                        RigidBodyType::KinematicPositionBased if coupling.kinematic => {
                            let span = frame_dt_s.max(f64::MIN_POSITIVE);
                            let next = rb.next_position();
                            let here = rb.position();
                            let next_com = next.transform_point(rb.local_center_of_mass());
                            let v = (next_com - com) / span;
                            let w = (next.rotation * here.rotation.inverse()).angle() / span;
                            let travel = (v.length() + w.abs() * extent) * frame_dt_s;
                            (Motion::Kinematic { v, w }, pose0, com, travel)
                        }
                        RigidBodyType::Dynamic if coupling.carry_dynamic => {
                            let (v, w) = (rb.linvel(), rb.angvel());
                            let travel =
                                (2.0 * (v.length() + w.abs() * extent) + floor) * frame_dt_s;
                            (Motion::Carried(usize::MAX), pose0, com, travel)
                        }
                        _ => continue,
                    }
                }
            };
            let shape = co.shared_shape().clone();
            let aabb = shape.compute_aabb(&pose0).loosened(travel);
            if !aabb.intersects(&chain) {
                continue;
            }
            let near = aabb.loosened(r + roller_travel);
            let groups = co.collision_groups();
            let first_pair = self.pairs.len();
            let obstacle = self.obstacles.len();
            for i in 0..s.x.len() {
                if !near.contains_local_point(Vector::new(s.x[i], s.y[i])) {
                    continue;
                }
                let Some(roller) = drive
                    .roller_colliders
                    .get(i)
                    .and_then(|&h| colliders.get(h))
                else {
                    continue;
                };
                if !roller.collision_groups().test(groups)
                    || !roller.solver_groups().test(co.solver_groups())
                {
                    continue;
                }
                let friction = CoefficientCombineRule::combine(
                    roller.friction(),
                    co.friction(),
                    roller.friction_combine_rule(),
                    co.friction_combine_rule(),
                );
                self.pairs.push(Pair {
                    roller: i,
                    obstacle,
                    friction,
                    free_until_s: 0.0,
                });
            }
            if self.pairs.len() == first_pair {
                continue;
            }
            let motion = match motion {
                Motion::Carried(_) => {
                    let Some(b) = co.parent() else { continue };
                    Motion::Carried(self.carry(b, bodies, gravity))
                }
                m => m,
            };
            self.moving |= !matches!(motion, Motion::Fixed);
            self.obstacles.push(Obstacle {
                collider: handle,
                reach: shape.compute_aabb(&pose0).loosened(r),
                shape,
                pose0,
                com0,
                motion,
                pose: pose0,
                com: com0,
                closing_m_s: (roller_travel + travel) / frame_dt_s.max(f64::MIN_POSITIVE),
            });
        }
        self.find_touches(coupling, drive, bodies, colliders, gravity, frame_dt_s);
    }

    /// The index of `body` in `carried`, adding it.
    fn carry(&mut self, body: RigidBodyHandle, bodies: &RigidBodySet, gravity: Vector) -> usize {
        if let Some(k) = self.carried.iter().position(|c| c.body == body) {
            return k;
        }
        let Some(rb) = bodies.get(body) else {
            return usize::MAX;
        };
        let props = rb.mass_properties();
        let scale = rb.gravity_scale();
        self.carried.push(Carried {
            body,
            inv_mass: props.effective_inv_mass,
            inv_inertia: props.effective_world_inv_inertia,
            dx: Vector::ZERO,
            dtheta: 0.0,
            v: rb.linvel(),
            w: rb.angvel(),
            force_ext: gravity * (scale * rb.mass()) + rb.user_force(),
            torque_ext: rb.user_torque(),
            force: Vector::ZERO,
            torque: 0.0,
            contacts_last: 1,
            contacts_now: 0,
            user_force: rb.user_force(),
            user_torque: rb.user_torque(),
            gravity_scale: scale,
            damping: [rb.linear_damping(), rb.angular_damping()],
            mean_v: Vector::ZERO,
            mean_w: 0.0,
            chain_force: Vector::ZERO,
            shared: false,
            keeper: true,
            total: (Vector::ZERO, 0.0),
        });
        self.carried.len() - 1
    }

    /// Adds the user's colliders' forces at the chain's current state (and
    /// `tau_s` into the frame) to the roller forces `fx`, `fy`; accumulates
    /// their reactions on carried bodies.
    pub(super) fn apply(
        &mut self,
        coupling: &Coupling,
        state: &DriveState,
        forces: &mut Forces,
        tau_s: f64,
        dt_s: f64,
    ) {
        let (x, y, vx, vy) = (&state.x, &state.y, &state.vx, &state.vy);
        let (fx, fy) = (&mut forces.fx, &mut forces.fy);
        let roller_radius_m = self.roller_radius_m;
        if self.moving {
            for c in &mut self.carried {
                c.contacts_last = c.contacts_now.max(1);
                c.contacts_now = 0;
                c.force = Vector::ZERO;
                c.torque = 0.0;
            }
            for ob in &mut self.obstacles {
                let (dx, dtheta) = match ob.motion {
                    Motion::Fixed => continue,
                    Motion::Kinematic { v, w } => (v * tau_s, w * tau_s),
                    Motion::Carried(k) => match self.carried.get(k) {
                        Some(c) => (c.dx, c.dtheta),
                        None => continue,
                    },
                };
                let rot = Rotation::new(dtheta);
                ob.com = ob.com0 + dx;
                ob.pose = Pose::from_parts(
                    ob.com + rot * (ob.pose0.translation - ob.com0),
                    rot * ob.pose0.rotation,
                );
                ob.reach = ob.shape.compute_aabb(&ob.pose).loosened(roller_radius_m);
            }
        }
        let inv_roller = 1.0 / self.roller_mass_kg;
        for pair in &mut self.pairs {
            if tau_s < pair.free_until_s {
                continue;
            }
            let i = pair.roller;
            let Some(ob) = self.obstacles.get(pair.obstacle) else {
                continue;
            };
            let (Some(&px), Some(&py), Some(&ux), Some(&uy), Some(onsets)) = (
                x.get(i),
                y.get(i),
                vx.get(i),
                vy.get(i),
                self.onsets.get_mut(i),
            ) else {
                continue;
            };
            let centre = Vector::new(px, py);
            if !ob.reach.contains_local_point(centre) {
                forget(onsets, ob.collider);
                continue;
            }
            let proj = ob.shape.project_point(&ob.pose, centre, false);
            self.projections += 1;
            let d = centre - proj.point;
            let dist = d.length();
            let depth = if proj.is_inside {
                roller_radius_m + dist
            } else {
                roller_radius_m - dist
            };
            // A centre exactly on the surface has no normal: no force this substep.
            let Some(out) = d.try_normalize() else {
                continue;
            };
            if !(depth > 0.0) {
                forget(onsets, ob.collider);
                // Not before the gap could close (at the bounds the pair search used).
                if ob.closing_m_s > 0.0 {
                    pair.free_until_s = tau_s + (-depth) / ob.closing_m_s;
                }
                continue;
            }
            let n = if proj.is_inside { -out } else { out };
            let lever = proj.point - ob.com;
            let (v_body, carried) = match ob.motion {
                Motion::Fixed => (Vector::ZERO, None),
                Motion::Kinematic { v, w } => (v + w * lever.perp(), None),
                Motion::Carried(k) => match self.carried.get(k) {
                    Some(c) => (c.v + c.w * lever.perp(), Some(k)),
                    None => continue,
                },
            };
            let v_rel = Vector::new(ux, uy) - v_body;
            let rate = -v_rel.dot(n);
            let damping = remember(onsets, ob.collider, &coupling.law, rate);
            let f_n = coupling.law.force_with(depth, rate, damping);
            self.max_depth_m = self.max_depth_m.max(depth);
            let t = n.perp();
            let v_t = v_rel.dot(t);
            let inv_body_t = carried.and_then(|k| self.carried.get(k)).map_or(0.0, |c| {
                let arm = lever.perp_dot(t);
                f64::from(c.contacts_last)
                    * (t.x * t.x * c.inv_mass.x
                        + t.y * t.y * c.inv_mass.y
                        + c.inv_inertia * arm * arm)
            });
            let stick = v_t.abs() / ((inv_roller + inv_body_t) * dt_s);
            let f_t = -v_t.signum() * (pair.friction * f_n).min(stick);
            let f = n * f_n + t * f_t;
            if let (Some(gx), Some(gy)) = (fx.get_mut(i), fy.get_mut(i)) {
                *gx += f.x;
                *gy += f.y;
            }
            if let Some(sum) = self.roller_force_sum.get_mut(i) {
                sum[0] += f.x;
                sum[1] += f.y;
            }
            if let Some(c) = carried.and_then(|k| self.carried.get_mut(k)) {
                c.force -= f;
                c.torque -= lever.perp_dot(f);
                c.contacts_now += 1;
            }
        }
        self.apply_touches(coupling, tau_s, dt_s);
    }

    /// Advances the carried bodies by one substep (symplectic Euler, as the
    /// chain; rapier's damping as rapier applies it, v / (1 + dt c)).
    pub(super) fn integrate(&mut self, dt_s: f64) {
        for c in &mut self.carried {
            let (force, torque) = if c.shared {
                c.total
            } else {
                (c.force, c.torque)
            };
            c.v += (c.force_ext + force) * c.inv_mass * dt_s;
            c.w += (c.torque_ext + torque) * c.inv_inertia * dt_s;
            c.chain_force += c.force;
            c.v /= 1.0 + dt_s * c.damping[0];
            c.w /= 1.0 + dt_s * c.damping[1];
            c.dx += c.v * dt_s;
            c.dtheta += c.w * dt_s;
        }
    }

    /// Ends the frame's substeps: mean roller forces over `substeps`, carried
    /// bodies set for rapier's step (frame-start pose, mean velocity, no
    /// gravity or user force: the substeps applied them). Returns false,
    /// touching no body, if a carried body's state is not finite.
    pub(super) fn finish_substeps(
        &mut self,
        bodies: &mut RigidBodySet,
        substeps: u64,
        frame_dt_s: f64,
    ) -> bool {
        let n = substeps.max(1) as f64;
        for (mean, sum) in self
            .roller_force_mean
            .iter_mut()
            .zip(&self.roller_force_sum)
        {
            *mean = Vector::new(sum[0] / n, sum[1] / n);
        }
        let span = frame_dt_s.max(f64::MIN_POSITIVE);
        for c in &mut self.carried {
            c.chain_force /= n;
            c.mean_v = c.dx / span;
            c.mean_w = c.dtheta / span;
            let finite = c.v.is_finite() && c.w.is_finite();
            if !(finite && c.mean_v.is_finite() && c.mean_w.is_finite()) {
                return false;
            }
        }
        for c in self.carried.iter().filter(|c| c.keeper) {
            if let Some(rb) = bodies.get_mut(c.body) {
                rb.set_linvel(c.mean_v, true);
                rb.set_angvel(c.mean_w, true);
                rb.reset_forces(false);
                rb.reset_torques(false);
                rb.set_gravity_scale(0.0, true);
                rb.set_linear_damping(0.0);
                rb.set_angular_damping(0.0);
            }
        }
        true
    }

    /// After rapier's step: carried bodies get the substeps' end velocity
    /// plus what rapier's step changed; their gravity, user forces and
    /// damping are restored. rapier only saw the frame's mean velocity: where
    /// one of its contacts pushed the body (a stop, a wall), the part of the
    /// substeps' late velocity change that still points into that contact is
    /// dropped, so a body held by a stop stays held.
    pub(super) fn after_step(
        &mut self,
        bodies: &mut RigidBodySet,
        narrow_phase: &NarrowPhase,
        is_roller: &dyn Fn(ColliderHandle) -> bool,
    ) {
        for c in self.carried.iter().filter(|c| c.keeper) {
            let Some(rb) = bodies.get_mut(c.body) else {
                continue;
            };
            let dv = rb.linvel() - c.mean_v;
            let dw = rb.angvel() - c.mean_w;
            let mut late = c.v - c.mean_v;
            for &own in rb.colliders() {
                for pair in narrow_phase.contact_pairs_with(own) {
                    let other = if pair.collider1 == own {
                        pair.collider2
                    } else {
                        pair.collider1
                    };
                    if is_roller(other) || !pair.has_any_active_contact() {
                        continue;
                    }
                    // rapier pushes collider 1's body along −normal, collider 2's along +normal.
                    let sign = if pair.collider1 == own { -1.0 } else { 1.0 };
                    for manifold in pair.manifolds() {
                        if manifold.points.iter().all(|p| !(p.data.impulse > 0.0)) {
                            continue;
                        }
                        let push = manifold.data.normal * sign;
                        let into = late.dot(push);
                        if into < 0.0 {
                            late -= push * into;
                        }
                    }
                }
            }
            rb.set_linvel(c.mean_v + late + dv, true);
            rb.set_angvel(c.w + dw, true);
            rb.set_gravity_scale(c.gravity_scale, true);
            rb.set_linear_damping(c.damping[0]);
            rb.set_angular_damping(c.damping[1]);
            rb.add_force(c.user_force, false);
            rb.add_torque(c.user_torque, false);
        }
    }
}

/// The damping factor χ / δ̇⁻ remembered for `collider`, set at onset.
fn remember(
    onsets: &mut [Onset; ONSETS],
    collider: ColliderHandle,
    law: &ContactLawParams,
    rate: f64,
) -> f64 {
    if let Some(o) = onsets.iter().find(|o| o.collider == Some(collider)) {
        return o.damping_per_speed;
    }
    let slot = onsets
        .iter()
        .position(|o| o.collider.is_none())
        .unwrap_or(ONSETS - 1);
    let damping_per_speed = law.damping_per_speed(rate);
    onsets[slot] = Onset {
        collider: Some(collider),
        damping_per_speed,
    };
    damping_per_speed
}

/// Forgets `collider`'s onset (the contact separated).
fn forget(onsets: &mut [Onset; ONSETS], collider: ColliderHandle) {
    for o in onsets.iter_mut() {
        if o.collider == Some(collider) {
            *o = NO_ONSET;
        }
    }
}
