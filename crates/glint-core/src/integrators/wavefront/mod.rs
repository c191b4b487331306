//! The path tracer as a wavefront: a tile's paths advance together, one bounce at a time, and
//! every stage but the ray queries runs eight paths at once in SIMD lanes (`lanes.rs`).
//!
//! It serves the scenes whose every part the lanes handle: flat triangles (meshes and triangle
//! shapes without a transform) of diffuse materials with constant colours, lit by triangle
//! area lights sampled by area, with no environment and no point, spot or directional light.
//! The Cornell box is one. Other scenes go path by path through `PathTracer::radiance`.
//!
//! It is that same estimator, operation for operation: each lane computes the bits the scalar
//! code computes and draws the same numbers in the same order, so the image is bit-identical
//! (tests/wavefront.rs) and every test of the path tracer holds for both. The closest-hit and
//! shadow queries stay one path at a time (the BVH's own SIMD runs across a node's children).

mod lanes;

use std::f32::consts::FRAC_1_PI;

use glam::Vec3;
use wide::{f32x8, CmpEq, CmpGe, CmpGt, CmpLe, CmpLt};

use self::lanes::{
    barycentric_point, offset_ray_origin, orthonormal_basis, square_to_cosine_hemisphere, Vec3x8, LANES,
};
use super::path::PathTracer;
use super::SampleContext;
use crate::geometry::Ray;
use crate::lights::{TriangleEmitter, TriangleSampling};
use crate::materials::{luminance, Material};
use crate::scene::{Scene, SHADOW_EPSILON};
use crate::shapes::Shape;
use crate::textures::Texture;
use crate::Rgb;

/// A material as the lanes read it.
#[derive(Clone, Copy, Debug)]
struct LaneMaterial {
    diffuse: Rgb,
    /// The BSDF has a lobe (p_diffuse = 1); a black one ends the path.
    reflects: bool,
    emission: Rgb,
    two_sided: bool,
}

impl LaneMaterial {
    /// Diffuse with a constant colour and nothing else, or `None`.
    fn of(material: &Material) -> Option<Self> {
        let Material::Phong(m) = material;
        let (Texture::Constant(diffuse), Texture::Constant(reflection), Texture::Constant(transmission)) =
            (&m.diffuse, &m.reflection, &m.transmission)
        else {
            return None;
        };
        if *reflection != Rgb::ZERO || *transmission != Rgb::ZERO || m.roughness > 0.0 {
            return None;
        }
        Some(Self {
            diffuse: *diffuse,
            reflects: luminance(*diffuse) > 0.0,
            emission: m.emission,
            two_sided: m.two_sided_emission,
        })
    }
}

/// The path tracer's wavefront over one scene.
pub(super) struct Wavefront<'a> {
    scene: &'a Scene,
    materials: Vec<LaneMaterial>,
    /// The area lights as triangles, then a black one for lanes without a light.
    emitters: &'a [TriangleEmitter],
    /// Some triangle has vertex normals (else the shading normal is the geometric one).
    smooth: bool,
    max_depth: u32,
    rr_depth: u32,
}

/// One path between bounces.
#[derive(Clone, Copy, Debug)]
struct Path {
    /// The ray to trace next.
    ray: Ray,
    throughput: Rgb,
    radiance: Rgb,
    /// Bounces so far.
    depth: u32,
    /// The last scattering point and the BSDF's density of the direction sampled there (for the
    /// MIS weight of emission found next), when `depth` > 0.
    from_point: Vec3,
    from_pdf: f32,
    /// The closest hit of `ray`: object, primitive, and the barycentric weights of the second
    /// and third corner.
    object: u32,
    prim: u32,
    b1: f32,
    b2: f32,
}

impl<'a> Wavefront<'a> {
    /// The wavefront for `scene`, if the lanes handle all of it.
    pub fn new(tracer: &PathTracer, scene: &'a Scene) -> Option<Self> {
        let lights = &scene.area_lights;
        let served = scene.geometry.all_triangles()
            && scene.lights.is_empty()
            && !scene.environment.emits()
            && lights.triangle_sampling == TriangleSampling::Area;
        if !served {
            return None;
        }
        let emitters = lights.triangle_table()?;
        let materials = scene.materials.iter().map(LaneMaterial::of).collect::<Option<Vec<_>>>()?;
        let smooth = scene.geometry.objects.iter().any(|o| match &o.shape {
            Shape::Mesh(m) => m.normals.is_some(),
            Shape::Triangle(t) => t.normals.is_some(),
            _ => false,
        });
        Some(Self { scene, materials, emitters, smooth, max_depth: tracer.max_depth, rr_depth: tracer.rr_depth })
    }

