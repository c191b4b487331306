//! BSDFs: each Mitsuba BSDF as a native material (wrappers as materials of their own that
//! name the nested ones), and a shape's material: its BSDF plus its area emitter's emission.

use super::properties::Properties;
use super::{polarized, Result, Translator};
use crate::located::Located;
use crate::mitsuba::xml::{Element, Position};
use crate::native::schema::*;

impl<'a> Translator<'a> {
    /// The material of a shape: its BSDF (Mitsuba's default: diffuse 0.5, or black diffuse on
    /// an emitter) plus its emission.
    pub(super) fn material_for(
        &mut self,
        bsdf: Option<&'a Element>,
        emission: Option<ColorDesc>,
        at: &Position,
    ) -> Result<String> {
        let key = bsdf.map(|b| (b.position.file, b.position.line, b.position.column));
        if emission.is_none() {
            if let Some(name) = key.and_then(|k| self.materials_by_element.get(&k)) {
                return Ok(name.clone());
            }
        }
        // Mitsuba's shapes without a BSDF are diffuse 0.5, but emitting ones black (checked on
        // Mitsuba 3.9.1): an area light reflects nothing unless it is given a BSDF.
        let default_reflectance = if emission.is_some() { 0.0 } else { 0.5 };
        let mut desc = match bsdf {
            Some(b) => self.bsdf(b)?,
            None => MaterialDesc::Diffuse {
                reflectance: Some(ColorDesc::Rgb([default_reflectance; 3])),
                emission: None,
                two_sided_emission: false,
                two_sided: Some(false),
            },
        };
        let base = match bsdf {
            Some(b) => b.attribute("id").map(str::to_string).unwrap_or(format!("bsdf@{}", b.position.line)),
            None if emission.is_some() => "default-black-diffuse".into(),
            None => "default-diffuse".into(),
        };
        let emits = emission.is_some();
        let name = match emission {
            Some(e) => {
                match (&mut desc, e) {
                    (MaterialDesc::Diffuse { emission, .. }, e) => *emission = Some(e),
                    (MaterialDesc::Phong { emission, .. }, ColorDesc::Rgb(e)) => *emission = Some(e),
                    (_, e) => {
                        // Any other BSDF: the surface under its own name, wrapped by the emitter.
                        let surface = format!("{base}+surface@{}", at.line);
                        let span = bsdf.and_then(|b| b.position.span.clone());
                        let surface_desc = std::mem::replace(
                            &mut desc,
                            MaterialDesc::Emitter { radiance: e, two_sided: false, material: surface.clone() },
                        );
                        self.scene.materials.insert(surface, Located { value: surface_desc, span });
                    }
                }
                format!("{base}+emitter@{}", at.line)
            }
            None => base,
        };
        let span = bsdf.and_then(|b| b.position.span.clone());
        self.scene.materials.insert(name.clone(), Located { value: desc, span });
        if !emits {
            if let Some(k) = key {
                self.materials_by_element.insert(k, name.clone());
            }
        }
        Ok(name)
    }

