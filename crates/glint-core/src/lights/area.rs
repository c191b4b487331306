//! Area lights: every primitive whose material emits (`emission` on a material). They are
//! sampled for next-event estimation from a shading point: an emitter chosen in proportion to
//! its power, then a point on it:
//!
//! * spheres by the cone of directions they subtend (uniform in solid angle; by area from
//!   inside);
//! * triangles uniformly on their area by default, the density converted to solid angle
//!   (pdf_ω = pdf_A · d² / |cos θ_light|), or, with `TriangleSampling::SolidAngle`, uniformly
//!   in the spherical triangle they subtend (Arvo 1995), warped by the receiver's cos θ when
//!   its normal is given (pbrt-v4's bilinear approximation: 13× lower variance of the
//!   irradiance from one large, close triangle in a test below). Solid-angle sampling has less
//!   noise next to a light but costs more: on the Cornell box it lowered the error by 2 % at
//!   equal samples and took 10–24 % longer (docs/performance.md), so area is the default.
//!
//! Sampled: triangles (triangle shapes, mesh triangles, quads; any transform, taken in world
//! space) and spheres without a transform. Other emissive shapes still emit: a path finds them
//! by BSDF sampling, whose multiple-importance weight is then 1 since their light pdf is 0, so
//! the estimate stays unbiased, only noisier.

use glam::{Vec2, Vec3};

use crate::geometry::orthonormal_basis;
use crate::materials::Material;
use crate::sampling::spherical::{SphericalCap, SphericalTriangle};
use crate::sampling::warp::{
    cosine_hemisphere_pdf, square_to_cosine_hemisphere, square_to_triangle, square_to_uniform_sphere,
};
use crate::scene::Object;
use crate::shapes::{barycentric_point, sphere_point, Shape};
use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
enum EmitterShape {
    Triangle { a: Vec3, b: Vec3, c: Vec3, normal: Vec3, area: f32 },
    Sphere { center: Vec3, radius: f32 },
}

impl EmitterShape {
    fn area(&self) -> f32 {
        match *self {
            EmitterShape::Triangle { area, .. } => area,
            EmitterShape::Sphere { radius, .. } => 4.0 * std::f32::consts::PI * radius * radius,
        }
    }
}

/// A point sampled on an emitter, before its radiance toward the shading point is known.
struct PointSample {
    point: Vec3,
    normal: Vec3,
    error: Vec3,
    /// Solid-angle density at the shading point, including the emitter's selection.
    pdf: f32,
}

#[derive(Clone, Debug, PartialEq)]
struct Emitter {
    shape: EmitterShape,
    radiance: Rgb,
    two_sided: bool,
}

/// A point sampled on a light, seen from a shading point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    pub point: Vec3,
    pub normal: Vec3,
    /// Error bound of `point`, to offset the shadow ray's far end.
    pub error: Vec3,
    /// Radiance leaving the light toward the shading point (0 from an emitter's back).
    pub radiance: Rgb,
    /// Solid-angle density at the shading point, including the emitter's selection probability.
    pub pdf: f32,
}

/// How a triangle light is sampled from a shading point.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TriangleSampling {
    /// A point uniform on its area.
    #[default]
    Area,
    /// A direction in its solid angle (where that is accurate, else by area): uniform, or,
    /// given the receiver's normal, warped toward its cos θ.
    SolidAngle,
}

impl TriangleSampling {
    pub const ALL: [TriangleSampling; 2] = [TriangleSampling::Area, TriangleSampling::SolidAngle];

    pub fn name(self) -> &'static str {
        match self {
            TriangleSampling::Area => "area",
            TriangleSampling::SolidAngle => "solid-angle",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }
}

#[derive(Clone, Debug, Default)]
pub struct AreaLights {
    pub triangle_sampling: TriangleSampling,
    emitters: Vec<Emitter>,
    /// Cumulative selection probabilities (by power), last = 1.
    cdf: Vec<f32>,
    /// Per object: index of its first emitter (its primitive p is `base + p`), or `NONE`.
    object_base: Vec<u32>,
    /// Emitted power (flux, mean over RGB): Σ L_e · π · area · sides.
    total_power: f32,
    /// Every emitter as a triangle, in order, then a black one no `choose_index` picks (for
    /// lanes without a light); `None` if some emitter is a sphere. For the path tracer's lanes.
    triangle_table: Option<Vec<TriangleEmitter>>,
}

