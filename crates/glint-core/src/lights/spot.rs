//! Spot light: a point light limited to a cone, with a smooth edge.
//!
//! Scene parameters: `position` (point), `direction` (the cone's axis, where the light points),
//! `cone_angle` (half-angle of the cone in degrees, default 30), `edge` (width in degrees of
//! the soft edge inside the cone, default 5), `color`, `intensity`, `falloff` (`"none"` or
//! `"inverse-square"`), as for point lights.
//! ```toml
//! [[lights]]
//! type = "spot"
//! position = [0, 5, 0]
//! direction = [0, -1, 0]
//! cone_angle = 25
//! ```
//! Full intensity inside `cone_angle − edge`, none outside `cone_angle`, a smoothstep of the
//! cosine between (pbrt-v4's spot light profile).

use glam::Vec3;

use super::{Falloff, Illumination, PointLight};
use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct SpotLight {
    pub light: PointLight,
    /// Unit direction of the cone's axis.
    pub direction: Vec3,
    pub cos_cone: f32,
    pub cos_full: f32,
}

impl SpotLight {
    pub fn new(
        position: Vec3,
        direction: Vec3,
        intensity: Rgb,
        falloff: Falloff,
        cone_degrees: f32,
        edge_degrees: f32,
    ) -> Self {
        let cone = cone_degrees.to_radians();
        let full = (cone_degrees - edge_degrees).max(0.0).to_radians();
        Self {
            light: PointLight { position, intensity, falloff },
            direction: direction.normalize(),
            cos_cone: cone.cos(),
            cos_full: full.cos(),
        }
    }

    pub fn illuminate(&self, point: Vec3) -> Illumination {
        let mut illumination = self.light.illuminate(point);
        let cos = (-illumination.direction).dot(self.direction);
        illumination.intensity *= smoothstep(self.cos_cone, self.cos_full, cos);
        illumination
    }
}

fn smoothstep(edge0: f32, edge1: f32, x: f32) -> f32 {
    if edge0 >= edge1 {
        return if x >= edge1 { 1.0 } else { 0.0 };
    }
    let t = ((x - edge0) / (edge1 - edge0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inside_edge_and_outside_the_cone() {
        let spot = SpotLight::new(Vec3::new(0.0, 1.0, 0.0), -Vec3::Y, Rgb::ONE, Falloff::None, 30.0, 10.0);
        let at = |degrees: f32| {
            let a = degrees.to_radians();
            spot.illuminate(Vec3::new(a.tan(), 0.0, 0.0)).intensity.x
        };
        assert_eq!(at(0.0), 1.0);
        assert_eq!(at(19.0), 1.0);
        assert!(at(25.0) > 0.0 && at(25.0) < 1.0);
        assert_eq!(at(31.0), 0.0);
        assert!(at(22.0) > at(28.0)); // fades toward the edge
    }
}
