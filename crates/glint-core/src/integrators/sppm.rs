//! Stochastic progressive photon mapping (`--integrator sppm`; Hachisuka & Jensen 2009, as
//! pbrt-v3 has it). Consistent: every pass shrinks each pixel's search radius, so the bias of
//! density estimation vanishes as passes accumulate, and it renders caustics that path tracing
//! cannot (from point lights) or finds slowly (from small lights).
//!
//! Each pass:
//! 1. **camera pass**: a camera sample per pixel follows mirrors and glass to the first surface
//!    with a non-delta part, its *visible point*; on the way, emission hit and light-sampled
//!    direct light at each such surface are added to the pixel's direct estimate; from
//!    `rr_depth` bounces on, Russian roulette (survival at most 0.95) ends chains that would
//!    not end by themselves (a closed mirror box, total internal reflection in nested glass);
//! 2. **photon pass**: as many photons as the image has pixels (or `photons_per_pass`) are
//!    traced; those landing after at least one bounce (direct light is step 1's) are stored in
//!    a kd-tree;
//! 3. **update**: each visible point gathers the photons within its pixel's radius r; with M
//!    found, N ← N + αM, r ← r·√(N_new / (N + M)), τ ← (τ + β·Σ f·Φ)·(r_new / r)², α = 2/3.
//!
//! A pixel's value is direct / passes + τ / (photons emitted · π r²). The first radius is
//! `sppm_radius`, or three pixel footprints at the visible point's distance.
//!
//! Every step is parallel and deterministic (per-pixel and per-batch random streams, gathers
//! in kd-tree order), so the image does not depend on the thread count. The per-pixel state
//! (radius, photon count, flux, direct sum) goes into checkpoints with the film, so a resumed
//! render equals an uninterrupted one.

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::estimators::{add_next_event, roulette, surface_next_event, Weighting};
use super::particle::BATCH;
use super::passes::{camera_samples, par_tiles, pixel_sample, Pass, PassRenderer};
use super::path_record::{PathEnd, PathLog, PathRecorder};
use super::photon_mapping::PhotonShooter;
use super::vertex::trace_seeing_light;
use super::{RayCounts, SampleContext};
use crate::film::Film;
use crate::geometry::Ray;
use crate::materials::Bsdf;
use crate::photons::PhotonMap;
use crate::scene::Scene;
use crate::RenderError;
use crate::Rgb;

/// The fraction of new photons kept each pass.
const ALPHA: f32 = 2.0 / 3.0;
const PHOTON_STREAM: u64 = 0x5350_504D;

/// A pixel's camera sample: its index, the direct light found, and its visible point.
type CameraSample<'a> = (u32, Rgb, Option<VisiblePoint<'a>>);

struct VisiblePoint<'a> {
    point: Vec3,
    /// The geometric normal on the side of `wo`.
    normal: Vec3,
    wo: Vec3,
    bsdf: Bsdf<'a>,
    /// Camera throughput to the point, over the probability of stopping there.
    weight: Rgb,
    /// Path length from the camera (for the first radius).
    distance: f32,
}

/// Per-pixel progressive state.
#[derive(Clone, Copy, Debug, Default)]
struct PixelState {
    radius: f32,
    photons: f32,
    tau: Rgb,
    direct: Rgb,
}

pub struct Sppm {
    pub max_depth: u32,
    /// Russian roulette on the camera path's delta bounces from this many on.
    pub rr_depth: u32,
    /// First radius; 0: three pixel footprints at the visible point.
    pub initial_radius: f32,
    /// Photons per pass; 0: the pixel count.
    pub photons_per_pass: u32,
    pixels: Vec<PixelState>,
    passes: u32,
    emitted: u64,
}

impl Sppm {
    pub fn new(
        scene: &Scene,
        max_depth: u32,
        rr_depth: u32,
        initial_radius: f32,
        photons_per_pass: u32,
    ) -> Result<Self, RenderError> {
        scene.lights().check_particles()?;
        let n = scene.camera().width as usize * scene.camera().height as usize;
        Ok(Self {
            max_depth,
            rr_depth,
            initial_radius,
            photons_per_pass,
            pixels: vec![PixelState::default(); n],
            passes: 0,
            emitted: 0,
        })
    }

