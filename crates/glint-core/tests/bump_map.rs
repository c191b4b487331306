//! A bump-mapped floor under a directional light, where the bumped normal is known by hand:
//! the floor y = 0 has u = x and v = −z (∂p/∂u = x̂, ∂p/∂v = −ẑ), and its height is a ramp
//! image whose luminance rises linearly along u. Displaced by scale·height, the surface has
//! the slope g = scale·∂h/∂u along x, so its normal is (−g, 1, 0) normalised, and a Lambertian
//! floor lit from direction l shines in proportion to n·l. Direct light only, through the path
//! tracer and the wavefront, under a transform that turns and stretches the floor too (the
//! tangents then come from the transform, and the slope per unit of length shrinks with the
//! stretch along u).

mod common;

use std::sync::Arc;

use common::{object_with, scene};
use glam::Mat4;
use glint_core::camera::Camera;
use glint_core::geometry::Transform;
use glint_core::integrators::{IntegratorKind, IntegratorSettings};
use glint_core::lights::{DirectionalLight, Light};
use glint_core::materials::{BumpMap, Diffuse, Material};
use glint_core::render::{render_with, RenderSettings};
use glint_core::scene::Scene;
use glint_core::shapes::{Plane, Shape};
use glint_core::textures::{ImageTexture, Texture, Wrap};
use glint_core::{Rgb, Vec3};

const TEXELS: u32 = 64;

/// Luminance k/63 at texel k: a slope of 64/63 per unit of u between the first and last
/// texel centres.
fn ramp() -> Texture {
    let pixels = (0..TEXELS).map(|k| Rgb::splat(k as f32 / (TEXELS - 1) as f32)).collect();
    Texture::Image(Arc::new(ImageTexture { wrap: Wrap::Clamp, ..ImageTexture::new(TEXELS, 1, pixels) }))
}

fn diffuse() -> Material {
    Material::Diffuse(Diffuse { reflectance: Texture::Constant(Rgb::splat(0.5)) })
}

/// The floor's mean pixel value, seen in a narrow view around the world point `at`.
fn floor_value(material: Material, transform: Option<Transform>, at: Vec3, wavefront: bool) -> f32 {
    let mut floor = object_with(Shape::Plane(Plane::new(Vec3::Y, 0.0)), 0);
    floor.transform = transform;
    let mut s: Scene = scene(vec![floor]);
    s.set_materials(vec![material]);
    s.set_camera(Camera::new(at + Vec3::new(0.0, 2.0, -0.5), at, Vec3::Y, 0.5, 6, 6).unwrap());
    let light = Vec3::new(-1.0, 2.0, 0.3).normalize();
    s.set_lights(vec![Light::Directional(DirectionalLight { direction: -light, intensity: Rgb::ONE })]);
    let settings = IntegratorSettings { max_depth: 1, wavefront, ..Default::default() };
    let mut renderer = IntegratorKind::Path.renderer(&settings, &s, 1).expect("a camera integrator");
    let image = render_with(&s, renderer.as_mut(), &RenderSettings { spp: 4, seed: 3, ..Default::default() }, &|| {})
        .film
        .to_rgb();
    image.iter().map(|p| p.x).sum::<f32>() / image.len() as f32
}

#[test]
fn a_ramp_height_tilts_a_floor_by_its_slope() {
    let light = Vec3::new(-1.0, 2.0, 0.3).normalize();
    // Identity, and the floor stretched 2× along x and turned about y by 90° (its u then runs
    // along −z in the world, 2 units of length per unit of u).
    let stretched = Transform::from_matrix(
        Mat4::from_rotation_y(std::f32::consts::FRAC_PI_2) * Mat4::from_scale(Vec3::new(2.0, 1.0, 1.0)),
    )
    .expect("invertible");
    let cases = [
        ("as is", None, Vec3::new(0.5, 0.0, -0.5), Vec3::X, 1.0),
        ("stretched and turned", Some(stretched), Vec3::new(-0.5, 0.0, -1.0), -Vec3::Z, 2.0),
    ];
    for wavefront in [false, true] {
        for (name, transform, at, along_u, length_per_u) in cases {
            let flat = floor_value(diffuse(), transform, at, wavefront);
            for scale in [0.3f32, -0.8] {
                let map = BumpMap { height: ramp(), scale, material: diffuse() };
                let bumped = floor_value(Material::BumpMap(Box::new(map)), transform, at, wavefront);
                let slope = scale * (TEXELS as f32 / (TEXELS - 1) as f32) / length_per_u;
                let normal = (Vec3::Y - slope * along_u).normalize();
                // Lambert about the bumped normal, shadowed by the map's G1 (α² = tan²θ_tilt / 8,
                // θ_i from the floor's own normal).
                let tan2 = |cos: f32| (1.0 - cos * cos) / (cos * cos);
                let alpha2 = (tan2(normal.y) / 8.0).min(1.0);
                let g1 = 2.0 / (1.0 + (1.0 + alpha2 * tan2(light.y)).sqrt());
                let expected = g1 * normal.dot(light) / Vec3::Y.dot(light);
                let ratio = bumped / flat;
                assert!(
                    (ratio - expected).abs() < 1e-4,
                    "wavefront {wavefront}, {name}, scale {scale}: bumped / flat = {ratio}, expected {expected}"
                );
            }
        }
    }
}
