//! Comparing an image with a reference (`glint compare`, and the render's error-vs-time log):
//! the usual error metrics per channel, ꟻLIP, and the per-pixel Z-test the project's own tests
//! judge renders by (Mitsuba's).
//!
//! - MSE, mean of (x − r)²; relMSE, mean of (x − r)² / (r² + 10⁻²) (pbrt's and most papers'
//!   form, the 10⁻² keeping black pixels from dominating); MAE, mean of |x − r|; and the ratio
//!   of the means, mean x / mean r, which tells a bias from noise.
//! - ꟻLIP (Andersson et al. 2020) as NVIDIA's implementation computes it (the `nv-flip`
//!   crate), at 67 pixels per degree (a 0.7 m viewing distance from a 0.7 m wide 4K screen):
//!   HDR-ꟻLIP (the largest LDR-ꟻLIP over the ACES-tone-mapped exposures the reference spans,
//!   Andersson et al. 2021), or LDR-ꟻLIP at one exposure; its mean and the error map in the
//!   magma colours. The images reach `nv-flip` as 8-bit sRGB.
//! - The Z-test: with the reference's per-sample variance σ² and the image's sample count n,
//!   each pixel channel in CIE XYZ passes when |x − r| √(n / σ²) has a two-sided p-value above
//!   α = 1 − 0.99^(1/pixels) (Šidák's correction for 1 % overall); the image passes when at
//!   least 99.75 % of channels pass. This is Mitsuba 3's own test of its variants.
//!
//! A pixel with a NaN or infinite channel in either image has no error to measure: the metrics
//! and ꟻLIP leave it out and count it (`NonFinite`), and `warnings` says so; the Z-test counts
//! its channels as failing, since a render that makes them is wrong there.

use std::collections::BTreeMap;
use std::path::Path;

use glint_core::sampling::chi2::gamma_q;
use glint_core::Rgb;

use crate::output::read_pfm;

/// A linear RGB image, row 0 at the top, with its header's text attributes (EXR).
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Rgb>,
    pub attributes: BTreeMap<String, String>,
}

/// Reads an image: OpenEXR (its R, G, B channels), PFM, Radiance HDR (linear as stored), PNG
/// or JPEG (decoded from sRGB to linear).
pub fn read_image(path: &Path) -> Result<Image, String> {
    let name = path.display();
    let lower = path.to_string_lossy().to_ascii_lowercase();
    if lower.ends_with(".exr") {
        return read_exr(path).map_err(|e| format!("`{name}`: {e}"));
    }
    if lower.ends_with(".pfm") {
        let (width, height, pixels) = read_pfm(path).map_err(|e| e.to_string())?;
        return Ok(Image { width, height, pixels, attributes: BTreeMap::new() });
    }
    let bytes = std::fs::read(path).map_err(|e| format!("`{name}`: {e}"))?;
    let (width, height, pixels) =
        glint_scene::decode_image(&lower, &bytes, false).map_err(|e| format!("`{name}`: {e}"))?;
    Ok(Image { width, height, pixels, attributes: BTreeMap::new() })
}

fn read_exr(path: &Path) -> Result<Image, String> {
    use exr::prelude::*;
    let bytes = std::fs::read(path).map_err(|e| e.to_string())?;
    crate::output::check_exr_size(&bytes)?;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgba_channels(
            |resolution, _| (resolution.width(), vec![Rgb::ZERO; resolution.width() * resolution.height()]),
            |(width, pixels), position, (r, g, b, _a): (f32, f32, f32, f32)| {
                pixels[position.y() * *width + position.x()] = Rgb::new(r, g, b);
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(std::io::Cursor::new(bytes))
        .map_err(|e| format!("cannot read it as an RGB OpenEXR image: {e}"))?;
    let layer = &image.layer_data;
    let attributes = crate::output::exr_text_attributes(&image.attributes.other, &layer.attributes.other);
    let (width, height) = (layer.size.width() as u32, layer.size.height() as u32);
    Ok(self::Image { width, height, pixels: layer.channel_data.pixels.1.clone(), attributes })
}

/// Per-channel error metrics (R, G, B) and their means over the channels, over the pixels
/// finite in both images.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Metrics {
    pub mse: [f64; 3],
    pub rel_mse: [f64; 3],
    pub mae: [f64; 3],
    /// mean x / mean r, per channel (NaN where the reference's mean is 0).
    pub mean_ratio: [f64; 3],
    /// The pixels left out.
    pub non_finite: NonFinite,
}

/// Pixels with a NaN or infinite channel: in the image, in the reference, and in either (the
/// ones the metrics and ꟻLIP leave out).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NonFinite {
    pub image: usize,
    pub reference: usize,
    pub either: usize,
}

