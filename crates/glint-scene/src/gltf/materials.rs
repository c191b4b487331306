//! glTF's metallic-roughness materials on glint's principled BSDF (the Disney model glTF's
//! is drawn from): base colour, metallic and roughness (α = roughness², as glTF), with their
//! textures (metallic from the blue channel, roughness from the green); transmission and
//! index (KHR_materials_transmission, _ior) on the solid principled BSDF when the material
//! has a volume, on the thin one when not (glTF's transmission is thin-walled without
//! KHR_materials_volume); clearcoat; emission (with _emissive_strength) as an emitter around
//! it; normal maps. Texture factors become the texture's tint; KHR_texture_transform and
//! glTF's downward v become the texture's uv map.

use std::collections::BTreeSet;

use glam::{Affine2, Mat2, Vec2};

use super::{alpha, normal_scale};
use crate::located::Located;
use crate::native::schema::*;
use crate::reader::{made_bytes, MadeFiles};

/// A glTF material as glint names it, whether it emits, whether it is partly transparent
/// (alpha `MASK` or `BLEND`), and the set of texture coordinates its textures read
/// (`TEXCOORD_n`).
pub struct MaterialInfo {
    pub name: String,
    pub emits: bool,
    pub alpha: bool,
    pub uv_set: u32,
    /// The same material with its base colour times the primitive's vertex colours, for
    /// primitives that have them.
    pub vertex_coloured: Option<String>,
    /// The absorbing medium inside the material's meshes (KHR_materials_volume's attenuation).
    pub interior: Option<String>,
}

/// The texture of a primitive's vertex colours (its mesh's `vertex_color` attribute).
const VERTEX_COLOURS: &str = "glTF vertex colours";

