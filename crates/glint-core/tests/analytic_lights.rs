//! Lights over a Lambertian floor (albedo ρ), where the floor's radiance is known in closed
//! form; direct light only (`max_depth` 1). The path tracer (lights sampled, with MIS) and the
//! naive one (lights found only by hitting them) must both match it.
//!
//! * A sphere of radiance L and radius r whose centre is at height h: below it the irradiance
//!   is E = π L r²/h² (the cap it subtends, cosine-weighted), so L_o = ρ L r²/h². Shadow rays
//!   that ended on the sphere's surface found it a few ulps early and were blocked 2 % of the
//!   time, which this caught: `SurfaceHit::spawn_ray_to_surface`.
//! * A quad light (two triangles), off-centre: Lambert's formula for a polygonal luminaire,
//!   E = (L/2) Σ θᵢ (n · γᵢ) over its edges, for both triangle-light sampling strategies.
//! * An L-shaped polygon light and a box light under a transform, each one light sampled by
//!   area: the same formula, over the box's faces that face the floor point.
//! * Point, spot and directional lights, off to the side: E = I cos θ / d², and E⊥ cos θ for
//!   the directional one (the path tracer only: no path can hit them).
//! * All of these at once, the sphere placed by a transform: the sum, though next-event
//!   estimation now samples one light per bounce, chosen by power.
//! * The floor beside a sphere light and an L-shaped polygon light, for the particle
//!   integrators, which start at the light: a sphere fully above a plane lights it as a point
//!   would, E = π L r² cos θ / D², D the distance to its centre; the polygon by Lambert's
//!   formula at each pixel's floor point.

mod common;

use common::{object_with, scene};
use glam::Mat4;
use glint_core::accel::Geometry;
use glint_core::camera::Camera;
use glint_core::geometry::Transform;
use glint_core::integrators::{IntegratorKind, IntegratorSettings};
use glint_core::lights::{DirectionalLight, Falloff, Light, PointLight, SpotLight, TriangleSampling};
use glint_core::materials::{Emitter, Material, Phong};
use glint_core::render::{render_with, RenderSettings};
use glint_core::scene::Scene;
use glint_core::shapes::{AaBox, Instance, Mesh, Plane, Polygon, Shape, Sphere, Triangle};
use glint_core::textures::{Checker, Texture};
use glint_core::{Rgb, Vec2, Vec3};

#[test]
fn a_floor_under_a_spherical_light_has_the_analytic_radiance() {
    let (radiance, radius, height, albedo) = (4.0f32, 0.5f32, 2.0f32, 0.5f32);
    let mut s = scene(vec![
        object_with(Shape::Plane(Plane::new(Vec3::Y, 0.0)), 0),
        object_with(Shape::Sphere(Sphere::new(Vec3::new(0.0, height, 0.0), radius)), 1),
    ]);
    s.set_materials(vec![material(albedo, 0.0), material(0.0, radiance)]);
    // A narrow view of the floor point below the centre, from the side, under the sphere.
    s.set_camera(Camera::new(Vec3::new(0.0, 1.0, -2.0), Vec3::ZERO, Vec3::Y, 0.2, 8, 8).unwrap());
    let expected = (albedo * radiance * radius * radius / (height * height)) as f64;

    // The path tracer to 0.2 %, not to its own standard error: blocked shadow rays would
    // widen that as they darken the image.
    check_image_mean(&s, IntegratorKind::Path, 64, expected, Some(0.002), "sphere light, path");
    check_image_mean(&s, IntegratorKind::PathNaive, 1024, expected, None, "sphere light, path-naive");
}

#[test]
fn a_floor_under_a_quad_light_matches_lamberts_formula() {
    let (radiance, albedo) = (3.0f32, 0.5f32);
    // Off-centre above the origin, facing down (one-sided): (b − a) × (c − a) points along −y.
    let quad =
        [Vec3::new(-0.5, 1.0, -0.2), Vec3::new(0.3, 1.0, -0.2), Vec3::new(0.3, 1.0, 0.6), Vec3::new(-0.5, 1.0, 0.6)];
    let mut s = scene(vec![
        object_with(Shape::Plane(Plane::new(Vec3::Y, 0.0)), 0),
        object_with(Shape::Triangle(Triangle::new(quad[0], quad[1], quad[2])), 1),
        object_with(Shape::Triangle(Triangle::new(quad[0], quad[2], quad[3])), 1),
    ]);
    s.set_materials(vec![material(albedo, 0.0), material(0.0, radiance)]);
    s.set_camera(Camera::new(Vec3::new(0.0, 0.5, -2.0), Vec3::ZERO, Vec3::Y, 0.2, 8, 8).unwrap());
    let expected = albedo as f64 / std::f64::consts::PI * lambert_irradiance(radiance as f64, &quad);
    for strategy in [TriangleSampling::Area, TriangleSampling::SolidAngle] {
        s.set_triangle_sampling(strategy);
        check_image_mean(&s, IntegratorKind::Path, 64, expected, None, &format!("quad light, path, {strategy:?}"));
    }
    check_image_mean(&s, IntegratorKind::PathNaive, 1024, expected, None, "quad light, path-naive");
}