/// A triangle emitter as the path tracer's SIMD lanes read it (`AreaLights::triangle_table`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TriangleEmitter {
    pub corners: [Vec3; 3],
    pub normal: Vec3,
    pub area: f32,
    pub radiance: Rgb,
    pub two_sided: bool,
    /// The probability of choosing this emitter.
    pub selection: f32,
}

/// A particle leaving an area light (for light tracing and photon mapping).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AreaEmission {
    pub point: Vec3,
    /// The side of the surface the particle leaves from.
    pub normal: Vec3,
    pub error: Vec3,
    pub direction: Vec3,
    /// The emitter's radiance L_e and whether it emits from both sides.
    pub radiance: Rgb,
    pub two_sided: bool,
    /// Density of `point` per unit area, including the emitter's selection probability.
    pub pdf_area: f32,
    /// Density of `direction` per solid angle (cosine-weighted on the emitting side).
    pub pdf_direction: f32,
}

const NONE: u32 = u32::MAX;

impl AreaLights {
    pub fn new(objects: &[Object], materials: &[Material]) -> Self {
        let mut emitters = Vec::new();
        let mut object_base = vec![NONE; objects.len()];
        for (o, object) in objects.iter().enumerate() {
            let Some(material) = materials.get(object.material as usize) else { continue };
            let (emission, two_sided) = material.emission();
            if emission == Rgb::ZERO {
                continue;
            }
            let triangles: Vec<[Vec3; 3]> = match &object.shape {
                Shape::Mesh(mesh) => (0..mesh.triangle_count()).map(|i| mesh.triangle_vertices(i)).collect(),
                Shape::Triangle(t) => vec![t.vertices],
                Shape::Sphere(s) if object.transform.is_none() => {
                    object_base[o] = emitters.len() as u32;
                    emitters.push(Emitter {
                        shape: EmitterShape::Sphere { center: s.center, radius: s.radius },
                        radiance: emission,
                        two_sided,
                    });
                    continue;
                }
                _ => continue, // found by BSDF sampling only
            };
            object_base[o] = emitters.len() as u32;
            for [a, b, c] in triangles {
                let (a, b, c) = match &object.transform {
                    Some(t) => (t.point(a), t.point(b), t.point(c)),
                    None => (a, b, c),
                };
                let cross = (b - a).cross(c - a);
                let area = 0.5 * cross.length();
                emitters.push(Emitter {
                    shape: EmitterShape::Triangle { a, b, c, normal: cross.normalize_or(Vec3::Z), area },
                    radiance: if area > 0.0 { emission } else { Rgb::ZERO },
                    two_sided,
                });
            }
        }
        let powers: Vec<f32> = emitters
            .iter()
            .map(|e| {
                let sides = if e.two_sided { 2.0 } else { 1.0 };
                e.radiance.dot(Rgb::splat(1.0 / 3.0)) * e.shape.area() * sides
            })
            .collect();
        let total: f32 = powers.iter().sum();
        let mut cdf = Vec::with_capacity(powers.len());
        let mut acc = 0.0;
        for p in &powers {
            acc += p / total;
            cdf.push(acc);
        }
        if let Some(last) = cdf.last_mut() {
            *last = 1.0;
        }
        if total <= 0.0 {
            return Self::default_for(objects.len());
        }
        Self {
            triangle_table: triangle_table(&emitters, &cdf),
            cdf,
            object_base,
            total_power: total * std::f32::consts::PI,
            triangle_sampling: TriangleSampling::default(),
            emitters,
        }
    }

    fn default_for(object_count: usize) -> Self {
        Self { object_base: vec![NONE; object_count], triangle_table: triangle_table(&[], &[]), ..Self::default() }
    }

    /// Total emitted flux (mean over RGB), for choosing between area and other lights.
    pub fn total_power(&self) -> f32 {
        self.total_power
    }

