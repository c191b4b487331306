//! `glint explain SCENE --pixel X,Y`: the ray tree of one pixel, as Whitted drew it.

use std::fmt::Write;
use std::path::PathBuf;

use clap::Args;
use glint_cli::error::CliError;
use glint_core::geometry::Ray;
use glint_core::integrators::passes::{pixel_sample, Pass};
use glint_core::integrators::path_record::{ParticleEvent, PathEnd, PathEvent, PathLog, TracesPaths};
use glint_core::integrators::recorder::{RayRecord, RayTree};
use glint_core::integrators::whitted::{DEPTH_CEILING, TREE_RAY_LIMIT};
use glint_core::integrators::{
    IntegratorKind, IntegratorSettings, LightTracer, NaivePathTracer, ParticleExplanation, PathTracer, PhotonMapper,
    SampleContext, Sppm, SppmExplanation, VolPathTracer, VolumePhotons, Whitted,
};
use glint_core::media::MediumKind;
use glint_core::photons::NearestPhotons;
use glint_core::sampling::Rng;
use glint_core::scene::Scene;
use glint_core::{Named, Rgb, Vec3};

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
    #[arg(long, default_value = "whitted", value_parser = ["whitted", "path", "path-naive", "photon", "volpath", "volphoton", "light", "sppm"])]
    integrator: String,
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

fn parse_pixel(s: &str) -> Result<(u32, u32), String> {
    let (x, y) = s.split_once(',').ok_or("expected X,Y (for example 320,240)")?;
    let parse = |v: &str| v.trim().parse::<u32>().map_err(|_| format!("`{v}` is not a pixel coordinate"));
    Ok((parse(x)?, parse(y)?))
}

pub fn run(args: ExplainArgs) -> Result<(), CliError> {
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
    let mut scene = loaded.scene;
    crate::render_command::resize_camera(&mut scene, args.width, args.height);
    let (w, h) = (scene.camera().width, scene.camera().height);
    let (x, y) = args.pixel;
    if x >= w || y >= h {
        return Err(CliError::Setting(format!("pixel {x},{y} is outside the {w}x{h} image")));
    }
    let mut settings = loaded.render.integrator_settings;
    if let Some(d) = args.max_depth {
        settings.max_depth = d;
    }
    if let Some(c) = args.min_contribution {
        settings.min_contribution = c;
    }
    settings.transparent_shadows |= args.transparent_shadows;
    if args.integrator == "whitted" && (args.json || args.ply.is_some()) {
        return Err(CliError::Setting(
            "--json and --ply write a Monte Carlo integrator's paths: give --integrator path, path-naive, photon, volpath, volphoton, light or sppm".into(),
        ));
    }
    if args.integrator == "light" || args.integrator == "sppm" {
        let seed = args.seed.unwrap_or(loaded.render.seed);
        let pass = Pass {
            seed,
            index: 0,
            centre: true,
            filter: loaded.render.filter,
            sampler: loaded.render.sampler,
            samples: 1,
        };
        let (text, json, ply) = if args.integrator == "light" {
            let explanation = LightTracer::new(&scene, settings.max_depth)?.explain_pixel(&scene, seed, (x, y));
            (
                explain_particles(&scene, &explanation, seed, x, y),
                particles_json(&scene, &explanation, seed, x, y),
                particles_ply(&scene, &explanation, x, y),
            )
        } else {
            let sppm = Sppm::new(
                &scene,
                settings.max_depth,
                settings.rr_depth,
                settings.sppm_radius,
                settings.photons_per_pass,
            )?;
            let explanation = sppm.explain_pixel(&scene, &pass, (x, y));
            let (ray, _) = pixel_sample(&scene, &pass, x, y);
            let traced = (ray, explanation.value, explanation.path.clone());
            (
                explain_sppm(&scene, &settings, &explanation, seed, x, y),
                sppm_json(&scene, &traced, &explanation, &pass, x, y),
                path_ply(&scene, &traced, x, y),
            )
        };
        if let Some(file) = &args.ply {
            glint_cli::output::write_file_atomically(file, ply.as_bytes(), "PLY line set")?;
        }
        if args.json {
            println!("{json}");
        } else {
            print!("{text}");
        }
        return Ok(());
    }
    if args.integrator != "whitted" {
        let pass = Pass {
            seed: args.seed.unwrap_or(loaded.render.seed),
            index: 0,
            centre: true,
            filter: loaded.render.filter,
            sampler: loaded.render.sampler,
            samples: 1,
        };
        let kind = IntegratorKind::from_name(&args.integrator).expect("clap admits only integrators");
        let traced = trace_path(&scene, &settings, &pass, x, y, kind)?;
        if let Some(file) = &args.ply {
            let bytes = path_ply(&scene, &traced, x, y);
            glint_cli::output::write_file_atomically(file, bytes.as_bytes(), "PLY line set")?;
        }
        if args.json {
            println!("{}", path_json(&scene, &traced, &pass, x, y, kind));
        } else {
            print!("{}", explain_path(&scene, &settings, &pass, &traced, x, y, kind));
        }
        return Ok(());
    }
    let (tree, colour, cut) = explain_pixel(&scene, &settings, x, y);
    print!("{}", format_tree(&scene, &settings, x, y, &tree, colour));
    if cut {
        println!(
            "the tree was cut at {DEPTH_CEILING} generations or {TREE_RAY_LIMIT} rays: neither the depth nor the contribution rule ended it"
        );
    }
    if let Some(k) = args.photons {
        print!("{}", explain_photons(&scene, &settings, loaded.render.seed, x, y, k)?);
    }
    Ok(())
}

