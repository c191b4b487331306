//! Whitted's reading of the BSDF set against path tracing, where the two must agree.
//!
//! The convention (docs/scene-format.md, Whitted's paragraph): Whitted's local term for a light
//! of intensity I is k_d·(N·L)·I with k_d the albedo, as the course writes it; the path tracers'
//! is the BSDF's ρ/π·(N·L)·I. So direct light from a point or directional light on a diffuse
//! surface is π times brighter under Whitted, for the course's material and the BSDF set alike,
//! while everything a mirror or a refraction carries (child rays, the background) agrees
//! exactly, or on average where path tracing chooses one branch by roulette.

mod common;

use std::f32::consts::PI;

use common::{object_with, scene};
use glint_core::geometry::Ray;
use glint_core::integrators::recorder::{RayKind, RayTree};
use glint_core::integrators::{Integrator, IntegratorSettings, PathTracer, SampleContext, Whitted};
use glint_core::lights::{Environment, Falloff, Light, PointLight};
use glint_core::materials::{
    fresnel_dielectric, Conductor, Dielectric, Diffuse, DiffuseTransmission, Material, Phong, Plastic, Principled,
    ThinDielectric, TwoSided,
};
use glint_core::sampling::Rng;
use glint_core::scene::Scene;
use glint_core::shapes::{AaBox, Polygon, Shape};
use glint_core::textures::Texture;
use glint_core::{Rgb, Vec3};

/// A square of side 2·`half` at height `y`, facing +y (its front, for one-sided members).
fn floor(y: f32, half: f32) -> Shape {
    let corner = |x: f32, z: f32| Vec3::new(x * half, y, z * half);
    Shape::Polygon(
        Polygon::new(vec![corner(-1.0, -1.0), corner(-1.0, 1.0), corner(1.0, 1.0), corner(1.0, -1.0)]).unwrap(),
    )
}

fn whitted() -> Whitted {
    Whitted::new(40, 0.0, false)
}

fn path() -> PathTracer {
    // No Russian roulette: every path runs to its end, so the only noise is the lobe choice.
    PathTracer::new(&IntegratorSettings { max_depth: 40, rr_depth: 1000, ..Default::default() })
}

fn trace(s: &Scene, ray: &Ray) -> (Rgb, RayTree) {
    let mut tree = RayTree::default();
    let mut context = SampleContext::new(Rng::new(0, 0));
    let radiance = whitted().trace_camera_ray(s, ray, &mut context, &mut tree);
    (radiance, tree)
}

/// The path tracer's mean radiance along `ray` over `samples` independent samples, and the
/// mean's standard error (per channel).
fn path_mean(s: &Scene, ray: &Ray, samples: u64) -> (Rgb, Rgb) {
    let tracer = path();
    let (mut sum, mut sum2) = (Rgb::ZERO, Rgb::ZERO);
    for i in 0..samples {
        let mut context = SampleContext::new(Rng::new(7, i));
        let l = tracer.radiance(s, ray, &mut context);
        sum += l;
        sum2 += l * l;
    }
    let n = samples as f32;
    let mean = sum / n;
    let variance = (sum2 / n - mean * mean).max(Rgb::ZERO);
    (mean, (variance / n).powf(0.5))
}

fn grey(v: f32) -> Texture {
    Texture::Constant(Rgb::splat(v))
}

/// A ray from above onto the origin of the floor y = 0, at `degrees` from its normal.
fn ray_onto_floor(degrees: f32) -> Ray {
    let theta = degrees.to_radians();
    let direction = Vec3::new(theta.sin(), -theta.cos(), 0.0);
    Ray::new(-2.0 * direction, direction)
}

/// glTF's materials are principled; with metallic 0, roughness 1 and no transmission (the
/// default material) it is a dielectric coat over a diffuse base. Its mirror ray carries the
/// dielectric Fresnel reflectance at the angle of incidence, F(θ) for η = 1.5 (4 % head-on),
/// as the BSDF's specular lobe does in its smooth limit: not 1, which made every glTF material
/// a perfect mirror under Whitted.
#[test]
fn a_principled_dielectrics_mirror_ray_carries_its_fresnel_reflectance() {
    let mut s = scene(vec![object_with(floor(0.0, 100.0), 0)]);
    s.set_materials(vec![Material::Principled(Box::new(Principled {
        base_color: Texture::Constant(Rgb::new(0.8, 0.6, 0.4)),
        roughness: grey(1.0),
        metallic: grey(0.0),
        spec_trans: grey(0.0),
        ..Principled::default()
    }))]);
    for degrees in [0.0f32, 30.0, 60.0, 80.0] {
        let (_, tree) = trace(&s, &ray_onto_floor(degrees));
        let children: Vec<_> = tree.rays[1..].iter().filter(|r| r.depth == 1).collect();
        assert_eq!(children.len(), 1, "one mirror ray, nothing refracted, at {degrees}°: {tree:#?}");
        assert_eq!(children[0].kind, RayKind::Reflection);
        let fresnel = fresnel_dielectric(degrees.to_radians().cos(), 1.0 / 1.5);
        let weight = children[0].weight;
        assert!((weight - Rgb::splat(fresnel)).abs().max_element() < 1e-5, "at {degrees}°: {weight} vs F = {fresnel}");
    }
}

