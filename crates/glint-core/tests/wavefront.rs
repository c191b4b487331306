//! The path tracer's wavefront (eight paths at a time in SIMD lanes) against the path tracer
//! one path at a time: the same radiance bit for bit and the same rays traced, for every
//! pixel, sampler, seed and depth setting tried. The scalar path tracer is what the ground
//! truth tests check against Mitsuba (glint-cli's cornell_box.rs) and the furnace; this
//! carries their verdict over to the wavefront. Runs in CI for AVX2 and for plain SSE2.

mod common;

use common::{object_with, scene};
use glint_core::camera::Camera;
use glint_core::geometry::Ray;
use glint_core::integrators::{Integrator, PathTracer, SampleContext, WavefrontPathTracer};
use glint_core::lights::{Environment, Falloff, Light, PointLight, TriangleSampling};
use glint_core::materials::{Fresnel, Material, Phong};
use glint_core::sampling::{Sampler, SamplerKind};
use glint_core::scene::{Object, Scene};
use glint_core::shapes::{Mesh, Polygon, Shape, Sphere, Triangle};
use glint_core::textures::{Checker, Texture};
use glint_core::Named;
use glint_core::{Rgb, Vec2, Vec3};

const SIZE: u32 = 40;

fn diffuse(reflectance: Rgb, emission: Rgb, two_sided: bool) -> Material {
    Material::Phong(Phong {
        diffuse: Texture::Constant(reflectance),
        emission,
        two_sided_emission: two_sided,
        ..Phong::default()
    })
}

/// Both triangles of the quad a, b, c, d.
fn quad(corners: [Vec3; 4], material: u32) -> [Object; 2] {
    let [a, b, c, d] = corners;
    [
        object_with(Shape::Triangle(Triangle::new(a, b, c)), material),
        object_with(Shape::Triangle(Triangle::new(a, c, d)), material),
    ]
}

/// A closed room of coloured walls with a one-sided lamp under its ceiling, a small two-sided
/// emitter, a black triangle, and a tilted quad with vertex normals (smooth shading), seen
/// from inside: every kind of hit the lanes handle.
fn room() -> Scene {
    let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    let mut objects = Vec::new();
    // Floor, ceiling, back, left, right and front walls.
    objects.extend(quad([v(-1., -1., -1.), v(1., -1., -1.), v(1., -1., 1.), v(-1., -1., 1.)], 0));
    objects.extend(quad([v(-1., 1., -1.), v(-1., 1., 1.), v(1., 1., 1.), v(1., 1., -1.)], 0));
    objects.extend(quad([v(-1., -1., 1.), v(1., -1., 1.), v(1., 1., 1.), v(-1., 1., 1.)], 0));
    objects.extend(quad([v(-1., -1., -1.), v(-1., -1., 1.), v(-1., 1., 1.), v(-1., 1., -1.)], 1));
    objects.extend(quad([v(1., -1., -1.), v(1., 1., -1.), v(1., 1., 1.), v(1., -1., 1.)], 2));
    objects.extend(quad([v(-1., -1., -1.), v(-1., 1., -1.), v(1., 1., -1.), v(1., -1., -1.)], 0));
    // The lamp faces down: (b − a) × (c − a) along −y. Then a two-sided emitter and a black
    // triangle.
    objects.extend(quad([v(-0.3, 0.98, -0.2), v(0.3, 0.98, -0.2), v(0.3, 0.98, 0.4), v(-0.3, 0.98, 0.4)], 3));
    objects
        .push(object_with(Shape::Triangle(Triangle::new(v(0.6, -0.2, 0.5), v(0.9, -0.2, 0.8), v(0.7, 0.3, 0.7))), 4));
    objects
        .push(object_with(Shape::Triangle(Triangle::new(v(-0.8, -1., 0.2), v(-0.4, -1., 0.6), v(-0.6, -0.4, 0.4))), 5));
    // A smooth quad: normals that bend away from the flat face, one past the horizon of
    // grazing views; one triangle a triangle shape, the other a mesh.
    let smooth = [v(-0.5, -0.6, 0.3), v(0.3, -0.8, 0.1), v(0.4, -0.1, 0.6), v(-0.4, 0.1, 0.7)];
    let bent = |p: Vec3| (Vec3::new(0.0, 0.2, -1.0) + 0.9 * p).normalize();
    let mut triangle = Triangle::new(smooth[0], smooth[1], smooth[2]);
    triangle.normals = Some(triangle.vertices.map(bent));
    objects.push(object_with(Shape::Triangle(triangle), 0));
    let mesh = Mesh {
        positions: smooth.to_vec(),
        normals: Some(smooth.map(bent).to_vec()),
        uvs: None,
        indices: vec![[0, 2, 3]],
        ..Mesh::default()
    };
    objects.push(object_with(Shape::Mesh(mesh), 0));
    let mut s = scene(objects);
    s.set_materials(vec![
        diffuse(Rgb::new(0.8, 0.75, 0.7), Rgb::ZERO, false),
        diffuse(Rgb::new(0.6, 0.05, 0.05), Rgb::ZERO, false),
        diffuse(Rgb::new(0.1, 0.5, 0.1), Rgb::ZERO, false),
        diffuse(Rgb::splat(0.7), Rgb::new(12.0, 10.0, 7.0), false),
        diffuse(Rgb::splat(0.5), Rgb::new(2.0, 3.0, 4.0), true),
        diffuse(Rgb::ZERO, Rgb::ZERO, false),
    ]);
    s.set_camera(
        Camera::new(Vec3::new(0.0, 0.0, -0.95), Vec3::new(0.0, -0.1, 0.0), Vec3::Y, 70.0, SIZE, SIZE).unwrap(),
    );
    s
}

/// Every pixel's camera sample `index`: rays and contexts as the render loop makes them.
fn camera_samples(scene: &Scene, sampler: SamplerKind, seed: u64, index: u32) -> (Vec<Ray>, Vec<SampleContext>) {
    let (w, h) = (scene.camera().width, scene.camera().height);
    (0..w * h)
        .map(|i| {
            let mut context = SampleContext::with_sampler(Sampler::new(sampler, seed, i as u64, index, 64));
            let (fx, fy) = ((i % w) as f32 + context.sampler.next_f32(), (i / w) as f32 + context.sampler.next_f32());
            (scene.camera().generate_ray(fx, fy), context)
        })
        .unzip()
}

