//! Parametric surfaces made into triangle meshes: a grid over (u, v) ∈ [0, 1]², for the
//! quadrics and patches that pbrt and Mitsuba scenes name and glint has no primitive for.

use glam::Vec3;

use crate::native::schema::MeshData;

/// A grid over (u, v) ∈ [0, 1]²: `nu` × `nv` cells, each two triangles, wound so their
/// normal agrees with `surface`'s.
pub(crate) fn grid(nu: usize, nv: usize, surface: impl Fn(f32, f32) -> (Vec3, Vec3)) -> MeshData {
    let mut data = MeshData::default();
    let mut normals = Vec::new();
    let mut uvs = Vec::new();
    for j in 0..=nv {
        for i in 0..=nu {
            let (u, v) = (i as f32 / nu as f32, j as f32 / nv as f32);
            let (p, n) = surface(u, v);
            data.positions.push(p.to_array());
            normals.push(n.to_array());
            uvs.push([u, v]);
        }
    }
    let index = |i: usize, j: usize| (j * (nu + 1) + i) as u32;
    for j in 0..nv {
        for i in 0..nu {
            let (a, b, c, d) = (index(i, j), index(i + 1, j), index(i + 1, j + 1), index(i, j + 1));
            for triangle in [[a, b, c], [a, c, d]] {
                push_facing(&mut data, triangle, &normals);
            }
        }
    }
    data.normals = Some(normals);
    data.uvs = Some(uvs);
    data
}

/// Adds a triangle wound to face its vertices' mean normal; drops one of zero area (a pole's
/// or a centre's collapsed corner).
fn push_facing(data: &mut MeshData, [a, b, c]: [u32; 3], normals: &[[f32; 3]]) {
    let p = |i: u32| Vec3::from(data.positions[i as usize]);
    let cross = (p(b) - p(a)).cross(p(c) - p(a));
    if cross.length_squared() <= 0.0 {
        return;
    }
    let mean: Vec3 = [a, b, c].iter().map(|&i| Vec3::from(normals[i as usize])).sum();
    data.indices.push(if cross.dot(mean) >= 0.0 { [a, b, c] } else { [a, c, b] });
}
