//! The `[materials]` table built into the core's closed set: each entry by its `type`, wrappers
//! (`blend`, `mask`, `two-sided`, `emitter`) resolved by name in any order, cycles refused.

use std::collections::BTreeMap;

use glint_core::materials::{
    named_metal, Blend, BumpMap, Conductor, Dielectric, Diffuse, DiffuseTransmission, Distribution, Emitter, Fresnel,
    Mask, Material, NormalMap, Phong, Plastic, Principled, PrincipledThin, RoughConductor, RoughDielectric,
    RoughPlastic, SamplingRates, ThinDielectric, TwoSided, MAX_LEAVES, METAL_NAMES,
};
use glint_core::textures::Texture;
use glint_core::{Named, Rgb};

use super::build::{non_negative, positive, quoted, resolve_colour, Context};
use super::schema::{ColorDesc, FractionDesc, FresnelDesc, MaterialDesc};
use crate::error::{did_you_mean, SceneError};
use crate::located::Located;

/// Mitsuba's defaults: BK7 glass, polypropylene, air.
const GLASS_IOR: f32 = 1.5046;
const PLASTIC_IOR: f32 = 1.49;
const AIR_IOR: f32 = 1.000277;
/// Mitsuba's default roughness.
const ALPHA: f32 = 0.1;

/// Every material of the file, in the file's (sorted) order.
pub(super) fn build_materials(
    cx: &Context,
    descs: &BTreeMap<String, Located<MaterialDesc>>,
    textures: &[(String, Texture)],
) -> Result<Vec<(String, Material)>, SceneError> {
    let mut builder = Builder { cx, descs, textures, built: BTreeMap::new(), stack: Vec::new() };
    let mut materials = Vec::new();
    for name in descs.keys() {
        let material = builder.material(name)?;
        if material.leaf_count() > MAX_LEAVES {
            let at = &descs[name].span;
            return Err(cx.error(
                at,
                None,
                format!(
                    "material `{name}` blends and masks {} materials in all; at most {MAX_LEAVES} can be combined",
                    material.leaf_count()
                ),
            ));
        }
        materials.push((name.clone(), material));
    }
    Ok(materials)
}

struct Builder<'a> {
    cx: &'a Context<'a>,
    descs: &'a BTreeMap<String, Located<MaterialDesc>>,
    textures: &'a [(String, Texture)],
    built: BTreeMap<String, Material>,
    /// The wrappers being built, innermost last (a name seen again is a cycle).
    stack: Vec<String>,
}

