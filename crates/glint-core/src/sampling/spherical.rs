//! Directions uniform in the solid angle a light subtends: a spherical triangle (Arvo 1995,
//! "Stratified Sampling of Spherical Triangles") and a spherical cap (the cone of directions
//! toward a sphere). Sampling a nearby light by solid angle rather than by area takes the
//! 1/d² and cos θ_light variation across it out of the estimate; a triangle's samples can also
//! follow the receiver's cos θ (`SphericalTriangle::sample_toward`).

use glam::{DVec3, Vec2, Vec3};

use crate::geometry::{gamma, orthonormal_basis};
use crate::sampling::warp::{bilinear_pdf, square_to_bilinear};

/// `v` made perpendicular to the unit vector `axis`, normalised (Gram–Schmidt).
fn perpendicular(v: DVec3, axis: DVec3) -> DVec3 {
    (v - v.dot(axis) * axis).normalize_or_zero()
}

/// The solid angle of the spherical triangle with unit corners a, b, c: Van Oosterom and
/// Strackee (1983), one arctangent, stable for small and large triangles alike.
fn solid_angle(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    2.0 * a.dot(b.cross(c)).abs().atan2(1.0 + a.dot(b) + b.dot(c) + c.dot(a))
}

/// A triangle as seen from a point: its corners as unit directions and its solid angle.
///
/// In f64: Arvo's construction subtracts nearly equal quantities for thin triangles (a sliver
/// of 3·10⁻⁴ sr came out 45 % of its own size off in f32), and a wrong direction would be
/// clamped onto the triangle unnoticed, biasing the estimate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphericalTriangle {
    a: DVec3,
    b: DVec3,
    c: DVec3,
    /// The interior angle α at corner `a`, by its cosine and sine.
    cos_alpha: f64,
    sin_alpha: f64,
    solid_angle: f64,
}

impl SphericalTriangle {
    /// The triangle `corners` seen from `p`; `None` when it subtends no solid angle (`p` on
    /// its plane, or a degenerate triangle).
    pub fn new(p: Vec3, corners: [Vec3; 3]) -> Option<Self> {
        let [a, b, c] = corners.map(|v| (v.as_dvec3() - p.as_dvec3()).normalize_or_zero());
        let (ab, ac) = (a.cross(b), a.cross(c));
        let (ab_length, ac_length) = (ab.length(), ac.length());
        let triple = a.dot(b.cross(c));
        if ab_length == 0.0 || ac_length == 0.0 || triple == 0.0 {
            return None;
        }
        let solid_angle = solid_angle(a, b, c);
        // α is the angle between the great circles a–b and a–c, whose normals are a × b and
        // a × c; (a × b) × (a × c) = (a · (b × c)) a gives its sine without trigonometry.
        let cos_alpha = (ab.dot(ac) / (ab_length * ac_length)).clamp(-1.0, 1.0);
        let sin_alpha = (triple.abs() / (ab_length * ac_length)).min(1.0);
        (solid_angle > 0.0).then_some(Self { a, b, c, cos_alpha, sin_alpha, solid_angle })
    }

    pub fn solid_angle(&self) -> f32 {
        self.solid_angle as f32
    }

    /// A direction uniform over the triangle's solid angle: `u.x` chooses the sub-triangle
    /// (a, b, ĉ) with ĉ on the arc from a to c that holds the fraction `u.x` of the area, `u.y`
    /// a point on the arc from b to ĉ so that the area is swept uniformly.
    pub fn sample(&self, u: Vec2) -> Vec3 {
        let Self { a, b, c, cos_alpha, sin_alpha, .. } = *self;
        // s, t: sin and cos of (Â − α), Â = u.x · Ω the sub-triangle's area.
        let (sin_area, cos_area) = (u.x as f64 * self.solid_angle).sin_cos();
        let s = sin_area * cos_alpha - cos_area * sin_alpha;
        let t = cos_area * cos_alpha + sin_area * sin_alpha;
        // Arvo's u and v (his figure 2), named for the sides they come from.
        let (arvo_u, arvo_v) = (t - cos_alpha, s + sin_alpha * a.dot(b));
        // cos of the arc from a to ĉ (Arvo's equation for the sub-triangle's area).
        let cos_arc = ((arvo_v * t - arvo_u * s) * cos_alpha - arvo_v) / ((arvo_v * s + arvo_u * t) * sin_alpha);
        let cos_arc = cos_arc.clamp(-1.0, 1.0);
        let c_hat = cos_arc * a + (1.0 - cos_arc * cos_arc).max(0.0).sqrt() * perpendicular(c, a);
        let z = 1.0 - u.y as f64 * (1.0 - c_hat.dot(b));
        (z * b + (1.0 - z * z).max(0.0).sqrt() * perpendicular(c_hat, b)).as_vec3()
    }

