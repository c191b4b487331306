//! The scene and its query interface: closest hit and any hit. Integrators reach geometry only
//! through these, so every integrator runs on every scene whichever reader built it.

use glam::Vec3;

use crate::accel::{Bvh, BvhStats};
use crate::camera::Camera;
use crate::geometry::{offset_ray_origin, transform_point_with_error, Aabb, Ray, Transform};
use crate::lights::Light;
use crate::materials::Material;
use crate::shapes::{IntersectMethods, PrimHit, Shape, SurfaceGeometry};
use crate::textures::TextureQuery;
use crate::Rgb;

/// A shape placed in the scene with a material and, optionally, a transform (object → world).
#[derive(Clone, Debug)]
pub struct Object {
    pub name: String,
    pub shape: Shape,
    pub transform: Option<Transform>,
    pub material: u32,
}

impl Object {
    fn world_bounds(&self, prim: u32) -> Option<Aabb> {
        let b = self.shape.bounds(prim)?;
        Some(match &self.transform {
            None => b,
            Some(t) => Aabb::from_points(b.corners().map(|c| t.point(c))),
        })
    }

    #[inline]
    fn intersect(&self, prim: u32, ray: &Ray, methods: &IntersectMethods) -> Option<PrimHit> {
        match &self.transform {
            None => self.shape.intersect(prim, ray, methods),
            Some(t) => self.shape.intersect(prim, &t.ray_to_object(ray), methods),
        }
    }

    fn surface(&self, prim: u32, ray: &Ray, hit: &PrimHit) -> SurfaceGeometry {
        match &self.transform {
            None => self.shape.surface(prim, ray, hit),
            Some(t) => {
                let local = self.shape.surface(prim, &t.ray_to_object(ray), hit);
                let (point, error) = transform_point_with_error(&t.to_world, local.point, local.error);
                SurfaceGeometry {
                    point,
                    geometric_normal: t.normal(local.geometric_normal),
                    shading_normal: t.normal(local.shading_normal),
                    uv: local.uv,
                    error,
                }
            }
        }
    }
}

/// One intersected surface point, everything an integrator needs to shade it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit {
    pub t: f32,
    pub geometry: SurfaceGeometry,
    pub object: u32,
    pub prim: u32,
    pub material: u32,
    /// The hit point in the object's own space (for solid textures).
    pub object_point: Vec3,
}

impl SurfaceHit {
    pub fn texture_query(&self) -> TextureQuery {
        TextureQuery { uv: self.geometry.uv, point: self.object_point }
    }

    /// A ray leaving the surface in `direction`, from an origin just past the point's error
    /// bound on that side, so it cannot hit this surface again at t ≈ 0.
    pub fn spawn_ray(&self, direction: Vec3) -> Ray {
        let g = &self.geometry;
        Ray::new(offset_ray_origin(g.point, g.error, g.geometric_normal, direction), direction)
    }

