//! The camera: a pinhole (the default), a thin lens (depth of field) or an orthographic view.
//!
//! Scene parameters (`[camera]`): `position`, `look_at` (points), `up` (vector, default
//! [0, 1, 0]), `fov` (vertical field of view in degrees, default 45), `resolution`
//! ([width, height] in pixels, default [640, 480]); `aperture_radius` and `focus_distance`
//! for a thin lens; `orthographic_height` (the height of the view in scene units) for an
//! orthographic camera.
//!
//! Image conventions: pixel (0, 0) is the top-left, row 0 is the top row; image right is
//! `forward × up`, image up is `right × forward`. Film coordinates are continuous: pixel
//! (x, y) covers [x, x+1) × [y, y+1), its centre is (x + ½, y + ½).
//!
//! A crop window (pbrt's `cropwindow`, Mitsuba's film crop) renders a rectangle of the film:
//! the image is that rectangle, its pixels those of the whole film at the same place, seen
//! through the same rays.

use glam::{Vec2, Vec3};
use wide::f32x8;

use crate::geometry::Ray;
use crate::lanes::{LaneVec3, Lanes, LANES};
use crate::sampling::warp::square_to_disk;

/// How rays leave the camera.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Lens {
    /// Every ray through one point: everything in focus.
    #[default]
    Pinhole,
    /// Rays through a disk of `radius`, focused on the plane at `focus_distance` along the
    /// view direction: depth of field.
    Thin { radius: f32, focus_distance: f32 },
    /// Parallel rays from a film `height` scene units high (the width follows the aspect).
    Orthographic { height: f32 },
}

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
    pub lens: Lens,
    /// The crop window: the whole film's resolution and where the image starts on it;
    /// `None` when the image is the whole film.
    crop: Option<Crop>,
}

