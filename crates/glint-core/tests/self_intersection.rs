//! A ray spawned from a hit must never hit the surface it leaves (pbrt-v4's re-intersection
//! test), at every scene scale: flat shapes are never hit again, convex shapes only on their
//! far side when the ray goes inward.

mod common;

use common::{object, scene, TestRng};
use glam::{Mat4, Quat};
use glint_core::geometry::{Ray, Transform};
use glint_core::scene::Scene;
use glint_core::shapes::{AaBox, Csg, CsgOperation, CsgSolid, CsgTree, Mesh, Plane, Polygon, Shape, Sphere, Triangle};
use glint_core::Vec3;

/// (shape, transform, convex, a point to aim at)
type Case = (Shape, Option<Transform>, bool, Vec3);

fn shapes(rng: &mut TestRng, scale: f32) -> Vec<Case> {
    let c = rng.vec3(-1.0, 1.0) * scale + Vec3::splat(3.0 * scale);
    let r = rng.range(0.2, 1.0) * scale;
    let tri = Triangle::new(c, c + rng.vec3(-1.0, 1.0) * scale, c + rng.vec3(-1.0, 1.0) * scale);
    let (s, t) = glint_core::geometry::orthonormal_basis(rng.vec3(-1.0, 1.0).normalize_or(Vec3::Y));
    let quad = Polygon::new(vec![c - s * r - t * r, c + s * r - t * r, c + s * r + t * r, c - s * r + t * r]).unwrap();
    let ellipsoid = Transform::from_matrix(
        Mat4::from_translation(c)
            * Mat4::from_quat(Quat::from_axis_angle(rng.vec3(-1.0, 1.0).normalize_or(Vec3::X), rng.range(0.0, 3.0)))
            * Mat4::from_scale(Vec3::new(1.0, 0.5, 2.0)),
    );
    // The Cornell box's green wall: a large quad of two coplanar triangles in the plane x = 0
    // exactly, so hit points have no error across the plane and spawned rays start on it.
    let wall = [[0.0f32, 0.0, 559.2], [0.0, 0.0, 0.0], [0.0, 548.8, 0.0], [0.0, 548.8, 559.2]]
        .map(|p| Vec3::from(p) * (scale / 300.0));
    let wall_centre = Vec3::new(0.0, 274.4, 279.6) * (scale / 300.0);
    let wall = Mesh { positions: wall.to_vec(), indices: vec![[0, 1, 2], [0, 2, 3]], ..Default::default() };
    // Convex CSG: a lens of two balls, and a turned cube with its corners cut by a ball.
    let ball = |centre: Vec3, radius: f32| CsgTree::solid(Shape::Sphere(Sphere::new(centre, radius)));
    let lens = [ball(c - 0.6 * r * s, r), ball(c + 0.6 * r * s, r)];
    let lens = Csg::new(CsgTree::Combine(CsgOperation::Intersection, lens.into())).unwrap();
    let mut cube = CsgSolid::new(Shape::AaBox(AaBox::new(c - Vec3::splat(r), c + Vec3::splat(r))));
    let turn = Quat::from_axis_angle(rng.vec3(-1.0, 1.0).normalize_or(Vec3::X), rng.range(0.0, 3.0));
    cube.transform =
        Transform::from_matrix(Mat4::from_translation(c) * Mat4::from_quat(turn) * Mat4::from_translation(-c));
    let rounded = [CsgTree::Solid(Box::new(cube)), ball(c, 1.4 * r)];
    let rounded = Csg::new(CsgTree::Combine(CsgOperation::Intersection, rounded.into())).unwrap();
    let shapes = vec![
        (Shape::Csg(Box::new(lens)), None, true, c),
        (Shape::Csg(Box::new(rounded)), None, true, c),
        (Shape::Mesh(wall), None, false, wall_centre),
        (Shape::Sphere(Sphere::new(c, r)), None, true, c),
        (Shape::Sphere(Sphere::new(Vec3::ZERO, r)), ellipsoid, true, c),
        (Shape::AaBox(AaBox::new(c - Vec3::splat(r), c + Vec3::splat(r))), None, true, c),
        (Shape::Triangle(tri), None, false, c),
        (Shape::Polygon(quad), None, false, c),
        (Shape::Plane(Plane::through_point(s.cross(t), c)), None, false, c),
    ];
    shapes
}

