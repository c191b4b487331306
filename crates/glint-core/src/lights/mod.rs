//! Lights: one closed set, and the scene's lights as one distribution.
//!
//! A `Light` is a point, spot or directional light (delta lights, listed in the scene), an
//! area light (one primitive whose material emits: a triangle, a sphere, any transform of
//! them), or the environment (a map or a constant background). Every light answers the same
//! questions, dispatched by `match` in this file:
//!
//! * `sample_li`: from a shading point, a direction toward the light, where its shadow ray
//!   ends, the radiance arriving and the solid-angle density (next-event estimation, in every
//!   Monte Carlo integrator);
//! * `pdf_li`: that density for a direction found by BSDF sampling (`Lights::pdf_area`,
//!   `Lights::pdf_environment`), for multiple importance sampling;
//! * `sample_le`: a particle leaving the light, for light tracing, photon mapping and SPPM
//!   (`emission.rs`);
//! * its power, by which `Lights` (`set.rs`) chooses one: next-event estimation and particle
//!   emission draw from the same distribution.
//!
//! Adding a light: a file with its struct and `illuminate` (delta) or `sample_li`/`pdf_li`, a
//! variant here with its arm in each `match`, its `sample_le` arm in `emission.rs`.
//!
//! Whitted and ray casting read only the delta lights (`Light::illuminate`): the course's
//! local shading knows no area light.

mod area;
mod directional;
mod emission;
mod environment;
mod point;
mod set;
mod spot;

pub(crate) use area::area_to_solid_angle_lanes;
pub(crate) use area::TriangleEmitter;
pub use area::{AreaEmission, AreaLight, TriangleSampling};
pub use directional::DirectionalLight;
pub use emission::Particle;
pub use environment::{Environment, EnvironmentMap, EnvironmentSample};
pub use point::{Falloff, PointLight};
pub use set::{LightSelection, Lights};
pub use spot::{Slide, SpotLight, SpotProfile};

use glam::{Vec2, Vec3};

use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    Point(PointLight),
    Directional(DirectionalLight),
    Spot(SpotLight),
    /// One emitting primitive; `Lights` finds them from the scene's materials.
    Area(AreaLight),
    /// The environment, when light arrives from outside the scene.
    Environment(Environment),
}

/// What a delta light sends to a point: the course's local shading reads it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Illumination {
    pub direction: Vec3,
    pub distance: f32,
    pub intensity: Rgb,
}

/// Where a shadow ray toward a sampled light ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightEnd {
    /// A point on an emitting surface, with its normal and error bound: the ray's far end is
    /// offset off that surface.
    Surface { point: Vec3, normal: Vec3, error: Vec3 },
    /// A point light's position.
    Point(Vec3),
    /// Infinitely far (directional light, environment): the ray leaves the scene.
    Infinite,
}

/// A light sampled from a shading point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Unit direction from the shading point toward the light.
    pub direction: Vec3,
    pub end: LightEnd,
    /// Radiance arriving along `direction` (for a delta light, its intensity at the point; 0
    /// from an emitter's back).
    pub radiance: Rgb,
    /// Solid-angle density, including the light's selection probability; for a delta light,
    /// the selection probability alone.
    pub pdf: f32,
    /// A delta light: no BSDF sample can find it, so it is not weighed against one.
    pub delta: bool,
}

/// How a light is asked to sample itself: its selection probability, which its density
/// includes, and the strategy for triangles.
#[derive(Clone, Copy, Debug)]
struct Asked {
    selection: f32,
    triangle_sampling: TriangleSampling,
}

impl Light {
    pub fn kind(&self) -> &'static str {
        match self {
            Light::Point(_) => "point",
            Light::Directional(_) => "directional",
            Light::Spot(_) => "spot",
            Light::Area(_) => "area",
            Light::Environment(_) => "environment",
        }
    }

    /// Point, spot or directional: only light sampling finds it.
    pub fn is_delta(&self) -> bool {
        matches!(self, Light::Point(_) | Light::Directional(_) | Light::Spot(_))
    }

    /// What a delta light sends to `point` (`None` for area lights and the environment, which
    /// the course's local shading does not read).
    pub fn illuminate(&self, point: Vec3) -> Option<Illumination> {
        match self {
            Light::Point(l) => Some(l.illuminate(point)),
            Light::Directional(l) => Some(l.illuminate()),
            Light::Spot(l) => Some(l.illuminate(point)),
            Light::Area(_) | Light::Environment(_) => None,
        }
    }

    /// Where a shadow ray toward a delta light ends: its position, or `None` at infinity.
    pub fn position(&self) -> Option<Vec3> {
        match self {
            Light::Point(l) => Some(l.position),
            Light::Spot(l) => Some(l.light.position),
            Light::Directional(_) | Light::Area(_) | Light::Environment(_) => None,
        }
    }

    /// Emitted power over π (flux / π, mean over RGB), by which `Lights` chooses among lights;
    /// `radius` is the scene's bounding sphere's, over which light from infinity is counted.
    /// Over π so an area light's share is L·A·sides over the sum, the form its selection had
    /// before the other lights joined the distribution.
    fn power_over_pi(&self, radius: f32) -> f32 {
        let mean = |c: Rgb| c.dot(Rgb::splat(1.0 / 3.0));
        match self {
            Light::Point(l) => 4.0 * mean(l.intensity),
            Light::Spot(s) => s.power_over_pi(),
            Light::Directional(d) => radius * radius * mean(d.intensity),
            Light::Area(a) => a.power_over_pi(),
            Light::Environment(e) => radius * radius * e.radiance_integral() * std::f32::consts::FRAC_1_PI,
        }
    }

    /// The light seen from `from` (with the receiver's shading normal, which triangles sampled
    /// by solid angle follow): `u` picks the point on it.
    fn sample_li(&self, from: Vec3, receiver: Option<Vec3>, u: Vec2, asked: Asked) -> Option<LightSample> {
        let delta = |illumination: Illumination, end: LightEnd| LightSample {
            direction: illumination.direction,
            end,
            radiance: illumination.intensity,
            pdf: asked.selection,
            delta: true,
        };
        match self {
            Light::Point(l) => Some(delta(l.illuminate(from), LightEnd::Point(l.position))),
            Light::Spot(l) => Some(delta(l.illuminate(from), LightEnd::Point(l.light.position))),
            Light::Directional(l) => Some(delta(l.illuminate(), LightEnd::Infinite)),
            Light::Area(a) => a.sample_li(from, receiver, u, asked),
            Light::Environment(e) => {
                let s = e.sample(u)?;
                Some(LightSample {
                    direction: s.direction,
                    end: LightEnd::Infinite,
                    radiance: s.radiance,
                    pdf: s.pdf * asked.selection,
                    delta: false,
                })
            }
        }
    }
}
