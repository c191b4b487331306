//! Loading a scene: the reader for the file's format, chosen from one table by its extension,
//! translates it into the native description, and that description is built here, once, by
//! the native builder. Dependencies run one way: this module calls the readers and the
//! builder; readers only translate (they never build, and never call each other), and the
//! builder knows no reader.

use std::path::{Path, PathBuf};

use crate::error::SceneError;
use crate::gltf::GltfOptions;
use crate::native::{Format, LoadedScene};
use crate::reader::{ReadScene, Translation};
use crate::source::Source;

/// What the command line adds to a scene file.
#[derive(Clone, Debug, Default)]
pub struct LoadOptions {
    /// `-D name=value` parameters for Mitsuba scenes.
    pub defines: Vec<(String, String)>,
    /// Directories searched, after the scene's own (and a Mitsuba scene's `<path>`s), for
    /// the files it names: meshes, textures, includes (Mitsuba's `-a`).
    pub search_path: Vec<PathBuf>,
    /// A glTF file without punctual lights is lit by a default environment unless this is
    /// set (`--no-default-light`; docs/gltf.md).
    pub no_default_light: bool,
}

/// A scene format's reader: the extensions it answers to, whether it takes `-D` parameters,
/// and how it reads a file into its translation and the search path its files are found on.
struct Reader {
    extensions: &'static [&'static str],
    takes_defines: bool,
    read: fn(&Path, &LoadOptions) -> ReadScene,
}

/// Every reader but the native one, which reads whatever no other claims (TOML, or JSON by
/// its extension).
const READERS: [Reader; 3] = [
    Reader {
        extensions: &["xml"],
        takes_defines: true,
        read: |path, options| crate::mitsuba::read_file(path, &options.defines, &options.search_path),
    },
    Reader {
        extensions: &["gltf", "glb"],
        takes_defines: false,
        read: |path, options| {
            let gltf = GltfOptions { no_default_light: options.no_default_light };
            crate::gltf::read_file(path, &options.search_path, gltf)
        },
    },
    Reader {
        extensions: &["pbrt", "pbrt.gz"],
        takes_defines: false,
        read: |path, options| crate::pbrt::read_file(path, &options.search_path),
    },
];

const NATIVE: Reader = Reader {
    extensions: &["toml", "json"],
    takes_defines: false,
    read: |path, options| crate::native::read_file(path, &options.search_path),
};

/// Reads a scene file: `.xml` is a Mitsuba 3 scene, `.pbrt` a pbrt-v4 scene, `.gltf` and `.glb`
/// glTF 2.0, `.json` JSON, anything else TOML.
pub fn load_scene(path: &Path) -> Result<LoadedScene, SceneError> {
    load_scene_with(path, &[])
}

/// `load_scene` with `-D name=value` parameters for Mitsuba scenes (native scenes have none:
/// giving any is an error).
pub fn load_scene_with(path: &Path, defines: &[(String, String)]) -> Result<LoadedScene, SceneError> {
    load_scene_with_options(path, &LoadOptions { defines: defines.to_vec(), ..LoadOptions::default() })
}

/// `load_scene` with parameters and a search path.
pub fn load_scene_with_options(path: &Path, options: &LoadOptions) -> Result<LoadedScene, SceneError> {
    // The last extension, or the last two of a gzipped file (`.pbrt.gz`).
    let name = path.file_name().map(|n| n.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
    let extension = match name.strip_suffix(".gz") {
        Some(stem) => Path::new(stem).extension().and_then(|e| e.to_str()).map(|e| format!("{e}.gz")),
        None => Path::new(&name).extension().and_then(|e| e.to_str()).map(str::to_string),
    };
    let claims = |reader: &&Reader| extension.as_deref().is_some_and(|e| reader.extensions.contains(&e));
    let reader = READERS.iter().find(claims).unwrap_or(&NATIVE);
    if let (false, Some((name, _))) = (reader.takes_defines, options.defines.first()) {
        let native = if std::ptr::eq(reader, &NATIVE) { "; this is a native scene" } else { "" };
        return Err(SceneError::new(
            path,
            None,
            format!("-D {name}=…: parameters are for Mitsuba scenes (.xml){native}"),
        ));
    }
    let (translation, source) = (reader.read)(path, options)?;
    build(translation, path, &source)
}

/// Parses native scene text (TOML or JSON). `file` is only used in messages; `source`
/// resolves the files it names.
pub fn parse_scene(
    text: &str,
    format: Format,
    file: impl AsRef<Path>,
    source: &Source,
) -> Result<LoadedScene, SceneError> {
    let file = file.as_ref();
    let translation = crate::native::translate(text.to_string(), format, file)?;
    build(translation, file, source)
}

/// Reads pbrt-v4 scene text; `name` is used in messages, `source` resolves what it names.
pub fn parse_pbrt(text: &str, name: &Path, source: Source<'_>) -> Result<LoadedScene, SceneError> {
    let translation = crate::pbrt::translate_bytes(name, text.as_bytes().to_vec(), &source)?;
    build(translation, name, &source)
}

/// Reads glTF bytes (JSON or binary); `name` is used in messages, `source` resolves the
/// buffers and images it names.
pub fn parse_gltf(
    bytes: &[u8],
    name: &Path,
    source: Source<'_>,
    options: GltfOptions,
) -> Result<LoadedScene, SceneError> {
    let translation = crate::gltf::translate_bytes(bytes, name, &source, options)?;
    build(translation, name, &source)
}

/// Builds a reader's translation of the scene `name`, with the files it made found before
/// `source`'s; the reader's warnings come before the builder's.
fn build(translation: Translation, name: &Path, source: &Source) -> Result<LoadedScene, SceneError> {
    let with_made;
    let source = if translation.made.is_empty() {
        source
    } else {
        with_made = source.clone().with_made_files(translation.made);
        &with_made
    };
    let mut loaded = crate::native::build_file(translation.file, &translation.text, name, source)?;
    let mut warnings = translation.warnings;
    warnings.append(&mut loaded.warnings);
    loaded.warnings = warnings;
    if !translation.scene_files.is_empty() {
        // The builder lists the scene file, then what it read; a reader's own files replace
        // the first.
        loaded.inputs = translation.scene_files.into_iter().chain(loaded.inputs.into_iter().skip(1)).collect();
    }
    Ok(loaded)
}
