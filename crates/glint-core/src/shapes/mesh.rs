//! Triangle mesh: shared vertex arrays and index triples, each triangle a primitive of its own
//! for the acceleration structure. Loaded from OBJ or PLY by the scene reader.
//!
//! Scene parameters: `file` (path relative to the scene file, `.obj`, `.ply` or `.ply.gz`),
//! `smooth` (bool, default true: interpolate the file's vertex normals where it has them).
//! ```toml
//! [[shapes]]
//! type = "mesh"
//! file = "meshes/torus.obj"
//! material = "gold"
//! ```

use glam::{Vec2, Vec3};

use super::triangle::{
    intersect_cramer, intersect_moller_trumbore, triangle_surface, triangle_tangents, WatertightRay,
};
use super::{PrimHit, SurfaceGeometry, TriangleMethod};
use crate::geometry::{Aabb, Ray, Transform};

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    /// Per-vertex normals, same length as `positions`, if the file had them.
    pub normals: Option<Vec<Vec3>>,
    /// Per-vertex texture coordinates, same length as `positions`, if the file had them.
    pub uvs: Option<Vec<Vec2>>,
    pub indices: Vec<[u32; 3]>,
    /// The transform baked into the vertices, kept to map hit points back to the mesh's own
    /// space for solid textures (boxed: a shape stays small).
    pub baked_transform: Option<Box<Transform>>,
    /// Other values the file gives per vertex or per face (colours, weights), for
    /// `mesh-attribute` textures.
    pub attributes: Vec<MeshAttribute>,
}

/// Values a mesh carries per vertex or per face beside positions, normals and uvs (a PLY
/// file's other properties: Mitsuba's mesh attributes).
#[derive(Clone, Debug, PartialEq)]
pub struct MeshAttribute {
    /// `vertex_NAME` or `face_NAME`, as Mitsuba names them (`vertex_color`, `face_weight`).
    pub name: String,
    /// Values per element, `dim` each (1 to 4): per vertex, or per triangle (a polygon cut
    /// into a fan repeats its face's values).
    pub values: Vec<f32>,
    pub dim: usize,
    pub per_vertex: bool,
}

impl MeshAttribute {
    /// Element `i`'s value as a colour: three channels as they are, one spread over all three
    /// (the first three of four; two and a zero).
    fn colour(&self, i: usize) -> Vec3 {
        let v = &self.values[i * self.dim..(i + 1) * self.dim];
        match *v {
            [x] => Vec3::splat(x),
            [x, y] => Vec3::new(x, y, 0.0),
            [x, y, z, ..] => Vec3::new(x, y, z),
            [] => Vec3::ZERO,
        }
    }
}

impl Mesh {
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    #[inline]
    pub fn triangle_vertices(&self, i: usize) -> [Vec3; 3] {
        // Spelled out: `array::map` compiled to a loop with its counter kept in memory.
        let [a, b, c] = self.indices[i];
        [self.positions[a as usize], self.positions[b as usize], self.positions[c as usize]]
    }

    pub fn triangle_bounds(&self, i: usize) -> Aabb {
        Aabb::from_points(self.triangle_vertices(i))
    }

    /// Indices of triangles with zero area; they can never be hit.
    /// The volume the mesh encloses if it is a closed, consistently wound surface (every edge,
    /// its ends found by position so split seams count as joined, met once in each direction
    /// by the triangles that share it): positive if the winding faces out, negative if in.
    /// `None` if it has a border, an edge with more than two triangles, or triangles wound
    /// against their neighbours: a surface that bounds no solid (CSG refuses it).
    pub fn enclosed_volume(&self) -> Option<f64> {
        use std::collections::HashMap;
        if self.indices.is_empty() {
            return None;
        }
        let mut ids: HashMap<[u32; 3], u32> = HashMap::with_capacity(self.positions.len());
        let welded: Vec<u32> = self
            .positions
            .iter()
            .map(|p| {
                let next = ids.len() as u32;
                // + 0.0 turns −0 into +0: a seam written as "-0.000000" on one side is joined.
                *ids.entry(p.to_array().map(|x| (x + 0.0).to_bits())).or_insert(next)
            })
            .collect();
        // Each directed edge once: its reverse must then be there exactly once too.
        let mut edges: HashMap<(u32, u32), u32> = HashMap::with_capacity(3 * self.indices.len());
        for tri in &self.indices {
            let [a, b, c] = tri.map(|i| welded[i as usize]);
            if a == b || b == c || c == a {
                continue; // collapsed to an edge or a point: no area, no boundary
            }
            for edge in [(a, b), (b, c), (c, a)] {
                *edges.entry(edge).or_default() += 1;
            }
        }
        let paired = edges.iter().all(|(&(a, b), &n)| n == 1 && edges.get(&(b, a)) == Some(&1));
        if !paired {
            return None;
        }
        // The divergence theorem: the sum of the signed tetrahedra from the origin.
        let volume = (0..self.triangle_count())
            .map(|i| {
                let [a, b, c] = self.triangle_vertices(i).map(|p| p.as_dvec3());
                a.dot(b.cross(c)) / 6.0
            })
            .sum();
        Some(volume)
    }

