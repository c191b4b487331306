//! Lights: a closed set dispatched per shading point. Every light answers `illuminate(p)`:
//! the unit direction from `p` toward it, the distance (∞ for directional light, for the
//! shadow ray's range) and the intensity arriving at `p`.

mod directional;
mod point;

pub use directional::DirectionalLight;
pub use point::{Falloff, PointLight};

use glam::Vec3;

use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    Point(PointLight),
    Directional(DirectionalLight),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Illumination {
    pub direction: Vec3,
    pub distance: f32,
    pub intensity: Rgb,
}

impl Light {
    pub fn illuminate(&self, point: Vec3) -> Illumination {
        match self {
            Light::Point(l) => l.illuminate(point),
            Light::Directional(l) => l.illuminate(),
        }
    }
}
