//! `glint compare` on hand-made images, and a render's error log against a reference.

mod common;

use std::path::Path;

use common::{assert_clean_failure, glint, stderr, temp_dir};
use glint_cli::output::write_image;
use glint_core::Rgb;

fn write(path: &Path, width: u32, pixels: &[Rgb]) {
    write_image(path, width, pixels.len() as u32 / width, pixels, 0.0, &[], &[]).unwrap();
}

/// Two 2×1 images, worked by hand: MSE R (0 + 4) / 2 = 2, MAE R 1, mean ratio R 2; with a
/// variance of 1 and 100 spp, a difference of 2 (z = 20) fails the Z-test.
#[test]
fn compare_reports_the_metrics_of_hand_made_images_as_json() {
    let dir = temp_dir("compare");
    let (image, reference, variance) = (dir.join("i.pfm"), dir.join("r.exr"), dir.join("v.exr"));
    write(&image, 2, &[Rgb::new(1.0, 2.0, 0.0), Rgb::new(3.0, 2.0, 0.1)]);
    write(&reference, 2, &[Rgb::new(1.0, 1.0, 0.0), Rgb::new(1.0, 1.0, 0.0)]);
    write(&variance, 2, &[Rgb::ONE, Rgb::ONE]);
    let map = dir.join("flip.png");
    let (i, r, v, m) =
        (image.to_str().unwrap(), reference.to_str().unwrap(), variance.to_str().unwrap(), map.to_str().unwrap());
    let o = glint(&["compare", i, r, "--variance", v, "--spp", "100", "--json", "--error-image", m]);
    assert!(o.status.success(), "{}", stderr(&o));
    let d: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    let number = |v: &serde_json::Value| v.as_f64().unwrap();
    assert!((number(&d["mse"][0]) - 2.0).abs() < 1e-9 && (number(&d["mse"][1]) - 1.0).abs() < 1e-9);
    assert!((number(&d["mae"][0]) - 1.0).abs() < 1e-9 && (number(&d["mean_ratio"][0]) - 2.0).abs() < 1e-9);
    assert!(number(&d["flip"]["mean"]) > 0.0);
    assert_eq!(d["z_test"]["passed"], false);
    assert!(image::open(&map).is_ok_and(|png| png.width() == 2 && png.height() == 1));
    // Against itself: all zero, and the Z-test passes.
    let o = glint(&["compare", r, r, "--variance", v, "--spp", "100", "--json"]);
    let d: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!((number(&d["mse_mean"]), number(&d["flip"]["mean"])), (0.0, 0.0));
    assert_eq!(d["z_test"]["passed"], true);
    // A Z-test without a sample count to go on is refused.
    assert!(assert_clean_failure(&glint(&["compare", i, r, "--variance", v])).contains("give --spp"));
    let small = dir.join("s.pfm");
    write(&small, 1, &[Rgb::ONE]);
    assert!(assert_clean_failure(&glint(&["compare", small.to_str().unwrap(), r])).contains("differ in size"));
    std::fs::remove_dir_all(dir).unwrap();
}

/// `render --reference` logs the error after each group of passes: a CSV whose relMSE falls
/// as samples accumulate, and its plot.
#[test]
fn a_render_logs_its_error_against_time() {
    let dir = temp_dir("error-log");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box.toml");
    let scene = scene.to_str().unwrap();
    let reference = dir.join("ref.exr");
    let o = glint(&["render", scene, "--width", "48", "--spp", "256", "-q", "-o", reference.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = dir.join("img.exr");
    let o = glint(&[
        "render",
        scene,
        "--width",
        "48",
        "--spp",
        "64",
        "--seed",
        "3",
        "-q",
        "-o",
        out.to_str().unwrap(),
        "--reference",
        reference.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let csv = std::fs::read_to_string(dir.join("img.exr.error.csv")).unwrap();
    let rows: Vec<Vec<f64>> = csv.lines().skip(1).map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect();
    assert!(!rows.is_empty(), "{csv}");
    let (first, last) = (&rows[0], rows.last().unwrap());
    assert_eq!(last[1], 64.0);
    assert!(last[3] < first[3] || rows.len() == 1, "relMSE does not fall: {csv}");
    assert!(rows.windows(2).all(|w| w[1][0] >= w[0][0] && w[1][1] > w[0][1]), "{csv}");
    assert!(std::fs::read_to_string(dir.join("img.exr.error.svg")).unwrap().contains("<polyline"));
    let wrong = glint(&[
        "render",
        scene,
        "--width",
        "40",
        "--spp",
        "4",
        "-q",
        "-o",
        out.to_str().unwrap(),
        "--reference",
        reference.to_str().unwrap(),
    ]);
    assert!(assert_clean_failure(&wrong).contains("is 48x48, the render 40x40"));
    std::fs::remove_dir_all(dir).unwrap();
}