    /// A particle leaving some emitter: the emitter chosen by power, a point uniform on its
    /// area, a direction cosine-weighted about the normal (on a side chosen at random if it
    /// emits from both), so the particle's weight L_e·cos / (pdf_area · pdf_direction) is the
    /// same for every particle of an emitter.
    pub fn sample_emission(&self, u_select: f32, u_point: Vec2, u_direction: Vec2) -> Option<AreaEmission> {
        let (i, emitter) = self.choose(u_select)?;
        let (point, normal, area, error) = self.point_on(emitter, u_point);
        if area <= 0.0 || emitter.radiance == Rgb::ZERO {
            return None;
        }
        let mut u = u_direction;
        let mut normal = normal;
        let mut side_probability = 1.0;
        if emitter.two_sided {
            side_probability = 0.5;
            if u.x < 0.5 {
                u.x *= 2.0;
            } else {
                u.x = 2.0 * u.x - 1.0;
                normal = -normal;
            }
        }
        let local = square_to_cosine_hemisphere(u);
        let (tangent, bitangent) = orthonormal_basis(normal);
        let direction = local.x * tangent + local.y * bitangent + local.z * normal;
        let pdf_direction = side_probability * cosine_hemisphere_pdf(local);
        if pdf_direction <= 0.0 {
            return None;
        }
        Some(AreaEmission {
            point,
            normal,
            error,
            direction,
            radiance: emitter.radiance,
            two_sided: emitter.two_sided,
            pdf_area: self.selection_probability(i) / area,
            pdf_direction,
        })
    }

    /// A point uniform on an emitter: (point, normal, area, error bound).
    #[inline]
    fn point_on(&self, emitter: &Emitter, u: Vec2) -> (Vec3, Vec3, f32, Vec3) {
        match emitter.shape {
            EmitterShape::Triangle { a, b, c, normal, area } => {
                let bary = square_to_triangle(u);
                let (point, error) = barycentric_point([a, b, c], bary.x, bary.y);
                (point, normal, area, error)
            }
            EmitterShape::Sphere { center, radius } => {
                let n = square_to_uniform_sphere(u);
                let (point, error) = sphere_point(center, radius, n);
                (point, n, emitter.shape.area(), error)
            }
        }
    }

    /// The number of emitters (each triangle of an emissive mesh is one).
    pub fn len(&self) -> usize {
        self.emitters.len()
    }

    pub fn is_empty(&self) -> bool {
        self.emitters.is_empty()
    }

    /// The emitter `u_select` picks, in proportion to power, and its index.
    fn choose(&self, u_select: f32) -> Option<(usize, &Emitter)> {
        if self.emitters.is_empty() {
            return None;
        }
        let i = self.cdf.partition_point(|&c| c <= u_select).min(self.emitters.len() - 1);
        Some((i, &self.emitters[i]))
    }

    fn selection_probability(&self, i: usize) -> f32 {
        probability_of(&self.cdf, i)
    }

    /// Every emitter as a triangle, then a black one that is never chosen (its index is the
    /// number of emitters); `None` if some emitter is a sphere.
    pub(crate) fn triangle_table(&self) -> Option<&[TriangleEmitter]> {
        self.triangle_table.as_deref()
    }

    /// The index of the emitter `u_select` picks (by power), as `sample` picks it.
    #[inline]
    pub(crate) fn choose_index(&self, u_select: f32) -> Option<usize> {
        self.choose(u_select).map(|(i, _)| i)
    }

    /// The cumulative probabilities by which `choose_index` picks an emitter.
    pub(crate) fn selection_cdf(&self) -> &[f32] {
        &self.cdf
    }

    /// The emitter that primitive `prim` of `object` is, if it is one (as `pdf` finds it).
    #[inline]
    pub(crate) fn emitter_index(&self, object: u32, prim: u32) -> Option<usize> {
        let base = self.object_base.get(object as usize).copied().unwrap_or(NONE);
        (base != NONE).then_some((base + prim) as usize)
    }

