//! The stress matrix's contract (`chaindrive bench stress`) and the scene
//! generator it relies on.

use crate::scene::DriveSpec;
use crate::sim::Simulation;

/// Generated drives lay out, settle and reach the pretension; the closing
/// link (last roller to first) is as long as every other.
#[test]
fn generated_drives_close_and_reach_their_pretension() {
    for (rollers, sprockets) in [(122, 4), (1000, 2), (10_000, 2), (500, 10)] {
        let mut spec = DriveSpec::new(rollers, sprockets).expect("spec");
        // A 10,000-roller chain's slowest mode outlasts the default 2 s of
        // relaxation; the pretension is reached long before.
        spec.equilibrium.max_relax_s = 0.3;
        let scene = spec.scene().expect("valid scene");
        assert_eq!(scene.chain().rollers, rollers);
        assert_eq!(scene.sprockets().len(), sprockets);
        let sim = Simulation::new(&scene)
            .unwrap_or_else(|e| panic!("{rollers} rollers, {sprockets} sprockets: {e}"));
        let target = scene.chain().pretension_n;
        let tension = sim.equilibrium.tension_n;
        assert!(
            ((tension - target) / target).abs() <= scene.equilibrium().tension_tolerance,
            "{rollers}x{sprockets}: static tension {tension} N, target {target} N"
        );
        let st = &sim.state;
        let n = st.rollers();
        assert_eq!(n, rollers);
        let forces = &sim.forces.output().link_force;
        // Every link, the closing one included, carries a force within the
        // pretension's order: none is a gap or an overlap.
        for (i, f) in forces.iter().enumerate() {
            assert!(
                f.is_finite() && f.abs() < 3.0 * target,
                "{rollers}x{sprockets}: link {i} carries {f} N"
            );
        }
        let closing = (st.x[0] - st.x[n - 1]).hypot(st.y[0] - st.y[n - 1]);
        let p = scene.chain().pitch_m;
        assert!(
            (closing - p).abs() < 1e-3 * p,
            "{rollers}x{sprockets}: closing link {closing} m vs pitch {p} m"
        );
    }
}

/// A fork of a settled drive starts where the drive is, with the scheme and
/// step asked for; a step the scene refuses is an error naming its field.
#[test]
fn a_fork_starts_from_the_settled_state_with_the_scheme_asked_for() {
    use crate::scene::{Integrator, Overrides, Scene};
    let base = Simulation::new(&Scene::l60mc()).expect("the paper's drive settles");
    let fork = base
        .fork(&Overrides {
            integrator: Some(Integrator::Rk4),
            dt_s: Some(2e-5),
            ..Overrides::default()
        })
        .expect("a valid rung");
    assert_eq!(fork.state, base.state);
    assert_eq!(fork.scene.solver().integrator, Integrator::Rk4);
    assert_eq!(fork.scene.solver().dt_s, 2e-5);
    assert_eq!(base.scene.solver().integrator, Integrator::VelocityVerlet);
    let refused = base
        .fork(&Overrides {
            dt_s: Some(-1e-5),
            ..Overrides::default()
        })
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(refused.contains("dt_s"), "{refused}");
}
