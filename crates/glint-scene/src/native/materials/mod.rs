//! The `[materials]` table built into the core's closed set: each entry by its `type`, wrappers
//! (`blend`, `mask`, `two-sided`, `emitter`) resolved by name in any order, cycles refused.
//! Each kind reads its own parameters in the file of its family (`phong.rs`, `diffuse.rs`,
//! `conductor.rs`, `dielectric.rs`, `plastic.rs`, `principled.rs`, `wrappers.rs`), through
//! the readers of `parameters.rs`.

mod conductor;
mod dielectric;
mod diffuse;
mod parameters;
mod phong;
mod plastic;
mod principled;
mod wrappers;

use std::collections::BTreeMap;

use glint_core::materials::{Material, MAX_LEAVES};
use glint_core::textures::Texture;

use self::parameters::Parameters;
use super::build::Context;
use super::schema::MaterialDesc;
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
        let p = Parameters { cx: self.cx, textures: self.textures, name, span: &entry.span };
        let desc = &entry.value;
        match desc {
            MaterialDesc::Phong { .. } => phong::phong(&p, desc),
            MaterialDesc::Metal { .. } => phong::metal(&p, desc),
            MaterialDesc::Diffuse { .. } => diffuse::diffuse(&p, desc),
            MaterialDesc::DiffuseTransmission { .. } => diffuse::diffuse_transmission(&p, desc),
            MaterialDesc::Conductor { .. } => conductor::conductor(&p, desc),
            MaterialDesc::RoughConductor { .. } => conductor::rough_conductor(&p, desc),
            MaterialDesc::Dielectric { .. } => dielectric::dielectric(&p, desc),
            MaterialDesc::RoughDielectric { .. } => dielectric::rough_dielectric(&p, desc),
            MaterialDesc::ThinDielectric { .. } => dielectric::thin_dielectric(&p, desc),
            MaterialDesc::Plastic { .. } => plastic::plastic(&p, desc),
            MaterialDesc::RoughPlastic { .. } => plastic::rough_plastic(&p, desc),
            MaterialDesc::FresnelPlastic { .. } => plastic::fresnel_plastic(&p, desc),
            MaterialDesc::Principled { .. } => principled::principled(&p, desc),
            MaterialDesc::PrincipledThin { .. } => principled::principled_thin(&p, desc),
            MaterialDesc::Blend { .. }
            | MaterialDesc::Null
            | MaterialDesc::Mask { .. }
            | MaterialDesc::NormalMap { .. }
            | MaterialDesc::BumpMap { .. }
            | MaterialDesc::TwoSided { .. }
            | MaterialDesc::Emitter { .. } => self.wrapper(&p, desc),
        }
    }
}
