//! Whitted ray tracing against answers known in closed form.

mod common;

use common::{object_with, scene};
use glint_core::geometry::Ray;
use glint_core::integrators::recorder::{RayKind, RayTree};
use glint_core::integrators::{SampleContext, Whitted};
use glint_core::lights::{DirectionalLight, Environment, Falloff, Light, PointLight};
use glint_core::materials::{Fresnel, Material, Phong};
use glint_core::sampling::Rng;
use glint_core::scene::Scene;
use glint_core::shapes::{AaBox, Polygon, Shape, Sphere};
use glint_core::textures::Texture;
use glint_core::{Rgb, Vec3};

fn phong(diffuse: Rgb) -> Phong {
    Phong { diffuse: Texture::Constant(diffuse), ambient: Some(Texture::Constant(Rgb::ZERO)), ..Phong::default() }
}

fn whitted(max_depth: u32) -> Whitted {
    Whitted::new(max_depth, 0.0, false)
}

fn trace(w: &Whitted, s: &Scene, ray: &Ray) -> (Rgb, RayTree) {
    let mut tree = RayTree::default();
    let mut context = SampleContext::new(Rng::new(0, 0));
    let c = w.trace_camera_ray(s, ray, &mut context, &mut tree);
    (c, tree)
}

fn square(centre: Vec3, half: f32, normal_axis: usize) -> Shape {
    let (a, b) = ((normal_axis + 1) % 3, (normal_axis + 2) % 3);
    let corner = |sa: f32, sb: f32| {
        let mut p = centre;
        p[a] += sa * half;
        p[b] += sb * half;
        p
    };
    Shape::Polygon(
        Polygon::new(vec![corner(-1.0, -1.0), corner(1.0, -1.0), corner(1.0, 1.0), corner(-1.0, 1.0)]).unwrap(),
    )
}

/// A mirror (k_r = 0.6, black otherwise) facing a uniformly lit matte wall: the mirror shows the
/// wall's colour times k_r.
#[test]
fn mirror_returns_the_wall_colour_times_kr() {
    let wall_colour = Rgb::new(0.2, 0.5, 0.8);
    let mut s = scene(vec![
        object_with(square(Vec3::new(0.0, 0.0, 5.0), 1.0, 2), 0), // mirror at z = 5
        object_with(square(Vec3::new(0.0, 0.0, -5.0), 50.0, 2), 1), // wall behind the eye
    ]);
    s.set_named_materials(vec![
        (
            "mirror".into(),
            Material::Phong(Phong { reflection: Texture::Constant(Rgb::splat(0.6)), ..phong(Rgb::ZERO) }),
        ),
        // Ambient-only wall: k_a = wall colour, I_a = 1, no lights: its radiance is its colour.
        ("wall".into(), Material::Phong(Phong { ambient: Some(Texture::Constant(wall_colour)), ..phong(Rgb::ONE) })),
    ]);
    s.set_environment(Environment { ambient_light: Rgb::ONE, ..s.environment().clone() });
    let (c, tree) = trace(&whitted(3), &s, &Ray::new(Vec3::ZERO, Vec3::new(0.1, 0.05, 1.0).normalize()));
    assert!((c - 0.6 * wall_colour).abs().max_element() < 1e-6, "{c}");
    assert_eq!(tree.rays.iter().map(|r| r.kind).collect::<Vec<_>>(), [RayKind::Camera, RayKind::Reflection]);
}

fn glass() -> Material {
    Material::Phong(Phong { transmission: Texture::Constant(Rgb::ONE), ior: 1.5, ..phong(Rgb::ZERO) })
}

/// Through a glass slab of thickness d at incidence θ: the ray leaves parallel to its entry
/// direction, displaced sideways by d·sin(θ − θ_t)/cos θ_t.
#[test]
fn glass_slab_displaces_a_ray_by_snells_law() {
    let thickness = 2.0;
    let mut s = scene(vec![object_with(
        Shape::AaBox(AaBox::new(Vec3::new(-100.0, -100.0, 0.0), Vec3::new(100.0, 100.0, thickness))),
        0,
    )]);
    s.set_materials(vec![glass()]);
    let theta = 40f32.to_radians();
    let incident = Vec3::new(theta.sin(), 0.0, theta.cos());
    let (_, tree) = trace(&whitted(4), &s, &Ray::new(Vec3::new(0.0, 0.0, -1.0), incident));
    let kinds: Vec<_> = tree.rays.iter().map(|r| r.kind).collect();
    assert_eq!(kinds, [RayKind::Camera, RayKind::Refraction, RayKind::Refraction], "{tree:#?}");
    let exit = &tree.rays[2];
    let direction = exit.ray.direction.normalize();
    assert!((direction - incident).length() < 1e-5, "exit {direction} vs entry {incident}");
    // Perpendicular distance between the entry line and the exit line.
    let theta_t = (theta.sin() / 1.5).asin();
    let expected = thickness * (theta - theta_t).sin() / theta_t.cos();
    let offset = exit.ray.origin - Vec3::new(0.0, 0.0, -1.0);
    let displacement = (offset - offset.dot(incident) * incident).length();
    assert!((displacement - expected).abs() < 1e-4, "displacement {displacement}, Snell says {expected}");
}

