//! Volumetric path tracing (`--integrator volpath`; Mitsuba's `volpath`, pbrt-v4's
//! `VolPathIntegrator` without its spectral machinery): the path tracer's estimator with
//! participating media between surfaces.
//!
//! A path knows the medium it travels in: the camera's, then the one a surface's interface
//! gives on the side the path leaves into. Along each segment in a medium a free flight is
//! drawn (`Medium::flight`: exponential by a channel chosen uniformly, with MIS over the
//! channels, in a homogeneous medium; delta tracking in a grid). A flight that scatters makes
//! a vertex in the medium: next-event estimation toward one light, its shadow ray's
//! transmittance through every medium and null surface on the way (exact, or ratio tracking
//! in grids), weighed by the power heuristic against phase-function sampling, then a new
//! direction from the phase function. A flight that passes reaches the surface, which is
//! shaded as the path tracer shades it, its light samples' shadow rays attenuated the same
//! way. Null surfaces (masks of opacity 0, Mitsuba's `null`) are crossed without a bounce:
//! they only change the medium; so is a thin sheet when light passes straight through it
//! (Mitsuba's null transmission: shadow rays pass it too, with its transmittance).
//! Scattering in a medium counts as a bounce for `max_depth` and Russian roulette, as in
//! Mitsuba. An emitting medium's light (σ_a L_e per unit length) is gathered at each
//! collision.

use std::sync::Arc;

use glam::Vec3;

use super::estimators::{
    add_emission, add_escaped, add_next_event, next_event, roulette, Scatter, Scattering, Weighting,
};
use super::path::BounceDraws;
use super::path_record::{PathEnd, PathRecorder, TracesPaths};
use super::vertex::Vertex;
use super::volume_photons::VolumePhotons;
use super::{IntegratorSettings, SampleContext};
use crate::geometry::{offset_ray_origin, Ray};
use crate::lights::{LightEnd, LightSample};
use crate::materials::Bsdf;
use crate::media::{Flight, MediumInterface, PhaseFunction};
use crate::sampling::Rng;
use crate::scene::{Scene, SurfaceHit};
use crate::Rgb;

#[derive(Clone)]
pub struct VolPathTracer {
    pub max_depth: u32,
    pub rr_depth: u32,
    /// Volumetric photon mapping (`volphoton`): a path stops at its first scattering in a
    /// medium, where the light that scattered before arriving comes from these photons.
    pub photons: Option<Arc<VolumePhotons>>,
}

impl VolPathTracer {
    pub fn new(settings: &IntegratorSettings) -> Self {
        Self { max_depth: settings.max_depth, rr_depth: settings.rr_depth, photons: None }
    }
}

/// Null surfaces a single shadow ray, path segment or particle may cross in a row before glint
/// gives up on it (the light beyond is lost: scenes of more nested null boundaries than this
/// render dark).
pub(super) const MAX_CROSSINGS: usize = 256;

/// The medium beyond `object`'s surface for a ray leaving along `direction` (the surface's
/// geometric normal `geometric`): its interface's medium on that side, or `current` where the
/// object has no interface (it keeps the medium it sits in).
pub(super) fn medium_beyond(
    scene: &Scene,
    object: u32,
    direction: Vec3,
    geometric: Vec3,
    current: Option<u32>,
) -> Option<u32> {
    let interface = scene.medium_interface(object);
    if interface != MediumInterface::default() {
        interface.toward(direction, geometric)
    } else {
        current
    }
}