/// The Whitted and path-traced radiance along `ray`: one path sample, which is exact where
/// path tracing chooses nothing by chance that changes the result.
fn both(s: &Scene, ray: &Ray) -> (Rgb, Rgb) {
    let mut context = SampleContext::new(Rng::new(3, 0));
    (trace(s, ray).0, path().radiance(s, ray, &mut context))
}

fn close(a: Rgb, b: Rgb, relative: f32) -> bool {
    (a - b).abs().max_element() <= relative * a.abs().max_element().max(b.abs().max_element()).max(1e-6)
}

/// Direct light from a point light on a diffuse surface: Whitted's k_d·(N·L)·I/d² is π times
/// the path tracer's ρ/π·(N·L)·I/d², for the course's material and each diffuse member alike.
/// With a black background the path tracer's only light is its light sample, so one sample
/// gives the exact value. The plastic's base lies under its coat: the light crosses it twice,
/// (1 − F(θ_i))(1 − F(θ_o))/η², for Whitted as for the BSDF; a diffuse transmitter is lit
/// through by a light behind it.
#[test]
fn direct_light_on_a_diffuse_surface_is_pi_times_path_tracings() {
    let above = Vec3::new(0.5, 2.0, -0.3);
    let below = Vec3::new(-0.4, -1.5, 0.6);
    let diffuse = || Material::Diffuse(Diffuse { reflectance: grey(0.6) });
    let cases = [
        ("phong", Material::Phong(Phong { diffuse: grey(0.6), ambient: Some(grey(0.0)), ..Phong::default() }), above),
        ("diffuse", diffuse(), above),
        (
            "plastic",
            Material::Plastic(Plastic { diffuse: grey(0.6), specular: grey(1.0), eta: 1.49, nonlinear: false }),
            above,
        ),
        (
            "diffuse-transmission",
            Material::DiffuseTransmission(DiffuseTransmission { reflectance: grey(0.3), transmittance: grey(0.5) }),
            below,
        ),
        (
            "diffuse-transmission lit on the viewer's side",
            Material::DiffuseTransmission(DiffuseTransmission { reflectance: grey(0.3), transmittance: grey(0.5) }),
            above,
        ),
        (
            "two-sided diffuse, lit from behind",
            Material::TwoSided(Box::new(TwoSided { front: diffuse(), back: diffuse() })),
            below,
        ),
    ];
    for (name, material, light) in cases {
        let mut s = scene(vec![object_with(floor(0.0, 100.0), 0)]);
        s.set_materials(vec![material]);
        s.set_lights(vec![Light::Point(PointLight {
            position: light,
            intensity: Rgb::new(3.0, 2.0, 1.0),
            falloff: Falloff::InverseSquare,
        })]);
        // Seen from the light's side (the two-sided case from below, looking up at its back).
        let ray = if light.y > 0.0 {
            ray_onto_floor(35.0)
        } else {
            Ray::new(Vec3::new(-1.0, -1.5, 0.2), Vec3::new(1.0, 1.5, -0.2))
        };
        let (whitted, path) = both(&s, &ray);
        assert!(path.max_element() > 0.0, "{name}: lit");
        assert!(close(whitted, PI * path, 1e-4), "{name}: Whitted {whitted}, π × path {}", PI * path);
        if name == "diffuse" {
            let cos = light.normalize().y;
            let expected = Rgb::new(3.0, 2.0, 1.0) * (0.6 * cos / light.length_squared());
            assert!(close(whitted, expected, 1e-5), "{whitted} vs k_d (N·L) I / d² = {expected}");
        }
    }
    // A one-sided member from behind is black to both.
    let mut s = scene(vec![object_with(floor(0.0, 100.0), 0)]);
    s.set_materials(vec![diffuse()]);
    s.set_lights(vec![Light::Point(PointLight {
        position: below,
        intensity: Rgb::ONE,
        falloff: Falloff::InverseSquare,
    })]);
    let (whitted, path) = both(&s, &Ray::new(Vec3::new(-1.0, -1.5, 0.2), Vec3::new(1.0, 1.5, -0.2)));
    assert_eq!((whitted, path), (Rgb::ZERO, Rgb::ZERO));
}

