//! Shapes and their ray intersection: one file per shape, the course's algorithms side by side.
//!
//! Every shape answers two questions, kept apart so the acceleration structure can test many
//! primitives cheaply and build the full surface record only for the closest one:
//! - `intersect(prim, ray, methods)`: is there a hit with `ray.t_min < t < ray.t_max`, and at
//!   what `t` (plus two shape-specific parameters, e.g. barycentrics);
//! - `surface(ray, hit)`: the hit point, geometric and shading normals and uv.
//!
//! Normal orientation: a shape returns its geometric normal as the geometry defines it —
//! outward for spheres and boxes, `normal` for planes, `(v1−v0)×(v2−v0)` (counter-clockwise
//! winding) for triangles and polygons. It is *not* flipped toward the ray; integrators do
//! that when they need a side (see `SurfaceHit::facing`).

mod aabox;
mod csg;
mod curves;
mod instance;
mod mesh;
mod plane;
mod polygon;
mod sdf_grid;
mod sphere;
mod triangle;

pub use aabox::{AaBox, BoxMethod};
pub use csg::{Csg, CsgError, CsgOperation, CsgSolid, CsgTree};
pub use curves::{CurveBasis, Curves};
pub use instance::{Instance, InstancedGeometry};
pub use mesh::{Mesh, MeshAttribute};
pub use plane::Plane;
pub use polygon::{inverse_bilinear, Polygon, PolygonTest, PolygonUvError};
pub use sdf_grid::{SdfGrid, SdfNormals};
pub(crate) use sphere::{sample_sphere, sample_sphere_seen_from, sphere_solid_angle_from, Ellipsoid};
pub use sphere::{Sphere, SphereMethod};
pub(crate) use triangle::{
    barycentric_point_lanes, barycentrics, plane_distance, sample_triangle, triangle_point_along, TriangleSurface,
};
pub use triangle::{intersect_cramer, moller_trumbore_edges, Triangle, TriangleMethod, WatertightRay};

use glam::{Vec2, Vec3};

use crate::geometry::{Aabb, Ray};

/// Which of the course's algorithms each shape uses. Every pair computes the same thing;
/// tests check that they agree.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct IntersectMethods {
    pub sphere: SphereMethod,
    pub triangle: TriangleMethod,
    pub polygon: PolygonTest,
    pub aabox: BoxMethod,
}

/// What a primitive test returns: the distance and two shape-specific parameters
/// (barycentrics for triangles, unused elsewhere), enough to build the surface later.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrimHit {
    pub t: f32,
    pub u: f32,
    pub v: f32,
    /// For an instance: the primitive hit inside the instanced geometry.
    pub inner: u32,
}

impl PrimHit {
    pub fn at(t: f32) -> Self {
        Self { t, u: 0.0, v: 0.0, inner: 0 }
    }
}

/// The local geometry at a hit point, in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceGeometry {
    pub point: Vec3,
    /// Unit normal of the true surface, oriented as the shape defines it.
    pub geometric_normal: Vec3,
    /// Unit normal for shading (interpolated vertex normals on meshes), same hemisphere as
    /// `geometric_normal`.
    pub shading_normal: Vec3,
    pub uv: Vec2,
    /// Bound on the absolute floating-point error of `point`, per axis (see
    /// `geometry::offset_ray_origin`).
    pub error: Vec3,
}

impl SurfaceGeometry {
    /// The surface in world space of a shape placed by `t`, from its surface in the shape's
    /// space. The error bound covers the next ray's trip back into the shape's space too: an
    /// origin offset past the world bound alone could round back onto a transformed sphere's
    /// outside and hit it again (an ellipsoid did, 6·10⁻⁷ away).
    #[inline]
    pub(crate) fn placed(self, t: &crate::geometry::Transform) -> SurfaceGeometry {
        let local_error = self.error + t.round_trip_margin(self.point);
        let (point, error) = crate::geometry::transform_point_with_error(&t.to_world, self.point, local_error);
        SurfaceGeometry {
            point,
            geometric_normal: t.normal(self.geometric_normal),
            shading_normal: t.normal(self.shading_normal),
            uv: self.uv,
            error,
        }
    }
}

/// The closed set of shapes, dispatched by `match` on every ray.
#[derive(Clone, Debug)]
pub enum Shape {
    Plane(Plane),
    Sphere(Sphere),
    Triangle(Triangle),
    Polygon(Polygon),
    AaBox(AaBox),
    Mesh(Mesh),
    /// A shared, separately built geometry (a mesh and its BVH) placed by the object's
    /// transform: the two-level BVH that lets one mesh appear many times.
    Instance(Instance),
    /// Closed solids combined by union, intersection and difference (boxed: a shape stays
    /// small).
    Csg(Box<Csg>),
    /// The zero set of a grid of signed distances, one primitive per voxel it crosses
    /// (shared: the grid can be large).
    SdfGrid(std::sync::Arc<SdfGrid>),
    /// Tubes along polylines and splines, one primitive per straight piece (shared: hair can
    /// be large).
    Curves(std::sync::Arc<Curves>),
}

