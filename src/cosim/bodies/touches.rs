//! Carried bodies' contacts with each other and with stops and kinematic
//! bodies ([`Touch`]): found once at the frame's start from parry's
//! manifolds, followed through the chain's substeps.

use rapier2d_f64::parry::query::details::ContactManifold;
use rapier2d_f64::prelude::*;

use super::*;

/// A contact of a carried body's collider with another collider (another
/// carried body's, a stop's, a kinematic body's), found once at the frame's
/// start and followed through the substeps.
#[derive(Clone, Copy, Debug)]
pub(super) struct Touch {
    pub(super) a: Side,
    pub(super) b: Side,
    /// The contact normal from `a` to `b`, in `a`'s collider frame.
    local_n: Vector,
    /// Contact points in `a`'s and `b`'s collider frames.
    points: [[Vector; 2]; 2],
    count: usize,
    /// Damping factor χ / δ̇⁻ per point, set at its onset in this frame.
    onset: [Option<f64>; 2],
    friction: f64,
}

/// One side of a [`Touch`]: a collider and how it moves.
#[derive(Clone, Copy, Debug)]
pub(super) struct Side {
    collider: ColliderHandle,
    pub(super) motion: Motion,
    /// Collider pose and its body's centre of mass at the frame's start.
    pose0: Pose,
    com0: Vector,
}

impl Touch {
    /// Whether it is between colliders `a` and `b`, either way round.
    fn pair_of(&self, a: ColliderHandle, b: ColliderHandle) -> bool {
        (self.a.collider == a && self.b.collider == b)
            || (self.a.collider == b && self.b.collider == a)
    }
}

/// How `co` moves this frame as a [`Touch`]'s side (a dynamic body as
/// `Carried(usize::MAX)`, not yet carried) and how far it can travel, m;
/// `None` where the coupling leaves it out.
fn side(
    co: &Collider,
    bodies: &RigidBodySet,
    coupling: &Coupling,
    floor_m_s: f64,
    frame_dt_s: f64,
) -> Option<(Side, f64)> {
    let Some(h) = co.parent() else {
        return coupling.fixed.then(|| {
            (
                Side {
                    collider: ColliderHandle::invalid(),
                    motion: Motion::Fixed,
                    pose0: *co.position(),
                    com0: Vector::ZERO,
                },
                0.0,
            )
        });
    };
    let rb = bodies.get(h)?;
    let pose0 = co
        .position_wrt_parent()
        .map_or(*co.position(), |local| *rb.position() * *local);
    let com0 = rb.position().transform_point(rb.local_center_of_mass());
    let extent = co.compute_aabb().extents().length() + (pose0.translation - com0).length();
    let span = frame_dt_s.max(f64::MIN_POSITIVE);
    let (motion, travel) = match rb.body_type() {
        RigidBodyType::Fixed if coupling.fixed => (Motion::Fixed, 0.0),
        RigidBodyType::KinematicVelocityBased if coupling.kinematic => {
            let (v, w) = (rb.linvel(), rb.angvel());
            (
                Motion::Kinematic { v, w },
                (v.length() + w.abs() * extent) * frame_dt_s,
            )
        }
        RigidBodyType::KinematicPositionBased if coupling.kinematic => {
            let next = rb.next_position();
            let v = (next.transform_point(rb.local_center_of_mass()) - com0) / span;
            let w = (next.rotation * rb.position().rotation.inverse()).angle() / span;
            (
                Motion::Kinematic { v, w },
                (v.length() + w.abs() * extent) * frame_dt_s,
            )
        }
        RigidBodyType::Dynamic if coupling.carry_dynamic => {
            let (v, w) = (rb.linvel(), rb.angvel());
            (
                Motion::Carried(usize::MAX),
                (2.0 * (v.length() + w.abs() * extent) + floor_m_s) * frame_dt_s,
            )
        }
        _ => return None,
    };
    Some((
        Side {
            collider: ColliderHandle::invalid(),
            motion,
            pose0,
            com0,
        },
        travel,
    ))
}