/// The path of pixel (x, y)'s sample `pass.index` (as `render --spp 1` takes it) by the
/// integrator `kind`, event by event; the last line is the pixel's value, the sum of the
/// lines that add.
pub fn explain_path(
    scene: &Scene,
    settings: &IntegratorSettings,
    pass: &Pass,
    (_, radiance, log): &(Ray, Rgb, PathLog),
    x: u32,
    y: u32,
    kind: IntegratorKind,
) -> String {
    let radiance = *radiance;
    let mut out = String::new();
    let depth = if settings.max_depth == u32::MAX { "unbounded".to_string() } else { settings.max_depth.to_string() };
    let _ = writeln!(
        out,
        "pixel {x},{y}: the {} path through the pixel centre (seed {}, max depth {depth}, roulette from bounce {})",
        match kind {
            IntegratorKind::PathNaive => "naive path tracer's (light found only by hitting it)",
            IntegratorKind::Photon => "photon mapper's (through delta bounces, estimated at each diffuse surface)",
            IntegratorKind::VolPath => "volume path tracer's (scattering in media and at surfaces)",
            IntegratorKind::VolPhoton => {
                "volumetric photon mapper's (its photons shot first; the path stops at its first scattering in a medium)"
            }
            _ => "path tracer's",
        },
        pass.seed,
        settings.rr_depth
    );
    write_events(&mut out, scene, log, kind);
    let _ = writeln!(out, "pixel value = the sum of what each line adds = {}", full(radiance));
    out
}

