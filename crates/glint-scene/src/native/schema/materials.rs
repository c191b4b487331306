//! The `[materials]` table: each material by its `type`, and the wrappers that name others.

use serde::Deserialize;

use super::{one, ColorDesc, FractionDesc, Vector};

#[derive(Deserialize, Debug)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
pub enum MaterialDesc {
    Phong {
        diffuse: Option<ColorDesc>,
        ambient: Option<ColorDesc>,
        specular: Option<ColorDesc>,
        shininess: Option<f32>,
        reflection: Option<ColorDesc>,
        transmission: Option<ColorDesc>,
        ior: Option<f32>,
        #[serde(default)]
        fresnel: FresnelDesc,
        roughness: Option<f32>,
        emission: Option<Vector>,
        #[serde(default)]
        two_sided_emission: bool,
    },
    /// A metal: a mirror (or GGX, with `roughness`) whose reflectance is the conductor
    /// Fresnel of `metal` (a name) or of `eta` and `k`, times `tint`.
    Metal {
        metal: Option<String>,
        eta: Option<Vector>,
        k: Option<Vector>,
        tint: Option<ColorDesc>,
        roughness: Option<f32>,
    },
    /// A Lambertian surface (Mitsuba's `diffuse`), two-sided unless `two_sided = false`.
    Diffuse {
        reflectance: Option<ColorDesc>,
        /// Radiance emitted: a colour or a texture over the surface's uv.
        emission: Option<ColorDesc>,
        #[serde(default)]
        two_sided_emission: bool,
        two_sided: Option<bool>,
    },
    /// No surface at all (Mitsuba's `null`): a medium's boundary that light crosses unchanged.
    Null,
    /// Lambert's lobe on both sides of a sheet (pbrt's `diffusetransmission`).
    DiffuseTransmission { reflectance: Option<ColorDesc>, transmittance: Option<ColorDesc> },
    /// A smooth metal (Mitsuba's `conductor`): `metal` (a name) or `eta` and `k`.
    Conductor {
        metal: Option<String>,
        eta: Option<Vector>,
        k: Option<Vector>,
        specular_reflectance: Option<ColorDesc>,
        two_sided: Option<bool>,
    },
    /// A rough metal (Mitsuba's `roughconductor`): `alpha`, or `alpha_u` and `alpha_v`, each
    /// a number or a texture's name.
    RoughConductor {
        metal: Option<String>,
        eta: Option<Vector>,
        k: Option<Vector>,
        specular_reflectance: Option<ColorDesc>,
        alpha: Option<FractionDesc>,
        alpha_u: Option<FractionDesc>,
        alpha_v: Option<FractionDesc>,
        /// `"ggx"` (default) or `"beckmann"`.
        distribution: Option<String>,
        two_sided: Option<bool>,
    },
    /// Smooth glass (Mitsuba's `dielectric`).
    Dielectric {
        int_ior: Option<f32>,
        ext_ior: Option<f32>,
        specular_reflectance: Option<ColorDesc>,
        specular_transmittance: Option<ColorDesc>,
    },
    /// Rough glass (Mitsuba's `roughdielectric`): widths as numbers or texture names.
    RoughDielectric {
        int_ior: Option<f32>,
        ext_ior: Option<f32>,
        specular_reflectance: Option<ColorDesc>,
        specular_transmittance: Option<ColorDesc>,
        alpha: Option<FractionDesc>,
        alpha_u: Option<FractionDesc>,
        alpha_v: Option<FractionDesc>,
        /// `"ggx"` (default) or `"beckmann"`.
        distribution: Option<String>,
    },
    /// A thin pane (Mitsuba's `thindielectric`).
    ThinDielectric {
        int_ior: Option<f32>,
        ext_ior: Option<f32>,
        specular_reflectance: Option<ColorDesc>,
        specular_transmittance: Option<ColorDesc>,
    },
    /// A diffuse base under a smooth coat (Mitsuba's `plastic`).
    Plastic {
        diffuse_reflectance: Option<ColorDesc>,
        specular_reflectance: Option<ColorDesc>,
        int_ior: Option<f32>,
        ext_ior: Option<f32>,
        #[serde(default)]
        nonlinear: bool,
        two_sided: Option<bool>,
    },
    /// A diffuse base under a rough coat (Mitsuba's `roughplastic`, GGX).
    RoughPlastic {
        diffuse_reflectance: Option<ColorDesc>,
        specular_reflectance: Option<ColorDesc>,
        int_ior: Option<f32>,
        ext_ior: Option<f32>,
        #[serde(default)]
        nonlinear: bool,
        alpha: Option<f32>,
        /// `"ggx"` (default) or `"beckmann"`.
        distribution: Option<String>,
        two_sided: Option<bool>,
    },
    /// A rough specular reflection over a Lambert term weighed by the Fresnel transmittance
    /// in and out (Mitsuba's `pplastic` without polarization); one-sided.
    FresnelPlastic {
        diffuse_reflectance: Option<ColorDesc>,
        specular_reflectance: Option<ColorDesc>,
        int_ior: Option<f32>,
        ext_ior: Option<f32>,
        alpha: Option<f32>,
        alpha_u: Option<f32>,
        alpha_v: Option<f32>,
        /// `"beckmann"` (default) or `"ggx"`.
        distribution: Option<String>,
    },
    /// Disney's principled BSDF (Mitsuba's `principled`): each weight a number in [0, 1] or a
    /// texture's luminance; `specular` (in [0, 1]) or `eta` sets the index.
    Principled {
        base_color: Option<ColorDesc>,
        roughness: Option<FractionDesc>,
        anisotropic: Option<FractionDesc>,
        metallic: Option<FractionDesc>,
        spec_trans: Option<FractionDesc>,
        specular: Option<f32>,
        eta: Option<f32>,
        spec_tint: Option<FractionDesc>,
        sheen: Option<FractionDesc>,
        sheen_tint: Option<FractionDesc>,
        flatness: Option<FractionDesc>,
        clearcoat: Option<FractionDesc>,
        clearcoat_gloss: Option<FractionDesc>,
    },
    /// Disney's thin-sheet principled BSDF (Mitsuba's `principledthin`): the weights as in
    /// `principled`, `diff_trans` in [0, 2], `eta` a number or texture, and the lobes'
    /// sampling rates.
    PrincipledThin {
        base_color: Option<ColorDesc>,
        roughness: Option<FractionDesc>,
        anisotropic: Option<FractionDesc>,
        spec_trans: Option<FractionDesc>,
        diff_trans: Option<FractionDesc>,
        eta: Option<FractionDesc>,
        spec_tint: Option<FractionDesc>,
        sheen: Option<FractionDesc>,
        sheen_tint: Option<FractionDesc>,
        flatness: Option<FractionDesc>,
        diffuse_reflectance_sampling_rate: Option<f32>,
        specular_reflectance_sampling_rate: Option<f32>,
        specular_transmittance_sampling_rate: Option<f32>,
        diffuse_transmittance_sampling_rate: Option<f32>,
    },
    /// (1 − weight)·first + weight·second (Mitsuba's `blendbsdf`); materials by name.
    Blend { weight: Option<FractionDesc>, first: String, second: String },
    /// `material` where the surface is, passed through elsewhere (Mitsuba's `mask`).
    Mask { opacity: Option<FractionDesc>, material: String },
    /// `material` about the shading normal a texture gives (Mitsuba's `normalmap`).
    NormalMap { normals: ColorDesc, material: String },
    /// `material` about a normal tilted by the height field `height` (a texture of uv, its
    /// luminance) times `scale` (Mitsuba's `bumpmap`).
    BumpMap {
        height: String,
        #[serde(default = "one")]
        scale: f32,
        material: String,
    },
    /// One material per side (Mitsuba's `twosided` with two BSDFs); `back` defaults to `front`.
    TwoSided { front: String, back: Option<String> },
    /// `material` emitting `radiance`, a colour or a texture over the surface's uv (Mitsuba's
    /// `area` emitter on a shape).
    Emitter {
        radiance: ColorDesc,
        #[serde(default)]
        two_sided: bool,
        material: String,
    },
}

#[derive(Deserialize, Debug, Default, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
pub enum FresnelDesc {
    #[default]
    None,
    Schlick,
    Exact,
}
