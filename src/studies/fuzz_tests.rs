//! Property test: mutated scene files never panic; every rejection names a
//! field (or, for a syntax error, a line); every accepted scene either fails
//! with a clear error or runs without NaN. The long version is
//! `chaindrive bench fuzz --cases N`.

use crate::scene::L60MC_TOML;
use crate::studies::fuzz::{FuzzOutcome, run_case};

#[test]
fn mutated_scenes_never_panic_and_explain_themselves() {
    let mut ran = 0;
    let mut rejected = 0;
    for seed in 0..400 {
        match run_case(L60MC_TOML, seed) {
            Ok(FuzzOutcome::Ran) => ran += 1,
            Ok(FuzzOutcome::Rejected) => rejected += 1,
            Ok(_) => {}
            Err(broken) => panic!("{broken}"),
        }
    }
    // Some mutations are harmless (a 10% change of a mass): those scenes must run.
    assert!(
        ran > 10 && rejected > 100,
        "ran {ran}, rejected {rejected} of 400"
    );
}
