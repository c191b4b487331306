//! `glint render`: load, override, render with progress, write, summarise.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::Args;
use glint_cli::checkpoint;
use glint_cli::error::CliError;
use glint_cli::output::write_file_atomically;
use glint_cli::output::{check_writable, check_writable_file, layer, write_image, ImageFormat, OutputError};
use glint_cli::{compare, limits, partial};
use glint_core::film::Film;
use glint_core::filter::Filter;
use glint_core::integrators::aov::{render_aovs, Aovs};
use glint_core::integrators::{heat_colour, IntegratorKind, IntegratorSettings};
use glint_core::lights::{LightSelection, TriangleSampling};
use glint_core::render::{
    render_progressive, tile_count, PassRenderer, Progressive, RenderOutput, RenderSettings, StopReason,
};
use glint_core::sampling::SamplerKind;
use glint_core::scene::Scene;
use glint_core::shapes::{BoxMethod, IntersectMethods, PolygonTest, SphereMethod, TriangleMethod};
use glint_core::{Named, Rgb};
use glint_scene::LoadedScene;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

#[derive(Args)]
pub struct RenderArgs {
    /// Scene file: .toml (or .json with the same schema), or a Mitsuba 3 .xml. Without one, the
    /// built-in default scene.
    scene: Option<PathBuf>,
    /// Mitsuba scenes: set a <default> parameter, as Mitsuba's -D (repeatable): -D spp=64.
    #[arg(short = 'D', value_name = "NAME=VALUE", value_parser = parse_define)]
    define: Vec<(String, String)>,
    /// Also look for the files a scene names (meshes, textures, includes) in DIR, after the
    /// scene's own directory and a Mitsuba scene's <path>s (repeatable; Mitsuba's -a).
    #[arg(short = 'a', long = "search-path", value_name = "DIR")]
    search_path: Vec<PathBuf>,
    /// glTF scenes: no default environment for a file without punctual lights (docs/gltf.md).
    #[arg(long)]
    no_default_light: bool,
    /// Output image; the format follows the extension (.png, .exr, .pfm). Default: <scene>.png.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Samples per pixel (1 = through the pixel centre; more = jittered, box-filtered).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    spp: Option<u32>,
    /// Render samples A to B − 1 of every pixel alone, as one part of a render split across
    /// runs or machines: written as an EXR that records the range and keeps exact sums, to be
    /// combined by `glint merge` into the image one render of all the parts' samples gives,
    /// bit for bit (that of `--samples 0..N`). Camera integrators only.
    #[arg(long, value_name = "A..B", value_parser = glint_cli::partial::parse_range)]
    samples: Option<(u32, u32)>,
    /// Image width in pixels (the height follows the scene's aspect ratio unless given).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=32768))]
    width: Option<u32>,
    /// Image height in pixels.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=32768))]
    height: Option<u32>,
    #[arg(long, value_parser = named::<IntegratorKind>())]
    integrator: Option<IntegratorKind>,
    /// Maximum recursion depth (Whitted: generations of reflection/refraction rays; path
    /// tracers: scattering events, -1 = unbounded).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_max_depth)]
    max_depth: Option<u32>,
    /// Whitted: stop a branch whose accumulated weight falls below this.
    #[arg(long)]
    min_contribution: Option<f32>,
    /// Whitted: let shadow rays through transparent objects, attenuated by their transmission.
    #[arg(long)]
    transparent_shadows: bool,
    /// Seed of the random sample streams; the same seed gives the same image at any --threads.
    #[arg(long)]
    seed: Option<u64>,
    /// Worker threads, 1 to 1024 (default: all cores).
    #[arg(long, value_parser = glint_cli::limits::parse_thread_count)]
    threads: Option<usize>,
    /// Pixel reconstruction filter (default: the scene's, else box).
    #[arg(long, value_parser = named::<Filter>())]
    filter: Option<Filter>,
    /// Where each pixel sample's random numbers come from (default: the scene's).
    #[arg(long, value_parser = named::<SamplerKind>())]
    sampler: Option<SamplerKind>,
    /// PNG exposure in stops (the image is multiplied by 2^exposure before sRGB encoding).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    exposure: f32,
    #[arg(long, value_parser = named::<SphereMethod>())]
    sphere_method: Option<SphereMethod>,
    #[arg(long, value_parser = named::<TriangleMethod>())]
    triangle_method: Option<TriangleMethod>,
    #[arg(long, value_parser = named::<PolygonTest>())]
    polygon_test: Option<PolygonTest>,
    #[arg(long, value_parser = named::<BoxMethod>())]
    box_method: Option<BoxMethod>,
    /// How next-event estimation samples triangle lights: uniformly on their area, or in the
    /// solid angle they subtend, weighted by the receiver's cosine (less noise near a light,
    /// slower). Default:
    /// the scene's `light_sampling`, else area.
    #[arg(long, value_parser = named::<TriangleSampling>())]
    light_sampling: Option<TriangleSampling>,
    /// How lights are chosen for next-event estimation and particles: in proportion to their
    /// power, or each emitter equally (Mitsuba's way). Default: the scene's `light_selection`
    /// (Mitsuba scenes: uniform), else power.
    #[arg(long, value_parser = named::<LightSelection>())]
    light_selection: Option<LightSelection>,
    /// Path tracing: trace one path at a time instead of a tile's paths eight at a time in
    /// SIMD lanes. The
    /// image is the same bit for bit; for comparing the speed of the two.
    #[arg(long)]
    no_wavefront: bool,
    /// Keep each pixel's second moment (the mean of its samples' squares, Mitsuba's `moment`)
    /// and write it as the EXR layer `m2` (m2.R, m2.G, m2.B): a sample's variance is
    /// m2 − mean², the pixel's that over the sample count. Camera integrators only; the
    /// scene's `moment` (a Mitsuba `moment` integrator) turns it on too.
    #[arg(long)]
    moment: bool,
    /// Also write arbitrary output variables as EXR layers beside the image: what the camera
    /// sees first (albedo.R/G/B, the BSDF's albedo toward the camera; normal.X/Y/Z, the shading
    /// normal in world space; depth.Z, the distance along the camera ray; each the mean of up
    /// to 16 rays per pixel) and, for camera integrators, each pixel's variance
    /// (variance.R/G/B: the variance of the pixel's mean, (E[L²] − E[L]²) / n from its samples'
    /// second moment, exact for independent samples; low-discrepancy samplers do better).
    #[arg(long)]
    aovs: bool,
    /// No progress bar and no summary line.
    #[arg(short, long)]
    quiet: bool,
    /// Print acceleration-structure statistics and rays traced by kind.
    #[arg(long)]
    stats: bool,
    /// Render passes until this many seconds are spent (then --spp is only an upper bound).
    /// Negative values reach the check that names them (not clap's "use -- -1" hint).
    #[arg(long, allow_hyphen_values = true)]
    time: Option<f64>,
    /// Compare the image with this reference (the same size) after every group of passes, and
    /// write the error against render time: OUTPUT.error.csv (seconds, spp, MSE, relMSE, MAE)
    /// and its log-log plot OUTPUT.error.svg. The comparisons' own time is not counted.
    #[arg(long, value_name = "REF")]
    reference: Option<PathBuf>,
    /// Save the float accumulator and sample count here, every --checkpoint-interval seconds
    /// and when the render ends (also on Ctrl-C or --time).
    #[arg(long)]
    checkpoint: Option<PathBuf>,
    #[arg(long, default_value_t = 30.0, allow_hyphen_values = true)]
    checkpoint_interval: f64,
    /// Refuse renders whose buffers (film, image, photon maps, SPPM state) would need more
    /// than this many GiB, and meshes that inflate to more (default: GLINT_MEMORY_LIMIT, else 8).
    #[arg(long, value_name = "GIB")]
    memory_limit: Option<f64>,
    /// Continue a render from a checkpoint (same scene and settings), to the same image an
    /// uninterrupted render gives.
    #[arg(long)]
    resume: Option<PathBuf>,
    /// Photon mapping: photons stored in the global map (volphoton: in the volume map).
    #[arg(long)]
    photons: Option<u32>,
    /// Photon mapping: photons stored in the caustic map.
    #[arg(long)]
    caustic_photons: Option<u32>,
    /// Photon mapping and volphoton: photons per radiance estimate (k nearest).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    photon_nearest: Option<u32>,
    /// Photon mapping and volphoton: largest search radius (0: 5 % of the scene's diagonal).
    #[arg(long)]
    photon_radius: Option<f32>,
    /// Photon mapping: final-gather rays per camera sample (0: no indirect light but caustics).
    #[arg(long)]
    final_gather: Option<u32>,
    /// SPPM: first search radius (0: three pixel footprints).
    #[arg(long)]
    sppm_radius: Option<f32>,
    /// SPPM: photons per pass (0: as many as the image has pixels).
    #[arg(long)]
    photons_per_pass: Option<u32>,
}

