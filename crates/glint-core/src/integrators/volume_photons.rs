//! Volumetric photon mapping (`--integrator volphoton`; Jensen & Christensen 1998, with point
//! estimates): the light that reaches a point of a medium after scattering at least once on
//! its way from the lights, gathered from photons stored where they collide in media.
//!
//! First pass: photons leave the lights in proportion to their power and are traced through
//! media (free flights, the phase function at real collisions) and surfaces (the BSDFs, null
//! surfaces and thin sheets crossed as `volpath` crosses them), with Russian roulette. At
//! every real collision in a medium after its first scattering event, a photon is stored in
//! that medium's map with the power it brings there over the collision's density (the
//! collision estimator of fluence): a map's density of stored power is the fluence of light
//! scattered at least once, whatever the medium's density.
//!
//! Second pass (`volpath` with this map): a camera path that first scatters in a medium at x
//! stops there. What x scatters toward the camera is σ_s ∫ p(ω, ω') L(x, ω') dω', taken in two
//! parts: the light arriving straight from the lights by next-event estimation, and the rest,
//! Σ p(ω, ω_p) Φ_p / V over the medium's k nearest photons in the sphere V that holds them. The
//! estimate is a point estimate at a collision drawn by the same free flights as `volpath`'s
//! (not a beam estimate along the ray). Surfaces are path traced as in `volpath`.
//!
//! Photons come from lights only: an emitting medium's own light is seen by the camera, but
//! not scattered (the renderer refuses such scenes).

use std::sync::atomic::{AtomicBool, Ordering};

use glam::{Vec2, Vec3};

use super::particle::{particle_roulette, shading_correction, shoot_batches, BATCH};
use super::vertex::Vertex;
use super::volpath::{medium_beyond, MAX_CROSSINGS};
use super::RayCounts;
use crate::geometry::Ray;
use crate::lights::Particle;
use crate::media::{Flight, PhaseFunction};
use crate::photons::{NearestPhotons, Photon, PhotonMap};
use crate::sampling::Rng;
use crate::scene::Scene;
use crate::{RenderError, Rgb};

/// The map's random stream, apart from the camera's and the other photon maps'.
const STREAM: u64 = 0x564F_4C50;
/// Particles emitted at most per photon wanted (a scene whose light rarely reaches a medium).
const EFFORT: u64 = 32;

/// The volume photon maps (one per medium, so that an estimate never gathers another
/// medium's photons) and how they are searched.
pub struct VolumePhotons {
    maps: Vec<PhotonMap>,
    nearest: usize,
    max_radius: f32,
    /// Rays traced to build the maps.
    pub photon_rays: RayCounts,
}

thread_local! {
    static NEAREST: std::cell::RefCell<NearestPhotons> = std::cell::RefCell::new(NearestPhotons::default());
}

impl VolumePhotons {
    /// Shoots photons until `wanted` are stored (or `wanted × EFFORT` particles are
    /// emitted), each path at most `max_depth` scattering events long. An estimate gathers
    /// the `nearest` photons (at least 2: the density of one photon has no finite mean)
    /// within `max_radius` (0: 5 % of the scene's diagonal).
    pub fn shoot(
        scene: &Scene,
        max_depth: u32,
        wanted: u64,
        nearest: usize,
        max_radius: f32,
        seed: u64,
        stop: &AtomicBool,
    ) -> Result<Self, RenderError> {
        scene.lights().check_particles()?;
        if scene.media().iter().any(|m| m.emission != Rgb::ZERO) {
            return Err(RenderError::EmittingMedium);
        }
        let (mut photons, mut emitted, mut rays, mut next) =
            (Vec::<(u32, Photon)>::new(), 0u64, RayCounts::default(), 0u64);
        while (photons.len() as u64) < wanted && emitted < wanted.saturating_mul(EFFORT) {
            if stop.load(Ordering::Relaxed) {
                return Err(RenderError::Interrupted);
            }
            let (round, round_rays) =
                shoot_batches(scene, seed ^ STREAM, next..next + 64, |particle, rng, rays, stored| {
                    trace(scene, particle, max_depth, rng, rays, stored)
                });
            next += 64;
            emitted += 64 * BATCH;
            photons.extend(round);
            rays.add(&round_rays);
        }
        let mut by_medium: Vec<Vec<Photon>> = vec![Vec::new(); scene.media().len()];
        for (medium, photon) in photons {
            by_medium[medium as usize].push(photon);
        }
        let bounds = scene.geometry().bounds();
        let max_radius = if max_radius > 0.0 {
            max_radius
        } else if bounds.is_empty() {
            1.0
        } else {
            0.05 * bounds.extent().length()
        };
        let maps = by_medium.into_iter().map(|photons| PhotonMap::build(photons, emitted)).collect();
        Ok(Self { maps, nearest: nearest.max(2), max_radius, photon_rays: rays })
    }

