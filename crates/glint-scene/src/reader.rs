//! What every scene reader shares around its own grammar: reading the scene file with the
//! search path for the files it names (one message for an unreadable file, one search order
//! whatever the format), and the `Translation` it hands back: the native description, the
//! files it made in memory and its warnings. Readers translate and never build; `load.rs`
//! builds what they translate.

use std::path::{Path, PathBuf};

use crate::error::SceneError;
use crate::native::schema::SceneFile;
use crate::source::{MadeFile, Source};

/// Files a reader makes in memory, by name: a glTF's embedded images as bytes, a pbrt map
/// resampled as a decoded image.
pub(crate) type MadeFiles = Vec<(String, MadeFile)>;

/// The bytes of the file `name` among `made`, if it is one made as bytes (not decoded).
pub(crate) fn made_bytes<'m>(made: &'m MadeFiles, name: &str) -> Option<&'m [u8]> {
    made.iter().find(|(n, _)| n == name).and_then(|(_, file)| match file {
        MadeFile::Bytes(bytes) => Some(bytes.as_slice()),
        MadeFile::Image { .. } => None,
    })
}

/// The scene file's bytes, and the directories the files it names are looked for in: the
/// scene's own directory, then `search_path`.
pub(crate) fn read_scene_file(path: &Path, search_path: &[PathBuf]) -> Result<(Vec<u8>, Vec<PathBuf>), SceneError> {
    let bytes = crate::source::read_file(path, u64::MAX)
        .map_err(|e| SceneError::new(path, None, format!("cannot read the scene file: {e}")))?;
    let mut directories = vec![path.parent().map(Path::to_path_buf).unwrap_or_default()];
    directories.extend(search_path.iter().cloned());
    Ok((bytes, directories))
}

/// What a reader's entry gives back: the translation, and where the files it names are found.
pub(crate) type ReadScene = Result<(Translation, Source<'static>), SceneError>;

/// What a reader made of a scene file: everything the builder needs, and nothing built.
pub(crate) struct Translation {
    /// The native description.
    pub(crate) file: SceneFile,
    /// The text the description's spans point into; empty where it has none.
    pub(crate) text: String,
    /// Files made in memory, found by name before those of the search path.
    pub(crate) made: MadeFiles,
    pub(crate) warnings: Vec<String>,
    /// The scene files the reader read itself, the scene file first (a Mitsuba scene's
    /// includes), when there are more than the one.
    pub(crate) scene_files: Vec<PathBuf>,
}

impl Translation {
    /// A description with nothing else: no text, nothing made, no warnings.
    pub(crate) fn new(file: SceneFile, text: String) -> Self {
        Self { file, text, made: Vec::new(), warnings: Vec::new(), scene_files: Vec::new() }
    }
}