/// Inside glass, beyond the critical angle (41.8° for n = 1.5), nothing is transmitted: the ray
/// reflects with all of k_r + k_t.
#[test]
fn total_internal_reflection_past_the_critical_angle() {
    let mut s = scene(vec![object_with(
        Shape::AaBox(AaBox::new(Vec3::new(-100.0, -100.0, -100.0), Vec3::new(100.0, 100.0, 0.0))),
        0,
    )]);
    s.set_materials(vec![glass()]);
    for (degrees, tir) in [(45.0f32, true), (60.0, true), (38.0, false)] {
        let theta = degrees.to_radians();
        let ray = Ray::new(Vec3::new(0.0, 0.0, -1.0), Vec3::new(theta.sin(), 0.0, theta.cos()));
        let (_, tree) = trace(&whitted(1), &s, &ray);
        let children: Vec<_> = tree.rays[1..].iter().map(|r| (r.kind, r.weight)).collect();
        if tir {
            assert_eq!(children, [(RayKind::Reflection, Rgb::ONE)], "at {degrees}°");
        } else {
            assert_eq!(children, [(RayKind::Refraction, Rgb::ONE)], "at {degrees}°");
        }
    }
}

fn lit_floor_with_blocker(blocker_transmission: f32, transparent_shadows: bool) -> Rgb {
    let mut s = scene(vec![
        object_with(square(Vec3::ZERO, 10.0, 1), 0),              // floor y = 0
        object_with(square(Vec3::new(0.0, 2.0, 0.0), 0.5, 1), 1), // blocker above the origin
    ]);
    s.set_materials(vec![
        Material::Phong(phong(Rgb::splat(0.5))),
        Material::Phong(Phong {
            transmission: Texture::Constant(Rgb::splat(blocker_transmission)),
            ..phong(Rgb::ZERO)
        }),
    ]);
    s.set_lights(vec![Light::Point(PointLight {
        position: Vec3::new(0.0, 4.0, 0.0),
        intensity: Rgb::ONE,
        falloff: Falloff::None,
    })]);
    let w = Whitted::new(0, 0.0, transparent_shadows);
    // Look straight down at the origin, from below the blocker.
    trace(&w, &s, &Ray::new(Vec3::new(0.0, 1.0, 0.0), -Vec3::Y)).0
}

#[test]
fn a_point_in_shadow_gets_nothing_from_the_blocked_light() {
    assert_eq!(lit_floor_with_blocker(0.0, false), Rgb::ZERO);
    // Opaque shadows ignore transmission.
    assert_eq!(lit_floor_with_blocker(0.3, false), Rgb::ZERO);
}

#[test]
fn transparent_shadows_attenuate_by_exactly_the_transmission() {
    let unblocked = 0.5; // k_d · I · (N·L) = 0.5 · 1 · 1
    let c = lit_floor_with_blocker(0.3, true);
    assert!((c - Rgb::splat(0.3 * unblocked)).abs().max_element() < 1e-6, "{c}");
    assert_eq!(lit_floor_with_blocker(0.0, true), Rgb::ZERO);
}

/// Two parallel mirrors with k_r = 0.5: the n-th reflection carries weight 0.5ⁿ, so a threshold
/// of 0.1 allows 0.5, 0.25, 0.125 and stops before 0.0625: exactly 3 reflection rays.
#[test]
fn contribution_threshold_stops_at_the_predicted_depth() {
    let mut s = scene(vec![
        object_with(square(Vec3::new(0.0, 0.0, -1.0), 100.0, 2), 0),
        object_with(square(Vec3::new(0.0, 0.0, 1.0), 100.0, 2), 0),
    ]);
    s.set_materials(vec![Material::Phong(Phong {
        reflection: Texture::Constant(Rgb::splat(0.5)),
        ..phong(Rgb::splat(0.2))
    })]);
    let ray = Ray::new(Vec3::ZERO, Vec3::new(0.05, 0.0, 1.0).normalize());
    let w = Whitted::new(100, 0.1, false);
    let (_, tree) = trace(&w, &s, &ray);
    let reflections = tree.rays.iter().filter(|r| r.kind == RayKind::Reflection).count();
    assert_eq!(reflections, 3);
    assert_eq!(tree.rays.iter().map(|r| r.depth).max(), Some(3));
    // And the depth limit alone, with no threshold: exactly max_depth generations.
    let (_, tree) = trace(&Whitted::new(7, 0.0, false), &s, &ray);
    assert_eq!(tree.rays.len(), 8);
}

#[test]
fn fresnel_weights_follow_the_angle() {
    let mut s = scene(vec![object_with(Shape::Sphere(Sphere::new(Vec3::new(0.0, 0.0, 5.0), 1.0)), 0)]);
    s.set_materials(vec![Material::Phong(Phong {
        transmission: Texture::Constant(Rgb::ONE),
        fresnel: Fresnel::Exact,
        ..phong(Rgb::ZERO)
    })]);
    let (_, tree) = trace(&whitted(1), &s, &Ray::new(Vec3::ZERO, Vec3::Z));
    // Head-on: 4 % reflected, 96 % transmitted.
    let w: Vec<_> = tree.rays[1..].iter().map(|r| (r.kind, r.weight.x)).collect();
    assert_eq!(w.len(), 2);
    assert!((w[0].1 - 0.04).abs() < 1e-5 && (w[1].1 - 0.96).abs() < 1e-5, "{w:?}");
    // A directional light adds nothing here: the glass has no diffuse or specular term.
    s.set_lights(vec![Light::Directional(DirectionalLight { direction: Vec3::Z, intensity: Rgb::ONE })]);
    assert_eq!(trace(&whitted(0), &s, &Ray::new(Vec3::ZERO, Vec3::Z)).0, Rgb::ZERO);
}
