//! `glint explain SCENE --pixel X,Y`: what one pixel's value is made of, by the integrator
//! that renders it. The scene is loaded and the integrator's settings checked by the render
//! job (`glint_cli::job`, as `glint render` does), and the integrator is made and asked by
//! `IntegratorKind::explain_pixel`, the construction a render uses; the text, JSON and PLY
//! writers are in `explain_command/`.

mod json;
mod ply;
mod text;

use std::path::PathBuf;

use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::Args;
use glint_cli::error::CliError;
use glint_cli::job::{self, IntegratorOverrides, Job, Request, SceneOverrides, SceneSource};
use glint_core::integrators::passes::Pass;
use glint_core::integrators::whitted::{DEPTH_CEILING, TREE_RAY_LIMIT};
use glint_core::integrators::{CameraExplanation, IntegratorKind, PixelExplanation};
use glint_core::Named;

#[derive(Args)]
pub struct ExplainArgs {
    /// Scene file (default: the built-in scene).
    scene: Option<PathBuf>,
    /// Mitsuba scenes: set a <default> parameter, as for `render` (repeatable).
    #[arg(short = 'D', value_name = "NAME=VALUE", value_parser = crate::render_command::parse_define)]
    define: Vec<(String, String)>,
    /// Also look for the files a scene names (meshes, textures, includes) in DIR, after the
    /// scene's own directory and a Mitsuba scene's <path>s (repeatable; Mitsuba's -a).
    #[arg(short = 'a', long = "search-path", value_name = "DIR")]
    search_path: Vec<PathBuf>,
    /// glTF scenes: no default environment for a file without punctual lights (docs/gltf.md).
    #[arg(long)]
    no_default_light: bool,
    /// The pixel, as X,Y from the top-left corner (at the scene's resolution, or --width/--height).
    #[arg(long, value_parser = parse_pixel)]
    pixel: (u32, u32),
    /// Image width (the height follows the scene's aspect ratio unless given), as for `render`.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=32768))]
    width: Option<u32>,
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=32768))]
    height: Option<u32>,
    /// Maximum recursion depth, -1 = unbounded (default: the scene's), as for `render`.
    #[arg(long, allow_hyphen_values = true, value_parser = crate::render_command::parse_max_depth)]
    max_depth: Option<u32>,
    #[arg(long)]
    min_contribution: Option<f32>,
    #[arg(long)]
    transparent_shadows: bool,
    /// Which integrator's path to show: `whitted` (the default: the ray tree), `path`,
    /// `path-naive`, `photon`, `volpath` or `volphoton` (the path of the pixel's first sample:
    /// each vertex, in a medium too, its emission, light sample or photon-map estimate, BSDF or phase sample
    /// and roulette, and what each adds to the pixel), `light` (the particles of the first pass that land in the pixel,
    /// their paths and splats) or `sppm` (the first pass's camera path to its visible point,
    /// and the photons gathered there).
    #[arg(long, default_value = "whitted", value_parser = explainable())]
    integrator: IntegratorKind,
    /// The seed of the sample streams (default: the scene's), as for `render`.
    #[arg(long)]
    seed: Option<u64>,
    /// With `--integrator path` or `path-naive`: print the path as JSON (for other tools)
    /// instead of text: the camera ray, each event with its numbers, and the pixel's value.
    #[arg(long)]
    json: bool,
    /// With `--integrator path` or `path-naive`: also write the path as a PLY line set (its
    /// segments from the camera through each vertex, and each light sample's shadow ray) to
    /// look at beside the scene in a 3D viewer.
    #[arg(long, value_name = "FILE")]
    ply: Option<PathBuf>,
    /// Also shoot the scene's photon maps (photon mapping's first pass, with the scene's
    /// settings and seed) and list the K photons of each map nearest to the pixel's first hit,
    /// with the radiance estimates made from them.
    #[arg(long, value_name = "K")]
    photons: Option<u32>,
}

/// The integrators `explain` follows (`IntegratorKind::explains`), by name.
fn explainable() -> impl TypedValueParser<Value = IntegratorKind> {
    let names = IntegratorKind::ALL.iter().filter(|k| k.explains()).map(|k| k.name());
    PossibleValuesParser::new(names).map(|name| IntegratorKind::from_name(&name).expect("clap admits only the names"))
}