    /// A pixel's camera path from `ray` (its pass's camera sample, drawn as every camera
    /// integrator's is): the direct light found on the way, and the visible point.
    fn camera_path<'s>(
        &self,
        scene: &'s Scene,
        mut ray: Ray,
        context: &mut SampleContext,
        recorder: &mut impl PathRecorder,
    ) -> (Rgb, Option<VisiblePoint<'s>>) {
        let mut direct = Rgb::ZERO;
        let mut throughput = Rgb::ONE;
        let mut eta_scale = 1.0;
        let mut distance = 0.0;
        let mut visible = None;
        for depth in 0..=self.max_depth {
            context.rays.camera += 1;
            let Some(vertex) = trace_seeing_light(scene, &ray, depth, throughput, &mut direct, recorder) else { break };
            let (hit, wo) = (&vertex.hit, vertex.wo);
            distance += hit.t * ray.direction.length();
            if depth == self.max_depth {
                recorder.end(PathEnd::Depth);
                break;
            }
            let bsdf = vertex.bsdf();
            if bsdf.has_diffuse() {
                let event = surface_next_event(scene, hit, &bsdf, wo, Weighting::LightOnly, context);
                add_next_event(event, throughput, &mut direct, recorder);
            }
            let p = bsdf.non_delta_probability();
            if context.sampler.next_f32() < p {
                // Photons give the indirect part (paths of two or more scattering events).
                if depth + 1 < self.max_depth {
                    let point = hit.geometry.point;
                    let normal = hit.geometric_normal_toward(wo);
                    visible = Some(VisiblePoint { point, normal, wo, bsdf, weight: throughput / p, distance });
                }
                recorder.end(PathEnd::Absorbed);
                break;
            }
            let u_lobe = context.sampler.next_f32();
            let u = Vec2::new(context.sampler.next_f32(), context.sampler.next_f32());
            let Some(sample) = bsdf.sample_delta(wo, u_lobe, u) else {
                recorder.end(PathEnd::Absorbed);
                break;
            };
            throughput *= sample.weight / (1.0 - p);
            recorder.scatter(&sample, throughput);
            eta_scale *= sample.eta_squared;
            if depth + 1 >= self.rr_depth && !roulette(&mut throughput, eta_scale, context, recorder) {
                recorder.end(PathEnd::Roulette);
                break;
            }
            if throughput == Rgb::ZERO {
                recorder.end(PathEnd::Absorbed);
                break;
            }
            ray = hit.spawn_ray(sample.wi);
        }
        (if direct.is_finite() { direct } else { Rgb::ZERO }, visible)
    }
}

impl Sppm {
    /// A pass's photons: those after at least one bounce (direct light is the camera path's),
    /// in a map.
    fn shoot(&self, scene: &Scene, pass: &Pass) -> (PhotonMap, RayCounts) {
        let wanted = if self.photons_per_pass > 0 { self.photons_per_pass as u64 } else { self.pixels.len() as u64 };
        let batches = wanted.div_ceil(BATCH);
        let first = pass.index as u64 * batches;
        let shooter = PhotonShooter { scene, max_depth: self.max_depth, seed: pass.seed, stop: None };
        let (photons, emitted, rays) = shooter.shoot(PHOTON_STREAM, first..first + batches, &|v| v.bounces > 0);
        (PhotonMap::build(photons, emitted), rays)
    }

