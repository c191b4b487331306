//! The Python package's own tests (`test_glint.py`, pytest), run by `cargo test`: a virtual
//! environment under target/ gets maturin, numpy, pytest and Ray from the Python registry
//! (once; later runs find them), the package is built as a wheel by maturin (reusing the
//! workspace's build) and installed into it, the `glint` command is built (tests compare the
//! two front ends' refusals), and pytest runs the tests against them.

use std::path::{Path, PathBuf};
use std::process::Command;

fn run(command: &mut Command, what: &str) {
    let shown = format!("{command:?}");
    let output = command.output().unwrap_or_else(|e| panic!("{what}: cannot run {shown}: {e}"));
    assert!(
        output.status.success(),
        "{what} failed ({shown}):\n{}\n{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
}

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").canonicalize().expect("the workspace")
}

#[test]
fn the_python_package_passes_its_tests() {
    let root = workspace();
    let venv = root.join("target/python-venv");
    let python = venv.join("bin/python");
    if !python.exists() {
        let system = std::env::var("PYTHON").unwrap_or_else(|_| "python3".into());
        run(Command::new(system).args(["-m", "venv"]).arg(&venv), "creating the virtual environment");
    }
    run(
        Command::new(&python).args([
            "-m",
            "pip",
            "install",
            "-q",
            "--disable-pip-version-check",
            "maturin>=1.5,<2",
            "numpy>=1.21",
            "pytest>=7",
            "ray>=2.9",
        ]),
        "installing maturin, numpy, pytest and Ray",
    );
    let wheels = root.join("target/wheels");
    let _ = std::fs::remove_dir_all(&wheels);
    run(
        Command::new(venv.join("bin/maturin"))
            .args(["build", "--release", "--quiet", "-i"])
            .arg(&python)
            .arg("-o")
            .arg(&wheels)
            .arg("-m")
            .arg(root.join("crates/glint-py/Cargo.toml")),
        "building the wheel",
    );
    let wheel = std::fs::read_dir(&wheels)
        .expect("maturin's output")
        .flatten()
        .map(|e| e.path())
        .find(|p| p.extension().is_some_and(|e| e == "whl"))
        .expect("a wheel");
    run(
        Command::new(&python).args(["-m", "pip", "install", "-q", "--force-reinstall", "--no-deps"]).arg(&wheel),
        "installing the wheel",
    );
    // The command, for the tests that check Python and the command refuse alike.
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    run(
        Command::new(cargo)
            .args(["build", "--release", "--quiet", "-p", "glint-cli", "--bin", "glint"])
            .current_dir(&root),
        "building the glint command",
    );
    let target = std::env::var_os("CARGO_TARGET_DIR").map_or_else(|| root.join("target"), PathBuf::from);
    run(
        Command::new(&python)
            .args(["-m", "pytest", "-q", "-p", "no:cacheprovider"])
            .arg(root.join("crates/glint-py/tests"))
            .env("GLINT_CLI", target.join("release/glint"))
            .current_dir(&root),
        "the Python tests",
    );
}
