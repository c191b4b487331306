//! What the path tracers (`path`, `path-naive`, `volpath`, the photon mappers' camera paths)
//! report about each vertex of a path, so one code path both renders and explains
//! (`glint explain --integrator path`). `()` records nothing and compiles away;
//! `PathLog` keeps every event of one path, and the radiance each adds to the pixel, so the
//! explanation adds up to the value the render computes.

use glam::Vec3;

use super::{CameraExplanation, Integrator, SampleContext};
use crate::geometry::Ray;
use crate::lights::{LightEnd, LightSample};
use crate::materials::BsdfSample;
use crate::scene::{Scene, SurfaceHit};
use crate::Rgb;

/// An integrator that follows one path per camera sample, telling a recorder what happens:
/// it renders with `()` and explains with a `PathLog` (the `Integrator` below, for all).
pub trait TracesPaths {
    fn trace(
        &self,
        scene: &Scene,
        camera_ray: &Ray,
        context: &mut SampleContext,
        recorder: &mut impl PathRecorder,
    ) -> Rgb;

    /// The radiance along `camera_ray` and the log of its path (`PathLog::total` is the
    /// radiance, bit for bit).
    fn explain(&self, scene: &Scene, camera_ray: &Ray, context: &mut SampleContext) -> (Rgb, PathLog) {
        let mut log = PathLog::default();
        let radiance = self.trace(scene, camera_ray, context, &mut log);
        (radiance, log)
    }
}

impl<T: TracesPaths + Send + Sync> Integrator for T {
    fn radiance(&self, scene: &Scene, camera_ray: &Ray, context: &mut SampleContext) -> Rgb {
        self.trace(scene, camera_ray, context, &mut ())
    }

    fn explain(&self, scene: &Scene, camera_ray: &Ray, context: &mut SampleContext) -> Option<CameraExplanation> {
        let (radiance, log) = TracesPaths::explain(self, scene, camera_ray, context);
        Some(CameraExplanation::Path { radiance, log })
    }
}

/// Next-event estimation at a vertex: the light sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSampleRecord {
    pub direction: Vec3,
    /// The point sampled on the light (`None` for a light at infinity).
    pub point: Option<Vec3>,
    /// The sample's solid-angle density, the light's choice included.
    pub pdf: f32,
    /// The power heuristic's weight against BSDF sampling (1 for a delta light).
    pub mis_weight: f32,
    /// The shadow ray found something in the way.
    pub occluded: bool,
    /// What it adds to the pixel (the path's throughput included).
    pub added: Rgb,
}

impl LightSampleRecord {
    pub(crate) fn new(light: &LightSample, mis_weight: f32, occluded: bool, added: Rgb) -> Self {
        let point = match light.end {
            LightEnd::Surface { point, .. } | LightEnd::Point(point) => Some(point),
            LightEnd::Infinite => None,
        };
        Self { direction: light.direction, point, pdf: light.pdf, mis_weight, occluded, added }
    }
}

/// Photon mapping's estimate at a diffuse vertex: direct light by light sampling, caustics from
/// the caustic map, indirect light by final gathering (none at the last bounce), and what
/// their sum adds to the pixel (the path's throughput included).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GatherRecord {
    pub direct: Rgb,
    pub caustic: Rgb,
    pub indirect: Option<Rgb>,
    pub added: Rgb,
}

/// Where a path ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathEnd {
    /// The ray left the scene.
    Escaped,
    /// `max_depth` scattering events.
    Depth,
    /// The BSDF gave no direction (black, or a sample below the surface).
    Absorbed,
    /// Russian roulette ended it.
    Roulette,
}

pub trait PathRecorder {
    /// A vertex at `depth` (0: the camera ray's hit), the path's throughput arriving there.
    fn vertex(&mut self, _depth: u32, _hit: &SurfaceHit, _throughput: Rgb) {}
    /// Emission found at the vertex, its MIS weight against light sampling, and what it adds.
    fn emission(&mut self, _emitted: Rgb, _mis_weight: f32, _added: Rgb) {}
    fn light_sample(&mut self, _record: LightSampleRecord) {}
    fn gather(&mut self, _record: GatherRecord) {}
    /// The BSDF's sample (its direction, weight, pdf, lobe kind) and the throughput after it.
    fn scatter(&mut self, _sample: &BsdfSample, _throughput: Rgb) {}
    /// Russian roulette's survival probability and verdict.
    fn roulette(&mut self, _survival: f32, _survived: bool) {}
    /// A real scattering collision in medium `medium` at `point`, the `depth`-th scattering of
    /// the path (volume path tracing), the path's throughput after it (σ_s and the flight's
    /// weight included).
    fn medium(&mut self, _depth: u32, _point: Vec3, _medium: u32, _throughput: Rgb) {}
    /// The phase function's sample (its weight is 1: sampled exactly) and its density.
    fn phase(&mut self, _direction: Vec3, _pdf: f32) {}
    /// Volumetric photon mapping's estimate at a medium collision: the light scattered there
    /// (∫ p L dω', from the medium's nearest photons) and what it adds.
    fn medium_photons(&mut self, _in_scattered: Rgb, _added: Rgb) {}
    /// The environment found by a ray that left the scene, its MIS weight, what it adds.
    fn escape(&mut self, _radiance: Rgb, _mis_weight: f32, _added: Rgb) {}
    fn end(&mut self, _why: PathEnd) {}
}

/// Records nothing.
impl PathRecorder for () {}

