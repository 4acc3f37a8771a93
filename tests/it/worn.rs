//! Worn chains from the command line: a study whose factor is the chain's
//! elongation (`chain.elongation_pct`) runs, and its table holds, per case,
//! the slack the wear added and how often the chain jumped teeth.

use crate::common::{chaindrive, stderr};
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// The column `name` of a CSV table as text, one entry per row.
fn csv_column(csv: &str, name: &str) -> Vec<String> {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    let i = header
        .iter()
        .position(|h| *h == name)
        .unwrap_or_else(|| panic!("no column {name} in {header:?}"));
    // The warnings column (text with commas) comes after every numeric
    // column, so splitting by commas is safe up to it.
    lines
        .map(|l| l.split(',').nth(i).unwrap_or_default().to_owned())
        .collect()
}

#[test]
fn a_study_over_the_elongation_counts_tooth_jumps_and_the_slack_per_case() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("s");
    let plan = data("study_elongation.toml");
    let (plan, out_s) = (plan.to_str().expect("utf-8"), out.to_str().expect("utf-8"));
    let run = chaindrive(&["study", plan, "--out", out_s, "--jobs", "2", "--quiet"]);
    assert!(run.status.success(), "{}", stderr(&run));
    let collect = chaindrive(&["study", "collect", out_s]);
    assert!(collect.status.success(), "{}", stderr(&collect));
    let csv = std::fs::read_to_string(out.join("results.csv")).expect("results.csv");
    let header = csv.lines().next().expect("header");

    assert_eq!(csv_column(&csv, "chain.elongation_pct"), ["0.0", "2.0"]);
    // The new chain on fixed centres keeps its teeth; worn by 2 % it gains
    // 111 P e = 111 × 25.4 mm × 0.02 = 56.4 mm of slack (the links are
    // lengthened, the centres stay), and jumps.
    let jumps: Vec<f64> = csv_column(&csv, "tooth_jump_count")
        .iter()
        .map(|j| j.parse().expect("a count"))
        .collect();
    assert_eq!(jumps[0], 0.0, "{header}");
    assert!(jumps[1] >= 1.0, "{jumps:?}");
    let slack = csv_column(&csv, "worn_chain.extra_slack_m");
    assert_eq!(slack[0], "", "a new chain has no worn_chain block");
    let slack: f64 = slack[1].parse().expect("a number");
    let expected = 111.0 * 0.0254 * 0.02;
    assert!(
        (slack / expected - 1.0).abs() < 0.01,
        "{slack} m against {expected} m"
    );
    // The first jump's fields are columns (its time, sprocket, roller,
    // gaps); the later jumps' are not (one set of columns per jump would
    // grow the table with every jump).
    assert!(header.contains("tooth_jumps.0.t_s"), "{header}");
    assert!(!header.contains("tooth_jumps.1."), "{header}");
    // The tip rides are counted, not listed: the new chain rode none, the
    // worn one's rollers rode the tips before they jumped.
    let rides = csv_column(&csv, "tip_ride_count");
    assert_eq!(rides[0], "0.0", "{header}");
    assert!(
        rides[1].parse::<f64>().expect("a count") >= 1.0,
        "{rides:?}"
    );
    assert!(!header.contains("tip_rides."), "{header}");
    assert!(
        out.join("main_effects/tooth_jump_count.png").exists(),
        "the jump count's main-effects figure"
    );
}

#[test]
fn a_sweep_of_a_worn_chain_counts_its_tooth_jumps_once_per_speed() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("sw");
    let scene = data("worn_30_30_fixed.toml");
    let run = chaindrive(&[
        "sweep",
        scene.to_str().expect("utf-8"),
        "--rpm",
        "100:100:10",
        "--set",
        "chain.elongation_pct=2",
        "--settle",
        "0.2",
        "--window",
        "0.7",
        "--jobs",
        "1",
        "--quiet",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert!(run.status.success(), "{}", stderr(&run));
    let csv = std::fs::read_to_string(out.join("sweep.csv")).expect("sweep.csv");
    // Long form: rpm, statistic, value; each statistic once per speed.
    let mut names: Vec<&str> = csv
        .lines()
        .skip(1)
        .filter_map(|l| l.split(',').nth(1))
        .collect();
    let all = names.len();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), all, "a statistic named twice");
    let count: f64 = csv
        .lines()
        .find_map(|l| l.strip_prefix("100,tooth_jump_count,"))
        .expect("the jump count")
        .parse()
        .expect("a number");
    // Worn by 2 % on fixed centres the chain jumps (as in the study above).
    assert!(count >= 1.0, "{count}");
}