/// A camera path's events, a line each (`explain_path`).
fn write_events(out: &mut String, scene: &Scene, log: &PathLog, kind: IntegratorKind) {
    let names = scene.material_names();
    for event in &log.events {
        let _ = match event {
            PathEvent::Vertex { depth, point, object, material, throughput } => writeln!(
                out,
                "vertex {depth}: `{}` (material `{}`) at {}, throughput {}",
                scene.objects()[*object as usize].name,
                names.get(*material as usize).map_or("?", String::as_str),
                v(*point),
                v(*throughput)
            ),
            PathEvent::Emission { emitted, mis_weight, added } => {
                writeln!(out, "  emission {} × MIS weight {mis_weight:.6} → adds {}", v(*emitted), full(*added))
            }
            PathEvent::Light(l) if l.occluded => writeln!(
                out,
                "  light sample toward {}, pdf {:.6}: its shadow ray is blocked → adds (0, 0, 0)",
                v(l.direction),
                l.pdf
            ),
            PathEvent::Light(l) => writeln!(
                out,
                "  light sample toward {}, pdf {:.6}, MIS weight {:.6} → adds {}",
                v(l.direction),
                l.pdf,
                l.mis_weight,
                full(l.added)
            ),
            PathEvent::Gather(g) => writeln!(
                out,
                "  photon mapping here: direct light (light sampling) {}, caustics (caustic map) {}, indirect light {} → adds {}",
                v(g.direct),
                v(g.caustic),
                g.indirect.map_or("(not gathered at the last bounce)".to_string(), |i| format!("(final gathering) {}", v(i))),
                full(g.added)
            ),
            PathEvent::Scatter { direction, weight, pdf, delta, throughput } => writeln!(
                out,
                "  BSDF sample ({} lobe) toward {}, pdf {pdf:.6}, weight f·cos/pdf {} → throughput {}",
                if *delta { "delta" } else { "non-delta" },
                v(*direction),
                v(*weight),
                v(*throughput)
            ),
            PathEvent::Medium { depth, point, medium, throughput } => writeln!(
                out,
                "vertex {depth}: scattered in medium {medium} ({}) at {}, throughput {} (σ_s and the flight's weight included)",
                medium_kind(scene, *medium),
                v(*point),
                v(*throughput)
            ),
            PathEvent::Phase { direction, pdf } => writeln!(
                out,
                "  phase-function sample toward {}, pdf {pdf:.6}, weight 1 (sampled exactly)",
                v(*direction)
            ),
            PathEvent::MediumPhotons { in_scattered, added } => writeln!(
                out,
                "  the medium's photons here: the light scattered toward the camera ray (∫ p L dω', from the nearest photons) {} → adds {}",
                v(*in_scattered),
                full(*added)
            ),
            PathEvent::Roulette { survival, survived } => writeln!(
                out,
                "  Russian roulette: survives with probability {survival:.6}: {}",
                if *survived { "survived (throughput divided by it)" } else { "ended" }
            ),
            PathEvent::Escape { radiance, mis_weight, added } => writeln!(
                out,
                "escaped: environment {} × MIS weight {mis_weight:.6} → adds {}",
                v(*radiance),
                full(*added)
            ),
            PathEvent::End(why) => writeln!(
                out,
                "path ends: {}",
                match why {
                    PathEnd::Escaped => "it left the scene",
                    PathEnd::Depth => "max depth reached",
                    PathEnd::Absorbed if kind == IntegratorKind::Photon => {
                        "no mirror or refraction to follow (photon mapping estimates the rest where it is)"
                    }
                    PathEnd::Absorbed if kind == IntegratorKind::Sppm => {
                        "the camera path stops here (its visible point, if photons can be gathered here)"
                    }
                    PathEnd::Absorbed if kind == IntegratorKind::VolPhoton => {
                        "the photons estimate the rest (after a scattering in a medium), or the BSDF gave no direction, or the throughput fell to zero"
                    }
                    PathEnd::Absorbed if kind == IntegratorKind::VolPath => {
                        "the BSDF gave no direction, or the throughput fell to zero, or the path crossed more than 256 boundaries in a row"
                    }
                    PathEnd::Absorbed => "the BSDF gave no direction",
                    PathEnd::Roulette => "Russian roulette",
                }
            ),
        };
    }
}

