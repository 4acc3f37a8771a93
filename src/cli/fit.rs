//! `chaindrive fit`: moves one sprocket along a direction until the
//! unstretched chain fits the path through the seated rollers exactly
//! (`crate::sim::fit_sprocket`), prints where, and writes the fitted
//! scene. The scene file is edited in place of its values — the sprocket's
//! `center_m` and, with `--rollers`, `chain.rollers` are replaced where they
//! stand in the text — so its comments, order and layout are kept.

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use crate::model::DriveModel;
use crate::scene::{Overrides, Scene, value_span};
use crate::sim::{FIT_TOLERANCE_M, default_direction, fit_sprocket};
use anyhow::Context;

/// Arguments of `chaindrive fit`.
#[derive(clap::Args)]
pub(super) struct FitArgs {
    /// Scene file (TOML).
    scene: PathBuf,
    /// The sprocket to move: its name or its 1-based position in the scene.
    #[arg(long = "move", value_name = "SPROCKET")]
    sprocket: String,
    /// Direction of the move, "X,Y" (any length). Default: a tensioner's
    /// adjust_direction, else away from the other sprockets' centroid (for
    /// two sprockets, along the centre line).
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true)]
    along: Option<String>,
    /// Roller count to fit (default: the scene's chain.rollers).
    #[arg(long)]
    rollers: Option<usize>,
    /// Where to write the fitted scene (default: SCENE with "-fitted"
    /// before its extension).
    #[arg(long, value_name = "FITTED.toml")]
    out: Option<PathBuf>,
}

pub(super) fn fit(args: FitArgs) -> anyhow::Result<ExitCode> {
    let name = args.scene.display().to_string();
    let text = std::fs::read_to_string(&args.scene)
        .with_context(|| format!("cannot read scene {name}"))?;
    let scene = match crate::cli::load_scene(Some(&args.scene), &Overrides::default())? {
        Ok(s) => s,
        Err(lines) => {
            eprintln!("{lines}");
            return Ok(ExitCode::FAILURE);
        }
    };
    let out = args.out.clone().unwrap_or_else(|| fitted_path(&args.scene));
    crate::cli::outputs::check_distinct(
        &[("scene file", Some(&args.scene))],
        &[("--out", Some(&out))],
    )?;
    let k = sprocket_index(&scene, &args.sprocket)?;
    let direction = match &args.along {
        Some(s) => parse_direction(s)?,
        None => default_direction(&scene, k).with_context(|| {
            format!(
                "sprocket \"{}\" sits on the other sprockets' centroid: give --along X,Y",
                scene.sprockets()[k].name
            )
        })?,
    };
    let rollers = args.rollers.unwrap_or(scene.chain().rollers);
    anyhow::ensure!(rollers >= 4, "--rollers must be at least 4, got {rollers}");
    let sp = &scene.sprockets()[k];
    let fit = match fit_sprocket(&scene, k, direction, rollers) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("{name}: no position fits {rollers} rollers: {e}");
            return Ok(ExitCode::FAILURE);
        }
    };
    say(format_args!(
        "sprocket \"{}\": centre [{:?}, {:?}] m -> [{:?}, {:?}] m, moved by [{:+.6}, {:+.6}] m",
        sp.name,
        sp.center_m[0],
        sp.center_m[1],
        fit.center_m[0],
        fit.center_m[1],
        fit.offset_m * fit.direction[0],
        fit.offset_m * fit.direction[1],
    ))?;
    say(format_args!(
        "the path through the seated rollers needed {:.4} pitches; now {:.9} for {rollers} rollers (misfit {:.1e} m, tolerance {FIT_TOLERANCE_M:.0e} m; {} layouts)",
        fit.needed_before, fit.needed_pitches, fit.misfit_m, fit.evaluations
    ))?;
    let mut edits = vec![(
        format!("sprockets[{k}].center_m"),
        format!("[{:?}, {:?}]", fit.center_m[0], fit.center_m[1]),
    )];
    if args.rollers.is_some() {
        edits.push(("chain.rollers".to_owned(), rollers.to_string()));
    }
    let fitted = edit_values(&text, &edits)?;
    // The fitted text is read back as a scene and laid out, as `check` would.
    let fitted_scene = match Scene::from_toml(&fitted) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("{name}: the fitted scene is not valid: {e}");
            return Ok(ExitCode::FAILURE);
        }
    };
    match DriveModel::build(&fitted_scene) {
        Ok((_, _, layout)) => say(format_args!(
            "fitted layout: strand links {:.9} m for a pitch of {} m (misfit {:.2e} pitches)",
            layout.strand_link_m,
            fitted_scene.chain().pitch_m,
            layout.misfit_pitches
        ))?,
        Err(e) => {
            eprintln!("{name}: the fitted scene does not lay out: {e}");
            return Ok(ExitCode::FAILURE);
        }
    }
    std::fs::write(&out, fitted).with_context(|| format!("cannot write {}", out.display()))?;
    say(format_args!("wrote {}", out.display()))?;
    Ok(ExitCode::SUCCESS)
}