/// A command-line parser for one of the core's named choices: its names are the core's own
/// (`Named`), so the CLI mirrors no enum and `--help` lists what the core has.
fn named<T: Named>() -> impl TypedValueParser<Value = T> {
    PossibleValuesParser::new(T::ALL.iter().map(|k| k.name()))
        .map(|name| T::from_name(&name).expect("clap admits only the possible values"))
}

/// `NAME=VALUE` of a -D parameter.
pub fn parse_define(s: &str) -> Result<(String, String), String> {
    let (name, value) = s.split_once('=').ok_or("expected NAME=VALUE (for example spp=64)")?;
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
        return Err(format!("`{name}` is not a parameter name (letters, digits and _)"));
    }
    Ok((name.to_string(), value.to_string()))
}

pub fn run(args: RenderArgs) -> Result<Outcome, CliError> {
    let output = output_path(&args);
    check_before_work(&args, &output)?;
    let memory_limit = memory_limit_bytes(args.memory_limit)?;
    glint_scene::set_memory_limit(memory_limit);
    let (scene, plan) = load(&args)?;
    check_memory(&plan, &scene, memory_limit)?;
    let checkpoint = read_checkpoint(&args, &plan, &scene)?;
    let stop = stop_on_signals(args.quiet);
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(n) = args.threads {
        pool = pool.num_threads(n);
    }
    let pool = pool.build()?;

    let started = Instant::now();
    let renderer = pool.install(|| plan.kind.renderer_until(&plan.integrator, &scene, plan.settings.seed, &stop));
    if stop.load(Ordering::Relaxed) {
        say!("interrupted before the first pass: nothing written");
        return Ok(Outcome::Interrupted);
    }
    let mut renderer = renderer?;
    // Once the render will run: a refused one says why alone.
    if plan.kind.is_monte_carlo() {
        for (name, material) in scene.material_names().iter().zip(scene.materials()) {
            if let Some(w) = material.highlight_warning(name) {
                say!("warning: {w}");
            }
        }
    }
    if plan.kind == IntegratorKind::Photon && !args.quiet {
        say!("photon maps built in {:.2} s", started.elapsed().as_secs_f64());
    }
    let resume = match checkpoint {
        Some(c) => {
            let path = args.resume.as_ref().expect("a checkpoint came from --resume");
            renderer.restore(&c.state).map_err(|source| CliError::Resume { path: path.clone(), source })?;
            Some((c.film, c.spp_done))
        }
        None => None,
    };
    let mut error_log = match &args.reference {
        Some(path) => Some(ErrorLog::new(path, &scene)?),
        None => None,
    };
    let progress = progress_bar(&args, &plan, &scene, resume.as_ref().map(|(_, spp_done)| *spp_done));
    let result = {
        let progressive = Progressive {
            settings: plan.settings,
            time_limit: plan.time_limit,
            second_moment: plan.moment || plan.variance,
            sample_range: args.samples,
        };
        let mut saver = CheckpointSaver::new(&args, &plan);
        let result = pool.install(|| {
            render_progressive(
                &scene,
                renderer.as_mut(),
                &progressive,
                resume,
                &stop,
                &|| progress.inc(1),
                &mut |film, spp_done, renderer| {
                    if let Some(log) = &mut error_log {
                        log.on_pass(film, spp_done);
                    }
                    saver.on_pass(film, spp_done, renderer)
                },
            )
        });
        progress.finish_and_clear();
        for w in renderer.warnings() {
            say!("warning: {w}");
        }
        if let Some(w) = glint_core::scene::black_image_warning(&scene, plan.kind, &result.film) {
            say!("warning: {w}");
        }
        if let Some(e) = saver.error {
            say!("warning: {e}");
        }
        result
    };
    if result.spp_done == 0 {
        if result.stopped_early == Some(StopReason::Interrupted) {
            say!("interrupted before the first pass: nothing written");
            return Ok(Outcome::Interrupted);
        }
        return Err(CliError::NothingRendered);
    }
    // What the camera sees first, at up to 16 rays per pixel (not part of the render's time).
    let aovs = args.aovs.then(|| pool.install(|| render_aovs(&scene, plan.settings.spp.min(16), plan.settings.seed)));
    write_outputs(&args, &plan, &scene, &output, &result, renderer.as_ref(), aovs.as_ref())?;
    if let Some(log) = &error_log {
        log.write(&output, &plan)?;
    }
    if args.stats {
        print_stats(&scene, &result);
    }
    if !args.quiet {
        print_summary(&plan, &scene, &output, &result);
    }
    Ok(match result.stopped_early {
        Some(StopReason::Interrupted) => Outcome::Interrupted,
        _ => Outcome::Finished,
    })
}