    pub(super) fn is_dielectric(&self, bsdf: &Element) -> bool {
        match bsdf.attribute("type") {
            Some("dielectric" | "roughdielectric") => true,
            Some("twosided" | "bumpmap" | "normalmap") => {
                bsdf.children.iter().filter(|c| c.tag == "bsdf").any(|c| self.is_dielectric(c))
            }
            _ => false,
        }
    }
    fn bsdf(&mut self, bsdf: &'a Element) -> Result<MaterialDesc> {
        let kind = bsdf.attribute("type").unwrap_or("");
        let p = self.properties(bsdf);
        // Nested BSDFs, inline or by reference (a reference to a texture is a parameter).
        let refers_to_bsdf =
            |c: &Element| c.attribute("id").and_then(|id| self.ids.get(id)).is_none_or(|target| target.tag == "bsdf");
        let nested: Vec<&'a Element> =
            bsdf.children.iter().filter(|c| c.tag == "bsdf" || (c.tag == "ref" && refers_to_bsdf(c))).collect();
        let needs = |t: &Self, n: usize| -> Result<()> {
            if nested.len() != n {
                let what = if n == 1 { "one nested <bsdf>".to_string() } else { format!("{n} nested <bsdf>s") };
                return Err(
                    t.error(&bsdf.position, format!("{} needs {what}, found {}", bsdf.describe(), nested.len()))
                );
            }
            Ok(())
        };
        let one_sided = Some(false);
        let desc = match kind {
            "twosided" => {
                if nested.is_empty() || nested.len() > 2 {
                    needs(self, 1)?;
                }
                let front = self.nested_material(bsdf, nested[0], "front")?;
                let back = match nested.get(1) {
                    Some(b) => Some(self.nested_material(bsdf, b, "back")?),
                    None => None,
                };
                MaterialDesc::TwoSided { front, back }
            }
            "normalmap" => {
                needs(self, 1)?;
                let Some(normals) = p.color(self, "normalmap")? else {
                    return Err(self.error(&bsdf.position, "a normalmap needs a `normalmap` texture (a raw bitmap)"));
                };
                let material = self.nested_material(bsdf, nested[0], "material")?;
                MaterialDesc::NormalMap { normals, material }
            }
            "bumpmap" => {
                // One nested BSDF and one texture of any name, either of them a reference.
                let mut materials = Vec::new();
                let mut heights = Vec::new();
                for child in bsdf.children.iter().filter(|c| matches!(c.tag.as_str(), "bsdf" | "texture" | "ref")) {
                    let target = if child.tag == "ref" { self.resolve(child)? } else { child };
                    match target.tag.as_str() {
                        "bsdf" => materials.push(child),
                        "texture" => {
                            if let Some(name) = child.attribute("name") {
                                p.used.borrow_mut().insert(name.to_string());
                            }
                            heights.push(target)
                        }
                        other => {
                            return Err(self.error(
                                &child.position,
                                format!("{} takes a <bsdf> and a <texture>, not a <{other}>", bsdf.describe()),
                            ))
                        }
                    }
                }
                if materials.len() != 1 || heights.len() != 1 {
                    return Err(self.error(
                        &bsdf.position,
                        format!(
                            "{} needs one nested <bsdf> and one <texture> (the height), found {} and {}",
                            bsdf.describe(),
                            materials.len(),
                            heights.len()
                        ),
                    ));
                }
                let height = self.texture(heights[0])?;
                let scale = p.float(self, "scale")?.unwrap_or(1.0);
                let material = self.nested_material(bsdf, materials[0], "material")?;
                MaterialDesc::BumpMap { height, scale, material }
            }
            "blendbsdf" => {
                needs(self, 2)?;
                let weight = self.fraction(&p, "weight")?;
                let first = self.nested_material(bsdf, nested[0], "first")?;
                let second = self.nested_material(bsdf, nested[1], "second")?;
                MaterialDesc::Blend { weight, first, second }
            }
            "mask" => {
                needs(self, 1)?;
                let opacity = self.fraction(&p, "opacity")?;
                let material = self.nested_material(bsdf, nested[0], "material")?;
                MaterialDesc::Mask { opacity, material }
            }
            // A medium's boundary, crossed without a bounce.
            "null" => MaterialDesc::Null,
            "diffuse" => MaterialDesc::Diffuse {
                reflectance: Some(p.color(self, "reflectance")?.unwrap_or(ColorDesc::Rgb([0.5; 3]))),
                emission: None,
                two_sided_emission: false,
                two_sided: one_sided,
            },
            "conductor" | "roughconductor" => {
                let specular_reflectance = p.color(self, "specular_reflectance")?;
                let eta = p.rgb(self, "eta")?;
                let k = p.rgb(self, "k")?;
                let (metal, eta, k) = match eta {
                    Some(eta) => (None, Some(eta), Some(k.unwrap_or([0.0; 3]))),
                    None => match p.string(self, "material")?.as_deref() {
                        // Mitsuba's default: a perfect mirror (η = 0, k = 1: F = 1).
                        None | Some("none") => (None, Some([0.0; 3]), Some([1.0; 3])),
                        Some(name) => {
                            if glint_core::materials::named_metal(name).is_none() {
                                return Err(self.error(
                                    &bsdf.position,
                                    format!(
                                        "unknown conductor material `{name}`; glint knows none, {}",
                                        glint_core::materials::METAL_NAMES.join(", ")
                                    ),
                                ));
                            }
                            (Some(name.to_string()), None, None)
                        }
                    },
                };
                if kind == "conductor" {
                    MaterialDesc::Conductor { metal, eta, k, specular_reflectance, two_sided: one_sided }
                } else {
                    let TexturedRoughness { alpha, alpha_u, alpha_v, distribution } = self.textured_alphas(&p)?;
                    MaterialDesc::RoughConductor {
                        metal,
                        eta,
                        k,
                        specular_reflectance,
                        alpha,
                        alpha_u,
                        alpha_v,
                        distribution: Some(distribution),
                        two_sided: one_sided,
                    }
                }
            }
            "dielectric" | "roughdielectric" | "thindielectric" => {
                let int_ior = Some(self.ior_ratio(&p, 1.5046)?);
                let ext_ior = Some(1.0);
                let specular_reflectance = p.color(self, "specular_reflectance")?;
                let specular_transmittance = p.color(self, "specular_transmittance")?;
                match kind {
                    "dielectric" => {
                        MaterialDesc::Dielectric { int_ior, ext_ior, specular_reflectance, specular_transmittance }
                    }
                    "thindielectric" => {
                        MaterialDesc::ThinDielectric { int_ior, ext_ior, specular_reflectance, specular_transmittance }
                    }
                    _ => {
                        let TexturedRoughness { alpha, alpha_u, alpha_v, distribution } = self.textured_alphas(&p)?;
                        MaterialDesc::RoughDielectric {
                            int_ior,
                            ext_ior,
                            specular_reflectance,
                            specular_transmittance,
                            alpha,
                            alpha_u,
                            alpha_v,
                            distribution: Some(distribution),
                        }
                    }
                }
            }
            "principled" => {
                let mut weight = |name: &str| self.fraction(&p, name);
                MaterialDesc::Principled {
                    roughness: weight("roughness")?,
                    anisotropic: weight("anisotropic")?,
                    metallic: weight("metallic")?,
                    spec_trans: weight("spec_trans")?,
                    spec_tint: weight("spec_tint")?,
                    sheen: weight("sheen")?,
                    sheen_tint: weight("sheen_tint")?,
                    flatness: weight("flatness")?,
                    clearcoat: weight("clearcoat")?,
                    clearcoat_gloss: weight("clearcoat_gloss")?,
                    base_color: p.color(self, "base_color")?,
                    specular: p.float(self, "specular")?,
                    eta: p.float(self, "eta")?,
                }
            }
            "principledthin" => {
                let mut weight = |name: &str| self.fraction(&p, name);
                let (roughness, anisotropic, spec_trans) =
                    (weight("roughness")?, weight("anisotropic")?, weight("spec_trans")?);
                let (spec_tint, sheen, sheen_tint, flatness) =
                    (weight("spec_tint")?, weight("sheen")?, weight("sheen_tint")?, weight("flatness")?);
                MaterialDesc::PrincipledThin {
                    base_color: p.color(self, "base_color")?,
                    roughness,
                    anisotropic,
                    spec_trans,
                    diff_trans: self.scalar(&p, "diff_trans")?,
                    eta: self.scalar(&p, "eta")?,
                    spec_tint,
                    sheen,
                    sheen_tint,
                    flatness,
                    diffuse_reflectance_sampling_rate: p.float(self, "diffuse_reflectance_sampling_rate")?,
                    specular_reflectance_sampling_rate: p.float(self, "specular_reflectance_sampling_rate")?,
                    specular_transmittance_sampling_rate: p.float(self, "specular_transmittance_sampling_rate")?,
                    diffuse_transmittance_sampling_rate: p.float(self, "diffuse_transmittance_sampling_rate")?,
                }
            }
            "plastic" | "roughplastic" => {
                let diffuse_reflectance =
                    Some(p.color(self, "diffuse_reflectance")?.unwrap_or(ColorDesc::Rgb([0.5; 3])));
                let specular_reflectance = p.color(self, "specular_reflectance")?;
                let int_ior = Some(self.ior_ratio(&p, 1.49)?);
                let ext_ior = Some(1.0);
                let nonlinear = p.boolean(self, "nonlinear")?.unwrap_or(false);
                if kind == "plastic" {
                    MaterialDesc::Plastic {
                        diffuse_reflectance,
                        specular_reflectance,
                        int_ior,
                        ext_ior,
                        nonlinear,
                        two_sided: one_sided,
                    }
                } else {
                    let distribution = self.distribution(&p)?;
                    let alpha = p.float(self, "alpha")?;
                    if p.find("alpha_u").is_some() || p.find("alpha_v").is_some() {
                        return Err(self.error(
                            &bsdf.position,
                            "roughplastic is isotropic: give `alpha`, not `alpha_u`/`alpha_v` (as Mitsuba requires)",
                        ));
                    }
                    MaterialDesc::RoughPlastic {
                        diffuse_reflectance,
                        specular_reflectance,
                        int_ior,
                        ext_ior,
                        nonlinear,
                        alpha,
                        distribution: Some(distribution),
                        two_sided: one_sided,
                    }
                }
            }
            // Without polarization Mitsuba's polarizer is a clear sheet that passes half of the
            // light (its RGB variants' reading): a thin sheet of index 1 (no reflection) whose
            // transmittance is half the polarizer's, whatever its angle.
            "polarizer" => {
                p.float(self, "theta")?;
                p.boolean(self, "polarizing")?;
                self.warn(
                    &bsdf.position,
                    "glint renders light without polarization: a polarizer passes half of the light whatever its angle, as in Mitsuba's RGB variants",
                );
                let half = match p.color(self, "transmittance")? {
                    None => ColorDesc::Rgb([0.5; 3]),
                    Some(ColorDesc::Rgb(c)) => ColorDesc::Rgb(c.map(|x| 0.5 * x)),
                    Some(ColorDesc::Texture(texture)) => {
                        let name = format!("half of {texture}");
                        let factors = [ColorDesc::Rgb([0.5; 3]), ColorDesc::Texture(texture)];
                        let desc = TextureDesc::Product { factors };
                        self.scene.textures.insert(name.clone(), Located { value: desc, span: None });
                        ColorDesc::Texture(name)
                    }
                };
                MaterialDesc::ThinDielectric {
                    int_ior: Some(1.0),
                    ext_ior: Some(1.0),
                    specular_reflectance: Some(ColorDesc::Rgb([0.0; 3])),
                    specular_transmittance: Some(half),
                }
            }
            // Without polarization, pplastic's Mueller matrices reduce to the Fresnel
            // reflectance and transmittance of unpolarized light: glint's Fresnel plastic.
            "pplastic" => {
                self.warn(
                    &bsdf.position,
                    "glint renders light without polarization: pplastic is rendered as Mitsuba's RGB variants render it",
                );
                if p.find("eta").is_some() && (p.find("int_ior").is_some() || p.find("ext_ior").is_some()) {
                    return Err(self.error(&bsdf.position, "give pplastic's `eta` or `int_ior`/`ext_ior`, not both"));
                }
                let eta = match p.float(self, "eta")? {
                    Some(eta) => eta,
                    None => self.ior_ratio(&p, 1.49)?,
                };
                MaterialDesc::FresnelPlastic {
                    diffuse_reflectance: Some(
                        p.color(self, "diffuse_reflectance")?.unwrap_or(ColorDesc::Rgb([0.5; 3])),
                    ),
                    specular_reflectance: p.color(self, "specular_reflectance")?,
                    int_ior: Some(eta),
                    ext_ior: Some(1.0),
                    alpha: p.float(self, "alpha")?,
                    alpha_u: p.float(self, "alpha_u")?,
                    alpha_v: p.float(self, "alpha_v")?,
                    distribution: Some(self.distribution(&p)?),
                }
            }
            "measured_polarized" | "retarder" => {
                return Err(self.error(&bsdf.position, polarized(&format!("<bsdf type=\"{kind}\">"))))
            }
            _ => {
                let why = match kind {
                    "hair" => " (glint has no hair fibre model)",
                    "measured" => " (glint reads no measured BSDF data)",
                    _ => "",
                };
                return Err(self.error(
                    &bsdf.position,
                    format!(
                        "<bsdf type=\"{kind}\"> is not supported{why}; glint reads diffuse, conductor, roughconductor, dielectric, thindielectric, roughdielectric, plastic, roughplastic, principled, principledthin, twosided, blendbsdf, mask, bumpmap, normalmap and null"
                    ),
                ));
            }
        };
        self.unused(&p);
        Ok(desc)
    }