/// A crop window of the film, in pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Crop {
    film_width: u32,
    film_height: u32,
    x0: u32,
    y0: u32,
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
            lens: Lens::Pinhole,
            crop: None,
        })
    }

    /// The same camera rendering only the film's pixels [x0, x1) × [y0, y1) (of its current
    /// resolution, which becomes the whole film's): `None` if that rectangle is empty or not
    /// on the film.
    pub fn with_crop(&self, x0: u32, y0: u32, x1: u32, y1: u32) -> Option<Self> {
        let (film_width, film_height) = self.film_resolution();
        if !(x0 < x1 && y0 < y1 && x1 <= film_width && y1 <= film_height) {
            return None;
        }
        let crop = (x0, y0, x1, y1) != (0, 0, film_width, film_height);
        let crop = crop.then_some(Crop { film_width, film_height, x0, y0 });
        Some(Self { width: x1 - x0, height: y1 - y0, crop, ..self.clone() })
    }

    /// The whole film's resolution (the image's, unless cropped).
    pub fn film_resolution(&self) -> (u32, u32) {
        self.crop.map_or((self.width, self.height), |c| (c.film_width, c.film_height))
    }

    /// The crop window on the film, [x0, x1) × [y0, y1) in pixels, if the image is one.
    pub fn crop_window(&self) -> Option<(u32, u32, u32, u32)> {
        self.crop.map(|c| (c.x0, c.y0, c.x0 + self.width, c.y0 + self.height))
    }

    /// The same camera with its image mirrored left to right: right becomes up × forward, as
    /// in left-handed formats (pbrt's).
    pub fn mirrored(self) -> Self {
        Self { right: -self.right, ..self }
    }

    /// The same camera with another lens.
    pub fn with_lens(self, lens: Lens) -> Self {
        Self { lens, ..self }
    }

    /// The camera's frame as a row-major 4×4 camera-to-world matrix: its columns the right,
    /// up and forward directions and the position (camera space: x right, y up, z forward).
    pub fn camera_to_world(&self) -> [[f32; 4]; 4] {
        let (r, u, f, p) = (self.right, self.up, self.forward, self.position);
        [[r.x, u.x, f.x, p.x], [r.y, u.y, f.y, p.y], [r.z, u.z, f.z, p.z], [0.0, 0.0, 0.0, 1.0]]
    }

    /// Whether `generate_ray_through_lens` needs its lens sample (a thin lens).
    pub fn samples_lens(&self) -> bool {
        matches!(self.lens, Lens::Thin { radius, .. } if radius > 0.0)
    }

    /// The side of a pixel's footprint on a surface `distance` along a camera ray, facing it:
    /// growing with distance through a lens, the film's pixel size for parallel rays.
    pub fn pixel_footprint(&self, distance: f32) -> f32 {
        let film_height = self.film_resolution().1 as f32;
        match self.lens {
            Lens::Orthographic { height } => height / film_height,
            Lens::Pinhole | Lens::Thin { .. } => 2.0 * self.tan_half_fov / film_height * distance,
        }
    }

    /// The same camera at another resolution of its whole film (the vertical field of view is
    /// kept); a crop window keeps its place on the film, scaled to the new resolution.
    pub fn with_resolution(&self, width: u32, height: u32) -> Self {
        let whole = Self { width, height, crop: None, ..self.clone() };
        let Some((x0, y0, x1, y1)) = self.crop_window() else { return whole };
        if width == 0 || height == 0 {
            return whole;
        }
        let (film_width, film_height) = self.film_resolution();
        let scale = |v: u32, to: u32, from: u32| ((v as u64 * to as u64 + from as u64 / 2) / from as u64) as u32;
        let (x0, x1) =
            (scale(x0, width, film_width), scale(x1, width, film_width).max(scale(x0, width, film_width) + 1));
        let (y0, y1) =
            (scale(y0, height, film_height), scale(y1, height, film_height).max(scale(y0, height, film_height) + 1));
        whole.with_crop(x0.min(width - 1), y0.min(height - 1), x1.min(width), y1.min(height)).unwrap_or(whole)
    }

    /// The ray through film point (x, y), in pixels from the top-left corner, through the lens
    /// centre. Unit direction.
    pub fn generate_ray(&self, film_x: f32, film_y: f32) -> Ray {
        self.generate_ray_through_lens(film_x, film_y, Vec2::splat(0.5))
    }

    /// `generate_ray` through eight film points at once, for a pinhole camera: the same rays,
    /// bit for bit (`None` for other lenses).
    pub(crate) fn pinhole_rays8(&self, film_x: f32x8, film_y: f32x8) -> Option<[Ray; LANES]> {
        if self.lens != Lens::Pinhole {
            return None;
        }
        let direction = self.pinhole_direction(film_x, film_y);
        Some(std::array::from_fn(|k| Ray::new(self.position, direction.lane(k))))
    }

    /// The film point (x, y) in [-1, 1] × [-1, 1], +y up, the crop's offset added.
    #[inline(always)]
    fn normalized_film<L: Lanes>(&self, film_x: L, film_y: L) -> (L, L) {
        let (film_x, film_y) = match self.crop {
            Some(c) => (film_x + L::splat(c.x0 as f32), film_y + L::splat(c.y0 as f32)),
            None => (film_x, film_y),
        };
        let (width, height) = self.film_resolution();
        let two = L::splat(2.0);
        (two * film_x / L::splat(width as f32) - L::ONE, L::ONE - two * film_y / L::splat(height as f32))
    }

    /// The unit direction of the pinhole's ray through film point (x, y).
    #[inline(always)]
    fn pinhole_direction<L: Lanes>(&self, film_x: L, film_y: L) -> LaneVec3<L> {
        let (nx, ny) = self.normalized_film(film_x, film_y);
        let (width, height) = self.film_resolution();
        let tan = L::splat(self.tan_half_fov);
        let (sx, sy) = (nx * tan * L::splat(width as f32 / height as f32), ny * tan);
        (LaneVec3::splat(self.forward) + LaneVec3::splat(self.right) * sx + LaneVec3::splat(self.up) * sy).normalize()
    }

    /// The ray of one camera sample through film point (x, y): `next` draws the lens sample's
    /// two numbers only for a camera that has a lens to sample.
    pub fn sample_ray(&self, film_x: f32, film_y: f32, mut next: impl FnMut() -> f32) -> Ray {
        if self.samples_lens() {
            let u_lens = Vec2::new(next(), next());
            self.generate_ray_through_lens(film_x, film_y, u_lens)
        } else {
            self.generate_ray(film_x, film_y)
        }
    }

    /// The ray through film point (x, y) and the lens point `u_lens` (a uniform sample of the
    /// unit square, mapped to the aperture disk; (½, ½) is the lens centre).
    pub fn generate_ray_through_lens(&self, film_x: f32, film_y: f32, u_lens: Vec2) -> Ray {
        match self.lens {
            Lens::Orthographic { height: view_height } => {
                let (nx, ny) = self.normalized_film(film_x, film_y);
                let (width, height) = self.film_resolution();
                let aspect = width as f32 / height as f32;
                let origin = self.position + (0.5 * view_height) * (nx * aspect * self.right + ny * self.up);
                Ray::new(origin, self.forward)
            }
            Lens::Pinhole | Lens::Thin { .. } => {
                let direction = Vec3::from(self.pinhole_direction(film_x, film_y));
                let Lens::Thin { radius, focus_distance } = self.lens else {
                    return Ray::new(self.position, direction);
                };
                // The point in focus along the pinhole ray, seen from a point on the aperture.
                let focus = self.position + direction * (focus_distance / direction.dot(self.forward));
                let disk = square_to_disk(u_lens) * radius;
                let origin = self.position + disk.x * self.right + disk.y * self.up;
                Ray::new(origin, (focus - origin).normalize())
            }
        }
    }
}