    /// A direction and its solid-angle density: uniform, or with `receiver` (a normal) also
    /// following |cos θ| against it, approximately: the square is first warped by the bilinear
    /// interpolation of the cosines toward the corners (pbrt-v4's product sampling).
    pub fn sample_toward(&self, u: Vec2, receiver: Option<Vec3>) -> (Vec3, f32) {
        let (u, warp_pdf) = match receiver {
            Some(n) => {
                let w = self.corner_cosines(n);
                let warped = square_to_bilinear(u, w);
                (warped, bilinear_pdf(warped, w))
            }
            None => (u, 1.0),
        };
        (self.sample(u), warp_pdf / self.solid_angle())
    }

    /// The solid-angle density with which `sample_toward` gives the direction `w`.
    pub fn pdf(&self, w: Vec3, receiver: Option<Vec3>) -> f32 {
        let warp_pdf = receiver.map_or(1.0, |n| bilinear_pdf(self.invert(w), self.corner_cosines(n)));
        warp_pdf / self.solid_angle()
    }

    /// |cos θ| against `normal` at the directions `sample` gives the corners of the unit square,
    /// [u(0,0), u(1,0), u(0,1), u(1,1)] → [b, b, a, c], each at least 0.01 so that the warp
    /// built from them still reaches every direction.
    fn corner_cosines(&self, normal: Vec3) -> [f32; 4] {
        let n = normal.as_dvec3();
        let cos = |v: DVec3| (n.dot(v).abs() as f32).max(0.01);
        [cos(self.b), cos(self.b), cos(self.a), cos(self.c)]
    }

    /// The `u` that `sample` maps to the direction `w` inside the triangle: the inverse warp.
    pub fn invert(&self, w: Vec3) -> Vec2 {
        let Self { a, b, c, .. } = *self;
        let w = w.as_dvec3().normalize();
        // ĉ: where the great circle through b and w crosses the arc from a to c.
        let mut c_hat = b.cross(w).cross(c.cross(a)).normalize_or_zero();
        if c_hat.dot(a + c) < 0.0 {
            c_hat = -c_hat;
        }
        let sub_area = solid_angle(a, b, c_hat);
        let u_x = (sub_area / self.solid_angle).clamp(0.0, 1.0);
        let u_y = ((1.0 - w.dot(b)) / (1.0 - c_hat.dot(b))).clamp(0.0, 1.0);
        Vec2::new(u_x as f32, u_y as f32)
    }
}

/// The cone of directions from a point outside a sphere toward it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphericalCap {
    /// Unit direction from the point to the sphere's centre.
    axis: Vec3,
    sin2_max: f32,
    /// 1 − cos θ_max, as sin² θ_max / (1 + cos θ_max): no cancellation for small cones.
    one_minus_cos_max: f32,
}

/// Below this sin² θ_max (about 1.5°) the cone is sampled in sin² θ: 1 − cos θ would cancel.
const SMALL_CONE: f32 = 0.000_685_23;