    /// A point on some light for the shading point `from`: spheres sampled by the solid angle
    /// they subtend, triangles by area or, with `TriangleSampling::SolidAngle`, by solid angle
    /// where that is accurate, then also following the receiver's |cos θ| when its normal is
    /// given (`SphericalTriangle::sample_toward`).
    pub fn sample(&self, from: Vec3, receiver_normal: Option<Vec3>, u_select: f32, u: Vec2) -> Option<LightSample> {
        let (i, emitter) = self.choose(u_select)?;
        if let EmitterShape::Triangle { a, b, c, normal, .. } = emitter.shape {
            // A one-sided triangle sends nothing to a point behind its plane (the ceiling above
            // the Cornell box's lamp): no point to sample. Every corner is asked, so only a
            // point within rounding of the plane, whose light would arrive edge on, can be
            // dropped that the sample below would have kept.
            let behind = |corner: Vec3| normal.dot(corner - from) > 0.0;
            if !emitter.two_sided && behind(a) && behind(b) && behind(c) {
                return None;
            }
        }
        let selection = self.selection_probability(i);
        let PointSample { point, normal, error, pdf } = match emitter.shape {
            EmitterShape::Triangle { a, b, c, normal, .. } => match self.spherical_triangle(from, [a, b, c]) {
                Some(spherical) => {
                    let (direction, pdf) = spherical.sample_toward(u, receiver_normal);
                    let (point, error) = point_along(from, direction, [a, b, c])?;
                    PointSample { point, normal, error, pdf: selection * pdf }
                }
                None => self.sample_by_area(emitter, selection, from, u)?,
            },
            EmitterShape::Sphere { center, radius } => match SphericalCap::new(from, center, radius) {
                Some(cap) => {
                    let normal = cap.sample_normal(u);
                    let (point, error) = sphere_point(center, radius, normal);
                    PointSample { point, normal, error, pdf: selection / cap.solid_angle() }
                }
                None => self.sample_by_area(emitter, selection, from, u)?,
            },
        };
        let cos_light = -normal.dot(point - from);
        if !(pdf > 0.0 && pdf.is_finite()) || cos_light == 0.0 {
            return None;
        }
        let radiance = if emitter.two_sided || cos_light > 0.0 { emitter.radiance } else { Rgb::ZERO };
        Some(LightSample { point, normal, error, radiance, pdf })
    }

    /// The triangle as seen from `from`, when it is sampled by solid angle and that is
    /// accurate (pbrt-v4's bounds): below 3·10⁻⁴ sr the corners' directions nearly coincide
    /// and the construction loses precision, while the area density hardly varies across so
    /// small a triangle anyway; above 6.22 sr `from` nearly lies in its plane.
    fn spherical_triangle(&self, from: Vec3, corners: [Vec3; 3]) -> Option<SphericalTriangle> {
        if self.triangle_sampling == TriangleSampling::Area {
            return None;
        }
        SphericalTriangle::new(from, corners).filter(|t| (3e-4..=6.22).contains(&t.solid_angle()))
    }

    /// A point uniform on the emitter's area, with its density converted to solid angle
    /// (pdf_ω = pdf_A · d² / |cos θ_light|).
    fn sample_by_area(&self, emitter: &Emitter, selection: f32, from: Vec3, u: Vec2) -> Option<PointSample> {
        let (point, normal, area, error) = self.point_on(emitter, u);
        if area <= 0.0 {
            return None;
        }
        let pdf = area_to_solid_angle(selection, area, from, point, normal)?;
        Some(PointSample { point, normal, error, pdf })
    }

    /// The solid-angle density with which `sample` from `from` would have produced the point
    /// `point` (with geometric normal `normal`) on primitive `prim` of object `object`; 0 if that
    /// primitive is not a sampled light. For multiple importance sampling of BSDF-sampled hits.
    /// `receiver_normal` as given to `sample`.
    pub fn pdf(
        &self,
        from: Vec3,
        receiver_normal: Option<Vec3>,
        object: u32,
        prim: u32,
        point: Vec3,
        normal: Vec3,
    ) -> f32 {
        let Some(i) = self.emitter_index(object, prim) else { return 0.0 };
        let selection = self.selection_probability(i);
        let shape = &self.emitters[i].shape;
        match *shape {
            EmitterShape::Triangle { a, b, c, .. } => {
                if let Some(spherical) = self.spherical_triangle(from, [a, b, c]) {
                    return selection * spherical.pdf((point - from).normalize(), receiver_normal);
                }
            }
            EmitterShape::Sphere { center, radius } => {
                if let Some(cap) = SphericalCap::new(from, center, radius) {
                    return selection / cap.solid_angle();
                }
            }
        }
        area_to_solid_angle(selection, shape.area(), from, point, normal).unwrap_or(0.0)
    }
}

