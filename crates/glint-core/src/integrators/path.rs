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
use wide::{f32x8, CmpEq};

use super::path_record::{LightSampleRecord, PathEnd, PathRecorder, TracesPaths};
use super::vertex::Vertex;
use super::{CameraExplanation, Integrator, IntegratorSettings, SampleContext};
use crate::geometry::Ray;
use crate::materials::Bsdf;
use crate::sampling::Sampler;
use crate::scene::{Scene, SurfaceHit};
use crate::Rgb;

/// The path tracer, one path at a time. `WavefrontPathTracer` runs a tile's paths together
/// with the same estimator (`--integrator path` unless `--no-wavefront`).
#[derive(Clone, Copy, Debug)]
pub struct PathTracer {
    pub max_depth: u32,
    pub rr_depth: u32,
}

impl PathTracer {
    pub fn new(settings: &IntegratorSettings) -> Self {
        Self { max_depth: settings.max_depth, rr_depth: settings.rr_depth }
    }
}

/// The random numbers of one bounce, in the order they are drawn: which light and the point
/// on it (next-event estimation, at surfaces with a non-delta lobe), the BSDF's lobe and
/// direction, and Russian roulette's from `rr_depth` bounces on. The scalar code draws them
/// through these functions; the wavefront's lanes draw the same numbers at these offsets, so
/// the two compute the same image.
pub(super) struct BounceDraws;

impl BounceDraws {
    pub const LIGHT: usize = 0;
    /// Two numbers.
    pub const LIGHT_POINT: usize = 1;
    pub const LOBE: usize = 3;
    /// Two numbers.
    pub const DIRECTION: usize = 4;
    pub const ROULETTE: usize = 6;
    pub const COUNT: usize = 7;

    /// The light's choice and the point on it.
    #[inline]
    pub fn light(sampler: &mut Sampler) -> (f32, Vec2) {
        let u_select = sampler.next_f32();
        (u_select, Vec2::new(sampler.next_f32(), sampler.next_f32()))
    }

    /// The BSDF's lobe and direction.
    #[inline]
    pub fn scatter(sampler: &mut Sampler) -> (f32, Vec2) {
        let u_lobe = sampler.next_f32();
        (u_lobe, Vec2::new(sampler.next_f32(), sampler.next_f32()))
    }

