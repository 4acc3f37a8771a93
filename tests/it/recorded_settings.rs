//! A recording read back is the scene as it was run: the settings the run
//! overrode (integrator, contact law, profile, step, stepping, duration)
//! come from the recording's metadata, not from the attached scene file.

use std::io::Cursor;

use chaindrive::record::read::read_recording_bytes;
use chaindrive::record::{Channels, RecordOptions, Recorder, RunEnd};
use chaindrive::scene::{ContactLaw, Integrator, L60MC_TOML, Overrides, ProfileKind, Scene};
use chaindrive::sim::{SampleRate, Simulation};

/// Regression: the reader took the profile, step, stepping and duration from
/// the metadata but rebuilt the integrator and the contact law from the
/// scene file, so a run made with `--integrator rk4 --contact-law
/// hunt_crossley` read back as symplectic Euler with Lankarani–Nikravesh.
#[test]
fn a_recording_reads_back_with_its_integrator_and_contact_law() {
    // The file says velocity Verlet, Lankarani–Nikravesh, circular, 10 µs.
    let file = Scene::l60mc();
    assert_eq!(file.solver().integrator, Integrator::VelocityVerlet);
    assert_eq!(file.contact().law, ContactLaw::LankaraniNikravesh);
    let scene = file
        .with(&Overrides {
            duration_s: Some(0.01),
            dt_s: Some(5e-6),
            integrator: Some(Integrator::Rk4),
            contact_law: Some(ContactLaw::HuntCrossley),
            profile: Some(ProfileKind::Real),
            ..Overrides::default()
        })
        .expect("valid overrides");
    let mut sim = Simulation::new(&scene).expect("sim");
    let sampling = SampleRate::new(1000.0, scene.solver().dt_s).expect("rate");
    let options = RecordOptions {
        channels: Channels::SEGMENTS | Channels::SPROCKETS,
        scene_file: Some(("l60mc.toml".to_owned(), L60MC_TOML.as_bytes().to_vec())),
        rate_hz: sampling.rate_hz,
    };
    let mut recorder = Recorder::new(Cursor::new(Vec::new()), &scene, &options).expect("recorder");
    sim.run(0.01, sampling.every, &mut recorder, None)
        .expect("run");
    let bytes = recorder
        .finish(RunEnd::Completed)
        .expect("finish")
        .into_inner();

    let read = read_recording_bytes("run.mcap", &bytes).expect("readable");
    let solver = read.scene.solver();
    assert_eq!(solver.integrator, Integrator::Rk4);
    assert_eq!(read.scene.contact().law, ContactLaw::HuntCrossley);
    assert_eq!(read.scene.profile_name(), "real");
    assert_eq!(solver.dt_s, 5e-6);
    assert_eq!(solver.duration_s, 0.01);
}
