//! The render job: what `glint render` and the Python module's `Scene.render` both run, so
//! that they hold a render to the same checks and limits, give it the same identity (parts
//! rendered by either merge with each other) and report the same warnings. The front ends
//! only parse their arguments into a [`Request`], show progress, and print or raise what the
//! job returns.
//!
//! The steps, each returning its warnings as values (the CLI prints them after `warning: `,
//! Python issues them as `glint.GlintWarning`s):
//!
//! 1. [`memory_limit`]: the limit (a flag, else GLINT_MEMORY_LIMIT, else 8 GiB), handed to the
//!    scene readers too.
//! 2. [`Job::load`]: the scene from a file (with Mitsuba parameters and a search path), the
//!    built-in scene or a description built in memory, with the overrides that change the
//!    scene itself ([`SceneOverrides`]: resolution, intersection methods, light sampling).
//! 3. [`Job::plan`]: a [`Request`]'s overrides applied to the scene's settings and checked;
//!    the integrator, the render's identity, the memory estimate against the limit, the
//!    worker threads: a [`Plan`], decided before any work.
//! 4. [`Job::start`]: the worker threads and the pass renderer (photon maps are shot here),
//!    stopped early by a flag; then [`Run::render`] with progress and per-pass callbacks, and
//!    the film, the AOVs, the partial's attributes and the checkpoint's expectations.

mod identity;
mod record;
mod request;
mod run;

use std::path::PathBuf;
use std::sync::OnceLock;

use glint_core::lights::{LightSelection, TriangleSampling};
use glint_core::scene::Scene;
use glint_core::shapes::{BoxMethod, IntersectMethods, PolygonTest, SphereMethod, TriangleMethod};
use glint_scene::{LoadedScene, RenderOptions};

pub use identity::RenderIdentity;
pub use request::{FrontEnd, IntegratorOverrides, Plan, Request};
pub use run::{variance, Rendered, Run};

use crate::description::DescriptionJson;
use crate::error::CliError;

/// The memory limit in bytes (`flag`: `--memory-limit` in GiB; else GLINT_MEMORY_LIMIT, else
/// the default), handed to the scene readers, which hold the files they read to it. Read at
/// each load and render, as the command reads it at each run.
pub fn memory_limit(flag: Option<f64>) -> Result<u64, CliError> {
    let limit = crate::limits::memory_limit_bytes(flag)?;
    glint_scene::set_memory_limit(limit);
    Ok(limit)
}

/// Where a scene comes from.
#[derive(Clone, Debug)]
pub enum SceneSource {
    /// A scene file (.toml, .json, Mitsuba .xml, pbrt, glTF), with Mitsuba's `-D` parameters,
    /// the directories searched for the files it names, and for glTF whether a file without
    /// punctual lights goes without the default environment.
    File { path: PathBuf, defines: Vec<(String, String)>, search_path: Vec<PathBuf>, no_default_light: bool },
    /// The built-in default scene (`glint render` without a scene).
    BuiltIn,
    /// A native description built in memory (Python's `load_dict`), whose files are found
    /// from `directory`.
    Description { json: DescriptionJson, directory: PathBuf },
}

impl SceneSource {
    /// A scene file without parameters or search path.
    pub fn file(path: impl Into<PathBuf>) -> Self {
        SceneSource::File { path: path.into(), defines: Vec::new(), search_path: Vec::new(), no_default_light: false }
    }

    /// Mitsuba's `-D` parameters (none but for a file).
    pub fn defines(&self) -> &[(String, String)] {
        match self {
            SceneSource::File { defines, .. } => defines,
            _ => &[],
        }
    }

    /// How a partial render's header names the scene (`glint:scene`).
    pub fn display_name(&self) -> String {
        match self {
            SceneSource::File { path, .. } => path.display().to_string(),
            SceneSource::BuiltIn => "<built-in>".into(),
            SceneSource::Description { .. } => crate::description::NAME.into(),
        }
    }
}

/// What a render changes in the scene itself (`--width`, `--height`, the intersection
/// methods, `--light-sampling`, `--light-selection`); `None` keeps the scene's.
#[derive(Clone, Copy, Debug, Default)]
pub struct SceneOverrides {
    pub width: Option<u32>,
    pub height: Option<u32>,
    pub sphere_method: Option<SphereMethod>,
    pub triangle_method: Option<TriangleMethod>,
    pub polygon_test: Option<PolygonTest>,
    pub box_method: Option<BoxMethod>,
    pub light_sampling: Option<TriangleSampling>,
    pub light_selection: Option<LightSelection>,
}

