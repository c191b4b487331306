//! Progressive rendering loses nothing: a time limit ends the render between passes, Ctrl-C
//! (SIGINT) finishes the passes under way and writes the image, and a render resumed from a
//! checkpoint equals an uninterrupted one. Outputs record the sample count and seed.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

fn glint() -> Command {
    Command::new(env!("CARGO_BIN_EXE_glint"))
}

fn cornell_box() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box.toml").to_string_lossy().to_string()
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("glint-progressive-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn run(args: &[&str]) -> Output {
    let o = glint().args(args).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    o
}

fn exr_attribute(path: &Path, name: &str) -> Option<String> {
    let meta = exr::meta::MetaData::read_from_file(path, false).ok()?;
    // Unknown attributes come back as the layer's own (the crate files them there on reading).
    let header = &meta.headers[0];
    let key = exr::prelude::Text::from(name);
    let value = header.own_attributes.other.get(&key).or_else(|| header.shared_attributes.other.get(&key))?.clone();
    match value {
        exr::meta::attribute::AttributeValue::Text(t) => Some(t.to_string()),
        _ => None,
    }
}

#[test]
fn time_limit_ends_the_render_and_the_exr_records_spp_and_seed() {
    let dir = temp_dir("time");
    let out = dir.join("t.exr");
    let start = Instant::now();
    let o =
        run(&["render", &cornell_box(), "--width", "64", "--time", "0.5", "--seed", "42", "-o", out.to_str().unwrap()]);
    assert!(start.elapsed() < Duration::from_secs(20));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("(time limit)"), "{err}");
    let spp: u32 = exr_attribute(&out, "glint:spp").expect("spp in the EXR header").parse().unwrap();
    assert!(spp >= 1 && err.contains(&format!("at {spp} spp")), "{err}");
    assert_eq!(exr_attribute(&out, "glint:seed").as_deref(), Some("42"));
    std::fs::remove_dir_all(dir).unwrap();
}

/// A time limit shorter than one pass (10 µs; the scene's loading alone takes longer) still
/// renders one pass and writes its image, rather than stopping "before its first pass".
#[test]
fn a_time_limit_shorter_than_a_pass_renders_one_pass() {
    let dir = temp_dir("short-time");
    let out = dir.join("t.exr");
    let o = run(&["render", &cornell_box(), "--width", "16", "--time", "1e-5", "-o", out.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert_eq!(exr_attribute(&out, "glint:spp").as_deref(), Some("1"), "{err}");
    std::fs::remove_dir_all(dir).unwrap();
}

/// SIGINT (Ctrl-C), SIGTERM (a render farm's stop) and SIGHUP (a closed terminal) each finish
/// the passes under way, write the image and the checkpoint, and exit with status 3; the
/// checkpoint resumes to the image an uninterrupted render gives.
#[test]
fn a_signal_finishes_the_passes_under_way_and_keeps_everything() {
    let dir = temp_dir("signals");
    let path = |n: &str| dir.join(n).to_string_lossy().to_string();
    let scene = cornell_box();
    for signal in ["INT", "TERM", "HUP"] {
        let (out, checkpoint) = (path(&format!("{signal}.pfm")), path(&format!("{signal}.ckp")));
        let child = glint()
            .args(["render", &scene, "--width", "32", "--spp", "1000000", "-o", &out])
            .args(["--checkpoint", &checkpoint, "--checkpoint-interval", "0"])
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        // Wait until rendering is under way (the first pass wrote a checkpoint), then signal.
        let start = Instant::now();
        while !Path::new(&checkpoint).exists() {
            assert!(start.elapsed() < Duration::from_secs(30), "no pass finished");
            std::thread::sleep(Duration::from_millis(20));
        }
        let sent = Command::new("kill").args([&format!("-{signal}"), &child.id().to_string()]).status().unwrap();
        assert!(sent.success());
        let o = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(3), "SIG{signal}: {err}");
        assert!(err.contains("(interrupted)"), "{err}");
        let (w, h, pixels) = glint_cli::output::read_pfm(Path::new(&out)).unwrap();
        assert_eq!((w, h), (32, 32));
        assert!(pixels.iter().any(|p| p.x > 0.0), "the written image is black");
        // Resumed a few passes further, it equals the render that ran there uninterrupted.
        let bytes = std::fs::read(&checkpoint).unwrap();
        let spp_done = u32::from_le_bytes(bytes[16..20].try_into().unwrap());
        let target = (spp_done + 3).to_string();
        let resumed = path(&format!("{signal}-resumed.pfm"));
        let full = path(&format!("{signal}-full.pfm"));
        let common = ["render", scene.as_str(), "--width", "32", "--spp", target.as_str(), "-q", "-o"];
        run(&[&common[..], &[resumed.as_str(), "--resume", checkpoint.as_str()]].concat());
        run(&[&common[..], &[full.as_str()]].concat());
        assert_eq!(std::fs::read(&full).unwrap(), std::fs::read(&resumed).unwrap(), "SIG{signal}");
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn resume_from_a_checkpoint_equals_an_uninterrupted_render() {
    let dir = temp_dir("resume");
    let path = |n: &str| dir.join(n).to_string_lossy().to_string();
    let scene = cornell_box();
    run(&["render", &scene, "--width", "48", "--spp", "9", "-q", "-o", &path("full.pfm")]);
    run(&[
        "render",
        &scene,
        "--width",
        "48",
        "--spp",
        "4",
        "-q",
        "-o",
        &path("part.pfm"),
        "--checkpoint",
        &path("c.ckp"),
    ]);
    run(&[
        "render",
        &scene,
        "--width",
        "48",
        "--spp",
        "9",
        "-q",
        "-o",
        &path("resumed.pfm"),
        "--resume",
        &path("c.ckp"),
    ]);
    assert_eq!(std::fs::read(path("full.pfm")).unwrap(), std::fs::read(path("resumed.pfm")).unwrap());
    // A checkpoint of another render is refused with a clear message.
    let o = glint()
        .args([
            "render",
            &scene,
            "--width",
            "48",
            "--spp",
            "9",
            "--seed",
            "7",
            "-o",
            &path("x.pfm"),
            "--resume",
            &path("c.ckp"),
        ])
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("another scene or other settings"));
    // So is one made with the other light sampling: it would converge to the same image, but
    // not equal the uninterrupted render.
    let args = ["render", &scene, "--width", "48", "--spp", "9", "--light-sampling", "solid-angle", "-o"];
    let o = glint().args(args).args([&path("y.pfm"), "--resume", &path("c.ckp")]).output().unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("another scene or other settings"));
    // So is one of another integrator setting (the render's identity holds every setting
    // that changes the image), but not one that only changes the speed: the wavefront and the
    // one-path-at-a-time tracer make the same image, so either resumes the other.
    let args = ["render", &scene, "--width", "48", "--spp", "9", "--max-depth", "3", "-o"];
    let o = glint().args(args).args([&path("z.pfm"), "--resume", &path("c.ckp")]).output().unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("another scene or other settings"));
    let scalar = ["render", &scene, "--width", "48", "--spp", "9", "-q", "--no-wavefront", "-o"];
    run(&[&scalar[..], &[&path("scalar.pfm"), "--resume", &path("c.ckp")]].concat());
    assert_eq!(std::fs::read(path("full.pfm")).unwrap(), std::fs::read(path("scalar.pfm")).unwrap());
    std::fs::remove_dir_all(dir).unwrap();
}

