//! Infinite plane n·P + D = 0.
//!
//! Scene parameters: `normal` (vector, normalised on load), and either `offset` (D, default 0)
//! or `point` (any point on the plane).
//! ```toml
//! [[shapes]]
//! type = "plane"
//! normal = [0, 1, 0]
//! offset = 0
//! material = "floor"
//! ```
//! t = −(n·O + D) / (n·d); a ray parallel to the plane (n·d = 0) misses, even when it lies in
//! it. uv are the hit point's coordinates along two tangent directions, in scene units.

use glam::{Vec2, Vec3};

use super::SurfaceGeometry;
use crate::geometry::{gamma, orthonormal_basis, Ray};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    pub normal: Vec3,
    pub offset: f32,
}

impl Plane {
    /// `normal` is normalised here; `offset` is D for the unit normal.
    pub fn new(normal: Vec3, offset: f32) -> Self {
        let length = normal.length();
        Self { normal: normal / length, offset: offset / length }
    }

    pub fn through_point(normal: Vec3, point: Vec3) -> Self {
        let n = normal.normalize();
        Self { normal: n, offset: -n.dot(point) }
    }

    pub fn intersect(&self, ray: &Ray) -> Option<f32> {
        let denominator = self.normal.dot(ray.direction);
        if denominator == 0.0 {
            return None;
        }
        let t = -(self.normal.dot(ray.origin) + self.offset) / denominator;
        ray.contains(t).then_some(t)
    }

    /// (∂p/∂u, ∂p/∂v): u and v are the coordinates along the two tangents.
    pub fn tangents(&self) -> (Vec3, Vec3) {
        orthonormal_basis(self.normal)
    }

    pub fn surface(&self, point: Vec3) -> SurfaceGeometry {
        // Project back onto the plane to drop the error of O + tD along the normal.
        let point = point - (self.normal.dot(point) + self.offset) * self.normal;
        let (s, t) = orthonormal_basis(self.normal);
        SurfaceGeometry {
            point,
            geometric_normal: self.normal,
            shading_normal: self.normal,
            uv: Vec2::new(point.dot(s), point.dot(t)),
            // The projection onto the plane: a dot product and a multiply-add per axis.
            error: gamma(7) * (point.abs() + Vec3::splat(self.offset.abs())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hit_miss_behind_parallel() {
        let floor = Plane::new(Vec3::Y, 1.0); // y = −1
        assert_eq!(floor.intersect(&Ray::new(Vec3::ZERO, -Vec3::Y)), Some(1.0));
        assert_eq!(floor.intersect(&Ray::new(Vec3::ZERO, Vec3::Y)), None); // behind
        assert_eq!(floor.intersect(&Ray::new(Vec3::ZERO, Vec3::X)), None); // parallel
        let in_plane = Ray::new(Vec3::new(0.0, -1.0, 0.0), Vec3::X);
        assert_eq!(floor.intersect(&in_plane), None);
        // From below, going up: hits the back side.
        assert_eq!(floor.intersect(&Ray::new(Vec3::new(0.0, -3.0, 0.0), Vec3::Y)), Some(2.0));
    }

    #[test]
    fn oblique_hit_and_offset_normalisation() {
        let p = Plane::new(Vec3::new(0.0, 2.0, 0.0), 2.0); // 2y + 2 = 0 → y = −1
        let t = p.intersect(&Ray::new(Vec3::ZERO, Vec3::new(1.0, -1.0, 0.0))).unwrap();
        assert!((t - 1.0).abs() < 1e-6);
        let q = Plane::through_point(Vec3::Y, Vec3::new(5.0, -1.0, 2.0));
        assert!((q.offset - 1.0).abs() < 1e-6);
        assert_eq!(p.surface(Vec3::new(1.0, -1.0, 0.0)).geometric_normal, Vec3::Y);
    }
}
