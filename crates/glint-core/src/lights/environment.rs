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

use crate::lanes::{atan2, sin_cos_turns, LaneVec3, Lanes};
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
    #[cfg(test)]
    fn grid_uv(&self, world: Vec3) -> Vec2 {
        let (u, v) = self.grid_uv_lanes(LaneVec3::<f32>::from(world));
        Vec2::new(u, v)
    }

    /// `grid_uv` in lanes. The arctangents are `lanes::atan2`'s, the same bits at every width.
    #[inline(always)]
    fn grid_uv_lanes<L: Lanes>(&self, world: LaneVec3<L>) -> (L, L) {
        let c = L::splat;
        let d = world.transformed_by(&self.to_map).normalize();
        let u = atan2(d.x, d.z.negate()) * c(0.5) * c(std::f32::consts::FRAC_1_PI) - c(0.5 / self.width as f32);
        let v = atan2((d.x * d.x + d.z * d.z).sqrt(), d.y) * c(std::f32::consts::FRAC_1_PI);
        // u ∈ [−½ − ½/width, ½]: `rem_euclid(1)` is a turn added below 0 (exact).
        let u = L::select(u.lt(L::ZERO), u + L::ONE, u);
        let most = c(1.0 - f32::EPSILON);
        (u.min(most), v.min(most))
    }

    /// The direction at a point of the sampling domain.
    #[cfg(test)]
    fn direction(&self, grid_uv: Vec2) -> Vec3 {
        self.direction_lanes(grid_uv.x, grid_uv.y).0.into()
    }

    /// The direction at a point (u, v) of the sampling domain, and sin θ there.
    #[inline(always)]
    fn direction_lanes<L: Lanes>(&self, u: L, v: L) -> (LaneVec3<L>, L) {
        // φ = 2π (u + ½/width) in turns, wrapped below one turn (exactly: Sterbenz).
        let turns = u + L::splat(0.5 / self.width as f32);
        let turns = L::select(turns.ge(L::ONE), turns - L::ONE, turns);
        let (sin_phi, cos_phi) = sin_cos_turns(turns);
        let (sin_theta, cos_theta) = sin_theta_cos_theta(v);
        let local = LaneVec3::new(sin_theta * sin_phi, cos_theta, (sin_theta * cos_phi).negate());
        (local.transformed_by(&self.to_world), sin_theta)
    }

    /// Bilinear between the four pixels around (u, v), in lanes: the loads of all the lanes'
    /// texels issued together.
    #[inline(always)]
    fn lookup_lanes<L: Lanes>(&self, u: L, v: L) -> LaneVec3<L> {
        let (w, h) = (self.width as usize, self.height as usize);
        let x = u * L::splat(w as f32);
        let y = v * L::splat((h - 1) as f32);
        let (x0, y0) = (x.floor().min(L::splat((w - 1) as f32)), y.floor().min(L::splat((h - 2) as f32)));
        let (fx, fy) = (x - x0, y - y0);
        let at = |dx: usize, dy: usize| {
            LaneVec3::gather(|k| {
                let column = x0.lane(k) as usize + dx;
                self.pixels[(y0.lane(k) as usize + dy) * w + if column == w { 0 } else { column }]
            })
        };
        let top = at(0, 0) * (L::ONE - fx) + at(1, 0) * fx;
        let bottom = at(0, 1) * (L::ONE - fx) + at(1, 1) * fx;
        top * (L::ONE - fy) + bottom * fy
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
        let (u, v) = self.grid_uv_lanes(LaneVec3::<f32>::from(direction));
        self.lookup_lanes(u, v).into()
    }

    /// A direction drawn in proportion to the map's luminance (times sin θ); `None` on the
    /// poles (probability 0), where the density per solid angle has no finite value.
    pub fn sample(&self, u: Vec2) -> Option<EnvironmentSample> {
        let s = self.sample_lanes(u.x, u.y);
        s.valid.then(|| EnvironmentSample { direction: s.direction.into(), radiance: s.radiance.into(), pdf: s.pdf })
    }

    /// `sample` in lanes: the lanes' searches of the density's tables, and their texels' loads,
    /// made together.
    #[inline(always)]
    pub(crate) fn sample_lanes<L: Lanes>(&self, u: L, v: L) -> EnvironmentSampleLanes<L> {
        let (gu, gv, pdf_uv) = self.distribution.sample_lanes(u, v);
        let (direction, sin) = self.direction_lanes(gu, gv);
        let valid = pdf_uv.gt(L::ZERO) & sin.gt(L::ZERO);
        EnvironmentSampleLanes {
            direction,
            radiance: self.lookup_lanes(gu, gv),
            pdf: per_solid_angle(pdf_uv, sin),
            valid,
        }
    }

    /// The solid-angle density of `sample` producing `direction`.
    pub fn pdf(&self, direction: Vec3) -> f32 {
        let (u, v) = self.grid_uv_lanes(LaneVec3::<f32>::from(direction));
        self.pdf_lanes(u, v)
    }

    /// `radiance` and `pdf` from one conversion of the direction.
    pub fn radiance_and_pdf(&self, direction: Vec3) -> (Rgb, f32) {
        let (radiance, pdf) = self.radiance_and_pdf_lanes(LaneVec3::<f32>::from(direction), true);
        (radiance.into(), pdf)
    }

    /// `radiance_and_pdf` in lanes; the density 0 unless `with_pdf`.
    #[inline(always)]
    pub(crate) fn radiance_and_pdf_lanes<L: Lanes>(&self, direction: LaneVec3<L>, with_pdf: bool) -> (LaneVec3<L>, L) {
        let (u, v) = self.grid_uv_lanes(direction);
        (self.lookup_lanes(u, v), if with_pdf { self.pdf_lanes(u, v) } else { L::ZERO })
    }

    /// The solid-angle density at a point (u, v) of the sampling domain; 0 on the poles.
    #[inline(always)]
    fn pdf_lanes<L: Lanes>(&self, u: L, v: L) -> L {
        let (sin, _) = sin_theta_cos_theta(v);
        L::select(sin.gt(L::ZERO), per_solid_angle(self.distribution.pdf_lanes(u, v), sin), L::ZERO)
    }
}

/// sin θ and cos θ at θ = π v (half a turn at most).
#[inline(always)]
fn sin_theta_cos_theta<L: Lanes>(v: L) -> (L, L) {
    sin_cos_turns(v * L::splat(0.5))
}

/// A density over the sampling domain as one per solid angle, where sin θ = `sin`: the domain's
/// cell at θ spans 2π² sin θ times its area in steradians.
#[inline(always)]
fn per_solid_angle<L: Lanes>(pdf_uv: L, sin: L) -> L {
    pdf_uv / (L::splat(2.0 * std::f32::consts::PI * std::f32::consts::PI) * sin)
}

/// `EnvironmentMap::sample` in lanes: where `valid`, a direction, the radiance from it and the
/// density per solid angle.
pub(crate) struct EnvironmentSampleLanes<L: Lanes> {
    pub direction: LaneVec3<L>,
    pub radiance: LaneVec3<L>,
    pub pdf: L,
    pub valid: L::Mask,
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
        assert!((plain.grid_uv(-Vec3::Z) - Vec2::new(0.875, 0.5)).length() < 1e-6, "{}", plain.grid_uv(-Vec3::Z));
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
