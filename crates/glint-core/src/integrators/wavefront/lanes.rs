//! The lane versions of the geometry the path tracer uses at every bounce, on eight
//! 3-vectors (`geometry::lanes`). Each is the scalar routine (`offset_ray_origin`,
//! `orthonormal_basis`, the concentric disk map, ...) in the same order of roundings, so a lane
//! computes the same bits as the scalar code it stands for.

use wide::{f32x8, CmpEq, CmpGt, CmpLt};

pub use crate::geometry::lanes::{negate, Vec3x8, LANES};
use crate::geometry::{gamma, step_toward8};

/// `offset_ray_origin` in lanes: the origin for a ray leaving `point` (error bound `error`)
/// toward `direction`, past the error box along `normal` and one ulp further.
#[inline(always)]
pub fn offset_ray_origin(point: Vec3x8, error: Vec3x8, normal: Vec3x8, direction: Vec3x8) -> Vec3x8 {
    let distance = normal.abs().dot(error);
    let offset = normal * distance;
    let offset = Vec3x8::select(direction.dot(normal).cmp_lt(f32x8::ZERO), -offset, offset);
    let moved = point + offset;
    Vec3x8 {
        x: step_toward8(moved.x, offset.x),
        y: step_toward8(moved.y, offset.y),
        z: step_toward8(moved.z, offset.z),
    }
}

/// `barycentric_point` in lanes: the point with weights (1 − b1 − b2, b1, b2) of the corners,
/// and the bound on its error from interpolating.
#[inline(always)]
pub fn barycentric_point([a, b, c]: [Vec3x8; 3], b1: f32x8, b2: f32x8) -> (Vec3x8, Vec3x8) {
    let b0 = f32x8::ONE - b1 - b2;
    let (pa, pb, pc) = (a * b0, b * b1, c * b2);
    (pa + pb + pc, (pa.abs() + pb.abs() + pc.abs()) * f32x8::splat(gamma(7)))
}

/// `orthonormal_basis` in lanes (Duff et al. 2017): two tangents completing the unit `n`.
#[inline(always)]
pub fn orthonormal_basis(n: Vec3x8) -> (Vec3x8, Vec3x8) {
    let sign = f32x8::ONE.copysign(n.z);
    let a = f32x8::splat(-1.0) / (sign + n.z);
    let b = n.x * n.y * a;
    let tangent = Vec3x8 { x: f32x8::ONE + sign * n.x * n.x * a, y: sign * b, z: negate(sign) * n.x };
    let bitangent = Vec3x8 { x: b, y: sign + n.y * n.y * a, z: negate(n.y) };
    (tangent, bitangent)
}

/// `square_to_cosine_hemisphere` in lanes: Shirley and Chiu's concentric disk, lifted.
#[inline(always)]
pub fn square_to_cosine_hemisphere(u: f32x8, v: f32x8) -> Vec3x8 {
    let two = f32x8::splat(2.0);
    let (px, py) = (two * u - f32x8::ONE, two * v - f32x8::ONE);
    let sideways = px.abs().cmp_gt(py.abs());
    let (r, q) = (sideways.blend(px, py), sideways.blend(py, px));
    let (sin, cos) = sin_cos_quarter(f32x8::splat(std::f32::consts::FRAC_PI_4) * (q / r));
    let (x, y) = (sideways.blend(cos, sin), sideways.blend(sin, cos));
    let centre = r.cmp_eq(f32x8::ZERO);
    let (dx, dy) = (centre.blend(f32x8::ZERO, r * x), centre.blend(f32x8::ZERO, r * y));
    let z = (f32x8::ONE - (dx * dx + dy * dy)).fast_max(f32x8::ZERO).sqrt();
    Vec3x8 { x: dx, y: dy, z }
}

/// `area_to_solid_angle` (lights/area.rs) in lanes: the density `selection / area` of a point
/// on a light as a density in solid angle, seen across `to_light` (the point minus the
/// receiver), and the mask of lanes where the light is not seen edge on.
#[inline(always)]
pub fn area_to_solid_angle(selection: f32x8, area: f32x8, to_light: Vec3x8, normal: Vec3x8) -> (f32x8, f32x8) {
    let distance_squared = to_light.dot(to_light);
    let projected = normal.dot(to_light).abs();
    (selection * distance_squared * distance_squared.sqrt() / (projected * area), projected.cmp_gt(f32x8::ZERO))
}