/// Light tracing's first pass as it reaches pixel (x, y): each particle that lands there,
/// its path, its splats; the pixel's value is the sum of the splats into it.
pub fn explain_particles(scene: &Scene, e: &ParticleExplanation, seed: u64, x: u32, y: u32) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "pixel {x},{y}: light tracing's first pass (seed {seed}): {} particles traced (one per pixel), {} of them land in this pixel",
        e.traced,
        e.particles.len()
    );
    let names = scene.material_names();
    for (index, log) in &e.particles {
        for event in &log.events {
            let _ = match event {
                ParticleEvent::Start { origin, flux } => {
                    writeln!(out, "particle {index}: leaves a light at {}, carrying flux {}", v(*origin), v(*flux))
                }
                ParticleEvent::Surface { bounces, point, object, material, flux } => writeln!(
                    out,
                    "  surface after {bounces} {}: `{}` (material `{}`) at {}, flux {}",
                    if *bounces == 1 { "bounce" } else { "bounces" },
                    scene.objects()[*object as usize].name,
                    names.get(*material as usize).map_or("?", String::as_str),
                    v(*point),
                    v(*flux)
                ),
                ParticleEvent::Splat { bounces, x: sx, y: sy, value } => {
                    let from = if bounces.is_some() { "this surface" } else { "the light itself" };
                    let (w, h) = (scene.camera().width, scene.camera().height);
                    if (*sx).min(w - 1) == x && (*sy).min(h - 1) == y {
                        writeln!(out, "  {from} seen by the camera: splat {} into this pixel", full(*value))
                    } else {
                        writeln!(out, "  {from} seen by the camera: splat {} into pixel {sx},{sy}", v(*value))
                    }
                }
                ParticleEvent::Roulette { survival, survived } => writeln!(
                    out,
                    "  Russian roulette: survives with probability {survival:.6}: {}",
                    if *survived { "survived (flux divided by it)" } else { "ended" }
                ),
                ParticleEvent::End(why) => writeln!(
                    out,
                    "  ends: {}",
                    match why {
                        PathEnd::Escaped => "it left the scene",
                        PathEnd::Depth => "max depth reached",
                        PathEnd::Absorbed => "the BSDF gave no direction",
                        PathEnd::Roulette => "Russian roulette",
                    }
                ),
            };
        }
    }
    if let Some(sky) = e.environment {
        let _ = writeln!(out, "the environment, seen by the pixel's own camera ray: splat {}", full(sky));
    }
    let _ = writeln!(out, "pixel value = the sum of the splats into this pixel = {}", full(e.value));
    out
}

/// `explain_particles` as JSON: `{"pixel", "integrator": "light", "seed", "particles":
/// [{"index", "events": [...]}], "environment", "value"}`.
pub fn particles_json(scene: &Scene, e: &ParticleExplanation, seed: u64, x: u32, y: u32) -> String {
    use serde_json::json;
    let a = |v: Vec3| json!([v.x, v.y, v.z]);
    let particles: Vec<serde_json::Value> = e
        .particles
        .iter()
        .map(|(index, log)| {
            let events: Vec<serde_json::Value> = log
                .events
                .iter()
                .map(|event| match event {
                    ParticleEvent::Start { origin, flux } => {
                        json!({ "event": "start", "origin": a(*origin), "flux": a(*flux) })
                    }
                    ParticleEvent::Surface { bounces, point, object, material, flux } => json!({
                        "event": "surface", "bounces": bounces, "point": a(*point),
                        "object": scene.objects()[*object as usize].name,
                        "material": scene.material_names().get(*material as usize), "flux": a(*flux),
                    }),
                    ParticleEvent::Splat { bounces, x, y, value } => {
                        json!({ "event": "splat", "from_bounces": bounces, "pixel": [x, y], "value": a(*value) })
                    }
                    ParticleEvent::Roulette { survival, survived } => {
                        json!({ "event": "roulette", "survival": survival, "survived": survived })
                    }
                    ParticleEvent::End(why) => json!({ "event": "end", "why": format!("{why:?}").to_lowercase() }),
                })
                .collect();
            json!({ "index": index, "events": events })
        })
        .collect();
    let document = json!({
        "pixel": [x, y], "integrator": "light", "seed": seed, "particles_traced": e.traced,
        "particles": particles, "environment": e.environment.map(a), "value": a(e.value),
    });
    serde_json::to_string_pretty(&document).unwrap_or_default()
}

/// The particles' paths as a PLY line set: from each particle's start through its surfaces,
/// and from each surface that splats into the pixel to the camera.
pub fn particles_ply(scene: &Scene, e: &ParticleExplanation, x: u32, y: u32) -> String {
    let camera = scene.camera().generate_ray(x as f32 + 0.5, y as f32 + 0.5).origin;
    let mut points = Vec::new();
    let mut edges = Vec::new();
    for (_, log) in &e.particles {
        let mut previous = None;
        for event in &log.events {
            match event {
                ParticleEvent::Start { origin: p, .. } | ParticleEvent::Surface { point: p, .. } => {
                    points.push(*p);
                    if let Some(q) = previous {
                        edges.push((q, points.len() - 1));
                    }
                    previous = Some(points.len() - 1);
                }
                ParticleEvent::Splat { x: sx, y: sy, .. } if (*sx, *sy) == (x, y) => {
                    if let Some(q) = previous {
                        points.push(camera);
                        edges.push((q, points.len() - 1));
                    }
                }
                _ => {}
            }
        }
    }
    line_set(&points, &edges, &format!("glint explain --integrator light: pixel {x},{y}"))
}