/// What a render will do, decided from the scene and the flags before any work.
struct Plan {
    kind: IntegratorKind,
    integrator: IntegratorSettings,
    settings: RenderSettings,
    time_limit: Option<Duration>,
    /// What makes the image what it is (`RenderIdentity`): a checkpoint resumes only the
    /// render it was written by.
    fingerprint: u64,
    /// Keep and write each pixel's second moment.
    moment: bool,
    /// Keep each pixel's second moment to write its variance (`--aovs`).
    variance: bool,
}

/// The output image's path: `--output`, else the scene's name as a PNG.
fn output_path(args: &RenderArgs) -> PathBuf {
    args.output.clone().unwrap_or_else(|| {
        let stem = args
            .scene
            .as_ref()
            .and_then(|s| s.file_stem())
            .map_or("default".into(), |s| s.to_string_lossy().to_string());
        PathBuf::from(format!("{stem}.png"))
    })
}

/// Before any work: a render must never be lost to an unwritable output or checkpoint, or to
/// a flag refused after it.
fn check_before_work(args: &RenderArgs, output: &Path) -> Result<(), CliError> {
    let format = check_writable(output)?;
    if args.aovs && format != ImageFormat::Exr {
        return Err(CliError::Setting(format!(
            "--aovs writes layers beside the image, which only EXR holds: `{}` is not .exr",
            output.display()
        )));
    }
    if args.samples.is_some() {
        let conflicts = [
            ("--spp", args.spp.is_some()),
            ("--time", args.time.is_some()),
            ("--checkpoint", args.checkpoint.is_some()),
            ("--resume", args.resume.is_some()),
            ("--moment", args.moment),
        ];
        if let Some((flag, _)) = conflicts.iter().find(|(_, given)| *given) {
            return Err(CliError::Setting(format!(
                "--samples renders exactly the samples it names: it cannot be combined with {flag}"
            )));
        }
        if args.aovs {
            return Err(CliError::Setting(
                "--samples writes a part to merge, whose sums alone merge exactly: leave --aovs to the merged render"
                    .into(),
            ));
        }
        if format != ImageFormat::Exr {
            return Err(CliError::Setting(format!(
                "--samples writes a part to merge, as an EXR whose header records its samples and whose channels keep exact sums: `{}` is not .exr",
                output.display()
            )));
        }
    }
    if let Some(path) = &args.checkpoint {
        check_writable_file(path, "checkpoint")?;
    }
    for (flag, value) in [("--exposure", args.exposure as f64), ("--checkpoint-interval", args.checkpoint_interval)] {
        if !value.is_finite() || (flag == "--checkpoint-interval" && value < 0.0) {
            return Err(CliError::Setting(format!(
                "{flag} must be a finite number{}, got {value}",
                if flag == "--exposure" { "" } else { " of seconds ≥ 0" }
            )));
        }
    }
    Ok(())
}