    #[inline]
    pub fn roulette(sampler: &mut Sampler) -> f32 {
        sampler.next_f32()
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

/// The MIS weight of emission at `hit`, reached by a direction sampled at `from` (shading
/// normal `normal`, `None` in a medium) with density `pdf` per solid angle, against next-event
/// estimation's density for the same point: what `path` and `volpath` add emission with.
pub(crate) fn emission_weight(scene: &Scene, from: Vec3, normal: Option<Vec3>, pdf: f32, hit: &SurfaceHit) -> f32 {
    let geometry = &hit.geometry;
    let light_pdf =
        scene.lights().pdf_area(from, normal, hit.object, hit.prim, geometry.point, geometry.geometric_normal);
    power_heuristic(pdf, light_pdf)
}

/// `power_heuristic` in lanes.
#[inline(always)]
pub(crate) fn power_heuristic8(a: f32x8, b: f32x8) -> f32x8 {
    let (a2, b2) = (a * a, b * b);
    let special = (a2 + b2).cmp_eq(f32x8::ZERO) | !a2.is_finite();
    special.blend(a2.is_inf().blend(f32x8::ONE, f32x8::ZERO), a2 / (a2 + b2))
}

impl Integrator for PathTracer {
    fn radiance(&self, scene: &Scene, camera_ray: &Ray, context: &mut SampleContext) -> Rgb {
        self.trace(scene, camera_ray, context, &mut ())
    }

    fn explain(&self, scene: &Scene, camera_ray: &Ray, context: &mut SampleContext) -> Option<CameraExplanation> {
        let (radiance, log) = TracesPaths::explain(self, scene, camera_ray, context);
        Some(CameraExplanation::Path { radiance, log })
    }
}

impl TracesPaths for PathTracer {
    fn trace(
        &self,
        scene: &Scene,
        camera_ray: &Ray,
        context: &mut SampleContext,
        recorder: &mut impl PathRecorder,
    ) -> Rgb {
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
                let seen = match path.previous {
                    Some(from) if !from.delta => scene
                        .lights()
                        .environment_seen(ray.direction)
                        .map(|(radiance, pdf)| (radiance, power_heuristic(from.pdf, pdf))),
                    _ => None,
                };
                let (background, weight) = seen.unwrap_or_else(|| (scene.environment().radiance(ray.direction), 1.0));
                let added = path.throughput * background * weight;
                path.radiance += added;
                recorder.escape(background, weight, added);
                recorder.end(PathEnd::Escaped);
                break;
            };
            match self.bounce_recorded(scene, &ray, &hit, &mut path, context, recorder) {
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
        self.bounce_recorded(scene, ray, hit, path, context, &mut ())
    }

    /// `bounce`, telling `recorder` what happens.
    #[inline(always)]
    fn bounce_recorded(
        &self,
        scene: &Scene,
        ray: &Ray,
        hit: &SurfaceHit,
        path: &mut PathState,
        context: &mut SampleContext,
        recorder: &mut impl PathRecorder,
    ) -> Option<Ray> {
        recorder.vertex(path.depth, hit, path.throughput);
        let vertex = Vertex::at(scene, ray, *hit);
        let wo = vertex.wo;
        let emitted = vertex.emitted();
        if emitted != Rgb::ZERO {
            let weight = match path.previous {
                Some(from) if !from.delta => {
                    emission_weight(scene, from.point, Some(from.shading_normal), from.pdf, hit)
                }
                _ => 1.0,
            };
            let added = path.throughput * emitted * weight;
            path.radiance += added;
            recorder.emission(emitted, weight, added);
        }
        if path.depth >= self.max_depth {
            recorder.end(PathEnd::Depth);
            return None;
        }
        let bsdf = vertex.bsdf();
        if bsdf.has_diffuse() {
            let event = next_event(scene, hit, &bsdf, wo, Weighting::Mis, context);
            let added = path.throughput * event.contribution;
            path.radiance += added;
            if let Some(sample) = event.sample {
                recorder.light_sample(LightSampleRecord { added, ..sample });
            }
        }
        let (u_lobe, u) = BounceDraws::scatter(&mut context.sampler);
        let Some(sample) = bsdf.sample(wo, u_lobe, u) else {
            recorder.end(PathEnd::Absorbed);
            return None;
        };
        path.throughput *= sample.weight;
        recorder.scatter(&sample, path.throughput);
        path.eta_scale *= sample.eta_squared;
        path.previous = Some(Scatter {
            point: hit.geometry.point,
            shading_normal: hit.geometry.shading_normal,
            pdf: sample.pdf,
            delta: sample.delta,
        });
        path.depth += 1;
        if path.depth >= self.rr_depth && !russian_roulette(&mut path.throughput, path.eta_scale, context, recorder) {
            return None;
        }
        if path.throughput == Rgb::ZERO {
            recorder.end(PathEnd::Absorbed);
            return None;
        }
        Some(hit.spawn_ray(sample.wi))
    }
}

/// Russian roulette (Mitsuba's rule): the path survives with probability
/// min(max throughput · η², 0.95), and a survivor's throughput is divided by that probability,
/// which keeps the estimate unbiased. Returns whether the path goes on; `recorder` is told
/// the survival probability and the verdict (and that the path ends there).
pub(super) fn russian_roulette(
    throughput: &mut Rgb,
    eta_scale: f32,
    context: &mut SampleContext,
    recorder: &mut impl PathRecorder,
) -> bool {
    let survival = (throughput.max_element() * eta_scale).min(0.95);
    // Written as the test for ending, so a NaN survival draws and goes on as it always did.
    let survived = !(survival <= 0.0 || BounceDraws::roulette(&mut context.sampler) >= survival);
    recorder.roulette(survival, survived);
    if !survived {
        recorder.end(PathEnd::Roulette);
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
    next_event(scene, hit, bsdf, wo, weighting, context).contribution
}

/// `sample_lights` times the path's `throughput`, its light sample told to `recorder`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(super) fn sample_lights_recorded(
    scene: &Scene,
    hit: &SurfaceHit,
    bsdf: &Bsdf,
    wo: Vec3,
    weighting: Weighting,
    context: &mut SampleContext,
    throughput: Rgb,
    recorder: &mut impl PathRecorder,
) -> Rgb {
    let event = next_event(scene, hit, bsdf, wo, weighting, context);
    let added = throughput * event.contribution;
    if let Some(sample) = event.sample {
        recorder.light_sample(LightSampleRecord { added, ..sample });
    }
    added
}

/// What next-event estimation adds (before the path's throughput), and its light sample where
/// one carried light toward the surface (its `added` left for the caller).
struct NextEvent {
    contribution: Rgb,
    sample: Option<LightSampleRecord>,
}

/// `sample_lights`, with its light sample.
#[inline(always)]
fn next_event(
    scene: &Scene,
    hit: &SurfaceHit,
    bsdf: &Bsdf,
    wo: Vec3,
    weighting: Weighting,
    context: &mut SampleContext,
) -> NextEvent {
    let none = NextEvent { contribution: Rgb::ZERO, sample: None };
    let p = hit.geometry.point;
    let (u_select, u) = BounceDraws::light(&mut context.sampler);
    let receiver = Some(hit.geometry.shading_normal);
    let Some(light) = scene.lights().sample_li(p, receiver, u_select, u) else { return none };
    let f = bsdf.eval(wo, light.direction);
    let carries_light = light.radiance != Rgb::ZERO && f != Rgb::ZERO && light.pdf > 0.0;
    if !carries_light {
        return none;
    }
    context.rays.shadow += 1;
    let record = |mis_weight: f32, occluded: bool| LightSampleRecord::new(&light, mis_weight, occluded, Rgb::ZERO);
    if scene.occluded(&hit.spawn_shadow_ray(&light)) {
        return NextEvent { contribution: Rgb::ZERO, sample: Some(record(0.0, true)) };
    }
    let weight = match weighting {
        Weighting::Mis if !light.delta => power_heuristic(light.pdf, bsdf.pdf(wo, light.direction)),
        _ => 1.0,
    };
    NextEvent { contribution: f * light.radiance * (weight / light.pdf), sample: Some(record(weight, false)) }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The draw functions take the numbers at the offsets the wavefront's lanes read.
    #[test]
    fn bounce_draws_come_in_their_written_order() {
        let fresh = || Sampler::independent(crate::sampling::Rng::new(3, 9));
        let mut plain = fresh();
        let numbers: Vec<f32> = (0..BounceDraws::COUNT).map(|_| plain.next_f32()).collect();
        let mut sampler = fresh();
        let (u_select, u_point) = BounceDraws::light(&mut sampler);
        let (u_lobe, u_direction) = BounceDraws::scatter(&mut sampler);
        let u_roulette = BounceDraws::roulette(&mut sampler);
        assert_eq!(u_select, numbers[BounceDraws::LIGHT]);
        assert_eq!(u_point.to_array(), numbers[BounceDraws::LIGHT_POINT..][..2]);
        assert_eq!(u_lobe, numbers[BounceDraws::LOBE]);
        assert_eq!(u_direction.to_array(), numbers[BounceDraws::DIRECTION..][..2]);
        assert_eq!(u_roulette, numbers[BounceDraws::ROULETTE]);
        assert_eq!(BounceDraws::ROULETTE + 1, BounceDraws::COUNT);
    }

    #[test]
    fn power_heuristic_by_hand() {
        assert_eq!(power_heuristic(1.0, 0.0), 1.0);
        assert_eq!(power_heuristic(0.0, 1.0), 0.0);
        assert!((power_heuristic(1.0, 2.0) - 0.2).abs() < 1e-6);
        assert!((power_heuristic(3.0, 1.0) + power_heuristic(1.0, 3.0) - 1.0).abs() < 1e-6);
    }

    /// The lane version computes the scalar one's bits, special values included (NaN, ±0,
    /// infinities).
    #[test]
    fn power_heuristic8_equals_the_scalar_routine() {
        let specials = [0.0, -0.0, 1.0, 0.5, f32::INFINITY, f32::NAN, 1e-30, 3.0e30, 2.0, -1.0];
        for i in 0..specials.len() {
            for &y in &specials {
                let lanes: [f32; 8] = std::array::from_fn(|k| specials[(i + k) % specials.len()]);
                let heuristic = power_heuristic8(wide::f32x8::from(lanes), wide::f32x8::splat(y)).to_array();
                for k in 0..8 {
                    let expected = power_heuristic(lanes[k], y);
                    assert_eq!(heuristic[k].to_bits(), expected.to_bits(), "heuristic of {}, {y}", lanes[k]);
                }
            }
        }
    }
}