    /// Pixel (x, y) after a render's first pass (`pass`, with index 0), step by step: its camera
    /// path through delta bounces to its visible point (the direct light found on the way),
    /// the pass's photons gathered there, and the pixel's value, computed as the render
    /// computes it (bit for bit what `render --spp 1` gives). `self` must not have rendered.
    pub fn explain_pixel(&self, scene: &Scene, pass: &Pass, (x, y): (u32, u32)) -> SppmExplanation {
        let (ray, mut context) = pixel_sample(scene, pass, x, y);
        let mut path = PathLog::default();
        let (direct, visible) = self.camera_path(scene, ray, &mut context, &mut path);
        let (map, _) = self.shoot(scene, pass);
        let mut state = PixelState::default();
        let gathered = visible.map(|vp| {
            let (found, flux, radius) = gather(scene, &map, &vp, &mut state, self.initial_radius);
            SppmGather {
                point: vp.point,
                weight: vp.weight,
                radius,
                found,
                flux,
                new_radius: state.radius,
                tau: state.tau,
            }
        });
        state.direct += direct;
        let value = estimate(&state, 1, map.emitted());
        let (photons_stored, photons_emitted) = (map.len(), map.emitted());
        SppmExplanation { path, direct, gather: gathered, photons_stored, photons_emitted, value }
    }
}

/// A visible point's gather from a pass's `map` within its pixel's radius (the first one set
/// here), and the pixel's progressive update: the photons found, Σ f·Φ, and the radius
/// searched.
fn gather(
    scene: &Scene,
    map: &PhotonMap,
    vp: &VisiblePoint,
    state: &mut PixelState,
    initial_radius: f32,
) -> (u32, Rgb, f32) {
    if state.radius == 0.0 {
        state.radius =
            if initial_radius > 0.0 { initial_radius } else { 3.0 * scene.camera().pixel_footprint(vp.distance) };
    }
    let radius = state.radius;
    let mut flux = Rgb::ZERO;
    let mut found = 0u32;
    map.for_each_within(vp.point, radius, |photon, _| {
        if !photon.can_reach(vp.point, vp.normal) {
            return;
        }
        let f = vp.bsdf.eval_without_cosine(vp.wo, photon.incoming());
        if f != Rgb::ZERO {
            flux += f * photon.power;
            found += 1;
        }
    });
    if found > 0 {
        let m = found as f32;
        let n_new = state.photons + ALPHA * m;
        let ratio = n_new / (state.photons + m);
        state.tau = (state.tau + vp.weight * flux) * ratio;
        state.radius *= ratio.sqrt();
        state.photons = n_new;
    }
    (found, flux, radius)
}

/// A pixel's value after `passes` passes that emitted `emitted` photons: direct / passes +
/// τ / (emitted · π r²).
fn estimate(state: &PixelState, passes: u32, emitted: u64) -> Rgb {
    let (passes, emitted) = (passes as f32, emitted as f32);
    let mut value = state.direct / passes;
    if state.radius > 0.0 {
        value += state.tau / (emitted * std::f32::consts::PI * state.radius * state.radius);
    }
    value
}

/// SPPM's account of one pixel after one pass (`Sppm::explain_pixel`).
#[derive(Clone, Debug)]
pub struct SppmExplanation {
    /// The camera path to the visible point.
    pub path: PathLog,
    /// Emission and light-sampled direct light found on it.
    pub direct: Rgb,
    /// The gather at the visible point, if the path found one.
    pub gather: Option<SppmGather>,
    pub photons_stored: usize,
    pub photons_emitted: u64,
    /// direct + τ / (emitted · π r²), the pixel's value.
    pub value: Rgb,
}

/// The photons gathered at a visible point in the first pass.
#[derive(Clone, Copy, Debug)]
pub struct SppmGather {
    pub point: Vec3,
    /// The camera path's throughput to the point, over the probability of stopping there.
    pub weight: Rgb,
    /// The search radius, and the photons found within it with Σ f·Φ.
    pub radius: f32,
    pub found: u32,
    pub flux: Rgb,
    /// After the update: the radius shrunk by √α (if photons were found) and τ = α·weight·Σ f·Φ.
    pub new_radius: f32,
    pub tau: Rgb,
}