/// The materials: index 0 is glTF's default material (white, metallic 1, roughness 1), index
/// i + 1 the document's material i.
pub fn translate(
    document: &gltf::Document,
    images: &[String],
    coloured: &BTreeSet<usize>,
    made: &mut MadeFiles,
    scene: &mut SceneFile,
    warnings: &mut Vec<String>,
) -> Result<Vec<MaterialInfo>, String> {
    let mut out = Vec::new();
    // glTF's default material: white, metallic 1, roughness 1.
    let default = |base_color: ColorDesc| MaterialDesc::Principled {
        base_color: Some(base_color),
        roughness: Some(FractionDesc::Number(1.0)),
        anisotropic: None,
        metallic: Some(FractionDesc::Number(1.0)),
        spec_trans: None,
        specular: None,
        eta: Some(1.5),
        spec_tint: None,
        sheen: None,
        sheen_tint: None,
        flatness: None,
        clearcoat: None,
        clearcoat_gloss: None,
    };
    if !coloured.is_empty() {
        let attribute = TextureDesc::MeshAttribute { name: "vertex_color".into(), scale: None };
        scene.textures.insert(VERTEX_COLOURS.into(), Located { value: attribute, span: None });
    }
    // Its white base colour times the vertex colours is the vertex colours.
    let default_coloured = coloured.contains(&0).then(|| {
        let name = "glTF default × vertex colours".to_string();
        let variant = default(ColorDesc::Texture(VERTEX_COLOURS.into()));
        scene.materials.insert(name.clone(), Located { value: variant, span: None });
        name
    });
    scene.materials.insert("glTF default".into(), Located { value: default(ColorDesc::Rgb([1.0; 3])), span: None });
    out.push(MaterialInfo {
        name: "glTF default".into(),
        emits: false,
        alpha: false,
        uv_set: 0,
        vertex_coloured: default_coloured,
        interior: None,
    });
    let mut textures = Textures { images, scene_textures: Vec::new(), uv_sets: Vec::new() };
    // Each material, and again with vertex colours where a primitive with them uses it.
    let variants = document.materials().flat_map(|m| {
        let with_colours = coloured.contains(&(m.index().unwrap_or(0) + 1));
        [Some((m.clone(), false)), with_colours.then_some((m, true))].into_iter().flatten()
    });
    for (m, vertex_coloured) in variants {
        let index = m.index().unwrap_or(0);
        let name = match m.name() {
            Some(n) => format!("material {index} ({n})"),
            None => format!("material {index}"),
        };
        let name = if vertex_coloured { format!("{name} × vertex colours") } else { name };
        // The variant's warnings are the plain material's, said once.
        let mut repeated = Vec::new();
        let warnings: &mut Vec<String> = if vertex_coloured { &mut repeated } else { &mut *warnings };
        let say = |warnings: &mut Vec<String>, what: &str| warnings.push(format!("{name}: {what}"));
        let pbr = m.pbr_metallic_roughness();
        let [r, g, b, _] = pbr.base_color_factor();
        let base_color = match pbr.base_color_texture() {
            Some(info) => ColorDesc::Texture(textures.get(&info, "base colour", false, None, [r, g, b])?),
            None => ColorDesc::Rgb([r, g, b]),
        };
        let base_color = if vertex_coloured {
            let product = format!("{name}: base colour");
            let desc = TextureDesc::Product { factors: [base_color, ColorDesc::Texture(VERTEX_COLOURS.into())] };
            scene.textures.insert(product.clone(), Located { value: desc, span: None });
            ColorDesc::Texture(product)
        } else {
            base_color
        };
        let unlit_colour = m.extension_value("KHR_materials_unlit").map(|_| base_color.clone());
        let fraction = |textures: &mut Textures,
                        info: Option<gltf::texture::Info>,
                        what: &str,
                        channel: u8,
                        factor: f32|
         -> Result<FractionDesc, String> {
            Ok(match info {
                Some(info) => FractionDesc::Texture(textures.get(&info, what, true, Some(channel), [factor; 3])?),
                None => FractionDesc::Number(factor.clamp(0.0, 1.0)),
            })
        };
        let unit = |warnings: &mut Vec<String>, field: &str, value: f32| {
            if !(0.0..=1.0).contains(&value) {
                let taken = value.clamp(0.0, 1.0);
                say(warnings, &format!("{field} is {value}, outside [0, 1] as glTF requires: taken as {taken}"));
            }
            value.clamp(0.0, 1.0)
        };
        let metallic_factor = unit(warnings, "pbrMetallicRoughness.metallicFactor", pbr.metallic_factor());
        let roughness_factor = unit(warnings, "pbrMetallicRoughness.roughnessFactor", pbr.roughness_factor());
        let metallic = fraction(&mut textures, pbr.metallic_roughness_texture(), "metallic", 2, metallic_factor)?;
        let roughness = fraction(&mut textures, pbr.metallic_roughness_texture(), "roughness", 1, roughness_factor)?;
        let mut ior = m.ior().unwrap_or(1.5);
        if ior == 0.0 {
            // KHR_materials_ior: 0 stands for an infinite index (specular-glossiness files).
            say(warnings, "an index of 0 (infinite) is taken as 1000: a Fresnel reflectance of 0.996");
            ior = 1000.0;
        }
        if !(ior.is_finite() && ior >= 1.0) {
            return Err(format!("{name}: its index of refraction must be ≥ 1 (or 0), got {ior}"));
        }
        let transmission = match m.transmission() {
            Some(t) if t.transmission_factor() > 0.0 => {
                Some(fraction(&mut textures, t.transmission_texture(), "transmission", 0, t.transmission_factor())?)
            }
            _ => None,
        };
        let volume = m.volume().filter(|v| v.thickness_factor() > 0.0);
        // KHR_materials_volume's attenuation: light inside falls off as the colour to the power
        // of the distance over `attenuationDistance` (world units), an absorbing medium of
        // σ_a = −ln(colour) / distance in the material's meshes (the extension's meshes are
        // closed). A colour channel of 0 absorbs as if 10⁻⁶.
        // (The variant shares the plain material's MaterialInfo, and so its medium.)
        let interior = match &volume {
            Some(v) if !vertex_coloured && v.attenuation_distance().is_finite() && v.attenuation_distance() > 0.0 => {
                if v.thickness_texture().is_some() {
                    say(warnings, "the volume's thickness texture is not read (glint traces the mesh's own thickness)");
                }
                let distance = v.attenuation_distance();
                let sigma_a = v.attenuation_color().map(|c| (1.0 / c.clamp(1e-6, 1.0)).ln() / distance);
                let medium = format!("{name}: volume");
                let desc = MediumDesc::Homogeneous {
                    sigma_a: Some(sigma_a),
                    sigma_s: Some([0.0; 3]),
                    sigma_t: None,
                    albedo: None,
                    scale: None,
                    phase: None,
                    emission: None,
                };
                scene.media.insert(medium.clone(), Located { value: desc, span: None });
                Some(medium)
            }
            _ => None,
        };
        let (clearcoat, clearcoat_gloss) = clearcoat(&m, &name, warnings);
        // The thin principled BSDF has no metal: a metallic transmitter (glTF's default
        // metallic is 1) stays on the solid one, where metal does not transmit.
        let metallic_at_all = metallic_factor > 0.0;
        if transmission.is_some() && volume.is_none() && metallic_at_all {
            say(warnings, "it transmits but is metallic: rendered on the solid principled BSDF (metal does not transmit), so its dielectric part refracts rather than passing straight through a thin wall");
        }
        let principled = match (&transmission, &volume) {
            (Some(t), None) if !metallic_at_all => MaterialDesc::PrincipledThin {
                base_color: Some(base_color),
                roughness: Some(roughness),
                anisotropic: None,
                spec_trans: Some(t.clone()),
                diff_trans: None,
                eta: Some(FractionDesc::Number(ior)),
                spec_tint: None,
                sheen: None,
                sheen_tint: None,
                flatness: None,
                diffuse_reflectance_sampling_rate: None,
                specular_reflectance_sampling_rate: None,
                specular_transmittance_sampling_rate: None,
                diffuse_transmittance_sampling_rate: None,
            },
            _ => MaterialDesc::Principled {
                base_color: Some(base_color),
                roughness: Some(roughness),
                anisotropic: None,
                metallic: Some(metallic),
                spec_trans: transmission.clone(),
                specular: None,
                eta: Some(ior),
                spec_tint: None,
                sheen: None,
                sheen_tint: None,
                flatness: None,
                clearcoat,
                clearcoat_gloss,
            },
        };
        let transmits = matches!(principled, MaterialDesc::PrincipledThin { .. }) || transmission.is_some();
        // KHR_materials_unlit: the base colour as it is, whatever the light: an emitter of it
        // over a surface that scatters nothing.
        let unlit = unlit_colour.is_some();
        let surface = if unlit {
            let black = Some(ColorDesc::Rgb([0.0; 3]));
            MaterialDesc::Diffuse {
                reflectance: black,
                emission: None,
                two_sided_emission: false,
                two_sided: Some(true),
            }
        } else {
            principled
        };
        let mut current = format!("{name}: surface");
        scene.materials.insert(current.clone(), Located { value: surface, span: None });
        // glTF shades a double-sided surface from behind as from the front; glint's principled
        // BSDF is dark from behind unless it transmits.
        if m.double_sided() && !transmits {
            let wrapped = format!("{name}: double-sided");
            let desc = MaterialDesc::TwoSided { front: current, back: None };
            scene.materials.insert(wrapped.clone(), Located { value: desc, span: None });
            current = wrapped;
        }
        if let Some(normal) = m.normal_texture() {
            let set = normal.extension_value("KHR_texture_transform").and_then(|t| t.get("texCoord")?.as_u64());
            textures.uv_sets.push(set.map_or(normal.tex_coord(), |s| s as u32));
            let transform = normal.extension_value("KHR_texture_transform").map(|t| {
                let pair = |key: &str, default: [f32; 2]| {
                    t.get(key).and_then(|v| v.as_array()).map_or(default, |a| {
                        [0, 1].map(|i| a.get(i).and_then(serde_json::Value::as_f64).map_or(default[i], |x| x as f32))
                    })
                };
                let rotation = t.get("rotation").and_then(serde_json::Value::as_f64).unwrap_or(0.0) as f32;
                (pair("offset", [0.0; 2]), rotation, pair("scale", [1.0; 2]))
            });
            let file = textures.image(&normal.texture())?.to_string();
            let scale = normal.scale();
            let file = if scale == 1.0 {
                file
            } else {
                if !scale.is_finite() {
                    return Err(format!("{name}: normalTexture.scale must be a finite number, got {scale}"));
                }
                let bytes = made_bytes(made, &file).ok_or_else(|| format!("{name}: no image {file}"))?;
                let scaled = normal_scale::scaled_image(bytes, scale)
                    .map_err(|e| format!("{name}: its normal map `{file}`: {e}"))?;
                let file = format!("gltf-normals-{index}");
                made.push((file.clone(), scaled));
                file
            };
            let texture = textures.make_of(&normal.texture(), &file, "normals", true, None, [1.0; 3], transform)?;
            let wrapped = format!("{name}: normal-mapped");
            let desc = MaterialDesc::NormalMap { normals: ColorDesc::Texture(texture), material: current };
            scene.materials.insert(wrapped.clone(), Located { value: desc, span: None });
            current = wrapped;
        }
        if m.occlusion_texture().is_some() {
            say(warnings, "its occlusion map is not read (a path tracer finds occlusion itself)");
        }
        let opacity = alpha::opacity(&m, &name, &mut textures, made)?;
        let alpha = opacity.is_some();
        if let Some(opacity) = opacity {
            let wrapped = format!("{name}: alpha");
            let desc = MaterialDesc::Mask { opacity: Some(opacity), material: current };
            scene.materials.insert(wrapped.clone(), Located { value: desc, span: None });
            current = wrapped;
        }
        let strength = m.emissive_strength().unwrap_or(1.0);
        let factor = m.emissive_factor();
        if factor.iter().any(|c| *c < 0.0) {
            say(
                warnings,
                &format!("emissiveFactor is {factor:?}, negative where glTF requires [0, 1]: taken as 0 there"),
            );
        }
        let [er, eg, eb] = factor.map(|c| c.max(0.0) * strength);
        let emits = unlit || er > 0.0 || eg > 0.0 || eb > 0.0;
        if emits {
            let radiance = match m.emissive_texture() {
                _ if unlit => unlit_colour.clone().expect("kept for unlit materials"),
                Some(info) => ColorDesc::Texture(textures.get(&info, "emission", false, None, [er, eg, eb])?),
                None => ColorDesc::Rgb([er, eg, eb]),
            };
            let wrapped = format!("{name}: emitting");
            let desc = MaterialDesc::Emitter { radiance, two_sided: m.double_sided(), material: current };
            scene.materials.insert(wrapped.clone(), Located { value: desc, span: None });
            current = wrapped;
        }
        // A primitive has one set of uvs in glint: the one its material's textures name (the
        // base colour's, first met, where they differ).
        let mut sets = std::mem::take(&mut textures.uv_sets);
        let uv_set = sets.first().copied().unwrap_or(0);
        sets.sort_unstable();
        sets.dedup();
        if sets.len() > 1 {
            let names: Vec<String> = sets.iter().map(|s| format!("TEXCOORD_{s}")).collect();
            say(
                warnings,
                &format!(
                    "its textures read {}: glint reads one set per primitive, TEXCOORD_{uv_set}, for all of them",
                    names.join(" and ")
                ),
            );
        }
        match (vertex_coloured, out.last_mut()) {
            (true, Some(plain)) => plain.vertex_coloured = Some(current),
            _ => out.push(MaterialInfo { name: current, emits, alpha, uv_set, vertex_coloured: None, interior }),
        }
    }
    for (name, desc) in textures.scene_textures {
        scene.textures.insert(name, Located { value: desc, span: None });
    }
    Ok(out)
}

