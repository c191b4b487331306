//! Pinhole camera.
//!
//! Scene parameters (`[camera]`): `position`, `look_at` (points), `up` (vector, default
//! [0, 1, 0]), `fov` (vertical field of view in degrees, default 45), `resolution`
//! ([width, height] in pixels, default [640, 480]).
//!
//! Image conventions: pixel (0, 0) is the top-left, row 0 is the top row; image right is
//! `forward × up`, image up is `right × forward`. Film coordinates are continuous: pixel
//! (x, y) covers [x, x+1) × [y, y+1), its centre is (x + ½, y + ½).

use glam::Vec3;

use crate::geometry::Ray;

#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    pub position: Vec3,
    pub width: u32,
    pub height: u32,
    pub fov_degrees: f32,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    tan_half_fov: f32,
}

impl Camera {
    /// `None` if `look_at` coincides with `position` or `up` is parallel to the view direction.
    pub fn new(position: Vec3, look_at: Vec3, up: Vec3, fov_degrees: f32, width: u32, height: u32) -> Option<Self> {
        let forward = (look_at - position).try_normalize()?;
        let right = forward.cross(up).try_normalize()?;
        let up = right.cross(forward);
        Some(Self {
            position,
            width,
            height,
            fov_degrees,
            forward,
            right,
            up,
            tan_half_fov: (0.5 * fov_degrees.to_radians()).tan(),
        })
    }

    /// The same camera at another resolution (the vertical field of view is kept).
    pub fn with_resolution(&self, width: u32, height: u32) -> Self {
        Self { width, height, ..self.clone() }
    }

    /// The ray through film point (x, y), in pixels from the top-left corner. Unit direction.
    pub fn generate_ray(&self, film_x: f32, film_y: f32) -> Ray {
        let aspect = self.width as f32 / self.height as f32;
        let sx = (2.0 * film_x / self.width as f32 - 1.0) * self.tan_half_fov * aspect;
        let sy = (1.0 - 2.0 * film_y / self.height as f32) * self.tan_half_fov;
        Ray::new(self.position, (self.forward + sx * self.right + sy * self.up).normalize())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_and_corner_rays() {
        let cam = Camera::new(Vec3::ZERO, Vec3::Z, Vec3::Y, 90.0, 200, 100).unwrap();
        assert_eq!(cam.generate_ray(100.0, 50.0).direction, Vec3::Z);
        // Top edge at 45° up; right = forward × up = z × y = −x.
        let top = cam.generate_ray(100.0, 0.0).direction;
        assert!((top - Vec3::new(0.0, 1.0, 1.0).normalize()).length() < 1e-6);
        let right = cam.generate_ray(200.0, 50.0).direction;
        assert!((right - Vec3::new(-2.0, 0.0, 1.0).normalize()).length() < 1e-6);
    }

    #[test]
    fn degenerate_cameras_are_refused() {
        assert!(Camera::new(Vec3::ZERO, Vec3::ZERO, Vec3::Y, 45.0, 1, 1).is_none());
        assert!(Camera::new(Vec3::ZERO, Vec3::Y, Vec3::Y, 45.0, 1, 1).is_none());
    }
}
