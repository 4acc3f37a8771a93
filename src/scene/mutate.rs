//! Scene-file mutations for property and fuzz testing: the mistakes people
//! make in hand-written scenes (a sign, a zero, NaN, a wrong unit, a deleted
//! or duplicated line, a typo in a key or a value), generated from a seed so
//! that every case can be replayed ([`crate::rng::SeededRng`]).

use crate::rng::SeededRng;

/// Applies 1–3 random mutations to a scene file's text.
pub fn mutate(text: &str, rng: &mut SeededRng) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    for _ in 0..1 + rng.below(3) {
        let assignments: Vec<usize> = lines
            .iter()
            .enumerate()
            .filter(|(_, l)| l.contains(" = ") && !l.trim_start().starts_with('#'))
            .map(|(i, _)| i)
            .collect();
        if assignments.is_empty() {
            break;
        }
        let i = assignments[rng.below(assignments.len())];
        let (key, value) = match lines[i].split_once(" = ") {
            Some((k, v)) => (k.to_owned(), v.to_owned()),
            None => continue,
        };
        let number = value
            .split_whitespace()
            .next()
            .and_then(|v| v.parse::<f64>().ok());
        lines[i] = match (rng.below(12), number) {
            (0, _) => continue_with(&mut lines, i, rng),
            (1, _) => format!("{key}x = {value}"),
            (2, _) => format!("{key} = \"{}\"", value.trim_matches('"')),
            (3, Some(v)) => format!("{key} = {}", -v),
            (4, Some(_)) => format!("{key} = 0.0"),
            (5, Some(_)) => format!("{key} = nan"),
            (6, Some(_)) => format!("{key} = inf"),
            (7, Some(v)) => format!("{key} = {:e}", v * 1000.0),
            (8, Some(v)) => format!("{key} = {:e}", v / 1000.0),
            (9, Some(v)) => format!("{key} = {:e}", v * (0.9 + 0.2 * rng.unit())),
            (10, _) => format!("{key} = [1.0, 2.0]"),
            _ => format!("{key} = {}", value.replace('0', "")),
        };
    }
    let mut out = lines.join("\n");
    out.push('\n');
    out
}

/// Deletes line `i` or duplicates it; returns the new content of line `i`.
fn continue_with(lines: &mut [String], i: usize, rng: &mut SeededRng) -> String {
    if rng.below(2) == 0 {
        String::new()
    } else {
        let l = lines[i].clone();
        format!("{l}\n{l}")
    }
}
