//! The estimators the camera-path integrators share, each written once: multiple importance
//! sampling's weights (the power heuristic, light found by a sampled direction where the path
//! leaves the scene or meets an emitter), next-event estimation (one light sample, its
//! visibility and its weight, at a surface or in a medium), and Russian roulette (for camera
//! paths; a particle's is in `particle.rs`). `path`, `volpath`, `path-naive`, photon mapping
//! and SPPM call these; the wavefront's lanes compute the same bits (their lane versions, with
//! an `8`, sit beside them).

use crate::lanes::{LaneVec3, Lanes};
use crate::sampling::warp::UNIFORM_SPHERE_PDF;
use glam::Vec3;

use super::path::BounceDraws;
use super::path_record::{LightSampleRecord, PathRecorder};
use super::SampleContext;
use crate::lights::LightSample;
use crate::materials::Bsdf;
use crate::scene::{Scene, SurfaceHit};
use crate::Rgb;

/// The power heuristic (β = 2) for the strategy with density `a` against one with `b`.
pub fn power_heuristic(a: f32, b: f32) -> f32 {
    power_heuristic_lanes(a, b)
}

/// `power_heuristic` in lanes: an infinite density (a delta lobe) weighs 1, two zero densities 0.
#[inline(always)]
pub(crate) fn power_heuristic_lanes<L: Lanes>(a: L, b: L) -> L {
    let (a2, b2) = (a * a, b * b);
    let special = (a2 + b2).eq(L::ZERO) | !a2.is_finite();
    L::select(special, L::select(a2.is_infinite(), L::ONE, L::ZERO), a2 / (a2 + b2))
}

/// A scattering event that sampled the ray now traced: what the MIS weight of light found
/// along that ray depends on.
#[derive(Clone, Copy, Debug)]
pub(super) struct Scatter {
    pub point: Vec3,
    /// What light sampling from `point` was given as the receiver's normal: the surface's
    /// shading normal, `None` in a medium.
    pub normal: Option<Vec3>,
    /// The BSDF's (or phase function's) solid-angle density for the sampled direction.
    pub pdf: f32,
    /// A mirror or refraction: light sampling could not have made it.
    pub delta: bool,
}

impl Scatter {
    /// The density that light sampling's is weighed against, if light sampling could have
    /// made the direction (`None` after a delta bounce).
    fn density(&self) -> Option<f32> {
        (!self.delta).then_some(self.pdf)
    }
}

/// The light a ray finds where it leaves the scene, and its MIS weight: the environment
/// weighed against light sampling where a non-delta scattering with density `bsdf_pdf` chose
/// the direction (the sky's background, in full, where light sampling cannot find it).
pub(super) fn escaped(scene: &Scene, direction: Vec3, bsdf_pdf: Option<f32>) -> (Rgb, f32) {
    let (radiance, weight) = escaped_lanes(scene, direction.into(), bsdf_pdf.unwrap_or(0.0), bsdf_pdf.is_some());
    (radiance.into(), weight)
}

/// `escaped` in lanes: each lane's direction, and its scattering's density `bsdf_pdf` where
/// `weighed` (else, a camera ray or a delta bounce, the light counts in full). An environment
/// map is read for all the lanes at once (`EnvironmentMap::radiance_and_pdf_lanes`).
#[inline(always)]
pub(crate) fn escaped_lanes<L: Lanes>(
    scene: &Scene,
    direction: LaneVec3<L>,
    bsdf_pdf: L,
    weighed: L::Mask,
) -> (LaneVec3<L>, L) {
    let environment = scene.environment();
    let selection = scene.lights().environment_selection().filter(|_| L::any(weighed));
    let (radiance, light_pdf) = match &environment.map {
        Some(map) => map.radiance_and_pdf_lanes(direction, selection.is_some()),
        None => (LaneVec3::splat(environment.background), L::splat(UNIFORM_SPHERE_PDF)),
    };
    let weight = match selection {
        Some(selection) => L::select(weighed, power_heuristic_lanes(bsdf_pdf, light_pdf * L::splat(selection)), L::ONE),
        None => L::ONE,
    };
    (radiance, weight)
}