/// The scene with the flags' overrides, and the plan of the render.
fn load(args: &RenderArgs) -> Result<(Scene, Plan), CliError> {
    let loaded = match &args.scene {
        Some(path) => glint_scene::load_scene_with_options(
            path,
            &glint_scene::LoadOptions {
                defines: args.define.clone(),
                search_path: args.search_path.clone(),
                no_default_light: args.no_default_light,
            },
        ),
        None => glint_scene::default_scene(),
    }?;
    let LoadedScene { mut scene, render: options, warnings, inputs } = loaded;
    for w in &warnings {
        say!("warning: {w}");
    }
    apply_overrides(args, &mut scene);
    let kind = args.integrator.unwrap_or(options.integrator);
    if args.samples.is_some() && !kind.samples_pixels() {
        return Err(CliError::Setting(format!(
            "--samples: `{}` does not take samples of its own per pixel (its passes share particles or photon statistics across pixels), so its passes cannot be rendered apart and merged; use a camera integrator",
            kind.name()
        )));
    }
    let integrator = args.integrator_settings(&options.integrator_settings)?;
    let mut settings = RenderSettings {
        spp: args.spp.unwrap_or(options.spp),
        seed: args.seed.unwrap_or(options.seed),
        filter: args.filter.unwrap_or(options.filter),
        sampler: args.sampler.unwrap_or(options.sampler),
    };
    let time_limit = match args.time {
        Some(t) if t.is_finite() && t > 0.0 => Some(Duration::from_secs_f64(t)),
        Some(t) => return Err(CliError::Setting(format!("--time must be a positive number of seconds, got {t}"))),
        None => None,
    };
    if time_limit.is_some() && args.spp.is_none() {
        settings.spp = u32::MAX; // the time limit decides
    }
    // The scene's files by content (not by path: the same scene named another way resumes),
    // read one at a time, and only when a checkpoint is written or read.
    let scene_contents = match &args.scene {
        Some(_) if args.checkpoint.is_some() || args.resume.is_some() || args.samples.is_some() => {
            inputs_fingerprint(&inputs)
        }
        Some(_) => Vec::new(),
        None => b"<built-in default scene>".to_vec(),
    };
    let identity = RenderIdentity {
        scene_contents: &scene_contents,
        defines: &args.define,
        kind,
        integrator,
        methods: scene.geometry().methods(),
        width: scene.camera().width,
        height: scene.camera().height,
        filter: settings.filter,
        sampler: settings.sampler,
        // A stratified render's strata depend on its sample count (a sample range's are open).
        strata_spp: (settings.sampler == SamplerKind::Stratified && args.samples.is_none()).then_some(settings.spp),
        triangle_sampling: scene.lights().triangle_sampling(),
    };
    let fingerprint = checkpoint::fingerprint_of(&identity);
    let moment = (args.moment || options.moment) && moment_possible(args, kind)?;
    // The variance layer needs the second moment, which only a fresh camera render keeps.
    let variance = args.aovs && kind.samples_pixels() && args.resume.is_none();
    Ok((scene, Plan { kind, integrator, settings, time_limit, fingerprint, moment, variance }))
}

