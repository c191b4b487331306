//! Integrators: algorithms that turn a camera ray into radiance. Each is one file (the path
//! tracer's wavefront, a directory); they are created once per render and reach geometry
//! through the scene's query interface (closest hit, any hit, and, for the wavefront, the
//! surface and corners of a hit primitive).

pub mod aov;
mod bvh_heat;
mod estimators;
mod explain;
mod light;
mod particle;
pub mod passes;
mod path;
mod path_naive;
pub mod path_record;
mod photon_mapping;
mod raycast;
pub mod recorder;
mod sppm;
mod vertex;
mod volpath;
mod volume_photons;
mod wavefront;
pub mod whitted;

pub use bvh_heat::{heat_colour, BvhHeat};
pub use estimators::power_heuristic;
pub use explain::{CameraExplanation, PixelExplanation};
pub use light::{LightTracer, ParticleExplanation};
pub use path::PathTracer;
pub use path_naive::NaivePathTracer;
pub use photon_mapping::{PhotonMapper, PhotonSettings};
pub use raycast::Raycast;
pub use sppm::{Sppm, SppmExplanation, SppmGather};
pub use volpath::VolPathTracer;
pub use volume_photons::VolumePhotons;
pub use wavefront::WavefrontPathTracer;
pub use whitted::Whitted;

use std::sync::atomic::AtomicBool;

use self::passes::{CameraPasses, PassRenderer};

use crate::geometry::Ray;
use crate::sampling::{Rng, Sampler};
use crate::scene::Scene;
use crate::Named;
use crate::RenderError;
use crate::Rgb;

/// Per-sample state an integrator may use: the sample's random numbers and counts of the rays
/// it traced.
///
/// `repr(C)`, the sampler first: a context is built on the stack and then moved in 32-byte
/// pieces, and with the counts first those pieces straddled the sampler's own stores, a
/// stall (store forwarding fails) of every camera sample.
#[derive(Clone, Debug)]
#[repr(C)]
pub struct SampleContext {
    pub sampler: Sampler,
    /// The rays this sample traced, or, for a tile's samples run together, all the tile's in
    /// its first sample's (`Integrator::radiance_tile`).
    pub rays: RayCounts,
}

impl SampleContext {
    /// Independent random numbers from `rng`.
    pub fn new(rng: Rng) -> Self {
        Self::with_sampler(Sampler::independent(rng))
    }

    pub fn with_sampler(sampler: Sampler) -> Self {
        Self { sampler, rays: RayCounts::default() }
    }
}

/// Rays traced, by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayCounts {
    pub camera: u64,
    pub shadow: u64,
    pub reflection: u64,
    pub refraction: u64,
    /// Rays traced from lights (light tracing, photons).
    pub light: u64,
}

impl RayCounts {
    pub fn total(&self) -> u64 {
        self.camera + self.shadow + self.reflection + self.refraction + self.light
    }

    pub fn add(&mut self, other: &RayCounts) {
        self.camera += other.camera;
        self.shadow += other.shadow;
        self.reflection += other.reflection;
        self.refraction += other.refraction;
        self.light += other.light;
    }
}

/// An integrator that estimates the radiance arriving along one camera ray.
pub trait Integrator: Send + Sync {
    fn radiance(&self, scene: &Scene, ray: &Ray, context: &mut SampleContext) -> Rgb;

    /// The radiance along many camera rays (an image tile's): `out[i]` for `rays[i]`, drawing
    /// from `contexts[i]`. The same as `radiance` for each; an integrator may run them
    /// together (the path tracer's wavefront), and may then count the rays they traced in all
    /// in the first context rather than each in its own.
    fn radiance_tile(&self, scene: &Scene, rays: &[Ray], contexts: &mut [SampleContext], out: &mut [Rgb]) {
        radiance_each(self, scene, rays, contexts, out);
    }

    /// What the user should know about the render so far (paths or ray trees cut at a
    /// ceiling, say); empty when all went as asked.
    fn warnings(&self) -> Vec<String> {
        Vec::new()
    }

