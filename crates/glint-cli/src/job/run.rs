//! A planned render run: its worker threads and pass renderer ([`Job::start`]), its passes
//! with progress, cancellation and per-pass callbacks ([`Run::render`]), and its AOVs.

use std::path::Path;
use std::sync::atomic::AtomicBool;

use glint_core::film::Film;
use glint_core::integrators::aov::{render_aovs, Aovs};
use glint_core::render::{render_progressive, PassRenderer, RenderOutput};
use glint_core::Rgb;

use super::{Job, Plan};
use crate::checkpoint::Checkpoint;
use crate::error::CliError;

/// A render under way: the job, its plan, its threads and its pass renderer.
pub struct Run<'a> {
    job: &'a Job,
    plan: &'a Plan,
    pool: rayon::ThreadPool,
    renderer: Box<dyn PassRenderer + Send>,
}

/// A finished run: the render loop's output and what is worth telling about it.
pub struct Rendered {
    pub output: RenderOutput,
    pub warnings: Vec<String>,
}

impl Job {
    /// Starts a planned render: its worker threads and its pass renderer (photon maps are shot
    /// here, given up soon after `stop` is raised), and the warnings about the scene's
    /// materials under a Monte Carlo integrator. An error where the integrator refuses the
    /// scene (no physical light) or was stopped.
    pub fn start<'a>(&'a self, plan: &'a Plan, stop: &AtomicBool) -> Result<(Run<'a>, Vec<String>), CliError> {
        let mut pool = rayon::ThreadPoolBuilder::new();
        if let Some(n) = plan.threads {
            pool = pool.num_threads(n);
        }
        let pool = pool.build()?;
        let scene = self.scene();
        let renderer = pool.install(|| plan.kind.renderer_until(&plan.integrator, scene, plan.settings.seed, stop))?;
        let mut warnings = Vec::new();
        if plan.kind.is_monte_carlo() {
            let materials = scene.material_names().iter().zip(scene.materials());
            warnings.extend(materials.filter_map(|(name, material)| material.highlight_warning(name)));
        }
        Ok((Run { job: self, plan, pool, renderer }, warnings))
    }
}

impl Run<'_> {
    /// The pass renderer (its state, for checkpoints).
    pub fn renderer(&self) -> &dyn PassRenderer {
        self.renderer.as_ref()
    }

    /// The integrator's state restored from a checkpoint read at `path` (checked against
    /// [`Job::expected_checkpoint`]); returns the film and sample count to resume from.
    pub fn restore(&mut self, checkpoint: Checkpoint, path: &Path) -> Result<(Film, u32), CliError> {
        self.renderer
            .restore(&checkpoint.state)
            .map_err(|source| CliError::Resume { path: path.to_path_buf(), source })?;
        Ok((checkpoint.film, checkpoint.spp_done))
    }

    /// Renders the planned passes (after `resume`'s, if given) until done, out of time, or
    /// `stop` is raised; `on_tile` is called per finished tile, `on_pass` after each group of
    /// passes (with the film, the samples per pixel done and the renderer). Returns the output
    /// and its warnings: the integrator's own, and why an image black in every pixel is black.
    pub fn render(
        &mut self,
        resume: Option<(Film, u32)>,
        stop: &AtomicBool,
        on_tile: &(dyn Fn() + Sync),
        on_pass: &mut (dyn FnMut(&Film, u32, &dyn PassRenderer) + Send),
    ) -> Rendered {
        let scene = self.job.scene();
        let progressive = self.plan.progressive();
        let renderer = &mut self.renderer;
        let output = self
            .pool
            .install(|| render_progressive(scene, renderer.as_mut(), &progressive, resume, stop, on_tile, on_pass));
        let mut warnings = self.renderer.warnings();
        warnings.extend(glint_core::scene::black_image_warning(scene, self.plan.kind, &output.film));
        Rendered { output, warnings }
    }

    /// What the camera sees first (albedo, normal, depth), at up to 16 rays per pixel, when
    /// the plan asks for the AOVs (not part of the render's time).
    pub fn aovs(&self) -> Option<Aovs> {
        let (scene, settings) = (self.job.scene(), self.plan.settings);
        self.plan.aovs.then(|| self.pool.install(|| render_aovs(scene, settings.spp.min(16), settings.seed)))
    }
}

/// The variance of each pixel's mean, (E[L²] − E[L]²) / n, from a film that kept the second
/// moment (`Plan::variance`); `pixels` are its image.
pub fn variance(film: &Film, pixels: &[Rgb], spp_done: u32) -> Option<Vec<Rgb>> {
    let m2 = film.second_moments()?;
    let n = spp_done.max(1) as f32;
    Some(m2.iter().zip(pixels).map(|(m2, mean)| (*m2 - *mean * *mean).max(Rgb::ZERO) / n).collect())
}