/// KHR_materials_clearcoat as the principled BSDF's clearcoat: its weight, and a gloss whose
/// α (Disney's lerp from 0.1 to 0.001) is glTF's α = roughness².
fn clearcoat(
    m: &gltf::Material,
    name: &str,
    warnings: &mut Vec<String>,
) -> (Option<FractionDesc>, Option<FractionDesc>) {
    let Some(ext) = m.extension_value("KHR_materials_clearcoat") else { return (None, None) };
    let number = |key: &str| ext.get(key).and_then(serde_json::Value::as_f64).unwrap_or(0.0) as f32;
    let weight = number("clearcoatFactor").clamp(0.0, 1.0);
    if weight == 0.0 {
        return (None, None);
    }
    if ["clearcoatTexture", "clearcoatRoughnessTexture", "clearcoatNormalTexture"].iter().any(|k| ext.get(*k).is_some())
    {
        warnings.push(format!("{name}: clearcoat textures are not read; its factors are"));
    }
    let r = number("clearcoatRoughnessFactor").clamp(0.0, 1.0);
    if r * r > 0.1 {
        warnings.push(format!(
            "{name}: a clearcoat rougher than √0.1 is rendered at α = 0.1, the principled coat's widest"
        ));
    }
    let gloss = ((0.1 - r * r) / (0.1 - 0.001)).clamp(0.0, 1.0);
    (Some(FractionDesc::Number(weight)), Some(FractionDesc::Number(gloss)))
}