/// Whether this render can keep the second moment it is asked for: a camera integrator's
/// samples each land in the film (particles' splats do not), from a fresh film (checkpoints
/// keep no second moment). Asked on the command line, a render that cannot is refused; asked
/// by the scene, it goes on without, with a warning.
fn moment_possible(args: &RenderArgs, kind: IntegratorKind) -> Result<bool, CliError> {
    let why = if !kind.samples_pixels() {
        format!("`{}` splats particles into the film, so its pixels have no samples of their own", kind.name())
    } else if args.resume.is_some() {
        "a checkpoint keeps no second moment, so a resumed render cannot write one".to_string()
    } else {
        return Ok(true);
    };
    if args.moment {
        return Err(CliError::Setting(format!("--moment: {why}")));
    }
    say!("warning: the scene asks for the second moment (`moment`), which is not written: {why}");
    Ok(false)
}

/// Everything that makes a render's image what it is, but the seed (which a checkpoint
/// records by itself): a checkpoint is resumed only by a render with the same identity.
#[derive(Hash)]
struct RenderIdentity<'a> {
    /// Each of the scene's files by content.
    scene_contents: &'a [u8],
    defines: &'a [(String, String)],
    kind: IntegratorKind,
    integrator: IntegratorSettings,
    methods: IntersectMethods,
    width: u32,
    height: u32,
    filter: Filter,
    sampler: SamplerKind,
    strata_spp: Option<u32>,
    triangle_sampling: TriangleSampling,
}

/// Refuses a render whose own buffers would not fit the memory limit (the check the Python
/// module makes too).
fn check_memory(plan: &Plan, scene: &Scene, memory_limit: u64) -> Result<(), CliError> {
    let (width, height) = (scene.camera().width, scene.camera().height);
    limits::check_memory(plan.kind, &plan.integrator, width, height, memory_limit)
}

/// The checkpoint `--resume` names, checked against this render.
fn read_checkpoint(args: &RenderArgs, plan: &Plan, scene: &Scene) -> Result<Option<checkpoint::Checkpoint>, CliError> {
    let Some(path) = &args.resume else { return Ok(None) };
    let filter = plan.settings.filter;
    let expected = checkpoint::Expected {
        width: scene.camera().width,
        height: scene.camera().height,
        seed: plan.settings.seed,
        fingerprint: plan.fingerprint,
        spp: plan.settings.spp,
        weights: match plan.kind {
            IntegratorKind::Sppm => checkpoint::WeightRule::One,
            IntegratorKind::Light => checkpoint::WeightRule::PerPass,
            _ if filter == Filter::Box => checkpoint::WeightRule::PerPass,
            _ => checkpoint::WeightRule::Finite,
        },
        nonnegative: filter != Filter::Mitchell,
    };
    let c = checkpoint::load(path, &expected)?;
    if !args.quiet {
        say!("resuming from `{}` at {} spp", path.display(), c.spp_done);
    }
    Ok(Some(c))
}

/// The flag raised by the first Ctrl-C (or SIGTERM, SIGHUP: a render farm stops jobs so):
/// the passes under way finish and everything is written; a second one quits.
fn stop_on_signals(quiet: bool) -> Arc<AtomicBool> {
    let stop = Arc::new(AtomicBool::new(false));
    let raised = stop.clone();
    let _ = ctrlc::set_handler(move || {
        if raised.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
        if !quiet {
            say!(
                "\ninterrupted: finishing the passes under way, then writing the image (Ctrl-C again to quit at once)"
            );
        }
    });
    stop
}

/// A bar advancing once per tile of every pass (hidden when quiet or not on a terminal).
fn progress_bar(args: &RenderArgs, plan: &Plan, scene: &Scene, spp_done: Option<u32>) -> ProgressBar {
    let tiles = tile_count(scene.camera().width, scene.camera().height);
    let progress = ProgressBar::new(tiles * plan.settings.spp.min(1 << 20) as u64);
    if let Some(spp_done) = spp_done {
        progress.set_position(tiles * spp_done as u64);
    }
    if args.quiet || !std::io::stderr().is_terminal() {
        progress.set_draw_target(ProgressDrawTarget::hidden());
    }
    progress.set_style(
        ProgressStyle::with_template(
            "{spinner} rendering [{bar:40}] {percent:>3}%  {elapsed_precise} elapsed, ETA {eta}",
        )
        .expect("the template is valid")
        .progress_chars("=> "),
    );
    progress
}

/// Writes `--checkpoint` every `--checkpoint-interval` seconds between passes; the first
/// failure is kept, to be reported, and the render goes on.
/// `--reference`: the image's error against the reference after each group of passes.
struct ErrorLog {
    reference: compare::Image,
    start: Instant,
    /// Time spent comparing, left out of the render's time.
    comparing: Duration,
    rows: Vec<compare::ErrorSample>,
}

