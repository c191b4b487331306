//! Metals: `conductor` (a smooth mirror with a conductor's Fresnel term) and
//! `rough-conductor` (a microfacet conductor, isotropic or anisotropic, widths that may be
//! textures); both two-sided unless told.

use glint_core::materials::{Conductor, Material, RoughConductor};

use super::parameters::{sided, Parameters};
use crate::error::SceneError;
use crate::native::schema::MaterialDesc;

pub(super) fn conductor(p: &Parameters, desc: &MaterialDesc) -> Result<Material, SceneError> {
    let MaterialDesc::Conductor { metal: m, eta, k, specular_reflectance, two_sided } = desc else {
        unreachable!("conductor is given a conductor description")
    };
    let (eta, k) = p.metal(m, eta, k)?;
    let specular = p.colour("specular_reflectance", specular_reflectance, 1.0)?;
    Ok(sided(Material::Conductor(Conductor { eta, k, specular }), two_sided))
}

pub(super) fn rough_conductor(p: &Parameters, desc: &MaterialDesc) -> Result<Material, SceneError> {
    let MaterialDesc::RoughConductor {
        metal: m,
        eta,
        k,
        specular_reflectance,
        alpha,
        alpha_u,
        alpha_v,
        distribution: d,
        two_sided,
    } = desc
    else {
        unreachable!("rough_conductor is given a rough-conductor description")
    };
    let (eta, k) = p.metal(m, eta, k)?;
    let specular = p.colour("specular_reflectance", specular_reflectance, 1.0)?;
    let (alpha_u, alpha_v) = p.textured_widths(alpha, alpha_u, alpha_v)?;
    let conductor = Conductor { eta, k, specular };
    let distribution = p.distribution(d)?;
    Ok(sided(Material::RoughConductor(RoughConductor { conductor, alpha_u, alpha_v, distribution }), two_sided))
}