    /// The radiance along each camera ray, `out[i]` for `rays[i]` drawing from `contexts[i]`.
    pub fn radiance_tile(&self, rays: &[Ray], contexts: &mut [SampleContext], out: &mut [Rgb]) {
        let mut paths: Vec<Path> = rays
            .iter()
            .map(|&ray| Path {
                ray,
                throughput: Rgb::ONE,
                radiance: Rgb::ZERO,
                depth: 0,
                from_point: Vec3::ZERO,
                from_pdf: 0.0,
                object: 0,
                prim: 0,
                b1: 0.0,
                b2: 0.0,
            })
            .collect();
        let mut active: Vec<u32> = (0..paths.len() as u32).collect();
        let mut hits = Vec::with_capacity(paths.len());
        while !active.is_empty() {
            hits.clear();
            for &i in &active {
                let path = &mut paths[i as usize];
                let counts = &mut contexts[i as usize].rays;
                if path.depth == 0 {
                    counts.camera += 1;
                } else {
                    counts.reflection += 1;
                }
                // The query narrows the path's own ray, which is then not needed again: a
                // fresh copy's fields would still be in the store buffer when the query loads
                // them as a vector, a stall (store forwarding fails) of every closest hit.
                match self.scene.geometry.closest_primitive(&mut path.ray) {
                    Some(((object, prim), hit)) => {
                        (path.object, path.prim, path.b1, path.b2) = (object, prim, hit.u, hit.v);
                        hits.push(i);
                    }
                    // Weight 1: the environment emits nothing, so it is not light-sampled.
                    None => path.radiance += path.throughput * self.scene.environment.radiance(path.ray.direction),
                }
            }
            active.clear();
            for chunk in hits.chunks(LANES) {
                self.bounce(chunk, &mut paths, contexts, &mut active);
            }
        }
        for (out, path) in out.iter_mut().zip(&paths) {
            *out = path.radiance;
        }
    }

