//! glTF's alpha as the opacity of glint's `mask` (Mitsuba's): alpha is baseColorFactor's
//! fourth component times the base colour texture's alpha channel. `MASK` makes the surface
//! present where alpha ≥ `alphaCutoff` (0.5 by default) and absent elsewhere; `BLEND` makes
//! it present with probability alpha, which a path tracer's average turns into partial
//! transparency. The texture's alpha becomes an image of its own (grey, decoded, among the
//! made files, thresholded for `MASK`) read with the base colour's sampler and transform, so
//! the image texture needs no alpha channel of its own.

use glint_core::Rgb;

use super::materials::Textures;
use crate::native::schema::FractionDesc;
use crate::reader::{made_bytes, MadeFiles};
use crate::source::MadeFile;

/// The opacity of material `m`, or `None` where it is opaque.
pub fn opacity(
    m: &gltf::Material,
    name: &str,
    textures: &mut Textures,
    made: &mut MadeFiles,
) -> Result<Option<FractionDesc>, String> {
    let cutoff = match m.alpha_mode() {
        gltf::material::AlphaMode::Opaque => return Ok(None),
        gltf::material::AlphaMode::Mask => Some(m.alpha_cutoff().unwrap_or(0.5)),
        gltf::material::AlphaMode::Blend => None,
    };
    if let Some(c) = cutoff {
        if !(c.is_finite() && c >= 0.0) {
            return Err(format!("{name}: alphaCutoff must be ≥ 0, got {c}"));
        }
    }
    let pbr = m.pbr_metallic_roughness();
    let factor = pbr.base_color_factor()[3].clamp(0.0, 1.0);
    if let Some(info) = pbr.base_color_texture() {
        let texture = info.texture();
        let file = textures.image(&texture)?.to_string();
        let bytes = made_bytes(made, &file).ok_or_else(|| format!("{name}: no image {file}"))?;
        let decoded = crate::image::decode_alpha(bytes).map_err(|e| format!("{name}: its base colour image: {e}"))?;
        if let Some((width, height, alpha)) = decoded {
            let (values, tint): (Vec<f32>, f32) = match cutoff {
                Some(c) => (alpha.iter().map(|a| if a * factor >= c { 1.0 } else { 0.0 }).collect(), 1.0),
                None => (alpha, factor),
            };
            let file = format!("gltf-opacity-{}", m.index().unwrap_or(0));
            let pixels = values.into_iter().map(Rgb::splat).collect();
            made.push((file.clone(), MadeFile::Image { width, height, pixels }));
            let transform = info.texture_transform().map(|t| (t.offset(), t.rotation(), t.scale()));
            let name = textures.make_of(&texture, &file, "opacity", true, None, [tint; 3], transform)?;
            return Ok(Some(FractionDesc::Texture(name)));
        }
    }
    let constant = match cutoff {
        Some(c) => threshold(factor, c),
        None => factor,
    };
    Ok((constant < 1.0).then_some(FractionDesc::Number(constant)))
}

/// `MASK`'s rule: present (1) where alpha reaches the cutoff, absent (0) below it.
fn threshold(alpha: f32, cutoff: f32) -> f32 {
    if alpha >= cutoff {
        1.0
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mask_keeps_what_reaches_the_cutoff() {
        assert_eq!(threshold(0.5, 0.5), 1.0);
        assert_eq!(threshold(0.49, 0.5), 0.0);
        assert_eq!(threshold(0.0, 0.0), 1.0);
    }
}
