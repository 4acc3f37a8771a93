//! Parking (`ChainDrive::set_parking`): the roller bodies no user collider
//! can reach leave rapier's step; what the user's bodies meet stays the
//! same. The reference is the same world stepped with every roller body in
//! rapier's step.

use super::cosim_tests::conveyor;
use crate::cosim::ChainDrive;
use rapier2d_f64::prelude::*;

/// Radius of the conveyor's rollers, m (its scene).
const ROLLER_RADIUS_M: f64 = 0.00397;

struct Run {
    world: PhysicsWorld,
    drive: ChainDrive,
    /// A box laid on the upper strand near the tail, and a ball dropped
    /// 0.2 m onto the strand ahead of it.
    bodies: [RigidBodyHandle; 2],
}

fn run(parking: bool) -> Run {
    let scene = conveyor("role = \"driver\"\nspeed_rpm = 60.0\nramp_s = 0.5", 0.0);
    let mut world = PhysicsWorld {
        gravity: Vector::new(0.0, -9.81),
        ..PhysicsWorld::default()
    };
    let mut drive =
        ChainDrive::insert(&scene, &[], &mut world.bodies, &mut world.colliders).expect("drive");
    drive.set_parking(parking);
    let top = drive.model().sprockets[0].pitch_radius_m + ROLLER_RADIUS_M;
    let bx = world
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.9, top + 0.026)));
    world.colliders.insert_with_parent(
        ColliderBuilder::cuboid(0.05, 0.025)
            .density(20.0)
            .friction(0.8),
        bx,
        &mut world.bodies,
    );
    let ball = world
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.75, top + 0.2)));
    world.colliders.insert_with_parent(
        ColliderBuilder::ball(0.02).density(500.0).friction(0.5),
        ball,
        &mut world.bodies,
    );
    Run {
        world,
        drive,
        bodies: [bx, ball],
    }
}

#[test]
fn parked_rollers_leave_a_carried_box_and_a_dropped_ball_as_they_were() {
    let (mut parked, mut all) = (run(true), run(false));
    let mut fewest_in_step = usize::MAX;
    let mut ball_carried = false;
    let mut most_parked = 0;
    for frame in 0..60 {
        for r in [&mut parked, &mut all] {
            r.drive.step_world(&mut r.world, &(), &()).expect("frame");
        }
        fewest_in_step = fewest_in_step.min(100 - parked.drive.parked_rollers());
        ball_carried |= parked.drive.carries(parked.bodies[1]);
        most_parked = most_parked.max(parked.drive.parked_rollers());
        for (&a, &b) in parked.bodies.iter().zip(&all.bodies) {
            let (pa, pb) = (
                parked.world.bodies[a].position(),
                all.world.bodies[b].position(),
            );
            let off = (pa.translation - pb.translation).length();
            let turn = (pa.rotation.angle() - pb.rotation.angle()).abs();
            assert!(
                off < 1e-9 && turn < 1e-9,
                "frame {frame}: {off:e} m, {turn:e} rad"
            );
        }
        let (sa, sb) = (parked.drive.state(), all.drive.state());
        let worst =
            sa.x.iter()
                .zip(&sb.x)
                .chain(sa.y.iter().zip(&sb.y))
                .map(|(a, b)| (a - b).abs())
                .fold(0.0f64, f64::max);
        assert!(worst < 1e-9, "frame {frame}: chain {worst:e} m apart");
    }
    // Not vacuous: the box rode the chain (60 rpm on a 20-tooth, 25.4 mm
    // sprocket, pitch radius 81.2 mm: 0.51 m/s, so 0.38 m in the 1 s with
    // its 0.5 s ramp, less what the box slips taking up speed), the ball
    // landed on the strand, and rollers were parked. A body's reach is its
    // box loosened on each side by its own travel bound and the rollers'
    // (the 5 m/s search speed over 1/60 s, 83 mm, each), the rollers'
    // 2 × 0.51 m/s over the frame (17 mm), their radius and 50 mm: about
    // 0.24 m. The box's (0.58 m long) and the ball's (0.52 m), overlapping,
    // cover both strands over about 30 pitches: some 60 rollers, so about
    // 40 of the 100 are parked while the two bodies are close together.
    let [bx, ball] = parked.bodies;
    let moved = 0.9 - parked.world.bodies[bx].translation().x;
    assert!(moved > 0.15, "the box moved {moved} m");
    let top = parked.drive.model().sprockets[0].pitch_radius_m + ROLLER_RADIUS_M;
    let ball_y = parked.world.bodies[ball].translation().y;
    assert!(ball_y < top + 0.1, "ball at y = {ball_y}");
    assert!(ball_carried, "the rollers never carried the ball");
    assert!(most_parked > 20, "at most {most_parked} rollers parked");
    assert!(fewest_in_step >= 1, "roller 0 stays in the step");
    // The rollers under the box are in rapier's step, at the chain's rollers.
    let p = parked.world.bodies[bx].translation();
    let s = parked.drive.state();
    let mut under = 0;
    for (i, &h) in parked.drive.roller_bodies().iter().enumerate() {
        if (s.x[i] - p.x).abs() < 0.05 && s.y[i] > 0.0 {
            let b = &parked.world.bodies[h];
            assert!(b.is_enabled(), "roller {i} under the box is parked");
            let off = (b.translation() - Vector::new(s.x[i], s.y[i])).length();
            assert!(off < 1e-9, "roller {i}'s body {off:e} m from its roller");
            under += 1;
        }
    }
    assert!(under >= 3, "{under} rollers under the box");
}

#[test]
fn parking_off_puts_every_roller_body_back_at_its_roller() {
    let mut r = run(true);
    for _ in 0..20 {
        r.drive.step_world(&mut r.world, &(), &()).expect("frame");
    }
    assert!(
        r.drive.parked_rollers() > 20,
        "{}",
        r.drive.parked_rollers()
    );
    r.drive.set_parking(false);
    r.drive.step_world(&mut r.world, &(), &()).expect("frame");
    assert_eq!(r.drive.parked_rollers(), 0);
    let s = r.drive.state();
    for (i, &h) in r.drive.roller_bodies().iter().enumerate() {
        let b = &r.world.bodies[h];
        assert!(b.is_enabled(), "roller {i} still parked");
        let off = (b.translation() - Vector::new(s.x[i], s.y[i])).length();
        assert!(off < 1e-9, "roller {i}'s body {off:e} m from its roller");
    }
}
