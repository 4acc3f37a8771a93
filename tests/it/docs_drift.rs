//! The docs against the code, for the drifts a reader trips on first: a
//! command-line option or a scene-file field the docs name that no longer
//! exists, and one that exists but no doc names.
//!
//! The options are those `chaindrive … --help` defines, every subcommand
//! walked; the scene fields are those of the `deny_unknown_fields` structs
//! in `src/scene/`. The docs are README.md, docs/*.md and benches/README.md.
//! A field is recognised in the docs as a dotted path that starts with a
//! scene section (`solver.dt_s`, `[sprockets.governor]`,
//! `sprockets[0].speed_rpm`), and as a key of a scene-file TOML block.
//! What this does not check: prose ("the pretension"), a field named under
//! the wrong section, or values.

use std::collections::BTreeSet;
use std::path::Path;

use crate::common::chaindrive_stdout;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// Options of other tools that the docs show (cargo, its test harness,
/// criterion, valgrind, rerun, the public-name count `.ci/public-names`).
const FOREIGN_OPTIONS: [&str; 19] = [
    "--release",
    "--features",
    "--list",
    "--example",
    "--bench",
    "--test",
    "--lib",
    "--open",
    "--path",
    "--ignored",
    "--nocapture",
    "--test-threads",
    "--noplot",
    "--tool",
    "--toggle-collect",
    "--dump-instr",
    "--inclusive",
    "--timeline-type",
    "--application-id",
];

/// The scene file's sections: a dotted path starting with one of these is
/// a scene field's.
const SECTIONS: [&str; 7] = [
    "chain",
    "contact",
    "sprockets",
    "solver",
    "equilibrium",
    "tensioners",
    "guides",
];

/// Every doc's text, with its file name.
fn docs() -> Vec<(String, String)> {
    let mut paths = vec![
        Path::new(ROOT).join("README.md"),
        Path::new(ROOT).join("benches/README.md"),
    ];
    let mut md: Vec<_> = std::fs::read_dir(Path::new(ROOT).join("docs"))
        .expect("docs/")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    md.sort();
    paths.extend(md);
    paths
        .into_iter()
        .map(|p| {
            let text = std::fs::read_to_string(&p).expect("a doc");
            (p.display().to_string(), text)
        })
        .collect()
}

/// The `--options` named in `text` (`--` after no word character, then a
/// lowercase letter).
fn options_in(text: &str) -> BTreeSet<String> {
    let mut found = BTreeSet::new();
    for (at, _) in text.match_indices("--") {
        let before = text[..at].chars().next_back();
        if before.is_some_and(|c| c.is_alphanumeric() || c == '-' || c == '_') {
            continue;
        }
        let name: String = text[at + 2..]
            .chars()
            .take_while(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || *c == '-')
            .collect();
        if name.starts_with(|c: char| c.is_ascii_lowercase()) {
            found.insert(format!("--{}", name.trim_end_matches('-')));
        }
    }
    found
}

/// The options `chaindrive <args> --help` defines (its `Options:` section),
/// and its subcommands', recursively.
fn defined_options(args: &mut Vec<String>, found: &mut BTreeSet<String>) {
    let mut call: Vec<&str> = args.iter().map(String::as_str).collect();
    call.push("--help");
    let help = chaindrive_stdout(&call);
    let mut section = "";
    let mut subcommands = Vec::new();
    for line in help.lines() {
        if !line.starts_with(' ') && line.ends_with(':') {
            section = line;
            continue;
        }
        let trimmed = line.trim_start();
        match section {
            "Commands:" if line.starts_with("  ") => {
                if let Some(name) = trimmed.split_whitespace().next().filter(|n| *n != "help") {
                    subcommands.push(name.to_owned());
                }
            }
            "Options:" => {
                let trimmed = trimmed.strip_prefix("-h, ").unwrap_or(trimmed);
                let trimmed = match trimmed.get(..4) {
                    Some(short) if short.starts_with('-') && short.ends_with(", ") => &trimmed[4..],
                    _ => trimmed,
                };
                if trimmed.starts_with("--") {
                    found.extend(options_in(trimmed.split_whitespace().next().unwrap_or("")));
                }
            }
            _ => {}
        }
    }
    for sub in subcommands {
        args.push(sub);
        defined_options(args, found);
        args.pop();
    }
}

