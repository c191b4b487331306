//! The `[textures]` table: checkerboards, images, marble, wood, mesh attributes, and pbrt's
//! procedural textures (noise patterns, polka dots, bilinear blends).

use serde::Deserialize;

use super::{ColorDesc, TransformOp, Vector};

/// A number for both axes or one per axis.
#[derive(Deserialize, Debug, Clone, Copy)]
#[serde(untagged)]
pub enum Scale2Desc {
    Uniform(f32),
    PerAxis([f32; 2]),
}

#[derive(Deserialize, Debug, Clone)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
pub enum TextureDesc {
    Checker {
        even: Vector,
        odd: Vector,
        scale: Option<Scale2Desc>,
        /// An affine map of uv after `scale`: rows [a, b, c] and [d, e, f].
        uv_transform: Option<[[f32; 3]; 2]>,
        /// Coordinates made from the point instead of the surface's uv.
        mapping: Option<MappingDesc>,
    },
    SolidChecker {
        even: Vector,
        odd: Vector,
        scale: Option<f32>,
    },
    Image {
        file: String,
        #[serde(default)]
        wrap: WrapDesc,
        #[serde(default)]
        filter: TexelFilterDesc,
        scale: Option<Scale2Desc>,
        uv_transform: Option<[[f32; 3]; 2]>,
        /// The stored values as they are (normal maps, data), not decoded from sRGB.
        #[serde(default)]
        raw: bool,
        /// One channel (0 red, 1 green, 2 blue) as grey: packed data, as glTF's
        /// metallic-roughness maps.
        channel: Option<u8>,
        /// A factor for every texel (glTF's colour factors, pbrt's `scale`).
        tint: Option<Vector>,
        /// Coordinates made from the point instead of the surface's uv.
        mapping: Option<MappingDesc>,
    },
    Marble {
        base: Vector,
        vein: Vector,
        scale: Option<f32>,
        turbulence: Option<f32>,
        octaves: Option<u32>,
    },
    Wood {
        light: Vector,
        dark: Vector,
        rings: Option<f32>,
        turbulence: Option<f32>,
    },
    /// A mesh's own values (`vertex_color`, `face_weight`, …: Mitsuba's `mesh_attribute`).
    MeshAttribute {
        name: String,
        scale: Option<f32>,
    },
    /// Two colours or textures multiplied channel by channel (glTF's base colour times its
    /// vertex colours); the textures it names cannot themselves be made of others (products,
    /// mixes, direction mixes).
    Product {
        factors: [ColorDesc; 2],
    },
    /// (1 − w)·first + w·second, w the `amount`'s luminance clamped to [0, 1] (pbrt's `mix`);
    /// the textures it names cannot themselves be made of others.
    Mix {
        first: ColorDesc,
        second: ColorDesc,
        amount: ColorDesc,
    },
    /// |n · direction|·first + (1 − |n · direction|)·second, n the surface's geometric normal
    /// and `direction` placed by `transform` (pbrt's `directionmix`); the textures it names
    /// cannot themselves be made of others.
    DirectionMix {
        first: ColorDesc,
        second: ColorDesc,
        direction: Vector,
        #[serde(default)]
        transform: Vec<TransformOp>,
    },
    /// pbrt's `fbm`: fractional Brownian motion of the point in the texture's space.
    Fbm {
        roughness: Option<f32>,
        octaves: Option<u32>,
        #[serde(default)]
        transform: Vec<TransformOp>,
    },
    /// pbrt's `wrinkled`: turbulence of the point in the texture's space.
    Wrinkled {
        roughness: Option<f32>,
        octaves: Option<u32>,
        #[serde(default)]
        transform: Vec<TransformOp>,
    },
    /// pbrt's `windy`: waves scaled by the wind's strength.
    Windy {
        #[serde(default)]
        transform: Vec<TransformOp>,
    },
    /// pbrt's `marble`: layers along y bent by fbm, through its spline of greys.
    PbrtMarble {
        roughness: Option<f32>,
        octaves: Option<u32>,
        scale: Option<f32>,
        variation: Option<f32>,
        #[serde(default)]
        transform: Vec<TransformOp>,
    },
    /// pbrt's `dots`: polka dots in uv.
    Dots {
        inside: Vector,
        outside: Vector,
        uv_transform: Option<[[f32; 3]; 2]>,
        mapping: Option<MappingDesc>,
    },
    /// pbrt's `bilerp`: four values blended bilinearly over the unit square of uv.
    Bilerp {
        v00: Vector,
        v01: Vector,
        v10: Vector,
        v11: Vector,
        uv_transform: Option<[[f32; 3]; 2]>,
        mapping: Option<MappingDesc>,
    },
}

/// A 2D texture's coordinates made from the hit point, in a texture space that `transform`
/// places in the world (pbrt's mappings): `spherical` (θ / π from +z, φ / 2π about it),
/// `cylindrical` ((π + φ) / 2π about +z, and z), `planar` (offsets plus the point's
/// projections on two axes).
#[derive(Deserialize, Debug, Clone)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
pub enum MappingDesc {
    Spherical {
        #[serde(default)]
        transform: Vec<TransformOp>,
    },
    Cylindrical {
        #[serde(default)]
        transform: Vec<TransformOp>,
    },
    Planar {
        #[serde(default)]
        transform: Vec<TransformOp>,
        s_axis: Option<Vector>,
        t_axis: Option<Vector>,
        #[serde(default)]
        s_offset: f32,
        #[serde(default)]
        t_offset: f32,
    },
}

#[derive(Deserialize, Debug, Default, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
pub enum WrapDesc {
    #[default]
    Repeat,
    Clamp,
    Mirror,
}

#[derive(Deserialize, Debug, Default, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
pub enum TexelFilterDesc {
    #[default]
    Bilinear,
    Nearest,
}