/// Sample `index` of every pixel both ways, asserted equal; returns how many pixels saw light.
fn assert_same(scene: &Scene, tracer: &WavefrontPathTracer, sampler: SamplerKind, seed: u64, index: u32) -> usize {
    let (rays, contexts) = camera_samples(scene, sampler, seed, index);
    let mut one_by_one = contexts.clone();
    let expected: Vec<Rgb> = rays
        .iter()
        .zip(one_by_one.iter_mut())
        .map(|(ray, context)| tracer.tracer.radiance(scene, ray, context))
        .collect();
    let mut together = contexts;
    let mut got = vec![Rgb::ZERO; rays.len()];
    // In tile-sized batches, as the render loop hands them over (the last one short).
    for ((rays, contexts), out) in rays.chunks(256).zip(together.chunks_mut(256)).zip(got.chunks_mut(256)) {
        tracer.radiance_tile(scene, rays, contexts, out);
    }
    for i in 0..rays.len() {
        let (g, e) = (got[i], expected[i]);
        assert_eq!(
            g.to_array().map(f32::to_bits),
            e.to_array().map(f32::to_bits),
            "pixel {i}, sample {index}, seed {seed}: {g} against {e}"
        );
    }
    // The rays traced: the wavefront counts a tile's in all (in its first context).
    let total = |contexts: &[SampleContext]| {
        let mut rays = glint_core::integrators::RayCounts::default();
        contexts.iter().for_each(|c| rays.add(&c.rays));
        rays
    };
    assert_eq!(total(&together), total(&one_by_one), "rays traced, sample {index}, seed {seed}");
    expected.iter().filter(|r| r.max_element() > 0.0).count()
}

/// A lane kind's scenes against the scalar path tracer: each `scenes` entry with both samplers
/// and both (seed, index) pairs of `seeds`, more than half its pixels lit, then each `limited`
/// (scene, sampler) at the depth limits and Russian roulette from the first bounce.
fn assert_same_in_lanes(scenes: &[(&Scene, &str)], seeds: [(u64, u32); 2], limited: &[(&Scene, SamplerKind)]) {
    let tracer = WavefrontPathTracer { tracer: PathTracer { max_depth: u32::MAX, rr_depth: 5 } };
    for &(scene, what) in scenes {
        for sampler in [SamplerKind::Independent, SamplerKind::Sobol] {
            for (seed, index) in seeds {
                let lit = assert_same(scene, &tracer, sampler, seed, index);
                assert!(lit > (SIZE * SIZE / 2) as usize, "{what}: {lit} pixels lit");
            }
        }
    }
    for (max_depth, rr_depth) in [(1, 5), (2, 1), (u32::MAX, 0)] {
        let tracer = WavefrontPathTracer { tracer: PathTracer { max_depth, rr_depth } };
        for seed in 0..2 {
            for &(scene, sampler) in limited {
                assert_same(scene, &tracer, sampler, seed, seed as u32);
            }
        }
    }
}

#[test]
fn the_wavefront_renders_a_room_bit_for_bit_as_the_path_tracer() {
    let scene = room();
    let tracer = WavefrontPathTracer { tracer: PathTracer { max_depth: u32::MAX, rr_depth: 5 } };
    for &sampler in SamplerKind::ALL {
        for (seed, index) in [(0, 0), (7, 3), (123, 41)] {
            let lit = assert_same(&scene, &tracer, sampler, seed, index);
            assert!(lit > (SIZE * SIZE / 2) as usize, "{lit} pixels lit");
        }
    }
}

/// Depth limits and roulette from the first bounce: paths that end at every stage.
#[test]
fn the_wavefront_ends_paths_as_the_path_tracer_does() {
    let scene = room();
    for (max_depth, rr_depth) in [(0, 5), (1, 5), (2, 1), (u32::MAX, 1), (6, 3), (u32::MAX, 0)] {
        let tracer = WavefrontPathTracer { tracer: PathTracer { max_depth, rr_depth } };
        for seed in 0..3 {
            assert_same(&scene, &tracer, SamplerKind::Sobol, seed, seed as u32);
        }
    }
}

/// The room with one change, for the lanes' other paths.
fn room_where(change: impl FnOnce(&mut Vec<Object>, &mut Vec<Material>)) -> Scene {
    let room = room();
    let (mut objects, mut materials) = (room.objects().to_vec(), room.materials().to_vec());
    change(&mut objects, &mut materials);
    let mut s = scene(objects);
    s.set_materials(materials);
    s.set_camera(room.camera().clone());
    s
}

/// What the lanes leave to the scalar code lane by lane, alone and together: triangle lights
/// by solid angle (surfaces in lanes, light points from the scalar code); a textured wall
/// (surfaces from the scalar code, light points in lanes); spheres, a sphere light and an
/// emissive polygon that light sampling does not know (both from the scalar code); and the
/// room without its back wall, where paths leave the scene.
#[test]
fn the_wavefront_serves_spheres_textures_open_rooms_and_solid_angle_light_sampling() {
    let tracer = WavefrontPathTracer { tracer: PathTracer { max_depth: u32::MAX, rr_depth: 5 } };
    let checker = Checker::new(Rgb::new(0.8, 0.7, 0.2), Rgb::new(0.2, 0.3, 0.7), Vec2::splat(4.0));
    let solid_angle = |mut s: Scene| {
        s.set_triangle_sampling(TriangleSampling::SolidAngle);
        s
    };
    let textured = room_where(|_, materials| {
        let Material::Phong(back) = &mut materials[2] else { unreachable!("the room is Phong") };
        back.diffuse = Texture::Checker(Box::new(checker));
    });
    let spheres = || {
        room_where(|objects, materials| {
            materials.push(diffuse(Rgb::splat(0.3), Rgb::new(6.0, 5.0, 3.0), false));
            objects.push(object_with(Shape::Sphere(Sphere::new(Vec3::new(0.45, -0.7, 0.3), 0.3)), 0));
            objects.push(object_with(Shape::Sphere(Sphere::new(Vec3::new(-0.6, 0.6, 0.6), 0.12)), 6));
            let corners = vec![Vec3::new(-0.9, -0.5, 0.99), Vec3::new(-0.5, -0.5, 0.99), Vec3::new(-0.7, -0.2, 0.99)];
            objects.push(object_with(Shape::Polygon(Polygon::new(corners).unwrap()), 4));
        })
    };
    let open = room_where(|objects, _| {
        objects.drain(4..6); // the back wall
    });
    // More lights than the lanes choose among by counting (a lamp of 48 small triangles, facing
    // down, with uneven powers), and more than they blend but few enough to count (16).
    let lamp_of = |triangles: usize| {
        room_where(move |objects, materials| {
            for i in 0..triangles {
                let (x, z) = (-0.8 + 0.1 * (i % 12) as f32, -0.6 + 0.3 * (i / 12) as f32);
                let [a, b, c] = [Vec3::new(x, 0.9, z), Vec3::new(x + 0.08, 0.9, z), Vec3::new(x, 0.9, z + 0.2)];
                materials.push(diffuse(Rgb::splat(0.5), Rgb::splat(1.0 + i as f32), false));
                objects.push(object_with(Shape::Triangle(Triangle::new(a, c, b)), materials.len() as u32 - 1));
            }
        })
    };
    let (many_lights, sixteen_lights) = (lamp_of(48), lamp_of(16));
    assert!(many_lights.lights().area_count() > 48, "the lamp's triangles are lights");
    assert!((17..=32).contains(&sixteen_lights.lights().area_count()));
    // No light at all: nothing for the lanes to choose.
    let dark = room_where(|_, materials| {
        for m in materials.iter_mut() {
            let Material::Phong(m) = m else { unreachable!("the room is Phong") };
            m.emission = Rgb::ZERO;
        }
    });
    assert_eq!(dark.lights().area_count(), 0);
    let scenes = [
        (solid_angle(room()), "solid-angle sampling", true),
        (textured, "a textured wall", true),
        (solid_angle(spheres()), "spheres, solid angle", true),
        (spheres(), "spheres", true),
        (open, "an open room", false),
        (many_lights, "many lights", true),
        (sixteen_lights, "sixteen lights", true),
        (dark, "no lights", false),
    ];
    for (scene, what, closed) in scenes {
        for sampler in [SamplerKind::Independent, SamplerKind::Sobol] {
            for (seed, index) in [(2, 0), (11, 9)] {
                let lit = assert_same(&scene, &tracer, sampler, seed, index);
                if closed {
                    assert!(lit > (SIZE * SIZE / 2) as usize, "{what}: {lit} pixels lit");
                }
            }
        }
    }
}

