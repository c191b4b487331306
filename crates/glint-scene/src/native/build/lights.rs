//! The `[[lights]]` array: point, spot (with a projector's slide) and directional lights,
//! checked.

use glam::Vec3;
use glint_core::lights::{DirectionalLight, Falloff, Light, PointLight, Slide, SpotLight, SpotProfile};
use glint_core::textures::Texture;

use super::checks::{finite, non_negative};
use super::textures::resolve_colour;
use super::Context;
use crate::error::SceneError;
use crate::located::Located;
use crate::native::schema::*;

pub(super) fn build_light(
    cx: &Context,
    index: usize,
    light: &Located<LightDesc>,
    textures: &[(String, Texture)],
) -> Result<Light, SceneError> {
    let at = |key: &str, m: String| cx.error(&light.span, Some(key), format!("lights[{index}]: {m}"));
    let intensity = |color: Vector, intensity: f32| -> Result<Vec3, SceneError> {
        if !(intensity.is_finite() && intensity >= 0.0) {
            return Err(at("intensity", format!("`intensity` must be a finite number ≥ 0, got {intensity}")));
        }
        Ok(non_negative(color).map_err(|m| at("color", m))? * intensity)
    };
    Ok(match &light.value {
        LightDesc::Point { position, color, intensity: i, falloff } => Light::Point(PointLight {
            position: finite(*position).map_err(|m| at("position", m))?,
            intensity: intensity(*color, *i)?,
            falloff: falloff_of(*falloff),
        }),
        LightDesc::Spot {
            position,
            direction,
            cone_angle,
            focal_length,
            edge,
            profile,
            texture,
            up,
            color,
            intensity: i,
            falloff,
        } => {
            let axis = finite(*direction)
                .map_err(|m| at("direction", m))?
                .try_normalize()
                .ok_or_else(|| at("direction", "`direction` must not be the zero vector".into()))?;
            let profile = match profile.as_deref() {
                None | Some("smooth") => SpotProfile::Smooth,
                Some("linear") => SpotProfile::Linear,
                Some("projector") => SpotProfile::Projector,
                Some(other) => {
                    return Err(at(
                        "profile",
                        format!("unknown spot profile `{other}`, expected \"smooth\", \"linear\" or \"projector\""),
                    ))
                }
            };
            // A projector's slide is its frustum: a white one where no texture is given.
            let slide = match texture {
                Some(name) => {
                    Some(resolve_colour(&ColorDesc::Texture(name.clone()), textures).map_err(|m| at("texture", m))?)
                }
                None => (profile == SpotProfile::Projector).then_some(Texture::from(1.0)),
            };
            // A projector's frame has its image's proportions; a spot's slide is square.
            let aspect = match (&slide, profile) {
                (Some(Texture::Image(image)), SpotProfile::Projector) => image.width as f32 / image.height as f32,
                _ => 1.0,
            };
            let cone_angle = match (cone_angle, focal_length) {
                (Some(_), Some(_)) => {
                    return Err(at("focal_length", "give `cone_angle` or `focal_length`, not both".into()))
                }
                (Some(c), None) => *c,
                (None, None) => DEFAULT_CONE,
                (None, Some(f)) if profile == SpotProfile::Projector && *f > 0.0 && f.is_finite() => {
                    projector_cone(*f, aspect)
                }
                (None, Some(f)) => {
                    return Err(at(
                        "focal_length",
                        format!("`focal_length` (mm, > 0) sets a projector's cone, got {f} on a {profile:?} spot"),
                    ))
                }
            };
            if !(cone_angle > 0.0 && cone_angle <= 180.0) {
                return Err(at(
                    "cone_angle",
                    format!("`cone_angle` is a half-angle in degrees in (0, 180], got {cone_angle}"),
                ));
            }
            if !(*edge >= 0.0 && *edge <= cone_angle) {
                return Err(at("edge", format!("`edge` must be between 0 and `cone_angle` degrees, got {edge}")));
            }
            let mut spot = SpotLight::new(
                finite(*position).map_err(|m| at("position", m))?,
                axis,
                intensity(*color, *i)?,
                falloff_of(*falloff),
                cone_angle,
                *edge,
            )
            .with_profile(profile);
            if let Some(texture) = slide {
                let default_up = if axis.y.abs() < 0.9 { Vec3::Y } else { Vec3::Z };
                let up = match up {
                    Some(u) => finite(*u).map_err(|m| at("up", m))?,
                    None => default_up,
                };
                let right = axis
                    .cross(up)
                    .try_normalize()
                    .ok_or_else(|| at("up", "`up` must not lie along `direction`".into()))?;
                spot = spot.with_slide(Slide { texture, right, up: right.cross(axis), aspect });
            }
            Light::Spot(spot)
        }
        LightDesc::Directional { direction, color, intensity: i } => Light::Directional(DirectionalLight {
            direction: finite(*direction)
                .map_err(|m| at("direction", m))?
                .try_normalize()
                .ok_or_else(|| at("direction", "`direction` must not be the zero vector".into()))?,
            intensity: intensity(*color, *i)?,
        }),
    })
}

/// A spot's half-angle when none is given, in degrees.
const DEFAULT_CONE: f32 = 30.0;

/// The half-angle (degrees) across the width of a projector's frame of this aspect (width /
/// height) for a lens of `focal_length` mm on 35 mm film, the film's diagonal (43.3 mm)
/// spanning the frame's, as Mitsuba sizes a projector without `fov`.
fn projector_cone(focal_length: f32, aspect: f32) -> f32 {
    let half_diagonal = 0.5 * 36f32.hypot(24.0) / focal_length;
    (half_diagonal * aspect / aspect.hypot(1.0)).atan().to_degrees()
}

fn falloff_of(f: FalloffDesc) -> Falloff {
    match f {
        FalloffDesc::None => Falloff::None,
        FalloffDesc::InverseSquare => Falloff::InverseSquare,
    }
}
