//! The stress matrix's contract (`chaindrive bench stress`) and the scene
//! generator it relies on.

#[cfg(feature = "cli")]
use crate::common::{command, stderr};
use chaindrive::scene::generate::DriveSpec;
use chaindrive::sim::Simulation;

/// The exact header of `stress.csv`, a public contract.
#[cfg(feature = "cli")]
const HEADER: &str = "case,rollers,sprockets,rpm,e,damping_ratio,kg,profile,integrator,dt_s,stable,detector,wall_per_sim_s";

#[cfg(feature = "cli")]
#[test]
fn quick_matrix_writes_the_promised_csv() {
    use chaindrive::studies::stress::CSV_HEADER;

    let dir = tempfile::tempdir().expect("tempdir");
    let out = command()
        .args(["bench", "stress", "--quick", "--out"])
        .arg(dir.path())
        .output()
        .expect("runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}\n{}", stderr(&out));
    assert!(stdout.contains("largest stable dt"), "{stdout}");
    let text = std::fs::read_to_string(dir.path().join("stress.csv")).expect("stress.csv");
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(HEADER));
    assert_eq!(CSV_HEADER, HEADER);
    let columns: Vec<&str> = HEADER.split(',').collect();
    let col = |name: &str| columns.iter().position(|c| *c == name).expect("column");
    let numeric = [
        "rollers",
        "sprockets",
        "rpm",
        "e",
        "damping_ratio",
        "kg",
        "dt_s",
        "wall_per_sim_s",
    ];
    let (mut stable, mut unstable) = (0, 0);
    for line in lines {
        let fields: Vec<&str> = line.split(',').collect();
        assert_eq!(fields.len(), columns.len(), "{line}");
        for name in numeric {
            let v: f64 = fields[col(name)]
                .parse()
                .unwrap_or_else(|_| panic!("{name} is not a number in {line}"));
            assert!(v.is_finite(), "{name} = {v} in {line}");
        }
        match fields[col("stable")] {
            "true" => {
                stable += 1;
                assert_eq!(fields[col("detector")], "", "{line}");
            }
            "false" => {
                unstable += 1;
                let d = fields[col("detector")];
                assert!(
                    [
                        "non-finite",
                        "penetration",
                        "link-stretch",
                        "stretch-growth",
                        "step-size"
                    ]
                    .contains(&d),
                    "unstable row names no detector: {line}"
                );
            }
            other => panic!("stable = {other:?} in {line}"),
        }
    }
    assert!(
        stable >= 1 && unstable >= 1,
        "{stable} stable, {unstable} unstable rows"
    );
    let limits = std::fs::read_to_string(dir.path().join("stress_limits.csv")).expect("limits");
    assert!(limits.lines().count() >= 2, "{limits}");
}

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
    use chaindrive::scene::{Integrator, Overrides, Scene};
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
