//! Area lights: every primitive whose material emits (`emission` on a material, Mitsuba's
//! `area`). From a shading point, a point on one is sampled for next-event estimation:
//!
//! * spheres by the cone of directions they subtend (uniform in solid angle; by area from
//!   inside), under any similarity transform; under another affine transform (an ellipsoid)
//!   by area;
//! * triangles uniformly on their area by default, the density converted to solid angle
//!   (pdf_ω = pdf_A · d² / |cos θ_light|), or, with `TriangleSampling::SolidAngle`, uniformly
//!   in the spherical triangle they subtend (Arvo 1995), warped by the receiver's cos θ when
//!   its normal is given (pbrt-v4's bilinear approximation: 13× lower variance of the
//!   irradiance from one large, close triangle in a test below). Solid-angle sampling has less
//!   noise next to a light but costs more: on the Cornell box it lowered the error by 2 % at
//!   equal samples and took 10–24 % longer (docs/performance.md), so area is the default.
//!
//! * polygons and boxes uniformly on their area, as one light each: the polygon cut into
//!   triangles on its plane (`Polygon::triangles`), the box into its twelve
//!   (`AaBox::triangles`), a triangle chosen by its share of the area (`TriangleSurface`).
//!
//! A radiance given as a texture is read at the sampled point's texture coordinates, which
//! the emitting object's own shape gives (`Object::texture_query_at`), so light samples,
//! particles and paths that hit the surface see the same radiance. Points are still sampled by
//! area (as Mitsuba samples a textured area emitter), not by the texture's brightness.
//!
//! Sampled: triangles (triangle shapes, mesh triangles, quads, the triangles of an instanced
//! mesh; any transform, taken in world space), spheres, polygons and boxes. The geometry of
//! each sampling routine lives in its shape's file. Other emissive shapes (planes,
//! self-intersecting polygons) still emit: a path finds them by BSDF sampling, whose
//! multiple-importance weight is then 1 since their light pdf is 0, so the estimate stays
//! unbiased, only noisier.

use std::sync::Arc;

use glam::{Vec2, Vec3};

use super::{Asked, LightEnd, LightSample};
use crate::accel::Object;
use crate::geometry::{orthonormal_basis, Transform};
use crate::lanes::{LaneVec3, Lanes};
use crate::materials::Material;
use crate::sampling::spherical::SphericalTriangle;
use crate::sampling::warp::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};
use crate::shapes::{
    barycentrics, sample_sphere, sample_sphere_seen_from, sample_triangle, sphere_solid_angle_from,
    triangle_point_along, Ellipsoid, PrimHit, Shape, TriangleSurface,
};
use crate::textures::Texture;
use crate::Named;
use crate::Rgb;

/// The surface of an area light, in world space.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum EmitterShape {
    Triangle {
        a: Vec3,
        b: Vec3,
        c: Vec3,
        normal: Vec3,
        area: f32,
    },
    Sphere {
        center: Vec3,
        radius: f32,
    },
    /// A sphere under a transform that is not a similarity (boxed: its transform is three
    /// times a triangle's size, and a mesh light is a vector of lights).
    Ellipsoid(Box<Ellipsoid>),
    /// A polygon's or a box's triangles, sampled together by area.
    Surface(Box<TriangleSurface>),
}

impl EmitterShape {
    fn area(&self) -> f32 {
        match self {
            EmitterShape::Triangle { area, .. } => *area,
            EmitterShape::Sphere { radius, .. } => 4.0 * std::f32::consts::PI * radius * radius,
            EmitterShape::Ellipsoid(e) => e.area,
            EmitterShape::Surface(s) => s.area(),
        }
    }

    /// A point by area: (point, normal, error bound, area density).
    #[inline]
    fn sample_area(&self, u: Vec2) -> (Vec3, Vec3, Vec3, f32) {
        match self {
            EmitterShape::Triangle { a, b, c, normal, area } => {
                let (point, error) = sample_triangle([*a, *b, *c], u);
                (point, *normal, error, 1.0 / area)
            }
            EmitterShape::Sphere { center, radius } => {
                let (point, normal, error) = sample_sphere(*center, *radius, u);
                (point, normal, error, 1.0 / self.area())
            }
            EmitterShape::Ellipsoid(e) => e.sample(u),
            EmitterShape::Surface(s) => {
                let (point, normal, error) = s.sample(u);
                (point, normal, error, 1.0 / s.area())
            }
        }
    }
}

