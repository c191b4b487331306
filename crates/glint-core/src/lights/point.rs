//! Point light.
//!
//! Scene parameters: `position` (point), `color` (RGB, default [1, 1, 1]), `intensity`
//! (scalar multiplier, default 1), `falloff` (`"none"`, the course's default, or
//! `"inverse-square"`, physical: intensity / distance²).
//! ```toml
//! [[lights]]
//! type = "point"
//! position = [2, 5, -3]
//! intensity = 0.8
//! ```

use glam::Vec3;

use super::Illumination;
use crate::Rgb;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Falloff {
    #[default]
    None,
    InverseSquare,
}

#[derive(Clone, Debug, PartialEq)]
pub struct PointLight {
    pub position: Vec3,
    /// Colour × intensity.
    pub intensity: Rgb,
    pub falloff: Falloff,
}

impl PointLight {
    pub fn illuminate(&self, point: Vec3) -> Illumination {
        let offset = self.position - point;
        let distance = offset.length();
        let intensity = match self.falloff {
            Falloff::None => self.intensity,
            Falloff::InverseSquare => self.intensity / (distance * distance),
        };
        Illumination { direction: offset / distance, distance, intensity }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_square_falloff() {
        let l = PointLight { position: Vec3::new(0.0, 2.0, 0.0), intensity: Rgb::ONE, falloff: Falloff::InverseSquare };
        let i = l.illuminate(Vec3::ZERO);
        assert_eq!((i.direction, i.distance, i.intensity), (Vec3::Y, 2.0, Rgb::splat(0.25)));
    }
}
