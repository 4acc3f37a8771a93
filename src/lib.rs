//! # chaindrive
//!
//! Dynamic simulation of roller-chain drives after S. L. Pedersen, "Model of
//! contact between rollers and sprockets in chain-drive systems", Arch. Appl.
//! Mech. 74 (2005) 489–508, as a plugin for the [rapier](https://rapier.rs)
//! 2D physics engine (f64).
//!
//! Rollers are lumped masses joined by linear spring-damper links; sprockets
//! are rigid bodies; each roller touches the sprocket teeth through a
//! continuous Hertzian penalty force (Lankarani–Nikravesh, or another law of
//! the Hunt–Crossley family) against a circular seating profile or the real
//! ASA B29.1 tooth form. Five integrators advance the chain
//! ([`scene::Integrator`]), from rapier's symplectic Euler to an adaptive
//! Dormand–Prince with located contact events.
//! The model shows polygonal action, roller impacts, link-force fluctuation
//! and the transverse vibration of the free strands.
//!
//! ## The front door
//!
//! `use chaindrive::prelude::*;` brings in what a user needs: the scene, a
//! run, its observers and summary, the drive in your own rapier world, the
//! recorder, their errors, and the seam for force elements of your own
//! ([`prelude`]). Five modules hold the rest of what a user may name, each
//! for one concept: [`scene`] (a scene's parts and its file form), [`sim`]
//! (a run's outcome, its errors, observers composed), [`cosim`] (mounts,
//! couplings, several drives in one world), [`analysis`] (the run summary's
//! parts) and [`record`] (the recording's channels). Everything else is
//! the crate's own (`docs/architecture.md`, "The public surface").
//!
//! ## Pipeline
//!
//! The data flows once, forward; each stage lives in one module and never
//! imports a later one (the stages without a link are the crate's own). `geometry` is plain arithmetic that imports nothing
//! else of the crate, so it is the lowest stage: the scene uses it for the
//! sprockets' pitch radii and to generate drives whose chain path closes.
//!
//! | stage | module | what it does |
//! |---|---|---|
//! | geometry | `geometry` | tooth profiles, chain path (plain/crossed tangents), roller layout |
//! | scene | [`scene`] | TOML → validated [`scene::Scene`], every error with its field path |
//! | model | `model` | parameters, structure-of-arrays state, rapier bodies |
//! | forces | `forces` | link spring-dampers, contact law, roller–tooth contact generator |
//! | stepping | [`sim`] | static equilibrium, substepped or rapier-integrated steps, blow-up detection, observers |
//! | co-simulation | [`cosim`] | the drive inside a user's rapier world, stepped at the user's dt |
//! | analysis | [`analysis`] | sampled signals, spectra, run summary, analytical references |
//! | studies | `studies` (feature `lab`) | experiments of many runs: the paper's study, stress matrix, work-precision, soak, fuzz |
//!
//! ## Quick start
//!
//! ```no_run
//! use chaindrive::prelude::*;
//!
//! // The paper's drive, for 2 s instead of the scene file's 10 s.
//! let scene = Scene::l60mc().with(&Overrides { duration_s: Some(2.0), ..Overrides::default() })?;
//! let mut sim = Simulation::new(&scene)?; // layout + static equilibrium at 21 kN
//! // 1 kHz: every 100 steps of 10 µs (a rate the step does not divide is an error).
//! let sampling = SampleRate::new(1000.0, scene.solver().dt_s)?;
//! // Statistics over the last second after the 1 s ramp (`Some(s)`: the last s seconds),
//! // their means counted every step of it.
//! let window = StatsWindow::of(&scene, None)?;
//! let mut signals = window.observe(&mut sim, sampling.rate_hz);
//! let outcome = sim.run(scene.solver().duration_s, sampling.every, &mut signals, None)?;
//! let summary = RunSummary::of_run_in(&sim, &outcome, &signals, 0.0, &window);
//! println!("segment 1 mean link force: {:.0} N", summary.segments[0].mean_link_force_n);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! ## Using chaindrive in your rapier scene
//!
//! [`cosim::ChainDrive`] adds a drive's bodies to your own sets (a sprocket
//! may sit on a body you already have: a motor shaft, a wheel), substeps the
//! chain at the scene's `dt_s` inside each of your world's steps, and keeps
//! rapier's solver out of roller–sprocket and roller–roller pairs through
//! [`cosim::ChainHooks`], which hands every other pair to your own hooks.
//! Your colliders meet the rollers inside the chain's substeps
//! ([`cosim::Coupling`]): fixed and kinematic ones (guides, wear strips)
//! push the chain, dynamic bodies near it (boxes on a conveyor) are carried
//! with it at its dt — heavy ones too — and handed back to your step.
//!
//! ```
//! use chaindrive::prelude::*;
//! use rapier2d_f64::prelude::*;
//!
//! let scene = Scene::from_toml(include_str!("../assets/conveyor.toml"))?;
//! let mut world = PhysicsWorld::default(); // your world, 60 Hz
//! // Your motor: a body on a fixed axle; the head sprocket is mounted on it.
//! let motor = world.bodies.insert(
//!     RigidBodyBuilder::dynamic()
//!         .lock_translations()
//!         .additional_mass_properties(MassProperties::new(Vector::ZERO, 2.0, 0.05)),
//! );
//! // The drive, its head mounted on the motor (by name or index; checked).
//! let mut drive = ChainDrive::builder(&scene)
//!     .mount("head (motor)", motor)
//!     .build(&mut world)?;
//! for _ in 0..6 {
//!     // Your motor torque, as you would set it for any rapier body.
//!     world.bodies[motor].reset_torques(false);
//!     world.bodies[motor].add_torque(5.0, true);
//!     drive.step_world(&mut world, &(), &())?; // before_step + world step + after_step
//! }
//! // A sprocket by name, then by its id in every per-sprocket call.
//! let head = drive.sprocket("head (motor)")?;
//! assert!(drive.sprocket_speed(head) > 0.0 && world.bodies[motor].angvel() > 0.0);
//!
//! // The same frame, composed with your own pipeline call and hooks:
//! let dt = world.integration_parameters.dt;
//! drive.before_step(&mut world.bodies, &world.colliders, world.gravity, dt)?;
//! world.step_with_events(&drive.hooks(&()), &());
//! drive.after_step(&mut world.bodies, &world.narrow_phase, dt)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! [`cosim::ChainDriveBuilder`] takes the scene, the mounts by sprocket
//! name or index (an unknown name, an index out of range or a sprocket
//! mounted twice is an error naming it), the [`cosim::Coupling`] and a pose
//! for the whole drive (`insert_at(pose)`: the scene's coordinates are the
//! drive's own frame), then `build`s into your world;
//! [`cosim::ChainDrive::insert`] is the same with mounts by index. The
//! drive's scene, model and state are read-only (`drive.state()`,
//! `drive.model()`); what you change mid-run has a setter
//! (`set_load_torque`, `set_driver_speed`, `set_governor_target`,
//! `set_driver_torque`, `set_coupling`). A sprocket is named by the
//! [`cosim::SprocketId`] that `drive.sprocket("tail")` finds (by name or
//! index), which every per-sprocket setter and getter takes
//! (`set_load_torque`, `set_mount_force`, `sprocket_speed`,
//! `sprocket_angle`, `chain_torque_on_sprocket`, `sprocket_body`).
//! Positions, velocities and forces at the boundary are rapier's `Vector`
//! (`roller_position(i)`, `roller_positions()`, `chain_force_on(body)`). Observers ([`sim::Observer`], several through
//! [`sim::Fanout`]) see the drive once per frame through
//! `step_world_observed`; `record::Recorder::co_simulated(writer,
//! drive.scene(), ...)` records the run with its
//! frame step, its real duration and mounted sprockets where their bodies
//! are.
//!
//! A fixed guide is any collider of yours; here a wear strip under the upper
//! strand, pressed 10 µm into its lowest roller (the strand sags under its
//! own weight):
//!
//! ```
//! # use chaindrive::prelude::*;
//! # use rapier2d_f64::prelude::*;
//! # let scene = Scene::from_toml(include_str!("../assets/conveyor.toml"))?;
//! # let mut world = PhysicsWorld::default();
//! let mut drive = ChainDrive::insert(&scene, &[], &mut world.bodies, &mut world.colliders)?;
//! let s = drive.state();
//! let lowest = (0..s.rollers())
//!     .filter(|&i| s.y[i] > 0.0 && (0.15..0.85).contains(&s.x[i]))
//!     .map(|i| s.y[i])
//!     .fold(f64::INFINITY, f64::min);
//! let top = lowest - scene.chain().roller_radius_m + 1e-5;
//! let strip = ColliderBuilder::cuboid(0.35, 0.005)
//!     .translation(Vector::new(0.5, top - 0.005))
//!     .friction(0.1);
//! world.colliders.insert(strip);
//! drive.step_world(&mut world, &(), &())?;
//! // The rollers' mean force from your colliders over that frame, N.
//! let lift: f64 = drive.body_forces().iter().map(|f| f.y).sum();
//! assert!(lift > 0.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! A sprocket on your dynamic body turns with the chain with the body's own
//! inertia, and the forces and torques you set on the body stay as rapier
//! keeps them (the chain's force is added for your step); the body may
//! already turn when the drive is inserted (the chain joins it). A sprocket on
//! your kinematic body turns at the body's speed. A body carrying a sprocket
//! along the chain (a tensioner carriage) is moved in the chain's substeps;
//! give its spring to the drive ([`cosim::ChainDrive::set_mount_force`],
//! [`cosim::MountSpring`]) or make it a prismatic joint's position motor
//! (imitated in the substeps; put the sprocket on a hub with a revolute joint
//! to the carriage), and it holds from 1 kg up at 60 Hz. A spring force you
//! set each frame is held over the frame and lets middle masses swing
//! (`examples/tensioner_carriage.rs` measures all three; docs/architecture.md,
//! "Mounted sprockets", says which joints still act once per frame). Misuse — a
//! bad mount, a bad dt, a world stepped by another dt or without
//! [`cosim::ChainDrive::hooks`] — is a [`cosim::CosimError`], never a panic;
//! [`cosim::ChainDrive::remove`] takes the drive out of your world.
//!
//! Examples: `conveyor.rs` (motor torque, boxes on the upper strand, one of
//! them 250 roller masses, a wear strip),
//! `tensioner_carriage.rs` (a sprung carriage holding the tail, by mass),
//! `bicycle.rs` (rider torque on the crank, drag on the wheel),
//! `paper_in_scene.rs` (the paper's drive beside bouncing balls, with the
//! wall time per frame).
//!
//! ## Units and conventions
//!
//! | quantity | unit | note |
//! |---|---|---|
//! | length, position | m | world frame, +y up |
//! | angle | rad | counter-clockwise positive; polar angles in [0, 2π) in outputs |
//! | time | s | t = 0 after static equilibrium, the driver then ramps up |
//! | force | N | link force tension positive |
//! | torque | N·m | counter-clockwise positive |
//! | speed | m/s, rad/s | rpm only in scene files (`speed_rpm`) |
//! | contact stiffness K_g | N/m^n | n = 1.5 (Hertz) |
//!
//! Sprockets and segments are numbered from 1 in every output; segment k is
//! the free strand from sprocket k to the next. A sprocket's *wrap* is
//! geometry: `ccw` if the chain, followed in scene order, goes
//! counter-clockwise around it. Its rotation follows the chain's travel.
//!
//! ## Features
//!
//! | feature | default | what it adds |
//! |---|---|---|
//! | `cli` | yes | the `chaindrive` binary (clap, anyhow, progress bar, Ctrl-C; the module `cli`); enables `record`, `figures`, `parquet` and `lab` |
//! | `lab` | yes | `studies`: experiments of many runs (speed sweeps, design studies, duty cycles), every batch through one work queue; `csv`; the module `lab`, what a second front end (the Python bindings) calls |
//! | `figures` | yes | PNG and SVG figures (`plotters`, embedded font) for `reproduce`, `sweep` and `analyze` |
//! | `record` | yes | [`record`]: MCAP recordings with Foxglove's schemas (`foxglove`, `mcap`), `run --record` |
//! | `parquet` | yes | a design study's results as a Parquet table (`study collect`); enables `lab` |
//! | `bench-kernels` | no | `benches/kernels.rs`'s reach into the contact law and profile queries; not an API |
//!
//! ## Reproducibility
//!
//! A run is a deterministic function of the scene and the settings: no
//! threads, no random numbers, no wall-clock input. Across machines, results
//! may differ in the last bits where `libm` functions (`sin`, `atan2`, `sqrt`
//! is exact) differ between platforms; chaotic growth then amplifies such
//! differences over seconds of simulated time, as it would any perturbation.

// Every public type is nameable from outside: a type reachable through the
// public API but unnameable would be a gap in the front door.
#![warn(unnameable_types)]
// Without the command-line tool, the parts of the crate only it drives
// (the studies, the reports, the recording reader) are compiled but unused.
#![cfg_attr(not(feature = "cli"), allow(dead_code, unused_imports))]
pub mod analysis;
#[cfg(feature = "cli")]
pub mod cli;
pub mod cosim;
mod forces;
mod geometry;
#[cfg(feature = "lab")]
pub mod lab;
mod model;
pub mod prelude;
#[cfg(feature = "record")]
pub mod record;
mod rng;
pub mod scene;
pub mod sim;
#[cfg(test)]
mod test_support;

/// The contact law and the tooth-profile queries, for the criterion benches
/// of `benches/kernels.rs` only (feature `bench-kernels`, off by default):
/// not part of the library's API.
#[cfg(feature = "bench-kernels")]
#[doc(hidden)]
pub mod kernels {
    pub use crate::forces::ContactLawParams;
    pub use crate::geometry::asa::{AsaDimensions, AsaProfile, GapPoints, LocatedPatch};
    pub use crate::geometry::{CircularProfile, Patch};
}
#[cfg(feature = "lab")]
mod studies;
