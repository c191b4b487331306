use glam::{Vec2, Vec3};
use glint_core::shapes::Mesh;

/// All objects of the file merged into one mesh; polygons triangulated as fans by `tobj`.
pub(super) fn read(data: &[u8]) -> Result<Mesh, String> {
    check_faces(data)?;
    let options = tobj::LoadOptions { triangulate: true, single_index: true, ..Default::default() };
    let (models, _) = tobj::load_obj_buf(&mut &data[..], &options, |_| Err(tobj::LoadError::OpenFileFailed))
        .map_err(|e| format!("not a valid OBJ file: {e}"))?;
    let mut mesh = Mesh::default();
    let (mut normals, mut uvs) = (Vec::new(), Vec::new());
    let (mut all_normals, mut all_uvs) = (true, true);
    for model in &models {
        let m = &model.mesh;
        let base = mesh.positions.len() as u32;
        let count = m.positions.len() / 3;
        mesh.positions.extend(m.positions.chunks_exact(3).map(|p| Vec3::new(p[0], p[1], p[2])));
        all_normals &= m.normals.len() == 3 * count;
        all_uvs &= m.texcoords.len() == 2 * count;
        normals.extend(m.normals.chunks_exact(3).map(|n| Vec3::new(n[0], n[1], n[2]).normalize_or(Vec3::Z)));
        uvs.extend(m.texcoords.chunks_exact(2).map(|t| Vec2::new(t[0], t[1])));
        mesh.indices.extend(m.indices.chunks_exact(3).map(|t| [base + t[0], base + t[1], base + t[2]]));
    }
    mesh.normals = (all_normals && !normals.is_empty()).then_some(normals);
    mesh.uvs = (all_uvs && !uvs.is_empty()).then_some(uvs);
    Ok(mesh)
}

/// Every face names at least three vertices (`tobj` turns a face of one or two into
/// zero-area triangles, which were then only a warning).
fn check_faces(data: &[u8]) -> Result<(), String> {
    for (index, line) in data.split(|&b| b == b'\n').enumerate() {
        let line = String::from_utf8_lossy(line);
        let mut words = line.split_whitespace();
        if words.next() == Some("f") {
            let count = words.take_while(|w| !w.starts_with('#')).count();
            if count < 3 {
                return Err(format!("line {}: a face needs at least 3 vertices, this one has {count}", index + 1));
            }
        }
    }
    Ok(())
}
