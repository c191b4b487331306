//! A path's vertex: what a ray finds (the surface, the direction back along the ray, the
//! material and its BSDF there). Every integrator that walks paths (the path tracers, particle
//! tracing, photon mapping's camera and gather paths, SPPM's camera paths) starts each bounce
//! here, so that a surface means the same to all of them.

use glam::Vec3;

use crate::geometry::Ray;
use crate::materials::{Bsdf, Material};
use crate::scene::{Scene, SurfaceHit};
use crate::Rgb;

/// The surface a ray met, seen from where the ray came.
pub(super) struct Vertex<'s> {
    pub hit: SurfaceHit,
    /// Back along the ray (unit length): toward the viewer for camera paths, toward the light
    /// for particles.
    pub wo: Vec3,
    pub material: &'s Material,
}

impl<'s> Vertex<'s> {
    /// The surface `ray` meets first, or `None` if it leaves the scene.
    pub fn trace(scene: &'s Scene, ray: &Ray) -> Option<Self> {
        scene.intersect(ray).map(|hit| Self::at(scene, ray, hit))
    }

    /// The vertex at `hit`, the closest hit of `ray`.
    pub fn at(scene: &'s Scene, ray: &Ray, hit: SurfaceHit) -> Self {
        let wo = -ray.direction.normalize();
        let material = &scene.materials()[hit.material as usize];
        Self { hit, wo, material }
    }

    /// The radiance the surface emits toward `wo`.
    pub fn emitted(&self) -> Rgb {
        self.material.emitted(self.wo, self.hit.geometry.geometric_normal)
    }

    /// The material's BSDF at the hit (textures evaluated, the shading frame set).
    pub fn bsdf(&self) -> Bsdf<'s> {
        let geometry = &self.hit.geometry;
        self.material.bsdf(&self.hit.texture_query(), self.wo, geometry.shading_normal, geometry.geometric_normal)
    }
}

/// The next vertex of a camera path that weighs found light by the throughput alone (no
/// multiple importance sampling): the environment's radiance if `ray` leaves the scene (and
/// `None`), otherwise the surface's emission, each times `throughput`, added to `radiance`.
pub(super) fn trace_seeing_light<'s>(
    scene: &'s Scene,
    ray: &Ray,
    throughput: Rgb,
    radiance: &mut Rgb,
) -> Option<Vertex<'s>> {
    let Some(vertex) = Vertex::trace(scene, ray) else {
        *radiance += throughput * scene.environment().radiance(ray.direction);
        return None;
    };
    *radiance += throughput * vertex.emitted();
    Some(vertex)
}
