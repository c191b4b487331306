//! From the parsed file to a core `Scene`: every value checked (finite, positive where it must
//! be, names that exist), meshes loaded, transforms composed.

use std::ops::Range;
use std::path::Path;
use std::sync::Arc;

use glam::{Affine2, Affine3A, Mat3, Mat4, Quat, Vec2, Vec3};
use glint_core::camera::{Camera, Lens};
use glint_core::filter::Filter;
use glint_core::geometry::Transform;
use glint_core::integrators::{IntegratorKind, IntegratorSettings, PhotonSettings};
use glint_core::lights::{
    DirectionalLight, Environment, EnvironmentMap, Falloff, Light, PointLight, Slide, SpotLight, SpotProfile,
};
use glint_core::lights::{LightSelection, TriangleSampling};
use glint_core::materials::Material;
use glint_core::media::{
    box_to_world, Albedo, GridMedium, Homogeneous, Medium, MediumInterface, MediumKind, PhaseFunction, VoxelField,
};
use glint_core::sampling::SamplerKind;
use glint_core::scene::{Geometry, Object, SceneBuilder};
use glint_core::shapes::{
    AaBox, Csg, CsgOperation, CsgSolid, CsgTree, Instance, IntersectMethods, Mesh, Plane, Polygon, SdfGrid, SdfNormals,
    Shape, Sphere, Triangle,
};
use glint_core::textures::{
    AttributeTexture, Checker, ImageTexture, Marble, SolidChecker, TexelFilter, Texture, Wood, Wrap,
};
use glint_core::Named;

use super::schema::*;
use super::{find_key, LoadedScene, RenderOptions};
use crate::error::{did_you_mean, Location, SceneError};
use crate::located::Located;
use crate::source::Source;

/// Error context: the file's text and name, to turn spans into locations.
pub(super) struct Context<'a> {
    text: &'a str,
    file: &'a Path,
}

impl Context<'_> {
    /// An error at `span` (the element), pointing at `key` inside it when given and found.
    pub(super) fn error(&self, span: &Option<Range<usize>>, key: Option<&str>, message: String) -> SceneError {
        let location = span.as_ref().map(|span| {
            let offset = key.and_then(|k| find_key(self.text, span.clone(), k)).unwrap_or(span.start);
            Location::from_offset(self.text, offset)
        });
        SceneError::new(self.file, location, message)
    }

    /// An error about a top-level key, found by searching the whole file.
    fn error_at_key(&self, key: &str, message: String) -> SceneError {
        let location = find_key(self.text, 0..self.text.len(), key).map(|o| Location::from_offset(self.text, o));
        SceneError::new(self.file, location, message)
    }
}

pub(crate) fn build(file: SceneFile, text: &str, path: &Path, source: &Source) -> Result<LoadedScene, SceneError> {
    let cx = Context { text, file: path };
    let mut warnings = Vec::new();

    let camera = build_camera(&cx, &file.camera)?;
    let render = build_render(&cx, &file.render)?;
    fn method<T: Named + Default>(cx: &Context, key: &str, what: &str, name: &Option<String>) -> Result<T, SceneError> {
        name.as_deref().map_or(Ok(T::default()), |name| by_name(cx, key, what, name))
    }
    let i = &file.intersection;
    let methods = IntersectMethods {
        sphere: method(&cx, "sphere", "sphere method", &i.sphere)?,
        triangle: method(&cx, "triangle", "triangle method", &i.triangle)?,
        polygon: method(&cx, "polygon", "polygon test", &i.polygon)?,
        aabox: method(&cx, "box", "box method", &i.aabox)?,
    };
    let environment = Environment {
        background: colour(&cx, "background", file.environment.background)?,
        ambient_light: colour(&cx, "ambient", file.environment.ambient)?,
        map: build_environment_map(&file.environment, source).map_err(|(key, m)| cx.error_at_key(key, m))?,
    };

    let mut textures = Vec::new();
    for (name, entry) in &file.textures {
        let texture = build_texture(&entry.value, source)
            .map_err(|(key, m)| cx.error(&entry.span, Some(key), format!("texture `{name}`: {m}")))?;
        textures.push((name.clone(), texture));
    }

    let materials = super::materials::build_materials(&cx, &file.materials, &textures)?;

    let lights =
        file.lights.iter().enumerate().map(|(i, l)| build_light(&cx, i, l, &textures)).collect::<Result<_, _>>()?;

    let mut library = MeshLibrary { descs: &file.meshes, built: Vec::new(), sdf_grids: Vec::new() };
    let mut objects = Vec::new();
    for (i, entry) in file.shapes.iter().enumerate() {
        objects.push(build_object(&cx, i, entry, &materials, &mut library, source, &mut warnings)?);
    }

    check_mesh_attributes(&cx, &file, &textures, &objects)?;
    let (media, interfaces, camera_medium) = build_media(&cx, &file, source)?;
    warnings.extend(materials.iter().filter_map(|(name, m)| m.energy_warning(name)));
    let scene = SceneBuilder::new(camera)
        .objects(objects)
        .materials(materials)
        .lights(lights)
        .environment(environment)
        .methods(methods)
        .triangle_sampling(render.light_sampling)
        .light_selection(render.light_selection)
        .media(media, interfaces, camera_medium)
        .build();
    let inputs = std::iter::once(path.to_path_buf()).chain(source.files_read()).collect();
    Ok(LoadedScene { scene, render, warnings, inputs })
}

