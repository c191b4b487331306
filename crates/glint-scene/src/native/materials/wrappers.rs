//! Materials that wrap others, named by reference in any order: `blend`, `null`, `mask`,
//! `normal-map`, `bump-map`, `two-sided` and `emitter`.

use glint_core::materials::{Blend, BumpMap, Diffuse, Mask, Material, NormalMap, TwoSided};
use glint_core::textures::{Mix, Texture};
use glint_core::Rgb;

use super::parameters::Parameters;
use super::Builder;
use crate::error::SceneError;
use crate::native::build::resolve_colour;
use crate::native::schema::{ColorDesc, MaterialDesc};

impl Builder<'_> {
    /// A wrapper: its own parameters, then the materials it names.
    pub(super) fn wrapper(&mut self, p: &Parameters, desc: &MaterialDesc) -> Result<Material, SceneError> {
        let (name, textures) = (p.name, p.textures);
        Ok(match desc {
            MaterialDesc::Blend { weight, first, second } => {
                let weight = p.fraction("weight", weight)?;
                let first = self.reference(name, "first", first)?;
                let second = self.reference(name, "second", second)?;
                blend(weight, first, second)
            }
            MaterialDesc::Null => Material::Mask(Box::new(Mask {
                opacity: Texture::Constant(Rgb::ZERO),
                material: Material::Diffuse(Diffuse { reflectance: Texture::Constant(Rgb::ZERO) }),
            })),
            MaterialDesc::Mask { opacity, material } => {
                let opacity = p.fraction("opacity", opacity)?;
                let material = self.reference(name, "material", material)?;
                Material::Mask(Box::new(Mask { opacity, material }))
            }
            MaterialDesc::NormalMap { normals, material } => {
                let normals = resolve_colour(normals, textures).map_err(|m| p.at("normals", m))?;
                let material = self.reference(name, "material", material)?;
                Material::NormalMap(Box::new(NormalMap { normals, material }))
            }
            MaterialDesc::BumpMap { height, scale, material } => {
                let height =
                    resolve_colour(&ColorDesc::Texture(height.clone()), textures).map_err(|m| p.at("height", m))?;
                if !height.has_uv_gradient() {
                    return Err(p.at(
                        "height",
                        "a bump map's height must vary with uv or the world point: an image, a checkerboard, a constant or one of pbrt's procedural textures (marble, wood, the solid checkerboard and mesh attributes have no slope along uv)".into(),
                    ));
                }
                if !scale.is_finite() {
                    return Err(p.at("scale", format!("`scale` must be a finite number; got {scale}")));
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
                p.emitting(surface, Some(("radiance", radiance)), *two_sided)?
            }
            _ => unreachable!("wrapper is given a wrapping material's description"),
        })
    }
}

/// (1 − w)·first + w·second. Of two Lambert reflectors alike in their sides, Lambert's lobe with
/// the mixed colour: the same BSDF and sampling density, and a material the path tracer's
/// lanes shade.
fn blend(weight: Texture, first: Material, second: Material) -> Material {
    if let (Some((a, a_two_sided)), Some((b, b_two_sided))) = (lambert(&first), lambert(&second)) {
        if a_two_sided == b_two_sided {
            let mix = Mix { weight, first: a.reflectance.clone(), second: b.reflectance.clone() };
            let side = Material::Diffuse(Diffuse { reflectance: Texture::Mix(Box::new(mix)) });
            return match a_two_sided {
                true => Material::TwoSided(Box::new(TwoSided { front: side.clone(), back: side })),
                false => side,
            };
        }
    }
    Material::Blend(Box::new(Blend { weight, first, second }))
}

/// A Lambert reflector's diffuse member, and whether it reflects on both sides (the same
/// diffuse material on each).
fn lambert(material: &Material) -> Option<(&Diffuse, bool)> {
    match material {
        Material::Diffuse(d) => Some((d, false)),
        Material::TwoSided(t) => match (&t.front, &t.back) {
            (Material::Diffuse(front), Material::Diffuse(back)) if front == back => Some((front, true)),
            _ => None,
        },
        _ => None,
    }
}
