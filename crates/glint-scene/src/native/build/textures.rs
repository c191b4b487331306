//! The `[textures]` table: checkerboards, images, marble, wood, mesh attributes and pbrt's
//! procedural textures, their uv maps, colours that name a texture, and the check that every
//! mesh attribute a texture reads is there.

use std::sync::Arc;

use glam::{Affine2, Affine3A, Vec2, Vec3};
use glint_core::scene::Object;
use glint_core::shapes::Shape;
use glint_core::textures::{
    AttributeTexture, Bilerp, Checker, DirectionMix, Dots, ImageTexture, Mapped, Marble, Mix, Noise, NoisePattern,
    Product, Projection, SolidChecker, TexelFilter, Texture, Wood, Wrap,
};

use super::checks::{non_negative, positive};
use super::transform::build_transform;
use super::Context;
use crate::error::{did_you_mean, SceneError};
use crate::native::schema::*;
use crate::source::Source;

/// Every texture of the `[textures]` table, by name; those made of others (products, mixes)
/// after the rest, which they name.
pub(super) fn build_textures(
    cx: &Context,
    file: &SceneFile,
    source: &Source,
) -> Result<Vec<(String, Texture)>, SceneError> {
    // Textures made of others last: they name the others.
    let mut textures = Vec::new();
    let (composites, others): (Vec<_>, Vec<_>) = file.textures.iter().partition(|(_, entry)| {
        matches!(entry.value, TextureDesc::Product { .. } | TextureDesc::Mix { .. } | TextureDesc::DirectionMix { .. })
    });
    for (name, entry) in others {
        let texture = build_texture(&entry.value, source)
            .map_err(|(key, m)| cx.error(&entry.span, Some(key), format!("texture `{name}`: {m}")))?;
        textures.push((name.clone(), texture));
    }
    let mut built = Vec::new();
    for &(name, entry) in &composites {
        let part = |key: &'static str, c: &ColorDesc| match c {
            ColorDesc::Texture(other) if composites.iter().any(|(p, _)| *p == other) => Err(cx.error(
                &entry.span,
                Some(key),
                format!("texture `{name}`: `{other}` is itself made of other textures, which a `{key}` cannot name"),
            )),
            _ => resolve_colour(c, &textures)
                .map_err(|m| cx.error(&entry.span, Some(key), format!("texture `{name}`: {m}"))),
        };
        let texture = match &entry.value {
            TextureDesc::Product { factors: [a, b] } => {
                Texture::Product(Box::new(Product { factors: [part("factors", a)?, part("factors", b)?] }))
            }
            TextureDesc::Mix { first, second, amount } => Texture::Mix(Box::new(Mix {
                weight: part("amount", amount)?,
                first: part("first", first)?,
                second: part("second", second)?,
            })),
            TextureDesc::DirectionMix { first, second, direction, transform } => {
                let to_world = build_transform(transform)
                    .map_err(|m| cx.error(&entry.span, Some("transform"), format!("texture `{name}`: {m}")))?;
                let direction = Vec3::from(*direction);
                let direction =
                    to_world.map_or(direction, |t| t.vector(direction)).try_normalize().ok_or_else(|| {
                        cx.error(
                            &entry.span,
                            Some("direction"),
                            format!("texture `{name}`: `direction` must be a nonzero vector"),
                        )
                    })?;
                Texture::DirectionMix(Box::new(DirectionMix {
                    direction,
                    first: part("first", first)?,
                    second: part("second", second)?,
                }))
            }
            _ => unreachable!("partitioned"),
        };
        built.push((name.clone(), texture));
    }
    textures.extend(built);
    Ok(textures)
}