fn is_finite(p: &Rgb) -> bool {
    p.is_finite()
}

impl NonFinite {
    pub fn count(image: &Image, reference: &Image) -> Self {
        let mut counts = NonFinite::default();
        for (x, r) in image.pixels.iter().zip(&reference.pixels) {
            counts.image += usize::from(!is_finite(x));
            counts.reference += usize::from(!is_finite(r));
            counts.either += usize::from(!is_finite(x) || !is_finite(r));
        }
        counts
    }
}

/// 8-bit formats, whose values stop at 1.
pub fn is_low_dynamic_range(path: &Path) -> bool {
    let lower = path.to_string_lossy().to_ascii_lowercase();
    [".png", ".jpg", ".jpeg", ".bmp", ".tga"].iter().any(|e| lower.ends_with(e))
}

/// What a reader of the metrics should know: pixels left out for being NaN or infinite, and an
/// 8-bit image compared with one whose values go past 1 (its clipped highlights look like a
/// bias).
pub fn warnings(image_path: &Path, image: &Image, reference_path: &Path, reference: &Image) -> Vec<String> {
    let mut said = Vec::new();
    let non_finite = NonFinite::count(image, reference);
    for (count, path) in [(non_finite.image, image_path), (non_finite.reference, reference_path)] {
        if count > 0 {
            said.push(format!(
                "`{}` has {count} pixel{} with a NaN or infinite value: the metrics and ꟻLIP leave {} out, the Z-test fails {}",
                path.display(),
                if count == 1 { "" } else { "s" },
                if count == 1 { "it" } else { "them" },
                if count == 1 { "it" } else { "them" },
            ));
        }
    }
    let brightest =
        |image: &Image| image.pixels.iter().filter(|p| is_finite(p)).map(|p| p.max_element()).fold(0.0f32, f32::max);
    for (ldr_path, other_path, other) in [(image_path, reference_path, reference), (reference_path, image_path, image)]
    {
        let peak = brightest(other);
        if is_low_dynamic_range(ldr_path) && !is_low_dynamic_range(other_path) && peak > 1.0 {
            said.push(format!(
                "`{}` is an 8-bit image, its values clipped at 1, and `{}` reaches {peak}: where it is brighter than 1 the difference is the clipping, not the render",
                ldr_path.display(),
                other_path.display()
            ));
        }
    }
    said
}

impl Metrics {
    pub fn mean(values: [f64; 3]) -> f64 {
        values.iter().sum::<f64>() / 3.0
    }
}

/// The images' sizes, checked equal.
fn same_size(image: &Image, reference: &Image) -> Result<(), String> {
    if (image.width, image.height) != (reference.width, reference.height) {
        return Err(format!(
            "the images differ in size: {}x{} and the reference's {}x{}",
            image.width, image.height, reference.width, reference.height
        ));
    }
    Ok(())
}

pub fn metrics(image: &Image, reference: &Image) -> Result<Metrics, String> {
    same_size(image, reference)?;
    let non_finite = NonFinite::count(image, reference);
    let compared = image.pixels.len() - non_finite.either;
    if compared == 0 && !image.pixels.is_empty() {
        return Err("no pixel is finite in both images: there is nothing to compare".into());
    }
    let n = compared.max(1) as f64;
    let (mut mse, mut rel_mse, mut mae, mut sum_x, mut sum_r) =
        ([0.0f64; 3], [0.0f64; 3], [0.0f64; 3], [0.0; 3], [0.0; 3]);
    for (x, r) in image.pixels.iter().zip(&reference.pixels).filter(|(x, r)| is_finite(x) && is_finite(r)) {
        let (x, r) = (x.to_array(), r.to_array());
        for c in 0..3 {
            let (x, r) = (x[c] as f64, r[c] as f64);
            let d = x - r;
            mse[c] += d * d;
            rel_mse[c] += d * d / (r * r + 1e-2);
            mae[c] += d.abs();
            sum_x[c] += x;
            sum_r[c] += r;
        }
    }
    Ok(Metrics {
        mse: mse.map(|v| v / n),
        rel_mse: rel_mse.map(|v| v / n),
        mae: mae.map(|v| v / n),
        mean_ratio: [0, 1, 2].map(|c| sum_x[c] / sum_r[c]),
        non_finite,
    })
}