/// Surfaces whose BSDF is more than Lambert's lobe, each bounce there taken by the scalar code
/// while the other paths take theirs in lanes: a mirror wall (alone, in a room of triangles
/// whose surfaces the lanes compute), a glass sphere (refraction, η² in the roulette), the
/// course's mixed material, a rough metal and rough glass (GGX); alone, in a pair and all
/// together, at depth limits and roulette from the first bounce.
#[test]
fn the_wavefront_serves_mirrors_glass_glossy_and_mixed_materials() {
    let phong = |f: &dyn Fn(&mut Phong)| {
        let mut p = Phong { diffuse: Texture::Constant(Rgb::ZERO), ..Phong::default() };
        f(&mut p);
        Material::Phong(p)
    };
    let glass = phong(&|p| {
        p.transmission = Texture::Constant(Rgb::ONE);
        p.ior = 1.5;
        p.fresnel = Fresnel::Exact;
    });
    let mixed = phong(&|p| {
        p.diffuse = Texture::Constant(Rgb::new(0.4, 0.4, 0.3));
        p.reflection = Texture::Constant(Rgb::splat(0.3));
        p.transmission = Texture::Constant(Rgb::splat(0.2));
        p.ior = 1.5;
    });
    let rough_metal = phong(&|p| {
        p.reflection = Texture::Constant(Rgb::new(0.9, 0.7, 0.4));
        p.roughness = 0.4;
        p.fresnel = Fresnel::Conductor { eta: Rgb::new(0.2, 0.4, 1.2), k: Rgb::new(3.6, 2.5, 2.2) };
    });
    let rough_glass = phong(&|p| {
        p.transmission = Texture::Constant(Rgb::ONE);
        p.ior = 1.5;
        p.roughness = 0.3;
        p.fresnel = Fresnel::Exact;
    });
    let with = |materials: Vec<Material>| {
        room_where(move |objects, room_materials| {
            // A half-mirror left wall, then each material on a sphere of its own.
            let Material::Phong(left) = &mut room_materials[1] else { unreachable!("the room is Phong") };
            left.reflection = Texture::Constant(Rgb::splat(0.5));
            let centres = [Vec3::new(0.45, -0.65, 0.3), Vec3::new(-0.4, -0.6, 0.5), Vec3::new(0.1, 0.3, 0.6)];
            for (j, material) in materials.into_iter().enumerate() {
                room_materials.push(material);
                let id = room_materials.len() as u32 - 1;
                objects.push(object_with(Shape::Sphere(Sphere::new(centres[j % 3], 0.25)), id));
            }
        })
    };
    let scenes = [
        // Triangles and constant colours alone: the lanes compute the other paths' surfaces.
        (with(vec![]), "a mirror wall"),
        (with(vec![glass.clone()]), "a glass sphere and a mirror wall"),
        (with(vec![mixed.clone()]), "the mixed material"),
        (with(vec![rough_metal.clone(), rough_glass]), "GGX metal and glass"),
        (with(vec![glass, mixed, rough_metal]), "all together"),
    ];
    for (scene, what) in &scenes {
        let tracer = WavefrontPathTracer { tracer: PathTracer { max_depth: u32::MAX, rr_depth: 5 } };
        for sampler in [SamplerKind::Independent, SamplerKind::Sobol] {
            for (seed, index) in [(3, 0), (17, 5)] {
                let lit = assert_same(scene, &tracer, sampler, seed, index);
                assert!(lit > (SIZE * SIZE / 2) as usize, "{what}: {lit} pixels lit");
            }
        }
    }
    let all = &scenes[4].0;
    for (max_depth, rr_depth) in [(1, 5), (2, 1), (u32::MAX, 1), (5, 0)] {
        let tracer = WavefrontPathTracer { tracer: PathTracer { max_depth, rr_depth } };
        for seed in 0..2 {
            assert_same(all, &tracer, SamplerKind::Sobol, seed, seed as u32);
        }
    }
}

