//! Each sprocket's rapier body and what a frame does to it: [`Mounts`].
//!
//! A sprocket sits on the drive's own kinematic body or on the user's body
//! (a mount, [`Mount`]). Per frame, [`Mounts`] reads every mounted body at
//! the frame's start (its centre, speed and the user's torque and force,
//! taken out of rapier's step), moves the centres through the substeps,
//! hands the bodies to rapier's step at the frame's mean motion, and puts
//! the users' torques, forces and gravity scales back after it; between
//! frames it holds the mounts' force laws ([`MountForce`]), their joints
//! and the joint motors the substeps imitate. A dynamic mount's translation
//! is integrated in `translation`.
//!
//! It does not step the chain, read the user's colliders near it, or check
//! the world: [`super::ChainDrive`]'s frame does, and hands this the
//! sprockets' part.

mod translation;

use rapier2d_f64::prelude::*;

pub(super) use translation::MountJoints;
use translation::{MountTranslation, mount_translation, read_mount_joints};

use super::error::CosimError;
use crate::model::{DriveState, SprocketModel};
use crate::scene::SpeedLaw;

/// A force law on a mounted body, evaluated in every substep of the chain
/// with the body's position and velocity there: the way to attach a spring
/// (or any stiff force) to a mount. A force set with rapier's `add_force`
/// is read once per frame and held constant over it, while the body moves
/// with the chain inside the frame; a stiff spring held that way lags the
/// carriage and can drive it unstable (docs/architecture.md, "Mounted
/// sprockets"). See [`crate::cosim::ChainDrive::set_mount_force`].
///
/// Any `Fn(position_m, velocity_m_s, t_s) -> force_n` that is `Send + Sync`
/// is one; [`MountSpring`] is the linear spring–damper.
pub trait MountForce: Send + Sync {
    /// The force on the body, N (world frame), with the body's centre at
    /// `position_m` moving at `velocity_m_s`, at the drive's time `t_s`.
    fn force(&self, position_m: Vector, velocity_m_s: Vector, t_s: f64) -> Vector;
}

impl<F> MountForce for F
where
    F: Fn(Vector, Vector, f64) -> Vector + Send + Sync,
{
    fn force(&self, position_m: Vector, velocity_m_s: Vector, t_s: f64) -> Vector {
        self(position_m, velocity_m_s, t_s)
    }
}

/// A linear spring–damper acting on a mount along `axis`: the force
/// `(preload_n − stiffness_n_m · s − damping_n_s_m · ṡ) · axis`, where
/// `s = axis · (position − anchor_m)`. A tensioner's spring: the anchor at
/// the sprocket's centre in the scene, the axis along which it pushes, the
/// preload balancing the chain's pull there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MountSpring {
    /// Where the spring's force is its preload, m (world).
    pub anchor_m: Vector,
    /// The direction along which it pushes (normalised when used; a zero
    /// axis gives no force).
    pub axis: Vector,
    /// Rate, N/m.
    pub stiffness_n_m: f64,
    /// Damping, N·s/m.
    pub damping_n_s_m: f64,
    /// Force at the anchor, N (positive along `axis`).
    pub preload_n: f64,
}

impl MountForce for MountSpring {
    fn force(&self, position_m: Vector, velocity_m_s: Vector, _t_s: f64) -> Vector {
        let a = self.axis.normalize_or_zero();
        let s = a.dot(position_m - self.anchor_m);
        a * (self.preload_n - self.stiffness_n_m * s - self.damping_n_s_m * a.dot(velocity_m_s))
    }
}

/// Whose body a sprocket sits on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Mount {
    /// The drive's own kinematic body.
    Own,
    /// The user's dynamic body: the chain and the body turn together.
    Dynamic,
    /// The user's kinematic (or fixed) body: it turns the sprocket at its speed.
    Kinematic,
}