/// SPPM's first pass at pixel (x, y): the camera path's events, then the gather at its visible
/// point and the pixel's value.
pub fn explain_sppm(
    scene: &Scene,
    settings: &IntegratorSettings,
    e: &SppmExplanation,
    seed: u64,
    x: u32,
    y: u32,
) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "pixel {x},{y}: SPPM's first pass (seed {seed}): the camera path through the pixel centre to its visible point, roulette from bounce {}",
        settings.rr_depth
    );
    write_events(&mut out, scene, &e.path, IntegratorKind::Sppm);
    let _ = writeln!(out, "direct light on the way (emission and light samples) = {}", full(e.direct));
    match &e.gather {
        None => {
            let _ = writeln!(out, "no visible point: the photons add nothing");
        }
        Some(g) => {
            let _ = writeln!(
                out,
                "visible point {}: the pass's photons ({} stored of {} emitted) within radius {:.6}: {} found, Σ f·Φ = {}, camera weight {}",
                v(g.point),
                e.photons_stored,
                e.photons_emitted,
                g.radius,
                g.found,
                v(g.flux),
                v(g.weight)
            );
            let indirect = e.value - e.direct;
            let _ = writeln!(
                out,
                "  update: radius → {:.6}, τ = α · weight · Σ f·Φ = {} (α = 2/3); indirect estimate τ / (emitted · π r²) ≈ {}",
                g.new_radius,
                v(g.tau),
                v(indirect)
            );
        }
    }
    let _ = writeln!(out, "pixel value = direct + τ / (emitted · π r²) = {}", full(e.value));
    out
}

/// `explain_sppm` as JSON: the camera path's events as `path_json` writes them, the gather,
/// and the value.
fn sppm_json(scene: &Scene, traced: &(Ray, Rgb, PathLog), e: &SppmExplanation, pass: &Pass, x: u32, y: u32) -> String {
    use serde_json::json;
    let a = |v: Vec3| json!([v.x, v.y, v.z]);
    let mut document: serde_json::Value =
        serde_json::from_str(&path_json(scene, traced, pass, x, y, IntegratorKind::Sppm)).unwrap_or_default();
    document["direct"] = a(e.direct);
    document["photons_stored"] = json!(e.photons_stored);
    document["photons_emitted"] = json!(e.photons_emitted);
    document["gather"] = match &e.gather {
        None => serde_json::Value::Null,
        Some(g) => json!({
            "point": a(g.point), "radius": g.radius, "found": g.found, "flux": a(g.flux), "weight": a(g.weight),
            "new_radius": g.new_radius, "tau": a(g.tau),
        }),
    };
    serde_json::to_string_pretty(&document).unwrap_or_default()
}

/// The camera ray of pixel (x, y)'s sample `pass.index`, the radiance along it, and the log of
/// its path, by the path tracer, the naive one, the volume path tracer, or photon mapping on
/// surfaces or in media (its photons shot first with the pass's seed, as a render shoots them).
fn trace_path(
    scene: &Scene,
    settings: &IntegratorSettings,
    pass: &Pass,
    x: u32,
    y: u32,
    kind: IntegratorKind,
) -> Result<(Ray, Rgb, PathLog), CliError> {
    let (ray, mut context) = pixel_sample(scene, pass, x, y);
    let (radiance, log) = match kind {
        IntegratorKind::PathNaive => NaivePathTracer { max_depth: settings.max_depth, rr_depth: settings.rr_depth }
            .explain(scene, &ray, &mut context),
        IntegratorKind::Photon => {
            PhotonMapper::new(scene, settings.max_depth, settings.rr_depth, settings.photon, pass.seed)?.explain(
                scene,
                &ray,
                &mut context,
            )
        }
        IntegratorKind::VolPath => VolPathTracer::new(settings).explain(scene, &ray, &mut context),
        IntegratorKind::VolPhoton => {
            let photon = &settings.photon;
            let (wanted, nearest) = (photon.global_photons as u64, photon.nearest as usize);
            let never = std::sync::atomic::AtomicBool::new(false);
            let photons =
                VolumePhotons::shoot(scene, settings.max_depth, wanted, nearest, photon.max_radius, pass.seed, &never)?;
            let tracer = VolPathTracer { photons: Some(std::sync::Arc::new(photons)), ..VolPathTracer::new(settings) };
            tracer.explain(scene, &ray, &mut context)
        }
        _ => PathTracer::new(settings).explain(scene, &ray, &mut context),
    };
    Ok((ray, radiance, log))
}

