//! Benchmarks: one chain step of the paper's drive in both stepping modes
//! (running at 120 rpm), through the library's public API.
//!
//! ```text
//! cargo bench --bench step
//! ```
//! Numbers and the machine: `benches/README.md`; the contact law and the
//! profile queries are timed by `benches/kernels.rs`.

// criterion_group! generates an undocumented public function.
#![allow(missing_docs)]

use chaindrive::prelude::*;
use chaindrive::scene::{ProfileKind, Stepping};
use criterion::{Criterion, criterion_group, criterion_main};

/// The paper's drive, run to full speed (1.5 s), in the given stepping mode.
fn running_drive(stepping: Stepping, profile: ProfileKind) -> Simulation {
    let scene = Scene::l60mc()
        .with(&Overrides {
            stepping: Some(stepping),
            profile: Some(profile),
            ..Overrides::default()
        })
        .expect("paper drive");
    let mut sim = Simulation::new(&scene).expect("paper drive");
    sim.run(1.5, 1000, &mut (), None).expect("run");
    sim
}

fn steps(c: &mut Criterion) {
    let mut group = c.benchmark_group("paper_drive_step");
    for (stepping, profile) in [
        (Stepping::Substepped, ProfileKind::Circular),
        (Stepping::Substepped, ProfileKind::Real),
        (Stepping::Rapier, ProfileKind::Circular),
    ] {
        let mut sim = running_drive(stepping, profile);
        let dt = sim.scene().solver().dt_s;
        let name = format!("{}_{}", stepping.name(), profile.name());
        group.bench_function(name, |b| b.iter(|| sim.step(dt).expect("stable")));
    }
    group.finish();
}

criterion_group!(benches, steps);
criterion_main!(benches);