/// The glint textures made so far, one per glTF texture and use.
pub(super) struct Textures<'a> {
    images: &'a [String],
    scene_textures: Vec<(String, TextureDesc)>,
    /// The texture coordinate sets the current material's textures read, in order.
    uv_sets: Vec<u32>,
}

impl Textures<'_> {
    /// A glint texture for a texture reference: its image, sampler, transform, the channel
    /// it is read from and the factor it is scaled by.
    fn get(
        &mut self,
        info: &gltf::texture::Info,
        what: &str,
        raw: bool,
        channel: Option<u8>,
        tint: [f32; 3],
    ) -> Result<String, String> {
        let transform = info.texture_transform();
        // KHR_texture_transform's texCoord overrides the texture's own.
        let set = transform.as_ref().and_then(|t| t.tex_coord()).unwrap_or(info.tex_coord());
        self.uv_sets.push(set);
        let transform = transform.map(|t| (t.offset(), t.rotation(), t.scale()));
        self.make(&info.texture(), what, raw, channel, tint, transform)
    }

    /// A glint texture of `file` (an image of `made`) with `texture`'s sampler.
    pub(super) fn make(
        &mut self,
        texture: &gltf::Texture,
        what: &str,
        raw: bool,
        channel: Option<u8>,
        tint: [f32; 3],
        transform: Option<([f32; 2], f32, [f32; 2])>,
    ) -> Result<String, String> {
        let file = self.image(texture)?.to_string();
        self.make_of(texture, &file, what, raw, channel, tint, transform)
    }

    /// The name of `texture`'s image among the made files.
    pub(super) fn image(&self, texture: &gltf::Texture) -> Result<&str, String> {
        let image = texture.source().index();
        self.images
            .get(image)
            .map(String::as_str)
            .ok_or_else(|| format!("texture {}: no image {image}", texture.index()))
    }

    /// A glint texture of the image `file` with `texture`'s sampler.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn make_of(
        &mut self,
        texture: &gltf::Texture,
        file: &str,
        what: &str,
        raw: bool,
        channel: Option<u8>,
        tint: [f32; 3],
        transform: Option<([f32; 2], f32, [f32; 2])>,
    ) -> Result<String, String> {
        let sampler = texture.sampler();
        let wrap = match sampler.wrap_s() {
            gltf::texture::WrappingMode::ClampToEdge => WrapDesc::Clamp,
            gltf::texture::WrappingMode::MirroredRepeat => WrapDesc::Mirror,
            gltf::texture::WrappingMode::Repeat => WrapDesc::Repeat,
        };
        let filter = match sampler.mag_filter() {
            Some(gltf::texture::MagFilter::Nearest) => TexelFilterDesc::Nearest,
            _ => TexelFilterDesc::Bilinear,
        };
        let name = format!("texture {} ({what}) #{}", texture.index(), self.scene_textures.len());
        let desc = TextureDesc::Image {
            file: file.to_string(),
            wrap,
            filter,
            scale: None,
            uv_transform: Some(uv_map(transform)),
            raw,
            channel,
            tint: (tint != [1.0; 3]).then_some(tint),
            mapping: None,
        };
        self.scene_textures.push((name.clone(), desc));
        Ok(name)
    }
}