/// One emitting primitive.
#[derive(Clone, Debug, PartialEq)]
pub struct AreaLight {
    pub(crate) shape: EmitterShape,
    /// L_e; where `texture` is given, its mean (what the light's power reads).
    pub radiance: Rgb,
    pub two_sided: bool,
    /// A radiance that varies over the surface (boxed: few lights have one, and a light stays
    /// about a triangle's size).
    pub(crate) texture: Option<Box<TexturedPrimitive>>,
}

/// A textured emitter's primitive: the texture is read at a sampled point's texture
/// coordinates, which the object's own shape gives (`Object::texture_query_at`), so a point a
/// light sample lands on and a ray that hits it see the same radiance.
#[derive(Clone, Debug)]
pub(crate) struct TexturedPrimitive {
    pub emitter: Arc<TexturedEmitter>,
    pub prim: u32,
}

/// The object of a textured emitter and its radiance, shared by its primitives' lights.
#[derive(Debug)]
pub(crate) struct TexturedEmitter {
    pub object: Object,
    pub radiance: Texture,
}

impl PartialEq for TexturedPrimitive {
    /// The same primitive of the same emitter.
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.emitter, &other.emitter) && self.prim == other.prim
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

/// How a triangle light is sampled from a shading point.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TriangleSampling {
    /// A point uniform on its area.
    #[default]
    Area,
    /// A direction in its solid angle (where that is accurate, else by area): uniform, or,
    /// given the receiver's normal, warped toward its cos θ.
    SolidAngle,
}

impl Named for TriangleSampling {
    const ALL: &'static [Self] = &[TriangleSampling::Area, TriangleSampling::SolidAngle];

    fn name(self) -> &'static str {
        match self {
            TriangleSampling::Area => "area",
            TriangleSampling::SolidAngle => "solid-angle",
        }
    }
}

/// A triangle emitter as the path tracer's SIMD lanes read it (`Lights::triangle_table`).
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

