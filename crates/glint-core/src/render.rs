//! The render loop: camera samples over image tiles in parallel (rayon), each pixel sample with
//! its own random stream, so the image is bit-identical for a given seed at any thread count.

use std::time::{Duration, Instant};

use rayon::prelude::*;

use crate::film::Film;
use crate::integrators::{Integrator, RayCounts, SampleContext};
use crate::sampling::Rng;
use crate::scene::Scene;
use crate::Rgb;

const TILE_SIZE: u32 = 16;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RenderSettings {
    /// Samples per pixel: 1 = through the pixel centre, more = jittered within the pixel.
    pub spp: u32,
    pub seed: u64,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self { spp: 1, seed: 0 }
    }
}

#[derive(Clone, Debug)]
pub struct RenderOutput {
    pub film: Film,
    pub rays: RayCounts,
    pub samples: u64,
    pub elapsed: Duration,
}

/// Renders the scene's camera view. `on_tile` is called once per finished tile (for progress).
pub fn render(
    scene: &Scene,
    integrator: &dyn Integrator,
    settings: &RenderSettings,
    on_tile: &(dyn Fn() + Sync),
) -> RenderOutput {
    let start = Instant::now();
    let (width, height) = (scene.camera.width, scene.camera.height);
    let tiles_x = width.div_ceil(TILE_SIZE);
    let tiles_y = height.div_ceil(TILE_SIZE);
    let tiles: Vec<(u32, u32, Vec<Rgb>, RayCounts)> = (0..tiles_x * tiles_y)
        .into_par_iter()
        .map(|tile| {
            let (x0, y0) = ((tile % tiles_x) * TILE_SIZE, (tile / tiles_x) * TILE_SIZE);
            let (x1, y1) = ((x0 + TILE_SIZE).min(width), (y0 + TILE_SIZE).min(height));
            let mut pixels = Vec::with_capacity(((x1 - x0) * (y1 - y0)) as usize);
            let mut rays = RayCounts::default();
            for y in y0..y1 {
                for x in x0..x1 {
                    pixels.push(render_pixel(scene, integrator, settings, x, y, &mut rays));
                }
            }
            on_tile();
            (x0, y0, pixels, rays)
        })
        .collect();

    let mut film = Film::new(width, height);
    let mut rays = RayCounts::default();
    for (x0, y0, pixels, tile_rays) in tiles {
        let tile_width = (x0 + TILE_SIZE).min(width) - x0;
        for (i, sum) in pixels.into_iter().enumerate() {
            let (x, y) = (x0 + i as u32 % tile_width, y0 + i as u32 / tile_width);
            film.add_sample(x, y, sum / settings.spp as f32, settings.spp as f32);
        }
        rays.add(&tile_rays);
    }
    RenderOutput { film, rays, samples: width as u64 * height as u64 * settings.spp as u64, elapsed: start.elapsed() }
}

/// Sum of the pixel's samples; the rays they traced are added to `rays`.
fn render_pixel(
    scene: &Scene,
    integrator: &dyn Integrator,
    settings: &RenderSettings,
    x: u32,
    y: u32,
    rays: &mut RayCounts,
) -> Rgb {
    let pixel_index = y as u64 * scene.camera.width as u64 + x as u64;
    let mut sum = Rgb::ZERO;
    for sample in 0..settings.spp {
        let mut context = SampleContext::new(Rng::for_sample(settings.seed, pixel_index, sample as u64));
        // One sample goes through the pixel centre; more are jittered over the pixel (box filter).
        let (dx, dy) = if settings.spp == 1 { (0.5, 0.5) } else { (context.rng.next_f32(), context.rng.next_f32()) };
        let ray = scene.camera.generate_ray(x as f32 + dx, y as f32 + dy);
        let radiance = integrator.radiance(scene, &ray, &mut context);
        sum += if radiance.is_finite() { radiance } else { Rgb::ZERO };
        rays.add(&context.rays);
    }
    sum
}
