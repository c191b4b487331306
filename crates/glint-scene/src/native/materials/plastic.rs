//! Coated diffuse surfaces: `plastic` (a diffuse base under a smooth dielectric coat,
//! Mitsuba's model) and `rough-plastic` (under a rough coat), both two-sided unless told; and
//! `fresnel-plastic` (Mitsuba's `pplastic`), one-sided.

use glint_core::materials::{Distribution, FresnelPlastic, Material, Plastic, RoughPlastic};

use super::parameters::{sided, Parameters};
use super::PLASTIC_IOR;
use crate::error::SceneError;
use crate::native::schema::{ColorDesc, MaterialDesc};

/// The base and coat the two share.
fn layers(
    p: &Parameters,
    d: &Option<ColorDesc>,
    s: &Option<ColorDesc>,
    int_ior: &Option<f32>,
    ext_ior: &Option<f32>,
    nonlinear: bool,
) -> Result<Plastic, SceneError> {
    Ok(Plastic {
        diffuse: p.colour("diffuse_reflectance", d, 0.5)?,
        specular: p.colour("specular_reflectance", s, 1.0)?,
        eta: p.ior(int_ior, ext_ior, PLASTIC_IOR)?,
        nonlinear,
    })
}

pub(super) fn plastic(p: &Parameters, desc: &MaterialDesc) -> Result<Material, SceneError> {
    let MaterialDesc::Plastic { diffuse_reflectance, specular_reflectance, int_ior, ext_ior, nonlinear, two_sided } =
        desc
    else {
        unreachable!("plastic is given a plastic description")
    };
    let plastic = layers(p, diffuse_reflectance, specular_reflectance, int_ior, ext_ior, *nonlinear)?;
    Ok(sided(Material::Plastic(plastic), two_sided))
}

pub(super) fn rough_plastic(p: &Parameters, desc: &MaterialDesc) -> Result<Material, SceneError> {
    let MaterialDesc::RoughPlastic {
        diffuse_reflectance,
        specular_reflectance,
        int_ior,
        ext_ior,
        nonlinear,
        alpha: a,
        distribution: d,
        two_sided,
    } = desc
    else {
        unreachable!("rough_plastic is given a rough-plastic description")
    };
    let plastic = layers(p, diffuse_reflectance, specular_reflectance, int_ior, ext_ior, *nonlinear)?;
    if (plastic.eta - 1.0).abs() < 1e-6 {
        return Err(p.at("int_ior", "a rough plastic's coat needs `int_ior` different from `ext_ior`".into()));
    }
    let material = RoughPlastic::new(plastic, p.alpha("alpha", *a)?, p.distribution(d)?);
    Ok(sided(Material::RoughPlastic(material), two_sided))
}

pub(super) fn fresnel_plastic(p: &Parameters, desc: &MaterialDesc) -> Result<Material, SceneError> {
    let MaterialDesc::FresnelPlastic {
        diffuse_reflectance,
        specular_reflectance,
        int_ior,
        ext_ior,
        alpha,
        alpha_u,
        alpha_v,
        distribution,
    } = desc
    else {
        unreachable!("fresnel_plastic is given a fresnel-plastic description")
    };
    let plastic = layers(p, diffuse_reflectance, specular_reflectance, int_ior, ext_ior, false)?;
    if (plastic.eta - 1.0).abs() < 1e-6 {
        return Err(p.at("int_ior", "a Fresnel plastic needs `int_ior` different from `ext_ior`".into()));
    }
    let alphas = match (alpha, alpha_u, alpha_v) {
        (a, None, None) => (p.alpha("alpha", *a)?, p.alpha("alpha", *a)?),
        (None, Some(u), Some(v)) => (p.alpha("alpha_u", Some(*u))?, p.alpha("alpha_v", Some(*v))?),
        _ => return Err(p.at("alpha", "give `alpha`, or both `alpha_u` and `alpha_v`".into())),
    };
    // Beckmann by default, as Mitsuba's pplastic.
    let distribution = match distribution {
        None => Distribution::Beckmann,
        d => p.distribution(d)?,
    };
    let material = FresnelPlastic::new(plastic.diffuse, plastic.specular, plastic.eta, alphas, distribution);
    Ok(Material::FresnelPlastic(Box::new(material)))
}
