//! Parking the rollers no user collider can reach: with
//! [`ChainDrive::set_parking`] on, a roller whose body no user collider can
//! meet within the frame has its body disabled in the user's
//! `RigidBodySet` (its collider leaves rapier's broad phase, its body the
//! island solver), and enabled again, at the chain's roller, as soon as one
//! can. A roller's neighbourhood is the user collider's bounding box at the
//! frame's start, loosened by what that collider and the rollers can travel
//! in the frame (the bound [`Coupling`]'s search uses, see
//! `BodyContacts::prepare`) plus [`PARK_MARGIN_M`] for rapier's contact
//! prediction. Parking changes neither the chain (it never reads the roller
//! bodies) nor what a user's body meets; it takes the unreachable rollers
//! out of rapier's step, queries and the drive's sync, so a parked roller's
//! body stays where it was parked. Roller 0 is never parked (the check that
//! the world stepped by the drive's dt reads the roller bodies), nor are the
//! rollers near a mounted body's colliders (the sprocket's included).

use rapier2d_f64::prelude::*;

use super::*;

/// Distance beyond the frame's travel within which a user collider keeps a
/// roller in rapier's step, m: covers rapier's contact prediction distance
/// (0.002 m at a length unit of 1 m) many times over. The docs of
/// [`ChainDrive::set_parking`] quote it.
pub(crate) const PARK_MARGIN_M: f64 = 0.05;

/// Whether parking is on, and which roller bodies are in rapier's step.
#[derive(Debug)]
pub(super) struct Parking {
    /// Whether the rollers no user collider can reach are parked.
    on: bool,
    /// The rollers in rapier's step this frame (not parked).
    active: Vec<bool>,
}

impl Parking {
    /// Parking off, all of `rollers` in rapier's step.
    pub(super) fn new(rollers: usize) -> Self {
        Self {
            on: false,
            active: vec![true; rollers],
        }
    }

    /// Whether each roller is in rapier's step this frame.
    pub(super) fn active(&self) -> &[bool] {
        &self.active
    }

    /// Keeps every roller in rapier's step.
    fn keep_all(&mut self) {
        self.active.fill(true);
    }
}

impl ChainDrive {
    /// Turns parking on or off (off by default): with it on, the roller
    /// bodies no user collider can reach within a frame are disabled in the
    /// `RigidBodySet` until one can, which takes them out of rapier's step.
    /// A roller is reachable when it lies, at the frame's start, within an
    /// enabled user collider's box loosened by what the collider and the
    /// rollers can travel in the frame (the bound of the search for the
    /// user's colliders, [`Coupling::search_speed_m_s`]), the roller radius
    /// and 50 mm; colliders on mounted bodies count, and roller 0 is never
    /// parked. What the user's bodies meet does not
    /// change; a parked roller's body stays where it was parked, so draw the
    /// chain from [`Self::state`], and do not cast rays or shapes at rollers
    /// far from the user's colliders. Turning it off enables every roller
    /// body again, at its roller, at the next frame.
    pub fn set_parking(&mut self, on: bool) {
        self.parking.on = on;
    }

    /// Whether parking is on ([`Self::set_parking`]).
    pub fn parking(&self) -> bool {
        self.parking.on
    }

    /// How many roller bodies the last frame left parked (disabled).
    pub fn parked_rollers(&self) -> usize {
        self.parking.active.iter().filter(|a| !**a).count()
    }

