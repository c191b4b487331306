//! Shapes under transforms: oriented boxes, ellipsoids, and normals that stay perpendicular.

mod common;

use common::{object, scene};
use glam::{Mat4, Quat};
use glint_core::geometry::{Ray, Transform};
use glint_core::shapes::{AaBox, Shape, Sphere};
use glint_core::Vec3;

#[test]
fn rotated_box_is_an_oriented_box() {
    let mut o = object(Shape::AaBox(AaBox::new(Vec3::splat(-1.0), Vec3::splat(1.0))));
    // 45° about y: the box's corner edge now faces −z, at distance √2 from the centre.
    o.transform = Transform::from_matrix(Mat4::from_quat(Quat::from_rotation_y(45f32.to_radians())));
    let s = scene(vec![o]);
    let hit = s.intersect(&Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z)).unwrap();
    assert!((hit.t - (5.0 - 2f32.sqrt())).abs() < 1e-5, "{}", hit.t);
    let off_centre = s.intersect(&Ray::new(Vec3::new(0.5, 0.0, -5.0), Vec3::Z)).unwrap();
    let n = off_centre.geometry.geometric_normal;
    assert!((n.length() - 1.0).abs() < 1e-5);
    assert!((n.y).abs() < 1e-6 && (n.x.abs() - n.z.abs()).abs() < 1e-5, "face normal at 45°: {n}");
}

#[test]
fn scaled_sphere_is_an_ellipsoid_with_correct_normals() {
    let mut o = object(Shape::Sphere(Sphere::new(Vec3::ZERO, 1.0)));
    o.transform = Transform::from_matrix(Mat4::from_scale(Vec3::new(3.0, 1.0, 1.0)));
    let s = scene(vec![o]);
    // Along x the ellipsoid reaches 3, along z only 1.
    let hit = s.intersect(&Ray::new(Vec3::new(-10.0, 0.0, 0.0), Vec3::X)).unwrap();
    assert!((hit.t - 7.0).abs() < 1e-5);
    assert!((hit.geometry.point - Vec3::new(-3.0, 0.0, 0.0)).length() < 1e-5);
    // At (x, y) on x²/9 + y² = 1 the normal is ∝ (x/9, y, 0).
    let y = 0.5f32;
    let x = -3.0 * (1.0 - y * y).sqrt();
    let hit = s.intersect(&Ray::new(Vec3::new(-10.0, y, 0.0), Vec3::X)).unwrap();
    assert!((hit.geometry.point - Vec3::new(x, y, 0.0)).length() < 1e-4);
    let expected = Vec3::new(x / 9.0, y, 0.0).normalize();
    assert!((hit.geometry.geometric_normal - expected).length() < 1e-4, "{}", hit.geometry.geometric_normal);
}