/// Every `mesh-attribute` texture names an attribute some mesh of the scene has: a typo would
/// otherwise render black.
fn check_mesh_attributes(
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

fn build_camera(cx: &Context, camera: &Located<CameraDesc>) -> Result<Camera, SceneError> {
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
    Ok(if c.mirror { camera.mirrored() } else { camera })
}

fn build_render(cx: &Context, r: &RenderDesc) -> Result<RenderOptions, SceneError> {
    let integrator: IntegratorKind = by_name(cx, "integrator", "integrator", &r.integrator)?;
    if r.spp == 0 {
        return Err(cx.error_at_key("spp", "`spp` (samples per pixel) must be at least 1".into()));
    }
    if !(r.min_contribution.is_finite() && r.min_contribution >= 0.0) {
        return Err(cx.error_at_key(
            "min_contribution",
            format!("`min_contribution` must be a number ≥ 0, got {}", r.min_contribution),
        ));
    }
    if r.max_depth < -1 || r.max_depth > u32::MAX as i64 {
        return Err(
            cx.error_at_key("max_depth", format!("`max_depth` must be -1 (unbounded) or ≥ 0, got {}", r.max_depth))
        );
    }
    for (key, value) in [("photon_radius", r.photon_radius), ("sppm_radius", r.sppm_radius)] {
        if !(value.is_finite() && value >= 0.0) {
            return Err(cx.error_at_key(key, format!("`{key}` must be a length ≥ 0 (0: automatic), got {value}")));
        }
    }
    if r.photon_nearest == 0 {
        return Err(cx.error_at_key("photon_nearest", "`photon_nearest` must be at least 1".into()));
    }
    let integrator_settings = IntegratorSettings {
        max_depth: if r.max_depth < 0 { u32::MAX } else { r.max_depth as u32 },
        rr_depth: r.rr_depth,
        min_contribution: r.min_contribution,
        transparent_shadows: r.transparent_shadows,
        photon: PhotonSettings {
            global_photons: r.photons,
            caustic_photons: r.caustic_photons,
            nearest: r.photon_nearest,
            max_radius: r.photon_radius,
            final_gather: r.final_gather,
        },
        sppm_radius: r.sppm_radius,
        photons_per_pass: r.photons_per_pass,
        wavefront: true,
    };
    let filter: Filter = by_name(cx, "filter", "filter", &r.filter)?;
    let sampler: SamplerKind = by_name(cx, "sampler", "sampler", &r.sampler)?;
    let light_sampling: TriangleSampling = by_name(cx, "light_sampling", "light sampling", &r.light_sampling)?;
    let light_selection: LightSelection = by_name(cx, "light_selection", "light selection", &r.light_selection)?;
    Ok(RenderOptions {
        spp: r.spp,
        integrator,
        seed: r.seed,
        integrator_settings,
        filter,
        sampler,
        light_sampling,
        light_selection,
        moment: r.moment,
    })
}

fn build_light(
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

/// A mesh's shading normals: none (flat) unless `smooth`; then the file's, or, where it has
/// none and `compute` asks, smooth ones made from the faces.
fn shade(mesh: &mut Mesh, smooth: bool, compute: bool) {
    if !smooth {
        mesh.normals = None;
    } else if compute && mesh.normals.is_none() {
        mesh.compute_vertex_normals();
    }
}

/// What `build_media` gives.
type SceneMedia = (Vec<Medium>, Vec<MediumInterface>, Option<u32>);

/// The scene's media, the interface of each shape (by shape, empty without media) and the
/// camera's medium.
fn build_media(cx: &Context, file: &SceneFile, source: &Source) -> Result<SceneMedia, SceneError> {
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
                Some(AlbedoDesc::Field(f)) => Albedo::Field(
                    voxel_field(Some(&f.file), None, (f.min, f.max), &f.transform, source)
                        .map_err(|(_, m)| ("albedo", format!("albedo: {m}")))?,
                ),
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

/// A mesh from its file or from the scene's own `data`, checked, and how to name it in
/// messages.
fn mesh_of(
    file: Option<&str>,
    data: Option<&MeshData>,
    shape_index: u32,
    source: &Source,
) -> Result<(Mesh, String), (&'static str, String)> {
    match (file, data) {
        (Some(file), None) => {
            let bytes = source.read(file).map_err(|m| ("file", format!("mesh file: {m}")))?;
            let mesh = crate::mesh::read_mesh_part(file, &bytes, shape_index)
                .map_err(|m| ("file", format!("mesh file `{file}`: {m}")))?;
            Ok((mesh, format!("`{file}`")))
        }
        (None, Some(data)) => {
            if shape_index != 0 {
                return Err(("shape_index", "`shape_index` picks a mesh of a file; `data` is one mesh".into()));
            }
            Ok((crate::mesh::from_data(data).map_err(|m| ("data", m))?, "its data".into()))
        }
        (Some(_), Some(_)) => Err(("data", "give a mesh's `file` or its `data`, not both".into())),
        (None, None) => Err(("file", "a mesh needs a `file` (or its triangles in `data`)".into())),
    }
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

/// Named meshes for instancing, each loaded and given its BVH on first use, then shared; and
/// SDF grids, each file read once however many shapes place it (a shapegroup's instances).
struct MeshLibrary<'a> {
    descs: &'a std::collections::BTreeMap<String, Located<MeshDesc>>,
    built: Vec<(String, Arc<Geometry>)>,
    sdf_grids: Vec<((String, SdfNormals), Arc<SdfGrid>)>,
}

impl MeshLibrary<'_> {
    /// The mesh's shared geometry; `unknown` makes the error for a name not in `[meshes]` (at
    /// the instance), problems with the file itself are reported at the mesh's entry.
    fn get(
        &mut self,
        cx: &Context,
        name: &str,
        source: &Source,
        warnings: &mut Vec<String>,
        unknown: impl Fn(String) -> SceneError,
    ) -> Result<Arc<Geometry>, SceneError> {
        if let Some((_, g)) = self.built.iter().find(|(n, _)| n == name) {
            return Ok(g.clone());
        }
        let Some(entry) = self.descs.get(name) else {
            let hint = did_you_mean(name, self.descs.keys().map(String::as_str));
            return Err(unknown(format!("unknown mesh `{name}` (instances name a mesh defined in [meshes]){hint}")));
        };
        let desc = &entry.value;
        let (mut mesh, origin) = mesh_of(desc.file.as_deref(), desc.data.as_ref(), desc.shape_index, source)
            .map_err(|(key, m)| cx.error(&entry.span, Some(key), format!("mesh `{name}`: {m}")))?;
        shade(&mut mesh, desc.smooth, desc.compute_normals);
        if let (true, Some(uvs)) = (desc.flip_v, &mut mesh.uvs) {
            uvs.iter_mut().for_each(|uv| uv.y = 1.0 - uv.y);
        }
        let degenerate = mesh.degenerate_triangles().count();
        if degenerate > 0 {
            warnings
                .push(format!("mesh `{name}`: {origin} has {degenerate} zero-area triangles; they can never be hit"));
        }
        let object = Object { name: name.to_string(), shape: Shape::Mesh(mesh), transform: None, material: 0 };
        let geometry = Arc::new(Geometry::new(vec![object], IntersectMethods::default()));
        self.built.push((name.to_string(), geometry.clone()));
        Ok(geometry)
    }
}

/// A sphere of the scene file (a shape or a CSG operand), checked: the key at fault and why.
fn sphere_shape(center: Vector, radius: f32) -> Result<Shape, (&'static str, String)> {
    let center = finite(center).map_err(|m| ("center", m))?;
    positive(radius).map_err(|m| ("radius", format!("`radius` {m}")))?;
    if radius > MAX_COORDINATE {
        return Err((
            "radius",
            format!(
                "`radius` must be at most {MAX_COORDINATE:e} (its square must fit in 32-bit floats), got {radius:e}"
            ),
        ));
    }
    Ok(Shape::Sphere(Sphere::new(center, radius)))
}

/// An axis-aligned box of the scene file (a shape or a CSG operand), checked.
fn box_shape(min: Vector, max: Vector) -> Result<Shape, (&'static str, String)> {
    let (lo, hi) = (finite(min).map_err(|m| ("min", m))?, finite(max).map_err(|m| ("max", m))?);
    if !lo.cmplt(hi).all() {
        return Err(("max", format!("`max` must exceed `min` on every axis, got min = {lo}, max = {hi}")));
    }
    Ok(Shape::AaBox(AaBox::new(lo, hi)))
}

/// The index of the material named `name`, or what names there are.
fn material_index(materials: &[(String, Material)], name: &str) -> Result<u32, String> {
    let index = materials.iter().position(|(n, _)| n == name).ok_or_else(|| {
        let hint = did_you_mean(name, materials.iter().map(|(n, _)| n.as_str()));
        let known = if materials.is_empty() {
            "no materials are defined".to_string()
        } else {
            format!("defined materials: {}", quoted(&materials.iter().map(|(n, _)| n.as_str()).collect::<Vec<_>>()))
        };
        format!("unknown material `{name}` ({known}){hint}")
    })?;
    Ok(index as u32)
}

/// What a CSG operand's checks need besides the operand: the scene's materials and named
/// meshes, where files come from, and the shape's label for messages.
struct OperandContext<'a, 'b, 'c> {
    cx: &'a Context<'a>,
    materials: &'a [(String, Material)],
    library: &'a mut MeshLibrary<'b>,
    source: &'a Source<'c>,
    warnings: &'a mut Vec<String>,
    label: &'a str,
}

/// A CSG node's operation over its operands, each checked and placed by its own transform
/// composed after the node's (`outer`); `material` is the node's, for operands without one.
fn csg_tree(
    oc: &mut OperandContext,
    span: &Option<Range<usize>>,
    operation: &str,
    operands: &[OperandDesc],
    outer: Option<Transform>,
    material: Option<u32>,
    path: &str,
) -> Result<CsgTree, SceneError> {
    let (cx, label) = (oc.cx, oc.label);
    let at = |key: &str, m: String| cx.error(span, Some(key), format!("{label}: {path}{m}"));
    let operation = CsgOperation::from_name(operation).ok_or_else(|| {
        let names: Vec<&str> = CsgOperation::ALL.iter().map(|o| o.name()).collect();
        let hint = did_you_mean(operation, names.iter().copied());
        at("operation", format!("unknown CSG operation `{operation}`, expected one of {}{hint}", quoted(&names)))
    })?;
    if operands.len() < 2 {
        let message = format!("a {} needs at least two operands, got {}", operation.name(), operands.len());
        return Err(at("operands", message));
    }
    let mut trees = Vec::with_capacity(operands.len());
    for (k, entry) in operands.iter().enumerate() {
        trees.push(csg_operand(oc, span, entry, outer, material, &format!("{path}operands[{k}]: "))?);
    }
    Ok(CsgTree::Combine(operation, trees))
}

fn csg_operand(
    oc: &mut OperandContext,
    span: &Option<Range<usize>>,
    operand: &OperandDesc,
    outer: Option<Transform>,
    inherited: Option<u32>,
    path: &str,
) -> Result<CsgTree, SceneError> {
    let cx = oc.cx;
    let label = oc.label;
    let at = |key: &str, m: String| cx.error(span, Some(key), format!("{label}: {path}{m}"));
    let (material, transform_ops) = match operand {
        OperandDesc::Sphere { material, transform, .. }
        | OperandDesc::Box { material, transform, .. }
        | OperandDesc::Instance { material, transform, .. }
        | OperandDesc::Csg { material, transform, .. } => (material, transform),
    };
    let material = match material {
        Some(name) => Some(material_index(oc.materials, name).map_err(|m| at("material", m))?),
        None => inherited,
    };
    let own = build_transform(transform_ops).map_err(|m| at("transform", m))?;
    let transform = match (outer, own) {
        (Some(o), Some(t)) => Some(o.after(&t)),
        (o, t) => o.or(t),
    };
    let shape = match operand {
        OperandDesc::Sphere { center, radius, .. } => sphere_shape(*center, *radius).map_err(|(k, m)| at(k, m))?,
        OperandDesc::Box { min, max, .. } => box_shape(*min, *max).map_err(|(k, m)| at(k, m))?,
        OperandDesc::Instance { mesh, .. } => {
            let geometry = oc.library.get(cx, mesh, oc.source, oc.warnings, |m| at("mesh", m))?;
            if geometry.objects().len() != 1
                || !matches!(&geometry.objects()[0].shape, Shape::Mesh(m) if m.enclosed_volume().is_some_and(|v| v != 0.0))
            {
                return Err(at(
                    "mesh",
                    format!("mesh `{mesh}` is not closed: a CSG operand must bound a solid (every edge shared by exactly two triangles wound the same way)"),
                ));
            }
            Shape::Instance(Instance { geometry })
        }
        OperandDesc::Csg { operation, operands, .. } => {
            return csg_tree(oc, span, operation, operands, transform, material, path);
        }
    };
    Ok(CsgTree::Solid(Box::new(CsgSolid { shape, transform, material })))
}

fn build_object(
    cx: &Context,
    index: usize,
    entry: &Located<ShapeDesc>,
    materials: &[(String, Material)],
    library: &mut MeshLibrary,
    source: &Source,
    warnings: &mut Vec<String>,
) -> Result<Object, SceneError> {
    let desc = &entry.value;
    let (material_name, transform_ops, name) = desc.common();
    let label = match name {
        Some(n) => format!("shapes[{index}] ({} `{n}`)", desc.kind()),
        None => format!("shapes[{index}] ({})", desc.kind()),
    };
    let at = |key: &str, m: String| cx.error(&entry.span, Some(key), format!("{label}: {m}"));

    let material = material_index(materials, material_name).map_err(|m| at("material", m))?;

    let transform = build_transform(transform_ops).map_err(|m| at("transform", m))?;

    let shape = match desc {
        ShapeDesc::Sphere { center, radius, .. } => sphere_shape(*center, *radius).map_err(|(k, m)| at(k, m))?,
        ShapeDesc::Plane { normal, offset, point, .. } => {
            let n = finite(*normal).map_err(|m| at("normal", m))?;
            if n.length_squared() == 0.0 {
                return Err(at("normal", "`normal` must not be the zero vector".into()));
            }
            match (offset, point) {
                (Some(_), Some(_)) => {
                    return Err(at("point", "give either `offset` (D of n·P + D = 0) or `point`, not both".into()))
                }
                (_, Some(p)) => Shape::Plane(Plane::through_point(n, finite(*p).map_err(|m| at("point", m))?)),
                (d, None) => {
                    let d = d.unwrap_or(0.0);
                    if !d.is_finite() {
                        return Err(at("offset", format!("`offset` must be finite, got {d}")));
                    }
                    Shape::Plane(Plane::new(n, d))
                }
            }
        }
        ShapeDesc::Triangle { vertices, normals, uvs, .. } => {
            let mut points = [Vec3::ZERO; 3];
            for (p, v) in points.iter_mut().zip(vertices) {
                *p = finite(*v).map_err(|m| at("vertices", m))?;
            }
            let mut triangle = Triangle::new(points[0], points[1], points[2]);
            if triangle.double_area() == 0.0 {
                return Err(at(
                    "vertices",
                    "the triangle has zero area (its vertices are collinear or coincide)".into(),
                ));
            }
            if let Some(ns) = normals {
                let mut out = [Vec3::ZERO; 3];
                for (o, n) in out.iter_mut().zip(ns) {
                    *o = finite(*n)
                        .map_err(|m| at("normals", m))?
                        .try_normalize()
                        .ok_or_else(|| at("normals", "vertex normals must not be zero vectors".into()))?;
                }
                triangle.normals = Some(out);
            }
            triangle.uvs = uvs.map(|t| t.map(Vec2::from));
            Shape::Triangle(triangle)
        }
        ShapeDesc::Polygon { vertices, uvs, .. } => {
            if vertices.len() < 3 {
                return Err(at("vertices", format!("a polygon needs at least 3 vertices, got {}", vertices.len())));
            }
            let points =
                vertices.iter().map(|p| finite(*p)).collect::<Result<Vec<_>, _>>().map_err(|m| at("vertices", m))?;
            let mut polygon = Polygon::new(points)
                .ok_or_else(|| at("vertices", "the polygon has zero area (its vertices are collinear)".into()))?;
            // The even-odd and winding tests work in the polygon's plane: a vertex off it
            // would be hit somewhere else than where it is drawn.
            // Beyond 1e-4 of its size, and beyond what rounding coordinates this far from the
            // origin makes of a flat one.
            let (vertex, off) = polygon.farthest_off_plane();
            let magnitude = vertices.iter().map(|v| Vec3::from(*v).abs().max_element()).fold(0.0f32, f32::max);
            let size = vertices
                .iter()
                .map(|v| (Vec3::from(*v) - Vec3::from(vertices[0])).length())
                .fold(f32::MIN_POSITIVE, f32::max);
            if off > 1e-4 + 8.0 * f32::EPSILON * magnitude / size {
                return Err(at(
                    "vertices",
                    format!("the polygon is not planar: vertex {vertex} lies {off:.2e} of the polygon's size off its plane (a polygon must be flat; split it into triangles)"),
                ));
            }
            if let Some(uvs) = uvs {
                polygon = polygon
                    .with_uvs(uvs.iter().map(|&t| Vec2::from(t)).collect())
                    .map_err(|e| at("uvs", e.to_string()))?;
            }
            Shape::Polygon(polygon)
        }
        ShapeDesc::Box { min, max, .. } => box_shape(*min, *max).map_err(|(k, m)| at(k, m))?,
        ShapeDesc::Quad { vertices, .. } => {
            let mut positions = Vec::with_capacity(4);
            for v in vertices {
                positions.push(finite(*v).map_err(|m| at("vertices", m))?);
            }
            let mesh = Mesh {
                positions,
                normals: None,
                uvs: Some(vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y]),
                indices: vec![[0, 1, 2], [0, 2, 3]],
                ..Mesh::default()
            };
            if mesh.degenerate_triangles().count() > 0 {
                return Err(at("vertices", "the quad has a zero-area half (three collinear corners)".into()));
            }
            Shape::Mesh(mesh)
        }
        ShapeDesc::Instance { mesh, .. } => {
            let geometry = library.get(cx, mesh, source, warnings, |m| at("mesh", m))?;
            Shape::Instance(Instance { geometry })
        }
        ShapeDesc::Csg { operation, operands, .. } => {
            let mut oc = OperandContext { cx, materials, library, source, warnings, label: &label };
            let tree = csg_tree(&mut oc, &entry.span, operation, operands, None, None, "")?;
            Shape::Csg(Box::new(Csg::new(tree).map_err(|e| at("operands", e.to_string()))?))
        }
        ShapeDesc::SdfGrid { file, normals, .. } => {
            let normals = match normals.as_deref() {
                None => SdfNormals::default(),
                Some(name) => SdfNormals::from_name(name).ok_or_else(|| {
                    at("normals", format!("unknown normals `{name}`: expected {}", SdfNormals::names()))
                })?,
            };
            let key = (file.clone(), normals);
            match library.sdf_grids.iter().find(|(k, _)| *k == key) {
                Some((_, grid)) => Shape::SdfGrid(grid.clone()),
                None => {
                    let bytes = source.read(file).map_err(|m| at("file", format!("SDF grid file: {m}")))?;
                    let grid = crate::volume::read_vol(&bytes).map_err(|m| at("file", format!("`{file}`: {m}")))?;
                    if grid.channels != 1 {
                        return Err(at(
                            "file",
                            format!("`{file}` has {} channels; an SDF grid has one", grid.channels),
                        ));
                    }
                    let sdf = SdfGrid::new(grid.resolution, grid.values, normals)
                        .map_err(|m| at("file", format!("`{file}`: {m}")))?;
                    let sdf = Arc::new(sdf);
                    library.sdf_grids.push((key, sdf.clone()));
                    Shape::SdfGrid(sdf)
                }
            }
        }
        ShapeDesc::Mesh { file, data, shape_index, smooth, flip_v, compute_normals, .. } => {
            let (mut mesh, origin) =
                mesh_of(file.as_deref(), data.as_ref(), *shape_index, source).map_err(|(k, m)| at(k, m))?;
            shade(&mut mesh, *smooth, *compute_normals);
            if let (true, Some(uvs)) = (*flip_v, &mut mesh.uvs) {
                uvs.iter_mut().for_each(|uv| uv.y = 1.0 - uv.y);
            }
            let degenerate = mesh.degenerate_triangles().count();
            if degenerate > 0 {
                warnings.push(format!("{label}: {origin} has {degenerate} zero-area triangles; they can never be hit"));
            }
            // Meshes are stored in world space: the BVH then sees their triangles directly.
            if let Some(t) = &transform {
                mesh.transform(t);
            }
            return Ok(Object { name: label, shape: Shape::Mesh(mesh), transform: None, material });
        }
    };
    Ok(Object { name: name.map_or(label, str::to_string), shape, transform, material })
}