    pub fn degenerate_triangles(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.triangle_count()).filter(|&i| {
            let [a, b, c] = self.triangle_vertices(i);
            (b - a).cross(c - a).length_squared() == 0.0
        })
    }

    #[inline]
    pub fn intersect(&self, i: usize, ray: &Ray, method: TriangleMethod) -> Option<PrimHit> {
        let [a, b, c] = self.triangle_vertices(i);
        match method {
            TriangleMethod::Cramer => intersect_cramer(a, b, c, ray),
            TriangleMethod::MollerTrumbore => intersect_moller_trumbore(a, b, c, ray),
            TriangleMethod::Watertight => WatertightRay::new(ray).intersect(a, b, c, ray),
        }
    }

    #[inline]
    pub fn surface(&self, i: usize, hit: &PrimHit) -> SurfaceGeometry {
        triangle_surface(self.triangle_vertices(i), self.triangle_normals(i), self.triangle_uvs(i), hit)
    }

    /// (∂p/∂u, ∂p/∂v) of triangle `i`.
    pub fn tangents(&self, i: usize) -> (Vec3, Vec3) {
        triangle_tangents(self.triangle_vertices(i), self.triangle_uvs(i))
    }

    /// Smooth vertex normals for a mesh whose file gave none, as Mitsuba makes them: each
    /// face's normal added to its corners weighted by the face's angle there (Thürmer and
    /// Wüthrich 1998), then normalised. Degenerate faces add nothing; a vertex no face
    /// reaches gets +z.
    pub fn compute_vertex_normals(&mut self) {
        let mut normals = vec![Vec3::ZERO; self.positions.len()];
        for i in 0..self.indices.len() {
            let corners = self.triangle_vertices(i);
            let Some(face) = (corners[1] - corners[0]).cross(corners[2] - corners[0]).try_normalize() else { continue };
            for k in 0..3 {
                let (a, b, c) = (corners[k], corners[(k + 1) % 3], corners[(k + 2) % 3]);
                let (Some(d0), Some(d1)) = ((b - a).try_normalize(), (c - a).try_normalize()) else { continue };
                normals[self.indices[i][k] as usize] += face * d0.dot(d1).clamp(-1.0, 1.0).acos();
            }
        }
        self.normals = Some(normals.into_iter().map(|n| n.normalize_or(Vec3::Z)).collect());
    }

    /// Attribute `name` on triangle `i` at barycentric coordinates `(u, v)` (of its second and
    /// third corners): a vertex attribute interpolated, a face attribute as it is; `None` if
    /// the mesh has no such attribute.
    pub fn attribute(&self, name: &str, i: usize, barycentrics: Vec2) -> Option<Vec3> {
        let attribute = self.attributes.iter().find(|a| a.name == name)?;
        if !attribute.per_vertex {
            return Some(attribute.colour(i));
        }
        let [a, b, c] = self.indices[i].map(|k| attribute.colour(k as usize));
        let (u, v) = (barycentrics.x, barycentrics.y);
        Some((1.0 - u - v) * a + u * b + v * c)
    }

    fn triangle_uvs(&self, i: usize) -> Option<[Vec2; 3]> {
        self.uvs.as_ref().map(|t| self.indices[i].map(|k| t[k as usize]))
    }

    /// The vertex normals of triangle `i`, if the mesh has them.
    #[inline]
    pub fn triangle_normals(&self, i: usize) -> Option<[Vec3; 3]> {
        self.normals.as_ref().map(|n| self.indices[i].map(|k| n[k as usize]))
    }

    /// Bakes a transform into the vertices (meshes are stored in world space so the
    /// acceleration structure sees their triangles directly). A mirroring transform reverses
    /// the winding so that geometric normals keep facing the same way relative to the surface.
    /// A world-space point in the mesh's own (file) space.
    pub fn object_point(&self, p: Vec3) -> Vec3 {
        self.baked_transform.as_ref().map_or(p, |t| t.to_object.transform_point3(p))
    }

    pub fn transform(&mut self, t: &Transform) {
        self.baked_transform = Some(Box::new(self.baked_transform.as_ref().map_or(*t, |b| t.after(b))));
        for p in &mut self.positions {
            *p = t.point(*p);
        }
        if let Some(normals) = &mut self.normals {
            for n in normals {
                *n = t.normal(*n);
            }
        }
        if t.flips_handedness() {
            for tri in &mut self.indices {
                tri.swap(1, 2);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Angle-weighted normals by hand, checked against Mitsuba 3.9's for a pyramid of four
    /// faces: at the corner where three faces meet at right angles, the diagonal.
    #[test]
    fn computed_vertex_normals_weigh_faces_by_their_angles_as_mitsuba_does() {
        let positions = vec![Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 0.0, 3.0)];
        let indices = vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
        let mut mesh = Mesh { positions, indices, ..Mesh::default() };
        mesh.compute_vertex_normals();
        // In the order of `positions` (Mitsuba's OBJ reader numbers vertices as faces first
        // use them, so its second and third are swapped).
        let mitsuba = [
            Vec3::new(-0.577_350_26, -0.577_350_26, -0.577_350_26),
            Vec3::new(0.927_008_33, -0.167_379_47, -0.335_618_23),
            Vec3::new(-0.411_490_08, 0.791_601_1, -0.451_711_86),
            Vec3::new(-0.198_251_93, -0.110_320_61, 0.973_922_8),
        ];
        for (n, m) in mesh.normals.unwrap().iter().zip(mitsuba) {
            assert!((*n - m).length() < 1e-5, "{n} vs {m}");
        }
    }
}
