//! Passes: what a progressive render repeats, and the tile machinery every integrator shares.
//! A pass adds one more estimate of every pixel to the film: camera integrators take one
//! camera sample per pixel (`CameraPasses`: a tile's camera rays made together and handed to
//! `Integrator::radiance_tile`); the particle integrators (light tracing, SPPM) implement
//! `PassRenderer` themselves over the same tiles (`par_tiles`). The render loop (`render.rs`)
//! runs passes; it depends on this module, never the other way round.

use std::borrow::Borrow;

use rayon::prelude::*;
use wide::f32x8;

use super::{Integrator, RayCounts, SampleContext};
use crate::film::Film;
use crate::filter::Filter;
use crate::geometry::Ray;
use crate::sampling::{Sampler, SamplerKind};
use crate::scene::Scene;
use crate::RenderError;
use crate::Rgb;

/// The side of the square image tiles, the unit of parallel work.
const TILE_SIZE: u32 = 16;

const _: () = assert!(Sampler::LANES == crate::lanes::LANES);

/// What a progressive render repeats: a pass adds one more estimate of every pixel to the
/// film. Camera integrators take one camera sample per pixel (`CameraPasses`); the particle
/// integrators (light tracing, SPPM) trace as many light paths as the image has pixels.
pub trait PassRenderer {
    /// Renders pass `pass.index`; calls `on_tile` once per image tile's worth of work.
    fn render_pass(&mut self, scene: &Scene, pass: &Pass, film: &mut Film, on_tile: &(dyn Fn() + Sync)) -> RayCounts;

    /// Renders consecutive passes, to the film `render_pass` would leave after each in turn.
    /// Box-filtered camera passes run each tile's passes in one parallel job, so that the
    /// threads wait for each other once per group rather than once per pass.
    fn render_passes(
        &mut self,
        scene: &Scene,
        passes: &[Pass],
        film: &mut Film,
        on_tile: &(dyn Fn() + Sync),
    ) -> RayCounts {
        let mut rays = RayCounts::default();
        for pass in passes {
            rays.add(&self.render_pass(scene, pass, film, on_tile));
        }
        rays
    }

    /// The render's state beyond the film, for checkpoints (SPPM's per-pixel radii, photon
    /// counts and fluxes); empty when the film holds everything.
    fn state(&self) -> Vec<u8> {
        Vec::new()
    }

    /// What the user should know about the render so far (see `Integrator::warnings`).
    fn warnings(&self) -> Vec<String> {
        Vec::new()
    }

    /// Restores what `state` saved, before resuming.
    fn restore(&mut self, state: &[u8]) -> Result<(), RenderError> {
        if state.is_empty() {
            Ok(())
        } else {
            Err(RenderError::UnexpectedState)
        }
    }
}

/// A camera integrator's passes: one sample per pixel. The integrator borrowed
/// (`&dyn Integrator`) or owned (`Box<dyn Integrator>`, one made for a scene, as photon mapping
/// is).
pub struct CameraPasses<I>(pub I);

impl<'a, I: Borrow<dyn Integrator + 'a>> PassRenderer for CameraPasses<I> {
    fn render_pass(&mut self, scene: &Scene, pass: &Pass, film: &mut Film, on_tile: &(dyn Fn() + Sync)) -> RayCounts {
        self.render_passes(scene, std::slice::from_ref(pass), film, on_tile)
    }

    fn render_passes(
        &mut self,
        scene: &Scene,
        passes: &[Pass],
        film: &mut Film,
        on_tile: &(dyn Fn() + Sync),
    ) -> RayCounts {
        camera_passes(scene, self.0.borrow(), passes, film, on_tile)
    }

    fn warnings(&self) -> Vec<String> {
        self.0.borrow().warnings()
    }
}

/// One pass of a progressive render.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pass {
    pub seed: u64,
    /// Passes done before this one (the sample index of camera samples).
    pub index: u32,
    /// Camera samples through pixel centres (a single-sample render) rather than jittered.
    pub centre: bool,
    pub filter: Filter,
    pub sampler: SamplerKind,
    /// Samples per pixel the render will take (`u32::MAX` if a time limit decides).
    pub samples: u32,
}

/// The image tiles, as (x0, y0, x1, y1): the unit of parallel work of every pass.
pub(super) fn tiles(width: u32, height: u32) -> Vec<(u32, u32, u32, u32)> {
    let (tiles_x, tiles_y) = (width.div_ceil(TILE_SIZE), height.div_ceil(TILE_SIZE));
    (0..tiles_x * tiles_y)
        .map(|tile| {
            let (x0, y0) = ((tile % tiles_x) * TILE_SIZE, (tile / tiles_x) * TILE_SIZE);
            (x0, y0, (x0 + TILE_SIZE).min(width), (y0 + TILE_SIZE).min(height))
        })
        .collect()
}