impl TracesPaths for VolPathTracer {
    fn trace(
        &self,
        scene: &Scene,
        camera_ray: &Ray,
        context: &mut SampleContext,
        recorder: &mut impl PathRecorder,
    ) -> Rgb {
        // The media's tracking draws many numbers: an independent stream per sample, seeded
        // by the sampler (deterministic for the seed, at any thread count).
        let seed = ((context.sampler.next_f32() as f64 * 4294967296.0) as u64) << 32
            | (context.sampler.next_f32() as f64 * 4294967296.0) as u64;
        let mut rng = Rng::new(seed, 0x766f6c70);
        let (mut radiance, mut throughput, mut eta_scale) = (Rgb::ZERO, Rgb::ONE, 1.0f32);
        let mut medium = scene.camera_medium();
        let mut previous: Option<Scatter> = None;
        let mut depth = 0u32;
        let mut ray = Ray::new(camera_ray.origin, camera_ray.direction.normalize());
        let mut crossings = 0usize;
        let end = loop {
            context.rays.reflection += 1;
            let hit = scene.intersect(&ray);
            let t_max = hit.as_ref().map_or(f32::INFINITY, |h| h.t);
            if let Some((index, m)) = medium.map(|i| (i, &scene.media()[i as usize])) {
                match m.flight(ray.origin, ray.direction, t_max, &mut rng) {
                    Flight::Scattered { t, weight } => {
                        let point = ray.origin + t * ray.direction;
                        let (sigma_s, sigma_a) = m.coefficients(point);
                        // An emitting medium's light along the flight, estimated at its
                        // collision (no light sampling finds it, so it counts in full).
                        let scattered = throughput * (weight * sigma_s);
                        recorder.medium(depth, point, index, scattered);
                        if m.emission != Rgb::ZERO {
                            let added = throughput * weight * sigma_a * m.emission;
                            radiance += added;
                            recorder.emission(weight * sigma_a * m.emission, 1.0, added);
                        }
                        throughput = scattered;
                        if depth >= self.max_depth {
                            break PathEnd::Depth;
                        }
                        if throughput == Rgb::ZERO {
                            break PathEnd::Absorbed;
                        }
                        // Light sampling from the medium, against phase sampling (in full where
                        // no phase sampling follows: photons).
                        let weighting = if self.photons.is_some() { Weighting::LightOnly } else { Weighting::Mis };
                        let phase =
                            InMedium { scene, phase: &m.phase, direction: ray.direction, point, medium, rng: &mut rng };
                        let event = next_event(scene, point, None, phase, weighting, context);
                        add_next_event(event, throughput, &mut radiance, recorder);
                        if let Some(photons) = &self.photons {
                            // The rest of the light scattered here, ∫ p L dω', from the
                            // medium's photons (the throughput holds σ_s).
                            let in_scattered = photons.in_scattered(index, point, ray.direction, &m.phase);
                            let added = throughput * in_scattered;
                            radiance += added;
                            recorder.medium_photons(in_scattered, added);
                            break PathEnd::Absorbed;
                        }
                        let (_, u) = BounceDraws::scatter(&mut context.sampler);
                        let sample = m.phase.sample(ray.direction, u);
                        recorder.phase(sample.outgoing, sample.pdf);
                        previous = Some(Scatter { point, normal: None, pdf: sample.pdf, delta: false });
                        ray = Ray::new(point, sample.outgoing);
                        depth += 1;
                        crossings = 0;
                        if depth > self.rr_depth && !roulette(&mut throughput, eta_scale, context, recorder) {
                            break PathEnd::Roulette;
                        }
                        continue;
                    }
                    Flight::Passed { weight } => throughput *= weight,
                }
            }
            let Some(hit) = hit else {
                add_escaped(scene, ray.direction, previous, throughput, &mut radiance, recorder);
                break PathEnd::Escaped;
            };
            let material = &scene.materials()[hit.material as usize];
            if material.is_null() {
                // A medium's boundary: cross it, the path unchanged but for its medium.
                crossings += 1;
                if crossings > MAX_CROSSINGS {
                    break PathEnd::Absorbed;
                }
                medium = medium_beyond(scene, hit.object, ray.direction, hit.geometry.geometric_normal, medium);
                ray = hit.spawn_ray(ray.direction);
                continue;
            }
            recorder.vertex(depth, &hit, throughput);
            let vertex = Vertex::at(scene, &ray, hit);
            let (wo, geometric) = (vertex.wo, hit.geometry.geometric_normal);
            add_emission(scene, &hit, vertex.emitted(), previous, throughput, &mut radiance, recorder);
            let bsdf = vertex.bsdf();
            let passable = bsdf.null_transmission(wo) != Rgb::ZERO;
            // Past the last bounce a path may still pass straight through a thin sheet: that
            // is no bounce (as in Mitsuba), and the light beyond still counts.
            let last = depth >= self.max_depth;
            if last && !passable {
                break PathEnd::Depth;
            }
            let medium_toward = |w: Vec3| medium_beyond(scene, hit.object, w, geometric, medium);
            if bsdf.has_diffuse() && !last {
                let surface = AtSurface { scene, hit: &hit, bsdf: &bsdf, wo, medium, rng: &mut rng };
                let (point, normal) = (hit.geometry.point, hit.geometry.shading_normal);
                let event = next_event(scene, point, Some(normal), surface, Weighting::Mis, context);
                add_next_event(event, throughput, &mut radiance, recorder);
            }
            let (u_lobe, u) = BounceDraws::scatter(&mut context.sampler);
            let Some(sample) = bsdf.sample(wo, u_lobe, u) else { break PathEnd::Absorbed };
            throughput *= sample.weight;
            recorder.scatter(&sample, throughput);
            if bsdf.is_null_event(wo, &sample) {
                // Straight through a thin sheet: a boundary crossed, as a null surface is (no
                // bounce; emission beyond is weighed against the last real scattering).
                crossings += 1;
                if crossings > MAX_CROSSINGS || throughput == Rgb::ZERO {
                    break PathEnd::Absorbed;
                }
                medium = medium_toward(sample.wi);
                ray = hit.spawn_ray(sample.wi);
                continue;
            }
            crossings = 0;
            if last {
                break PathEnd::Depth;
            }
            eta_scale *= sample.eta_squared;
            previous = Some(Scatter {
                point: hit.geometry.point,
                normal: Some(hit.geometry.shading_normal),
                pdf: sample.pdf,
                delta: sample.delta,
            });
            medium = medium_toward(sample.wi);
            depth += 1;
            if depth > self.rr_depth && !roulette(&mut throughput, eta_scale, context, recorder) {
                break PathEnd::Roulette;
            }
            if throughput == Rgb::ZERO {
                break PathEnd::Absorbed;
            }
            ray = hit.spawn_ray(sample.wi.normalize());
        };
        recorder.end(end);
        radiance
    }
}

