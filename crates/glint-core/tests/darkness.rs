//! Why a scene renders black (`Scene::why_dark`): each cause built on purpose, and named.

mod common;

use common::{object, object_with, scene};
use glint_core::lights::{Falloff, Light, PointLight};
use glint_core::materials::{Material, Phong};
use glint_core::scene::{Darkness, Scene};
use glint_core::shapes::{AaBox, Polygon, Shape, Sphere};
use glint_core::{Rgb, Vec3};

/// A square of half-side `half` about `centre`, perpendicular to axis `normal_axis`; its
/// normal points along +axis, or −axis when `flipped`.
fn square(centre: Vec3, half: f32, normal_axis: usize, flipped: bool) -> Shape {
    let (a, b) = ((normal_axis + 1) % 3, (normal_axis + 2) % 3);
    let corner = |sa: f32, sb: f32| {
        let mut p = centre;
        p[a] += sa * half;
        p[b] += sb * half;
        p
    };
    let mut corners = vec![corner(-1.0, -1.0), corner(1.0, -1.0), corner(1.0, 1.0), corner(-1.0, 1.0)];
    if flipped {
        corners.reverse();
    }
    Shape::Polygon(Polygon::new(corners).unwrap())
}

fn point_light(position: Vec3) -> Light {
    Light::Point(PointLight { position, intensity: Rgb::splat(10.0), falloff: Falloff::InverseSquare })
}

/// The white material (index 0) and a one-sided emitter (index 1).
fn with_emitter(mut s: Scene) -> Scene {
    let white = s.material_names()[0].clone();
    let white_material = s.materials()[0].clone();
    let emitter = Phong { emission: Rgb::splat(5.0), ..Phong::default() };
    s.set_named_materials(vec![(white, white_material), ("lamp".into(), Material::Phong(emitter))]);
    s
}

/// The camera (at z = −5, looking along +z) before a wall at z = 5 that faces it.
fn wall() -> Shape {
    square(Vec3::new(0.0, 0.0, 5.0), 20.0, 2, true)
}

#[test]
fn a_scene_without_light_says_so() {
    assert_eq!(scene(vec![object(wall())]).why_dark(false), Darkness::NoLight);
}

/// Ray casting and Whitted read point, spot and directional lights; an emitting surface alone
/// leaves them black, and the message points to `path`.
#[test]
fn whitted_without_a_delta_light_points_to_the_path_tracer() {
    let s = with_emitter(scene(vec![object(wall()), object_with(square(Vec3::new(0.0, 3.0, 0.0), 1.0, 1, true), 1)]));
    let verdict = s.why_dark(true);
    assert_eq!(verdict, Darkness::NoDeltaLight { area_lights: 1, environment: false });
    assert!(verdict.to_string().contains("--integrator path"), "{verdict}");
    assert_ne!(s.why_dark(false), verdict);
}

#[test]
fn a_camera_inside_a_closed_object_is_named() {
    let mut s = scene(vec![object(Shape::Sphere(Sphere::new(Vec3::new(0.0, 0.0, -5.0), 1.0))), object(wall())]);
    s.set_lights(vec![point_light(Vec3::new(0.0, 0.0, 0.0))]);
    let verdict = s.why_dark(false);
    assert_eq!(verdict, Darkness::CameraInside { object: "sphere".into() });
}

/// A ceiling lamp that faces up, over a floor: the floor is behind the lamp's emitting side.
/// Turned down, light falls on the floor, and the verdict changes.
#[test]
fn a_lamp_facing_away_is_told_apart_from_one_facing_the_floor() {
    let floor = square(Vec3::new(0.0, -1.0, 5.0), 20.0, 1, false);
    let lamp = |flipped| square(Vec3::new(0.0, 2.0, 5.0), 1.0, 1, flipped);
    let up = with_emitter(scene(vec![object(floor.clone()), object_with(lamp(false), 1)]));
    assert_eq!(up.why_dark(false), Darkness::LightsFaceAway);
    let down = with_emitter(scene(vec![object(floor), object_with(lamp(true), 1)]));
    assert_eq!(down.why_dark(false), Darkness::NothingReflected);
}

/// A point light shut in a box between the camera and the wall: the wall would be lit, but
/// every shadow ray meets the box.
#[test]
fn a_light_shut_in_a_box_is_blocked() {
    let shut = AaBox::new(Vec3::new(-0.5, -0.5, 2.5), Vec3::new(0.5, 0.5, 3.5));
    let mut s = scene(vec![object(wall()), object(Shape::AaBox(shut))]);
    s.set_lights(vec![point_light(Vec3::new(0.0, 0.0, 3.0))]);
    assert_eq!(s.why_dark(false), Darkness::LightsBlocked);
}
