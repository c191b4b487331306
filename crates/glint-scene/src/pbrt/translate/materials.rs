//! Materials: pbrt's diffuse, conductor, dielectric, thin dielectric, coated diffuse and
//! conductor, diffuse transmission, mix and interface mapped onto glint's, with their
//! roughness, index and conductor parameters, and a normal map on any of them.

use glam::Vec3;

use super::textures::Tex;
use super::{Result, Translator};
use crate::located::Located;
use crate::native::schema::*;
use crate::pbrt::params::{Params, Textured};
use crate::pbrt::parse::{At, Directive};
use crate::pbrt::spectra::{self, Spectrum};

/// pbrt's `RoughnessToAlpha` (with `remaproughness`): α = √roughness.
fn alpha_of(roughness: f32, remap: bool) -> f32 {
    if remap {
        roughness.max(0.0).sqrt()
    } else {
        roughness
    }
}

impl Translator<'_> {
    /// The glint material a named material becomes, named at `at`. pbrt resolves the names
    /// when the scene is complete, so a material may be made after (or in a file included
    /// after) its use; `check_material_references` finds the names never made.
    pub(super) fn named_material(&mut self, name: &str, at: At) -> String {
        self.material_references.push((name.to_string(), at));
        format!("named:{name}")
    }

    /// An α as it is, or a roughness texture's mean value made an α as pbrt makes numbers
    /// (`remap`: its square root), for a coat that takes one number, with a warning saying so.
    fn mean_fraction(&mut self, fraction: &FractionDesc, at: At, remap: bool) -> Result<f32> {
        let texture = match fraction {
            FractionDesc::Number(x) => return Ok(*x),
            FractionDesc::Texture(t) => t.clone(),
        };
        let mean = match self.scene.textures.get(&texture).map(|t| &t.value) {
            Some(TextureDesc::Image { file, raw, channel, tint, .. }) => {
                let bytes = self.source.read(file).map_err(|m| self.parser.error(at, m))?;
                let (_, _, pixels) = crate::image::decode(file, &bytes, *raw)
                    .map_err(|m| self.parser.error(at, format!("`{file}`: {m}")))?;
                let value = |p: &glint_core::Rgb| match channel {
                    Some(c) => p[*c as usize],
                    None => (p.x + p.y + p.z) / 3.0,
                };
                let mean = pixels.iter().map(|p| f64::from(value(p))).sum::<f64>() / pixels.len().max(1) as f64;
                mean as f32 * tint.map_or(1.0, |t| (t[0] + t[1] + t[2]) / 3.0)
            }
            Some(TextureDesc::Checker { even, odd, .. }) => (even[0] + odd[0]) / 2.0,
            _ => {
                return Err(self
                    .parser
                    .error(at, "a coated material's roughness texture must be an image or a checkerboard"))
            }
        };
        let alpha = alpha_of(mean, remap);
        self.warn(
            at,
            format!("glint's coat takes one roughness: the texture's mean {mean}, α = {alpha}, is used everywhere"),
        );
        Ok(alpha)
    }

    /// Every named material used is made somewhere in the scene.
    pub(super) fn check_material_references(&self) -> Result<()> {
        for (name, at) in &self.material_references {
            if !self.named_materials.contains_key(name) {
                let hint = crate::error::did_you_mean_among_keys(name, self.named_materials.keys());
                return Err(self.parser.error(*at, format!("no material named `{name}`{hint}")));
            }
        }
        Ok(())
    }

    pub(super) fn default_material(&mut self) -> String {
        let name = "pbrt-default".to_string();
        self.scene.materials.entry(name.clone()).or_insert_with(|| Located {
            value: MaterialDesc::Diffuse {
                reflectance: Some(ColorDesc::Rgb([0.5; 3])),
                emission: None,
                two_sided_emission: false,
                two_sided: None,
            },
            span: None,
        });
        name
    }

    pub(super) fn current_material(&mut self) -> String {
        match self.state.material.clone() {
            Some(m) => m,
            None => self.default_material(),
        }
    }

    /// Roughness as glint's α: `None` for a smooth surface; (α_u, α_v) when anisotropic.
    fn roughness(&mut self, p: &Params, prefix: &str) -> Result<Option<(FractionDesc, Option<FractionDesc>)>> {
        let key = |k: &str| format!("{prefix}{k}");
        let remap = p.bool("remaproughness", true).map_err(|f| self.fail(f))?;
        let r = self.fraction(p, &key("roughness"))?;
        let u = self.fraction(p, &key("uroughness"))?.or_else(|| r.clone());
        let v = self.fraction(p, &key("vroughness"))?.or_else(|| r.clone());
        let alpha = |f: FractionDesc, this: &mut Self| match f {
            FractionDesc::Number(x) => FractionDesc::Number(alpha_of(x, remap)),
            FractionDesc::Texture(t) => {
                if remap {
                    this.warn(
                        p.at,
                        "a roughness texture is used as α directly (`remaproughness` applies to numbers only)",
                    );
                }
                FractionDesc::Texture(t)
            }
        };
        Ok(match (u, v) {
            (None, None) => None,
            (Some(FractionDesc::Number(a)), Some(FractionDesc::Number(b))) if a == 0.0 && b == 0.0 => None,
            (u, v) => {
                let u = alpha(u.unwrap_or(FractionDesc::Number(0.0)), self);
                let v = alpha(v.unwrap_or(FractionDesc::Number(0.0)), self);
                let isotropic = matches!((&u, &v), (FractionDesc::Number(a), FractionDesc::Number(b)) if a == b)
                    || matches!((&u, &v), (FractionDesc::Texture(a), FractionDesc::Texture(b)) if a == b);
                Some(if isotropic { (u, None) } else { (u, Some(v)) })
            }
        })
    }

    fn index(&self, p: &Params, name: &str, default: f32) -> Result<f32> {
        let at = self.param_at(p, name);
        if p.list.iter().any(|x| x.name == name && x.ty == "float") {
            return p.float(name, default).map_err(|f| self.fail(f));
        }
        match self.spectrum_or_file(p, name)? {
            None => Ok(default),
            Some(s) => spectra::index(&s).map_err(|m| self.parser.error(at, format!("`{name}`: {m}"))),
        }
    }

    /// A spectrum parameter, where a name ending in `.spd` is read as the file of
    /// wavelength–value pairs pbrt reads there (`"spectrum eta" "spds/Au.eta.spd"`).
    fn spectrum_or_file(&self, p: &Params, key: &str) -> Result<Option<Spectrum>> {
        match p.spectrum(key).map_err(|f| self.fail(f))? {
            Some(Spectrum::Named(file)) if file.to_ascii_lowercase().ends_with(".spd") => {
                let at = self.param_at(p, key);
                let bytes = self.source.read(&file).map_err(|m| self.parser.error(at, m))?;
                let samples = spectra::read_spd(&String::from_utf8_lossy(&bytes))
                    .map_err(|m| self.parser.error(at, format!("`{file}`: {m}")))?;
                Ok(Some(Spectrum::Sampled(samples)))
            }
            other => Ok(other),
        }
    }

    /// Conductor η and k, from names, values or an artist's `reflectance`.
    fn conductor_optics(&self, p: &Params, prefix: &str) -> Result<(Option<String>, [f32; 3], [f32; 3])> {
        let (eta_key, k_key) = (format!("{prefix}eta"), format!("{prefix}k"));
        let eta = self.spectrum_or_file(p, &eta_key)?;
        let k = self.spectrum_or_file(p, &k_key)?;
        if let Some(r) = p.spectrum("reflectance").map_err(|f| self.fail(f))? {
            if eta.is_some() || k.is_some() {
                return Err(self.parser.error(p.at, "give a conductor `reflectance` or its η and k, not both"));
            }
            let r = spectra::albedo(&r).map_err(|m| self.parser.error(self.param_at(p, "reflectance"), m))?;
            // pbrt: η = 1, k = 2√r / √(1 − r), the metal whose normal reflectance is r.
            let k = r.map(|r| {
                let r = r.min(0.9999);
                2.0 * r.sqrt() / (1.0 - r).sqrt()
            });
            return Ok((None, [1.0; 3], k));
        }
        let copper = glint_core::materials::named_metal("Cu").expect("glint knows copper");
        let named = |s: &Option<Spectrum>| match s {
            Some(Spectrum::Named(n)) => Some(n.clone()),
            _ => None,
        };
        if let (Some(a), Some(b)) = (named(&eta), named(&k)) {
            let metal = spectra::metal(&a, &b).map_err(|m| self.parser.error(self.param_at(p, &eta_key), m))?;
            return Ok((Some(metal.to_string()), [0.0; 3], [0.0; 3]));
        }
        let value = |s: &Option<Spectrum>, key: &str, default: Vec3| -> Result<[f32; 3]> {
            match s {
                None => Ok(default.to_array()),
                Some(Spectrum::Named(n)) => Err(self.parser.error(
                    self.param_at(p, key),
                    format!("`{n}`: a named metal needs both its η and k spectra (metal-Cu-eta with metal-Cu-k)"),
                )),
                Some(s) => spectra::unbounded(s).map_err(|m| self.parser.error(self.param_at(p, key), m)),
            }
        };
        if eta.is_none() && k.is_none() {
            return Ok((Some("Cu".into()), [0.0; 3], [0.0; 3]));
        }
        Ok((None, value(&eta, &eta_key, copper.0)?, value(&k, &k_key, copper.1)?))
    }

    pub(super) fn material(&mut self, d: &Directive, kind: &str, name: String) -> Result<()> {
        let p = self.params(d);
        p.ignore(&["type"]);
        // pbrt-v4's `displacement` bump-maps the surface: the shading normal tilts with the
        // height's slope in uv (a constant height tilts nothing).
        let bump = match p.float_or_texture("displacement").map_err(|f| self.fail(f))? {
            Some(Textured::Texture(t)) => match self.float_textures.get(&t) {
                Some(Tex::Glint(texture, _)) => Some(texture.clone()),
                Some(Tex::Constant(_)) => None,
                None => return Err(self.unknown_texture(&p, "displacement", &t)),
            },
            Some(Textured::Value(_)) | None => None,
        };
        let desc = match kind {
            "diffuse" => MaterialDesc::Diffuse {
                reflectance: Some(self.colour(&p, "reflectance", [0.5; 3], true)?),
                emission: None,
                two_sided_emission: false,
                two_sided: None,
            },
            "conductor" => {
                let (metal, eta, k) = self.conductor_optics(&p, "")?;
                let (eta, k) = if metal.is_some() { (None, None) } else { (Some(eta), Some(k)) };
                conductor(metal, eta, k, self.roughness(&p, "")?)
            }
            "dielectric" | "thindielectric" => {
                let eta = self.index(&p, "eta", 1.5)?;
                if !(eta.is_finite() && eta > 0.0) {
                    return Err(self.parser.error(self.param_at(&p, "eta"), format!("`eta` must be > 0, got {eta}")));
                }
                if kind == "thindielectric" {
                    MaterialDesc::ThinDielectric { int_ior: Some(eta), ext_ior: Some(1.0), specular_reflectance: None, specular_transmittance: None }
                } else {
                    match self.roughness(&p, "")? {
                        None => MaterialDesc::Dielectric { int_ior: Some(eta), ext_ior: Some(1.0), specular_reflectance: None, specular_transmittance: None },
                        Some((u, v)) => MaterialDesc::RoughDielectric {
                            int_ior: Some(eta),
                            ext_ior: Some(1.0),
                            specular_reflectance: None,
                            specular_transmittance: None,
                            alpha: if v.is_none() { Some(u.clone()) } else { None },
                            alpha_u: v.is_some().then(|| u.clone()),
                            alpha_v: v,
                            distribution: None,
                        },
                    }
                }
            }
            "coateddiffuse" => {
                let reflectance = self.colour(&p, "reflectance", [0.5; 3], true)?;
                let eta = self.index(&p, "eta", 1.5)?;
                // glint's rough plastic takes one α: an anisotropic pair becomes its geometric
                // mean, a texture its mean value, with a warning.
                let alpha = match self.roughness(&p, "")? {
                    None => None,
                    Some((u, v)) => {
                        let at = self.param_at(&p, "roughness");
                        let remap = p.bool("remaproughness", true).map_err(|f| self.fail(f))?;
                        let u = self.mean_fraction(&u, at, remap)?;
                        let v = match &v {
                            Some(v) => self.mean_fraction(v, at, remap)?,
                            None => u,
                        };
                        if u != v {
                            self.warn(at, format!("glint's coat is isotropic: the roughnesses α = {u} and {v} become their geometric mean"));
                        }
                        let alpha = (u * v).sqrt();
                        if alpha.is_nan() {
                            return Err(self.parser.error(at, "a coateddiffuse's roughness must be a number ≥ 0"));
                        }
                        Some(alpha)
                    }
                };
                p.ignore(&["thickness", "g", "maxdepth", "nsamples"]);
                if p.spectrum("albedo").map_err(|f| self.fail(f))?.is_some_and(|a| a != Spectrum::Rgb([0.0; 3])) {
                    self.warn(d.at, "coateddiffuse: the layer's `albedo` is ignored (glint's coat holds no medium)");
                }
                self.warn(d.at, "coateddiffuse is approximated by glint's plastic (a diffuse base under a dielectric coat, Mitsuba's model): no layer thickness, and the coat's inter-reflection is Mitsuba's closed form rather than pbrt's random walk");
                match alpha {
                    None => MaterialDesc::Plastic { diffuse_reflectance: Some(reflectance), specular_reflectance: None, int_ior: Some(eta), ext_ior: Some(1.0), nonlinear: false, two_sided: None },
                    Some(a) => MaterialDesc::RoughPlastic { diffuse_reflectance: Some(reflectance), specular_reflectance: None, int_ior: Some(eta), ext_ior: Some(1.0), nonlinear: false, alpha: Some(a), distribution: None, two_sided: None },
                }
            }
            "coatedconductor" => {
                let interface_eta = self.index(&p, "interface.eta", 1.5)?;
                let (metal, eta, k) = self.conductor_optics(&p, "conductor.")?;
                let (eta, k) = match metal {
                    Some(m) => glint_core::materials::named_metal(&m).map(|(e, k)| (e.to_array(), k.to_array())).unwrap_or((eta, k)),
                    None => (eta, k),
                };
                // Seen through the coat, the metal's indices are relative to the coat's.
                let (eta, k) = (eta.map(|x| x / interface_eta), k.map(|x| x / interface_eta));
                let _ = self.roughness(&p, "interface.")?;
                let roughness = self.roughness(&p, "conductor.")?;
                p.ignore(&["thickness", "g", "maxdepth", "nsamples", "albedo"]);
                self.warn(d.at, "coatedconductor is approximated by its conductor alone, its η and k taken relative to the coat's index: the coat's own reflection and roughness are left out");
                conductor(None, Some(eta), Some(k), roughness)
            }
            "diffusetransmission" => {
                let scale = p.float("scale", 1.0).map_err(|f| self.fail(f))?;
                let scaled = |c: ColorDesc| match c {
                    ColorDesc::Rgb(rgb) => Ok(ColorDesc::Rgb(rgb.map(|x| (x * scale).clamp(0.0, 1.0)))),
                    texture if scale == 1.0 => Ok(texture),
                    ColorDesc::Texture(_) => Err(self.parser.error(self.param_at(&p, "scale"), "a diffusetransmission's `scale` with a textured albedo is not supported")),
                };
                MaterialDesc::DiffuseTransmission {
                    reflectance: Some(scaled(self.colour(&p, "reflectance", [0.25; 3], true)?)?),
                    transmittance: Some(scaled(self.colour(&p, "transmittance", [0.25; 3], true)?)?),
                }
            }
            "mix" => {
                let names = p.strings("materials", &["string"]).map_err(|f| self.fail(f))?;
                let [first, second] = names.unwrap_or_default() else {
                    return Err(self.parser.error(d.at, "a mix material needs `\"string materials\" [ \"a\" \"b\" ]`, two named materials"));
                };
                let at = self.param_at(&p, "materials");
                let (first, second) = (self.named_material(first, at), self.named_material(second, at));
                MaterialDesc::Blend { weight: Some(self.fraction(&p, "amount")?.unwrap_or(FractionDesc::Number(0.5))), first, second }
            }
            "interface" | "none" | "" => {
                let inner = self.default_material();
                MaterialDesc::Mask { opacity: Some(FractionDesc::Number(0.0)), material: inner }
            }
            other => {
                return Err(self.parser.error(
                    d.at,
                    format!("material `{other}` is not supported; glint reads diffuse, diffusetransmission, conductor, dielectric, thindielectric, coateddiffuse, coatedconductor, mix and interface"),
                ))
            }
        };
        let normal_map = p.string("normalmap").map_err(|f| self.fail(f))?;
        let desc = match (normal_map, bump) {
            (None, None) => desc,
            (None, Some(height)) => {
                let inner = format!("{name}:base");
                self.scene.materials.insert(inner.clone(), Located { value: desc, span: None });
                MaterialDesc::BumpMap { height, scale: 1.0, material: inner }
            }
            (Some(file), bump) => {
                if bump.is_some() {
                    self.warn(d.at, "a material with a `normalmap` ignores its `displacement`, as pbrt does");
                }
                let inner = format!("{name}:base");
                self.scene.materials.insert(inner.clone(), Located { value: desc, span: None });
                let texture = self.unique("normal map", d.at);
                let image = TextureDesc::Image {
                    file,
                    wrap: WrapDesc::Repeat,
                    filter: TexelFilterDesc::Bilinear,
                    scale: None,
                    uv_transform: None,
                    raw: true,
                    channel: None,
                    tint: None,
                    mapping: None,
                };
                self.scene.textures.insert(texture.clone(), Located { value: image, span: None });
                MaterialDesc::NormalMap { normals: ColorDesc::Texture(texture), material: inner }
            }
        };
        self.scene.materials.insert(name, Located { value: desc, span: None });
        Ok(())
    }
}

/// A two-sided metal: smooth without roughness, else GGX of width α (or α_u, α_v).
fn conductor(
    metal: Option<String>,
    eta: Option<[f32; 3]>,
    k: Option<[f32; 3]>,
    roughness: Option<(FractionDesc, Option<FractionDesc>)>,
) -> MaterialDesc {
    match roughness {
        None => MaterialDesc::Conductor { metal, eta, k, specular_reflectance: None, two_sided: Some(true) },
        Some((u, v)) => MaterialDesc::RoughConductor {
            metal,
            eta,
            k,
            specular_reflectance: None,
            alpha: if v.is_none() { Some(u.clone()) } else { None },
            alpha_u: v.is_some().then(|| u.clone()),
            alpha_v: v,
            distribution: None,
            two_sided: Some(true),
        },
    }
}
