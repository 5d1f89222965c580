//! End-to-end tests of the `stoss` binary.

use std::process::Command;

fn stoss() -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_stoss"));
    command.current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."));
    command
}

#[test]
fn verify_prints_the_table_and_succeeds() {
    // GOAL: `stoss verify` (the README's command) runs on a fresh clone and passes.
    // SETUP: run from the workspace root with the bundled golden files.
    // REFERENCE: exit 0, a table with every model, all goldens bit-identical.
    let output = stoss().arg("verify").output().unwrap();
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{text}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    for model in [
        "jc-4340",
        "za-bcc-armco",
        "za-fcc-copper",
        "mjc-hha",
        "tjc-hha",
    ] {
        assert!(text.contains(model), "missing {model}");
    }
    assert!(text.contains("golden histories: 35 of 35 bit-identical"));
}

#[test]
fn verify_fails_with_a_clear_error_on_a_missing_golden_directory() {
    // GOAL: bad input gives a non-zero exit and names the file.
    // SETUP: point --golden-dir at a folder that does not exist.
    // REFERENCE: exit code 1, stderr names the missing file.
    let output = stoss()
        .args(["verify", "--golden-dir", "does/not/exist"])
        .output()
        .unwrap();
    assert!(!output.status.success());
    let errors = String::from_utf8_lossy(&output.stderr);
    assert!(
        errors.contains("does/not/exist/jc-4340__uniaxial-stress.golden"),
        "{errors}"
    );
}