/// The fields of the scene file's serde structs: every `pub name:` of a
/// `#[serde(deny_unknown_fields)]` struct in `src/scene/`, but `#[serde(skip)]` ones.
fn scene_fields() -> BTreeSet<String> {
    let mut fields = BTreeSet::new();
    let dir = Path::new(ROOT).join("src/scene");
    for entry in std::fs::read_dir(dir).expect("src/scene") {
        let code = std::fs::read_to_string(entry.expect("entry").path()).expect("source");
        for (at, _) in code.match_indices("#[serde(deny_unknown_fields)]") {
            let rest = &code[at..];
            let (Some(open), Some(close)) = (rest.find('{'), rest.find("\n}")) else {
                continue;
            };
            let mut skip = false;
            for line in rest[open..close].lines().map(str::trim) {
                if line.starts_with("#[serde(skip)]") {
                    skip = true;
                }
                let Some(field) = line
                    .strip_prefix("pub ")
                    .or_else(|| line.strip_prefix("pub(crate) "))
                    .and_then(|l| l.split_once(':'))
                    .map(|(name, _)| name)
                else {
                    continue;
                };
                if !skip {
                    fields.insert(field.to_owned());
                }
                skip = false;
            }
        }
    }
    fields
}

/// Every property name of the run summary's JSON schema (a dotted path of
/// summary fields, as study plans write them, is not a scene path).
fn summary_fields() -> BTreeSet<String> {
    fn walk(v: &serde_json::Value, out: &mut BTreeSet<String>) {
        match v {
            serde_json::Value::Object(map) => {
                if let Some(serde_json::Value::Object(props)) = map.get("properties") {
                    out.extend(props.keys().cloned());
                }
                map.values().for_each(|v| walk(v, out));
            }
            serde_json::Value::Array(a) => a.iter().for_each(|v| walk(v, out)),
            _ => {}
        }
    }
    let text = std::fs::read_to_string(Path::new(ROOT).join("tests/data/run-summary.schema.json"))
        .expect("schema");
    let mut out = BTreeSet::new();
    walk(&serde_json::from_str(&text).expect("JSON"), &mut out);
    out
}

/// The dotted paths in `text` that start with a scene section
/// (`solver.limits.max_stretch_m`, `sprockets[0].speed_rpm`), as their
/// components (indices dropped); file names (`chain.rs`) and recording
/// channels' message paths (`/sprockets.speed_rad_s[0]`) left out.
fn scene_paths_in(text: &str) -> Vec<Vec<String>> {
    let word = |c: char| c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '[' | ']');
    let mut paths = Vec::new();
    let mut tokens = Vec::new();
    let mut start = None;
    for (i, c) in text.char_indices().chain([(text.len(), ' ')]) {
        match (word(c), start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                if !text[..s].ends_with('/') {
                    tokens.push(&text[s..i]);
                }
                start = None;
            }
            _ => {}
        }
    }
    for token in tokens {
        let token = token.trim_end_matches('.');
        let Some(section) = SECTIONS.iter().find(|s| {
            token
                .strip_prefix(**s)
                .is_some_and(|r| r.starts_with(['.', '[']))
        }) else {
            continue;
        };
        let parts: Vec<String> = token
            .split('.')
            .map(|p| p.split('[').next().unwrap_or("").to_owned())
            .filter(|p| !p.is_empty() && !p.chars().all(|c| c.is_ascii_digit()))
            .collect();
        let file = [
            "rs", "md", "toml", "csv", "json", "png", "svg", "mcap", "py", "sh",
        ];
        if parts.len() < 2 || parts.last().is_some_and(|p| file.contains(&p.as_str())) {
            continue;
        }
        debug_assert_eq!(parts[0], *section);
        paths.push(parts);
    }
    paths
}

/// The keys and table headers of the scene-file TOML blocks in `text` (a
/// block with a header of a scene section), comments dropped.
fn scene_toml_keys_in(text: &str) -> Vec<String> {
    let mut keys = Vec::new();
    for block in text.split("```toml").skip(1) {
        let block = block.split("```").next().unwrap_or("");
        let lines: Vec<&str> = block
            .lines()
            .map(|l| l.split('#').next().unwrap_or("").trim())
            .collect();
        let scene = lines.iter().any(|l| {
            let header = l.trim_start_matches('[');
            l.starts_with('[')
                && SECTIONS.iter().any(|s| {
                    header
                        .strip_prefix(*s)
                        .is_some_and(|r| r.starts_with([']', '.']))
                })
        });
        if !scene {
            continue;
        }
        for line in lines {
            if line.starts_with('[') {
                let header = line.trim_matches(|c| c == '[' || c == ']');
                keys.extend(header.split('.').map(str::to_owned));
                continue;
            }
            // `key = …`, and the keys of inline tables `{ a = 1, b = 2 }`.
            for piece in line.split(['{', ',']) {
                if let Some((key, _)) = piece.split_once('=') {
                    let key = key.trim();
                    if !key.is_empty() && key.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
                    {
                        keys.push(key.to_owned());
                    }
                }
            }
        }
    }
    keys
}

