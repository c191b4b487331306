//! Lights: a closed set dispatched per shading point. Every light answers `illuminate(p)`:
//! the unit direction from `p` toward it, the distance (∞ for directional light, for the
//! shadow ray's range) and the intensity arriving at `p`. For the integrators that trace light
//! forward, `ParticleSource` makes every light (area ones included) emit particles.

mod area;
mod directional;
mod emission;
mod environment;
mod point;
mod spot;

#[cfg(test)]
pub(crate) use area::area_to_solid_angle;
pub(crate) use area::TriangleEmitter;
pub use area::{AreaEmission, AreaLights, LightSample, TriangleSampling};
pub use directional::DirectionalLight;
pub use emission::{Particle, ParticleSource};
pub use environment::{EnvironmentMap, EnvironmentSample};
pub use point::{Falloff, PointLight};
pub use spot::SpotLight;

use glam::Vec3;

use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    Point(PointLight),
    Directional(DirectionalLight),
    Spot(SpotLight),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Illumination {
    pub direction: Vec3,
    pub distance: f32,
    pub intensity: Rgb,
}

impl Light {
    /// Where a shadow ray toward the light ends: its position, or `None` for a light at infinity.
    pub fn position(&self) -> Option<Vec3> {
        match self {
            Light::Point(l) => Some(l.position),
            Light::Spot(l) => Some(l.light.position),
            Light::Directional(_) => None,
        }
    }

    pub fn kind(&self) -> &'static str {
        match self {
            Light::Point(_) => "point",
            Light::Directional(_) => "directional",
            Light::Spot(_) => "spot",
        }
    }

    pub fn illuminate(&self, point: Vec3) -> Illumination {
        match self {
            Light::Point(l) => l.illuminate(point),
            Light::Directional(l) => l.illuminate(),
            Light::Spot(l) => l.illuminate(point),
        }
    }
}