    /// One bounce of the (up to eight) paths `chunk`, which hit something: emission found,
    /// next-event estimation, the BSDF sample and Russian roulette. The paths that go on are
    /// added to `active`.
    fn bounce(&self, chunk: &[u32], paths: &mut [Path], contexts: &mut [SampleContext], active: &mut Vec<u32>) {
        let scene = self.scene;
        let n = chunk.len();
        // Lanes past the chunk's end repeat its first path; nothing of theirs is kept.
        let index: [usize; LANES] = std::array::from_fn(|k| chunk[if k < n { k } else { 0 }] as usize);
        // Read in place: a copy of the eight paths cost more than the reads.
        let p = |k: usize| &paths[index[k]];
        let corners: [[Vec3; 3]; LANES] = std::array::from_fn(|k| {
            scene.geometry.triangle(p(k).object, p(k).prim).expect("the wavefront serves triangle scenes")
        });
        let material: [LaneMaterial; LANES] =
            std::array::from_fn(|k| self.materials[scene.geometry.objects[p(k).object as usize].material as usize]);
        let depth: [u32; LANES] = std::array::from_fn(|k| p(k).depth);
        let zero = f32x8::ZERO;

        // The surface: triangle_surface's point, error bound and geometric normal.
        let wo = -Vec3x8::from_fn(|k| p(k).ray.direction).normalize();
        let [a, b, c] = [0, 1, 2].map(|j| Vec3x8::from_fn(|k| corners[k][j]));
        let (b1, b2) = (lanes(|k| p(k).b1), lanes(|k| p(k).b2));
        let (point, error) = barycentric_point([a, b, c], b1, b2);
        let geometric = (b - a).cross(c - a).normalize_or(Vec3x8::splat(Vec3::Z));
        let mut throughput = Vec3x8::from_fn(|k| p(k).throughput);
        let mut radiance = Vec3x8::from_fn(|k| p(k).radiance);

        // Emission found, weighed against light sampling from the last bounce (not at the first).
        let wo_dot_n = wo.dot(geometric);
        let emits_toward = mask(|k| material[k].two_sided) | wo_dot_n.cmp_gt(zero);
        let emitted = Vec3x8::select(emits_toward, Vec3x8::from_fn(|k| material[k].emission), Vec3x8::ZERO);
        let found = emitted.nonzero();
        if found.any() {
            let none = self.emitters.len() - 1;
            let emitter: [&TriangleEmitter; LANES] = std::array::from_fn(|k| {
                &self.emitters[scene.area_lights.emitter_index(p(k).object, p(k).prim).unwrap_or(none)]
            });
            let to_light = point - Vec3x8::from_fn(|k| p(k).from_point);
            let (light_pdf, seen) =
                area_to_solid_angle(lanes(|k| emitter[k].selection), lanes(|k| emitter[k].area), to_light, geometric);
            let light_pdf = (mask(|k| !std::ptr::eq(emitter[k], &self.emitters[none])) & seen).blend(light_pdf, zero);
            let weight =
                mask(|k| depth[k] == 0).blend(f32x8::ONE, power_heuristic(lanes(|k| p(k).from_pdf), light_pdf));
            radiance = Vec3x8::select(found, radiance + throughput.mul_lanes(emitted) * weight, radiance);
        }

        // Paths at the maximum depth, and on black surfaces, end here.
        let goes_on: [bool; LANES] =
            std::array::from_fn(|k| k < n && depth[k] < self.max_depth && material[k].reflects);
        let mut draws = [[0f32; 7]; LANES];
        for k in (0..n).filter(|&k| goes_on[k]) {
            let sampler = &mut contexts[index[k]].sampler;
            // Light (selection, point), lobe, direction, and roulette if it comes.
            let count = if depth[k] + 1 >= self.rr_depth { 7 } else { 6 };
            for draw in &mut draws[k][..count] {
                *draw = sampler.next_f32();
            }
        }
        let draw = |j: usize| lanes(|k| draws[k][j]);
        let on = mask(|k| goes_on[k]);

        // The shading normal: the vertex normals interpolated where the mesh has them
        // (triangle_surface), kept on the geometric normal's side.
        let vertex_normals: [Option<[Vec3; 3]>; LANES] = std::array::from_fn(|k| match self.smooth {
            true => scene.geometry.triangle_normals(p(k).object, p(k).prim),
            false => None,
        });
        let smooth = mask(|k| vertex_normals[k].is_some());
        let shading = if smooth.any() {
            let [na, nb, nc] = [0, 1, 2].map(|j| Vec3x8::from_fn(|k| vertex_normals[k].map_or(Vec3::ZERO, |n| n[j])));
            let n = (na * (f32x8::ONE - b1 - b2) + nb * b1 + nc * b2).normalize_or(geometric);
            Vec3x8::select(smooth, Vec3x8::select(n.dot(geometric).cmp_lt(zero), -n, n), geometric)
        } else {
            geometric
        };
        // The BSDF's frame (Bsdf::new): both normals turned to wo's side, and the geometric one
        // where the shading normal would face away from the viewer.
        let facing = Vec3x8::select(wo_dot_n.cmp_ge(zero), geometric, -geometric);
        let normal = Vec3x8::select(shading.dot(facing).cmp_ge(zero), shading, -shading);
        let normal = Vec3x8::select(normal.dot(wo).cmp_le(zero), facing, normal);
        let diffuse = Vec3x8::from_fn(|k| material[k].diffuse);

        // Next-event estimation: one point uniform on a light chosen by power.
        let none = self.emitters.len() - 1;
        let chosen: [usize; LANES] = std::array::from_fn(|k| match goes_on[k] {
            true => scene.area_lights.choose_index(draws[k][0]).unwrap_or(none),
            false => none,
        });
        let mut direct = Vec3x8::ZERO;
        if chosen.iter().any(|&i| i != none) {
            let light = chosen.map(|i| &self.emitters[i]);
            let [la, lb, lc] = [0, 1, 2].map(|j| Vec3x8::from_fn(|k| light[k].corners[j]));
            let light_normal = Vec3x8::from_fn(|k| light[k].normal);
            let area = lanes(|k| light[k].area);
            let two_sided = mask(|k| light[k].two_sided);
            // A one-sided light with every corner behind its plane sends nothing here.
            let behind = |corner: Vec3x8| light_normal.dot(corner - point).cmp_gt(zero);
            let hidden = !two_sided & behind(la) & behind(lb) & behind(lc);
            let s = draw(1).sqrt();
            let (light_point, light_error) = barycentric_point([la, lb, lc], f32x8::ONE - s, draw(2) * s);
            let to_light = light_point - point;
            let (pdf, seen) = area_to_solid_angle(lanes(|k| light[k].selection), area, to_light, light_normal);
            let cos_light = lanes::negate(light_normal.dot(to_light));
            let sampled = mask(|k| chosen[k] != none)
                & !hidden
                & !area.cmp_le(zero)
                & seen
                & pdf.cmp_gt(zero)
                & pdf.is_finite()
                & !cos_light.cmp_eq(zero);
            let light_radiance = Vec3x8::select(
                two_sided | cos_light.cmp_gt(zero),
                Vec3x8::from_fn(|k| light[k].radiance),
                Vec3x8::ZERO,
            );
            let wi = to_light.normalize();
            let (cos, above) = (wi.dot(normal), wi.dot(facing));
            let f = Vec3x8::select(
                cos.cmp_le(zero) | above.cmp_le(zero),
                Vec3x8::ZERO,
                diffuse * (cos * f32x8::splat(FRAC_1_PI)),
            );
            let traced = sampled & light_radiance.nonzero() & f.nonzero() & pdf.cmp_gt(zero);
            // The shadow ray, each end offset off its surface toward the other.
            let origin = offset_ray_origin(point, error, geometric, to_light);
            let end = offset_ray_origin(light_point, light_error, light_normal, point - light_point);
            let toward = end - origin;
            let traced = traced.move_mask();
            // All eight written before the first is traced: a query that loads a ray as vectors
            // while its fields' stores are still on their way to the cache stalls until they
            // arrive (store forwarding fails).
            let shadow_rays: [Ray; LANES] =
                std::array::from_fn(|k| Ray::with_range(origin.lane(k), toward.lane(k), 0.0, 1.0 - SHADOW_EPSILON));
            let bsdf_pdf = (above.cmp_gt(zero) & cos.cmp_gt(zero)).blend(cos * f32x8::splat(FRAC_1_PI), zero);
            let weight = power_heuristic(pdf, bsdf_pdf);
            let contribution = Vec3x8::ZERO + f.mul_lanes(light_radiance) * (weight / pdf);
            let unoccluded = mask(|k| {
                if traced & (1 << k) == 0 {
                    return false;
                }
                contexts[index[k]].rays.shadow += 1;
                !scene.occluded(&shadow_rays[k])
            });
            direct = Vec3x8::select(unoccluded, contribution, Vec3x8::ZERO);
        }
        radiance = Vec3x8::select(on, radiance + throughput.mul_lanes(direct), radiance);

        // The BSDF sample: cosine-weighted, weight k_d.
        let local = square_to_cosine_hemisphere(draw(4), draw(5));
        let (tangent, bitangent) = orthonormal_basis(normal);
        let wi = tangent * local.x + bitangent * local.y + normal * local.z;
        let scattered = !(local.z.cmp_le(zero) | wi.dot(facing).cmp_le(zero));
        let pdf = local.z.cmp_gt(zero).blend(local.z * f32x8::splat(FRAC_1_PI), zero);
        throughput = throughput.mul_lanes(diffuse);
        // Russian roulette (Mitsuba's rule), from rr_depth bounces on.
        let roulette = mask(|k| depth[k] + 1 >= self.rr_depth);
        let max = throughput.max_element();
        let survival = max.cmp_lt(f32x8::splat(0.95)).blend(max, f32x8::splat(0.95));
        let killed = roulette & (survival.cmp_le(zero) | draw(6).cmp_ge(survival));
        let survivor = Vec3x8 { x: throughput.x / survival, y: throughput.y / survival, z: throughput.z / survival };
        throughput = Vec3x8::select(roulette, survivor, throughput);
        let continues = (on & scattered & !killed & throughput.nonzero()).move_mask();
        let origin = offset_ray_origin(point, error, geometric, wi);

        for (k, &i) in index.iter().enumerate().take(n) {
            let path = &mut paths[i];
            path.radiance = radiance.lane(k);
            if continues & (1 << k) != 0 {
                path.throughput = throughput.lane(k);
                path.ray = Ray::new(origin.lane(k), wi.lane(k));
                path.from_point = point.lane(k);
                path.from_pdf = pdf.as_array_ref()[k];
                path.depth += 1;
                active.push(i as u32);
            }
        }
    }
}

