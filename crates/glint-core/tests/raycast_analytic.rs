//! Ray casting against values computed by hand.

mod common;

use common::{object, scene};
use glint_core::integrators::{IntegratorKind, Raycast};
use glint_core::lights::{DirectionalLight, Environment, Falloff, Light, PointLight};
use glint_core::materials::{Material, Phong};
use glint_core::render::{render, RenderSettings};
use glint_core::shapes::{Shape, Sphere};
use glint_core::{Rgb, Vec3};

/// A Lambert sphere lit by a directional light, seen along −z... by pixel: the centre pixel's
/// ray hits the sphere where N = (0, 0, −1); light from direction L makes k_d·I·(N·L).
#[test]
fn lambert_sphere_under_a_directional_light() {
    let mut s = scene(vec![object(Shape::Sphere(Sphere::new(Vec3::ZERO, 1.0)))]);
    let kd = Rgb::new(0.5, 0.25, 0.8);
    let ka = Rgb::new(0.1, 0.2, 0.3);
    s.set_material(0, Material::Phong(Phong { ambient: Some(ka.into()), diffuse: kd.into(), ..Phong::default() }));
    s.set_environment(Environment {
        ambient_light: Rgb::splat(0.5),
        background: Rgb::new(0.0, 0.0, 1.0),
        ..s.environment().clone()
    });
    // The light travels along (1, 0, 2)/√5: toward the sphere's −z side from the front-left.
    let travel = Vec3::new(1.0, 0.0, 2.0).normalize();
    s.set_lights(vec![Light::Directional(DirectionalLight { direction: travel, intensity: Rgb::splat(2.0) })]);
    // 16×16 at 45°: pixel (8, 8)'s centre is at film (8.5, 8.5), a little off the axis. Use an
    // odd size so one pixel centre lies exactly on the axis.
    s.set_camera(s.camera().with_resolution(15, 15));
    let out = render(&s, &Raycast, &RenderSettings::default(), &|| {});

    let n = Vec3::new(0.0, 0.0, -1.0);
    let expected = ka * 0.5 + kd * 2.0 * n.dot(-travel);
    let got = out.film.pixel(7, 7);
    assert!((got - expected).abs().max_element() < 1e-5, "got {got}, expected {expected}");
    // A corner pixel misses the sphere and sees the background.
    assert_eq!(out.film.pixel(0, 0), Rgb::new(0.0, 0.0, 1.0));
    assert_eq!(out.rays.camera, 15 * 15);
    assert_eq!(out.rays.total(), 15 * 15);
}

/// The raycaster has no shadows: a light behind an occluder still lights the point.
#[test]
fn ray_casting_casts_no_shadows() {
    let mut s = scene(vec![
        object(Shape::Sphere(Sphere::new(Vec3::ZERO, 1.0))),
        object(Shape::Sphere(Sphere::new(Vec3::new(0.0, 0.0, -3.0), 0.5))),
    ]);
    s.set_lights(vec![Light::Point(PointLight {
        position: Vec3::new(0.0, 0.0, -2.0),
        intensity: Rgb::ONE,
        falloff: Falloff::None,
    })]);
    let ray = glint_core::geometry::Ray::new(Vec3::new(0.0, 0.0, -1.4), Vec3::Z);
    let mut context = glint_core::integrators::SampleContext::new(glint_core::sampling::Rng::new(0, 0));
    use glint_core::integrators::Integrator;
    let l = Raycast.radiance(&s, &ray, &mut context);
    assert!((l - Rgb::splat(0.8)).abs().max_element() < 1e-5, "{l}");
}

#[test]
fn same_seed_same_image_at_any_thread_count() {
    let mut s = scene(vec![object(Shape::Sphere(Sphere::new(Vec3::ZERO, 1.0)))]);
    s.set_lights(vec![Light::Directional(DirectionalLight { direction: Vec3::Z, intensity: Rgb::ONE })]);
    s.set_camera(s.camera().with_resolution(40, 30));
    let settings = RenderSettings { spp: 8, seed: 7, ..Default::default() };
    let integrator = IntegratorKind::Raycast.create(&Default::default()).expect("a camera integrator");
    let images: Vec<_> = [1, 2, 3]
        .iter()
        .map(|&threads| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| render(&s, integrator.as_ref(), &settings, &|| {}).film.to_rgb())
        })
        .collect();
    assert!(images.windows(2).all(|w| w[0] == w[1]));
    // A different seed moves the jittered samples: the silhouette pixels change.
    let other = render(&s, integrator.as_ref(), &RenderSettings { spp: 8, seed: 8, ..Default::default() }, &|| {})
        .film
        .to_rgb();
    assert_ne!(images[0], other);
}