impl BodyContacts {
    /// Finds the contacts of carried bodies with the colliders around them
    /// (other dynamic bodies, which are then carried too, stops, kinematic
    /// bodies), at the frame's start, with a margin of the distance they can
    /// close over the frame.
    pub(super) fn find_touches(
        &mut self,
        coupling: &Coupling,
        drive: &DriveView<'_>,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        gravity: Vector,
        frame_dt_s: f64,
    ) {
        let floor = coupling.search_speed_m_s.max(0.0);
        let mut manifolds: Vec<ContactManifold<(), ()>> = Vec::new();
        let mut k = 0;
        while k < self.carried.len() {
            let body = self.carried[k].body;
            let carried_a = Motion::Carried(k);
            k += 1;
            let Some(rb) = bodies.get(body) else { continue };
            for &ha in rb.colliders() {
                let Some(ca) = colliders.get(ha) else {
                    continue;
                };
                if ca.is_sensor() || !ca.is_enabled() {
                    continue;
                }
                let Some((a, travel_a)) = side(ca, bodies, coupling, floor, frame_dt_s) else {
                    continue;
                };
                let box_a = ca.shape().compute_aabb(&a.pose0);
                for (hb, cb) in colliders.iter() {
                    if cb.parent() == Some(body) || cb.is_sensor() || !cb.is_enabled() {
                        continue;
                    }
                    let Some((b, travel_b)) = side(cb, bodies, coupling, floor, frame_dt_s) else {
                        continue;
                    };
                    // A fixed collider (a stop, a wall) is left to rapier's
                    // contact: met in the substeps as well, rapier's step
                    // answered the depth the substeps' law holds with a second
                    // push, and a box held by a stop kept 0.018 m/s off it.
                    if matches!(b.motion, Motion::Fixed) {
                        continue;
                    }
                    let margin = travel_a + travel_b;
                    if !box_a
                        .loosened(margin)
                        .intersects(&cb.shape().compute_aabb(&b.pose0))
                        || (drive.owns)(hb)
                        || cb.parent().is_some_and(|p| (drive.mounted)(p))
                        || !ca.collision_groups().test(cb.collision_groups())
                        || !ca.solver_groups().test(cb.solver_groups())
                    {
                        continue;
                    }
                    // A pair of carried bodies once.
                    if self.touches.iter().any(|t| t.pair_of(hb, ha)) {
                        continue;
                    }
                    manifolds.clear();
                    let pos12 = a.pose0.inv_mul(&b.pose0);
                    if DefaultQueryDispatcher
                        .contact_manifolds(
                            &pos12,
                            ca.shape(),
                            cb.shape(),
                            margin,
                            &mut manifolds,
                            &mut None,
                        )
                        .is_err()
                    {
                        continue;
                    }
                    let b = match (b.motion, cb.parent()) {
                        (Motion::Carried(_), Some(p))
                            if manifolds.iter().any(|m| !m.points.is_empty()) =>
                        {
                            Side {
                                motion: Motion::Carried(self.carry(p, bodies, gravity)),
                                ..b
                            }
                        }
                        _ => b,
                    };
                    let friction = CoefficientCombineRule::combine(
                        ca.friction(),
                        cb.friction(),
                        ca.friction_combine_rule(),
                        cb.friction_combine_rule(),
                    );
                    for m in &manifolds {
                        if m.points.is_empty() {
                            continue;
                        }
                        let sub1 = m.subshape_pos1().copied().unwrap_or(Pose::IDENTITY);
                        let sub2 = m.subshape_pos2().copied().unwrap_or(Pose::IDENTITY);
                        let mut points = [[Vector::ZERO; 2]; 2];
                        let mut count = 0;
                        for (slot, p) in points.iter_mut().zip(&m.points) {
                            *slot = [
                                sub1.transform_point(p.local_p1),
                                sub2.transform_point(p.local_p2),
                            ];
                            count += 1;
                        }
                        self.moving = true;
                        self.touches.push(Touch {
                            a: Side {
                                collider: ha,
                                motion: carried_a,
                                ..a
                            },
                            b: Side { collider: hb, ..b },
                            local_n: sub1.rotation * m.local_n1,
                            points,
                            count,
                            onset: [None; 2],
                            friction,
                        });
                    }
                }
            }
        }
    }

