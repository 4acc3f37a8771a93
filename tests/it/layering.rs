//! The layering rule of `src/lib.rs` and docs/architecture.md: data flows
//! once, forward, and no module imports a later stage.

use std::collections::BTreeSet;
use std::path::Path;

/// The stages, earliest first; modules of one rank are siblings, which may
/// not import each other either.
const STAGES: [(&str, u8); 10] = [
    ("geometry", 0),
    ("scene", 1),
    ("model", 2),
    ("forces", 3),
    ("sim", 4),
    ("cosim", 5),
    ("record", 5),
    ("analysis", 6),
    ("studies", 7),
    ("cli", 8),
];

fn rank(module: &str) -> Option<u8> {
    STAGES.iter().find(|(m, _)| *m == module).map(|&(_, r)| r)
}

/// The crate's top-level modules named by `crate::…` paths in `code`
/// (comments dropped; `crate::{a::…, b}` groups opened).
fn crate_modules(code: &str) -> BTreeSet<String> {
    let mut found = BTreeSet::new();
    let code: String = code
        .lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n");
    let ident = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect()
    };
    for (at, _) in code.match_indices("crate::") {
        let rest = &code[at + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            // Top-level names of the group: after `{` and after each `,` at depth 0.
            let mut depth = 0;
            let mut start = true;
            for (i, c) in group.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => break,
                    '}' => depth -= 1,
                    ',' if depth == 0 => start = true,
                    c if start && !c.is_whitespace() => {
                        found.insert(ident(&group[i..]));
                        start = false;
                    }
                    _ => {}
                }
            }
        } else {
            found.insert(ident(rest));
        }
    }
    found
}

fn rust_files(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("readable src") {
        let path = entry.expect("entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

#[test]
fn no_module_imports_a_later_stage() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut violations = Vec::new();
    let mut seen = BTreeSet::new();
    for (module, own) in STAGES {
        let mut files = Vec::new();
        let dir = src.join(module);
        if dir.is_dir() {
            rust_files(&dir, &mut files);
        }
        let single = src.join(format!("{module}.rs"));
        if single.is_file() {
            files.push(single);
        }
        assert!(!files.is_empty(), "src/{module} exists");
        for file in files {
            // Unit tests beside the code may drive a later stage (record a
            // run, run a study) to check their module: tests, not the module.
            if file.to_string_lossy().ends_with("_tests.rs") {
                continue;
            }
            let code = std::fs::read_to_string(&file).expect("readable");
            for used in crate_modules(&code) {
                seen.insert((module, used.clone()));
                if let Some(r) = rank(&used)
                    && used != module
                    && r >= own
                {
                    violations.push(format!(
                        "{} imports crate::{used} (a later or sibling stage of {module})",
                        file.strip_prefix(&src).unwrap_or(&file).display()
                    ));
                }
            }
        }
    }
    // The scan sees the imports it must allow: it can find a violation.
    assert!(seen.contains(&("sim", "forces".to_owned())), "{seen:?}");
    assert!(seen.contains(&("model", "geometry".to_owned())), "{seen:?}");
    assert!(violations.is_empty(), "{}", violations.join("\n"));
}

#[test]
fn the_scan_opens_use_groups_and_skips_comments() {
    let code =
        "use crate::{forces::{A, B}, model::C};\n// crate::studies\nlet x = crate::sim::f();";
    let found = crate_modules(code);
    let want: BTreeSet<String> = ["forces", "model", "sim"].map(str::to_owned).into();
    assert_eq!(found, want);
}

/// The modules a user is documented to reach besides the prelude: each
/// holds the parts of a concept the prelude names (a scene's parts, a run's
/// outcome, the co-simulation's details, the summary's parts, the
/// recording's options).
const USER_MODULES: [&str; 6] = ["prelude", "scene", "sim", "cosim", "analysis", "record"];

/// The top-level modules named by `chaindrive::…` paths in `code`.
fn library_modules(code: &str) -> BTreeSet<String> {
    crate_modules(&code.replace("chaindrive::", "crate::"))
}

#[test]
fn examples_use_only_the_prelude_and_user_modules() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut files = Vec::new();
    rust_files(&dir, &mut files);
    assert!(files.len() > 5, "examples found: {files:?}");
    let mut seen = BTreeSet::new();
    let mut violations = Vec::new();
    for file in files {
        let code = std::fs::read_to_string(&file).expect("readable");
        for used in library_modules(&code) {
            seen.insert(used.clone());
            if !USER_MODULES.contains(&used.as_str()) {
                violations.push(format!("{} uses chaindrive::{used}", file.display()));
            }
        }
    }
    // The scan sees the examples' imports at all.
    assert!(seen.contains("prelude"), "{seen:?}");
    assert!(violations.is_empty(), "{}", violations.join("\n"));
}