/// Polygon and box lights are sampled as one light each: an L-shaped polygon (not convex, so
/// cut into triangles of unequal area) and a box turned and lifted by a transform, whose
/// faces that face the floor point each add their Lambert term.
#[test]
fn a_floor_under_polygon_and_box_lights_matches_lamberts_formula() {
    let (radiance, albedo) = (3.0f32, 0.5f32);
    let floor = || object_with(Shape::Plane(Plane::new(Vec3::Y, 0.0)), 0);
    let camera = || Camera::new(Vec3::new(0.0, 0.5, -2.0), Vec3::ZERO, Vec3::Y, 0.2, 8, 8).unwrap();
    let check = |s: &mut Scene, irradiance: f64, name: &str| {
        s.set_materials(vec![material(albedo, 0.0), material(0.0, radiance)]);
        s.set_camera(camera());
        let expected = albedo as f64 / std::f64::consts::PI * irradiance;
        assert_eq!(s.lights().area_count(), 1, "{name}: one light");
        check_image_mean(s, IntegratorKind::Path, 64, expected, None, &format!("{name}, path"));
        check_image_mean(s, IntegratorKind::PathNaive, 1024, expected, None, &format!("{name}, path-naive"));
    };

    // Wound like the quad above, so it faces down.
    let l_shape: Vec<Vec3> = [(-0.5, -0.2), (0.3, -0.2), (0.3, 0.2), (0.0, 0.2), (0.0, 0.6), (-0.5, 0.6)]
        .map(|(x, z)| Vec3::new(x, 1.0, z))
        .to_vec();
    let polygon = Polygon::new(l_shape.clone()).unwrap();
    assert!(polygon.normal().y < 0.0, "the polygon faces the floor");
    let mut s = scene(vec![floor(), object_with(Shape::Polygon(polygon), 1)]);
    check(&mut s, lambert_irradiance(radiance as f64, &l_shape), "L-shaped polygon light");

    let (min, max) = (Vec3::new(-0.4, 0.0, -0.3), Vec3::new(0.4, 0.3, 0.5));
    let placed = Mat4::from_translation(Vec3::new(0.1, 1.0, 0.0)) * Mat4::from_rotation_y(0.5);
    let mut aabox = object_with(Shape::AaBox(AaBox::new(min, max)), 1);
    aabox.transform = Transform::from_matrix(placed);
    let mut irradiance = 0.0;
    for axis in 0..3 {
        for (level, outward) in [(min[axis], -1.0), (max[axis], 1.0)] {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let corner = |cu: f32, cv: f32| {
                let mut p = Vec3::ZERO;
                (p[axis], p[u], p[v]) = (level, cu, cv);
                placed.transform_point3(p)
            };
            let face = [corner(min[u], min[v]), corner(max[u], min[v]), corner(max[u], max[v]), corner(min[u], max[v])];
            let mut normal = Vec3::ZERO;
            normal[axis] = outward;
            if placed.transform_vector3(normal).dot(-face[0]) > 0.0 {
                irradiance += lambert_irradiance(radiance as f64, &face);
            }
        }
    }
    let mut s = scene(vec![floor(), aabox]);
    check(&mut s, irradiance, "turned box light");
}

