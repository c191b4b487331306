//! Integrators: algorithms that turn a camera ray into radiance. Each is one file; they are
//! called once per render and reach the scene only through its query interface.

mod bvh_heat;
mod path;
mod path_naive;
mod raycast;
pub mod recorder;
mod whitted;

pub use bvh_heat::{heat_colour, BvhHeat};
pub use path::{power_heuristic, PathTracer};
pub use path_naive::NaivePathTracer;
pub use raycast::Raycast;
pub use whitted::Whitted;

use crate::geometry::Ray;
use crate::sampling::Rng;
use crate::scene::Scene;
use crate::Rgb;

/// Per-sample state an integrator may use: random numbers and counts of the rays it traced.
pub struct SampleContext {
    pub rng: Rng,
    pub rays: RayCounts,
}

impl SampleContext {
    pub fn new(rng: Rng) -> Self {
        Self { rng, rays: RayCounts::default() }
    }
}

/// Rays traced, by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayCounts {
    pub camera: u64,
    pub shadow: u64,
    pub reflection: u64,
    pub refraction: u64,
}

impl RayCounts {
    pub fn total(&self) -> u64 {
        self.camera + self.shadow + self.reflection + self.refraction
    }

    pub fn add(&mut self, other: &RayCounts) {
        self.camera += other.camera;
        self.shadow += other.shadow;
        self.reflection += other.reflection;
        self.refraction += other.refraction;
    }
}

/// An integrator that estimates the radiance arriving along one camera ray.
pub trait Integrator: Sync {
    fn radiance(&self, scene: &Scene, ray: &Ray, context: &mut SampleContext) -> Rgb;
}

/// The integrators selectable by name (`--integrator`, `render.integrator`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum IntegratorKind {
    #[default]
    Raycast,
    Whitted,
    BvhHeat,
    Path,
    PathNaive,
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
}

impl Default for IntegratorSettings {
    fn default() -> Self {
        Self { max_depth: 5, min_contribution: 1e-3, transparent_shadows: false, rr_depth: 5 }
    }
}

impl IntegratorKind {
    pub const ALL: [IntegratorKind; 5] = [
        IntegratorKind::Raycast,
        IntegratorKind::Whitted,
        IntegratorKind::BvhHeat,
        IntegratorKind::Path,
        IntegratorKind::PathNaive,
    ];

    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::Raycast => "raycast",
            IntegratorKind::Whitted => "whitted",
            IntegratorKind::BvhHeat => "bvh-heat",
            IntegratorKind::Path => "path",
            IntegratorKind::PathNaive => "path-naive",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }

    pub fn create(self, settings: &IntegratorSettings) -> Box<dyn Integrator> {
        match self {
            IntegratorKind::Raycast => Box::new(Raycast),
            IntegratorKind::BvhHeat => Box::new(BvhHeat),
            IntegratorKind::Path => Box::new(PathTracer { max_depth: settings.max_depth, rr_depth: settings.rr_depth }),
            IntegratorKind::PathNaive => {
                Box::new(NaivePathTracer { max_depth: settings.max_depth, rr_depth: settings.rr_depth })
            }
            IntegratorKind::Whitted => Box::new(Whitted {
                max_depth: settings.max_depth,
                min_contribution: settings.min_contribution,
                transparent_shadows: settings.transparent_shadows,
            }),
        }
    }
}