    /// Marks the rollers a user collider can reach this frame as active in
    /// [`Parking`] (all of them with parking off), leaving the colliders
    /// of this drive and of `others` aside. Call at the frame's start, with
    /// the rollers where the frame starts.
    pub(super) fn mark_reach(
        &mut self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        others: Option<&Others<'_>>,
        frame_dt_s: f64,
    ) {
        if !self.parking.on {
            self.parking.keep_all();
            return;
        }
        self.parking.active.fill(false);
        let s = &self.state;
        if let Some(first) = self.parking.active.first_mut() {
            *first = true;
        }
        let r = self.scene.chain.roller_radius_m;
        let floor = self.coupling.search_speed_m_s.max(0.0);
        let mut chain = Aabb::new_invalid();
        let mut v_max_sq = 0.0f64;
        for i in 0..s.x.len() {
            chain.take_point(Vector::new(s.x[i], s.y[i]));
            v_max_sq = v_max_sq.max(s.vx[i] * s.vx[i] + s.vy[i] * s.vy[i]);
        }
        let roller_travel = (2.0 * v_max_sq.sqrt() + floor) * frame_dt_s;
        let reach = r + roller_travel + PARK_MARGIN_M;
        if !(chain.mins.is_finite() && chain.maxs.is_finite() && reach.is_finite()) {
            // Nothing to bound by: keep every roller in rapier's step.
            self.parking.keep_all();
            return;
        }
        let chain = chain.loosened(reach);
        let own = &self.handles;
        let owns = |h: ColliderHandle| own.owns(h) || others.is_some_and(|o| (o.owns)(h));
        for (handle, co) in colliders.iter() {
            // The rollers' own colliders first: the cheapest test, and
            // most of a large drive's world.
            if own.is_roller(handle) || !co.is_enabled() {
                continue;
            }
            if owns(handle)
                && !co
                    .parent()
                    .is_some_and(|b| self.mounts.mounted().contains(&b))
            {
                continue;
            }
            let (pose0, travel) = match co.parent().map(|b| bodies.get(b)) {
                Some(None) => continue,
                None => (*co.position(), 0.0),
                Some(Some(rb)) => {
                    // From the body's pose, which a user's teleport updates at once.
                    let pose0 = co
                        .position_wrt_parent()
                        .map_or(*co.position(), |local| *rb.position() * *local);
                    (pose0, travel_m(co, &pose0, rb, floor, frame_dt_s))
                }
            };
            let aabb = co.shape().compute_aabb(&pose0).loosened(travel);
            if !(aabb.mins.is_finite() && aabb.maxs.is_finite()) {
                self.parking.keep_all();
                return;
            }
            if !aabb.intersects(&chain) {
                continue;
            }
            let near = aabb.loosened(reach);
            for (i, active) in self.parking.active.iter_mut().enumerate() {
                *active |= near.contains_local_point(Vector::new(s.x[i], s.y[i]));
            }
        }
    }

    /// Sets the roller bodies for rapier's step: the reachable ones (all
    /// with parking off) at the frame's start with the frame's mean
    /// velocity, enabled; the others disabled where they are. Touches a
    /// parked body only when it is parked or enabled again.
    pub(super) fn sync_rollers(&mut self, bodies: &mut RigidBodySet, span: f64) {
        for (i, &h) in self.handles.rollers().iter().enumerate() {
            let Some(enabled) = bodies.get(h).map(|b| b.is_enabled()) else {
                continue;
            };
            let active = self.parking.active.get(i).copied().unwrap_or(true);
            if !active && !enabled {
                continue;
            }
            let Some(b) = bodies.get_mut(h) else {
                continue;
            };
            if active {
                let [x0, y0] = self.scratch.start()[i];
                let v = Vector::new((self.state.x[i] - x0) / span, (self.state.y[i] - y0) / span);
                b.set_translation(Vector::new(x0, y0), true);
                b.set_linvel(v, true);
                if !enabled {
                    b.set_enabled(true);
                }
            } else {
                b.set_linvel(Vector::ZERO, false);
                b.set_enabled(false);
            }
        }
    }
}

/// How far a collider on `rb` can travel in the frame, m: as the search for
/// the user's colliders bounds it (twice the frame-start speed plus the
/// search speed for a dynamic body, which contacts can speed up).
fn travel_m(co: &Collider, pose0: &Pose, rb: &RigidBody, floor: f64, frame_dt_s: f64) -> f64 {
    let com = rb.position().transform_point(rb.local_center_of_mass());
    let extent =
        co.shape().compute_aabb(pose0).extents().length() + (pose0.translation - com).length();
    match rb.body_type() {
        RigidBodyType::Fixed => 0.0,
        RigidBodyType::KinematicVelocityBased => {
            (rb.linvel().length() + rb.angvel().abs() * extent) * frame_dt_s
        }
        RigidBodyType::KinematicPositionBased => {
            let span = frame_dt_s.max(f64::MIN_POSITIVE);
            let next = rb.next_position();
            let here = rb.position();
            let next_com = next.transform_point(rb.local_center_of_mass());
            let v = (next_com - com) / span;
            let w = (next.rotation * here.rotation.inverse()).angle() / span;
            (v.length() + w.abs() * extent) * frame_dt_s
        }
        _ => (2.0 * (rb.linvel().length() + rb.angvel().abs() * extent) + floor) * frame_dt_s,
    }
}