/// A light whose radiance is a texture: a checker of two cells across u, so the quad's two
/// halves shine at L₀ and L₁ and the irradiance is Lambert's formula over each half. As a
/// mesh (its triangles sampled by area, uv by barycentrics) and as a polygon (one light, uv
/// bilinear over its corners), as an instance of the mesh, under the path tracers and light
/// tracing, whose particles start with the texture's radiance where they leave.
#[test]
fn a_floor_under_a_textured_quad_light_matches_lamberts_formula_over_each_half() {
    let (dim, bright, albedo) = (1.0f32, 5.0f32, 0.5f32);
    // Facing down, u along +x: the halves are x < −0.1 (dim) and x > −0.1 (bright).
    let quad =
        [Vec3::new(-0.5, 1.0, -0.2), Vec3::new(0.3, 1.0, -0.2), Vec3::new(0.3, 1.0, 0.6), Vec3::new(-0.5, 1.0, 0.6)];
    let uvs = vec![Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0), Vec2::new(1.0, 1.0), Vec2::new(0.0, 1.0)];
    let middle = |z: f32| Vec3::new(-0.1, 1.0, z);
    let halves =
        [(dim, [quad[0], middle(-0.2), middle(0.6), quad[3]]), (bright, [middle(-0.2), quad[1], quad[2], middle(0.6)])];
    let irradiance_at =
        |at: Vec3| -> f64 { halves.iter().map(|(l, half)| lambert_irradiance(*l as f64, &half.map(|v| v - at))).sum() };
    let mesh = Mesh {
        positions: quad.to_vec(),
        uvs: Some(uvs.clone()),
        indices: vec![[0, 1, 2], [0, 2, 3]],
        ..Mesh::default()
    };
    let polygon = Polygon::new(quad.to_vec()).unwrap().with_uvs(uvs).unwrap();
    let checker = Texture::Checker(Box::new(Checker::new(Rgb::splat(dim), Rgb::splat(bright), Vec2::new(2.0, 1.0))));
    let lamp =
        Material::Emitter(Box::new(Emitter { radiance: checker, two_sided: false, surface: material(0.0, 0.0) }));
    let instanced = Geometry::new(vec![object_with(Shape::Mesh(mesh.clone()), 0)], Default::default());
    let instance = Shape::Instance(Instance { geometry: std::sync::Arc::new(instanced) });
    for (name, light) in [("mesh", Shape::Mesh(mesh)), ("polygon", Shape::Polygon(polygon)), ("instance", instance)] {
        let mut s = scene(vec![object_with(Shape::Plane(Plane::new(Vec3::Y, 0.0)), 0), object_with(light, 1)]);
        s.set_materials(vec![material(albedo, 0.0), lamp.clone()]);
        s.set_camera(Camera::new(Vec3::new(0.0, 0.5, -2.0), Vec3::ZERO, Vec3::Y, 0.2, 8, 8).unwrap());
        let expected = albedo as f64 / std::f64::consts::PI * irradiance_at(Vec3::ZERO);
        check_image_mean(&s, IntegratorKind::Path, 64, expected, None, &format!("textured {name} light, path"));
        check_image_mean(&s, IntegratorKind::PathNaive, 1024, expected, None, &format!("textured {name} light, naive"));

        // Light tracing, over a wide view of the floor beside the light (out of view).
        s.set_camera(Camera::new(Vec3::new(1.2, 2.5, -2.0), Vec3::new(1.2, 0.0, 0.6), Vec3::Y, 20.0, 16, 16).unwrap());
        let expected = floor_mean(&s, |at| albedo as f64 / std::f64::consts::PI * irradiance_at(at));
        let mean = light_tracing_mean(&s, 4096);
        assert!((mean / expected - 1.0).abs() < 0.005, "textured {name} light, light tracing: {mean} vs {expected}");
    }
}

