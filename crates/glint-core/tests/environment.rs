//! Environment maps: a diffuse sphere under a uniform sky has the analytic radiance ρ·L
//! (a convex body sees the whole sky from every point), and under a sky with a bright sun
//! `path` (which samples the map) and `path-naive` (which only finds it by escaping) agree.

mod common;

use std::sync::Arc;

use common::{object, scene};
use glam::Mat3;
use glint_core::integrators::{IntegratorKind, IntegratorSettings};
use glint_core::lights::{Environment, EnvironmentMap};
use glint_core::render::{render, RenderSettings};
use glint_core::shapes::{Shape, Sphere};
use glint_core::{Rgb, Vec3};

fn sphere_under(map: EnvironmentMap) -> glint_core::scene::Scene {
    let mut s = scene(vec![object(Shape::Sphere(Sphere::new(Vec3::ZERO, 1.0)))]);
    s.set_environment(Environment { map: Some(Arc::new(map)), ..s.environment().clone() });
    s
}

/// The sphere under a constant background `sky` (no map).
fn sphere_under_constant(sky: Rgb) -> glint_core::scene::Scene {
    let mut s = scene(vec![object(Shape::Sphere(Sphere::new(Vec3::ZERO, 1.0)))]);
    s.set_environment(Environment { background: sky, ..s.environment().clone() });
    s
}

fn image(s: &glint_core::scene::Scene, kind: IntegratorKind, spp: u32, seed: u64) -> Vec<Rgb> {
    let settings = IntegratorSettings { max_depth: u32::MAX, ..Default::default() };
    let integrator = kind.create(&settings).expect("a camera integrator");
    render(s, integrator.as_ref(), &RenderSettings { spp, seed, ..Default::default() }, &|| {}).film.to_rgb()
}

#[test]
fn a_diffuse_sphere_under_a_uniform_sky_reflects_albedo_times_sky() {
    let sky = Rgb::new(0.5, 1.0, 2.0);
    let s = sphere_under(EnvironmentMap::new(8, 4, vec![sky; 32], 1.5, Mat3::from_rotation_z(0.3)));
    let img = image(&s, IntegratorKind::Path, 64, 1);
    // Pixel (8, 8) looks at the sphere's centre; pixel (0, 0) at the sky.
    assert_eq!(img[0], sky * 1.5);
    let centre: Rgb = [(7, 7), (7, 8), (8, 7), (8, 8)].iter().map(|&(x, y)| img[y * 16 + x]).sum::<Rgb>() / 4.0;
    let expected = sky * 1.5 * 0.8; // the test material's albedo is 0.8
    assert!(((centre - expected) / expected).abs().max_element() < 0.03, "{centre} vs {expected}");
}

#[test]
fn path_and_path_naive_agree_under_a_sun() {
    let (w, h) = (64u32, 32u32);
    let pixels = (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            if (20..23).contains(&x) && (8..10).contains(&y) {
                Rgb::new(300.0, 280.0, 250.0) // a small sun high in the sky
            } else {
                Rgb::new(0.3, 0.4, 0.6)
            }
        })
        .collect();
    let s = sphere_under(EnvironmentMap::new(w, h, pixels, 1.0, Mat3::IDENTITY));
    let mean = |img: &[Rgb]| img.iter().sum::<Rgb>() / img.len() as f32;
    let path = mean(&image(&s, IntegratorKind::Path, 256, 2));
    let naive = mean(&image(&s, IntegratorKind::PathNaive, 4096, 3));
    assert!(((path - naive) / naive).abs().max_element() < 0.03, "path {path} vs naive {naive}");
}

/// The environment is a light for the integrators that start at the lights too: light tracing,
/// photon mapping and SPPM see the sphere under a uniform sky as ρ·L, whether the sky is a map
/// or a constant background.
#[test]
fn particle_integrators_are_lit_by_the_sky() {
    use glint_core::render::render_with;
    let sky = Rgb::new(0.5, 1.0, 2.0);
    let with_map = sphere_under(EnvironmentMap::new(8, 4, vec![sky; 32], 1.0, Mat3::IDENTITY));
    let constant = sphere_under_constant(sky);
    for (name, s) in [("map", &with_map), ("constant", &constant)] {
        for kind in [IntegratorKind::Path, IntegratorKind::Light, IntegratorKind::Photon, IntegratorKind::Sppm] {
            let mut settings = IntegratorSettings { max_depth: u32::MAX, ..Default::default() };
            settings.photon.global_photons = 20_000;
            settings.photon.final_gather = 4;
            let mut renderer = kind.renderer(&settings, s, 5).expect("the sky is a light");
            let spp = match kind {
                IntegratorKind::Photon => 64,
                // A particle lands in a given pixel rarely; a pass of SPPM shoots as many
                // photons as the 256 pixels. 1024 particles and 64 passes left ±10 % of noise
                // in the six pixels read (seeds 1 to 5), twice the tolerance.
                IntegratorKind::Light => 4096,
                IntegratorKind::Sppm => 1024,
                _ => 64,
            };
            let img = render_with(s, renderer.as_mut(), &RenderSettings { spp, seed: 5, ..Default::default() }, &|| {})
                .film
                .to_rgb();
            let centre: Rgb =
                [(6, 6), (9, 6), (6, 9), (9, 9), (7, 7), (8, 8)].iter().map(|&(x, y)| img[y * 16 + x]).sum::<Rgb>()
                    / 6.0;
            let expected = sky * 0.8;
            assert!(
                ((centre - expected) / expected).abs().max_element() < 0.05,
                "{kind:?} ({name}): {centre} vs {expected}"
            );
        }
    }
}

/// Light tracing against the analytic ρ·L at the sphere's centre, and the sky seen directly,
/// with enough particles to see a bias of 0.75 %: the central 4 × 4 pixels after 32,768 passes
/// have a noise of about 0.24 % (a float64 replica of the estimator: 1.0003 ± 0.0002). The
/// 1.2 % once suspected (issue 23) was the noise of a 1024-pass test (±1.3 %).
#[test]
fn light_tracing_under_a_uniform_sky_is_unbiased() {
    use glint_core::render::render_with;
    let sky = Rgb::new(0.5, 1.0, 2.0);
    let s = sphere_under_constant(sky);
    let settings = IntegratorSettings { max_depth: u32::MAX, ..Default::default() };
    let mut renderer = IntegratorKind::Light.renderer(&settings, &s, 11).expect("the sky is a light");
    let img =
        render_with(&s, renderer.as_mut(), &RenderSettings { spp: 32_768, seed: 11, ..Default::default() }, &|| {})
            .film
            .to_rgb();
    // The sky where the camera sees it: one camera ray per pixel and pass finds it.
    assert!(((img[0] - sky) / sky).abs().max_element() < 1e-4, "{} vs {sky}", img[0]);
    let img = &img;
    let centre = (6..10).flat_map(|y| (6..10).map(move |x| img[y * 16 + x])).sum::<Rgb>() / 16.0;
    let ratio = centre / (sky * 0.8);
    eprintln!("light tracing / analytic = {ratio}");
    assert!((ratio - Rgb::ONE).abs().max_element() < 0.0075, "light tracing / analytic = {ratio}");
}
