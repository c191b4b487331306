//! Sphere, by the course's two methods.
//!
//! Scene parameters: `center` (point, default origin), `radius` (> 0).
//! ```toml
//! [[shapes]]
//! type = "sphere"
//! center = [0, 1, 0]
//! radius = 1
//! material = "red"
//! ```
//! - **algebraic**: substitute the ray into |P − C|² = r² and solve the quadratic.
//! - **geometric**: project C − O on the ray (t_ca), compare the squared distance of the
//!   closest approach with r², then step back and forth by t_hc = √(r² − d²).
//!
//! Both pick the nearest root inside `(t_min, t_max)`, so an origin inside the sphere hits the
//! far wall, and an origin on the surface (with `t_min > 0`) does not hit itself at t = 0.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use super::{first_in_range, solve_quadratic, SurfaceGeometry};
use crate::geometry::{gamma, Aabb, Ray, Transform};
use crate::sampling::spherical::SphericalCap;
use crate::sampling::warp::square_to_uniform_sphere;
use crate::Named;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SphereMethod {
    #[default]
    Algebraic,
    Geometric,
}

impl Named for SphereMethod {
    const ALL: &'static [Self] = &[SphereMethod::Algebraic, SphereMethod::Geometric];

    fn name(self) -> &'static str {
        match self {
            SphereMethod::Algebraic => "algebraic",
            SphereMethod::Geometric => "geometric",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
}

impl Sphere {
    pub fn new(center: Vec3, radius: f32) -> Self {
        Self { center, radius }
    }

    pub fn bounds(&self) -> Aabb {
        Aabb::new(self.center - Vec3::splat(self.radius), self.center + Vec3::splat(self.radius))
    }

    pub fn intersect(&self, ray: &Ray, method: SphereMethod) -> Option<f32> {
        match method {
            SphereMethod::Algebraic => self.intersect_algebraic(ray),
            SphereMethod::Geometric => self.intersect_geometric(ray),
        }
    }

    /// (d·d)t² + 2(d·(O−C))t + |O−C|² − r² = 0.
    pub fn intersect_algebraic(&self, ray: &Ray) -> Option<f32> {
        let (t0, t1) = self.roots_algebraic(ray)?;
        first_in_range(ray, t0, t1)
    }

    /// Where the ray's line meets the sphere, in ascending order, by `method` (`None` if it
    /// misses, or by the geometric method if the sphere lies wholly behind the origin): the
    /// interval of the line inside the ball, which CSG combines.
    pub fn roots(&self, ray: &Ray, method: SphereMethod) -> Option<(f32, f32)> {
        match method {
            SphereMethod::Algebraic => self.roots_algebraic(ray),
            SphereMethod::Geometric => self.roots_geometric(ray),
        }
    }

    fn roots_algebraic(&self, ray: &Ray) -> Option<(f32, f32)> {
        let oc = ray.origin - self.center;
        let a = ray.direction.length_squared();
        let half_b = ray.direction.dot(oc);
        let c = oc.length_squared() - self.radius * self.radius;
        solve_quadratic(a, half_b, c)
    }

    /// The geometric construction, with distances along the unit direction, converted back to
    /// the ray's parameter at the end.
    pub fn intersect_geometric(&self, ray: &Ray) -> Option<f32> {
        let (t0, t1) = self.roots_geometric(ray)?;
        first_in_range(ray, t0, t1)
    }

    fn roots_geometric(&self, ray: &Ray) -> Option<(f32, f32)> {
        let length = ray.direction.length();
        let unit = ray.direction / length;
        let l = self.center - ray.origin;
        let r2 = self.radius * self.radius;
        let t_ca = l.dot(unit);
        let origin_outside = l.length_squared() > r2;
        if origin_outside && t_ca < 0.0 {
            return None; // the sphere is behind the ray
        }
        // |L − t_ca·D|² instead of |L|² − t_ca²: no cancellation for distant spheres.
        let d2 = (l - t_ca * unit).length_squared();
        if d2 > r2 {
            return None; // the ray passes the sphere by
        }
        let t_hc = (r2 - d2).sqrt();
        Some(((t_ca - t_hc) / length, (t_ca + t_hc) / length))
    }

