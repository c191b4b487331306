//! The `[environment]` table: the background, the ambient light and the environment map,
//! which may only be turned.

use std::sync::Arc;

use glam::{Mat3, Vec3};
use glint_core::lights::EnvironmentMap;

use super::checks::non_negative;
use super::transform::build_transform;
use super::Context;
use crate::error::SceneError;
use crate::native::schema::*;
use crate::source::Source;

/// The environment map, loaded and set up for importance sampling.
pub(super) fn build_environment_map(
    desc: &EnvironmentDesc,
    source: &Source,
) -> Result<Option<Arc<EnvironmentMap>>, (&'static str, String)> {
    let Some(file) = &desc.map else { return Ok(None) };
    let (width, height, pixels) = match source.made_image(file) {
        Some(image) => image,
        None => {
            let bytes = source.read(file).map_err(|m| ("map", format!("environment map: {m}")))?;
            crate::image::decode(file, &bytes, false).map_err(|m| ("map", format!("environment map `{file}`: {m}")))?
        }
    };
    // Radiance is finite and never negative: one +inf texel made the map's importance
    // sampling black out the lit half of a sphere, one of −5 gave negative pixels.
    if let Some(i) = pixels.iter().position(|p| !p.is_finite() || p.min_element() < 0.0) {
        let (x, y) = (i % width as usize, i / width as usize);
        return Err((
            "map",
            format!("environment map `{file}`: texel ({x}, {y}) is {}; radiance must be finite and ≥ 0", pixels[i]),
        ));
    }
    let scale = desc.map_scale.unwrap_or(1.0);
    if !(scale.is_finite() && scale >= 0.0) {
        return Err(("map_scale", format!("`map_scale` must be a number ≥ 0, got {scale}")));
    }
    let rotation = environment_rotation(&desc.map_transform).map_err(|m| ("map_transform", m))?;
    Ok(Some(Arc::new(EnvironmentMap::new(width, height, pixels, scale, rotation))))
}

/// A transform that must be a rotation (an environment map can only be turned).
pub(crate) fn environment_rotation(ops: &[TransformOp]) -> Result<Mat3, String> {
    let Some(t) = build_transform(ops)? else { return Ok(Mat3::IDENTITY) };
    let m = Mat3::from_mat4(t.to_world);
    let orthonormal = (m.transpose() * m - Mat3::IDENTITY).to_cols_array().iter().all(|x| x.abs() < 1e-4);
    if !orthonormal || m.determinant() < 0.0 || t.to_world.w_axis.truncate().length() > 1e-6 {
        return Err("an environment map's transform must be a rotation (no scale, mirror or translation)".into());
    }
    Ok(m)
}

/// An environment colour (`background`, `ambient`), checked.
pub(super) fn environment_colour(cx: &Context, key: &str, v: Vector) -> Result<Vec3, SceneError> {
    non_negative(v).map_err(|m| cx.error_at_key(key, format!("environment `{key}`: {m}")))
}