/// `jump-margin` along the elongation of the worn 30/30 drive on fixed
/// centres, checked against a brute-force grid of the same drive run as a
/// study (a run counting its jumps jumps exactly where one stopping at the
/// first jump does): every elongation at or below the bracket's clean end
/// runs clean, every one at or above its jumping end jumps or rides a tip
/// (the search counts a ride as a jump).
#[test]
fn jump_margin_brackets_the_onset_that_a_grid_of_runs_finds() {
    let scene = data("worn_30_30_fixed.toml");
    let scene = scene.to_str().expect("utf-8");
    // One search along the elongation, 0 to 2 % over 0.4 s runs.
    let search = |tolerance: &str, extra: &[&str]| {
        let mut args = vec![
            "jump-margin",
            scene,
            "--path",
            "chain.elongation_pct",
            "--from",
            "0",
            "--to",
            "2",
            "--tolerance",
            tolerance,
            "--duration",
            "0.4",
            "--jobs",
            "2",
            "--json",
        ];
        args.extend_from_slice(extra);
        let run = chaindrive(&args);
        assert!(run.status.success(), "{}", stderr(&run));
        serde_json::from_slice::<serde_json::Value>(&run.stdout).expect("JSON")
    };
    let out = search("0.2", &[]);
    let margin = &out["margin"];
    let clean = margin["clean"].as_f64().expect("clean");
    let jumping = margin["jumping"].as_f64().expect("jumping");
    assert_eq!(margin["low_end_jumps"], false, "{out}");
    assert_eq!(margin["monotone"], true, "{out}");
    assert!(clean < jumping && jumping - clean <= 0.2, "{out}");

    // Counting jumps alone, the same drive runs clean beyond the tip rides'
    // onset: its rollers drag over the tips well before they jump.
    let only = search("0.4", &["--jumps-only"]);
    let clean_of_jumps = only["margin"]["clean"].as_f64().expect("clean");
    assert!(
        clean_of_jumps >= jumping,
        "jumps alone: clean to {clean_of_jumps} %, rides from {jumping} %: {only}"
    );

    // Rollers leaving the driven sprocket drag over its tips from about
    // 0.3 % on, well before the first jump (about 1 %).
    let levels: Vec<f64> = (1..=8).map(|k| 0.1 * f64::from(k)).collect();
    let plan = format!(
        "scene = {scene:?}\nresponses = \"all\"\nset = {{ \"solver.duration_s\" = 0.4 }}\nwindow_s = 0.2\n\n[[factors]]\npath = \"chain.elongation_pct\"\nlevels = {levels:?}\n\n[design]\nkind = \"full_factorial\"\n"
    );
    let csv = study_table(&plan);
    let jumps = csv_column(&csv, "tooth_jump_count");
    let rides = csv_column(&csv, "tip_ride_count");
    let mut seen_both = (false, false);
    for ((e, jumps), rides) in levels.iter().zip(&jumps).zip(&rides) {
        let count: f64 =
            jumps.parse::<f64>().expect("a count") + rides.parse::<f64>().expect("a count");
        if *e <= clean {
            assert_eq!(count, 0.0, "{e} % jumped, at or below the clean {clean} %");
            seen_both.0 = true;
        }
        if *e >= jumping {
            assert!(
                count >= 1.0,
                "{e} % ran clean, at or above the jumping {jumping} %"
            );
            seen_both.1 = true;
        }
    }
    assert!(
        seen_both.0 && seen_both.1,
        "the grid {levels:?} straddles {clean}..{jumping}"
    );
}

/// The paper's drive on the real tooth form: no roller jumps a tooth or
/// rides a tip (the summary has neither list, and no warning of them).
#[test]
fn the_papers_drive_neither_jumps_nor_rides_a_tip() {
    let dir = tempfile::tempdir().expect("temp dir");
    let summary = dir.path().join("s.json");
    let run = chaindrive(&[
        "run",
        "--quiet",
        "--profile",
        "real",
        "--duration",
        "1.5",
        "--summary",
        summary.to_str().expect("utf-8"),
    ]);
    assert!(run.status.success(), "{}", stderr(&run));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&summary).expect("summary")).expect("JSON");
    assert!(s.get("tooth_jumps").is_none(), "{}", s["tooth_jumps"]);
    assert!(s.get("tip_rides").is_none(), "{}", s["tip_rides"]);
    let warnings = s["warnings"].as_array().expect("warnings");
    assert!(
        !warnings.iter().any(|w| w
            .as_str()
            .is_some_and(|w| w.starts_with("tip ride") || w.starts_with("tooth jump"))),
        "{warnings:?}"
    );
}