/// An emitting instance is a light of its mesh's triangles, placed by the instance's
/// transform (turned and scaled here): Lambert's formula over its corners where they land,
/// under the path tracers (the light sampled, and found by BSDF paths through the instance's
/// inner primitive) and light tracing.
#[test]
fn a_floor_under_an_instanced_quad_light_matches_lamberts_formula() {
    let (radiance, albedo) = (3.0f32, 0.5f32);
    // A quad facing down in its own space (its two triangles of unequal area, so a light
    // sample and a hit must agree on which is which), turned, stretched and lifted.
    let local =
        [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.6, 0.0, 1.0), Vec3::new(0.0, 0.0, 1.0)];
    let placed = Mat4::from_translation(Vec3::new(-0.4, 1.0, -0.3))
        * Mat4::from_rotation_y(0.4)
        * Mat4::from_scale(Vec3::new(0.8, 1.0, 0.7));
    let corners = local.map(|p| placed.transform_point3(p));
    let mesh = Mesh { positions: local.to_vec(), indices: vec![[0, 1, 2], [0, 2, 3]], ..Mesh::default() };
    let geometry = Geometry::new(vec![object_with(Shape::Mesh(mesh), 0)], Default::default());
    let mut instance = object_with(Shape::Instance(Instance { geometry: std::sync::Arc::new(geometry) }), 1);
    instance.transform = Transform::from_matrix(placed);
    let mut s = scene(vec![object_with(Shape::Plane(Plane::new(Vec3::Y, 0.0)), 0), instance]);
    s.set_materials(vec![material(albedo, 0.0), material(0.0, radiance)]);
    assert_eq!(s.lights().area_count(), 2, "the instance's two triangles");
    // A hit names the triangle inside the instance (the light's own index within it): the
    // centroid of each triangle, seen from below.
    for (prim, [a, b, c]) in [[0, 1, 2], [0, 2, 3]].into_iter().enumerate() {
        let centroid = (corners[a] + corners[b] + corners[c]) / 3.0;
        let hit = s.intersect(&glint_core::geometry::Ray::new(centroid - Vec3::Y, Vec3::Y)).expect("the light");
        assert_eq!((hit.object, hit.prim), (1, prim as u32));
    }
    s.set_camera(Camera::new(Vec3::new(0.0, 0.5, -2.0), Vec3::ZERO, Vec3::Y, 0.2, 8, 8).unwrap());
    let expected = albedo as f64 / std::f64::consts::PI * lambert_irradiance(radiance as f64, &corners);
    // By solid angle, a light sample's density depends on which triangle it is: a path that
    // hits the instance must name the same one for its MIS weight.
    for strategy in [TriangleSampling::Area, TriangleSampling::SolidAngle] {
        s.set_triangle_sampling(strategy);
        check_image_mean(
            &s,
            IntegratorKind::Path,
            64,
            expected,
            None,
            &format!("instanced quad light, path, {strategy:?}"),
        );
    }
    check_image_mean(&s, IntegratorKind::PathNaive, 1024, expected, None, "instanced quad light, path-naive");
    // Light tracing over the floor beside it.
    s.set_camera(Camera::new(Vec3::new(1.8, 2.5, -2.0), Vec3::new(1.8, 0.0, 0.6), Vec3::Y, 20.0, 16, 16).unwrap());
    let expected = floor_mean(&s, |at| {
        albedo as f64 / std::f64::consts::PI * lambert_irradiance(radiance as f64, &corners.map(|c| c - at))
    });
    let mean = light_tracing_mean(&s, 16384);
    assert!((mean / expected - 1.0).abs() < 0.005, "instanced light, light tracing: {mean} vs {expected}");
}

#[test]
fn a_floor_under_delta_lights_gets_their_analytic_irradiance() {
    let (intensity, albedo, at) = (2.0f32, 0.5f32, Vec3::new(0.6, 1.5, 0.3));
    let d2 = at.length_squared() as f64;
    let cos = at.y as f64 / d2.sqrt();
    let point = PointLight { position: at, intensity: Rgb::splat(intensity), falloff: Falloff::InverseSquare };
    let lights = [
        // I cos θ / d².
        ("point", Light::Point(point.clone()), intensity as f64 * cos / d2),
        // The same inside its cone: the origin lies on the axis, 25° from the soft edge.
        (
            "spot",
            Light::Spot(SpotLight::new(at, -at, point.intensity, Falloff::InverseSquare, 30.0, 5.0)),
            intensity as f64 * cos / d2,
        ),
        // `intensity` is the irradiance across the beam: E = E⊥ cos θ.
        (
            "directional",
            Light::Directional(DirectionalLight { direction: -at.normalize(), intensity: point.intensity }),
            intensity as f64 * cos,
        ),
    ];
    for (name, light, irradiance) in lights {
        let mut s = scene(vec![object_with(Shape::Plane(Plane::new(Vec3::Y, 0.0)), 0)]);
        s.set_materials(vec![material(albedo, 0.0)]);
        s.set_lights(vec![light]);
        s.set_camera(Camera::new(Vec3::new(0.0, 0.5, -2.0), Vec3::ZERO, Vec3::Y, 0.2, 8, 8).unwrap());
        let expected = albedo as f64 / std::f64::consts::PI * irradiance;
        check_image_mean(&s, IntegratorKind::Path, 16, expected, None, &format!("{name} light, path"));
    }
}

