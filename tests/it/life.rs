//! `chaindrive life`: a duty cycle run point by point as a study (in
//! parallel, resumably) and combined by hours. The combination is checked
//! against the points' own numbers by Miner's rule done here: the cycle's
//! damage per hour is Σ fᵢ dᵢ over the points' time fractions fᵢ and
//! damages per hour dᵢ, its life the inverse.

use crate::common::{chaindrive, read_json, stderr};

const MOTO: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/tests/data/moto_10b_15_44_560nm.toml"
);
const MOTO_DUTY: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/duty_moto_10b.toml");
const PAPER_DUTY: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/l60mc-duty.toml");

fn f(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("{v} is not a number"))
}

/// The motorcycle drive's three points (town, cruise, full throttle as
/// fractions of the time), two at once; a second call runs nothing and
/// gives the same report; a point removed runs again alone.
#[test]
fn a_motorcycle_duty_cycle_runs_in_parallel_resumably_and_combines_by_miner() {
    let dir = tempfile::tempdir().expect("tmp");
    let out = dir.path().join("life");
    let out_s = out.to_str().expect("utf-8");
    let args = [
        "life",
        MOTO,
        "--duty",
        MOTO_DUTY,
        "--out",
        out_s,
        "--jobs",
        "2",
        "--duration",
        "0.4",
        "--window",
        "0.15",
    ];
    let first = chaindrive(&args);
    assert!(first.status.success(), "{}", stderr(&first));
    assert!(
        stderr(&first).contains("3 points, 3 to run on 2 jobs"),
        "{}",
        stderr(&first)
    );
    let report = read_json(&out.join("life.json"));
    let points = report["points"].as_array().expect("points");
    assert_eq!(points.len(), 3);
    let fractions: Vec<f64> = points.iter().map(|p| f(&p["hours"])).collect();
    assert_eq!(fractions, vec![0.3, 0.65, 0.05]);
    let damage: Vec<f64> = points.iter().map(|p| f(&p["damage_per_hour"])).collect();
    let rate: f64 = fractions.iter().zip(&damage).map(|(a, b)| a * b).sum();
    let fatigue = &report["limits"][0];
    assert_eq!(fatigue["check"], "fatigue");
    approx::assert_relative_eq!(f(&fatigue["rate_per_hour"]), rate, max_relative = 1e-12);
    approx::assert_relative_eq!(f(&report["life_h"]), 1.0 / rate, max_relative = 1e-12);
    // The point with the largest fᵢ dᵢ dominates: at 80 kW, full throttle.
    let largest = (0..3)
        .max_by(|&a, &b| (fractions[a] * damage[a]).total_cmp(&(fractions[b] * damage[b])))
        .expect("points");
    assert_eq!(fatigue["dominated_by"], points[largest]["name"]);
    assert_eq!(points[largest]["name"], "full throttle");
    for p in points {
        assert!(f(&p["rating_margin"]) > 0.0 && f(&p["static_safety_factor"]) > 0.0);
    }
    let csv = std::fs::read_to_string(out.join("life.csv")).expect("csv");
    assert_eq!(csv.lines().count(), 4, "{csv}");
    assert!(csv.starts_with("point,fraction,time_share,"), "{csv}");
    // Each point's fatigue life alone: a number of hours, 1 / its damage
    // per hour (the column's name carries the unit, the cells none), or
    // `infinite` where there is no damage.
    // The column by its name (the `set` column's cells hold commas, so from
    // the end): wear columns follow it.
    let header: Vec<&str> = csv.lines().next().unwrap_or("").split(',').collect();
    let from_end = header.len()
        - header
            .iter()
            .position(|h| *h == "fatigue_life_h")
            .expect("a fatigue_life_h column");
    for (line, &d) in csv.lines().skip(1).zip(&damage) {
        let cells: Vec<&str> = line.rsplitn(from_end + 1, ',').collect();
        let cell = cells[from_end - 1];
        if d == 0.0 {
            assert_eq!(cell, "infinite", "{line}");
            continue;
        }
        let life: f64 = cell
            .parse()
            .unwrap_or_else(|_| panic!("fatigue_life_h {cell:?} in {line}"));
        approx::assert_relative_eq!(life * d, 1.0, max_relative = 1e-12);
    }
    assert!(out.join("damage.png").exists());

    // Again: every point is finished, nothing runs, the same life.
    let again = chaindrive(&args);
    assert!(again.status.success(), "{}", stderr(&again));
    assert!(stderr(&again).contains("0 to run"), "{}", stderr(&again));
    assert_eq!(
        read_json(&out.join("life.json"))["life_h"],
        report["life_h"]
    );

    // A point lost (a killed task) runs again, alone.
    std::fs::remove_dir_all(out.join("cases").join("1")).expect("remove");
    let resumed = chaindrive(&args);
    assert!(resumed.status.success(), "{}", stderr(&resumed));
    assert!(
        stderr(&resumed).contains("1 to run") && stderr(&resumed).contains("\"cruise\" finished"),
        "{}",
        stderr(&resumed)
    );
}

/// The paper's drive with its 56B chain over three crankshaft speeds (the
/// duty cycle in the scene file): its link forces stay below the fatigue
/// limit at each, so the life is infinite, written as the string.
#[test]
fn the_papers_duty_cycle_has_an_infinite_life() {
    let dir = tempfile::tempdir().expect("tmp");
    let out = dir.path().join("life");
    let run = chaindrive(&[
        "life",
        PAPER_DUTY,
        "--out",
        out.to_str().expect("utf-8"),
        "--jobs",
        "2",
        "--duration",
        "1.3",
        "--window",
        "0.3",
    ]);
    assert!(run.status.success(), "{}", stderr(&run));
    let report = read_json(&out.join("life.json"));
    assert_eq!(report["life_h"], "infinite");
    assert_eq!(report["governed_by"], "fatigue");
    for p in report["points"].as_array().expect("points") {
        assert_eq!(f(&p["damage_per_hour"]), 0.0);
        assert!(f(&p["fatigue_safety_factor"]) > 1.0, "{p}");
    }
    let text = String::from_utf8_lossy(&run.stdout);
    assert!(
        text.contains("life: infinite, governed by fatigue"),
        "{text}"
    );
}

/// Points that cannot be run are refused before anything runs, each
/// problem with its path.
#[test]
fn a_bad_duty_cycle_is_refused_with_its_paths() {
    let dir = tempfile::tempdir().expect("tmp");
    let duty = dir.path().join("duty.toml");
    std::fs::write(
        &duty,
        "[[duty]]\nfraction = 0.5\nset = { \"sprockets.0.speed_rpm\" = -5.0e9 }\n\n[[duty]]\nfraction = 0.3\nset = { \"sprockets.7.speed_rpm\" = 100.0 }\n",
    )
    .expect("write");
    let out = dir.path().join("life");
    let run = chaindrive(&[
        "life",
        MOTO,
        "--duty",
        duty.to_str().expect("utf-8"),
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert!(!run.status.success());
    let e = stderr(&run);
    assert!(e.contains("duty: the fractions sum to 0.8"), "{e}");
    std::fs::write(
        &duty,
        "[[duty]]\nfraction = 1.0\nset = { \"sprockets.7.speed_rpm\" = 100.0 }\n",
    )
    .expect("write");
    let run = chaindrive(&[
        "life",
        MOTO,
        "--duty",
        duty.to_str().expect("utf-8"),
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert!(!run.status.success());
    let e = stderr(&run);
    assert!(
        e.contains("duty[0].set:") && e.contains("sprockets[7]"),
        "{e}"
    );
    assert!(!out.join("cases").join("0").join("status.json").exists());
}
