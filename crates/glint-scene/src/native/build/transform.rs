//! A shape's (or grid's, or map's) `transform`: its operations composed in order.

use glam::{Mat4, Quat, Vec3};
use glint_core::geometry::Transform;

use super::checks::finite;
use crate::native::schema::*;

/// Composes the operations in order: the first is applied to the shape first.
pub(super) fn build_transform(ops: &[TransformOp]) -> Result<Option<Transform>, String> {
    if ops.is_empty() {
        return Ok(None);
    }
    let mut matrix = Mat4::IDENTITY;
    for op in ops {
        let m = match op {
            TransformOp::Translate(v) => Mat4::from_translation(finite(*v)?),
            TransformOp::Rotate(r) => {
                let axis = finite(r.axis)?.try_normalize().ok_or("rotation `axis` must not be the zero vector")?;
                if !r.angle.is_finite() {
                    return Err(format!("rotation `angle` must be finite, got {}", r.angle));
                }
                Mat4::from_quat(Quat::from_axis_angle(axis, r.angle.to_radians()))
            }
            TransformOp::Scale(ScaleDesc::Uniform(s)) => Mat4::from_scale(Vec3::splat(*s)),
            TransformOp::Scale(ScaleDesc::PerAxis(s)) => Mat4::from_scale(finite(*s)?),
            TransformOp::Matrix(rows) => {
                if rows.iter().flatten().any(|x| !x.is_finite()) {
                    return Err("`matrix` entries must be finite".into());
                }
                Mat4::from_cols_array_2d(rows).transpose()
            }
        };
        matrix = m * matrix;
    }
    Transform::from_matrix(matrix).map(Some).ok_or_else(|| {
        let determinant = matrix.determinant().abs();
        if determinant.is_finite() {
            "the transform is singular (a zero scale?)".to_string()
        } else {
            format!("the transform scales volumes by {determinant}: more than single precision holds (a huge scale?)")
        }
    })
}
