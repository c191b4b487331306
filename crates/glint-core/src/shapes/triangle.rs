//! Triangle, by barycentric coordinates and Cramer's rule (the course's derivation), by
//! Möller–Trumbore, and by the watertight test of Woop, Benthin and Wald (the fast path, and the
//! default): a ray through an edge shared by two triangles hits one of them, never neither.
//!
//! Scene parameters: `vertices` (three points, counter-clockwise seen from the front),
//! optional `normals` (three vectors, for smooth shading) and `uvs` (three 2D points).
//! ```toml
//! [[shapes]]
//! type = "triangle"
//! vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
//! material = "white"
//! ```
//! Both solve O + tD = A + β(B − A) + γ(C − A) for (t, β, γ) and accept β ≥ 0, γ ≥ 0,
//! β + γ ≤ 1: a ray through an edge or a vertex hits. A ray parallel to the triangle's
//! plane (determinant 0) misses.

use glam::{Vec2, Vec3, Vec3A};

use super::{PrimHit, SurfaceGeometry};
use crate::geometry::{gamma, Aabb, Ray};
use crate::lanes::{LaneVec3, Lanes};
use crate::Named;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TriangleMethod {
    Cramer,
    MollerTrumbore,
    #[default]
    Watertight,
}

impl Named for TriangleMethod {
    const ALL: &'static [Self] = &[TriangleMethod::Cramer, TriangleMethod::MollerTrumbore, TriangleMethod::Watertight];

    fn name(self) -> &'static str {
        match self {
            TriangleMethod::Cramer => "cramer",
            TriangleMethod::MollerTrumbore => "moller-trumbore",
            TriangleMethod::Watertight => "watertight",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    pub vertices: [Vec3; 3],
    pub normals: Option<[Vec3; 3]>,
    pub uvs: Option<[Vec2; 3]>,
}

impl Triangle {
    pub fn new(a: Vec3, b: Vec3, c: Vec3) -> Self {
        Self { vertices: [a, b, c], normals: None, uvs: None }
    }

    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(self.vertices)
    }

    /// Twice the area; 0 for a degenerate (collinear) triangle.
    pub fn double_area(&self) -> f32 {
        let [a, b, c] = self.vertices;
        (b - a).cross(c - a).length()
    }

    pub fn intersect(&self, ray: &Ray, method: TriangleMethod) -> Option<PrimHit> {
        let [a, b, c] = self.vertices;
        match method {
            TriangleMethod::Cramer => intersect_cramer(a, b, c, ray),
            TriangleMethod::MollerTrumbore => intersect_moller_trumbore(a, b, c, ray),
            TriangleMethod::Watertight => WatertightRay::new(ray).intersect(a, b, c, ray),
        }
    }

    pub fn surface(&self, hit: &PrimHit) -> SurfaceGeometry {
        triangle_surface(self.vertices, self.normals, self.uvs, hit)
    }

    /// (∂p/∂u, ∂p/∂v).
    pub fn tangents(&self) -> (Vec3, Vec3) {
        triangle_tangents(self.vertices, self.uvs)
    }
}

/// The 3×3 system [A−B | A−C | D]·(β, γ, t) = A − O solved by Cramer's rule, with the
/// determinants expanded as in Shirley & Marschner, Fundamentals of Computer Graphics §4.4.2.
pub fn intersect_cramer(va: Vec3, vb: Vec3, vc: Vec3, ray: &Ray) -> Option<PrimHit> {
    let (a, b, c) = (va.x - vb.x, va.y - vb.y, va.z - vb.z);
    let (d, e, f) = (va.x - vc.x, va.y - vc.y, va.z - vc.z);
    let (g, h, i) = (ray.direction.x, ray.direction.y, ray.direction.z);
    let (j, k, l) = (va.x - ray.origin.x, va.y - ray.origin.y, va.z - ray.origin.z);

    let ei_hf = e * i - h * f;
    let gf_di = g * f - d * i;
    let dh_eg = d * h - e * g;
    let m = a * ei_hf + b * gf_di + c * dh_eg;
    if m == 0.0 {
        return None;
    }
    let ak_jb = a * k - j * b;
    let jc_al = j * c - a * l;
    let bl_kc = b * l - k * c;

    let t = -(f * ak_jb + e * jc_al + d * bl_kc) / m;
    if !ray.contains(t) {
        return None;
    }
    let gamma = (i * ak_jb + h * jc_al + g * bl_kc) / m;
    if !(0.0..=1.0).contains(&gamma) {
        return None;
    }
    let beta = (j * ei_hf + k * gf_di + l * dh_eg) / m;
    if beta < 0.0 || beta > 1.0 - gamma {
        return None;
    }
    Some(PrimHit { t, u: beta, v: gamma, inner: 0 })
}

