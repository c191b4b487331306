//! Ray casting (`--integrator raycast`): the nearest hit of all objects along each camera ray,
//! shaded with ambient + Lambert diffuse + Phong specular from every light, *without* shadow
//! rays (as the course defines ray casting; shadows come with Whitted ray tracing). A ray that
//! hits nothing sees the background colour.

use super::{Integrator, SampleContext};
use crate::geometry::Ray;
use crate::scene::Scene;
use crate::Rgb;

pub struct Raycast;

impl Integrator for Raycast {
    fn radiance(&self, scene: &Scene, ray: &Ray, context: &mut SampleContext) -> Rgb {
        context.rays.camera += 1;
        let Some(hit) = scene.intersect(ray) else {
            return scene.environment().radiance(ray.direction);
        };
        let outside = ray.direction.dot(hit.geometry.geometric_normal) < 0.0;
        let material = scene.materials()[hit.material as usize].whitted(&hit.texture_query(scene.geometry()), outside);
        let normal = hit.facing(ray.direction);
        let wo = -ray.direction.normalize();
        let mut radiance = material.ambient * scene.environment().ambient_light;
        for illumination in scene.lights().all().iter().filter_map(|l| l.illuminate(hit.geometry.point)) {
            radiance += material.local(normal, wo, illumination.direction, illumination.intensity);
        }
        radiance
    }
}