/// A texture, or the key its error is about and the message.
pub(super) fn build_texture(desc: &TextureDesc, source: &Source) -> Result<Texture, (&'static str, String)> {
    let texture = build_unmapped(desc, source)?;
    let (TextureDesc::Checker { mapping: Some(mapping), .. }
    | TextureDesc::Image { mapping: Some(mapping), .. }
    | TextureDesc::Dots { mapping: Some(mapping), .. }
    | TextureDesc::Bilerp { mapping: Some(mapping), .. }) = desc
    else {
        return Ok(texture);
    };
    let (transform, projection) = match mapping {
        MappingDesc::Spherical { transform } => (transform, Projection::Spherical),
        MappingDesc::Cylindrical { transform } => (transform, Projection::Cylindrical),
        MappingDesc::Planar { transform, s_axis, t_axis, s_offset, t_offset } => {
            let axis = |key: &'static str, v: Option<Vector>, default: Vec3| -> Result<Vec3, (&'static str, String)> {
                let v = v.map_or(default, Vec3::from);
                if v.is_finite() && v != Vec3::ZERO {
                    Ok(v)
                } else {
                    Err(("mapping", format!("a planar mapping's `{key}` must be a vector other than zero, got {v}")))
                }
            };
            if !(s_offset.is_finite() && t_offset.is_finite()) {
                return Err(("mapping", "a planar mapping's offsets must be finite".into()));
            }
            let (s_axis, t_axis) = (axis("s_axis", *s_axis, Vec3::X)?, axis("t_axis", *t_axis, Vec3::Y)?);
            (transform, Projection::Planar { s_axis, t_axis, s_offset: *s_offset, t_offset: *t_offset })
        }
    };
    let to_texture = texture_space(transform).map_err(|m| ("mapping", format!("the mapping's transform: {m}")))?;
    Ok(Texture::Mapped(Box::new(Mapped { to_texture, projection, texture })))
}

/// World space → the space a texture's `transform` places in the world.
fn texture_space(transform: &[TransformOp]) -> Result<Affine3A, String> {
    let to_world = build_transform(transform)?;
    Ok(to_world.map_or(Affine3A::IDENTITY, |t| Affine3A::from_mat4(t.to_object)))
}

