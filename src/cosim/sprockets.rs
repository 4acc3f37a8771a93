//! A drive's sprockets by name, and its rollers and sprockets read as
//! rapier values: [`SprocketId`] and the per-sprocket and per-roller
//! getters of [`ChainDrive`].
//!
//! A sprocket is found once by its name or its place in the scene
//! ([`ChainDrive::sprocket`]) and then named by its id in every
//! per-sprocket setter and getter, as rapier names a body by its handle.
//! Positions, velocities and forces come out as rapier's [`Vector`] in the
//! world's frame (the insertion pose applied). The structure-of-arrays
//! state ([`ChainDrive::state`]) stays for bulk reads.

use rapier2d_f64::prelude::{RigidBodyHandle, Vector};

use super::{ChainDrive, CosimError, SprocketKey};
use crate::scene::Scene;

/// A sprocket of a [`ChainDrive`], from [`ChainDrive::sprocket`].
///
/// It is only meaningful for the drive that gave it (or a drive inserted
/// again from it with `settled_from`, which has the same sprockets). The
/// getters taking one panic on an id past the drive's last sprocket, as
/// indexing rapier's sets with a stale handle does; the setters return an
/// error.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SprocketId(usize);

impl SprocketId {
    /// The sprocket's place in the scene's `[[sprockets]]`, from 0.
    pub fn index(self) -> usize {
        self.0
    }
}

impl From<SprocketId> for SprocketKey {
    fn from(id: SprocketId) -> Self {
        Self::Index(id.0)
    }
}

/// The index of the sprocket `key` names in `scene`; `call` names the call
/// in the error (`mount`, `sprocket`).
pub(super) fn resolve(scene: &Scene, key: &SprocketKey, call: &str) -> Result<usize, CosimError> {
    let sprockets = scene.sprockets();
    match key {
        SprocketKey::Index(k) if *k < sprockets.len() => Ok(*k),
        SprocketKey::Index(k) => Err(CosimError::input(
            format!("{call}({k})"),
            format!(
                "no sprocket {k}: the scene has sprockets 0 to {}",
                sprockets.len().saturating_sub(1)
            ),
        )),
        SprocketKey::Name(name) => {
            sprockets
                .iter()
                .position(|s| s.name == *name)
                .ok_or_else(|| {
                    let names: Vec<String> =
                        sprockets.iter().map(|s| format!("{:?}", s.name)).collect();
                    CosimError::input(
                        format!("{call}({name:?})"),
                        format!(
                            "no sprocket named {name:?} in the scene: its sprockets are {}",
                            names.join(", ")
                        ),
                    )
                })
        }
    }
}

impl ChainDrive {
    /// The sprocket of that name (`name` in `[[sprockets]]`) or index, for
    /// the per-sprocket setters and getters. An error naming the scene's
    /// sprockets when there is none such.
    ///
    /// ```no_run
    /// # use chaindrive::prelude::*;
    /// # fn f(drive: &mut ChainDrive) -> Result<(), CosimError> {
    /// let tail = drive.sprocket("tail")?;
    /// drive.set_load_torque(tail, -2.0)?;
    /// println!("{} rad/s", drive.sprocket_speed(tail));
    /// # Ok(()) }
    /// ```
    pub fn sprocket(&self, key: impl Into<SprocketKey>) -> Result<SprocketId, CosimError> {
        resolve(&self.scene, &key.into(), "sprocket").map(SprocketId)
    }

    /// Every sprocket's id and name, in the scene's order.
    pub fn sprockets(&self) -> impl ExactSizeIterator<Item = (SprocketId, &str)> + '_ {
        self.scene
            .sprockets()
            .iter()
            .enumerate()
            .map(|(k, s)| (SprocketId(k), s.name.as_str()))
    }

    /// The sprocket's angle, rad (counter-clockwise positive), at the end of
    /// the last substep.
    pub fn sprocket_angle(&self, id: SprocketId) -> f64 {
        self.state.theta[id.0]
    }

    /// The sprocket's angular speed, rad/s (counter-clockwise positive), at
    /// the end of the last substep.
    pub fn sprocket_speed(&self, id: SprocketId) -> f64 {
        self.state.omega[id.0]
    }

    /// The torque the chain exerts on the sprocket about its centre, N·m,
    /// at the end of the last substep.
    pub fn chain_torque_on_sprocket(&self, id: SprocketId) -> f64 {
        self.forces.output().chain_torque[id.0]
    }

    /// The force the chain exerts on the sprocket's centre, N, at the end
    /// of the last substep.
    pub fn chain_force_on_sprocket(&self, id: SprocketId) -> Vector {
        let [fx, fy] = self.forces.output().chain_force[id.0];
        Vector::new(fx, fy)
    }

    /// The sprocket's body: the user's where mounted, the drive's own
    /// otherwise.
    pub fn sprocket_body(&self, id: SprocketId) -> RigidBodyHandle {
        self.handles.sprockets()[id.0]
    }

    /// The number of rollers.
    pub fn roller_count(&self) -> usize {
        self.state.x.len()
    }

    /// Roller `i`'s centre in the world, m (`None` past the last roller).
    pub fn roller_position(&self, i: usize) -> Option<Vector> {
        Some(Vector::new(*self.state.x.get(i)?, *self.state.y.get(i)?))
    }

    /// Roller `i`'s velocity, m/s (`None` past the last roller).
    pub fn roller_velocity(&self, i: usize) -> Option<Vector> {
        Some(Vector::new(*self.state.vx.get(i)?, *self.state.vy.get(i)?))
    }

    /// Every roller's centre in the world, m, in the chain's order.
    pub fn roller_positions(&self) -> impl ExactSizeIterator<Item = Vector> + '_ {
        let s = &self.state;
        s.x.iter().zip(&s.y).map(|(&x, &y)| Vector::new(x, y))
    }
}