/// The Z-test's outcome.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ZTest {
    /// The fraction of pixel channels that pass.
    pub fraction: f64,
    /// At least 99.75 % pass.
    pub passed: bool,
    /// The per-channel significance level (Šidák-corrected).
    pub alpha: f64,
}

/// Linear sRGB (D65) to CIE XYZ.
fn to_xyz(c: Rgb) -> [f64; 3] {
    let (r, g, b) = (c.x as f64, c.y as f64, c.z as f64);
    [
        0.412453 * r + 0.357580 * g + 0.180423 * b,
        0.212671 * r + 0.715160 * g + 0.072169 * b,
        0.019334 * r + 0.119193 * g + 0.950227 * b,
    ]
}

/// Mitsuba's Z-test of `image` (`spp` samples per pixel) against `reference` with the
/// per-sample `variance` (variances below 10⁻⁴ count as 10⁻⁴, as Mitsuba's do).
pub fn z_test(image: &Image, reference: &Image, variance: &Image, spp: u64) -> Result<ZTest, String> {
    same_size(image, reference)?;
    same_size(variance, reference).map_err(|e| format!("variance: {e}"))?;
    let pixel_count = reference.pixels.len().max(1);
    let alpha = 1.0 - 0.99f64.powf(1.0 / pixel_count as f64);
    let mut passed = 0usize;
    for ((x, r), v) in image.pixels.iter().zip(&reference.pixels).zip(&variance.pixels) {
        let (x, r, v) = (to_xyz(*x), to_xyz(*r), to_xyz(*v));
        for c in 0..3 {
            let z = (x[c] - r[c]).abs() * (spp as f64 / v[c].max(1e-4)).sqrt();
            // p = 2 (1 − Φ(z)) = Q(½, z²/2).
            let p = if z.is_finite() { gamma_q(0.5, z * z / 2.0) } else { 0.0 };
            passed += usize::from(p > alpha);
        }
    }
    let fraction = passed as f64 / (3 * pixel_count) as f64;
    Ok(ZTest { fraction, passed: fraction >= 0.9975, alpha })
}

/// Pixels per degree of visual angle at which ꟻLIP compares (`nv_flip::DEFAULT_PIXELS_PER_DEGREE`).
pub const FLIP_PIXELS_PER_DEGREE: f32 = nv_flip::DEFAULT_PIXELS_PER_DEGREE;

/// A ꟻLIP comparison: the mean error (0 to 1), the per-pixel error map in magma colours (8-bit
/// RGB, row 0 at the top), and the exposures it looked at (in stops).
#[derive(Clone, Debug, PartialEq)]
pub struct Flip {
    pub mean: f64,
    pub map: Vec<u8>,
    pub exposures: Vec<f32>,
}

/// LDR-ꟻLIP of the images as 8-bit sRGB at `exposure` stops (clamped to [0, 1]).
pub fn flip(image: &Image, reference: &Image, exposure: f32) -> Result<Flip, String> {
    same_size(image, reference)?;
    let (image, reference, kept) = finite_only(image, reference);
    let scale = exposure.exp2();
    let error = ldr_flip(&image, &reference, |c| c * scale);
    Ok(finish(&error, &kept, vec![exposure]))
}

/// The images with every pixel that is not finite in both set to black in both (no error
/// there), and which pixels are kept.
fn finite_only(image: &Image, reference: &Image) -> (Image, Image, Vec<bool>) {
    let kept: Vec<bool> =
        image.pixels.iter().zip(&reference.pixels).map(|(x, r)| is_finite(x) && is_finite(r)).collect();
    let clean = |source: &Image| Image {
        pixels: source.pixels.iter().zip(&kept).map(|(p, &k)| if k { *p } else { Rgb::ZERO }).collect(),
        ..source.clone()
    };
    (clean(image), clean(reference), kept)
}