/// `explain_path` as JSON: `{"pixel", "integrator", "seed", "camera_ray": {"origin",
/// "direction"}, "events": [{"event": "vertex" | "emission" | "light_sample" | "scatter" |
/// "medium" | "phase" | "medium_photons" | "roulette" | "escape" | "end", …}], "value"}`, colours and vectors as
/// [x, y, z].
pub fn path_json(
    scene: &Scene,
    (ray, radiance, log): &(Ray, Rgb, PathLog),
    pass: &Pass,
    x: u32,
    y: u32,
    kind: IntegratorKind,
) -> String {
    use serde_json::json;
    let a = |v: Vec3| json!([v.x, v.y, v.z]);
    let events: Vec<serde_json::Value> = log
        .events
        .iter()
        .map(|event| match event {
            PathEvent::Vertex { depth, point, object, material, throughput } => json!({
                "event": "vertex", "depth": depth, "point": a(*point),
                "object": scene.objects()[*object as usize].name,
                "material": scene.material_names().get(*material as usize),
                "throughput": a(*throughput),
            }),
            PathEvent::Emission { emitted, mis_weight, added } => json!({
                "event": "emission", "emitted": a(*emitted), "mis_weight": mis_weight, "added": a(*added),
            }),
            PathEvent::Light(l) => json!({
                "event": "light_sample", "direction": a(l.direction), "pdf": l.pdf, "mis_weight": l.mis_weight,
                "occluded": l.occluded, "added": a(l.added),
            }),
            PathEvent::Gather(g) => json!({
                "event": "photon_estimate", "direct": a(g.direct), "caustic": a(g.caustic),
                "indirect": g.indirect.map(a), "added": a(g.added),
            }),
            PathEvent::Scatter { direction, weight, pdf, delta, throughput } => json!({
                "event": "scatter", "direction": a(*direction), "weight": a(*weight), "pdf": pdf, "delta": delta,
                "throughput": a(*throughput),
            }),
            PathEvent::Roulette { survival, survived } => {
                json!({ "event": "roulette", "survival": survival, "survived": survived })
            }
            PathEvent::Medium { depth, point, medium, throughput } => json!({
                "event": "medium", "depth": depth, "point": a(*point),
                "medium": medium, "medium_kind": medium_kind(scene, *medium), "throughput": a(*throughput),
            }),
            PathEvent::Phase { direction, pdf } => json!({ "event": "phase", "direction": a(*direction), "pdf": pdf }),
            PathEvent::MediumPhotons { in_scattered, added } => {
                json!({ "event": "medium_photons", "in_scattered": a(*in_scattered), "added": a(*added) })
            }
            PathEvent::Escape { radiance, mis_weight, added } => json!({
                "event": "escape", "radiance": a(*radiance), "mis_weight": mis_weight, "added": a(*added),
            }),
            PathEvent::End(why) => json!({ "event": "end", "why": format!("{why:?}").to_lowercase() }),
        })
        .collect();
    let document = json!({
        "pixel": [x, y],
        "integrator": kind.name(),
        "seed": pass.seed,
        "camera_ray": { "origin": a(ray.origin), "direction": a(ray.direction) },
        "events": events,
        "value": a(*radiance),
    });
    serde_json::to_string_pretty(&document).unwrap_or_default()
}