    /// A nested <bsdf> (or a <ref> to one) as a named material of its own, for a wrapper.
    fn nested_material(&mut self, parent: &'a Element, child: &'a Element, role: &str) -> Result<String> {
        let element = if child.tag == "ref" { self.resolve(child)? } else { child };
        let key = (element.position.file, element.position.line, element.position.column);
        if let Some(name) = self.materials_by_element.get(&key) {
            return Ok(name.clone());
        }
        let name = match element.attribute("id") {
            Some(id) => id.to_string(),
            None => format!("bsdf@{}/{role}", parent.position.line),
        };
        let desc = self.bsdf(element)?;
        self.scene.materials.insert(name.clone(), Located { value: desc, span: element.position.span.clone() });
        self.materials_by_element.insert(key, name.clone());
        Ok(name)
    }

    /// A blend weight or an opacity: a number or a texture (default: unset, glint's 0.5).
    fn fraction(&mut self, p: &Properties<'a>, name: &str) -> Result<Option<FractionDesc>> {
        Ok(self.scalar(p, name)?.map(|f| match f {
            FractionDesc::Number(x) => FractionDesc::Number(x.clamp(0.0, 1.0)),
            texture => texture,
        }))
    }

    /// Property `name` where Mitsuba reads one number of a texture (`eval_1`), unbounded.
    fn scalar(&mut self, p: &Properties<'a>, name: &str) -> Result<Option<FractionDesc>> {
        Ok(match p.color(self, name)? {
            None => None,
            Some(ColorDesc::Texture(t)) => Some(FractionDesc::Texture(self.scalar_texture(&t))),
            Some(ColorDesc::Rgb(c)) => Some(FractionDesc::Number((c[0] + c[1] + c[2]) / 3.0)),
        })
    }