    /// Carried bodies' contacts with each other and with the colliders
    /// around them, by the same law as the rollers' (normal: the drive's
    /// contact law at the tracked points; friction: Coulomb, capped by the
    /// pair's relative tangential speed over one substep).
    pub(super) fn apply_touches(&mut self, coupling: &Coupling, tau_s: f64, dt_s: f64) {
        let carried = &mut self.carried;
        let at = |side: &Side,
                  carried: &[Carried]|
         -> Option<(Pose, Vector, Vector, f64, Option<usize>)> {
            let (dx, dtheta, v, w, k) = match side.motion {
                Motion::Fixed => (Vector::ZERO, 0.0, Vector::ZERO, 0.0, None),
                Motion::Kinematic { v, w } => (v * tau_s, w * tau_s, v, w, None),
                Motion::Carried(k) => {
                    let c = carried.get(k)?;
                    (c.dx, c.dtheta, c.v, c.w, Some(k))
                }
            };
            let rot = Rotation::new(dtheta);
            let com = side.com0 + dx;
            let pose = Pose::from_parts(
                com + rot * (side.pose0.translation - side.com0),
                rot * side.pose0.rotation,
            );
            Some((pose, com, v, w, k))
        };
        let inv_at = |k: Option<usize>, carried: &[Carried], lever: Vector, t: Vector| {
            k.and_then(|k| carried.get(k)).map_or(0.0, |c| {
                let arm = lever.perp_dot(t);
                f64::from(c.contacts_last)
                    * (t.x * t.x * c.inv_mass.x
                        + t.y * t.y * c.inv_mass.y
                        + c.inv_inertia * arm * arm)
            })
        };
        for touch in &mut self.touches {
            let (Some(a), Some(b)) = (at(&touch.a, &carried[..]), at(&touch.b, &carried[..]))
            else {
                continue;
            };
            let (pose_a, com_a, v_a, w_a, ka) = a;
            let (pose_b, com_b, v_b, w_b, kb) = b;
            let n = pose_a.rotation * touch.local_n;
            for (p, onset) in touch.points[..touch.count].iter().zip(&mut touch.onset) {
                let (pa, pb) = (pose_a.transform_point(p[0]), pose_b.transform_point(p[1]));
                let depth = -(pb - pa).dot(n);
                if !(depth > 0.0) {
                    *onset = None;
                    continue;
                }
                let point = (pa + pb) * 0.5;
                let (la, lb) = (point - com_a, point - com_b);
                let v_rel = (v_b + w_b * lb.perp()) - (v_a + w_a * la.perp());
                let rate = -v_rel.dot(n);
                let damping = *onset.get_or_insert_with(|| coupling.law.damping_per_speed(rate));
                let f_n = coupling.law.force_with(depth, rate, damping);
                self.max_depth_m = self.max_depth_m.max(depth);
                let t = n.perp();
                let v_t = v_rel.dot(t);
                let inv = inv_at(ka, &carried[..], la, t) + inv_at(kb, &carried[..], lb, t);
                let stick = if inv > 0.0 {
                    v_t.abs() / (inv * dt_s)
                } else {
                    0.0
                };
                // The force on b; its reaction on a.
                let f = n * f_n - t * (v_t.signum() * (touch.friction * f_n).min(stick));
                if let Some(c) = ka.and_then(|k| carried.get_mut(k)) {
                    c.force -= f;
                    c.torque -= la.perp_dot(f);
                    c.contacts_now += 1;
                }
                if let Some(c) = kb.and_then(|k| carried.get_mut(k)) {
                    c.force += f;
                    c.torque += lb.perp_dot(f);
                    c.contacts_now += 1;
                }
            }
        }
    }
}
