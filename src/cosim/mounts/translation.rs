//! Mounted bodies that translate, integrated with the chain in the substeps.
//!
//! A dynamic mount's translation (and, for a hub on a revolute joint to a
//! carriage, the carriage's with it) is advanced at the chain's dt under the
//! chain's force on the sprocket, gravity, the users' forces (held over the
//! frame, rapier's semantics), the mount's force law ([`super::MountForce`],
//! called every substep) and a prismatic joint's motor and limits (read from
//! the user's `ImpulseJointSet`). rapier's step then moves the bodies from
//! the frame's start at the frame's mean velocity with those forces taken out.
//!
//! It does not integrate: a body whose position a joint ties to a body that
//! rapier moves on its own (a fixed or kinematic body: the translation is
//! rapier's), longer chains of jointed bodies, or joints other than one
//! prismatic (or pin-slot) joint and one revolute joint to a carriage.

use rapier2d_f64::prelude::*;

/// A prismatic (or pin-slot) joint on the translating body, imitated in the
/// substeps: its free axis, its motor and its limits.
#[derive(Clone, Copy, Debug)]
pub(in crate::cosim) struct Slide {
    pub joint: ImpulseJointHandle,
    /// The translating body is the joint's second body (else its first).
    pub moving_is_2: bool,
    pub body1: RigidBodyHandle,
    pub body2: RigidBodyHandle,
    pub frame1: Pose,
    pub frame2: Pose,
    /// The free axis in the joint's frame: 0 (x) or 1 (y).
    pub axis: usize,
    /// The motor along it, where enabled.
    pub motor: Option<JointMotor>,
    /// The limits along it, where enabled, m.
    pub limits: Option<[f64; 2]>,
}

impl Slide {
    /// The mask bit of the free axis.
    pub(in crate::cosim) fn mask(&self) -> JointAxesMask {
        if self.axis == 0 {
            JointAxesMask::LIN_X
        } else {
            JointAxesMask::LIN_Y
        }
    }
}

/// What [`crate::cosim::ChainDrive::read_joints`] found on a dynamic mount.
#[derive(Clone, Copy, Debug, Default)]
pub(in crate::cosim) struct MountJoints {
    /// A joint ties the body's position to a body rapier moves itself.
    pub fixed: bool,
    /// The dynamic body (a carriage) the mount turns on by a revolute joint:
    /// the two translate together.
    pub carrier: Option<RigidBodyHandle>,
    /// The prismatic joint along which the body (or its carrier) slides.
    pub slide: Option<Slide>,
    /// An arrangement the drive cannot run, described.
    pub unsupported: Option<&'static str>,
}

/// A dynamic body's user force, gravity scale and damping, taken out of
/// rapier's step and put back after it.
#[derive(Clone, Copy, Debug)]
pub(in crate::cosim) struct Stash {
    pub user_force: Vector,
    pub gravity_scale: f64,
    pub damping: f64,
}

/// The slide's state over one frame.
#[derive(Clone, Copy, Debug)]
pub(in crate::cosim) struct SlideFrame {
    /// The free axis, world, unit.
    pub axis: Vector,
    /// The joint's coordinate along it at the frame's start, m.
    pub dist0: f64,
    /// +1 where the translating body is the joint's second body, else −1.
    pub sign: f64,
    /// The other body's velocity (held over the frame), m/s.
    pub other_v: Vector,
    /// The other body's inverse mass along the axis (0 unless dynamic), 1/kg.
    pub other_inv_mass: f64,
    /// The motor's force on the translating body summed over the substeps,
    /// then their mean, N.
    pub motor_sum: Vector,
}

/// A dynamic mount's translation over a frame, integrated with the chain.
#[derive(Clone, Copy, Debug)]
pub(in crate::cosim) struct MountTranslation {
    /// Inverse mass per axis (zero on a locked axis) of the body and its
    /// carrier together, 1/kg.
    pub inv_mass: Vector,
    /// Gravity and the users' forces, N.
    pub force_ext: Vector,
    /// Velocity in the substeps, m/s.
    pub v: Vector,
    /// Displacement since the frame's start, m.
    pub dx: Vector,
    /// Mean velocity over the frame, given to rapier, m/s.
    pub mean_v: Vector,
    /// Linear damping (mass-weighted over the body and its carrier), 1/s.
    pub damping: f64,
    /// The mount's own stash.
    pub stash: Stash,
    /// The carrier and its stash.
    pub carrier: Option<(RigidBodyHandle, Stash)>,
    /// The prismatic joint, imitated.
    pub slide: Option<(Slide, SlideFrame)>,
}

fn stash_of(b: &RigidBody, user_force: Vector) -> Stash {
    Stash {
        user_force,
        gravity_scale: b.gravity_scale(),
        damping: b.linear_damping(),
    }
}

