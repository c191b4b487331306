//! The environment: what rays that leave the scene see (a constant background or a map), and
//! the course's ambient light level. When light arrives from outside it is a light like the
//! others (`Light::Environment`).
//!
//! An environment map: radiance arriving from infinitely far away, by direction, stored as a
//! latitude-longitude (equirectangular) image in Mitsuba's convention: +y is up (the image's
//! top row), and a direction d (in the map's own frame) is at u = atan2(d.x, −d.z) / 2π
//! (wrapped into [0, 1)), v = acos(d.y) / π.
//!
//! Radiance is interpolated bilinearly between pixels as Mitsuba's `envmap` does: the pixels
//! are the vertices of a grid, column x at u = (x + ½) / width (wrapping around), row y at
//! v = y / (height − 1), so the first and last rows lie on the poles.
//!
//! Sampled for next-event estimation by a piecewise-constant density over the grid's cells,
//! in proportion to the mean luminance of a cell's four corners × sin θ at its centre: a
//! small sun in a large sky is found by light sampling, and every direction whose radiance
//! is not zero has a density (a corner that is not black makes its cells' weight positive),
//! so the estimate is unbiased. The density per solid angle is p(u, v) / (2π² sin θ).

use glam::{Mat3, Vec2, Vec3};

use crate::sampling::distribution::Distribution2D;
use crate::sampling::warp::{square_to_uniform_sphere, UNIFORM_SPHERE_PDF};
use crate::Rgb;

/// Scene-wide values that are not objects.
#[derive(Clone, Debug, PartialEq)]
pub struct Environment {
    /// Radiance seen by rays that leave the scene (when there is no map).
    pub background: Rgb,
    /// The course's ambient light level I_a.
    pub ambient_light: Rgb,
    /// An environment map: radiance by direction, importance-sampled by the path tracer.
    pub map: Option<std::sync::Arc<EnvironmentMap>>,
}

impl Environment {
    /// No light from outside, no ambient light.
    pub const BLACK: Self = Self { background: Rgb::ZERO, ambient_light: Rgb::ZERO, map: None };

    /// Radiance seen looking along `direction` out of the scene.
    pub fn radiance(&self, direction: Vec3) -> Rgb {
        match &self.map {
            Some(map) => map.radiance(direction),
            None => self.background,
        }
    }

    /// `radiance` and `pdf` together, for a path that leaves the scene after a BSDF sample:
    /// a map's direction is turned into its texel coordinates once (two arctangents) instead
    /// of twice. The same values, bit for bit.
    pub fn radiance_and_pdf(&self, direction: Vec3) -> (Rgb, f32) {
        match &self.map {
            Some(map) => map.radiance_and_pdf(direction),
            None => (self.background, self.pdf(direction)),
        }
    }

    /// Whether light arrives from outside the scene (a map, or a background that is not black):
    /// then it is a light like the others, sampled and emitting particles.
    pub fn emits(&self) -> bool {
        self.map.is_some() || self.background != Rgb::ZERO
    }

    /// A direction toward the environment: by the map's brightness, or uniform over the sphere
    /// for a constant background. `None` if nothing comes from outside.
    pub fn sample(&self, u: Vec2) -> Option<EnvironmentSample> {
        match &self.map {
            Some(map) => map.sample(u),
            None if self.background != Rgb::ZERO => Some(EnvironmentSample {
                direction: square_to_uniform_sphere(u),
                radiance: self.background,
                pdf: UNIFORM_SPHERE_PDF,
            }),
            None => None,
        }
    }

    /// The solid-angle density of `sample` for `direction`.
    pub fn pdf(&self, direction: Vec3) -> f32 {
        match &self.map {
            Some(map) => map.pdf(direction),
            None if self.background != Rgb::ZERO => UNIFORM_SPHERE_PDF,
            None => 0.0,
        }
    }

