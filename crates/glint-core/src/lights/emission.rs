//! Lights as sources of particles, for the integrators that trace light forward (light
//! tracing, photon mapping, SPPM): one light chosen in proportion to its power, then a ray
//! leaving it, with the flux the particle carries.
//!
//! Powers (mean over RGB): area light L_e·π·A (twice that if two-sided), point light 4π·I,
//! spot light 2π·I·(1 − (cos θ_full + cos θ_cone)/2) (the smooth edge counted half), directional
//! light E·π·R² over a disk that covers the scene's bounding sphere of radius R, and the
//! environment (a map or a constant background) π·R²·∫L dω: a direction drawn as light
//! sampling draws it, then a point on the disk facing it. Lights with `falloff = "none"` are
//! not physical (their power is unbounded) and are refused.

use glam::{Vec2, Vec3};

use super::{AreaEmission, Falloff, Light};
use crate::geometry::{offset_ray_origin, orthonormal_basis, Ray};
use crate::sampling::warp::{square_to_disk, square_to_uniform_sphere};
use crate::scene::Scene;
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

/// All lights of a scene as one distribution over particles.
#[derive(Clone, Debug)]
pub struct ParticleSource {
    /// Cumulative selection probabilities: the scene's `lights` in order, then the environment,
    /// then the area lights as one group (they choose among themselves by power).
    cdf: Vec<f32>,
    scene_center: Vec3,
    scene_radius: f32,
    total_power: f32,
}

impl ParticleSource {
    /// The lights of `scene`; an error if it has none that emit, or one that is not physical.
    pub fn new(scene: &Scene) -> Result<Self, String> {
        let bounds = scene.geometry.bounds();
        let (scene_center, scene_radius) =
            if bounds.is_empty() { (Vec3::ZERO, 1.0) } else { (bounds.centroid(), 0.5 * bounds.extent().length()) };
        let mut powers = Vec::with_capacity(scene.lights.len() + 1);
        for (i, light) in scene.lights.iter().enumerate() {
            let mean = |c: Rgb| c.dot(Rgb::splat(1.0 / 3.0));
            let power = match light {
                Light::Point(l) => {
                    check_falloff(l.falloff, i)?;
                    4.0 * std::f32::consts::PI * mean(l.intensity)
                }
                Light::Spot(s) => {
                    check_falloff(s.light.falloff, i)?;
                    2.0 * std::f32::consts::PI * mean(s.light.intensity) * (1.0 - 0.5 * (s.cos_full + s.cos_cone))
                }
                Light::Directional(d) => std::f32::consts::PI * scene_radius * scene_radius * mean(d.intensity),
            };
            powers.push(power);
        }
        let disk = std::f32::consts::PI * scene_radius * scene_radius;
        powers.push(if scene.environment.emits() { disk * scene.environment.radiance_integral() } else { 0.0 });
        powers.push(scene.area_lights.total_power());
        let total_power: f32 = powers.iter().sum();
        if total_power.is_nan() || total_power <= 0.0 {
            return Err(
                "the scene has no light that emits (light tracing and photon mapping start at the lights)".into()
            );
        }
        let mut cdf = Vec::with_capacity(powers.len());
        let mut acc = 0.0;
        for p in powers {
            acc += p / total_power;
            cdf.push(acc);
        }
        *cdf.last_mut().expect("at least the area group") = 1.0;
        Ok(Self { cdf, scene_center, scene_radius, total_power })
    }

    /// The lights' total emitted power (mean over RGB).
    pub fn total_power(&self) -> f32 {
        self.total_power
    }

    /// A particle: `u_select` picks the light, `u_point` a point on it, `u_direction` the
    /// direction. `None` if the choice emits nothing (the particle is then a zero sample).
    pub fn sample(&self, scene: &Scene, u_select: f32, u_point: Vec2, u_direction: Vec2) -> Option<Particle> {
        let i = self.cdf.partition_point(|&c| c <= u_select).min(self.cdf.len() - 1);
        let lower = if i == 0 { 0.0 } else { self.cdf[i - 1] };
        let probability = self.cdf[i] - lower;
        if probability <= 0.0 {
            return None;
        }
        if i == scene.lights.len() {
            // The environment: a direction toward it, then a point on the disk that faces it
            // just outside the scene; the particle travels back along the direction.
            let s = scene.environment.sample(u_direction)?;
            let (ray, area) = self.arriving_from(s.direction, u_point);
            let weight = s.radiance * (area / (s.pdf * probability));
            return Some(Particle { ray, weight, area: None });
        }
        let Some(light) = scene.lights.get(i) else {
            // The area group: rescale u_select to reuse it for the emitter choice.
            let u = ((u_select - lower) / probability).clamp(0.0, 1.0 - f32::EPSILON);
            let mut e = scene.area_lights.sample_emission(u, u_point, u_direction)?;
            e.pdf_area *= probability;
            let cos = e.direction.dot(e.normal);
            let weight = e.radiance * (cos / (e.pdf_area * e.pdf_direction));
            let origin = offset_ray_origin(e.point, e.error, e.normal, e.direction);
            return Some(Particle { ray: Ray::new(origin, e.direction), weight, area: Some(e) });
        };
        let four_pi = 4.0 * std::f32::consts::PI;
        let (ray, weight) = match light {
            Light::Point(l) => (Ray::new(l.position, square_to_uniform_sphere(u_direction)), l.intensity * four_pi),
            Light::Spot(s) => {
                // Uniform over the cone's solid angle 2π(1 − cos θ_cone); the profile weighs it.
                let cos = 1.0 - u_direction.x * (1.0 - s.cos_cone);
                let sin = (1.0 - cos * cos).max(0.0).sqrt();
                let phi = 2.0 * std::f32::consts::PI * u_direction.y;
                let (t, b) = orthonormal_basis(s.direction);
                let direction = sin * phi.cos() * t + sin * phi.sin() * b + cos * s.direction;
                let intensity = s.illuminate(s.light.position + direction).intensity;
                let solid_angle = 2.0 * std::f32::consts::PI * (1.0 - s.cos_cone);
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
}

impl ParticleSource {
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

fn check_falloff(falloff: Falloff, index: usize) -> Result<(), String> {
    match falloff {
        Falloff::InverseSquare => Ok(()),
        Falloff::None => Err(format!(
            "light {} has falloff = \"none\", which no physical light has; light tracing, photon mapping and SPPM need falloff = \"inverse-square\"",
            index + 1
        )),
    }
}