impl SceneOverrides {
    fn apply(&self, scene: &mut Scene) {
        resize_camera(scene, self.width, self.height);
        let m = scene.geometry().methods();
        scene.set_methods(IntersectMethods {
            sphere: self.sphere_method.unwrap_or(m.sphere),
            triangle: self.triangle_method.unwrap_or(m.triangle),
            polygon: self.polygon_test.unwrap_or(m.polygon),
            aabox: self.box_method.unwrap_or(m.aabox),
        });
        if let Some(sampling) = self.light_sampling {
            scene.set_triangle_sampling(sampling);
        }
        if let Some(selection) = self.light_selection {
            scene.set_light_selection(selection);
        }
    }
}

/// The scene's camera at the requested size of its whole film (a crop window keeps its place
/// on it); a missing side keeps the film's aspect ratio.
pub fn resize_camera(scene: &mut Scene, width: Option<u32>, height: Option<u32>) {
    let (w, h) = scene.camera().film_resolution();
    let (width, height) = match (width, height) {
        (Some(width), Some(height)) => (width, height),
        (Some(width), None) => (width, ((width as f64 * h as f64 / w as f64).round() as u32).max(1)),
        (None, Some(height)) => (((height as f64 * w as f64 / h as f64).round() as u32).max(1), height),
        (None, None) => return,
    };
    scene.set_camera(scene.camera().with_resolution(width, height));
}

/// A loaded scene, its own render settings, and where it came from: what every render of it
/// starts from. It never changes, so one job serves many renders (Python's `Scene`).
pub struct Job {
    scene: Scene,
    options: RenderOptions,
    source: SceneSource,
    /// Every file the scene was read from, the scene file first.
    inputs: Vec<PathBuf>,
    /// Each of those files by content (`scene_contents`), read when first asked for.
    contents: OnceLock<Vec<u8>>,
}

impl Job {
    /// Loads the scene `source` names (within the memory limit the readers were given, see
    /// [`memory_limit`]) with `overrides`; returns it and the readers' warnings.
    pub fn load(source: SceneSource, overrides: &SceneOverrides) -> Result<(Job, Vec<String>), CliError> {
        let loaded = match &source {
            SceneSource::File { path, defines, search_path, no_default_light } => {
                let options = glint_scene::LoadOptions {
                    defines: defines.clone(),
                    search_path: search_path.clone(),
                    no_default_light: *no_default_light,
                };
                glint_scene::load_scene_with_options(path, &options)?
            }
            SceneSource::BuiltIn => glint_scene::default_scene()?,
            SceneSource::Description { json, directory } => {
                json.load(&glint_scene::Source::directory(directory.clone()))?
            }
        };
        let LoadedScene { mut scene, render: options, warnings, inputs } = loaded;
        overrides.apply(&mut scene);
        Ok((Job { scene, options, source, inputs, contents: OnceLock::new() }, warnings))
    }

    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The render settings the scene asks for.
    pub fn options(&self) -> &RenderOptions {
        &self.options
    }

    pub fn source(&self) -> &SceneSource {
        &self.source
    }

    /// The scene by its contents (not by path: the same scene named another way is the same
    /// render): a fingerprint of each file it was read from, in order. Read once, when first
    /// asked for (a render asks only when a checkpoint or a part needs its identity).
    pub fn scene_contents(&self) -> &[u8] {
        self.contents.get_or_init(|| identity::scene_contents(&self.source, &self.inputs))
    }

    /// The scene's contents and parameters as one number: a scene read again from the same
    /// place is the same scene only if this is unchanged (Python's pickled scenes).
    pub fn source_fingerprint(&self) -> u64 {
        crate::checkpoint::fingerprint_of(&(self.scene_contents(), self.source.defines()))
    }
}

#[cfg(test)]
mod tests {
    use glint_core::integrators::IntegratorKind;

    use super::*;

    const GIB: u64 = 1 << 30;

    fn built_in(overrides: &SceneOverrides) -> Job {
        Job::load(SceneSource::BuiltIn, overrides).unwrap().0
    }

    fn identity(job: &Job, request: &Request) -> u64 {
        job.plan(request, 8 * GIB).unwrap().0.identity.expect("a part's identity")
    }

    /// A cropped scene keeps its window through the job (no override leaves the camera as
    /// the scene made it); a width override scales the whole film, and the window with it.
    #[test]
    fn a_crop_window_survives_the_jobs_resize() {
        let mut scene = glint_scene::default_scene().expect("the built-in scene").scene;
        let film = scene.camera().film_resolution();
        let cropped = scene.camera().with_crop(10, 5, 30, 45).unwrap();
        scene.set_camera(cropped.clone());
        resize_camera(&mut scene, None, None);
        assert_eq!(scene.camera(), &cropped);
        resize_camera(&mut scene, Some(film.0 * 2), None);
        assert_eq!(scene.camera().film_resolution(), (film.0 * 2, film.1 * 2));
        assert_eq!(scene.camera().crop_window(), Some((20, 10, 60, 90)));
    }

