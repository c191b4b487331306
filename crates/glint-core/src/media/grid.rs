//! A heterogeneous medium: extinction σ_t(p) = `scale` × a density grid, looked up by
//! trilinear interpolation between voxel centres over an axis-aligned box (Mitsuba's
//! `gridvolume` under a `heterogeneous` medium), with a constant single-scattering albedo.
//!
//! Transmittance has no closed form here; it is estimated against the grid's majorant
//! σ̄ = scale × max density (Woodcock's construction: fictitious "null" collisions make the
//! medium homogeneous at σ̄):
//! * delta tracking draws free flights and keeps a tentative collision as real with
//!   probability σ_t(p) / σ̄; a flight that reaches the end has probability T exactly;
//! * ratio tracking walks the same tentative collisions and multiplies 1 − σ_t(p) / σ̄ at
//!   each: an unbiased estimate of T with lower variance than delta tracking's 0 or 1.

use glam::Vec3;

use crate::geometry::Aabb;
use crate::sampling::Rng;
use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct GridMedium {
    /// Voxels along x, y and z (private with the densities and the scale: the majorant is
    /// made from them once).
    resolution: [usize; 3],
    /// x fastest, then y, then z.
    density: Vec<f32>,
    bounds: Aabb,
    scale: f32,
    pub albedo: Rgb,
    majorant: f32,
}

/// Tentative collisions one tracking walk may take (σ̄ × the length inside the box on
/// average): a bound on the work of a walk through a very dense grid, past which it stops as
/// if it had left the box (a bias only in grids some 10⁶ mean free paths across).
const MAX_STEPS: usize = 1 << 20;

/// Where delta tracking ends a flight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Collision {
    /// A real collision at distance `t` (the medium scatters with weight `albedo`).
    At(f32),
    /// Reached the end of the segment.
    Escaped,
}

impl GridMedium {
    /// `None` if the sizes disagree or a density is negative or not finite.
    pub fn new(resolution: [usize; 3], density: Vec<f32>, bounds: Aabb, scale: f32, albedo: Rgb) -> Option<Self> {
        let count = resolution.iter().try_fold(1usize, |n, &r| n.checked_mul(r).filter(|_| r > 0))?;
        if count != density.len()
            || density.iter().any(|d| !(d.is_finite() && *d >= 0.0))
            || !(scale.is_finite() && scale >= 0.0)
        {
            return None;
        }
        let majorant = scale * density.iter().fold(0.0f32, |m, &d| m.max(d));
        if !majorant.is_finite() {
            return None;
        }
        if !majorant.is_finite() {
            return None;
        }
        Some(Self { resolution, density, bounds, scale, albedo, majorant })
    }

    /// σ_t at a point: trilinear between voxel centres, clamped at the grid's edges; zero
    /// outside its box.
    pub fn sigma_t(&self, p: Vec3) -> f32 {
        let size = self.bounds.max - self.bounds.min;
        let local = (p - self.bounds.min) / size;
        if local.min_element() < 0.0 || local.max_element() > 1.0 {
            return 0.0;
        }
        let [nx, ny, nz] = self.resolution;
        let at = |axis: f32, n: usize| {
            let x = (axis * n as f32 - 0.5).clamp(0.0, (n - 1) as f32);
            let i = (x as usize).min(n.saturating_sub(2));
            (i, (i + 1).min(n - 1), x - i as f32)
        };
        let ((x0, x1, fx), (y0, y1, fy), (z0, z1, fz)) = (at(local.x, nx), at(local.y, ny), at(local.z, nz));
        let d = |x: usize, y: usize, z: usize| self.density[(z * ny + y) * nx + x];
        let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
        let bottom = lerp(lerp(d(x0, y0, z0), d(x1, y0, z0), fx), lerp(d(x0, y1, z0), d(x1, y1, z0), fx), fy);
        let top = lerp(lerp(d(x0, y0, z1), d(x1, y0, z1), fx), lerp(d(x0, y1, z1), d(x1, y1, z1), fx), fy);
        self.scale * lerp(bottom, top, fz)
    }

    pub fn majorant(&self) -> f32 {
        self.majorant
    }

    /// The part of [0, t_max] where a ray from `origin` along `direction` is inside the
    /// grid's box (the medium is empty elsewhere): tracking runs there alone. `None` if it
    /// misses the box or the part is not finite.
    fn span(&self, origin: Vec3, direction: Vec3, t_max: f32) -> Option<(f32, f32)> {
        let inverse = direction.recip();
        let (a, b) = ((self.bounds.min - origin) * inverse, (self.bounds.max - origin) * inverse);
        let (near, far) = (a.min(b), a.max(b));
        // NaN (a zero direction component on a face) reads as unbounded on that axis.
        let enter = [near.x, near.y, near.z].into_iter().filter(|t| !t.is_nan()).fold(0.0f32, f32::max);
        let exit = [far.x, far.y, far.z].into_iter().filter(|t| !t.is_nan()).fold(t_max, f32::min);
        (enter < exit && exit.is_finite()).then_some((enter, exit))
    }

    /// Delta tracking along `origin + t·direction` (unit direction) for t < `t_max`.
    pub fn delta_track(&self, origin: Vec3, direction: Vec3, t_max: f32, rng: &mut Rng) -> Collision {
        if self.majorant <= 0.0 {
            return Collision::Escaped;
        }
        let Some((mut t, t_max)) = self.span(origin, direction, t_max) else { return Collision::Escaped };
        for _ in 0..MAX_STEPS {
            let next = t - (1.0 - rng.next_f32()).max(f32::MIN_POSITIVE).ln() / self.majorant;
            if next >= t_max || next <= t {
                return Collision::Escaped;
            }
            t = next;
            if rng.next_f32() * self.majorant < self.sigma_t(origin + t * direction) {
                return Collision::At(t);
            }
        }
        Collision::Escaped
    }

