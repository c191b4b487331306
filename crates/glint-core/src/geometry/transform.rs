use super::gamma;
use glam::{Mat3, Mat4, Vec3};

use super::Ray;

/// An affine transform with its inverse and the matrix that maps normals (the inverse
/// transpose), all computed once.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    pub to_world: Mat4,
    pub to_object: Mat4,
    normal_to_world: Mat3,
}

impl Default for Transform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Transform {
    pub const IDENTITY: Transform =
        Transform { to_world: Mat4::IDENTITY, to_object: Mat4::IDENTITY, normal_to_world: Mat3::IDENTITY };

    /// `None` if the matrix cannot be inverted (a zero scale, say).
    pub fn from_matrix(m: Mat4) -> Option<Self> {
        let det = m.determinant();
        if !det.is_finite() || det.abs() < 1e-30 {
            return None;
        }
        let inv = m.inverse();
        Some(Self { to_world: m, to_object: inv, normal_to_world: Mat3::from_mat4(inv).transpose() })
    }

    /// `self` applied after `first`.
    pub fn after(&self, first: &Transform) -> Transform {
        Transform {
            to_world: self.to_world * first.to_world,
            to_object: first.to_object * self.to_object,
            normal_to_world: self.normal_to_world * first.normal_to_world,
        }
    }

    pub fn point(&self, p: Vec3) -> Vec3 {
        self.to_world.transform_point3(p)
    }

    pub fn vector(&self, v: Vec3) -> Vec3 {
        self.to_world.transform_vector3(v)
    }

    /// A normal mapped to world space, unit length.
    pub fn normal(&self, n: Vec3) -> Vec3 {
        (self.normal_to_world * n).normalize()
    }

    /// The ray in object space. The direction is not renormalised, so `t` is unchanged.
    pub fn ray_to_object(&self, ray: &Ray) -> Ray {
        Ray {
            origin: self.to_object.transform_point3(ray.origin),
            direction: self.to_object.transform_vector3(ray.direction),
            ..*ray
        }
    }

    /// A bound, per object axis, on how far an object-space point `p` can move by a round
    /// trip: to world space, off its surface there by its error bound (along the world
    /// normal, which a non-uniform scale turns off the object's axes), and back to object
    /// space, where the next ray query starts. Each leg rounds within γ₃ of the magnitudes it
    /// adds up, the offset is within γ₃ of the world magnitudes, and the inverse matrix is
    /// itself rounded: γ₁₆ of the magnitudes, four times over, bounds them all with room.
    pub fn round_trip_margin(&self, p: Vec3) -> Vec3 {
        let abs = |m: &Mat4| {
            let c = Mat3::from_mat4(*m).to_cols_array_2d().map(|c| Vec3::from(c).abs());
            Mat3::from_cols(c[0], c[1], c[2])
        };
        let world = abs(&self.to_world) * p.abs() + self.to_world.w_axis.truncate().abs();
        let back = abs(&self.to_object) * world + self.to_object.w_axis.truncate().abs();
        4.0 * gamma(16) * back
    }

    /// Whether the transform flips handedness (negative determinant): normals defined by
    /// winding must then be flipped to keep pointing the same way relative to the surface.
    pub fn flips_handedness(&self) -> bool {
        self.to_world.determinant() < 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normals_stay_perpendicular_under_nonuniform_scale() {
        let t = Transform::from_matrix(Mat4::from_scale(Vec3::new(4.0, 1.0, 1.0))).unwrap();
        // The plane x + y = 0 in object space, normal (1,1,0)/√2, tangent (1,-1,0).
        let n = t.normal(Vec3::new(1.0, 1.0, 0.0).normalize());
        let tangent = t.vector(Vec3::new(1.0, -1.0, 0.0));
        assert!(n.dot(tangent).abs() < 1e-6);
    }

    #[test]
    fn singular_matrix_is_rejected() {
        assert!(Transform::from_matrix(Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0))).is_none());
    }

    #[test]
    fn composition_order() {
        let s = Transform::from_matrix(Mat4::from_scale(Vec3::splat(2.0))).unwrap();
        let t = Transform::from_matrix(Mat4::from_translation(Vec3::X)).unwrap();
        // Scale first, then translate: (1,0,0) → (2,0,0) → (3,0,0).
        assert_eq!(t.after(&s).point(Vec3::X), Vec3::new(3.0, 0.0, 0.0));
        let inv = t.after(&s).to_object.transform_point3(Vec3::new(3.0, 0.0, 0.0));
        assert!((inv - Vec3::X).length() < 1e-6);
    }
}
