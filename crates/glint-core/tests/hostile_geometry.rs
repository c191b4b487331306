//! No ray leaks through hostile geometry: tiny objects seen from afar, objects far from the
//! origin, needles and slivers, and rays through the exact vertices of a flat grid. Each ray
//! here passes through the interior of a closed mesh or of a triangle (or exactly through a
//! shared vertex of a watertight sheet), so it must hit, by the BVH and by brute force alike,
//! and at the right distance. (The t error bound had rejected most hits on small, far and
//! thin triangles, and on scaled ones near the origin; the node test, not conservative, culled
//! leaves of zero thickness.)
//! `benchmarks/hostile_meshes.py` measures the same families against Embree.

mod common;

use common::{object, scene, TestRng};
use glint_core::geometry::Ray;
use glint_core::scene::Scene;
use glint_core::shapes::{Mesh, Shape};
use glint_core::Vec3;

/// An icosphere of `radius` about `centre`, subdivided `levels` times: closed, its shared
/// vertices bit-identical.
fn icosphere(centre: Vec3, radius: f32, levels: u32) -> Mesh {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut positions: Vec<Vec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut faces: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut midpoints = std::collections::HashMap::new();
        let mut midpoint = |a: u32, b: u32, positions: &mut Vec<Vec3>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                positions.push(((positions[a as usize] + positions[b as usize]) * 0.5).normalize());
                positions.len() as u32 - 1
            })
        };
        faces = faces
            .iter()
            .flat_map(|&[a, b, c]| {
                let (ab, bc, ca) =
                    (midpoint(a, b, &mut positions), midpoint(b, c, &mut positions), midpoint(c, a, &mut positions));
                [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
            })
            .collect();
    }
    let positions = positions.iter().map(|p| centre + radius * *p).collect();
    Mesh { positions, indices: faces, ..Default::default() }
}

fn mesh_scene(mesh: Mesh) -> Scene {
    scene(vec![object(Shape::Mesh(mesh))])
}

/// Both queries hit, at the same distance (to the bit on the same triangle; a ray through a
/// shared edge or vertex may name either triangle), within `tolerance` (relative) of
/// `expected_t` if given.
fn assert_hits(scene: &Scene, ray: &Ray, expected_t: Option<f32>, tolerance: f32, what: &str) {
    let fast = scene.intersect(ray).unwrap_or_else(|| panic!("{what}: the BVH missed {ray:?}"));
    let brute = scene.intersect_brute_force(ray).unwrap_or_else(|| panic!("{what}: brute force missed {ray:?}"));
    if fast.prim == brute.prim {
        assert_eq!(fast.t, brute.t, "{what}: {ray:?}");
    } else {
        assert!(((fast.t - brute.t) / brute.t).abs() < 1e-5, "{what}: {} vs {}, {ray:?}", fast.t, brute.t);
    }
    if let Some(t) = expected_t {
        assert!(((fast.t - t) / t).abs() < tolerance, "{what}: t = {} for {t}, {ray:?}", fast.t);
    }
}

#[test]
fn rays_into_a_tiny_blob_from_afar_hit_its_front() {
    let radius = 1e-4;
    let blob = mesh_scene(icosphere(Vec3::ZERO, radius, 3));
    let mut rng = TestRng(3);
    for _ in 0..4000 {
        let origin = rng.vec3(-1.0, 1.0).normalize();
        // Aimed within half the radius of the centre: through the front face, well inside.
        let target = rng.vec3(-0.5, 0.5) * radius;
        let ray = Ray::new(origin, (target - origin).normalize());
        assert_hits(&blob, &ray, None, 0.0, "tiny blob");
        let hit = blob.intersect(&ray).unwrap();
        assert!(hit.geometry.geometric_normal.dot(ray.direction) < 0.0, "a back face: the front leaked");
    }
}

