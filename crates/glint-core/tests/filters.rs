//! Reconstruction filters: flat regions stay exact under every filter (weights are
//! normalised, even Mitchell's negative lobes), wider filters soften an edge, and the splatting
//! leaves the image independent of the thread count.

mod common;

use common::{object_with, scene};
use glint_core::filter::Filter;
use glint_core::integrators::Raycast;
use glint_core::materials::{Material, Phong};
use glint_core::render::{render, RenderSettings};
use glint_core::shapes::{Polygon, Shape};
use glint_core::textures::Texture;
use glint_core::{Rgb, Vec3};

/// A white, ambient-lit square covering the right half of the view, black background.
fn half_white() -> glint_core::scene::Scene {
    let quad = Polygon::new(vec![
        Vec3::new(-100.0, -100.0, 0.0),
        Vec3::new(0.0, -100.0, 0.0),
        Vec3::new(0.0, 100.0, 0.0),
        Vec3::new(-100.0, 100.0, 0.0),
    ])
    .unwrap();
    let mut s = scene(vec![object_with(Shape::Polygon(quad), 0)]);
    s.materials = vec![Material::Phong(Phong {
        ambient: Some(Texture::Constant(Rgb::ONE)),
        diffuse: Texture::Constant(Rgb::ZERO),
        ..Phong::default()
    })];
    s.environment.ambient_light = Rgb::ONE;
    s.environment.background = Rgb::ZERO;
    s
}

fn image(s: &glint_core::scene::Scene, filter: Filter) -> Vec<Rgb> {
    render(s, &Raycast, &RenderSettings { spp: 16, seed: 1, filter, ..Default::default() }, &|| {}).film.to_rgb()
}

#[test]
fn flat_regions_are_exact_under_every_filter() {
    let mut s = half_white();
    s.environment.background = Rgb::splat(0.25);
    s.geometry = glint_core::scene::Geometry::new(Vec::new(), Default::default());
    for f in Filter::ALL {
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
