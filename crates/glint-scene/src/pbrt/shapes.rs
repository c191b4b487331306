//! pbrt's shapes that glint has no primitive for, made into triangle meshes at load: partial
//! spheres, disks, cylinders, bilinear patches and Loop subdivision surfaces.
//!
//! Quadrics are cut into a grid fine enough that the chord's sag stays below 0.1 % of the
//! radius (64 segments around a full turn); a bilinear patch is two triangles when flat and a
//! grid of up to 16 × 16 cells otherwise (fewer when there are many patches). Loop subdivision follows Loop's 1987 rules with the boundary
//! rules of Hoppe et al., then moves every vertex to its limit position, as pbrt does.

use std::collections::BTreeMap;
use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use crate::mesh::parametric::grid;
use crate::native::schema::MeshData;

/// Segments of a full turn.
const TURN_SEGMENTS: usize = 64;

fn segments(phi_max: f32) -> usize {
    ((TURN_SEGMENTS as f32 * phi_max / (2.0 * PI)).ceil() as usize).max(1)
}

/// pbrt's sphere between heights `z_min` and `z_max` and up to angle `phi_max` (radians).
pub fn partial_sphere(radius: f32, z_min: f32, z_max: f32, phi_max: f32) -> MeshData {
    let theta = |z: f32| (z / radius).clamp(-1.0, 1.0).acos();
    let (theta_min, theta_max) = (theta(z_min), theta(z_max));
    let rows = ((TURN_SEGMENTS as f32 / 2.0 * (theta_min - theta_max).abs() / PI).ceil() as usize).max(1);
    grid(segments(phi_max), rows, |u, v| {
        let (phi, theta) = (u * phi_max, theta_min + v * (theta_max - theta_min));
        let n = Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
        (radius * n, n)
    })
}

/// pbrt's disk: the plane z = `height` between radii `inner` and `radius`, facing +z.
pub fn disk(height: f32, radius: f32, inner: f32, phi_max: f32) -> MeshData {
    let mut data = grid(segments(phi_max), 1, |u, v| {
        let (phi, r) = (u * phi_max, radius - v * (radius - inner));
        (Vec3::new(r * phi.cos(), r * phi.sin(), height), Vec3::Z)
    });
    data.normals = None; // flat
    data
}

/// pbrt's cylinder: radius `radius` about the z axis from `z_min` to `z_max`, facing out,
/// without caps.
pub fn cylinder(radius: f32, z_min: f32, z_max: f32, phi_max: f32) -> MeshData {
    grid(segments(phi_max), 1, |u, v| {
        let phi = u * phi_max;
        let n = Vec3::new(phi.cos(), phi.sin(), 0.0);
        (radius * n + Vec3::Z * (z_min + v * (z_max - z_min)), n)
    })
}

/// One bilinear patch, corners p00, p10, p01, p11 (pbrt's order), with their uvs and, if
/// given, normals: p(u, v) = lerp(v, lerp(u, p00, p10), lerp(u, p01, p11)); a curved one is
/// cut into `cells` × `cells`.
pub fn bilinear_patch(corners: [Vec3; 4], uvs: [Vec2; 4], normals: Option<[Vec3; 4]>, cells: usize) -> MeshData {
    let [p00, p10, p01, p11] = corners;
    let lerp2 = |c: [Vec3; 4], u: f32, v: f32| (c[0].lerp(c[1], u)).lerp(c[2].lerp(c[3], u), v);
    let uv_at = |u: f32, v: f32| (uvs[0].lerp(uvs[1], u)).lerp(uvs[2].lerp(uvs[3], u), v);
    // Flat when the fourth corner lies in the plane of the other three.
    let plane = (p10 - p00).cross(p01 - p00);
    let size = (p10 - p00).length().max((p01 - p00).length()).max((p11 - p00).length());
    let flat = plane.length() > 0.0 && (p11 - p00).dot(plane.normalize()).abs() <= 1e-5 * size;
    let cells = if flat { 1 } else { cells.max(1) };
    let mut data = grid(cells, cells, |u, v| {
        let dpdu = (p10 - p00).lerp(p11 - p01, v);
        let dpdv = (p01 - p00).lerp(p11 - p10, u);
        let geometric = dpdu.cross(dpdv).normalize_or_zero();
        let n = normals.map_or(geometric, |ns| lerp2(ns, u, v).normalize_or_zero());
        (lerp2(corners, u, v), if n == Vec3::ZERO { geometric } else { n })
    });
    // The grid's own uv runs over [0, 1]²; the patch's come from its corners.
    if let Some(grid_uvs) = &mut data.uvs {
        for uv in grid_uvs.iter_mut() {
            *uv = uv_at(uv[0], uv[1]).to_array();
        }
    }
    // A flat patch keeps its plane's normal at its corners: a mesh of flat and curved
    // patches has a normal at every vertex, and ReverseOrientation turns them all.
    data
}