    /// ∫ L dω over the sphere (mean over RGB): the power per unit area it sends across a
    /// plane, summed over directions.
    pub fn radiance_integral(&self) -> f32 {
        match &self.map {
            Some(map) => map.radiance_integral(),
            None => 4.0 * std::f32::consts::PI * self.background.dot(Rgb::splat(1.0 / 3.0)),
        }
    }
}

/// Each cell of the vertex grid (cell (x, y) spans columns x..x+1 and rows y..y+1, the last
/// column wrapping to the first), row by row: the mean of `value` at its four corners times
/// sin θ at its centre, its share of solid angle. What sampling weighs cells by (luminance)
/// and what the radiance integral sums (the mean over RGB).
fn cell_weights(pixels: &[Rgb], w: usize, h: usize, value: impl Fn(Rgb) -> f32) -> Vec<f32> {
    (0..w * (h - 1))
        .map(|i| {
            let (x, y) = (i % w, i / w);
            let at = |x: usize, y: usize| value(pixels[y * w + x % w]);
            let corners = at(x, y) + at(x + 1, y) + at(x, y + 1) + at(x + 1, y + 1);
            let sin = (std::f32::consts::PI * (y as f32 + 0.5) / (h - 1) as f32).sin();
            0.25 * corners * sin
        })
        .collect()
}

#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentMap {
    width: u32,
    height: u32,
    /// Row-major, row 0 = top (+y), already multiplied by the scale.
    pixels: Vec<Rgb>,
    /// Map frame → world (a rotation), and back.
    to_world: Mat3,
    to_map: Mat3,
    distribution: Distribution2D,
}

/// A direction sampled toward the environment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvironmentSample {
    pub direction: Vec3,
    pub radiance: Rgb,
    /// Per solid angle.
    pub pdf: f32,
}

impl EnvironmentMap {
    /// `pixels` are `width × height` linear RGB, row 0 at the top; `to_world` rotates the map.
    pub fn new(width: u32, height: u32, pixels: Vec<Rgb>, scale: f32, to_world: Mat3) -> Self {
        assert!(width >= 1 && height >= 2, "an environment map needs at least two rows");
        let pixels: Vec<Rgb> = pixels.into_iter().map(|p| p * scale).collect();
        let (w, h) = (width as usize, height as usize);
        let weights = cell_weights(&pixels, w, h, |p| p.dot(Rgb::new(0.2126, 0.7152, 0.0722)).max(0.0));
        let distribution = Distribution2D::new(&weights, w, h - 1);
        Self { width, height, pixels, to_world, to_map: to_world.transpose(), distribution }
    }

    /// The sampling domain's point for a direction: (u − half a texel, v), wrapped into [0, 1).
    fn grid_uv(&self, world: Vec3) -> Vec2 {
        let d = (self.to_map * world).normalize();
        let u = d.x.atan2(-d.z) * 0.5 * std::f32::consts::FRAC_1_PI - 0.5 / self.width as f32;
        // θ by atan2, which keeps its precision near the poles (acos of d.y does not).
        let v = d.x.hypot(d.z).atan2(d.y) * std::f32::consts::FRAC_1_PI;
        Vec2::new(u.rem_euclid(1.0).min(1.0 - f32::EPSILON), v.min(1.0 - f32::EPSILON))
    }

    fn direction(&self, grid_uv: Vec2) -> Vec3 {
        let phi = 2.0 * std::f32::consts::PI * (grid_uv.x + 0.5 / self.width as f32);
        let theta = std::f32::consts::PI * grid_uv.y;
        let (sin_t, cos_t) = theta.sin_cos();
        self.to_world * Vec3::new(sin_t * phi.sin(), cos_t, -sin_t * phi.cos())
    }

