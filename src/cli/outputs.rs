//! Output paths checked before anything runs: no two outputs of one command
//! at one path (the later would overwrite the earlier), and no output over an
//! input (the scene file, the recording being read).

use std::path::{Path, PathBuf};

/// `path` made absolute with its links resolved, as far as it exists: an
/// existing file is canonicalised; a file still to be written is its
/// canonicalised folder joined with its name (so `out.json`, `./out.json`
/// and `dir/../out.json` are one path).
fn resolved(path: &Path) -> PathBuf {
    if let Ok(p) = path.canonicalize() {
        return p;
    }
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    match (parent.canonicalize(), path.file_name()) {
        (Ok(dir), Some(name)) => dir.join(name),
        // The folder does not exist either: creating the file will fail
        // with its own message; compare the path as written.
        _ => std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf()),
    }
}

/// Refuses two `outputs` (option name, path) at one path, and an output at
/// one of the `inputs` (what it is, path), naming the options involved.
pub(crate) fn check_distinct(
    inputs: &[(&str, Option<&Path>)],
    outputs: &[(&str, Option<&Path>)],
) -> anyhow::Result<()> {
    let outputs: Vec<(&str, &Path, PathBuf)> = outputs
        .iter()
        .filter_map(|&(name, p)| p.map(|p| (name, p, resolved(p))))
        .collect();
    for (i, (a, path, resolved_a)) in outputs.iter().enumerate() {
        if let Some((b, _, _)) = outputs[..i].iter().find(|o| &o.2 == resolved_a) {
            anyhow::bail!(
                "{b} and {a} both write to {}: the second would overwrite the first; give each output its own path",
                path.display()
            );
        }
        for &(what, input) in inputs {
            if input.is_some_and(|input| &resolved(input) == resolved_a) {
                anyhow::bail!(
                    "{a} {} is the {what}: writing there would overwrite it; choose another path",
                    path.display()
                );
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_file_spelled_two_ways_is_one_path() {
        let dir = std::env::temp_dir();
        let a = dir.join("chaindrive-outputs-x.json");
        let b = dir.join(".").join("chaindrive-outputs-x.json");
        assert_eq!(resolved(&a), resolved(&b));
        let err = check_distinct(&[], &[("--summary", Some(&a)), ("--series", Some(&b))]);
        let message = err.err().map(|e| e.to_string()).unwrap_or_default();
        assert!(
            message.starts_with("--summary and --series both write to"),
            "{message}"
        );
        let other = dir.join("chaindrive-outputs-y.csv");
        assert!(
            check_distinct(&[], &[("--summary", Some(&a)), ("--series", Some(&other))]).is_ok()
        );
    }
}