    /// Parts from either front end are parts of one render: the identity is the request's,
    /// not its front end's; it changes with what changes the image and nothing else.
    #[test]
    fn the_identity_is_the_renders_whoever_asks() {
        let job = built_in(&SceneOverrides { width: Some(32), ..Default::default() });
        let part = Request { samples: Some((0, 4)), ..Default::default() };
        let base = identity(&job, &part);
        let python = Request { front_end: FrontEnd::Python, ..part.clone() };
        assert_eq!(identity(&job, &python), base);
        // The same for all the samples of one render, the seed apart (which a part spells out),
        // and whatever the threads or the wavefront.
        for same in [
            Request { samples: Some((4, 9)), ..part.clone() },
            Request { seed: Some(7), threads: Some(1), ..part.clone() },
            Request { settings: IntegratorOverrides { no_wavefront: true, ..Default::default() }, ..part.clone() },
        ] {
            assert_eq!(identity(&job, &same), base, "{same:?}");
        }
        for other in [
            Request { integrator: Some(IntegratorKind::VolPath), ..part.clone() },
            Request { settings: IntegratorOverrides { max_depth: Some(2), ..Default::default() }, ..part.clone() },
            Request { filter: Some(glint_core::filter::Filter::Gaussian), ..part.clone() },
        ] {
            assert_ne!(identity(&job, &other), base, "{other:?}");
        }
        let wider = built_in(&SceneOverrides { width: Some(33), ..Default::default() });
        assert_ne!(identity(&wider, &part), base);
        // No part, no checkpoint: no identity (the scene's files are not read again).
        assert_eq!(job.plan(&Request::default(), 8 * GIB).unwrap().0.identity, None);
        assert!(job.plan(&Request { checkpoint: true, ..Default::default() }, 8 * GIB).unwrap().0.identity.is_some());
    }

    /// A scene file by content: the same file under another name is the same scene, and a
    /// changed file another.
    #[test]
    fn the_scene_counts_by_its_contents() {
        let dir = std::env::temp_dir().join(format!("glint-job-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let scene = "[camera]\nposition = [0, 0, -5]\nlook_at = [0, 0, 0]\nresolution = [8, 8]\n\n\
                     [materials.m]\ntype = \"diffuse\"\nreflectance = [0.5, 0.5, 0.5]\n\n\
                     [[shapes]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"m\"\n";
        let load = |name: &str, text: &str| {
            let path = dir.join(name);
            std::fs::write(&path, text).unwrap();
            Job::load(SceneSource::file(path), &SceneOverrides::default()).unwrap().0
        };
        let part = Request { samples: Some((0, 2)), ..Default::default() };
        let (a, b) = (load("a.toml", scene), load("b.toml", scene));
        assert_eq!(identity(&a, &part), identity(&b, &part));
        assert_eq!(a.source_fingerprint(), b.source_fingerprint());
        let c = load("c.toml", &scene.replace("radius = 1", "radius = 2"));
        assert_ne!(identity(&a, &part), identity(&c, &part));
        assert_ne!(a.source_fingerprint(), c.source_fingerprint());
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn the_plan_holds_the_render_to_the_memory_limit() {
        let job = built_in(&SceneOverrides { width: Some(16384), height: Some(16384), ..Default::default() });
        let refused = job.plan(&Request::default(), 8 * GIB).unwrap_err();
        assert!(matches!(refused, CliError::TooLarge(_)), "{refused}");
        assert!(refused.to_string().starts_with("this render needs about 10.0 GiB (16384x16384 pixels)"), "{refused}");
        assert!(job.plan(&Request::default(), 11 * GIB).is_ok());
    }

    /// The second moment asked for where it cannot be kept: refused when the request asks,
    /// a warning when the scene does.
    #[test]
    fn a_moment_that_cannot_be_kept_is_refused_or_warned_about() {
        let mut job = built_in(&SceneOverrides { width: Some(16), ..Default::default() });
        let light = Request { integrator: Some(IntegratorKind::Light), ..Default::default() };
        let asked = Request { moment: true, ..light.clone() };
        assert!(job.plan(&asked, GIB).unwrap_err().to_string().starts_with("--moment: `light` splats particles"));
        job.options.moment = true;
        let (plan, warnings) = job.plan(&light, GIB).unwrap();
        assert!(!plan.moment);
        assert_eq!(warnings.len(), 1);
        assert!(warnings[0].starts_with("the scene asks for the second moment (`moment`), which is not written"));
        let (plan, warnings) = job.plan(&Request::default(), GIB).unwrap();
        assert!(plan.moment && warnings.is_empty());
    }
}
