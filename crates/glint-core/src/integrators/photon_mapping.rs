//! Photon mapping (`--integrator photon`), Jensen 1996, both passes.
//!
//! First pass, once per render: photons leave the lights in proportion to their power and are
//! traced with the BSDFs' sampling and Russian roulette; wherever one lands on a surface with
//! a non-delta BSDF it is stored in the **global map**, and, if its path from the light was
//! L S+ D (only mirrors and glass before), in the **caustic map**, which is filled by shooting
//! on until it holds its own count. Each map is a balanced kd-tree (`crate::photons`).
//!
//! Second pass, per camera sample: along the camera path through mirrors and glass, at every
//! surface with a non-delta part the radiance is
//! * direct light, by light sampling (emission seen directly or through specular bounces is
//!   added where it is hit);
//! * caustics, from the caustic map seen directly (k nearest photons, cone filter);
//! * indirect light, by **final gathering**: rays sampled from the BSDF, each estimating the
//!   radiance where it lands from the global map (through mirrors and glass, if it meets them).
//!
//! Those three cover every path once: L D, L S+ D and L … D (S*) D.
//!
//! Final gathering is what costs: every gather ray needs a radiance estimate. As Christensen
//! (1999) and Jensen's book do, the irradiance is precomputed at every fourth photon of the
//! global map (from its k nearest photons on the same side of the same surface); a gather ray
//! landing on a Lambertian surface then takes k_d/π times the irradiance of the nearest such
//! record facing the same way, and only glossy surfaces pay for a full estimate.
//!
//! Emitters that light sampling cannot sample (only transformed spheres and non-triangle
//! shapes) light the scene through the photons only. The environment (map or constant
//! background) is sampled for direct light and emits photons like any light.

use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, Ordering};

use glam::Vec2;
use rayon::prelude::*;

use super::estimators::{roulette, surface_next_event, Weighting};
use super::particle::{shoot_batches, trace_particle, ParticleVertex, BATCH};
use super::path_record::{GatherRecord, PathEnd, PathRecorder, TracesPaths};
use super::vertex::{trace_seeing_light, Vertex};
use super::{RayCounts, SampleContext};
use crate::geometry::Ray;
use crate::materials::Bsdf;
use crate::photons::{NearestPhotons, Photon, PhotonMap};
use crate::scene::{Scene, SurfaceHit};
use crate::RenderError;
use crate::Rgb;

/// Photon-mapping parameters (the defaults are `PhotonSettings::default()`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhotonSettings {
    /// Photons stored in the global map.
    pub global_photons: u32,
    /// Photons stored in the caustic map.
    pub caustic_photons: u32,
    /// Photons in each radiance estimate.
    pub nearest: u32,
    /// Largest search radius of an estimate; 0: 5 % of the scene's bounding-box diagonal.
    pub max_radius: f32,
    /// Final-gather rays per camera sample.
    pub final_gather: u32,
}

impl Default for PhotonSettings {
    fn default() -> Self {
        Self { global_photons: 200_000, caustic_photons: 200_000, nearest: 50, max_radius: 0.0, final_gather: 16 }
    }
}

/// Batches shot between checks of the stored count.
const ROUND: u64 = 64;
/// A map gives up after this many particles per photon wanted (few caustics, say).
const CAUSTIC_EFFORT: u64 = 32;
/// Gather rays follow at most this many specular bounces.
const GATHER_SPECULAR_DEPTH: u32 = 8;
/// Every this many global photons, one irradiance record.
const IRRADIANCE_STRIDE: usize = 4;
/// Photons and records count as on the same surface when their normals agree this well.
const SAME_SURFACE_COS: f32 = 0.9;
/// Irradiance records examined for one facing the right way.
const IRRADIANCE_CANDIDATES: usize = 8;
/// The cone filter's constant k (Jensen: w = 1 − d / (k r)), and its normalisation.
const CONE_K: f32 = 1.1;

/// Random-number streams of the photon sets, apart from each other and the camera's.
const GLOBAL_STREAM: u64 = 0x474C_4F42;
const CAUSTIC_STREAM: u64 = 0x4341_5553;

