//! One frame of a co-simulated drive: [`ChainDrive::before_step`] (the
//! checks, the mounts and the user's colliders near the chain read, then the
//! chain's substeps to the frame's end and its bodies set for rapier's step)
//! and [`ChainDrive::after_step`] (what rapier's step did to the chain, and
//! the users' forces, torques and gravity scales put back).

use rapier2d_f64::prelude::*;

use super::*;

impl ChainDrive {
    /// Advances the chain to the end of the coming frame of `dt_s` and sets
    /// its bodies for rapier's step. Call right before the user's step, with
    /// the world's gravity (carried bodies feel it in the substeps) and the
    /// world's dt. A blow-up of the chain is an error (the bodies are then
    /// left as they were), as are a dt that is not positive and finite and a
    /// mount removed from `bodies`.
    pub fn before_step(
        &mut self,
        bodies: &mut RigidBodySet,
        colliders: &ColliderSet,
        gravity: Vector,
        dt_s: f64,
    ) -> Result<(), CosimError> {
        self.check_world(bodies, colliders, gravity, dt_s)?;
        let frame = self.begin_frame(bodies, colliders, gravity, dt_s, None)?;
        self.run_frame(bodies, dt_s, frame)
    }

    /// The first half of [`Self::before_step`], after
    /// [`Self::check_world`]: mounts read, the user's colliders near the
    /// chain found (leaving `others`' bodies alone). Touches only mounted
    /// bodies' user torques.
    pub(super) fn begin_frame(
        &mut self,
        bodies: &mut RigidBodySet,
        colliders: &ColliderSet,
        gravity: Vector,
        dt_s: f64,
        others: Option<&Others<'_>>,
    ) -> Result<FrameStart, CosimError> {
        self.note_gravity(gravity);
        let started = Instant::now();
        // Sprockets: centres, user torques (taken out of rapier's step). A
        // mounted body moves on through the frame at its velocity (rapier's
        // step will take it there): its sprocket follows in the substeps. A
        // kinematic mount turns its sprocket at its own speed.
        let mut moving = false;
        let span = dt_s;
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
            let sprocket = &mut self.model.sprockets[k];
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
        if moving {
            // The kept reach sets assumed the old centres and speeds.
            self.forces.forget_reach();
        }
        for (s, p) in self
            .start
            .iter_mut()
            .zip(self.state.x.iter().zip(&self.state.y))
        {
            *s = [*p.0, *p.1];
        }
        self.theta0.copy_from_slice(&self.state.theta);
        let colliders_map = &self.colliders;
        let owns = |h: ColliderHandle| {
            colliders_map.contains_key(&h) || others.is_some_and(|o| (o.owns)(h))
        };
        let (own_mounts, links) = (&self.mounted, &self.links);
        let mounted = |b: RigidBodyHandle| {
            holds_body(own_mounts, links, b) || others.is_some_and(|o| (o.mounted)(b))
        };
        self.contacts.prepare(
            &self.coupling,
            &DriveView {
                owns: &owns,
                mounted: &mounted,
                roller_colliders: &self.roller_colliders,
                state: &self.state,
            },
            bodies,
            colliders,
            gravity,
            dt_s,
        );
        self.mark_reach(bodies, colliders, others, dt_s);
        Ok(FrameStart { started, moving })
    }

    /// The second half of [`Self::before_step`]: the substeps, and the
    /// bodies set for rapier's step.
    pub(super) fn run_frame(
        &mut self,
        bodies: &mut RigidBodySet,
        dt_s: f64,
        frame: FrameStart,
    ) -> Result<(), CosimError> {
        let FrameStart { started, moving } = frame;
        let span = dt_s;
        let searched = Instant::now();
        let substeps = self.substeps(dt_s, moving)?;
        self.check_substeps(bodies, substeps, dt_s)?;
        let stepped = Instant::now();
        self.hand_back(bodies, substeps, span);
        self.frame_dt_s = dt_s;
        self.in_frame = true;
        self.hook_calls_at_frame = self.hook_calls.load(Ordering::Relaxed);
        let t = &mut self.stage_times;
        t.frames += 1;
        t.search_s += (searched - started).as_secs_f64();
        t.substeps_s += (stepped - searched).as_secs_f64();
        t.sync_s += stepped.elapsed().as_secs_f64();
        t.projections = self.contacts.projections;
        Ok(())
    }