/// Rough conductors shaded in the lanes (`RoughConductorLanes` at eight lanes, the scalar
/// BSDF at one): a metal wall among the room's triangles (the lanes compute the surfaces),
/// metal spheres with a textured width and colour (surfaces from the scalar code), anisotropic
/// ones (the frame turned to ∂p/∂u lane by lane, where the widths differ) and Beckmann's
/// (visible normals by Newton's method, lanes stopping as they converge), beside a smooth
/// conductor the scalar code shades; at depth limits and roulette from the first bounce too.
#[test]
fn the_wavefront_shades_rough_conductors_in_lanes() {
    use glint_core::materials::{named_metal, Conductor, Distribution, RoughConductor};
    let metal = |name: &str, alpha_u: Texture, alpha_v: Texture, distribution: Distribution| {
        let (eta, k) = named_metal(name).expect("a named metal");
        Material::RoughConductor(RoughConductor {
            conductor: Conductor { eta, k, specular: Texture::Constant(Rgb::new(0.9, 0.85, 0.8)) },
            alpha_u,
            alpha_v,
            distribution,
        })
    };
    let ggx = |name: &str, alpha: f32| metal(name, alpha.into(), alpha.into(), Distribution::Ggx);
    let checker = || Texture::Checker(Box::new(Checker::new(Rgb::splat(0.05), Rgb::splat(0.6), Vec2::splat(4.0))));
    let metal_wall = room_where(|_, materials| materials[2] = ggx("Au", 0.3));
    let spheres = |extra: Vec<Material>| {
        room_where(move |objects, materials| {
            let mut textured = metal("Cu", checker(), checker(), Distribution::Ggx);
            let Material::RoughConductor(m) = &mut textured else { unreachable!("a rough conductor") };
            m.conductor.specular = checker();
            let centres = [Vec3::new(0.45, -0.65, 0.3), Vec3::new(-0.4, -0.6, 0.5), Vec3::new(0.1, 0.3, 0.6)];
            for (j, material) in [ggx("Al", 0.05), textured].into_iter().chain(extra).enumerate() {
                materials.push(material);
                let id = materials.len() as u32 - 1;
                objects.push(object_with(Shape::Sphere(Sphere::new(centres[j % 3], 0.25)), id));
            }
        })
    };
    let (eta, k) = named_metal("Au").expect("gold");
    let smooth = Material::Conductor(Conductor { eta, k, specular: Texture::Constant(Rgb::ONE) });
    let beckmann = || {
        vec![
            metal("Cr", 0.2.into(), 0.2.into(), Distribution::Beckmann),
            metal("Ag", checker(), 0.3.into(), Distribution::Beckmann),
            smooth.clone(),
        ]
    };
    let scenes = [
        (metal_wall, "a gold wall among triangles"),
        (spheres(vec![metal("Ag", 0.1.into(), 0.4.into(), Distribution::Ggx)]), "GGX spheres"),
        (spheres(beckmann()), "Beckmann spheres and a smooth metal"),
    ];
    let tracer = WavefrontPathTracer { tracer: PathTracer { max_depth: u32::MAX, rr_depth: 5 } };
    for (scene, what) in &scenes {
        for sampler in [SamplerKind::Independent, SamplerKind::Sobol] {
            for (seed, index) in [(5, 0), (19, 7)] {
                let lit = assert_same(scene, &tracer, sampler, seed, index);
                assert!(lit > (SIZE * SIZE / 2) as usize, "{what}: {lit} pixels lit");
            }
        }
    }
    for (max_depth, rr_depth) in [(1, 5), (2, 1), (u32::MAX, 0)] {
        let tracer = WavefrontPathTracer { tracer: PathTracer { max_depth, rr_depth } };
        for seed in 0..2 {
            assert_same(&scenes[2].0, &tracer, SamplerKind::Sobol, seed, seed as u32);
            assert_same(&scenes[0].0, &tracer, SamplerKind::Independent, seed, seed as u32);
        }
    }
}

/// Rough plastics shaded in the lanes (`RoughPlasticLanes`): GGX and Beckmann coats, linear
/// and nonlinear, constant (a wall among triangles) and textured (spheres), the coat's
/// reflection or the base chosen lane by lane; at depth limits too.
#[test]
fn the_wavefront_shades_rough_plastics_in_lanes() {
    use glint_core::materials::{Distribution, Plastic, RoughPlastic};
    let plastic = |diffuse: Texture, nonlinear: bool, alpha: f32, distribution: Distribution| {
        let specular = Texture::Constant(Rgb::splat(0.9));
        Material::RoughPlastic(RoughPlastic::new(
            Plastic { diffuse, specular, eta: 1.5, nonlinear },
            alpha,
            distribution,
        ))
    };
    let checker =
        || Texture::Checker(Box::new(Checker::new(Rgb::new(0.7, 0.2, 0.1), Rgb::splat(0.3), Vec2::splat(4.0))));
    let wall = room_where(|_, materials| {
        materials[2] = plastic(Texture::Constant(Rgb::new(0.2, 0.4, 0.7)), false, 0.2, Distribution::Ggx)
    });
    let spheres = room_where(|objects, materials| {
        let centres = [
            Vec3::new(0.45, -0.65, 0.3),
            Vec3::new(-0.4, -0.6, 0.5),
            Vec3::new(0.1, 0.3, 0.6),
            Vec3::new(-0.5, 0.4, 0.2),
        ];
        let coats = [
            plastic(checker(), true, 0.1, Distribution::Beckmann),
            plastic(Texture::Constant(Rgb::new(0.6, 0.6, 0.2)), false, 0.4, Distribution::Beckmann),
            plastic(checker(), false, 0.05, Distribution::Ggx),
            // Below the lobe's floor on the width (1e-4): the scalar lobe's width.
            plastic(Texture::Constant(Rgb::new(0.3, 0.5, 0.2)), false, 0.0, Distribution::Ggx),
        ];
        for (j, material) in coats.into_iter().enumerate() {
            materials.push(material);
            let id = materials.len() as u32 - 1;
            objects.push(object_with(Shape::Sphere(Sphere::new(centres[j], 0.25)), id));
        }
    });
    assert_same_in_lanes(
        &[(&wall, "a plastic wall among triangles"), (&spheres, "plastic spheres")],
        [(6, 0), (29, 4)],
        &[(&spheres, SamplerKind::Sobol)],
    );
}

/// Disney's principled BSDF shaded in the lanes (`PrincipledLanes`): a constant coated plastic
/// with sheen and fake subsurface (a wall among triangles, read once for the tile), and spheres
/// of a brushed (anisotropic) tinted half-metal, a frosted glass with a clearcoat (refracting
/// from inside, black from behind where it does not transmit), a textured plastic and a glass
/// whose diffuse share is 0 but whose sheen is not; at depth limits too.
#[test]
fn the_wavefront_shades_the_principled_bsdf_in_lanes() {
    use glint_core::materials::Principled;
    let grey = |v: f32| Texture::Constant(Rgb::splat(v));
    let checker = |a: Rgb, b: Rgb| Texture::Checker(Box::new(Checker::new(a, b, Vec2::splat(4.0))));
    let principled = |p: Principled| Material::Principled(Box::new(p));
    let wall = room_where(|_, materials| {
        materials[2] = principled(Principled {
            base_color: Texture::Constant(Rgb::new(0.2, 0.8, 0.1)),
            roughness: grey(0.3),
            clearcoat: grey(0.9),
            clearcoat_gloss: grey(0.5),
            sheen: grey(0.6),
            sheen_tint: grey(0.5),
            flatness: grey(0.3),
            ..Principled::default()
        })
    });
    let spheres = room_where(|objects, materials| {
        let centres = [
            Vec3::new(0.45, -0.65, 0.3),
            Vec3::new(-0.4, -0.6, 0.5),
            Vec3::new(0.1, 0.3, 0.6),
            Vec3::new(-0.5, 0.4, 0.2),
        ];
        let members = [
            Principled {
                base_color: Texture::Constant(Rgb::new(0.9, 0.6, 0.3)),
                roughness: grey(0.4),
                anisotropic: grey(0.7),
                metallic: grey(0.6),
                spec_tint: grey(0.4),
                ..Principled::default()
            },
            Principled {
                base_color: Texture::Constant(Rgb::new(0.8, 0.9, 1.0)),
                roughness: grey(0.5),
                spec_trans: grey(0.7),
                clearcoat: grey(0.5),
                ..Principled::default()
            },
            Principled {
                base_color: checker(Rgb::new(0.7, 0.2, 0.1), Rgb::splat(0.3)),
                roughness: checker(Rgb::splat(0.2), Rgb::splat(0.7)),
                metallic: checker(Rgb::ZERO, Rgb::splat(0.8)),
                ..Principled::default()
            },
            Principled { spec_trans: grey(1.0), sheen: grey(0.8), roughness: grey(0.2), ..Principled::default() },
        ];
        for (j, member) in members.into_iter().enumerate() {
            materials.push(principled(member));
            let id = materials.len() as u32 - 1;
            objects.push(object_with(Shape::Sphere(Sphere::new(centres[j], 0.25)), id));
        }
    });
    assert_same_in_lanes(
        &[(&wall, "a principled wall among triangles"), (&spheres, "principled spheres")],
        [(7, 0), (31, 5)],
        &[(&spheres, SamplerKind::Sobol)],
    );
}

