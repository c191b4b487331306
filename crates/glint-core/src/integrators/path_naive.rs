//! The course's Monte Carlo path tracing, exactly (`--integrator path-naive`): from the eye,
//! at each hit the kind of scattering (diffuse, mirror, refraction) is chosen by roulette in
//! proportion to the material's weights, diffuse directions are sampled cosine-weighted, light
//! is found only when a path happens to hit an emitter, and paths end by Russian roulette.
//! No light sampling: point lights are never found. Slower to converge than `path`, to the
//! same image (tests check it).

use glam::Vec2;

use super::estimators::roulette;
use super::path_record::{PathEnd, PathRecorder, TracesPaths};
use super::vertex::trace_seeing_light;
use super::SampleContext;
use crate::geometry::Ray;
use crate::scene::Scene;
use crate::Rgb;

pub struct NaivePathTracer {
    pub max_depth: u32,
    pub rr_depth: u32,
}

impl TracesPaths for NaivePathTracer {
    fn trace(
        &self,
        scene: &Scene,
        camera_ray: &Ray,
        context: &mut SampleContext,
        recorder: &mut impl PathRecorder,
    ) -> Rgb {
        let mut radiance = Rgb::ZERO;
        let mut throughput = Rgb::ONE;
        let mut eta_scale = 1.0f32;
        let mut ray = *camera_ray;
        let mut depth = 0u32;
        loop {
            if depth == 0 {
                context.rays.camera += 1;
            } else {
                context.rays.reflection += 1;
            }
            // Light is found only where the path meets it: the environment, or an emitter.
            let Some(vertex) = trace_seeing_light(scene, &ray, depth, throughput, &mut radiance, recorder) else {
                break;
            };
            if depth >= self.max_depth {
                recorder.end(PathEnd::Depth);
                break;
            }
            let bsdf = vertex.bsdf();
            let u_lobe = context.sampler.next_f32();
            let u = Vec2::new(context.sampler.next_f32(), context.sampler.next_f32());
            let Some(sample) = bsdf.sample(vertex.wo, u_lobe, u) else {
                recorder.end(PathEnd::Absorbed);
                break;
            };
            throughput *= sample.weight;
            recorder.scatter(&sample, throughput);
            eta_scale *= sample.eta_squared;
            depth += 1;
            if depth >= self.rr_depth && !roulette(&mut throughput, eta_scale, context, recorder) {
                recorder.end(PathEnd::Roulette);
                break;
            }
            ray = vertex.hit.spawn_ray(sample.wi);
        }
        radiance
    }
}
