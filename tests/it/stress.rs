//! The stress matrix's contract (`chaindrive bench stress`) and the scene
//! generator it relies on.

#[cfg(feature = "cli")]
use crate::common::{command, stderr};

/// The exact header of `stress.csv`, a public contract.
#[cfg(feature = "cli")]
const HEADER: &str = "case,rollers,sprockets,rpm,e,damping_ratio,kg,profile,integrator,dt_s,stable,detector,wall_per_sim_s";

#[cfg(feature = "cli")]
#[test]
fn quick_matrix_writes_the_promised_csv() {
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
