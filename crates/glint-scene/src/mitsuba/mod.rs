//! Mitsuba 3 scene files (`.xml`): read, mapped onto glint's native scene description, and
//! built by the same builder as TOML scenes. docs/mitsuba.md lists what is supported and how
//! each element maps onto glint.

mod translate;
mod xml;

use std::path::Path;

use crate::error::SceneError;
use crate::native::LoadedScene;
use crate::source::Source;

/// Reads a Mitsuba 3 scene. `defines` are `-D name=value` parameters, which override the
/// file's `<default>`s.
pub fn load_mitsuba(path: &Path, defines: &[(String, String)]) -> Result<LoadedScene, SceneError> {
    let (root, files) = xml::read_scene(path, defines)?;
    let translator = translate::Translator::new(&files, &root)?;
    let (file, mut warnings) = translator.translate(&root)?;
    let text = &files.files[0].1;
    let mut loaded = crate::native::build_file(file, text, path, &Source::directory_of(path))?;
    warnings.append(&mut loaded.warnings);
    loaded.warnings = warnings;
    Ok(loaded)
}