impl TriangleEmitter {
    /// What lanes without a light read: black, never chosen.
    pub const NONE: Self = Self {
        corners: [Vec3::ZERO; 3],
        normal: Vec3::Z,
        area: 1.0,
        radiance: Rgb::ZERO,
        two_sided: false,
        selection: 0.0,
    };
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

/// The area lights of `objects`: each object whose material emits, as its primitives' lights
/// in order, with the object's index. Shapes without a sampling routine are left out (found by
/// BSDF sampling only).
pub(crate) fn area_lights(objects: &[Object], materials: &[Material]) -> Vec<(usize, Vec<AreaLight>)> {
    let mut found = Vec::new();
    for (o, object) in objects.iter().enumerate() {
        let Some(material) = materials.get(object.material as usize) else { continue };
        let (radiance, two_sided) = material.emission();
        if radiance == Rgb::ZERO {
            continue;
        }
        let textured = material
            .emission_texture()
            .map(|texture| Arc::new(TexturedEmitter { object: object.clone(), radiance: texture.clone() }));
        let texture =
            |prim: u32| textured.as_ref().map(|emitter| Box::new(TexturedPrimitive { emitter: emitter.clone(), prim }));
        let light = |shape: EmitterShape| AreaLight { shape, radiance, two_sided, texture: texture(0) };
        let triangles: Vec<[Vec3; 3]> = match &object.shape {
            Shape::Mesh(mesh) => (0..mesh.triangle_count()).map(|i| mesh.triangle_vertices(i)).collect(),
            Shape::Triangle(t) => vec![t.vertices],
            Shape::Sphere(s) => {
                let shape = match &object.transform {
                    None => EmitterShape::Sphere { center: s.center, radius: s.radius },
                    Some(t) => match similarity_scale(t) {
                        Some(scale) => EmitterShape::Sphere { center: t.point(s.center), radius: s.radius * scale },
                        None => EmitterShape::Ellipsoid(Box::new(Ellipsoid::new(s.center, s.radius, *t))),
                    },
                };
                found.push((o, vec![light(shape)]));
                continue;
            }
            Shape::Polygon(p) => {
                // A self-intersecting polygon has no triangles: found by BSDF sampling only.
                let Some(triangles) = p.triangles() else { continue };
                let normals = vec![p.normal(); triangles.len()];
                if let Some(shape) = surface(triangles, normals, object.transform.as_ref()) {
                    found.push((o, vec![light(shape)]));
                }
                continue;
            }
            // Every primitive of the instanced geometry, in its order (a hit's inner
            // primitive is its light's index within the instance), if all are triangles.
            Shape::Instance(i) => {
                let count = i.geometry.primitive_count() as u32;
                match (0..count).map(|p| i.geometry.triangle_corners(0, p)).collect::<Option<Vec<_>>>() {
                    Some(triangles) => triangles,
                    None => continue,
                }
            }
            Shape::AaBox(b) => {
                let triangles = b.triangles().to_vec();
                let normals = triangles.iter().map(|[a, b, c]| (*b - *a).cross(*c - *a).normalize()).collect();
                if let Some(shape) = surface(triangles, normals, object.transform.as_ref()) {
                    found.push((o, vec![light(shape)]));
                }
                continue;
            }
            _ => continue,
        };
        let lights = triangles
            .into_iter()
            .enumerate()
            .map(|(prim, [a, b, c])| {
                let (a, b, c) = match &object.transform {
                    Some(t) => (t.point(a), t.point(b), t.point(c)),
                    None => (a, b, c),
                };
                let cross = (b - a).cross(c - a);
                let area = 0.5 * cross.length();
                AreaLight {
                    shape: EmitterShape::Triangle { a, b, c, normal: cross.normalize_or(Vec3::Z), area },
                    radiance: if area > 0.0 { radiance } else { Rgb::ZERO },
                    two_sided,
                    texture: texture(prim as u32),
                }
            })
            .collect();
        found.push((o, lights));
    }
    found
}

/// Object-space triangles with their normals as a surface emitter in world space: corners
/// mapped as points, normals as normals (as a hit's geometric normal is, so the emitting side
/// agrees with what a path that hits the surface sees).
fn surface(triangles: Vec<[Vec3; 3]>, normals: Vec<Vec3>, transform: Option<&Transform>) -> Option<EmitterShape> {
    let (triangles, normals) = match transform {
        None => (triangles, normals),
        Some(t) => (
            triangles.into_iter().map(|corners| corners.map(|p| t.point(p))).collect(),
            normals.into_iter().map(|n| t.normal(n)).collect(),
        ),
    };
    TriangleSurface::new(triangles, normals).map(|s| EmitterShape::Surface(Box::new(s)))
}

/// The scale s of a transform whose linear part is s times a rotation (or reflection), to
/// within 10⁻⁵: a sphere stays a sphere under it.
fn similarity_scale(t: &Transform) -> Option<f32> {
    let m = glam::Mat3::from_mat4(t.to_world);
    let gram = m.transpose() * m;
    let s2 = gram.x_axis.x;
    let expected = glam::Mat3::from_diagonal(Vec3::splat(s2));
    let close = (0..3).all(|i| (gram.col(i) - expected.col(i)).abs().max_element() <= 1e-5 * s2);
    (s2 > 0.0 && close).then(|| s2.sqrt())
}

impl AreaLight {
    /// L_e at `point`, a point on the light.
    #[inline]
    fn radiance_at(&self, point: Vec3) -> Rgb {
        let Some(textured) = &self.texture else { return self.radiance };
        let barycentrics = match self.shape {
            EmitterShape::Triangle { a, b, c, .. } => barycentrics(point, [a, b, c]),
            _ => Vec2::ZERO,
        };
        let hit = PrimHit { t: 0.0, u: barycentrics.x, v: barycentrics.y, inner: 0 };
        let emitter = &textured.emitter;
        match emitter.object.texture_query_at(textured.prim, point, &hit) {
            Some(query) => emitter.radiance.evaluate(&query),
            None => self.radiance,
        }
    }

    /// L·A·sides: the emitter's power over π (mean over RGB).
    pub(super) fn power_over_pi(&self) -> f32 {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        self.radiance.dot(Rgb::splat(1.0 / 3.0)) * self.shape.area() * sides
    }