    /// What the estimate along one camera ray is made of, for `glint explain`: Whitted's ray
    /// tree or a path's events, computed by the code that renders. `None` for the integrators
    /// that explain nothing (ray casting, the BVH heat map).
    fn explain(&self, _scene: &Scene, _camera_ray: &Ray, _context: &mut SampleContext) -> Option<CameraExplanation> {
        None
    }
}

/// `radiance_tile` one ray at a time.
pub fn radiance_each<I: Integrator + ?Sized>(
    integrator: &I,
    scene: &Scene,
    rays: &[Ray],
    contexts: &mut [SampleContext],
    out: &mut [Rgb],
) {
    for ((ray, context), out) in rays.iter().zip(contexts.iter_mut()).zip(out.iter_mut()) {
        *out = integrator.radiance(scene, ray, context);
    }
}

/// The integrators selectable by name (`--integrator`, `render.integrator`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum IntegratorKind {
    #[default]
    Raycast,
    Whitted,
    BvhHeat,
    Path,
    PathNaive,
    /// Path tracing through participating media (Mitsuba's `volpath`).
    VolPath,
    /// `volpath` with the light scattered in media gathered from a volume photon map
    /// (Jensen & Christensen 1998).
    VolPhoton,
    Light,
    Photon,
    Sppm,
}

/// Settings that integrators read (each uses the ones that apply to it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IntegratorSettings {
    /// Maximum number of recursive bounces (Whitted: reflection/refraction generations).
    pub max_depth: u32,
    /// Whitted: a ray whose accumulated weight is below this on every channel is not traced.
    pub min_contribution: f32,
    /// Whitted: shadow rays pass through transparent occluders, attenuated by their k_t.
    pub transparent_shadows: bool,
    /// Path tracers: Russian roulette starts after this many bounces.
    pub rr_depth: u32,
    /// Photon mapping: map sizes, estimate size and radius, final gathering.
    pub photon: PhotonSettings,
    /// SPPM: the first search radius (0: three pixel footprints at the visible point).
    pub sppm_radius: f32,
    /// SPPM: photons per pass (0: as many as the image has pixels).
    pub photons_per_pass: u32,
    /// Path tracing: run a tile's paths together, eight at a time in SIMD lanes
    /// (`WavefrontPathTracer`: the same image, faster); false: one path at a time.
    pub wavefront: bool,
}

/// What the settings make of an image, for checkpoint fingerprints: every field but
/// `wavefront` (the same image either way), floats by their bits. Destructured, so that a new
/// field must be placed here or left out knowingly.
impl std::hash::Hash for IntegratorSettings {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        let Self {
            max_depth,
            min_contribution,
            transparent_shadows,
            rr_depth,
            photon,
            sppm_radius,
            photons_per_pass,
            wavefront: _,
        } = self;
        let PhotonSettings { global_photons, caustic_photons, nearest, max_radius, final_gather } = photon;
        (max_depth, min_contribution.to_bits(), transparent_shadows, rr_depth).hash(state);
        (global_photons, caustic_photons, nearest, max_radius.to_bits(), final_gather).hash(state);
        (sppm_radius.to_bits(), photons_per_pass).hash(state);
    }
}

impl Default for IntegratorSettings {
    fn default() -> Self {
        Self {
            max_depth: 5,
            min_contribution: 1e-3,
            transparent_shadows: false,
            rr_depth: 5,
            photon: PhotonSettings::default(),
            sppm_radius: 0.0,
            photons_per_pass: 0,
            wavefront: true,
        }
    }
}