/// HDR-ꟻLIP (Andersson et al., "Visualizing errors in rendered high dynamic range images",
/// 2021): LDR-ꟻLIP of the images tone-mapped by ACES (Narkowicz's fit, as the paper's tool
/// uses it) at exposures from the one that brings the reference's brightest luminance to 0.85
/// to the one that brings its median there, one stop apart (at least two), each pixel's error
/// the largest over them. Computed on 8-bit sRGB images, as `nv-flip` takes them.
pub fn hdr_flip(image: &Image, reference: &Image) -> Result<Flip, String> {
    same_size(image, reference)?;
    let (image, reference, kept) = finite_only(image, reference);
    let (image, reference) = (&image, &reference);
    let (start, stop) = exposure_range(reference);
    let count = ((stop - start).ceil() as usize).max(2);
    let step = (stop - start) / (count - 1) as f32;
    let exposures: Vec<f32> = (0..count).map(|i| start + i as f32 * step).collect();
    let mut worst: Vec<f32> = Vec::new();
    for &exposure in &exposures {
        let scale = exposure.exp2();
        let error = ldr_flip(image, reference, |c| aces(c * scale)).to_vec();
        if worst.is_empty() {
            worst = error;
        } else {
            worst.iter_mut().zip(error).for_each(|(w, e)| *w = w.max(e));
        }
    }
    let error = nv_flip::FlipImageFloat::with_data(reference.width, reference.height, &worst);
    Ok(finish(&error, &kept, exposures))
}

/// ACES filmic tone mapping (Narkowicz 2016) with its 0.6 pre-exposure, clamped to [0, 1].
fn aces(x: f32) -> f32 {
    let x = 0.6 * x.max(0.0);
    ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
}

/// HDR-ꟻLIP's exposures (stops): the value that `aces` maps to 0.85, over the reference's
/// largest luminance (start) and over its median (stop).
fn exposure_range(reference: &Image) -> (f32, f32) {
    // aces(x) = 0.85, solved: the positive root of (a − 0.85c)x² + (b − 0.85d)x − 0.85e = 0 in
    // x' = 0.6x.
    let (a, b, c, d, e, t) = (2.51f64, 0.03, 2.43, 0.59, 0.14, 0.85);
    let (qa, qb, qc) = (a - t * c, b - t * d, -t * e);
    let x = ((-qb + (qb * qb - 4.0 * qa * qc).sqrt()) / (2.0 * qa)) / 0.6;
    let mut luminance: Vec<f64> =
        reference.pixels.iter().map(|p| 0.2126 * p.x as f64 + 0.7152 * p.y as f64 + 0.0722 * p.z as f64).collect();
    luminance.sort_by(f64::total_cmp);
    let (Some(&highest), median) = (luminance.last(), luminance.get(luminance.len() / 2).copied().unwrap_or(0.0))
    else {
        return (0.0, 0.0);
    };
    if highest <= 0.0 {
        return (0.0, 0.0);
    }
    let start = (x / highest).log2();
    let stop = if median > 0.0 { (x / median).log2() } else { start };
    (start as f32, stop.max(start) as f32)
}

/// LDR-ꟻLIP of the images mapped channel by channel by `map` into [0, 1], then sRGB-encoded.
fn ldr_flip(image: &Image, reference: &Image, map: impl Fn(f32) -> f32) -> nv_flip::FlipImageFloat {
    let encode = |image: &Image| {
        let bytes: Vec<u8> =
            image.pixels.iter().flat_map(|p| p.to_array().map(|c| crate::output::encode_srgb(map(c)))).collect();
        nv_flip::FlipImageRgb8::with_data(image.width, image.height, &bytes)
    };
    nv_flip::flip(encode(reference), encode(image), FLIP_PIXELS_PER_DEGREE)
}

/// ꟻLIP's mean over the kept pixels, and its map.
fn finish(error: &nv_flip::FlipImageFloat, kept: &[bool], exposures: Vec<f32>) -> Flip {
    let values = error.to_vec();
    let (sum, count) = values
        .iter()
        .zip(kept)
        .filter(|(_, &k)| k)
        .fold((0.0f64, 0usize), |(sum, count), (&e, _)| (sum + e as f64, count + 1));
    let mean = if count > 0 { sum / count as f64 } else { 0.0 };
    Flip { mean, map: error.apply_color_lut(&nv_flip::magma_lut()).to_vec(), exposures }
}

/// One row of a render's error log: seconds rendering so far, samples per pixel, and the
/// image's MSE, relMSE and MAE (means over the channels) against the reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorSample {
    pub seconds: f64,
    pub spp: u32,
    pub mse: f64,
    pub rel_mse: f64,
    pub mae: f64,
}

