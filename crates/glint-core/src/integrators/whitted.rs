//! Whitted ray tracing (`--integrator whitted`; Whitted 1980, "An Improved Illumination Model
//! for Shaded Display"), the course's recursion:
//!
//! colour = k_a I_a + Σ_lights visible [k_d (N·L) + k_s (R·V)^n] I + k_r·trace(R) + k_t·trace(T)
//!
//! - the terms are the material's at the hit, with the child rays' weights at the angle of
//!   incidence (`Material::whitted_at`): the course's material by its `fresnel` rule; each
//!   member of the BSDF set by its own BSDF (a dielectric's F and 1 − F, a conductor's Fresnel
//!   reflectance, a plastic's coat, a principled material's blended Fresnel term), its rough
//!   lobes as their smooth limit, and light a thin sheet or a mask passes unbent as a third,
//!   straight child ray; a diffuse transmitter is lit through by lights behind it. k_d is an
//!   albedo, so a light's share here is π times the path tracers' ρ/π·(N·L)·I, for every
//!   material alike; what the child rays carry agrees with them (tests/whitted_bsdf_set.rs);
//! - shadow rays test each light with an any-hit query; with `transparent_shadows` the light
//!   is instead multiplied by the transmission k_t of every occluder along the shadow ray
//!   (the course's approximation: no refraction of the shadow ray, opaque occluders block;
//!   for a member of the BSDF set, what it passes on at the shadow ray's angle);
//! - R = I − 2(I·N)N; T by Snell's law, entering when I·N < 0 against the outward geometric
//!   normal; on total internal reflection the transmitted weight goes to reflection;
//! - recursion ends at `max_depth` bounces (0 = local shading with shadows only), when the
//!   path's accumulated weight falls below `min_contribution`, and when a ray leaves the scene
//!   (background colour). Where none of these ends it (unbounded depth in a closed box of
//!   perfect mirrors, or glass whose k_r + k_t ≥ 1 without Fresnel, whose tree doubles at
//!   every surface), two ceilings do: `DEPTH_CEILING` generations, which keeps the recursion
//!   within a worker thread's stack, and `TREE_RAY_LIMIT` rays per sample; the render counts
//!   the samples so cut and warns (`Integrator::warnings`).
//!
//! The same code renders and explains a pixel: it reports every ray to a `Recorder`, a no-op
//! when rendering and the ray tree for `glint explain`.

use std::sync::atomic::{AtomicU64, Ordering};

use super::recorder::{LightRecord, NoRecorder, RayKind, RayTree, Recorder};
use super::{CameraExplanation, Integrator, SampleContext};
use crate::geometry::{reflect, refract, Ray};
use crate::scene::{Scene, SurfaceHit};
use crate::Rgb;

/// How many transparent surfaces a shadow ray passes through at most.
const MAX_SHADOW_OCCLUDERS: usize = 256;

/// The most generations of reflection and refraction, whatever `max_depth` says: each costs
/// a recursion's stack frames (under 1 KiB), and a worker thread has 2 MiB.
pub const DEPTH_CEILING: u32 = 1000;
/// The most rays (camera, reflected, refracted) in one sample's ray tree.
pub const TREE_RAY_LIMIT: u32 = 1 << 12;

#[derive(Debug)]
pub struct Whitted {
    pub max_depth: u32,
    pub min_contribution: f32,
    pub transparent_shadows: bool,
    /// Samples whose tree a ceiling cut, for the render's warning.
    cut_trees: AtomicU64,
}

/// One sample's tree as it grows: rays left before `TREE_RAY_LIMIT`, and whether a ceiling
/// cut a branch.
struct TreeBudget {
    rays_left: u32,
    cut: bool,
}

impl Integrator for Whitted {
    fn radiance(&self, scene: &Scene, ray: &Ray, context: &mut SampleContext) -> Rgb {
        self.trace_camera_ray(scene, ray, context, &mut NoRecorder)
    }

    /// The ray tree of `ray`; its colour is what the render computes for the pixel.
    fn explain(&self, scene: &Scene, ray: &Ray, context: &mut SampleContext) -> Option<CameraExplanation> {
        let cut_before = self.cut_trees();
        let mut tree = RayTree::default();
        let colour = self.trace_camera_ray(scene, ray, context, &mut tree);
        Some(CameraExplanation::Tree { tree, colour, cut: self.cut_trees() > cut_before })
    }

