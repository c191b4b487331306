//! Mitsuba 3 scene files (`.xml`): read, mapped onto glint's native scene description, and
//! built by the same builder as TOML scenes. docs/mitsuba.md lists what is supported and how
//! each element maps onto glint.

pub(crate) mod cie_tables;
pub(crate) mod spectrum;
mod translate;
mod xml;

use std::path::{Path, PathBuf};

use crate::reader::{ReadScene, Translation};
use crate::source::Source;

/// Reads a Mitsuba 3 scene into its native description, with the search path for the files it
/// names: the scene's directory, its `<path>`s, then `search_path`. `defines` are
/// `-D name=value` parameters, which override the file's `<default>`s.
pub(crate) fn read_file(path: &Path, defines: &[(String, String)], search_path: &[PathBuf]) -> ReadScene {
    let (root, files) = xml::read_scene(path, defines, search_path)?;
    let translator = translate::Translator::new(&files, &root)?;
    let (file, translated_warnings) = translator.translate(&root)?;
    let mut warnings = files.warnings.clone();
    warnings.extend(translated_warnings);
    // A -D that no <default> declares and no `$name` uses changes nothing: most likely a typo.
    let used = |name: &str| {
        files.declared.iter().any(|d| d == name)
            || files.files.iter().any(|(_, text)| text.contains(&format!("${name}")))
    };
    for (name, _) in defines.iter().filter(|(name, _)| !used(name)) {
        let suggestion = crate::error::did_you_mean(name, files.declared.iter().map(String::as_str));
        warnings
            .push(format!("-D {name}: no <default name=\"{name}\"> in the scene, so it changes nothing{suggestion}"));
    }
    let translation = Translation {
        warnings,
        // The XML files (the scene and what it includes) come before the meshes and textures.
        scene_files: files.files.iter().map(|(path, _)| path.clone()).collect(),
        ..Translation::new(file, files.files[0].1.clone())
    };
    Ok((translation, Source::search_path(files.search_path.clone())))
}
