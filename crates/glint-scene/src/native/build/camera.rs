//! The `[camera]` table: a pinhole, thin-lens or orthographic camera, checked.

use glint_core::camera::{Camera, Lens};

use super::checks::finite;
use super::Context;
use crate::error::SceneError;
use crate::located::Located;
use crate::native::schema::*;

pub(super) fn build_camera(cx: &Context, camera: &Located<CameraDesc>) -> Result<Camera, SceneError> {
    let c = &camera.value;
    let at = |key: &str, m: String| cx.error(&camera.span, Some(key), format!("camera: {m}"));
    let position = finite(c.position).map_err(|m| at("position", m))?;
    let look_at = finite(c.look_at).map_err(|m| at("look_at", m))?;
    let up = finite(c.up).map_err(|m| at("up", m))?;
    if !(c.fov > 0.0 && c.fov < 180.0) {
        return Err(at(
            "fov",
            format!("`fov` is the vertical field of view in degrees, between 0 and 180 (exclusive); got {}", c.fov),
        ));
    }
    let [width, height] = c.resolution;
    if width == 0 || height == 0 || width > 1 << 15 || height > 1 << 15 {
        return Err(at(
            "resolution",
            format!("`resolution` must be [width, height] with each between 1 and 32768, got [{width}, {height}]"),
        ));
    }
    let camera = Camera::new(position, look_at, up, c.fov, width, height).ok_or_else(|| {
        at(
            "look_at",
            "`look_at` must differ from `position`, and `up` must not be parallel to the view direction".into(),
        )
    })?;
    let length = |key: &str, v: f32| {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(at(key, format!("`{key}` must be a length > 0, got {v}")))
        }
    };
    let lens = match (c.aperture_radius, c.focus_distance, c.orthographic_height) {
        (None, None, None) => Lens::Pinhole,
        (None, None, Some(h)) => Lens::Orthographic { height: length("orthographic_height", h)? },
        (Some(r), Some(f), None) => {
            if !(r.is_finite() && r >= 0.0) {
                return Err(at("aperture_radius", format!("`aperture_radius` must be ≥ 0, got {r}")));
            }
            Lens::Thin { radius: r, focus_distance: length("focus_distance", f)? }
        }
        (_, _, Some(_)) => {
            return Err(at("orthographic_height", "an orthographic camera has no aperture or focus distance".into()))
        }
        _ => return Err(at("aperture_radius", "a thin lens needs both `aperture_radius` and `focus_distance`".into())),
    };
    let camera = camera.with_lens(lens);
    let camera = match c.crop {
        None => camera,
        Some([x0, y0, x1, y1]) => camera.with_crop(x0, y0, x1, y1).ok_or_else(|| {
            at(
                "crop",
                format!("`crop` [x0, y0, x1, y1] must be a rectangle of the {width}×{height} film with x0 < x1 and y0 < y1, got [{x0}, {y0}, {x1}, {y1}]"),
            )
        })?,
    };
    Ok(if c.mirror { camera.mirrored() } else { camera })
}