/// Where a point is seen on the film, for light tracing's connections to the camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    pub film_x: f32,
    pub film_y: f32,
    /// The pinhole's importance toward the point, converted to the point's area measure:
    /// 1 / (A · cos³θ · d²), with A the image's area on the plane at distance 1 and θ the angle
    /// off the optical axis (orthographic: 1 / A, A the film's area). A point's contribution to
    /// the mean over the image of its pixel is (pixel count) · (radiance toward the camera ·
    /// |cos at the point|) · this.
    pub importance: f32,
    /// Unit direction from the point toward the camera, and where the camera is along it (the
    /// end of a visibility ray).
    pub to_camera: Vec3,
    pub camera_point: Vec3,
}

impl Camera {
    /// The film position of `point` and the camera's importance toward it; `None` if it is
    /// behind the camera or outside the image. A thin lens has no single point to connect to:
    /// `None` (light tracing refuses such cameras).
    pub fn project(&self, point: Vec3) -> Option<Projection> {
        let projection = self.project_on_film(point)?;
        let Some(c) = self.crop else { return Some(projection) };
        let (film_x, film_y) = (projection.film_x - c.x0 as f32, projection.film_y - c.y0 as f32);
        if !(0.0..self.width as f32).contains(&film_x) || !(0.0..self.height as f32).contains(&film_y) {
            return None;
        }
        // The importance is over the image's area: the crop's share of the film's.
        let share = (self.width as f64 * self.height as f64) / (c.film_width as f64 * c.film_height as f64);
        Some(Projection { film_x, film_y, importance: projection.importance / share as f32, ..projection })
    }