/// A recording of a worn chain's run lists its tip rides and tooth jumps in
/// the metadata records `chaindrive.tip_rides` and `chaindrive.tooth_jumps`,
/// read back here from the MCAP file with the `mcap` crate: as many entries
/// as the run's summary counts, each sprocket's first ride at the time and
/// roller the summary gives (the 30/30 drive on fixed centres worn 2 %,
/// whose slack strand's rollers drag over the driven sprocket's tips from
/// about 0.12 s and jump near 0.16 s).
#[cfg(feature = "record")]
#[test]
fn a_recording_lists_the_tip_rides_and_tooth_jumps_its_summary_counts() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = std::fs::read_to_string(data("worn_30_30_fixed.toml")).expect("scene");
    assert!(
        text.contains("elongation_pct = 0.0"),
        "the scene's elongation line"
    );
    let scene = dir.path().join("worn.toml");
    std::fs::write(
        &scene,
        text.replace("elongation_pct = 0.0", "elongation_pct = 2.0"),
    )
    .expect("scene");
    let (mcap, summary) = (dir.path().join("worn.mcap"), dir.path().join("s.json"));
    let run = chaindrive(&[
        "run",
        scene.to_str().expect("utf-8"),
        "--quiet",
        "--duration",
        "0.25",
        "--record",
        mcap.to_str().expect("utf-8"),
        "--summary",
        summary.to_str().expect("utf-8"),
    ]);
    assert!(run.status.success(), "{}", stderr(&run));
    let s = crate::common::read_json(&summary);
    let top = crate::common::mcap_top_level(&mcap).metadata;

    let per_sprocket = s["tip_rides"].as_array().expect("the run rode tips");
    let counted: u64 = per_sprocket
        .iter()
        .map(|r| r["count"].as_u64().expect("count"))
        .sum();
    let rides = top.get("chaindrive.tip_rides").expect("a tip_rides record");
    assert_eq!(rides["count"], counted.to_string(), "{rides:?}");
    let entries: Vec<&String> = rides
        .iter()
        .filter(|(k, _)| k.starts_with("ride "))
        .map(|(_, v)| v)
        .collect();
    assert_eq!(entries.len() as u64, counted, "{rides:?}");
    // Each sprocket's first entry (the entries are in time order) is the
    // summary's first ride there.
    for r in per_sprocket {
        let sprocket = format!("sprocket={}", r["sprocket"]);
        let first = entries
            .iter()
            .find(|e| e.split(' ').any(|f| f == sprocket))
            .unwrap_or_else(|| panic!("no ride on {sprocket}: {rides:?}"));
        let field = |name: &str| {
            first
                .split(' ')
                .find_map(|f| f.strip_prefix(name))
                .unwrap_or_else(|| panic!("{name} in {first}"))
                .to_owned()
        };
        let t_s: f64 = field("t_s=").parse().expect("a time");
        assert!(
            (t_s - r["first_t_s"].as_f64().expect("t")).abs() < 1e-12,
            "{first} {r}"
        );
        assert_eq!(
            field("roller="),
            r["first_roller"].to_string(),
            "{first} {r}"
        );
    }

    let jumps = s["tooth_jumps"].as_array().expect("the run jumped");
    let record = top
        .get("chaindrive.tooth_jumps")
        .expect("a tooth_jumps record");
    assert_eq!(record["count"], jumps.len().to_string(), "{record:?}");

    // `analyze` reads both records back: its analysis lists the run's
    // jumps and rides as the run's summary does, and its report says so.
    let analyze = chaindrive(&[
        "analyze",
        mcap.to_str().expect("utf-8"),
        "--out",
        dir.path().join("a").to_str().expect("utf-8"),
    ]);
    assert!(analyze.status.success(), "{}", stderr(&analyze));
    let a = crate::common::read_json(&dir.path().join("a").join("analysis.json"));
    assert_eq!(a["tooth_jumps"], s["tooth_jumps"]);
    assert_eq!(a["tip_rides"], s["tip_rides"]);
    let report = std::fs::read_to_string(dir.path().join("a").join("report.md")).expect("report");
    for what in ["**Mesh:** tooth jump:", "**Mesh:** tip ride:"] {
        assert!(report.contains(what), "{what} not in the report");
    }
}

