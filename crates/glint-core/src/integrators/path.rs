//! Path tracing with next-event estimation and multiple importance sampling
//! (`--integrator path`; Veach 1997, pbrt-v4's `PathIntegrator`).
//!
//! At every hit: light sampling (one light chosen by power among all of them: an area light's
//! point, a sphere by the cone it subtends, a triangle by area or by solid angle as
//! `light_sampling` says; a point, spot or directional light; a direction toward the
//! environment) and BSDF sampling, combined by the power heuristic, so both small bright
//! lights and glossy reflections converge well. Emission seen directly or through
//! delta (mirror, glass) bounces counts in full. Russian roulette from `rr_depth` bounces on,
//! with survival min(max throughput · η², 0.95) as Mitsuba does. `max_depth` counts scattering
//! events (0 = emitters only, 1 = direct lighting); unbounded by default in path-tracing
//! scenes. Unbiased: it converges to the same image as `path-naive`.

use glam::{Vec2, Vec3};

use super::wavefront::Wavefront;
use super::{radiance_each, Integrator, IntegratorSettings, SampleContext};
use crate::geometry::Ray;
use crate::materials::Bsdf;
use crate::scene::{Scene, SurfaceHit};
use crate::Rgb;

#[derive(Clone, Copy, Debug)]
pub struct PathTracer {
    pub max_depth: u32,
    pub rr_depth: u32,
    /// Run a tile's paths as a wavefront where the scene allows (`wavefront`); false: one
    /// path at a time. The image is the same.
    pub wavefront: bool,
}

impl PathTracer {
    pub fn new(settings: &IntegratorSettings) -> Self {
        Self { max_depth: settings.max_depth, rr_depth: settings.rr_depth, wavefront: settings.wavefront }
    }

    /// Whether a render of `scene` runs as a wavefront in SIMD lanes (see `wavefront`).
    pub fn runs_as_wavefront(&self, scene: &Scene) -> bool {
        self.wavefront_for(scene).is_some()
    }

    /// The wavefront over `scene`, if it is on.
    fn wavefront_for<'a>(&self, scene: &'a Scene) -> Option<Wavefront<'a>> {
        self.wavefront.then(|| Wavefront::new(self, scene))
    }
}

/// A scattering event that sampled the ray now traced.
#[derive(Clone, Copy, Debug)]
pub(super) struct Scatter {
    pub point: Vec3,
    /// What light sampling from `point` was given as the receiver's normal.
    pub shading_normal: Vec3,
    /// The BSDF's solid-angle density for the sampled direction.
    pub pdf: f32,
    /// A mirror or refraction: light sampling could not have made it.
    pub delta: bool,
}

/// A path between bounces, as `PathTracer::bounce` reads and leaves it.
#[derive(Clone, Copy, Debug)]
pub(super) struct PathState {
    pub radiance: Rgb,
    pub throughput: Rgb,
    /// The product of the refractions' relative η², for Russian roulette.
    pub eta_scale: f32,
    /// Bounces so far.
    pub depth: u32,
    /// Where the last bounce was sampled, and how (`None` for a camera ray): for the MIS
    /// weight of emission found next.
    pub previous: Option<Scatter>,
}

impl PathState {
    /// A path before its camera ray is traced.
    pub const CAMERA: Self =
        Self { radiance: Rgb::ZERO, throughput: Rgb::ONE, eta_scale: 1.0, depth: 0, previous: None };
}

/// The power heuristic (β = 2) for the strategy with density `a` against one with `b`.
pub fn power_heuristic(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 == 0.0 || !a2.is_finite() {
        return if a2.is_infinite() { 1.0 } else { 0.0 };
    }
    a2 / (a2 + b2)
}

impl Integrator for PathTracer {
    /// A tile's paths as a wavefront in SIMD lanes where the scene allows (`wavefront`), with
    /// the same result as one by one.
    fn radiance_tile(&self, scene: &Scene, rays: &[Ray], contexts: &mut [SampleContext], out: &mut [Rgb]) {
        match self.wavefront_for(scene) {
            Some(wavefront) => wavefront.radiance_tile(rays, contexts, out),
            None => radiance_each(self, scene, rays, contexts, out),
        }
    }

    fn radiance(&self, scene: &Scene, camera_ray: &Ray, context: &mut SampleContext) -> Rgb {
        let mut path = PathState::CAMERA;
        let mut ray = *camera_ray;
        loop {
            if path.previous.is_none() {
                context.rays.camera += 1;
            } else {
                context.rays.reflection += 1;
            }
            let Some(hit) = scene.intersect(&ray) else {
                // The environment is light-sampled too: weigh this BSDF sample against that.
                let weight = match path.previous {
                    Some(from) if !from.delta && scene.lights().has_environment() => {
                        power_heuristic(from.pdf, scene.lights().pdf_environment(ray.direction))
                    }
                    _ => 1.0,
                };
                path.radiance += path.throughput * scene.environment().radiance(ray.direction) * weight;
                break;
            };
            match self.bounce(scene, &ray, &hit, &mut path, context) {
                Some(next) => ray = next,
                None => break,
            }
        }
        path.radiance
    }
}