    fn warnings(&self) -> Vec<String> {
        let cut = self.cut_trees.load(Ordering::Relaxed);
        if cut == 0 {
            return Vec::new();
        }
        vec![format!(
            "whitted: the ray trees of {cut} samples were cut at {DEPTH_CEILING} generations or {TREE_RAY_LIMIT} rays, where neither `max_depth` nor `min_contribution` ended them (a closed room of perfect mirrors, or materials whose k_r + k_t ≥ 1); the branches cut add nothing"
        )]
    }
}

impl Whitted {
    pub fn new(max_depth: u32, min_contribution: f32, transparent_shadows: bool) -> Self {
        Self { max_depth, min_contribution, transparent_shadows, cut_trees: AtomicU64::new(0) }
    }

    /// Samples whose ray tree a ceiling cut so far (`DEPTH_CEILING`, `TREE_RAY_LIMIT`).
    pub fn cut_trees(&self) -> u64 {
        self.cut_trees.load(Ordering::Relaxed)
    }

    /// Radiance along a camera ray, every ray of its tree reported to `recorder`.
    pub fn trace_camera_ray<R: Recorder>(
        &self,
        scene: &Scene,
        ray: &Ray,
        context: &mut SampleContext,
        recorder: &mut R,
    ) -> Rgb {
        let mut budget = TreeBudget { rays_left: TREE_RAY_LIMIT - 1, cut: false };
        let radiance = self.trace(scene, ray, RayKind::Camera, 0, Rgb::ONE, context, recorder, &mut budget);
        if budget.cut {
            self.cut_trees.fetch_add(1, Ordering::Relaxed);
        }
        radiance
    }

    /// Radiance along `ray`, which carries `weight` (the product of k_r / k_t above it).
    #[allow(clippy::too_many_arguments)]
    fn trace<R: Recorder>(
        &self,
        scene: &Scene,
        ray: &Ray,
        kind: RayKind,
        depth: u32,
        weight: Rgb,
        context: &mut SampleContext,
        recorder: &mut R,
        budget: &mut TreeBudget,
    ) -> Rgb {
        match kind {
            RayKind::Camera => context.rays.camera += 1,
            RayKind::Reflection => context.rays.reflection += 1,
            RayKind::Refraction => context.rays.refraction += 1,
        }
        recorder.begin_ray(kind, depth, ray, weight);
        let Some(hit) = scene.intersect(ray) else {
            let background = scene.environment().radiance(ray.direction);
            recorder.miss(background);
            return background;
        };
        recorder.hit(&hit);
        let radiance = self.shade(scene, ray, &hit, depth, weight, context, recorder, budget);
        recorder.end_ray(radiance);
        radiance
    }