/// The least return-spring preload that keeps a timing chain in mesh with
/// no supply pressure (`tests/data/user_timing_06b_arm.toml`, 3000 rpm,
/// 0.1 s runs): the search brackets it with the jumping end at the low end
/// of the range (a force that must be large enough), and a grid of plain
/// runs of the same drive, run as a study, agrees: a preload below the
/// bracket rides a tip, one above it runs clean.
///
/// Hand number: with no supply pressure the plunger pushes only with its
/// return spring, max(0, F0 - k x), and the arm lies at x = 17.37 mm of
/// travel to take up the chain (`check`'s "laid" line). A preload below
/// k x = 2000 N/m * 17.37 mm = 34.7 N pushes nothing there: the chain hangs
/// by its weight and the roller leaving the crank rests on a tip. So the
/// bracket's jumping end lies below 34.7 N and its clean end above it.
#[test]
fn jump_margin_finds_the_least_spring_preload_that_a_grid_of_runs_confirms() {
    let scene = data("user_timing_06b_arm.toml");
    let scene = scene.to_str().expect("utf-8");
    let path = "tensioners.0.hydraulic.spring_preload_n";
    let run = chaindrive(&[
        "jump-margin",
        scene,
        "--path",
        path,
        "--from",
        "0",
        "--to",
        "80",
        "--tolerance",
        "10",
        "--set",
        "tensioners.0.hydraulic.supply_pressure_pa=0",
        "--elongation",
        "0",
        "--duration",
        "0.1",
        "--jobs",
        "2",
        "--json",
    ]);
    assert!(run.status.success(), "{}", stderr(&run));
    let out: serde_json::Value = serde_json::from_slice(&run.stdout).expect("JSON");
    let margin = &out["margin"];
    let clean = margin["clean"].as_f64().expect("clean");
    let jumping = margin["jumping"].as_f64().expect("jumping");
    // Low preload loses the mesh, high preload keeps it: the bracket runs
    // from the jumping value up to the clean one, across k x.
    assert_eq!(margin["low_end_jumps"], true, "{out}");
    assert!(jumping < clean && clean - jumping <= 10.0, "{out}");
    let spring_at_rest = 2000.0 * 17.37e-3;
    assert!(
        jumping < spring_at_rest && spring_at_rest < clean,
        "k x = {spring_at_rest} N outside the bracket: {out}"
    );

    // The grid: one value below the bracket's jumping end, one above its
    // clean end (neither tried by the search).
    let levels = [jumping / 2.0, (clean + 80.0) / 2.0];
    let plan = format!(
        "scene = {scene:?}\nresponses = \"all\"\nset = {{ \"solver.duration_s\" = 0.1, \"chain.elongation_pct\" = 0.0, \"tensioners.0.hydraulic.supply_pressure_pa\" = 0.0 }}\nwindow_s = 0.05\n\n[[factors]]\npath = \"{path}\"\nlevels = {levels:?}\n\n[design]\nkind = \"full_factorial\"\n"
    );
    let csv = study_table(&plan);
    let lost: Vec<f64> = csv_column(&csv, "tooth_jump_count")
        .iter()
        .zip(csv_column(&csv, "tip_ride_count"))
        .map(|(j, r)| j.parse::<f64>().expect("a count") + r.parse::<f64>().expect("a count"))
        .collect();
    assert!(
        lost[0] >= 1.0,
        "{} N ran clean below {jumping} N: {csv}",
        levels[0]
    );
    assert_eq!(
        lost[1], 0.0,
        "{} N lost the mesh above {clean} N: {csv}",
        levels[1]
    );
}

/// Runs the study `plan` (a plan file's text) on two jobs, collects it and
/// returns its `results.csv`.
fn study_table(plan: &str) -> String {
    let dir = tempfile::tempdir().expect("temp dir");
    let plan_path = dir.path().join("plan.toml");
    std::fs::write(&plan_path, plan).expect("plan");
    let out_dir = dir.path().join("grid");
    let (plan_s, out_s) = (
        plan_path.to_str().expect("utf-8"),
        out_dir.to_str().expect("utf-8"),
    );
    let run = chaindrive(&["study", plan_s, "--out", out_s, "--jobs", "2", "--quiet"]);
    assert!(run.status.success(), "{}", stderr(&run));
    let collect = chaindrive(&["study", "collect", out_s]);
    assert!(collect.status.success(), "{}", stderr(&collect));
    std::fs::read_to_string(out_dir.join("results.csv")).expect("results.csv")
}