/// Möller & Trumbore 1997, "Fast, Minimum Storage Ray/Triangle Intersection".
#[inline]
pub fn intersect_moller_trumbore(a: Vec3, b: Vec3, c: Vec3, ray: &Ray) -> Option<PrimHit> {
    moller_trumbore_edges(a, b - a, c - a, ray)
}

/// Möller–Trumbore from the first vertex and the two edges from it (the layout the BVH's
/// leaves store, so the edges are not recomputed per ray).
#[inline(always)]
pub fn moller_trumbore_edges(a: Vec3, edge1: Vec3, edge2: Vec3, ray: &Ray) -> Option<PrimHit> {
    let p = ray.direction.cross(edge2);
    let determinant = edge1.dot(p);
    if determinant == 0.0 {
        return None;
    }
    let inv_det = 1.0 / determinant;
    let s = ray.origin - a;
    let u = s.dot(p) * inv_det;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(edge1);
    let v = ray.direction.dot(q) * inv_det;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = edge2.dot(q) * inv_det;
    ray.contains(t).then_some(PrimHit { t, u, v, inner: 0 })
}

/// A ray prepared for the watertight test (Woop, Benthin, Wald 2013, "Watertight Ray/Triangle
/// Intersection", JCGT 2(1)): space is translated to the origin, permuted so the ray's largest
/// direction component is z, and sheared so the ray runs along +z. The triangle's vertices are
/// then tested by 2D edge functions, which two triangles sharing an edge compute from the same
/// two transformed vertices: their signs are consistent, so no ray slips between them. Exact
/// zeros (the ray through an edge or a vertex) are recomputed in f64.
#[derive(Clone, Copy, Debug)]
pub struct WatertightRay {
    /// The permutation (kx, ky, kz) that makes the ray's largest direction component z.
    pub(crate) axes: [usize; 3],
    /// (dx/dz, dy/dz, 1/dz) in the permuted frame.
    pub(crate) shear: Vec3,
}

impl WatertightRay {
    pub fn new(ray: &Ray) -> Self {
        // An array, not a `Vec3`: indexing a `Vec3` by a variable compiles to a branch per
        // lane.
        let d = ray.direction.to_array();
        // Selects rather than branches throughout: the axis and its sign vary at random from
        // ray to ray. kz is the largest |d|, the first of equals (glam's `max_position`).
        let a = ray.direction.abs();
        let y_over_x = a.y > a.x;
        let xy_max = if y_over_x { a.y } else { a.x };
        let kz = if a.z > xy_max { 2 } else { usize::from(y_over_x) };
        const NEXT: [usize; 3] = [1, 2, 0];
        let (kx, ky) = (NEXT[kz], NEXT[NEXT[kz]]);
        // Keep the winding.
        let (kx, ky) = if d[kz] < 0.0 { (ky, kx) } else { (kx, ky) };
        // One vector division for the three quotients, each rounded as the scalar one.
        let shear = Vec3A::new(d[kx], d[ky], 1.0) / Vec3A::splat(d[kz]);
        Self { axes: [kx, ky, kz], shear: shear.into() }
    }

