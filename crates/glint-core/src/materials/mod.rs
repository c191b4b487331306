//! Materials: how a surface answers light. The closed set is an enum dispatched per hit.
//!
//! Conventions: colours are linear RGB; directions given to a material point *away* from the
//! surface (`wo` toward the viewer, `wi` toward the light), and the normal has been turned to
//! the viewer's side by the integrator.

mod phong;

pub use phong::Phong;

use crate::Rgb;
use glam::Vec3;

#[derive(Clone, Debug, PartialEq)]
pub enum Material {
    Phong(Phong),
}

impl Material {
    /// The ambient reflectance k_a (what the course's ambient term multiplies).
    pub fn ambient(&self) -> Rgb {
        match self {
            Material::Phong(p) => p.ambient,
        }
    }

    /// The local reflection of one light: k_d (N·L) + k_s (R·V)^n, times the light's intensity.
    pub fn local(&self, normal: Vec3, wo: Vec3, wi: Vec3, intensity: Rgb) -> Rgb {
        match self {
            Material::Phong(p) => p.local(normal, wo, wi, intensity),
        }
    }
}
