//! The files a scene names, in every reader: only regular files are read (`/dev/zero` never
//! ends and a FIFO waits for a writer for ever), each no further than the length that
//! matters, and a refusal names the file and, where the format tells, the line that names it.

use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

use glint_scene::{load_scene, LoadedScene, SceneError};

/// A fresh directory holding `files` (name, bytes).
fn scene_dir(test: &str, files: &[(&str, &[u8])]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("glint-files-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (name, bytes) in files {
        std::fs::write(dir.join(name), bytes).unwrap();
    }
    dir
}

/// Loads `path` on a thread of its own and gives up after 20 s, so that a reader that waits
/// for ever fails the test instead of hanging it.
fn load_within_time(path: &Path) -> Result<LoadedScene, SceneError> {
    let (sender, receiver) = mpsc::channel();
    let path = path.to_path_buf();
    std::thread::spawn(move || {
        // The receiver is gone only when the test has given up.
        let _ = sender.send(load_scene(&path));
    });
    receiver
        .recv_timeout(Duration::from_secs(20))
        .expect("the scene took more than 20 s to load: does it wait on a file?")
}

fn error_of(path: &Path) -> String {
    match load_within_time(path) {
        Ok(_) => panic!("{}: expected an error", path.display()),
        Err(e) => e.to_string(),
    }
}

const PBRT_HEAD: &str = "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n";

/// Before, each of these read `/dev/zero` until the machine's memory ran out (23 GB, then the
/// kernel killed the process).
#[cfg(unix)]
#[test]
fn a_device_named_by_a_scene_is_refused_at_the_line_that_names_it() {
    let device = "it is a character device, not a regular file";
    let pbrt = format!("{PBRT_HEAD}Include \"/dev/zero\"\n");
    let ply = format!("{PBRT_HEAD}Shape \"plymesh\" \"string filename\" \"/dev/zero\"\n");
    let toml = "[camera]\nposition = [0, 0, -5]\nlook_at = [0, 0, 0]\n\n[materials.grey]\ntype = \"diffuse\"\n\n\
                [[shapes]]\ntype = \"mesh\"\nmaterial = \"grey\"\nfile = \"/dev/zero\"\n";
    let xml = r#"<scene version="3.0.0">
    <include filename="/dev/zero"/>
</scene>"#;
    let gltf_buffer = r#"{ "asset": { "version": "2.0" }, "buffers": [{ "uri": "/dev/zero", "byteLength": 64 }] }"#;
    let gltf_image = r#"{ "asset": { "version": "2.0" }, "images": [{ "uri": "/dev/zero" }] }"#;
    let dir = scene_dir(
        "device",
        &[
            ("include.pbrt", pbrt.as_bytes()),
            ("ply.pbrt", ply.as_bytes()),
            ("mesh.toml", toml.as_bytes()),
            ("include.xml", xml.as_bytes()),
            ("buffer.gltf", gltf_buffer.as_bytes()),
            ("image.gltf", gltf_image.as_bytes()),
        ],
    );
    let expected = [
        ("include.pbrt", "include.pbrt:4:1: cannot read `/dev/zero` (/dev/zero): "),
        ("ply.pbrt", "ply.pbrt:4:1: cannot read `/dev/zero` (/dev/zero): "),
        ("mesh.toml", "mesh.toml:11:1: shapes[0] (mesh): mesh file: cannot read `/dev/zero` (/dev/zero): "),
        ("include.xml", "include.xml:2:5: cannot read `/dev/zero` (/dev/zero): "),
        ("buffer.gltf", "buffer.gltf: buffer 0: cannot read `/dev/zero` (/dev/zero): "),
        ("image.gltf", "image.gltf: image 0: cannot read `/dev/zero` (/dev/zero): "),
    ];
    for (name, start) in expected {
        let e = error_of(&dir.join(name));
        assert!(e.contains(start) && e.contains(device), "{name}: expected `{start}…{device}` in\n{e}");
    }
    // The scene file itself.
    let e = error_of(Path::new("/dev/zero"));
    assert!(e.starts_with("/dev/zero: cannot read the scene file: ") && e.contains(device), "{e}");
    std::fs::remove_dir_all(dir).unwrap();
}

