//! Disney's principled BSDF as Mitsuba has it: `principled` (the full model with metal,
//! clearcoat and specular transmission) and `principled-thin` (a thin sheet that also
//! transmits diffusely, with its lobes' sampling rates).

use glint_core::materials::{Material, Principled, PrincipledThin, SamplingRates};

use super::parameters::Parameters;
use crate::error::SceneError;
use crate::native::schema::MaterialDesc;

pub(super) fn principled(p: &Parameters, desc: &MaterialDesc) -> Result<Material, SceneError> {
    let MaterialDesc::Principled {
        base_color,
        roughness,
        anisotropic,
        metallic,
        spec_trans,
        specular,
        eta,
        spec_tint,
        sheen,
        sheen_tint,
        flatness,
        clearcoat,
        clearcoat_gloss,
    } = desc
    else {
        unreachable!("principled is given a principled description")
    };
    // Mitsuba's adjustments: an index of 1 (or a specular of 0) cannot transmit.
    let transmits = spec_trans.is_some();
    let eta = match (specular, eta) {
        (Some(_), Some(_)) => return Err(p.at("eta", "give `specular` or `eta`, not both".into())),
        (None, Some(e)) if *e > 0.0 && e.is_finite() => {
            if transmits && *e == 1.0 {
                1.001
            } else {
                *e
            }
        }
        (None, Some(e)) => return Err(p.at("eta", format!("`eta` must be positive, got {e}"))),
        (Some(s), None) if (0.0..=1.0).contains(s) => {
            Principled::eta_from_specular(if transmits && *s == 0.0 { 1e-3 } else { *s })
        }
        (Some(s), None) => return Err(p.at("specular", format!("`specular` must be between 0 and 1, got {s}"))),
        (None, None) => Principled::eta_from_specular(0.5),
    };
    Ok(Material::Principled(Box::new(Principled {
        base_color: p.colour("base_color", base_color, 0.5)?,
        roughness: p.weight("roughness", roughness, 0.5)?,
        anisotropic: p.weight("anisotropic", anisotropic, 0.0)?,
        metallic: p.weight("metallic", metallic, 0.0)?,
        spec_trans: p.weight("spec_trans", spec_trans, 0.0)?,
        spec_tint: p.weight("spec_tint", spec_tint, 0.0)?,
        sheen: p.weight("sheen", sheen, 0.0)?,
        sheen_tint: p.weight("sheen_tint", sheen_tint, 0.0)?,
        flatness: p.weight("flatness", flatness, 0.0)?,
        clearcoat: p.weight("clearcoat", clearcoat, 0.0)?,
        clearcoat_gloss: p.weight("clearcoat_gloss", clearcoat_gloss, 0.0)?,
        eta,
    })))
}

pub(super) fn principled_thin(p: &Parameters, desc: &MaterialDesc) -> Result<Material, SceneError> {
    let MaterialDesc::PrincipledThin {
        base_color,
        roughness,
        anisotropic,
        spec_trans,
        diff_trans,
        eta,
        spec_tint,
        sheen,
        sheen_tint,
        flatness,
        diffuse_reflectance_sampling_rate,
        specular_reflectance_sampling_rate,
        specular_transmittance_sampling_rate,
        diffuse_transmittance_sampling_rate,
    } = desc
    else {
        unreachable!("principled_thin is given a principled-thin description")
    };
    let rate = |key: &str, r: &Option<f32>| match r {
        None => Ok(1.0),
        Some(r) if *r >= 0.0 && r.is_finite() => Ok(*r),
        Some(r) => Err(p.at(key, format!("`{key}` must be a sampling rate ≥ 0, got {r}"))),
    };
    let rates = SamplingRates {
        diffuse_reflection: rate("diffuse_reflectance_sampling_rate", diffuse_reflectance_sampling_rate)?,
        specular_reflection: rate("specular_reflectance_sampling_rate", specular_reflectance_sampling_rate)?,
        specular_transmission: rate("specular_transmittance_sampling_rate", specular_transmittance_sampling_rate)?,
        diffuse_transmission: rate("diffuse_transmittance_sampling_rate", diffuse_transmittance_sampling_rate)?,
    };
    if rates.diffuse_reflection + rates.specular_reflection + rates.specular_transmission + rates.diffuse_transmission
        <= 0.0
    {
        return Err(p.at("diffuse_reflectance_sampling_rate", "the sampling rates cannot all be 0".into()));
    }
    Ok(Material::PrincipledThin(Box::new(PrincipledThin {
        base_color: p.colour("base_color", base_color, 0.5)?,
        roughness: p.weight("roughness", roughness, 0.5)?,
        anisotropic: p.weight("anisotropic", anisotropic, 0.0)?,
        spec_trans: p.weight("spec_trans", spec_trans, 0.0)?,
        diff_trans: p.ranged("diff_trans", diff_trans, 0.0, 0.0..=2.0)?,
        eta: p.ranged("eta", eta, 1.5, 1e-3..=f32::MAX)?,
        spec_tint: p.weight("spec_tint", spec_tint, 0.0)?,
        sheen: p.weight("sheen", sheen, 0.0)?,
        sheen_tint: p.weight("sheen_tint", sheen_tint, 0.0)?,
        flatness: p.weight("flatness", flatness, 0.0)?,
        rates,
    })))
}