/// The path as an ASCII PLY line set: vertices, then edges from the camera through each path
/// vertex (to a point 1 scene radius past the last one where the path leaves the scene), and
/// from each vertex to its light sample's point (a unit-length stub toward a light at infinity).
pub fn path_ply(scene: &Scene, (ray, _, log): &(Ray, Rgb, PathLog), x: u32, y: u32) -> String {
    let mut points = vec![ray.origin];
    let mut edges = Vec::new();
    let (mut previous, mut last_direction) = (0usize, ray.direction.normalize());
    let bounds = scene.geometry().bounds();
    let reach = if bounds.is_empty() { 1.0 } else { bounds.extent().length().clamp(1.0, 1e6) };
    for event in &log.events {
        match event {
            PathEvent::Vertex { point, .. } | PathEvent::Medium { point, .. } => {
                points.push(*point);
                edges.push((previous, points.len() - 1));
                previous = points.len() - 1;
            }
            PathEvent::Light(l) => {
                points.push(l.point.unwrap_or(points[previous] + l.direction));
                edges.push((previous, points.len() - 1));
            }
            PathEvent::Scatter { direction, .. } | PathEvent::Phase { direction, .. } => last_direction = *direction,
            PathEvent::Escape { .. } => {
                points.push(points[previous] + last_direction * reach);
                edges.push((previous, points.len() - 1));
            }
            _ => {}
        }
    }
    line_set(&points, &edges, &format!("glint explain: pixel {x},{y}"))
}

/// Points and the edges between them as an ASCII PLY line set.
fn line_set(points: &[Vec3], edges: &[(usize, usize)], comment: &str) -> String {
    let mut out = format!(
        "ply\nformat ascii 1.0\ncomment {comment}\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nelement edge {}\nproperty int vertex1\nproperty int vertex2\nend_header\n",
        points.len(),
        edges.len()
    );
    for p in points {
        let _ = writeln!(out, "{} {} {}", p.x, p.y, p.z);
    }
    for (a, b) in edges {
        let _ = writeln!(out, "{a} {b}");
    }
    out
}

/// What kind of medium the scene's medium `index` is.
fn medium_kind(scene: &Scene, index: u32) -> &'static str {
    match scene.media().get(index as usize).map(|m| &m.kind) {
        Some(MediumKind::Homogeneous(_)) => "homogeneous",
        Some(MediumKind::Grid(_)) => "grid",
        None => "?",
    }
}

/// A colour printed so that it reads back to the same bits.
fn full(c: Rgb) -> String {
    format!("({}, {}, {})", c.x, c.y, c.z)
}

/// The photons of both maps nearest to the first surface the pixel-centre ray hits, and the
/// radiance estimates photon mapping makes there.
pub fn explain_photons(
    scene: &Scene,
    settings: &IntegratorSettings,
    seed: u64,
    x: u32,
    y: u32,
    k: u32,
) -> Result<String, CliError> {
    let mapper = PhotonMapper::new(scene, settings.max_depth, settings.rr_depth, settings.photon, seed)?;
    let mut out = String::new();
    let ray = scene.camera().generate_ray(x as f32 + 0.5, y as f32 + 0.5);
    let Some(hit) = scene.intersect(&ray) else {
        let _ = writeln!(out, "photons: the pixel-centre ray hits nothing");
        return Ok(out);
    };
    let wo = -ray.direction.normalize();
    let material = &scene.materials()[hit.material as usize];
    let bsdf = material.bsdf(
        &hit.texture_query(scene.geometry()),
        wo,
        hit.geometry.shading_normal,
        hit.geometry.geometric_normal,
    );
    let _ = writeln!(
        out,
        "photons near the first hit {} (search radius at most {:.6}, seed {seed}):",
        v(hit.geometry.point),
        mapper.max_radius()
    );
    for (name, map) in [("global", mapper.global_map()), ("caustic", mapper.caustic_map())] {
        let _ = writeln!(
            out,
            "  {name} map: {} photons stored from {} emitted; the {k} nearest:",
            map.len(),
            map.emitted()
        );
        let mut nearest = NearestPhotons::default();
        map.k_nearest(hit.geometry.point, k as usize, mapper.max_radius(), &mut nearest);
        let mut found: Vec<(f32, u32)> = nearest.iter().collect();
        found.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (d2, i) in found {
            let photon = map.photon(i);
            let _ = writeln!(
                out,
                "    at distance {:.6}: flux {} (per photon emitted), arrived from {}, surface normal {}",
                d2.sqrt(),
                v(photon.power / map.emitted().max(1) as f32),
                v(photon.incoming()),
                v(photon.normal())
            );
        }
        if map.is_empty() {
            let _ = writeln!(out, "    (none)");
        }
        let _ = writeln!(
            out,
            "    radiance estimate toward the camera ({} nearest, cone filter): {}",
            settings.photon.nearest,
            v(mapper.estimate(map, &hit, &bsdf, wo))
        );
    }
    Ok(out)
}