#[test]
fn a_floor_under_every_kind_of_light_at_once_gets_the_sum() {
    let (intensity, albedo, at) = (2.0f32, 0.5f32, Vec3::new(0.6, 1.5, 0.3));
    let (d2, cos) = (at.length_squared() as f64, at.normalize().y as f64);
    let point = PointLight { position: at, intensity: Rgb::splat(intensity), falloff: Falloff::InverseSquare };
    let spot = SpotLight::new(at, -at, point.intensity, Falloff::InverseSquare, 30.0, 5.0);
    let sun = DirectionalLight { direction: -at.normalize(), intensity: point.intensity };
    // A sphere of radius 0.25 scaled to 0.5 and lifted to height 2: E = π L r² / h². The
    // delta lights' shadow rays pass it 0.8 from its centre.
    let (radiance, radius, height) = (4.0f64, 0.5f64, 2.0f64);
    let lifted =
        Transform::from_matrix(Mat4::from_translation(Vec3::new(0.0, 2.0, 0.0)) * Mat4::from_scale(Vec3::splat(2.0)));
    let mut sphere = object_with(Shape::Sphere(Sphere::new(Vec3::ZERO, 0.25)), 1);
    sphere.transform = lifted;
    let mut s = scene(vec![object_with(Shape::Plane(Plane::new(Vec3::Y, 0.0)), 0), sphere]);
    s.set_materials(vec![material(albedo, 0.0), material(0.0, radiance as f32)]);
    s.set_lights(vec![Light::Point(point), Light::Spot(spot), Light::Directional(sun)]);
    s.set_camera(Camera::new(Vec3::new(0.0, 0.5, -2.0), Vec3::ZERO, Vec3::Y, 0.2, 8, 8).unwrap());
    let irradiance = 2.0 * intensity as f64 * cos / d2
        + intensity as f64 * cos
        + std::f64::consts::PI * radiance * radius * radius / (height * height);
    let expected = albedo as f64 / std::f64::consts::PI * irradiance;
    check_image_mean(&s, IntegratorKind::Path, 256, expected, None, "every kind of light, path");
}

#[test]
fn particle_integrators_light_the_floor_beside_sphere_and_polygon_lights_as_expected() {
    let (radiance, radius, centre, albedo) = (4.0f32, 0.3f32, Vec3::new(0.0, 1.0, 0.0), 0.5f32);
    // Facing down, as in the polygon test above.
    let l_shape: Vec<Vec3> = [(-0.5, -0.2), (0.3, -0.2), (0.3, 0.2), (0.0, 0.2), (0.0, 0.6), (-0.5, 0.6)]
        .map(|(x, z)| Vec3::new(x, 1.0, z))
        .to_vec();
    let lights = [
        ("sphere", Shape::Sphere(Sphere::new(centre, radius))),
        ("polygon", Shape::Polygon(Polygon::new(l_shape.clone()).unwrap())),
    ];
    for (name, light) in lights {
        let mut s = scene(vec![object_with(Shape::Plane(Plane::new(Vec3::Y, 0.0)), 0), object_with(light, 1)]);
        s.set_materials(vec![material(albedo, 0.0), material(0.0, radiance)]);
        // The floor from 0.5 to 2 beside the light, the light itself out of view.
        s.set_camera(Camera::new(Vec3::new(1.2, 2.5, -2.0), Vec3::new(1.2, 0.0, 0.6), Vec3::Y, 20.0, 24, 24).unwrap());
        // Per pixel, the radiance at the floor point through its centre (the irradiance
        // varies slowly over a pixel's footprint, a few hundredths across).
        let expected: Vec<f64> = (0..24 * 24)
            .map(|i| {
                let ray = s.camera().generate_ray((i % 24) as f32 + 0.5, (i / 24) as f32 + 0.5);
                let hit = s.intersect(&ray).expect("every pixel sees the floor");
                assert_eq!(hit.object, 0, "the {name} is out of view");
                let at = hit.geometry.point;
                let irradiance = if name == "sphere" {
                    // A sphere fully above the plane lights it as a point would.
                    let to_centre = (centre - at).as_dvec3();
                    let (d2, cos) = (to_centre.length_squared(), to_centre.normalize().y);
                    std::f64::consts::PI * radiance as f64 * (radius * radius) as f64 * cos / d2
                } else {
                    let seen: Vec<Vec3> = l_shape.iter().map(|&v| v - at).collect();
                    lambert_irradiance(radiance as f64, &seen)
                };
                albedo as f64 / std::f64::consts::PI * irradiance
            })
            .collect();
        let expected_mean = expected.iter().sum::<f64>() / expected.len() as f64;
        // Light tracing is unbiased (two seeds came within 0.15 %); SPPM is consistent, its
        // bias shrinking with the radius (two seeds within 0.05 %).
        for (kind, passes, tolerance) in [(IntegratorKind::Light, 4096, 0.005), (IntegratorKind::Sppm, 64, 0.01)] {
            let settings = IntegratorSettings { max_depth: 1, ..Default::default() };
            let mut renderer = kind.renderer(&settings, &s, 1).expect("a physical light");
            let image = render_with(
                &s,
                renderer.as_mut(),
                &RenderSettings { spp: passes, seed: 4, ..Default::default() },
                &|| {},
            )
            .film
            .to_rgb();
            let mean = image.iter().map(|p| p.x as f64).sum::<f64>() / image.len() as f64;
            assert!((mean / expected_mean - 1.0).abs() < tolerance, "{name}, {kind:?}: {mean} vs {expected_mean}");
        }
    }
}