/// Lane k is `f(k)`.
#[inline(always)]
fn lanes(f: impl Fn(usize) -> f32) -> f32x8 {
    f32x8::from(std::array::from_fn::<f32, LANES, _>(f))
}

/// A lane mask, set where `f(k)`.
#[inline(always)]
fn mask(mut f: impl FnMut(usize) -> bool) -> f32x8 {
    let all = f32::from_bits(u32::MAX);
    f32x8::from(std::array::from_fn::<f32, LANES, _>(|k| if f(k) { all } else { 0.0 }))
}

/// `area_to_solid_angle` in lanes: the density `selection / area` on the light as a density
/// in solid angle seen across `to_light`, and the mask of lanes where the light is not seen
/// edge on.
#[inline(always)]
fn area_to_solid_angle(selection: f32x8, area: f32x8, to_light: Vec3x8, normal: Vec3x8) -> (f32x8, f32x8) {
    let distance_squared = to_light.dot(to_light);
    let projected = normal.dot(to_light).abs();
    (selection * distance_squared * distance_squared.sqrt() / (projected * area), projected.cmp_gt(f32x8::ZERO))
}

/// `power_heuristic` in lanes.
#[inline(always)]
fn power_heuristic(a: f32x8, b: f32x8) -> f32x8 {
    let (a2, b2) = (a * a, b * b);
    let special = (a2 + b2).cmp_eq(f32x8::ZERO) | !a2.is_finite();
    special.blend(a2.is_inf().blend(f32x8::ONE, f32x8::ZERO), a2 / (a2 + b2))
}