/// Traces the pixel-centre ray with the Whitted integrator, recording the ray tree. The colour
/// is exactly what `glint render --integrator whitted --spp 1` computes for that pixel; the
/// flag says whether a ceiling cut the tree (`DEPTH_CEILING`, `TREE_RAY_LIMIT`).
pub fn explain_pixel(scene: &Scene, settings: &IntegratorSettings, x: u32, y: u32) -> (RayTree, Rgb, bool) {
    let whitted = Whitted::new(settings.max_depth, settings.min_contribution, settings.transparent_shadows);
    let ray = scene.camera().generate_ray(x as f32 + 0.5, y as f32 + 0.5);
    let mut tree = RayTree::default();
    let mut context = SampleContext::new(Rng::new(0, 0));
    let colour = whitted.trace_camera_ray(scene, &ray, &mut context, &mut tree);
    (tree, colour, whitted.cut_trees() > 0)
}

fn v(p: Vec3) -> String {
    format!("({:.6}, {:.6}, {:.6})", p.x, p.y, p.z)
}

fn format_tree(scene: &Scene, s: &IntegratorSettings, x: u32, y: u32, tree: &RayTree, colour: Rgb) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "pixel ({x}, {y}) of {}x{}: Whitted ray tree, ray through the pixel centre, max depth {}, min contribution {}, {} shadows",
        scene.camera().width,
        scene.camera().height,
        s.max_depth,
        s.min_contribution,
        if s.transparent_shadows { "transparent" } else { "opaque" }
    );
    for record in &tree.rays {
        write_record(&mut out, scene, record);
    }
    let _ = writeln!(out, "pixel colour = {}", v(colour));
    out
}

fn write_record(out: &mut String, scene: &Scene, r: &RayRecord) {
    let pad = "    ".repeat(r.depth as usize);
    let _ = writeln!(
        out,
        "{pad}{} ray (depth {}, weight {}): origin {}, direction {}",
        r.kind.name(),
        r.depth,
        v(r.weight),
        v(r.ray.origin),
        v(r.ray.direction)
    );
    let Some(hit) = &r.hit else {
        let _ = writeln!(out, "{pad}  missed everything: background {}", v(r.radiance));
        return;
    };
    let object = &scene.objects()[hit.object as usize];
    let _ = writeln!(
        out,
        "{pad}  hit `{}` ({}) with material `{}` at t = {:.5}: point {}, normal {}, uv ({:.4}, {:.4})",
        object.name,
        object.shape.kind(),
        scene.material_names()[hit.material as usize],
        hit.t,
        v(hit.geometry.point),
        v(hit.geometry.shading_normal),
        hit.geometry.uv.x,
        hit.geometry.uv.y
    );
    let _ = writeln!(out, "{pad}  ambient {}", v(r.ambient));
    for l in &r.lights {
        let kind = scene.lights().all()[l.index].kind();
        let state = if !l.facing {
            "behind the surface".to_string()
        } else if l.visibility == Rgb::ZERO {
            "in shadow".to_string()
        } else if l.visibility == Rgb::ONE {
            "visible".to_string()
        } else {
            format!("seen through transparent occluders, transmission {}", v(l.visibility))
        };
        let _ = writeln!(out, "{pad}  light {} ({kind}): {state}, contributes {}", l.index, v(l.contribution));
    }
    let _ = writeln!(out, "{pad}  local (ambient + lights) {}", v(r.local));
    let _ = writeln!(out, "{pad}  = {} (local + weighted reflection and refraction below)", v(r.radiance));
}
