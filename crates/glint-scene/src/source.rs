use std::cell::RefCell;
use std::path::{Path, PathBuf};

/// Where the files a scene refers to (meshes, textures, environment maps) come from, and a
/// record of the ones read from disk: a render's checkpoint fingerprint hashes them, so a
/// changed mesh behind the same scene refuses to resume.
#[derive(Clone, Debug)]
pub struct Source<'a> {
    origin: Origin<'a>,
    /// Files a reader made in memory (a glTF's embedded images, a pbrt map resampled), found
    /// by name before the origin's.
    made: Vec<(String, Vec<u8>)>,
    read: RefCell<Vec<PathBuf>>,
}

#[derive(Clone, Debug)]
enum Origin<'a> {
    /// Paths relative to the first of these directories that holds them (the scene file's
    /// first, then Mitsuba's `<path>` entries: Mitsuba's file resolver).
    Directories(Vec<PathBuf>),
    /// Files compiled into the binary, by the path the scene writes.
    Embedded(&'a [(&'a str, &'a [u8])]),
}

impl<'a> Source<'a> {
    /// Files compiled into the binary, by the path the scene writes.
    pub fn embedded(files: &'a [(&'a str, &'a [u8])]) -> Self {
        Self { origin: Origin::Embedded(files), made: Vec::new(), read: RefCell::default() }
    }

    /// Paths relative to `directory`.
    pub fn directory(directory: PathBuf) -> Self {
        Self::search_path(vec![directory])
    }

    /// Paths relative to the first directory of `directories` that holds them (a path found
    /// in none is reported against the first).
    pub fn search_path(directories: Vec<PathBuf>) -> Self {
        Self { origin: Origin::Directories(directories), made: Vec::new(), read: RefCell::default() }
    }

    pub fn directory_of(scene_path: &Path) -> Source<'static> {
        Source::directory(scene_path.parent().map(Path::to_path_buf).unwrap_or_default())
    }

    /// The same source with files made in memory, found by name before any other.
    pub fn with_made_files(self, made: Vec<(String, Vec<u8>)>) -> Self {
        Self { made, ..self }
    }

    /// The bytes of `path` as written in the scene, or a message saying why not.
    pub fn read(&self, path: &str) -> Result<Vec<u8>, String> {
        if let Some((_, bytes)) = self.made.iter().find(|(name, _)| name == path) {
            return Ok(bytes.clone());
        }
        match &self.origin {
            Origin::Directories(directories) => {
                let full = resolve(directories, Path::new(path));
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

/// Mitsuba's file resolution: `path` under the first of `directories` where it exists, else
/// under the first directory (an absolute path is itself).
pub fn resolve(directories: &[PathBuf], path: &Path) -> PathBuf {
    directories
        .iter()
        .map(|dir| dir.join(path))
        .find(|candidate| candidate.exists())
        .unwrap_or_else(|| directories.first().map_or_else(|| path.to_path_buf(), |dir| dir.join(path)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resolution_takes_the_first_directory_that_holds_the_file() {
        let root = std::env::temp_dir().join(format!("glint-resolve-{}", std::process::id()));
        let (a, b) = (root.join("a"), root.join("b"));
        std::fs::create_dir_all(&a).unwrap();
        std::fs::create_dir_all(&b).unwrap();
        std::fs::write(b.join("mesh.obj"), "v 0 0 0").unwrap();
        std::fs::write(a.join("both.obj"), "").unwrap();
        std::fs::write(b.join("both.obj"), "").unwrap();
        let dirs = vec![a.clone(), b.clone()];
        assert_eq!(resolve(&dirs, Path::new("mesh.obj")), b.join("mesh.obj"));
        assert_eq!(resolve(&dirs, Path::new("both.obj")), a.join("both.obj"));
        assert_eq!(resolve(&dirs, Path::new("missing.obj")), a.join("missing.obj"));
        let source = Source::search_path(dirs);
        assert_eq!(source.read("mesh.obj").unwrap(), b"v 0 0 0");
        assert!(source.read("missing.obj").unwrap_err().contains("missing.obj"));
        std::fs::remove_dir_all(&root).unwrap();
    }
}