/// A dynamic mount's translation for the coming frame, if the substeps
/// move it: not when its translations are locked or a joint fixes its
/// position. Called between frames only (a second `before_step` before
/// `after_step` is refused), so the bodies' gravity scales and damping are
/// the user's.
pub(in crate::cosim) fn mount_translation(
    bodies: &RigidBodySet,
    body: RigidBodyHandle,
    joints: &MountJoints,
    user_force: Vector,
    gravity: Vector,
) -> Option<MountTranslation> {
    let b = bodies.get(body)?;
    if joints.fixed || joints.unsupported.is_some() {
        return None;
    }
    let stash = stash_of(b, user_force);
    let (mut inv_mass, mut mass, mut momentum) = (
        b.mass_properties().effective_inv_mass,
        b.mass(),
        b.linvel() * b.mass(),
    );
    let mut force_ext = gravity * (stash.gravity_scale * b.mass()) + user_force;
    let mut damping_mass = stash.damping * b.mass();
    let mut carrier = None;
    if let Some(h) = joints.carrier {
        let c = bodies.get(h)?;
        let cs = stash_of(c, c.user_force());
        let ci = c.mass_properties().effective_inv_mass;
        let combine = |a: f64, b: f64| {
            if a > 0.0 && b > 0.0 {
                1.0 / (1.0 / a + 1.0 / b)
            } else {
                0.0
            }
        };
        inv_mass = Vector::new(combine(inv_mass.x, ci.x), combine(inv_mass.y, ci.y));
        force_ext += gravity * (cs.gravity_scale * c.mass()) + cs.user_force;
        damping_mass += cs.damping * c.mass();
        momentum += c.linvel() * c.mass();
        mass += c.mass();
        carrier = Some((h, cs));
    }
    if inv_mass == Vector::ZERO || mass <= 0.0 {
        return None;
    }
    let mut v = momentum / mass;
    let mut slide = None;
    if let Some(s) = joints.slide {
        let (b1, b2) = (bodies.get(s.body1)?, bodies.get(s.body2)?);
        let f1 = *b1.position() * s.frame1;
        let f2 = *b2.position() * s.frame2;
        let unit = if s.axis == 0 { Vector::X } else { Vector::Y };
        let axis = (f1.rotation * unit).normalize_or_zero();
        let other = if s.moving_is_2 { b1 } else { b2 };
        let other_v = other.linvel();
        let other_inv_mass = if other.is_dynamic() {
            let i = other.mass_properties().effective_inv_mass;
            axis.x * axis.x * i.x + axis.y * axis.y * i.y
        } else {
            0.0
        };
        // Only the motion along the axis, relative to the other body, is free.
        v = other_v + axis * axis.dot(v - other_v);
        slide = Some((
            s,
            SlideFrame {
                axis,
                dist0: axis.dot(f2.translation - f1.translation),
                sign: if s.moving_is_2 { 1.0 } else { -1.0 },
                other_v,
                other_inv_mass,
                motor_sum: Vector::ZERO,
            },
        ));
    }
    Some(MountTranslation {
        inv_mass,
        force_ext,
        v,
        dx: Vector::ZERO,
        mean_v: Vector::ZERO,
        damping: damping_mass / mass,
        stash,
        carrier,
        slide,
    })
}

impl MountTranslation {
    /// One substep of `dt` (symplectic Euler, as the rollers), `tau` into
    /// the frame, under the chain's force `chain` and the law's force `law`
    /// (both at the substep's start).
    pub(in crate::cosim) fn advance(&mut self, chain: Vector, law: Vector, tau: f64, dt: f64) {
        let mut f = chain + self.force_ext + law;
        if let Some((s, sf)) = &mut self.slide {
            if let Some(m) = &s.motor {
                // rapier's motor drives the joint's coordinate to its target:
                // acceleration (or force, for a force-based motor)
                // k (x* − x) + c (v* − v), at most max_force.
                let dist = sf.dist0 + sf.sign * sf.axis.dot(self.dx - sf.other_v * tau);
                let rate = sf.sign * sf.axis.dot(self.v - sf.other_v);
                let mut fm =
                    m.stiffness * (m.target_pos - dist) + m.damping * (m.target_vel - rate);
                if m.model == MotorModel::AccelerationBased {
                    let inv = sf.axis.x * sf.axis.x * self.inv_mass.x
                        + sf.axis.y * sf.axis.y * self.inv_mass.y
                        + sf.other_inv_mass;
                    fm = if inv > 0.0 { fm / inv } else { 0.0 };
                }
                let fm = fm.clamp(-m.max_force, m.max_force);
                let on_body = sf.axis * (sf.sign * fm);
                sf.motor_sum += on_body;
                f += on_body;
            }
        }
        let mut dv = f * self.inv_mass * dt;
        if let Some((_, sf)) = &self.slide {
            dv = sf.axis * sf.axis.dot(dv);
        }
        self.v = (self.v + dv) / (1.0 + dt * self.damping);
        self.dx += self.v * dt;
        if let Some((s, sf)) = &self.slide {
            if let Some([lo, hi]) = s.limits {
                // The limits stop the body inelastically.
                let tau = tau + dt;
                let dist = sf.dist0 + sf.sign * sf.axis.dot(self.dx - sf.other_v * tau);
                let rate = sf.sign * sf.axis.dot(self.v - sf.other_v);
                let over = if dist < lo {
                    Some((lo - dist, rate < 0.0))
                } else if dist > hi {
                    Some((hi - dist, rate > 0.0))
                } else {
                    None
                };
                if let Some((back, closing)) = over {
                    self.dx += sf.axis * (sf.sign * back);
                    if closing {
                        self.v -= sf.axis * sf.axis.dot(self.v - sf.other_v);
                    }
                }
            }
        }
    }
}