/// The thin principled sheet shaded in the lanes (`PrincipledThinLanes`): a constant leaf-like
/// wall among triangles and spheres (seen from both sides: a sheet has no inside) of a glossy
/// transmitting sheet, a brushed tinted one and a textured one; at depth limits too.
#[test]
fn the_wavefront_shades_the_thin_principled_bsdf_in_lanes() {
    use glint_core::materials::PrincipledThin;
    let grey = |v: f32| Texture::Constant(Rgb::splat(v));
    let checker = |a: Rgb, b: Rgb| Texture::Checker(Box::new(Checker::new(a, b, Vec2::splat(4.0))));
    let thin = |p: PrincipledThin| Material::PrincipledThin(Box::new(p));
    let wall = room_where(|_, materials| {
        materials[2] = thin(PrincipledThin {
            base_color: Texture::Constant(Rgb::new(0.2, 0.6, 0.1)),
            roughness: grey(0.4),
            spec_trans: grey(0.3),
            diff_trans: grey(0.8),
            eta: grey(1.33),
            sheen: grey(0.5),
            flatness: grey(0.4),
            ..PrincipledThin::default()
        })
    });
    let spheres = room_where(|objects, materials| {
        let centres = [Vec3::new(0.45, -0.65, 0.3), Vec3::new(-0.4, -0.6, 0.5), Vec3::new(0.1, 0.3, 0.6)];
        let members = [
            PrincipledThin {
                base_color: Texture::Constant(Rgb::new(0.8, 0.9, 1.0)),
                roughness: grey(0.2),
                spec_trans: grey(0.8),
                eta: grey(1.5),
                ..PrincipledThin::default()
            },
            PrincipledThin {
                base_color: Texture::Constant(Rgb::new(0.9, 0.6, 0.3)),
                roughness: grey(0.5),
                anisotropic: grey(0.6),
                spec_trans: grey(0.5),
                spec_tint: grey(0.7),
                diff_trans: grey(0.4),
                ..PrincipledThin::default()
            },
            PrincipledThin {
                base_color: checker(Rgb::new(0.7, 0.2, 0.1), Rgb::splat(0.3)),
                roughness: checker(Rgb::splat(0.2), Rgb::splat(0.7)),
                diff_trans: checker(Rgb::ZERO, Rgb::splat(1.5)),
                ..PrincipledThin::default()
            },
        ];
        for (j, member) in members.into_iter().enumerate() {
            materials.push(thin(member));
            let id = materials.len() as u32 - 1;
            objects.push(object_with(Shape::Sphere(Sphere::new(centres[j], 0.25)), id));
        }
    });
    assert_same_in_lanes(
        &[(&wall, "a thin wall among triangles"), (&spheres, "thin spheres")],
        [(8, 0), (37, 6)],
        &[(&spheres, SamplerKind::Sobol)],
    );
}

/// Smooth plastic shaded in the lanes (`PlasticLanes`): the coat's mirror or the base chosen
/// lane by lane, so a bounce's lanes mix delta and non-delta samples, and lanes whose base is
/// black (the mirror alone: no light sampled, the lobe's numbers drawn first) share bounces
/// with lanes whose base is not; a constant wall among triangles, textured spheres, and the
/// black backs of the one-sided coat; at depth limits too.
#[test]
fn the_wavefront_shades_smooth_plastic_in_lanes() {
    use glint_core::materials::Plastic;
    let plastic = |diffuse: Texture, specular: Rgb, nonlinear: bool| {
        Material::Plastic(Plastic { diffuse, specular: Texture::Constant(specular), eta: 1.5, nonlinear })
    };
    let checker = || Texture::Checker(Box::new(Checker::new(Rgb::new(0.7, 0.2, 0.1), Rgb::ZERO, Vec2::splat(4.0))));
    let wall =
        room_where(|_, materials| materials[2] = plastic(Texture::Constant(Rgb::new(0.2, 0.4, 0.7)), Rgb::ONE, false));
    let spheres = room_where(|objects, materials| {
        let centres = [
            Vec3::new(0.45, -0.65, 0.3),
            Vec3::new(-0.4, -0.6, 0.5),
            Vec3::new(0.1, 0.3, 0.6),
            Vec3::new(-0.5, 0.4, 0.2),
        ];
        let coats = [
            plastic(checker(), Rgb::ONE, true),
            // A black base: the coat's mirror alone.
            plastic(Texture::Constant(Rgb::ZERO), Rgb::splat(0.9), false),
            plastic(Texture::Constant(Rgb::new(0.6, 0.6, 0.2)), Rgb::new(0.8, 0.9, 1.0), false),
            plastic(checker(), Rgb::splat(0.5), false),
        ];
        for (j, material) in coats.into_iter().enumerate() {
            materials.push(material);
            let id = materials.len() as u32 - 1;
            objects.push(object_with(Shape::Sphere(Sphere::new(centres[j], 0.25)), id));
        }
    });
    assert_same_in_lanes(
        &[(&wall, "a plastic wall among triangles"), (&spheres, "plastic spheres")],
        [(9, 0), (41, 3)],
        &[(&spheres, SamplerKind::Sobol), (&spheres, SamplerKind::Independent)],
    );
}

