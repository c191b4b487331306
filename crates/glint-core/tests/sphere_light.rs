//! A spherical light over a Lambertian floor, an analytic scene: the irradiance directly below
//! a sphere of radiance L and radius r whose centre is at height h is E = π L r²/h² (the cap it
//! subtends, cosine-weighted), so the floor (albedo ρ) reflects L_o = ρ L r²/h². Direct light
//! only (`max_depth` 1). The path tracer (the sphere sampled by the cone it subtends, with MIS)
//! and the naive one (the sphere found only by hitting it) must both match it. Shadow rays that
//! ended on the sphere's surface found it a few ulps early and were blocked 2 % of the time,
//! which this caught: `SurfaceHit::spawn_ray_to_surface`.

mod common;

use common::{object_with, scene};
use glint_core::camera::Camera;
use glint_core::integrators::{IntegratorKind, IntegratorSettings};
use glint_core::lights::AreaLights;
use glint_core::materials::{Material, Phong};
use glint_core::render::{render_with, RenderSettings};
use glint_core::shapes::{Plane, Shape, Sphere};
use glint_core::textures::Texture;
use glint_core::{Rgb, Vec3};

#[test]
fn a_floor_under_a_spherical_light_has_the_analytic_radiance() {
    let (radiance, radius, height, albedo) = (4.0f32, 0.5f32, 2.0f32, 0.5f32);
    let mut s = scene(vec![
        object_with(Shape::Plane(Plane::new(Vec3::Y, 0.0)), 0),
        object_with(Shape::Sphere(Sphere::new(Vec3::new(0.0, height, 0.0), radius)), 1),
    ]);
    let material = |diffuse: f32, emission: f32| {
        Material::Phong(Phong {
            diffuse: Texture::Constant(Rgb::splat(diffuse)),
            ambient: Some(Texture::Constant(Rgb::ZERO)),
            emission: Rgb::splat(emission),
            ..Phong::default()
        })
    };
    s.materials = vec![material(albedo, 0.0), material(0.0, radiance)];
    s.area_lights = AreaLights::new(s.objects(), &s.materials);
    // A narrow view of the floor point below the centre, from the side, under the sphere.
    s.camera = Camera::new(Vec3::new(0.0, 1.0, -2.0), Vec3::ZERO, Vec3::Y, 0.2, 8, 8).unwrap();
    let expected = (albedo * radiance * radius * radius / (height * height)) as f64;

    for (kind, spp) in [(IntegratorKind::Path, 64), (IntegratorKind::PathNaive, 1024)] {
        let settings = IntegratorSettings { max_depth: 1, rr_depth: 5, ..Default::default() };
        let mut renderer = kind.renderer(&settings, &s, 1).expect("a camera integrator");
        let image = render_with(&s, renderer.as_mut(), &RenderSettings { spp, seed: 9, ..Default::default() }, &|| {})
            .film
            .to_rgb();
        let values: Vec<f64> = image.iter().map(|p| p.x as f64).collect();
        let n = values.len() as f64;
        let mean = values.iter().sum::<f64>() / n;
        let standard_error = (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt();
        // The pixels see floor points up to 0.01 from the centre, where E is lower by 4·10⁻⁵.
        let tolerance = 4.0 * standard_error + 1e-3 * expected;
        assert!((mean - expected).abs() < tolerance, "{kind:?}: {mean} vs {expected} (± {standard_error})");
    }
}
