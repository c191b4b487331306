//! `glint explain`'s text: a line per ray of Whitted's tree, per event of a path, per
//! particle's event; each line that adds to the pixel says what it adds, and the last line is
//! the pixel's value, their sum.

use std::fmt::Write;

use glint_core::geometry::Ray;
use glint_core::integrators::passes::Pass;
use glint_core::integrators::path_record::{ParticleEvent, PathEnd, PathEvent, PathLog};
use glint_core::integrators::recorder::{RayRecord, RayTree};
use glint_core::integrators::{Built, IntegratorKind, IntegratorSettings, ParticleExplanation, SppmExplanation};
use glint_core::media::MediumKind;
use glint_core::photons::NearestPhotons;
use glint_core::scene::Scene;
use glint_core::{Rgb, Vec3};

use glint_cli::error::CliError;

/// The path of pixel (x, y)'s sample `pass.index` (as `render --spp 1` takes it) by the
/// integrator `kind`, event by event; the last line is the pixel's value, the sum of the
/// lines that add.
pub(super) fn explain_path(
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
pub(super) fn write_events(out: &mut String, scene: &Scene, log: &PathLog, kind: IntegratorKind) {
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
pub(super) fn explain_particles(scene: &Scene, e: &ParticleExplanation, seed: u64, x: u32, y: u32) -> String {
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

/// SPPM's first pass at pixel (x, y): the camera path's events, then the gather at its visible
/// point and the pixel's value.
pub(super) fn explain_sppm(
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

/// The photons of both maps nearest to the first surface the pixel-centre ray hits, and the
/// radiance estimates photon mapping makes there.
pub(super) fn explain_photons(
    scene: &Scene,
    settings: &IntegratorSettings,
    seed: u64,
    x: u32,
    y: u32,
    k: u32,
) -> Result<String, CliError> {
    // Photon mapping's maps, made as a render makes them.
    let never = std::sync::atomic::AtomicBool::new(false);
    let Built::Photon(mapper) = IntegratorKind::Photon.build_until(settings, scene, seed, &never)? else {
        unreachable!("photon mapping is built as a photon mapper")
    };
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

pub(super) fn format_tree(
    scene: &Scene,
    s: &IntegratorSettings,
    x: u32,
    y: u32,
    tree: &RayTree,
    colour: Rgb,
) -> String {
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

pub(super) fn write_record(out: &mut String, scene: &Scene, r: &RayRecord) {
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

/// What kind of medium the scene's medium `index` is.
pub(super) fn medium_kind(scene: &Scene, index: u32) -> &'static str {
    match scene.media().get(index as usize).map(|m| &m.kind) {
        Some(MediumKind::Homogeneous(_)) => "homogeneous",
        Some(MediumKind::Grid(_)) => "grid",
        None => "?",
    }
}

/// A colour printed so that it reads back to the same bits.
pub(super) fn full(c: Rgb) -> String {
    format!("({}, {}, {})", c.x, c.y, c.z)
}

pub(super) fn v(p: Vec3) -> String {
    format!("({:.6}, {:.6}, {:.6})", p.x, p.y, p.z)
}
