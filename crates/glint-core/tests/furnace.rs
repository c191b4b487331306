//! Furnace test: a camera inside a closed sphere whose inside is diffuse with albedo ρ and emits
//! radiance L_e sees, in every direction, L = L_e / (1 − ρ) (the geometric series of bounces).
//! Every Monte Carlo integrator, with every sampler, must match it within its noise: the path tracers and light
//! tracing (unbiased) by a Z-test on the image mean, photon mapping and SPPM (consistent; in a
//! sphere a photon search disk of radius r covers exactly the cap area πr², so their density
//! estimates have no bias here) within 2 %.

mod common;

use common::{object_with, scene};
use glint_core::integrators::{IntegratorKind, IntegratorSettings};
use glint_core::materials::{Material, Phong};
use glint_core::render::{render_with, RenderSettings};
use glint_core::sampling::SamplerKind;
use glint_core::shapes::{Shape, Sphere};
use glint_core::textures::Texture;
use glint_core::Named;
use glint_core::{Rgb, Vec3};

fn furnace(albedo: f32, emission: f32) -> glint_core::scene::Scene {
    let mut s = scene(vec![object_with(Shape::Sphere(Sphere::new(Vec3::ZERO, 1.0)), 0)]);
    s.set_materials(vec![Material::Phong(Phong {
        diffuse: Texture::Constant(Rgb::splat(albedo)),
        ambient: Some(Texture::Constant(Rgb::ZERO)),
        emission: Rgb::splat(emission),
        two_sided_emission: true,
        ..Phong::default()
    })]);
    s.set_camera(
        glint_core::camera::Camera::new(Vec3::new(0.1, -0.2, 0.05), Vec3::new(1.0, 0.3, 0.7), Vec3::Y, 70.0, 24, 24)
            .unwrap(),
    );
    s
}

#[test]
fn every_path_integrator_matches_the_analytic_furnace() {
    for (albedo, emission) in [(0.5f32, 1.0f32), (0.8, 0.25)] {
        let s = furnace(albedo, emission);
        assert!(s.lights().area_count() > 0, "the emitting sphere must be sampled as a light");
        let expected = emission / (1.0 - albedo);
        // Every camera integrator with every sampler; the particle integrators draw their own
        // streams.
        let runs = SamplerKind::ALL
            .iter()
            .copied()
            .flat_map(|sampler| [(IntegratorKind::Path, sampler), (IntegratorKind::PathNaive, sampler)])
            .chain(
                [IntegratorKind::Light, IntegratorKind::Photon, IntegratorKind::Sppm]
                    .map(|k| (k, SamplerKind::default())),
            );
        for (kind, sampler) in runs {
            let mut settings = IntegratorSettings { max_depth: u32::MAX, rr_depth: 3, ..Default::default() };
            settings.photon.global_photons = 50_000;
            settings.photon.final_gather = 4;
            let spp = if kind == IntegratorKind::Photon { 16 } else { 64 };
            let mut renderer = kind.renderer(&settings, &s, 3).expect("the furnace has a light");
            let image = render_with(
                &s,
                renderer.as_mut(),
                &RenderSettings { spp, seed: 3, sampler, ..Default::default() },
                &|| {},
            )
            .film
            .to_rgb();
            // Pixels are independent estimates of the same value: compare their mean with its
            // standard error.
            let values: Vec<f64> = image.iter().map(|p| p.x as f64).collect();
            let n = values.len() as f64;
            let mean = values.iter().sum::<f64>() / n;
            let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
            let standard_error = (variance / n).sqrt();
            let z = (mean - expected as f64) / standard_error;
            let unbiased = matches!(kind, IntegratorKind::Path | IntegratorKind::PathNaive | IntegratorKind::Light);
            assert!(
                !unbiased || z.abs() < 4.0,
                "{kind:?} ({sampler:?}) ρ={albedo}: mean {mean}, expected {expected}, z = {z:.2}"
            );
            assert!((mean / expected as f64 - 1.0).abs() < 0.02, "{kind:?} ({sampler:?}): {mean} vs {expected}");
        }
    }
}
