//! Nothing lost, nothing trusted blindly: unwritable or odd outputs and checkpoints are refused
//! before the render (or fail with a clear message, never a false success), writes are whole
//! or not at all, crafted checkpoints are refused, and resource limits hold.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

mod common;
use common::{assert_clean_failure, glint, stderr, temp_dir, wait_within};

fn cornell_box() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box.toml").to_string_lossy().to_string()
}

fn files_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> =
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().to_string()).collect();
    names.sort();
    names
}

#[test]
fn an_unwritable_checkpoint_is_refused_before_rendering() {
    let dir = temp_dir("checkpoint-path");
    let out = dir.join("o.pfm");
    let scene = cornell_box();
    let missing = dir.join("nodir").join("ck");
    for (checkpoint, why) in [(missing.as_path(), "No such file"), (dir.as_path(), "is a directory")] {
        let start = Instant::now();
        let o = glint(&[
            "render",
            &scene,
            "--width",
            "32",
            "--spp",
            "100000",
            "--checkpoint",
            checkpoint.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]);
        let err = assert_clean_failure(&o);
        assert!(err.contains("checkpoint") && err.contains(why), "{err}");
        assert!(start.elapsed() < Duration::from_secs(10), "it rendered first");
    }
    assert!(files_in(&dir).is_empty(), "left behind: {:?}", files_in(&dir));
    std::fs::remove_dir_all(dir).unwrap();
}