/// Adds to `radiance` what a path of `throughput` finds leaving the scene along `direction`,
/// sampled by `previous` (`None`: a camera ray), and tells `recorder`.
pub(super) fn add_escaped(
    scene: &Scene,
    direction: Vec3,
    previous: Option<Scatter>,
    throughput: Rgb,
    radiance: &mut Rgb,
    recorder: &mut impl PathRecorder,
) {
    let (background, weight) = escaped(scene, direction, previous.and_then(|from| from.density()));
    let added = throughput * background * weight;
    *radiance += added;
    recorder.escape(background, weight, added);
}

/// Adds to `radiance` the emission `emitted` found at `hit` by a path of `throughput` whose
/// direction `previous` sampled, weighed against light sampling's density for the same point
/// (in full after a camera ray or a delta bounce), and tells `recorder`.
pub(super) fn add_emission(
    scene: &Scene,
    hit: &SurfaceHit,
    emitted: Rgb,
    previous: Option<Scatter>,
    throughput: Rgb,
    radiance: &mut Rgb,
    recorder: &mut impl PathRecorder,
) {
    if emitted == Rgb::ZERO {
        return;
    }
    let weight = match previous {
        Some(from) if !from.delta => {
            let g = &hit.geometry;
            let light_pdf =
                scene.lights().pdf_area(from.point, from.normal, hit.object, hit.prim, g.point, g.geometric_normal);
            power_heuristic(from.pdf, light_pdf)
        }
        _ => 1.0,
    };
    let added = throughput * emitted * weight;
    *radiance += added;
    recorder.emission(emitted, weight, added);
}

/// Russian roulette on a camera path (Mitsuba's rule): the path survives with probability
/// min(max throughput · η², 0.95), and a survivor's throughput is divided by that probability,
/// which keeps the estimate unbiased. Returns whether the path goes on (the caller ends it
/// otherwise); `recorder` is told the survival probability and the verdict.
pub(super) fn roulette(
    throughput: &mut Rgb,
    eta_scale: f32,
    context: &mut SampleContext,
    recorder: &mut impl PathRecorder,
) -> bool {
    let survival = (throughput.max_element() * eta_scale).min(0.95);
    // Written as the test for ending, so a NaN survival draws and goes on, as the path tracer
    // always did (volpath's own roulette ended such a path; its throughput is NaN already).
    let survived = !(survival <= 0.0 || BounceDraws::roulette(&mut context.sampler) >= survival);
    recorder.roulette(survival, survived);
    if survived {
        *throughput /= survival;
    }
    survived
}

/// How next-event estimation weighs its sample of a light that BSDF sampling can also find
/// (an area light, the environment; a delta light counts in full).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Weighting {
    /// Against BSDF sampling by the power heuristic (the caller counts BSDF-sampled emission
    /// with the matching weight).
    Mis,
    /// In full: the caller never counts emission found by sampling the BSDF's non-delta
    /// lobes (photon mapping, SPPM, volumetric photon mapping).
    LightOnly,
}

/// What next-event estimation adds (before the path's throughput), and its light sample where
/// one carried light toward the point (its `added` left for the caller).
pub(super) struct NextEvent {
    pub contribution: Rgb,
    pub sample: Option<LightSampleRecord>,
}

/// How light leaves the point toward a light sample's direction: the BSDF or phase function's
/// value there (cosine included), its density for MIS, and the visibility of the sample (the
/// shadow ray's transmittance: 0 or 1 for an opaque scene, attenuated through media).
pub(super) trait Scattering {
    fn value(&self, wi: Vec3) -> Rgb;
    fn density(&self, wi: Vec3) -> f32;
    fn visibility(&mut self, light: &LightSample) -> Rgb;
}