/// The probability of entry `i` of a discrete distribution from its cumulative `cdf`.
fn probability_of(cdf: &[f32], i: usize) -> f32 {
    cdf[i] - if i == 0 { 0.0 } else { cdf[i - 1] }
}

/// `AreaLights::triangle_table` of `emitters` with cumulative selection probabilities `cdf`.
fn triangle_table(emitters: &[Emitter], cdf: &[f32]) -> Option<Vec<TriangleEmitter>> {
    let mut table: Vec<TriangleEmitter> = emitters
        .iter()
        .enumerate()
        .map(|(i, e)| match e.shape {
            EmitterShape::Triangle { a, b, c, normal, area } => Some(TriangleEmitter {
                corners: [a, b, c],
                normal,
                area,
                radiance: e.radiance,
                two_sided: e.two_sided,
                selection: probability_of(cdf, i),
            }),
            EmitterShape::Sphere { .. } => None,
        })
        .collect::<Option<_>>()?;
    let none = TriangleEmitter {
        corners: [Vec3::ZERO; 3],
        normal: Vec3::Z,
        area: 1.0,
        radiance: Rgb::ZERO,
        two_sided: false,
        selection: 0.0,
    };
    table.push(none);
    Some(table)
}

/// The density `selection / area` of a point uniform on an emitter's area, at `point` (normal
/// `normal`), as a solid-angle density seen from `from`: pdf_ω = pdf_A · d² / |cos θ_light|;
/// `None` when the light is seen edge on.
pub(crate) fn area_to_solid_angle(selection: f32, area: f32, from: Vec3, point: Vec3, normal: Vec3) -> Option<f32> {
    let to_light = point - from;
    let distance_squared = to_light.length_squared();
    // d² / |cos θ| = d³ / |n · (point − from)|: one division on the path, not two.
    let projected = normal.dot(to_light).abs();
    (projected > 0.0).then(|| selection * distance_squared * distance_squared.sqrt() / (projected * area))
}

