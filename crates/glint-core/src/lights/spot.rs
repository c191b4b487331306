//! Spot light: a point light limited to a cone, with a soft edge, optionally projecting a
//! texture (a slide).
//!
//! Scene parameters: `position` (point), `direction` (the cone's axis, where the light points),
//! `cone_angle` (half-angle of the cone in degrees, default 30), `edge` (width in degrees of
//! the soft edge inside the cone, default 5), `profile` (`"smooth"`, default, `"linear"` or
//! `"projector"`),
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
//! The `projector` profile is Mitsuba's `projector`: the slide is the irradiance the light
//! casts on a plane at unit distance across its axis, so the intensity is π·E(uv)/cos³θ inside
//! the slide's frame (uv in [0, 1]², half-width tan cone_angle at unit distance, half-height
//! that over the image's aspect) and nothing outside it; `edge` plays no part.
//! A texture multiplies the intensity by its value at the direction's position on the slide:
//! with d in the light's frame (x, y across the beam, z along it),
//! uv = ½ + ½ (d_x, d_y) / (d_z tan cone_angle), Mitsuba's projection.

use glam::{Vec2, Vec3};

use super::{Falloff, Illumination, PointLight};
use crate::sampling::distribution::Distribution2D;
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
    /// For a slide that is an image: where its light leaves, over the slide's uv square, by
    /// the texels' brightness (each cell the brightest texel within one of it, since the
    /// bilinear lookup reaches half a texel past its own), for light tracing and photons.
    emission: Option<Box<Distribution2D>>,
}

/// How the intensity fades across the edge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SpotProfile {
    /// A smoothstep of the cosine (pbrt-v4).
    #[default]
    Smooth,
    /// Linear in the angle from the axis (Mitsuba).
    Linear,
    /// A slide projector (Mitsuba's `projector`): π/cos³θ within the slide's square frustum.
    Projector,
}