/// Next-event estimation from `point` (with the receiver's `normal`, `None` in a medium): one
/// light chosen by the scene's light selection, one sample of it (a point on an area light, a
/// direction toward the environment, or a delta light, which only light sampling can find),
/// its visibility, and the scattering there, weighed by `weighting`.
#[inline(always)]
pub(super) fn next_event(
    scene: &Scene,
    point: Vec3,
    normal: Option<Vec3>,
    mut scattering: impl Scattering,
    weighting: Weighting,
    context: &mut SampleContext,
) -> NextEvent {
    let none = NextEvent { contribution: Rgb::ZERO, sample: None };
    let (u_select, u) = BounceDraws::light(&mut context.sampler);
    let Some(light) = scene.lights().sample_li(point, normal, u_select, u) else { return none };
    let f = scattering.value(light.direction);
    let carries_light = light.radiance != Rgb::ZERO && f != Rgb::ZERO && light.pdf > 0.0;
    if !carries_light {
        return none;
    }
    context.rays.shadow += 1;
    let record = |mis_weight: f32, occluded: bool| LightSampleRecord::new(&light, mis_weight, occluded, Rgb::ZERO);
    let transmittance = scattering.visibility(&light);
    if transmittance == Rgb::ZERO {
        return NextEvent { contribution: Rgb::ZERO, sample: Some(record(0.0, true)) };
    }
    let weight = match weighting {
        Weighting::Mis if !light.delta => power_heuristic(light.pdf, scattering.density(light.direction)),
        _ => 1.0,
    };
    let contribution = f * light.radiance * transmittance * (weight / light.pdf);
    NextEvent { contribution, sample: Some(record(weight, false)) }
}

/// A surface's BSDF seen from `wo`, lit through an opaque scene: the shadow ray is blocked or
/// not.
struct OpaqueSurface<'a> {
    scene: &'a Scene,
    hit: &'a SurfaceHit,
    bsdf: &'a Bsdf<'a>,
    wo: Vec3,
}

impl Scattering for OpaqueSurface<'_> {
    #[inline(always)]
    fn value(&self, wi: Vec3) -> Rgb {
        self.bsdf.eval(self.wo, wi)
    }

    #[inline(always)]
    fn density(&self, wi: Vec3) -> f32 {
        self.bsdf.pdf(self.wo, wi)
    }

    #[inline(always)]
    fn visibility(&mut self, light: &LightSample) -> Rgb {
        if self.scene.occluded(&self.hit.spawn_shadow_ray(light)) {
            Rgb::ZERO
        } else {
            Rgb::ONE
        }
    }
}

/// Next-event estimation at a surface of an opaque scene (no media): what a light sample adds
/// there before the path's throughput, and the sample.
#[inline(always)]
pub(super) fn surface_next_event(
    scene: &Scene,
    hit: &SurfaceHit,
    bsdf: &Bsdf,
    wo: Vec3,
    weighting: Weighting,
    context: &mut SampleContext,
) -> NextEvent {
    let surface = OpaqueSurface { scene, hit, bsdf, wo };
    next_event(scene, hit.geometry.point, Some(hit.geometry.shading_normal), surface, weighting, context)
}

/// Adds `event` times the path's `throughput` to `radiance`, its light sample told to
/// `recorder`; returns what was added.
pub(super) fn add_next_event(
    event: NextEvent,
    throughput: Rgb,
    radiance: &mut Rgb,
    recorder: &mut impl PathRecorder,
) -> Rgb {
    let added = throughput * event.contribution;
    *radiance += added;
    if let Some(sample) = event.sample {
        recorder.light_sample(LightSampleRecord { added, ..sample });
    }
    added
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_heuristic_by_hand() {
        assert_eq!(power_heuristic(1.0, 0.0), 1.0);
        assert_eq!(power_heuristic(0.0, 1.0), 0.0);
        assert!((power_heuristic(1.0, 2.0) - 0.2).abs() < 1e-6);
        assert!((power_heuristic(3.0, 1.0) + power_heuristic(1.0, 3.0) - 1.0).abs() < 1e-6);
    }

    /// Eight lanes compute one lane's bits, special values included (NaN, ±0,
    /// infinities).
    #[test]
    fn power_heuristic_in_eight_lanes_equals_one_lane() {
        let specials = [0.0, -0.0, 1.0, 0.5, f32::INFINITY, f32::NAN, 1e-30, 3.0e30, 2.0, -1.0];
        for i in 0..specials.len() {
            for &y in &specials {
                let lanes: [f32; 8] = std::array::from_fn(|k| specials[(i + k) % specials.len()]);
                let heuristic = power_heuristic_lanes(wide::f32x8::from(lanes), wide::f32x8::splat(y)).to_array();
                for k in 0..8 {
                    let expected = power_heuristic(lanes[k], y);
                    assert_eq!(heuristic[k].to_bits(), expected.to_bits(), "heuristic of {}, {y}", lanes[k]);
                }
            }
        }
    }
}
