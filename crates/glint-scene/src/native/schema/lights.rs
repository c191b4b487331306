//! The `[[lights]]` array: point, spot and directional lights.

use serde::Deserialize;

use super::{one, Vector};

#[derive(Deserialize, Debug)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
pub enum LightDesc {
    Point {
        position: Vector,
        #[serde(default = "white")]
        color: Vector,
        #[serde(default = "one")]
        intensity: f32,
        #[serde(default)]
        falloff: FalloffDesc,
    },
    Spot {
        position: Vector,
        direction: Vector,
        /// Half-angle in degrees (30 unless `focal_length` gives it).
        cone_angle: Option<f32>,
        /// A projector's lens in mm on 35 mm film (36 × 24), the film's diagonal spanning the
        /// slide's: its cone follows (Mitsuba's projector without `fov`: 50).
        focal_length: Option<f32>,
        #[serde(default = "default_edge")]
        edge: f32,
        /// `"smooth"` (default) or `"linear"` (in the angle, as Mitsuba's spot).
        profile: Option<String>,
        /// A texture projected across the cone, and the slide's up direction.
        texture: Option<String>,
        up: Option<Vector>,
        #[serde(default = "white")]
        color: Vector,
        #[serde(default = "one")]
        intensity: f32,
        #[serde(default)]
        falloff: FalloffDesc,
    },
    Directional {
        direction: Vector,
        #[serde(default = "white")]
        color: Vector,
        #[serde(default = "one")]
        intensity: f32,
    },
}

fn default_edge() -> f32 {
    5.0
}

fn white() -> Vector {
    [1.0; 3]
}

#[derive(Deserialize, Debug, Default, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
pub enum FalloffDesc {
    #[default]
    None,
    InverseSquare,
}
