//! The `[environment]` table: background, ambient light and environment map.

use serde::Deserialize;

use super::{TransformOp, Vector};

#[derive(Deserialize, Debug, Default)]
#[serde(deny_unknown_fields)]
pub struct EnvironmentDesc {
    #[serde(default)]
    pub background: Vector,
    #[serde(default)]
    pub ambient: Vector,
    /// An equirectangular environment map (EXR for HDR), relative to the scene.
    pub map: Option<String>,
    pub map_scale: Option<f32>,
    /// Rotations of the map (applied in order).
    #[serde(default)]
    pub map_transform: Vec<TransformOp>,
}