    /// A point on the light for the shading point `from`: spheres sampled by the solid angle
    /// they subtend, triangles by area or, with `TriangleSampling::SolidAngle`, by solid angle
    /// where that is accurate, then also following the receiver's |cos θ| when its normal is
    /// given (`SphericalTriangle::sample_toward`).
    pub(super) fn sample_li(&self, from: Vec3, receiver: Option<Vec3>, u: Vec2, asked: Asked) -> Option<LightSample> {
        let selection = asked.selection;
        if let EmitterShape::Triangle { a, b, c, normal, .. } = self.shape {
            // A one-sided triangle sends nothing to a point behind its plane (the ceiling above
            // the Cornell box's lamp): no point to sample. Every corner is asked, so only a
            // point within rounding of the plane, whose light would arrive edge on, can be
            // dropped that the sample below would have kept.
            let behind = |corner: Vec3| normal.dot(corner - from) > 0.0;
            if !self.two_sided && behind(a) && behind(b) && behind(c) {
                return None;
            }
        }
        let PointSample { point, normal, error, pdf } = match self.shape {
            EmitterShape::Triangle { a, b, c, normal, .. } => {
                match spherical_triangle(asked.triangle_sampling, from, [a, b, c]) {
                    Some(spherical) => {
                        let (direction, pdf) = spherical.sample_toward(u, receiver);
                        let (point, error) = triangle_point_along(from, direction, [a, b, c])?;
                        PointSample { point, normal, error, pdf: selection * pdf }
                    }
                    None => self.sample_by_area(selection, from, u)?,
                }
            }
            EmitterShape::Sphere { center, radius } => match sample_sphere_seen_from(center, radius, from, u) {
                Some((point, normal, error, solid_angle)) => {
                    PointSample { point, normal, error, pdf: selection / solid_angle }
                }
                None => self.sample_by_area(selection, from, u)?,
            },
            EmitterShape::Ellipsoid(_) | EmitterShape::Surface(_) => self.sample_by_area(selection, from, u)?,
        };
        let cos_light = -normal.dot(point - from);
        if !(pdf > 0.0 && pdf.is_finite()) || cos_light == 0.0 {
            return None;
        }
        let radiance = if self.two_sided || cos_light > 0.0 { self.radiance_at(point) } else { Rgb::ZERO };
        Some(LightSample {
            direction: (point - from).normalize(),
            end: LightEnd::Surface { point, normal, error },
            radiance,
            pdf,
            delta: false,
        })
    }

    /// A point by area, with its density converted to solid angle (pdf_ω = pdf_A · d² /
    /// |cos θ_light|).
    fn sample_by_area(&self, selection: f32, from: Vec3, u: Vec2) -> Option<PointSample> {
        let (point, normal, error, pdf_area) = self.shape.sample_area(u);
        if !(pdf_area > 0.0 && pdf_area.is_finite()) {
            return None;
        }
        let pdf = match self.shape {
            // The triangle's and sphere's density as it always was: selection / area.
            EmitterShape::Ellipsoid(_) => area_to_solid_angle(selection * pdf_area, 1.0, from, point, normal)?,
            _ => area_to_solid_angle(selection, self.shape.area(), from, point, normal)?,
        };
        Some(PointSample { point, normal, error, pdf })
    }

    /// The solid-angle density with which `sample_li` from `from` (chosen with probability
    /// `selection`) would have produced `point` (geometric normal `normal`) on this light.
    pub(super) fn pdf_li(&self, from: Vec3, receiver: Option<Vec3>, point: Vec3, normal: Vec3, asked: Asked) -> f32 {
        let selection = asked.selection;
        match self.shape {
            EmitterShape::Triangle { a, b, c, .. } => {
                if let Some(spherical) = spherical_triangle(asked.triangle_sampling, from, [a, b, c]) {
                    return selection * spherical.pdf((point - from).normalize(), receiver);
                }
            }
            EmitterShape::Sphere { center, radius } => {
                if let Some(solid_angle) = sphere_solid_angle_from(center, radius, from) {
                    return selection / solid_angle;
                }
            }
            EmitterShape::Ellipsoid(ref e) => {
                return area_to_solid_angle(selection * e.pdf_area(point), 1.0, from, point, normal).unwrap_or(0.0);
            }
            EmitterShape::Surface(_) => {}
        }
        area_to_solid_angle(selection, self.shape.area(), from, point, normal).unwrap_or(0.0)
    }

