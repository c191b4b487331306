//! Scene readers for glint. The native format (TOML, or the same schema as JSON) is
//! documented in `docs/scene-format.md`, Mitsuba 3's XML in `docs/mitsuba.md`, pbrt-v4's
//! files in `docs/pbrt.md`, glTF 2.0 in `docs/gltf.md`; meshes come from OBJ and PLY files.
//!
//! Every error names the file, the line and column where that can be known, and what was
//! expected; nothing a user writes can make a reader panic.

mod error;
pub mod gltf;
mod image;
mod limits;
mod load;
mod located;
pub mod mesh;
pub mod mitsuba;
pub mod native;
pub mod pbrt;
mod reader;
mod source;
pub mod volume;

pub use error::{Location, SceneError};
pub use gltf::GltfOptions;
pub use image::decode as decode_image;
pub use limits::{describe as describe_bytes, memory_limit, set_memory_limit, RAISE as RAISE_MEMORY_LIMIT};
pub use load::{
    load_scene, load_scene_with, load_scene_with_options, parse_gltf, parse_pbrt, parse_scene, LoadOptions,
};
pub use native::{LoadedScene, RenderOptions};
pub use source::{read_file, Source};

/// The scene `glint render` shows when given no scene file: spheres, a polygon, a box and a
/// mesh under two lights. Its files are compiled into the binary.
pub fn default_scene() -> Result<LoadedScene, SceneError> {
    const TOML: &str = include_str!("../../../scenes/default.toml");
    const TORUS: &[u8] = include_bytes!("../../../scenes/meshes/torus.obj");
    let source = Source::embedded(&[("meshes/torus.obj", TORUS)]);
    parse_scene(TOML, native::Format::Toml, "<built-in default scene>", &source)
}