/// Thin glass and diffuse transmission shaded in the lanes (`ThinDielectricLanes`,
/// `DiffuseTransmissionLanes`): panes that reflect or pass light straight on (delta lobes alone:
/// no light sampled) and sheets that scatter it to both sides, constant and textured, seen from
/// both sides, one black (the path ends there); at depth limits too.
#[test]
fn the_wavefront_shades_thin_glass_and_diffuse_transmission_in_lanes() {
    use glint_core::materials::{Dielectric, DiffuseTransmission, ThinDielectric};
    let checker = |a: Rgb, b: Rgb| Texture::Checker(Box::new(Checker::new(a, b, Vec2::splat(4.0))));
    let pane = |eta: f32, transmittance: Texture| {
        Material::ThinDielectric(ThinDielectric {
            sheet: Dielectric {
                eta,
                specular_reflectance: Texture::Constant(Rgb::ONE),
                specular_transmittance: transmittance,
            },
        })
    };
    let sheet = |reflectance: Texture, transmittance: Texture| {
        Material::DiffuseTransmission(DiffuseTransmission { reflectance, transmittance })
    };
    let walls = room_where(|_, materials| {
        materials[2] = pane(1.5, Texture::Constant(Rgb::new(0.9, 0.8, 0.7)));
        materials[3] = sheet(Texture::Constant(Rgb::splat(0.4)), Texture::Constant(Rgb::new(0.3, 0.5, 0.2)));
    });
    let spheres = room_where(|objects, materials| {
        let centres = [
            Vec3::new(0.45, -0.65, 0.3),
            Vec3::new(-0.4, -0.6, 0.5),
            Vec3::new(0.1, 0.3, 0.6),
            Vec3::new(-0.5, 0.4, 0.2),
        ];
        let members = [
            pane(1.33, checker(Rgb::ONE, Rgb::new(0.2, 0.6, 0.9))),
            sheet(checker(Rgb::new(0.7, 0.2, 0.1), Rgb::ZERO), checker(Rgb::ZERO, Rgb::splat(0.6))),
            sheet(Texture::Constant(Rgb::ZERO), Texture::Constant(Rgb::ZERO)),
            pane(2.0, Texture::Constant(Rgb::ONE)),
        ];
        for (j, member) in members.into_iter().enumerate() {
            materials.push(member);
            let id = materials.len() as u32 - 1;
            objects.push(object_with(Shape::Sphere(Sphere::new(centres[j], 0.25)), id));
        }
    });
    assert_same_in_lanes(
        &[(&walls, "a pane and a sheet among triangles"), (&spheres, "panes and sheets")],
        [(10, 0), (43, 2)],
        &[(&spheres, SamplerKind::Sobol), (&walls, SamplerKind::Independent)],
    );
}

/// Rough glass shaded in the lanes (`RoughDielectricLanes`): spheres of GGX and Beckmann glass,
/// one anisotropic and textured, seen from outside and refracting from inside, a glass wall
/// among the room's triangles; η² carried into the roulette from the first bounce.
#[test]
fn the_wavefront_shades_rough_glass_in_lanes() {
    use glint_core::materials::{Dielectric, Distribution, RoughDielectric};
    let glass = |alpha_u: Texture, alpha_v: Texture, distribution: Distribution| {
        let dielectric = Dielectric {
            eta: 1.5,
            specular_reflectance: Texture::Constant(Rgb::ONE),
            specular_transmittance: Texture::Constant(Rgb::new(0.9, 0.95, 1.0)),
        };
        Material::RoughDielectric(RoughDielectric { dielectric, alpha_u, alpha_v, distribution })
    };
    let checker = || Texture::Checker(Box::new(Checker::new(Rgb::splat(0.05), Rgb::splat(0.4), Vec2::splat(4.0))));
    let spheres = room_where(|objects, materials| {
        let centres = [Vec3::new(0.45, -0.65, 0.3), Vec3::new(-0.4, -0.6, 0.5), Vec3::new(0.1, 0.3, 0.6)];
        let panes = [
            glass(0.1.into(), 0.1.into(), Distribution::Ggx),
            glass(0.3.into(), 0.3.into(), Distribution::Beckmann),
            glass(checker(), 0.2.into(), Distribution::Beckmann),
        ];
        for (j, material) in panes.into_iter().enumerate() {
            materials.push(material);
            let id = materials.len() as u32 - 1;
            objects.push(object_with(Shape::Sphere(Sphere::new(centres[j], 0.25)), id));
        }
    });
    let wall = room_where(|_, materials| materials[1] = glass(0.2.into(), 0.2.into(), Distribution::Ggx));
    let tracer = WavefrontPathTracer { tracer: PathTracer { max_depth: u32::MAX, rr_depth: 5 } };
    for (scene, what) in [(&spheres, "glass spheres"), (&wall, "a glass wall among triangles")] {
        for sampler in [SamplerKind::Independent, SamplerKind::Sobol] {
            for (seed, index) in [(8, 0), (31, 6)] {
                let lit = assert_same(scene, &tracer, sampler, seed, index);
                assert!(lit > (SIZE * SIZE / 2) as usize, "{what}: {lit} pixels lit");
            }
        }
    }
    for (max_depth, rr_depth) in [(2, 1), (u32::MAX, 0), (u32::MAX, 1)] {
        let tracer = WavefrontPathTracer { tracer: PathTracer { max_depth, rr_depth } };
        for seed in 0..2 {
            assert_same(&spheres, &tracer, SamplerKind::Sobol, seed, seed as u32);
        }
    }
}