impl SphericalCap {
    /// The cap a sphere subtends from `p`; `None` from inside it and from its surface: a
    /// shading point on the sphere sees its inside, whatever side rounding put it on.
    pub fn new(p: Vec3, center: Vec3, radius: f32) -> Option<Self> {
        let to_center = center - p;
        let d2 = to_center.length_squared();
        // A computed hit point on a sphere is off by a few roundings of its coordinates
        // (pbrt-v4 bounds it by γ₅|p|), and |p − centre| adds a few more: allow four times
        // that, in the scene's own scale.
        let slack = 4.0 * gamma(5) * (p.abs().max_element() + center.abs().max_element() + radius);
        if d2 <= (radius + slack) * (radius + slack) {
            return None;
        }
        let sin2_max = radius * radius / d2;
        let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
        Some(Self { axis: to_center / d2.sqrt(), sin2_max, one_minus_cos_max: sin2_max / (1.0 + cos_max) })
    }

    pub fn solid_angle(&self) -> f32 {
        2.0 * std::f32::consts::PI * self.one_minus_cos_max
    }

    /// A direction uniform over the cap, as the unit normal of the sphere's point it meets
    /// (the visible side): `center + radius · normal` is the sampled point.
    pub fn sample_normal(&self, u: Vec2) -> Vec3 {
        let (sin2_theta, cos_theta) = if self.sin2_max < SMALL_CONE {
            let sin2 = self.sin2_max * u.x;
            (sin2, (1.0 - sin2).sqrt())
        } else {
            let one_minus_cos = u.x * self.one_minus_cos_max;
            let cos = 1.0 - one_minus_cos;
            (one_minus_cos * (1.0 + cos), cos)
        };
        // The angle at the centre between the axis back to p and the sampled point: the law of
        // sines in the triangle (p, centre, point), solved for the nearer intersection.
        let sin_max = self.sin2_max.sqrt();
        let cos_alpha = sin2_theta / sin_max + cos_theta * (1.0 - sin2_theta / self.sin2_max).max(0.0).sqrt();
        let sin_alpha = (1.0 - cos_alpha * cos_alpha).max(0.0).sqrt();
        let phi = 2.0 * std::f32::consts::PI * u.y;
        let (tangent, bitangent) = orthonormal_basis(self.axis);
        let (sin_phi, cos_phi) = phi.sin_cos();
        -(cos_alpha * self.axis) + sin_alpha * (cos_phi * tangent + sin_phi * bitangent)
    }

    /// The `u` that `sample_normal` maps to the point seen in direction `w` (unit, inside the
    /// cap): the inverse warp. The point and its direction share the azimuth about the axis.
    pub fn invert(&self, w: Vec3) -> Vec2 {
        // sin² θ from the cross product: 1 − cos² θ would cancel near the axis.
        let sin2_theta = w.cross(self.axis).length_squared();
        let u_x = if self.sin2_max < SMALL_CONE {
            sin2_theta / self.sin2_max
        } else {
            sin2_theta / (1.0 + w.dot(self.axis)) / self.one_minus_cos_max
        };
        let (tangent, bitangent) = orthonormal_basis(self.axis);
        let phi = w.dot(bitangent).atan2(w.dot(tangent)).rem_euclid(2.0 * std::f32::consts::PI);
        Vec2::new(u_x.clamp(0.0, 1.0), phi / (2.0 * std::f32::consts::PI))
    }
}

