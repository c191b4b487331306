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

use glam::Vec2;

use super::estimators::{add_emission, add_escaped, add_next_event, roulette, surface_next_event, Scatter, Weighting};
use super::path_record::{PathEnd, PathRecorder, TracesPaths};
use super::vertex::Vertex;
use super::{IntegratorSettings, SampleContext};
use crate::geometry::Ray;
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
                add_escaped(scene, ray.direction, path.previous, path.throughput, &mut path.radiance, recorder);
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
        add_emission(scene, hit, vertex.emitted(), path.previous, path.throughput, &mut path.radiance, recorder);
        if path.depth >= self.max_depth {
            recorder.end(PathEnd::Depth);
            return None;
        }
        let bsdf = vertex.bsdf();
        if bsdf.has_diffuse() {
            let event = surface_next_event(scene, hit, &bsdf, wo, Weighting::Mis, context);
            add_next_event(event, path.throughput, &mut path.radiance, recorder);
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
            normal: Some(hit.geometry.shading_normal),
            pdf: sample.pdf,
            delta: sample.delta,
        });
        path.depth += 1;
        if path.depth >= self.rr_depth && !roulette(&mut path.throughput, path.eta_scale, context, recorder) {
            recorder.end(PathEnd::Roulette);
            return None;
        }
        if path.throughput == Rgb::ZERO {
            recorder.end(PathEnd::Absorbed);
            return None;
        }
        Some(hit.spawn_ray(sample.wi))
    }
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
}