/// The error log as CSV, a header line first.
pub fn error_csv(rows: &[ErrorSample]) -> String {
    let mut out = String::from("seconds,spp,mse,rel_mse,mae\n");
    for r in rows {
        out += &format!("{},{},{:e},{:e},{:e}\n", r.seconds, r.spp, r.mse, r.rel_mse, r.mae);
    }
    out
}

/// relMSE against time on log-log axes, as an SVG drawing (decades marked on both axes): the
/// straight line of slope −1 that an unbiased estimator's error follows shows as such.
pub fn error_plot_svg(rows: &[ErrorSample], title: &str) -> String {
    let (width, height, margin) = (640.0, 420.0, 60.0);
    let points: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.seconds > 0.0 && r.rel_mse > 0.0 && r.rel_mse.is_finite())
        .map(|r| (r.seconds.log10(), r.rel_mse.log10()))
        .collect();
    let decades = |values: &mut dyn Iterator<Item = f64>| {
        let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
        if lo.is_finite() {
            (lo.floor(), hi.ceil().max(lo.floor() + 1.0))
        } else {
            (0.0, 1.0)
        }
    };
    let (x0, x1) = decades(&mut points.iter().map(|p| p.0));
    let (y0, y1) = decades(&mut points.iter().map(|p| p.1));
    let sx = |x: f64| margin + (x - x0) / (x1 - x0) * (width - 2.0 * margin);
    let sy = |y: f64| height - margin - (y - y0) / (y1 - y0) * (height - 2.0 * margin);
    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n<text x=\"{}\" y=\"24\" text-anchor=\"middle\" font-size=\"14\">{}</text>\n",
        width / 2.0,
        escape(title)
    );
    for d in (x0 as i32)..=(x1 as i32) {
        let x = sx(d as f64);
        svg += &format!("<line x1=\"{x}\" y1=\"{}\" x2=\"{x}\" y2=\"{}\" stroke=\"#ddd\"/><text x=\"{x}\" y=\"{}\" text-anchor=\"middle\">1e{d} s</text>\n", margin, height - margin, height - margin + 18.0);
    }
    for d in (y0 as i32)..=(y1 as i32) {
        let y = sy(d as f64);
        svg += &format!("<line x1=\"{margin}\" y1=\"{y}\" x2=\"{}\" y2=\"{y}\" stroke=\"#ddd\"/><text x=\"{}\" y=\"{}\" text-anchor=\"end\">1e{d}</text>\n", width - margin, margin - 6.0, y + 4.0);
    }
    svg += &format!(
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">render time</text><text x=\"16\" y=\"{}\" transform=\"rotate(-90 16 {})\" text-anchor=\"middle\">relMSE</text>\n",
        width / 2.0,
        height - 12.0,
        height / 2.0,
        height / 2.0
    );
    let line: Vec<String> = points.iter().map(|&(x, y)| format!("{:.2},{:.2}", sx(x), sy(y))).collect();
    svg += &format!(
        "<polyline fill=\"none\" stroke=\"#c03\" stroke-width=\"2\" points=\"{}\"/>\n</svg>\n",
        line.join(" ")
    );
    svg
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(values: &[Rgb], width: u32) -> Image {
        let height = values.len() as u32 / width;
        Image { width, height, pixels: values.to_vec(), attributes: BTreeMap::new() }
    }

    /// Metrics worked by hand: pixels (1, 2, 0) and (3, 2, 0.1) against (1, 1, 0) and (1, 1, 0).
    #[test]
    fn metrics_by_hand() {
        let image = flat(&[Rgb::new(1.0, 2.0, 0.0), Rgb::new(3.0, 2.0, 0.1)], 2);
        let reference = flat(&[Rgb::new(1.0, 1.0, 0.0), Rgb::new(1.0, 1.0, 0.0)], 2);
        let m = metrics(&image, &reference).unwrap();
        let close = |a: f64, b: f64| (a - b).abs() < 1e-6 * b.abs().max(1.0);
        assert!(close(m.mse[0], 2.0) && close(m.mse[1], 1.0) && close(m.mse[2], 0.005), "{m:?}");
        // relMSE: R (0 + 4 / 1.01) / 2; B (0 + 0.01 / 0.01) / 2.
        assert!(close(m.rel_mse[0], 2.0 / 1.01) && close(m.rel_mse[2], 0.5), "{m:?}");
        assert!(close(m.mae[0], 1.0) && close(m.mae[1], 1.0) && close(m.mae[2], 0.05), "{m:?}");
        assert!(close(m.mean_ratio[0], 2.0) && close(m.mean_ratio[1], 2.0) && m.mean_ratio[2].is_infinite());
        let smaller = flat(&[Rgb::ZERO], 1);
        assert!(metrics(&smaller, &reference).unwrap_err().contains("differ in size"));
    }

    /// A +inf pixel in the reference made HDR-ꟻLIP's exposure range infinite (a panic: capacity
    /// overflow), and a NaN made it NaN (ꟻLIP 0 where every pixel differs by 0.5). Such pixels
    /// are left out of the metrics and ꟻLIP, and counted.
    #[test]
    fn non_finite_pixels_are_left_out_and_counted() {
        let pattern: Vec<Rgb> = (0..32 * 32).map(|i| Rgb::splat(((i % 32) / 4) as f32 / 8.0 + 0.1)).collect();
        let image = flat(&pattern.iter().map(|p| *p + Rgb::splat(0.5)).collect::<Vec<_>>(), 32);
        let mut reference = flat(&pattern, 32);
        reference.pixels[3] = Rgb::splat(f32::INFINITY);
        let with_infinity = hdr_flip(&image, &reference).unwrap();
        assert!(with_infinity.exposures.iter().all(|e| e.is_finite()), "{:?}", with_infinity.exposures);
        let clean = hdr_flip(&image, &flat(&pattern, 32)).unwrap();
        assert_eq!(with_infinity.exposures, clean.exposures);
        assert!(with_infinity.mean > 0.05, "{}", with_infinity.mean);
        reference.pixels[5] = Rgb::new(f32::NAN, 0.0, 0.0);
        let with_nan = hdr_flip(&image, &reference).unwrap();
        assert!(with_nan.mean > 0.05 && with_nan.exposures.iter().all(|e| e.is_finite()), "{with_nan:?}");
        assert!(flip(&image, &reference, 0.0).unwrap().mean > 0.05);
        let m = metrics(&image, &reference).unwrap();
        assert_eq!(m.non_finite, NonFinite { image: 0, reference: 2, either: 2 });
        assert!(m.mae.iter().all(|&e| (e - 0.5).abs() < 1e-6), "{m:?}");
        assert!(m.mse.iter().all(|&e| (e - 0.25).abs() < 1e-6), "{m:?}");
        let said = warnings(Path::new("a.exr"), &image, Path::new("ref.exr"), &reference);
        assert_eq!(said.len(), 1, "{said:?}");
        assert!(said[0].contains("`ref.exr` has 2 pixels with a NaN or infinite value"), "{said:?}");
        let nothing = flat(&[Rgb::splat(f32::NAN)], 1);
        assert!(metrics(&nothing, &nothing).unwrap_err().contains("no pixel is finite"));
    }

    /// An 8-bit image against a reference brighter than 1 is compared, with a warning that
    /// names the clipping; against a reference within [0, 1], none.
    #[test]
    fn an_8_bit_image_against_hdr_is_flagged_as_clipped() {
        let bright = flat(&[Rgb::splat(0.5), Rgb::splat(3.0)], 2);
        let clipped = flat(&[Rgb::splat(0.5), Rgb::splat(1.0)], 2);
        let said = warnings(Path::new("render.PNG"), &clipped, Path::new("ref.exr"), &bright);
        assert_eq!(said.len(), 1);
        assert!(said[0].contains("`render.PNG` is an 8-bit image") && said[0].contains("reaches 3"), "{said:?}");
        let said = warnings(Path::new("ref.exr"), &bright, Path::new("render.jpg"), &clipped);
        assert!(said[0].contains("`render.jpg` is an 8-bit image"), "{said:?}");
        assert!(warnings(Path::new("a.png"), &clipped, Path::new("b.exr"), &clipped).is_empty());
        assert!(warnings(Path::new("a.png"), &clipped, Path::new("b.png"), &bright).is_empty());
    }

    /// The Z-test against its corrected significance: 400 pixels, α = 2.5·10⁻⁵ (z* ≈ 4.21); at
    /// 100 spp and σ² = 1, a difference of 0.3 (z = 3) passes, 0.5 (z = 5) fails; one pixel of
    /// 400 off is 0.25 % of the channels and passes, two do not.
    #[test]
    fn z_test_counts_channels_against_the_corrected_significance() {
        let uniform = |v: f32| flat(&vec![Rgb::splat(v); 400], 400);
        let (reference, variance) = (uniform(1.0), uniform(1.0));
        // Grey in XYZ: Y = 1 for (1, 1, 1); X and Z near 0.95 and 1.09, the same differences
        // scaled alike.
        assert!(z_test(&uniform(1.3), &reference, &variance, 100).unwrap().passed);
        let failed = z_test(&uniform(1.5), &reference, &variance, 100).unwrap();
        assert!(!failed.passed && failed.fraction < 0.01, "{failed:?}");
        let mut image = uniform(1.0);
        image.pixels[7] = Rgb::splat(9.0);
        assert!(z_test(&image, &reference, &variance, 100).unwrap().passed);
        image.pixels[8] = Rgb::splat(9.0);
        assert!(!z_test(&image, &reference, &variance, 100).unwrap().passed);
    }

    /// The error log's CSV has a row per sample and the plot a point per sample.
    #[test]
    fn error_log_as_csv_and_plot() {
        let rows: Vec<ErrorSample> = (1..=4)
            .map(|k| ErrorSample {
                seconds: k as f64,
                spp: 4 * k,
                mse: 0.1 / k as f64,
                rel_mse: 1.0 / k as f64,
                mae: 0.3,
            })
            .collect();
        let csv = error_csv(&rows);
        assert_eq!(csv.lines().count(), 5);
        assert_eq!(csv.lines().nth(2).unwrap(), "2,8,5e-2,5e-1,3e-1");
        let svg = error_plot_svg(&rows, "a <test>");
        assert!(svg.contains("a &lt;test&gt;") && svg.ends_with("</svg>\n"));
        let polyline = svg.lines().find(|l| l.starts_with("<polyline")).unwrap();
        assert_eq!(polyline.matches(',').count(), 4);
    }

    /// ꟻLIP, LDR and HDR, is 0 for identical images and grows with the difference.
    #[test]
    fn flip_is_zero_for_the_same_image_and_grows_with_the_difference() {
        let pattern: Vec<Rgb> = (0..64 * 64).map(|i| Rgb::splat(((i % 64) / 8) as f32 / 8.0)).collect();
        let reference = flat(&pattern, 64);
        let same = flip(&reference, &reference, 0.0).unwrap();
        assert_eq!(same.mean, 0.0);
        assert_eq!(same.map.len(), 64 * 64 * 3);
        assert_eq!(hdr_flip(&reference, &reference).unwrap().mean, 0.0);
        let shifted = |d: f32| flat(&pattern.iter().map(|p| *p + Rgb::splat(d)).collect::<Vec<_>>(), 64);
        let (small, large) =
            (flip(&shifted(0.02), &reference, 0.0).unwrap(), flip(&shifted(0.3), &reference, 0.0).unwrap());
        assert!(0.0 < small.mean && small.mean < large.mean && large.mean <= 1.0, "{small:?} {large:?}");
        let (small, large) =
            (hdr_flip(&shifted(0.02), &reference).unwrap(), hdr_flip(&shifted(0.3), &reference).unwrap());
        assert!(0.0 < small.mean && small.mean < large.mean && large.mean <= 1.0);
    }

    /// HDR-ꟻLIP's exposures by hand: ACES (with its 0.6 pre-exposure) reaches 0.85 at
    /// x ≈ 2.119; a reference whose brightest luminance is 8 and median 1 starts at
    /// log₂(2.119 / 8) ≈ −1.92 and stops at log₂ 2.119 ≈ 1.08: three stops, three exposures.
    #[test]
    fn hdr_flip_exposures_span_the_brightest_to_the_median() {
        let x = (0..1000).map(|i| i as f32 * 0.01).find(|&x| aces(x) >= 0.85).unwrap();
        assert!((x - 2.119).abs() < 0.01, "{x}");
        let mut values = vec![Rgb::ONE; 9];
        values[0] = Rgb::splat(8.0);
        let reference = flat(&values, 3);
        let (start, stop) = exposure_range(&reference);
        assert!((start - (x / 8.0).log2()).abs() < 0.02 && (stop - x.log2()).abs() < 0.02, "{start} {stop}");
        assert_eq!(hdr_flip(&reference, &reference).unwrap().exposures.len(), 3);
        assert!((aces(1e6) - 1.0).abs() < 1e-6 && aces(0.0) == 0.0);
    }
}