    /// Photons stored, in all media.
    pub fn len(&self) -> usize {
        self.maps.iter().map(PhotonMap::len).sum()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// ∫ p(ω, ω') L_s(x, ω') dω' at `point` of medium `medium`, for a ray travelling along
    /// `direction`, where L_s is the light that has scattered at least once: Σ p Φ / V over
    /// the medium's nearest photons.
    pub fn in_scattered(&self, medium: u32, point: Vec3, direction: Vec3, phase: &PhaseFunction) -> Rgb {
        let Some(map) = self.maps.get(medium as usize).filter(|m| !m.is_empty()) else { return Rgb::ZERO };
        NEAREST.with_borrow_mut(|nearest| {
            map.k_nearest(point, self.nearest, self.max_radius, nearest);
            if nearest.is_empty() {
                return Rgb::ZERO;
            }
            let radius2 = if nearest.len() < self.nearest {
                self.max_radius * self.max_radius
            } else {
                nearest.max_distance_squared()
            };
            let volume = 4.0 / 3.0 * std::f32::consts::PI * radius2 * radius2.sqrt();
            if volume.is_nan() || volume <= 0.0 {
                return Rgb::ZERO; // photons all at the point itself: no density to speak of
            }
            let mut sum = Rgb::ZERO;
            for (_, i) in nearest.iter() {
                let photon = map.photon(i);
                sum += photon.power * phase.eval(direction, photon.incoming());
            }
            sum / (volume * map.emitted() as f32)
        })
    }
}

/// Follows one particle from its light, storing a photon at each real collision in a medium
/// after its first scattering event.
fn trace(
    scene: &Scene,
    particle: &Particle,
    max_depth: u32,
    rng: &mut Rng,
    rays: &mut RayCounts,
    stored: &mut Vec<(u32, Photon)>,
) {
    let direction = particle.ray.direction.normalize();
    let mut ray = Ray::new(particle.ray.origin, direction);
    let mut power = particle.weight;
    let mut medium = scene.medium_at(ray.origin, ray.direction);
    let (mut events, mut crossings) = (0u32, 0usize);
    loop {
        rays.light += 1;
        let hit = scene.intersect(&ray);
        let t_max = hit.as_ref().map_or(f32::INFINITY, |h| h.t);
        if let Some((index, m)) = medium.map(|i| (i, &scene.media()[i as usize])) {
            match m.flight(ray.origin, ray.direction, t_max, rng) {
                Flight::Scattered { t, weight } => {
                    let point = ray.origin + t * ray.direction;
                    let (sigma_s, _) = m.coefficients(point);
                    if events > 0 {
                        // The power arriving here over the collision's density: stored
                        // power's density is the fluence.
                        stored.push((index, Photon::new(point, -ray.direction, -ray.direction, power * weight)));
                    }
                    if events + 1 >= max_depth || !particle_roulette(&mut power, weight * sigma_s, rng).1 {
                        return;
                    }
                    let u = Vec2::new(rng.next_f32(), rng.next_f32());
                    let sample = m.phase.sample(ray.direction, u);
                    ray = Ray::new(point, sample.outgoing);
                    events += 1;
                    crossings = 0;
                    continue;
                }
                Flight::Passed { weight } => power *= weight,
            }
        }
        let Some(hit) = hit else { return };
        let medium_toward = |w: Vec3| medium_beyond(scene, hit.object, w, hit.geometry.geometric_normal, medium);
        if scene.materials()[hit.material as usize].is_null() {
            crossings += 1;
            if crossings > MAX_CROSSINGS {
                return;
            }
            medium = medium_toward(ray.direction);
            ray = hit.spawn_ray(ray.direction);
            continue;
        }
        let vertex = Vertex::at(scene, &ray, hit);
        let bsdf = vertex.bsdf();
        let wo = vertex.wo;
        let u_lobe = rng.next_f32();
        let Some(sample) = bsdf.sample(wo, u_lobe, Vec2::new(rng.next_f32(), rng.next_f32())) else { return };
        let scale = sample.weight * shading_correction(&hit, wo, sample.wi);
        if bsdf.is_null_event(wo, &sample) {
            crossings += 1;
            power *= scale;
            if crossings > MAX_CROSSINGS || power == Rgb::ZERO {
                return;
            }
        } else {
            if events + 1 >= max_depth || !particle_roulette(&mut power, scale, rng).1 {
                return;
            }
            events += 1;
            crossings = 0;
        }
        medium = medium_toward(sample.wi);
        ray = hit.spawn_ray(sample.wi.normalize());
    }
}
