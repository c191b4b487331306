//! A path's vertex: what a ray finds (the surface, the direction back along the ray, the
//! material and its BSDF there). Every integrator that walks paths (the path tracers, particle
//! tracing, photon mapping's camera and gather paths, SPPM's camera paths) starts each bounce
//! here, so that a surface means the same to all of them.

use glam::Vec3;

use super::path_record::{PathEnd, PathRecorder};
use crate::accel::Geometry;
use crate::geometry::Ray;
use crate::materials::{Bsdf, Material};
use crate::scene::{Scene, SurfaceHit};
use crate::textures::TextureQuery;
use crate::Rgb;

/// The surface a ray met, seen from where the ray came.
pub(super) struct Vertex<'s> {
    pub hit: SurfaceHit,
    /// Back along the ray (unit length): toward the viewer for camera paths, toward the light
    /// for particles.
    pub wo: Vec3,
    pub material: &'s Material,
    /// The surface's (∂p/∂u, ∂p/∂v) where the material reads them (zero elsewhere: no one asks).
    tangents: (Vec3, Vec3),
    /// The scene's aggregate, where the hit's mesh attributes are.
    geometry: &'s Geometry,
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
        let tangents = if material.needs_tangent() {
            scene.geometry().tangents(hit.object, hit.prim, &hit.geometry)
        } else {
            (Vec3::ZERO, Vec3::ZERO)
        };
        Self { hit, wo, material, tangents, geometry: scene.geometry() }
    }

    /// The radiance the surface emits toward `wo`.
    pub fn emitted(&self) -> Rgb {
        self.material.emitted(self.wo, self.hit.geometry.geometric_normal, || self.hit.texture_query(self.geometry))
    }

    /// The material's BSDF at the hit (textures evaluated, the shading frame set).
    pub fn bsdf(&self) -> Bsdf<'s> {
        let geometry = &self.hit.geometry;
        let (dpdu, dpdv) = self.tangents;
        let query = TextureQuery { dpdu, dpdv, ..self.hit.texture_query(self.geometry) };
        self.material.bsdf(&query, self.wo, geometry.shading_normal, geometry.geometric_normal)
    }
}

/// The next vertex of a camera path that weighs found light by the throughput alone (no
/// multiple importance sampling): the environment's radiance if `ray` leaves the scene (and
/// `None`), otherwise the surface's emission, each times `throughput`, added to `radiance`;
/// `recorder` is told (the vertex at `depth`, its emission, or the escape).
pub(super) fn trace_seeing_light<'s>(
    scene: &'s Scene,
    ray: &Ray,
    depth: u32,
    throughput: Rgb,
    radiance: &mut Rgb,
    recorder: &mut impl PathRecorder,
) -> Option<Vertex<'s>> {
    let Some(vertex) = Vertex::trace(scene, ray) else {
        let background = scene.environment().radiance(ray.direction);
        let added = throughput * background;
        *radiance += added;
        recorder.escape(background, 1.0, added);
        recorder.end(PathEnd::Escaped);
        return None;
    };
    recorder.vertex(depth, &vertex.hit, throughput);
    let emitted = vertex.emitted();
    let added = throughput * emitted;
    *radiance += added;
    if emitted != Rgb::ZERO {
        recorder.emission(emitted, 1.0, added);
    }
    Some(vertex)
}

#[cfg(test)]
mod tests {
    use glam::Vec2;

    use super::*;
    use crate::accel::Object;
    use crate::camera::Camera;
    use crate::materials::{Conductor, RoughConductor};
    use crate::scene::SceneBuilder;
    use crate::shapes::{Shape, Triangle};
    use crate::textures::Texture;

    /// A vertex on an anisotropic material hands the BSDF the surface's ∂p/∂u (here a triangle
    /// whose u runs along −y in a transform that turns it), one on an isotropic material none.
    #[test]
    fn an_anisotropic_vertex_gets_the_surface_tangent() {
        let mut triangle =
            Triangle::new(Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(0.0, 1.0, 0.0));
        // u grows from the top corner down: ∂p/∂u = (0, −2, 0) before the turn.
        triangle.uvs = Some([Vec2::new(1.0, 0.0), Vec2::new(1.0, 1.0), Vec2::new(0.0, 0.5)]);
        let turn = crate::geometry::Transform::from_matrix(glam::Mat4::from_rotation_z(0.5));
        let metal = |alpha_v: f32| {
            let conductor = Conductor { eta: Rgb::ZERO, k: Rgb::ONE, specular: Texture::Constant(Rgb::ONE) };
            Material::RoughConductor(RoughConductor {
                conductor,
                alpha_u: 0.05.into(),
                alpha_v: alpha_v.into(),
                distribution: Default::default(),
            })
        };
        for (alpha_v, expected) in [(0.5, turn.unwrap().vector(Vec3::new(0.0, -2.0, 0.0))), (0.05, Vec3::ZERO)] {
            let object = Object { name: "t".into(), shape: Shape::Triangle(triangle), transform: turn, material: 0 };
            let camera = Camera::new(Vec3::new(0.0, 0.0, -3.0), Vec3::ZERO, Vec3::Y, 45.0, 8, 8).unwrap();
            let scene = SceneBuilder::new(camera).object(object).material("metal", metal(alpha_v)).build();
            let vertex = Vertex::trace(&scene, &Ray::new(Vec3::new(0.1, 0.0, -3.0), Vec3::Z)).expect("a hit");
            assert!(
                (vertex.tangents.0 - expected).length() < 1e-5,
                "α_v {alpha_v}: {} vs {expected}",
                vertex.tangents.0
            );
        }
    }
}
