//! Mesh files: OBJ (through `tobj`) and PLY (through `ply-rs`), optionally gzipped
//! (`.ply.gz`, `.obj.gz`). Errors are plain messages; the caller adds the scene location.

mod obj;
mod ply;

use std::io::Read;
use std::path::Path;

use glint_core::shapes::Mesh;

/// Reads a mesh from its bytes, choosing the format by the file name.
pub fn read_mesh(name: &str, bytes: &[u8]) -> Result<Mesh, String> {
    let (stem, data) = match name.strip_suffix(".gz") {
        Some(stem) => {
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
            (stem, out)
        }
        None => (name, bytes.to_vec()),
    };
    let mesh = match Path::new(stem).extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
        Some("obj") => obj::read(&data)?,
        Some("ply") => ply::read(&data)?,
        _ => return Err("unknown mesh format: expected a file ending in .obj, .ply, .obj.gz or .ply.gz".into()),
    };
    validate(&mesh)?;
    Ok(mesh)
}

/// Reads a mesh file from disk.
pub fn load_mesh(path: &Path) -> Result<Mesh, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read `{}`: {e}", path.display()))?;
    read_mesh(&path.to_string_lossy(), &bytes)
}

fn validate(mesh: &Mesh) -> Result<(), String> {
    if mesh.indices.is_empty() {
        return Err("the mesh has no faces".into());
    }
    let n = mesh.positions.len() as u32;
    if let Some((f, _)) = mesh.indices.iter().enumerate().find(|(_, t)| t.iter().any(|&i| i >= n)) {
        return Err(format!("face {f} refers to a vertex that does not exist (the file has {n} vertices)"));
    }
    if let Some(i) = mesh.positions.iter().position(|p| !p.is_finite()) {
        return Err(format!("vertex {i} has a coordinate that is not a finite number"));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn obj_quad_is_triangulated_with_uvs_and_normals() {
        let obj = b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1 4/4/1\n";
        let m = read_mesh("quad.obj", obj).unwrap();
        assert_eq!(m.triangle_count(), 2);
        assert!(m.normals.is_some() && m.uvs.is_some());
    }

    #[test]
    fn ascii_ply_triangle() {
        let ply = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
        let m = read_mesh("t.ply", ply).unwrap();
        assert_eq!((m.positions.len(), m.indices), (3, vec![[0, 1, 2]]));
    }

    #[test]
    fn malformed_faces_and_vertices_are_refused_with_their_line() {
        let e = read_mesh("x.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2\n").unwrap_err();
        assert!(e.contains("line 5") && e.contains("at least 3 vertices"), "{e}");
        let e = read_mesh("x.obj", b"v 0 0 0\nf 1 # a point\n").unwrap_err();
        assert!(e.contains("line 2"), "{e}");
        let only_x = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0\n1\n2\n3 0 1 2\n";
        let e = read_mesh("x.ply", only_x).unwrap_err();
        assert!(e.contains("no `y` property"), "{e}");
        let nan = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n";
        let e = read_mesh("x.ply", nan).unwrap_err();
        assert!(e.contains("line 11") && e.contains("`nan`"), "{e}");
        // Found by glint-fuzz: a format version that overflows panicked inside ply-rs.
        let overflow = b"ply\nformat binary_little_endian 99999999999999999999\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n\0\0\0\0\0\0\0\0\0\0\0\0";
        assert!(read_mesh("x.ply", overflow).unwrap_err().contains("line 2"));
        let huge = b"ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n";
        assert!(read_mesh("x.ply", huge).unwrap_err().contains("larger than the file"));
        // Windows line ends are a valid header.
        let crlf = b"ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty float x\r\nproperty float y\r\nproperty float z\r\nelement face 1\r\nproperty list uchar int vertex_indices\r\nend_header\r\n0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n";
        assert_eq!(read_mesh("x.ply", crlf).map(|m| m.triangle_count()), Ok(1));
    }

    #[test]
    fn corrupt_files_give_messages() {
        assert!(read_mesh("x.ply", b"not a ply").is_err());
        assert!(read_mesh("x.obj", b"v 0 0 0\nf 1 2 3\n").unwrap_err().contains("vertex"));
        assert!(read_mesh("x.stl", b"").unwrap_err().contains("unknown mesh format"));
        assert!(read_mesh("x.ply.gz", b"nope").unwrap_err().contains("gzip"));
    }

    #[test]
    fn reads_the_shared_bunny_when_present() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/meshes/stanford_bunny.ply.gz");
        if !path.exists() {
            eprintln!("skipped: {} not found", path.display());
            return;
        }
        let m = load_mesh(&path).unwrap();
        assert_eq!((m.positions.len(), m.triangle_count()), (35_947, 69_451));
    }
}
