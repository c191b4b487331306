//! The `glint` binary end to end: renders, errors, determinism, algorithm flags.

use std::path::Path;

use glint_cli::output::read_pfm;

mod common;
use common::{assert_clean_failure, glint, stderr, temp_dir};

const LAMBERT: &str = r#"
[camera]
position = [0, 0, -5]
look_at = [0, 0, 0]
fov = 45
resolution = [15, 15]

[environment]
background = [0, 0, 1]
ambient = [0.5, 0.5, 0.5]

[materials.m]
type = "phong"
diffuse = [0.5, 0.25, 0.8]
ambient = [0.1, 0.2, 0.3]

[[lights]]
type = "directional"
direction = [1, 0, 2]
intensity = 2

[[shapes]]
type = "sphere"
radius = 1
material = "m"
"#;

#[test]
fn renders_a_scene_file_to_pfm_with_the_analytic_pixel_value() {
    let dir = temp_dir("lambert");
    let scene = dir.join("lambert.toml");
    std::fs::write(&scene, LAMBERT).unwrap();
    let out = dir.join("out.pfm");
    let o = glint(&["render", scene.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("M rays/s"), "summary line missing: {}", stderr(&o));
    let (w, h, pixels) = read_pfm(&out).unwrap();
    assert_eq!((w, h), (15, 15));
    // k_a·I_a + k_d·I·(N·L) with N = (0,0,−1), L = −(1,0,2)/√5.
    let cos = 2.0 / 5f32.sqrt();
    let expected = [0.05 + 0.5 * 2.0 * cos, 0.1 + 0.25 * 2.0 * cos, 0.15 + 0.8 * 2.0 * cos];
    let centre = pixels[7 * 15 + 7].to_array();
    for c in 0..3 {
        assert!((centre[c] - expected[c]).abs() < 1e-5, "{centre:?} vs {expected:?}");
    }
    assert_eq!(pixels[0].to_array(), [0.0, 0.0, 1.0]);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn default_scene_renders_to_exr_and_png() {
    let dir = temp_dir("default");
    for name in ["d.exr", "d.png"] {
        let out = dir.join(name);
        let o = glint(&["render", "--width", "64", "--spp", "1", "-q", "-o", out.to_str().unwrap()]);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(stderr(&o).is_empty(), "--quiet printed: {}", stderr(&o));
        let bytes = std::fs::read(&out).unwrap();
        let magic: &[u8] = if name.ends_with("exr") { &[0x76, 0x2f, 0x31, 0x01] } else { b"\x89PNG" };
        assert_eq!(&bytes[..4], magic);
    }
    std::fs::remove_dir_all(dir).unwrap();
}

fn render_default(dir: &Path, name: &str, extra: &[&str]) -> Vec<[f32; 3]> {
    let out = dir.join(name);
    let mut args = vec!["render", "--width", "96", "--spp", "2", "-q", "-o", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    let o = glint(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    read_pfm(&out).unwrap().2.iter().map(|p| p.to_array()).collect()
}

#[test]
fn same_seed_gives_the_same_image_at_any_thread_count() {
    let dir = temp_dir("threads");
    let one = render_default(&dir, "t1.pfm", &["--threads", "1", "--seed", "3"]);
    let two = render_default(&dir, "t2.pfm", &["--threads", "2", "--seed", "3"]);
    assert_eq!(one, two);
    std::fs::remove_dir_all(dir).unwrap();
}

/// The course's alternative algorithms render the same picture. Their hit distances differ in
/// the last bits, which moves shading by far less than 1e-3; only where a ray grazes an edge
/// may the outcome differ, so nearly every pixel agrees to 1e-3.
#[test]
fn alternative_intersection_algorithms_render_the_same_image() {
    let dir = temp_dir("methods");
    let reference = render_default(&dir, "a.pfm", &[]);
    let alternative = render_default(
        &dir,
        "b.pfm",
        &[
            "--sphere-method",
            "geometric",
            "--triangle-method",
            "cramer",
            "--polygon-test",
            "winding",
            "--box-method",
            "woo",
        ],
    );
    let differing = reference
        .iter()
        .zip(&alternative)
        .filter(|(a, b)| a.iter().zip(b.iter()).any(|(x, y)| (x - y).abs() > 1e-3))
        .count();
    assert!(differing * 200 < reference.len(), "{differing} of {} pixels differ", reference.len());
    // Each option reaches the intersection code: alone, it changes some pixel's last bits. The
    // Cornell box has triangles alone, whose leaf blocks once kept the watertight test whatever
    // the option said (the built-in scene's spheres took another path, so the test above passed).
    let cornell = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/cornell-box.toml");
    let cornell_with = |name: &str, extra: &[&str]| render_default(&dir, name, &[&[cornell], extra].concat());
    let watertight = cornell_with("w.pfm", &[]);
    for method in ["cramer", "moller-trumbore"] {
        assert_ne!(cornell_with("m.pfm", &["--triangle-method", method]), watertight, "{method} changed nothing");
    }
    let sphere = render_default(&dir, "s.pfm", &["--sphere-method", "geometric"]);
    assert_ne!(sphere, reference, "--sphere-method changed nothing");
    std::fs::remove_dir_all(dir).unwrap();
}

/// `--light-sampling solid-angle` reaches the light sampler: the same scene and seed give a
/// different image (other light samples) of the same brightness.
#[test]
fn solid_angle_light_sampling_changes_the_samples_not_the_image() {
    let dir = temp_dir("light-sampling");
    let cornell = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/cornell-box.toml");
    let render = |name: &str, strategy: &str| {
        let out = dir.join(name);
        let args = ["render", cornell, "--width", "32", "--spp", "64", "--light-sampling", strategy, "-q", "-o"];
        let o = glint(&[&args[..], &[out.to_str().unwrap()]].concat());
        assert!(o.status.success(), "{}", stderr(&o));
        read_pfm(&out).unwrap().2
    };
    let (area, solid_angle) = (render("a.pfm", "area"), render("s.pfm", "solid-angle"));
    assert_ne!(area, solid_angle);
    let mean = |img: &[glint_core::Rgb]| img.iter().map(|p| p.element_sum() as f64).sum::<f64>() / img.len() as f64;
    let (a, s) = (mean(&area), mean(&solid_angle));
    assert!((a / s - 1.0).abs() < 0.03, "{a} vs {s}");
    std::fs::remove_dir_all(dir).unwrap();
}

/// The path tracer's wavefront (eight paths at a time in SIMD lanes) and `--no-wavefront` (one
/// at a time) write the same image, at any thread count, and the summary says which ran: on
/// the Cornell box, and on its mixed-material and glass versions, whose mirror and glass
/// bounces the wavefront leaves to the scalar code (the glass box's own integrator is SPPM).
#[test]
fn the_wavefront_and_one_path_at_a_time_write_the_same_image() {
    let dir = temp_dir("wavefront");
    for scene in ["cornell-box", "cornell-box-mixed", "cornell-box-glass"] {
        let file = format!("{}/../../scenes/{scene}.toml", env!("CARGO_MANIFEST_DIR"));
        let render = |name: &str, extra: &[&str]| {
            let out = dir.join(format!("{scene}-{name}"));
            let out = out.to_str().unwrap();
            let args =
                ["render", &file, "--integrator", "path", "--width", "48", "--spp", "6", "--seed", "3", "-o", out];
            let o = glint(&[&args[..], extra].concat());
            assert!(o.status.success(), "{}", stderr(&o));
            (std::fs::read(out).unwrap(), stderr(&o))
        };
        let ((lanes, said), (one, said_one)) = (render("w.pfm", &[]), render("o.pfm", &["--no-wavefront"]));
        assert!(said.contains("with path (wavefront, 8 lanes)"), "{scene}: {said}");
        assert!(said_one.contains("with path in"), "{scene}: {said_one}");
        assert_eq!(lanes, one, "{scene}: the two image files differ");
        // Any thread count: each tile's paths are their own wavefront.
        let (three, _) = render("t.pfm", &["--threads", "3"]);
        assert_eq!(lanes, three, "{scene}: the image depends on the thread count");
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn bad_scene_names_file_and_line() {
    let dir = temp_dir("bad");
    let scene = dir.join("bad.toml");
    std::fs::write(&scene, LAMBERT.replace("radius = 1", "radius = -1")).unwrap();
    let err =
        assert_clean_failure(&glint(&["render", scene.to_str().unwrap(), "-o", dir.join("x.png").to_str().unwrap()]));
    assert!(err.contains("bad.toml:24:") && err.contains("radius"), "{err}");
    assert!(!dir.join("x.png").exists(), "a failed render must not leave an output file");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn unwritable_output_fails_before_rendering() {
    let err = assert_clean_failure(&glint(&["render", "-o", "/nonexistent-dir/x.png"]));
    assert!(err.contains("/nonexistent-dir/x.png"), "{err}");
    let err = assert_clean_failure(&glint(&["render", "-o", "out.jpeg"]));
    assert!(err.contains(".png, .exr, .hdr or .pfm"), "{err}");
}

#[test]
fn missing_scene_file_is_reported() {
    let dir = temp_dir("missing");
    let err =
        assert_clean_failure(&glint(&["render", "no-such-scene.toml", "-o", dir.join("x.png").to_str().unwrap()]));
    assert!(err.contains("no-such-scene.toml"), "{err}");
    std::fs::remove_dir_all(dir).unwrap();
}

/// `glint explain` traces the same ray the renderer traces through a pixel's centre at 1 spp:
/// its final colour is the rendered pixel's.
#[test]
fn explain_prints_the_rendered_pixel_colour() {
    let dir = temp_dir("explain");
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    // Sky, checkerboard, the glass sphere and the mirror sphere; on the CSG scene the hollow
    // glass block, the die and the lens.
    for (file, pixels) in [
        ("whitted-1980.toml", [(10, 5), (80, 110), (62, 62), (100, 55)]),
        ("csg.toml", [(40, 48), (78, 50), (125, 48), (80, 90)]),
    ] {
        let scene = scenes.join(file);
        let out = dir.join("w.pfm");
        let o = glint(&[
            "render",
            scene.to_str().unwrap(),
            "--spp",
            "1",
            "--width",
            "160",
            "-q",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let (w, _, pixels_rendered) = read_pfm(&out).unwrap();
        for (x, y) in pixels {
            let o = glint(&["explain", scene.to_str().unwrap(), "--width", "160", "--pixel", &format!("{x},{y}")]);
            assert!(o.status.success(), "{}", stderr(&o));
            let text = String::from_utf8_lossy(&o.stdout).to_string();
            assert!(text.contains("camera ray (depth 0"), "{text}");
            let last = text.lines().last().unwrap();
            let numbers: Vec<f32> = last
                .trim_start_matches("pixel colour = (")
                .trim_end_matches(')')
                .split(", ")
                .map(|n| n.parse().unwrap())
                .collect();
            let rendered = pixels_rendered[(y * w + x) as usize].to_array();
            for c in 0..3 {
                assert!(
                    (numbers[c] - rendered[c]).abs() < 1e-6,
                    "{file}, pixel {x},{y}: explain {numbers:?} vs render {rendered:?}"
                );
            }
        }
        // The glass pieces' pixels show refraction rays in their trees.
        let o = glint(&[
            "explain",
            scene.to_str().unwrap(),
            "--width",
            "160",
            "--pixel",
            &format!("{},{}", pixels[2].0, pixels[2].1),
        ]);
        let text = String::from_utf8_lossy(&o.stdout).to_string();
        assert!(text.contains("refraction ray"), "{file}: {text}");
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// A colour as `explain` prints it, "(r, g, b)".
fn triple(text: &str) -> [f32; 3] {
    let inner = text.trim().trim_start_matches('(').trim_end_matches(')');
    let v: Vec<f32> = inner.split(", ").map(|n| n.parse().unwrap()).collect();
    [v[0], v[1], v[2]]
}

/// `glint explain --integrator path` (and `path-naive`, `photon`) follows the path the renderer
/// follows through a pixel's centre at 1 spp: what its lines add sums to its last line, the rendered pixel's value,
/// bit for bit; somewhere the path bounces more than once and meets roulette or a light.
#[test]
fn explain_of_a_path_adds_up_to_the_rendered_pixel() {
    let dir = temp_dir("explain-path");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box.toml");
    let mut vertices = 0;
    // Photon mapping shoots its maps for each command: two pixels of it.
    let photon = [((24, 30), "photon"), ((12, 40), "photon")];
    let pixels_and_kinds = [(24, 30), (10, 20), (40, 40), (24, 2), (30, 44)]
        .into_iter()
        .flat_map(|p| [(p, "path"), (p, "path-naive")])
        .chain(photon);
    for ((x, y), kind) in pixels_and_kinds {
        let out = dir.join(format!("{kind}.pfm"));
        let (scene, out) = (scene.to_str().unwrap(), out.to_str().unwrap());
        let o = glint(&["render", scene, "--spp", "1", "--width", "48", "--integrator", kind, "-q", "-o", out]);
        assert!(o.status.success(), "{}", stderr(&o));
        let (w, _, pixels) = read_pfm(Path::new(out)).unwrap();
        let pixel = format!("{x},{y}");
        let o = glint(&["explain", scene, "--width", "48", "--pixel", &pixel, "--integrator", kind]);
        assert!(o.status.success(), "{}", stderr(&o));
        let text = String::from_utf8_lossy(&o.stdout).to_string();
        vertices += text.lines().filter(|l| l.starts_with("vertex ")).count();
        let mut sum = [0.0f32; 3];
        for line in text.lines().filter(|l| l.contains("→ adds")) {
            let added = triple(line.rsplit("→ adds").next().unwrap());
            for c in 0..3 {
                sum[c] += added[c];
            }
        }
        let total = triple(text.lines().last().unwrap().rsplit('=').next().unwrap());
        let rendered = pixels[(y * w + x) as usize].to_array();
        assert_eq!(total.map(f32::to_bits), rendered.map(f32::to_bits), "{kind}, pixel {x},{y}: {text}");
        for c in 0..3 {
            assert!(
                (sum[c] - total[c]).abs() <= 1e-6 * total[c].max(1.0),
                "pixel {x},{y}: lines add to {sum:?}: {text}"
            );
        }
    }
    assert!(vertices > 10, "the paths bounce: {vertices} vertices in ten paths");
    // The same path as JSON: its value and its events' additions agree with the text's.
    let (scene, pixel) = (scene.to_str().unwrap(), "32,10");
    let text = glint(&["explain", scene, "--width", "48", "--pixel", pixel, "--integrator", "path"]);
    let json = glint(&["explain", scene, "--width", "48", "--pixel", pixel, "--integrator", "path", "--json"]);
    assert!(json.status.success(), "{}", stderr(&json));
    let document: serde_json::Value = serde_json::from_slice(&json.stdout).expect("JSON");
    let value: Vec<f32> = document["value"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap() as f32).collect();
    let text = String::from_utf8_lossy(&text.stdout).to_string();
    assert_eq!(value, triple(text.lines().last().unwrap().rsplit('=').next().unwrap()).to_vec());
    let events = document["events"].as_array().unwrap();
    let vertices = events.iter().filter(|e| e["event"] == "vertex").count();
    assert_eq!(vertices, text.lines().filter(|l| l.starts_with("vertex ")).count());
    assert!(events.last().is_some_and(|e| e["event"] == "end"));
    // As a PLY line set: the camera, each vertex, each light sample's point and the escape,
    // joined in order.
    let ply = dir.join("path.ply");
    let o = glint(&[
        "explain",
        scene,
        "--width",
        "48",
        "--pixel",
        pixel,
        "--integrator",
        "path",
        "--ply",
        ply.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let ply = std::fs::read_to_string(&ply).unwrap();
    let count = |element: &str| -> usize {
        let line = ply.lines().find(|l| l.starts_with(&format!("element {element} "))).unwrap();
        line.rsplit(' ').next().unwrap().parse().unwrap()
    };
    let drawn =
        events.iter().filter(|e| ["vertex", "light_sample", "escape"].contains(&e["event"].as_str().unwrap())).count();
    assert_eq!((count("vertex"), count("edge")), (drawn + 1, drawn));
    let body: Vec<&str> = ply.lines().skip_while(|l| *l != "end_header").skip(1).collect();
    let camera: Vec<f64> = body[0].split(' ').map(|v| v.parse().unwrap()).collect();
    let origin: Vec<f64> =
        document["camera_ray"]["origin"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    assert_eq!(camera, origin);
    let e = assert_clean_failure(&glint(&["explain", scene, "--pixel", pixel, "--json"]));
    assert!(e.contains("--integrator path"), "{e}");
    std::fs::remove_dir_all(dir).unwrap();
}

/// `glint explain` for every Monte Carlo integrator on a second scene (glass on a floor), for
/// light tracing and SPPM on the Cornell box too, and for volume path tracing on two fog
/// scenes and volumetric photon mapping on one (their paths scatter in the media): the last line is the pixel `render --spp
/// 1` computes, bit for bit, and the lines that add sum to it: light tracing's splats into the
/// pixel; SPPM's light samples to its direct light, which the gather's estimate completes.
#[test]
fn explain_of_every_integrator_adds_up_on_two_scenes() {
    let dir = temp_dir("explain-all");
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let sum_after = |text: &str, marker: &str| {
        let mut sum = [0.0f32; 3];
        for line in text.lines().filter(|l| l.contains(marker)) {
            let added = triple(line.rsplit(marker).next().unwrap());
            (0..3).for_each(|c| sum[c] += added[c]);
        }
        sum
    };
    let runs = [
        ("caustic-glass.toml", "path", [(24, 30), (20, 12)]),
        ("caustic-glass.toml", "path-naive", [(24, 30), (20, 12)]),
        ("caustic-glass.toml", "photon", [(24, 30), (24, 33)]),
        ("caustic-glass.toml", "light", [(24, 30), (22, 36)]),
        ("caustic-glass.toml", "sppm", [(24, 30), (22, 36)]),
        ("cornell-box.toml", "light", [(24, 30), (30, 44)]),
        ("cornell-box.toml", "sppm", [(24, 30), (10, 20)]),
        ("fog-box.toml", "volpath", [(30, 30), (24, 20)]),
        ("fog.toml", "volpath", [(24, 15), (10, 20)]),
        ("fog-box.toml", "volphoton", [(30, 30), (20, 26)]),
    ];
    let (mut particles, mut gathered, mut in_media, mut photon_estimates) = (0, 0, 0, 0);
    for (file, kind, pixels) in runs {
        let scene = scenes.join(file);
        let out = dir.join(format!("{kind}.pfm"));
        let (scene, out) = (scene.to_str().unwrap(), out.to_str().unwrap());
        let o = glint(&["render", scene, "--spp", "1", "--width", "48", "--integrator", kind, "-q", "-o", out]);
        assert!(o.status.success(), "{}", stderr(&o));
        let (w, _, image) = read_pfm(Path::new(out)).unwrap();
        // Light tracing: also the brightest pixel, where particles surely land.
        let brightest = (0..image.len()).max_by(|&a, &b| image[a].x.total_cmp(&image[b].x)).unwrap() as u32;
        let pixels = if kind == "light" { vec![pixels[0], (brightest % w, brightest / w)] } else { pixels.to_vec() };
        for (x, y) in pixels {
            let pixel = format!("{x},{y}");
            let o = glint(&["explain", scene, "--width", "48", "--pixel", &pixel, "--integrator", kind]);
            assert!(o.status.success(), "{}", stderr(&o));
            let text = String::from_utf8_lossy(&o.stdout).to_string();
            let total = triple(text.lines().last().unwrap().rsplit('=').next().unwrap());
            let rendered = image[(y * w + x) as usize].to_array();
            let what = format!("{file}, {kind}, pixel {x},{y}");
            assert_eq!(total.map(f32::to_bits), rendered.map(f32::to_bits), "{what}: {text}");
            let close = |a: [f32; 3], b: [f32; 3]| (0..3).all(|c| (a[c] - b[c]).abs() <= 1e-6 * b[c].max(1.0));
            match kind {
                "light" => {
                    let mut sum = sum_after(&text, "camera ray: splat");
                    for line in text.lines().filter(|l| l.ends_with("into this pixel")) {
                        let splat = line.rsplit("splat ").next().unwrap().trim_end_matches(" into this pixel");
                        let splat = triple(splat);
                        (0..3).for_each(|c| sum[c] += splat[c]);
                    }
                    assert!(close(sum, total), "{what}: the splats add to {sum:?}: {text}");
                    particles += text.lines().filter(|l| l.starts_with("particle ")).count();
                }
                "sppm" => {
                    let direct = triple(
                        text.lines().find(|l| l.starts_with("direct light")).unwrap().rsplit('=').next().unwrap(),
                    );
                    assert!(close(sum_after(&text, "→ adds"), direct), "{what}: {text}");
                    gathered += text.lines().filter(|l| l.starts_with("visible point")).count();
                }
                // The volume path tracers add each line's value to the pixel in the order
                // printed: the sum is the pixel, bit for bit.
                "volpath" | "volphoton" => {
                    let sum = sum_after(&text, "→ adds");
                    assert_eq!(sum.map(f32::to_bits), total.map(f32::to_bits), "{what}: {text}");
                }
                _ => assert!(close(sum_after(&text, "→ adds"), total), "{what}: {text}"),
            }
            in_media += text.lines().filter(|l| l.contains(": scattered in medium ")).count();
            photon_estimates += text.lines().filter(|l| l.contains("the medium's photons here")).count();
        }
    }
    assert!(particles >= 3 && gathered >= 4, "{particles} particles, {gathered} gathers shown");
    assert!(
        in_media >= 3 && photon_estimates >= 1,
        "{in_media} scatterings in media, {photon_estimates} photon estimates"
    );
    // As JSON and as a PLY line set.
    let scene = scenes.join("cornell-box.toml");
    let scene = scene.to_str().unwrap();
    for kind in ["light", "sppm"] {
        let args = ["explain", scene, "--width", "48", "--pixel", "24,30", "--integrator", kind];
        let text = String::from_utf8_lossy(&glint(&args).stdout).to_string();
        let ply = dir.join(format!("{kind}.ply"));
        let json = glint(&[&args[..], &["--json", "--ply", ply.to_str().unwrap()]].concat());
        assert!(json.status.success(), "{}", stderr(&json));
        let document: serde_json::Value = serde_json::from_slice(&json.stdout).expect("JSON");
        let value: Vec<f32> =
            document["value"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap() as f32).collect();
        assert_eq!(value, triple(text.lines().last().unwrap().rsplit('=').next().unwrap()).to_vec(), "{kind}");
        let ply = std::fs::read_to_string(&ply).unwrap();
        assert!(ply.starts_with("ply\n") && ply.contains("element edge "), "{kind}: {ply}");
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// `glint explain --photons K` lists the photons around a pixel's hit point: in the caustic
/// under the glass ball the caustic map is dense and its estimate bright; on the far wall
/// there is no caustic at all.
#[test]
fn explain_lists_the_photons_around_a_hit() {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/caustic-point-light.toml");
    let caustic_estimate = |pixel: &str| {
        let o = glint(&["explain", scene.to_str().unwrap(), "--pixel", pixel, "--photons", "3"]);
        assert!(o.status.success(), "{}", stderr(&o));
        let text = String::from_utf8_lossy(&o.stdout).to_string();
        let caustic = text.split("caustic map:").nth(1).expect("the caustic map is listed").to_string();
        let distances: Vec<f32> = caustic
            .lines()
            .filter_map(|l| l.trim().strip_prefix("at distance ")?.split(':').next()?.parse().ok())
            .collect();
        assert!(distances.windows(2).all(|w| w[0] <= w[1]), "{caustic}");
        let estimate = caustic.lines().find(|l| l.contains("radiance estimate")).unwrap().to_string();
        let value: f32 = estimate.split(": (").nth(1).unwrap().split(',').next().unwrap().parse().unwrap();
        (distances.len(), value)
    };
    let (found, in_spot) = caustic_estimate("100,168");
    assert_eq!(found, 3);
    assert!(in_spot > 0.3, "{in_spot}");
    let (_, on_wall) = caustic_estimate("128,40");
    assert!(on_wall < 0.01 * in_spot, "{on_wall} vs {in_spot}");
}

/// The integrators that start at the lights refuse what they cannot honour, with a message;
/// SPPM resumes from a checkpoint exactly; all of them honour --time.
#[test]
fn particle_integrators_refuse_unphysical_lights_and_sppm_resumes() {
    let dir = temp_dir("particles");
    let whitted = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/whitted-1980.toml");
    let out = dir.join("x.png");
    let o = glint(&["render", whitted.to_str().unwrap(), "--integrator", "light", "-o", out.to_str().unwrap()]);
    let err = assert_clean_failure(&o);
    assert!(err.contains("falloff") && err.contains("inverse-square"), "{err}");
    let glass = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/caustic-glass.toml");
    // SPPM resumed from a checkpoint (its per-pixel radii and fluxes saved with the film)
    // equals an uninterrupted render.
    let sppm = |spp: &str, out: &str, extra: &[&str]| {
        let out = dir.join(out);
        let mut args =
            vec!["render", glass.to_str().unwrap(), "--integrator", "sppm", "--width", "24", "--spp", spp, "-q"];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["-o", out.to_str().unwrap()]);
        let o = glint(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        std::fs::read(out).unwrap()
    };
    let checkpoint = dir.join("s.ckp");
    let full = sppm("6", "full.pfm", &[]);
    sppm("3", "part.pfm", &["--checkpoint", checkpoint.to_str().unwrap()]);
    let resumed = sppm("6", "resumed.pfm", &["--resume", checkpoint.to_str().unwrap()]);
    assert_eq!(full, resumed, "SPPM resumed from a checkpoint differs from an uninterrupted render");
    // --time works for every progressive integrator: a short limit still writes an image.
    for integrator in ["light", "photon", "sppm"] {
        let o = glint(&[
            "render",
            glass.to_str().unwrap(),
            "--width",
            "24",
            "--integrator",
            integrator,
            "--time",
            "0.5",
            "--photons",
            "20000",
            "--caustic-photons",
            "20000",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{integrator}: {}", stderr(&o));
        assert!(stderr(&o).contains("time limit"), "{integrator}: {}", stderr(&o));
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// A Mitsuba scene renders from the command line, its parameters set with -D as in Mitsuba.
#[test]
fn mitsuba_scenes_render_with_d_parameters() {
    let dir = temp_dir("mitsuba");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../glint-scene/tests/mitsuba/furnace.xml");
    let out = dir.join("f.pfm");
    let o = glint(&["render", scene.to_str().unwrap(), "-D", "spp=3", "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("at 3 spp"), "{}", stderr(&o));
    let (w, h, _) = read_pfm(&out).unwrap();
    assert_eq!((w, h), (16, 16));
    let o = glint(&["render", scene.to_str().unwrap(), "-D", "3", "-o", out.to_str().unwrap()]);
    assert!(!o.status.success() && stderr(&o).contains("NAME=VALUE"), "{}", stderr(&o));
    let toml = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box.toml");
    let o = glint(&["render", toml.to_str().unwrap(), "-D", "spp=3", "-o", out.to_str().unwrap()]);
    let err = assert_clean_failure(&o);
    assert!(err.contains("Mitsuba scenes"), "{err}");
    std::fs::remove_dir_all(dir).unwrap();
}
