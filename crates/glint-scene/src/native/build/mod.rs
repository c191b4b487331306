//! From the parsed file to a core `Scene`: every value checked (finite, positive where it must
//! be, names that exist), meshes loaded, transforms composed. This file holds the entry and
//! the error context; each table of the file is built in its own: `camera.rs`, `render.rs`
//! (the render settings), `environment.rs`, `textures.rs`, `lights.rs`, `shapes.rs` (with
//! `csg.rs` for CSG trees), `media.rs`; the materials in `native/materials/`; the checks
//! every value goes through in `checks.rs`, transforms in `transform.rs`.

mod camera;
mod checks;
mod csg;
mod environment;
mod lights;
mod media;
mod render;
mod shapes;
mod textures;
mod transform;

use std::ops::Range;
use std::path::Path;

use glint_core::lights::Environment;
use glint_core::scene::SceneBuilder;
use glint_core::shapes::IntersectMethods;
use glint_core::Named;

use self::camera::build_camera;
use self::checks::by_name;
pub(super) use self::checks::{non_negative, positive, quoted};
pub(crate) use self::environment::environment_rotation;
use self::environment::{build_environment_map, environment_colour};
use self::lights::build_light;
use self::media::build_media;
use self::render::build_render;
use self::shapes::{build_object, MeshLibrary};
pub(super) use self::textures::resolve_colour;
use self::textures::{build_textures, check_mesh_attributes};
use super::schema::*;
use super::{find_key, LoadedScene};
use crate::error::{Location, SceneError};
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
        background: environment_colour(&cx, "background", file.environment.background)?,
        ambient_light: environment_colour(&cx, "ambient", file.environment.ambient)?,
        map: build_environment_map(&file.environment, source).map_err(|(key, m)| cx.error_at_key(key, m))?,
    };

    let textures = build_textures(&cx, &file, source)?;

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
