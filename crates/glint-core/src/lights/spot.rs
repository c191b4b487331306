//! Spot light: a point light limited to a cone, with a soft edge, optionally projecting a
//! texture (a slide).
//!
//! Scene parameters: `position` (point), `direction` (the cone's axis, where the light points),
//! `cone_angle` (half-angle of the cone in degrees, default 30), `edge` (width in degrees of
//! the soft edge inside the cone, default 5), `profile` (`"smooth"`, default, or `"linear"`),
//! `texture` (a texture's name), `up` (the slide's up, default +y or +z), `color`,
//! `intensity`, `falloff` (`"none"` or `"inverse-square"`), as for point lights.
//! ```toml
//! [[lights]]
//! type = "spot"
//! position = [0, 5, 0]
//! direction = [0, -1, 0]
//! cone_angle = 25
//! ```
//! Full intensity inside `cone_angle − edge`, none outside `cone_angle`; between the two a
//! smoothstep of the cosine (pbrt-v4's profile) or linear in the angle (Mitsuba's `spot`).
//! A texture multiplies the intensity by its value at the direction's position on the slide:
//! with d in the light's frame (x, y across the beam, z along it),
//! uv = ½ + ½ (d_x, d_y) / (d_z tan cone_angle), Mitsuba's projection.

use glam::{Vec2, Vec3};

use super::{Falloff, Illumination, PointLight};
use crate::textures::{Texture, TextureQuery};
use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct SpotLight {
    pub light: PointLight,
    /// Unit direction of the cone's axis.
    pub direction: Vec3,
    pub cos_cone: f32,
    pub cos_full: f32,
    pub profile: SpotProfile,
    /// Boxed so a light stays small (the light set is read per shading point).
    pub slide: Option<Box<Slide>>,
}

/// How the intensity fades across the edge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SpotProfile {
    /// A smoothstep of the cosine (pbrt-v4).
    #[default]
    Smooth,
    /// Linear in the angle from the axis (Mitsuba).
    Linear,
}

/// A texture projected by a spot light.
#[derive(Clone, Debug, PartialEq)]
pub struct Slide {
    pub texture: Texture,
    /// The slide's axes in world space: u grows along `right`, v along `up`.
    pub right: Vec3,
    pub up: Vec3,
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
            profile: SpotProfile::Smooth,
            slide: None,
        }
    }

    pub fn with_profile(self, profile: SpotProfile) -> Self {
        Self { profile, ..self }
    }

    pub fn with_slide(self, slide: Slide) -> Self {
        Self { slide: Some(Box::new(slide)), ..self }
    }

    pub fn illuminate(&self, point: Vec3) -> Illumination {
        let mut illumination = self.light.illuminate(point);
        let outward = -illumination.direction;
        let cos = outward.dot(self.direction);
        illumination.intensity *= match self.profile {
            SpotProfile::Smooth => smoothstep(self.cos_cone, self.cos_full, cos),
            SpotProfile::Linear => linear_in_angle(self.cos_cone, self.cos_full, cos),
        };
        if let Some(slide) = &self.slide {
            if cos > 0.0 {
                let tan_cone = (1.0 - self.cos_cone * self.cos_cone).max(0.0).sqrt() / self.cos_cone;
                let across = Vec2::new(outward.dot(slide.right), outward.dot(slide.up)) / (cos * tan_cone);
                let query = TextureQuery { uv: Vec2::splat(0.5) + 0.5 * across, ..Default::default() };
                illumination.intensity *= slide.texture.evaluate(&query);
            }
        }
        illumination
    }
}

/// 1 inside the full beam, 0 outside the cone, linear in the angle between.
fn linear_in_angle(cos_cone: f32, cos_full: f32, cos: f32) -> f32 {
    if cos >= cos_full {
        return 1.0;
    }
    if cos <= cos_cone {
        return 0.0;
    }
    let (cone, full, angle) = (cos_cone.acos(), cos_full.acos(), cos.clamp(-1.0, 1.0).acos());
    ((cone - angle) / (cone - full)).clamp(0.0, 1.0)
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

    #[test]
    fn mitsubas_profile_is_linear_in_the_angle() {
        let spot = SpotLight::new(Vec3::new(0.0, 1.0, 0.0), -Vec3::Y, Rgb::ONE, Falloff::None, 20.0, 5.0)
            .with_profile(SpotProfile::Linear);
        let at = |degrees: f32| {
            let a = degrees.to_radians();
            spot.illuminate(Vec3::new(a.tan(), 0.0, 0.0)).intensity.x
        };
        assert_eq!(at(10.0), 1.0);
        assert!((at(16.0) - 0.8).abs() < 1e-3 && (at(17.5) - 0.5).abs() < 1e-3, "{} {}", at(16.0), at(17.5));
        assert_eq!(at(20.5), 0.0);
    }

    #[test]
    fn a_slide_is_projected_across_the_cone() {
        // A 2 × 1 image: left half 1, right half 3, across the light's `right` axis.
        let texture = Texture::Image(std::sync::Arc::new(crate::textures::ImageTexture {
            wrap: crate::textures::Wrap::Clamp,
            ..crate::textures::ImageTexture::new(2, 1, vec![Rgb::ONE, Rgb::splat(3.0)])
        }));
        let slide = Slide { texture, right: Vec3::X, up: Vec3::Z };
        let spot = SpotLight::new(Vec3::ZERO, Vec3::Y, Rgb::ONE, Falloff::None, 45.0, 0.0).with_slide(slide);
        // On the axis: uv (½, ½), between the texels. Toward +x at 40°: u = ½ + ½ tan 40° / tan 45°.
        assert!((spot.illuminate(Vec3::Y).intensity.x - 2.0).abs() < 1e-4);
        let toward = |degrees: f32| Vec3::new(degrees.to_radians().tan(), 1.0, 0.0);
        assert!((spot.illuminate(toward(40.0)).intensity.x - 3.0).abs() < 1e-4);
        assert!((spot.illuminate(toward(-40.0)).intensity.x - 1.0).abs() < 1e-4);
    }
}
