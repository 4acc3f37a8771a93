//! Benchmarks: the contact law, the circular profile query, and one chain
//! step of the paper's drive in both stepping modes (running at 120 rpm).
//!
//! ```text
//! cargo bench --bench step
//! ```
//! Numbers and the machine: `benches/README.md`.

// criterion_group! generates an undocumented public function.
#![allow(missing_docs)]

use std::hint::black_box;

use chaindrive::forces::ContactLawParams;
use chaindrive::geometry::{CircularProfile, Patch};
use chaindrive::scene::{Scene, Stepping};
use chaindrive::sim::{NoObserver, Simulation};
use criterion::{Criterion, criterion_group, criterion_main};

/// The paper's drive, run to full speed (1.5 s), in the given stepping mode.
fn running_drive(stepping: Stepping) -> Simulation {
    let mut scene = Scene::l60mc();
    scene.solver.stepping = stepping;
    let mut sim = Simulation::new(&scene).expect("paper drive");
    sim.run(1.5, 1000, &mut NoObserver, None).expect("run");
    sim
}

fn kernels(c: &mut Criterion) {
    let scene = Scene::l60mc();
    let law = ContactLawParams::new(&scene.contact);
    c.bench_function("contact_law/lankarani_nikravesh", |b| {
        b.iter(|| law.force_with(black_box(2e-4), black_box(0.3), black_box(15.0)))
    });
    let profile = CircularProfile::new(60, 0.0889, 0.027);
    let p = [profile.pitch_radius_m - 2e-4, 1e-4];
    c.bench_function("profile/circular_contacts", |b| {
        let mut out = [Patch::default(); 2];
        let mut hint = 0;
        b.iter(|| profile.contacts(black_box(p), &mut hint, &mut out))
    });
}

fn steps(c: &mut Criterion) {
    let mut group = c.benchmark_group("paper_drive_step");
    for stepping in [Stepping::Substepped, Stepping::Rapier] {
        let mut sim = running_drive(stepping);
        let dt = sim.scene.solver.dt_s;
        group.bench_function(stepping.name(), |b| b.iter(|| sim.step(dt)));
    }
    group.finish();
}

criterion_group!(benches, kernels, steps);
criterion_main!(benches);
