//! The `[media]` table: homogeneous and grid media and their phase functions.

use serde::Deserialize;

use super::{TransformOp, Vector};

/// A participating medium.
#[derive(Deserialize, Debug)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
pub enum MediumDesc {
    /// σ_a and σ_s, or σ_t and the albedo σ_s / σ_t (per channel, per unit length), each
    /// times `scale`.
    Homogeneous {
        sigma_a: Option<Vector>,
        sigma_s: Option<Vector>,
        sigma_t: Option<Vector>,
        albedo: Option<Vector>,
        scale: Option<f32>,
        phase: Option<PhaseDesc>,
        /// Radiance emitted where the medium absorbs (σ_a × this per unit length).
        emission: Option<Vector>,
    },
    /// σ_t = `scale` × a density field: a Mitsuba `.vol` grid (`file`, one channel or three)
    /// or one `value` (per channel), over a box: the file's own, or `min`–`max`, or the unit
    /// cube moved by `transform` (as Mitsuba's `to_world`). The medium is empty outside the
    /// box. The `albedo` is a constant or a field of its own.
    Grid {
        file: Option<String>,
        value: Option<Vector>,
        min: Option<Vector>,
        max: Option<Vector>,
        #[serde(default)]
        transform: Vec<TransformOp>,
        albedo: Option<AlbedoDesc>,
        scale: Option<f32>,
        phase: Option<PhaseDesc>,
        emission: Option<Vector>,
    },
}

/// A grid medium's albedo: one colour, or a `.vol` field placed as the density's is.
#[derive(Deserialize, Debug)]
#[serde(untagged)]
pub enum AlbedoDesc {
    Constant(Vector),
    Field(AlbedoField),
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct AlbedoField {
    pub file: String,
    pub min: Option<Vector>,
    pub max: Option<Vector>,
    #[serde(default)]
    pub transform: Vec<TransformOp>,
    /// `clamp` (the default: outside its box, the nearest edge) or `repeat` (the field
    /// repeated past its box, Mitsuba's `wrap_mode`).
    pub wrap: Option<String>,
}

#[derive(Deserialize, Debug, Clone, Copy)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
pub enum PhaseDesc {
    Isotropic,
    /// Henyey–Greenstein, mean cosine `g` in (−1, 1).
    Hg {
        g: f32,
    },
}