/// A floor 2000 wide made of a unit quad under a scale of 1000 (how Mitsuba's rectangles and
/// instances arrive), seen from 1 above: every ray down to it hits, in both queries, the
/// transformed object's and the same quad's baked into world space. (The t error bound, mixing
/// the sheared lengths with distances in the scaled ray's units, had dropped hits in an X
/// through the point below the eye.)
#[test]
fn rays_from_near_a_scaled_floor_hit_it() {
    use glint_core::geometry::Transform;
    let quad = Mesh {
        positions: vec![
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
        ],
        indices: vec![[0, 1, 2], [0, 2, 3]],
        ..Default::default()
    };
    let scale = Transform::from_matrix(glam::Mat4::from_scale(Vec3::splat(1000.0))).unwrap();
    let mut scaled = object(Shape::Mesh(quad.clone()));
    scaled.transform = Some(scale);
    let mut baked = quad;
    baked.transform(&scale);
    let eye = Vec3::new(0.0, 0.0, 1.0);
    let mut rng = TestRng(9);
    for floor in [scene(vec![scaled]), mesh_scene(baked)] {
        for _ in 0..4000 {
            let target = rng.vec3(-20.0, 20.0) * Vec3::new(1.0, 1.0, 0.0);
            let ray = Ray::new(eye, (target - eye).normalize());
            assert_hits(&floor, &ray, Some((target - eye).length()), 1e-4, "scaled floor");
        }
    }
}

#[test]
fn rays_from_the_origin_hit_a_blob_far_from_it() {
    let centre = Vec3::new(1e5, -2e5, 3e5);
    let blob = mesh_scene(icosphere(centre, 25.0, 3));
    let mut rng = TestRng(4);
    for _ in 0..4000 {
        let target = centre + rng.vec3(-12.0, 12.0);
        let ray = Ray::new(Vec3::ZERO, target.normalize());
        assert_hits(&blob, &ray, None, 0.0, "far blob");
    }
}

/// The distance at which `ray` meets the plane of a triangle, by Cramer's rule on the
/// triangle's edges in f64 (where differences of f32 are exact): the reference for the
/// distances the f32 tests report.
fn distance_in_f64([a, b, c]: [Vec3; 3], ray: &Ray) -> Option<f64> {
    let [a, b, c, origin, direction] = [a, b, c, ray.origin, ray.direction].map(|p| p.as_dvec3());
    let (edge1, edge2, to_origin) = (b - a, c - a, origin - a);
    let det = direction.cross(edge2).dot(edge1);
    (det != 0.0).then(|| to_origin.cross(edge1).dot(edge2) / det)
}

