//! The `[render]` table: the integrator and its settings, samples, filter, sampler and how
//! lights are sampled and chosen, checked.

use glint_core::filter::Filter;
use glint_core::integrators::{IntegratorKind, IntegratorSettings, PhotonSettings};
use glint_core::lights::{LightSelection, TriangleSampling};
use glint_core::sampling::SamplerKind;

use super::checks::by_name;
use super::Context;
use crate::error::SceneError;
use crate::native::schema::*;
use crate::native::RenderOptions;

pub(super) fn build_render(cx: &Context, r: &RenderDesc) -> Result<RenderOptions, SceneError> {
    let integrator: IntegratorKind = by_name(cx, "integrator", "integrator", &r.integrator)?;
    if r.spp == 0 {
        return Err(cx.error_at_key("spp", "`spp` (samples per pixel) must be at least 1".into()));
    }
    if !(r.min_contribution.is_finite() && r.min_contribution >= 0.0) {
        return Err(cx.error_at_key(
            "min_contribution",
            format!("`min_contribution` must be a number ≥ 0, got {}", r.min_contribution),
        ));
    }
    if r.max_depth < -1 || r.max_depth > u32::MAX as i64 {
        return Err(
            cx.error_at_key("max_depth", format!("`max_depth` must be -1 (unbounded) or ≥ 0, got {}", r.max_depth))
        );
    }
    for (key, value) in [("photon_radius", r.photon_radius), ("sppm_radius", r.sppm_radius)] {
        if !(value.is_finite() && value >= 0.0) {
            return Err(cx.error_at_key(key, format!("`{key}` must be a length ≥ 0 (0: automatic), got {value}")));
        }
    }
    if r.photon_nearest == 0 {
        return Err(cx.error_at_key("photon_nearest", "`photon_nearest` must be at least 1".into()));
    }
    let integrator_settings = IntegratorSettings {
        max_depth: if r.max_depth < 0 { u32::MAX } else { r.max_depth as u32 },
        rr_depth: r.rr_depth,
        min_contribution: r.min_contribution,
        transparent_shadows: r.transparent_shadows,
        photon: PhotonSettings {
            global_photons: r.photons,
            caustic_photons: r.caustic_photons,
            nearest: r.photon_nearest,
            max_radius: r.photon_radius,
            final_gather: r.final_gather,
        },
        sppm_radius: r.sppm_radius,
        photons_per_pass: r.photons_per_pass,
        wavefront: true,
    };
    let filter: Filter = by_name(cx, "filter", "filter", &r.filter)?;
    let sampler: SamplerKind = by_name(cx, "sampler", "sampler", &r.sampler)?;
    let light_sampling: TriangleSampling = by_name(cx, "light_sampling", "light sampling", &r.light_sampling)?;
    let light_selection: LightSelection = by_name(cx, "light_selection", "light selection", &r.light_selection)?;
    Ok(RenderOptions {
        spp: r.spp,
        integrator,
        seed: r.seed,
        integrator_settings,
        filter,
        sampler,
        light_sampling,
        light_selection,
        moment: r.moment,
    })
}