/// What shooting photons needs: the scene (its lights checked as particle sources, by
/// `Lights::check_particles`), the path-length limit and the render's seed.
pub(super) struct PhotonShooter<'a> {
    pub scene: &'a Scene,
    pub max_depth: u32,
    pub seed: u64,
    /// Raised (Ctrl-C): `fill_map` stops after the round under way.
    pub stop: Option<&'a AtomicBool>,
}

/// Which particle vertices become photons.
pub(super) type Keep<'k> = &'k (dyn Fn(&ParticleVertex) -> bool + Sync);

impl PhotonShooter<'_> {
    /// Shoots the batches `batches` of random stream `stream` (batch b draws from its own
    /// generator) and keeps the photons `keep` accepts, in batch order. Returns the photons,
    /// the particles emitted and the rays traced.
    pub fn shoot(&self, stream: u64, batches: std::ops::Range<u64>, keep: Keep) -> (Vec<Photon>, u64, RayCounts) {
        let emitted = (batches.end - batches.start) * BATCH;
        let (photons, rays) = shoot_batches(self.scene, self.seed ^ stream, batches, |particle, rng, rays, photons| {
            trace_particle(self.scene, particle, self.max_depth, rng, rays, &mut (), |v, _, _, _| {
                if keep(v) {
                    let n = v.hit.geometric_normal_toward(v.wo);
                    photons.push(Photon::new(v.hit.geometry.point, v.wo, n, v.weight));
                }
            });
        });
        (photons, emitted, rays)
    }

    /// Shoots rounds of batches until `wanted` photons are kept or `max_particles` emitted.
    fn fill_map(&self, stream: u64, wanted: u64, max_particles: u64, keep: Keep) -> (PhotonMap, RayCounts) {
        let mut photons = Vec::new();
        let mut emitted = 0u64;
        let mut rays = RayCounts::default();
        let mut next_batch = 0u64;
        while (photons.len() as u64) < wanted && emitted < max_particles {
            if self.stop.is_some_and(|stop| stop.load(Ordering::Relaxed)) {
                break;
            }
            let (more, n, r) = self.shoot(stream, next_batch..next_batch + ROUND, keep);
            photons.extend(more);
            emitted += n;
            rays.add(&r);
            next_batch += ROUND;
            if photons.is_empty() {
                break; // none in a whole round: this scene makes none (no caustics, say)
            }
        }
        if self.stop.is_some_and(|stop| stop.load(Ordering::Relaxed)) {
            // Interrupted: the map will not be used, and building it takes a while.
            photons.clear();
        }
        (PhotonMap::build(photons, emitted), rays)
    }
}

pub struct PhotonMapper {
    pub max_depth: u32,
    pub rr_depth: u32,
    settings: PhotonSettings,
    max_radius: f32,
    global: PhotonMap,
    caustic: PhotonMap,
    /// Irradiance precomputed at every `IRRADIANCE_STRIDE`-th global photon: `power` holds the
    /// irradiance, `normal` the surface's normal on the side it was estimated for.
    irradiance: PhotonMap,
    /// Rays traced to build the maps.
    pub photon_rays: RayCounts,
}

thread_local! {
    static NEAREST: RefCell<NearestPhotons> = RefCell::new(NearestPhotons::default());
}

impl PhotonMapper {
    /// Builds both photon maps for `scene` (the first pass).
    pub fn new(
        scene: &Scene,
        max_depth: u32,
        rr_depth: u32,
        settings: PhotonSettings,
        seed: u64,
    ) -> Result<Self, RenderError> {
        Self::new_until(scene, max_depth, rr_depth, settings, seed, &AtomicBool::new(false))
    }