    /// Bilinear between the four pixels around `grid_uv`.
    fn lookup(&self, grid_uv: Vec2) -> Rgb {
        let (w, h) = (self.width as usize, self.height as usize);
        let x = grid_uv.x * w as f32;
        let y = grid_uv.y * (h - 1) as f32;
        let (x0, y0) = ((x as usize).min(w - 1), (y as usize).min(h - 2));
        let (fx, fy) = (x - x0 as f32, y - y0 as f32);
        // The column right of x0, wrapped around the seam (a comparison: the modulo's
        // divisions were a third of this lookup).
        let x1 = if x0 + 1 == w { 0 } else { x0 + 1 };
        let at = |x: usize, y: usize| self.pixels[y * w + x];
        let top = at(x0, y0) * (1.0 - fx) + at(x1, y0) * fx;
        let bottom = at(x0, y0 + 1) * (1.0 - fx) + at(x1, y0 + 1) * fx;
        top * (1.0 - fy) + bottom * fy
    }

    /// ∫ L dω over the sphere, mean over RGB (each cell's mean radiance times its solid angle).
    pub fn radiance_integral(&self) -> f32 {
        let (w, h) = (self.width as usize, self.height as usize);
        let cell = 2.0 * std::f32::consts::PI / w as f32 * std::f32::consts::PI / (h - 1) as f32;
        let weights = cell_weights(&self.pixels, w, h, |p| p.dot(Rgb::splat(1.0 / 3.0)));
        weights.iter().map(|&weight| (weight * cell) as f64).sum::<f64>() as f32
    }

    /// Radiance arriving along `-direction`, i.e. seen when looking toward `direction`.
    pub fn radiance(&self, direction: Vec3) -> Rgb {
        self.lookup(self.grid_uv(direction))
    }

    pub fn sample(&self, u: Vec2) -> Option<EnvironmentSample> {
        let (grid_uv, pdf_uv) = self.distribution.sample(u);
        let sin = (std::f32::consts::PI * grid_uv.y).sin();
        if pdf_uv <= 0.0 || sin <= 0.0 {
            return None;
        }
        let pdf = pdf_uv / (2.0 * std::f32::consts::PI * std::f32::consts::PI * sin);
        Some(EnvironmentSample { direction: self.direction(grid_uv), radiance: self.lookup(grid_uv), pdf })
    }

    /// The solid-angle density of `sample` producing `direction`.
    pub fn pdf(&self, direction: Vec3) -> f32 {
        self.pdf_at(self.grid_uv(direction))
    }

    /// `radiance` and `pdf` from one conversion of the direction.
    pub fn radiance_and_pdf(&self, direction: Vec3) -> (Rgb, f32) {
        let grid_uv = self.grid_uv(direction);
        (self.lookup(grid_uv), self.pdf_at(grid_uv))
    }

