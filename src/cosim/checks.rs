//! The checks a frame makes before it writes anything, and after the
//! world's step: each misuse named by its cause.
//!
//! Before the substeps ([`ChainDrive::check_world`], called by
//! [`ChainDrive::before_step`] and, for every drive first, by
//! [`super::DriveSet::before_step`]): a bad `dt_s`; `before_step` twice
//! without `after_step`; a non-finite world gravity; a sprocket's body, a
//! roller's body or its collider no longer in the user's sets (removed, or
//! the drive inserted into another world); a non-finite user torque, force,
//! position or velocity on a mounted body; a force law on a mount whose
//! translations are locked; a joint arrangement the substeps cannot run.
//! After the step ([`ChainDrive::check_frame`]): `after_step` without
//! `before_step`, another `dt_s`, a world not stepped at all, a world
//! stepped without the drive's hooks while something dynamic touches the
//! chain, a world stepped by another dt.
//!
//! A world gravity other than the scene's is legitimate (a weightless chain
//! under boxes that fall): a warning ([`ChainDrive::warnings`]), once.
//!
//! What is not checked: two drives that are not in one
//! [`super::DriveSet`] sharing a world (each takes the other's rollers for
//! the user's bodies), and a drive inserted into another world built the
//! same way as its own (its handles name the same bodies there).

use rapier2d_f64::prelude::*;

use super::{ChainDrive, CosimError, Mount, ROLLER_SYNC_TOLERANCE_M};

/// What the drive noticed that is legitimate but may surprise, each once.
#[derive(Debug, Default)]
pub(super) struct Notes {
    /// The sentences, in the order noticed.
    warnings: Vec<String>,
    /// Whether a world gravity other than the scene's was noted.
    gravity_noted: bool,
}

impl Notes {
    /// Notes that start with `warnings` (the static equilibrium's: a roller
    /// on a seating arc's rim, a misfit's tension, loads with no rest state).
    pub(super) fn starting_with(warnings: Vec<String>) -> Self {
        Self {
            warnings,
            gravity_noted: false,
        }
    }

    /// The sentences, in the order noticed.
    pub(super) fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// Records, once, a world `gravity` other than the scene's `scene_gravity`.
    fn note_gravity(&mut self, scene_gravity: [f64; 2], gravity: Vector) {
        let [gx, gy] = scene_gravity;
        if self.gravity_noted || (gravity.x == gx && gravity.y == gy) {
            return;
        }
        self.gravity_noted = true;
        self.warnings.push(format!(
            "the world's gravity [{}, {}] m/s² differs from the scene's gravity_m_s2 [{gx}, {gy}]: \
             the chain hangs under the scene's, the bodies it carries fall under the world's",
            gravity.x, gravity.y
        ));
    }
}

impl ChainDrive {
    /// Everything a frame needs of the world, checked before anything is
    /// written (see the module's docs).
    pub(super) fn check_world(
        &self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        gravity: Vector,
        dt_s: f64,
    ) -> Result<(), CosimError> {
        if !(dt_s.is_finite() && dt_s > 0.0) {
            return Err(CosimError::input(
                "dt_s",
                format!(
                    "{dt_s} s: the frame's step must be positive and finite (the world's \
                     integration_parameters.dt)"
                ),
            ));
        }
        if self.clock.in_frame() {
            return Err(CosimError::World(
                "before_step again without after_step: the bodies are still set for the last \
                 frame's step; call before_step, the world's step, then after_step, once each \
                 per frame"
                    .to_owned(),
            ));
        }
        if !gravity.is_finite() {
            return Err(CosimError::input(
                "gravity",
                format!(
                    "[{}, {}] m/s²: the world's gravity must be finite (PhysicsWorld::gravity)",
                    gravity.x, gravity.y
                ),
            ));
        }
        for (k, link) in self.mounts.links().iter().enumerate() {
            let field = if link.mount == Mount::Own {
                format!("sprockets[{k}]")
            } else {
                format!("mounts[{k}]")
            };
            let Some(b) = bodies.get(link.body) else {
                return Err(CosimError::input(
                    field,
                    "the sprocket's body is no longer in the RigidBodySet: take the drive out \
                     with ChainDrive::remove before removing its mounts",
                ));
            };
            if let Some(why) = link.joints.unsupported {
                return Err(CosimError::input(field, why));
            }
            if link.mount == Mount::Dynamic {
                check_mount_body(&field, b)?;
                if self.mounts.has_law(k) && b.locked_axes().contains(LOCKED_TRANSLATIONS) {
                    return Err(CosimError::input(
                        field,
                        "a force law (set_mount_force) on a body whose translations are locked \
                         moves nothing: free a translation (enabled_translations) or take the \
                         law away (clear_mount_force)",
                    ));
                }
            }
        }
        self.check_rollers(bodies, colliders)
    }