impl PathTracer {
    /// One bounce of `path` at `hit`, the closest hit of `ray`: the emission found there, light
    /// sampling, the BSDF's sample and Russian roulette. Returns the ray to trace next, or
    /// `None` where the path ends. (The wavefront takes the bounces its lanes do not model
    /// from here.)
    pub(super) fn bounce(
        &self,
        scene: &Scene,
        ray: &Ray,
        hit: &SurfaceHit,
        path: &mut PathState,
        context: &mut SampleContext,
    ) -> Option<Ray> {
        let wo = -ray.direction.normalize();
        let material = &scene.materials()[hit.material as usize];
        let geometric = hit.geometry.geometric_normal;
        let emitted = material.emitted(wo, geometric);
        if emitted != Rgb::ZERO {
            let weight = match path.previous {
                Some(from) if !from.delta => {
                    let light_pdf = scene.lights().pdf_area(
                        from.point,
                        Some(from.shading_normal),
                        hit.object,
                        hit.prim,
                        hit.geometry.point,
                        geometric,
                    );
                    power_heuristic(from.pdf, light_pdf)
                }
                _ => 1.0,
            };
            path.radiance += path.throughput * emitted * weight;
        }
        if path.depth >= self.max_depth {
            return None;
        }
        let bsdf = material.bsdf(&hit.texture_query(), wo, hit.geometry.shading_normal, geometric);
        if bsdf.has_diffuse() {
            path.radiance += path.throughput * sample_lights(scene, hit, &bsdf, wo, Weighting::Mis, context);
        }
        let u_lobe = context.sampler.next_f32();
        let u = Vec2::new(context.sampler.next_f32(), context.sampler.next_f32());
        let sample = bsdf.sample(wo, u_lobe, u)?;
        path.throughput *= sample.weight;
        path.eta_scale *= sample.eta_squared;
        path.previous = Some(Scatter {
            point: hit.geometry.point,
            shading_normal: hit.geometry.shading_normal,
            pdf: sample.pdf,
            delta: sample.delta,
        });
        path.depth += 1;
        if path.depth >= self.rr_depth && !russian_roulette(&mut path.throughput, path.eta_scale, context) {
            return None;
        }
        if path.throughput == Rgb::ZERO {
            return None;
        }
        Some(hit.spawn_ray(sample.wi))
    }
}

/// Russian roulette (Mitsuba's rule): the path survives with probability
/// min(max throughput · η², 0.95), and a survivor's throughput is divided by that probability,
/// which keeps the estimate unbiased. Returns whether the path goes on.
pub(super) fn russian_roulette(throughput: &mut Rgb, eta_scale: f32, context: &mut SampleContext) -> bool {
    let survival = (throughput.max_element() * eta_scale).min(0.95);
    if survival <= 0.0 || context.sampler.next_f32() >= survival {
        return false;
    }
    *throughput /= survival;
    true
}

/// How next-event estimation weighs its sample of a light that BSDF sampling can also find
/// (an area light, the environment; a delta light counts in full).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Weighting {
    /// Against BSDF sampling by the power heuristic (the caller counts BSDF-sampled emission
    /// with the matching weight).
    Mis,
    /// In full: the caller never counts emission found by sampling the BSDF's non-delta
    /// lobes (photon mapping, SPPM).
    LightOnly,
}

/// Next-event estimation at a hit: one light chosen by power, one sample of it (a point on an
/// area light, a direction toward the environment, or a delta light, which only light sampling
/// can find), its shadow ray, and the BSDF there.
pub(super) fn sample_lights(
    scene: &Scene,
    hit: &SurfaceHit,
    bsdf: &Bsdf,
    wo: Vec3,
    weighting: Weighting,
    context: &mut SampleContext,
) -> Rgb {
    let p = hit.geometry.point;
    let u_select = context.sampler.next_f32();
    let u = Vec2::new(context.sampler.next_f32(), context.sampler.next_f32());
    let receiver = Some(hit.geometry.shading_normal);
    let Some(light) = scene.lights().sample_li(p, receiver, u_select, u) else { return Rgb::ZERO };
    let f = bsdf.eval(wo, light.direction);
    let carries_light = light.radiance != Rgb::ZERO && f != Rgb::ZERO && light.pdf > 0.0;
    if !carries_light {
        return Rgb::ZERO;
    }
    context.rays.shadow += 1;
    if scene.occluded(&hit.spawn_shadow_ray(&light)) {
        return Rgb::ZERO;
    }
    let weight = match weighting {
        Weighting::Mis if !light.delta => power_heuristic(light.pdf, bsdf.pdf(wo, light.direction)),
        _ => 1.0,
    };
    f * light.radiance * (weight / light.pdf)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_heuristic_by_hand() {
        assert_eq!(power_heuristic(1.0, 0.0), 1.0);
        assert_eq!(power_heuristic(0.0, 1.0), 0.0);
        assert!((power_heuristic(1.0, 2.0) - 0.2).abs() < 1e-6);
        assert!((power_heuristic(3.0, 1.0) + power_heuristic(1.0, 3.0) - 1.0).abs() < 1e-6);
    }
}
