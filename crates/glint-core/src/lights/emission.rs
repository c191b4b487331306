//! Lights as sources of particles, for the integrators that trace light forward (light
//! tracing, photon mapping, SPPM): one light chosen in proportion to its power (as next-event
//! estimation chooses it), then a ray leaving it, with the flux the particle carries.
//!
//! Area lights: a point by area, a cosine-weighted direction (`AreaLight::sample_le`). Point
//! lights: a uniform direction; spot lights: uniform in the cone, weighed by its profile.
//! Directional light and the environment (a map or a constant background): a direction drawn
//! as light sampling draws it, then a point on the disk facing it that covers the scene's
//! bounding sphere. Lights with `falloff = "none"` are not physical (their power is
//! unbounded) and are refused.

use glam::{Vec2, Vec3};

use super::{AreaEmission, Falloff, Light, Lights};
use crate::geometry::{offset_ray_origin, orthonormal_basis, Ray};
use crate::sampling::warp::{square_to_disk, square_to_uniform_sphere};
use crate::RenderError;
use crate::Rgb;

/// A particle leaving a light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Particle {
    pub ray: Ray,
    /// The flux it carries: emitted radiance (or intensity) over the densities of its choice,
    /// position and direction. The mean of `weight` over particles is the lights' total power.
    pub weight: Rgb,
    /// Set for particles from area lights: the emission point, which light tracing also
    /// connects to the camera (the light seen directly); its `pdf_area` includes the choice
    /// of the light among all lights.
    pub area: Option<AreaEmission>,
}

impl Lights {
    /// Whether particles can leave these lights: an error if none emits, or one is not
    /// physical.
    pub fn check_particles(&self) -> Result<(), RenderError> {
        for (i, light) in self.all().iter().enumerate() {
            let falloff = match light {
                Light::Point(l) => l.falloff,
                Light::Spot(s) => s.light.falloff,
                _ => continue,
            };
            if falloff == Falloff::None {
                return Err(RenderError::UnphysicalLight { light: i + 1 });
            }
        }
        if !self.emits() {
            return Err(RenderError::NoEmittingLight);
        }
        Ok(())
    }

    /// A particle: `u_select` picks the light, `u_point` a point on it, `u_direction` the
    /// direction. `None` if the choice emits nothing (the particle is then a zero sample).
    pub fn sample_le(&self, u_select: f32, u_point: Vec2, u_direction: Vec2) -> Option<Particle> {
        let (light, probability) = self.choose_for_particle(u_select)?;
        let four_pi = 4.0 * std::f32::consts::PI;
        let (ray, weight) = match light {
            Light::Area(a) => {
                let e = a.sample_le(probability, u_point, u_direction)?;
                let cos = e.direction.dot(e.normal);
                let weight = e.radiance * (cos / (e.pdf_area * e.pdf_direction));
                let origin = offset_ray_origin(e.point, e.error, e.normal, e.direction);
                return Some(Particle { ray: Ray::new(origin, e.direction), weight, area: Some(e) });
            }
            Light::Environment(environment) => {
                // A direction toward it, then a point on the disk that faces it just outside
                // the scene; the particle travels back along the direction.
                let s = environment.sample(u_direction)?;
                let (ray, area) = self.arriving_from(s.direction, u_point);
                return Some(Particle { ray, weight: s.radiance * (area / (s.pdf * probability)), area: None });
            }
            Light::Point(l) => (Ray::new(l.position, square_to_uniform_sphere(u_direction)), l.intensity * four_pi),
            Light::Spot(s) => {
                // A projector's slide: by its brightness (`sample_projection`).
                if let Some((direction, weight)) = s.sample_projection(u_direction) {
                    return Some(Particle {
                        ray: Ray::new(s.light.position, direction),
                        weight: weight / probability,
                        area: None,
                    });
                }
                // Uniform over the cone's solid angle 2π(1 − cos θ_cone); the profile weighs it.
                let cos_cone = s.emission_cos();
                let cos = 1.0 - u_direction.x * (1.0 - cos_cone);
                let sin = (1.0 - cos * cos).max(0.0).sqrt();
                let phi = 2.0 * std::f32::consts::PI * u_direction.y;
                let (t, b) = orthonormal_basis(s.direction);
                let direction = sin * phi.cos() * t + sin * phi.sin() * b + cos * s.direction;
                let intensity = s.illuminate(s.light.position + direction).intensity;
                let solid_angle = 2.0 * std::f32::consts::PI * (1.0 - cos_cone);
                // illuminate() at distance 1 returns the intensity for either falloff.
                (Ray::new(s.light.position, direction), intensity * solid_angle)
            }
            Light::Directional(d) => {
                let (ray, area) = self.arriving_from(-d.direction, u_point);
                (ray, d.intensity * area)
            }
        };
        Some(Particle { ray, weight: weight / probability, area: None })
    }

    /// Light from infinitely far in direction `source` (a unit vector toward it): a ray from a
    /// point uniform on the disk perpendicular to it that covers the scene, just outside it,
    /// travelling back into the scene; and the disk's area.
    fn arriving_from(&self, source: Vec3, u_point: Vec2) -> (Ray, f32) {
        let (t, b) = orthonormal_basis(source);
        let disk = square_to_disk(u_point) * self.scene_radius;
        let origin = self.scene_center + source * self.scene_radius + disk.x * t + disk.y * b;
        (Ray::new(origin, -source), std::f32::consts::PI * self.scene_radius * self.scene_radius)
    }
}
