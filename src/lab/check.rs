//! A scene laid out and brought to static equilibrium, reported as plain
//! data: what `chaindrive check` prints, for a front end to format.

use serde_json::{Value, json};

use crate::scene::Scene;
use crate::sim::{SimError, Simulation};

/// `scene` laid out and brought to static equilibrium: its strands (from
/// and to sprocket, length, tangent angles, free links), its sprockets
/// (teeth, centre, pitch radius, wrap), the path's and the chain's length,
/// the static tension against the target, the links' rest length, the
/// solve's iterations and residual, the step with its one-line note, and
/// the scene's warnings. Sprockets and segments are numbered from 1.
///
/// # Errors
///
/// The [`SimError`] of a scene that cannot be laid out or settled (a chain
/// too short or too long for its path, a tensioner out of travel, …).
pub fn check_report(scene: &Scene) -> Result<Value, SimError> {
    let sim = Simulation::new(scene)?;
    let (s, model, layout, eq) = (&sim.scene, &sim.model, &sim.layout, &sim.equilibrium);
    let strands: Vec<Value> = model
        .path
        .strands
        .iter()
        .enumerate()
        .map(|(k, st)| {
            json!({
                "segment": k + 1,
                "from": st.from + 1,
                "to": st.to + 1,
                "length_m": st.length_m,
                "angle_on_from_rad": st.angle_on_from_rad,
                "angle_on_to_rad": st.angle_on_to_rad,
                "links": layout.strand_links.get(k).copied().unwrap_or(0),
            })
        })
        .collect();
    let sprockets: Vec<Value> = s
        .sprockets()
        .iter()
        .zip(&model.path.wraps)
        .enumerate()
        .map(|(i, (sp, w))| {
            json!({
                "sprocket": i + 1,
                "name": sp.name,
                "teeth": sp.teeth,
                "center_m": sp.center_m,
                "pitch_radius_m": sp.pitch_radius_m,
                "wrap_rad": w.wrap_rad,
                "wrap_pitches": w.wrap_rad * f64::from(sp.teeth) / std::f64::consts::TAU,
            })
        })
        .collect();
    Ok(json!({
        "scene": s.name(),
        "rollers": s.chain().rollers,
        "pitch_m": s.chain().pitch_m,
        "strands": strands,
        "sprockets": sprockets,
        "polygon_length_m": layout.polygon_length_m,
        "chain_length_m": s.chain().rollers as f64 * s.chain().pitch_m,
        "static_tension_n": eq.tension_n,
        "target_tension_n": scene.chain().pretension_n,
        "rest_length_m": model.rest_length_m,
        "equilibrium_iterations": eq.iterations,
        "force_residual": eq.force_residual,
        "dt_s": s.solver().dt_s,
        "step_note": crate::scene::step_note(s),
        "warnings": scene.warnings(),
    }))
}