    /// The point is projected back onto the sphere, which removes most of the error of
    /// `O + tD` (pbrt-v4 §6.8.5). uv: u = φ/2π around +y from +x, v = 1 at the north pole (+y).
    /// (∂p/∂u, ∂p/∂v) at `point`: p = c + r (sin θ cos φ, cos θ, sin θ sin φ), u = φ / 2π and
    /// v = 1 − θ / π. Both vanish at the poles, where φ is undefined.
    pub fn tangents(&self, point: Vec3) -> (Vec3, Vec3) {
        let d = point - self.center;
        let rho = d.x.hypot(d.z);
        if rho == 0.0 {
            return (Vec3::ZERO, Vec3::ZERO);
        }
        let dpdu = 2.0 * PI * Vec3::new(-d.z, 0.0, d.x);
        // ∂p/∂θ = (r cos θ cos φ, −r sin θ, r cos θ sin φ), with r cos θ = d.y and r sin θ = ρ.
        let dpdv = -PI * Vec3::new(d.y * d.x / rho, -rho, d.y * d.z / rho);
        (dpdu, dpdv)
    }

    pub fn surface(&self, point: Vec3) -> SurfaceGeometry {
        let mut normal = (point - self.center) / self.radius;
        normal = normal.normalize_or(Vec3::Y);
        let (point, error) = sphere_point(self.center, self.radius, normal);
        let phi = normal.z.atan2(normal.x).rem_euclid(2.0 * PI);
        let theta = normal.y.clamp(-1.0, 1.0).acos();
        SurfaceGeometry {
            point,
            geometric_normal: normal,
            shading_normal: normal,
            uv: Vec2::new(phi / (2.0 * PI), 1.0 - theta / PI),
            error,
        }
    }
}

/// The point of a sphere with outward normal `normal`, and its error bound: computing it
/// from the normal leaves a few roundings of the centre and the radius.
pub(crate) fn sphere_point(center: Vec3, radius: f32, normal: Vec3) -> (Vec3, Vec3) {
    (center + normal * radius, gamma(6) * (center.abs() + (normal * radius).abs()))
}

/// A point on a sphere light, sampled from the shading point `from` in the cone of directions
/// the sphere subtends (uniform in solid angle): (point, outward normal, error bound, the
/// cone's solid angle). `None` from inside the sphere or on it, where the caller samples by
/// area instead.
pub(crate) fn sample_sphere_seen_from(
    center: Vec3,
    radius: f32,
    from: Vec3,
    u: Vec2,
) -> Option<(Vec3, Vec3, Vec3, f32)> {
    let cap = SphericalCap::new(from, center, radius)?;
    let normal = cap.sample_normal(u);
    let (point, error) = sphere_point(center, radius, normal);
    Some((point, normal, error, cap.solid_angle()))
}

/// The solid angle of the cone `sample_sphere_seen_from` samples from `from`; `None` where it
/// samples none.
pub(crate) fn sphere_solid_angle_from(center: Vec3, radius: f32, from: Vec3) -> Option<f32> {
    SphericalCap::new(from, center, radius).map(|cap| cap.solid_angle())
}

/// A point uniform on the sphere's area: (point, outward normal, error bound).
pub(crate) fn sample_sphere(center: Vec3, radius: f32, u: Vec2) -> (Vec3, Vec3, Vec3) {
    let normal = square_to_uniform_sphere(u);
    let (point, error) = sphere_point(center, radius, normal);
    (point, normal, error)
}

/// A sphere under an affine transform that is not a similarity (an ellipsoid), sampled by
/// area: a point uniform on the object's sphere, mapped to world space. A linear map M scales
/// the area around a point of object normal n by J = |det M| · |M⁻ᵀ n|, so the world density
/// there is 1 / (4π r² J).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Ellipsoid {
    pub center: Vec3,
    pub radius: f32,
    pub transform: Transform,
    /// The world area, ∫ J dA over the object's sphere (by quadrature).
    pub area: f32,
}