#[test]
fn rays_aimed_inside_needles_and_slivers_hit_them_at_the_right_distance() {
    let mut rng = TestRng(5);
    // At several scales and off the origin too: the test's error bounds are relative, so is
    // the answer. (The offset stays small enough that 1e-5 is still 40 ulps of it: farther
    // out, the needle's width is no longer representable.)
    let placements = [(1.0f32, Vec3::ZERO), (1e-3, Vec3::ZERO), (1e3, Vec3::ZERO), (1.0, Vec3::new(3.0, -2.0, 1.5))];
    for (width, (scale, offset)) in [1e-3f32, 1e-4, 1e-5].into_iter().flat_map(|w| placements.map(|p| (w, p))) {
        // A needle from x = 0 to 1, two triangles, in the plane z = 0 (exact coordinates) and
        // turned at random (rounded ones), seen from 2.5 in front of it.
        for turned in [false, true] {
            let rotation = if turned {
                glam::Quat::from_axis_angle(rng.vec3(-1.0, 1.0).normalize(), rng.range(0.3, 3.0))
            } else {
                glam::Quat::IDENTITY
            };
            let local = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, width, 0.0), Vec3::new(0.0, width, 0.0)];
            let place = |p: Vec3| offset + scale * (rotation * p);
            let positions: Vec<Vec3> = local.iter().map(|p| place(*p)).collect();
            let indices = vec![[0, 1, 2], [0, 2, 3]];
            let corners = |prim: u32| indices[prim as usize].map(|i: u32| positions[i as usize]);
            let needle =
                mesh_scene(Mesh { positions: positions.clone(), indices: indices.clone(), ..Default::default() });
            for _ in 0..250 {
                let local_target = Vec3::new(rng.range(0.05, 0.95), width * rng.range(0.25, 0.75), 0.0);
                let target = place(local_target);
                let origin = place(local_target + Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), -2.5));
                let ray = Ray::new(origin, (target - origin).normalize());
                let t = (target - origin).length();
                let what = format!("needle {width}, turned {turned}, scale {scale}, offset {offset}");
                assert_hits(&needle, &ray, Some(t), 1e-3, &what);
                // On the triangle it names, the hit's distance is the f64 answer to the f32
                // rounding (Embree's robust mode's accuracy; the edge functions' own distance
                // was up to 4e-4 off on the needles 1e-5 wide).
                let hit = needle.intersect(&ray).unwrap();
                let exact = distance_in_f64(corners(hit.prim), &ray).unwrap();
                let error = (hit.t as f64 - exact).abs() / exact;
                assert!(error < 3e-7, "{what}: t = {} for {exact} (relative error {error:.1e}), {ray:?}", hit.t);
            }
        }
    }
    // Slivers: a base of 0.1 under a height of 1e-4 to 1e-2, hit in their middles.
    for height in [1e-4f32, 1e-3, 1e-2] {
        let positions = vec![Vec3::ZERO, Vec3::new(0.1, 0.0, 0.0), Vec3::new(0.05, height, 0.0)];
        let cap = mesh_scene(Mesh { positions, indices: vec![[0, 1, 2]], ..Default::default() });
        for _ in 0..500 {
            let target = Vec3::new(0.05 + rng.range(-0.01, 0.01), height * rng.range(0.3, 0.5), 0.0);
            let origin = target + Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), -2.5);
            let ray = Ray::new(origin, (target - origin).normalize());
            assert_hits(&cap, &ray, Some((target - origin).length()), 1e-4, &format!("cap {height}"));
            let exact = distance_in_f64([Vec3::ZERO, Vec3::new(0.1, 0.0, 0.0), Vec3::new(0.05, height, 0.0)], &ray);
            let t = cap.intersect(&ray).unwrap().t as f64;
            assert!((t - exact.unwrap()).abs() < 3e-7 * t, "cap {height}: t = {t} for {exact:?}");
        }
    }
}

#[test]
fn rays_through_the_vertices_of_a_flat_grid_hit_it() {
    // A 16 × 16 grid of squares of side 1/16, two triangles each, in z = 0: every coordinate
    // exact, so a ray aimed at a vertex goes exactly through it, where six triangles meet.
    let n = 16u32;
    let positions: Vec<Vec3> =
        (0..=n).flat_map(|j| (0..=n).map(move |i| Vec3::new(i as f32 / 16.0, j as f32 / 16.0, 0.0))).collect();
    let index = |i: u32, j: u32| j * (n + 1) + i;
    let indices: Vec<[u32; 3]> = (0..n)
        .flat_map(|j| {
            (0..n).flat_map(move |i| {
                [
                    [index(i, j), index(i + 1, j), index(i + 1, j + 1)],
                    [index(i, j), index(i + 1, j + 1), index(i, j + 1)],
                ]
            })
        })
        .collect();
    let mut rng = TestRng(6);
    // Scales by powers of two and whole offsets keep every coordinate exact.
    for (scale, offset) in
        [(1.0f32, Vec3::ZERO), (1.0 / 1024.0, Vec3::ZERO), (1024.0, Vec3::ZERO), (1.0, Vec3::new(4096.0, -256.0, 64.0))]
    {
        let placed = positions.iter().map(|p| offset + scale * *p).collect();
        let grid = mesh_scene(Mesh { positions: placed, indices: indices.clone(), ..Default::default() });
        for _ in 0..1000 {
            let (i, j) = (1 + rng.below(n as u64 - 1), 1 + rng.below(n as u64 - 1));
            let vertex = Vec3::new(i as f32 / 16.0, j as f32 / 16.0, 0.0);
            // Edge midpoints too: exact in f32 as well.
            let target = if rng.below(2) == 0 { vertex } else { vertex + Vec3::new(1.0 / 32.0, 0.0, 0.0) };
            let origin = target + Vec3::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), rng.range(-3.0, -0.5));
            let ray = Ray::new(offset + scale * origin, scale * (target - origin));
            assert_hits(&grid, &ray, Some(1.0), 1e-4, &format!("grid vertex, scale {scale}, offset {offset}"));
        }
    }
}

