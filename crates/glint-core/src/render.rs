//! The render loop: progressive passes of camera samples over image tiles in parallel (rayon).
//! Every pixel sample draws from its own random stream, seeded by (seed, pixel, sample index),
//! so the image is bit-identical for a given seed at any thread count, and a render resumed
//! from a checkpoint equals an uninterrupted one (the pass boundaries are the same).
//!
//! A render ends when the target sample count is reached, when its time limit is spent, or
//! when the caller raises the stop flag (Ctrl-C); it always ends between passes, so what has
//! been rendered is complete and kept. Passes run in groups of about `GROUP_TIME` (with the box
//! filter, each tile's passes of a group in one parallel job, so that the threads wait for
//! each other once per group), and the stop flag and time limit are checked between groups.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crate::film::Film;
use crate::filter::Filter;
pub use crate::integrators::passes::{par_tiles, splat, tile_count, CameraPasses, Pass, PassRenderer};
use crate::integrators::{Integrator, RayCounts};
use crate::sampling::SamplerKind;
use crate::scene::Scene;

/// About how long a group of passes takes: the stop flag and the time limit are checked and
/// checkpoints may be saved between groups.
const GROUP_TIME: f64 = 0.2;
/// The most passes in a group.
const MAX_GROUP: u32 = 16;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RenderSettings {
    /// Samples per pixel: 1 = through the pixel centre; more = jittered within the pixel.
    pub spp: u32,
    pub seed: u64,
    pub filter: Filter,
    pub sampler: SamplerKind,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self { spp: 1, seed: 0, filter: Filter::Box, sampler: SamplerKind::default() }
    }
}

/// How a progressive render runs: to `settings.spp` samples per pixel, and no longer than
/// `time_limit` (then `settings.spp` is only an upper bound).
#[derive(Clone, Copy, Debug)]
pub struct Progressive {
    pub settings: RenderSettings,
    pub time_limit: Option<Duration>,
    /// Keep each pixel's second moment in the film (`Film::second_moments`): camera
    /// integrators only, whose samples each land in the film.
    pub second_moment: bool,
    /// Render samples `a..b` of every pixel alone (`settings.spp` is then ignored), as one part
    /// of a render split by sample range: the film keeps exact sums (`ExactPixel`), and the
    /// samples are those of the open-ended sequence (jittered, no stratum count), so parts
    /// merged give one render of their union bit for bit.
    pub sample_range: Option<(u32, u32)>,
}

