//! Area lights: every primitive whose material emits (`emission` on a material). They are
//! sampled for next-event estimation from a shading point: an emitter chosen in proportion to
//! its power, then a point uniformly on its area, the density converted to solid angle
//! (pdf_ω = pdf_A · d² / |cos θ_light|).
//!
//! Sampled: triangles (triangle shapes, mesh triangles, quads; any transform, taken in world
//! space) and spheres without a transform. Other emissive shapes still emit: a path finds them
//! by BSDF sampling, whose multiple-importance weight is then 1 since their light pdf is 0, so
//! the estimate stays unbiased, only noisier.

use glam::{Vec2, Vec3};

use crate::geometry::gamma;
use crate::materials::Material;
use crate::sampling::warp::{square_to_triangle, square_to_uniform_sphere};
use crate::scene::Object;
use crate::shapes::Shape;
use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
enum EmitterShape {
    Triangle { a: Vec3, b: Vec3, c: Vec3, normal: Vec3, area: f32 },
    Sphere { center: Vec3, radius: f32 },
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

#[derive(Clone, Debug, Default)]
pub struct AreaLights {
    emitters: Vec<Emitter>,
    /// Cumulative selection probabilities (by power), last = 1.
    cdf: Vec<f32>,
    /// Per object: index of its first emitter (its primitive p is `base + p`), or `NONE`.
    object_base: Vec<u32>,
}

const NONE: u32 = u32::MAX;

impl AreaLights {
    pub fn new(objects: &[Object], materials: &[Material]) -> Self {
        let mut emitters = Vec::new();
        let mut object_base = vec![NONE; objects.len()];
        for (o, object) in objects.iter().enumerate() {
            let Some(Material::Phong(m)) = materials.get(object.material as usize) else { continue };
            if m.emission == Rgb::ZERO {
                continue;
            }
            let triangles: Vec<[Vec3; 3]> = match &object.shape {
                Shape::Mesh(mesh) => (0..mesh.triangle_count()).map(|i| mesh.triangle_vertices(i)).collect(),
                Shape::Triangle(t) => vec![t.vertices],
                Shape::Sphere(s) if object.transform.is_none() => {
                    object_base[o] = emitters.len() as u32;
                    emitters.push(Emitter {
                        shape: EmitterShape::Sphere { center: s.center, radius: s.radius },
                        radiance: m.emission,
                        two_sided: m.two_sided_emission,
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
                    radiance: if area > 0.0 { m.emission } else { Rgb::ZERO },
                    two_sided: m.two_sided_emission,
                });
            }
        }
        let powers: Vec<f32> = emitters
            .iter()
            .map(|e| {
                let area = match e.shape {
                    EmitterShape::Triangle { area, .. } => area,
                    EmitterShape::Sphere { radius, .. } => 4.0 * std::f32::consts::PI * radius * radius,
                };
                let sides = if e.two_sided { 2.0 } else { 1.0 };
                e.radiance.dot(Rgb::splat(1.0 / 3.0)) * area * sides
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
            return Self { emitters: Vec::new(), cdf: Vec::new(), object_base: vec![NONE; objects.len()] };
        }
        Self { emitters, cdf, object_base }
    }

    pub fn is_empty(&self) -> bool {
        self.emitters.is_empty()
    }

    fn selection_probability(&self, i: usize) -> f32 {
        self.cdf[i] - if i == 0 { 0.0 } else { self.cdf[i - 1] }
    }

    /// A point on some light for the shading point `from`.
    pub fn sample(&self, from: Vec3, u_select: f32, u: Vec2) -> Option<LightSample> {
        if self.emitters.is_empty() {
            return None;
        }
        let i = self.cdf.partition_point(|&c| c <= u_select).min(self.emitters.len() - 1);
        let emitter = &self.emitters[i];
        let (point, normal, area, error) = match emitter.shape {
            EmitterShape::Triangle { a, b, c, normal, area } => {
                let bary = square_to_triangle(u);
                let w = 1.0 - bary.x - bary.y;
                let point = w * a + bary.x * b + bary.y * c;
                let error = gamma(7) * ((w * a).abs() + (bary.x * b).abs() + (bary.y * c).abs());
                (point, normal, area, error)
            }
            EmitterShape::Sphere { center, radius } => {
                let n = square_to_uniform_sphere(u);
                let point = center + radius * n;
                (point, n, 4.0 * std::f32::consts::PI * radius * radius, gamma(6) * (center.abs() + (radius * n).abs()))
            }
        };
        let to_light = point - from;
        let distance_squared = to_light.length_squared();
        let cos_light = -normal.dot(to_light) / distance_squared.sqrt();
        if cos_light.abs() <= 0.0 || area <= 0.0 {
            return None;
        }
        let radiance = if emitter.two_sided || cos_light > 0.0 { emitter.radiance } else { Rgb::ZERO };
        let pdf = self.selection_probability(i) * distance_squared / (cos_light.abs() * area);
        Some(LightSample { point, normal, error, radiance, pdf })
    }

    /// The solid-angle density with which `sample` from `from` would have produced the point
    /// `point` (with geometric normal `normal`) on primitive `prim` of object `object`; 0 if that
    /// primitive is not a sampled light. For multiple importance sampling of BSDF-sampled hits.
    pub fn pdf(&self, from: Vec3, object: u32, prim: u32, point: Vec3, normal: Vec3) -> f32 {
        let base = self.object_base.get(object as usize).copied().unwrap_or(NONE);
        if base == NONE {
            return 0.0;
        }
        let i = (base + prim) as usize;
        let area = match self.emitters[i].shape {
            EmitterShape::Triangle { area, .. } => area,
            EmitterShape::Sphere { radius, .. } => 4.0 * std::f32::consts::PI * radius * radius,
        };
        let to_light = point - from;
        let distance_squared = to_light.length_squared();
        let cos_light = normal.dot(to_light).abs() / distance_squared.sqrt();
        if cos_light <= 0.0 {
            return 0.0;
        }
        self.selection_probability(i) * distance_squared / (cos_light * area)
    }
}
