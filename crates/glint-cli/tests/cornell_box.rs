//! Ground truth: glint's Cornell box against the converged Mitsuba 3 reference
//! (../shared/references/cbox_256.exr, 16,384 spp, with its per-pixel variance), the statistical
//! way Mitsuba's own render tests compare: a per-pixel Z-test whose significance is corrected
//! for the number of pixels, and the image means within 0.5 %.

use std::path::Path;

use glint_core::integrators::{IntegratorKind, SampleContext};
use glint_core::lights::TriangleSampling;
use glint_core::sampling::chi2::gamma_q;
use glint_core::sampling::Rng;
use glint_core::scene::Scene;
use glint_core::Rgb;
use rayon::prelude::*;

const SIZE: u32 = 64;
const SPP: u32 = 512;

fn reference_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/references")
}

/// A 256² EXR box-downsampled to 64² (a 4×4 block mean: exact for the box pixel filter). For
/// the variance image, the variance of a block mean: Σ var / 16².
fn read_downsampled(name: &str, variance: bool) -> Vec<Rgb> {
    let image = exr::prelude::read_first_rgba_layer_from_file(
        reference_dir().join(name),
        |resolution, _| vec![Rgb::ZERO; resolution.width() * resolution.height()],
        |pixels, position, (r, g, b, _a): (f32, f32, f32, f32)| {
            pixels[position.y() * 256 + position.x()] = Rgb::new(r, g, b);
        },
    )
    .expect("the reference EXR reads");
    let full = image.layer_data.channel_data.pixels;
    let k = 256 / SIZE as usize;
    (0..(SIZE * SIZE) as usize)
        .map(|i| {
            let (x, y) = (i % SIZE as usize, i / SIZE as usize);
            let mut sum = Rgb::ZERO;
            for dy in 0..k {
                for dx in 0..k {
                    sum += full[(y * k + dy) * 256 + x * k + dx];
                }
            }
            if variance {
                sum / (k * k * k * k) as f32
            } else {
                sum / (k * k) as f32
            }
        })
        .collect()
}

/// Per-pixel mean and variance of the mean, from the samples themselves.
fn render_with_variance(kind: IntegratorKind, seed: u64, spp: u32) -> (Vec<Rgb>, Vec<Rgb>) {
    render_scene_with_variance(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box.toml"),
        kind,
        seed,
        spp,
    )
}

fn render_scene_with_variance(scene_path: &Path, kind: IntegratorKind, seed: u64, spp: u32) -> (Vec<Rgb>, Vec<Rgb>) {
    render_configured_with_variance(scene_path, kind, seed, spp, |_| {})
}

/// `render_scene_with_variance` after `configure` has changed the loaded scene.
fn render_configured_with_variance(
    scene_path: &Path,
    kind: IntegratorKind,
    seed: u64,
    spp: u32,
    configure: impl FnOnce(&mut Scene),
) -> (Vec<Rgb>, Vec<Rgb>) {
    let loaded = glint_scene::load_scene(scene_path).expect("the Cornell box loads");
    let mut scene = loaded.scene;
    scene.set_camera(scene.camera().with_resolution(SIZE, SIZE));
    configure(&mut scene);
    let integrator = kind.create(&loaded.render.integrator_settings).expect("a camera integrator");
    (0..SIZE * SIZE)
        .into_par_iter()
        .map(|i| {
            let (x, y) = (i % SIZE, i / SIZE);
            let (mut mean, mut m2) = (Rgb::ZERO, Rgb::ZERO);
            for s in 0..spp {
                let mut context = SampleContext::new(Rng::for_sample(seed, i as u64, s as u64));
                let ray = scene
                    .camera()
                    .generate_ray(x as f32 + context.sampler.next_f32(), y as f32 + context.sampler.next_f32());
                let value = integrator.radiance(&scene, &ray, &mut context);
                // Welford's running mean and sum of squared deviations.
                let delta = value - mean;
                mean += delta / (s + 1) as f32;
                m2 += delta * (value - mean);
            }
            (mean, m2 / ((spp - 1) * spp) as f32)
        })
        .unzip()
}

/// z* of a two-sided test at significance 0.01 corrected for `tests` tests (Bonferroni):
/// P(|Z| > z) = Q(½, z²/2), the chi-square tail with one degree of freedom, solved by bisection.
fn z_critical(tests: usize) -> f32 {
    let target = 0.01 / tests as f64;
    let (mut lo, mut hi) = (0.0f64, 20.0f64);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if gamma_q(0.5, mid * mid / 2.0) > target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo as f32
}

/// Block means and the variance of each block mean (Σ var / n² for n independent pixels).
fn blocks(image: &(Vec<Rgb>, Vec<Rgb>), block: usize) -> (Vec<Rgb>, Vec<Rgb>) {
    let side = SIZE as usize / block;
    let n = (block * block) as f32;
    (0..side * side)
        .map(|b| {
            let (bx, by) = (b % side, b / side);
            let (mut mean, mut var) = (Rgb::ZERO, Rgb::ZERO);
            for dy in 0..block {
                for dx in 0..block {
                    let i = (by * block + dy) * SIZE as usize + bx * block + dx;
                    mean += image.0[i];
                    var += image.1[i];
                }
            }
            (mean / n, var / (n * n))
        })
        .unzip()
}

fn z_scores(a: &(Vec<Rgb>, Vec<Rgb>), b: &(Vec<Rgb>, Vec<Rgb>)) -> Vec<f32> {
    (0..a.0.len())
        .flat_map(|i| (0..3).map(move |c| (a.0[i][c] - b.0[i][c]) / (a.1[i][c] + b.1[i][c]).sqrt().max(1e-6)))
        .collect()
}

