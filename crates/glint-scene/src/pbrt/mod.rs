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
use crate::reader::{ReadScene, Translation};
use crate::source::Source;

/// Reads a pbrt-v4 scene into its native description, with the search path for the files it
/// names: the scene's directory, then `search_path`.
pub(crate) fn read_file(path: &Path, search_path: &[PathBuf]) -> ReadScene {
    let (bytes, directories) = crate::reader::read_scene_file(path, search_path)?;
    let source = Source::search_path(directories);
    Ok((translate_bytes(path, bytes, &source)?, source))
}

/// Translates pbrt-v4 scene bytes (the files it makes: resampled maps); `name` is used in
/// messages, `source` resolves what it names.
pub(crate) fn translate_bytes(name: &Path, bytes: Vec<u8>, source: &Source) -> Result<Translation, SceneError> {
    let (file, made, warnings) = translate::translate(name, bytes, source)?;
    Ok(Translation { made, warnings, ..Translation::new(file, String::new()) })
}
