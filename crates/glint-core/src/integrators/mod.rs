//! Integrators: algorithms that turn a camera ray into radiance. Each is one file; they are
//! called once per render and reach the scene only through its query interface.

mod raycast;

pub use raycast::Raycast;

use crate::geometry::Ray;
use crate::sampling::Rng;
use crate::scene::Scene;
use crate::Rgb;

/// Per-sample state an integrator may use: random numbers and a count of the rays it traced.
pub struct SampleContext {
    pub rng: Rng,
    pub rays_traced: u64,
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
}

impl IntegratorKind {
    pub const ALL: [IntegratorKind; 1] = [IntegratorKind::Raycast];

    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::Raycast => "raycast",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }

    pub fn create(self) -> Box<dyn Integrator> {
        match self {
            IntegratorKind::Raycast => Box::new(Raycast),
        }
    }
}