/// The environment map, loaded and set up for importance sampling.
fn build_environment_map(
    desc: &EnvironmentDesc,
    source: &Source,
) -> Result<Option<Arc<EnvironmentMap>>, (&'static str, String)> {
    let Some(file) = &desc.map else { return Ok(None) };
    let bytes = source.read(file).map_err(|m| ("map", format!("environment map: {m}")))?;
    let (width, height, pixels) =
        crate::image::decode(file, &bytes, false).map_err(|m| ("map", format!("environment map `{file}`: {m}")))?;
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

/// Composes the operations in order: the first is applied to the shape first.
pub(crate) fn build_transform(ops: &[TransformOp]) -> Result<Option<Transform>, String> {
    if ops.is_empty() {
        return Ok(None);
    }
    let mut matrix = Mat4::IDENTITY;
    for op in ops {
        let m = match op {
            TransformOp::Translate(v) => Mat4::from_translation(finite(*v)?),
            TransformOp::Rotate(r) => {
                let axis = finite(r.axis)?.try_normalize().ok_or("rotation `axis` must not be the zero vector")?;
                if !r.angle.is_finite() {
                    return Err(format!("rotation `angle` must be finite, got {}", r.angle));
                }
                Mat4::from_quat(Quat::from_axis_angle(axis, r.angle.to_radians()))
            }
            TransformOp::Scale(ScaleDesc::Uniform(s)) => Mat4::from_scale(Vec3::splat(*s)),
            TransformOp::Scale(ScaleDesc::PerAxis(s)) => Mat4::from_scale(finite(*s)?),
            TransformOp::Matrix(rows) => {
                if rows.iter().flatten().any(|x| !x.is_finite()) {
                    return Err("`matrix` entries must be finite".into());
                }
                Mat4::from_cols_array_2d(rows).transpose()
            }
        };
        matrix = m * matrix;
    }
    Transform::from_matrix(matrix).map(Some).ok_or_else(|| "the transform is singular (a zero scale?)".to_string())
}

/// A texture, or the key its error is about and the message.
fn build_texture(desc: &TextureDesc, source: &Source) -> Result<Texture, (&'static str, String)> {
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
        TextureDesc::Checker { even, odd, scale, uv_transform } => Texture::Checker(Box::new(Checker {
            even: rgb("even", *even)?,
            odd: rgb("odd", *odd)?,
            uv_transform: uv_map(scale2(*scale, 8.0)?, uv_transform.as_ref())?,
        })),
        TextureDesc::SolidChecker { even, odd, scale } => Texture::SolidChecker(SolidChecker {
            even: rgb("even", *even)?,
            odd: rgb("odd", *odd)?,
            scale: number("scale", *scale, 1.0)?,
        }),
        TextureDesc::Image { file, wrap, filter, scale, uv_transform, raw, channel, tint } => {
            let bytes = source.read(file).map_err(|m| ("file", format!("image file: {m}")))?;
            let (width, height, mut pixels) =
                crate::image::decode(file, &bytes, *raw).map_err(|m| ("file", format!("image `{file}`: {m}")))?;
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

pub(super) fn resolve_colour(c: &ColorDesc, textures: &[(String, Texture)]) -> Result<Texture, String> {
    match c {
        ColorDesc::Rgb(v) => Ok(Texture::Constant(non_negative(*v)?)),
        ColorDesc::Texture(name) => textures.iter().find(|(n, _)| n == name).map(|(_, t)| t.clone()).ok_or_else(|| {
            let hint = did_you_mean(name, textures.iter().map(|(n, _)| n.as_str()));
            format!("unknown texture `{name}` (a colour is [r, g, b] or the name of a texture in [textures]){hint}")
        }),
    }
}

/// The largest coordinate (or length) a scene may hold: squared, as lengths and the sphere's
/// quadratic square it, it must stay within f32 (3.4e38), with room for sums of three. A
/// sphere of radius 1e38 rendered as background only (r² was infinite), a camera at
/// −1e38 was told its `look_at` equals its `position`.
const MAX_COORDINATE: f32 = 1e18;

fn finite(v: Vector) -> Result<Vec3, String> {
    let v3 = Vec3::from(v);
    if !v3.is_finite() {
        Err(format!("expected finite numbers, got {v:?}"))
    } else if v3.abs().max_element() > MAX_COORDINATE {
        Err(format!("expected numbers of magnitude at most {MAX_COORDINATE:e} (their squares must fit in 32-bit floats), got {v:?}"))
    } else {
        Ok(v3)
    }
}

pub(super) fn non_negative(v: Vector) -> Result<Vec3, String> {
    let v3 = finite(v)?;
    if v3.min_element() < 0.0 {
        return Err(format!("colours must be ≥ 0, got {v:?}"));
    }
    Ok(v3)
}

pub(super) fn positive(x: f32) -> Result<(), String> {
    if x.is_finite() && x > 0.0 {
        Ok(())
    } else {
        Err(format!("must be a finite number > 0, got {x}"))
    }
}

fn colour(cx: &Context, key: &str, v: Vector) -> Result<Vec3, SceneError> {
    non_negative(v).map_err(|m| cx.error_at_key(key, format!("environment `{key}`: {m}")))
}

/// The setting `key` names by `value` (one of `names`), or an error at `key` that lists them
/// and suggests the closest.
/// A named choice (`Named`): an unknown name is an error listing the choices, with a guess.
fn by_name<T: Named>(cx: &Context, key: &str, what: &str, value: &str) -> Result<T, SceneError> {
    T::from_name(value).ok_or_else(|| {
        let names: Vec<&str> = T::ALL.iter().map(|k| k.name()).collect();
        let hint = did_you_mean(value, names.iter().copied());
        cx.error_at_key(key, format!("unknown {what} `{value}`, expected one of {}{hint}", quoted(&names)))
    })
}

pub(super) fn quoted(names: &[&str]) -> String {
    names.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", ")
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