    /// Substeps at the scene's dt until the world's frame end of `dt_s`,
    /// moving the mounts with them where any moves; how many it took.
    fn substeps(&mut self, dt_s: f64, moving: bool) -> Result<u64, CosimError> {
        // The chain's clock lags the world's by less than one substep and is
        // counted from the start (steps × dt) as `Simulation::run` counts it,
        // so a drive with no outside contact evolves exactly as it does
        // standalone.
        self.world_time_s += dt_s;
        let dt = self.scene.solver.dt_s;
        let t0 = self.state.t_s;
        let substeps = ((self.world_time_s - t0) / dt + 1e-9).floor().max(0.0) as u64;
        self.force_sum.fill([0.0; 2]);
        let with_bodies = !self.contacts.is_empty();
        for step in 1..=substeps {
            if self.any_external {
                for (i, f) in self.external.iter().enumerate() {
                    self.forces.output_mut().fx[i] += f.x;
                    self.forces.output_mut().fy[i] += f.y;
                }
            }
            if with_bodies {
                let tau = (step - 1) as f64 * dt;
                self.contacts.apply(
                    &self.coupling,
                    &self.state,
                    self.forces.output_mut(),
                    tau,
                    dt,
                );
            }
            // The rollers' update and the links at the new state in one
            // pass (large drives); the mounts' move does not touch the links.
            let linked =
                symplectic_euler_with_links(&self.model, &mut self.state, &mut self.forces, dt);
            if with_bodies {
                self.contacts.integrate(dt);
            }
            self.clock_steps += 1;
            self.state.t_s = self.clock_steps as f64 * dt;
            if moving {
                self.move_mounts(step, t0, dt);
            }
            if linked {
                self.forces.evaluate_after_links(&self.model, &self.state);
            } else {
                self.forces.evaluate(&self.model, &self.state);
            }
            check_blow_up(&self.model, &self.state, &self.forces, &self.limits)
                .map_err(|e| at_coupling_limit(e, dt_s))?;
            for (sum, f) in self
                .force_sum
                .iter_mut()
                .zip(&self.forces.output().chain_force)
            {
                sum[0] += f[0];
                sum[1] += f[1];
            }
        }
        Ok(substeps)
    }