/// A texture projected by a spot light.
#[derive(Clone, Debug, PartialEq)]
pub struct Slide {
    pub texture: Texture,
    /// The slide's axes in world space: u grows along `right`, v along `up`.
    pub right: Vec3,
    pub up: Vec3,
    /// Width over height of the slide's frame: v spans 1/aspect of what u spans (1 for a
    /// spot, whose slide is square; a projector's image keeps its proportions).
    pub aspect: f32,
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
            emission: None,
        }
    }

    pub fn with_profile(self, profile: SpotProfile) -> Self {
        Self { profile, ..self }.with_emission()
    }

    pub fn with_slide(self, slide: Slide) -> Self {
        Self { slide: Some(Box::new(slide)), ..self }.with_emission()
    }

    /// The slide's emission density, made for a projector with an image only (a spot's
    /// particles go uniformly over its cone: no density to make, for a slide of any size).
    fn with_emission(self) -> Self {
        let emission = match (&self.slide, self.profile) {
            (Some(slide), SpotProfile::Projector) => slide_distribution(&slide.texture).map(Box::new),
            _ => None,
        };
        Self { emission, ..self }
    }

    /// A direction a projector sends light along, through its slide's frame, and the
    /// particle's weight: intensity over the density of the direction. The frame's point is
    /// drawn by the slide's brightness (uniformly for a slide that is no image) rather than
    /// uniformly over the cone around the frame: at unit distance dω = cos³θ dA, so the
    /// projector's π·E/cos³θ over a density p(uv)/(A·cos³θ) leaves π·E·A/p, which the
    /// brightness makes nearly constant, and no direction is lost outside the frame. `None`
    /// for another profile or a projector without a slide (uniform over the cone then).
    pub fn sample_projection(&self, u: Vec2) -> Option<(Vec3, Rgb)> {
        let slide = self.slide.as_ref().filter(|_| self.profile == SpotProfile::Projector)?;
        let (uv, pdf) = match &self.emission {
            Some(distribution) => distribution.sample(u),
            None => (u, 1.0),
        };
        if pdf <= 0.0 {
            return Some((self.direction, Rgb::ZERO));
        }
        // The inverse of `illuminate`'s projection: uv = ½ + ½ (x, aspect·y) / tan at unit
        // distance along the axis.
        let tan_cone = self.tan_cone();
        let across = (2.0 * uv - Vec2::ONE) * tan_cone;
        let on_slide = self.direction + across.x * slide.right + (across.y / slide.aspect) * slide.up;
        let direction = on_slide.normalize();
        let cos = direction.dot(self.direction);
        let frame_area = 4.0 * tan_cone * tan_cone / slide.aspect;
        // `illuminate` at unit distance is the intensity for either falloff.
        let intensity = self.illuminate(self.light.position + direction).intensity;
        Some((direction, intensity * (cos * cos * cos * frame_area / pdf)))
    }

    pub fn illuminate(&self, point: Vec3) -> Illumination {
        let mut illumination = self.light.illuminate(point);
        let outward = -illumination.direction;
        let cos = outward.dot(self.direction);
        illumination.intensity *= match self.profile {
            SpotProfile::Smooth => smoothstep(self.cos_cone, self.cos_full, cos),
            SpotProfile::Linear => linear_in_angle(self.cos_cone, self.cos_full, cos),
            SpotProfile::Projector if cos > 0.0 => std::f32::consts::PI / (cos * cos * cos),
            SpotProfile::Projector => 0.0,
        };
        if let Some(slide) = &self.slide {
            if cos > 0.0 {
                let tan_cone = self.tan_cone();
                let across =
                    Vec2::new(outward.dot(slide.right), slide.aspect * outward.dot(slide.up)) / (cos * tan_cone);
                let uv = Vec2::splat(0.5) + 0.5 * across;
                if self.profile == SpotProfile::Projector && !(uv.cmpge(Vec2::ZERO).all() && uv.cmple(Vec2::ONE).all())
                {
                    illumination.intensity = Rgb::ZERO;
                    return illumination;
                }
                illumination.intensity *= slide.texture.evaluate(&TextureQuery { uv, ..Default::default() });
            }
        }
        illumination
    }

    /// tan of the cone's half-angle: the slide's half-width at unit distance.
    fn tan_cone(&self) -> f32 {
        (1.0 - self.cos_cone * self.cos_cone).max(0.0).sqrt() / self.cos_cone
    }

    /// The cosine of the cone its light leaves within: the cone itself, or for a projector
    /// the cone around the slide's frame (through its corners).
    pub fn emission_cos(&self) -> f32 {
        if self.profile != SpotProfile::Projector {
            return self.cos_cone;
        }
        let tan_cone = self.tan_cone();
        let aspect = self.slide.as_ref().map_or(1.0, |s| s.aspect);
        let corner = tan_cone * tan_cone * (1.0 + 1.0 / (aspect * aspect));
        (1.0 + corner).sqrt().recip()
    }

    /// The power over π: ∫ I dω / π. A projector sends π·E over the slide's frame, 2 tan θ
    /// by 2 tan θ / aspect at unit distance (dω = cos³θ dA there), so its power over π is that
    /// area times the slide's mean; the others integrate their profile over the cone, the soft
    /// edge counted half.
    pub fn power_over_pi(&self) -> f32 {
        let mean = |c: Rgb| c.dot(Rgb::splat(1.0 / 3.0));
        if self.profile == SpotProfile::Projector {
            let tan_cone = self.tan_cone();
            let (slide, aspect) = self.slide.as_ref().map_or((Rgb::ONE, 1.0), |s| (s.texture.mean_value(), s.aspect));
            return 4.0 * tan_cone * tan_cone / aspect * mean(self.light.intensity * slide);
        }
        2.0 * mean(self.light.intensity) * (1.0 - 0.5 * (self.cos_full + self.cos_cone))
    }
}