    fn pdf_at(&self, grid_uv: Vec2) -> f32 {
        let sin = (std::f32::consts::PI * grid_uv.y).sin();
        if sin <= 0.0 {
            return 0.0;
        }
        self.distribution.pdf(grid_uv) / (2.0 * std::f32::consts::PI * std::f32::consts::PI * sin)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::chi2::chi2_test;

    /// A sky with a bright patch, rotated: a non-trivial distribution in every direction.
    fn sky() -> EnvironmentMap {
        let (w, h) = (32u32, 16u32);
        let pixels = (0..w * h)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                let base = Rgb::new(0.2, 0.3, 0.5) * (1.0 + (x as f32 * 0.7).sin().abs());
                if (10..13).contains(&x) && (3..6).contains(&y) {
                    base + Rgb::splat(40.0)
                } else {
                    base
                }
            })
            .collect();
        EnvironmentMap::new(w, h, pixels, 2.0, Mat3::from_rotation_x(0.4) * Mat3::from_rotation_y(1.1))
    }

    #[test]
    fn directions_round_trip_through_uv() {
        let map = sky();
        for i in 0..50 {
            let uv = Vec2::new((i as f32 * 0.137).fract(), 0.02 + 0.96 * (i as f32 * 0.311).fract());
            let back = map.grid_uv(map.direction(uv));
            let du = (back.x - uv.x).abs();
            assert!(du.min(1.0 - du) < 1e-4 && (back.y - uv.y).abs() < 1e-4, "{uv} → {back}");
        }
        // Mitsuba's convention in the map's own frame: +y is the top row, −z is u = 0, and
        // the grid is shifted by half a texel (4 columns: u = 0 is grid u = 1 − 1/8).
        let plain = EnvironmentMap::new(4, 2, vec![Rgb::ONE; 8], 1.0, Mat3::IDENTITY);
        assert!((plain.grid_uv(Vec3::Y).y).abs() < 1e-6);
        assert!((plain.grid_uv(-Vec3::Z) - Vec2::new(0.875, 0.5)).length() < 1e-6);
        assert!((plain.grid_uv(Vec3::X) - Vec2::new(0.125, 0.5)).length() < 1e-6);
    }

    #[test]
    fn radiance_is_bilinear_between_pixel_centres_and_rows_on_the_poles() {
        // 4 × 3: column x at u = (x + ½)/4, row y at v = y/2 (rows 0 and 2 on the poles).
        let pixels: Vec<Rgb> = (0..12).map(|i| Rgb::splat(i as f32)).collect();
        let map = EnvironmentMap::new(4, 3, pixels, 1.0, Mat3::IDENTITY);
        let toward = |u: f32, v: f32| {
            let (phi, theta) = (2.0 * std::f32::consts::PI * u, std::f32::consts::PI * v);
            Vec3::new(theta.sin() * phi.sin(), theta.cos(), -theta.sin() * phi.cos())
        };
        let close = |a: Rgb, b: f32| (a.x - b).abs() < 1e-4;
        // Pixel (1, 1): u = 3/8 on the equator.
        assert!(close(map.radiance(toward(0.375, 0.5)), 5.0), "{}", map.radiance(toward(0.375, 0.5)));
        // Halfway between columns 1 and 2, and between rows 1 and 2.
        assert!(close(map.radiance(toward(0.5, 0.5)), 5.5));
        assert!(close(map.radiance(toward(0.375, 0.75)), 7.0));
        // Across the seam: between column 3 (u = 7/8) and column 0 (u = 1/8 + 1).
        assert!(close(map.radiance(toward(0.0, 0.5)), 0.5 * (7.0 + 4.0)));
        // Next to the north pole: row 0.
        assert!(close(map.radiance(toward(0.375, 1e-5)), 1.0));
    }

    #[test]
    fn sampling_matches_its_pdf() {
        let map = sky();
        // 200,000 samples: with more, the harness's midpoint integration of this pdf's 40×
        // jumps across cell edges becomes the larger error.
        let r = chi2_test(|u| map.sample(u).map(|s| s.direction), |w| map.pdf(w) as f64, 200_000, 31, 61, 9);
        assert!(r.p_value > 0.01, "p = {}", r.p_value);
        for i in 0..200 {
            // Off the seam u = 0, where a direction may map back into the last column (measure zero).
            let u = Vec2::new((i as f32 * 0.61 + 0.003).fract(), (i as f32 * 0.37 + 0.001).fract());
            let s = map.sample(u).expect("only the poles (v = 0 or 1, probability 0) give none");
            assert!((map.pdf(s.direction) / s.pdf - 1.0).abs() < 1e-3, "{u}: {} vs {}", map.pdf(s.direction), s.pdf);
            let difference = (map.radiance(s.direction) - s.radiance).abs().max_element();
            assert!(difference <= 1e-3 * s.radiance.max_element(), "{} vs {}", map.radiance(s.direction), s.radiance);
        }
    }

    #[test]
    fn the_pdf_integrates_to_one() {
        let map = sky();
        let n = 400;
        let mut total = 0.0f64;
        for i in 0..n {
            for j in 0..2 * n {
                let z = -1.0 + 2.0 * (i as f64 + 0.5) / n as f64;
                let phi = std::f64::consts::PI * (j as f64 + 0.5) / n as f64;
                let r = (1.0 - z * z).sqrt();
                let w = Vec3::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32);
                total += map.pdf(w) as f64 * (2.0 / n as f64) * (std::f64::consts::PI / n as f64);
            }
        }
        assert!((total - 1.0).abs() < 0.01, "{total}");
    }
}