    #[inline(always)]
    pub fn intersect(&self, a: Vec3, b: Vec3, c: Vec3, ray: &Ray) -> Option<PrimHit> {
        let [kx, ky, kz] = self.axes;
        let (sx, sy, sz) = (self.shear.x, self.shear.y, self.shear.z);
        let vertices = [a, b, c];
        let [a, b, c] = [a, b, c].map(|p| (p - ray.origin).to_array());
        let (ax, ay) = (a[kx] - sx * a[kz], a[ky] - sy * a[kz]);
        let (bx, by) = (b[kx] - sx * b[kz], b[ky] - sy * b[kz]);
        let (cx, cy) = (c[kx] - sx * c[kz], c[ky] - sy * c[kz]);
        let (mut u, mut v, mut w) = (cx * by - cy * bx, ax * cy - ay * cx, bx * ay - by * ax);
        if u == 0.0 || v == 0.0 || w == 0.0 {
            let f = |p: f32, q: f32, r: f32, s: f32| (p as f64 * q as f64 - r as f64 * s as f64) as f32;
            (u, v, w) = (f(cx, by, cy, bx), f(ax, cy, ay, cx), f(bx, ay, by, ax));
        }
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 {
            return None;
        }
        let (az, bz, cz) = (sz * a[kz], sz * b[kz], sz * c[kz]);
        let t_scaled = u * az + v * bz + w * cz;
        let inv_det = 1.0 / det;
        let t = t_scaled * inv_det;
        // A t that rounding may have pushed above 0 is no hit: the ray starts on (or within
        // rounding of) this triangle's plane. Conservative bound of pbrt-v4 §6.8.4 on the error
        // of t from the error of the sheared coordinates and of the edge functions. Where all
        // three vertices lie ahead of the origin (their sheared z, whose signs are exact, all
        // positive), t is a weighted mean of positive distances and cannot be behind the
        // origin: the bound, which grows as t² over the triangle's size, is not asked. It had
        // rejected most hits on small, far or thin triangles (a blob of radius 1e-4 seen from
        // 1, a needle 1e-5 wide seen from 2.5), where it exceeded t itself.
        // The sheared x and y are lengths, and so is the error the shear adds (γ of the
        // vertices' extent along the ray's axis); the sheared z are distances in units of the
        // ray's parameter. pbrt-v4 adds the latter to the former, which holds for a unit
        // direction only: in an instance's scaled space (a 2000-wide floor under a scale of
        // 1000, seen from 1 above) the bound outgrew t and dropped every hit near the origin.
        let max_z = az.abs().max(bz.abs()).max(cz.abs());
        let max_z_length = a[kz].abs().max(b[kz].abs()).max(c[kz].abs());
        let max_x = ax.abs().max(bx.abs()).max(cx.abs());
        let max_y = ay.abs().max(by.abs()).max(cy.abs());
        let delta_z = gamma(3) * max_z;
        let delta_x = gamma(5) * (max_x + max_z_length);
        let delta_y = gamma(5) * (max_y + max_z_length);
        let delta_e = 2.0 * (gamma(2) * max_x * max_y + delta_y * max_x + delta_x * max_y);
        let max_e = u.abs().max(v.abs()).max(w.abs());
        let delta_t = 3.0 * (gamma(3) * max_e * max_z + delta_e * max_z + delta_z * max_e) * inv_det.abs();
        let ahead = az.min(bz).min(cz) > 0.0;
        if !ahead && t <= delta_t {
            return None;
        }
        if !ray.contains(t) {
            return None;
        }
        let t = plane_distance(vertices, ray, t);
        // u weighs vertex a, v vertex b, w vertex c; PrimHit keeps the weights of b and c.
        ray.contains(t).then_some(PrimHit { t, u: v * inv_det, v: w * inv_det, inner: 0 })
    }
}

/// The distance along `ray` to the plane of a triangle the watertight test has found hit,
/// in f64 from the f32 vertices (`watertight_t` where the ray runs in the plane).
///
/// The watertight test decides hit or miss exactly enough, but its own distance, the edge
/// functions' weighted mean of the vertices' distances, is ill-conditioned on needles and
/// slivers: an edge function's rounding error, small against the vertices' coordinates, is
/// large against the triangle's tiny area, and it moves t by that ratio times the spread of
/// the vertices' distances (4e-4 relative on a needle 1e-5 wide). The plane's normal from
/// the edges' cross product in f64, where differences of f32 are exact, keeps its error
/// about 1e-16 × length / width, so t is right to the f32 rounding. Called once per hit, not
/// per test.
#[inline]
pub(crate) fn plane_distance(vertices: [Vec3; 3], ray: &Ray, watertight_t: f32) -> f32 {
    let [a, b, c] = vertices.map(|p| p.as_dvec3());
    let normal = (b - a).cross(c - a);
    let t = (a - ray.origin.as_dvec3()).dot(normal) / ray.direction.as_dvec3().dot(normal);
    if t.is_finite() {
        t as f32
    } else {
        watertight_t
    }
}

