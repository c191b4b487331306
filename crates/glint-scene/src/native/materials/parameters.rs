//! One `[materials]` entry's parameters as each kind reads them: colours and fractions (a
//! value or a texture's name), indices of refraction, roughness widths, microfacet
//! distributions and metals, and the two-sided and emitting wrappers a kind may ask for.
//! Every error names the entry and points at the key at fault.

use std::ops::{Range, RangeInclusive};

use glint_core::materials::{named_metal, Distribution, Emitter, Material, TwoSided, METAL_NAMES};
use glint_core::textures::Texture;
use glint_core::{Named, Rgb};

use super::{AIR_IOR, ALPHA};
use crate::error::{did_you_mean, SceneError};
use crate::native::build::{non_negative, positive, quoted, resolve_colour, Context};
use crate::native::schema::{ColorDesc, FractionDesc};

/// The entry being built: its name and span (for messages), and the scene's textures (for
/// parameters that name one).
pub(super) struct Parameters<'a> {
    pub(super) cx: &'a Context<'a>,
    pub(super) textures: &'a [(String, Texture)],
    pub(super) name: &'a str,
    pub(super) span: &'a Option<Range<usize>>,
}

impl Parameters<'_> {
    /// An error about `key` of this entry.
    pub(super) fn at(&self, key: &str, m: String) -> SceneError {
        self.cx.error(self.span, Some(key), format!("material `{}`: {m}", self.name))
    }

    /// A colour: a value, a texture's name, or `default` (grey) if absent.
    pub(super) fn colour(&self, key: &str, c: &Option<ColorDesc>, default: f32) -> Result<Texture, SceneError> {
        match c {
            Some(c) => resolve_colour(c, self.textures).map_err(|m| self.at(key, m)),
            None => Ok(Texture::Constant(Rgb::splat(default))),
        }
    }

    /// A number in `range` (`default` if absent), or a texture read as given.
    pub(super) fn ranged(
        &self,
        key: &str,
        f: &Option<FractionDesc>,
        default: f32,
        range: RangeInclusive<f32>,
    ) -> Result<Texture, SceneError> {
        match f {
            None => Ok(Texture::Constant(Rgb::splat(default))),
            Some(FractionDesc::Number(x)) if range.contains(x) => Ok(Texture::Constant(Rgb::splat(*x))),
            Some(FractionDesc::Number(x)) => {
                Err(self.at(key, format!("`{key}` must be between {} and {}, got {x}", range.start(), range.end())))
            }
            Some(FractionDesc::Texture(t)) => {
                resolve_colour(&ColorDesc::Texture(t.clone()), self.textures).map_err(|m| self.at(key, m))
            }
        }
    }

    /// A weight in [0, 1], `default` if absent.
    pub(super) fn weight(&self, key: &str, f: &Option<FractionDesc>, default: f32) -> Result<Texture, SceneError> {
        self.ranged(key, f, default, 0.0..=1.0)
    }

    /// A weight in [0, 1], ½ if absent.
    pub(super) fn fraction(&self, key: &str, f: &Option<FractionDesc>) -> Result<Texture, SceneError> {
        self.weight(key, f, 0.5)
    }

    /// A microfacet distribution by name, GGX if absent.
    pub(super) fn distribution(&self, d: &Option<String>) -> Result<Distribution, SceneError> {
        match d.as_deref() {
            None => Ok(Distribution::Ggx),
            Some(name) => Distribution::from_name(name).ok_or_else(|| {
                let names: Vec<&str> = Distribution::ALL.iter().map(|d| d.name()).collect();
                self.at(
                    "distribution",
                    format!("unknown microfacet distribution `{name}`, expected one of {}", quoted(&names)),
                )
            }),
        }
    }

    /// A metal's η and k: by name, by value, or aluminium if neither is given.
    pub(super) fn metal(
        &self,
        metal: &Option<String>,
        eta: &Option<[f32; 3]>,
        k: &Option<[f32; 3]>,
    ) -> Result<(Rgb, Rgb), SceneError> {
        match (metal, eta, k) {
            (Some(m), None, None) => named_metal(m).ok_or_else(|| {
                let hint = did_you_mean(m, METAL_NAMES);
                self.at("metal", format!("unknown metal `{m}`, expected one of {}{hint}", quoted(&METAL_NAMES)))
            }),
            (None, Some(eta), Some(k)) => Ok((
                non_negative(*eta).map_err(|m| self.at("eta", format!("`eta` {m}")))?,
                non_negative(*k).map_err(|m| self.at("k", format!("`k` {m}")))?,
            )),
            // Mitsuba's default conductor: aluminium.
            (None, None, None) => Ok(named_metal("Al").expect("aluminium is a named metal")),
            _ => Err(self.at("metal", "a metal needs either `metal` (a name) or both `eta` and `k`, not both".into())),
        }
    }

    /// The relative index of refraction, inside over outside (`default` inside, air outside).
    pub(super) fn ior(&self, int_ior: &Option<f32>, ext_ior: &Option<f32>, default: f32) -> Result<f32, SceneError> {
        let (int, ext) = (int_ior.unwrap_or(default), ext_ior.unwrap_or(AIR_IOR));
        positive(int).map_err(|m| self.at("int_ior", format!("`int_ior` {m}")))?;
        positive(ext).map_err(|m| self.at("ext_ior", format!("`ext_ior` {m}")))?;
        Ok(int / ext)
    }

    /// A microfacet width α ≥ 0, Mitsuba's default if absent.
    pub(super) fn alpha(&self, key: &str, a: Option<f32>) -> Result<f32, SceneError> {
        match a {
            Some(a) if !(a.is_finite() && a >= 0.0) => {
                Err(self.at(key, format!("`{key}` must be a finite number ≥ 0, got {a}")))
            }
            Some(a) => Ok(a),
            None => Ok(ALPHA),
        }
    }

    /// A width that may be a texture: a number as `alpha` checks it, or a texture's name.
    pub(super) fn textured_alpha(&self, key: &str, a: &Option<FractionDesc>) -> Result<Texture, SceneError> {
        match a {
            None => Ok(Texture::from(ALPHA)),
            Some(FractionDesc::Number(x)) => self.alpha(key, Some(*x)).map(Texture::from),
            Some(FractionDesc::Texture(t)) => {
                resolve_colour(&ColorDesc::Texture(t.clone()), self.textures).map_err(|m| self.at(key, m))
            }
        }
    }

    /// The widths (α_u, α_v): one `alpha` for both, or one per axis.
    pub(super) fn textured_widths(
        &self,
        a: &Option<FractionDesc>,
        u: &Option<FractionDesc>,
        v: &Option<FractionDesc>,
    ) -> Result<(Texture, Texture), SceneError> {
        match (a, u, v) {
            (a, None, None) => Ok((self.textured_alpha("alpha", a)?, self.textured_alpha("alpha", a)?)),
            (None, Some(_), Some(_)) => Ok((self.textured_alpha("alpha_u", u)?, self.textured_alpha("alpha_v", v)?)),
            _ => Err(self.at("alpha", "give `alpha`, or both `alpha_u` and `alpha_v`".into())),
        }
    }

    /// `material` emitting the radiance `emission` names (its key and value), if given.
    pub(super) fn emitting(
        &self,
        material: Material,
        emission: Option<(&str, &ColorDesc)>,
        two_sided: bool,
    ) -> Result<Material, SceneError> {
        match emission {
            Some((key, e)) => Ok(Material::Emitter(Box::new(Emitter {
                radiance: resolve_colour(e, self.textures).map_err(|m| self.at(key, m))?,
                two_sided,
                surface: material,
            }))),
            None => Ok(material),
        }
    }
}

/// `material` on both sides unless `two_sided` is false (two-sided by default).
pub(super) fn sided(material: Material, two_sided: &Option<bool>) -> Material {
    if two_sided.unwrap_or(true) {
        Material::TwoSided(Box::new(TwoSided { front: material.clone(), back: material }))
    } else {
        material
    }
}
