//! Reconstruction filters: flat regions stay exact under every filter (weights are
//! normalised, even Mitchell's negative lobes), wider filters soften an edge, and the splatting
//! leaves the image independent of the thread count and of how passes are grouped.

mod common;

use common::{object_with, scene};
use glint_core::film::Film;
use glint_core::filter::Filter;
use glint_core::integrators::Raycast;
use glint_core::lights::{Environment, Falloff, Light, PointLight};
use glint_core::materials::{Material, Phong};
use glint_core::render::{render, CameraPasses, Pass, PassRenderer, RenderSettings};
use glint_core::sampling::SamplerKind;
use glint_core::shapes::{Polygon, Shape, Sphere};
use glint_core::textures::Texture;
use glint_core::Named;
use glint_core::{Rgb, Vec3};

/// A white, ambient-lit square covering the right half of the view, black background.
fn half_white() -> glint_core::scene::Scene {
    let mut s = scene(vec![object_with(Shape::Polygon(half_white_quad()), 0)]);
    s.set_materials(vec![Material::Phong(Phong {
        ambient: Some(Texture::Constant(Rgb::ONE)),
        diffuse: Texture::Constant(Rgb::ZERO),
        ..Phong::default()
    })]);
    s.set_environment(Environment { ambient_light: Rgb::ONE, background: Rgb::ZERO, ..s.environment().clone() });
    s
}

/// The right half of the view.
fn half_white_quad() -> Polygon {
    Polygon::new(vec![
        Vec3::new(-100.0, -100.0, 0.0),
        Vec3::new(0.0, -100.0, 0.0),
        Vec3::new(0.0, 100.0, 0.0),
        Vec3::new(-100.0, 100.0, 0.0),
    ])
    .unwrap()
}

fn image(s: &glint_core::scene::Scene, filter: Filter) -> Vec<Rgb> {
    render(s, &Raycast, &RenderSettings { spp: 16, seed: 1, filter, ..Default::default() }, &|| {}).film.to_rgb()
}

#[test]
fn flat_regions_are_exact_under_every_filter() {
    let mut s = half_white();
    s.set_environment(Environment { background: Rgb::splat(0.25), ..s.environment().clone() });
    s.set_objects(Vec::new());
    for &f in Filter::ALL {
        for p in image(&s, f) {
            assert!((p - Rgb::splat(0.25)).abs().max_element() < 1e-6, "{f:?}: {p}");
        }
    }
}

#[test]
fn a_wider_filter_softens_an_edge() {
    let s = half_white();
    let intermediate = |img: &[Rgb]| img.iter().filter(|p| p.x > 0.02 && p.x < 0.98).count();
    let (b, t) = (intermediate(&image(&s, Filter::Box)), intermediate(&image(&s, Filter::Tent)));
    assert!(t > b, "tent {t} vs box {b} soft pixels");
    // Both keep the two halves apart: the left and right columns stay black and white.
    let img = image(&s, Filter::Gaussian);
    assert!(img[0].x < 1e-6 && img[15].x > 1.0 - 1e-6, "{} {}", img[0], img[15]);
}

#[test]
fn filtered_images_do_not_depend_on_the_thread_count() {
    let s = half_white();
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| image(&s, Filter::Mitchell))
    };
    assert_eq!(run(1), run(2));
}

/// The render loop runs passes in groups (each tile's passes in one parallel job): the film
/// equals that of passes one at a time, bit for bit, for the box filter (added by the tiles)
/// and for a splatting one.
#[test]
fn passes_in_groups_equal_passes_one_at_a_time() {
    // A sphere in front of the half-white square, lit by a point light: shading that varies
    // from sample to sample, so that sums in another order would differ in their last bits.
    let mut s = half_white();
    s.set_objects(vec![
        object_with(Shape::Polygon(half_white_quad()), 0),
        object_with(Shape::Sphere(Sphere::new(Vec3::new(0.0, 0.0, -1.0), 0.6)), 1),
    ]);
    let mut materials = s.materials().to_vec();
    materials.push(Material::Phong(Phong { diffuse: Texture::Constant(Rgb::new(0.8, 0.5, 0.3)), ..Phong::default() }));
    s.set_materials(materials);
    s.add_light(Light::Point(PointLight {
        position: Vec3::new(1.0, 2.0, -4.0),
        intensity: Rgb::splat(20.0),
        falloff: Falloff::InverseSquare,
    }));
    let spp = 21;
    let raycast: &dyn glint_core::integrators::Integrator = &Raycast;
    let pass =
        |index, filter| Pass { seed: 5, index, centre: false, filter, sampler: SamplerKind::Sobol, samples: spp };
    for filter in [Filter::Box, Filter::Mitchell] {
        let film = || Film::new(s.camera().width, s.camera().height);
        let (mut grouped, mut one_by_one) = (film(), film());
        for group in [0..1, 1..8, 8..spp] {
            let passes: Vec<Pass> = group.map(|index| pass(index, filter)).collect();
            CameraPasses(raycast).render_passes(&s, &passes, &mut grouped, &|| {});
        }
        for index in 0..spp {
            CameraPasses(raycast).render_pass(&s, &pass(index, filter), &mut one_by_one, &|| {});
        }
        let (a, b) = (grouped.accumulators(), one_by_one.accumulators());
        assert!(a.0.iter().any(|p| p.x > 0.0 && p.x < spp as f32 * 0.9), "{filter:?}: no shaded pixels");
        let bits = |sums: &[Rgb]| sums.iter().map(|p| p.to_array().map(f32::to_bits)).collect::<Vec<_>>();
        assert_eq!(bits(a.0), bits(b.0), "{filter:?}: sums");
        assert_eq!(a.1, b.1, "{filter:?}: weights");
    }
    // And the render loop, which groups passes by their time, gives the same film.
    let settings = RenderSettings { spp, seed: 5, filter: Filter::Box, sampler: SamplerKind::Sobol };
    let rendered = render(&s, &Raycast, &settings, &|| {}).film;
    let mut one_by_one = Film::new(s.camera().width, s.camera().height);
    for index in 0..spp {
        CameraPasses(raycast).render_pass(&s, &pass(index, Filter::Box), &mut one_by_one, &|| {});
    }
    assert_eq!(rendered.accumulators().0, one_by_one.accumulators().0);
}
