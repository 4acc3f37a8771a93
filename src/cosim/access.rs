//! Read-only access to a drive's scene, model and state, and the setters
//! for what a user changes while it runs.
//!
//! The drive refreshes parts of its model at every frame (a mounted
//! sprocket's centre, the user's torques, a kinematic mount's speed), so
//! none of it is a public field a user could write and see silently
//! overwritten: what may change mid-run has a setter here or in the parent
//! module ([`ChainDrive::set_load_torque`], [`ChainDrive::set_driver_speed`]).

use rapier2d_f64::prelude::RigidBodyHandle;

use super::{ChainDrive, CosimError, Coupling, FrameTimes};
#[cfg(test)]
use crate::forces::Culling;
use crate::model::{DriveModel, DriveState};
use crate::scene::{Scene, SpeedLaw};
use crate::sim::StaticEquilibrium;

impl ChainDrive {
    /// The scene the drive was built from.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The drive's model: sprockets (centres, loads and speed laws as the
    /// last frame used them), chain, segments.
    pub fn model(&self) -> &DriveModel {
        &self.model
    }

    /// The chain's state at the end of the last substep (time, roller
    /// positions and velocities, sprocket angles and speeds).
    pub fn state(&self) -> &DriveState {
        &self.state
    }

    /// The static equilibrium the drive relaxed to before t = 0.
    pub fn equilibrium(&self) -> &StaticEquilibrium {
        &self.equilibrium
    }

    /// The roller bodies the drive added, in the chain's order.
    pub fn roller_bodies(&self) -> &[RigidBodyHandle] {
        self.handles.rollers()
    }

    /// What the drive noticed that is legitimate but may surprise, each
    /// once, in the order noticed: a world gravity other than the scene's
    /// (the chain hangs under the scene's, the bodies it carries fall under
    /// the world's).
    pub fn warnings(&self) -> &[String] {
        self.notes.warnings()
    }

    /// How the user's colliders near the rollers are treated.
    pub fn coupling(&self) -> &Coupling {
        &self.coupling
    }

    /// Wall time spent per stage, summed over frames.
    pub fn stage_times(&self) -> FrameTimes {
        self.stage_times
    }

    /// Sets how the user's colliders near the rollers are treated, from the
    /// next frame on. An error naming the field when the search speed is not
    /// positive and finite.
    pub fn set_coupling(&mut self, coupling: Coupling) -> Result<(), CosimError> {
        check_coupling(&coupling)?;
        self.coupling = coupling;
        self.apply_tooth_tips();
        Ok(())
    }

    /// The sprockets' circular profiles with the coupling's tooth tips, and
    /// their reach to match.
    pub(super) fn apply_tooth_tips(&mut self) {
        for sp in &mut self.model.sprockets {
            sp.profile.set_tips(self.coupling.tooth_tips);
            sp.reach_m = sp.profile.reach_m();
            sp.reach_sq_m2 = sp.reach_m * sp.reach_m;
        }
        self.forces.forget_reach();
    }

    /// Sets the roller–tooth contact's reach caching (`None`: every pair is
    /// tested at every substep). It changes the cost, not the result, within
    /// the caching's safety margin.
    #[cfg(test)]
    pub(crate) fn set_culling(&mut self, culling: Option<Culling>) {
        self.forces.contact.culling = culling;
        self.forces.forget_reach();
    }

    /// Sets a torque-driven driver's target speed, rad/s (counter-clockwise
    /// positive), from now on, without a ramp. The governor's integral action
    /// carries on from the angle the driver has reached: the target angle
    /// continues from the old target's at this instant, so the change acts
    /// as a speed step, not as an angle jump. An error when the scene's
    /// driver has no governor (use [`Self::set_driver_speed`] for a
    /// kinematic one) or the speed is not finite.
    pub fn set_governor_target(&mut self, speed_rad_s: f64) -> Result<(), CosimError> {
        let t = self.state.t_s;
        let g = self.governor_mut()?;
        if !speed_rad_s.is_finite() {
            return Err(CosimError::input(
                "governor.speed_rpm",
                format!("{speed_rad_s} rad/s: a finite speed"),
            ));
        }
        // The new target angle ω t + offset equals the old one at t.
        let angle = crate::model::target_angle_rad(&g.target, t) + g.target_angle_offset_rad;
        g.target_angle_offset_rad = angle - speed_rad_s * t;
        g.target = SpeedLaw {
            speed_rad_s,
            ramp_s: 0.0,
            run_up: None,
        };
        Ok(())
    }

    /// Sets a torque-driven driver's constant drive torque, N·m, from now on
    /// (the governor's control torque comes on top). An error when the
    /// scene's driver has no governor or the torque is not finite.
    pub fn set_driver_torque(&mut self, torque_n_m: f64) -> Result<(), CosimError> {
        let g = self.governor_mut()?;
        if !torque_n_m.is_finite() {
            return Err(CosimError::input(
                "governor.drive_torque_n_m",
                format!("{torque_n_m}: a finite torque, N·m"),
            ));
        }
        g.drive_torque_n_m = torque_n_m;
        Ok(())
    }

    fn governor_mut(&mut self) -> Result<&mut crate::model::Governor, CosimError> {
        self.model
            .driving()
            .and_then(|k| self.model.sprockets.get_mut(k))
            .and_then(|sp| sp.governor.as_mut())
            .ok_or_else(|| {
                CosimError::input(
                    "governor",
                    "the scene's driver has no governor (a torque-driven driver needs a \
                     [governor] table): set a kinematic driver's speed with set_driver_speed",
                )
            })
    }
}

/// Coupling options a drive can use.
pub(super) fn check_coupling(c: &Coupling) -> Result<(), CosimError> {
    if !(c.search_speed_m_s.is_finite() && c.search_speed_m_s > 0.0) {
        return Err(CosimError::input(
            "coupling.search_speed_m_s",
            format!("{} m/s: a positive, finite speed", c.search_speed_m_s),
        ));
    }
    Ok(())
}