/// One event of a path, as `PathLog` keeps it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PathEvent {
    Vertex { depth: u32, point: Vec3, object: u32, material: u32, throughput: Rgb },
    Emission { emitted: Rgb, mis_weight: f32, added: Rgb },
    Light(LightSampleRecord),
    Gather(GatherRecord),
    Scatter { direction: Vec3, weight: Rgb, pdf: f32, delta: bool, throughput: Rgb },
    Roulette { survival: f32, survived: bool },
    Medium { depth: u32, point: Vec3, medium: u32, throughput: Rgb },
    Phase { direction: Vec3, pdf: f32 },
    MediumPhotons { in_scattered: Rgb, added: Rgb },
    Escape { radiance: Rgb, mis_weight: f32, added: Rgb },
    End(PathEnd),
}

/// Every event of one path.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PathLog {
    pub events: Vec<PathEvent>,
}

impl PathLog {
    /// The sum of what the events add to the pixel, in the order the path tracer adds them.
    pub fn total(&self) -> Rgb {
        self.events.iter().fold(Rgb::ZERO, |sum, event| match event {
            PathEvent::Emission { added, .. }
            | PathEvent::Escape { added, .. }
            | PathEvent::MediumPhotons { added, .. } => sum + *added,
            PathEvent::Light(record) => sum + record.added,
            PathEvent::Gather(record) => sum + record.added,
            _ => sum,
        })
    }
}

impl PathRecorder for PathLog {
    fn vertex(&mut self, depth: u32, hit: &SurfaceHit, throughput: Rgb) {
        let (point, object, material) = (hit.geometry.point, hit.object, hit.material);
        self.events.push(PathEvent::Vertex { depth, point, object, material, throughput });
    }
    fn emission(&mut self, emitted: Rgb, mis_weight: f32, added: Rgb) {
        self.events.push(PathEvent::Emission { emitted, mis_weight, added });
    }
    fn light_sample(&mut self, record: LightSampleRecord) {
        self.events.push(PathEvent::Light(record));
    }
    fn gather(&mut self, record: GatherRecord) {
        self.events.push(PathEvent::Gather(record));
    }
    fn scatter(&mut self, sample: &BsdfSample, throughput: Rgb) {
        let (direction, weight, pdf, delta) = (sample.wi, sample.weight, sample.pdf, sample.delta);
        self.events.push(PathEvent::Scatter { direction, weight, pdf, delta, throughput });
    }
    fn roulette(&mut self, survival: f32, survived: bool) {
        self.events.push(PathEvent::Roulette { survival, survived });
    }
    fn medium(&mut self, depth: u32, point: Vec3, medium: u32, throughput: Rgb) {
        self.events.push(PathEvent::Medium { depth, point, medium, throughput });
    }
    fn phase(&mut self, direction: Vec3, pdf: f32) {
        self.events.push(PathEvent::Phase { direction, pdf });
    }
    fn medium_photons(&mut self, in_scattered: Rgb, added: Rgb) {
        self.events.push(PathEvent::MediumPhotons { in_scattered, added });
    }
    fn escape(&mut self, radiance: Rgb, mis_weight: f32, added: Rgb) {
        self.events.push(PathEvent::Escape { radiance, mis_weight, added });
    }
    fn end(&mut self, why: PathEnd) {
        self.events.push(PathEvent::End(why));
    }
}

/// What a particle from a light does (light tracing), as `PathRecorder` is for camera paths.
pub trait ParticleRecorder {
    /// It leaves a light at `origin` carrying `flux`.
    fn start(&mut self, _origin: Vec3, _flux: Rgb) {}
    /// It reaches a surface after `bounces` scattering events, carrying `flux` there.
    fn surface(&mut self, _hit: &SurfaceHit, _flux: Rgb, _bounces: u32) {}
    /// A connection to the camera lands `value` in pixel (x, y); `bounces` is the surface it
    /// leaves from (`None`: the light itself, seen by the camera).
    fn splat(&mut self, _bounces: Option<u32>, _x: u32, _y: u32, _value: Rgb) {}
    /// Russian roulette's survival probability and verdict.
    fn roulette(&mut self, _survival: f32, _survived: bool) {}
    fn end(&mut self, _why: PathEnd) {}
}

/// Records nothing.
impl ParticleRecorder for () {}

/// One event of a particle's path, as `ParticleLog` keeps it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParticleEvent {
    Start { origin: Vec3, flux: Rgb },
    Surface { bounces: u32, point: Vec3, object: u32, material: u32, flux: Rgb },
    Splat { bounces: Option<u32>, x: u32, y: u32, value: Rgb },
    Roulette { survival: f32, survived: bool },
    End(PathEnd),
}

/// Every event of one particle's path.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ParticleLog {
    pub events: Vec<ParticleEvent>,
}

impl ParticleRecorder for ParticleLog {
    fn start(&mut self, origin: Vec3, flux: Rgb) {
        self.events.push(ParticleEvent::Start { origin, flux });
    }
    fn surface(&mut self, hit: &SurfaceHit, flux: Rgb, bounces: u32) {
        let (point, object, material) = (hit.geometry.point, hit.object, hit.material);
        self.events.push(ParticleEvent::Surface { bounces, point, object, material, flux });
    }
    fn splat(&mut self, bounces: Option<u32>, x: u32, y: u32, value: Rgb) {
        self.events.push(ParticleEvent::Splat { bounces, x, y, value });
    }
    fn roulette(&mut self, survival: f32, survived: bool) {
        self.events.push(ParticleEvent::Roulette { survival, survived });
    }
    fn end(&mut self, why: PathEnd) {
        self.events.push(ParticleEvent::End(why));
    }
}