impl Shape {
    /// Number of primitives the acceleration structure sees (triangles for a mesh, else 1).
    pub fn primitive_count(&self) -> u32 {
        match self {
            Shape::Mesh(m) => m.triangle_count() as u32,
            Shape::SdfGrid(g) => g.primitive_count(),
            Shape::Curves(c) => c.primitive_count(),
            _ => 1,
        }
    }

    /// Bounds of one primitive in the shape's own space; `None` if unbounded (a plane).
    pub fn bounds(&self, prim: u32) -> Option<Aabb> {
        match self {
            Shape::Plane(_) => None,
            Shape::Sphere(s) => Some(s.bounds()),
            Shape::Triangle(t) => Some(t.bounds()),
            Shape::Polygon(p) => Some(p.bounds()),
            Shape::AaBox(b) => Some(b.bounds()),
            Shape::Mesh(m) => Some(m.triangle_bounds(prim as usize)),
            Shape::Instance(i) => Some(i.bounds()),
            Shape::Csg(c) => Some(c.bounds()),
            Shape::SdfGrid(g) => Some(g.bounds(prim)),
            Shape::Curves(c) => Some(c.bounds(prim)),
        }
    }

    #[inline]
    pub fn intersect(&self, prim: u32, ray: &Ray, methods: &IntersectMethods) -> Option<PrimHit> {
        match self {
            Shape::Plane(p) => p.intersect(ray).map(PrimHit::at),
            Shape::Sphere(s) => s.intersect(ray, methods.sphere).map(PrimHit::at),
            Shape::Triangle(t) => t.intersect(ray, methods.triangle),
            Shape::Polygon(p) => p.intersect(ray, methods.polygon).map(PrimHit::at),
            Shape::AaBox(b) => b.intersect(ray, methods.aabox).map(PrimHit::at),
            Shape::Mesh(m) => m.intersect(prim as usize, ray, methods.triangle),
            Shape::Instance(i) => i.intersect(ray),
            Shape::Csg(c) => c.intersect(ray, methods),
            Shape::SdfGrid(g) => g.intersect(prim, ray),
            Shape::Curves(c) => c.intersect(prim, ray),
        }
    }

    /// (∂p/∂u, ∂p/∂v) at `point` (normal `normal`) on primitive `prim`, in the shape's space:
    /// how the point moves as u and v grow (not unit length; zero where unknown: instances,
    /// degenerate uvs, a sphere's poles). Asked only by anisotropic materials, which align
    /// their tangent with ∂p/∂u as Mitsuba's do, and by bump maps, so a hit does not pay for it.
    pub fn tangents(&self, prim: u32, point: Vec3, normal: Vec3) -> (Vec3, Vec3) {
        match self {
            Shape::Plane(p) => p.tangents(),
            Shape::Sphere(s) => s.tangents(point),
            Shape::Triangle(t) => t.tangents(),
            Shape::Polygon(p) => p.tangents(),
            Shape::AaBox(b) => b.tangents(normal),
            Shape::Mesh(m) => m.tangents(prim as usize),
            Shape::Instance(_) | Shape::SdfGrid(_) => (Vec3::ZERO, Vec3::ZERO),
            Shape::Curves(c) => c.tangents(prim, point),
            // `prim` is the solid (a hit's `inner`).
            Shape::Csg(c) => c.tangents(prim, point, normal),
        }
    }

    /// The surface where `ray` hit. Its own match, not a call of `surface_at`: through that
    /// (an `Option` unwrapped) every hit cost path-naive 10 % on the Cornell box.
    #[inline]
    pub fn surface(&self, prim: u32, ray: &Ray, hit: &PrimHit) -> SurfaceGeometry {
        match self {
            Shape::Plane(p) => p.surface(ray.at(hit.t)),
            Shape::Sphere(s) => s.surface(ray.at(hit.t)),
            Shape::Triangle(t) => t.surface(hit),
            Shape::Polygon(p) => p.surface(ray.at(hit.t)),
            Shape::AaBox(b) => b.surface(ray.at(hit.t)),
            Shape::Mesh(m) => m.surface(prim as usize, hit),
            Shape::Instance(i) => i.surface(ray, hit),
            Shape::Csg(c) => c.surface(ray, hit),
            Shape::SdfGrid(g) => g.surface(prim, ray, hit),
            Shape::Curves(c) => c.surface(prim, ray, hit),
        }
    }

