//! Instance: one geometry (a mesh with its own BVH, built once) placed anywhere by the
//! object's transform, as many times as wanted; the scene's BVH sees each placement as one
//! primitive (a two-level BVH). Memory grows by one object per placement, not by a mesh.
//!
//! Scene parameters: a named mesh in `[meshes.NAME]` (`file`, `smooth`), then per placement
//! ```toml
//! [[shapes]]
//! type = "instance"
//! mesh = "dragon"
//! material = "jade"
//! transform = [{ scale = 0.1 }, { translate = [2, 0, 0] }]
//! ```

use std::sync::Arc;

use glam::Vec3;

use super::{PrimHit, SurfaceGeometry};
use crate::geometry::{Aabb, Ray};

/// What an instance places: a geometry with its own acceleration structure (the scene's
/// aggregate, `accel::Geometry`, implements it).
pub trait InstancedGeometry: Send + Sync {
    fn bounds(&self) -> Aabb;
    /// The closest primitive along the ray, which it narrows: (object, primitive) and the hit.
    fn closest_primitive(&self, ray: &mut Ray) -> Option<((u32, u32), PrimHit)>;
    fn primitive_surface(&self, object: u32, prim: u32, ray: &Ray, hit: &PrimHit) -> SurfaceGeometry;
    fn primitive_count(&self) -> usize;
    /// The corners of primitive `prim` of `object` in the geometry's space, if it is a
    /// triangle (an emitting instance's lights).
    fn triangle_corners(&self, object: u32, prim: u32) -> Option<[Vec3; 3]>;
    /// The surface at `point` (the geometry's space) of primitive `prim` of `object`, a
    /// triangle's point by `hit`'s barycentric coordinates (`Shape::surface_at`).
    fn surface_at(&self, object: u32, prim: u32, point: Vec3, hit: &PrimHit) -> Option<SurfaceGeometry>;
    /// Every triangle the ray meets within `(t_min, t_max)`, in no order: the hit (`inner` the
    /// triangle's index) and whether the ray leaves along its winding's normal (d·n > 0).
    /// Other primitives are skipped (CSG asks only closed meshes).
    fn crossings(&self, ray: &Ray, found: &mut dyn FnMut(PrimHit, bool));
    /// The volume the geometry encloses if it is one closed, consistently wound mesh
    /// (`Mesh::enclosed_volume`), negative if its winding faces in.
    fn enclosed_volume(&self) -> Option<f64>;
}

#[derive(Clone)]
pub struct Instance {
    pub geometry: Arc<dyn InstancedGeometry>,
}

impl std::fmt::Debug for Instance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Instance({} primitives)", self.geometry.primitive_count())
    }
}

impl Instance {
    pub fn bounds(&self) -> Aabb {
        self.geometry.bounds()
    }

    /// The closest hit inside the instanced geometry (the ray is already in its space).
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<PrimHit> {
        let mut ray = *ray;
        let ((_, prim), hit) = self.geometry.closest_primitive(&mut ray)?;
        Some(PrimHit { inner: prim, ..hit })
    }

    pub fn surface(&self, ray: &Ray, hit: &PrimHit) -> SurfaceGeometry {
        self.geometry.primitive_surface(0, hit.inner, ray, hit)
    }
}