/// The mean over the camera's pixels of `radiance_at` the floor point through each pixel's
/// centre (the floor is object 0 and every pixel sees it: the light is out of view).
fn floor_mean(s: &Scene, radiance_at: impl Fn(Vec3) -> f64) -> f64 {
    let (w, h) = (s.camera().width, s.camera().height);
    let total: f64 = (0..w * h)
        .map(|i| {
            let ray = s.camera().generate_ray((i % w) as f32 + 0.5, (i / w) as f32 + 0.5);
            let hit = s.intersect(&ray).expect("every pixel sees the floor");
            assert_eq!(hit.object, 0, "the light is out of view");
            radiance_at(hit.geometry.point)
        })
        .sum();
    total / (w * h) as f64
}

/// The image mean of light tracing's direct light (seed 4) at `spp` passes.
fn light_tracing_mean(s: &Scene, spp: u32) -> f64 {
    let settings = IntegratorSettings { max_depth: 1, ..Default::default() };
    let mut renderer = IntegratorKind::Light.renderer(&settings, s, 1).expect("a physical light");
    let image =
        render_with(s, renderer.as_mut(), &RenderSettings { spp, seed: 4, ..Default::default() }, &|| {}).film.to_rgb();
    image.iter().map(|p| p.x as f64).sum::<f64>() / image.len() as f64
}

/// Lambert (1760): the irradiance at the origin on the floor (normal +y) from a polygon of
/// radiance L that the origin sees whole, E = (L/2) |Σ θᵢ (n · γᵢ)| over its edges, θᵢ the
/// angle the edge i subtends and γᵢ the unit normal of the plane through the origin and it.
fn lambert_irradiance(radiance: f64, polygon: &[Vec3]) -> f64 {
    let corners: Vec<_> = polygon.iter().map(|v| v.as_dvec3().normalize()).collect();
    let sum: f64 = (0..corners.len())
        .map(|i| {
            let (u, v) = (corners[i], corners[(i + 1) % corners.len()]);
            u.angle_between(v) * u.cross(v).normalize().y
        })
        .sum();
    radiance / 2.0 * sum.abs()
}

fn material(diffuse: f32, emission: f32) -> Material {
    Material::Phong(Phong {
        diffuse: Texture::Constant(Rgb::splat(diffuse)),
        ambient: Some(Texture::Constant(Rgb::ZERO)),
        emission: Rgb::splat(emission),
        ..Phong::default()
    })
}

/// Renders direct light only and checks the image mean against `expected`: within
/// `relative` of it if given, else within 4 standard errors of the pixel mean plus 10⁻³ for
/// the pixels' floor points, at most 0.01 from the origin.
fn check_image_mean(s: &Scene, kind: IntegratorKind, spp: u32, expected: f64, relative: Option<f64>, name: &str) {
    let settings = IntegratorSettings { max_depth: 1, rr_depth: 5, ..Default::default() };
    let mut renderer = kind.renderer(&settings, s, 1).expect("a camera integrator");
    let image =
        render_with(s, renderer.as_mut(), &RenderSettings { spp, seed: 9, ..Default::default() }, &|| {}).film.to_rgb();
    let values: Vec<f64> = image.iter().map(|p| p.x as f64).collect();
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let standard_error = (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt();
    let tolerance = relative.map_or(4.0 * standard_error + 1e-3 * expected, |r| r * expected);
    assert!((mean - expected).abs() < tolerance, "{name}: {mean} vs {expected} (± {standard_error})");
}