/// A surface in a scene with media, lit through them: its BSDF, and shadow rays that start in
/// the medium on the light's side and pass media, null surfaces and thin sheets.
struct AtSurface<'a> {
    scene: &'a Scene,
    hit: &'a SurfaceHit,
    bsdf: &'a Bsdf<'a>,
    wo: Vec3,
    /// The medium the path arrived in.
    medium: Option<u32>,
    rng: &'a mut Rng,
}

impl Scattering for AtSurface<'_> {
    fn value(&self, wi: Vec3) -> Rgb {
        self.bsdf.eval(self.wo, wi)
    }

    fn density(&self, wi: Vec3) -> f32 {
        self.bsdf.pdf(self.wo, wi)
    }

    fn visibility(&mut self, light: &LightSample) -> Rgb {
        let (hit, scene) = (self.hit, self.scene);
        let medium = medium_beyond(scene, hit.object, light.direction, hit.geometry.geometric_normal, self.medium);
        transmittance(scene, hit.spawn_shadow_ray(light), medium, self.rng)
    }
}

/// A scattering collision in a medium, seen along `direction`: its phase function, and shadow
/// rays through the media beyond.
struct InMedium<'a> {
    scene: &'a Scene,
    phase: &'a PhaseFunction,
    direction: Vec3,
    point: Vec3,
    medium: Option<u32>,
    rng: &'a mut Rng,
}

impl Scattering for InMedium<'_> {
    fn value(&self, wi: Vec3) -> Rgb {
        Rgb::splat(self.phase.eval(self.direction, wi))
    }

    /// The phase function samples itself exactly: its density is its value.
    fn density(&self, wi: Vec3) -> f32 {
        self.phase.eval(self.direction, wi)
    }

    fn visibility(&mut self, light: &LightSample) -> Rgb {
        transmittance(self.scene, shadow_ray_from(self.point, light), self.medium, self.rng)
    }
}

/// A shadow ray from a point in a medium toward a sampled light: over t ∈ (0, 1) to a point
/// (short of a surface light by a relative margin), unbounded toward the environment.
fn shadow_ray_from(point: Vec3, light: &LightSample) -> Ray {
    match light.end {
        LightEnd::Surface { point: target, normal, error } => {
            // The far end off the light's surface by its error bound, as surface points'
            // shadow rays end (a sphere light must not shadow its own sample).
            let target = offset_ray_origin(target, error, normal, point - target);
            Ray { origin: point, direction: target - point, t_min: 0.0, t_max: 1.0 - 1e-4 }
        }
        LightEnd::Point(target) => Ray { origin: point, direction: target - point, t_min: 0.0, t_max: 1.0 - 1e-4 },
        LightEnd::Infinite => Ray::new(point, light.direction),
    }
}

/// The transmittance along a shadow ray that starts in `medium`: zero at the first opaque
/// surface; through null surfaces and thin sheets (their null transmission), the product of
/// the media's transmittances piece by piece, as Mitsuba's `volpath` lets shadow rays through.
/// (Shadow rays toward points come with their direction unnormalised and t ∈ (0, 1): the ray
/// is put in world units first, so every piece's length is a distance.)
fn transmittance(scene: &Scene, ray: Ray, mut medium: Option<u32>, rng: &mut Rng) -> Rgb {
    let length = ray.direction.length();
    if length.is_nan() || length <= 0.0 {
        return Rgb::ZERO;
    }
    let direction = ray.direction / length;
    let mut ray = Ray { origin: ray.origin, direction, t_min: ray.t_min * length, t_max: ray.t_max * length };
    let mut tr = Rgb::ONE;
    for _ in 0..MAX_CROSSINGS {
        let hit = scene.intersect(&ray);
        let end = hit.as_ref().map_or(ray.t_max, |h| h.t);
        if let Some(m) = medium.map(|i| &scene.media()[i as usize]) {
            let from = ray.origin + ray.t_min * direction;
            tr *= m.transmittance(from, direction, (end - ray.t_min).max(0.0), rng);
            if tr == Rgb::ZERO {
                return tr;
            }
        }
        let Some(hit) = hit else { return tr };
        let material = &scene.materials()[hit.material as usize];
        if !material.is_null() {
            if !material.may_pass_straight() {
                return Rgb::ZERO;
            }
            // A thin sheet lets light through, straight, with its transmittance.
            let vertex = Vertex::at(scene, &ray, hit);
            tr *= vertex.bsdf().null_transmission(vertex.wo);
            if tr == Rgb::ZERO {
                return tr;
            }
        }
        medium = medium_beyond(scene, hit.object, direction, hit.geometry.geometric_normal, medium);
        // On from the crossing, the rest of the segment.
        let remaining = ray.t_max - hit.t;
        ray = Ray { t_max: remaining, ..hit.spawn_ray(direction) };
        if ray.t_max <= ray.t_min {
            return tr;
        }
    }
    Rgb::ZERO
}
