//! Two algorithms, one answer: the BVH's closest and any hit against testing every primitive,
//! on random scenes of every shape, including the degenerate cases.

mod common;

use common::{object, scene, scene_with_methods, TestRng};
use glint_core::geometry::Ray;
use glint_core::scene::Scene;
use glint_core::shapes::{
    AaBox, Csg, CsgOperation, CsgTree, CurveBasis, Curves, IntersectMethods, Mesh, Plane, Polygon, Shape, Sphere,
    Triangle, TriangleMethod,
};
use glint_core::Vec3;

fn random_scene(rng: &mut TestRng, n: usize) -> Scene {
    scene(random_objects(rng, n))
}

fn random_objects(rng: &mut TestRng, n: usize) -> Vec<glint_core::scene::Object> {
    let mut objects = Vec::new();
    for _ in 0..n {
        let c = rng.vec3(-5.0, 5.0);
        let shape = match rng.below(8) {
            0 => Shape::Sphere(Sphere::new(c, rng.range(0.05, 1.0))),
            1 => Shape::Triangle(Triangle::new(c, c + rng.vec3(-1.0, 1.0), c + rng.vec3(-1.0, 1.0))),
            2 => Shape::AaBox(AaBox::new(c, c + rng.vec3(0.05, 1.5))),
            3 => {
                let (s, t) = glint_core::geometry::orthonormal_basis(rng.vec3(-1.0, 1.0).normalize());
                let verts = (0..5)
                    .map(|k| {
                        let a = k as f32 * std::f32::consts::TAU / 5.0;
                        c + rng.range(0.3, 1.0) * (a.cos() * s + a.sin() * t)
                    })
                    .collect();
                Shape::Polygon(Polygon::new(verts).unwrap())
            }
            4 => Shape::Triangle(Triangle::new(c, c + Vec3::X, c + 2.0 * Vec3::X)), // zero area
            5 => {
                // A die: a cube less a ball at a random corner, with a lens (two balls' overlap)
                // joined to it.
                let solid = |shape| CsgTree::solid(shape);
                let r = rng.range(0.1, 0.8);
                let corner = c + r * rng.vec3(-1.0, 1.0);
                let die = CsgTree::Combine(
                    CsgOperation::Difference,
                    vec![
                        solid(Shape::AaBox(AaBox::new(c - Vec3::splat(r), c + Vec3::splat(r)))),
                        solid(Shape::Sphere(Sphere::new(corner, r * rng.range(0.3, 1.2)))),
                    ],
                );
                let offset = rng.vec3(-1.0, 1.0) * r;
                let lens = CsgTree::Combine(
                    CsgOperation::Intersection,
                    vec![
                        solid(Shape::Sphere(Sphere::new(c + offset, r))),
                        solid(Shape::Sphere(Sphere::new(c + 1.5 * offset, r))),
                    ],
                );
                Shape::Csg(Box::new(Csg::new(CsgTree::Combine(CsgOperation::Union, vec![die, lens])).unwrap()))
            }
            6 => {
                // Curves of every basis through random points, tapering.
                let basis = [CurveBasis::Linear, CurveBasis::BSpline, CurveBasis::Bezier][rng.below(3) as usize];
                let points = (0..7)
                    .map(|_| {
                        let p = c + rng.vec3(-1.0, 1.0);
                        [p.x, p.y, p.z, rng.range(0.0, 0.3)]
                    })
                    .collect();
                Shape::Curves(std::sync::Arc::new(Curves::new(basis, &[points]).unwrap()))
            }
            _ => {
                // A small mesh with a duplicated (coincident) triangle.
                let positions = vec![c, c + Vec3::X, c + Vec3::Y, c + Vec3::Z];
                let indices = vec![[0, 1, 2], [0, 2, 3], [0, 1, 2]];
                Shape::Mesh(Mesh { positions, indices, ..Default::default() })
            }
        };
        objects.push(object(shape));
    }
    objects
}

