//! Outputs that would overwrite each other, or the scene, are refused
//! before anything runs (through the real binary).

use crate::common::{chaindrive_in, stderr};

#[test]
fn two_outputs_at_one_path_are_refused_naming_both_options() {
    let dir = tempfile::tempdir().expect("tmp");
    // One file, spelled two ways: the check compares resolved paths.
    let out = chaindrive_in(
        dir.path(),
        &[
            "run",
            "--duration",
            "0.1",
            "--summary",
            "x.out",
            "--series",
            "./x.out",
        ],
    );
    assert!(!out.status.success());
    let err = stderr(&out);
    assert!(
        err.contains("--summary and --series both write to ./x.out"),
        "{err}"
    );
    // Refused before anything ran: nothing was written.
    assert!(!dir.path().join("x.out").exists(), "{err}");

    let out = chaindrive_in(
        dir.path(),
        &[
            "run",
            "--duration",
            "0.1",
            "--series",
            "y.mcap",
            "--record",
            "y.mcap",
        ],
    );
    assert!(!out.status.success());
    let err = stderr(&out);
    assert!(err.contains("--series and --record both write to"), "{err}");
    assert!(!dir.path().join("y.mcap").exists(), "{err}");
}

#[test]
fn an_output_over_the_scene_file_is_refused_and_the_scene_kept() {
    let dir = tempfile::tempdir().expect("tmp");
    let scene = dir.path().join("drive.toml");
    std::fs::write(&scene, chaindrive::scene::L60MC_TOML).expect("write scene");
    let scene_arg = scene.to_str().expect("utf8");
    for option in ["--summary", "--series", "--record"] {
        // The scene named relative to the working folder, the output absolute.
        let out = chaindrive_in(
            dir.path(),
            &["run", "drive.toml", "--duration", "0.1", option, scene_arg],
        );
        assert!(!out.status.success(), "{option}");
        let err = stderr(&out);
        assert!(
            err.contains(&format!("{option} {scene_arg} is the scene file")),
            "{err}"
        );
        assert_eq!(
            std::fs::read_to_string(&scene).expect("scene"),
            chaindrive::scene::L60MC_TOML,
            "{option} changed the scene"
        );
    }
}
