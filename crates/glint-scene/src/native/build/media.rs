//! The `[media]` table: homogeneous and grid media with their phase functions, the media
//! on either side of each shape, and the camera's.

use glam::{Affine3A, Vec3};
use glint_core::media::{
    box_to_world, Albedo, GridMedium, Homogeneous, Medium, MediumInterface, MediumKind, PhaseFunction, VoxelField,
};

use super::checks::{finite, non_negative};
use super::transform::build_transform;
use super::Context;
use crate::error::{did_you_mean, SceneError};
use crate::native::schema::*;
use crate::source::Source;

/// What `build_media` gives.
type SceneMedia = (Vec<Medium>, Vec<MediumInterface>, Option<u32>);

/// The scene's media, the interface of each shape (by shape, empty without media) and the
/// camera's medium.
pub(super) fn build_media(cx: &Context, file: &SceneFile, source: &Source) -> Result<SceneMedia, SceneError> {
    let names: Vec<&String> = file.media.keys().collect();
    let index =
        |name: &str| -> Result<u32, String> {
            names.iter().position(|n| *n == name).map(|i| i as u32).ok_or_else(|| {
                format!("unknown medium `{name}`{}", did_you_mean(name, names.iter().map(|n| n.as_str())))
            })
        };
    let mut media = Vec::new();
    for (name, entry) in &file.media {
        let at = |key: &str, m: String| cx.error(&entry.span, Some(key), format!("medium `{name}`: {m}"));
        media.push(build_medium(&entry.value, source).map_err(|(key, m)| at(key, m))?);
    }
    let camera = &file.camera;
    let camera_medium = match &camera.value.medium {
        Some(name) => Some(index(name).map_err(|m| cx.error(&camera.span, Some("medium"), format!("camera: {m}")))?),
        None => None,
    };
    let mut interfaces = Vec::new();
    if !media.is_empty() {
        for (i, entry) in file.shapes.iter().enumerate() {
            let (inside, outside) = entry.value.media();
            let at = |key: &str, m: String| cx.error(&entry.span, Some(key), format!("shapes[{i}]: {m}"));
            interfaces.push(MediumInterface {
                inside: inside.map(index).transpose().map_err(|m| at("interior", m))?,
                outside: outside.map(index).transpose().map_err(|m| at("exterior", m))?,
            });
        }
    } else if let Some((i, _)) = file.shapes.iter().enumerate().find(|(_, e)| e.value.media() != (None, None)) {
        return Err(cx.error(
            &file.shapes[i].span,
            Some("interior"),
            format!("shapes[{i}]: it names a medium, but `[media]` defines none"),
        ));
    }
    Ok((media, interfaces, camera_medium))
}

