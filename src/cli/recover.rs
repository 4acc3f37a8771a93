//! `chaindrive recover`: a complete, indexed copy of a recording cut short
//! (`crate::record::recover`).

use std::fs::File;
use std::io::BufWriter;
use std::path::PathBuf;
use std::process::ExitCode;

use crate::record::recover::recover as recover_bytes;
use anyhow::Context;

/// Arguments of `chaindrive recover`.
#[derive(clap::Args)]
pub(super) struct RecoverArgs {
    /// The damaged recording (e.g. of a run that was killed).
    input: PathBuf,
    /// The complete copy to write (must differ from the input).
    output: PathBuf,
}

pub(super) fn recover(args: RecoverArgs) -> anyhow::Result<ExitCode> {
    crate::cli::outputs::check_distinct(
        &[("input recording", Some(&args.input))],
        &[("the output", Some(&args.output))],
    )?;
    let bytes = std::fs::read(&args.input)
        .with_context(|| format!("cannot read {}", args.input.display()))?;
    let file = File::create(&args.output)
        .with_context(|| format!("cannot write {}", args.output.display()))?;
    let result = recover_bytes(&bytes, BufWriter::new(file));
    let found = match result {
        Ok((_, found)) => found,
        Err(e) => {
            // Leave no half-written file that looks like a recording.
            let _ = std::fs::remove_file(&args.output);
            return Err(e).with_context(|| format!("cannot recover {}", args.input.display()));
        }
    };
    if found.input_complete {
        eprintln!(
            "note: {} was already complete; {} is a copy",
            args.input.display(),
            args.output.display()
        );
    }
    if let Some(damage) = &found.damage {
        eprintln!("read up to the first damaged record: {damage}");
    }
    println!(
        "recovered {} messages up to t = {:.3} s ({} channels, {} schemas, {} attachments, {} metadata records) into {}",
        found.messages,
        found.last_log_time_ns as f64 * 1e-9,
        found.channels,
        found.schemas,
        found.attachments,
        found.metadata,
        args.output.display()
    );
    Ok(ExitCode::SUCCESS)
}
