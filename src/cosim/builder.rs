//! [`ChainDriveBuilder`]: a drive put together from its scene, its mounts
//! (by sprocket name or index), its coupling and its pose, then built into
//! the user's world.

use std::sync::Arc;

use rapier2d_f64::prelude::*;

use super::access::check_coupling;
use super::settled::{self, Settled};
use super::{ChainDrive, CosimError, Coupling};
use crate::scene::Scene;

/// A sprocket of the scene, by its name (`name` in `[[sprockets]]`) or its
/// index in the scene's order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SprocketKey {
    /// The `k`-th sprocket, from 0.
    Index(usize),
    /// The sprocket of that name.
    Name(String),
}

impl From<usize> for SprocketKey {
    fn from(k: usize) -> Self {
        Self::Index(k)
    }
}

impl From<&str> for SprocketKey {
    fn from(name: &str) -> Self {
        Self::Name(name.to_owned())
    }
}

impl From<String> for SprocketKey {
    fn from(name: String) -> Self {
        Self::Name(name)
    }
}

impl std::fmt::Display for SprocketKey {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Index(k) => write!(f, "{k}"),
            Self::Name(n) => write!(f, "{n:?}"),
        }
    }
}

/// Builds a [`ChainDrive`] into a rapier world:
///
/// ```no_run
/// # use chaindrive::cosim::ChainDrive;
/// # use chaindrive::scene::Scene;
/// # use rapier2d_f64::prelude::*;
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let scene = Scene::l60mc();
/// let mut world = PhysicsWorld::default();
/// let shaft = world.bodies.insert(RigidBodyBuilder::dynamic());
/// let drive = ChainDrive::builder(&scene)
///     .mount("crankshaft", shaft) // or .mount(0, shaft)
///     .insert_at(Pose::translation(0.0, 0.0))
///     .build(&mut world)?;
/// # Ok(()) }
/// ```
///
/// Every check is made in [`Self::build`], which returns a [`CosimError`]
/// naming what is wrong: an unknown sprocket name, an index out of range, a
/// sprocket mounted twice, a body that is not in the world or carries two
/// sprockets, a mount not at its sprocket's centre (after the pose), a
/// coupling that cannot be used. Nothing is added to the world on an error.
#[derive(Clone, Debug)]
pub struct ChainDriveBuilder<'a> {
    scene: &'a Scene,
    mounts: Vec<(SprocketKey, RigidBodyHandle)>,
    coupling: Option<Coupling>,
    pose: Option<Pose>,
    settled: Option<Arc<Settled>>,
    start_moving: bool,
}

impl ChainDrive {
    /// A builder for `scene`'s drive ([`ChainDriveBuilder`]).
    pub fn builder(scene: &Scene) -> ChainDriveBuilder<'_> {
        ChainDriveBuilder::new(scene)
    }
}

impl<'a> ChainDriveBuilder<'a> {
    /// A drive of `scene`, every sprocket on a body of the drive's own, the
    /// scene's coupling, at the scene's coordinates.
    pub fn new(scene: &'a Scene) -> Self {
        Self {
            scene,
            mounts: Vec::new(),
            coupling: None,
            pose: None,
            settled: None,
            start_moving: false,
        }
    }

    /// Mounts a sprocket (by name or index) on the user's `body`: a dynamic
    /// body turns with the chain (its inertia is the body's), a kinematic or
    /// fixed one turns the sprocket at its own speed (see
    /// [`ChainDrive::insert`]). The body must sit at the sprocket's centre
    /// (with the pose applied).
    pub fn mount(mut self, sprocket: impl Into<SprocketKey>, body: RigidBodyHandle) -> Self {
        self.mounts.push((sprocket.into(), body));
        self
    }

    /// How the user's colliders near the rollers are treated (default:
    /// [`Coupling::new`] with the scene's contact law).
    pub fn coupling(mut self, coupling: Coupling) -> Self {
        self.coupling = Some(coupling);
        self
    }

    /// Places the whole drive at `pose`: the scene's coordinates are the
    /// drive's own frame, and a point `p` of the scene (a sprocket's centre,
    /// a guide's end, a tensioner's pivot) goes to `pose * p` in the world.
    /// Directions turn with it (a tensioner's line); the scene's gravity does
    /// not (it is the world's). Default: the identity.
    pub fn insert_at(mut self, pose: Pose) -> Self {
        self.pose = Some(pose);
        self
    }

    /// Starts the drive from `drive`'s static equilibrium, as it settled
    /// when `drive` was built (whatever it has done since), instead of
    /// settling anew: the same drive inserted again, into another world or
    /// after [`ChainDrive::remove`], in microseconds per roller instead of
    /// the solve's milliseconds to seconds. `drive` must have been built
    /// from the same scene at the same pose ([`Self::build`] names the
    /// mismatch otherwise). The rest state is `drive`'s: where no sprocket
    /// of the scene is held (a driver), `drive`'s solve held one mounted
    /// sprocket at rest (see [`ChainDrive::insert`]), and the loads stay
    /// reacted there.
    pub fn settled_from(mut self, drive: &ChainDrive) -> Self {
        self.settled = Some(Arc::clone(&drive.settled));
        self
    }

