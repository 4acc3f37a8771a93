//! The paper's study through the library: the L60MC four-sprocket drive run
//! with the circular profile, the real profile at the same pretension and the
//! real profile with the circular run's rest length; the report, summaries and
//! Figs. 16–24 written to a directory (what `chaindrive reproduce` does).
//!
//! ```sh
//! cargo run --release --example four_sprocket -- OUT_DIR [DURATION_S]
//! ```

use chaindrive::analysis::figures::{FigureChoice, paper_figures};
use chaindrive::studies::reproduce::{
    Findings, StudySettings, report_markdown, run_paper_study, summaries_json,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let out = std::path::PathBuf::from(args.next().unwrap_or_else(|| "four_sprocket".into()));
    let duration_s: f64 = args.next().map_or(Ok(10.0), |d| d.parse())?;
    std::fs::create_dir_all(&out)?;
    let study = run_paper_study(&StudySettings {
        duration_s,
        ..StudySettings::default()
    })?;
    let findings = Findings::measure(&study)?;
    let runs: Vec<_> = study.runs.iter().collect();
    let figures = paper_figures(&runs, FigureChoice::default(), &out)?;
    std::fs::write(
        out.join("summary.json"),
        serde_json::to_string_pretty(&summaries_json(&study))?,
    )?;
    std::fs::write(
        out.join("report.md"),
        report_markdown(&study, &findings, &figures),
    )?;
    for r in &findings.runs {
        if let Some(Ok(b)) = r.binder.first() {
            println!(
                "{:>22}: static {:.0} N, sprocket 1 contact force RMS vs (49) {:.0} N",
                r.label, r.static_tension_n, b.rms_n
            );
        }
    }
    println!("report: {}", out.join("report.md").display());
    Ok(())
}