/// Point, normals and uv from barycentrics. The point is interpolated from the vertices
/// rather than computed as O + tD, which is more accurate (pbrt-v4 §6.5.3).
/// The barycentric coordinates of `point` (in the triangle's plane) for the second and third
/// corners: p = a + u (b − a) + v (c − a).
pub(crate) fn barycentrics(point: Vec3, [a, b, c]: [Vec3; 3]) -> Vec2 {
    let (e1, e2, d) = (b - a, c - a, point - a);
    let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let (d1, d2) = (d.dot(e1), d.dot(e2));
    let denominator = d11 * d22 - d12 * d12;
    if denominator <= 0.0 {
        return Vec2::ZERO;
    }
    let u = (d22 * d1 - d12 * d2) / denominator;
    let v = (d11 * d2 - d12 * d1) / denominator;
    Vec2::new(u, v).clamp(Vec2::ZERO, Vec2::ONE)
}

pub(crate) fn triangle_surface(
    [a, b, c]: [Vec3; 3],
    normals: Option<[Vec3; 3]>,
    uvs: Option<[Vec2; 3]>,
    hit: &PrimHit,
) -> SurfaceGeometry {
    let w = 1.0 - hit.u - hit.v;
    let (point, error) = barycentric_point([a, b, c], hit.u, hit.v);
    let geometric_normal = (b - a).cross(c - a).normalize_or(Vec3::Z);
    let shading_normal = match normals {
        Some([na, nb, nc]) => {
            let n = (w * na + hit.u * nb + hit.v * nc).normalize_or(geometric_normal);
            // Keep the shading normal on the geometric normal's side.
            if n.dot(geometric_normal) < 0.0 {
                -n
            } else {
                n
            }
        }
        None => geometric_normal,
    };
    let uv = match uvs {
        Some([ta, tb, tc]) => w * ta + hit.u * tb + hit.v * tc,
        None => Vec2::new(hit.u, hit.v),
    };
    SurfaceGeometry { point, geometric_normal, shading_normal, uv, error }
}

/// (∂p/∂u, ∂p/∂v) of a triangle: with uvs, of the plane through the corners that carries them
/// (the solution of Δp = ∂p/∂u Δu + ∂p/∂v Δv for two edges; zero if the uvs are degenerate);
/// without, of its barycentrics of b and c (p = a + u (b − a) + v (c − a)).
pub(crate) fn triangle_tangents([a, b, c]: [Vec3; 3], uvs: Option<[Vec2; 3]>) -> (Vec3, Vec3) {
    let Some([ta, tb, tc]) = uvs else { return (b - a, c - a) };
    let (d02, d12) = (ta - tc, tb - tc);
    let (p02, p12) = (a - c, b - c);
    let determinant = d02.x * d12.y - d02.y * d12.x;
    let dpdu = (d12.y * p02 - d02.y * p12) / determinant;
    let dpdv = (d02.x * p12 - d12.x * p02) / determinant;
    if determinant != 0.0 && dpdu.is_finite() && dpdv.is_finite() {
        (dpdu, dpdv)
    } else {
        (Vec3::ZERO, Vec3::ZERO)
    }
}

/// The point with barycentric weights (1 − b1 − b2, b1, b2) of the corners, and the bound on
/// its error from interpolating (pbrt-v4 eq. 6.17).
pub(crate) fn barycentric_point([a, b, c]: [Vec3; 3], b1: f32, b2: f32) -> (Vec3, Vec3) {
    let corners = [a, b, c].map(LaneVec3::<f32>::from);
    let (point, error) = barycentric_point_lanes(corners, b1, b2);
    (point.into(), error.into())
}

