//! Benchmarks of the kernels: the contact law and the tooth-profile queries
//! (circular, and the real ASA B29.1 profile at several places of a gap).
//! They reach inside the library through `chaindrive::kernels`, which the
//! feature `bench-kernels` opens for them.
//!
//! ```text
//! cargo bench --features bench-kernels --bench kernels
//! ```
//! Numbers and the machine: `benches/README.md`.

// criterion_group! generates an undocumented public function.
#![allow(missing_docs)]

use std::hint::black_box;

use chaindrive::kernels::{AsaProfile, CircularProfile, ContactLawParams, LocatedPatch, Patch};
use chaindrive::prelude::*;
use criterion::{Criterion, criterion_group, criterion_main};

fn kernels(c: &mut Criterion) {
    let scene = Scene::l60mc();
    let law = ContactLawParams::new(scene.contact());
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
    // The same seated roller against the real (ASA B29.1) profile, one deep on a flank
    // (general path), one rocked onto the working curve just past the joint x (where the
    // running drive's flank contacts are), one lifted 5 mm out of the seat (free), and one
    // 0.1 mm off the flank (just outside).
    let real = AsaProfile::new(60, 0.0889, 0.054).expect("profile");
    let d = real.dimensions();
    let g = real.gap_points();
    let seated = [d.pitch_radius_m - d.clearance_m - 2e-4, 1e-4];
    let flank = [d.pitch_radius_m + 0.01, 0.024];
    // Gap 0's local (ξ, η) is the sprocket frame's (−y, x − Rs).
    let from_local = |q: [f64; 2]| [d.pitch_radius_m + q[1], -q[0]];
    let past_x = |depth: f64, sigma: f64| {
        let u = [g.x_m[0] - g.c_m[0], g.x_m[1] - g.c_m[1]];
        let len = u[0].hypot(u[1]);
        let (s, c) = sigma.sin_cos();
        let u = [(c * u[0] - s * u[1]) / len, (s * u[0] + c * u[1]) / len];
        let rho = d.working_radius_m - 0.027 + depth;
        from_local([g.c_m[0] + rho * u[0], g.c_m[1] + rho * u[1]])
    };
    let working = past_x(2e-4, 0.002);
    let lifted = from_local([0.0, 5e-3]);
    let just_outside = past_x(-1e-4, 0.05);
    for (name, q) in [
        ("profile/real_contacts_seated", seated),
        ("profile/real_contacts_flank", flank),
        ("profile/real_contacts_working_past_x", working),
        ("profile/real_contacts_lifted", lifted),
        ("profile/real_contacts_just_outside", just_outside),
    ] {
        c.bench_function(name, |b| {
            let mut out = [LocatedPatch::default(); 2];
            let mut hint = 0;
            b.iter(|| real.contacts_hinted(black_box(q), 0.027, &mut hint, &mut out))
        });
    }
    // The contact generator's call (own roller, no contact point) on the seated roller.
    c.bench_function("profile/real_contacts_nominal_seated", |b| {
        let mut out = [Patch::default(); 2];
        let mut hint = 0;
        b.iter(|| real.contacts_nominal(black_box(seated), &mut hint, &mut out))
    });
}

criterion_group!(benches, kernels);
criterion_main!(benches);