/// Per-frame coupling of one sprocket to its rapier body.
#[derive(Clone, Copy, Debug)]
pub(super) struct SprocketLink {
    pub(super) body: RigidBodyHandle,
    /// Whose body it is.
    pub(super) mount: Mount,
    /// The body's angle less the sprocket's, rad (fixed at insertion: a
    /// mounted body keeps its rotation).
    pub(super) angle_offset: f64,
    /// The user's torque, stashed during rapier's step, N·m.
    pub(super) user_torque_n_m: f64,
    /// The user's force, kept through rapier's step, N.
    pub(super) user_force: Vector,
    /// Mean angular speed given to rapier for this frame, rad/s.
    pub(super) mean_omega: f64,
    /// The chain's mean force on the sprocket over the frame, N.
    pub(super) mean_chain_force: [f64; 2],
    /// A mounted body's position at the frame's start, m.
    pub(super) frame_start_m: [f64; 2],
    /// A dynamic mount's translation, integrated in the substeps (`None`
    /// where rapier moves the body: locked, or tied by a joint that fixes
    /// its position).
    pub(super) translation: Option<MountTranslation>,
    /// The joints on a dynamic mount, read by [`Mounts::read_joints`].
    pub(super) joints: MountJoints,
}

/// The sprockets' bodies: one [`SprocketLink`] per sprocket, in the
/// scene's order, the mounts' force laws and the joint motors switched off
/// for the world's step.
pub(super) struct Mounts {
    links: Vec<SprocketLink>,
    /// Mounted sprockets' bodies (the user's).
    mounted: Vec<RigidBodyHandle>,
    /// Force laws on dynamic mounts, called in every substep.
    laws: Vec<Option<Box<dyn MountForce>>>,
    /// Joint motors the substeps imitate, switched off in the joint set
    /// during the world's step.
    motors_off: Vec<(ImpulseJointHandle, JointAxesMask)>,
}

impl Mounts {
    /// The sprockets' couplings, no force laws.
    pub(super) fn new(links: Vec<SprocketLink>) -> Self {
        Self {
            mounted: links
                .iter()
                .filter(|l| l.mount != Mount::Own)
                .map(|l| l.body)
                .collect(),
            laws: (0..links.len()).map(|_| None).collect(),
            motors_off: Vec::new(),
            links,
        }
    }

    /// One coupling per sprocket, in the scene's order.
    pub(super) fn links(&self) -> &[SprocketLink] {
        &self.links
    }

    /// The user's bodies that carry sprockets.
    pub(super) fn mounted(&self) -> &[RigidBodyHandle] {
        &self.mounted
    }

    /// Whose body sprocket `k` sits on.
    pub(super) fn mount_of(&self, k: usize) -> Option<Mount> {
        self.links.get(k).map(|l| l.mount)
    }

    /// Whether any sprocket sits on a dynamic body.
    pub(super) fn has_dynamic(&self) -> bool {
        self.links.iter().any(|l| l.mount == Mount::Dynamic)
    }

    /// Whether dynamic mount `k` has a force law.
    pub(super) fn has_law(&self, k: usize) -> bool {
        self.laws.get(k).is_some_and(Option::is_some)
    }

    /// Whether `b` is a mounted body, or a carriage a mount turns on.
    pub(super) fn holds_body(&self, b: RigidBodyHandle) -> bool {
        self.mounted.contains(&b) || self.links.iter().any(|l| l.joints.carrier == Some(b))
    }

    /// Reads the joints on dynamic mounts (see
    /// [`super::ChainDrive::read_joints`]).
    pub(super) fn read_joints(&mut self, bodies: &RigidBodySet, joints: &ImpulseJointSet) {
        for link in &mut self.links {
            if link.mount == Mount::Dynamic {
                link.joints = read_mount_joints(bodies, joints, link.body);
            }
        }
    }

