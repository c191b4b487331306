//! Mesh files: OBJ (through `tobj`) and PLY (through `ply-rs`), optionally gzipped
//! (`.ply.gz`, `.obj.gz`), and Mitsuba's `.serialized` meshes. Errors are plain messages; the
//! caller adds the scene location.

mod curves;
mod obj;
pub(crate) mod parametric;
mod ply;
mod serialized;

use std::path::Path;

use glint_core::shapes::{Mesh, MeshAttribute};

pub use curves::read_curves;

/// Reads a mesh from its bytes, choosing the format by the file name.
pub fn read_mesh(name: &str, bytes: &[u8]) -> Result<Mesh, String> {
    read_mesh_part(name, bytes, 0)
}

/// Mesh `shape_index` of a file that holds several (a `.serialized` file; any other holds
/// one, index 0).
pub fn read_mesh_part(name: &str, bytes: &[u8], shape_index: u32) -> Result<Mesh, String> {
    let (stem, data) = match name.strip_suffix(".gz") {
        Some(stem) => (stem, crate::source::gunzip(bytes)?),
        None => (name, bytes.to_vec()),
    };
    let extension = Path::new(stem).extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if shape_index != 0 && extension.as_deref() != Some("serialized") {
        return Err(format!(
            "`shape_index` {shape_index} asks for one of several meshes, but only a .serialized file holds several"
        ));
    }
    let mesh = match extension.as_deref() {
        Some("obj") => obj::read(&data)?,
        Some("ply") => ply::read(&data)?,
        Some("serialized") => serialized::read(&data, shape_index)?,
        _ => {
            return Err(
                "unknown mesh format: expected a file ending in .obj, .ply, .serialized, .obj.gz or .ply.gz".into()
            )
        }
    };
    validate(&mesh)?;
    Ok(mesh)
}

/// A mesh written in the scene itself, checked as a file's would be (and its normals and uvs
/// one per position).
pub fn from_data(data: &crate::native::schema::MeshData) -> Result<Mesh, String> {
    let n = data.positions.len();
    let per_vertex = |what: &str, len: usize| {
        if len == n {
            Ok(())
        } else {
            Err(format!("{len} {what} for {n} positions: give one per position"))
        }
    };
    if let Some(normals) = &data.normals {
        per_vertex("normals", normals.len())?;
    }
    if let Some(uvs) = &data.uvs {
        per_vertex("uvs", uvs.len())?;
    }
    if let Some(colors) = &data.colors {
        per_vertex("colors", colors.len())?;
        if let Some(i) = colors.iter().position(|c| !c.iter().all(|x| x.is_finite())) {
            return Err(format!("color {i} is not finite: {:?}", colors[i]));
        }
    }
    let attributes = data.colors.iter().map(|colors| MeshAttribute {
        name: "vertex_color".into(),
        values: colors.iter().flatten().copied().collect(),
        dim: 3,
        per_vertex: true,
    });
    let mesh = Mesh {
        positions: data.positions.iter().map(|&p| p.into()).collect(),
        normals: data.normals.as_ref().map(|ns| ns.iter().map(|&v| glam::Vec3::from(v).normalize_or_zero()).collect()),
        uvs: data.uvs.as_ref().map(|uvs| uvs.iter().map(|&uv| uv.into()).collect()),
        indices: data.indices.clone(),
        attributes: attributes.collect(),
        ..Mesh::default()
    };
    validate(&mesh)?;
    if let Some(i) = mesh.normals.iter().flatten().position(|n| *n == glam::Vec3::ZERO) {
        return Err(format!("normal {i} is zero or not a finite vector"));
    }
    Ok(mesh)
}

/// Reads a mesh file from disk.
pub fn load_mesh(path: &Path) -> Result<Mesh, String> {
    let bytes =
        crate::source::read_file(path, u64::MAX).map_err(|e| format!("cannot read `{}`: {e}", path.display()))?;
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

    /// Mitsuba's grouping of a PLY file's other properties: 8-bit `r, g, b` as `vertex_color`
    /// in [0, 1], `n_x, n_y` as `vertex_n`, a lone `quality`; per face `color_0 … color_2`
    /// as `face_color` and `weight_0` as `face_weight`, repeated over a quad's two triangles.
    #[test]
    fn ply_attributes_are_grouped_as_mitsuba_groups_them() {
        let ply = b"ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty uchar r\nproperty uchar g\nproperty uchar b\nproperty float n_x\nproperty float n_y\nproperty float quality\nelement face 2\nproperty list uchar int vertex_indices\nproperty float color_0\nproperty float color_1\nproperty float color_2\nproperty float weight_0\nend_header\n0 0 0 255 0 51 1 2 0.5\n1 0 0 0 255 0 3 4 0.25\n1 1 0 0 0 255 5 6 1\n0 1 0 255 255 255 7 8 2\n4 0 1 2 3 0.1 0.2 0.3 0.9\n3 0 2 3 0.4 0.5 0.6 0.7\n";
        let m = read_mesh("a.ply", ply).unwrap();
        let names: Vec<(&str, usize, bool)> =
            m.attributes.iter().map(|a| (a.name.as_str(), a.dim, a.per_vertex)).collect();
        assert_eq!(
            names,
            [
                ("vertex_color", 3, true),
                ("vertex_n", 2, true),
                ("vertex_quality", 1, true),
                ("face_color", 3, false),
                ("face_weight", 1, false)
            ]
        );
        assert_eq!(&m.attributes[0].values[..3], &[1.0, 0.0, 0.2]);
        assert_eq!(m.attributes[1].values, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0]);
        // Three triangles: the quad's two carry its values, the triangle its own.
        assert_eq!(m.attributes[4].values, [0.9, 0.9, 0.7]);
        assert_eq!(&m.attributes[3].values[3..], &[0.1, 0.2, 0.3, 0.4, 0.5, 0.6]);
        // Interpolated by hand: the centre of triangle 1 (corners 0, 2, 3) averages their
        // colours; a face value is the same anywhere on its face.
        let centre = m.attribute("vertex_color", 1, glam::Vec2::splat(1.0 / 3.0)).unwrap();
        let expected = (glam::Vec3::new(1.0, 0.0, 0.2) + glam::Vec3::new(0.0, 0.0, 1.0) + glam::Vec3::ONE) / 3.0;
        assert!((centre - expected).abs().max_element() < 1e-6, "{centre}");
        assert_eq!(m.attribute("face_weight", 2, glam::Vec2::new(0.1, 0.7)), Some(glam::Vec3::splat(0.7)));
        assert_eq!(m.attribute("vertex_missing", 0, glam::Vec2::ZERO), None);
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
    fn reads_the_shared_bunny() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/meshes/stanford_bunny.ply.gz");
        assert!(path.exists(), "the bunny must be at {} (../shared/meshes)", path.display());
        let m = load_mesh(&path).unwrap();
        assert_eq!((m.positions.len(), m.triangle_count()), (35_947, 69_451));
    }
}