    /// Texture `name` where Mitsuba reads it as one number (`eval_1`: weights, opacities,
    /// the principled parameters). Mitsuba's checkerboard swaps its colours there (`color0`
    /// where the half-checks differ), which its references show; the checker is copied with
    /// them swapped.
    fn scalar_texture(&mut self, name: &str) -> String {
        let Some(Located { value: TextureDesc::Checker { even, odd, scale, uv_transform, mapping }, span }) =
            self.scene.textures.get(name)
        else {
            return name.to_string();
        };
        let swapped = TextureDesc::Checker {
            even: *odd,
            odd: *even,
            scale: *scale,
            uv_transform: *uv_transform,
            mapping: mapping.clone(),
        };
        let scalar = format!("{name}@scalar");
        let span = span.clone();
        self.scene.textures.insert(scalar.clone(), Located { value: swapped, span });
        scalar
    }

    /// The microfacet `distribution` (`beckmann` unless given, as in Mitsuba).
    fn distribution(&mut self, p: &Properties) -> Result<String> {
        let distribution = p.string(self, "distribution")?.unwrap_or_else(|| "beckmann".into());
        if distribution != "ggx" && distribution != "beckmann" {
            return Err(self.error(
                &p.element.position,
                format!("microfacet distribution `{distribution}`: glint has `beckmann` and `ggx`"),
            ));
        }
        // Visible-normal sampling or not changes only the noise.
        p.boolean(self, "sample_visible")?;
        Ok(distribution)
    }

