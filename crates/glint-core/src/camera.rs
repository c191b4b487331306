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

/// Where a point is seen on the film, for light tracing's connections to the camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    pub film_x: f32,
    pub film_y: f32,
    /// The pinhole's importance toward the point, converted to the point's area measure:
    /// 1 / (A · cos³θ · d²), with A the image's area on the plane at distance 1 and θ the angle
    /// off the optical axis. A point's contribution to the mean over the image of its pixel is
    /// (pixel count) · (radiance toward the camera · |cos at the point|) · this.
    pub importance: f32,
}

impl Camera {
    /// The film position of `point` and the camera's importance toward it; `None` if it is
    /// behind the camera or outside the image.
    pub fn project(&self, point: Vec3) -> Option<Projection> {
        let d = point - self.position;
        let depth = d.dot(self.forward);
        if depth <= 0.0 {
            return None;
        }
        let aspect = self.width as f32 / self.height as f32;
        let sx = d.dot(self.right) / depth;
        let sy = d.dot(self.up) / depth;
        let film_x = (sx / (self.tan_half_fov * aspect) + 1.0) * 0.5 * self.width as f32;
        let film_y = (1.0 - sy / self.tan_half_fov) * 0.5 * self.height as f32;
        if !(0.0..self.width as f32).contains(&film_x) || !(0.0..self.height as f32).contains(&film_y) {
            return None;
        }
        let distance_squared = d.length_squared();
        let cos = depth / distance_squared.sqrt();
        let image_area = 4.0 * self.tan_half_fov * self.tan_half_fov * aspect;
        Some(Projection { film_x, film_y, importance: 1.0 / (image_area * cos * cos * cos * distance_squared) })
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
    fn projection_inverts_generate_ray() {
        let cam = Camera::new(Vec3::new(1.0, 2.0, 3.0), Vec3::new(0.0, 1.5, 0.0), Vec3::Y, 50.0, 64, 48).unwrap();
        for (fx, fy) in [(0.5, 0.5), (32.0, 24.0), (63.2, 47.9), (10.25, 40.75)] {
            let ray = cam.generate_ray(fx, fy);
            let p = cam.project(ray.at(7.0)).unwrap();
            assert!((p.film_x - fx).abs() < 1e-3 && (p.film_y - fy).abs() < 1e-3, "{fx},{fy} -> {p:?}");
        }
        assert!(cam.project(cam.position - (Vec3::new(0.0, 1.5, 0.0) - cam.position)).is_none());
    }

    #[test]
    fn importance_integrates_to_the_pixel_count_over_a_plane() {
        // A plane facing the camera at distance 2, wider than the view: the importance times
        // |cos| over it is the fraction of the image it covers, 1 here.
        let cam = Camera::new(Vec3::ZERO, Vec3::Z, Vec3::Y, 60.0, 40, 30).unwrap();
        let n = 400;
        let half = 4.0;
        let cell = (2.0 * half / n as f32).powi(2);
        let mut total = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let p = Vec3::new(
                    -half + (i as f32 + 0.5) * 2.0 * half / n as f32,
                    -half + (j as f32 + 0.5) * 2.0 * half / n as f32,
                    2.0,
                );
                if let Some(proj) = cam.project(p) {
                    let cos = p.normalize().z;
                    total += (proj.importance * cos * cell) as f64;
                }
            }
        }
        assert!((total - 1.0).abs() < 0.01, "{total}");
    }

    #[test]
    fn degenerate_cameras_are_refused() {
        assert!(Camera::new(Vec3::ZERO, Vec3::ZERO, Vec3::Y, 45.0, 1, 1).is_none());
        assert!(Camera::new(Vec3::ZERO, Vec3::Y, Vec3::Y, 45.0, 1, 1).is_none());
    }
}