/// Appends `part` to `whole`.
pub fn append(whole: &mut MeshData, part: MeshData) {
    let base = whole.positions.len() as u32;
    let had = whole.positions.len();
    whole.positions.extend(part.positions);
    whole.indices.extend(part.indices.iter().map(|t| t.map(|i| i + base)));
    merge(&mut whole.normals, part.normals, had, whole.positions.len(), [0.0f32; 3]);
    merge(&mut whole.uvs, part.uvs, had, whole.positions.len(), [0.0f32; 2]);
}

/// Keeps a per-vertex array whole when one part has it and another not (the missing ones
/// zero; normals then are made from the faces where they are zero).
fn merge<T: Copy>(all: &mut Option<Vec<T>>, some: Option<Vec<T>>, had: usize, now: usize, default: T) {
    match (all.as_mut(), some) {
        (Some(a), Some(s)) => a.extend(s),
        (Some(a), None) => a.resize(now, default),
        (None, Some(s)) => {
            let mut a = vec![default; had];
            a.extend(s);
            *all = Some(a);
        }
        (None, None) => {}
    }
}

/// Loop subdivision of a triangle mesh, `levels` times, then every vertex moved to its limit
/// position. An edge shared by more than two triangles is refused.
pub fn loop_subdivide(positions: &[Vec3], triangles: &[[u32; 3]], levels: u32) -> Result<MeshData, String> {
    let mut positions = positions.to_vec();
    let mut triangles = triangles.to_vec();
    for _ in 0..levels {
        let topology = Topology::of(positions.len(), &triangles)?;
        // Even vertices: the old ones, smoothed.
        let mut next: Vec<Vec3> = (0..positions.len()).map(|v| topology.smoothed(v, &positions)).collect();
        // Odd vertices: one per edge.
        let mut edge_vertex = BTreeMap::new();
        for (&(a, b), opposite) in &topology.edges {
            let (pa, pb) = (positions[a as usize], positions[b as usize]);
            let p = match opposite.as_slice() {
                [c, d] => 0.375 * (pa + pb) + 0.125 * (positions[*c as usize] + positions[*d as usize]),
                _ => 0.5 * (pa + pb),
            };
            edge_vertex.insert((a, b), next.len() as u32);
            next.push(p);
        }
        let mid = |a: u32, b: u32| edge_vertex[&(a.min(b), a.max(b))];
        let mut finer = Vec::with_capacity(triangles.len() * 4);
        for &[a, b, c] in &triangles {
            let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
            finer.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        positions = next;
        triangles = finer;
    }
    let topology = Topology::of(positions.len(), &triangles)?;
    let limit: Vec<Vec3> = (0..positions.len()).map(|v| topology.limit(v, &positions)).collect();
    Ok(MeshData {
        positions: limit.iter().map(|p| p.to_array()).collect(),
        indices: triangles,
        normals: None,
        uvs: None,
        colors: None,
    })
}

/// Each edge's opposite vertices and each vertex's neighbours (for a boundary vertex, its
/// two boundary neighbours).
struct Topology {
    /// Ordered, so that vertices are numbered and sums taken the same way every run.
    edges: BTreeMap<(u32, u32), Vec<u32>>,
    neighbours: Vec<Vec<u32>>,
    boundary: Vec<Vec<u32>>,
}

impl Topology {
    fn of(vertices: usize, triangles: &[[u32; 3]]) -> Result<Self, String> {
        let mut edges: BTreeMap<(u32, u32), Vec<u32>> = BTreeMap::new();
        for &[a, b, c] in triangles {
            for (x, y, opposite) in [(a, b, c), (b, c, a), (c, a, b)] {
                let entry = edges.entry((x.min(y), x.max(y))).or_default();
                entry.push(opposite);
                if entry.len() > 2 {
                    return Err(format!(
                        "the edge between vertices {x} and {y} is shared by more than two triangles (Loop subdivision needs a manifold mesh)"
                    ));
                }
            }
        }
        let mut neighbours = vec![Vec::new(); vertices];
        let mut boundary = vec![Vec::new(); vertices];
        for (&(a, b), opposite) in &edges {
            neighbours[a as usize].push(b);
            neighbours[b as usize].push(a);
            if opposite.len() == 1 {
                boundary[a as usize].push(b);
                boundary[b as usize].push(a);
            }
        }
        Ok(Self { edges, neighbours, boundary })
    }

    /// Loop's β for a vertex of valence n.
    fn beta(n: usize) -> f32 {
        if n == 3 {
            3.0 / 16.0
        } else {
            3.0 / (8.0 * n as f32)
        }
    }

    fn smoothed(&self, v: usize, positions: &[Vec3]) -> Vec3 {
        let p = positions[v];
        match self.boundary[v].as_slice() {
            [a, b] => 0.75 * p + 0.125 * (positions[*a as usize] + positions[*b as usize]),
            [] if !self.neighbours[v].is_empty() => {
                let n = self.neighbours[v].len();
                let beta = Self::beta(n);
                let sum: Vec3 = self.neighbours[v].iter().map(|&u| positions[u as usize]).sum();
                (1.0 - n as f32 * beta) * p + beta * sum
            }
            _ => p, // a corner where boundaries meet, or an unused vertex: kept
        }
    }

    fn limit(&self, v: usize, positions: &[Vec3]) -> Vec3 {
        let p = positions[v];
        match self.boundary[v].as_slice() {
            [a, b] => 0.6 * p + 0.2 * (positions[*a as usize] + positions[*b as usize]),
            [] if !self.neighbours[v].is_empty() => {
                let n = self.neighbours[v].len();
                let gamma = 1.0 / (n as f32 + 3.0 / (8.0 * Self::beta(n)));
                let sum: Vec3 = self.neighbours[v].iter().map(|&u| positions[u as usize]).sum();
                (1.0 - n as f32 * gamma) * p + gamma * sum
            }
            _ => p,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area_and_volume(data: &MeshData) -> (f32, f32) {
        let p = |i: u32| Vec3::from(data.positions[i as usize]);
        data.indices.iter().fold((0.0, 0.0), |(area, volume), &[a, b, c]| {
            let cross = (p(b) - p(a)).cross(p(c) - p(a));
            (area + 0.5 * cross.length(), volume + p(a).dot(p(b).cross(p(c))) / 6.0)
        })
    }

    #[test]
    fn quadrics_have_their_area_and_face_out() {
        let tolerance = 2e-3; // a 64-gon's area is 0.16 % short of the circle's
        let (area, _) = area_and_volume(&disk(1.0, 2.0, 1.0, 2.0 * PI));
        assert!((area / (PI * 3.0) - 1.0).abs() < tolerance, "{area}");
        let d = disk(0.0, 1.0, 0.0, PI);
        let (area, _) = area_and_volume(&d);
        assert!((area / (PI / 2.0) - 1.0).abs() < tolerance, "half disk {area}");
        let p = |i: u32| Vec3::from(d.positions[i as usize]);
        assert!(d.indices.iter().all(|&[a, b, c]| (p(b) - p(a)).cross(p(c) - p(a)).z > 0.0));
        let (area, _) = area_and_volume(&cylinder(2.0, -1.0, 2.0, 2.0 * PI));
        assert!((area / (2.0 * PI * 2.0 * 3.0) - 1.0).abs() < tolerance, "{area}");
        // A closed sphere, wound outward, encloses (nearly) 4/3 π r³.
        let (area, volume) = area_and_volume(&partial_sphere(2.0, -2.0, 2.0, 2.0 * PI));
        assert!((area / (16.0 * PI) - 1.0).abs() < 4e-3, "{area}");
        assert!((volume / (32.0 / 3.0 * PI) - 1.0).abs() < 6e-3, "{volume}");
        // The upper half: area 2π r².
        let (area, _) = area_and_volume(&partial_sphere(1.0, 0.0, 1.0, 2.0 * PI));
        assert!((area / (2.0 * PI) - 1.0).abs() < 4e-3, "{area}");
    }

    #[test]
    fn a_flat_patch_is_two_triangles_and_a_twisted_one_a_saddle() {
        let uv = [Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::ONE];
        let flat = bilinear_patch([Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)], uv, None, 16);
        assert_eq!(flat.indices.len(), 2);
        assert_eq!(area_and_volume(&flat).0, 1.0);
        // z = u·v over the unit square: the hyperbolic paraboloid, its middle at height ¼.
        let saddle = bilinear_patch([Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::ONE], uv, None, 16);
        assert_eq!(saddle.indices.len(), 2 * 16 * 16);
        let centre = saddle.positions.iter().find(|p| p[0] == 0.5 && p[1] == 0.5).unwrap();
        assert_eq!(centre[2], 0.25);
        // Its normals face +z, as pbrt's dp/du × dp/dv does.
        assert!(saddle.normals.unwrap().iter().all(|n| n[2] > 0.0));
    }

    #[test]
    fn loop_subdivision_of_a_tetrahedron_shrinks_it_toward_a_smooth_blob() {
        let p = [
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(1.0, -1.0, -1.0),
            Vec3::new(-1.0, 1.0, -1.0),
            Vec3::new(-1.0, -1.0, 1.0),
        ];
        let t = [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]];
        let once = loop_subdivide(&p, &t, 1).unwrap();
        assert_eq!((once.positions.len(), once.indices.len()), (10, 16));
        let thrice = loop_subdivide(&p, &t, 3).unwrap();
        assert_eq!(thrice.indices.len(), 4 * 64);
        // Convex hull property: every limit point lies inside the tetrahedron's bounding
        // sphere and the shape keeps its symmetry (centroid at the origin).
        let centroid: Vec3 =
            thrice.positions.iter().map(|&q| Vec3::from(q)).sum::<Vec3>() / thrice.positions.len() as f32;
        assert!(centroid.length() < 1e-5, "{centroid}");
        assert!(thrice.positions.iter().all(|&q| Vec3::from(q).length() < 3f32.sqrt()));
        // By hand: the corner (1,1,1), valence 3 (β = 3/16), smooths to 7/16·(1,1,1) +
        // 3/16·(−1,−1,−1) = (¼,¼,¼); its edges' new vertices are 3/8·(p0 + p1) + 1/8·(p2 + p3)
        // = (½,0,0), (0,½,0), (0,0,½); at the limit (γ = 1/(3 + 3/(8β)) = 1/5) it is
        // (1 − 3/5)·(¼,¼,¼) + 1/5·(½,½,½) = (0.2, 0.2, 0.2).
        assert!((Vec3::from(once.positions[0]) - Vec3::splat(0.2)).length() < 1e-6, "{:?}", once.positions[0]);
        let flat = loop_subdivide(&[Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 2]], 2).unwrap();
        // A single triangle is all boundary: it stays in its plane.
        assert!(flat.positions.iter().all(|q| q[2] == 0.0));
        let bad =
            loop_subdivide(&[Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z, Vec3::ONE], &[[0, 1, 2], [0, 1, 3], [0, 1, 4]], 1);
        assert!(bad.unwrap_err().contains("more than two"));
    }
}