fn parse_pixel(s: &str) -> Result<(u32, u32), String> {
    let (x, y) = s.split_once(',').ok_or("expected X,Y (for example 320,240)")?;
    let parse = |v: &str| v.trim().parse::<u32>().map_err(|_| format!("`{v}` is not a pixel coordinate"));
    Ok((parse(x)?, parse(y)?))
}

pub fn run(args: ExplainArgs) -> Result<(), CliError> {
    let kind = args.integrator;
    let request = Request {
        integrator: Some(kind),
        settings: IntegratorOverrides {
            max_depth: args.max_depth,
            min_contribution: args.min_contribution,
            transparent_shadows: args.transparent_shadows,
            ..Default::default()
        },
        seed: args.seed,
        ..Default::default()
    };
    request.check()?;
    let memory_limit = job::memory_limit(None)?;
    let source = match &args.scene {
        Some(path) => SceneSource::File {
            path: path.clone(),
            defines: args.define.clone(),
            search_path: args.search_path.clone(),
            no_default_light: args.no_default_light,
        },
        None => SceneSource::BuiltIn,
    };
    let overrides = SceneOverrides { width: args.width, height: args.height, ..Default::default() };
    let (job, warnings) = Job::load(source, &overrides)?;
    crate::render_command::print_warnings(&warnings);
    let scene = job.scene();
    let (w, h) = (scene.camera().width, scene.camera().height);
    let (x, y) = args.pixel;
    if x >= w || y >= h {
        return Err(CliError::Setting(format!("pixel {x},{y} is outside the {w}x{h} image")));
    }
    if kind == IntegratorKind::Whitted && (args.json || args.ply.is_some()) {
        return Err(CliError::Setting(
            "--json and --ply write a Monte Carlo integrator's paths: give --integrator path, path-naive, photon, volpath, volphoton, light or sppm".into(),
        ));
    }
    // The render's checks and limits; its warnings are about an image, which explain does
    // not write.
    let (plan, _) = job.plan(&request, memory_limit)?;
    let settings = &plan.integrator;
    // The first sample of a one-sample render: through the pixel centre.
    let pass = Pass {
        seed: plan.settings.seed,
        index: 0,
        centre: true,
        filter: plan.settings.filter,
        sampler: plan.settings.sampler,
        samples: 1,
    };
    let (text, json, ply) = match kind.explain_pixel(settings, scene, &pass, (x, y))? {
        PixelExplanation::Camera { explanation: CameraExplanation::Tree { tree, colour, cut }, .. } => {
            print!("{}", text::format_tree(scene, settings, x, y, &tree, colour));
            if cut {
                println!(
                    "the tree was cut at {DEPTH_CEILING} generations or {TREE_RAY_LIMIT} rays: neither the depth nor the contribution rule ended it"
                );
            }
            if let Some(k) = args.photons {
                // The scene's seed, as a render of the scene shoots its photons.
                print!("{}", text::explain_photons(scene, settings, job.options().seed, x, y, k)?);
            }
            return Ok(());
        }
        PixelExplanation::Camera { ray, explanation: CameraExplanation::Path { radiance, log } } => {
            let traced = (ray, radiance, log);
            (
                text::explain_path(scene, settings, &pass, &traced, x, y, kind),
                json::path_json(scene, &traced, &pass, x, y, kind),
                ply::path_ply(scene, &traced, x, y),
            )
        }
        PixelExplanation::Particles(explanation) => (
            text::explain_particles(scene, &explanation, pass.seed, x, y),
            json::particles_json(scene, &explanation, pass.seed, x, y),
            ply::particles_ply(scene, &explanation, x, y),
        ),
        PixelExplanation::Sppm { ray, explanation } => {
            let traced = (ray, explanation.value, explanation.path.clone());
            (
                text::explain_sppm(scene, settings, &explanation, pass.seed, x, y),
                json::sppm_json(scene, &traced, &explanation, &pass, x, y),
                ply::path_ply(scene, &traced, x, y),
            )
        }
    };
    if let Some(file) = &args.ply {
        glint_cli::output::write_file_atomically(file, ply.as_bytes(), "PLY line set")?;
    }
    if args.json {
        println!("{json}");
    } else {
        print!("{text}");
    }
    Ok(())
}
