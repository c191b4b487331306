use std::path::{Path, PathBuf};

/// Where the files a scene refers to (meshes, later textures) come from.
#[derive(Clone, Debug)]
pub enum Source<'a> {
    /// Paths relative to this directory (the scene file's).
    Directory(PathBuf),
    /// Files compiled into the binary, by the path the scene writes.
    Embedded(&'a [(&'a str, &'a [u8])]),
}

impl Source<'_> {
    /// The bytes of `path` as written in the scene, or a message saying why not.
    pub fn read(&self, path: &str) -> Result<Vec<u8>, String> {
        match self {
            Source::Directory(dir) => {
                let full = dir.join(path);
                std::fs::read(&full).map_err(|e| format!("cannot read `{path}` ({}): {e}", full.display()))
            }
            Source::Embedded(files) => files
                .iter()
                .find(|(name, _)| *name == path)
                .map(|(_, bytes)| bytes.to_vec())
                .ok_or_else(|| format!("no built-in file `{path}`")),
        }
    }

    pub fn directory_of(scene_path: &Path) -> Source<'static> {
        Source::Directory(scene_path.parent().map(Path::to_path_buf).unwrap_or_default())
    }
}