fn build_medium(desc: &MediumDesc, source: &Source) -> Result<Medium, (&'static str, String)> {
    let colour = |key: &'static str, v: Vector| non_negative(v).map_err(|m| (key, format!("`{key}` {m}")));
    let scale = |s: Option<f32>| match s.unwrap_or(1.0) {
        x if x.is_finite() && x >= 0.0 => Ok(x),
        x => Err(("scale", format!("`scale` must be ≥ 0, got {x}"))),
    };
    let albedo_of = |v: Option<Vector>, default: f32| -> Result<Vec3, (&'static str, String)> {
        let a = colour("albedo", v.unwrap_or([default; 3]))?;
        if a.max_element() > 1.0 {
            return Err(("albedo", format!("`albedo` is a fraction in [0, 1], got {a}")));
        }
        Ok(a)
    };
    let phase = |p: &Option<PhaseDesc>| match p {
        None | Some(PhaseDesc::Isotropic) => Ok(PhaseFunction::Isotropic),
        Some(PhaseDesc::Hg { g }) if g.abs() < 1.0 => Ok(PhaseFunction::HenyeyGreenstein { g: *g }),
        Some(PhaseDesc::Hg { g }) => Err(("phase", format!("Henyey–Greenstein's `g` lies in (−1, 1), got {g}"))),
    };
    let emitted = |e: Option<Vector>| e.map_or(Ok(Vec3::ZERO), |v| colour("emission", v));
    Ok(match desc {
        MediumDesc::Homogeneous { sigma_a, sigma_s, sigma_t, albedo, scale: s, phase: p, emission } => {
            let k = scale(*s)?;
            let (sigma_a, sigma_s) = match (sigma_a, sigma_s, sigma_t, albedo) {
                (a, s, None, None) => {
                    (colour("sigma_a", a.unwrap_or([0.0; 3]))?, colour("sigma_s", s.unwrap_or([0.0; 3]))?)
                }
                (None, None, t, albedo) => {
                    let t = colour("sigma_t", t.unwrap_or([1.0; 3]))?;
                    let albedo = albedo_of(*albedo, 0.8)?;
                    (t * (Vec3::ONE - albedo), t * albedo)
                }
                _ => {
                    return Err(("sigma_t", "give `sigma_a` and `sigma_s`, or `sigma_t` and `albedo`, not both".into()))
                }
            };
            Medium {
                kind: MediumKind::Homogeneous(Homogeneous { sigma_a: sigma_a * k, sigma_s: sigma_s * k }),
                phase: phase(p)?,
                emission: emitted(*emission)?,
            }
        }
        MediumDesc::Grid { file, value, min, max, transform, albedo, scale: s, phase: p, emission } => {
            let density = voxel_field(file.as_deref(), *value, (*min, *max), transform, source)?;
            let albedo = match albedo {
                None => Albedo::Constant(albedo_of(None, 0.8)?),
                Some(AlbedoDesc::Constant(a)) => Albedo::Constant(albedo_of(Some(*a), 0.8)?),
                Some(AlbedoDesc::Field(f)) => {
                    let field = voxel_field(Some(&f.file), None, (f.min, f.max), &f.transform, source)
                        .map_err(|(_, m)| ("albedo", format!("albedo: {m}")))?;
                    Albedo::Field(match f.wrap.as_deref() {
                        None | Some("clamp") => field,
                        Some("repeat") => field.repeating(),
                        Some(other) => {
                            return Err(("albedo", format!("albedo: `wrap` is `clamp` or `repeat`, not `{other}`")))
                        }
                    })
                }
            };
            let medium = GridMedium::new(density, scale(*s)?, albedo)
                .ok_or(("scale", "the grid's largest density times `scale` is not finite".to_string()))?;
            Medium { kind: MediumKind::Grid(Box::new(medium)), phase: phase(p)?, emission: emitted(*emission)? }
        }
    })
}

/// A grid medium's field: a `.vol` file's or one value's, over the file's box, `min`–`max`
/// or the unit cube under `transform`.
fn voxel_field(
    file: Option<&str>,
    value: Option<Vector>,
    (min, max): (Option<Vector>, Option<Vector>),
    transform: &[TransformOp],
    source: &Source,
) -> Result<VoxelField, (&'static str, String)> {
    let (resolution, channels, values, own_box) = match (file, value) {
        (Some(file), None) => {
            let bytes = source.read(file).map_err(|m| ("file", format!("volume file: {m}")))?;
            let grid = crate::volume::read_vol(&bytes).map_err(|m| ("file", format!("`{file}`: {m}")))?;
            (grid.resolution, grid.channels, grid.values, Some((grid.min, grid.max)))
        }
        (None, Some(v)) => ([1, 1, 1], 3, non_negative(v).map_err(|m| ("value", m))?.to_array().to_vec(), None),
        (Some(_), Some(_)) => return Err(("value", "give a grid's `file` or one `value`, not both".into())),
        (None, None) => return Err(("file", "a grid medium needs a `file` (or one `value`)".into())),
    };
    let to_world = match (min, max, transform.is_empty()) {
        (None, None, false) => {
            let t = build_transform(transform).map_err(|m| ("transform", m))?.expect("a transform is given");
            Affine3A::from_mat4(t.to_world)
        }
        (_, _, false) => {
            return Err(("transform", "give a grid's box by `min`–`max` or by `transform`, not both".into()))
        }
        (min, max, true) => {
            let unit = (Vec3::ZERO, Vec3::ONE);
            let (own_min, own_max) = own_box.unwrap_or(unit);
            let min = min.map_or(Ok(own_min), |v| finite(v).map_err(|m| ("min", m)))?;
            let max = max.map_or(Ok(own_max), |v| finite(v).map_err(|m| ("max", m)))?;
            if !min.cmplt(max).all() {
                return Err(("min", format!("the grid's box {min} – {max} is empty")));
            }
            box_to_world(min, max)
        }
    };
    VoxelField::new(resolution, channels, values, to_world)
        .ok_or(("file", "a grid's values must be finite and ≥ 0, and its transform invertible".to_string()))
}
