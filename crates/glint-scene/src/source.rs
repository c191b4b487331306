use std::cell::RefCell;
use std::io::Read;
use std::path::{Path, PathBuf};

/// Where the files a scene refers to (meshes, textures, environment maps) come from, and a
/// record of the ones read from disk: a render's checkpoint fingerprint hashes them, so a
/// changed mesh behind the same scene refuses to resume.
#[derive(Clone, Debug)]
pub struct Source<'a> {
    origin: Origin<'a>,
    /// Files a reader made in memory (a glTF's embedded images, a pbrt map resampled), found
    /// by name before the origin's.
    made: Vec<(String, MadeFile)>,
    read: RefCell<Vec<PathBuf>>,
}

/// A file a reader made in memory: bytes to decode as a file's, or an image already decoded
/// (linear RGB, row 0 the top), handed over as it is.
#[derive(Clone, Debug)]
pub(crate) enum MadeFile {
    Bytes(Vec<u8>),
    Image { width: u32, height: u32, pixels: Vec<glint_core::Rgb> },
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
    pub(crate) fn with_made_files(self, made: Vec<(String, MadeFile)>) -> Self {
        Self { made, ..self }
    }

    /// The image a reader made in memory under the name `path`, decoded (linear RGB, row 0
    /// the top), if it made one; a file's image is read and decoded by the caller.
    pub(crate) fn made_image(&self, path: &str) -> Option<(u32, u32, Vec<glint_core::Rgb>)> {
        self.made.iter().find(|(name, _)| name == path).and_then(|(_, made)| match made {
            MadeFile::Image { width, height, pixels } => Some((*width, *height, pixels.clone())),
            MadeFile::Bytes(_) => None,
        })
    }

    /// The bytes of `path` as written in the scene, or a message saying why not.
    pub fn read(&self, path: &str) -> Result<Vec<u8>, String> {
        self.read_at_most(path, u64::MAX)
    }

    /// The first `at_most` bytes of `path` (all of a shorter file): what a reader uses of a
    /// file that declares its own length (a glTF buffer's `byteLength`).
    pub fn read_at_most(&self, path: &str, at_most: u64) -> Result<Vec<u8>, String> {
        let prefix = |bytes: &[u8]| bytes[..bytes.len().min(usize::try_from(at_most).unwrap_or(usize::MAX))].to_vec();
        if let Some((_, made)) = self.made.iter().find(|(name, _)| name == path) {
            return match made {
                MadeFile::Bytes(bytes) => Ok(prefix(bytes)),
                MadeFile::Image { .. } => Err(format!("`{path}` is an image made in memory, not a file")),
            };
        }
        match &self.origin {
            Origin::Directories(directories) => {
                let full = resolve(directories, Path::new(path));
                let bytes =
                    read_file(&full, at_most).map_err(|e| format!("cannot read `{path}` ({}): {e}", full.display()))?;
                self.read.borrow_mut().push(full);
                Ok(bytes)
            }
            Origin::Embedded(files) => files
                .iter()
                .find(|(name, _)| *name == path)
                .map(|(_, bytes)| prefix(bytes))
                .ok_or_else(|| format!("no built-in file `{path}`")),
        }
    }

    /// The files read from disk so far, in order.
    pub fn files_read(&self) -> Vec<PathBuf> {
        self.read.borrow().clone()
    }
}

/// The first `at_most` bytes of the file at `path` (`u64::MAX`: all of it), within the memory
/// limit. Every file a scene reads from disk is read here, so that none can take more than
/// the limit or wait for ever: only a regular file is read (`/dev/zero` never ends and a FIFO
/// waits for a writer; neither is opened). On failure, the reason without the path: the
/// caller names the file as the scene wrote it.
pub fn read_file(path: &Path, at_most: u64) -> Result<Vec<u8>, String> {
    read_within(path, at_most, crate::limits::memory_limit())
}

fn read_within(path: &Path, at_most: u64, limit: u64) -> Result<Vec<u8>, String> {
    let kind = std::fs::metadata(path).map_err(|e| e.to_string())?.file_type();
    if !kind.is_file() {
        return Err(format!("it is {}, not a regular file", describe_kind(kind)));
    }
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    // The length of what is open (a path swapped for a device since is refused here too).
    let metadata = file.metadata().map_err(|e| e.to_string())?;
    if !metadata.is_file() {
        return Err(format!("it is {}, not a regular file", describe_kind(metadata.file_type())));
    }
    let wanted = metadata.len().min(at_most);
    let too_large = |bytes: u64| {
        format!(
            "it holds {}, more than the memory limit of {} ({})",
            crate::limits::describe(bytes),
            crate::limits::describe(limit),
            crate::limits::RAISE
        )
    };
    if wanted > limit {
        return Err(too_large(wanted));
    }
    // A file that grows while it is read (or says it is empty, as /proc's do) is still read no
    // further than the limit.
    let mut bytes = Vec::new();
    bytes.try_reserve_exact(usize::try_from(wanted).unwrap_or(usize::MAX)).map_err(|e| e.to_string())?;
    file.take(at_most.min(limit.saturating_add(1))).read_to_end(&mut bytes).map_err(|e| e.to_string())?;
    if bytes.len() as u64 > limit {
        return Err(too_large(bytes.len() as u64));
    }
    Ok(bytes)
}