#[derive(Clone, Debug)]
pub struct RenderOutput {
    pub film: Film,
    pub rays: RayCounts,
    /// Camera samples taken in this run (not counting those of a resumed checkpoint).
    pub samples: u64,
    /// Samples per pixel in the film, including a resumed checkpoint's.
    pub spp_done: u32,
    pub elapsed: Duration,
    /// Why the render ended before its target, if it did.
    pub stopped_early: Option<StopReason>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StopReason {
    TimeLimit,
    Interrupted,
}

/// Renders the scene's camera view in one go. `on_tile` is called per finished tile.
pub fn render(
    scene: &Scene,
    integrator: &dyn Integrator,
    settings: &RenderSettings,
    on_tile: &(dyn Fn() + Sync),
) -> RenderOutput {
    render_with(scene, &mut CameraPasses(integrator), settings, on_tile)
}

/// `render` for any pass renderer.
pub fn render_with(
    scene: &Scene,
    renderer: &mut dyn PassRenderer,
    settings: &RenderSettings,
    on_tile: &(dyn Fn() + Sync),
) -> RenderOutput {
    let progressive = Progressive { settings: *settings, time_limit: None, second_moment: false, sample_range: None };
    render_progressive(scene, renderer, &progressive, None, &AtomicBool::new(false), on_tile, &mut |_, _, _| {})
}

/// Renders in passes of one sample per pixel (all samples in one pass at 1 spp, the pixel
/// centre). `resume` is a film and its sample count from a checkpoint; `stop` is checked
/// between groups of passes; `on_pass(film, spp_done, renderer)` is called after every group
/// (to save checkpoints, with the renderer's own state).
pub fn render_progressive(
    scene: &Scene,
    renderer: &mut dyn PassRenderer,
    progressive: &Progressive,
    resume: Option<(Film, u32)>,
    stop: &AtomicBool,
    on_tile: &(dyn Fn() + Sync),
    on_pass: &mut dyn FnMut(&Film, u32, &dyn PassRenderer),
) -> RenderOutput {
    assert!(
        resume.is_none() || progressive.sample_range.is_none(),
        "a sample range renders into a fresh film of exact sums; a checkpoint's film has none"
    );
    let start = Instant::now();
    let mut settings = progressive.settings;
    let (width, height) = (scene.camera().width, scene.camera().height);
    let (first, open_ended) = match progressive.sample_range {
        Some((a, b)) => {
            settings.spp = b;
            (a, true)
        }
        None => (0, progressive.time_limit.is_some()),
    };
    let (mut film, mut spp_done) = resume.unwrap_or_else(|| {
        let mut film = Film::new(width, height);
        if progressive.second_moment {
            film = film.with_second_moment();
        }
        if progressive.sample_range.is_some() {
            film = film.with_exact_sums();
        }
        (film, first)
    });
    let mut rays = RayCounts::default();
    let mut samples = 0u64;
    let mut stopped_early = None;
    // Passes per group: one at first, then as many as take about GROUP_TIME.
    let mut group = 1;
    while spp_done < settings.spp {
        if stop.load(Ordering::Relaxed) {
            stopped_early = Some(StopReason::Interrupted);
            break;
        }
        // A time limit shorter than one pass still gets one: an image, not nothing.
        if samples > 0 && progressive.time_limit.is_some_and(|limit| start.elapsed() >= limit) {
            stopped_early = Some(StopReason::TimeLimit);
            break;
        }
        let centre = settings.spp == 1 && !open_ended;
        let passes: Vec<Pass> = (spp_done..settings.spp)
            .take(group as usize)
            .map(|index| Pass {
                seed: settings.seed,
                index,
                centre,
                filter: settings.filter,
                sampler: settings.sampler,
                // Stratification needs the count up front; a time limit or a sample range
                // leaves it open.
                samples: if open_ended { u32::MAX } else { settings.spp },
            })
            .collect();
        let group_start = Instant::now();
        rays.add(&renderer.render_passes(scene, &passes, &mut film, on_tile));
        let count = passes.len() as u32;
        // The passes' own time (saving a checkpoint after them is not part of it).
        let per_pass = group_start.elapsed().as_secs_f64() / count as f64;
        spp_done += count;
        samples += count as u64 * width as u64 * height as u64;
        on_pass(&film, spp_done, &*renderer);
        let left = progressive.time_limit.map(|limit| limit.saturating_sub(start.elapsed()).as_secs_f64());
        group = next_group(per_pass, left);
    }
    // A sample range's film holds its own samples only.
    let spp_done = spp_done - first;
    RenderOutput { film, rays, samples, spp_done, elapsed: start.elapsed(), stopped_early }
}

/// The passes of the next group, after passes of `per_pass` seconds each, with `left` seconds
/// of a time limit to go: as many as take about `GROUP_TIME`, at least one, and none that
/// would run past the time limit (so that it overshoots by one pass at most, as passes one at
/// a time would).
fn next_group(per_pass: f64, left: Option<f64>) -> u32 {
    let per_pass = per_pass.max(1e-9);
    let group = (GROUP_TIME / per_pass).clamp(1.0, MAX_GROUP as f64) as u32;
    match left {
        Some(left) => group.min((left / per_pass) as u32).max(1),
        None => group,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Groups of passes: about `GROUP_TIME` long, at least one pass, at most `MAX_GROUP`, and
    /// none running past a time limit.
    #[test]
    fn groups_take_about_their_time_and_stop_at_the_limit() {
        assert_eq!(next_group(0.02, None), 10);
        assert_eq!(next_group(1e-12, None), MAX_GROUP);
        assert_eq!(next_group(0.0, None), MAX_GROUP);
        assert_eq!(next_group(5.0, None), 1);
        assert_eq!(next_group(0.02, Some(0.05)), 2);
        assert_eq!(next_group(0.02, Some(0.01)), 1);
        assert_eq!(next_group(0.02, Some(0.0)), 1);
        assert_eq!(next_group(0.02, Some(100.0)), 10);
    }
}