/// `power_heuristic` (integrators/path.rs) in lanes.
#[inline(always)]
pub fn power_heuristic(a: f32x8, b: f32x8) -> f32x8 {
    let (a2, b2) = (a * a, b * b);
    let special = (a2 + b2).cmp_eq(f32x8::ZERO) | !a2.is_finite();
    special.blend(a2.is_inf().blend(f32x8::ONE, f32x8::ZERO), a2 / (a2 + b2))
}

/// `sin_cos_quarter` in lanes: the same Taylor polynomials for |x| ≤ π/4.
#[inline(always)]
fn sin_cos_quarter(x: f32x8) -> (f32x8, f32x8) {
    let c = f32x8::splat;
    let x2 = x * x;
    let sin =
        x * (c(1.0) + x2 * (c(-1.0 / 6.0) + x2 * (c(1.0 / 120.0) + x2 * (c(-1.0 / 5040.0) + x2 * c(1.0 / 362_880.0)))));
    let cos = c(1.0)
        + x2 * (c(-0.5)
            + x2 * (c(1.0 / 24.0) + x2 * (c(-1.0 / 720.0) + x2 * (c(1.0 / 40_320.0) + x2 * c(-1.0 / 3_628_800.0)))));
    (sin, cos)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;
    use glam::Vec3;

    fn random_vectors(rng: &mut Rng, scale: f32) -> [Vec3; LANES] {
        std::array::from_fn(|_| Vec3::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, rng.next_f32() - 0.5) * scale)
    }

    fn assert_lanes_equal(lanes: Vec3x8, scalar: [Vec3; LANES], what: &str) {
        for (k, s) in scalar.iter().enumerate() {
            let l = lanes.lane(k);
            assert_eq!(
                l.to_array().map(f32::to_bits),
                s.to_array().map(f32::to_bits),
                "{what}, lane {k}: {l} against {s}"
            );
        }
    }

    /// Every lane routine computes the scalar routine's bits, on random inputs of many scales.
    #[test]
    fn lanes_equal_the_scalar_routines_bit_for_bit() {
        let mut rng = Rng::new(11, 5);
        for round in 0..2_000 {
            let scale = 10f32.powi(round % 9 - 4);
            let (a, b, e) =
                (random_vectors(&mut rng, scale), random_vectors(&mut rng, 1.0), random_vectors(&mut rng, 1e-4));
            let (la, lb, le) = (Vec3x8::from_fn(|k| a[k]), Vec3x8::from_fn(|k| b[k]), Vec3x8::from_fn(|k| e[k]));
            assert_lanes_equal(la.cross(lb), std::array::from_fn(|k| a[k].cross(b[k])), "cross");
            assert_lanes_equal(la.normalize(), a.map(Vec3::normalize), "normalize");
            assert_lanes_equal(la.normalize_or(lb), std::array::from_fn(|k| a[k].normalize_or(b[k])), "normalize_or");
            let n = b.map(Vec3::normalize);
            let ln = Vec3x8::from_fn(|k| n[k]);
            let scalar: [Vec3; LANES] =
                std::array::from_fn(|k| crate::geometry::offset_ray_origin(a[k], e[k].abs(), n[k], b[k]));
            assert_lanes_equal(offset_ray_origin(la, le.abs(), ln, lb), scalar, "offset_ray_origin");
            let (t, s) = orthonormal_basis(ln);
            let basis = n.map(crate::geometry::orthonormal_basis);
            assert_lanes_equal(t, basis.map(|(t, _)| t), "tangent");
            assert_lanes_equal(s, basis.map(|(_, s)| s), "bitangent");
            let (b1, b2): ([f32; LANES], [f32; LANES]) =
                (std::array::from_fn(|_| rng.next_f32() * 0.5), std::array::from_fn(|_| rng.next_f32() * 0.5));
            let (point, error) = barycentric_point([la, lb, le], f32x8::from(b1), f32x8::from(b2));
            let scalar: [(Vec3, Vec3); LANES] =
                std::array::from_fn(|k| crate::shapes::barycentric_point([a[k], b[k], e[k]], b1[k], b2[k]));
            assert_lanes_equal(point, scalar.map(|(p, _)| p), "barycentric point");
            assert_lanes_equal(error, scalar.map(|(_, e)| e), "barycentric error");
            let (u, v): ([f32; LANES], [f32; LANES]) =
                (std::array::from_fn(|_| rng.next_f32()), std::array::from_fn(|_| rng.next_f32()));
            let scalar: [Vec3; LANES] = std::array::from_fn(|k| {
                crate::sampling::warp::square_to_cosine_hemisphere(glam::Vec2::new(u[k], v[k]))
            });
            assert_lanes_equal(
                square_to_cosine_hemisphere(f32x8::from(u), f32x8::from(v)),
                scalar,
                "cosine hemisphere",
            );
        }
        // normalize_or's fallback: zero, tiny and infinite vectors.
        let odd = [Vec3::ZERO, Vec3::splat(1e-30), Vec3::new(f32::INFINITY, 0.0, 0.0), Vec3::new(-0.0, 0.0, 0.0)];
        let a: [Vec3; LANES] = std::array::from_fn(|k| if k < 4 { odd[k] } else { Vec3::new(k as f32, 1.0, -2.0) });
        let fallback: [Vec3; LANES] = std::array::from_fn(|k| Vec3::new(0.0, k as f32, 1.0).normalize());
        let lanes_a = Vec3x8::from_fn(|k| a[k]);
        let scalar: [Vec3; LANES] = std::array::from_fn(|k| a[k].normalize_or(fallback[k]));
        assert_lanes_equal(lanes_a.normalize_or(Vec3x8::from_fn(|k| fallback[k])), scalar, "normalize_or fallback");
        // The disk's centre, and the diagonals where the quadrant choice flips.
        let (u, v) = ([0.5, 0.5, 0.0, 1.0, 0.25, 0.75, 0.5, 0.0], [0.5, 0.0, 0.0, 1.0, 0.25, 0.25, 1.0, 1.0]);
        let scalar: [Vec3; LANES] =
            std::array::from_fn(|k| crate::sampling::warp::square_to_cosine_hemisphere(glam::Vec2::new(u[k], v[k])));
        assert_lanes_equal(
            square_to_cosine_hemisphere(f32x8::from(u), f32x8::from(v)),
            scalar,
            "disk's centre and diagonals",
        );
    }

    /// `max_element`, the power heuristic and the area-to-solid-angle density against the
    /// scalar routines, special values included (NaN, ±0, infinities, a light seen edge on).
    #[test]
    fn lane_weights_equal_the_scalar_ones() {
        let specials = [0.0, -0.0, 1.0, 0.5, f32::INFINITY, f32::NAN, 1e-30, 3.0e30, 2.0, -1.0];
        for (i, &x) in specials.iter().enumerate() {
            for &y in &specials {
                let lanes: [f32; LANES] = std::array::from_fn(|k| specials[(i + k) % specials.len()]);
                let v = Vec3x8 { x: f32x8::from(lanes), y: f32x8::splat(y), z: f32x8::splat(x) };
                let max = v.max_element().to_array();
                let heuristic = power_heuristic(f32x8::from(lanes), f32x8::splat(y)).to_array();
                for k in 0..LANES {
                    let expected = Vec3::new(lanes[k], y, x).max_element();
                    assert_eq!(max[k].to_bits(), expected.to_bits(), "max of {}, {y}, {x}", lanes[k]);
                    let expected = crate::integrators::power_heuristic(lanes[k], y);
                    assert_eq!(heuristic[k].to_bits(), expected.to_bits(), "heuristic of {}, {y}", lanes[k]);
                }
            }
        }
        let mut rng = Rng::new(3, 9);
        for _ in 0..500 {
            let from = random_vectors(&mut rng, 10.0);
            let point = random_vectors(&mut rng, 10.0);
            // Half the normals lie in the plane of the receiver's view: the light seen edge on.
            let normal: [Vec3; LANES] = std::array::from_fn(|k| match k % 2 {
                0 => (point[k] - from[k]).cross(Vec3::new(0.3, 1.0, -0.2)).normalize(),
                _ => Vec3::new(0.2, -1.0, 0.4).normalize(),
            });
            let (selection, area) = (rng.next_f32(), rng.next_f32() * 4.0);
            let to_light = Vec3x8::from_fn(|k| point[k] - from[k]);
            let (pdf, seen) = area_to_solid_angle(
                f32x8::splat(selection),
                f32x8::splat(area),
                to_light,
                Vec3x8::from_fn(|k| normal[k]),
            );
            let (pdf, seen) = (pdf.to_array(), seen.move_mask());
            for k in 0..LANES {
                let expected = crate::lights::area_to_solid_angle(selection, area, from[k], point[k], normal[k]);
                assert_eq!(seen & (1 << k) != 0, expected.is_some(), "seen, lane {k}");
                if let Some(expected) = expected {
                    assert_eq!(pdf[k].to_bits(), expected.to_bits(), "pdf, lane {k}");
                }
            }
        }
    }
}