/// `--moment` writes each pixel's second moment beside the image as the EXR layer `m2`, at
/// least the square of the pixel's mean (its sample variance is m2 − mean² ≥ 0), and the
/// image itself is the one a render without it gives; a particle integrator is refused, and a
/// PNG output says it holds the image alone.
#[test]
fn moment_writes_the_second_moment_as_an_exr_layer() {
    use exr::prelude::*;
    let dir = temp_dir("moment");
    let (with, without) = (dir.join("m.exr"), dir.join("plain.exr"));
    let common = ["render", &cornell_box(), "--width", "24", "--spp", "4", "--seed", "3", "--quiet"];
    run(&[&common[..], &["--moment", "-o", with.to_str().unwrap()]].concat());
    run(&[&common[..], &["-o", without.to_str().unwrap()]].concat());
    let read = |path: &Path| {
        read_all_flat_layers_from_file(path).unwrap().layer_data.into_iter().next().unwrap().channel_data.list
    };
    let channels = read(&with);
    let names: Vec<String> = channels.iter().map(|c| c.name.to_string()).collect();
    assert_eq!(names, ["B", "G", "R", "m2.B", "m2.G", "m2.R"]);
    let values = |name: &str| -> Vec<f32> {
        channels.iter().find(|c| c.name.to_string() == name).unwrap().sample_data.values_as_f32().collect()
    };
    let plain = read(&without);
    let plain_red: Vec<f32> =
        plain.iter().find(|c| c.name.to_string() == "R").unwrap().sample_data.values_as_f32().collect();
    assert_eq!(values("R"), plain_red, "the image does not change");
    let (red, m2) = (values("R"), values("m2.R"));
    assert!(red.iter().zip(&m2).all(|(r, m)| *m >= r * r * (1.0 - 1e-5)), "m2 ≥ mean²");
    assert!(red.iter().zip(&m2).any(|(r, m)| *m > 1.01 * r * r), "four samples of a path tracer differ somewhere");

    let o = glint()
        .args(common)
        .args(["--moment", "--integrator", "light", "-o", with.to_str().unwrap()])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("--moment") && err.contains("splats particles"), "{err}");
    let png = dir.join("m.png");
    let o = run(&[&common[..], &["--moment", "-o", png.to_str().unwrap()]].concat());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("written only into EXR"), "{err}");
    std::fs::remove_dir_all(dir).unwrap();
}
