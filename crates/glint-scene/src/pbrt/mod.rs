//! pbrt-v4 scene files (`.pbrt`): tokenized and parsed here (a hand-written reader: pbrt's
//! grammar is a dozen lines, and ours keeps every token's file and offset for messages and
//! reads `Include`d files through the scene's `Source`), interpreted as pbrt's graphics state
//! machine, mapped onto glint's native scene description, and built by the same builder as
//! TOML scenes. docs/pbrt.md lists what maps to what.

mod envmap;
mod lens;
mod params;
mod parse;
mod shapes;
mod spectra;
mod tokens;
mod translate;

use std::path::{Path, PathBuf};

use crate::error::SceneError;
use crate::native::LoadedScene;
use crate::reader::Translation;
use crate::source::Source;

/// Reads a pbrt-v4 scene; `search_path` is searched after the scene's directory for the
/// files it names.
pub fn load_pbrt(path: &Path, search_path: &[PathBuf]) -> Result<LoadedScene, SceneError> {
    let (bytes, directories) = crate::reader::read_scene_file(path, search_path)?;
    build(path, bytes, Source::search_path(directories))
}

/// Reads pbrt-v4 scene text; `name` is used in messages, `source` resolves what it names.
pub fn parse_pbrt(text: &str, name: &Path, source: Source<'_>) -> Result<LoadedScene, SceneError> {
    build(name, text.as_bytes().to_vec(), source)
}

/// Translates the file and builds its description, with the files the translation made
/// (resampled maps).
fn build(name: &Path, bytes: Vec<u8>, source: Source<'_>) -> Result<LoadedScene, SceneError> {
    let (file, made, warnings) = translate::translate(name, bytes, &source)?;
    crate::reader::build(Translation { file, text: "", made, warnings }, name, source)
}