fn check(scene: &Scene, target: Vec3, rng: &mut TestRng, convex: bool, scale: f32) -> usize {
    let mut checked = 0;
    for _ in 0..200 {
        let origin = target + rng.vec3(-1.0, 1.0).normalize_or(Vec3::X) * 10.0 * scale;
        let aim = target + rng.vec3(-0.5, 0.5) * scale;
        let Some(hit) = scene.intersect(&Ray::new(origin, aim - origin)) else { continue };
        checked += 1;
        let n = hit.geometry.geometric_normal;
        for _ in 0..20 {
            let mut d = rng.vec3(-1.0, 1.0).normalize_or(Vec3::Y);
            if d.dot(n).abs() < 1e-3 {
                continue;
            }
            let outward = d.dot(n) > 0.0;
            // Leave on each side in turn.
            for flip in [false, true] {
                if flip {
                    d = -d;
                }
                let spawned = hit.spawn_ray(d);
                let again = scene.intersect(&spawned);
                let leaving = outward != flip;
                match again {
                    None => {}
                    // Near a CSG node's seam (a lens's rim) the next surface inward is another
                    // solid's, legitimately close.
                    Some(h) if convex && !leaving && h.prim != hit.prim => {}
                    Some(h) if convex && !leaving => {
                        // Going inward hits the far side, never the starting point again (within
                        // its error bound, which is where self-intersection would land).
                        let moved = (h.geometry.point - hit.geometry.point).length();
                        let error = hit.geometry.error.length();
                        assert!(
                            moved > 4.0 * error,
                            "{}: re-hit {moved} from the start, error {error} (scale {scale}), {spawned:?}",
                            scene.objects()[0].name
                        );
                    }
                    Some(h) => panic!("spawned ray re-hit its surface at t = {} (scale {scale}, convex {convex})", h.t),
                }
            }
        }
    }
    checked
}

#[test]
fn spawned_rays_never_rehit_their_surface_at_any_scale() {
    let mut rng = TestRng(99);
    for scale in [1e-3f32, 1.0, 1e3, 1e5] {
        for _ in 0..20 {
            for (shape, transform, convex, centre) in shapes(&mut rng, scale) {
                let mut o = object(shape);
                o.transform = transform;
                let s = scene(vec![o]);
                assert!(check(&s, centre, &mut rng, convex, scale) > 0, "no hits on {}", s.objects()[0].name);
            }
        }
    }
}

/// Flat sheets hit at their edges and vertices, where the triangle test's shortcut for
/// vertices ahead of the origin could matter: needles 1e-3 to 1e-5 wide, a sliver, and a
/// 1/16 grid hit exactly at its vertices. A ray spawned there on either side, even at a
/// grazing angle, never meets the sheet again.
#[test]
fn rays_spawned_at_edges_and_vertices_of_slivers_never_rehit_them() {
    let mut rng = TestRng(101);
    let mut sheets: Vec<(Mesh, Vec<Vec3>)> = Vec::new();
    for width in [1e-3f32, 1e-4, 1e-5] {
        let positions = vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, width, 0.0), Vec3::new(0.0, width, 0.0)];
        let targets = vec![Vec3::ZERO, Vec3::X, Vec3::new(0.5, 0.0, 0.0), Vec3::new(0.5, 0.5 * width, 0.0)];
        sheets.push((Mesh { positions, indices: vec![[0, 1, 2], [0, 2, 3]], ..Default::default() }, targets));
    }
    let sliver = vec![Vec3::ZERO, Vec3::new(0.1, 0.0, 0.0), Vec3::new(0.05, 1e-5, 0.0)];
    sheets.push((Mesh { positions: sliver.clone(), indices: vec![[0, 1, 2]], ..Default::default() }, sliver));
    let n = 8u32;
    let grid: Vec<Vec3> =
        (0..=n).flat_map(|j| (0..=n).map(move |i| Vec3::new(i as f32, j as f32, 0.0) / 16.0)).collect();
    let index = |i: u32, j: u32| j * (n + 1) + i;
    let indices = (0..n)
        .flat_map(|j| {
            (0..n).flat_map(move |i| {
                [
                    [index(i, j), index(i + 1, j), index(i + 1, j + 1)],
                    [index(i, j), index(i + 1, j + 1), index(i, j + 1)],
                ]
            })
        })
        .collect();
    sheets.push((Mesh { positions: grid.clone(), indices, ..Default::default() }, grid[10..70].to_vec()));
    let mut spawned = 0;
    for (mesh, targets) in sheets {
        let s = scene(vec![object(Shape::Mesh(mesh))]);
        for target in targets {
            for _ in 0..20 {
                let origin = target + Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-2.0, -0.5));
                let Some(hit) = s.intersect(&Ray::new(origin, target - origin)) else { continue };
                for _ in 0..20 {
                    // Any direction, a grazing one now and then.
                    let mut d = rng.vec3(-1.0, 1.0).normalize_or(Vec3::X);
                    if rng.below(3) == 0 {
                        d.z *= 1e-2;
                    }
                    if d.z.abs() < 1e-4 {
                        continue;
                    }
                    for d in [d, -d] {
                        let again = s.intersect(&hit.spawn_ray(d.normalize()));
                        assert!(
                            again.is_none(),
                            "a ray spawned at {} along {d} re-hit the sheet: {again:?}",
                            hit.geometry.point
                        );
                        spawned += 1;
                    }
                }
            }
        }
    }
    assert!(spawned > 10_000, "{spawned}");
}
