//! What the `glint` binary's tests share: running it, scratch folders, and the check that a
//! failure is one clear message.
#![allow(dead_code)] // each test file uses its own part

use std::path::PathBuf;
use std::process::{Child, Command, Output};
use std::time::{Duration, Instant};

pub fn glint(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_glint")).args(args).output().expect("the glint binary runs")
}

/// A fresh, empty folder for one test.
pub fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("glint-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).to_string()
}

/// Errors are one clear message and a non-zero exit, never a panic or a backtrace.
pub fn assert_clean_failure(o: &Output) -> String {
    let err = stderr(o);
    assert!(!o.status.success(), "expected failure, got success: {err}");
    assert!(!err.contains("panicked") && !err.contains("RUST_BACKTRACE") && !err.contains("internal error"), "{err}");
    assert!(err.starts_with("error: "), "{err}");
    err
}

/// Waits for `child` to end, killing it and failing the test (`what` says why) if it has not
/// `limit` after `start`.
pub fn wait_within(child: &mut Child, start: Instant, limit: Duration, what: &str) {
    while child.try_wait().expect("the child can be waited for").is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            panic!("{what}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}
