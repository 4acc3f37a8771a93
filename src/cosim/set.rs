//! Several drives in one world: [`DriveSet`].
//!
//! Two [`ChainDrive`]s stepped one after the other in the same world do not
//! know each other: each would take the other's rollers for the user's
//! kinematic bodies and its mounted motor for a box to carry, and a box near
//! both chains would be carried twice (the second drive saving the gravity
//! scale the first had zeroed for rapier's step, so the box floats off). A
//! set steps them as one:
//!
//! - each drive leaves the others' colliders and mounted bodies alone;
//! - a body near several chains is carried by all of them in the same
//!   substeps: the drives' substeps run side by side, and in each every
//!   drive's forces on the body are summed before any copy of it advances
//!   (each drive keeps an equal copy; see `bodies/shared.rs`). One drive,
//!   its keeper (most rollers near it; on a tie, the drive whose first
//!   roller body has the lowest handle), hands it to rapier's step, saving
//!   and restoring its gravity, damping and user force once. Drives of
//!   different `solver.dt_s` cannot share substeps: such a body is carried
//!   by its keeper alone in that frame, the others' rollers passing through it;
//! - one [`SetHooks`] keeps rapier's solver out of every pair of two drives'
//!   colliders and of every roller–carried-body pair.
//!
//! With no shared body in a frame, each drive runs its frame as it would
//! alone. Not coupled: two drives' own bodies (their rollers and sprockets
//! pass through each other).

use std::collections::HashMap;
use std::time::Instant;

use rapier2d_f64::prelude::*;

use super::{ChainDrive, CosimError, DynHooks, FrameStart, Others};

/// Several chain drives stepped together in one rapier world.
#[derive(Default)]
pub struct DriveSet {
    drives: Vec<ChainDrive>,
    /// Scratch: the frame's starts.
    starts: Vec<FrameStart>,
    /// How many drives [`Self::check_shared`] found apart.
    checked: usize,
}

impl DriveSet {
    /// An empty set.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a drive (inserted into the same world); returns its index.
    pub fn push(&mut self, drive: ChainDrive) -> usize {
        self.drives.push(drive);
        self.drives.len() - 1
    }

    /// The drives, in the order they were added.
    pub fn drives(&self) -> &[ChainDrive] {
        &self.drives
    }

    /// The drives, to set loads or speeds.
    pub fn drives_mut(&mut self) -> &mut [ChainDrive] {
        &mut self.drives
    }

    /// Takes the drives back.
    pub fn into_drives(self) -> Vec<ChainDrive> {
        self.drives
    }

    /// Whether a collider belongs to one of the drives.
    pub fn owns_collider(&self, h: ColliderHandle) -> bool {
        self.drives.iter().any(|d| d.owns_collider(h))
    }

    /// Whether one of the drives carried `body` this frame.
    pub fn carries(&self, body: RigidBodyHandle) -> bool {
        self.drives.iter().any(|d| d.carries(body))
    }

    /// Hooks for the user's step: pairs of the drives' colliders and
    /// roller–carried-body pairs are filtered out, every other pair goes to `user`.
    pub fn hooks<'a, H: PhysicsHooks>(&'a self, user: &'a H) -> SetHooks<'a, H> {
        SetHooks { set: self, user }
    }

    /// [`ChainDrive::read_joints`] for every drive.
    pub fn read_joints(&mut self, bodies: &RigidBodySet, joints: &ImpulseJointSet) {
        for d in &mut self.drives {
            d.read_joints(bodies, joints);
        }
    }

    /// [`ChainDrive::joint_motors_off`] for every drive: call right before
    /// the world's step when stepping by hand ([`Self::step_world`] does).
    pub fn joint_motors_off(&mut self, joints: &mut ImpulseJointSet) {
        for d in &mut self.drives {
            d.joint_motors_off(joints);
        }
    }

    /// [`ChainDrive::joint_motors_on`] for every drive: call right after
    /// the world's step.
    pub fn joint_motors_on(&mut self, joints: &mut ImpulseJointSet) {
        for d in &mut self.drives {
            d.joint_motors_on(joints);
        }
    }