impl Ellipsoid {
    pub fn new(center: Vec3, radius: f32, transform: Transform) -> Self {
        // Midpoint rule in (cos θ, φ), where the sphere's area element is uniform: J is
        // smooth, so 64 × 128 cells leave an error far below f32's.
        let (rows, columns) = (64, 128);
        let mut sum = 0.0f64;
        for i in 0..rows {
            for j in 0..columns {
                let u = Vec2::new((i as f32 + 0.5) / rows as f32, (j as f32 + 0.5) / columns as f32);
                sum += Self::jacobian(&transform, square_to_uniform_sphere(u)) as f64;
            }
        }
        let sphere_area = 4.0 * PI as f64 * (radius as f64).powi(2);
        Self { center, radius, transform, area: (sum / (rows * columns) as f64 * sphere_area) as f32 }
    }

    /// The area scale J at object normal `n`.
    fn jacobian(transform: &Transform, n: Vec3) -> f32 {
        let m = glam::Mat3::from_mat4(transform.to_world);
        m.determinant().abs() * (m.inverse().transpose() * n).length()
    }

    /// A point by area on the object's sphere, in world space: (point, world normal, error
    /// bound, world area density).
    pub fn sample(&self, u: Vec2) -> (Vec3, Vec3, Vec3, f32) {
        let (object_point, n, error) = sample_sphere(self.center, self.radius, u);
        let point = self.transform.point(object_point);
        // The object point's error carried through the map, plus the map's own roundings.
        let m = glam::Mat4::to_cols_array_2d(&self.transform.to_world).map(|c| Vec3::new(c[0], c[1], c[2]).abs());
        let linear = glam::Mat3::from_cols(m[0], m[1], m[2]);
        let error = linear * error + gamma(4) * (linear * object_point.abs() + m[3].abs());
        (point, self.transform.normal(n), error, self.pdf_area_at_normal(n))
    }

    /// The world area density of `sample` at the world point `point` on the surface.
    pub fn pdf_area(&self, point: Vec3) -> f32 {
        let n = (self.transform.to_object.transform_point3(point) - self.center).normalize_or(Vec3::Z);
        self.pdf_area_at_normal(n)
    }

    fn pdf_area_at_normal(&self, n: Vec3) -> f32 {
        1.0 / (4.0 * PI * self.radius * self.radius * Self::jacobian(&self.transform, n))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::test_util::TestRng;

    const METHODS: [SphereMethod; 2] = [SphereMethod::Algebraic, SphereMethod::Geometric];

    fn unit_sphere() -> Sphere {
        Sphere::new(Vec3::ZERO, 1.0)
    }

    #[test]
    fn hit_from_outside() {
        let ray = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z);
        for m in METHODS {
            assert_eq!(unit_sphere().intersect(&ray, m), Some(4.0), "{m:?}");
        }
    }

    #[test]
    fn unnormalised_direction_scales_t() {
        let ray = Ray::new(Vec3::new(0.0, 0.0, -5.0), 2.0 * Vec3::Z);
        for m in METHODS {
            assert_eq!(unit_sphere().intersect(&ray, m), Some(2.0), "{m:?}");
        }
    }

