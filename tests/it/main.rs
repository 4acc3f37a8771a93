//! Integration tests: one binary, one module per topic. Every expected
//! number comes from outside the code under test (the paper's Table 4,
//! closed forms, the public contract), with its source in a comment.

mod analysis;
mod analyze;
mod cli;
mod cosim;
mod fuzz;
mod paper;
mod profile;
mod record;
mod scene_errors;
mod stepping;
mod stress;

use chaindrive::scene::Scene;

/// The paper's drive, shortened for tests.
pub fn l60mc(duration_s: f64) -> Scene {
    let mut scene = Scene::l60mc();
    scene.solver.duration_s = duration_s;
    scene
}
