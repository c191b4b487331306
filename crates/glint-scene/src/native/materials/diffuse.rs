//! Lambertian materials: `diffuse` (two-sided unless told, optionally emitting) and
//! `diffuse-transmission` (reflecting and transmitting diffusely).

use glint_core::materials::{Diffuse, DiffuseTransmission, Material};

use super::parameters::{sided, Parameters};
use crate::error::SceneError;
use crate::native::schema::MaterialDesc;

pub(super) fn diffuse(p: &Parameters, desc: &MaterialDesc) -> Result<Material, SceneError> {
    let MaterialDesc::Diffuse { reflectance, emission, two_sided_emission, two_sided } = desc else {
        unreachable!("diffuse is given a diffuse description")
    };
    let diffuse = Material::Diffuse(Diffuse { reflectance: p.colour("reflectance", reflectance, 0.8)? });
    p.emitting(sided(diffuse, two_sided), emission.as_ref().map(|e| ("emission", e)), *two_sided_emission)
}

pub(super) fn diffuse_transmission(p: &Parameters, desc: &MaterialDesc) -> Result<Material, SceneError> {
    let MaterialDesc::DiffuseTransmission { reflectance, transmittance } = desc else {
        unreachable!("diffuse_transmission is given a diffuse-transmission description")
    };
    Ok(Material::DiffuseTransmission(DiffuseTransmission {
        reflectance: p.colour("reflectance", reflectance, 0.25)?,
        transmittance: p.colour("transmittance", transmittance, 0.25)?,
    }))
}
