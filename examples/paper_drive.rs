//! The paper's four-sprocket drive (MAN B&W L60MC camshaft chain), run
//! through the library API: layout, static equilibrium, 3 s of simulation,
//! then the run summary as JSON.
//!
//! ```text
//! cargo run --release --example paper_drive
//! ```

use chaindrive::analysis::{RunSummary, Signals};
use chaindrive::scene::{Overrides, Scene};
use chaindrive::sim::Simulation;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let scene = Scene::l60mc().with(&Overrides {
        duration_s: Some(3.0),
        ..Overrides::default()
    })?;
    let mut sim = Simulation::new(&scene)?;
    println!(
        "static tension {:.0} N with link rest length {:.6} m",
        sim.equilibrium.tension_n, sim.model.rest_length_m
    );
    let rate_hz = 1000.0;
    let every = (1.0 / (rate_hz * scene.solver().dt_s)).round() as u64;
    let mut signals = Signals::new(&sim.model, rate_hz, scene.solver().duration_s - 1.0);
    let outcome = sim.run(scene.solver().duration_s, every, &mut signals, None)?;
    let summary = RunSummary::of_run(&sim, &outcome, &signals, 0.0);
    println!("{}", serde_json::to_string_pretty(&summary)?);
    Ok(())
}