/// How many tiles a pass over a `width` × `height` image has (each reports once to a pass's
/// `on_tile`).
pub fn tile_count(width: u32, height: u32) -> u64 {
    u64::from(width.div_ceil(TILE_SIZE)) * u64::from(height.div_ceil(TILE_SIZE))
}

/// The image tiles as parallel work, one job per tile: rayon would otherwise hand out runs of
/// tiles, and a thread still busy with its last run at the end of a pass keeps the others
/// idle (5 % of a Cornell box render on two threads).
pub fn par_tiles(width: u32, height: u32) -> impl IndexedParallelIterator<Item = (u32, u32, u32, u32)> {
    tiles(width, height).into_par_iter().with_max_len(1)
}

/// A tile's camera samples: their film positions (in pixels) and radiances, in row-major
/// pixel order, and the rays they traced.
type TileResult = (Vec<(f32, f32)>, Vec<Rgb>, RayCounts);

/// Consecutive passes of one sample per pixel (sample index `pass.index`), added to the film
/// as one pass after another would: for the box filter, each into its own pixel by each tile as
/// it finishes it (tiles are disjoint, and a tile adds its passes in order, so the order of
/// additions to a pixel is the passes' order); for other filters, each tile renders a chunk of
/// the passes in one job and the chunk is then splatted to every pixel within the filter's
/// radius, by bands of rows in parallel, in the order of a serial splat of pass after pass
/// (`splat_tiles`), so that the image does not depend on the thread count.
fn camera_passes(
    scene: &Scene,
    integrator: &dyn Integrator,
    passes: &[Pass],
    film: &mut Film,
    on_tile: &(dyn Fn() + Sync),
) -> RayCounts {
    let (width, height) = (scene.camera().width, scene.camera().height);
    let render_tile = |pass: &Pass, (x0, y0, x1, y1)| -> TileResult {
        let (positions, rays, mut contexts) = camera_samples(scene, pass, (x0, y0, x1, y1));
        let mut radiance = vec![Rgb::ZERO; rays.len()];
        integrator.radiance_tile(scene, &rays, &mut contexts, &mut radiance);
        for r in &mut radiance {
            if !r.is_finite() {
                *r = Rgb::ZERO;
            }
        }
        let mut counts = RayCounts::default();
        for context in &contexts {
            counts.add(&context.rays);
        }
        (positions, radiance, counts)
    };
    let mut rays = RayCounts::default();
    if passes.iter().all(|pass| pass.filter == Filter::Box) {
        // Added in the tiles: serially after them, the additions took 2 % of a two-thread
        // render of the Cornell box.
        let bands: Vec<_> = film.bands_mut(TILE_SIZE).into_iter().map(std::sync::Mutex::new).collect();
        let counts: Vec<RayCounts> = par_tiles(width, height)
            .map(|(x0, y0, x1, y1)| {
                let mut counts = RayCounts::default();
                for pass in passes {
                    let (_, radiance, pass_counts) = render_tile(pass, (x0, y0, x1, y1));
                    let mut band = bands[(y0 / TILE_SIZE) as usize].lock().expect("no tile panicked");
                    for (i, &r) in radiance.iter().enumerate() {
                        band.add_sample(x0 + i as u32 % (x1 - x0), y0 + i as u32 / (x1 - x0), r, 1.0);
                    }
                    drop(band);
                    on_tile();
                    counts.add(&pass_counts);
                }
                counts
            })
            .collect();
        for c in &counts {
            rays.add(c);
        }
        return rays;
    }
    // The group's passes a chunk at a time: each tile renders the chunk's passes in one
    // parallel job, and the chunk's samples, held until then, are splatted pass after pass.
    // (A pass at a time, two parallel rounds per pass on a small image cost more in waking
    // the threads than the pass took.) Chunks hold at most SPLAT_CHUNK_SAMPLES samples.
    let per_chunk = (SPLAT_CHUNK_SAMPLES / (u64::from(width) * u64::from(height)).max(1)).max(1) as usize;
    for chunk in passes.chunks(per_chunk) {
        let tiles: Vec<Vec<TileResult>> = par_tiles(width, height)
            .map(|tile| {
                chunk
                    .iter()
                    .map(|pass| {
                        let result = render_tile(pass, tile);
                        on_tile();
                        result
                    })
                    .collect()
            })
            .collect();
        splat_tiles(film, chunk, &tiles);
        for (_, _, tile_rays) in tiles.iter().flatten() {
            rays.add(tile_rays);
        }
    }
    rays
}