    /// `project` onto the whole film.
    fn project_on_film(&self, point: Vec3) -> Option<Projection> {
        let d = point - self.position;
        let depth = d.dot(self.forward);
        if depth <= 0.0 {
            return None;
        }
        let (width, height) = self.film_resolution();
        let (width, height) = (width as f32, height as f32);
        let aspect = width / height;
        match self.lens {
            Lens::Thin { radius, .. } if radius > 0.0 => return None,
            Lens::Orthographic { height: view_height } => {
                let film_x = (d.dot(self.right) / (0.5 * view_height * aspect) + 1.0) * 0.5 * width;
                let film_y = (1.0 - d.dot(self.up) / (0.5 * view_height)) * 0.5 * height;
                if !(0.0..width).contains(&film_x) || !(0.0..height).contains(&film_y) {
                    return None;
                }
                let height = view_height;
                return Some(Projection {
                    film_x,
                    film_y,
                    importance: 1.0 / (height * height * aspect),
                    to_camera: -self.forward,
                    camera_point: point - depth * self.forward,
                });
            }
            _ => {}
        }
        let sx = d.dot(self.right) / depth;
        let sy = d.dot(self.up) / depth;
        let film_x = (sx / (self.tan_half_fov * aspect) + 1.0) * 0.5 * width;
        let film_y = (1.0 - sy / self.tan_half_fov) * 0.5 * height;
        if !(0.0..width).contains(&film_x) || !(0.0..height).contains(&film_y) {
            return None;
        }
        let distance_squared = d.length_squared();
        let cos = depth / distance_squared.sqrt();
        let image_area = 4.0 * self.tan_half_fov * self.tan_half_fov * aspect;
        Some(Projection {
            film_x,
            film_y,
            importance: 1.0 / (image_area * cos * cos * cos * distance_squared),
            to_camera: -d / distance_squared.sqrt(),
            camera_point: self.position,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pixel's footprint, by hand: with a 90° field of view the film spans 2·d at distance d,
    /// so each of 100 rows covers 0.02·d; parallel rays over a 3-unit film, 3/100 at any
    /// distance. Cross-checked against two neighbouring pixels' rays.
    #[test]
    fn pixel_footprint_by_hand() {
        let camera = Camera::new(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y, 90.0, 100, 100).unwrap();
        assert!((camera.pixel_footprint(5.0) - 0.1).abs() < 1e-6);
        let ortho = camera.clone().with_lens(Lens::Orthographic { height: 3.0 });
        assert!((ortho.pixel_footprint(5.0) - 0.03).abs() < 1e-6);
        assert!((ortho.pixel_footprint(50.0) - 0.03).abs() < 1e-6);
        // Two rays a pixel apart at the image centre, where the film faces the camera, meet the
        // plane z = −5 a footprint apart.
        let meet = |ray: Ray| ray.origin + ray.direction * (-5.0 - ray.origin.z) / ray.direction.z;
        let gap = (meet(camera.generate_ray(50.0, 50.0)) - meet(camera.generate_ray(50.0, 51.0))).length();
        assert!((gap - camera.pixel_footprint(5.0)).abs() < 1e-4, "{gap}");
        let gap = (meet(ortho.generate_ray(50.0, 50.0)) - meet(ortho.generate_ray(50.0, 51.0))).length();
        assert!((gap - ortho.pixel_footprint(5.0)).abs() < 1e-5, "{gap}");
    }

    /// A pinhole's rays made eight at a time are `generate_ray`'s, bit for bit, over cameras of
    /// many positions, views, fields of view and aspect ratios, at film points anywhere
    /// (outside the film too); other lenses are left to the scalar code.
    #[test]
    fn eight_pinhole_rays_equal_one_at_a_time() {
        let mut rng = crate::sampling::Rng::new(21, 4);
        let mut r = |scale: f32| (rng.next_f32() - 0.5) * scale;
        for _ in 0..300 {
            let position = Vec3::new(r(20.0), r(20.0), r(20.0));
            let look_at = position + Vec3::new(r(2.0), r(2.0), r(2.0)) + Vec3::splat(0.1);
            let (width, height) = (1 + (r(600.0) + 300.0) as u32, 1 + (r(400.0) + 200.0) as u32);
            let fov = 5.0 + (r(1.0) + 0.5) * 160.0;
            let Some(camera) = Camera::new(position, look_at, Vec3::new(r(0.2), 1.0, r(0.2)), fov, width, height)
            else {
                continue;
            };
            let x: [f32; LANES] = std::array::from_fn(|_| r(1.2 * width as f32) + 0.5 * width as f32);
            let y: [f32; LANES] = std::array::from_fn(|_| r(1.2 * height as f32) + 0.5 * height as f32);
            let eight = camera.pinhole_rays8(f32x8::from(x), f32x8::from(y)).expect("a pinhole");
            for k in 0..LANES {
                assert_eq!(eight[k], camera.generate_ray(x[k], y[k]), "film point ({}, {})", x[k], y[k]);
            }
            let thin = camera.clone().with_lens(Lens::Thin { radius: 0.0, focus_distance: 1.0 });
            assert!(thin.pinhole_rays8(f32x8::from(x), f32x8::from(y)).is_none());
        }
    }

    #[test]
    fn centre_and_corner_rays() {
        let cam = Camera::new(Vec3::ZERO, Vec3::Z, Vec3::Y, 90.0, 200, 100).unwrap();
        assert_eq!(cam.generate_ray(100.0, 50.0).direction, Vec3::Z);
        // Top edge at 45° up; right = forward × up = z × y = −x.
        let top = cam.generate_ray(100.0, 0.0).direction;
        assert!((top - Vec3::new(0.0, 1.0, 1.0).normalize()).length() < 1e-6);
        let right = cam.generate_ray(200.0, 50.0).direction;
        assert!((right - Vec3::new(-2.0, 0.0, 1.0).normalize()).length() < 1e-6);
        // Mirrored (a left-handed camera, pbrt's): the right edge looks toward +x, the top
        // edge as before.
        let mirrored = cam.clone().mirrored();
        assert!((mirrored.generate_ray(200.0, 50.0).direction - Vec3::new(2.0, 0.0, 1.0).normalize()).length() < 1e-6);
        assert_eq!(mirrored.generate_ray(100.0, 0.0).direction, top);
        // Its projection still inverts its rays.
        let p = mirrored.project(Vec3::new(1.5, 0.25, 1.0)).expect("in view");
        let back = mirrored.generate_ray(p.film_x, p.film_y).direction;
        assert!((back - Vec3::new(1.5, 0.25, 1.0).normalize()).length() < 1e-5, "{back}");
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
    fn orthographic_rays_are_parallel_and_project_back() {
        let cam = Camera::new(Vec3::new(0.0, 1.0, -5.0), Vec3::new(0.0, 1.0, 0.0), Vec3::Y, 45.0, 40, 20)
            .unwrap()
            .with_lens(Lens::Orthographic { height: 4.0 });
        let top_left = cam.generate_ray(0.0, 0.0);
        assert_eq!(top_left.direction, Vec3::Z);
        // 4 high, 8 wide; image right is forward × up = −x.
        assert!((top_left.origin - Vec3::new(4.0, 3.0, -5.0)).length() < 1e-5, "{}", top_left.origin);
        for (fx, fy) in [(0.5, 0.5), (20.0, 10.0), (39.5, 19.5)] {
            let p = cam.project(cam.generate_ray(fx, fy).at(3.0)).unwrap();
            assert!((p.film_x - fx).abs() < 1e-3 && (p.film_y - fy).abs() < 1e-3);
            assert_eq!(p.to_camera, -Vec3::Z);
        }
        // Importance × projected area over the film's area = 1.
        let p = cam.project(Vec3::new(0.0, 1.0, 2.0)).unwrap();
        assert!((p.importance * 32.0 - 1.0).abs() < 1e-6);
    }

    #[test]
    fn a_thin_lens_focuses_on_its_focus_plane() {
        let cam = Camera::new(Vec3::ZERO, Vec3::Z, Vec3::Y, 40.0, 30, 30)
            .unwrap()
            .with_lens(Lens::Thin { radius: 0.5, focus_distance: 3.0 });
        assert!(cam.samples_lens());
        for (fx, fy) in [(15.0, 15.0), (2.0, 27.0)] {
            let centre = cam.generate_ray(fx, fy);
            let focus = centre.at(3.0 / centre.direction.z);
            for u in [Vec2::new(0.1, 0.9), Vec2::new(0.8, 0.3), Vec2::new(0.5, 0.0)] {
                let r = cam.generate_ray_through_lens(fx, fy, u);
                assert!(r.origin.z == 0.0 && r.origin.length() <= 0.5 + 1e-6 && r.origin.length() > 0.0);
                let at_focus = r.at((3.0 - r.origin.z) / r.direction.z);
                assert!((at_focus - focus).length() < 1e-4, "{at_focus} vs {focus}");
            }
        }
        assert!(cam.project(Vec3::new(0.0, 0.0, 3.0)).is_none(), "no connections to a lens");
    }

    #[test]
    fn degenerate_cameras_are_refused() {
        assert!(Camera::new(Vec3::ZERO, Vec3::ZERO, Vec3::Y, 45.0, 1, 1).is_none());
        assert!(Camera::new(Vec3::ZERO, Vec3::Y, Vec3::Y, 45.0, 1, 1).is_none());
    }

    /// A cropped camera's image is the window of the whole film's: the same rays, bit for bit
    /// (one at a time and eight at a time, through a pinhole and a lens), and points project
    /// to the same film places less the window's corner, with the importance of the window's
    /// share of the film.
    #[test]
    fn a_crop_window_sees_the_films_pixels_there() {
        let whole = Camera::new(Vec3::new(1.0, 2.0, -3.0), Vec3::new(0.2, 0.1, 0.0), Vec3::Y, 40.0, 64, 48).unwrap();
        let crop = whole.with_crop(10, 5, 30, 45).unwrap();
        assert_eq!((crop.width, crop.height), (20, 40));
        assert_eq!(crop.film_resolution(), (64, 48));
        assert_eq!(crop.crop_window(), Some((10, 5, 30, 45)));
        for (x, y) in [(0.5f32, 0.5f32), (19.9, 39.9), (7.25, 13.5)] {
            assert_eq!(crop.generate_ray(x, y), whole.generate_ray(x + 10.0, y + 5.0));
            let u = Vec2::new(0.3, 0.8);
            let lens = Lens::Thin { radius: 0.1, focus_distance: 4.0 };
            assert_eq!(
                crop.clone().with_lens(lens).generate_ray_through_lens(x, y, u),
                whole.clone().with_lens(lens).generate_ray_through_lens(x + 10.0, y + 5.0, u)
            );
        }
        let xs: [f32; 8] = std::array::from_fn(|k| k as f32 * 2.3 + 0.5);
        let ys: [f32; 8] = std::array::from_fn(|k| 39.0 - k as f32 * 4.1);
        let eight = crop.pinhole_rays8(f32x8::from(xs), f32x8::from(ys)).unwrap();
        for k in 0..8 {
            assert_eq!(eight[k], whole.generate_ray(xs[k] + 10.0, ys[k] + 5.0), "lane {k}");
        }
        let point = whole.generate_ray(20.5, 30.5).at(5.0);
        let (p, q) = (whole.project(point).unwrap(), crop.project(point).unwrap());
        assert!((q.film_x - (p.film_x - 10.0)).abs() < 1e-4 && (q.film_y - (p.film_y - 5.0)).abs() < 1e-4);
        let share = (20.0 * 40.0) / (64.0 * 48.0);
        assert!((q.importance * share - p.importance).abs() < 1e-6 * p.importance);
        // Seen on the film but outside the window: not in the image.
        assert!(crop.project(whole.generate_ray(5.5, 20.5).at(5.0)).is_none());
        assert_eq!(crop.pixel_footprint(3.0), whole.pixel_footprint(3.0));
    }

    #[test]
    fn crop_windows_off_the_film_or_empty_are_refused_and_rescale_with_it() {
        let whole = Camera::new(Vec3::ZERO, Vec3::Z, Vec3::Y, 40.0, 64, 48).unwrap();
        assert!(whole.with_crop(10, 5, 10, 45).is_none());
        assert!(whole.with_crop(10, 5, 65, 45).is_none());
        assert!(whole.with_crop(40, 5, 30, 45).is_none());
        // The whole film is no crop at all.
        assert_eq!(whole.with_crop(0, 0, 64, 48).unwrap(), whole);
        // Twice the resolution: the window keeps its place on the film.
        let crop = whole.with_crop(10, 5, 30, 45).unwrap().with_resolution(128, 96);
        assert_eq!(crop.film_resolution(), (128, 96));
        assert_eq!(crop.crop_window(), Some((20, 10, 60, 90)));
    }
}