/// The solid angle of a triangle seen from `from` by Girard's theorem, in f64: its interior
/// angles' excess over π. An independent route for tests.
#[cfg(test)]
pub(crate) fn girard_solid_angle(from: Vec3, corners: [Vec3; 3]) -> f64 {
    let [a, b, c] = corners.map(|x| (x - from).as_dvec3().normalize());
    let angle = |x: glam::DVec3, y: glam::DVec3, z: glam::DVec3| {
        x.cross(y).normalize().dot(x.cross(z).normalize()).clamp(-1.0, 1.0).acos()
    };
    angle(a, b, c) + angle(b, c, a) + angle(c, a, b) - std::f64::consts::PI
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::chi2::chi2_test_with_resolution;
    use crate::shapes::test_util::ray_meets_triangle;

    fn corners() -> [Vec3; 3] {
        [Vec3::new(1.0, -0.5, 2.0), Vec3::new(2.0, 0.5, 2.5), Vec3::new(0.5, 1.0, 1.5)]
    }

    fn inside(from: Vec3, w: Vec3, tri: [Vec3; 3]) -> bool {
        ray_meets_triangle(from, w, tri).is_some()
    }

    /// An octant of the sphere is a spherical triangle with three right angles: area 4π/8.
    #[test]
    fn an_octant_has_an_eighth_of_the_sphere() {
        let t = SphericalTriangle::new(Vec3::ZERO, [Vec3::X, Vec3::Y, Vec3::Z]).unwrap();
        assert!((t.solid_angle() - std::f32::consts::FRAC_PI_2).abs() < 1e-6, "{}", t.solid_angle());
        assert!(SphericalTriangle::new(Vec3::new(0.5, 0.5, 0.0), [Vec3::X, Vec3::Y, Vec3::ZERO]).is_none());
    }

    /// Girard's theorem in f64, an independent route to the same solid angle: the interior
    /// angles' excess over π.
    #[test]
    fn solid_angle_agrees_with_girards_theorem() {
        let mut rng = crate::sampling::Rng::for_sample(5, 6, 7);
        let mut tested = 0;
        for _ in 0..1000 {
            let mut v = || Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - 1.0;
            let (p, corners) = (v(), [v(), v(), v()]);
            let Some(t) = SphericalTriangle::new(p, corners) else { continue };
            let expected = girard_solid_angle(p, corners);
            let [a, b, c] = corners.map(|x| (x - p).as_dvec3().normalize());
            assert!((t.solid_angle() as f64 - expected).abs() < 1e-6 * (1.0 + expected), "{t:?} vs {expected}");
            let cos_alpha = a.cross(b).normalize().dot(a.cross(c).normalize());
            assert!(
                (t.cos_alpha - cos_alpha).abs() < 1e-9 && (t.sin_alpha - (1.0 - cos_alpha.powi(2)).sqrt()).abs() < 1e-6
            );
            tested += 1;
        }
        assert!(tested > 900);
    }

    #[test]
    fn spherical_triangle_sampling_is_uniform_in_solid_angle() {
        let tri = corners();
        // In front, close (2.3 sr), and nearly in the triangle's plane (wide, flat angles).
        for from in [Vec3::new(0.64, 0.43, 2.84), Vec3::new(1.1, 0.35, 2.05), Vec3::new(0.2, 0.6, 2.05)] {
            let t = SphericalTriangle::new(from, tri).unwrap();
            assert!(t.solid_angle() > 0.2, "from {from}: {} sr, too small for the histogram", t.solid_angle());
            let pdf = |w: Vec3| if inside(from, w, tri) { 1.0 / t.solid_angle() as f64 } else { 0.0 };
            let r = chi2_test_with_resolution(|u| Some(t.sample(u)), pdf, 300_000, 21, 41, 3, 64);
            assert!(r.p_value > 0.01, "from {from}: p = {}", r.p_value);
        }
    }

    /// Round trips from near and far, and on a sliver of 3.3·10⁻⁴ sr with a 0.95° corner,
    /// where Arvo's construction cancels most (off by 45 % of the sliver's size in f32).
    #[test]
    fn spherical_triangle_sampling_round_trips() {
        let sliver = [Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.2, 0.0, 1.0), Vec3::new(0.2, 0.0033, 1.0)];
        for (from, tri) in [
            (Vec3::new(0.64, 0.43, 2.84), corners()),
            (Vec3::new(-3.0, 2.0, 1.0), corners()),
            (Vec3::ZERO, sliver),
            (Vec3::ZERO, [sliver[1], sliver[2], sliver[0]]),
        ] {
            let t = SphericalTriangle::new(from, tri).unwrap();
            for i in 1..20 {
                for j in 1..20 {
                    let u = Vec2::new(i as f32 / 20.0, j as f32 / 20.0);
                    let w = t.sample(u);
                    assert!(inside(from, w, tri), "{u} -> {w} outside");
                    let back = t.invert(w);
                    assert!((back - u).abs().max_element() < 2e-3, "from {from}, {tri:?}: {u} -> {back}");
                }
            }
        }
    }

    /// From inside the sphere and from points on it (rounded either way) there is no cap.
    #[test]
    fn no_cap_from_inside_or_on_the_sphere() {
        let (center, radius) = (Vec3::new(0.3, -0.2, 1.5), 0.6);
        assert!(SphericalCap::new(center, center, radius).is_none());
        for w in [Vec3::X, Vec3::new(0.6, 0.0, 0.8), Vec3::new(-0.48, 0.6, 0.64)] {
            let on = center + radius * w;
            assert!(SphericalCap::new(on, center, radius).is_none());
            assert!(SphericalCap::new(center + radius * 1.000_001 * w, center, radius).is_none());
            assert!(SphericalCap::new(center + radius * 1.001 * w, center, radius).is_some());
        }
        // Far from the origin a hit point's rounding is larger than 1e-4 of the radius.
        let (far, unit) = (Vec3::new(1000.0, -700.0, 300.0), 1.0);
        for w in [Vec3::X, Vec3::new(0.6, 0.0, 0.8), Vec3::new(-0.48, 0.6, 0.64)] {
            assert!(SphericalCap::new(far + unit * w, far, unit).is_none());
            assert!(SphericalCap::new(far + 1.01 * unit * w, far, unit).is_some());
        }
    }

    #[test]
    fn spherical_cap_sampling_round_trips() {
        let (center, radius) = (Vec3::new(0.3, -0.2, 1.5), 0.6);
        // A wide cone, and one narrow enough for the small-angle form.
        for (from, tolerance) in [(Vec3::ZERO, 1e-3), (Vec3::new(0.0, 0.0, -40.0), 1e-3)] {
            let cap = SphericalCap::new(from, center, radius).unwrap();
            for i in 1..20 {
                for j in 1..20 {
                    let u = Vec2::new(i as f32 / 20.0, j as f32 / 20.0);
                    let w = (center + radius * cap.sample_normal(u) - from).normalize();
                    let back = cap.invert(w);
                    assert!((back - u).abs().max_element() < tolerance, "from {from}: {u} -> {back}");
                }
            }
        }
    }

    #[test]
    fn spherical_cap_sampling_is_uniform_in_solid_angle() {
        let (center, radius) = (Vec3::new(0.3, -0.2, 1.5), 0.6);
        for (from, r) in [(Vec3::ZERO, radius), (Vec3::new(0.0, 0.0, -40.0), radius)] {
            let cap = SphericalCap::new(from, center, r).unwrap();
            let mut points_on_sphere = true;
            let sample = |u: Vec2| {
                let n = cap.sample_normal(u);
                let p = center + r * n;
                points_on_sphere &= n.is_normalized() && (p - from).dot(n) < 1e-4 * (p - from).length();
                Some((p - from).normalize())
            };
            let axis = (center - from).normalize();
            let cos_max = (1.0 - r * r / (center - from).length_squared()).sqrt() as f64;
            let pdf = |w: Vec3| {
                if w.dot(axis) as f64 >= cos_max {
                    1.0 / cap.solid_angle() as f64
                } else {
                    0.0
                }
            };
            if from == Vec3::ZERO {
                let r = chi2_test_with_resolution(sample, pdf, 300_000, 21, 41, 9, 64);
                assert!(r.p_value > 0.01, "p = {}", r.p_value);
            } else {
                // A cone of 0.86°, narrower than a histogram cell: check the outline instead.
                let mut rng = crate::sampling::Rng::for_sample(1, 1, 1);
                let mut sample = sample;
                for _ in 0..10_000 {
                    let w = sample(Vec2::new(rng.next_f32(), rng.next_f32())).unwrap();
                    assert!(w.dot(axis) as f64 >= cos_max - 1e-6);
                }
                let expected = 2.0 * std::f64::consts::PI * (1.0 - cos_max);
                assert!((cap.solid_angle() as f64 / expected - 1.0).abs() < 2e-3);
            }
            assert!(points_on_sphere, "a sampled point faces away from {from}");
        }
    }
}