/// The most camera samples a chunk of splatted passes holds before splatting them (20 bytes
/// each: 80 MB).
const SPLAT_CHUNK_SAMPLES: u64 = 1 << 22;

/// Passes' tiles splatted to the film (`results[tile][pass]`, tiles in `tiles` order): the
/// additions a serial splat of pass after pass, tile after tile, would make, each band of
/// rows taking its own in parallel. A pixel lies in one band, and its band visits the passes
/// in order and in each the tiles within the filter's reach in order, so each pixel receives
/// its additions in the serial order, bit for bit. (Splatted serially after the parallel
/// tiles, this was a sixth of a render of a 48² test scene.)
fn splat_tiles(film: &mut Film, passes: &[Pass], results: &[Vec<TileResult>]) {
    let (width, height) = (film.width, film.height);
    let rects = tiles(width, height);
    let bands = film.bands_mut(TILE_SIZE);
    bands.into_par_iter().with_max_len(1).for_each(|mut band| {
        let rows = band.rows();
        for (p, pass) in passes.iter().enumerate() {
            let (filter, reach) = (pass.filter, pass.filter.radius());
            let near = |&(_, y0, _, y1): &(u32, u32, u32, u32)| {
                (y0 as f32 - reach) < rows.end as f32 && (y1 as f32 + reach) > rows.start as f32
            };
            for (_, tile) in rects.iter().zip(results).filter(|(rect, _)| near(rect)) {
                let (positions, radiance, _) = &tile[p];
                for (&(fx, fy), &r) in positions.iter().zip(radiance) {
                    footprint(filter, width, rows.clone(), fx, fy, |x, y, w| band.add_sample(x, y, r, w));
                }
            }
        }
    });
}

/// Adds a sample at film position (fx, fy) to every pixel whose centre is within the radius.
pub fn splat(film: &mut Film, filter: Filter, fx: f32, fy: f32, radiance: Rgb) {
    let (width, height) = (film.width, film.height);
    footprint(filter, width, 0..height, fx, fy, |x, y, w| film.add_sample(x, y, radiance, w));
}

/// The pixels of rows `rows` (of a film `width` wide) whose centres lie within the filter's
/// radius of film position (fx, fy), row by row, each with its weight w(dx)·w(dy) (`add(x, y,
/// w)`; pixels of weight 0 skipped). The 1D weights are evaluated once per column and row.
#[inline]
fn footprint(
    filter: Filter,
    width: u32,
    rows: std::ops::Range<u32>,
    fx: f32,
    fy: f32,
    mut add: impl FnMut(u32, u32, f32),
) {
    // At most five pixels across: the widest filters' radius is 2.
    const MOST: usize = 5;
    let r = filter.radius();
    let x0 = (fx - 0.5 - r).ceil().max(0.0) as u32;
    let y0 = ((fy - 0.5 - r).ceil().max(0.0) as u32).max(rows.start);
    let x1 = ((fx - 0.5 + r).floor() as i64).min(width as i64 - 1);
    let y1 = ((fy - 0.5 + r).floor() as i64).min(rows.end as i64 - 1);
    if x1 < x0 as i64 || y1 < y0 as i64 {
        return;
    }
    let (columns, lines) = ((x1 - x0 as i64 + 1) as usize, (y1 - y0 as i64 + 1) as usize);
    debug_assert!(columns <= MOST && lines <= MOST, "a filter reaches {columns} × {lines} pixels");
    let mut wx = [0f32; MOST];
    for (i, w) in wx.iter_mut().enumerate().take(columns) {
        *w = filter.weight_1d((x0 + i as u32) as f32 + 0.5 - fx);
    }
    for j in 0..lines as u32 {
        let y = y0 + j;
        let wy = filter.weight_1d(y as f32 + 0.5 - fy);
        if wy == 0.0 {
            continue;
        }
        for (i, &w) in wx.iter().enumerate().take(columns) {
            let w = w * wy;
            if w != 0.0 {
                add(x0 + i as u32, y, w);
            }
        }
    }
}