fn check_ray(scene: &Scene, ray: &Ray) {
    let fast = scene.intersect(ray);
    let reference = scene.intersect_brute_force(ray);
    match (fast, reference) {
        (Some(a), Some(b)) => {
            // The same routine computes both, so equal distances are equal to the bit; on a tie
            // (coincident primitives) either primitive is right.
            assert_eq!(a.t, b.t, "{ray:?}");
            if (a.object, a.prim) != (b.object, b.prim) {
                assert_eq!(a.t, b.t);
            }
        }
        (None, None) => {}
        _ => panic!("BVH {fast:?} vs brute force {reference:?} for {ray:?}"),
    }
    assert_eq!(scene.occluded(ray), reference.is_some(), "any-hit disagrees for {ray:?}");
}

#[test]
fn bvh_equals_brute_force_on_random_scenes() {
    let mut rng = TestRng(1);
    // Trees of one node and deeper ones take differently compiled queries (the leaf tests
    // inlined or called): both must be here.
    let mut wide_nodes = Vec::new();
    for n in [1, 2, 3, 10, 100, 1000] {
        let scene = random_scene(&mut rng, n);
        wide_nodes.push(scene.geometry().bvh_stats().wide_nodes);
        for _ in 0..20_000 {
            let origin = rng.vec3(-8.0, 8.0);
            let ray = Ray::new(origin, rng.vec3(-1.0, 1.0).normalize_or(Vec3::X));
            check_ray(&scene, &ray);
            let short = Ray::with_range(origin, ray.direction, rng.range(0.0, 2.0), rng.range(2.0, 10.0));
            check_ray(&scene, &short);
        }
    }
    assert!(wide_nodes.contains(&1) && wide_nodes.iter().any(|&n| n > 1), "{wide_nodes:?}");
}

/// The leaf blocks test triangles eight at a time with the watertight test; the other triangle
/// methods take the scalar path through the same blocks.
#[test]
fn every_triangle_method_agrees_with_brute_force() {
    for triangle in [TriangleMethod::Watertight, TriangleMethod::MollerTrumbore, TriangleMethod::Cramer] {
        let mut rng = TestRng(3);
        let methods = IntersectMethods { triangle, ..IntersectMethods::default() };
        let scene = scene_with_methods(random_objects(&mut rng, 300), methods);
        for _ in 0..10_000 {
            let origin = rng.vec3(-8.0, 8.0);
            let ray = Ray::new(origin, rng.vec3(-1.0, 1.0).normalize_or(Vec3::X));
            check_ray(&scene, &ray);
        }
    }
}

#[test]
fn empty_scene_and_rays_along_box_faces() {
    let empty = scene(Vec::new());
    assert!(empty.intersect(&Ray::new(Vec3::ZERO, Vec3::X)).is_none());
    assert!(!empty.occluded(&Ray::new(Vec3::ZERO, Vec3::X)));

    let boxes = scene(vec![
        object(Shape::AaBox(AaBox::new(Vec3::ZERO, Vec3::ONE))),
        object(Shape::AaBox(AaBox::new(Vec3::new(2.0, 0.0, 0.0), Vec3::new(3.0, 1.0, 1.0)))),
    ]);
    // Along the shared bottom plane y = 0 and the top plane y = 1, through both boxes.
    for y in [0.0, 1.0] {
        let ray = Ray::new(Vec3::new(-1.0, y, 0.5), Vec3::X);
        check_ray(&boxes, &ray);
        assert_eq!(boxes.intersect(&ray).map(|h| h.t), Some(1.0));
    }
}

#[test]
fn planes_are_found_outside_the_bvh() {
    let s = scene(vec![
        object(Shape::Plane(Plane::new(Vec3::Y, 1.0))),
        object(Shape::Sphere(Sphere::new(Vec3::new(0.0, 0.0, 3.0), 0.5))),
    ]);
    let down = Ray::new(Vec3::ZERO, -Vec3::Y);
    assert_eq!(s.intersect(&down).map(|h| (h.object, h.t)), Some((0, 1.0)));
    let ahead = Ray::new(Vec3::ZERO, Vec3::Z);
    assert_eq!(s.intersect(&ahead).map(|h| (h.object, h.t)), Some((1, 2.5)));
    check_ray(&s, &down);
    check_ray(&s, &ahead);
}