/// A texture as its uv makes it.
fn build_unmapped(desc: &TextureDesc, source: &Source) -> Result<Texture, (&'static str, String)> {
    let rgb = |key: &'static str, v: Vector| non_negative(v).map_err(|m| (key, m));
    let number = |key: &'static str, x: Option<f32>, default: f32| -> Result<f32, (&'static str, String)> {
        let x = x.unwrap_or(default);
        positive(x).map_err(|m| (key, format!("`{key}` {m}")))?;
        Ok(x)
    };
    let scale2 = |s: Option<Scale2Desc>, default: f32| -> Result<Vec2, (&'static str, String)> {
        let v = match s {
            None => Vec2::splat(default),
            Some(Scale2Desc::Uniform(x)) => Vec2::splat(x),
            Some(Scale2Desc::PerAxis(a)) => Vec2::from(a),
        };
        if !(v.is_finite() && v.min_element() > 0.0) {
            return Err(("scale", format!("`scale` must be positive, got {v}")));
        }
        Ok(v)
    };
    Ok(match desc {
        TextureDesc::Checker { even, odd, scale, uv_transform, .. } => Texture::Checker(Box::new(Checker {
            even: rgb("even", *even)?,
            odd: rgb("odd", *odd)?,
            uv_transform: uv_map(scale2(*scale, 8.0)?, uv_transform.as_ref())?,
        })),
        TextureDesc::SolidChecker { even, odd, scale } => Texture::SolidChecker(SolidChecker {
            even: rgb("even", *even)?,
            odd: rgb("odd", *odd)?,
            scale: number("scale", *scale, 1.0)?,
        }),
        TextureDesc::Image { file, wrap, filter, scale, uv_transform, raw, channel, tint, .. } => {
            // An image a reader made decoded is linear already; a file is decoded here.
            let (width, height, mut pixels) = match source.made_image(file) {
                Some(image) => image,
                None => {
                    let bytes = source.read(file).map_err(|m| ("file", format!("image file: {m}")))?;
                    crate::image::decode(file, &bytes, *raw).map_err(|m| ("file", format!("image `{file}`: {m}")))?
                }
            };
            if let Some(c) = *channel {
                if c > 2 {
                    return Err(("channel", format!("`channel` is 0 (red), 1 (green) or 2 (blue), got {c}")));
                }
                pixels.iter_mut().for_each(|p| *p = Vec3::splat(p[c as usize]));
            }
            if let Some(tint) = tint {
                let tint = rgb("tint", *tint)?;
                pixels.iter_mut().for_each(|p| *p *= tint);
            }
            Texture::Image(Arc::new(ImageTexture {
                width,
                height,
                pixels,
                wrap: match wrap {
                    WrapDesc::Repeat => Wrap::Repeat,
                    WrapDesc::Clamp => Wrap::Clamp,
                    WrapDesc::Mirror => Wrap::Mirror,
                },
                filter: match filter {
                    TexelFilterDesc::Bilinear => TexelFilter::Bilinear,
                    TexelFilterDesc::Nearest => TexelFilter::Nearest,
                },
                uv_transform: uv_map(scale2(*scale, 1.0)?, uv_transform.as_ref())?,
            }))
        }
        TextureDesc::Marble { base, vein, scale, turbulence, octaves } => Texture::Marble(Marble {
            base: rgb("base", *base)?,
            vein: rgb("vein", *vein)?,
            scale: number("scale", *scale, 4.0)?,
            turbulence: number("turbulence", *turbulence, 5.0)?,
            octaves: octaves.unwrap_or(6).clamp(1, 16),
        }),
        TextureDesc::Wood { light, dark, rings, turbulence } => Texture::Wood(Wood {
            light: rgb("light", *light)?,
            dark: rgb("dark", *dark)?,
            rings: number("rings", *rings, 8.0)?,
            turbulence: number("turbulence", *turbulence, 0.3)?,
        }),
        TextureDesc::Fbm { roughness, octaves, transform } => {
            let (omega, octaves) = noise_octaves(*roughness, *octaves)?;
            noise(transform, NoisePattern::Fbm { omega, octaves })?
        }
        TextureDesc::Wrinkled { roughness, octaves, transform } => {
            let (omega, octaves) = noise_octaves(*roughness, *octaves)?;
            noise(transform, NoisePattern::Wrinkled { omega, octaves })?
        }
        TextureDesc::Windy { transform } => noise(transform, NoisePattern::Windy)?,
        TextureDesc::PbrtMarble { roughness, octaves, scale, variation, transform } => {
            let (omega, octaves) = noise_octaves(*roughness, *octaves)?;
            let variation = variation.unwrap_or(0.2);
            if !variation.is_finite() {
                return Err(("variation", format!("`variation` must be finite, got {variation}")));
            }
            let scale = number("scale", *scale, 1.0)?;
            noise(transform, NoisePattern::Marble { omega, octaves, scale, variation })?
        }
        TextureDesc::Dots { inside, outside, uv_transform, .. } => Texture::Dots(Box::new(Dots {
            inside: rgb("inside", *inside)?,
            outside: rgb("outside", *outside)?,
            uv_transform: uv_map(Vec2::ONE, uv_transform.as_ref())?,
        })),
        TextureDesc::Bilerp { v00, v01, v10, v11, uv_transform, .. } => Texture::Bilerp(Box::new(Bilerp {
            v00: finite("v00", *v00)?,
            v01: finite("v01", *v01)?,
            v10: finite("v10", *v10)?,
            v11: finite("v11", *v11)?,
            uv_transform: uv_map(Vec2::ONE, uv_transform.as_ref())?,
        })),
        TextureDesc::Product { .. } | TextureDesc::Mix { .. } | TextureDesc::DirectionMix { .. } => {
            return Err(("type", "a texture made of others is made after them (see `build`)".into()))
        }
        TextureDesc::MeshAttribute { name, scale } => {
            if !(name.starts_with("vertex_") || name.starts_with("face_")) {
                return Err(("name", format!("a mesh attribute is named `vertex_…` or `face_…`, got `{name}`")));
            }
            let scale = scale.unwrap_or(1.0);
            if !(scale >= 0.0 && scale.is_finite()) {
                return Err(("scale", format!("`scale` must be ≥ 0, got {scale}")));
            }
            Texture::Attribute(Box::new(AttributeTexture { name: name.clone(), scale }))
        }
    })
}