    /// The surface at `point` (in the shape's space) of primitive `prim`, a triangle's point
    /// read from `hit`'s barycentric coordinates instead: what a hit there finds, for a point
    /// no ray found (one sampled on a light). `None` for an instance and a CSG object, whose
    /// surfaces need the ray, and for an SDF grid and curves, which have no sampling routine.
    #[inline]
    pub fn surface_at(&self, prim: u32, point: Vec3, hit: &PrimHit) -> Option<SurfaceGeometry> {
        Some(match self {
            Shape::Plane(p) => p.surface(point),
            Shape::Sphere(s) => s.surface(point),
            Shape::Triangle(t) => t.surface(hit),
            Shape::Polygon(p) => p.surface(point),
            Shape::AaBox(b) => b.surface(point),
            Shape::Mesh(m) => m.surface(prim as usize, hit),
            Shape::Instance(_) | Shape::Csg(_) | Shape::SdfGrid(_) | Shape::Curves(_) => return None,
        })
    }

    /// The shape's name as written in scene files.
    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Plane(_) => "plane",
            Shape::Sphere(_) => "sphere",
            Shape::Triangle(_) => "triangle",
            Shape::Polygon(_) => "polygon",
            Shape::AaBox(_) => "box",
            Shape::Mesh(_) => "mesh",
            Shape::Instance(_) => "instance",
            Shape::Csg(_) => "csg",
            Shape::SdfGrid(_) => "sdfgrid",
            Shape::Curves(_) => "curves",
        }
    }
}

/// Solutions of a·t² + 2·half_b·t + c = 0 in ascending order, computed without the
/// cancellation of the textbook formula (Numerical Recipes §5.6). `None` if complex.
pub(crate) fn solve_quadratic(a: f32, half_b: f32, c: f32) -> Option<(f32, f32)> {
    let discriminant = half_b * half_b - a * c;
    if discriminant < 0.0 || a == 0.0 {
        return None;
    }
    let q = -(half_b + discriminant.sqrt().copysign(half_b));
    if q == 0.0 {
        // half_b = 0 and discriminant = 0, so c = 0: a double root at 0.
        return Some((0.0, 0.0));
    }
    let (t0, t1) = (q / a, c / q);
    Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) })
}

/// The first of two ascending roots inside the ray's interval.
#[inline]
pub(crate) fn first_in_range(ray: &Ray, t0: f32, t1: f32) -> Option<f32> {
    if ray.contains(t0) {
        Some(t0)
    } else if ray.contains(t1) {
        Some(t1)
    } else {
        None
    }
}

#[cfg(test)]
pub(crate) mod test_util {
    use glam::Vec3;

    /// Where the ray from `o` along `w` meets the triangle, by Möller–Trumbore in plain form:
    /// the independent check that sampled light directions land on the light.
    pub fn ray_meets_triangle(o: Vec3, w: Vec3, [a, b, c]: [Vec3; 3]) -> Option<Vec3> {
        let (e1, e2) = (b - a, c - a);
        let p = w.cross(e2);
        let det = e1.dot(p);
        let s = o - a;
        let (u, q) = (s.dot(p) / det, s.cross(e1));
        let (v, t) = (w.dot(q) / det, e2.dot(q) / det);
        (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0).then(|| o + t * w)
    }

    /// A tiny deterministic generator for randomized tests (SplitMix64).
    pub struct TestRng(pub u64);

    impl TestRng {
        pub fn next_u64(&mut self) -> u64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        }
        /// Uniform in [lo, hi).
        pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
            let u = (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32;
            lo + (hi - lo) * u
        }
        pub fn vec3(&mut self, lo: f32, hi: f32) -> glam::Vec3 {
            glam::Vec3::new(self.range(lo, hi), self.range(lo, hi), self.range(lo, hi))
        }
        pub fn unit_vector(&mut self) -> glam::Vec3 {
            loop {
                let v = self.vec3(-1.0, 1.0);
                let l = v.length_squared();
                if l > 1e-4 && l <= 1.0 {
                    return v / l.sqrt();
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadratic_roots_are_ordered_and_stable() {
        assert_eq!(solve_quadratic(1.0, -3.0, 8.0), Some((2.0, 4.0))); // t² − 6t + 8
        assert_eq!(solve_quadratic(1.0, 0.0, 1.0), None);
        assert_eq!(solve_quadratic(1.0, 0.0, 0.0), Some((0.0, 0.0)));
        // Widely separated roots: 1e-4 and 1e4 (x² − (1e4+1e-4)x + 1).
        let (t0, t1) = solve_quadratic(1.0, -0.5 * (1e4 + 1e-4), 1.0).unwrap();
        assert!((t0 - 1e-4).abs() < 1e-9 && (t1 - 1e4).abs() < 1e-2);
    }
}