/// `bytes` read from `file` as UTF-8 text, or an error at the line of the first byte that is
/// not.
pub(crate) fn utf8_text(file: &Path, bytes: Vec<u8>) -> Result<String, crate::error::SceneError> {
    String::from_utf8(bytes).map_err(|e| {
        let offset = e.utf8_error().valid_up_to();
        let bytes = e.into_bytes();
        // The text before the byte is UTF-8, so its line and column are exact.
        let text = String::from_utf8_lossy(&bytes);
        crate::error::SceneError::new(
            file,
            Some(crate::error::Location::from_offset(&text, offset)),
            format!("byte 0x{:02X} is not UTF-8 text (the file must be UTF-8)", bytes[offset]),
        )
    })
}

/// "a directory", "a FIFO", …: what a path that is not a regular file is, for messages.
fn describe_kind(kind: std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return "a named pipe (FIFO)";
        }
        if kind.is_char_device() {
            return "a character device";
        }
        if kind.is_block_device() {
            return "a block device";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    if kind.is_dir() {
        "a directory"
    } else {
        "a special file"
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

/// Gzip data inflated, within the memory limit, or a message saying why not.
pub(crate) fn gunzip(bytes: &[u8]) -> Result<Vec<u8>, String> {
    let limit = crate::limits::memory_limit();
    let mut out = Vec::new();
    flate2::read::GzDecoder::new(bytes)
        .take(limit.saturating_add(1))
        .read_to_end(&mut out)
        .map_err(|e| format!("not valid gzip data: {e}"))?;
    if out.len() as u64 > limit {
        return Err(format!(
            "it inflates to more than {}, the memory limit ({})",
            crate::limits::describe(limit),
            crate::limits::RAISE
        ));
    }
    Ok(out)
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

    #[test]
    fn reading_stops_at_the_length_asked_for_and_at_the_memory_limit() {
        let dir = std::env::temp_dir().join(format!("glint-bounded-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("hundred.bin");
        std::fs::write(&path, [7u8; 100]).unwrap();
        assert_eq!(read_within(&path, u64::MAX, 100).unwrap().len(), 100);
        assert_eq!(read_within(&path, 36, 100).unwrap(), [7u8; 36]);
        // Longer than the limit, but only 36 bytes of it are wanted.
        assert_eq!(read_within(&path, 36, 50).unwrap().len(), 36);
        let e = read_within(&path, u64::MAX, 50).unwrap_err();
        assert!(e.contains("memory limit") && e.contains("--memory-limit"), "{e}");
        let e = read_within(&dir, u64::MAX, 100).unwrap_err();
        assert!(e.contains("a directory, not a regular file"), "{e}");
        let source = Source::directory(dir.clone());
        assert_eq!(source.read_at_most("hundred.bin", 10).unwrap().len(), 10);
        let e = source.read(".").unwrap_err();
        assert!(e.contains("`.`") && e.contains("not a regular file"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Before, `/dev/zero` was read until the machine's memory ran out and a FIFO waited for a
    /// writer for ever; both are refused without being opened.
    #[cfg(unix)]
    #[test]
    fn devices_and_fifos_are_refused_unopened() {
        let e = read_file(Path::new("/dev/zero"), u64::MAX).unwrap_err();
        assert_eq!(e, "it is a character device, not a regular file");
        let dir = std::env::temp_dir().join(format!("glint-fifo-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let fifo = dir.join("pipe.pbrt");
        match std::process::Command::new("mkfifo").arg(&fifo).status() {
            Ok(status) if status.success() => {
                let e = read_file(&fifo, u64::MAX).unwrap_err();
                assert_eq!(e, "it is a named pipe (FIFO), not a regular file");
            }
            _ => eprintln!("skipped the FIFO: mkfifo is not here"),
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn text_that_is_not_utf8_is_refused_at_its_line() {
        let e = utf8_text(Path::new("s.toml"), b"a = 1\nb = \"\xe9\"\n".to_vec()).unwrap_err();
        let location = e.location.unwrap();
        assert_eq!((location.line, location.column), (2, 6));
        assert!(e.message.contains("0xE9"), "{}", e.message);
    }
}