    /// [`ChainDrive::before_step`] for the set: every drive finds its
    /// bodies, each body near several chains is given to one drive, then
    /// every drive runs its substeps. An error names the drive (`drives[i]`).
    pub fn before_step(
        &mut self,
        bodies: &mut RigidBodySet,
        colliders: &ColliderSet,
        gravity: Vector,
        dt_s: f64,
    ) -> Result<(), CosimError> {
        self.check_shared()?;
        for (i, drive) in self.drives.iter().enumerate() {
            drive
                .check_world(bodies, colliders, gravity, dt_s)
                .map_err(|e| in_drive(i, e))?;
        }
        self.starts.clear();
        for i in 0..self.drives.len() {
            let (before, rest) = self.drives.split_at_mut(i);
            let Some((drive, after)) = rest.split_first_mut() else {
                continue;
            };
            let others = |f: &dyn Fn(&ChainDrive) -> bool| before.iter().chain(after.iter()).any(f);
            let owns = |h: ColliderHandle| others(&|d| d.owns_collider(h));
            let mounted = |b: RigidBodyHandle| others(&|d| d.holds_body(b));
            let start = drive
                .begin_frame(
                    bodies,
                    colliders,
                    gravity,
                    dt_s,
                    Some(&Others {
                        owns: &owns,
                        mounted: &mounted,
                    }),
                )
                .map_err(|e| in_drive(i, e))?;
            self.starts.push(start);
        }
        if self.share_bodies() {
            return self.run_interleaved(bodies, dt_s);
        }
        for (i, (drive, start)) in self.drives.iter_mut().zip(&self.starts).enumerate() {
            drive
                .run_frame(bodies, dt_s, *start)
                .map_err(|e| in_drive(i, e))?;
        }
        Ok(())
    }

    /// The drives' substeps side by side, substep by substep: in each, every
    /// drive's forces at its current state, then every shared body's total
    /// given to each copy of it, then every drive advanced.
    fn run_interleaved(&mut self, bodies: &mut RigidBodySet, dt_s: f64) -> Result<(), CosimError> {
        let searched = Instant::now();
        let opened: Vec<(u64, f64, bool)> = self
            .drives
            .iter_mut()
            .map(|d| {
                let (substeps, t0) = d.open_substeps(dt_s);
                (substeps, t0, !d.contacts.is_empty())
            })
            .collect();
        let most = opened.iter().map(|o| o.0).max().unwrap_or(0);
        let mut shared: Vec<RigidBodyHandle> = Vec::new();
        for d in &self.drives {
            shared.extend(d.contacts.shared_bodies());
        }
        shared.sort_unstable_by_key(|b| b.into_raw_parts());
        shared.dedup();
        for step in 1..=most {
            let stepping = |k: usize| opened.get(k).is_some_and(|o| step <= o.0);
            for (k, d) in self.drives.iter_mut().enumerate() {
                if let Some(&(_, _, with_bodies)) = opened.get(k).filter(|o| step <= o.0) {
                    d.substep_forces(step, with_bodies);
                }
            }
            for &body in &shared {
                let mut total = (Vector::ZERO, 0.0, 0u32);
                for (k, d) in self.drives.iter().enumerate() {
                    if let Some(p) = d.contacts.push_on(body).filter(|_| stepping(k)) {
                        total = (total.0 + p.0, total.1 + p.1, total.2 + p.2);
                    }
                }
                for d in &mut self.drives {
                    d.contacts.set_total(body, total);
                }
            }
            for (k, (d, start)) in self.drives.iter_mut().zip(&self.starts).enumerate() {
                if let Some(&(_, t0, with_bodies)) = opened.get(k).filter(|o| step <= o.0) {
                    d.substep_advance(step, t0, start.moving, with_bodies, dt_s)
                        .map_err(|e| in_drive(k, e))?;
                }
            }
        }
        for (k, (d, start)) in self.drives.iter_mut().zip(&self.starts).enumerate() {
            let substeps = opened.get(k).map_or(0, |o| o.0);
            d.end_frame(bodies, dt_s, *start, substeps, searched)
                .map_err(|e| in_drive(k, e))?;
        }
        Ok(())
    }

    /// An error when two drives share a body (one was inserted into another
    /// world built the same way, whose handles name this world's bodies):
    /// checked once for each drive added.
    fn check_shared(&mut self) -> Result<(), CosimError> {
        if self.checked == self.drives.len() {
            return Ok(());
        }
        let mut seen: HashMap<RigidBodyHandle, usize> = HashMap::new();
        for (i, d) in self.drives.iter().enumerate() {
            for &h in d.roller_bodies() {
                if let Some(j) = seen.insert(h, i).filter(|&j| j != i) {
                    return Err(CosimError::input(
                        format!("drives[{i}]"),
                        format!(
                            "its bodies are drives[{j}]'s too: it was inserted into another \
                             world (a set's drives are inserted into the world it steps)"
                        ),
                    ));
                }
            }
        }
        self.checked = self.drives.len();
        Ok(())
    }

