//! Arbitrary output variables: what the camera sees first, per pixel, beside the image (for
//! denoisers, compositing and debugging): the surface's albedo, its shading normal and its
//! distance. Each pixel's values are the mean over `samples` camera rays jittered within it
//! (their own random stream, apart from the image's), so edges are averaged as the image's
//! are.
//!
//! - albedo: the BSDF's directional albedo toward the camera, ∫ f cos dω, estimated by one
//!   BSDF sample per ray (its weight f·cos/pdf): for a diffuse surface its reflectance, for
//!   glass and mirrors about 1; 0 where the ray leaves the scene;
//! - normal: the shading normal on the camera's side, in world space (0 where it leaves);
//! - depth: the distance from the camera to the surface along the ray (0 where it leaves).

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::vertex::Vertex;
use crate::sampling::Rng;
use crate::scene::Scene;
use crate::Rgb;

/// Streams of the AOV rays, apart from the camera samples' (seed, pixel, sample).
const AOV_STREAM: u64 = 0x414F_5600_0000_0000;

/// The AOVs of every pixel, row-major from the top-left.
#[derive(Clone, Debug, PartialEq)]
pub struct Aovs {
    pub albedo: Vec<Rgb>,
    pub normal: Vec<Vec3>,
    pub depth: Vec<f32>,
}

/// The AOVs of `scene`'s camera view, `samples` rays per pixel (at least 1), from `seed`.
pub fn render_aovs(scene: &Scene, samples: u32, seed: u64) -> Aovs {
    let (width, height) = (scene.camera().width, scene.camera().height);
    let samples = samples.max(1);
    let pixels: Vec<(Rgb, Vec3, f32)> = (0..width as u64 * height as u64)
        .into_par_iter()
        .map(|index| {
            let (x, y) = ((index % width as u64) as f32, (index / width as u64) as f32);
            let mut rng = Rng::for_sample(seed ^ AOV_STREAM, index, 0);
            let (mut albedo, mut normal, mut depth) = (Rgb::ZERO, Vec3::ZERO, 0.0f32);
            for _ in 0..samples {
                let (jx, jy) = (rng.next_f32(), rng.next_f32());
                let ray = scene.camera().sample_ray(x + jx, y + jy, || rng.next_f32());
                let Some(vertex) = Vertex::trace(scene, &ray) else { continue };
                let (u_lobe, u) = (rng.next_f32(), Vec2::new(rng.next_f32(), rng.next_f32()));
                if let Some(sample) = vertex.bsdf().sample(vertex.wo, u_lobe, u) {
                    if sample.weight.is_finite() {
                        albedo += sample.weight;
                    }
                }
                normal += vertex.hit.facing(ray.direction);
                depth += vertex.hit.t * ray.direction.length();
            }
            let n = samples as f32;
            (albedo / n, normal.normalize_or_zero(), depth / n)
        })
        .collect();
    Aovs {
        albedo: pixels.iter().map(|p| p.0).collect(),
        normal: pixels.iter().map(|p| p.1).collect(),
        depth: pixels.iter().map(|p| p.2).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::Object;
    use crate::camera::Camera;
    use crate::materials::{Diffuse, Material};
    use crate::scene::SceneBuilder;
    use crate::shapes::{Shape, Sphere};
    use crate::textures::Texture;

    /// A diffuse ball of reflectance (0.2, 0.4, 0.6) and radius 1, 4 units ahead: the centre
    /// pixel sees albedo ≈ the reflectance, the normal toward the camera and depth 3; a corner
    /// pixel sees nothing.
    #[test]
    fn a_diffuse_ball_by_hand() {
        let camera = Camera::new(Vec3::new(0.0, 0.0, -4.0), Vec3::ZERO, Vec3::Y, 30.0, 33, 33).unwrap();
        let ball = Object {
            name: "ball".into(),
            shape: Shape::Sphere(Sphere::new(Vec3::ZERO, 1.0)),
            transform: None,
            material: 0,
        };
        let reflectance = Rgb::new(0.2, 0.4, 0.6);
        let clay = Material::Diffuse(Diffuse { reflectance: Texture::Constant(reflectance) });
        let scene = SceneBuilder::new(camera).object(ball).material("clay", clay).build();
        let aovs = render_aovs(&scene, 64, 1);
        let centre = 16 * 33 + 16;
        assert!((aovs.albedo[centre] - reflectance).abs().max_element() < 1e-4, "{}", aovs.albedo[centre]);
        // Averaged over the pixel, which spans about a degree of the ball.
        assert!(aovs.normal[centre].abs_diff_eq(-Vec3::Z, 1e-2), "{}", aovs.normal[centre]);
        assert!((aovs.depth[centre] - 3.0).abs() < 1e-2, "{}", aovs.depth[centre]);
        assert_eq!((aovs.albedo[0], aovs.normal[0], aovs.depth[0]), (Rgb::ZERO, Vec3::ZERO, 0.0));
        assert_eq!(render_aovs(&scene, 64, 1), aovs, "deterministic");
    }
}
