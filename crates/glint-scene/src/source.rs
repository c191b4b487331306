use std::cell::RefCell;
use std::path::{Path, PathBuf};

/// Where the files a scene refers to (meshes, textures, environment maps) come from, and a
/// record of the ones read from disk: a render's checkpoint fingerprint hashes them, so a
/// changed mesh behind the same scene refuses to resume.
#[derive(Clone, Debug)]
pub struct Source<'a> {
    origin: Origin<'a>,
    read: RefCell<Vec<PathBuf>>,
}

#[derive(Clone, Debug)]
enum Origin<'a> {
    /// Paths relative to this directory (the scene file's).
    Directory(PathBuf),
    /// Files compiled into the binary, by the path the scene writes.
    Embedded(&'a [(&'a str, &'a [u8])]),
}

impl<'a> Source<'a> {
    /// Files compiled into the binary, by the path the scene writes.
    pub fn embedded(files: &'a [(&'a str, &'a [u8])]) -> Self {
        Self { origin: Origin::Embedded(files), read: RefCell::default() }
    }

    /// Paths relative to `directory`.
    pub fn directory(directory: PathBuf) -> Self {
        Self { origin: Origin::Directory(directory), read: RefCell::default() }
    }

    pub fn directory_of(scene_path: &Path) -> Source<'static> {
        Source::directory(scene_path.parent().map(Path::to_path_buf).unwrap_or_default())
    }

    /// The bytes of `path` as written in the scene, or a message saying why not.
    pub fn read(&self, path: &str) -> Result<Vec<u8>, String> {
        match &self.origin {
            Origin::Directory(dir) => {
                let full = dir.join(path);
                let bytes =
                    std::fs::read(&full).map_err(|e| format!("cannot read `{path}` ({}): {e}", full.display()))?;
                self.read.borrow_mut().push(full);
                Ok(bytes)
            }
            Origin::Embedded(files) => files
                .iter()
                .find(|(name, _)| *name == path)
                .map(|(_, bytes)| bytes.to_vec())
                .ok_or_else(|| format!("no built-in file `{path}`")),
        }
    }

    /// The files read from disk so far, in order.
    pub fn files_read(&self) -> Vec<PathBuf> {
        self.read.borrow().clone()
    }
}