/// Reads the joints on a dynamic mount `body`.
pub(in crate::cosim) fn read_mount_joints(
    bodies: &RigidBodySet,
    joints: &ImpulseJointSet,
    body: RigidBodyHandle,
) -> MountJoints {
    let mut found = MountJoints::default();
    let is_dynamic = |h: RigidBodyHandle| bodies.get(h).is_some_and(|b| b.is_dynamic());
    for (b1, b2, handle, joint) in joints.attached_joints(body) {
        let data = &joint.data;
        if !data.is_enabled() {
            continue;
        }
        let other = if b1 == body { b2 } else { b1 };
        let locked = data.locked_axes;
        let (lx, ly, ang) = (
            locked.contains(JointAxesMask::LIN_X),
            locked.contains(JointAxesMask::LIN_Y),
            locked.contains(JointAxesMask::ANG_X),
        );
        if ang && !is_dynamic(other) {
            found.unsupported = Some(
                "a joint locks the body's rotation to a fixed or kinematic body, so its sprocket \
                 cannot turn (a prismatic joint does): mount the sprocket on a hub body with a \
                 revolute joint to the carriage, or slide the body on a pin-slot joint",
            );
            continue;
        }
        match (lx, ly) {
            (false, false) => {}
            (true, true) if is_dynamic(other) && !ang => {
                if found.carrier.replace(other).is_some() {
                    found.unsupported = Some(
                        "the body turns on revolute joints to two dynamic bodies; one carriage \
                         is supported",
                    );
                }
            }
            (true, true) if is_dynamic(other) => {
                found.unsupported = Some(
                    "a fixed joint ties the body to another dynamic body; mount the sprocket on \
                     that body instead",
                );
            }
            (true, true) => found.fixed = true,
            _ => {
                if found.slide.is_some() {
                    found.fixed = true;
                }
                found.slide = Some(slide(handle, b1, b2, body, data, ly));
            }
        }
    }
    let Some(carrier) = found.carrier else {
        return found;
    };
    if found.fixed || found.slide.is_some() {
        found.unsupported = Some(
            "the body turns on a revolute joint to a carriage and has other joints tying its \
             position; joint it to the carriage only",
        );
        return found;
    }
    // The carriage's own joints: a prismatic joint, or one that fixes it.
    for (b1, b2, handle, joint) in joints.attached_joints(carrier) {
        let data = &joint.data;
        let other = if b1 == carrier { b2 } else { b1 };
        if !data.is_enabled() || other == body {
            continue;
        }
        let locked = data.locked_axes;
        let (lx, ly) = (
            locked.contains(JointAxesMask::LIN_X),
            locked.contains(JointAxesMask::LIN_Y),
        );
        match (lx, ly) {
            (false, false) => {}
            (true, true) if is_dynamic(other) => {
                found.unsupported = Some(
                    "the carriage the body turns on is jointed to a further dynamic body; one \
                     carriage on a prismatic joint (or free) is supported",
                );
            }
            (true, true) => found.fixed = true,
            _ => {
                if found.slide.is_some() {
                    found.fixed = true;
                }
                found.slide = Some(slide(handle, b1, b2, carrier, data, ly));
            }
        }
    }
    found
}

/// A joint that leaves one translation free (`ly`: y is locked, x free).
fn slide(
    joint: ImpulseJointHandle,
    body1: RigidBodyHandle,
    body2: RigidBodyHandle,
    moving: RigidBodyHandle,
    data: &GenericJoint,
    ly: bool,
) -> Slide {
    let axis = if ly { 0 } else { 1 };
    let mask = if ly {
        JointAxesMask::LIN_X
    } else {
        JointAxesMask::LIN_Y
    };
    let m = data.motors[axis];
    let motor =
        (data.motor_axes.contains(mask) && (m.stiffness != 0.0 || m.damping != 0.0)).then_some(m);
    let l = data.limits[axis];
    let limits = data.limit_axes.contains(mask).then_some([l.min, l.max]);
    Slide {
        joint,
        moving_is_2: body2 == moving,
        body1,
        body2,
        frame1: data.local_frame1,
        frame2: data.local_frame2,
        axis,
        motor,
        limits,
    }
}