impl Named for IntegratorKind {
    const ALL: &'static [Self] = &[
        IntegratorKind::Raycast,
        IntegratorKind::Whitted,
        IntegratorKind::BvhHeat,
        IntegratorKind::Path,
        IntegratorKind::PathNaive,
        IntegratorKind::VolPath,
        IntegratorKind::VolPhoton,
        IntegratorKind::Light,
        IntegratorKind::Photon,
        IntegratorKind::Sppm,
    ];

    fn name(self) -> &'static str {
        match self {
            IntegratorKind::Raycast => "raycast",
            IntegratorKind::Whitted => "whitted",
            IntegratorKind::BvhHeat => "bvh-heat",
            IntegratorKind::Path => "path",
            IntegratorKind::PathNaive => "path-naive",
            IntegratorKind::VolPath => "volpath",
            IntegratorKind::VolPhoton => "volphoton",
            IntegratorKind::Light => "light",
            IntegratorKind::Photon => "photon",
            IntegratorKind::Sppm => "sppm",
        }
    }
}

impl IntegratorKind {
    /// Whether it follows light from the lights (and so needs physical lights).
    pub fn traces_particles(self) -> bool {
        matches!(
            self,
            IntegratorKind::Light | IntegratorKind::Photon | IntegratorKind::Sppm | IntegratorKind::VolPhoton
        )
    }

    /// Whether each of its camera samples lands in its own pixel (not light tracing's splats,
    /// nor SPPM's estimate made once a pass): what a pixel's second moment needs.
    pub fn samples_pixels(self) -> bool {
        !matches!(self, IntegratorKind::Light | IntegratorKind::Sppm)
    }

    /// Whether it estimates light transport by random paths (every integrator but ray casting,
    /// Whitted's recursion and the BVH heat map), so that Phong's highlight is one of a
    /// material's lobes.
    pub fn is_monte_carlo(self) -> bool {
        !matches!(self, IntegratorKind::Raycast | IntegratorKind::Whitted | IntegratorKind::BvhHeat)
    }

    /// Whether `glint explain` can follow it (every integrator but ray casting and the BVH heat
    /// map, which have nothing to tell but the first hit).
    pub fn explains(self) -> bool {
        !matches!(self, IntegratorKind::Raycast | IntegratorKind::BvhHeat)
    }

    /// The integrator, for those that need nothing but the camera ray (`None` for those that
    /// must first look at the scene: use `build`).
    pub fn create(self, settings: &IntegratorSettings) -> Option<Box<dyn Integrator>> {
        Some(match self {
            IntegratorKind::Raycast => Box::new(Raycast),
            IntegratorKind::BvhHeat => Box::new(BvhHeat),
            IntegratorKind::Path if settings.wavefront => {
                Box::new(WavefrontPathTracer { tracer: PathTracer::new(settings) })
            }
            IntegratorKind::Path => Box::new(PathTracer::new(settings)),
            IntegratorKind::PathNaive => {
                Box::new(NaivePathTracer { max_depth: settings.max_depth, rr_depth: settings.rr_depth })
            }
            IntegratorKind::VolPath => Box::new(VolPathTracer::new(settings)),
            IntegratorKind::Whitted => {
                Box::new(Whitted::new(settings.max_depth, settings.min_contribution, settings.transparent_shadows))
            }
            IntegratorKind::Light | IntegratorKind::Photon | IntegratorKind::Sppm | IntegratorKind::VolPhoton => {
                return None
            }
        })
    }

    /// The integrator of this kind made for `scene` (photon mapping shoots its photons here,
    /// with `seed`): the one place integrators are constructed, for rendering (`renderer`) and
    /// for explaining a pixel (`explain_pixel`). An error if the scene cannot be rendered so
    /// (no physical light), or soon after `stop` is raised (photon maps take a while).
    pub fn build_until(
        self,
        settings: &IntegratorSettings,
        scene: &Scene,
        seed: u64,
        stop: &AtomicBool,
    ) -> Result<Built, RenderError> {
        Ok(match self {
            IntegratorKind::Light => Built::Light(LightTracer::new(scene, settings.max_depth)?),
            IntegratorKind::Sppm => Built::Sppm(Sppm::new(
                scene,
                settings.max_depth,
                settings.rr_depth,
                settings.sppm_radius,
                settings.photons_per_pass,
            )?),
            IntegratorKind::Photon => Built::Photon(PhotonMapper::new_until(
                scene,
                settings.max_depth,
                settings.rr_depth,
                settings.photon,
                seed,
                stop,
            )?),
            IntegratorKind::VolPhoton => {
                let photons = VolumePhotons::shoot(
                    scene,
                    settings.max_depth,
                    settings.photon.global_photons as u64,
                    settings.photon.nearest as usize,
                    settings.photon.max_radius,
                    seed,
                    stop,
                )?;
                Built::Camera(Box::new(VolPathTracer {
                    photons: Some(std::sync::Arc::new(photons)),
                    ..VolPathTracer::new(settings)
                }))
            }
            camera => Built::Camera(camera.create(settings).expect("a camera integrator")),
        })
    }

