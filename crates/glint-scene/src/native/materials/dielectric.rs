//! Glass: `dielectric` (smooth), `rough-dielectric` (microfacet, widths that may be textures)
//! and `thin-dielectric` (a sheet: both faces, no refraction of the ray's direction).

use glint_core::materials::{Dielectric, Material, RoughDielectric, ThinDielectric};

use super::parameters::Parameters;
use super::GLASS_IOR;
use crate::error::SceneError;
use crate::native::schema::{ColorDesc, MaterialDesc};

/// The smooth interface the three share: its relative index and its tints.
fn interface(
    p: &Parameters,
    int_ior: &Option<f32>,
    ext_ior: &Option<f32>,
    r: &Option<ColorDesc>,
    t: &Option<ColorDesc>,
) -> Result<Dielectric, SceneError> {
    Ok(Dielectric {
        eta: p.ior(int_ior, ext_ior, GLASS_IOR)?,
        specular_reflectance: p.colour("specular_reflectance", r, 1.0)?,
        specular_transmittance: p.colour("specular_transmittance", t, 1.0)?,
    })
}

pub(super) fn dielectric(p: &Parameters, desc: &MaterialDesc) -> Result<Material, SceneError> {
    let MaterialDesc::Dielectric { int_ior, ext_ior, specular_reflectance, specular_transmittance } = desc else {
        unreachable!("dielectric is given a dielectric description")
    };
    Ok(Material::Dielectric(interface(p, int_ior, ext_ior, specular_reflectance, specular_transmittance)?))
}

pub(super) fn rough_dielectric(p: &Parameters, desc: &MaterialDesc) -> Result<Material, SceneError> {
    let MaterialDesc::RoughDielectric {
        int_ior,
        ext_ior,
        specular_reflectance,
        specular_transmittance,
        alpha,
        alpha_u,
        alpha_v,
        distribution: d,
    } = desc
    else {
        unreachable!("rough_dielectric is given a rough-dielectric description")
    };
    let dielectric = interface(p, int_ior, ext_ior, specular_reflectance, specular_transmittance)?;
    let (alpha_u, alpha_v) = p.textured_widths(alpha, alpha_u, alpha_v)?;
    let distribution = p.distribution(d)?;
    Ok(Material::RoughDielectric(RoughDielectric { dielectric, alpha_u, alpha_v, distribution }))
}

pub(super) fn thin_dielectric(p: &Parameters, desc: &MaterialDesc) -> Result<Material, SceneError> {
    let MaterialDesc::ThinDielectric { int_ior, ext_ior, specular_reflectance, specular_transmittance } = desc else {
        unreachable!("thin_dielectric is given a thin-dielectric description")
    };
    let sheet = interface(p, int_ior, ext_ior, specular_reflectance, specular_transmittance)?;
    Ok(Material::ThinDielectric(ThinDielectric { sheet }))
}
