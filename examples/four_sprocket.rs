//! The paper's four-sprocket drive with both tooth forms: the circular
//! seating profile and the real ASA B29.1 tooth, at the same 21 kN
//! pretension, side by side — each free strand's mean link force and its
//! RMS, and each sprocket's mean chain torque over the last second.
//! (`chaindrive reproduce` runs the paper's whole study with its report and
//! figures.)
//!
//! ```sh
//! cargo run --release --example four_sprocket -- [DURATION_S]
//! ```

use chaindrive::prelude::*;
use chaindrive::scene::ProfileKind;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let duration_s: f64 = std::env::args().nth(1).map_or(Ok(3.0), |d| d.parse())?;
    let mut summaries = Vec::new();
    for profile in [ProfileKind::Circular, ProfileKind::Real] {
        let scene = Scene::l60mc().with(&Overrides {
            profile: Some(profile),
            duration_s: Some(duration_s),
            ..Overrides::default()
        })?;
        let mut sim = Simulation::new(&scene)?;
        let sampling = SampleRate::new(1000.0, scene.solver().dt_s)?;
        let window = StatsWindow::of(&scene, None)?;
        let mut signals = window.observe(&mut sim, sampling.rate_hz);
        let outcome = sim.run(duration_s, sampling.every, &mut signals, None)?;
        summaries.push(RunSummary::of_run_in(
            &sim, &outcome, &signals, 0.0, &window,
        ));
    }
    let [circular, real] = &summaries[..] else {
        unreachable!("two runs")
    };
    println!("segment  mean link force, N      link force RMS, N");
    println!("         circular     real       circular     real");
    for (c, r) in circular.segments.iter().zip(&real.segments) {
        println!(
            "{:>7}  {:>8.0} {:>8.0}       {:>8.0} {:>8.0}",
            c.segment,
            c.mean_link_force_n,
            r.mean_link_force_n,
            c.link_force_rms_n,
            r.link_force_rms_n
        );
    }
    println!("sprocket  mean chain torque, N·m");
    for (c, r) in circular.sprockets.iter().zip(&real.sprockets) {
        println!(
            "{:>8}  {:>8.0} {:>8.0}",
            c.sprocket, c.mean_torque_n_m, r.mean_torque_n_m
        );
    }
    Ok(())
}
