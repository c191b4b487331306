//! Rays, boxes and transforms.
//!
//! Conventions: right-handed world space, y up in the example scenes; lengths in scene
//! units (whatever the scene uses); angles in degrees at the scene-file level and radians
//! inside the core. A ray's direction need not be unit length: `t` is measured in units of
//! the direction's length, which is what lets transformed rays keep the same `t`.

mod aabb;
mod ray;
mod robust;
mod transform;

pub use aabb::Aabb;
pub use ray::Ray;
pub(crate) use robust::offset_ray_origin_lanes;
pub use robust::{gamma, next_float_down, next_float_up, offset_ray_origin, transform_point_with_error};
pub use transform::Transform;

use crate::lanes::{LaneVec3, Lanes};
use glam::Vec3;

/// Two unit vectors perpendicular to `n` and to each other (Duff et al. 2017,
/// "Building an Orthonormal Basis, Revisited"): branch-free and exact at the poles.
pub fn orthonormal_basis(n: Vec3) -> (Vec3, Vec3) {
    let (tangent, bitangent) = orthonormal_basis_lanes(LaneVec3::<f32>::from(n));
    (tangent.into(), bitangent.into())
}

/// `orthonormal_basis` in lanes: two tangents completing the unit `n`.
#[inline(always)]
pub(crate) fn orthonormal_basis_lanes<L: Lanes>(n: LaneVec3<L>) -> (LaneVec3<L>, LaneVec3<L>) {
    let sign = L::ONE.copysign(n.z);
    let a = L::splat(-1.0) / (sign + n.z);
    let b = n.x * n.y * a;
    let tangent = LaneVec3::new(L::ONE + sign * n.x * n.x * a, sign * b, sign.negate() * n.x);
    let bitangent = LaneVec3::new(b, sign + n.y * n.y * a, n.y.negate());
    (tangent, bitangent)
}

/// Mirror reflection of the incident direction `incident` about the normal `n`:
/// R = I − 2(I·N)N (both pointing "through" the surface as the course draws them).
pub fn reflect(incident: Vec3, n: Vec3) -> Vec3 {
    crate::lanes::reflect(LaneVec3::<f32>::from(incident), n.into()).into()
}

/// Refraction of the unit incident direction `incident` (pointing toward the surface) through a
/// surface with unit normal `n` facing the incident side, for the ratio of indices
/// `eta = n_incident / n_transmitted` (Snell's law, the course's formula):
/// T = η I + (η cos θ_i − cos θ_t) N with cos θ_t = √(1 − η²(1 − cos² θ_i)).
/// `None` when the root is imaginary: total internal reflection.
pub fn refract(incident: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let (refracted, exists) = crate::lanes::refract(LaneVec3::<f32>::from(incident), n.into(), eta);
    exists.then(|| refracted.into())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lanes::testing::{assert_lanes_equal, random_vectors};

    #[test]
    fn basis_is_orthonormal_everywhere() {
        for n in [Vec3::Z, -Vec3::Z, Vec3::X, Vec3::new(0.3, -0.4, 0.5).normalize()] {
            let (s, t) = orthonormal_basis(n);
            assert!((s.length() - 1.0).abs() < 1e-6 && (t.length() - 1.0).abs() < 1e-6);
            assert!(s.dot(t).abs() < 1e-6 && s.dot(n).abs() < 1e-6 && t.dot(n).abs() < 1e-6);
        }
    }

    #[test]
    fn snell_by_hand_and_total_internal_reflection() {
        // 45° into glass (η = 1/1.5): sin θ_t = sin 45° / 1.5.
        let i = Vec3::new(1.0, -1.0, 0.0).normalize();
        let t = refract(i, Vec3::Y, 1.0 / 1.5).unwrap();
        assert!((t.length() - 1.0).abs() < 1e-6);
        assert!((t.x - std::f32::consts::FRAC_1_SQRT_2 / 1.5).abs() < 1e-6 && t.y < 0.0);
        // Leaving glass at 45° > critical angle 41.8°: total internal reflection.
        assert!(refract(i, Vec3::Y, 1.5).is_none());
        // Just under the critical angle it still refracts, grazing.
        let critical = (1.0f32 / 1.5).asin() - 1e-3;
        let i = Vec3::new(critical.sin(), -critical.cos(), 0.0);
        assert!(refract(i, Vec3::Y, 1.5).unwrap().y.abs() < 0.1);
    }

    #[test]
    fn reflection_of_a_45_degree_ray() {
        let r = reflect(Vec3::new(1.0, -1.0, 0.0), Vec3::Y);
        assert_eq!(r, Vec3::new(1.0, 1.0, 0.0));
    }

    /// Eight lanes compute one lane's bits, the poles included.
    #[test]
    fn orthonormal_basis_in_eight_lanes_equals_one_lane() {
        let mut rng = crate::sampling::Rng::new(11, 5);
        for round in 0..2_000 {
            let mut n = random_vectors(&mut rng, 1.0).map(|v| v.normalize_or(Vec3::Z));
            if round == 0 {
                n[..4].copy_from_slice(&[Vec3::Z, -Vec3::Z, Vec3::X, Vec3::new(0.0, -0.0, -1.0)]);
            }
            let (t, s) = orthonormal_basis_lanes(crate::lanes::Vec3x8::from_fn(|k| n[k]));
            let basis = n.map(orthonormal_basis);
            assert_lanes_equal(t, basis.map(|(t, _)| t), "tangent");
            assert_lanes_equal(s, basis.map(|(_, s)| s), "bitangent");
        }
    }
}
