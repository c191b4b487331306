//! Textures: pbrt's imagemap, checkerboard, scale, mix and constant textures, its procedural
//! ones (fbm, wrinkled, windy, marble, dots, bilerp), and the colour and fraction parameters
//! of materials, which name a texture or give a value.

use glam::Mat4;

use super::state::matrix_op;
use super::{Result, Translator};
use crate::error::SceneError;
use crate::located::Located;
use crate::native::schema::*;
use crate::pbrt::params::{Params, Textured};
use crate::pbrt::parse::Directive;
use crate::pbrt::spectra;

/// A texture as the translator keeps it: a constant folds into the parameters that use it.
#[derive(Clone)]
pub(super) enum Tex {
    Constant([f32; 3]),
    /// A glint texture, and its description when it is an image (to scale it).
    Glint(String, Option<TextureDesc>),
}

impl Tex {
    /// The value or the texture's name, as a colour parameter gives it.
    fn colour(self) -> ColorDesc {
        match self {
            Tex::Constant(c) => ColorDesc::Rgb(c),
            Tex::Glint(name, _) => ColorDesc::Texture(name),
        }
    }
}

impl Translator<'_> {
    /// A colour parameter: a value, or a texture (a constant one folded in).
    pub(super) fn colour(&self, p: &Params, name: &str, default: [f32; 3], albedo: bool) -> Result<ColorDesc> {
        match p.spectrum_or_texture(name, true).map_err(|f| self.fail(f))? {
            None => Ok(ColorDesc::Rgb(default)),
            Some(Textured::Value(s)) => {
                let rgb = if albedo { spectra::albedo(&s) } else { spectra::unbounded(&s) };
                rgb.map(ColorDesc::Rgb).map_err(|m| self.parser.error(self.param_at(p, name), format!("`{name}`: {m}")))
            }
            Some(Textured::Texture(t)) => {
                match self.spectrum_textures.get(&t).or_else(|| self.float_textures.get(&t)) {
                    Some(Tex::Constant(c)) => Ok(ColorDesc::Rgb(*c)),
                    Some(Tex::Glint(g, _)) => Ok(ColorDesc::Texture(g.clone())),
                    None => Err(self.unknown_texture(p, name, &t)),
                }
            }
        }
    }

    pub(super) fn fraction(&self, p: &Params, name: &str) -> Result<Option<FractionDesc>> {
        Ok(match p.float_or_texture(name).map_err(|f| self.fail(f))? {
            None => None,
            Some(Textured::Value(x)) => Some(FractionDesc::Number(x)),
            Some(Textured::Texture(t)) => match self.float_textures.get(&t) {
                Some(Tex::Constant(c)) => Some(FractionDesc::Number(c[0])),
                Some(Tex::Glint(g, _)) => Some(FractionDesc::Texture(g.clone())),
                None => return Err(self.unknown_texture(p, name, &t)),
            },
        })
    }

    /// A procedural texture made under a name of its own.
    fn procedural(&mut self, name: &str, d: &Directive, desc: TextureDesc) -> Tex {
        let glint = self.unique(&format!("texture \"{name}\""), d.at);
        self.scene.textures.insert(glint.clone(), Located { value: desc, span: None });
        Tex::Glint(glint, None)
    }

    pub(super) fn unknown_texture(&self, p: &Params, name: &str, texture: &str) -> SceneError {
        let names = self.float_textures.keys().chain(self.spectrum_textures.keys());
        let hint = crate::error::did_you_mean_among_keys(texture, names);
        self.parser.error(self.param_at(p, name), format!("`{name}`: no texture named `{texture}`{hint}"))
    }

    pub(super) fn texture(&mut self, d: &Directive) -> Result<()> {
        let p = self.params(d);
        let (name, class, kind) = (d.args[0].clone(), d.args[1].as_str(), d.args[2].as_str());
        let float = match class {
            "float" => true,
            "spectrum" | "color" => false,
            other => {
                return Err(self.parser.error(d.at, format!("a texture is \"float\" or \"spectrum\", not `{other}`")))
            }
        };
        let constant_of = |this: &Self, key: &str, default: f32| -> Result<Tex> {
            if float {
                match p.float_or_texture(key).map_err(|f| this.fail(f))? {
                    None => Ok(Tex::Constant([default; 3])),
                    Some(Textured::Value(x)) => Ok(Tex::Constant([x; 3])),
                    Some(Textured::Texture(t)) => {
                        this.float_textures.get(&t).cloned().ok_or_else(|| this.unknown_texture(&p, key, &t))
                    }
                }
            } else {
                match p.spectrum_or_texture(key, true).map_err(|f| this.fail(f))? {
                    None => Ok(Tex::Constant([default; 3])),
                    Some(Textured::Value(s)) => spectra::unbounded(&s)
                        .map(Tex::Constant)
                        .map_err(|m| this.parser.error(this.param_at(&p, key), m)),
                    Some(Textured::Texture(t)) => {
                        this.spectrum_textures.get(&t).cloned().ok_or_else(|| this.unknown_texture(&p, key, &t))
                    }
                }
            }
        };
        // pbrt's texture mappings: `uv` (scaled and offset), or coordinates made from the point
        // in the texture's space (the transform where the texture is made).
        let mapping = |this: &Self| -> Result<([[f32; 3]; 2], Option<MappingDesc>)> {
            let kind = p.string("mapping").map_err(|f| this.fail(f))?.unwrap_or_else(|| "uv".into());
            let g = |k: &str, dflt: f32| p.float(k, dflt).map_err(|f| this.fail(f));
            let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
            let transform = vec![matrix_op(this.state.ctm)];
            Ok(match kind.as_str() {
                "uv" => {
                    ([[g("uscale", 1.0)?, 0.0, g("udelta", 0.0)?], [0.0, g("vscale", 1.0)?, g("vdelta", 0.0)?]], None)
                }
                "spherical" => (identity, Some(MappingDesc::Spherical { transform })),
                "cylindrical" => (identity, Some(MappingDesc::Cylindrical { transform })),
                "planar" => {
                    let v = |k: &str, dflt: [f32; 3]| p.triple(k, dflt).map_err(|f| this.fail(f));
                    let planar = MappingDesc::Planar {
                        transform,
                        s_axis: Some(v("v1", [1.0, 0.0, 0.0])?),
                        t_axis: Some(v("v2", [0.0, 1.0, 0.0])?),
                        s_offset: g("udelta", 0.0)?,
                        t_offset: g("vdelta", 0.0)?,
                    };
                    (identity, Some(planar))
                }
                other => {
                    return Err(this.parser.error(
                        this.param_at(&p, "mapping"),
                        format!(
                            "texture mapping `{other}` is not known; pbrt's are uv, spherical, cylindrical and planar"
                        ),
                    ))
                }
            })
        };
        let tex = match kind {
            "constant" => constant_of(self, "value", 1.0)?,
            "imagemap" => {
                let file = p
                    .string("filename")
                    .map_err(|f| self.fail(f))?
                    .ok_or_else(|| self.parser.error(d.at, "an imagemap needs a `filename`"))?;
                let wrap = match p.string("wrap").map_err(|f| self.fail(f))?.as_deref() {
                    None | Some("repeat") => WrapDesc::Repeat,
                    Some("clamp") => WrapDesc::Clamp,
                    Some("black") => {
                        self.warn(d.at, "wrap mode `black` is not available: clamping instead");
                        WrapDesc::Clamp
                    }
                    Some(other) => {
                        return Err(self
                            .parser
                            .error(self.param_at(&p, "wrap"), format!("wrap mode `{other}` is not known")))
                    }
                };
                let filter = match p.string("filter").map_err(|f| self.fail(f))?.as_deref() {
                    Some("point") => TexelFilterDesc::Nearest,
                    _ => TexelFilterDesc::Bilinear,
                };
                let raw = match p.string("encoding").map_err(|f| self.fail(f))?.as_deref() {
                    // pbrt-v4: PNG files are sRGB, others linear unless told (float files are
                    // linear either way).
                    None => !file.to_ascii_lowercase().ends_with(".png"),
                    Some("sRGB") => false,
                    Some("linear") => true,
                    Some(other) => {
                        return Err(self.parser.error(
                            self.param_at(&p, "encoding"),
                            format!("encoding `{other}` is not supported; glint reads sRGB and linear"),
                        ))
                    }
                };
                if p.bool("invert", false).map_err(|f| self.fail(f))? {
                    return Err(self.parser.error(self.param_at(&p, "invert"), "`invert` is not supported"));
                }
                let scale = p.float("scale", 1.0).map_err(|f| self.fail(f))?;
                p.ignore(&["maxanisotropy"]);
                let (uv_transform, mapping) = mapping(self)?;
                let desc = TextureDesc::Image {
                    file,
                    wrap,
                    filter,
                    scale: None,
                    uv_transform: Some(uv_transform),
                    raw,
                    channel: None,
                    tint: (scale != 1.0).then_some([scale; 3]),
                    mapping,
                };
                let glint = self.unique(&format!("texture \"{name}\""), d.at);
                self.scene.textures.insert(glint.clone(), Located { value: desc.clone(), span: None });
                Tex::Glint(glint, Some(desc))
            }
            "checkerboard" => {
                let dimension = p.int("dimension", 2).map_err(|f| self.fail(f))?;
                let (Tex::Constant(even), Tex::Constant(odd)) =
                    (constant_of(self, "tex1", 1.0)?, constant_of(self, "tex2", 0.0)?)
                else {
                    return Err(self
                        .parser
                        .error(d.at, "a checkerboard of textures is not supported: give tex1 and tex2 as values"));
                };
                let desc = match dimension {
                    2 => {
                        let (uv_transform, mapping) = mapping(self)?;
                        TextureDesc::Checker {
                            even,
                            odd,
                            scale: Some(Scale2Desc::Uniform(1.0)),
                            uv_transform: Some(uv_transform),
                            mapping,
                        }
                    }
                    3 => {
                        if self.state.ctm != Mat4::IDENTITY {
                            self.warn(d.at, "a solid checkerboard's checks lie in the shape's own space, not the texture's transform");
                        }
                        TextureDesc::SolidChecker { even, odd, scale: Some(1.0) }
                    }
                    other => {
                        return Err(self
                            .parser
                            .error(d.at, format!("a checkerboard's dimension is 2 or 3, not {other}")))
                    }
                };
                let glint = self.unique(&format!("texture \"{name}\""), d.at);
                self.scene.textures.insert(glint.clone(), Located { value: desc, span: None });
                Tex::Glint(glint, None)
            }
            "scale" => {
                let a = constant_of(self, "tex", 1.0)?;
                let b = match p.float_or_texture("scale").map_err(|f| self.fail(f))? {
                    None => Tex::Constant([1.0; 3]),
                    Some(Textured::Value(x)) => Tex::Constant([x; 3]),
                    Some(Textured::Texture(t)) => {
                        self.float_textures.get(&t).cloned().ok_or_else(|| self.unknown_texture(&p, "scale", &t))?
                    }
                };
                match (a, b) {
                    (Tex::Constant(x), Tex::Constant(y)) => Tex::Constant([x[0] * y[0], x[1] * y[1], x[2] * y[2]]),
                    (Tex::Glint(_, Some(image)), Tex::Constant(k)) | (Tex::Constant(k), Tex::Glint(_, Some(image))) => {
                        let TextureDesc::Image { file, wrap, filter, scale, uv_transform, raw, channel, tint, mapping } =
                            image
                        else {
                            unreachable!("only images keep their description")
                        };
                        let tint = tint.unwrap_or([1.0; 3]);
                        let desc = TextureDesc::Image {
                            file,
                            wrap,
                            filter,
                            scale,
                            uv_transform,
                            raw,
                            channel,
                            tint: Some([tint[0] * k[0], tint[1] * k[1], tint[2] * k[2]]),
                            mapping,
                        };
                        let glint = self.unique(&format!("texture \"{name}\""), d.at);
                        self.scene.textures.insert(glint.clone(), Located { value: desc.clone(), span: None });
                        Tex::Glint(glint, Some(desc))
                    }
                    (a, b) => {
                        let desc = TextureDesc::Product { factors: [a.colour(), b.colour()] };
                        self.procedural(&name, d, desc)
                    }
                }
            }
            "mix" => {
                let (a, b) = (constant_of(self, "tex1", 0.0)?, constant_of(self, "tex2", 1.0)?);
                let amount = match p.float_or_texture("amount").map_err(|f| self.fail(f))? {
                    None => Tex::Constant([0.5; 3]),
                    Some(Textured::Value(x)) => Tex::Constant([x; 3]),
                    Some(Textured::Texture(t)) => {
                        self.float_textures.get(&t).cloned().ok_or_else(|| self.unknown_texture(&p, "amount", &t))?
                    }
                };
                match (a, b, amount) {
                    (Tex::Constant(x), Tex::Constant(y), Tex::Constant([w, ..])) => {
                        Tex::Constant([0, 1, 2].map(|i| (1.0 - w) * x[i] + w * y[i]))
                    }
                    (a, b, amount) => {
                        let desc = TextureDesc::Mix { first: a.colour(), second: b.colour(), amount: amount.colour() };
                        self.procedural(&name, d, desc)
                    }
                }
            }
            "directionmix" => {
                let (a, b) = (constant_of(self, "tex1", 0.0)?, constant_of(self, "tex2", 1.0)?);
                let direction = p.triple("dir", [0.0, 1.0, 0.0]).map_err(|f| self.fail(f))?;
                let desc = TextureDesc::DirectionMix {
                    first: a.colour(),
                    second: b.colour(),
                    direction,
                    transform: vec![matrix_op(self.state.ctm)],
                };
                self.procedural(&name, d, desc)
            }
            "fbm" | "wrinkled" | "windy" | "marble" => {
                // Solid textures: the point in the texture's space, the transform in force here.
                let transform = vec![matrix_op(self.state.ctm)];
                let roughness = Some(p.float("roughness", 0.5).map_err(|f| self.fail(f))?);
                let octaves = p.int("octaves", 8).map_err(|f| self.fail(f))?;
                let octaves = Some(u32::try_from(octaves).map_err(|_| {
                    self.parser.error(self.param_at(&p, "octaves"), format!("`octaves` must be positive, got {octaves}"))
                })?);
                let desc = match kind {
                    "fbm" => TextureDesc::Fbm { roughness, octaves, transform },
                    "wrinkled" => TextureDesc::Wrinkled { roughness, octaves, transform },
                    "windy" => TextureDesc::Windy { transform },
                    _ => TextureDesc::PbrtMarble {
                        roughness,
                        octaves,
                        scale: Some(p.float("scale", 1.0).map_err(|f| self.fail(f))?),
                        variation: Some(p.float("variation", 0.2).map_err(|f| self.fail(f))?),
                        transform,
                    },
                };
                self.procedural(&name, d, desc)
            }
            "dots" | "bilerp" => {
                let (uv_transform, mapping) = mapping(self)?;
                let desc = if kind == "dots" {
                    let (Tex::Constant(inside), Tex::Constant(outside)) =
                        (constant_of(self, "inside", 1.0)?, constant_of(self, "outside", 0.0)?)
                    else {
                        return Err(self.parser.error(
                            d.at,
                            "dots of textures are not supported: give `inside` and `outside` as values",
                        ));
                    };
                    TextureDesc::Dots { inside, outside, uv_transform: Some(uv_transform), mapping }
                } else {
                    let corner = |this: &Self, key: &str, default: f32| -> Result<[f32; 3]> {
                        match constant_of(this, key, default)? {
                            Tex::Constant(v) => Ok(v),
                            Tex::Glint(..) => Err(this
                                .parser
                                .error(this.param_at(&p, key), format!("a bilerp's `{key}` must be a value"))),
                        }
                    };
                    TextureDesc::Bilerp {
                        v00: corner(self, "v00", 0.0)?,
                        v01: corner(self, "v01", 1.0)?,
                        v10: corner(self, "v10", 0.0)?,
                        v11: corner(self, "v11", 1.0)?,
                        uv_transform: Some(uv_transform),
                        mapping,
                    }
                };
                self.procedural(&name, d, desc)
            }
            "ptex" => {
                return Err(self.parser.error(
                    d.at,
                    "`ptex` textures are not supported: glint has no Ptex reader (bake the texture to an image)",
                ))
            }
            other => {
                return Err(self.parser.error(
                    d.at,
                    format!(
                    "texture `{other}` is not supported; glint reads imagemap, checkerboard, scale, mix, directionmix, constant, fbm, wrinkled, windy, marble, dots and bilerp"
                ),
                ))
            }
        };
        if float {
            self.float_textures.insert(name, tex);
        } else {
            self.spectrum_textures.insert(name, tex);
        }
        Ok(())
    }
}
