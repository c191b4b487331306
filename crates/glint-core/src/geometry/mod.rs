//! Rays, boxes and transforms.
//!
//! Conventions: right-handed world space, y up in the example scenes; lengths in scene
//! units (whatever the scene uses); angles in degrees at the scene-file level and radians
//! inside the core. A ray's direction need not be unit length: `t` is measured in units of
//! the direction's length, which is what lets transformed rays keep the same `t`.

mod aabb;
mod ray;
mod transform;

pub use aabb::Aabb;
pub use ray::Ray;
pub use transform::Transform;

use glam::Vec3;

/// Two unit vectors perpendicular to `n` and to each other (Duff et al. 2017,
/// "Building an Orthonormal Basis, Revisited"): branch-free and exact at the poles.
pub fn orthonormal_basis(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1.0f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), Vec3::new(b, sign + n.y * n.y * a, -n.y))
}

/// Mirror reflection of the incident direction `incident` about the normal `n`:
/// R = I − 2(I·N)N (both pointing "through" the surface as the course draws them).
pub fn reflect(incident: Vec3, n: Vec3) -> Vec3 {
    incident - 2.0 * incident.dot(n) * n
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_is_orthonormal_everywhere() {
        for n in [Vec3::Z, -Vec3::Z, Vec3::X, Vec3::new(0.3, -0.4, 0.5).normalize()] {
            let (s, t) = orthonormal_basis(n);
            assert!((s.length() - 1.0).abs() < 1e-6 && (t.length() - 1.0).abs() < 1e-6);
            assert!(s.dot(t).abs() < 1e-6 && s.dot(n).abs() < 1e-6 && t.dot(n).abs() < 1e-6);
        }
    }

    #[test]
    fn reflection_of_a_45_degree_ray() {
        let r = reflect(Vec3::new(1.0, -1.0, 0.0), Vec3::Y);
        assert_eq!(r, Vec3::new(1.0, 1.0, 0.0));
    }
}