/// Smooth conductors and glass, delta lobes alone, shaded in the lanes (`ConductorLanes`,
/// `DielectricLanes`), where the scalar code samples no light and its draws start with the
/// lobe's: a mirror wall among the room's triangles, a gold sphere with a textured colour,
/// glass spheres (refraction from outside and inside, total internal reflection, η² in the
/// roulette), beside the room's diffuse lanes; at depth limits and roulette from the first
/// bounce.
#[test]
fn the_wavefront_shades_mirrors_and_glass_in_lanes() {
    use glint_core::materials::{named_metal, Conductor, Dielectric};
    let (eta, k) = named_metal("Au").expect("gold");
    let checker =
        || Texture::Checker(Box::new(Checker::new(Rgb::splat(0.9), Rgb::new(0.6, 0.3, 0.2), Vec2::splat(4.0))));
    let gold = Material::Conductor(Conductor { eta, k, specular: checker() });
    let (eta, k) = named_metal("Ag").expect("silver");
    let mirror = Material::Conductor(Conductor { eta, k, specular: Texture::Constant(Rgb::ONE) });
    let glass = |eta: f32| {
        Material::Dielectric(Dielectric {
            eta,
            specular_reflectance: Texture::Constant(Rgb::ONE),
            specular_transmittance: Texture::Constant(Rgb::new(0.95, 0.9, 1.0)),
        })
    };
    let wall = room_where({
        let mirror = mirror.clone();
        move |_, materials| materials[1] = mirror
    });
    let spheres = room_where(move |objects, materials| {
        let centres = [Vec3::new(0.45, -0.65, 0.3), Vec3::new(-0.4, -0.6, 0.5), Vec3::new(0.1, 0.3, 0.6)];
        for (j, material) in [gold, glass(1.5), glass(1.0 / 1.33)].into_iter().enumerate() {
            materials.push(material);
            let id = materials.len() as u32 - 1;
            objects.push(object_with(Shape::Sphere(Sphere::new(centres[j], 0.25)), id));
        }
        materials[1] = mirror;
    });
    let tracer = WavefrontPathTracer { tracer: PathTracer { max_depth: u32::MAX, rr_depth: 5 } };
    for (scene, what) in [(&wall, "a mirror wall among triangles"), (&spheres, "gold, glass and a mirror")] {
        for sampler in [SamplerKind::Independent, SamplerKind::Sobol] {
            for (seed, index) in [(9, 0), (37, 2)] {
                let lit = assert_same(scene, &tracer, sampler, seed, index);
                assert!(lit > (SIZE * SIZE / 2) as usize, "{what}: {lit} pixels lit");
            }
        }
    }
    for (max_depth, rr_depth) in [(1, 5), (2, 1), (u32::MAX, 0), (u32::MAX, 1)] {
        let tracer = WavefrontPathTracer { tracer: PathTracer { max_depth, rr_depth } };
        for seed in 0..2 {
            assert_same(&spheres, &tracer, SamplerKind::Sobol, seed, seed as u32);
            assert_same(&wall, &tracer, SamplerKind::Independent, seed, seed as u32);
        }
    }
}

/// Normal and bump maps over the lanes' BSDFs, their frames tilted and their terminators
/// shadowed in the lanes (`MapShadowing`): a checkered normal map over the diffuse back wall,
/// a bump map over a metal sphere and a steep constant normal over another; a map inside a
/// map (the scalar code's) beside them.
#[test]
fn the_wavefront_tilts_frames_under_normal_and_bump_maps() {
    use glint_core::materials::{named_metal, BumpMap, Conductor, Distribution, NormalMap, RoughConductor};
    let (eta, k) = named_metal("Cu").expect("copper");
    let metal = Material::RoughConductor(RoughConductor {
        conductor: Conductor { eta, k, specular: Texture::Constant(Rgb::ONE) },
        alpha_u: 0.2.into(),
        alpha_v: 0.2.into(),
        distribution: Distribution::Beckmann,
    });
    let normals = |a: Rgb, b: Rgb| Texture::Checker(Box::new(Checker::new(a, b, Vec2::splat(6.0))));
    let normal_map =
        |normals: Texture, material: Material| Material::NormalMap(Box::new(NormalMap { normals, material }));
    let bumps = |material: Material| {
        let height = Texture::Checker(Box::new(Checker::new(Rgb::ZERO, Rgb::ONE, Vec2::splat(5.0))));
        Material::BumpMap(Box::new(BumpMap { height, scale: 0.02, material }))
    };
    let tilted = Rgb::new(0.85, 0.5, 0.6); // (0.7, 0, 0.2) before normalising: steep
    let with = |nested: bool| {
        let metal = metal.clone();
        room_where(move |objects, materials| {
            let back = materials[0].clone();
            materials.push(normal_map(normals(Rgb::new(0.5, 0.5, 1.0), Rgb::new(0.7, 0.4, 0.9)), back));
            objects[4].material = materials.len() as u32 - 1;
            objects[5].material = materials.len() as u32 - 1;
            let centres = [Vec3::new(0.45, -0.65, 0.3), Vec3::new(-0.4, -0.6, 0.5), Vec3::new(0.1, 0.3, 0.6)];
            let mut spheres = vec![bumps(metal.clone()), normal_map(Texture::Constant(tilted), metal)];
            if nested {
                spheres.push(normal_map(Texture::Constant(tilted), bumps(materials[1].clone())));
            }
            for (j, material) in spheres.into_iter().enumerate() {
                materials.push(material);
                let id = materials.len() as u32 - 1;
                objects.push(object_with(Shape::Sphere(Sphere::new(centres[j], 0.25)), id));
            }
        })
    };
    let tracer = WavefrontPathTracer { tracer: PathTracer { max_depth: u32::MAX, rr_depth: 5 } };
    for (scene, what) in [(with(false), "maps over diffuse and metal"), (with(true), "and a map in a map")] {
        for sampler in [SamplerKind::Independent, SamplerKind::Sobol] {
            for (seed, index) in [(4, 0), (23, 3)] {
                let lit = assert_same(&scene, &tracer, sampler, seed, index);
                assert!(lit > (SIZE * SIZE / 2) as usize, "{what}: {lit} pixels lit");
            }
        }
    }
}

/// Every kind of light in the lanes (an environment map sampled for the eight lanes at once,
/// the others by the scalar code lane by lane, each shadow ray
/// spawned as the scalar code spawns it): point, spot and directional lights, a constant
/// environment and a map, a sphere light, and all of them with the room's triangle lights,
/// bit for bit as one path at a time.
#[test]
fn the_wavefront_serves_every_kind_of_light() {
    use glint_core::lights::{DirectionalLight, EnvironmentMap, SpotLight};
    let tracer = WavefrontPathTracer { tracer: PathTracer { max_depth: u32::MAX, rr_depth: 5 } };
    let point = Light::Point(PointLight {
        position: Vec3::new(0.2, 0.5, 0.1),
        intensity: Rgb::splat(0.5),
        falloff: Falloff::InverseSquare,
    });
    let spot = Light::Spot(SpotLight::new(
        Vec3::new(-0.3, 0.8, 0.2),
        Vec3::new(0.2, -1.0, 0.3),
        Rgb::splat(2.0),
        Falloff::InverseSquare,
        30.0,
        8.0,
    ));
    // Through a hole: the room's front wall is gone in the scenes lit from outside.
    let sun =
        Light::Directional(DirectionalLight { direction: Vec3::new(0.1, -0.3, 1.0).normalize(), intensity: Rgb::ONE });
    let open_room = || room_where(|objects, _| drop(objects.drain(10..12)));
    let map = EnvironmentMap::new(
        8,
        4,
        (0..32).map(|i| Rgb::new(0.2 + 0.1 * (i % 8) as f32, 0.3, 0.1 * (i / 8) as f32)).collect(),
        1.0,
        glam::Mat3::IDENTITY,
    );
    let mut scenes: Vec<(Scene, &str)> = Vec::new();
    for (light, what) in [(point.clone(), "a point light"), (spot.clone(), "a spot light")] {
        let mut s = room();
        s.add_light(light);
        scenes.push((s, what));
    }
    let mut s = open_room();
    s.add_light(sun.clone());
    scenes.push((s, "a directional light"));
    let mut s = open_room();
    s.set_environment(Environment { background: Rgb::splat(0.2), ..s.environment().clone() });
    scenes.push((s, "a constant environment"));
    let mut s = open_room();
    s.set_environment(Environment { map: Some(std::sync::Arc::new(map)), ..s.environment().clone() });
    s.set_lights(vec![point, spot, sun]);
    scenes.push((s, "a map and three delta lights"));
    let sphere_light = room_where(|objects, materials| {
        materials.push(diffuse(Rgb::ZERO, Rgb::new(3.0, 2.0, 1.0), false));
        let id = materials.len() as u32 - 1;
        objects.push(object_with(Shape::Sphere(Sphere::new(Vec3::new(0.4, 0.3, 0.5), 0.15)), id));
    });
    scenes.push((sphere_light, "a sphere light"));
    for (scene, what) in &scenes {
        for sampler in [SamplerKind::Independent, SamplerKind::Sobol] {
            for (seed, index) in [(1, 0), (8, 3)] {
                let lit = assert_same(scene, &tracer, sampler, seed, index);
                assert!(lit > (SIZE * SIZE / 2) as usize, "{what}: {lit} pixels lit");
            }
        }
    }
}