/// pbrt's `roughness` (ω, each octave's weight over the last's; default ½) and `octaves`
/// (default 8).
fn noise_octaves(roughness: Option<f32>, octaves: Option<u32>) -> Result<(f32, u32), (&'static str, String)> {
    let omega = roughness.unwrap_or(0.5);
    if !omega.is_finite() {
        return Err(("roughness", format!("`roughness` must be finite, got {omega}")));
    }
    let octaves = octaves.unwrap_or(8);
    if !(1..=32).contains(&octaves) {
        return Err(("octaves", format!("`octaves` must be 1 to 32, got {octaves}")));
    }
    Ok((omega, octaves))
}

/// A noise pattern in the space its `transform` places.
fn noise(transform: &[TransformOp], pattern: NoisePattern) -> Result<Texture, (&'static str, String)> {
    let to_texture = texture_space(transform).map_err(|m| ("transform", format!("the texture's transform: {m}")))?;
    Ok(Texture::Noise(Box::new(Noise { to_texture, pattern })))
}

/// A value that may be negative (a bilinear blend's corners), but finite.
fn finite(key: &'static str, v: Vector) -> Result<glint_core::Rgb, (&'static str, String)> {
    let v = glint_core::Rgb::from(v);
    if v.is_finite() {
        Ok(v)
    } else {
        Err((key, format!("`{key}` must be finite, got {v}")))
    }
}

pub(in crate::native) fn resolve_colour(c: &ColorDesc, textures: &[(String, Texture)]) -> Result<Texture, String> {
    match c {
        ColorDesc::Rgb(v) => Ok(Texture::Constant(non_negative(*v)?)),
        ColorDesc::Texture(name) => textures.iter().find(|(n, _)| n == name).map(|(_, t)| t.clone()).ok_or_else(|| {
            let hint = did_you_mean(name, textures.iter().map(|(n, _)| n.as_str()));
            format!("unknown texture `{name}` (a colour is [r, g, b] or the name of a texture in [textures]){hint}")
        }),
    }
}

/// A texture's uv map: its `scale`, then its `uv_transform` (two rows of an affine map).
fn uv_map(scale: Vec2, rows: Option<&[[f32; 3]; 2]>) -> Result<Affine2, (&'static str, String)> {
    let Some([[a, b, c], [d, e, f]]) = rows.copied() else { return Ok(Affine2::from_scale(scale)) };
    let map = Affine2::from_cols_array(&[a, d, b, e, c, f]);
    if !map.is_finite() || map.matrix2.determinant() == 0.0 {
        return Err(("uv_transform", format!("`uv_transform` must be finite and invertible, got {rows:?}")));
    }
    Ok(map * Affine2::from_scale(scale))
}

/// Every `mesh-attribute` texture names an attribute some mesh of the scene has: a typo would
/// otherwise render black.
pub(super) fn check_mesh_attributes(
    cx: &Context,
    file: &SceneFile,
    textures: &[(String, Texture)],
    objects: &[Object],
) -> Result<(), SceneError> {
    let present: Vec<&str> = objects
        .iter()
        .filter_map(|o| match &o.shape {
            Shape::Mesh(m) => Some(m.attributes.iter().map(|a| a.name.as_str())),
            _ => None,
        })
        .flatten()
        .collect();
    for (name, texture) in textures {
        let Texture::Attribute(t) = texture else { continue };
        if !present.contains(&t.name.as_str()) {
            let span = file.textures.get(name).map(|e| e.span.clone());
            let known = if present.is_empty() {
                "no mesh has attributes".to_string()
            } else {
                format!("the meshes have {}", present.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", "))
            };
            return Err(cx.error(
                &span.flatten(),
                Some("name"),
                format!("texture `{name}`: no mesh of the scene has the attribute `{}` ({known})", t.name),
            ));
        }
    }
    Ok(())
}
