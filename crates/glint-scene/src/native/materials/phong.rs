//! The course's materials: `phong` (diffuse, ambient and specular lobes with mirror
//! reflection and refraction, a Fresnel choice and optional emission) and `metal` (a Phong
//! surface that reflects as a conductor of the given η and k).

use glint_core::materials::{Fresnel, Material, Phong};
use glint_core::textures::Texture;
use glint_core::Rgb;

use super::parameters::Parameters;
use crate::error::SceneError;
use crate::native::build::{non_negative, positive};
use crate::native::schema::{FresnelDesc, MaterialDesc};

/// The course's material, every Phong parameter checked.
pub(super) fn phong(p: &Parameters, desc: &MaterialDesc) -> Result<Material, SceneError> {
    let MaterialDesc::Phong {
        diffuse,
        ambient,
        specular,
        shininess,
        reflection,
        transmission,
        ior,
        fresnel,
        roughness,
        emission,
        two_sided_emission,
    } = desc
    else {
        unreachable!("phong is given a phong description")
    };
    let mut phong = Phong::default();
    if let Some(r) = roughness {
        if !(0.0..=1.0).contains(r) {
            return Err(p.at("roughness", format!("`roughness` must be between 0 and 1, got {r}")));
        }
        phong.roughness = *r;
    }
    if let Some(e) = emission {
        phong.emission = non_negative(*e).map_err(|m| p.at("emission", m))?;
    }
    phong.two_sided_emission = *two_sided_emission;
    if diffuse.is_some() {
        phong.diffuse = p.colour("diffuse", diffuse, 0.0)?;
    }
    if ambient.is_some() {
        phong.ambient = Some(p.colour("ambient", ambient, 0.0)?);
    }
    if specular.is_some() {
        phong.specular = p.colour("specular", specular, 0.0)?;
    }
    if reflection.is_some() {
        phong.reflection = p.colour("reflection", reflection, 0.0)?;
    }
    if transmission.is_some() {
        phong.transmission = p.colour("transmission", transmission, 0.0)?;
    }
    if let Some(n) = shininess {
        if !(n.is_finite() && *n >= 0.0) {
            return Err(p.at("shininess", format!("`shininess` must be a finite number ≥ 0, got {n}")));
        }
        phong.shininess = *n;
    }
    if let Some(eta) = ior {
        positive(*eta).map_err(|m| p.at("ior", format!("`ior` {m}")))?;
        phong.ior = *eta;
    }
    phong.fresnel = match fresnel {
        FresnelDesc::None => Fresnel::None,
        FresnelDesc::Schlick => Fresnel::Schlick,
        FresnelDesc::Exact => Fresnel::Exact,
    };
    Ok(Material::Phong(phong))
}

/// A metal as the course's material: no diffuse or ambient light, a tinted mirror (blurred
/// by `roughness`) with a conductor's Fresnel term.
pub(super) fn metal(p: &Parameters, desc: &MaterialDesc) -> Result<Material, SceneError> {
    let MaterialDesc::Metal { metal: m, eta, k, tint, roughness } = desc else {
        unreachable!("metal is given a metal description")
    };
    let (eta, k) = p.metal(m, eta, k)?;
    let roughness = roughness.unwrap_or(0.0);
    if !(0.0..=1.0).contains(&roughness) {
        return Err(p.at("roughness", format!("`roughness` must be between 0 and 1, got {roughness}")));
    }
    Ok(Material::Phong(Phong {
        diffuse: Texture::Constant(Rgb::ZERO),
        ambient: Some(Texture::Constant(Rgb::ZERO)),
        reflection: p.colour("tint", tint, 1.0)?,
        fresnel: Fresnel::Conductor { eta, k },
        roughness,
        ..Phong::default()
    }))
}
