//! Tracing a particle from a light through the scene, for every integrator that starts at the
//! lights (light tracing, photon mapping, SPPM). The particle carries flux; at each surface it
//! reaches, the caller sees it (to connect it to the camera or store a photon), then the BSDF
//! scatters it. Russian roulette keeps its weight nearly constant (Jensen: absorb, or go on
//! with the power scaled by the BSDF's weight over the survival probability).
//!
//! Shading normals make the BSDF non-symmetric for particles (importance transport): the
//! weight is corrected by |wo·n_s||wi·n_g| / (|wo·n_g||wi·n_s|) (Veach 1997, §5.3).

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::path_record::{ParticleRecorder, PathEnd};
use super::vertex::Vertex;
use super::RayCounts;
use crate::geometry::Ray;
use crate::lights::Particle;
use crate::materials::Bsdf;
use crate::sampling::Rng;
use crate::scene::{Scene, SurfaceHit};
use crate::Rgb;

/// A particle at a surface whose BSDF has a non-delta part (where a photon is stored or a
/// camera connection made).
pub(super) struct ParticleVertex<'a> {
    pub hit: SurfaceHit,
    pub bsdf: &'a Bsdf<'a>,
    /// Unit direction toward where the particle came from.
    pub wo: Vec3,
    /// Flux carried to this surface.
    pub weight: Rgb,
    /// Scattering events before this surface (0: straight from the light).
    pub bounces: u32,
    /// Whether every scattering event before this surface was specular (mirror, refraction):
    /// with `bounces > 0`, a caustic path L S+ D.
    pub specular_chain: bool,
}

/// Particles per batch of photon shooting (the unit of parallel work; batch b draws from its
/// own random stream, so the photons do not depend on the thread count).
pub(super) const BATCH: u64 = 1024;

/// Shoots the particles of `batches` of random stream `stream`: batch b draws its
/// `BATCH` particles from its own generator, each emitted by a light chosen by power (the
/// lights checked as particle sources by the caller) and handed to `trace` with that
/// generator, to append what it keeps. Returns what was kept, in batch order, and the rays
/// traced.
pub(super) fn shoot_batches<T: Send>(
    scene: &Scene,
    stream: u64,
    batches: std::ops::Range<u64>,
    trace: impl Fn(&Particle, &mut Rng, &mut RayCounts, &mut Vec<T>) + Sync,
) -> (Vec<T>, RayCounts) {
    let per_batch: Vec<(Vec<T>, RayCounts)> = batches
        .into_par_iter()
        .map(|batch| {
            let mut rng = Rng::for_sample(stream, batch, 0);
            let (mut kept, mut rays) = (Vec::new(), RayCounts::default());
            for _ in 0..BATCH {
                let u_select = rng.next_f32();
                let u_point = Vec2::new(rng.next_f32(), rng.next_f32());
                let u_direction = Vec2::new(rng.next_f32(), rng.next_f32());
                if let Some(particle) = scene.lights().sample_le(u_select, u_point, u_direction) {
                    trace(&particle, &mut rng, &mut rays, &mut kept);
                }
            }
            (kept, rays)
        })
        .collect();
    let (mut kept, mut rays) = (Vec::new(), RayCounts::default());
    for (k, r) in per_batch {
        kept.extend(k);
        rays.add(&r);
    }
    (kept, rays)
}

/// Russian roulette on a particle whose flux `weight` a scattering scales by `scale` (Jensen:
/// absorb, or go on with the power scaled by the BSDF's weight over the survival
/// probability): it survives with the largest channel's scale, capped, so that a lossless
/// mirror box or medium ends. Returns the survival probability and whether it survived.
pub(super) fn particle_roulette(weight: &mut Rgb, scale: Rgb, rng: &mut Rng) -> (f32, bool) {
    let survival = scale.max_element().min(0.95);
    let survived = !(survival <= 0.0 || rng.next_f32() >= survival);
    if survived {
        *weight *= scale / survival;
    }
    (survival, survived)
}

/// The shading-normal correction for particles going from `wo` to `wi` at `hit`.
pub(super) fn shading_correction(hit: &SurfaceHit, wo: Vec3, wi: Vec3) -> f32 {
    let (ns, ng) = (hit.geometry.shading_normal, hit.geometry.geometric_normal);
    let denominator = wo.dot(ng).abs() * wi.dot(ns).abs();
    if denominator <= 0.0 {
        return 0.0;
    }
    wo.dot(ns).abs() * wi.dot(ng).abs() / denominator
}

/// Traces `particle` for at most `max_depth` scattering events in all (the last vertex seen
/// has `bounces = max_depth − 1`, so a connection from it makes a path of `max_depth`
/// scattering events), calling `visit` at every surface with a non-delta part and telling
/// `recorder` what happens (`()` for nothing).
pub(super) fn trace_particle<R: ParticleRecorder>(
    scene: &Scene,
    particle: &Particle,
    max_depth: u32,
    rng: &mut Rng,
    rays: &mut RayCounts,
    recorder: &mut R,
    mut visit: impl FnMut(&ParticleVertex, &mut Rng, &mut RayCounts, &mut R),
) {
    let mut ray: Ray = particle.ray;
    let mut weight = particle.weight;
    let mut bounces = 0u32;
    let mut specular_chain = true;
    while bounces < max_depth {
        rays.light += 1;
        let Some(vertex) = Vertex::trace(scene, &ray) else {
            recorder.end(PathEnd::Escaped);
            return;
        };
        let bsdf = vertex.bsdf();
        let Vertex { hit, wo, .. } = vertex;
        recorder.surface(&hit, weight, bounces);
        if bsdf.has_diffuse() {
            let vertex = ParticleVertex { hit, bsdf: &bsdf, wo, weight, bounces, specular_chain };
            visit(&vertex, rng, rays, recorder);
        }
        if bounces + 1 >= max_depth {
            recorder.end(PathEnd::Depth);
            return;
        }
        let u_lobe = rng.next_f32();
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        let Some(sample) = bsdf.sample(wo, u_lobe, u) else {
            recorder.end(PathEnd::Absorbed);
            return;
        };
        let scale = sample.weight * shading_correction(&hit, wo, sample.wi);
        let (survival, survived) = particle_roulette(&mut weight, scale, rng);
        recorder.roulette(survival, survived);
        if !survived {
            recorder.end(PathEnd::Roulette);
            return;
        }
        specular_chain &= sample.delta;
        bounces += 1;
        ray = hit.spawn_ray(sample.wi);
    }
}