/// The problems of `docs` against the options and fields that exist.
fn drifts(
    docs: &[(String, String)],
    options: &BTreeSet<String>,
    fields: &BTreeSet<String>,
    summary: &BTreeSet<String>,
) -> Vec<String> {
    let mut problems = Vec::new();
    for (name, text) in docs {
        for o in options_in(text) {
            if !options.contains(&o) && !FOREIGN_OPTIONS.contains(&o.as_str()) {
                problems.push(format!(
                    "{name}: {o} is no option of any chaindrive command"
                ));
            }
        }
        for path in scene_paths_in(text) {
            let known = |set: &BTreeSet<String>| path.iter().all(|p| set.contains(p));
            if !known(fields) && !known(summary) {
                problems.push(format!(
                    "{name}: {} is no scene-file field (nor a summary field)",
                    path.join(".")
                ));
            }
        }
        for key in scene_toml_keys_in(text) {
            if !fields.contains(&key) {
                problems.push(format!(
                    "{name}: `{key}` in a scene-file block is no scene-file field"
                ));
            }
        }
    }
    let all: String = docs.iter().map(|(_, t)| t.as_str()).collect();
    let named = options_in(&all);
    for o in options {
        if !named.contains(o) && o != "--help" && o != "--version" {
            problems.push(format!("{o} is an option no doc names"));
        }
    }
    for f in fields {
        let whole_word = all.match_indices(f.as_str()).any(|(at, _)| {
            let before = all[..at].chars().next_back();
            let after = all[at + f.len()..].chars().next();
            let edge = |c: Option<char>| !c.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_');
            edge(before) && edge(after)
        });
        if !whole_word {
            problems.push(format!("scene-file field `{f}` is named by no doc"));
        }
    }
    problems
}

#[test]
fn the_docs_name_the_options_and_fields_that_exist() {
    let mut options = BTreeSet::new();
    defined_options(&mut Vec::new(), &mut options);
    let fields = scene_fields();
    let summary = summary_fields();
    let docs = docs();
    // First: the checks see what they look for at all.
    assert!(options.len() > 40, "options found: {options:?}");
    for o in ["--dt", "--rate", "--resume", "--submit", "--warmup"] {
        assert!(options.contains(o), "{o} not found in: {options:?}");
    }
    assert!(fields.len() > 100, "fields found: {fields:?}");
    for f in [
        "dt_s",
        "pretension_n",
        "bore_m",
        "drive_table",
        "start_ramp",
    ] {
        assert!(fields.contains(f), "{f} not found in: {fields:?}");
    }
    assert!(!fields.contains("base_dir") && !fields.contains("sample_period_s"));
    let paths: usize = docs.iter().map(|(_, t)| scene_paths_in(t).len()).sum();
    assert!(paths > 30, "dotted scene paths found: {paths}");
    // A drift of each kind is caught.
    let planted = [(
        "planted".to_owned(),
        "Run with `--no-such-option`; set `solver.no_such_field`.\n```toml\n[solver]\nno_such_key = 1\n```\n"
            .to_owned(),
    )];
    let caught = drifts(&planted, &options, &fields, &summary);
    for needle in ["--no-such-option", "solver.no_such_field", "`no_such_key`"] {
        assert!(
            caught.iter().any(|p| p.contains(needle)),
            "{needle} not caught: {caught:#?}"
        );
    }
    let fewer: BTreeSet<String> = options
        .iter()
        .cloned()
        .chain(["--new-option".to_owned()])
        .collect();
    let caught = drifts(&docs, &fewer, &fields, &summary);
    assert!(
        caught.iter().any(|p| p.contains("--new-option")),
        "{caught:#?}"
    );
    // The docs as they are.
    let problems = drifts(&docs, &options, &fields, &summary);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