    /// A particle leaving the light: a point by area, a direction cosine-weighted about the
    /// normal (on a side chosen at random if it emits from both), so the particle's weight
    /// L_e·cos / (pdf_area · pdf_direction) is the same for every particle of an emitter.
    pub(super) fn sample_le(&self, selection: f32, u_point: Vec2, u_direction: Vec2) -> Option<AreaEmission> {
        let (point, normal, error, pdf_area) = self.shape.sample_area(u_point);
        if !(pdf_area > 0.0 && pdf_area.is_finite()) || self.radiance == Rgb::ZERO {
            return None;
        }
        let mut u = u_direction;
        let mut normal = normal;
        let mut side_probability = 1.0;
        if self.two_sided {
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
        let pdf_area = match self.shape {
            EmitterShape::Ellipsoid(_) => selection * pdf_area,
            // As it always was: selection / area.
            _ => selection / self.shape.area(),
        };
        Some(AreaEmission {
            point,
            normal,
            error,
            direction,
            radiance: self.radiance_at(point),
            two_sided: self.two_sided,
            pdf_area,
            pdf_direction,
        })
    }

    /// The light as the lanes read a triangle, if it is one of constant radiance.
    pub(super) fn as_triangle(&self, selection: f32) -> Option<TriangleEmitter> {
        if self.texture.is_some() {
            return None;
        }
        match self.shape {
            EmitterShape::Triangle { a, b, c, normal, area } => Some(TriangleEmitter {
                corners: [a, b, c],
                normal,
                area,
                radiance: self.radiance,
                two_sided: self.two_sided,
                selection,
            }),
            _ => None,
        }
    }
}

/// The triangle as seen from `from`, when it is sampled by solid angle and that is accurate
/// (pbrt-v4's bounds): below 3·10⁻⁴ sr the corners' directions nearly coincide and the
/// construction loses precision, while the area density hardly varies across so small a
/// triangle anyway; above 6.22 sr `from` nearly lies in its plane.
fn spherical_triangle(strategy: TriangleSampling, from: Vec3, corners: [Vec3; 3]) -> Option<SphericalTriangle> {
    if strategy == TriangleSampling::Area {
        return None;
    }
    SphericalTriangle::new(from, corners).filter(|t| (3e-4..=6.22).contains(&t.solid_angle()))
}

/// The density `selection / area` of a point uniform on an emitter's area, at `point` (normal
/// `normal`), as a solid-angle density seen from `from`: pdf_ω = pdf_A · d² / |cos θ_light|;
/// `None` when the light is seen edge on.
pub(crate) fn area_to_solid_angle(selection: f32, area: f32, from: Vec3, point: Vec3, normal: Vec3) -> Option<f32> {
    let to_light = LaneVec3::<f32>::from(point - from);
    let (pdf, seen) = area_to_solid_angle_lanes(selection, area, to_light, normal.into());
    seen.then_some(pdf)
}

/// `area_to_solid_angle` in lanes: the density `selection / area` of a point on a light as a
/// density in solid angle, seen across `to_light` (the point minus the receiver), and the mask
/// of lanes where the light is not seen edge on.
#[inline(always)]
pub(crate) fn area_to_solid_angle_lanes<L: Lanes>(
    selection: L,
    area: L,
    to_light: LaneVec3<L>,
    normal: LaneVec3<L>,
) -> (L, L::Mask) {
    let distance_squared = to_light.dot(to_light);
    // d² / |cos θ| = d³ / |n · (point − from)|: one division on the path, not two.
    let projected = normal.dot(to_light).abs();
    (selection * distance_squared * distance_squared.sqrt() / (projected * area), projected.gt(L::ZERO))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Aabb;
    use crate::lanes::testing::random_vectors;
    use crate::lanes::{Vec3x8, LANES};
    use crate::lights::{Environment, Lights};
    use crate::materials::Phong;
    use crate::sampling::chi2::chi2_test_with_resolution;
    use crate::shapes::test_util::ray_meets_triangle;
    use crate::shapes::{Sphere, Triangle};
    use wide::f32x8;

    /// The area lights of `objects` alone.
    fn lights_of(objects: &[Object], materials: &[Material]) -> Lights {
        Lights::new(Vec::new(), &Environment::BLACK, objects, materials, Aabb::EMPTY)
    }

    /// The point a sample of an area light lies at.
    fn point(s: &LightSample) -> Vec3 {
        match s.end {
            LightEnd::Surface { point, .. } => point,
            _ => panic!("an area light's sample ends on its surface"),
        }
    }

    /// A triangle and a sphere that emit, seen from a point outside both.
    fn lights() -> (Lights, [Vec3; 3], (Vec3, f32)) {
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
        (lights_of(&objects, &[emitting(3.0), emitting(1.0)]), tri, sphere)
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
            lights.set_triangle_sampling(strategy);
            // u_select = 0 always picks the triangle: its pdf is the full pdf over p_triangle.
            let sample = |u: Vec2| lights.sample_li(from, receiver, 0.0, u).map(|s| (point(&s) - from).normalize());
            let pdf = |w: Vec3| match ray_meets_triangle(from, w, tri) {
                Some(p) => {
                    let n = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize();
                    lights.pdf_area(from, receiver, 0, 0, p, n) as f64 / p_triangle
                }
                None => 0.0,
            };
            let r = chi2_test_with_resolution(sample, pdf, 500_000, 21, 41, 5, 64);
            assert!(r.p_value > 0.01, "{strategy:?}, {receiver:?}: p = {}", r.p_value);
        }
    }