    /// Roughness that may be textured (a conductor's, a dielectric's): `alpha`, or `alpha_u`
    /// and `alpha_v`, each a number or a texture, and the `distribution`.
    fn textured_alphas(&mut self, p: &Properties<'a>) -> Result<TexturedRoughness> {
        let distribution = self.distribution(p)?;
        let (alpha, alpha_u, alpha_v) =
            (self.textured_alpha(p, "alpha")?, self.textured_alpha(p, "alpha_u")?, self.textured_alpha(p, "alpha_v")?);
        if alpha.is_some() && (alpha_u.is_some() || alpha_v.is_some()) {
            return Err(self.error(&p.element.position, "give `alpha`, or `alpha_u` and `alpha_v`, not both"));
        }
        if alpha_u.is_some() != alpha_v.is_some() {
            return Err(self.error(&p.element.position, "`alpha_u` and `alpha_v` go together"));
        }
        Ok(TexturedRoughness { alpha, alpha_u, alpha_v, distribution })
    }

    /// A roughness that may be a texture (a conductor's): a number, or the texture as Mitsuba
    /// reads it as one number.
    fn textured_alpha(&mut self, p: &Properties<'a>, name: &str) -> Result<Option<FractionDesc>> {
        Ok(match p.color(self, name)? {
            None => None,
            Some(ColorDesc::Texture(t)) => Some(FractionDesc::Texture(self.scalar_texture(&t))),
            Some(ColorDesc::Rgb(c)) => Some(FractionDesc::Number(c[0])),
        })
    }