/// A perfect mirror shows exactly what path tracing shows: the background times the mirror's
/// reflectance at the angle (1 for Mitsuba's perfect mirror, η = 0 and k = 1; gold's Fresnel
/// reflectance; the course's k_r).
#[test]
fn a_perfect_mirror_agrees_with_path_tracing_exactly() {
    let (gold_eta, gold_k) = glint_core::materials::named_metal("Au").unwrap();
    let cases = [
        ("perfect conductor", Material::Conductor(Conductor { eta: Rgb::ZERO, k: Rgb::ONE, specular: grey(1.0) })),
        ("gold", Material::Conductor(Conductor { eta: gold_eta, k: gold_k, specular: grey(1.0) })),
        (
            "phong mirror",
            Material::Phong(Phong {
                diffuse: grey(0.0),
                reflection: grey(1.0),
                ambient: Some(grey(0.0)),
                ..Phong::default()
            }),
        ),
    ];
    let background = Rgb::new(0.2, 0.5, 0.9);
    for (name, material) in cases {
        let mut s = scene(vec![object_with(floor(0.0, 100.0), 0)]);
        s.set_materials(vec![material]);
        s.set_environment(Environment { background, ..Environment::BLACK });
        for degrees in [0.0f32, 40.0, 75.0] {
            let (whitted, path) = both(&s, &ray_onto_floor(degrees));
            assert!(close(whitted, path, 1e-5), "{name} at {degrees}°: Whitted {whitted}, path {path}");
            if name == "perfect conductor" {
                assert!(close(whitted, background, 1e-5), "{whitted}");
            }
        }
    }
}

/// Smooth glass, a slab over a black floor under a blue sky: Whitted follows both the
/// reflected and the refracted ray with their Fresnel weights; path tracing follows one, chosen
/// with the Fresnel probability. Their means agree within the path tracer's noise (the light
/// that leaves the slab upward, after any number of internal reflections). A pane of thin
/// glass and principled glass (spec_trans 1, roughness 0: its smooth limit) the same way.
#[test]
fn smooth_glass_agrees_with_path_tracing_on_average() {
    let slab = Shape::AaBox(AaBox::new(Vec3::new(-50.0, -1.0, -50.0), Vec3::new(50.0, 0.0, 50.0)));
    let black = Shape::AaBox(AaBox::new(Vec3::new(-60.0, -5.0, -60.0), Vec3::new(60.0, -2.0, 60.0)));
    let glass = || Dielectric { eta: 1.5, specular_reflectance: grey(1.0), specular_transmittance: grey(1.0) };
    let cases = [
        ("dielectric", slab.clone(), Material::Dielectric(glass())),
        (
            "tinted dielectric",
            slab.clone(),
            Material::Dielectric(Dielectric {
                specular_reflectance: Texture::Constant(Rgb::new(0.9, 0.7, 0.5)),
                specular_transmittance: Texture::Constant(Rgb::new(0.5, 0.8, 1.0)),
                ..glass()
            }),
        ),
        ("thin dielectric", floor(0.0, 50.0), Material::ThinDielectric(ThinDielectric { sheet: glass() })),
        (
            "principled glass",
            slab,
            Material::Principled(Box::new(Principled {
                base_color: grey(1.0),
                roughness: grey(0.0),
                spec_trans: grey(1.0),
                ..Principled::default()
            })),
        ),
    ];
    let background = Rgb::new(0.2, 0.5, 0.9);
    for (name, shape, material) in cases {
        let mut s = scene(vec![object_with(shape, 0), object_with(black.clone(), 1)]);
        s.set_materials(vec![material, Material::Diffuse(Diffuse { reflectance: grey(0.0) })]);
        s.set_environment(Environment { background, ..Environment::BLACK });
        for degrees in [0.0f32, 50.0, 80.0] {
            let ray = ray_onto_floor(degrees);
            let whitted = trace(&s, &ray).0;
            let (mean, error) = path_mean(&s, &ray, 40_000);
            for c in 0..3 {
                let z = (whitted[c] - mean[c]) / error[c].max(1e-4);
                assert!(z.abs() < 4.5, "{name} at {degrees}°, channel {c}: Whitted {whitted}, path {mean} ± {error}");
            }
            assert!(whitted.max_element() > 0.01, "{name} at {degrees}°: the sky's reflection shows");
        }
    }
}