    /// A surface light under a rotation, a non-uniform scale and a shift, seen from outside it:
    /// sampled directions against the density of the points they reach (every crossing of the
    /// surface along a direction adds its pdf_A · d² / |cos θ|), by chi-square. An L-shaped
    /// polygon (six triangles of unequal area: the area shares), and a box (twelve triangles
    /// on six faces, a direction crossing two of them).
    #[test]
    fn polygon_and_box_lights_match_their_pdf_under_a_transform() {
        let transform = Transform::from_matrix(
            glam::Mat4::from_translation(Vec3::new(0.2, 0.1, -0.3))
                * glam::Mat4::from_rotation_y(0.5)
                * glam::Mat4::from_scale(Vec3::new(1.3, 0.8, 1.0)),
        )
        .unwrap();
        let l_shape = [(-0.5, -0.2), (0.3, -0.2), (0.3, 0.2), (0.0, 0.2), (0.0, 0.6), (-0.5, 0.6)]
            .map(|(x, z)| Vec3::new(x, 1.0, z))
            .to_vec();
        let polygon = crate::shapes::Polygon::new(l_shape).unwrap();
        let aabox = crate::shapes::AaBox::new(Vec3::new(-0.4, 0.9, -0.3), Vec3::new(0.3, 1.2, 0.4));
        let from = Vec3::new(0.1, -0.2, 0.05);
        // The object-space crossings (t along the world direction, local normal) of each shape.
        type Crossings = dyn Fn(&crate::geometry::Ray) -> Vec<(f32, Vec3)>;
        let polygon_crossings: Box<Crossings> = {
            let polygon = polygon.clone();
            Box::new(move |ray| {
                polygon
                    .intersect(ray, crate::shapes::PolygonTest::Crossing)
                    .map(|t| vec![(t, polygon.normal())])
                    .unwrap_or_default()
            })
        };
        let box_crossings: Box<Crossings> = Box::new(move |ray| {
            let (enter, exit) = aabox.bounds().slab_interval(ray.origin, ray.direction.recip());
            let at = |t: f32| (t, aabox.surface(ray.at(t)).geometric_normal);
            if enter <= exit && enter > 0.0 {
                vec![at(enter), at(exit)]
            } else {
                Vec::new()
            }
        });
        for (name, shape, crossings) in [
            ("polygon", Shape::Polygon(polygon.clone()), polygon_crossings),
            ("box", Shape::AaBox(aabox), box_crossings),
        ] {
            let emitting = Material::Phong(Phong { emission: Rgb::ONE, two_sided_emission: true, ..Phong::default() });
            let object = Object { name: name.into(), shape, transform: Some(transform), material: 0 };
            let lights = lights_of(&[object], &[emitting]);
            assert_eq!(lights.area_count(), 1, "{name} is one light");
            let sample = |u: Vec2| lights.sample_li(from, None, 0.5, u).map(|s| (point(&s) - from).normalize());
            let pdf = |w: Vec3| {
                let local = transform.ray_to_object(&crate::geometry::Ray::new(from, w));
                crossings(&local)
                    .into_iter()
                    .map(|(t, n)| lights.pdf_area(from, None, 0, 0, from + t * w, transform.normal(n)) as f64)
                    .sum()
            };
            let r = chi2_test_with_resolution(sample, pdf, 500_000, 21, 41, 5, 64);
            assert!(r.p_value > 0.01, "{name}: p = {}", r.p_value);
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
            let mut lights = lights_of(&[object], &[material]);
            for &strategy in TriangleSampling::ALL {
                lights.set_triangle_sampling(strategy);
                let u = Vec2::new(0.3, 0.6);
                let front = lights.sample_li(Vec3::new(0.2, 0.2, 1.0), None, 0.5, u).unwrap();
                assert!(front.radiance == Rgb::ONE && front.pdf > 0.0, "{strategy:?}");
                let back = lights.sample_li(Vec3::new(0.2, 0.2, -1.0), None, 0.5, u);
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
        lights.set_triangle_sampling(TriangleSampling::SolidAngle);
        let from = Vec3::new(1.1, 0.35, 2.05);
        let spherical = SphericalTriangle::new(from, tri).unwrap();
        let omega = crate::sampling::spherical::girard_solid_angle(from, tri);
        let p_triangle = lights.selection_probability(0) as f64;
        for i in 0..100 {
            let u = Vec2::new((i % 10) as f32 / 10.0 + 0.05, (i / 10) as f32 / 10.0 + 0.05);
            let s = lights.sample_li(from, None, 0.0, u).unwrap();
            let w = spherical.sample(u);
            assert!((point(&s) - from).normalize().dot(w) > 1.0 - 1e-6, "{} is not along {w}", point(&s));
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
        let mut lights = lights_of(&[light], &[emitting]);
        lights.set_triangle_sampling(TriangleSampling::SolidAngle);
        let (p, n) = (Vec3::new(-0.05, 0.9, 0.0), Vec3::X);
        let estimate = |receiver: Option<Vec3>| {
            let mut rng = crate::sampling::Rng::new(1, 1);
            let k = 100_000;
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for _ in 0..k {
                let s = lights.sample_li(p, receiver, 0.0, Vec2::new(rng.next_f32(), rng.next_f32())).unwrap();
                let x = (n.dot((point(&s) - p).normalize()).max(0.0) / s.pdf) as f64;
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
        let sample = |u: Vec2| lights.sample_li(from, None, 0.9999, u).map(|s| (point(&s) - from).normalize());
        let pdf = |w: Vec3| match first_hit(w) {
            Some(p) => lights.pdf_area(from, None, 1, 0, p, (p - centre) / radius) as f64 / p_sphere,
            None => 0.0,
        };
        let r = chi2_test_with_resolution(sample, pdf, 500_000, 21, 41, 5, 64);
        assert!(r.p_value > 0.01, "p = {}", r.p_value);

        let mut rng = crate::sampling::Rng::for_sample(1, 2, 3);
        let n = 100_000;
        let spheres = (0..n)
            .filter(|_| {
                let s =
                    lights.sample_li(from, None, rng.next_f32(), Vec2::new(rng.next_f32(), rng.next_f32())).unwrap();
                (point(&s) - centre).length() < radius * 1.001
            })
            .count() as f64;
        // The sphere chosen with its power share (binomial, 4σ).
        let sigma = (n as f64 * p_sphere * (1.0 - p_sphere)).sqrt();
        assert!((spheres - n as f64 * p_sphere).abs() < 4.0 * sigma, "{spheres} of {n} vs p = {p_sphere}");
    }

    /// Eight lanes compute one lane's bits and says "edge on" where it does.
    #[test]
    fn area_to_solid_angle_in_eight_lanes_equals_one_lane() {
        let mut rng = crate::sampling::Rng::new(3, 9);
        for _ in 0..500 {
            let from = random_vectors(&mut rng, 10.0);
            let point = random_vectors(&mut rng, 10.0);
            // Half the normals lie in the plane of the receiver's view: the light seen edge on.
            let normal: [Vec3; LANES] = std::array::from_fn(|k| match k % 2 {
                0 => (point[k] - from[k]).cross(Vec3::new(0.3, 1.0, -0.2)).normalize(),
                _ => Vec3::new(0.2, -1.0, 0.4).normalize(),
            });
            let (selection, area) = (rng.next_f32(), rng.next_f32() * 4.0);
            let to_light = Vec3x8::from_fn(|k| point[k] - from[k]);
            let (pdf, seen) = area_to_solid_angle_lanes(
                f32x8::splat(selection),
                f32x8::splat(area),
                to_light,
                Vec3x8::from_fn(|k| normal[k]),
            );
            let (pdf, seen) = (pdf.to_array(), seen.move_mask());
            for k in 0..LANES {
                let expected = area_to_solid_angle(selection, area, from[k], point[k], normal[k]);
                assert_eq!(seen & (1 << k) != 0, expected.is_some(), "seen, lane {k}");
                if let Some(expected) = expected {
                    assert_eq!(pdf[k].to_bits(), expected.to_bits(), "pdf, lane {k}");
                }
            }
        }
    }
}
