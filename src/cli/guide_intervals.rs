//! How often each fixed guide is evaluated against its contact's estimated
//! largest stable interval at rest: `check` prints it, `run` warns.

use crate::sim::Simulation;

/// Per fixed guide of a simulation at rest: the line saying how often it is
/// evaluated against its contact's estimated largest stable interval at its
/// most loaded roller, and the warning where a guide evaluated every k > 1
/// steps exceeds [`GUIDE_SAFETY`] of that interval (`check` prints both, `run` warns).
pub(super) fn guide_intervals(sim: &Simulation) -> Vec<(String, Option<String>)> {
    let dt = sim.scene.solver.dt_s;
    let mass = sim.scene.chain().roller_mass_kg;
    sim.forces
        .elements_of::<crate::forces::GuideElement>()
        .enumerate()
        .map(|(k, g)| {
            let load = g.largest_normal_n();
            let limit = g.stable_interval_s(mass, load);
            let every = g.configured_every();
            let interval = f64::from(every) * dt;
            let line = format!(
                "guide \"{}\": evaluated every {every} step(s) ({:.2} µs); its most loaded roller at rest carries {load:.3} N, for which the contact's estimated largest stable interval is {:.1} µs",
                g.name(),
                interval * 1e6,
                limit * 1e6
            );
            let warning = (every > 1 && interval > GUIDE_SAFETY * limit).then(|| {
                format!(
                    "guides[{k}].every_steps = {every} evaluates the guide every {:.2} µs, above {GUIDE_SAFETY} of its contact's estimated limit {:.1} µs at the load at rest: lower it",
                    interval * 1e6,
                    limit * 1e6
                )
            });
            (line, warning)
        })
        .collect()
}

/// The fraction of a guide contact's estimated largest stable interval its
/// evaluations may be apart without a warning.
const GUIDE_SAFETY: f64 = 0.5;