/// Camera sample `pass.index` of pixel (x, y), as a render takes it: its ray and the context
/// its path draws the rest of its numbers from (for explaining one pixel's path).
pub fn pixel_sample(scene: &Scene, pass: &Pass, x: u32, y: u32) -> (Ray, SampleContext) {
    let (_, mut rays, mut contexts) = camera_samples(scene, pass, (x, y, x + 1, y + 1));
    (rays.remove(0), contexts.remove(0))
}

/// Camera sample `pass.index` of every pixel of a tile (x0, y0, x1, y1), row by row: the
/// film positions, the rays, and the contexts the samples draw the rest of their numbers from.
pub(super) fn camera_samples(
    scene: &Scene,
    pass: &Pass,
    (x0, y0, x1, y1): (u32, u32, u32, u32),
) -> (Vec<(f32, f32)>, Vec<Ray>, Vec<SampleContext>) {
    const GROUP: usize = Sampler::LANES;
    let mut pixels = Vec::with_capacity(((x1 - x0) * (y1 - y0)) as usize);
    for y in y0..y1 {
        pixels.extend((x0..x1).map(|x| (x, y)));
    }
    let pixel_index = |(x, y): (u32, u32)| y as u64 * scene.camera().width as u64 + x as u64;
    // Eight samplers made together (Sobol's index shuffles in SIMD lanes), the rest one by one.
    let mut contexts = Vec::with_capacity(pixels.len());
    let mut eights = pixels.chunks_exact(GROUP);
    for eight in &mut eights {
        let indices = std::array::from_fn(|k| pixel_index(eight[k]));
        let samplers = Sampler::new_eight(pass.sampler, pass.seed, indices, pass.index, pass.samples);
        contexts.extend(samplers.map(SampleContext::with_sampler));
    }
    for &pixel in eights.remainder() {
        let sampler = Sampler::new(pass.sampler, pass.seed, pixel_index(pixel), pass.index, pass.samples);
        contexts.push(SampleContext::with_sampler(sampler));
    }
    // Through the pixel centre for a single-sample render; otherwise jittered over the pixel
    // (the box filter: every sample in the pixel's square weighs the same). Eight samplers
    // draw their jitter together (Sobol's sets for eight samples in SIMD lanes), the same
    // numbers each would draw alone.
    let mut jitter = vec![(0.5, 0.5); pixels.len()];
    if !pass.centre {
        let mut groups = contexts.chunks_exact_mut(GROUP);
        for (group, offsets) in (&mut groups).zip(jitter.chunks_exact_mut(GROUP)) {
            let group: &mut [SampleContext; GROUP] = group.try_into().expect("a chunk of eight");
            let [dx, dy] = Sampler::next_f32_lanes::<2>(group.each_mut().map(|c| &mut c.sampler)).map(|v| v.to_array());
            for (k, offset) in offsets.iter_mut().enumerate() {
                *offset = (dx[k], dy[k]);
            }
        }
        let rest = groups.into_remainder();
        let first = pixels.len() - rest.len();
        for (context, offset) in rest.iter_mut().zip(&mut jitter[first..]) {
            *offset = (context.sampler.next_f32(), context.sampler.next_f32());
        }
    }
    let positions: Vec<(f32, f32)> =
        pixels.iter().zip(&jitter).map(|(&(x, y), &(dx, dy))| (x as f32 + dx, y as f32 + dy)).collect();
    // A pinhole's rays eight at a time (they draw no numbers); the rest one by one.
    let mut rays = Vec::with_capacity(positions.len());
    for eight in positions.chunks_exact(GROUP) {
        let (x, y) = (std::array::from_fn(|k| eight[k].0), std::array::from_fn(|k| eight[k].1));
        match scene.camera().pinhole_rays8(f32x8::from(x), f32x8::from(y)) {
            Some(eight_rays) => rays.extend(eight_rays),
            None => break,
        }
    }
    for (&(fx, fy), context) in positions.iter().zip(contexts.iter_mut()).skip(rays.len()) {
        rays.push(scene.camera().sample_ray(fx, fy, || context.sampler.next_f32()));
    }
    (positions, rays, contexts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{Camera, Lens};
    use crate::lights::Environment;
    use crate::scene::SceneBuilder;
    use crate::{Named, Vec3};

    /// Passes' tiles splatted by bands in parallel make the additions of a serial splat, pass
    /// after pass and tile after tile: the same sums, weights and second moments bit for bit,
    /// for every filter, on a film whose bands and tiles leave remainders (37 × 29 pixels:
    /// three bands, the last of 13 rows, and tiles of 5 and 13 pixels at the edges).
    #[test]
    fn banded_splats_equal_a_serial_splat() {
        let (width, height) = (37, 29);
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        // results[pass][tile]
        let results: Vec<Vec<TileResult>> = (0..3)
            .map(|_| {
                tiles(width, height)
                    .into_iter()
                    .map(|(x0, y0, x1, y1)| {
                        let mut positions = Vec::new();
                        let mut radiance = Vec::new();
                        for y in y0..y1 {
                            for x in x0..x1 {
                                positions.push((x as f32 + next(), y as f32 + next()));
                                radiance.push(Rgb::new(next(), 4.0 * next(), next() * next()));
                            }
                        }
                        (positions, radiance, RayCounts::default())
                    })
                    .collect()
            })
            .collect();
        for &filter in Filter::ALL {
            let mut serial = Film::new(width, height).with_second_moment();
            for (positions, radiance, _) in results.iter().flatten() {
                for (&(fx, fy), &r) in positions.iter().zip(radiance) {
                    splat(&mut serial, filter, fx, fy, r);
                }
            }
            let pass = Pass { seed: 0, index: 0, centre: false, filter, sampler: SamplerKind::Independent, samples: 3 };
            let by_tile: Vec<Vec<TileResult>> =
                (0..results[0].len()).map(|t| results.iter().map(|pass| pass[t].clone()).collect()).collect();
            let mut banded = Film::new(width, height).with_second_moment();
            splat_tiles(&mut banded, &[pass; 3], &by_tile);
            assert!(serial.accumulators() == banded.accumulators(), "{}: the sums differ", filter.name());
            assert!(serial.second_moments() == banded.second_moments(), "{}: the moments differ", filter.name());
            // And the splat reached past the tile borders (a filter wider than the box).
            assert!(serial.accumulators().1.iter().all(|&w| w > 0.0), "{}: a pixel got nothing", filter.name());
        }
    }

    /// A tile's camera samples, drawn eight samplers at a time (and a pinhole's rays made
    /// eight at a time), are what each pixel's sample draws alone: film position, ray
    /// (through a thin lens, which draws two more numbers, or a pinhole) and the sampler's
    /// state after, for every sampler kind and a tile whose pixel count leaves a remainder of
    /// the eights.
    #[test]
    fn grouped_camera_samples_equal_one_at_a_time() {
        let pinhole = Camera::new(Vec3::new(0.3, -0.2, -5.0), Vec3::new(0.1, 0.2, 0.0), Vec3::Y, 45.0, 21, 13).unwrap();
        let thin = pinhole.clone().with_lens(Lens::Thin { radius: 0.2, focus_distance: 5.0 });
        let environment = Environment { background: Rgb::ZERO, ambient_light: Rgb::ZERO, map: None };
        let tile = (16, 8, 21, 13); // 5 × 5 pixels: three eights and a remainder of one
        for (sampler, camera) in
            SamplerKind::ALL.iter().copied().flat_map(|s| [(s, thin.clone()), (s, pinhole.clone())])
        {
            let scene = SceneBuilder::new(camera).environment(environment.clone()).build();
            // Sample 70,000 is past the first 2¹⁶, where Sobol's seeds change.
            for (index, centre) in [(0, false), (5, false), (70_000, false), (0, true)] {
                let pass = Pass { seed: 3, index, centre, filter: Filter::Box, sampler, samples: 16 };
                let (positions, rays, mut contexts) = camera_samples(&scene, &pass, tile);
                assert_eq!(rays.len(), 25);
                let mut k = 0;
                for y in tile.1..tile.3 {
                    for x in tile.0..tile.2 {
                        let pixel = y as u64 * 21 + x as u64;
                        let mut alone = Sampler::new(sampler, pass.seed, pixel, index, pass.samples);
                        let (dx, dy) = if centre { (0.5, 0.5) } else { (alone.next_f32(), alone.next_f32()) };
                        let (fx, fy) = (x as f32 + dx, y as f32 + dy);
                        let ray = scene.camera().sample_ray(fx, fy, || alone.next_f32());
                        let what = format!("{sampler:?}, pass {index}, pixel ({x}, {y})");
                        assert_eq!(positions[k], (fx, fy), "{what}");
                        assert_eq!(rays[k], ray, "{what}");
                        // The same state after: the next numbers agree.
                        let next: Vec<f32> = (0..6).map(|_| contexts[k].sampler.next_f32()).collect();
                        assert_eq!(next, (0..6).map(|_| alone.next_f32()).collect::<Vec<_>>(), "{what}");
                        k += 1;
                    }
                }
            }
        }
    }
}
