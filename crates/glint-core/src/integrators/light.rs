//! Light tracing (`--integrator light`): the course's forward ray tracing. Particles leave the
//! lights in proportion to their power; where one reaches a surface with a non-delta BSDF (and
//! where it leaves an area light), a shadow ray connects it to the camera and its contribution
//! is splatted into the pixel it is seen in. Each pass traces as many particles as the image
//! has pixels, so a pass weighs like one sample per pixel of the path tracer.
//!
//! It converges to the same image as `path` wherever the camera sees the scene directly;
//! light reaching the camera only through mirrors or glass (a pinhole cannot be hit by a
//! particle) is missing. Area lights are seen by connecting their particles' origins to the
//! camera; the environment, which no particle can bring to a pinhole, by one camera ray per
//! pixel and pass; point, spot and directional lights are invisible, as in every integrator. Caustics on
//! diffuse surfaces, which the path tracer finds slowly, come out quickly.
//!
//! The estimate for pixel j from a vertex x carrying flux β (per particle, N particles):
//! β · f(x, wo → w_cam) · |cos θ_x| · W_e / N, with W_e the pinhole's importance in x's area
//! measure (see `Camera::project`) times the pixel count. The splats are gathered per tile
//! and added to the film in tile order, so the image does not depend on the thread count.

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::particle::{shading_correction, trace_particle, ParticleVertex};
use super::passes::{par_tiles, tiles, Pass, PassRenderer};
use super::path_record::{ParticleLog, ParticleRecorder};
use super::RayCounts;
use crate::film::Film;
use crate::geometry::{offset_ray_origin, Ray};
use crate::lights::AreaEmission;
use crate::sampling::Rng;
use crate::scene::Scene;
use crate::RenderError;
use crate::Rgb;

pub struct LightTracer {
    pub max_depth: u32,
}

/// A particle's contribution to one pixel.
type Splat = (u32, u32, Rgb);

impl LightTracer {
    pub fn new(scene: &Scene, max_depth: u32) -> Result<Self, RenderError> {
        if scene.camera().samples_lens() {
            return Err(RenderError::ThinLensLightTracing);
        }
        scene.lights().check_particles()?;
        Ok(Self { max_depth })
    }

    /// Traces the particle `rng` draws and collects its splats (unscaled: the caller
    /// multiplies by pixels / particles), telling `recorder` what happens.
    fn trace<R: ParticleRecorder>(
        &self,
        scene: &Scene,
        rng: &mut Rng,
        splats: &mut Vec<Splat>,
        rays: &mut RayCounts,
        recorder: &mut R,
    ) {
        let u_select = rng.next_f32();
        let u_point = Vec2::new(rng.next_f32(), rng.next_f32());
        let u_direction = Vec2::new(rng.next_f32(), rng.next_f32());
        let Some(particle) = scene.lights().sample_le(u_select, u_point, u_direction) else { return };
        recorder.start(particle.ray.origin, particle.weight);
        if let Some(splat @ (x, y, value)) = particle.area.as_ref().and_then(|e| connect_emission(scene, e, rays)) {
            splats.push(splat);
            recorder.splat(None, x, y, value);
        }
        trace_particle(scene, &particle, self.max_depth, rng, rays, recorder, |vertex, _, rays, recorder| {
            if let Some(splat @ (x, y, value)) = connect_vertex(scene, vertex, rays) {
                splats.push(splat);
                recorder.splat(Some(vertex.bounces), x, y, value);
            }
        });
    }

    /// The particles of a render's first pass (`seed`) that land in pixel (x, y), each with its
    /// path and splats, and the pixel's value after the pass: their splats (and the
    /// environment's, where the camera sees it) added in the order the render adds them, so
    /// the value is what `render --spp 1` computes, bit for bit.
    pub fn explain_pixel(&self, scene: &Scene, seed: u64, (x, y): (u32, u32)) -> ParticleExplanation {
        let (width, height) = (scene.camera().width, scene.camera().height);
        let mut explanation = ParticleExplanation::default();
        let mut rays = RayCounts::default();
        let mut sum = Rgb::ZERO;
        let here = |&(sx, sy, value): &Splat| sx.min(width - 1) == x && sy.min(height - 1) == y && value.is_finite();
        for (x0, y0, x1, y1) in tiles(width, height) {
            for (px, py) in (y0..y1).flat_map(|py| (x0..x1).map(move |px| (px, py))) {
                let index = py as u64 * width as u64 + px as u64;
                let mut rng = Rng::for_sample(seed ^ PARTICLE_STREAM, index, 0);
                let (mut splats, mut log) = (Vec::new(), ParticleLog::default());
                self.trace(scene, &mut rng, &mut splats, &mut rays, &mut log);
                explanation.traced += 1;
                let mut landed = false;
                for splat in splats.iter().filter(|s| here(s)) {
                    sum += splat.2;
                    landed = true;
                }
                if landed {
                    explanation.particles.push((index, log));
                }
                if scene.lights().has_environment() && (px, py) == (x, y) {
                    let mut rng = Rng::for_sample(seed ^ SKY_STREAM, index, 0);
                    let mut sky = Vec::new();
                    see_environment(scene, (px, py), &mut rng, &mut sky, &mut rays);
                    if let Some(splat) = sky.first().filter(|s| here(s)) {
                        sum += splat.2;
                        explanation.environment = Some(splat.2);
                    }
                }
            }
        }
        // The pass adds a weight of 1 to every pixel.
        explanation.value = sum / 1.0;
        explanation
    }
}