    /// Marks each body carried by several drives as shared among them, and
    /// gives it to one keeper (most roller pairs; on a tie the drive whose
    /// first roller body has the lowest handle) to hand to rapier's step.
    /// Drives of different `solver.dt_s` cannot advance a body together: a
    /// body near several of those is left to its keeper alone. Whether any
    /// body is shared.
    fn share_bodies(&mut self) -> bool {
        let key = |d: &ChainDrive| d.handles.rollers().first().map(|h| h.into_raw_parts());
        let mut claims: Vec<(RigidBodyHandle, usize, usize)> = Vec::new();
        for (i, d) in self.drives.iter().enumerate() {
            claims.extend(d.contacts.carried_pairs().map(|(b, n)| (b, n, i)));
        }
        let mut any = false;
        for &(body, _, _) in &claims {
            let mine = || claims.iter().filter(|c| c.0 == body);
            let Some(keeper) = mine()
                .max_by(|x, y| {
                    x.1.cmp(&y.1).then_with(|| {
                        // Lower handle wins a tie.
                        key(&self.drives[y.2]).cmp(&key(&self.drives[x.2]))
                    })
                })
                .map(|c| c.2)
            else {
                continue;
            };
            if mine().count() < 2 {
                continue;
            }
            let dt = |i: usize| self.drives[i].scene.solver.dt_s;
            let alike = mine().all(|c| dt(c.2) == dt(keeper));
            for (i, d) in self.drives.iter_mut().enumerate() {
                if alike {
                    d.contacts.share(body, i == keeper);
                } else if i != keeper {
                    d.contacts.release(body);
                }
            }
            any |= alike;
        }
        if any {
            for d in &mut self.drives {
                d.contacts.drop_touches_kept_elsewhere();
            }
        }
        any
    }

    /// [`ChainDrive::after_step`] for every drive.
    pub fn after_step(
        &mut self,
        bodies: &mut RigidBodySet,
        narrow_phase: &NarrowPhase,
        dt_s: f64,
    ) -> Result<(), CosimError> {
        for (i, d) in self.drives.iter_mut().enumerate() {
            d.after_step(bodies, narrow_phase, dt_s)
                .map_err(|e| in_drive(i, e))?;
        }
        Ok(())
    }

    /// One frame of a [`PhysicsWorld`] with the user's hooks and events.
    pub fn step_world(
        &mut self,
        world: &mut PhysicsWorld,
        user_hooks: &dyn PhysicsHooks,
        events: &dyn EventHandler,
    ) -> Result<(), CosimError> {
        let dt = world.integration_parameters.dt;
        self.read_joints(&world.bodies, &world.impulse_joints);
        self.before_step(&mut world.bodies, &world.colliders, world.gravity, dt)?;
        self.joint_motors_off(&mut world.impulse_joints);
        let started = Instant::now();
        world.step_with_events(&self.hooks(&DynHooks(user_hooks)), events);
        let share = started.elapsed().as_secs_f64() / self.drives.len().max(1) as f64;
        self.joint_motors_on(&mut world.impulse_joints);
        for d in &mut self.drives {
            d.stage_times.world_s += share;
        }
        self.after_step(&mut world.bodies, &world.narrow_phase, dt)
    }
}

/// `e` from drive `i` of a set.
fn in_drive(i: usize, e: CosimError) -> CosimError {
    match e {
        CosimError::Input { field, message } => CosimError::Input {
            field: format!("drives[{i}].{field}"),
            message,
        },
        CosimError::World(m) => CosimError::World(format!("drives[{i}]: {m}")),
        other => other,
    }
}

/// Keeps rapier's solver out of the drives' own pairs and their rollers'
/// pairs with carried bodies, and defers everything else to the user's hooks.
pub struct SetHooks<'a, H: PhysicsHooks> {
    set: &'a DriveSet,
    user: &'a H,
}

impl<H: PhysicsHooks> PhysicsHooks for SetHooks<'_, H> {
    fn filter_contact_pair(&self, c: &PairFilterContext) -> Option<SolverFlags> {
        super::hooks::filter_contact_pair(self.set, self.user, c)
    }

    fn filter_intersection_pair(&self, c: &PairFilterContext) -> bool {
        super::hooks::filter_intersection_pair(self.set, self.user, c)
    }

    fn modify_solver_contacts(&self, c: &mut ContactModificationContext) {
        self.user.modify_solver_contacts(c)
    }
}
