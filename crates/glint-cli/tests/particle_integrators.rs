//! The integrators that start at the lights (light tracing, photon mapping, SPPM) converge to
//! the path tracer's image on the Cornell box, a diffuse scene the camera sees directly, and
//! give the same image at any thread count.

use std::path::Path;

use glint_core::integrators::IntegratorKind;
use glint_core::render::{render_with, RenderSettings};
use glint_core::scene::Scene;
use glint_core::Rgb;
use glint_scene::LoadedScene;

const SIZE: u32 = 32;

fn cornell_box() -> LoadedScene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box.toml");
    let mut loaded = glint_scene::load_scene(&path).expect("the Cornell box loads");
    loaded.scene.set_camera(loaded.scene.camera().with_resolution(SIZE, SIZE));
    loaded
}

fn render(loaded: &LoadedScene, scene: &Scene, kind: IntegratorKind, spp: u32, seed: u64) -> Vec<Rgb> {
    let mut settings = loaded.render.integrator_settings;
    settings.photon.final_gather = 8;
    let mut renderer = kind.renderer(&settings, scene, seed).expect("the Cornell box has a light");
    render_with(scene, renderer.as_mut(), &RenderSettings { spp, seed, ..Default::default() }, &|| {}).film.to_rgb()
}

/// The mean over the pixels that do not see the light: a pixel partly covering the bright
/// lamp is far noisier than the rest (its coverage is jittered), and the lamp seen directly
/// is the same emission term in every integrator.
fn mean(image: &[Rgb], lamp: &[bool]) -> Rgb {
    let kept = image.iter().zip(lamp).filter(|(_, &l)| !l).map(|(p, _)| *p);
    kept.clone().sum::<Rgb>() / kept.count() as f32
}

/// Means of 8×8-pixel blocks (16 of them): regions of the box, each lit differently.
fn blocks(image: &[Rgb]) -> Vec<Rgb> {
    let k = 8;
    (0..(SIZE / k) * (SIZE / k))
        .map(|b| {
            let (bx, by) = (b % (SIZE / k), b / (SIZE / k));
            let mut sum = Rgb::ZERO;
            for y in by * k..(by + 1) * k {
                for x in bx * k..(bx + 1) * k {
                    sum += image[(y * SIZE + x) as usize];
                }
            }
            sum / (k * k) as f32
        })
        .collect()
}

#[test]
fn light_tracing_photon_mapping_and_sppm_converge_to_path() {
    let loaded = cornell_box();
    let scene = &loaded.scene;
    let reference = render(&loaded, scene, IntegratorKind::Path, 1024, 1);
    let reference_blocks = blocks(&reference);
    // The lamp's pixels and their neighbours (partly covered ones are as noisy).
    let bright: Vec<bool> = reference.iter().map(|p| p.max_element() > 1.0).collect();
    let lamp: Vec<bool> = (0..(SIZE * SIZE) as i32)
        .map(|i| {
            let (x, y) = (i % SIZE as i32, i / SIZE as i32);
            (-1..=1).any(|dy| {
                (-1..=1).any(|dx| {
                    let (nx, ny) = (x + dx, y + dy);
                    (0..SIZE as i32).contains(&nx)
                        && (0..SIZE as i32).contains(&ny)
                        && bright[(ny * SIZE as i32 + nx) as usize]
                })
            })
        })
        .collect();
    assert!(bright.iter().any(|&l| l) && lamp.iter().filter(|&&l| l).count() < 80);
    let mean = |image: &[Rgb]| mean(image, &lamp);
    // Light tracing is unbiased: its mean is checked against the spread of independent runs.
    let runs: Vec<Rgb> =
        (0..4).map(|seed| mean(&render(&loaded, scene, IntegratorKind::Light, 64, 10 + seed))).collect();
    let light_mean = runs.iter().sum::<Rgb>() / 4.0;
    let spread = runs.iter().map(|m| (*m - light_mean) * (*m - light_mean)).sum::<Rgb>() / 3.0;
    let standard_error = (spread / 4.0).powf(0.5);
    let z = (light_mean - mean(&reference)) / standard_error.max(Rgb::splat(1e-6));
    assert!(z.abs().max_element() < 5.0, "light tracing mean {light_mean} vs path {}, z = {z}", mean(&reference));
    assert!(((light_mean / mean(&reference)) - Rgb::ONE).abs().max_element() < 0.01);

    for (kind, spp, tolerance) in
        [(IntegratorKind::Light, 128, 0.08), (IntegratorKind::Sppm, 512, 0.08), (IntegratorKind::Photon, 8, 0.08)]
    {
        let image = render(&loaded, scene, kind, spp, 2);
        let relative = (mean(&image) / mean(&reference) - Rgb::ONE).abs().max_element();
        assert!(relative < 0.02, "{kind:?}: mean {} vs path {}", mean(&image), mean(&reference));
        // Block by block: the light lands where the path tracer says it does (blocks 1 and 2
        // hold the lamp).
        let mut worst = 0.0f32;
        for (i, (b, r)) in blocks(&image).iter().zip(&reference_blocks).enumerate().filter(|(i, _)| ![1, 2].contains(i))
        {
            let error = (*b - *r).abs().max_element() / r.max_element().max(1e-3);
            worst = worst.max(error);
            assert!(error < tolerance, "{kind:?}: block {i} {b} vs path {r}");
        }
        eprintln!("{kind:?}: worst block error {worst:.3}");
    }
}

#[test]
fn particle_integrators_are_deterministic_at_any_thread_count() {
    let loaded = cornell_box();
    for kind in [IntegratorKind::Light, IntegratorKind::Photon, IntegratorKind::Sppm] {
        let images: Vec<Vec<Rgb>> = [1, 3]
            .iter()
            .map(|&threads| {
                let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
                pool.install(|| render(&loaded, &loaded.scene, kind, 3, 7))
            })
            .collect();
        assert_eq!(images[0], images[1], "{kind:?}");
    }
}