impl Builder<'_> {
    fn material(&mut self, name: &str) -> Result<Material, SceneError> {
        if let Some(m) = self.built.get(name) {
            return Ok(m.clone());
        }
        let entry = &self.descs[name];
        self.stack.push(name.to_string());
        let material = self.build(name, entry)?;
        self.stack.pop();
        self.built.insert(name.to_string(), material.clone());
        Ok(material)
    }

    /// The material `reference` names, from the wrapper `owner`'s key `key`.
    fn reference(&mut self, owner: &str, key: &str, reference: &str) -> Result<Material, SceneError> {
        let span = &self.descs[owner].span;
        if !self.descs.contains_key(reference) {
            let hint = did_you_mean(reference, self.descs.keys().map(String::as_str));
            return Err(self.cx.error(
                span,
                Some(key),
                format!("material `{owner}`: unknown material `{reference}`{hint}"),
            ));
        }
        if let Some(i) = self.stack.iter().position(|n| n == reference) {
            let cycle: Vec<&str> = self.stack[i..].iter().map(String::as_str).chain([reference]).collect();
            return Err(self.cx.error(
                span,
                Some(key),
                format!("material `{owner}`: materials refer to each other in a cycle ({})", cycle.join(" → ")),
            ));
        }
        self.material(reference)
    }

    fn build(&mut self, name: &str, entry: &Located<MaterialDesc>) -> Result<Material, SceneError> {
        let cx = self.cx;
        let textures = self.textures;
        let at = |key: &str, m: String| cx.error(&entry.span, Some(key), format!("material `{name}`: {m}"));
        let colour = |key: &str, c: &Option<ColorDesc>, default: f32| match c {
            Some(c) => resolve_colour(c, textures).map_err(|m| at(key, m)),
            None => Ok(Texture::Constant(Rgb::splat(default))),
        };
        // A number in `range` (`default` if absent), or a texture read as given.
        let ranged = |key: &str, f: &Option<FractionDesc>, default: f32, range: std::ops::RangeInclusive<f32>| match f {
            None => Ok(Texture::Constant(Rgb::splat(default))),
            Some(FractionDesc::Number(x)) if range.contains(x) => Ok(Texture::Constant(Rgb::splat(*x))),
            Some(FractionDesc::Number(x)) => {
                Err(at(key, format!("`{key}` must be between {} and {}, got {x}", range.start(), range.end())))
            }
            Some(FractionDesc::Texture(t)) => {
                resolve_colour(&ColorDesc::Texture(t.clone()), textures).map_err(|m| at(key, m))
            }
        };
        // A weight in [0, 1], `default` if absent.
        let weight = |key: &str, f: &Option<FractionDesc>, default: f32| ranged(key, f, default, 0.0..=1.0);
        let fraction = |key: &str, f: &Option<FractionDesc>| weight(key, f, 0.5);
        let distribution = |d: &Option<String>| match d.as_deref() {
            None => Ok(Distribution::Ggx),
            Some(name) => Distribution::from_name(name).ok_or_else(|| {
                let names: Vec<&str> = Distribution::ALL.iter().map(|d| d.name()).collect();
                at(
                    "distribution",
                    format!("unknown microfacet distribution `{name}`, expected one of {}", quoted(&names)),
                )
            }),
        };
        let metal = |metal: &Option<String>, eta: &Option<[f32; 3]>, k: &Option<[f32; 3]>| match (metal, eta, k) {
            (Some(m), None, None) => named_metal(m).ok_or_else(|| {
                let hint = did_you_mean(m, METAL_NAMES);
                at("metal", format!("unknown metal `{m}`, expected one of {}{hint}", quoted(&METAL_NAMES)))
            }),
            (None, Some(eta), Some(k)) => Ok((
                non_negative(*eta).map_err(|m| at("eta", format!("`eta` {m}")))?,
                non_negative(*k).map_err(|m| at("k", format!("`k` {m}")))?,
            )),
            // Mitsuba's default conductor: aluminium.
            (None, None, None) => Ok(named_metal("Al").expect("aluminium is a named metal")),
            _ => Err(at("metal", "a metal needs either `metal` (a name) or both `eta` and `k`, not both".into())),
        };
        let ior = |int_ior: &Option<f32>, ext_ior: &Option<f32>, default: f32| -> Result<f32, SceneError> {
            let (int, ext) = (int_ior.unwrap_or(default), ext_ior.unwrap_or(AIR_IOR));
            positive(int).map_err(|m| at("int_ior", format!("`int_ior` {m}")))?;
            positive(ext).map_err(|m| at("ext_ior", format!("`ext_ior` {m}")))?;
            Ok(int / ext)
        };
        let alpha = |key: &str, a: Option<f32>| match a {
            Some(a) if !(a.is_finite() && a >= 0.0) => {
                Err(at(key, format!("`{key}` must be a finite number ≥ 0, got {a}")))
            }
            Some(a) => Ok(a),
            None => Ok(ALPHA),
        };
        // A width that may be a texture: a number as `alpha` checks it, or a texture's name.
        let textured_alpha = |key: &str, a: &Option<FractionDesc>| match a {
            None => Ok(Texture::from(ALPHA)),
            Some(FractionDesc::Number(x)) => alpha(key, Some(*x)).map(Texture::from),
            Some(FractionDesc::Texture(t)) => {
                resolve_colour(&ColorDesc::Texture(t.clone()), textures).map_err(|m| at(key, m))
            }
        };
        let textured_widths =
            |a: &Option<FractionDesc>, u: &Option<FractionDesc>, v: &Option<FractionDesc>| match (a, u, v) {
                (a, None, None) => Ok((textured_alpha("alpha", a)?, textured_alpha("alpha", a)?)),
                (None, Some(_), Some(_)) => Ok((textured_alpha("alpha_u", u)?, textured_alpha("alpha_v", v)?)),
                _ => Err(at("alpha", "give `alpha`, or both `alpha_u` and `alpha_v`".into())),
            };
        let dielectric =
            |int_ior: &Option<f32>, ext_ior: &Option<f32>, r: &Option<ColorDesc>, t: &Option<ColorDesc>| {
                Ok::<_, SceneError>(Dielectric {
                    eta: ior(int_ior, ext_ior, GLASS_IOR)?,
                    specular_reflectance: colour("specular_reflectance", r, 1.0)?,
                    specular_transmittance: colour("specular_transmittance", t, 1.0)?,
                })
            };
        let plastic = |d: &Option<ColorDesc>, s: &Option<ColorDesc>, int_ior, ext_ior, nonlinear: bool| {
            Ok::<_, SceneError>(Plastic {
                diffuse: colour("diffuse_reflectance", d, 0.5)?,
                specular: colour("specular_reflectance", s, 1.0)?,
                eta: ior(int_ior, ext_ior, PLASTIC_IOR)?,
                nonlinear,
            })
        };
        let sided = |material: Material, two_sided: &Option<bool>| {
            if two_sided.unwrap_or(true) {
                Material::TwoSided(Box::new(TwoSided { front: material.clone(), back: material }))
            } else {
                material
            }
        };
        let emitting = |material: Material, emission: Option<(&str, &ColorDesc)>, two_sided: bool| match emission {
            Some((key, e)) => Ok(Material::Emitter(Box::new(Emitter {
                radiance: resolve_colour(e, textures).map_err(|m| at(key, m))?,
                two_sided,
                surface: material,
            }))),
            None => Ok(material),
        };
        Ok(match &entry.value {
            MaterialDesc::Phong { .. } => build_phong(&entry.value, &at, &colour)?,
            MaterialDesc::Metal { metal: m, eta, k, tint, roughness } => {
                let (eta, k) = metal(m, eta, k)?;
                let roughness = roughness.unwrap_or(0.0);
                if !(0.0..=1.0).contains(&roughness) {
                    return Err(at("roughness", format!("`roughness` must be between 0 and 1, got {roughness}")));
                }
                Material::Phong(Phong {
                    diffuse: Texture::Constant(Rgb::ZERO),
                    ambient: Some(Texture::Constant(Rgb::ZERO)),
                    reflection: colour("tint", tint, 1.0)?,
                    fresnel: Fresnel::Conductor { eta, k },
                    roughness,
                    ..Phong::default()
                })
            }
            MaterialDesc::Diffuse { reflectance, emission, two_sided_emission, two_sided } => {
                let diffuse = Material::Diffuse(Diffuse { reflectance: colour("reflectance", reflectance, 0.8)? });
                emitting(sided(diffuse, two_sided), emission.as_ref().map(|e| ("emission", e)), *two_sided_emission)?
            }
            MaterialDesc::DiffuseTransmission { reflectance, transmittance } => {
                Material::DiffuseTransmission(DiffuseTransmission {
                    reflectance: colour("reflectance", reflectance, 0.25)?,
                    transmittance: colour("transmittance", transmittance, 0.25)?,
                })
            }
            MaterialDesc::Conductor { metal: m, eta, k, specular_reflectance, two_sided } => {
                let (eta, k) = metal(m, eta, k)?;
                let specular = colour("specular_reflectance", specular_reflectance, 1.0)?;
                sided(Material::Conductor(Conductor { eta, k, specular }), two_sided)
            }
            MaterialDesc::RoughConductor {
                metal: m,
                eta,
                k,
                specular_reflectance,
                alpha,
                alpha_u,
                alpha_v,
                distribution: d,
                two_sided,
            } => {
                let (eta, k) = metal(m, eta, k)?;
                let specular = colour("specular_reflectance", specular_reflectance, 1.0)?;
                let (alpha_u, alpha_v) = textured_widths(alpha, alpha_u, alpha_v)?;
                let conductor = Conductor { eta, k, specular };
                let distribution = distribution(d)?;
                sided(Material::RoughConductor(RoughConductor { conductor, alpha_u, alpha_v, distribution }), two_sided)
            }
            MaterialDesc::Dielectric { int_ior, ext_ior, specular_reflectance, specular_transmittance } => {
                Material::Dielectric(dielectric(int_ior, ext_ior, specular_reflectance, specular_transmittance)?)
            }
            MaterialDesc::RoughDielectric {
                int_ior,
                ext_ior,
                specular_reflectance,
                specular_transmittance,
                alpha,
                alpha_u,
                alpha_v,
                distribution: d,
            } => {
                let dielectric = dielectric(int_ior, ext_ior, specular_reflectance, specular_transmittance)?;
                let (alpha_u, alpha_v) = textured_widths(alpha, alpha_u, alpha_v)?;
                let distribution = distribution(d)?;
                Material::RoughDielectric(RoughDielectric { dielectric, alpha_u, alpha_v, distribution })
            }
            MaterialDesc::ThinDielectric { int_ior, ext_ior, specular_reflectance, specular_transmittance } => {
                let sheet = dielectric(int_ior, ext_ior, specular_reflectance, specular_transmittance)?;
                Material::ThinDielectric(ThinDielectric { sheet })
            }
            MaterialDesc::Plastic {
                diffuse_reflectance,
                specular_reflectance,
                int_ior,
                ext_ior,
                nonlinear,
                two_sided,
            } => {
                let plastic = plastic(diffuse_reflectance, specular_reflectance, int_ior, ext_ior, *nonlinear)?;
                sided(Material::Plastic(plastic), two_sided)
            }
            MaterialDesc::RoughPlastic {
                diffuse_reflectance,
                specular_reflectance,
                int_ior,
                ext_ior,
                nonlinear,
                alpha: a,
                distribution: d,
                two_sided,
            } => {
                let plastic = plastic(diffuse_reflectance, specular_reflectance, int_ior, ext_ior, *nonlinear)?;
                if (plastic.eta - 1.0).abs() < 1e-6 {
                    return Err(at(
                        "int_ior",
                        "a rough plastic's coat needs `int_ior` different from `ext_ior`".into(),
                    ));
                }
                let material = RoughPlastic::new(plastic, alpha("alpha", *a)?, distribution(d)?);
                sided(Material::RoughPlastic(material), two_sided)
            }
            MaterialDesc::Principled {
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
            } => {
                // Mitsuba's adjustments: an index of 1 (or a specular of 0) cannot transmit.
                let transmits = spec_trans.is_some();
                let eta = match (specular, eta) {
                    (Some(_), Some(_)) => return Err(at("eta", "give `specular` or `eta`, not both".into())),
                    (None, Some(e)) if *e > 0.0 && e.is_finite() => {
                        if transmits && *e == 1.0 {
                            1.001
                        } else {
                            *e
                        }
                    }
                    (None, Some(e)) => return Err(at("eta", format!("`eta` must be positive, got {e}"))),
                    (Some(s), None) if (0.0..=1.0).contains(s) => {
                        Principled::eta_from_specular(if transmits && *s == 0.0 { 1e-3 } else { *s })
                    }
                    (Some(s), None) => {
                        return Err(at("specular", format!("`specular` must be between 0 and 1, got {s}")))
                    }
                    (None, None) => Principled::eta_from_specular(0.5),
                };
                Material::Principled(Box::new(Principled {
                    base_color: colour("base_color", base_color, 0.5)?,
                    roughness: weight("roughness", roughness, 0.5)?,
                    anisotropic: weight("anisotropic", anisotropic, 0.0)?,
                    metallic: weight("metallic", metallic, 0.0)?,
                    spec_trans: weight("spec_trans", spec_trans, 0.0)?,
                    spec_tint: weight("spec_tint", spec_tint, 0.0)?,
                    sheen: weight("sheen", sheen, 0.0)?,
                    sheen_tint: weight("sheen_tint", sheen_tint, 0.0)?,
                    flatness: weight("flatness", flatness, 0.0)?,
                    clearcoat: weight("clearcoat", clearcoat, 0.0)?,
                    clearcoat_gloss: weight("clearcoat_gloss", clearcoat_gloss, 0.0)?,
                    eta,
                }))
            }
            MaterialDesc::PrincipledThin {
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
            } => {
                let rate = |key: &str, r: &Option<f32>| match r {
                    None => Ok(1.0),
                    Some(r) if *r >= 0.0 && r.is_finite() => Ok(*r),
                    Some(r) => Err(at(key, format!("`{key}` must be a sampling rate ≥ 0, got {r}"))),
                };
                let rates = SamplingRates {
                    diffuse_reflection: rate("diffuse_reflectance_sampling_rate", diffuse_reflectance_sampling_rate)?,
                    specular_reflection: rate(
                        "specular_reflectance_sampling_rate",
                        specular_reflectance_sampling_rate,
                    )?,
                    specular_transmission: rate(
                        "specular_transmittance_sampling_rate",
                        specular_transmittance_sampling_rate,
                    )?,
                    diffuse_transmission: rate(
                        "diffuse_transmittance_sampling_rate",
                        diffuse_transmittance_sampling_rate,
                    )?,
                };
                if rates.diffuse_reflection
                    + rates.specular_reflection
                    + rates.specular_transmission
                    + rates.diffuse_transmission
                    <= 0.0
                {
                    return Err(at("diffuse_reflectance_sampling_rate", "the sampling rates cannot all be 0".into()));
                }
                Material::PrincipledThin(Box::new(PrincipledThin {
                    base_color: colour("base_color", base_color, 0.5)?,
                    roughness: weight("roughness", roughness, 0.5)?,
                    anisotropic: weight("anisotropic", anisotropic, 0.0)?,
                    spec_trans: weight("spec_trans", spec_trans, 0.0)?,
                    diff_trans: ranged("diff_trans", diff_trans, 0.0, 0.0..=2.0)?,
                    eta: ranged("eta", eta, 1.5, 1e-3..=f32::MAX)?,
                    spec_tint: weight("spec_tint", spec_tint, 0.0)?,
                    sheen: weight("sheen", sheen, 0.0)?,
                    sheen_tint: weight("sheen_tint", sheen_tint, 0.0)?,
                    flatness: weight("flatness", flatness, 0.0)?,
                    rates,
                }))
            }
            MaterialDesc::Blend { weight, first, second } => {
                let weight = fraction("weight", weight)?;
                let first = self.reference(name, "first", first)?;
                let second = self.reference(name, "second", second)?;
                Material::Blend(Box::new(Blend { weight, first, second }))
            }
            MaterialDesc::Null => Material::Mask(Box::new(Mask {
                opacity: Texture::Constant(Rgb::ZERO),
                material: Material::Diffuse(Diffuse { reflectance: Texture::Constant(Rgb::ZERO) }),
            })),
            MaterialDesc::Mask { opacity, material } => {
                let opacity = fraction("opacity", opacity)?;
                let material = self.reference(name, "material", material)?;
                Material::Mask(Box::new(Mask { opacity, material }))
            }
            MaterialDesc::NormalMap { normals, material } => {
                let normals = resolve_colour(normals, textures).map_err(|m| at("normals", m))?;
                let material = self.reference(name, "material", material)?;
                Material::NormalMap(Box::new(NormalMap { normals, material }))
            }
            MaterialDesc::BumpMap { height, scale, material } => {
                let height =
                    resolve_colour(&ColorDesc::Texture(height.clone()), textures).map_err(|m| at("height", m))?;
                if !height.has_uv_gradient() {
                    return Err(at(
                        "height",
                        "a bump map's height must vary with uv: an image, a checkerboard or a constant (solid textures vary with the point and have no uv slope)".into(),
                    ));
                }
                if !scale.is_finite() {
                    return Err(at("scale", format!("`scale` must be a finite number; got {scale}")));
                }
                let material = self.reference(name, "material", material)?;
                Material::BumpMap(Box::new(BumpMap { height, scale: *scale, material }))
            }
            MaterialDesc::TwoSided { front, back } => {
                let front = self.reference(name, "front", front)?;
                let back = match back {
                    Some(b) => self.reference(name, "back", b)?,
                    None => front.clone(),
                };
                Material::TwoSided(Box::new(TwoSided { front, back }))
            }
            MaterialDesc::Emitter { radiance, two_sided, material } => {
                let surface = self.reference(name, "material", material)?;
                emitting(surface, Some(("radiance", radiance)), *two_sided)?
            }
        })
    }
}

