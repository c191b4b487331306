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

/// A reference with a +inf and a NaN pixel (a panic before, and a ꟻLIP of 0 where every pixel
/// differs): compared over the finite pixels, the others counted in the JSON and named in a
/// warning. An 8-bit PNG against an HDR reference is compared with a warning that it is clipped.
#[test]
fn compare_leaves_out_non_finite_pixels_and_flags_a_clipped_png() {
    let dir = temp_dir("compare-hostile");
    let (image, reference) = (dir.join("i.pfm"), dir.join("r.pfm"));
    let values: Vec<Rgb> = (0..64).map(|i| Rgb::splat(0.1 + (i % 8) as f32 / 10.0)).collect();
    let mut broken = values.clone();
    broken[3] = Rgb::splat(f32::INFINITY);
    broken[9] = Rgb::new(f32::NAN, 0.5, 0.5);
    write(&reference, 8, &broken);
    write(&image, 8, &values.iter().map(|p| *p + Rgb::splat(0.5)).collect::<Vec<_>>());
    let (i, r) = (image.to_str().unwrap(), reference.to_str().unwrap());
    let o = glint(&["compare", i, r, "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let d: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(d["non_finite_pixels"]["reference"], 2);
    assert_eq!(d["non_finite_pixels"]["left_out"], 2);
    assert!((d["mae_mean"].as_f64().unwrap() - 0.5).abs() < 1e-6, "{d}");
    assert!(d["flip"]["mean"].as_f64().unwrap() > 0.05, "{d}");
    assert!(d["warnings"][0].as_str().unwrap().contains("2 pixels with a NaN or infinite value"), "{d}");
    let o = glint(&["compare", i, r]);
    assert!(o.status.success() && stderr(&o).contains("warning:"), "{}", stderr(&o));

    let (png, hdr) = (dir.join("clipped.png"), dir.join("bright.exr"));
    let bright: Vec<Rgb> = (0..64).map(|i| Rgb::splat(if i < 8 { 4.0 } else { 0.5 })).collect();
    write(&hdr, 8, &bright);
    write(&png, 8, &bright);
    let o = glint(&["compare", png.to_str().unwrap(), hdr.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("is an 8-bit image, its values clipped at 1"), "{}", stderr(&o));
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

/// Reads every channel of an EXR by name, and its text attributes.
fn exr_channels(path: &Path) -> (glint_cli::output::Channels, std::collections::BTreeMap<String, String>) {
    use exr::prelude::*;
    let image = read_all_flat_layers_from_file(path).unwrap();
    let layer = &image.layer_data[0];
    let channels =
        layer.channel_data.list.iter().map(|c| (c.name.to_string(), c.sample_data.values_as_f32().collect())).collect();
    let attributes = glint_cli::output::exr_text_attributes(&image.attributes.other, &layer.attributes.other);
    (channels, attributes)
}

/// `--aovs`: albedo, normal and depth of what the camera sees first, and each pixel's
/// variance, which predicts the spread of the pixel between renders of other seeds; the
/// header carries the camera and the render time. `.hdr` output reads back as written.
#[test]
fn aovs_and_metadata_beside_the_image() {
    let dir = temp_dir("aovs");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box.toml");
    let scene = scene.to_str().unwrap();
    let render = |seed: u32, extra: &[&str]| {
        let out = dir.join(format!("r{seed}.exr"));
        let seed = seed.to_string();
        let args = [
            // Independent samples: a low-discrepancy sampler's pixel error is below σ²/n.
            &[
                "render",
                scene,
                "--width",
                "32",
                "--spp",
                "16",
                "--sampler",
                "independent",
                "--seed",
                &seed,
                "-q",
                "-o",
                out.to_str().unwrap(),
            ],
            extra,
        ]
        .concat();
        let o = glint(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        exr_channels(&out)
    };
    let (channels, attributes) = render(0, &["--aovs"]);
    let get = |name: &str| &channels.iter().find(|(n, _)| n == name).unwrap_or_else(|| panic!("no {name}")).1;
    for name in ["albedo.R", "normal.X", "normal.Z", "depth.Z", "variance.G"] {
        assert_eq!(get(name).len(), 32 * 32, "{name}");
    }
    // The back wall behind the centre pixel: diffuse white, facing the camera (−z), about
    // 1200 units away (its normal averaged over the pixel, which the tall box edges into).
    let centre = 16 * 32 + 16;
    assert!((get("albedo.R")[centre] - 0.885809).abs() < 0.03, "{}", get("albedo.R")[centre]);
    assert!(
        get("normal.Z")[centre] < -0.95 && get("depth.Z")[centre] > 700.0,
        "{} {}",
        get("normal.Z")[centre],
        get("depth.Z")[centre]
    );
    let matrix: Vec<f32> = attributes["glint:camera_to_world"].split(' ').map(|v| v.parse().unwrap()).collect();
    assert_eq!(matrix.len(), 16);
    assert!(attributes["glint:render_seconds"].parse::<f64>().unwrap() > 0.0);
    // The variance layer against the spread over eight other seeds, averaged over the image.
    let images: Vec<Vec<f32>> =
        (1..=8).map(|seed| render(seed, &[]).0.into_iter().find(|(n, _)| n == "G").unwrap().1).collect();
    let n = 32 * 32;
    let spread: f64 = (0..n)
        .map(|i| {
            let values: Vec<f64> = images.iter().map(|im| im[i] as f64).collect();
            let mean = values.iter().sum::<f64>() / 8.0;
            values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / 7.0
        })
        .sum::<f64>()
        / n as f64;
    let predicted: f64 = get("variance.G").iter().map(|v| *v as f64).sum::<f64>() / n as f64;
    assert!((predicted / spread - 1.0).abs() < 0.25, "variance layer {predicted} vs spread {spread}");
    // HDR output.
    let hdr = dir.join("x.hdr");
    let o = glint(&["render", scene, "--width", "32", "--spp", "4", "-q", "-o", hdr.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let back = glint_cli::compare::read_image(&hdr).unwrap();
    assert_eq!((back.width, back.height), (32, 32));
    assert!(back.pixels.iter().any(|p| p.max_element() > 0.05));
    std::fs::remove_dir_all(dir).unwrap();
}