impl PassRenderer for Sppm {
    fn render_pass(&mut self, scene: &Scene, pass: &Pass, film: &mut Film, on_tile: &(dyn Fn() + Sync)) -> RayCounts {
        let (width, height) = (scene.camera().width, scene.camera().height);
        let per_tile: Vec<(Vec<CameraSample>, RayCounts)> = par_tiles(width, height)
            .map(|(x0, y0, x1, y1)| {
                let mut rays = RayCounts::default();
                let (_, camera_rays, mut contexts) = camera_samples(scene, pass, (x0, y0, x1, y1));
                let pixels = (y0..y1).flat_map(|y| (x0..x1).map(move |x| y * width + x));
                let mut out = Vec::with_capacity(camera_rays.len());
                for ((ray, context), pixel) in camera_rays.into_iter().zip(&mut contexts).zip(pixels) {
                    let (direct, visible) = self.camera_path(scene, ray, context, &mut ());
                    rays.add(&context.rays);
                    out.push((pixel, direct, visible));
                }
                on_tile();
                (out, rays)
            })
            .collect();
        let mut rays = RayCounts::default();
        let mut visible: Vec<Option<VisiblePoint>> = (0..self.pixels.len()).map(|_| None).collect();
        for (out, tile_rays) in per_tile {
            rays.add(&tile_rays);
            for (i, direct, vp) in out {
                self.pixels[i as usize].direct += direct;
                visible[i as usize] = vp;
            }
        }

        let (map, photon_rays) = self.shoot(scene, pass);
        rays.add(&photon_rays);
        self.emitted += map.emitted();
        self.passes += 1;

        let initial_radius = self.initial_radius;
        self.pixels.par_iter_mut().zip(visible.par_iter()).for_each(|(state, vp)| {
            if let Some(vp) = vp {
                gather(scene, &map, vp, state, initial_radius);
            }
        });

        // The film holds the current estimate, one sample of weight 1 per pixel.
        *film = Film::new(width, height);
        for (i, state) in self.pixels.iter().enumerate() {
            film.add_samples(i as u32 % width, i as u32 / width, estimate(state, self.passes, self.emitted), 1.0);
        }
        rays
    }

    fn state(&self) -> Vec<u8> {
        let mut bytes = Vec::with_capacity(16 + self.pixels.len() * 32);
        bytes.extend_from_slice(&self.passes.to_le_bytes());
        bytes.extend_from_slice(&self.emitted.to_le_bytes());
        bytes.extend_from_slice(&(self.pixels.len() as u32).to_le_bytes());
        for p in &self.pixels {
            for v in [p.radius, p.photons, p.tau.x, p.tau.y, p.tau.z, p.direct.x, p.direct.y, p.direct.z] {
                bytes.extend_from_slice(&v.to_le_bytes());
            }
        }
        bytes
    }

    fn restore(&mut self, state: &[u8]) -> Result<(), RenderError> {
        if state.len() != 16 + self.pixels.len() * 32 {
            return Err(RenderError::StateMismatch);
        }
        let word = |i: usize| u32::from_le_bytes([state[i], state[i + 1], state[i + 2], state[i + 3]]);
        if word(12) as usize != self.pixels.len() {
            return Err(RenderError::StateMismatch);
        }
        let (passes, emitted) = (word(0), u64::from(word(4)) | u64::from(word(8)) << 32);
        // A pass emits at least one photon batch; none before the first pass.
        if (passes == 0) != (emitted == 0) {
            return Err(RenderError::StateMismatch);
        }
        let float = |i: usize| f32::from_bits(word(i));
        let mut pixels = Vec::with_capacity(self.pixels.len());
        for k in 0..self.pixels.len() {
            let o = 16 + 32 * k;
            let p = PixelState {
                radius: float(o),
                photons: float(o + 4),
                tau: Rgb::new(float(o + 8), float(o + 12), float(o + 16)),
                direct: Rgb::new(float(o + 20), float(o + 24), float(o + 28)),
            };
            // Radii, counts and fluxes are finite and never negative.
            let values = [p.radius, p.photons, p.tau.min_element(), p.direct.min_element()];
            if !(values.iter().all(|v| *v >= 0.0)
                && p.tau.is_finite()
                && p.direct.is_finite()
                && p.radius.is_finite()
                && p.photons.is_finite())
            {
                return Err(RenderError::BadPixelState { pixel: k });
            }
            pixels.push(p);
        }
        self.passes = passes;
        self.emitted = emitted;
        self.pixels = pixels;
        Ok(())
    }
}