    /// Starts the drive already moving at its driver's speed, as it runs
    /// once settled, instead of ramping the driver up from rest: the
    /// driver's ramp (`ramp_s`) is skipped, every roller moves along the
    /// chain's path at the speed the driver gives it, every free sprocket
    /// turns at the speed its seated rollers give it (so an equal-pitch
    /// sprocket of z teeth at the driver's ω·z_driver/z), from the static
    /// equilibrium's positions and tensions. A start from rest launches a
    /// wave along the chain that a long chain carries for seconds (the
    /// sprockets' speeds swing with it); started moving, the chain only
    /// takes up the small difference between the rest and the running
    /// tensions. [`Self::build`] names the error where the scene has no
    /// driver with a speed (`speed_rpm`) or the driver is mounted (a
    /// mount's own speed sets the chain moving, see [`ChainDrive::insert`]).
    pub fn start_moving(mut self) -> Self {
        self.start_moving = true;
        self
    }

    /// The mounts by sprocket index, checked: names known, indices in
    /// range, no sprocket mounted twice.
    fn resolve(&self, scene: &Scene) -> Result<Vec<Option<RigidBodyHandle>>, CosimError> {
        let sprockets = scene.sprockets();
        let mut by_index = vec![None; sprockets.len()];
        for (key, body) in &self.mounts {
            let k = super::sprockets::resolve(scene, key, "mount")?;
            if by_index[k].is_some() {
                return Err(CosimError::input(
                    format!("mount({key})"),
                    format!(
                        "sprocket {k} ({:?}) is mounted twice: one body per sprocket",
                        sprockets[k].name
                    ),
                ));
            }
            by_index[k] = Some(*body);
        }
        Ok(by_index)
    }

    /// Builds the drive into `world` (see [`ChainDrive::insert`] for what is
    /// added, how mounts behave and what the static equilibrium costs;
    /// nothing of it with [`Self::settled_from`]).
    pub fn build(self, world: &mut PhysicsWorld) -> Result<ChainDrive, CosimError> {
        self.build_in(&mut world.bodies, &mut world.colliders)
    }

    /// [`Self::build`] into the user's own sets.
    pub fn build_in(
        self,
        bodies: &mut RigidBodySet,
        colliders: &mut ColliderSet,
    ) -> Result<ChainDrive, CosimError> {
        if let Some(c) = &self.coupling {
            check_coupling(c)?;
        }
        let posed;
        let scene = match &self.pose {
            Some(pose) => {
                posed = posed_scene(self.scene, pose)?;
                &posed
            }
            None => self.scene,
        };
        let mounts = self.resolve(scene)?;
        let settled = match self.settled {
            Some(s) if s.given == *scene => s,
            Some(s) => {
                return Err(CosimError::input(
                    "settled_from",
                    format!(
                        "the drive given was settled from scene {:?}{}, not from this builder's \
                         scene and pose: settle from a drive of the same scene, placed alike",
                        s.given.name,
                        if s.given.name == scene.name {
                            " (another version or pose)"
                        } else {
                            ""
                        }
                    ),
                ));
            }
            None => settled::settle(scene, settled::held_for_the_solve(scene, &mounts, bodies))?,
        };
        let mut drive =
            ChainDrive::insert_settled(settled, &mounts, bodies, colliders, self.start_moving)?;
        if let Some(c) = self.coupling {
            drive.coupling = c;
            drive.apply_tooth_tips();
        }
        Ok(drive)
    }
}

/// `scene` moved to `pose`: every point and direction of its file form
/// transformed, then validated again.
fn posed_scene(scene: &Scene, pose: &Pose) -> Result<Scene, CosimError> {
    let (t, a) = (pose.translation, pose.rotation.angle());
    if !(t.is_finite() && a.is_finite()) {
        return Err(CosimError::input(
            "insert_at",
            format!(
                "a pose at [{}, {}] m turned {a} rad: a finite pose",
                t.x, t.y
            ),
        ));
    }
    let point = |p: &mut [f64; 2]| {
        let q = pose.transform_point(Vector::new(p[0], p[1]));
        *p = [q.x, q.y];
    };
    let direction = |p: &mut [f64; 2]| {
        let q = pose.transform_vector(Vector::new(p[0], p[1]));
        *p = [q.x, q.y];
    };
    let mut file = scene.file.clone();
    for s in &mut file.sprockets {
        point(&mut s.center_m);
    }
    for g in &mut file.guides {
        point(&mut g.start_m);
        point(&mut g.end_m);
        if let Some(c) = &mut g.center_m {
            point(c);
        }
    }
    for arm in &mut file.tensioners {
        point(&mut arm.pivot_m);
        if let Some(c) = &mut arm.center_of_mass_m {
            point(c);
        }
        point(&mut arm.shoe_center_m);
        point(&mut arm.point_m);
        direction(&mut arm.direction);
        arm.shoe_start_deg += a.to_degrees();
        arm.shoe_end_deg += a.to_degrees();
    }
    let mut posed = Scene::try_from(file).map_err(|e| {
        CosimError::input(
            "insert_at",
            format!("the scene placed at the pose is not valid: {e}"),
        )
    })?;
    posed.source_toml.clone_from(&scene.source_toml);
    Ok(posed)
}