    /// `new`, giving up with an error soon after `stop` is raised (Ctrl-C while shooting).
    pub fn new_until(
        scene: &Scene,
        max_depth: u32,
        rr_depth: u32,
        settings: PhotonSettings,
        seed: u64,
        stop: &AtomicBool,
    ) -> Result<Self, RenderError> {
        scene.lights().check_particles()?;
        let shooter = PhotonShooter { scene, max_depth, seed, stop: Some(stop) };
        let (global, mut photon_rays) = shooter.fill_map(
            GLOBAL_STREAM,
            settings.global_photons as u64,
            settings.global_photons as u64 * CAUSTIC_EFFORT,
            &|_| true,
        );
        let (caustic, caustic_rays) = shooter.fill_map(
            CAUSTIC_STREAM,
            settings.caustic_photons as u64,
            settings.caustic_photons as u64 * CAUSTIC_EFFORT,
            &|v| v.bounces > 0 && v.specular_chain,
        );
        photon_rays.add(&caustic_rays);
        if stop.load(Ordering::Relaxed) {
            return Err(RenderError::Interrupted);
        }
        let bounds = scene.geometry().bounds();
        let max_radius = if settings.max_radius > 0.0 {
            settings.max_radius
        } else if bounds.is_empty() {
            1.0
        } else {
            0.05 * bounds.extent().length()
        };
        let irradiance = precompute_irradiance(&global, settings.nearest as usize, max_radius);
        Ok(Self { max_depth, rr_depth, settings, max_radius, global, caustic, irradiance, photon_rays })
    }

    /// Radiance leaving a Lambertian surface at `hit` toward the side of `normal`, from the
    /// nearest irradiance record on that surface; `None` if there is none near.
    fn cached_radiance(&self, hit: &SurfaceHit, normal: glam::Vec3, reflectance: Rgb) -> Option<Rgb> {
        NEAREST.with_borrow_mut(|nearest| {
            self.irradiance.k_nearest(hit.geometry.point, IRRADIANCE_CANDIDATES, self.max_radius, nearest);
            let mut best: Option<(f32, u32)> = None;
            for (d2, i) in nearest.iter() {
                if self.irradiance.photon(i).normal().dot(normal) >= SAME_SURFACE_COS
                    && best.is_none_or(|(b, _)| d2 < b)
                {
                    best = Some((d2, i));
                }
            }
            best.map(|(_, i)| reflectance * std::f32::consts::FRAC_1_PI * self.irradiance.photon(i).power)
        })
    }

    pub fn global_map(&self) -> &PhotonMap {
        &self.global
    }

    pub fn caustic_map(&self) -> &PhotonMap {
        &self.caustic
    }

    pub fn max_radius(&self) -> f32 {
        self.max_radius
    }

    /// Radiance reflected toward `wo` at `hit`, estimated from the `nearest` photons of `map`
    /// with the cone filter.
    pub fn estimate(&self, map: &PhotonMap, hit: &SurfaceHit, bsdf: &Bsdf, wo: glam::Vec3) -> Rgb {
        if map.is_empty() {
            return Rgb::ZERO;
        }
        NEAREST.with_borrow_mut(|nearest| {
            map.k_nearest(hit.geometry.point, self.settings.nearest as usize, self.max_radius, nearest);
            let r2 = nearest.max_distance_squared();
            if r2 <= 0.0 {
                return Rgb::ZERO;
            }
            let r = r2.sqrt();
            let normal = hit.geometric_normal_toward(wo);
            let mut sum = Rgb::ZERO;
            for (d2, i) in nearest.iter() {
                let photon = map.photon(i);
                if !photon.can_reach(hit.geometry.point, normal) {
                    continue;
                }
                let weight = 1.0 - d2.sqrt() / (CONE_K * r);
                sum += bsdf.eval_without_cosine(wo, photon.incoming()) * photon.power * weight;
            }
            let normalisation = (1.0 - 2.0 / (3.0 * CONE_K)) * std::f32::consts::PI * r2 * map.emitted() as f32;
            sum / normalisation
        })
    }