    /// What renders the passes of this integrator on `scene` (photon mapping shoots its photons
    /// here, with `seed`). An error if the scene cannot be rendered so (no physical light).
    pub fn renderer(
        self,
        settings: &IntegratorSettings,
        scene: &Scene,
        seed: u64,
    ) -> Result<Box<dyn PassRenderer + Send>, RenderError> {
        self.renderer_until(settings, scene, seed, &AtomicBool::new(false))
    }

    /// `renderer`, giving up with an error soon after `stop` is raised (photon mapping's maps
    /// take a while to build).
    pub fn renderer_until(
        self,
        settings: &IntegratorSettings,
        scene: &Scene,
        seed: u64,
        stop: &AtomicBool,
    ) -> Result<Box<dyn PassRenderer + Send>, RenderError> {
        Ok(self.build_until(settings, scene, seed, stop)?.into_renderer())
    }
}

/// An integrator made for a scene (`IntegratorKind::build_until`), by how it renders.
pub enum Built {
    /// One that estimates each camera sample alone, in camera passes.
    Camera(Box<dyn Integrator>),
    /// Photon mapping: camera passes too, after its maps (which `glint explain --photons` lists).
    Photon(PhotonMapper),
    /// Light tracing: particles splatted into the film.
    Light(LightTracer),
    /// SPPM: visible points and a photon pass, per pass.
    Sppm(Sppm),
}

impl Built {
    /// What renders its passes.
    pub fn into_renderer(self) -> Box<dyn PassRenderer + Send> {
        match self {
            Built::Camera(integrator) => Box::new(CameraPasses(integrator)),
            Built::Photon(mapper) => {
                let mapper: Box<dyn Integrator> = Box::new(mapper);
                Box::new(CameraPasses(mapper))
            }
            Built::Light(tracer) => Box::new(tracer),
            Built::Sppm(sppm) => Box::new(sppm),
        }
    }
}

#[cfg(test)]
mod tests {
    use std::hash::{DefaultHasher, Hash, Hasher};

    use super::*;

    fn hash(s: &IntegratorSettings) -> u64 {
        let mut h = DefaultHasher::new();
        s.hash(&mut h);
        h.finish()
    }

    /// Every setting that changes the image changes the hash; the wavefront, which does not,
    /// leaves it.
    #[test]
    fn settings_hash_what_changes_the_image() {
        let base = IntegratorSettings::default();
        let changed: [fn(&mut IntegratorSettings); 10] = [
            |s| s.max_depth += 1,
            |s| s.min_contribution *= 2.0,
            |s| s.transparent_shadows ^= true,
            |s| s.rr_depth += 1,
            |s| s.photon.global_photons += 1,
            |s| s.photon.caustic_photons += 1,
            |s| s.photon.nearest += 1,
            |s| s.photon.max_radius = 0.5,
            |s| s.photon.final_gather += 1,
            |s| s.sppm_radius = 0.25,
        ];
        for (i, change) in changed.iter().enumerate() {
            let mut s = base;
            change(&mut s);
            assert_ne!(hash(&s), hash(&base), "change {i}");
        }
        let mut s = base;
        s.photons_per_pass += 1;
        assert_ne!(hash(&s), hash(&base));
        s = base;
        s.wavefront ^= true;
        assert_eq!(hash(&s), hash(&base));
    }
}