impl ErrorLog {
    fn new(path: &Path, scene: &Scene) -> Result<Self, CliError> {
        let reference = compare::read_image(path).map_err(|e| CliError::Setting(format!("--reference: {e}")))?;
        let (w, h) = (scene.camera().width, scene.camera().height);
        if (reference.width, reference.height) != (w, h) {
            return Err(CliError::Setting(format!(
                "--reference: `{}` is {}x{}, the render {w}x{h}",
                path.display(),
                reference.width,
                reference.height
            )));
        }
        Ok(Self { reference, start: Instant::now(), comparing: Duration::ZERO, rows: Vec::new() })
    }

    fn on_pass(&mut self, film: &Film, spp: u32) {
        let began = Instant::now();
        let seconds = (self.start.elapsed().saturating_sub(self.comparing)).as_secs_f64();
        let image = compare::Image {
            width: film.width,
            height: film.height,
            pixels: film.to_rgb(),
            attributes: Default::default(),
        };
        if let Ok(m) = compare::metrics(&image, &self.reference) {
            let mean = compare::Metrics::mean;
            let row =
                compare::ErrorSample { seconds, spp, mse: mean(m.mse), rel_mse: mean(m.rel_mse), mae: mean(m.mae) };
            self.rows.push(row);
        }
        self.comparing += began.elapsed();
    }

    /// OUTPUT.error.csv and OUTPUT.error.svg.
    fn write(&self, output: &Path, plan: &Plan) -> Result<(), CliError> {
        let beside = |extension: &str| {
            let mut name = output.file_name().unwrap_or_default().to_os_string();
            name.push(extension);
            output.with_file_name(name)
        };
        write_file_atomically(&beside(".error.csv"), compare::error_csv(&self.rows).as_bytes(), "output")?;
        let title = format!("{}: relMSE against render time", plan.kind.name());
        write_file_atomically(&beside(".error.svg"), compare::error_plot_svg(&self.rows, &title).as_bytes(), "output")?;
        Ok(())
    }
}

struct CheckpointSaver<'a> {
    path: Option<&'a Path>,
    interval: f64,
    seed: u64,
    fingerprint: u64,
    last: Instant,
    error: Option<OutputError>,
}

impl<'a> CheckpointSaver<'a> {
    fn new(args: &'a RenderArgs, plan: &Plan) -> Self {
        Self {
            path: args.checkpoint.as_deref(),
            interval: args.checkpoint_interval,
            seed: plan.settings.seed,
            fingerprint: plan.fingerprint,
            last: Instant::now(),
            error: None,
        }
    }

    fn on_pass(&mut self, film: &Film, spp_done: u32, renderer: &dyn PassRenderer) {
        let Some(path) = self.path else { return };
        if self.last.elapsed().as_secs_f64() >= self.interval {
            let state = renderer.state();
            if let Err(e) = checkpoint::save(path, film, spp_done, self.seed, self.fingerprint, &state) {
                self.error.get_or_insert(e);
            }
            self.last = Instant::now();
        }
    }
}

/// A colour layer's channels.
const RGB: [&str; 3] = ["R", "G", "B"];