/// `barycentric_point` in lanes.
#[inline(always)]
pub(crate) fn barycentric_point_lanes<L: Lanes>(
    [a, b, c]: [LaneVec3<L>; 3],
    b1: L,
    b2: L,
) -> (LaneVec3<L>, LaneVec3<L>) {
    let b0 = L::ONE - b1 - b2;
    let (pa, pb, pc) = (a * b0, b * b1, c * b2);
    (pa + pb + pc, (pa.abs() + pb.abs() + pc.abs()) * L::splat(gamma(7)))
}

/// A point uniform on the triangle's area, for sampling it as a light: `u` warped to
/// barycentric weights (`square_to_triangle`; the wavefront's lanes repeat that warp), and
/// the point's error bound.
pub(crate) fn sample_triangle(corners: [Vec3; 3], u: Vec2) -> (Vec3, Vec3) {
    let b = crate::sampling::warp::square_to_triangle(u);
    barycentric_point(corners, b.x, b.y)
}

/// Triangles sampled together uniformly by area, each with its own geometric normal: a polygon
/// or a box as one area light. A triangle is chosen by its share of the area (the first
/// coordinate of `u`, rescaled to its interval, picks it and then serves the point), so the
/// density is 1 / `area` everywhere on the surface.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct TriangleSurface {
    triangles: Vec<[Vec3; 3]>,
    normals: Vec<Vec3>,
    /// Cumulative area of the triangles, the last entry the total.
    cumulative: Vec<f32>,
}

impl TriangleSurface {
    /// `None` if the triangles have no area between them.
    pub fn new(triangles: Vec<[Vec3; 3]>, normals: Vec<Vec3>) -> Option<Self> {
        debug_assert_eq!(triangles.len(), normals.len());
        let mut total = 0.0f32;
        let cumulative = triangles
            .iter()
            .map(|[a, b, c]| {
                total += 0.5 * (*b - *a).cross(*c - *a).length();
                total
            })
            .collect();
        (total > 0.0 && total.is_finite()).then_some(Self { triangles, normals, cumulative })
    }

    pub fn area(&self) -> f32 {
        *self.cumulative.last().expect("a surface has a triangle")
    }

    /// A point uniform on the surface: (point, geometric normal, error bound).
    pub fn sample(&self, u: Vec2) -> (Vec3, Vec3, Vec3) {
        let target = u.x * self.area();
        let last = self.triangles.len() - 1;
        // The first triangle whose cumulative area passes the target; never one of no area.
        let i = self.cumulative.partition_point(|&c| c <= target).min(last);
        let below = if i == 0 { 0.0 } else { self.cumulative[i - 1] };
        let share = self.cumulative[i] - below;
        let ux = if share > 0.0 { ((target - below) / share).clamp(0.0, 1.0 - f32::EPSILON / 2.0) } else { 0.5 };
        let (point, error) = sample_triangle(self.triangles[i], Vec2::new(ux, u.y));
        (point, self.normals[i], error)
    }
}

