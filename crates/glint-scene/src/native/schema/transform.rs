//! A `transform`: a list of operations, the first applied first.

use serde::Deserialize;

use super::Vector;

#[derive(Deserialize, Debug, Clone)]
#[serde(rename_all = "kebab-case", deny_unknown_fields)]
pub enum TransformOp {
    Translate(Vector),
    Rotate(RotateDesc),
    Scale(ScaleDesc),
    /// Row-major 4×4 matrix (the last row is normally [0, 0, 0, 1]).
    Matrix([[f32; 4]; 4]),
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct RotateDesc {
    pub axis: Vector,
    /// Degrees, counter-clockwise looking down the axis toward the origin (right-hand rule).
    pub angle: f32,
}

#[derive(Deserialize, Debug, Clone, Copy)]
#[serde(untagged)]
pub enum ScaleDesc {
    Uniform(f32),
    PerAxis(Vector),
}
