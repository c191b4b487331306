//! Rays that never re-hit the surface they leave, at any scene scale.
//!
//! Each shape reports a conservative bound on the floating-point error of its hit point
//! (pbrt-v4 §6.8: Higham's γ_n = nε/(1 − nε) bounds n roundings). A spawned ray's origin is
//! moved along the geometric normal just past that error box, then rounded away from the
//! surface, so it lies strictly on the side the ray leaves toward. No fixed epsilon: the offset
//! scales with the coordinates, so the same scene at 1e-3 or 1e5 renders the same. The one
//! margin is relative too: a shadow ray toward a point on a light stops 10⁻⁴ of its length
//! short (`SurfaceHit::spawn_ray_to_surface`), since the light's own intersection routine may
//! find its surface a few ulps before the sampled point.

use glam::{Mat4, Vec3};

/// Half an ulp of 1: the unit roundoff of f32.
const MACHINE_EPSILON: f32 = f32::EPSILON * 0.5;

/// γ_n: the relative error bound of n successive floating-point operations.
pub const fn gamma(n: i32) -> f32 {
    let n = n as f32;
    (n * MACHINE_EPSILON) / (1.0 - n * MACHINE_EPSILON)
}

/// The smallest f32 greater than `x` (−0 and +0 both step to the smallest subnormal).
pub fn next_float_up(x: f32) -> f32 {
    if x.is_infinite() && x > 0.0 {
        return x;
    }
    let x = if x == -0.0 { 0.0 } else { x };
    let bits = x.to_bits();
    f32::from_bits(if x >= 0.0 { bits + 1 } else { bits - 1 })
}

pub fn next_float_down(x: f32) -> f32 {
    if x.is_infinite() && x < 0.0 {
        return x;
    }
    let x = if x == 0.0 { -0.0 } else { x };
    let bits = x.to_bits();
    f32::from_bits(if x > 0.0 { bits - 1 } else { bits + 1 })
}

/// The origin for a ray leaving `point` (with error bound `error`) in direction `direction`,
/// on that direction's side of the surface with geometric normal `normal`.
pub fn offset_ray_origin(point: Vec3, error: Vec3, normal: Vec3, direction: Vec3) -> Vec3 {
    let distance = normal.abs().dot(error);
    let mut offset = distance * normal;
    if direction.dot(normal) < 0.0 {
        offset = -offset;
    }
    // Arrays, not `Vec3` indexing, which compiles to a branch per lane.
    let (origin, offset) = ((point + offset).to_array(), offset.to_array());
    Vec3::from_array(std::array::from_fn(|axis| {
        if offset[axis] > 0.0 {
            next_float_up(origin[axis])
        } else if offset[axis] < 0.0 {
            next_float_down(origin[axis])
        } else {
            origin[axis]
        }
    }))
}

/// Transforms a point and its error bound (pbrt-v4 §6.8.6, eq. 6.30).
pub fn transform_point_with_error(m: &Mat4, point: Vec3, error: Vec3) -> (Vec3, Vec3) {
    let p = m.transform_point3(point);
    let abs_linear = glam::Mat3::from_mat4(*m).to_cols_array_2d().map(|c| Vec3::from(c).abs());
    let abs_m = glam::Mat3::from_cols(abs_linear[0], abs_linear[1], abs_linear[2]);
    let translation = m.w_axis.truncate().abs();
    let from_rounding = gamma(3) * (abs_m * point.abs() + translation);
    let carried = (gamma(3) + 1.0) * (abs_m * error);
    (p, from_rounding + carried)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn next_float_steps_one_ulp() {
        assert!(next_float_up(1.0) > 1.0 && next_float_up(1.0) - 1.0 == f32::EPSILON);
        assert!(next_float_down(1.0) < 1.0);
        assert!(next_float_up(0.0) > 0.0 && next_float_up(-0.0) > 0.0);
        assert!(next_float_down(0.0) < 0.0);
        assert_eq!(next_float_up(f32::INFINITY), f32::INFINITY);
    }

    #[test]
    fn offset_lands_on_the_leaving_side() {
        let p = Vec3::new(1e5, 2.0, -3e-3);
        let err = Vec3::splat(1e-2);
        let n = Vec3::Y;
        let up = offset_ray_origin(p, err, n, Vec3::new(0.3, 1.0, 0.0));
        let down = offset_ray_origin(p, err, n, Vec3::new(0.3, -1.0, 0.0));
        assert!(up.y > p.y + 1e-2 - 1e-9 && down.y < p.y - 1e-2 + 1e-9);
        assert_eq!((up.x, up.z), (p.x, p.z));
    }
}