    /// Switches off, in `joints`, the joint motors the substeps imitate.
    pub(super) fn motors_off(&mut self, joints: &mut ImpulseJointSet) {
        self.motors_off.clear();
        for link in &self.links {
            let Some(s) = link.joints.slide.filter(|s| s.motor.is_some()) else {
                continue;
            };
            if let Some(j) = joints.get_mut(s.joint, false) {
                if j.data.motor_axes.contains(s.mask()) {
                    j.data.motor_axes.remove(s.mask());
                    self.motors_off.push((s.joint, s.mask()));
                }
            }
        }
    }

    /// Switches back on the motors [`Self::motors_off`] switched off.
    pub(super) fn motors_on(&mut self, joints: &mut ImpulseJointSet) {
        for (h, mask) in self.motors_off.drain(..) {
            if let Some(j) = joints.get_mut(h, false) {
                j.data.motor_axes.insert(mask);
            }
        }
    }

    /// Gives dynamic mount `k` the force law `law` (`None`: none). An error
    /// unless sprocket `k` sits on a dynamic body.
    pub(super) fn set_law(
        &mut self,
        k: usize,
        law: Option<Box<dyn MountForce>>,
    ) -> Result<(), CosimError> {
        match self.mount_of(k) {
            Some(Mount::Dynamic) => {
                self.laws[k] = law;
                Ok(())
            }
            Some(_) => Err(CosimError::input(
                format!("mounts[{k}]"),
                "a force law needs a dynamic body under the sprocket (mount it on one in \
                 ChainDrive::insert)",
            )),
            None => Err(CosimError::input(
                "k",
                format!(
                    "sprocket {k}, but the scene has {} sprockets",
                    self.links.len()
                ),
            )),
        }
    }

    /// The frame's start: each sprocket's centre and centre velocity from
    /// its body, the users' torques and forces taken out of rapier's step
    /// (a kinematic mount's speed taken as its sprocket's speed law), a
    /// dynamic mount's translation set up for the substeps. Whether a
    /// sprocket centre moves this frame.
    pub(super) fn begin_frame(
        &mut self,
        sprockets: &mut [SprocketModel],
        bodies: &mut RigidBodySet,
        colliders: &ColliderSet,
        gravity: Vector,
        span: f64,
    ) -> bool {
        // A mounted body moves on through the frame at its velocity
        // (rapier's step will take it there): its sprocket follows in the
        // substeps. A kinematic mount turns its sprocket at its own speed.
        let mut moving = false;
        for (k, link) in self.links.iter_mut().enumerate() {
            if link.mount == Mount::Dynamic {
                // rapier computes a new body's mass properties at its next
                // step; a carriage added with the drive has none before the
                // first (its substeps would think it fixed): now.
                if let Some(c) = link.joints.carrier.and_then(|h| bodies.get_mut(h)) {
                    if c.is_dynamic() && c.mass() == 0.0 {
                        c.recompute_mass_properties_from_colliders(colliders);
                    }
                }
                let user_force = bodies
                    .get(link.body)
                    .map_or(Vector::ZERO, |b| b.user_force());
                link.translation =
                    mount_translation(bodies, link.body, &link.joints, user_force, gravity);
            }
            let Some(b) = bodies.get_mut(link.body) else {
                continue;
            };
            let sprocket = &mut sprockets[k];
            if link.mount != Mount::Own {
                let c = b.translation();
                let (v, w) = if b.body_type() == RigidBodyType::KinematicPositionBased {
                    let next = b.next_position();
                    let here = b.position();
                    (
                        (next.translation - here.translation) / span,
                        (next.rotation * here.rotation.inverse()).angle() / span,
                    )
                } else {
                    (b.linvel(), b.angvel())
                };
                moving |= sprocket.center_m != [c.x, c.y]
                    || sprocket.center_velocity_m_s != [0.0; 2]
                    || v != Vector::ZERO;
                sprocket.center_m = [c.x, c.y];
                sprocket.center_velocity_m_s = [v.x, v.y];
                link.frame_start_m = [c.x, c.y];
                if link.mount == Mount::Kinematic {
                    sprocket.speed_law = Some(SpeedLaw::ramped(w, 0.0));
                } else {
                    link.user_torque_n_m = b.user_torque();
                    link.user_force = b.user_force();
                    b.reset_torques(false);
                    if let Some(tr) = &link.translation {
                        moving = true;
                        sprocket.center_velocity_m_s = [tr.v.x, tr.v.y];
                    }
                }
            }
            // The scene's load keeps its ramp; the user's torque does not ramp.
            sprocket.user_torque_n_m = link.user_torque_n_m;
        }
        moving
    }

