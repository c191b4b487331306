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

use crate::lanes::{LaneVec3, Lanes};
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
    let lanes = LaneVec3::<f32>::from;
    offset_ray_origin_lanes(lanes(point), lanes(error), lanes(normal), lanes(direction)).into()
}

/// `offset_ray_origin` in lanes: the origin for a ray leaving `point` (error bound `error`)
/// toward `direction`, past the error box along `normal` and one ulp further.
#[inline(always)]
pub(crate) fn offset_ray_origin_lanes<L: Lanes>(
    point: LaneVec3<L>,
    error: LaneVec3<L>,
    normal: LaneVec3<L>,
    direction: LaneVec3<L>,
) -> LaneVec3<L> {
    let distance = normal.abs().dot(error);
    let offset = normal * distance;
    let offset = LaneVec3::select(direction.dot(normal).lt(L::ZERO), -offset, offset);
    L::step_toward(point + offset, offset)
}

/// `next_float_up(x)` where `sign > 0`, `next_float_down(x)` where `sign < 0`, `x` where it is
/// 0, bit for bit for every x but NaN (whose bits step like any other's, so a NaN of the
/// smallest or largest payload can become +∞ or −0), computed with
/// selects: the branches of the two functions depend on the signs of the coordinates and of
/// the offset, which change at random from ray to ray, and their mispredictions made
/// `offset_ray_origin` 5 % of a path tracer's time.
#[cfg(test)] // the reference the lane versions are tested against
#[inline(always)]
fn step_toward(x: f32, sign: f32) -> f32 {
    let up = sign > 0.0;
    // A zero steps from the zero of the side it leaves: +0 going up, −0 going down.
    let from = if x == 0.0 { f32::from_bits(if up { 0 } else { 0x8000_0000 }) } else { x };
    // Stepping away from zero makes the magnitude's bits grow, toward zero shrink.
    let away = from.is_sign_positive() == up;
    let stepped = from.to_bits().wrapping_add((2 * i32::from(away) - 1) as u32);
    // ±∞ stay where they are going outward, and a zero offset leaves `x` alone. Masks, not an
    // `if`, which the compiler turns back into a branch.
    let keep = (sign == 0.0) | sign.is_nan() | (from.is_infinite() & away);
    let keep = 0u32.wrapping_sub(u32::from(keep));
    f32::from_bits((x.to_bits() & keep) | (stepped & !keep))
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
    use crate::lanes::testing::{assert_lanes_equal, random_vectors};
    use crate::lanes::{step_toward8, Vec3x8, LANES};

    /// The branch-free step equals `next_float_up` and `next_float_down` bit for bit, zeros,
    /// subnormals, the largest floats and infinities included.
    #[test]
    fn step_toward_equals_next_float() {
        let mut values = vec![0.0, -0.0, f32::MIN_POSITIVE, -f32::MIN_POSITIVE, 1e-45, -1e-45, f32::MAX, f32::MIN];
        values.extend([f32::INFINITY, f32::NEG_INFINITY, 1.0, -1.0, 0.5, -3.25e7, 123.456]);
        let mut bits = 0x9E37_79B9u32;
        for _ in 0..100_000 {
            bits = bits.wrapping_mul(0x0019_660D).wrapping_add(0x3C6E_F35F);
            let x = f32::from_bits(bits);
            if !x.is_nan() {
                values.push(x);
            }
        }
        for x in values {
            assert_eq!(step_toward(x, 1.0).to_bits(), next_float_up(x).to_bits(), "up from {x:e}");
            assert_eq!(step_toward(x, -2.5).to_bits(), next_float_down(x).to_bits(), "down from {x:e}");
            assert_eq!(step_toward(x, 0.0).to_bits(), x.to_bits(), "stay at {x:e}");
            assert_eq!(step_toward(x, -0.0).to_bits(), x.to_bits(), "stay at {x:e}");
        }
    }

    /// The eight-lane step equals the scalar one bit for bit, for every sign of the offset.
    #[test]
    fn eight_lane_step_equals_the_scalar_step() {
        let mut values =
            vec![0.0, -0.0, f32::MIN_POSITIVE, -1e-45, f32::MAX, f32::MIN, f32::INFINITY, f32::NEG_INFINITY];
        let mut bits = 0x2545_F491u32;
        while values.len() < 80_000 {
            bits = bits.wrapping_mul(0x0019_660D).wrapping_add(0x3C6E_F35F);
            values.push(f32::from_bits(bits));
        }
        let signs = [1.0, -2.5, 0.0, -0.0, f32::NAN, f32::INFINITY, -1e-40, 3.0];
        for chunk in values.chunks_exact(8) {
            let x: [f32; 8] = chunk.try_into().unwrap();
            for rotation in 0..8 {
                let sign: [f32; 8] = std::array::from_fn(|k| signs[(k + rotation) % 8]);
                let lanes = step_toward8(wide::f32x8::from(x), wide::f32x8::from(sign)).to_array();
                for k in 0..8 {
                    let expected = step_toward(x[k], sign[k]);
                    assert_eq!(lanes[k].to_bits(), expected.to_bits(), "{:e} toward {}", x[k], sign[k]);
                }
            }
        }
    }

    /// The one-lane step (three coordinates in lanes of the eight-lane step) equals the scalar
    /// one lane by lane.
    #[test]
    fn one_lane_step_equals_the_scalar_step() {
        let mut values =
            vec![0.0, -0.0, f32::MIN_POSITIVE, -1e-45, f32::MAX, f32::MIN, f32::INFINITY, f32::NEG_INFINITY];
        values.extend([f32::NAN, 1.0, -1.0, 3.5e-3]);
        let signs = [1.0, -2.5, 0.0, -0.0, f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 1e-40, -1e-40];
        let mut bits = 0x2545_F491u32;
        for _ in 0..20_000 {
            bits = bits.wrapping_mul(0x0019_660D).wrapping_add(0x3C6E_F35F);
            values.push(f32::from_bits(bits));
        }
        for (i, &x) in values.iter().enumerate() {
            let xs = Vec3::new(x, values[(i * 7 + 1) % values.len()], values[(i * 13 + 5) % values.len()]);
            let sign = Vec3::new(signs[i % signs.len()], signs[(i / 3) % signs.len()], signs[(i / 7) % signs.len()]);
            let stepped = Vec3::from(f32::step_toward(xs.into(), sign.into())).to_array();
            for axis in 0..3 {
                let expected = step_toward(xs[axis], sign[axis]);
                assert_eq!(stepped[axis].to_bits(), expected.to_bits(), "{:e} toward {:e}", xs[axis], sign[axis]);
            }
        }
    }

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

    /// Eight lanes compute one lane's bits, on random inputs of many scales.
    #[test]
    fn offset_ray_origin_in_eight_lanes_equals_one_lane() {
        let mut rng = crate::sampling::Rng::new(11, 5);
        for round in 0..2_000 {
            let scale = 10f32.powi(round % 9 - 4);
            let (p, d, e) =
                (random_vectors(&mut rng, scale), random_vectors(&mut rng, 1.0), random_vectors(&mut rng, 1e-4));
            let (e, n) = (e.map(Vec3::abs), d.map(|v| (v + Vec3::splat(0.01)).normalize()));
            let lanes = |v: [Vec3; LANES]| Vec3x8::from_fn(|k| v[k]);
            let scalar = std::array::from_fn(|k| offset_ray_origin(p[k], e[k], n[k], d[k]));
            let eight = offset_ray_origin_lanes(lanes(p), lanes(e), lanes(n), lanes(d));
            assert_lanes_equal(eight, scalar, "offset_ray_origin");
        }
    }
}
