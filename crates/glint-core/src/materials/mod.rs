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

    /// A warning if the material passes on more light than it receives somewhere, per channel:
    /// k_d + k_r + k_t above 1 (the lobes the Monte Carlo integrators choose among), or
    /// k_r + k_t above 1 (the weights of Whitted's child rays). The Phong highlight k_s is left
    /// out: only the local model reads it, and it does not recurse.
    pub fn energy_warning(&self, name: &str) -> Option<String> {
        let Material::Phong(p) = self;
        let (diffuse, reflection, transmission) =
            (p.diffuse.max_value(), p.reflection.max_value(), p.transmission.max_value());
        let all = (diffuse + reflection + transmission).max_element();
        let children = (reflection + transmission).max_element();
        if all <= 1.0 {
            return None;
        }
        let whitted = if children > 1.0 {
            format!("Whitted's child rays gain weight at each surface (k_r + k_t = {children}), so no `min_contribution` ends a tree through it: depth and the ray ceilings do")
        } else {
            "Whitted's recursion still loses weight at each surface (k_r + k_t ≤ 1)".to_string()
        };
        Some(format!(
            "material `{name}` passes on more light than it receives (k_d + k_r + k_t = {all} on some channel): the path tracers, light tracing and photon mapping follow it as given, so each bounce off it adds light and pixel values can grow without bound (Russian roulette survives at most 0.95 a bounce); {whitted}. Keep k_d + k_r + k_t ≤ 1 on every channel"
        ))
    }
}