/// Mitsuba's one-sided `diffuse` in the lanes: the room's materials turned into it, and some
/// walls facing away from the room, so paths land on their black backs; also as a two-sided
/// pair and inside an emitter. Bit for bit as the scalar code.
#[test]
fn the_wavefront_serves_one_sided_and_two_sided_diffuse() {
    use glint_core::materials::{Diffuse, Emitter, TwoSided};
    let tracer = WavefrontPathTracer { tracer: PathTracer { max_depth: u32::MAX, rr_depth: 3 } };
    let scene = room_where(|objects, materials| {
        for m in materials.iter_mut() {
            let Material::Phong(p) = m.clone() else { unreachable!("the room is Phong") };
            let lambert = Material::Diffuse(Diffuse { reflectance: p.diffuse.clone() });
            *m = if p.emission != Rgb::ZERO {
                let two_sided = Material::TwoSided(Box::new(TwoSided { front: lambert.clone(), back: lambert }));
                Material::Emitter(Box::new(Emitter {
                    radiance: Texture::Constant(p.emission),
                    two_sided: p.two_sided_emission,
                    surface: two_sided,
                }))
            } else {
                lambert
            };
        }
        // Turn the first two walls' triangles inside out: the room sees their backs.
        for object in objects.iter_mut().take(4) {
            if let Shape::Triangle(t) = &object.shape {
                let [a, b, c] = t.vertices;
                object.shape = Shape::Triangle(Triangle::new(a, c, b));
            }
        }
    });
    for (seed, index) in [(0, 0), (5, 2), (9, 17)] {
        assert_same(&scene, &tracer, SamplerKind::Sobol, seed, index);
    }
}

/// Textured emitters (Mitsuba's textured `radiance`): the lanes read the texture where paths
/// hit them, and light samples, which the lanes' triangle table cannot hold, come from the
/// scalar code. Bit for bit as the scalar code, and the texture shows.
#[test]
fn the_wavefront_serves_textured_emitters() {
    use glint_core::materials::{Diffuse, Emitter};
    let tracer = WavefrontPathTracer { tracer: PathTracer { max_depth: u32::MAX, rr_depth: 3 } };
    let textured = |bright: f32| {
        room_where(|_, materials| {
            for m in materials.iter_mut() {
                let Material::Phong(p) = m.clone() else { unreachable!("the room is Phong") };
                if p.emission != Rgb::ZERO {
                    let checker = Checker::new(p.emission, p.emission * bright, Vec2::splat(4.0));
                    *m = Material::Emitter(Box::new(Emitter {
                        radiance: Texture::Checker(Box::new(checker)),
                        two_sided: p.two_sided_emission,
                        surface: Material::Diffuse(Diffuse { reflectance: p.diffuse.clone() }),
                    }));
                }
            }
        })
    };
    let (plain, checkered) = (textured(1.0), textured(3.0));
    for (seed, index) in [(0, 0), (5, 2), (9, 17)] {
        assert_same(&checkered, &tracer, SamplerKind::Sobol, seed, index);
    }
    let mean = |scene: &Scene| {
        let (rays, mut contexts) = camera_samples(scene, SamplerKind::Sobol, 1, 0);
        let total: f64 = rays.iter().zip(&mut contexts).map(|(ray, c)| tracer.radiance(scene, ray, c).x as f64).sum();
        total / rays.len() as f64
    };
    assert!(mean(&checkered) > 1.2 * mean(&plain), "the brighter checks light the room");
}

/// The lamp as an emitting instance of a two-triangle mesh (placed by a shift): its triangles
/// are lights in the lanes' table, and a lane that hits it names the triangle inside the
/// instance. Bit for bit as the scalar code.
#[test]
fn the_wavefront_serves_an_emitting_instance() {
    use glint_core::accel::Geometry;
    use glint_core::geometry::Transform;
    use glint_core::shapes::Instance;
    let tracer = WavefrontPathTracer { tracer: PathTracer { max_depth: 4, rr_depth: 2 } };
    let scene = room_where(|objects, _| {
        // The room's lamp is objects 12 and 13 (its quad's triangles, material 3).
        let lamp: Vec<Object> = objects.drain(12..14).collect();
        assert!(lamp.iter().all(|o| o.material == 3));
        let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
        // A quad of unequal triangles, facing down, shifted into place.
        let positions = vec![v(-0.3, 0.0, -0.2), v(0.3, 0.0, -0.2), v(0.5, 0.0, 0.4), v(-0.3, 0.0, 0.4)];
        let mesh = Mesh { positions, indices: vec![[0, 1, 2], [0, 2, 3]], ..Mesh::default() };
        let geometry = Geometry::new(vec![object_with(Shape::Mesh(mesh), 0)], Default::default());
        let mut instance = object_with(Shape::Instance(Instance { geometry: std::sync::Arc::new(geometry) }), 3);
        instance.transform = Transform::from_matrix(glam::Mat4::from_translation(v(0.0, 0.98, 0.0)));
        objects.push(instance);
    });
    assert!(scene.lights().area_count() >= 2);
    let mut lit = 0;
    for (seed, index) in [(0, 0), (5, 2), (9, 17)] {
        lit += assert_same(&scene, &tracer, SamplerKind::Sobol, seed, index);
    }
    assert!(lit > 0, "the instance lights the room");
}
