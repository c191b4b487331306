//! `glint explain --json`: the same events as the text, as JSON for other tools; colours and
//! vectors as [x, y, z].

use glint_core::geometry::Ray;
use glint_core::integrators::passes::Pass;
use glint_core::integrators::path_record::{ParticleEvent, PathEvent, PathLog};
use glint_core::integrators::{IntegratorKind, ParticleExplanation, SppmExplanation};
use glint_core::scene::Scene;
use glint_core::{Named, Rgb, Vec3};

use super::text::medium_kind;

/// `explain_particles` as JSON: `{"pixel", "integrator": "light", "seed", "particles":
/// [{"index", "events": [...]}], "environment", "value"}`.
pub(super) fn particles_json(scene: &Scene, e: &ParticleExplanation, seed: u64, x: u32, y: u32) -> String {
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

/// `explain_sppm` as JSON: the camera path's events as `path_json` writes them, the gather,
/// and the value.
pub(super) fn sppm_json(
    scene: &Scene,
    traced: &(Ray, Rgb, PathLog),
    e: &SppmExplanation,
    pass: &Pass,
    x: u32,
    y: u32,
) -> String {
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

/// `explain_path` as JSON: `{"pixel", "integrator", "seed", "camera_ray": {"origin",
/// "direction"}, "events": [{"event": "vertex" | "emission" | "light_sample" | "scatter" |
/// "medium" | "phase" | "medium_photons" | "roulette" | "escape" | "end", …}], "value"}`, colours and vectors as
/// [x, y, z].
pub(super) fn path_json(
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
