//! Hits and the rays that leave them: the surface record of a closest hit (`SurfaceHit`), and
//! where secondary and shadow rays start (`Spawn`), offset past the hit point's error bound.

use glam::Vec3;

use crate::accel::Geometry;
use crate::geometry::{offset_ray_origin, Ray};
use crate::lights::{LightEnd, LightSample};
use crate::shapes::{PrimHit, Shape, SurfaceGeometry};
use crate::textures::TextureQuery;

/// How far short of a target surface a shadow ray stops, as a fraction of its length.
pub(crate) const SHADOW_EPSILON: f32 = 1e-4;

/// One intersected surface point, everything an integrator needs to shade it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit {
    pub t: f32,
    pub geometry: SurfaceGeometry,
    pub object: u32,
    /// The primitive of `object` hit (for an instance, the one inside it).
    pub prim: u32,
    pub material: u32,
    /// The hit point in the object's own space (for solid textures).
    pub object_point: Vec3,
}

impl SurfaceHit {
    /// Where the hit's textures are looked up (on `geometry`, the aggregate it was found in,
    /// which holds a mesh's attributes); ∂p/∂u is left zero (only anisotropic materials ask for
    /// it: `Geometry::dpdu`).
    pub fn texture_query<'g>(&self, geometry: &'g Geometry) -> TextureQuery<'g> {
        let object = &geometry.objects()[self.object as usize];
        TextureQuery {
            uv: self.geometry.uv,
            point: self.object_point,
            world_point: self.geometry.point,
            normal: self.geometry.geometric_normal,
            dpdu: Vec3::ZERO,
            dpdv: Vec3::ZERO,
            mesh: object.mesh_point(self.prim, || match &object.transform {
                Some(t) => t.to_object.transform_point3(self.geometry.point),
                None => self.geometry.point,
            }),
        }
    }

    /// A ray leaving the surface in `direction`, from an origin just past the point's error
    /// bound on that side, so it cannot hit this surface again at t ≈ 0.
    pub fn spawn_ray(&self, direction: Vec3) -> Ray {
        Spawn::from(&self.geometry).ray(direction)
    }

    /// A ray toward `target` over t ∈ (0, 1) (a shadow ray to a point light, say); the
    /// direction is not normalised, so t = 1 is the target.
    pub fn spawn_ray_to(&self, target: Vec3) -> Ray {
        Spawn::from(&self.geometry).ray_to(target)
    }

    /// A shadow ray toward `target`, a point sampled on another surface (a light) with that
    /// surface's error bound and normal (`Spawn::ray_to_surface`).
    pub fn spawn_ray_to_surface(&self, target: Vec3, target_error: Vec3, target_normal: Vec3) -> Ray {
        Spawn::from(&self.geometry).ray_to_surface(target, target_error, target_normal)
    }

    /// The shadow ray toward a sampled light.
    pub fn spawn_shadow_ray(&self, light: &LightSample) -> Ray {
        Spawn::from(&self.geometry).shadow_ray(light)
    }

    /// The geometric normal on the side of `w` (a direction away from the surface): the side
    /// a photon arrived on, or the viewer's.
    pub fn geometric_normal_toward(&self, w: Vec3) -> Vec3 {
        let n = self.geometry.geometric_normal;
        if n.dot(w) < 0.0 {
            -n
        } else {
            n
        }
    }

    /// The shading normal turned to the side the ray came from (two-sided shading).
    pub fn facing(&self, ray_direction: Vec3) -> Vec3 {
        if self.geometry.geometric_normal.dot(ray_direction) > 0.0 {
            -self.geometry.shading_normal
        } else {
            self.geometry.shading_normal
        }
    }
}

/// Where rays leave a surface point: the point, its error bound and its geometric normal (the
/// wavefront's lanes build one per lane to spawn exactly the scalar code's rays).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Spawn {
    pub point: Vec3,
    pub error: Vec3,
    pub normal: Vec3,
}

