//! Materials: how a surface answers light. The closed set is an enum dispatched per hit; a
//! material evaluated at a hit is a small value on the stack.
//!
//! Conventions: colours are linear RGB; directions given to a material point *away* from the
//! surface (`wo` toward the viewer, `wi` toward the light), and the normal has been turned to
//! the viewer's side by the integrator.

mod bsdf;
mod conductor;
mod ggx;
mod phong;

pub(crate) use bsdf::luminance;
pub use bsdf::{Bsdf, BsdfSample};
pub use conductor::{fresnel_conductor, named_metal, METAL_NAMES};
pub use ggx::Ggx;
pub use phong::{fresnel_dielectric, fresnel_schlick, Fresnel, Phong, PhongPoint};

use crate::textures::TextureQuery;

#[derive(Clone, Debug, PartialEq)]
pub enum Material {
    Phong(Phong),
}

impl Material {
    /// The material's values at a point, for the course's local model and Whitted's recursion.
    pub fn evaluate(&self, query: &TextureQuery) -> PhongPoint {
        match self {
            Material::Phong(p) => p.evaluate(query),
        }
    }
}
