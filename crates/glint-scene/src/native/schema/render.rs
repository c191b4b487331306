//! The `[render]` table (integrator, samples, filter, sampler, photon mapping) and the
//! `[intersection]` table (which of the course's methods intersects each shape).

use glint_core::integrators::PhotonSettings;
use glint_core::lights::{LightSelection, TriangleSampling};
use glint_core::sampling::SamplerKind;
use glint_core::Named;
use serde::Deserialize;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct RenderDesc {
    #[serde(default = "default_spp")]
    pub spp: u32,
    #[serde(default = "default_max_depth")]
    pub max_depth: i64,
    #[serde(default = "default_rr_depth")]
    pub rr_depth: u32,
    #[serde(default = "default_integrator")]
    pub integrator: String,
    #[serde(default)]
    pub seed: u64,
    #[serde(default = "default_min_contribution")]
    pub min_contribution: f32,
    #[serde(default)]
    pub transparent_shadows: bool,
    #[serde(default = "default_filter")]
    pub filter: String,
    #[serde(default = "default_sampler")]
    pub sampler: String,
    #[serde(default = "default_light_sampling")]
    pub light_sampling: String,
    #[serde(default = "default_light_selection")]
    pub light_selection: String,
    /// Keep each pixel's second moment and write it beside the image (Mitsuba's `moment`).
    #[serde(default)]
    pub moment: bool,
    /// Photon mapping (see `PhotonSettings`).
    #[serde(default = "default_photons")]
    pub photons: u32,
    #[serde(default = "default_photons")]
    pub caustic_photons: u32,
    #[serde(default = "default_photon_nearest")]
    pub photon_nearest: u32,
    #[serde(default)]
    pub photon_radius: f32,
    #[serde(default = "default_final_gather")]
    pub final_gather: u32,
    /// SPPM.
    #[serde(default)]
    pub sppm_radius: f32,
    #[serde(default)]
    pub photons_per_pass: u32,
}

fn default_sampler() -> String {
    SamplerKind::default().name().into()
}
fn default_light_sampling() -> String {
    TriangleSampling::default().name().into()
}
fn default_light_selection() -> String {
    LightSelection::default().name().into()
}
fn default_photons() -> u32 {
    PhotonSettings::default().global_photons
}
fn default_photon_nearest() -> u32 {
    PhotonSettings::default().nearest
}
fn default_final_gather() -> u32 {
    PhotonSettings::default().final_gather
}

impl Default for RenderDesc {
    fn default() -> Self {
        Self {
            spp: default_spp(),
            max_depth: default_max_depth(),
            rr_depth: default_rr_depth(),
            integrator: default_integrator(),
            seed: 0,
            min_contribution: default_min_contribution(),
            transparent_shadows: false,
            filter: default_filter(),
            sampler: default_sampler(),
            light_sampling: default_light_sampling(),
            light_selection: default_light_selection(),
            moment: false,
            photons: default_photons(),
            caustic_photons: default_photons(),
            photon_nearest: default_photon_nearest(),
            photon_radius: 0.0,
            final_gather: default_final_gather(),
            sppm_radius: 0.0,
            photons_per_pass: 0,
        }
    }
}

fn default_filter() -> String {
    "box".into()
}

fn default_min_contribution() -> f32 {
    1e-3
}

fn default_spp() -> u32 {
    1
}
fn default_max_depth() -> i64 {
    5
}
fn default_rr_depth() -> u32 {
    5
}
fn default_integrator() -> String {
    "raycast".into()
}

#[derive(Deserialize, Debug, Default)]
#[serde(deny_unknown_fields)]
pub struct IntersectionDesc {
    /// Names of the core's methods (`Named`), parsed by the builder; `None`: the default.
    pub sphere: Option<String>,
    pub triangle: Option<String>,
    pub polygon: Option<String>,
    #[serde(rename = "box")]
    pub aabox: Option<String>,
}