    /// Moves the mounted sprockets' centres over substep `step` (of `dt`
    /// from the frame's start `t0`): a translating mount by the chain's
    /// force and its law, another by its velocity.
    pub(super) fn move_centres(
        &mut self,
        sprockets: &mut [SprocketModel],
        chain_force: &[[f64; 2]],
        step: u64,
        t0: f64,
        dt: f64,
    ) {
        let tau = step as f64 * dt;
        for (k, (link, sprocket)) in self.links.iter_mut().zip(sprockets).enumerate() {
            if let Some(tr) = &mut link.translation {
                // The chain's force and the law's at the substep's
                // start, as the rollers were advanced.
                let start = Vector::new(link.frame_start_m[0], link.frame_start_m[1]);
                let law = self.laws[k].as_ref().map_or(Vector::ZERO, |f| {
                    f.force(start + tr.dx, tr.v, t0 + (step - 1) as f64 * dt)
                });
                let f = Vector::new(chain_force[k][0], chain_force[k][1]);
                tr.advance(f, law, tau - dt, dt);
                sprocket.center_m = [start.x + tr.dx.x, start.y + tr.dx.y];
                sprocket.center_velocity_m_s = [tr.v.x, tr.v.y];
            } else if link.mount != Mount::Own {
                let [vx, vy] = sprocket.center_velocity_m_s;
                sprocket.center_m = [
                    link.frame_start_m[0] + vx * tau,
                    link.frame_start_m[1] + vy * tau,
                ];
            }
        }
    }

    /// After `substeps` substeps over the frame of `dt_s`: each
    /// translating mount's mean velocity and its motor's mean force.
    /// `false` as soon as a mount's velocity is not finite.
    pub(super) fn close_substeps(&mut self, substeps: u64, dt_s: f64) -> bool {
        for link in &mut self.links {
            if let Some(tr) = &mut link.translation {
                tr.mean_v = tr.dx / dt_s;
                if let Some((_, sf)) = &mut tr.slide {
                    sf.motor_sum /= substeps.max(1) as f64;
                }
                if !(tr.mean_v.is_finite() && tr.v.is_finite()) {
                    return false;
                }
            }
        }
        true
    }