    /// Indirect light at `hit` by final gathering into the global map.
    fn gather(&self, scene: &Scene, hit: &SurfaceHit, bsdf: &Bsdf, wo: glam::Vec3, context: &mut SampleContext) -> Rgb {
        let n = self.settings.final_gather;
        let mut sum = Rgb::ZERO;
        for _ in 0..n {
            let u_lobe = context.sampler.next_f32();
            let u = Vec2::new(context.sampler.next_f32(), context.sampler.next_f32());
            let Some(sample) = bsdf.sample_non_delta(wo, u_lobe, u) else { continue };
            let mut weight = sample.weight;
            let mut ray: Ray = hit.spawn_ray(sample.wi);
            for _ in 0..GATHER_SPECULAR_DEPTH {
                context.rays.reflection += 1;
                // Light from the environment is direct light, which light sampling counted.
                let Some(vertex) = Vertex::trace(scene, &ray) else { break };
                let (y, wo_y, bsdf_y) = (&vertex.hit, vertex.wo, vertex.bsdf());
                let p = bsdf_y.non_delta_probability();
                if context.sampler.next_f32() < p {
                    let n = y.geometric_normal_toward(wo_y);
                    let cached = bsdf_y.lambertian().and_then(|k_d| self.cached_radiance(y, n, k_d));
                    let radiance = cached.unwrap_or_else(|| self.estimate(&self.global, y, &bsdf_y, wo_y));
                    sum += weight * radiance / p;
                    break;
                }
                let u_lobe = context.sampler.next_f32();
                let u = Vec2::new(context.sampler.next_f32(), context.sampler.next_f32());
                let Some(delta) = bsdf_y.sample_delta(wo_y, u_lobe, u) else { break };
                weight *= delta.weight / (1.0 - p);
                ray = y.spawn_ray(delta.wi);
            }
        }
        if n == 0 {
            Rgb::ZERO
        } else {
            sum / n as f32
        }
    }
}

/// Irradiance at every `IRRADIANCE_STRIDE`-th photon of `global`, from its `nearest` nearest
/// photons on the same surface (normals within `SAME_SURFACE_COS`), as records of a new map.
fn precompute_irradiance(global: &PhotonMap, nearest: usize, max_radius: f32) -> PhotonMap {
    let records: Vec<Photon> = (0..global.len())
        .step_by(IRRADIANCE_STRIDE)
        .collect::<Vec<_>>()
        .into_par_iter()
        .map(|i| {
            let photon = global.photon(i as u32);
            let normal = photon.normal();
            let irradiance = NEAREST.with_borrow_mut(|found| {
                global.k_nearest(photon.position, nearest, max_radius, found);
                let r2 = found.max_distance_squared();
                if r2 <= 0.0 {
                    return Rgb::ZERO;
                }
                let mut flux = Rgb::ZERO;
                for (_, j) in found.iter() {
                    let other = global.photon(j);
                    if other.normal().dot(normal) >= SAME_SURFACE_COS {
                        flux += other.power;
                    }
                }
                flux / (std::f32::consts::PI * r2 * global.emitted() as f32)
            });
            Photon::new(photon.position, normal, normal, irradiance)
        })
        .collect();
    PhotonMap::build(records, 1)
}