/// A hit triangle's corners, which the wavefront reads from the leaf blocks, are its shape's
/// own corners, bit for bit; a transformed triangle (not in the blocks) has none, and neither
/// has any other shape.
#[test]
fn corners_read_from_the_blocks_are_the_shapes_own() {
    let mut rng = TestRng(11);
    let mut objects = random_objects(&mut rng, 300);
    let moved = glint_core::geometry::Transform::from_matrix(glam::Mat4::from_translation(Vec3::X)).unwrap();
    objects.push(glint_core::scene::Object {
        transform: Some(moved),
        ..object(Shape::Triangle(Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y)))
    });
    let s = scene(objects);
    let mut triangles = 0;
    for (o, object) in s.objects().iter().enumerate() {
        for p in 0..object.shape.primitive_count() {
            let expected = match (&object.shape, &object.transform) {
                (Shape::Triangle(t), None) => Some(t.vertices),
                (Shape::Mesh(m), None) => Some(m.triangle_vertices(p as usize)),
                _ => None,
            };
            let corners = s.geometry().triangle(o as u32, p);
            let bits = |c: Option<[Vec3; 3]>| c.map(|c| c.map(|v| v.to_array().map(f32::to_bits)));
            assert_eq!(bits(corners), bits(expected), "object {o}, primitive {p}");
            triangles += usize::from(expected.is_some());
        }
    }
    assert!(triangles > 100, "too few triangles ({triangles}) to mean anything");
}

/// Rays traced together with their traversals interleaved (`Geometry::closest_primitives`)
/// get each the answer of the one-ray query, to the bit: on the mixed random scenes (generic
/// primitives in the blocks) and on a soup of 20,000 triangles (a deep tree of SIMD blocks
/// only), with whole and short rays, in batches of every size around the walks' count.
#[test]
fn interleaved_queries_answer_as_one_ray_queries() {
    let mut rng = TestRng(3);
    let soup: Vec<Vec3> = (0..20_000)
        .flat_map(|_| {
            let c = rng.vec3(-5.0, 5.0);
            [c, c + rng.vec3(-0.3, 0.3), c + rng.vec3(-0.3, 0.3)]
        })
        .collect();
    let indices = (0..20_000u32).map(|k| [3 * k, 3 * k + 1, 3 * k + 2]).collect();
    let soup = scene(vec![object(Shape::Mesh(Mesh { positions: soup, indices, ..Default::default() }))]);
    let mut checked = 0;
    for scene in [random_scene(&mut rng, 1000), soup] {
        assert!(scene.geometry().bvh_stats().wide_nodes > 1);
        for batch in [1usize, 7, 8, 9, 100, 1000] {
            let mut rays: Vec<Ray> = (0..batch)
                .map(|k| {
                    let origin = rng.vec3(-8.0, 8.0);
                    let direction = rng.vec3(-1.0, 1.0).normalize_or(Vec3::X);
                    match k % 3 {
                        0 => Ray::with_range(origin, direction, rng.range(0.0, 2.0), rng.range(2.0, 10.0)),
                        _ => Ray::new(origin, direction),
                    }
                })
                .collect();
            let expected: Vec<_> = rays
                .iter()
                .map(|ray| {
                    let (mut ray, mut found) = (*ray, glint_core::accel::PrimitiveHit::NONE);
                    let hit = scene.geometry().closest_primitive_into(&mut ray, &mut found);
                    (
                        hit.then(|| (found.object, found.prim, found.at.t.to_bits(), found.at.u.to_bits())),
                        ray.t_max.to_bits(),
                    )
                })
                .collect();
            let mut found = vec![glint_core::accel::PrimitiveHit::NONE; batch];
            scene.geometry().closest_primitives(&mut rays, &mut found);
            for ((ray, found), expected) in rays.iter().zip(&found).zip(&expected) {
                let got = (found.object != u32::MAX)
                    .then(|| (found.object, found.prim, found.at.t.to_bits(), found.at.u.to_bits()));
                assert_eq!((got, ray.t_max.to_bits()), *expected, "batch of {batch}: {ray:?}");
                checked += usize::from(got.is_some());
            }
        }
    }
    assert!(checked > 500, "only {checked} hits compared");
}
