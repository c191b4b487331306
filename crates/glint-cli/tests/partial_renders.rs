//! A render split by sample range and merged (`render --samples A..B`, `glint merge`): the
//! merge of any split equals one render of the union, bit for bit, whatever the order of the
//! parts and the threads used; parts that overlap or belong to other renders are refused.

mod common;

use std::path::{Path, PathBuf};

use common::{assert_clean_failure, glint, stderr, temp_dir};
use glint_cli::output::read_pfm;

fn scene_path(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name).to_str().unwrap().to_string()
}

/// Renders samples a..b of `scene` into `dir`, with `extra` flags.
fn part(dir: &Path, scene: &str, (a, b): (u32, u32), extra: &[&str]) -> PathBuf {
    let out = dir.join(format!("part-{a}-{b}{}.exr", extra.join("").replace('-', "")));
    let range = format!("{a}..{b}");
    let args =
        [&["render", scene, "--width", "40", "--samples", &range, "-q", "-o", out.to_str().unwrap()], extra].concat();
    let o = glint(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    out
}

/// The image of a partial render, read through a merge of it alone into a PFM.
fn pixels(dir: &Path, parts: &[PathBuf]) -> Vec<glint_core::Rgb> {
    let out = dir.join("merged.pfm");
    let mut args = vec!["merge".to_string(), "-q".into(), out.to_str().unwrap().into()];
    args.extend(parts.iter().map(|p| p.to_str().unwrap().to_string()));
    let o = glint(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(o.status.success(), "{}", stderr(&o));
    read_pfm(&out).unwrap().2
}

fn bits(image: &[glint_core::Rgb]) -> Vec<[u32; 3]> {
    image.iter().map(|p| p.to_array().map(f32::to_bits)).collect()
}

#[test]
fn merges_of_two_three_and_seven_parts_equal_one_render_bit_for_bit() {
    let dir = temp_dir("partial-merge");
    for (file, extra) in
        [("cornell-box.toml", vec![]), ("caustic-glass.toml", vec!["--integrator", "path", "--filter", "gaussian"])]
    {
        let scene = scene_path(file);
        let whole = pixels(&dir, &[part(&dir, &scene, (0, 14), &extra)]);
        let lit = whole.iter().filter(|p| p.max_element() > 0.0).count();
        assert!(lit > whole.len() / 4, "{file}: {lit} of {} pixels lit", whole.len());
        for splits in [vec![0, 9, 14], vec![0, 1, 6, 14], vec![0, 2, 4, 6, 8, 10, 12, 14]] {
            let mut parts: Vec<PathBuf> = splits.windows(2).map(|w| part(&dir, &scene, (w[0], w[1]), &extra)).collect();
            parts.reverse();
            let merged = pixels(&dir, &parts);
            assert_eq!(bits(&merged), bits(&whole), "{file}: split at {splits:?}");
        }
        // A part rendered on one thread is the same part.
        let threads = [&extra[..], &["--threads", "1"]].concat();
        let one_thread = pixels(&dir, &[part(&dir, &scene, (0, 9), &threads), part(&dir, &scene, (9, 14), &extra)]);
        assert_eq!(bits(&one_thread), bits(&whole), "{file}: one thread");
    }
    // A merged EXR is itself a part: merged again with the rest, it gives the whole.
    let scene = scene_path("cornell-box.toml");
    let (a, b, c) =
        (part(&dir, &scene, (0, 5), &[]), part(&dir, &scene, (5, 9), &[]), part(&dir, &scene, (9, 14), &[]));
    let ab = dir.join("ab.exr");
    let o = glint(&["merge", ab.to_str().unwrap(), a.to_str().unwrap(), b.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("samples 0..9 (9 per pixel)"), "{}", stderr(&o));
    let header = glint_cli::compare::read_image(&ab).unwrap().attributes;
    assert_eq!((header["glint:spp"].as_str(), header["glint:samples"].as_str()), ("9", "0..9"));
    let whole = pixels(&dir, &[part(&dir, &scene, (0, 14), &[])]);
    assert_eq!(bits(&pixels(&dir, &[ab, c])), bits(&whole));
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn overlapping_foreign_and_unsplittable_parts_are_refused() {
    let dir = temp_dir("partial-refused");
    let scene = scene_path("cornell-box.toml");
    let a = part(&dir, &scene, (0, 4), &[]);
    let b = part(&dir, &scene, (2, 6), &[]);
    let out = dir.join("m.exr");
    let merge = |parts: &[&Path]| {
        let mut args = vec!["merge", out.to_str().unwrap()];
        args.extend(parts.iter().map(|p| p.to_str().unwrap()));
        assert_clean_failure(&glint(&args))
    };
    assert!(merge(&[&a, &b]).contains("both hold samples 2..4"));
    let seeded = part(&dir, &scene, (4, 8), &["--seed", "9"]);
    assert!(merge(&[&a, &seeded]).contains("`glint:seed` differ (`0` and `9`)"));
    let other = part(&dir, &scene_path("cornell-box-mixed.toml"), (4, 8), &[]);
    assert!(merge(&[&a, &other]).contains("`glint:identity` differ"));
    let plain = dir.join("plain.exr");
    let o = glint(&["render", &scene, "--width", "40", "--spp", "2", "-q", "-o", plain.to_str().unwrap()]);
    assert!(o.status.success());
    assert!(merge(&[&a, &plain]).contains("is not a partial render"));
    assert!(!out.exists(), "nothing is written when a merge is refused");
    let render = |args: &[&str]| {
        let mut all = vec!["render", scene.as_str(), "--width", "40", "-q"];
        all.extend(args);
        assert_clean_failure(&glint(&all))
    };
    assert!(render(&["--samples", "0..4", "-o", "x.png"]).contains("is not .exr"));
    assert!(render(&["--samples", "4..4", "-o", "x.exr"]).contains("empty"));
    assert!(render(&["--samples", "0..4", "--spp", "4", "-o", "x.exr"]).contains("cannot be combined with --spp"));
    assert!(render(&["--samples", "0..4", "--integrator", "light", "-o", "x.exr"]).contains("use a camera integrator"));
    std::fs::remove_dir_all(dir).unwrap();
}