/// One line on stdout; a closed pipe (`chaindrive fit ... | head`) is not
/// an error: the fitted scene is still written.
fn say(args: std::fmt::Arguments<'_>) -> std::io::Result<()> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    crate::cli::chains::quiet_on_closed_pipe(
        out.write_fmt(args).and_then(|()| out.write_all(b"\n")),
    )
}

/// `scene.toml` -> `scene-fitted.toml`, beside it.
fn fitted_path(scene: &Path) -> PathBuf {
    let stem = scene
        .file_stem()
        .map_or_else(|| "scene".to_owned(), |s| s.to_string_lossy().into_owned());
    scene.with_file_name(format!("{stem}-fitted.toml"))
}

/// A sprocket by name, or by 1-based position.
fn sprocket_index(scene: &Scene, key: &str) -> anyhow::Result<usize> {
    let sprockets = scene.sprockets();
    if let Some(k) = sprockets.iter().position(|s| s.name == key) {
        return Ok(k);
    }
    if let Ok(i) = key.parse::<usize>()
        && (1..=sprockets.len()).contains(&i)
    {
        return Ok(i - 1);
    }
    anyhow::bail!(
        "--move \"{key}\": no such sprocket; the scene has {}",
        sprockets
            .iter()
            .enumerate()
            .map(|(i, s)| format!("{} (\"{}\")", i + 1, s.name))
            .collect::<Vec<_>>()
            .join(", ")
    )
}

/// "X,Y" as a finite, non-zero vector.
fn parse_direction(s: &str) -> anyhow::Result<[f64; 2]> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let parsed: Option<Vec<f64>> = parts.iter().map(|p| p.parse::<f64>().ok()).collect();
    match parsed.as_deref() {
        Some(&[x, y]) if x.is_finite() && y.is_finite() && x.hypot(y) > 0.0 => Ok([x, y]),
        _ => anyhow::bail!("--along \"{s}\": expected two numbers X,Y, not both zero (e.g. 1,0)"),
    }
}

/// `text` with the value at each (path, new value) replaced in place.
fn edit_values(text: &str, edits: &[(String, String)]) -> anyhow::Result<String> {
    let mut spans: Vec<(Range<usize>, &str)> = edits
        .iter()
        .map(|(path, value)| {
            value_span(text, path)
                .map(|r| (r, value.as_str()))
                .with_context(|| format!("{path} is not written in the scene file"))
        })
        .collect::<anyhow::Result<_>>()?;
    // Replace from the end so that earlier spans stay valid.
    spans.sort_by_key(|(r, _)| std::cmp::Reverse(r.start));
    let mut out = text.to_owned();
    for (range, value) in spans {
        out.replace_range(range, value);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edits_replace_only_the_values() {
        let text = "name = \"x\" # keep\n[chain]\nrollers = 86 # count\n[[sprockets]]\ncenter_m = [1.0, 0.0]\n[[sprockets]]\ncenter_m = [ 0.0 , 0.0 ] # second\n";
        let out = edit_values(
            text,
            &[
                (
                    "sprockets[1].center_m".to_owned(),
                    "[0.5, -0.25]".to_owned(),
                ),
                ("chain.rollers".to_owned(), "88".to_owned()),
            ],
        )
        .expect("edited");
        assert_eq!(
            out,
            "name = \"x\" # keep\n[chain]\nrollers = 88 # count\n[[sprockets]]\ncenter_m = [1.0, 0.0]\n[[sprockets]]\ncenter_m = [0.5, -0.25] # second\n"
        );
    }

    #[test]
    fn directions_parse() {
        assert_eq!(parse_direction("1,0").expect("ok"), [1.0, 0.0]);
        assert_eq!(parse_direction(" -0.5 , 2 ").expect("ok"), [-0.5, 2.0]);
        assert!(parse_direction("0,0").is_err());
        assert!(parse_direction("1").is_err());
        assert!(parse_direction("a,b").is_err());
    }
}