    /// Ratio tracking's estimate of the transmittance from `origin` over `t_max`.
    pub fn ratio_track(&self, origin: Vec3, direction: Vec3, t_max: f32, rng: &mut Rng) -> f32 {
        if self.majorant <= 0.0 {
            return 1.0;
        }
        let Some((mut t, t_max)) = self.span(origin, direction, t_max) else { return 1.0 };
        let mut transmittance = 1.0f32;
        for _ in 0..MAX_STEPS {
            let next = t - (1.0 - rng.next_f32()).max(f32::MIN_POSITIVE).ln() / self.majorant;
            if next >= t_max || next <= t {
                return transmittance;
            }
            t = next;
            transmittance *= 1.0 - self.sigma_t(origin + t * direction) / self.majorant;
            // Roulette once the estimate is small: unbiased, and it ends long walks.
            if transmittance < 0.1 {
                if rng.next_f32() >= transmittance {
                    return 0.0;
                }
                transmittance = 1.0;
            }
        }
        transmittance
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 4 × 1 × 1 grid ramping along x over the box [0, 4] × [0, 1]²: densities 0, 1, 2, 3
    /// at x = ½, 1½, 2½, 3½.
    fn ramp() -> GridMedium {
        let bounds = Aabb { min: Vec3::ZERO, max: Vec3::new(4.0, 1.0, 1.0) };
        GridMedium::new([4, 1, 1], vec![0.0, 1.0, 2.0, 3.0], bounds, 0.5, Rgb::splat(0.8)).unwrap()
    }

    /// ∫ σ_t along the x axis through the ramp, by the midpoint rule.
    fn optical_depth(grid: &GridMedium, y: f32, t_max: f32) -> f64 {
        let n = 100_000;
        (0..n).map(|i| grid.sigma_t(Vec3::new((i as f32 + 0.5) * t_max / n as f32, y, 0.5)) as f64).sum::<f64>()
            * t_max as f64
            / n as f64
    }

    #[test]
    fn lookups_interpolate_between_voxel_centres_by_hand() {
        let grid = ramp();
        // At x = 2 (halfway between the centres of voxels 1 and 2): 0.5 × 1.5.
        assert!((grid.sigma_t(Vec3::new(2.0, 0.5, 0.5)) - 0.75).abs() < 1e-6);
        // Clamped beyond the outer centres, zero outside the box.
        assert_eq!(grid.sigma_t(Vec3::new(3.9, 0.5, 0.5)), 1.5);
        assert_eq!(grid.sigma_t(Vec3::new(0.1, 0.5, 0.5)), 0.0);
        assert_eq!(grid.sigma_t(Vec3::new(4.5, 0.5, 0.5)), 0.0);
        assert_eq!(grid.majorant(), 1.5);
        // The optical depth across the box, by hand: scale ½ × ∫ density, where ∫ density =
        // 0 on [0, ½] (clamped) + 4.5 (the ramp 0 → 3 over [½, 3½]) + 1.5 (3 on [3½, 4]) = 6.
        assert!((optical_depth(&grid, 0.5, 4.0) - 3.0).abs() < 1e-4);
        assert!(GridMedium::new([2, 1, 1], vec![1.0], grid.bounds, 1.0, Rgb::ONE).is_none());
        assert!(GridMedium::new([1, 1, 1], vec![-1.0], grid.bounds, 1.0, Rgb::ONE).is_none());
    }

    /// Both estimators agree with exp(−∫σ_t) by quadrature, on the ramp and a 3-D field.
    #[test]
    fn ratio_and_delta_tracking_estimate_the_transmittance_without_bias() {
        let field = {
            let n = 6;
            let density = (0..n * n * n)
                .map(|i| {
                    let (x, y, z) = (i % n, (i / n) % n, i / (n * n));
                    ((x * 7 + y * 3 + z * 5) % 11) as f32 / 4.0
                })
                .collect();
            GridMedium::new([n, n, n], density, Aabb { min: Vec3::ZERO, max: Vec3::new(4.0, 1.0, 1.0) }, 0.6, Rgb::ONE)
                .unwrap()
        };
        for (name, grid) in [("ramp", ramp()), ("field", field)] {
            for (y, t_max) in [(0.5f32, 4.0f32), (0.3, 2.5)] {
                let expected = (-optical_depth(&grid, y, t_max)).exp();
                let origin = Vec3::new(0.0, y, 0.5);
                let mut rng = Rng::new(3, 7);
                let n = 200_000;
                let (mut ratio, mut ratio2, mut escaped) = (0.0f64, 0.0f64, 0usize);
                for _ in 0..n {
                    let r = grid.ratio_track(origin, Vec3::X, t_max, &mut rng) as f64;
                    ratio += r;
                    ratio2 += r * r;
                    if grid.delta_track(origin, Vec3::X, t_max, &mut rng) == Collision::Escaped {
                        escaped += 1;
                    }
                }
                let mean = ratio / n as f64;
                let error = ((ratio2 / n as f64 - mean * mean) / n as f64).sqrt();
                assert!((mean - expected).abs() < 4.0 * error + 1e-5, "{name}: ratio {mean} vs {expected} ± {error}");
                let p = escaped as f64 / n as f64;
                let error = (expected * (1.0 - expected) / n as f64).sqrt();
                assert!((p - expected).abs() < 4.0 * error + 1e-5, "{name}: delta {p} vs {expected} ± {error}");
            }
        }
    }
}
