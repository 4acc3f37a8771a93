//! The paper's four-sprocket drive (MAN B&W L60MC camshaft chain), run
//! through the library API: layout, static equilibrium, 3 s of simulation,
//! then the run summary as JSON.
//!
//! ```text
//! cargo run --release --example paper_drive
//! ```

use chaindrive::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let scene = Scene::l60mc().with(&Overrides {
        duration_s: Some(3.0),
        ..Overrides::default()
    })?;
    let mut sim = Simulation::new(&scene)?;
    println!(
        "static tension {:.0} N with link rest length {:.6} m",
        sim.equilibrium().tension_n,
        sim.model().rest_length_m
    );
    let sampling = SampleRate::new(1000.0, scene.solver().dt_s)?;
    let mut signals = Signals::new(
        sim.model(),
        sampling.rate_hz,
        scene.solver().duration_s - 1.0,
    );
    let outcome = sim.run(
        scene.solver().duration_s,
        sampling.every,
        &mut signals,
        None,
    )?;
    let summary = RunSummary::of_run(&sim, &outcome, &signals, 0.0);
    println!("{}", serde_json::to_string_pretty(&summary)?);
    Ok(())
}