/// The map from glint's uv (v up; the meshes' v was turned over at load) to the image's in
/// glint's convention, through KHR_texture_transform's offset · rotation · scale, which
/// works in glTF's uv (v down): F · M · F with F(u, v) = (u, 1 − v).
fn uv_map(transform: Option<([f32; 2], f32, [f32; 2])>) -> [[f32; 3]; 2] {
    let (offset, rotation, scale) = transform.unwrap_or(([0.0; 2], 0.0, [1.0; 2]));
    let (s, c) = rotation.sin_cos();
    let m = Affine2::from_translation(Vec2::from(offset))
        * Affine2::from_mat2(Mat2::from_cols_array(&[c, -s, s, c]))
        * Affine2::from_scale(Vec2::from(scale));
    let flip = Affine2::from_cols(Vec2::X, -Vec2::Y, Vec2::Y);
    let a = flip * m * flip;
    [
        [a.matrix2.x_axis.x, a.matrix2.y_axis.x, a.translation.x],
        [a.matrix2.x_axis.y, a.matrix2.y_axis.y, a.translation.y],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn apply(rows: [[f32; 3]; 2], uv: [f32; 2]) -> [f32; 2] {
        [0, 1].map(|r| rows[r][0] * uv[0] + rows[r][1] * uv[1] + rows[r][2])
    }

    #[test]
    fn the_uv_map_is_identity_without_a_transform_and_follows_gltf_with_one() {
        assert_eq!(uv_map(None), [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        // glTF: offset (0.5, 0), scale 2: its uv (0.1, 0.2) → (0.7, 0.4). In glint's terms
        // the surface's (0.1, 0.8) must reach the image's (0.7, 0.6).
        let rows = uv_map(Some(([0.5, 0.0], 0.0, [2.0, 2.0])));
        let out = apply(rows, [0.1, 0.8]);
        assert!((out[0] - 0.7).abs() < 1e-6 && (out[1] - 0.6).abs() < 1e-6, "{out:?}");
        // A quarter turn: glTF's (u, v) → (cos·u + sin·v, −sin·u + cos·v) = (v, −u) at 90°,
        // as three.js applies it: glTF (0.25, 0) → (0, −0.25), glint (0.25, 1) → (0, 1.25).
        let rows = uv_map(Some(([0.0, 0.0], std::f32::consts::FRAC_PI_2, [1.0, 1.0])));
        let out = apply(rows, [0.25, 1.0]);
        assert!((out[0] - 0.0).abs() < 1e-6 && (out[1] - 1.25).abs() < 1e-6, "{out:?}");
    }
}