/// Where the ray from `from` along `w` meets the triangle `[a, b, c]`, as barycentric
/// interpolation of the corners (so it lies on the triangle), with its error bound.
fn point_along(from: Vec3, w: Vec3, [a, b, c]: [Vec3; 3]) -> Option<(Vec3, Vec3)> {
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
    use crate::materials::Phong;
    use crate::sampling::chi2::chi2_test_with_resolution;
    use crate::shapes::test_util::ray_meets_triangle;
    use crate::shapes::{Sphere, Triangle};

    /// A triangle and a sphere that emit, seen from a point outside both.
    fn lights() -> (AreaLights, [Vec3; 3], (Vec3, f32)) {
        let tri = [Vec3::new(1.0, -0.5, 2.0), Vec3::new(2.0, 0.5, 2.5), Vec3::new(0.5, 1.0, 1.5)];
        let sphere = (Vec3::new(-1.5, 0.3, 1.0), 0.6);
        let emitting =
            |e: f32| Material::Phong(Phong { emission: Rgb::splat(e), two_sided_emission: true, ..Phong::default() });
        let objects = vec![
            Object {
                name: "t".into(),
                shape: Shape::Triangle(Triangle::new(tri[0], tri[1], tri[2])),
                transform: None,
                material: 0,
            },
            Object {
                name: "s".into(),
                shape: Shape::Sphere(Sphere::new(sphere.0, sphere.1)),
                transform: None,
                material: 1,
            },
        ];
        (AreaLights::new(&objects, &[emitting(3.0), emitting(1.0)]), tri, sphere)
    }

    /// The triangle's light sampling from a point in front of it, as directions, against the
    /// solid-angle pdf (chi-square): by area, by solid angle, and by solid angle warped by the
    /// cosine at a receiver whose normal the triangle's corners face at very different angles.
    #[test]
    fn triangle_sampling_matches_its_pdf() {
        let (mut lights, tri, _) = lights();
        let from = Vec3::new(0.64, 0.43, 2.84); // one unit in front of the triangle's centroid
        let p_triangle = lights.selection_probability(0) as f64;
        let tilted = Vec3::new(1.0, 0.2, 0.1).normalize();
        for (strategy, receiver) in [
            (TriangleSampling::Area, None),
            (TriangleSampling::SolidAngle, None),
            (TriangleSampling::SolidAngle, Some(tilted)),
        ] {
            lights.triangle_sampling = strategy;
            // u_select = 0 always picks the triangle: its pdf is the full pdf over p_triangle.
            let sample = |u: Vec2| lights.sample(from, receiver, 0.0, u).map(|s| (s.point - from).normalize());
            let pdf = |w: Vec3| match ray_meets_triangle(from, w, tri) {
                Some(p) => {
                    let n = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize();
                    lights.pdf(from, receiver, 0, 0, p, n) as f64 / p_triangle
                }
                None => 0.0,
            };
            let r = chi2_test_with_resolution(sample, pdf, 500_000, 21, 41, 5, 64);
            assert!(r.p_value > 0.01, "{strategy:?}, {receiver:?}: p = {}", r.p_value);
        }
    }

    /// A one-sided triangle light is not sampled from behind its plane, whatever the strategy,
    /// while a two-sided one is; from in front both give a point with radiance.
    #[test]
    fn one_sided_triangles_are_not_sampled_from_behind() {
        let tri = [Vec3::ZERO, Vec3::X, Vec3::Y]; // normal +z
        for two_sided in [false, true] {
            let material =
                Material::Phong(Phong { emission: Rgb::ONE, two_sided_emission: two_sided, ..Phong::default() });
            let object = Object {
                name: "t".into(),
                shape: Shape::Triangle(Triangle::new(tri[0], tri[1], tri[2])),
                transform: None,
                material: 0,
            };
            let mut lights = AreaLights::new(&[object], &[material]);
            for strategy in TriangleSampling::ALL {
                lights.triangle_sampling = strategy;
                let u = Vec2::new(0.3, 0.6);
                let front = lights.sample(Vec3::new(0.2, 0.2, 1.0), None, 0.5, u).unwrap();
                assert!(front.radiance == Rgb::ONE && front.pdf > 0.0, "{strategy:?}");
                let back = lights.sample(Vec3::new(0.2, 0.2, -1.0), None, 0.5, u);
                match two_sided {
                    false => assert_eq!(back, None, "{strategy:?}"),
                    true => assert!(back.is_some_and(|s| s.radiance == Rgb::ONE), "{strategy:?}"),
                }
            }
        }
    }

    /// Solid-angle sampling finds the point where the sampled direction meets the triangle
    /// (not a clamped stand-in), with the density 1 / Ω, Ω from Girard's theorem in f64.
    #[test]
    fn solid_angle_sampling_puts_points_on_the_triangle() {
        let (mut lights, tri, _) = lights();
        lights.triangle_sampling = TriangleSampling::SolidAngle;
        let from = Vec3::new(1.1, 0.35, 2.05);
        let spherical = SphericalTriangle::new(from, tri).unwrap();
        let omega = crate::sampling::spherical::girard_solid_angle(from, tri);
        let p_triangle = lights.selection_probability(0) as f64;
        for i in 0..100 {
            let u = Vec2::new((i % 10) as f32 / 10.0 + 0.05, (i / 10) as f32 / 10.0 + 0.05);
            let s = lights.sample(from, None, 0.0, u).unwrap();
            let w = spherical.sample(u);
            assert!((s.point - from).normalize().dot(w) > 1.0 - 1e-6, "{} is not along {w}", s.point);
            assert!((s.pdf as f64 / p_triangle * omega - 1.0).abs() < 1e-4);
        }
    }

    /// The point of the cosine warp: irradiance at a wall point just below and beside a large
    /// triangle light, E = ∫ L cos θ dω, estimated as L cos θ / pdf. Uniform in solid angle the
    /// estimate varies with cos θ across the triangle (0.05 to 0.7 here); warped by the
    /// receiver's cosine it is nearly constant: 13× lower variance, the same mean.
    #[test]
    fn the_cosine_warp_lowers_the_variance_of_irradiance_from_a_close_light() {
        let corners = [Vec3::new(0.0, 1.0, -0.5), Vec3::new(1.0, 1.0, 0.5), Vec3::new(1.0, 1.0, -0.5)];
        let light = Object {
            name: "light".into(),
            shape: Shape::Triangle(Triangle::new(corners[0], corners[1], corners[2])),
            transform: None,
            material: 0,
        };
        let emitting = Material::Phong(Phong { emission: Rgb::ONE, two_sided_emission: true, ..Phong::default() });
        let mut lights = AreaLights::new(&[light], &[emitting]);
        lights.triangle_sampling = TriangleSampling::SolidAngle;
        let (p, n) = (Vec3::new(-0.05, 0.9, 0.0), Vec3::X);
        let estimate = |receiver: Option<Vec3>| {
            let mut rng = crate::sampling::Rng::new(1, 1);
            let k = 100_000;
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for _ in 0..k {
                let s = lights.sample(p, receiver, 0.0, Vec2::new(rng.next_f32(), rng.next_f32())).unwrap();
                let x = (n.dot((s.point - p).normalize()).max(0.0) / s.pdf) as f64;
                sum += x;
                sum2 += x * x;
            }
            let mean = sum / k as f64;
            (mean, sum2 / k as f64 - mean * mean, ((sum2 / k as f64 - mean * mean) / k as f64).sqrt())
        };
        let (plain, warped) = (estimate(None), estimate(Some(n)));
        assert!((plain.0 - warped.0).abs() < 4.0 * (plain.2 + warped.2), "{plain:?} vs {warped:?}");
        assert!(warped.1 * 5.0 < plain.1, "variance {} warped against {} plain", warped.1, plain.1);
    }

    /// The sphere is sampled by the cone it subtends: a chi-square test of the directions
    /// against the pdf of the point they reach first; and the emitters are chosen by power.
    #[test]
    fn sphere_sampling_matches_its_pdf_and_emitters_are_chosen_by_power() {
        let (lights, _, (centre, radius)) = lights();
        let from = Vec3::new(0.64, 0.43, 2.84);
        let p_sphere = 1.0 - lights.selection_probability(0) as f64;
        let first_hit = |w: Vec3| {
            let oc = from - centre;
            let (b, c) = (oc.dot(w), oc.length_squared() - radius * radius);
            let disc = b * b - c;
            let t = -b - disc.max(0.0).sqrt();
            (disc >= 0.0 && t > 0.0).then(|| from + t * w)
        };
        // u_select near 1 always picks the sphere.
        let sample = |u: Vec2| lights.sample(from, None, 0.9999, u).map(|s| (s.point - from).normalize());
        let pdf = |w: Vec3| match first_hit(w) {
            Some(p) => lights.pdf(from, None, 1, 0, p, (p - centre) / radius) as f64 / p_sphere,
            None => 0.0,
        };
        let r = chi2_test_with_resolution(sample, pdf, 500_000, 21, 41, 5, 64);
        assert!(r.p_value > 0.01, "p = {}", r.p_value);

        let mut rng = crate::sampling::Rng::for_sample(1, 2, 3);
        let n = 100_000;
        let spheres = (0..n)
            .filter(|_| {
                let s = lights.sample(from, None, rng.next_f32(), Vec2::new(rng.next_f32(), rng.next_f32())).unwrap();
                (s.point - centre).length() < radius * 1.001
            })
            .count() as f64;
        // The sphere chosen with its power share (binomial, 4σ).
        let sigma = (n as f64 * p_sphere * (1.0 - p_sphere)).sqrt();
        assert!((spheres - n as f64 * p_sphere).abs() < 4.0 * sigma, "{spheres} of {n} vs p = {p_sphere}");
    }
}
