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

/// Glass that absorbs nothing, under a uniform sky of radiance 1, is invisible to a path
/// tracer: every path in and out of it carries 1. A closed CSG glass piece (seams where balls
/// cut a cube, pits, a hollow, a lens) passes only if no path is lost in it: ended by a
/// degenerate normal, a NaN, or a surface its next ray cannot find. (glint leaves the η² out of
/// refracted radiance, so this cannot see which way a surface faces; the CSG unit tests check
/// that against point classification.)
#[test]
fn closed_csg_glass_vanishes_in_a_uniform_sky() {
    use glint_core::camera::Camera;
    use glint_core::lights::Environment;
    use glint_core::materials::Dielectric;
    use glint_core::scene::SceneBuilder;
    use glint_core::shapes::{AaBox, Csg, CsgOperation, CsgTree};

    let ball = |centre: Vec3, radius: f32| CsgTree::solid(Shape::Sphere(Sphere::new(centre, radius)));
    let cube = CsgTree::solid(Shape::AaBox(AaBox::new(Vec3::splat(-0.6), Vec3::splat(0.6))));
    // A rounded die with two pits and a hollow, beside a lens.
    let die = CsgTree::Combine(
        CsgOperation::Difference,
        vec![
            CsgTree::Combine(CsgOperation::Intersection, vec![cube, ball(Vec3::ZERO, 0.8)]),
            ball(Vec3::new(0.0, 0.0, -0.65), 0.2),
            ball(Vec3::new(0.65, 0.2, 0.0), 0.15),
            ball(Vec3::new(0.1, -0.1, 0.1), 0.3),
        ],
    );
    let lens = CsgTree::Combine(
        CsgOperation::Intersection,
        vec![ball(Vec3::new(0.9, 0.0, -1.0), 1.0), ball(Vec3::new(0.9, 0.0, 0.6), 1.0)],
    );
    let piece = Csg::new(CsgTree::Combine(CsgOperation::Union, vec![die, lens])).unwrap();
    let glass = Material::Dielectric(Dielectric {
        eta: 1.5,
        specular_reflectance: Texture::Constant(Rgb::ONE),
        specular_transmittance: Texture::Constant(Rgb::ONE),
    });
    let camera = Camera::new(Vec3::new(0.3, 0.4, -3.0), Vec3::new(0.3, 0.0, 0.0), Vec3::Y, 40.0, 24, 24).unwrap();
    let s = SceneBuilder::new(camera)
        .object(object_with(Shape::Csg(Box::new(piece)), 0))
        .material("glass", glass)
        .environment(Environment { background: Rgb::ONE, ambient_light: Rgb::ZERO, map: None })
        .build();
    for kind in [IntegratorKind::Path, IntegratorKind::PathNaive] {
        // No roulette and a deep limit: each path is then exactly 1 unless caught inside by
        // total internal reflection for 200 bounces.
        let settings = IntegratorSettings { max_depth: 200, rr_depth: u32::MAX, ..Default::default() };
        let mut renderer = kind.renderer(&settings, &s, 3).expect("the sky lights the scene");
        let settings = RenderSettings { spp: 16, seed: 5, ..Default::default() };
        let image = render_with(&s, renderer.as_mut(), &settings, &|| {}).film.to_rgb();
        let worst = image.iter().map(|p| (p.x - 1.0).abs().max((p.z - 1.0).abs())).fold(0.0f32, f32::max);
        assert!(worst < 1e-3, "{kind:?}: a pixel is {worst} from 1");
    }
}