impl From<&SurfaceGeometry> for Spawn {
    fn from(g: &SurfaceGeometry) -> Self {
        Self { point: g.point, error: g.error, normal: g.geometric_normal }
    }
}

impl Spawn {
    pub fn ray(&self, direction: Vec3) -> Ray {
        Ray::new(offset_ray_origin(self.point, self.error, self.normal, direction), direction)
    }

    pub fn ray_to(&self, target: Vec3) -> Ray {
        let origin = offset_ray_origin(self.point, self.error, self.normal, target - self.point);
        Ray::with_range(origin, target - origin, 0.0, 1.0)
    }

    /// The far end is offset off the target's surface as an origin would be, and the ray stops
    /// 10⁻⁴ of the way short of it besides, pbrt-v4's and Mitsuba 3's shadow epsilon: the
    /// surface's own intersection routine may still place it a few ulps of the distance early.
    /// A sphere's quadratic did so for 2 % of the shadow rays toward a sphere light of radius
    /// 0.5 two units away, darkening the floor below by 0.5 % (tests/analytic_lights.rs).
    pub fn ray_to_surface(&self, target: Vec3, target_error: Vec3, target_normal: Vec3) -> Ray {
        // Each end offset toward the other's true point (as pbrt-v4 does), so neither waits on
        // the other's offset; against the far end's offset point the origin's side could differ
        // only for a light point within that offset of the receiver's plane.
        let end = offset_ray_origin(target, target_error, target_normal, self.point - target);
        let mut ray = self.ray_to(target);
        ray.direction = end - ray.origin;
        ray.t_max = 1.0 - SHADOW_EPSILON;
        ray
    }

    /// The shadow ray toward a sampled light: to the point on its surface, to its position, or
    /// out of the scene along its direction.
    pub fn shadow_ray(&self, light: &LightSample) -> Ray {
        match light.end {
            LightEnd::Surface { point, normal, error } => self.ray_to_surface(point, error, normal),
            LightEnd::Point(position) => self.ray_to(position),
            LightEnd::Infinite => self.ray(light.direction),
        }
    }
}

/// The surface records of the aggregate's hits.
impl Geometry {
    /// The nearest surface along the ray within `(t_min, t_max)`.
    pub fn intersect(&self, ray: &Ray) -> Option<SurfaceHit> {
        let mut ray = *ray;
        self.closest_primitive(&mut ray).map(|(id, hit)| self.surface_hit(id, &ray, &hit))
    }

    /// Closest hit by testing every primitive: the reference the BVH is checked against.
    pub fn intersect_brute_force(&self, ray: &Ray) -> Option<SurfaceHit> {
        let mut ray = *ray;
        let mut best = None;
        let all = self
            .objects()
            .iter()
            .enumerate()
            .flat_map(|(o, object)| (0..object.shape.primitive_count()).map(move |p| (o as u32, p)));
        for (o, p) in all {
            if let Some(h) = self.objects()[o as usize].intersect(p, &ray, &self.methods()) {
                ray.t_max = h.t;
                best = Some(((o, p), h));
            }
        }
        best.map(|(id, hit)| self.surface_hit(id, &ray, &hit))
    }

    pub(crate) fn surface_hit(&self, (o, p): (u32, u32), ray: &Ray, hit: &PrimHit) -> SurfaceHit {
        let object = &self.objects()[o as usize];
        let geometry = object.surface(p, ray, hit);
        let object_point = match (&object.transform, &object.shape) {
            (Some(t), _) => t.to_object.transform_point3(geometry.point),
            (None, Shape::Mesh(m)) => m.object_point(geometry.point),
            (None, _) => geometry.point,
        };
        // An instance is one primitive of the scene's; its hit's own is the one inside it.
        SurfaceHit {
            t: hit.t,
            geometry,
            object: o,
            prim: p + hit.inner,
            material: object.material_at(hit.inner),
            object_point,
        }
    }
}
