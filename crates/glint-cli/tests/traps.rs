//! Hostile scenes (tests/traps/): every render of them ends within a bound at every
//! integrator, without a crash, and the closed boxes stay black where no light can reach.
//! Each failed before its fix: Whitted overflowed the stack at unbounded depth, SPPM's camera
//! paths never ended in the mirror box, rays left the boxes through their edges, and photon
//! mapping counted the photons on the outside of a wall.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use glint_cli::output::read_pfm;

const INTEGRATORS: [&str; 7] = ["raycast", "whitted", "path", "path-naive", "light", "photon", "sppm"];

fn trap(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/traps").join(name)
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("glint-traps-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs glint, failing the test if it has not ended after `limit` (the child is killed).
fn glint_within(args: &[&str], limit: Duration) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_glint"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the glint binary runs");
    // Read both pipes as the child writes, or a long explain fills a pipe and waits forever.
    let drain = |mut pipe: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            pipe.read_to_end(&mut bytes).map(|_| bytes).unwrap_or_default()
        })
    };
    let stdout = drain(Box::new(child.stdout.take().unwrap()));
    let stderr = drain(Box::new(child.stderr.take().unwrap()));
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("the child can be waited for") {
            break status;
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            panic!("glint {args:?} did not end within {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let output = Output { status, stdout: stdout.join().unwrap(), stderr: stderr.join().unwrap() };
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "glint {args:?} failed: {stderr}");
    assert!(!stderr.contains("panicked") && !stderr.contains("overflow"), "{stderr}");
    output
}

/// Renders `scene` with `integrator` at unbounded depth; returns the pixels and stderr.
fn render(scene: &str, integrator: &str, spp: &str, extra: &[&str]) -> (Vec<f32>, String) {
    let out = temp_dir(&format!("{scene}-{integrator}")).join("out.pfm");
    let scene = trap(scene);
    let mut args =
        vec!["render", scene.to_str().unwrap(), "--integrator", integrator, "--spp", spp, "--max-depth", "-1"];
    args.extend_from_slice(extra);
    args.extend_from_slice(&["-o", out.to_str().unwrap()]);
    let output = glint_within(&args, Duration::from_secs(60));
    let (_, _, pixels) = read_pfm(&out).expect("the image was written");
    let _ = std::fs::remove_dir_all(out.parent().expect("the image's folder"));
    let pixels = pixels.iter().flat_map(|p| p.to_array()).collect();
    (pixels, String::from_utf8_lossy(&output.stderr).to_string())
}

fn lit_pixels(pixels: &[f32]) -> usize {
    pixels.chunks(3).filter(|p| p.iter().any(|&v| v != 0.0)).count()
}

#[test]
fn the_closed_mirror_box_is_black_under_every_integrator() {
    for integrator in INTEGRATORS {
        let (pixels, stderr) = render("mirror-box.toml", integrator, "4", &[]);
        assert_eq!(lit_pixels(&pixels), 0, "{integrator}: light where there is none");
        if integrator == "whitted" {
            // Perfect mirrors never lose weight: only the ceilings end the trees, and say so.
            assert!(stderr.contains("were cut at"), "{stderr}");
        }
    }
}

#[test]
fn whitted_at_any_depth_ends_without_overflowing_the_stack() {
    for depth in ["5000", "-1"] {
        let out = temp_dir(&format!("deep-{depth}")).join("out.pfm");
        let scene = trap("mirror-box.toml");
        let args = [
            "render",
            scene.to_str().unwrap(),
            "--max-depth",
            depth,
            "--width",
            "8",
            "--min-contribution",
            "0",
            "-o",
            out.to_str().unwrap(),
        ];
        glint_within(&args, Duration::from_secs(60));
        let _ = std::fs::remove_dir_all(out.parent().expect("the image's folder"));
    }
}

#[test]
fn no_light_leaks_into_a_box_lit_from_outside() {
    // Raycast has no shadow rays: the course's ray casting lights the inside too.
    for integrator in INTEGRATORS.into_iter().filter(|&i| i != "raycast") {
        let spp = if integrator == "photon" { "1" } else { "8" };
        let (pixels, _) = render("dark-box.toml", integrator, spp, &["--photons", "20000"]);
        assert_eq!(lit_pixels(&pixels), 0, "{integrator}: light leaked into the closed box");
    }
}

#[test]
fn nested_glass_that_makes_light_ends_and_warns() {
    for integrator in INTEGRATORS {
        let (_, stderr) = render("nested-glass.toml", integrator, "1", &["--photons", "5000"]);
        assert!(stderr.contains("passes on more light than it receives"), "{integrator}: {stderr}");
    }
}

#[test]
fn sppm_stops_at_its_time_limit_in_a_trap() {
    let out = temp_dir("sppm-time").join("out.pfm");
    for scene in ["nested-glass.toml", "mirror-box.toml"] {
        let scene = trap(scene);
        let args = [
            "render",
            scene.to_str().unwrap(),
            "--integrator",
            "sppm",
            "--max-depth",
            "-1",
            "--time",
            "1",
            "-o",
            out.to_str().unwrap(),
        ];
        let start = Instant::now();
        glint_within(&args, Duration::from_secs(30));
        assert!(start.elapsed() < Duration::from_secs(10), "{:?}", start.elapsed());
    }
    let _ = std::fs::remove_dir_all(out.parent().expect("the image's folder"));
}

#[test]
fn explain_takes_unbounded_depth_and_its_rays_stay_in_the_mirror_box() {
    let scene = trap("mirror-box.toml");
    for (x, y) in [(0, 0), (3, 3), (31, 0), (0, 23), (31, 23), (16, 12), (7, 19), (25, 5)] {
        let pixel = format!("{x},{y}");
        for depth in ["100", "-1"] {
            let args = ["explain", scene.to_str().unwrap(), "--pixel", &pixel, "--max-depth", depth];
            let output = glint_within(&args, Duration::from_secs(60));
            let text = String::from_utf8_lossy(&output.stdout);
            assert!(text.contains("reflection ray (depth 100"), "pixel {pixel}: the tree ended early");
            assert!(!text.contains("missed everything"), "pixel {pixel}, depth {depth}: a ray left the box");
        }
    }
}
