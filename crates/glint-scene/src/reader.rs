//! What every scene reader does around its own grammar: read the scene file and make the
//! search path for the files it names, and build the native description it wrote, with the
//! files it made in memory and its warnings. The readers call these, so that the message for
//! an unreadable file, the search order and the order of warnings are one whatever the format.

use std::path::{Path, PathBuf};

use crate::error::SceneError;
use crate::native::schema::SceneFile;
use crate::native::LoadedScene;
use crate::source::{MadeFile, Source};

/// Files a reader makes in memory, by name: a glTF's embedded images as bytes, a pbrt map
/// resampled as a decoded image.
pub(crate) type MadeFiles = Vec<(String, MadeFile)>;

/// The scene file's bytes, and the directories the files it names are looked for in: the
/// scene's own directory, then `search_path`.
pub(crate) fn read_scene_file(path: &Path, search_path: &[PathBuf]) -> Result<(Vec<u8>, Vec<PathBuf>), SceneError> {
    let bytes = crate::source::read_file(path, u64::MAX)
        .map_err(|e| SceneError::new(path, None, format!("cannot read the scene file: {e}")))?;
    let mut directories = vec![path.parent().map(Path::to_path_buf).unwrap_or_default()];
    directories.extend(search_path.iter().cloned());
    Ok((bytes, directories))
}

/// What a reader made of a scene file.
pub(crate) struct Translation<'t> {
    /// The native description.
    pub(crate) file: SceneFile,
    /// The text the description's spans point into; empty where it has none.
    pub(crate) text: &'t str,
    /// Files made in memory, found by name before `source`'s.
    pub(crate) made: MadeFiles,
    pub(crate) warnings: Vec<String>,
}

/// Builds the translation of the scene `name`; the reader's warnings come before the
/// builder's.
pub(crate) fn build(translation: Translation, name: &Path, source: Source) -> Result<LoadedScene, SceneError> {
    let source = source.with_made_files(translation.made);
    let mut loaded = crate::native::build_file(translation.file, translation.text, name, &source)?;
    let mut warnings = translation.warnings;
    warnings.append(&mut loaded.warnings);
    loaded.warnings = warnings;
    Ok(loaded)
}