    /// Moves the mounted sprockets' centres over substep `step` (of `dt`
    /// from the frame's start `t0`): a translating mount by the chain's
    /// force and its law, another by its velocity.
    fn move_mounts(&mut self, step: u64, t0: f64, dt: f64) {
        let tau = step as f64 * dt;
        let chain_force = &self.forces.output().chain_force;
        for (k, (link, sprocket)) in self
            .links
            .iter_mut()
            .zip(&mut self.model.sprockets)
            .enumerate()
        {
            if let Some(tr) = &mut link.translation {
                // The chain's force and the law's at the substep's
                // start, as the rollers were advanced.
                let start = Vector::new(link.frame_start_m[0], link.frame_start_m[1]);
                let law = self.mount_forces[k].as_ref().map_or(Vector::ZERO, |f| {
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

    /// The frame's checks after its substeps: no roller too deep in a
    /// user's collider, every carried and mounted body finite.
    fn check_substeps(
        &mut self,
        bodies: &mut RigidBodySet,
        substeps: u64,
        dt_s: f64,
    ) -> Result<(), CosimError> {
        if self.contacts.max_depth_m > self.limits.max_penetration_m {
            return Err(at_coupling_limit(
                SimError::BlowUp {
                    t_s: self.state.t_s,
                    detector: crate::sim::Detector::Penetration.name(),
                    body: "a roller against a user's collider".to_owned(),
                    value: self.contacts.max_depth_m,
                    limit: self.limits.max_penetration_m,
                    detail: String::new(),
                },
                dt_s,
            ));
        }
        if !self.contacts.finish_substeps(bodies, substeps, dt_s) {
            return Err(at_coupling_limit(
                SimError::BlowUp {
                    t_s: self.state.t_s,
                    detector: crate::sim::Detector::NonFinite.name(),
                    body: "a carried body".to_owned(),
                    value: f64::NAN,
                    limit: 0.0,
                    detail: String::new(),
                },
                dt_s,
            ));
        }
        for link in &mut self.links {
            if let Some(tr) = &mut link.translation {
                tr.mean_v = tr.dx / dt_s;
                if let Some((_, sf)) = &mut tr.slide {
                    sf.motor_sum /= substeps.max(1) as f64;
                }
                if !(tr.mean_v.is_finite() && tr.v.is_finite()) {
                    return Err(at_coupling_limit(
                        SimError::BlowUp {
                            t_s: self.state.t_s,
                            detector: crate::sim::Detector::NonFinite.name(),
                            body: "a mounted body".to_owned(),
                            value: f64::NAN,
                            limit: 0.0,
                            detail: String::new(),
                        },
                        dt_s,
                    ));
                }
            }
        }
        Ok(())
    }

    /// Hands the frame back to rapier: the rollers synced, each sprocket's
    /// body set to turn (and a mount to move) over the frame `span` as the
    /// substeps did, the chain's mean force on it.
    fn hand_back(&mut self, bodies: &mut RigidBodySet, substeps: u64, span: f64) {
        self.sync_rollers(bodies, span);
        let n = substeps.max(1) as f64;
        for (k, link) in self.links.iter_mut().enumerate() {
            link.mean_omega = (self.state.theta[k] - self.theta0[k]) / span;
            link.mean_chain_force = [self.force_sum[k][0] / n, self.force_sum[k][1] / n];
            let Some(b) = bodies.get_mut(link.body) else {
                continue;
            };
            match link.mount {
                // rapier turns a kinematic mount itself; the chain followed it.
                Mount::Kinematic => {}
                Mount::Own => {
                    b.set_rotation(Rotation::new(self.theta0[k]), true);
                    b.set_angvel(link.mean_omega, true);
                }
                Mount::Dynamic => {
                    b.set_rotation(Rotation::new(self.theta0[k] + link.angle_offset), true);
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
                        let law = self.mount_forces[k].as_ref().map_or(Vector::ZERO, |f| {
                            f.force(b.translation(), b.linvel(), self.state.t_s)
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

    /// Reads what rapier's step did to the drive's bodies beyond the chain's
    /// own motion — the contact impulses bodies that are not carried
    /// exchanged with the rollers, the speed change joints gave mounted
    /// sprockets, what other contacts and joints did to carried bodies — and
    /// restores the users' torques, forces and gravity scales. Call right
    /// after the user's step, with the same `dt_s` as [`Self::before_step`].
    ///
    /// An error, touching nothing, when the frame does not add up: no
    /// `before_step` before it, another `dt_s`, a world stepped by another dt
    /// (the roller bodies are not where the chain is), or a world stepped
    /// without [`Self::hooks`] while a dynamic body carries a sprocket.
    pub fn after_step(
        &mut self,
        bodies: &mut RigidBodySet,
        narrow_phase: &NarrowPhase,
        dt_s: f64,
    ) -> Result<(), CosimError> {
        self.check_frame(bodies, narrow_phase, dt_s)?;
        self.in_frame = false;
        let started = Instant::now();
        let span = dt_s;
        self.any_external = false;
        for (i, &rc) in self.roller_colliders.iter().enumerate() {
            if !self.roller_active[i] {
                self.external[i] = Vector::ZERO;
                continue;
            }
            let mut impulse = [0.0f64; 2];
            for pair in narrow_phase.contact_pairs_with(rc) {
                if !pair.has_any_active_contact() {
                    continue;
                }
                // rapier applies `impulse` along −normal and the friction impulse along
                // its perpendicular to collider 1's body, the opposite to collider 2's.
                let sign = if pair.collider1 == rc { 1.0 } else { -1.0 };
                for manifold in pair.manifolds() {
                    let d = -manifold.data.normal;
                    let t = Vector::new(-d.y, d.x);
                    for point in &manifold.points {
                        let (n, f) = (point.data.impulse, point.data.tangent_impulse[0]);
                        impulse[0] += sign * (n * d.x + f * t.x);
                        impulse[1] += sign * (n * d.y + f * t.y);
                    }
                }
            }
            self.external[i] = Vector::new(impulse[0] / span, impulse[1] / span);
            self.any_external |= impulse != [0.0; 2];
        }
        for (k, link) in self.links.iter().enumerate() {
            if link.mount != Mount::Dynamic {
                continue;
            }
            if let Some(b) = bodies.get_mut(link.body) {
                // The body's joints changed its speed by this much during rapier's step.
                self.state.omega[k] += b.angvel() - link.mean_omega;
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
        let colliders = &self.colliders;
        let is_roller = |h: ColliderHandle| colliders.get(&h).copied().unwrap_or(false);
        self.contacts.after_step(bodies, narrow_phase, &is_roller);
        self.stage_times.sync_s += started.elapsed().as_secs_f64();
        Ok(())
    }
}