/// Before, opening the FIFO waited for a writer for ever.
#[cfg(unix)]
#[test]
fn an_included_fifo_is_refused_without_waiting_for_a_writer() {
    let pbrt = format!("{PBRT_HEAD}Include \"pipe.pbrt\"\n");
    let dir = scene_dir("fifo", &[("scene.pbrt", pbrt.as_bytes())]);
    match std::process::Command::new("mkfifo").arg(dir.join("pipe.pbrt")).status() {
        Ok(status) if status.success() => {
            let e = error_of(&dir.join("scene.pbrt"));
            assert!(e.contains("scene.pbrt:4:1: cannot read `pipe.pbrt`"), "{e}");
            assert!(e.contains("it is a named pipe (FIFO), not a regular file"), "{e}");
            let e = error_of(&dir.join("pipe.pbrt"));
            assert!(e.contains("pipe.pbrt: cannot read the scene file: it is a named pipe (FIFO)"), "{e}");
        }
        _ => eprintln!("skipped: mkfifo is not here"),
    }
    let e = error_of(&dir);
    assert!(e.contains("it is a directory, not a regular file"), "{e}");
    std::fs::remove_dir_all(dir).unwrap();
}

/// A glTF buffer file longer than its `byteLength`: only `byteLength` bytes are read. The
/// file is 64 GiB long but sparse (a hole after the triangle, taking no disk): before, it
/// was read whole.
#[test]
fn a_gltf_buffer_is_read_no_further_than_its_byte_length() {
    let positions: Vec<u8> =
        [[0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]].iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
    let document = serde_json::json!({
        "asset": { "version": "2.0" },
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0 }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 } }] }],
        "buffers": [{ "uri": "long.bin", "byteLength": positions.len() }],
        "bufferViews": [{ "buffer": 0, "byteLength": positions.len() }],
        "accessors": [{ "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                        "min": [0, 0, 0], "max": [1, 1, 0] }],
    });
    let dir =
        scene_dir("long-buffer", &[("scene.gltf", &serde_json::to_vec(&document).unwrap()), ("long.bin", &positions)]);
    let file = std::fs::OpenOptions::new().write(true).open(dir.join("long.bin")).unwrap();
    if file.set_len(64 << 30).is_err() {
        eprintln!("skipped: this file system holds no 64 GiB sparse file");
        std::fs::remove_dir_all(dir).unwrap();
        return;
    }
    drop(file);
    let loaded = load_within_time(&dir.join("scene.gltf"));
    std::fs::remove_dir_all(dir).unwrap();
    if let Err(e) = loaded {
        panic!("{e}");
    }
}

#[test]
fn a_pbrt_file_may_open_with_a_byte_order_mark_and_hold_other_bytes_in_comments() {
    // Before: "unknown directive `\u{feff}LookAt`", and the Latin-1 `é` refused the file
    // with no line.
    let main = format!("\u{feff}{PBRT_HEAD}Include \"more.pbrt\"\nShape \"sphere\"\n");
    let more = b"\xef\xbb\xbf# Caf\xe9 de Fl\xf6re\nLightSource \"point\" # \xff\n";
    let dir = scene_dir("text", &[("scene.pbrt", main.as_bytes()), ("more.pbrt", more)]);
    let loaded = load_within_time(&dir.join("scene.pbrt")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(loaded.scene.listed_lights().count(), 1);
    // Outside a comment such a byte is refused at its line and column.
    std::fs::write(dir.join("more.pbrt"), b"# fine\nShape \"sph\xe9re\"\n").unwrap();
    let e = error_of(&dir.join("scene.pbrt"));
    assert!(e.contains("more.pbrt:2:11: byte 0xE9 is not UTF-8 text"), "{e}");
    std::fs::remove_dir_all(dir).unwrap();
}
