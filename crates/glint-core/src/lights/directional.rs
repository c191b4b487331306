//! Directional light (a light at infinity, like the sun).
//!
//! Scene parameters: `direction` (the direction the light *travels*, normalised on load),
//! `color` (RGB, default [1, 1, 1]), `intensity` (default 1).
//! ```toml
//! [[lights]]
//! type = "directional"
//! direction = [-1, -1, 0.5]
//! ```

use glam::Vec3;

use super::Illumination;
use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct DirectionalLight {
    /// Unit direction of travel.
    pub direction: Vec3,
    pub intensity: Rgb,
}

impl DirectionalLight {
    pub fn illuminate(&self) -> Illumination {
        Illumination { direction: -self.direction, distance: f32::INFINITY, intensity: self.intensity }
    }
}