/// The density a projector's light leaves with over its slide's uv square (v up, as the
/// slide's rows are read bottom row first), when the slide is an image read through the
/// identity uv map; `None` otherwise (then uniform). Each cell holds the brightest texel
/// within one of it, so the density is positive wherever the bilinear lookup can be.
fn slide_distribution(texture: &Texture) -> Option<Distribution2D> {
    let Texture::Image(image) = texture else { return None };
    if image.uv_transform != glam::Affine2::IDENTITY {
        return None;
    }
    let (width, height) = (image.width as i64, image.height as i64);
    let brightness = |x: i64, y: i64| crate::textures::luminance(image.texel(x, y)).max(0.0);
    let mut cells = Vec::with_capacity((width * height) as usize);
    // Distribution rows run up from v = 0, the image's rows down from its top.
    for row in (0..height).rev() {
        for column in 0..width {
            let mut brightest = 0.0f32;
            for dy in -1..=1 {
                for dx in -1..=1 {
                    brightest = brightest.max(brightness(column + dx, row + dy));
                }
            }
            cells.push(brightest);
        }
    }
    cells.iter().any(|&c| c > 0.0).then(|| Distribution2D::new(&cells, width as usize, height as usize))
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
        let slide = Slide { texture, right: Vec3::X, up: Vec3::Z, aspect: 1.0 };
        let spot = SpotLight::new(Vec3::ZERO, Vec3::Y, Rgb::ONE, Falloff::None, 45.0, 0.0).with_slide(slide);
        // On the axis: uv (½, ½), between the texels. Toward +x at 40°: u = ½ + ½ tan 40° / tan 45°.
        assert!((spot.illuminate(Vec3::Y).intensity.x - 2.0).abs() < 1e-4);
        let toward = |degrees: f32| Vec3::new(degrees.to_radians().tan(), 1.0, 0.0);
        assert!((spot.illuminate(toward(40.0)).intensity.x - 3.0).abs() < 1e-4);
        assert!((spot.illuminate(toward(-40.0)).intensity.x - 1.0).abs() < 1e-4);
    }

    /// A projector of half-angle 30° and aspect 2 down −z from the origin (no falloff, so
    /// `illuminate` is the intensity): π·E/cos³θ inside x ∈ ±tan 30°, y ∈ ±tan 30°/2 at unit
    /// distance, nothing outside, the slide's texels where Mitsuba puts them (Mitsuba 3.9's
    /// `projector` gives the same, measured from Python); its emission cone holds the frame's
    /// corners, and its power is the integral of its intensity over the sphere.
    #[test]
    fn a_projector_lights_its_frame_with_irradiance() {
        let texture = Texture::Image(std::sync::Arc::new(crate::textures::ImageTexture {
            filter: crate::textures::TexelFilter::Nearest,
            ..crate::textures::ImageTexture::new(2, 1, vec![Rgb::ONE, Rgb::splat(3.0)])
        }));
        let slide = Slide { texture, right: Vec3::X, up: Vec3::Y, aspect: 2.0 };
        let projector = SpotLight::new(Vec3::ZERO, -Vec3::Z, Rgb::ONE, Falloff::None, 30.0, 0.0)
            .with_profile(SpotProfile::Projector)
            .with_slide(slide);
        let t = 30f32.to_radians().tan();
        let seen = |x: f32, y: f32| {
            let d = Vec3::new(x, y, -1.0);
            let cos = 1.0 / d.length();
            projector.illuminate(d).intensity.x * cos * cos * cos / std::f32::consts::PI
        };
        assert!((seen(-0.3 * t, 0.0) - 1.0).abs() < 1e-5 && (seen(0.3 * t, 0.2 * t) - 3.0).abs() < 1e-5);
        assert!((seen(0.99 * t, 0.49 * t) - 3.0).abs() < 1e-5, "a corner is lit");
        assert_eq!([seen(1.01 * t, 0.0), seen(0.0, 0.51 * t), seen(-0.2, -0.51 * t)], [0.0; 3]);
        assert_eq!(projector.illuminate(Vec3::Z).intensity, Rgb::ZERO, "nothing behind");
        let corner = Vec3::new(t, 0.5 * t, -1.0).normalize();
        assert!((corner.dot(-Vec3::Z) - projector.emission_cos()).abs() < 1e-6);
        // ∫ I dω by the midpoint rule over the emission cone, in (cos θ, φ).
        let (n, cos_min) = (600, projector.emission_cos());
        let mut integral = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let cos = cos_min + (1.0 - cos_min) * (i as f32 + 0.5) / n as f32;
                let phi = 2.0 * std::f32::consts::PI * (j as f32 + 0.5) / n as f32;
                let sin = (1.0 - cos * cos).sqrt();
                let d = Vec3::new(sin * phi.cos(), sin * phi.sin(), -cos);
                integral += projector.illuminate(d).intensity.x as f64;
            }
        }
        integral *= (2.0 * std::f64::consts::PI * (1.0 - cos_min as f64)) / (n * n) as f64;
        // The frame is 2t × t at unit distance, its texels' mean 2: power π·(2t²)·2.
        let expected = std::f64::consts::PI * projector.power_over_pi() as f64;
        assert!((projector.power_over_pi() - 4.0 * t * t).abs() < 1e-5);
        assert!((integral / expected - 1.0).abs() < 0.01, "{integral} vs {expected}");
    }

    /// A projector's particles leave through its slide's frame, drawn by its brightness: a
    /// constant slide's weights are all its power; an image with dark texels (repeated, so
    /// the bilinear lookup wraps) is sampled where it is lit, and the weights' mean over the
    /// frame, and over its right half, is the integral of the intensity there (a midpoint
    /// rule over the frame at unit distance, dω = cos³θ dA).
    #[test]
    fn a_projectors_particles_follow_its_slide() {
        let projector = |texture: Texture| {
            let slide = Slide { texture, right: Vec3::X, up: Vec3::Y, aspect: 2.0 };
            SpotLight::new(Vec3::new(0.5, 1.0, 2.0), -Vec3::Z, Rgb::splat(1.5), Falloff::InverseSquare, 30.0, 0.0)
                .with_profile(SpotProfile::Projector)
                .with_slide(slide)
        };
        let constant = projector(Texture::Constant(Rgb::new(1.0, 2.0, 0.5)));
        let power = std::f32::consts::PI * constant.power_over_pi();
        for (i, j) in [(0, 0), (3, 7), (9, 9), (5, 2)] {
            let u = Vec2::new(i as f32 + 0.5, j as f32 + 0.5) / 10.0;
            let (direction, weight) = constant.sample_projection(u).expect("a projector with a slide");
            assert!(direction.dot(-Vec3::Z) >= constant.emission_cos() - 1e-6, "outside the cone");
            assert!((weight.dot(Rgb::splat(1.0 / 3.0)) / power - 1.0).abs() < 1e-4, "{weight} vs {power}");
        }
        let texels = [0.0, 0.0, 5.0, 0.0, 1.0, 0.0, 0.0, 2.0].map(Rgb::splat).to_vec();
        let image = projector(Texture::Image(std::sync::Arc::new(crate::textures::ImageTexture::new(4, 2, texels))));
        let t = 30f32.to_radians().tan();
        let intensity = |d: Vec3| image.illuminate(image.light.position + d).intensity.x as f64;
        // The reference: the frame is 2t wide, t high at unit distance.
        let (n, mut whole, mut right) = (800, 0.0f64, 0.0f64);
        for i in 0..n {
            for j in 0..n {
                let (x, y) = ((i as f32 + 0.5) / n as f32 * 2.0 - 1.0, (j as f32 + 0.5) / n as f32 * 2.0 - 1.0);
                let d = Vec3::new(x * t, y * t / 2.0, -1.0);
                let cos = 1.0 / d.length() as f64;
                let value = intensity(d.normalize()) * cos * cos * cos * (2.0 * t as f64 * t as f64) / (n * n) as f64;
                whole += value;
                if x > 0.0 {
                    right += value;
                }
            }
        }
        let (m, mut sampled_whole, mut sampled_right) = (512, 0.0f64, 0.0f64);
        for i in 0..m {
            for j in 0..m {
                let u = Vec2::new((i as f32 + 0.5) / m as f32, (j as f32 + 0.5) / m as f32);
                let (direction, weight) = image.sample_projection(u).expect("a projector with a slide");
                assert!(weight.x > 0.0 || intensity(direction) == 0.0, "a lit direction drawn with no weight");
                sampled_whole += weight.x as f64;
                if direction.x > 0.0 {
                    sampled_right += weight.x as f64;
                }
            }
        }
        let (sampled_whole, sampled_right) = (sampled_whole / (m * m) as f64, sampled_right / (m * m) as f64);
        assert!((sampled_whole / whole - 1.0).abs() < 0.01, "{sampled_whole} vs {whole}");
        assert!((sampled_right / right - 1.0).abs() < 0.01, "{sampled_right} vs {right}");
        // And the texels' mean is the power (a repeated image's bilinear mean is its mean).
        assert!((whole / (std::f64::consts::PI * image.power_over_pi() as f64) - 1.0).abs() < 0.01);
    }
}