/// The image, then the final checkpoint: a checkpoint that cannot be written must not cost
/// the render.
fn write_outputs(
    args: &RenderArgs,
    plan: &Plan,
    scene: &Scene,
    output: &Path,
    result: &RenderOutput,
    renderer: &dyn PassRenderer,
    aovs: Option<&Aovs>,
) -> Result<(), CliError> {
    let (width, height) = (scene.camera().width, scene.camera().height);
    let mut pixels = result.film.to_rgb();
    let mut exposure = args.exposure;
    let heat_png = plan.kind == IntegratorKind::BvhHeat && ImageFormat::from_path(output)? == ImageFormat::Png;
    if heat_png {
        let max = false_colour_heat_map(&mut pixels, width, height);
        exposure = 0.0;
        say!(
            "bvh-heat: colour = BVH nodes visited + primitives tested per camera ray, from 0 (dark blue) to {max:.0} (red); the bar along the bottom of the image is the scale, ticks at quarters"
        );
    }
    let camera = scene.camera();
    let matrix = camera.camera_to_world().iter().flatten().map(|v| v.to_string()).collect::<Vec<_>>().join(" ");
    let metadata = vec![
        ("glint:spp", result.spp_done.to_string()),
        ("glint:seed", plan.settings.seed.to_string()),
        ("glint:integrator", plan.kind.name().to_string()),
        ("glint:version", env!("CARGO_PKG_VERSION").to_string()),
        ("glint:render_seconds", result.elapsed.as_secs_f64().to_string()),
        // Row-major 4×4, camera space x right, y up, z forward.
        ("glint:camera_to_world", matrix),
        ("glint:fov", camera.fov_degrees.to_string()),
    ];
    if let Some((first, _)) = args.samples {
        // What was rendered: a render stopped early holds the passes it finished.
        let range = (first, first + result.spp_done);
        let mut attributes = metadata.to_vec();
        attributes.extend([
            (partial::SAMPLES_KEY, partial::format_ranges(&[range])),
            ("glint:sampler", plan.settings.sampler.name().to_string()),
            ("glint:filter", plan.settings.filter.name().to_string()),
            ("glint:identity", format!("{:016x}", plan.fingerprint)),
            ("glint:scene", args.scene.as_ref().map_or("<built-in>".into(), |p| p.display().to_string())),
        ]);
        partial::write(output, &result.film, &attributes)?;
        return Ok(());
    }
    let moments = result.film.second_moments();
    let mut layers = Vec::new();
    if let (true, Some(m2)) = (plan.moment, &moments) {
        layers.extend(layer("m2", RGB, m2));
    }
    if !layers.is_empty() && ImageFormat::from_path(output)? != ImageFormat::Exr {
        say!("warning: the second moment is written only into EXR images; `{}` has the image alone", output.display());
    }
    if let Some(aovs) = aovs {
        layers.extend(layer("albedo", RGB, &aovs.albedo));
        layers.extend(layer("normal", ["X", "Y", "Z"], &aovs.normal));
        layers.push(("depth.Z".to_string(), aovs.depth.clone()));
        if let (true, Some(m2)) = (plan.variance, &moments) {
            // The variance of the pixel's mean: (E[L²] − E[L]²) / n.
            let n = result.spp_done.max(1) as f32;
            let variance: Vec<Rgb> =
                m2.iter().zip(&pixels).map(|(m2, mean)| (*m2 - *mean * *mean).max(Rgb::ZERO) / n).collect();
            layers.extend(layer("variance", RGB, &variance));
        }
    }
    write_image(output, width, height, &pixels, exposure, &metadata, &layers)?;
    if let Some(path) = &args.checkpoint {
        let state = renderer.state();
        checkpoint::save(path, &result.film, result.spp_done, plan.settings.seed, plan.fingerprint, &state)?;
    }
    Ok(())
}

/// `--stats`: the acceleration structure and the rays traced by kind.
fn print_stats(scene: &Scene, result: &RenderOutput) {
    let g = &scene.geometry();
    let s = g.bvh_stats();
    let r = &result.rays;
    say!(
        "BVH: {} primitives, built in {:.3} s; binary tree {} nodes, {} leaves, depth {}, SAH cost {:.2}; 8-wide tree {} nodes, {} leaf blocks; {:.1} bytes per primitive",
        g.primitive_count(),
        g.build_time().as_secs_f64(),
        s.nodes,
        s.leaves,
        s.depth,
        s.sah_cost,
        s.wide_nodes,
        s.leaf_blocks,
        s.bytes as f64 / g.primitive_count().max(1) as f64
    );
    say!(
        "rays: {} camera, {} shadow, {} reflection, {} refraction, {} from lights, {} in all",
        r.camera,
        r.shadow,
        r.reflection,
        r.refraction,
        r.light,
        r.total()
    );
}

/// The summary line: what was rendered, how fast, and where it went.
fn print_summary(plan: &Plan, scene: &Scene, output: &Path, result: &RenderOutput) {
    let seconds = result.elapsed.as_secs_f64().max(1e-9);
    let wavefront = plan.kind == IntegratorKind::Path && plan.integrator.wavefront;
    // Milliseconds: benchmarks read this line, and a hundredth of a second is about 1 % of
    // the Cornell box's render, the size of the differences they compare.
    say!(
        "rendered {}x{} at {} spp{} with {}{} in {:.3} s: {:.2} M samples/s, {:.2} M rays/s -> {}",
        scene.camera().width,
        scene.camera().height,
        result.spp_done,
        match result.stopped_early {
            Some(StopReason::Interrupted) => " (interrupted)",
            Some(StopReason::TimeLimit) => " (time limit)",
            None => "",
        },
        plan.kind.name(),
        if wavefront { " (wavefront, 8 lanes)" } else { "" },
        seconds,
        result.samples as f64 / seconds / 1e6,
        result.rays.total() as f64 / seconds / 1e6,
        output.display()
    );
}

/// How a render ended, for the exit status.
pub enum Outcome {
    Finished,
    /// Stopped by Ctrl-C, SIGTERM or SIGHUP, with what was rendered written.
    Interrupted,
}

/// The exit status of a render that was interrupted but wrote its image (and checkpoint).
pub const EXIT_INTERRUPTED: u8 = 3;

/// The memory limit (`--memory-limit`, GLINT_MEMORY_LIMIT, the default): `glint compare`
/// and `glint merge` hold what they read to it too.
pub(crate) use glint_cli::limits::memory_limit_bytes;