    #[allow(clippy::too_many_arguments)]
    fn shade<R: Recorder>(
        &self,
        scene: &Scene,
        ray: &Ray,
        hit: &SurfaceHit,
        depth: u32,
        weight: Rgb,
        context: &mut SampleContext,
        recorder: &mut R,
        budget: &mut TreeBudget,
    ) -> Rgb {
        let incident = ray.direction.normalize();
        let entering = incident.dot(hit.geometry.geometric_normal) < 0.0;
        let normal = hit.facing(incident);
        let wo = -incident;
        let cos_incident = -incident.dot(normal);
        // The local model, and the child rays' weights at this angle (every Fresnel factor in).
        let material = scene.materials()[hit.material as usize].whitted_at(
            &hit.texture_query(scene.geometry()),
            entering,
            cos_incident,
        );

        let ambient = material.ambient * scene.environment().ambient_light;
        let mut radiance = ambient;
        recorder.ambient(ambient);
        for (index, light) in scene.lights().all().iter().enumerate() {
            // The course's local shading reads the delta lights alone.
            let Some(illumination) = light.illuminate(hit.geometry.point) else { continue };
            let wi = illumination.direction;
            // A light behind the surface (as seen from the viewer's side) cannot light it, but
            // through a translucent one (diffuse transmission).
            if normal.dot(wi) <= 0.0 && material.translucency == Rgb::ZERO {
                recorder.light(LightRecord {
                    index,
                    direction: wi,
                    facing: false,
                    visibility: Rgb::ZERO,
                    contribution: Rgb::ZERO,
                });
                continue;
            }
            let shadow_ray = match light.position() {
                None => hit.spawn_ray(wi),
                Some(position) => hit.spawn_ray_to(position),
            };
            let visibility = self.visibility(scene, &shadow_ray, context);
            let contribution = visibility * material.local(normal, wo, wi, illumination.intensity);
            recorder.light(LightRecord { index, direction: wi, facing: true, visibility, contribution });
            radiance += contribution;
        }
        recorder.local(radiance);

        if depth >= self.max_depth {
            return radiance;
        }
        if depth >= DEPTH_CEILING {
            budget.cut = true;
            return radiance;
        }
        let eta = if entering { 1.0 / material.ior } else { material.ior };
        let (mut reflection_weight, mut transmission_weight) = (material.reflection, material.transmission);
        let refracted = if transmission_weight != Rgb::ZERO { refract(incident, normal, eta) } else { None };
        if refracted.is_none() {
            // Total internal reflection (or nothing transmitted): the energy is reflected.
            reflection_weight += transmission_weight;
            transmission_weight = Rgb::ZERO;
        }
        if let Some(w) = self.worth_tracing(weight, reflection_weight, budget) {
            let reflected = hit.spawn_ray(reflect(incident, normal));
            radiance += reflection_weight
                * self.trace(scene, &reflected, RayKind::Reflection, depth + 1, w, context, recorder, budget);
        }
        if let Some(direction) = refracted {
            if let Some(w) = self.worth_tracing(weight, transmission_weight, budget) {
                let transmitted = hit.spawn_ray(direction);
                radiance += transmission_weight
                    * self.trace(scene, &transmitted, RayKind::Refraction, depth + 1, w, context, recorder, budget);
            }
        }
        // Light that goes on unbent (a thin sheet, a mask's clear part): a transmitted ray too.
        if let Some(w) = self.worth_tracing(weight, material.straight, budget) {
            let through = hit.spawn_ray(incident);
            radiance += material.straight
                * self.trace(scene, &through, RayKind::Refraction, depth + 1, w, context, recorder, budget);
        }
        radiance
    }

    /// The child ray's accumulated weight, if it is at least `min_contribution` on some channel
    /// and the tree has a ray left for it (which it then takes).
    fn worth_tracing(&self, weight: Rgb, factor: Rgb, budget: &mut TreeBudget) -> Option<Rgb> {
        let w = weight * factor;
        if factor == Rgb::ZERO || w.max_element() < self.min_contribution {
            return None;
        }
        if budget.rays_left == 0 {
            budget.cut = true;
            return None;
        }
        budget.rays_left -= 1;
        Some(w)
    }

    /// Fraction of the light that reaches the end of the shadow ray: 0 or 1, or with transparent
    /// shadows the product of the occluders' transmissions.
    fn visibility(&self, scene: &Scene, shadow_ray: &Ray, context: &mut SampleContext) -> Rgb {
        context.rays.shadow += 1;
        if !self.transparent_shadows {
            return if scene.occluded(shadow_ray) { Rgb::ZERO } else { Rgb::ONE };
        }
        let mut visibility = Rgb::ONE;
        let mut ray = *shadow_ray;
        // Walk the occluders front to back, continuing past each from its far side. A bound on
        // the walk keeps a pathological scene (thousands of coincident layers) finite; past it
        // the light counts as blocked.
        for _ in 0..MAX_SHADOW_OCCLUDERS {
            let Some(hit) = scene.intersect(&ray) else {
                return visibility;
            };
            let outside = ray.direction.dot(hit.geometry.geometric_normal) < 0.0;
            let cos = ray.direction.normalize().dot(hit.geometry.shading_normal).abs();
            let transmission = scene.materials()[hit.material as usize].shadow_transmission(
                &hit.texture_query(scene.geometry()),
                outside,
                cos,
            );
            visibility *= transmission;
            if visibility == Rgb::ZERO {
                break;
            }
            let end = ray.at(ray.t_max);
            let next = hit.spawn_ray(ray.direction);
            // Keep the same end point: the light (or infinity) stays where it was.
            ray = if ray.t_max.is_finite() { Ray::with_range(next.origin, end - next.origin, 0.0, 1.0) } else { next };
            context.rays.shadow += 1;
        }
        Rgb::ZERO
    }
}