/// Watertight: a ray from outside through a closed mesh's vertex, or through a point on one
/// of its edges (within the rounding of that point), hits one of the faces there, at every
/// scale and offset.
#[test]
fn rays_through_a_closed_meshs_edges_and_vertices_hit_it() {
    let mut rng = TestRng(7);
    for (radius, centre) in
        [(1.0f32, Vec3::ZERO), (1e-4, Vec3::ZERO), (1e3, Vec3::ZERO), (25.0, Vec3::new(1e3, -2e3, 3e3))]
    {
        let mesh = icosphere(centre, radius, 2);
        let (positions, indices) = (mesh.positions.clone(), mesh.indices.clone());
        let blob = mesh_scene(mesh);
        for _ in 0..2000 {
            let [a, b, _] = indices[rng.below(indices.len() as u64) as usize];
            let (a, b) = (positions[a as usize], positions[b as usize]);
            let target = if rng.below(2) == 0 { a } else { a + rng.range(0.0, 1.0) * (b - a) };
            // From outside, within 30° of the outward direction there, so the ray enters the
            // blob there (the faces around a vertex are within 10° of it), never grazing it.
            let out = (target - centre).normalize() + 0.5 * rng.vec3(-1.0, 1.0).normalize_or_zero();
            let origin = target + 3.0 * radius * out.normalize();
            let ray = Ray::new(origin, (target - origin).normalize());
            assert_hits(&blob, &ray, None, 0.0, &format!("edge or vertex of a blob of radius {radius}"));
        }
    }
}

/// A closed mirror box turned, stretched and moved by a transform: rays from inside aimed at
/// its edges and corners, reflected fifty times off whatever they hit, never leave it. (The
/// edge margin in the box's own space had not covered the transform's round trip.)
#[test]
fn mirror_rays_stay_inside_a_transformed_box() {
    use glint_core::geometry::{reflect, Transform};
    use glint_core::shapes::AaBox;
    let mut rng = TestRng(8);
    // Turned at three scales, then stretched unevenly far from the origin.
    let placements = [
        (1e-3f32, Vec3::splat(1.0), 3.0),
        (1.0, Vec3::splat(1.0), 3.0),
        (1e3, Vec3::splat(1.0), 3.0),
        (1.0, Vec3::new(1.0, 0.3, 2.0), 1e4),
    ];
    for (scale, stretch, distance) in placements {
        let matrix = glam::Mat4::from_translation(Vec3::new(1.0, -0.7, 0.3) * distance * scale)
            * glam::Mat4::from_quat(glam::Quat::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 0.7))
            * glam::Mat4::from_scale(stretch * scale);
        let mut o = object(Shape::AaBox(AaBox::new(Vec3::splat(-2.0), Vec3::splat(2.0))));
        o.transform = Transform::from_matrix(matrix);
        let s = scene(vec![o]);
        for i in 0..500 {
            let mut corner = rng.vec3(-2.0, 2.0);
            for k in 0..2 + i % 2 {
                corner[(i + k) % 3] = if rng.below(2) == 0 { -2.0 } else { 2.0 };
            }
            let origin = matrix.transform_point3(rng.vec3(-1.5, 1.5));
            let mut ray = Ray::new(origin, matrix.transform_point3(corner) - origin);
            for bounce in 0..50 {
                let hit =
                    s.intersect(&ray).unwrap_or_else(|| panic!("scale {scale}: left the box after {bounce} bounces"));
                ray = hit.spawn_ray(reflect(ray.direction, hit.geometry.geometric_normal));
            }
        }
    }
}