    /// Sets each sprocket's body for rapier's step: to turn (and a mount to
    /// move) over the frame `span` as the substeps did from the frame-start
    /// angles `theta0` to `state`, with the chain's mean force over
    /// `substeps` (summed in `force_sum`) on it.
    pub(super) fn hand_back(
        &mut self,
        bodies: &mut RigidBodySet,
        state: &DriveState,
        theta0: &[f64],
        force_sum: &[[f64; 2]],
        substeps: u64,
        span: f64,
    ) {
        let n = substeps.max(1) as f64;
        for (k, link) in self.links.iter_mut().enumerate() {
            link.mean_omega = (state.theta[k] - theta0[k]) / span;
            link.mean_chain_force = [force_sum[k][0] / n, force_sum[k][1] / n];
            let Some(b) = bodies.get_mut(link.body) else {
                continue;
            };
            match link.mount {
                // rapier turns a kinematic mount itself; the chain followed it.
                Mount::Kinematic => {}
                Mount::Own => {
                    b.set_rotation(Rotation::new(theta0[k]), true);
                    b.set_angvel(link.mean_omega, true);
                }
                Mount::Dynamic => {
                    b.set_rotation(Rotation::new(theta0[k] + link.angle_offset), true);
                    b.set_angvel(link.mean_omega, true);
                    b.reset_forces(false);
                    if let Some(tr) = &link.translation {
                        // The substeps moved it under the chain's force, the
                        // user's and gravity: rapier's step takes it from the
                        // frame's start to the substeps' end at the mean
                        // velocity, with only its joints and contacts acting.
                        b.set_linvel(tr.mean_v, true);
                        b.set_gravity_scale(0.0, true);
                        b.set_linear_damping(0.0);
                    } else {
                        // The user's force (rapier's semantics: it stays
                        // until the user resets it), the chain's and the
                        // law's (held over the frame: rapier moves the body).
                        let law = self.laws[k].as_ref().map_or(Vector::ZERO, |f| {
                            f.force(b.translation(), b.linvel(), state.t_s)
                        });
                        b.add_force(
                            link.user_force
                                + law
                                + Vector::new(link.mean_chain_force[0], link.mean_chain_force[1]),
                            true,
                        );
                    }
                }
            }
            if let Some(tr) = &link.translation {
                if let Some(c) = tr.carrier.and_then(|(h, _)| bodies.get_mut(h)) {
                    // The carriage moves with the body: the same treatment.
                    c.reset_forces(false);
                    c.set_linvel(tr.mean_v, true);
                    c.set_gravity_scale(0.0, true);
                    c.set_linear_damping(0.0);
                }
                if let Some((s, sf)) = &tr.slide {
                    // The imitated motor's reaction on a dynamic other body.
                    let other = if s.moving_is_2 { s.body1 } else { s.body2 };
                    if let Some(o) = bodies.get_mut(other).filter(|o| o.is_dynamic()) {
                        o.add_force(-sf.motor_sum, true);
                    }
                }
            }
        }
    }

    /// After rapier's step: the angular-speed change a dynamic mount's
    /// joints gave it added to the sprocket's `omega`, a translating mount
    /// (and its carriage) at the substeps' end velocity plus what its
    /// joints and contacts changed, the users' torques, forces, gravity
    /// scales and damping put back.
    pub(super) fn after_step(&self, bodies: &mut RigidBodySet, omega: &mut [f64]) {
        for (k, link) in self.links.iter().enumerate() {
            if link.mount != Mount::Dynamic {
                continue;
            }
            if let Some(b) = bodies.get_mut(link.body) {
                // The body's joints changed its speed by this much during rapier's step.
                omega[k] += b.angvel() - link.mean_omega;
                if let Some(tr) = &link.translation {
                    // The substeps' end velocity and what the joints and
                    // contacts changed in rapier's step.
                    b.set_linvel(tr.v + (b.linvel() - tr.mean_v), false);
                    b.set_gravity_scale(tr.stash.gravity_scale, false);
                    b.set_linear_damping(tr.stash.damping);
                }
                b.reset_forces(false);
                b.add_force(link.user_force, false);
                b.add_torque(link.user_torque_n_m, false);
            }
            let Some(tr) = &link.translation else {
                continue;
            };
            if let Some((h, stash)) = tr.carrier {
                if let Some(c) = bodies.get_mut(h) {
                    c.set_linvel(tr.v + (c.linvel() - tr.mean_v), false);
                    c.set_gravity_scale(stash.gravity_scale, false);
                    c.set_linear_damping(stash.damping);
                    c.reset_forces(false);
                    c.add_force(stash.user_force, false);
                }
            }
            if let Some((s, sf)) = &tr.slide {
                let other = if s.moving_is_2 { s.body1 } else { s.body2 };
                if let Some(o) = bodies.get_mut(other).filter(|o| o.is_dynamic()) {
                    o.add_force(sf.motor_sum, false);
                }
            }
        }
    }
}