#[cfg(unix)]
#[test]
fn a_full_disk_is_an_error_and_a_fifo_is_refused_without_waiting() {
    let dir = temp_dir("devices");
    let full = dir.join("full.png");
    std::os::unix::fs::symlink("/dev/full", &full).unwrap();
    let err = assert_clean_failure(&glint(&["render", "--spp", "1", "--width", "64", "-o", full.to_str().unwrap()]));
    assert!(err.contains("No space left"), "{err}");

    let fifo = dir.join("fifo.png");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let mut child = Command::new(env!("CARGO_BIN_EXE_glint"))
        .args(["render", "--spp", "1", "--width", "64", "-o", fifo.to_str().unwrap()])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    wait_within(&mut child, start, Duration::from_secs(20), "glint waited for a reader of the FIFO");
    let err = assert_clean_failure(&child.wait_with_output().unwrap());
    assert!(err.contains("not a regular file"), "{err}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[cfg(unix)]
#[test]
fn images_are_replaced_whole_through_links_and_leave_no_temporary_files() {
    let dir = temp_dir("atomic");
    let target = dir.join("target.png");
    std::fs::write(&target, b"the previous image").unwrap();
    let link = dir.join("link.png");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    let o = glint(&["render", "--spp", "1", "--width", "32", "-q", "-o", link.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink(), "the link was replaced");
    assert_eq!(&std::fs::read(&target).unwrap()[..4], b"\x89PNG");
    assert_eq!(files_in(&dir), ["link.png", "target.png"]);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn nan_settings_are_refused() {
    for (flag, value) in [("--exposure", "nan"), ("--checkpoint-interval", "nan"), ("--checkpoint-interval", "-1")] {
        let err = assert_clean_failure(&glint(&["render", "--spp", "1", "--width", "8", flag, value, "-o", "x.png"]));
        assert!(err.contains(flag), "{err}");
    }
}

/// `--time -1` reaches glint's own check (clap's hint before was to write `-- -1`, which
/// would make −1 a scene path).
#[test]
fn a_negative_time_limit_is_refused_by_name() {
    let err = assert_clean_failure(&glint(&["render", "--spp", "1", "--width", "8", "--time", "-1", "-o", "x.png"]));
    assert!(err.contains("--time must be a positive number of seconds, got -1"), "{err}");
}

/// A render whose every pixel is black says why: Whitted on the Cornell box (lit by an area
/// light, which the course's local model does not read), and a scene with no light at all.
#[test]
fn a_black_image_says_why() {
    let dir = std::env::temp_dir().join(format!("glint-black-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("black.png");
    let o = glint(&["render", &cornell_box(), "--integrator", "whitted", "--width", "16", "-o", out.to_str().unwrap()]);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("the image is black in every pixel") && err.contains("--integrator path"), "{err}");
    let unlit = dir.join("unlit.toml");
    std::fs::write(
        &unlit,
        "[camera]\nposition = [0, 0, -5]\nlook_at = [0, 0, 0]\nresolution = [16, 16]\n[render]\nintegrator = \"path\"\nspp = 2\n[materials.grey]\ntype = \"diffuse\"\n[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"grey\"\n",
    )
    .unwrap();
    let o = glint(&["render", unlit.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("black in every pixel: the scene has no light"), "{err}");
    // A lit render says nothing of the kind.
    let o = glint(&["render", &cornell_box(), "--width", "16", "--spp", "4", "-o", out.to_str().unwrap()]);
    assert!(!stderr(&o).contains("black in every pixel"), "{}", stderr(&o));
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn renders_beyond_the_memory_limit_are_refused_with_the_way_to_raise_it() {
    let scene = cornell_box();
    let big = glint(&["render", &scene, "--width", "32768", "--height", "32768", "-o", "big.pfm"]);
    let err = assert_clean_failure(&big);
    assert!(err.contains("memory limit") && err.contains("--memory-limit"), "{err}");
    let photons = glint(&["render", &scene, "--width", "8", "--integrator", "photon", "--photons", "4294967295"]);
    assert!(assert_clean_failure(&photons).contains("memory limit"));
    // The limit is the one set: lowered far enough, even a small render is refused.
    let small = glint(&["render", &scene, "--width", "8", "--spp", "1", "--memory-limit", "0.000001", "-o", "s.pfm"]);
    assert!(assert_clean_failure(&small).contains("memory limit"));
}

#[test]
fn a_mesh_that_inflates_past_the_limit_is_refused() {
    let dir = temp_dir("inflate");
    // 64 MiB of zeros gzip to about 64 KiB.
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
    std::io::Write::write_all(&mut encoder, &vec![b' '; 64 << 20]).unwrap();
    std::fs::write(dir.join("bomb.obj.gz"), encoder.finish().unwrap()).unwrap();
    let scene = dir.join("s.toml");
    std::fs::write(
        &scene,
        "[camera]\nposition = [0, 0, -5]\nlook_at = [0, 0, 0]\n\n[materials.m]\ntype = \"phong\"\n\n[[shapes]]\ntype = \"mesh\"\nfile = \"bomb.obj.gz\"\nmaterial = \"m\"\n",
    )
    .unwrap();
    let o = glint(&["render", scene.to_str().unwrap(), "--memory-limit", "0.01", "-o", "x.pfm"]);
    let err = assert_clean_failure(&o);
    assert!(err.contains("inflates to more than") && err.contains("bomb.obj.gz"), "{err}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn ctrl_c_while_the_photon_maps_are_built_stops_soon() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_glint"))
        .args(["render", &cornell_box(), "--width", "16", "--integrator", "photon", "--photons", "200000000"])
        .args(["--memory-limit", "64", "-o", "never.pfm"])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(1500));
    let start = Instant::now();
    assert!(Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap().success());
    wait_within(&mut child, start, Duration::from_secs(10), "Ctrl-C went unnoticed while the photon maps were built");
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(stderr(&o).contains("nothing written"), "{}", stderr(&o));
    assert!(!Path::new("never.pfm").exists());
}

#[test]
fn the_exit_statuses_are_in_the_help() {
    let help = String::from_utf8_lossy(&glint(&["render", "--help"]).stdout).to_string();
    assert!(help.contains("3 when interrupted by Ctrl-C, SIGTERM or SIGHUP"), "{help}");
}

/// FNV-1a as checkpoints use it: over the bytes, then a 0xFF.
fn checksum(bytes: &[u8]) -> u64 {
    let mut hash = 0xcbf2_9ce4_8422_2325u64;
    for &b in bytes.iter().chain(&[0xFF]) {
        hash ^= b as u64;
        hash = hash.wrapping_mul(0x0100_0000_01b3);
    }
    hash
}

/// A checkpoint's bytes changed by `edit`, its checksum made right again, so that the test
/// reaches the field checks behind it.
fn crafted(valid: &[u8], edit: impl Fn(&mut Vec<u8>)) -> Vec<u8> {
    let mut bytes = valid[..valid.len() - 8].to_vec();
    edit(&mut bytes);
    let sum = checksum(&bytes);
    bytes.extend_from_slice(&sum.to_le_bytes());
    bytes
}

#[test]
fn crafted_and_damaged_checkpoints_are_refused() {
    let dir = temp_dir("crafted");
    let path = |n: &str| dir.join(n).to_string_lossy().to_string();
    let scene = cornell_box();
    let render = ["render", scene.as_str(), "--width", "32", "--spp", "8", "-q", "-o"];
    let o = glint(&[&render[..], &[path("a.pfm").as_str(), "--checkpoint", path("c.ckp").as_str()]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let valid = std::fs::read(path("c.ckp")).unwrap();
    let put_u32 = |at: usize, v: u32| move |b: &mut Vec<u8>| b[at..at + 4].copy_from_slice(&v.to_le_bytes());
    let first_sum = 36;
    let first_weight = 36 + 32 * 32 * 12;
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "huge",
            {
                let mut b = valid[..44].to_vec();
                b[8..16].copy_from_slice(&[0, 0, 0, 64, 0, 0, 0, 64]); // 2^30 x 2^30
                b
            },
            "render",
        ),
        (
            "swapped",
            crafted(&valid, |b| {
                put_u32(8, 16)(b);
                put_u32(12, 64)(b);
            }),
            "16x64",
        ),
        ("nan", crafted(&valid, put_u32(first_sum, f32::NAN.to_bits())), "sum"),
        ("negative", crafted(&valid, put_u32(first_sum, (-6e28f32).to_bits())), "sum"),
        ("zero weight", crafted(&valid, put_u32(first_weight, 0)), "weight"),
        ("no passes", crafted(&valid, put_u32(16, 0)), "holds 0 samples"),
        ("too many passes", crafted(&valid, put_u32(16, u32::MAX)), "holds 4294967295"),
        ("double", crafted(&valid, put_u32(16, 16)), "holds 16 samples"),
        (
            "flipped bit",
            {
                let mut b = valid.clone();
                b[first_sum + 5] ^= 1;
                b
            },
            "checksum",
        ),
        ("cut short", valid[..valid.len() - 100].to_vec(), "cut short"),
    ];
    for (name, bytes, expected) in cases {
        let file = path(&format!("{name}.ckp"));
        std::fs::write(&file, &bytes).unwrap();
        let o = glint(&[&render[..], &[path("r.pfm").as_str(), "--resume", file.as_str()]].concat());
        let err = assert_clean_failure(&o);
        assert!(err.contains(expected), "{name}: {err}");
    }
    // The same checkpoint resumes as made.
    let o = glint(&[&render[..], &[path("r.pfm").as_str(), "--resume", path("c.ckp").as_str()]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_changed_mesh_behind_the_same_scene_refuses_to_resume() {
    let dir = temp_dir("mesh-changed");
    let path = |n: &str| dir.join(n).to_string_lossy().to_string();
    let triangle = |z: f32| format!("v -1 -1 {z}\nv 1 -1 {z}\nv 0 1 {z}\nf 1 2 3\n");
    std::fs::write(path("m.obj"), triangle(0.0)).unwrap();
    std::fs::write(
        path("s.toml"),
        "[camera]\nposition = [0, 0, -5]\nlook_at = [0, 0, 0]\nresolution = [8, 8]\n\n[materials.m]\ntype = \"phong\"\n\n[[shapes]]\ntype = \"mesh\"\nfile = \"m.obj\"\nmaterial = \"m\"\n",
    )
    .unwrap();
    let scene = path("s.toml");
    let render = |spp: &str, out: &str, extra: &[&str]| {
        let out = path(out);
        glint(&[&["render", scene.as_str(), "--spp", spp, "-q", "-o", out.as_str()][..], extra].concat())
    };
    let checkpoint = path("c.ckp");
    assert!(render("2", "a.pfm", &["--checkpoint", &checkpoint]).status.success());
    std::fs::write(path("m.obj"), triangle(0.5)).unwrap();
    let err = assert_clean_failure(&render("4", "b.pfm", &["--resume", &checkpoint]));
    assert!(err.contains("another scene or other settings"), "{err}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn bench_rays_refuses_empty_ray_files_and_zero_counts() {
    let dir = temp_dir("bench-rays");
    let mesh = dir.join("t.obj");
    std::fs::write(&mesh, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let empty = dir.join("empty.rays");
    std::fs::write(&empty, b"").unwrap();
    let (mesh, empty) = (mesh.to_str().unwrap(), empty.to_str().unwrap());
    let err = assert_clean_failure(&glint(&["bench-rays", mesh, empty]));
    assert!(err.contains("holds no rays"), "{err}");
    // A ray file with one ray, and counts of zero: usage errors naming the flag.
    let one = dir.join("one.rays");
    let ray: Vec<u8> =
        [0.2f32, 0.2, -1.0, 0.0, 0.0, 1.0, 0.0, f32::INFINITY].iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(&one, ray).unwrap();
    for flag in ["--repeat", "--threads"] {
        let o = glint(&["bench-rays", mesh, one.to_str().unwrap(), flag, "0"]);
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        assert!(stderr(&o).contains(flag), "{}", stderr(&o));
    }
    let o = glint(&["bench-rays", mesh, one.to_str().unwrap(), "--repeat", "1"]);
    assert!(o.status.success() && !String::from_utf8_lossy(&o.stdout).contains("NaN"), "{}", stderr(&o));
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_scene_file_too_large_to_read_within_the_limit_is_refused() {
    let dir = temp_dir("big-toml");
    let scene = dir.join("lights.toml");
    let mut text = String::from("[camera]\nposition = [0, 0, -5]\nlook_at = [0, 0, 0]\n\n");
    for i in 0..20_000 {
        text += &format!("[[lights]]\ntype = \"point\"\nposition = [{i}, 4.5, -3.25]\nintensity = 0.002\n\n");
    }
    std::fs::write(&scene, &text).unwrap();
    let o = glint(&["render", scene.to_str().unwrap(), "--memory-limit", "0.01", "-o", "x.pfm"]);
    let err = assert_clean_failure(&o);
    assert!(err.contains("memory limit") && err.contains("as JSON"), "{err}");
    std::fs::remove_dir_all(dir).unwrap();
}

/// A glTF model without punctual lights is lit by the default environment, and says so;
/// `--no-default-light` leaves it out, and the black image then says the scene has no light.
#[test]
fn no_default_light_leaves_a_gltf_model_unlit_and_says_why_it_is_black() {
    let dir = std::env::temp_dir().join(format!("glint-default-light-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("spheres.png");
    let spheres = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/gltf/spheres.glb");
    let render = |extra: &[&str]| {
        let mut args = vec!["render", spheres, "--spp", "1", "--width", "16", "-o", out.to_str().unwrap()];
        args.extend_from_slice(extra);
        let o = glint(&args);
        let err = stderr(&o);
        assert!(o.status.success(), "{err}");
        err
    };
    let lit = render(&[]);
    assert!(lit.contains("lit by the default environment") && !lit.contains("black in every pixel"), "{lit}");
    let unlit = render(&["--no-default-light"]);
    assert!(!unlit.contains("default environment"), "{unlit}");
    assert!(unlit.contains("the image is black in every pixel") && unlit.contains("the scene has no light"), "{unlit}");
    std::fs::remove_dir_all(dir).unwrap();
}