    /// A ray toward `target` over t ∈ (0, 1) (a shadow ray to a point light, say); the
    /// direction is not normalised, so t = 1 is the target.
    pub fn spawn_ray_to(&self, target: Vec3) -> Ray {
        let g = &self.geometry;
        let origin = offset_ray_origin(g.point, g.error, g.geometric_normal, target - g.point);
        Ray::with_range(origin, target - origin, 0.0, 1.0)
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

/// Scene-wide values that are not objects.
#[derive(Clone, Debug, PartialEq)]
pub struct Environment {
    /// Radiance seen by rays that leave the scene.
    pub background: Rgb,
    /// The course's ambient light level I_a.
    pub ambient_light: Rgb,
}

pub struct Scene {
    pub camera: Camera,
    pub objects: Vec<Object>,
    pub materials: Vec<Material>,
    pub material_names: Vec<String>,
    pub lights: Vec<Light>,
    pub environment: Environment,
    pub methods: IntersectMethods,
    /// (object, primitive) pairs in the order the BVH's leaves reference them.
    bounded: Vec<(u32, u32)>,
    /// Primitives without bounds (planes), tested on every ray.
    unbounded: Vec<(u32, u32)>,
    bvh: Bvh,
}

impl Scene {
    pub fn new(
        camera: Camera,
        objects: Vec<Object>,
        materials: Vec<(String, Material)>,
        lights: Vec<Light>,
        environment: Environment,
        methods: IntersectMethods,
    ) -> Self {
        let mut bounded = Vec::new();
        let mut bounds = Vec::new();
        let mut unbounded = Vec::new();
        for (o, object) in objects.iter().enumerate() {
            for p in 0..object.shape.primitive_count() {
                match object.world_bounds(p) {
                    Some(b) => {
                        bounded.push((o as u32, p));
                        bounds.push(b);
                    }
                    None => unbounded.push((o as u32, p)),
                }
            }
        }
        let (bvh, order) = Bvh::build(&bounds);
        let bounded = order.iter().map(|&i| bounded[i as usize]).collect();
        let (material_names, materials) = materials.into_iter().unzip();
        Self { camera, objects, materials, material_names, lights, environment, methods, bounded, unbounded, bvh }
    }

    pub fn primitive_count(&self) -> usize {
        self.bounded.len() + self.unbounded.len()
    }

    pub fn bvh_stats(&self) -> BvhStats {
        self.bvh.stats()
    }

    /// The nearest surface along the ray within `(t_min, t_max)`.
    pub fn intersect(&self, ray: &Ray) -> Option<SurfaceHit> {
        let mut ray = *ray;
        let mut best: Option<((u32, u32), PrimHit)> = None;
        for &(o, p) in &self.unbounded {
            if let Some(h) = self.objects[o as usize].intersect(p, &ray, &self.methods) {
                ray.t_max = h.t;
                best = Some(((o, p), h));
            }
        }
        self.bvh.closest(&mut ray, |i, ray| {
            let (o, p) = self.bounded[i as usize];
            let h = self.objects[o as usize].intersect(p, ray, &self.methods)?;
            best = Some(((o, p), h));
            Some(h.t)
        });
        best.map(|(id, hit)| self.surface_hit(id, &ray, &hit))
    }

    /// Whether anything lies along the ray within `(t_min, t_max)`; stops at the first hit.
    pub fn occluded(&self, ray: &Ray) -> bool {
        self.unbounded.iter().any(|&(o, p)| self.objects[o as usize].intersect(p, ray, &self.methods).is_some())
            || self.bvh.any(ray, |i, ray| {
                let (o, p) = self.bounded[i as usize];
                self.objects[o as usize].intersect(p, ray, &self.methods).is_some()
            })
    }

    /// Closest hit by testing every primitive: the reference the BVH is checked against.
    pub fn intersect_brute_force(&self, ray: &Ray) -> Option<SurfaceHit> {
        let mut ray = *ray;
        let mut best = None;
        for &(o, p) in self.unbounded.iter().chain(&self.bounded) {
            if let Some(h) = self.objects[o as usize].intersect(p, &ray, &self.methods) {
                ray.t_max = h.t;
                best = Some(((o, p), h));
            }
        }
        best.map(|(id, hit)| self.surface_hit(id, &ray, &hit))
    }

    fn surface_hit(&self, (o, p): (u32, u32), ray: &Ray, hit: &PrimHit) -> SurfaceHit {
        let object = &self.objects[o as usize];
        let geometry = object.surface(p, ray, hit);
        let object_point = match (&object.transform, &object.shape) {
            (Some(t), _) => t.to_object.transform_point3(geometry.point),
            (None, Shape::Mesh(m)) => m.object_point(geometry.point),
            (None, _) => geometry.point,
        };
        SurfaceHit { t: hit.t, geometry, object: o, prim: p, material: object.material, object_point }
    }
}