/// Light tracing's account of one pixel after one pass (`LightTracer::explain_pixel`).
#[derive(Clone, Debug, Default)]
pub struct ParticleExplanation {
    /// The particles that land in the pixel: their index in the pass, and their paths.
    pub particles: Vec<(u64, ParticleLog)>,
    /// The environment the pixel's camera ray saw, if it saw it.
    pub environment: Option<Rgb>,
    /// Particles traced in the pass (one per pixel).
    pub traced: u64,
    /// The pixel's value: the sum of its splats.
    pub value: Rgb,
}

/// The light itself seen by the camera: L_e · |cos θ_light| · W_e / pdf_area.
fn connect_emission(scene: &Scene, e: &AreaEmission, rays: &mut RayCounts) -> Option<Splat> {
    let projection = scene.camera().project(e.point)?;
    let to_camera = projection.to_camera;
    let cos = to_camera.dot(e.normal);
    // `normal` is the side the particle left from; a one-sided light shows only that side.
    let cos = if e.two_sided { cos.abs() } else { cos };
    if cos <= 0.0 {
        return None;
    }
    let side = if e.normal.dot(to_camera) >= 0.0 { e.normal } else { -e.normal };
    let origin = offset_ray_origin(e.point, e.error, side, to_camera);
    rays.shadow += 1;
    if scene.occluded(&Ray::with_range(origin, projection.camera_point - origin, 0.0, 1.0)) {
        return None;
    }
    let value = e.radiance * (cos * projection.importance / e.pdf_area);
    Some((projection.film_x as u32, projection.film_y as u32, value))
}

/// A particle at a surface seen by the camera: β · f · |cos| · W_e, with the shading-normal
/// correction of importance transport.
fn connect_vertex(scene: &Scene, v: &ParticleVertex, rays: &mut RayCounts) -> Option<Splat> {
    let point = v.hit.geometry.point;
    let projection = scene.camera().project(point)?;
    let to_camera: Vec3 = projection.to_camera;
    let f = v.bsdf.eval(v.wo, to_camera);
    if f == Rgb::ZERO {
        return None;
    }
    let correction = shading_correction(&v.hit, v.wo, to_camera);
    if correction == 0.0 {
        return None;
    }
    rays.shadow += 1;
    if scene.occluded(&v.hit.spawn_ray_to(projection.camera_point)) {
        return None;
    }
    let value = v.weight * f * (correction * projection.importance);
    Some((projection.film_x as u32, projection.film_y as u32, value))
}

/// Streams of particle random numbers, apart from the camera samples' (seed, pixel, sample).
const PARTICLE_STREAM: u64 = 0x4C49_4748_5400_0000;
/// Streams of the camera rays that look for the directly visible environment.
const SKY_STREAM: u64 = 0x534B_5900_0000_0000;

/// The environment where the camera sees it directly: no particle can reach a pinhole from
/// infinitely far, so one camera ray per pixel and pass looks for it instead. The splat is the
/// radiance itself: a pass adds one such ray to each pixel, as it adds one sample's worth of
/// particles.
fn see_environment(scene: &Scene, (x, y): (u32, u32), rng: &mut Rng, splats: &mut Vec<Splat>, rays: &mut RayCounts) {
    let ray = scene.camera().generate_ray(x as f32 + rng.next_f32(), y as f32 + rng.next_f32());
    rays.camera += 1;
    if scene.intersect(&ray).is_none() {
        splats.push((x, y, scene.environment().radiance(ray.direction)));
    }
}

impl PassRenderer for LightTracer {
    fn render_pass(&mut self, scene: &Scene, pass: &Pass, film: &mut Film, on_tile: &(dyn Fn() + Sync)) -> RayCounts {
        let (width, height) = (scene.camera().width, scene.camera().height);
        // One particle per pixel of each tile, so the work is cut as the camera passes cut it.
        let per_tile: Vec<(Vec<Splat>, RayCounts)> = par_tiles(width, height)
            .map(|(x0, y0, x1, y1)| {
                let mut splats = Vec::new();
                let mut rays = RayCounts::default();
                for y in y0..y1 {
                    for x in x0..x1 {
                        let index = y as u64 * width as u64 + x as u64;
                        let mut rng = Rng::for_sample(pass.seed ^ PARTICLE_STREAM, index, pass.index as u64);
                        self.trace(scene, &mut rng, &mut splats, &mut rays, &mut ());
                        if scene.lights().has_environment() {
                            let mut rng = Rng::for_sample(pass.seed ^ SKY_STREAM, index, pass.index as u64);
                            see_environment(scene, (x, y), &mut rng, &mut splats, &mut rays);
                        }
                    }
                }
                on_tile();
                (splats, rays)
            })
            .collect();
        let mut rays = RayCounts::default();
        // N particles = pixel count: the splat's factor pixels / N is 1.
        for (splats, tile_rays) in per_tile {
            for (x, y, value) in splats {
                if value.is_finite() {
                    film.add_splat(x.min(width - 1), y.min(height - 1), value);
                }
            }
            rays.add(&tile_rays);
        }
        film.add_weight_everywhere(1.0);
        rays
    }
}