    /// Every roller's body and collider still in the user's sets, the
    /// collider on its body.
    fn check_rollers(
        &self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
    ) -> Result<(), CosimError> {
        for (i, (&h, &c)) in self
            .handles
            .rollers()
            .iter()
            .zip(self.handles.roller_colliders())
            .enumerate()
        {
            let on_body = colliders.get(c).and_then(|c| c.parent()) == Some(h);
            if bodies.get(h).is_none() || !on_body {
                return Err(CosimError::input(
                    format!("rollers[{i}]"),
                    "the roller's body or collider is not in the world's sets: removed by hand \
                     (take the drive out with ChainDrive::remove), or the drive was inserted into \
                     another world",
                ));
            }
        }
        Ok(())
    }

    /// Records, once, a world gravity other than the scene's.
    pub(super) fn note_gravity(&mut self, gravity: Vector) {
        self.notes.note_gravity(self.scene.gravity_m_s2(), gravity);
    }

    /// Whether the world's step was the one `before_step` prepared.
    pub(super) fn check_frame(
        &self,
        bodies: &RigidBodySet,
        narrow_phase: &NarrowPhase,
        dt_s: f64,
    ) -> Result<(), CosimError> {
        if !self.clock.in_frame() {
            return Err(CosimError::World(
                "after_step without before_step: call before_step, the world's step, then \
                 after_step, once each per frame"
                    .to_owned(),
            ));
        }
        if dt_s != self.clock.frame_dt_s() {
            return Err(CosimError::input(
                "dt_s",
                format!(
                    "{dt_s} s, but before_step had {} s: give both the world's dt",
                    self.clock.frame_dt_s()
                ),
            ));
        }
        let hooked = self.clock.hooked();
        let (mut worst, mut at, mut moved, mut stayed) = (0.0f64, 0, false, true);
        let start = self.scratch.start();
        for (i, &h) in self.handles.rollers().iter().enumerate() {
            if let Some(b) = bodies.get(h).filter(|b| b.is_enabled()) {
                let p = b.translation();
                let d = (p.x - self.state.x[i]).hypot(p.y - self.state.y[i]);
                if !(d <= worst) {
                    (worst, at) = (d, i);
                }
                let [x0, y0] = start[i];
                moved |=
                    (self.state.x[i] - x0).hypot(self.state.y[i] - y0) > ROLLER_SYNC_TOLERANCE_M;
                stayed &= p.x == x0 && p.y == y0;
            }
        }
        if !hooked && moved && stayed {
            return Err(CosimError::World(
                "the world was not stepped between before_step and after_step (every roller body \
                 is where the frame started): step it once in between"
                    .to_owned(),
            ));
        }
        if !hooked && (self.mounts.has_dynamic() || self.touched(narrow_phase)) {
            return Err(CosimError::World(format!(
                "the world was stepped without the drive's hooks, so rapier's solver pushed {}: \
                 pass drive.hooks(&your_hooks) to the step (or use ChainDrive::step_world)",
                if self.mounts.has_dynamic() {
                    "the rollers' colliders against the mounted sprockets"
                } else {
                    "the rollers' colliders against the bodies touching them"
                }
            )));
        }
        if !(worst <= ROLLER_SYNC_TOLERANCE_M) {
            return Err(CosimError::World(format!(
                "roller {at}'s body is {worst:.3e} m from the chain's roller after the step \
                 (more than {ROLLER_SYNC_TOLERANCE_M:e} m): the world stepped by another dt than \
                 before_step's {} s (give before_step the world's integration_parameters.dt), \
                 or was stepped other than once between before_step and after_step",
                self.clock.frame_dt_s()
            )));
        }
        Ok(())
    }

    /// Whether a roller has an active contact with a collider that is not
    /// the drive's (a pair the drive's hooks would have seen).
    fn touched(&self, narrow_phase: &NarrowPhase) -> bool {
        self.handles.roller_colliders().iter().any(|&rc| {
            narrow_phase.contact_pairs_with(rc).any(|pair| {
                let other = if pair.collider1 == rc {
                    pair.collider2
                } else {
                    pair.collider1
                };
                pair.has_any_active_contact() && !self.owns_collider(other)
            })
        })
    }
}

/// Both translations locked.
const LOCKED_TRANSLATIONS: LockedAxes =
    LockedAxes::TRANSLATION_LOCKED_X.union(LockedAxes::TRANSLATION_LOCKED_Y);

/// A dynamic mount's user torque and force, pose and velocity, finite.
fn check_mount_body(field: &str, b: &RigidBody) -> Result<(), CosimError> {
    let bad = |what: &str, value: String| {
        Err(CosimError::input(
            field,
            format!("the body's {what} is {value}: it must be finite"),
        ))
    };
    let (f, v, p) = (b.user_force(), b.linvel(), b.translation());
    if !b.user_torque().is_finite() {
        return bad("user torque", format!("{} N·m", b.user_torque()));
    }
    if !f.is_finite() {
        return bad("user force", format!("[{}, {}] N", f.x, f.y));
    }
    if !(p.is_finite() && b.rotation().angle().is_finite()) {
        return bad("pose", format!("[{}, {}] m", p.x, p.y));
    }
    if !(v.is_finite() && b.angvel().is_finite()) {
        return bad(
            "velocity",
            format!("[{}, {}] m/s, {} rad/s", v.x, v.y, b.angvel()),
        );
    }
    Ok(())
}