    /// int_ior / ext_ior, each a number or a named material.
    fn ior_ratio(&mut self, p: &Properties, default_inside: f32) -> Result<f32> {
        let ior = |name: &str, default: f32| -> Result<f32> {
            match p.string_or_number(self, name)? {
                None => Ok(default),
                Some(v) => v.parse::<f32>().ok().or_else(|| named_ior(&v)).ok_or_else(|| {
                    self.error(&p.element.position, format!("`{name}`: unknown index of refraction `{v}`"))
                }),
            }
        };
        let inside = ior("int_ior", default_inside)?;
        let outside = ior("ext_ior", 1.000277)?;
        Ok(inside / outside)
    }
}

/// Mitsuba's named indices of refraction.
fn named_ior(name: &str) -> Option<f32> {
    Some(match name {
        "vacuum" => 1.0,
        "helium" => 1.000036,
        "hydrogen" => 1.000132,
        "air" => 1.000277,
        "carbon dioxide" => 1.00045,
        "water" => 1.333,
        "acetone" => 1.36,
        "ethanol" => 1.361,
        "carbon tetrachloride" => 1.461,
        "glycerol" => 1.4729,
        "benzene" => 1.501,
        "silicone oil" => 1.52045,
        "bromine" => 1.661,
        "water ice" => 1.31,
        "fused quartz" => 1.458,
        "pyrex" => 1.470,
        "acrylic glass" => 1.49,
        "polypropylene" => 1.49,
        "bk7" => 1.5046,
        "sodium chloride" => 1.544,
        "amber" => 1.55,
        "pet" => 1.5750,
        "diamond" => 2.419,
        _ => return None,
    })
}

/// Microfacet widths, each a number or a texture, and the distribution's name.
struct TexturedRoughness {
    alpha: Option<FractionDesc>,
    alpha_u: Option<FractionDesc>,
    alpha_v: Option<FractionDesc>,
    distribution: String,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn named_indices_of_refraction() {
        assert_eq!(named_ior("bk7"), Some(1.5046));
    }
}