impl TracesPaths for PhotonMapper {
    /// The camera path through delta bounces to the diffuse surfaces it meets, each estimated
    /// from light sampling and the photon maps.
    fn trace(
        &self,
        scene: &Scene,
        camera_ray: &Ray,
        context: &mut SampleContext,
        recorder: &mut impl PathRecorder,
    ) -> Rgb {
        let mut radiance = Rgb::ZERO;
        let mut throughput = Rgb::ONE;
        let mut ray = *camera_ray;
        let mut depth = 0u32;
        loop {
            if depth == 0 {
                context.rays.camera += 1;
            } else {
                context.rays.refraction += 1;
            }
            let Some(vertex) = trace_seeing_light(scene, &ray, depth, throughput, &mut radiance, recorder) else {
                break;
            };
            if depth >= self.max_depth {
                recorder.end(PathEnd::Depth);
                break;
            }
            let bsdf = vertex.bsdf();
            let (hit, wo) = (&vertex.hit, vertex.wo);
            if bsdf.has_diffuse() {
                let direct = surface_next_event(scene, hit, &bsdf, wo, Weighting::LightOnly, context).contribution;
                let caustic = self.estimate(&self.caustic, hit, &bsdf, wo);
                let mut local = direct;
                local += caustic;
                let indirect = (depth + 1 < self.max_depth).then(|| self.gather(scene, hit, &bsdf, wo, context));
                if let Some(indirect) = indirect {
                    local += indirect;
                }
                let added = throughput * local;
                radiance += added;
                recorder.gather(GatherRecord { direct, caustic, indirect, added });
            }
            let u_lobe = context.sampler.next_f32();
            let u = Vec2::new(context.sampler.next_f32(), context.sampler.next_f32());
            let Some(sample) = bsdf.sample_delta(wo, u_lobe, u) else {
                recorder.end(PathEnd::Absorbed);
                break;
            };
            throughput *= sample.weight;
            recorder.scatter(&sample, throughput);
            depth += 1;
            if depth >= self.rr_depth && !roulette(&mut throughput, 1.0, context, recorder) {
                recorder.end(PathEnd::Roulette);
                break;
            }
            if throughput == Rgb::ZERO {
                recorder.end(PathEnd::Absorbed);
                break;
            }
            ray = hit.spawn_ray(sample.wi);
        }
        radiance
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Camera;
    use crate::lights::{Falloff, Light, PointLight, SpotLight};
    use crate::materials::{Material, Phong};
    use crate::scene::{Object, SceneBuilder};
    use crate::shapes::{Shape, Sphere, Triangle};
    use crate::textures::Texture;
    use glam::Vec3;

    /// Photon bookkeeping: inside a closed sphere every particle lands once straight from its
    /// light, so the flux of first-hit photons over the particles emitted is the lights' power.
    #[test]
    fn first_hit_photons_carry_the_lights_power() {
        let grey = Material::Phong(Phong { diffuse: Texture::Constant(Rgb::splat(0.5)), ..Phong::default() });
        let lamp = Material::Phong(Phong {
            diffuse: Texture::Constant(Rgb::splat(0.5)),
            emission: Rgb::new(2.0, 1.0, 0.5),
            ..Phong::default()
        });
        let (a, b, c) = (Vec3::new(-0.2, 0.5, 0.0), Vec3::new(0.2, 0.5, 0.0), Vec3::new(0.0, 0.5, 0.3));
        let objects = vec![
            Object {
                name: "shell".into(),
                shape: Shape::Sphere(Sphere::new(Vec3::ZERO, 3.0)),
                transform: None,
                material: 0,
            },
            Object {
                name: "lamp".into(),
                shape: Shape::Triangle(Triangle::new(a, b, c)),
                transform: None,
                material: 1,
            },
        ];
        let point = PointLight {
            position: Vec3::new(0.5, 0.0, 0.0),
            intensity: Rgb::new(1.0, 2.0, 3.0),
            falloff: Falloff::InverseSquare,
        };
        let spot = SpotLight::new(Vec3::ZERO, Vec3::Y, Rgb::splat(4.0), Falloff::InverseSquare, 30.0, 10.0);
        let camera = Camera::new(Vec3::ZERO, Vec3::Z, Vec3::Y, 45.0, 8, 8).unwrap();
        let scene = SceneBuilder::new(camera)
            .objects(objects)
            .materials(vec![("grey".into(), grey), ("lamp".into(), lamp)])
            .lights(vec![Light::Point(point), Light::Spot(spot.clone())])
            .build();
        scene.lights().check_particles().unwrap();
        let shooter = PhotonShooter { scene: &scene, max_depth: 1, seed: 9, stop: None };
        let (photons, emitted, _) = shooter.shoot(1, 0..400, &|v| v.bounces == 0);
        // Summed in f64: 400,000 values of f32 drift by a percent.
        let sum = photons.iter().fold(glam::DVec3::ZERO, |acc, p| acc + p.power.as_dvec3());
        let flux: Rgb = (sum / emitted as f64).as_vec3();
        let pi = std::f32::consts::PI;
        let spot_power = 2.0 * pi * 4.0 * (1.0 - 0.5 * (spot.cos_full + spot.cos_cone));
        // The lamp triangle is one-sided: L_e · π · area.
        let lamp_power = Rgb::new(2.0, 1.0, 0.5) * pi * 0.5 * (b - a).cross(c - a).length();
        let expected = Rgb::new(1.0, 2.0, 3.0) * 4.0 * pi + Rgb::splat(spot_power) + lamp_power;
        let relative = (flux - expected).abs() / expected;
        // 409,600 particles; the spot's weights vary over its edge, the rest are constant.
        assert!(relative.max_element() < 0.015, "flux {flux} vs power {expected}");
    }
}