/// Where the ray from `from` along `w` meets the triangle, as barycentric interpolation of
/// the corners (so the point lies on the triangle even where rounding put the ray a hair
/// outside an edge), with its error bound: a direction sampled in the triangle's solid angle
/// turned into its point.
pub(crate) fn triangle_point_along(from: Vec3, w: Vec3, [a, b, c]: [Vec3; 3]) -> Option<(Vec3, Vec3)> {
    let (e1, e2) = (b - a, c - a);
    let s1 = w.cross(e2);
    let divisor = s1.dot(e1);
    // Also refuses a NaN direction, which the clamps below would turn into corner a.
    if divisor == 0.0 || !divisor.is_finite() {
        return None;
    }
    let s = from - a;
    let b1 = (s.dot(s1) / divisor).max(0.0);
    let b2 = (w.dot(s.cross(e1)) / divisor).max(0.0);
    let (b1, b2) = if b1 + b2 > 1.0 { (b1 / (b1 + b2), b2 / (b1 + b2)) } else { (b1, b2) };
    Some(barycentric_point([a, b, c], b1, b2))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lanes::testing::{assert_lanes_equal, random_floats, random_vectors};
    use crate::lanes::{Vec3x8, LANES};
    use crate::shapes::test_util::TestRng;
    use wide::f32x8;

    const METHODS: [TriangleMethod; 3] =
        [TriangleMethod::Cramer, TriangleMethod::MollerTrumbore, TriangleMethod::Watertight];

    fn tri() -> Triangle {
        Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y)
    }

    #[test]
    fn hit_with_barycentrics() {
        let ray = Ray::new(Vec3::new(0.25, 0.5, -2.0), Vec3::Z);
        for m in METHODS {
            let h = tri().intersect(&ray, m).unwrap();
            assert_eq!((h.t, h.u, h.v), (2.0, 0.25, 0.5), "{m:?}");
            let g = tri().surface(&h);
            assert_eq!(g.point, Vec3::new(0.25, 0.5, 0.0));
            assert_eq!(g.geometric_normal, Vec3::Z);
        }
    }

    #[test]
    fn miss_behind_and_parallel() {
        for m in METHODS {
            assert!(tri().intersect(&Ray::new(Vec3::new(0.8, 0.8, -1.0), Vec3::Z), m).is_none());
            assert!(tri().intersect(&Ray::new(Vec3::new(0.2, 0.2, 1.0), Vec3::Z), m).is_none());
            assert!(tri().intersect(&Ray::new(Vec3::new(-1.0, 0.2, 0.0), Vec3::X), m).is_none());
        }
    }

    #[test]
    fn edge_and_vertex_hits_count() {
        for m in METHODS {
            for p in [Vec3::new(0.5, 0.0, -1.0), Vec3::new(0.5, 0.5, -1.0), Vec3::new(0.0, 0.3, -1.0)] {
                assert!(tri().intersect(&Ray::new(p, Vec3::Z), m).is_some(), "edge {p} {m:?}");
            }
            for v in tri().vertices {
                let h = tri().intersect(&Ray::new(v - Vec3::Z, Vec3::Z), m);
                assert_eq!(h.map(|h| h.t), Some(1.0), "vertex {v} {m:?}");
            }
        }
    }

    #[test]
    fn back_face_hits_too() {
        for m in METHODS {
            let h = tri().intersect(&Ray::new(Vec3::new(0.2, 0.2, 3.0), -Vec3::Z), m);
            // Within a few ulps: the watertight test computes t through a scaled shear.
            assert!(h.is_some_and(|h| (h.t - 3.0).abs() < 1e-6), "{m:?}: {h:?}");
        }
    }

    #[test]
    fn smooth_normals_and_uvs_interpolate() {
        let mut t = tri();
        t.normals = Some([Vec3::Z, Vec3::Z, Vec3::new(0.0, 1.0, 1.0).normalize()]);
        t.uvs = Some([Vec2::ZERO, Vec2::new(2.0, 0.0), Vec2::new(0.0, 4.0)]);
        let g = t.surface(&PrimHit { t: 1.0, u: 0.5, v: 0.25, inner: 0 });
        assert_eq!(g.uv, Vec2::new(1.0, 1.0));
        assert!(g.shading_normal.y > 0.0 && (g.shading_normal.length() - 1.0).abs() < 1e-6);
    }

    /// Two methods, one answer: random triangles and rays. Hit/miss may differ only where the
    /// f64 barycentrics put the hit within rounding of an edge.
    /// A closed mesh (an octahedron split finely, shared vertices) seen from inside: every ray
    /// must hit, including rays aimed exactly at vertices and along edges, where a test that is
    /// not watertight lets some through.
    #[test]
    fn watertight_test_lets_no_ray_escape_a_closed_mesh() {
        let mut rng = TestRng(21);
        let n = 24; // grid per octant face
        let mut triangles = Vec::new();
        for sx in [-1.0f32, 1.0] {
            for sy in [-1.0f32, 1.0] {
                for sz in [-1.0f32, 1.0] {
                    let corner = |i: usize, j: usize| {
                        let (a, b) = (i as f32 / n as f32, j as f32 / n as f32);
                        Vec3::new(sx * (1.0 - a - b), sy * a, sz * b)
                    };
                    for i in 0..n {
                        for j in 0..n - i {
                            triangles.push([corner(i, j), corner(i + 1, j), corner(i, j + 1)]);
                            if i + j + 1 < n {
                                triangles.push([corner(i + 1, j), corner(i + 1, j + 1), corner(i, j + 1)]);
                            }
                        }
                    }
                }
            }
        }
        let origin = Vec3::new(1e-3, -2e-3, 3e-3);
        let mut targets: Vec<Vec3> = triangles.iter().flat_map(|t| [t[0], 0.5 * (t[0] + t[1])]).collect();
        targets.extend((0..50_000).map(|_| rng.unit_vector()));
        for target in targets {
            let ray = Ray::new(origin, target - origin);
            let prepared = WatertightRay::new(&ray);
            let hit = triangles.iter().any(|&[a, b, c]| prepared.intersect(a, b, c, &ray).is_some());
            assert!(hit, "a ray toward {target} escaped the closed mesh");
        }
    }

    #[test]
    fn cramer_and_moller_trumbore_agree_on_a_million_rays() {
        let mut rng = TestRng(11);
        let mut disagreements = 0;
        for _ in 0..1_000_000 {
            let t = Triangle::new(rng.vec3(-1.0, 1.0), rng.vec3(-1.0, 1.0), rng.vec3(-1.0, 1.0));
            let origin = rng.vec3(-3.0, 3.0);
            let target = rng.vec3(-1.0, 1.0);
            let ray = Ray::new(origin, target - origin);
            let c = t.intersect(&ray, TriangleMethod::Cramer);
            for other in [TriangleMethod::MollerTrumbore, TriangleMethod::Watertight] {
                let m = t.intersect(&ray, other);
                match (c, m) {
                    (Some(a), Some(b)) => {
                        assert!((a.t - b.t).abs() <= 1e-4 * (1.0 + a.t), "{other:?}: {a:?} vs {b:?}");
                        assert!((a.u - b.u).abs() < 1e-3 && (a.v - b.v).abs() < 1e-3, "{other:?}: {a:?} vs {b:?}");
                    }
                    (None, None) => {}
                    _ => {
                        let margin = f64_edge_margin(&t, &ray);
                        assert!(margin < 1e-4, "{other:?}: hit/miss differ away from an edge: {c:?} {m:?} {margin}");
                        disagreements += 1;
                    }
                }
            }
        }
        assert!(disagreements < 400, "{disagreements}");
    }

    /// Smallest barycentric (and t) of the ray's crossing with the triangle's plane, in f64.
    fn f64_edge_margin(t: &Triangle, ray: &Ray) -> f64 {
        let v = |p: Vec3| glam::DVec3::new(p.x as f64, p.y as f64, p.z as f64);
        let [a, b, c] = t.vertices.map(v);
        let (o, d) = (v(ray.origin), v(ray.direction));
        let (e1, e2) = (b - a, c - a);
        let p = d.cross(e2);
        let det = e1.dot(p);
        let s = o - a;
        let u = s.dot(p) / det;
        let q = s.cross(e1);
        let w = d.dot(q) / det;
        let tt = e2.dot(q) / det;
        u.abs().min(w.abs()).min((1.0 - u - w).abs()).min(tt.abs()).min(det.abs())
    }

    /// Eight lanes compute one lane's bits, point and error bound.
    #[test]
    fn barycentric_point_in_eight_lanes_equals_one_lane() {
        let mut rng = crate::sampling::Rng::new(11, 5);
        for round in 0..2_000 {
            let scale = 10f32.powi(round % 9 - 4);
            let corners = [(); 3].map(|_| random_vectors(&mut rng, scale));
            let (b1, b2) = (random_floats(&mut rng, 0.5), random_floats(&mut rng, 0.5));
            let lanes = corners.map(|c| Vec3x8::from_fn(|k| c[k]));
            let (point, error) = barycentric_point_lanes(lanes, f32x8::from(b1), f32x8::from(b2));
            let scalar: [(Vec3, Vec3); LANES] =
                std::array::from_fn(|k| barycentric_point([corners[0][k], corners[1][k], corners[2][k]], b1[k], b2[k]));
            assert_lanes_equal(point, scalar.map(|(p, _)| p), "barycentric point");
            assert_lanes_equal(error, scalar.map(|(_, e)| e), "barycentric error");
        }
    }
}