/// A fingerprint of each file a scene was read from, in order: its contents' FNV-1a hash (a
/// file that cannot be read now counts as empty).
fn inputs_fingerprint(inputs: &[PathBuf]) -> Vec<u8> {
    // Through the scene readers' bounded reader: a file past the memory limit (a glTF buffer
    // far longer than its byteLength, of which the reader took only that) is not read whole
    // again here; its length still counts.
    inputs
        .iter()
        .flat_map(|path| {
            let length = std::fs::metadata(path).map(|m| m.len()).unwrap_or_default().to_le_bytes();
            let bytes = glint_scene::read_file(path, u64::MAX).unwrap_or_default();
            checkpoint::fingerprint(&[&bytes, &length]).to_le_bytes()
        })
        .collect()
}

/// `--max-depth` for every command: a count of bounces, or -1 for unbounded (`u32::MAX`).
pub fn parse_max_depth(s: &str) -> Result<u32, String> {
    match s.trim().parse::<i64>() {
        Ok(-1) => Ok(u32::MAX),
        Ok(d) if (0..u32::MAX as i64).contains(&d) => Ok(d as u32),
        _ => Err(format!("expected -1 (unbounded) or a depth from 0 to {}, got `{s}`", u32::MAX - 1)),
    }
}

/// Replaces heat-map counts (channel R) by false colours scaled to the image's maximum, and
/// draws the colour bar along the bottom rows. Returns the count that maps to red.
fn false_colour_heat_map(pixels: &mut [Rgb], width: u32, height: u32) -> f32 {
    let max = pixels.iter().map(|p| p.x).fold(1.0f32, f32::max);
    for p in pixels.iter_mut() {
        *p = heat_colour(p.x / max);
    }
    let bar = (height / 24).max(4).min(height);
    for y in height - bar..height {
        for x in 0..width {
            let t = x as f32 / (width - 1).max(1) as f32;
            let quarter = (0..=4).any(|q| (x as i64 - (q * (width as i64 - 1)) / 4).abs() < 1);
            pixels[(y * width + x) as usize] = if quarter { Rgb::ONE } else { heat_colour(t) };
        }
    }
    max
}

impl RenderArgs {
    pub fn integrator_settings(&self, from_scene: &IntegratorSettings) -> Result<IntegratorSettings, CliError> {
        let mut s = *from_scene;
        if let Some(d) = self.max_depth {
            s.max_depth = d;
        }
        if let Some(c) = self.min_contribution {
            if !(c.is_finite() && c >= 0.0) {
                return Err(CliError::Setting(format!("--min-contribution must be a number ≥ 0, got {c}")));
            }
            s.min_contribution = c;
        }
        s.transparent_shadows |= self.transparent_shadows;
        s.wavefront &= !self.no_wavefront;
        for (flag, value) in [("--photon-radius", self.photon_radius), ("--sppm-radius", self.sppm_radius)] {
            if value.is_some_and(|v| !(v.is_finite() && v >= 0.0)) {
                return Err(CliError::Setting(format!(
                    "{flag} must be a length ≥ 0 (0: automatic), got {}",
                    value.unwrap_or_default()
                )));
            }
        }
        let p = &mut s.photon;
        p.global_photons = self.photons.unwrap_or(p.global_photons);
        p.caustic_photons = self.caustic_photons.unwrap_or(p.caustic_photons);
        p.nearest = self.photon_nearest.unwrap_or(p.nearest);
        p.max_radius = self.photon_radius.unwrap_or(p.max_radius);
        p.final_gather = self.final_gather.unwrap_or(p.final_gather);
        s.sppm_radius = self.sppm_radius.unwrap_or(s.sppm_radius);
        s.photons_per_pass = self.photons_per_pass.unwrap_or(s.photons_per_pass);
        Ok(s)
    }
}

/// The scene's camera at the requested size; a missing side keeps the scene's aspect ratio.
pub fn resize_camera(scene: &mut Scene, width: Option<u32>, height: Option<u32>) {
    let (w, h) = (scene.camera().width, scene.camera().height);
    let (width, height) = match (width, height) {
        (Some(width), Some(height)) => (width, height),
        (Some(width), None) => (width, ((width as f64 * h as f64 / w as f64).round() as u32).max(1)),
        (None, Some(height)) => (((height as f64 * w as f64 / h as f64).round() as u32).max(1), height),
        (None, None) => (w, h),
    };
    scene.set_camera(scene.camera().with_resolution(width, height));
}

fn apply_overrides(args: &RenderArgs, scene: &mut Scene) {
    resize_camera(scene, args.width, args.height);
    let m = scene.geometry().methods();
    scene.set_methods(IntersectMethods {
        sphere: args.sphere_method.unwrap_or(m.sphere),
        triangle: args.triangle_method.unwrap_or(m.triangle),
        polygon: args.polygon_test.unwrap_or(m.polygon),
        aabox: args.box_method.unwrap_or(m.aabox),
    });
    if let Some(sampling) = args.light_sampling {
        scene.set_triangle_sampling(sampling);
    }
    if let Some(selection) = args.light_selection {
        scene.set_light_selection(selection);
    }
}