/// A statistical comparison robust to the heavy tails of path tracing: per-pixel variance
/// estimates are unreliable where rare paths carry most of the light (a pixel whose samples
/// all missed them looks both dark and certain), so the significance test is made on block
/// means (4×4 or 8×8 pixels), which hold 16 or 64 times more samples. With `pixel_guard`, gross
/// per-pixel outliers are counted too (not for the naive tracer, whose per-pixel variance
/// estimates at this sample count are meaningless: most of its samples never reach the light).
fn check_against(
    name: &str,
    ours: &(Vec<Rgb>, Vec<Rgb>),
    reference: &(Vec<Rgb>, Vec<Rgb>),
    block: usize,
    pixel_guard: bool,
) {
    let block_z = z_scores(&blocks(ours, block), &blocks(reference, block));
    let z_star = z_critical(block_z.len());
    let (worst, at) =
        block_z.iter().enumerate().map(|(i, z)| (z.abs(), i)).fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a });
    let side = SIZE as usize / block;
    assert!(
        worst < z_star,
        "{name}: block ({}, {}) differs with |z| = {worst:.2} (z* = {z_star:.2})",
        (at / 3) % side,
        (at / 3) / side
    );
    let pixel_z = z_scores(ours, reference);
    let outliers = pixel_z.iter().filter(|z| z.abs() > 4.0).count();
    assert!(
        !pixel_guard || outliers * 200 <= pixel_z.len(),
        "{name}: {outliers} of {} pixel values beyond |z| = 4",
        pixel_z.len()
    );
    let average = |img: &[Rgb]| img.iter().copied().sum::<Rgb>() / img.len() as f32;
    let (a, b) = (average(&ours.0), average(&reference.0));
    for c in 0..3 {
        assert!((a[c] / b[c] - 1.0).abs() < 0.005, "{name}: mean {a} vs {b}");
    }
    eprintln!("{name}: worst {block}×{block} block |z| = {worst:.2} (z* = {z_star:.2}), {outliers} pixel values beyond |z| = 4, mean {a} vs {b}");
}

#[test]
fn bonferroni_critical_values() {
    assert!((z_critical(1) - 2.576).abs() < 1e-3);
    // P(|Z| > 4.36) = 1.3e-5 = 0.01 / 768.
    assert!((z_critical(768) - 4.36).abs() < 0.01, "{}", z_critical(768));
}

/// The Mitsuba reference and its variance at 64². ../shared is part of the test set-up: a
/// missing reference fails the test rather than skipping it.
fn reference() -> (Vec<Rgb>, Vec<Rgb>) {
    let file = reference_dir().join("cbox_256.exr");
    assert!(file.exists(), "the Mitsuba reference must be at {} (../shared/references)", file.display());
    (read_downsampled("cbox_256.exr", false), read_downsampled("cbox_256_var.exr", true))
}

#[test]
fn path_tracer_matches_the_mitsuba_reference_and_the_naive_path_tracer() {
    let reference = reference();
    let path = render_with_variance(IntegratorKind::Path, 1, SPP);
    check_against("path vs Mitsuba", &path, &reference, 4, true);
    // The naive tracer finds the small light only by chance: it needs more samples.
    let naive = render_with_variance(IntegratorKind::PathNaive, 2, 4 * SPP);
    check_against("path-naive vs Mitsuba", &naive, &reference, 8, false);
    check_against("path vs path-naive", &path, &naive, 8, false);
}

/// The light sampled by solid angle (spherical triangles) instead of by area: the same image.
#[test]
fn solid_angle_light_sampling_matches_the_mitsuba_reference() {
    let reference = reference();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box.toml");
    let path = render_configured_with_variance(&scene, IntegratorKind::Path, 3, SPP, |s| {
        s.set_triangle_sampling(TriangleSampling::SolidAngle);
    });
    check_against("path (solid-angle light sampling) vs Mitsuba", &path, &reference, 4, true);
}

/// The same ground truth through the Mitsuba XML reader: ../shared/scenes/cbox.xml, Mitsuba's
/// own file for the reference, read by glint.
#[test]
fn mitsuba_xml_cornell_box_matches_the_mitsuba_reference() {
    let xml = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/scenes/cbox.xml");
    assert!(xml.exists(), "Mitsuba's Cornell box must be at {} (../shared/scenes)", xml.display());
    let reference = reference();
    let loaded = glint_scene::load_scene(&xml).expect("cbox.xml loads");
    assert_eq!(loaded.render.integrator, IntegratorKind::Path);
    assert_eq!(loaded.render.integrator_settings.max_depth, u32::MAX, "max_depth -1 is unbounded");
    let path = render_scene_with_variance(&xml, IntegratorKind::Path, 5, SPP);
    check_against("path (cbox.xml) vs Mitsuba", &path, &reference, 4, true);
}

/// The same ground truth through the pbrt-v4 reader: scenes/cbox.pbrt, the same box written
/// in pbrt's format (left-handed, mirrored back by `Scale -1 1 1`).
#[test]
fn pbrt_cornell_box_matches_the_mitsuba_reference() {
    let reference = reference();
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cbox.pbrt");
    let loaded = glint_scene::load_scene(&file).expect("cbox.pbrt loads");
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    assert_eq!(loaded.render.integrator, IntegratorKind::Path);
    assert_eq!(loaded.render.integrator_settings.max_depth, 101, "pbrt's maxdepth 100 is 101 segments");
    let path = render_scene_with_variance(&file, IntegratorKind::Path, 6, SPP);
    check_against("path (cbox.pbrt) vs Mitsuba", &path, &reference, 4, true);
}