/// A colour parameter (`key`, its description, the default) read as a texture.
type ColourOf<'a> = dyn Fn(&str, &Option<ColorDesc>, f32) -> Result<Texture, SceneError> + 'a;

/// The course's material, every Phong parameter checked.
fn build_phong(
    desc: &MaterialDesc,
    at: &dyn Fn(&str, String) -> SceneError,
    colour: &ColourOf,
) -> Result<Material, SceneError> {
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
        unreachable!("build_phong is given a phong description")
    };
    let mut phong = Phong::default();
    if let Some(r) = roughness {
        if !(0.0..=1.0).contains(r) {
            return Err(at("roughness", format!("`roughness` must be between 0 and 1, got {r}")));
        }
        phong.roughness = *r;
    }
    if let Some(e) = emission {
        phong.emission = non_negative(*e).map_err(|m| at("emission", m))?;
    }
    phong.two_sided_emission = *two_sided_emission;
    if diffuse.is_some() {
        phong.diffuse = colour("diffuse", diffuse, 0.0)?;
    }
    if ambient.is_some() {
        phong.ambient = Some(colour("ambient", ambient, 0.0)?);
    }
    if specular.is_some() {
        phong.specular = colour("specular", specular, 0.0)?;
    }
    if reflection.is_some() {
        phong.reflection = colour("reflection", reflection, 0.0)?;
    }
    if transmission.is_some() {
        phong.transmission = colour("transmission", transmission, 0.0)?;
    }
    if let Some(n) = shininess {
        if !(n.is_finite() && *n >= 0.0) {
            return Err(at("shininess", format!("`shininess` must be a finite number ≥ 0, got {n}")));
        }
        phong.shininess = *n;
    }
    if let Some(eta) = ior {
        positive(*eta).map_err(|m| at("ior", format!("`ior` {m}")))?;
        phong.ior = *eta;
    }
    phong.fresnel = match fresnel {
        FresnelDesc::None => Fresnel::None,
        FresnelDesc::Schlick => Fresnel::Schlick,
        FresnelDesc::Exact => Fresnel::Exact,
    };
    Ok(Material::Phong(phong))
}