    #[test]
    fn miss_and_behind() {
        let miss = Ray::new(Vec3::new(0.0, 2.0, -5.0), Vec3::Z);
        let behind = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::Z);
        for m in METHODS {
            assert_eq!(unit_sphere().intersect(&miss, m), None);
            assert_eq!(unit_sphere().intersect(&behind, m), None);
        }
    }

    #[test]
    fn origin_inside_hits_far_wall() {
        let ray = Ray::new(Vec3::new(0.0, 0.0, 0.5), Vec3::Z);
        for m in METHODS {
            assert_eq!(unit_sphere().intersect(&ray, m), Some(0.5), "{m:?}");
        }
    }

    #[test]
    fn origin_on_surface_does_not_hit_itself() {
        // Leaving outward: no hit. Going inward: the far side at t = 2.
        let out = Ray::with_range(Vec3::new(0.0, 0.0, -1.0), -Vec3::Z, 1e-4, f32::INFINITY);
        let inward = Ray::with_range(Vec3::new(0.0, 0.0, -1.0), Vec3::Z, 1e-4, f32::INFINITY);
        for m in METHODS {
            assert_eq!(unit_sphere().intersect(&out, m), None, "{m:?}");
            assert_eq!(unit_sphere().intersect(&inward, m), Some(2.0), "{m:?}");
        }
    }

    #[test]
    fn tangent_ray_touches_at_one_point() {
        let ray = Ray::new(Vec3::new(-3.0, 1.0, 0.0), Vec3::X);
        for m in METHODS {
            assert_eq!(unit_sphere().intersect(&ray, m), Some(3.0), "{m:?}");
        }
    }

    #[test]
    fn t_max_limits_the_hit() {
        let ray = Ray::with_range(Vec3::new(0.0, 0.0, -5.0), Vec3::Z, 0.0, 3.9);
        for m in METHODS {
            assert_eq!(unit_sphere().intersect(&ray, m), None);
        }
    }

    #[test]
    fn surface_normal_and_uv() {
        let s = Sphere::new(Vec3::new(1.0, 2.0, 3.0), 2.0);
        let g = s.surface(Vec3::new(1.0, 4.0, 3.0));
        assert_eq!(g.geometric_normal, Vec3::Y);
        assert!((g.uv.y - 1.0).abs() < 1e-6);
        let g = s.surface(Vec3::new(3.0, 2.0, 3.0));
        assert!((g.uv - Vec2::new(0.0, 0.5)).length() < 1e-6);
    }

    /// Two methods, one answer, on a million random rays from inside, outside and near the
    /// sphere. Disagreement on hit/miss is allowed only for near-tangent rays, whose outcome
    /// rounding may decide either way.
    #[test]
    fn algebraic_and_geometric_agree_on_a_million_rays() {
        let mut rng = TestRng(7);
        let mut disagreements = 0;
        for _ in 0..1_000_000 {
            let sphere = Sphere::new(rng.vec3(-2.0, 2.0), rng.range(0.1, 3.0));
            let origin = sphere.center + rng.unit_vector() * rng.range(0.0, 4.0 * sphere.radius);
            let ray = Ray::new(origin, rng.unit_vector() * rng.range(0.5, 2.0));
            let a = sphere.intersect_algebraic(&ray);
            let g = sphere.intersect_geometric(&ray);
            match (a, g) {
                (Some(ta), Some(tg)) => {
                    let scale = 1.0 + ta.abs() + sphere.radius / ray.direction.length();
                    assert!((ta - tg).abs() <= 1e-4 * scale, "t differs: {ta} vs {tg} for {ray:?}");
                }
                (None, None) => {}
                _ => {
                    // Near-tangent: the closest approach is within rounding of the radius.
                    let unit = ray.direction.normalize();
                    let l = sphere.center - ray.origin;
                    let d = (l - l.dot(unit) * unit).length();
                    let near_tangent = (d - sphere.radius).abs() < 1e-4 * sphere.radius;
                    let near_surface = (l.length() - sphere.radius).abs() < 1e-4 * sphere.radius;
                    assert!(near_tangent || near_surface, "hit/miss differ: {a:?} vs {g:?} for {ray:?}");
                    disagreements += 1;
                }
            }
        }
        assert!(disagreements < 100, "{disagreements} disagreements");
    }
}
