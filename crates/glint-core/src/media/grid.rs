//! A heterogeneous medium: extinction σ_t(p) = `scale` × a density field (grey or per
//! channel; `voxels.rs`), zero outside the field's box (Mitsuba's `heterogeneous` medium over
//! a `gridvolume` or a `constvolume`), with an albedo constant or itself a field.
//!
//! Transmittance has no closed form here; it is estimated against the grid's majorant
//! σ̄ = scale × the largest density of any channel (Woodcock's construction: fictitious
//! "null" collisions make the medium homogeneous at σ̄):
//! * delta tracking draws free flights and keeps a tentative collision as real with
//!   probability σ_t(p) / σ̄ (of a channel drawn per flight, weighed over all three);
//! * ratio tracking walks the same tentative collisions and multiplies 1 − σ_t(p) / σ̄ at
//!   each: an unbiased estimate of T with lower variance than delta tracking's 0 or 1.

use glam::Vec3;

use super::homogeneous::Flight;
use super::voxels::VoxelField;
use crate::sampling::Rng;
use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct GridMedium {
    /// The density (grey or per channel); the medium is empty outside its box. Private with
    /// the scale: the majorant is made from them once.
    density: VoxelField,
    scale: f32,
    pub albedo: Albedo,
    majorant: f32,
}

/// A grid medium's single-scattering albedo σ_s / σ_t.
#[derive(Clone, Debug, PartialEq)]
pub enum Albedo {
    Constant(Rgb),
    /// Looked up where the medium scatters (clamped to its field's edges outside its box).
    Field(VoxelField),
}

/// Tentative collisions one tracking walk may take (σ̄ × the length inside the box on
/// average): a bound on the work of a walk through a very dense grid, past which it stops as
/// if it had left the box (a bias only in grids some 10⁶ mean free paths across).
const MAX_STEPS: usize = 1 << 20;

impl GridMedium {
    /// `None` if the scale is negative or the majorant not finite.
    pub fn new(density: VoxelField, scale: f32, albedo: Albedo) -> Option<Self> {
        let majorant = scale * density.max();
        if !(scale.is_finite() && scale >= 0.0 && majorant.is_finite()) {
            return None;
        }
        Some(Self { density, scale, albedo, majorant })
    }

    /// σ_t at a point: zero outside the grid's box.
    pub fn sigma_t(&self, p: Vec3) -> Rgb {
        if !self.density.contains(p) {
            return Rgb::ZERO;
        }
        self.scale * self.density.eval(p)
    }

    pub fn albedo_at(&self, p: Vec3) -> Rgb {
        match &self.albedo {
            Albedo::Constant(a) => *a,
            Albedo::Field(field) => field.eval(p).min(Rgb::ONE),
        }
    }

    pub fn majorant(&self) -> f32 {
        self.majorant
    }

    /// A tentative collision after `t` against the majorant (`None` past `t_max`). A step
    /// below the precision of `t` (a dense grid far from the ray's origin) still advances, by
    /// one ulp: rounding must not end a walk as if it had left the grid.
    fn next_collision(&self, t: f32, t_max: f32, rng: &mut Rng) -> Option<f32> {
        let next = t - (1.0 - rng.next_f32()).max(f32::MIN_POSITIVE).ln() / self.majorant;
        let next = next.max(t.next_up());
        (next < t_max).then_some(next)
    }

    /// A free flight along `origin + t·direction` (unit direction) for t < `t_max`, by delta
    /// tracking against the majorant σ̄ (the same for every channel, so tentative collisions
    /// are too): a channel c is drawn, and each tentative collision is real with probability
    /// σ_t,c / σ̄. The weight is the flight's contribution over the mean of the three
    /// channels' probabilities of the same decisions (one-sample MIS over the channels, as
    /// for homogeneous media): for a grey density it is 1 / σ_t at a real collision (times
    /// σ_s: the albedo, as plain delta tracking) and 1 for a pass; densities that differ by
    /// channel are tracked without bias wherever any channel is dense.
    pub fn flight(&self, origin: Vec3, direction: Vec3, t_max: f32, rng: &mut Rng) -> Flight {
        let passed = Flight::Passed { weight: Rgb::ONE };
        if self.majorant <= 0.0 {
            return passed;
        }
        let Some((mut t, t_max)) = self.density.span(origin, direction, t_max) else { return passed };
        let channel = ((rng.next_f32() * 3.0) as usize).min(2);
        // Π (1 − σ_t/σ̄) over the null collisions so far, per channel: both the flight's
        // contribution and each channel's probability of the same decisions (before the
        // last one), so the weights below are ratios of it alone.
        let mut nulls = Rgb::ONE;
        for _ in 0..MAX_STEPS {
            let Some(next) = self.next_collision(t, t_max, rng) else { break };
            t = next;
            let point = origin + t * direction;
            let real = (self.sigma_t(point) / self.majorant).min(Rgb::ONE);
            if rng.next_f32() < real[channel] {
                // Over σ̄ once more: the contribution's coefficient at the collision (σ_s, σ_t
                // or the emission, over σ̄) is the caller's.
                let mean = (nulls * real).element_sum() / 3.0;
                return Flight::Scattered { t, weight: nulls / (mean * self.majorant) };
            }
            nulls *= Rgb::ONE - real;
            // Kept in range: only ratios of it matter.
            let mean = nulls.element_sum() / 3.0;
            if mean < 1e-20 {
                nulls /= mean;
            }
        }
        Flight::Passed { weight: nulls / (nulls.element_sum() / 3.0) }
    }

    /// Ratio tracking's estimate of the transmittance from `origin` over `t_max`: the product
    /// of 1 − σ_t / σ̄ over the tentative collisions, per channel.
    pub fn ratio_track(&self, origin: Vec3, direction: Vec3, t_max: f32, rng: &mut Rng) -> Rgb {
        if self.majorant <= 0.0 {
            return Rgb::ONE;
        }
        let Some((mut t, t_max)) = self.density.span(origin, direction, t_max) else { return Rgb::ONE };
        let mut transmittance = Rgb::ONE;
        for _ in 0..MAX_STEPS {
            let Some(next) = self.next_collision(t, t_max, rng) else { break };
            t = next;
            transmittance *= (Rgb::ONE - self.sigma_t(origin + t * direction) / self.majorant).max(Rgb::ZERO);
            // Roulette once the estimate is small: unbiased, and it ends long walks.
            let largest = transmittance.max_element();
            if largest < 0.1 {
                if rng.next_f32() >= largest {
                    return Rgb::ZERO;
                }
                transmittance /= largest;
            }
        }
        transmittance
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::media::voxels::box_to_world;

    fn box_4x1x1() -> glam::Affine3A {
        box_to_world(Vec3::ZERO, Vec3::new(4.0, 1.0, 1.0))
    }

    /// A 4 × 1 × 1 grid ramping along x over the box [0, 4] × [0, 1]²: densities 0, 1, 2, 3
    /// at x = ½, 1½, 2½, 3½.
    fn ramp() -> GridMedium {
        let density = VoxelField::new([4, 1, 1], 1, vec![0.0, 1.0, 2.0, 3.0], box_4x1x1()).unwrap();
        GridMedium::new(density, 0.5, Albedo::Constant(Rgb::splat(0.8))).unwrap()
    }

    /// ∫ σ_t along the x axis through a grid, by the midpoint rule.
    fn optical_depth(grid: &GridMedium, y: f32, t_max: f32) -> [f64; 3] {
        let n = 100_000;
        let mut sum = [0.0f64; 3];
        for i in 0..n {
            let s = grid.sigma_t(Vec3::new((i as f32 + 0.5) * t_max / n as f32, y, 0.5));
            for c in 0..3 {
                sum[c] += s[c] as f64 * t_max as f64 / n as f64;
            }
        }
        sum
    }

    #[test]
    fn lookups_interpolate_between_voxel_centres_by_hand() {
        let grid = ramp();
        let at = |x: f32| grid.sigma_t(Vec3::new(x, 0.5, 0.5)).x;
        // At x = 2 (halfway between the centres of voxels 1 and 2): 0.5 × 1.5.
        assert!((at(2.0) - 0.75).abs() < 1e-6);
        // Clamped beyond the outer centres, zero outside the box.
        assert_eq!(at(3.9), 1.5);
        assert_eq!(at(0.1), 0.0);
        assert_eq!(at(4.5), 0.0);
        assert_eq!(grid.majorant(), 1.5);
        // The optical depth across the box, by hand: scale ½ × ∫ density, where ∫ density =
        // 0 on [0, ½] (clamped) + 4.5 (the ramp 0 → 3 over [½, 3½]) + 1.5 (3 on [3½, 4]) = 6.
        assert!((optical_depth(&grid, 0.5, 4.0)[0] - 3.0).abs() < 1e-4);
    }

    /// A 6³ field of densities that differ by channel (as Mitsuba's RGB `gridvolume`s may),
    /// with an albedo field of its own.
    fn chromatic_field() -> GridMedium {
        let n = 6;
        let density = (0..n * n * n)
            .flat_map(|i| {
                let (x, y, z) = (i % n, (i / n) % n, i / (n * n));
                let d = ((x * 7 + y * 3 + z * 5) % 11) as f32 / 4.0;
                [d, 0.3 * d + 0.2, 2.5 - d.min(2.5)]
            })
            .collect();
        let density = VoxelField::new([n, n, n], 3, density, box_4x1x1()).unwrap();
        let albedo = VoxelField::new([2, 1, 1], 3, vec![0.9, 0.5, 0.1, 0.2, 0.6, 1.0], box_4x1x1()).unwrap();
        GridMedium::new(density, 0.6, Albedo::Field(albedo)).unwrap()
    }

    /// Ratio tracking and delta tracking's passes agree with exp(−∫σ_t) by quadrature, per
    /// channel, on the ramp and on the chromatic field.
    #[test]
    fn ratio_and_delta_tracking_estimate_the_transmittance_without_bias() {
        for (name, grid) in [("ramp", ramp()), ("field", chromatic_field())] {
            for (y, t_max) in [(0.5f32, 4.0f32), (0.3, 2.5)] {
                let depth = optical_depth(&grid, y, t_max);
                let origin = Vec3::new(0.0, y, 0.5);
                let mut rng = Rng::new(3, 7);
                let n = 200_000;
                let mut sums = [[0.0f64; 3]; 4]; // ratio, ratio², pass, pass²
                for _ in 0..n {
                    let r = grid.ratio_track(origin, Vec3::X, t_max, &mut rng);
                    let pass = match grid.flight(origin, Vec3::X, t_max, &mut rng) {
                        Flight::Passed { weight } => weight,
                        Flight::Scattered { .. } => Rgb::ZERO,
                    };
                    for c in 0..3 {
                        sums[0][c] += r[c] as f64;
                        sums[1][c] += (r[c] as f64).powi(2);
                        sums[2][c] += pass[c] as f64;
                        sums[3][c] += (pass[c] as f64).powi(2);
                    }
                }
                for c in 0..3 {
                    let expected = (-depth[c]).exp();
                    for (estimator, sum, sum2) in [("ratio", sums[0][c], sums[1][c]), ("delta", sums[2][c], sums[3][c])]
                    {
                        let mean = sum / n as f64;
                        let error = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
                        assert!(
                            (mean - expected).abs() < 4.0 * error + 1e-5,
                            "{name} {estimator} channel {c}: {mean} vs {expected} ± {error}"
                        );
                    }
                }
            }
        }
    }

    /// A dense grid far from the ray's origin: its steps (1/σ̄ = 10⁻³) are below the precision
    /// of t there (ulp(1000) ≈ 6·10⁻⁵ on some steps' scale), and rounding must not end a walk
    /// as if it had left the grid. Optical depth 1000: nothing gets through.
    #[test]
    fn tracking_far_away_through_a_dense_grid_does_not_leak() {
        let density = VoxelField::constant(Rgb::ONE, box_to_world(Vec3::splat(1000.0), Vec3::splat(1001.0))).unwrap();
        let grid = GridMedium::new(density, 1000.0, Albedo::Constant(Rgb::splat(0.5))).unwrap();
        let origin = Vec3::new(0.0, 1000.5, 1000.5);
        let mut rng = Rng::new(1, 2);
        let (mut passed, mut transmitted) = (0, Rgb::ZERO);
        for _ in 0..2000 {
            if matches!(grid.flight(origin, Vec3::X, 2000.0, &mut rng), Flight::Passed { .. }) {
                passed += 1;
            }
            transmitted += grid.ratio_track(origin, Vec3::X, 2000.0, &mut rng);
        }
        assert_eq!(passed, 0, "flights leaked through");
        assert_eq!(transmitted, Rgb::ZERO, "ratio tracking leaked");
    }

    /// Delta tracking's scattering events are unbiased too: E[weight · 1(scattered)] is the
    /// single-scattering integral ∫₀^T σ_s(t) e^{−∫₀^t σ_t} dt, per channel, by quadrature.
    #[test]
    fn delta_tracking_scatters_without_bias_per_channel() {
        let grid = chromatic_field();
        let (y, t_max) = (0.4f32, 3.5f32);
        let origin = Vec3::new(0.0, y, 0.5);
        let steps = 100_000;
        let dt = t_max as f64 / steps as f64;
        let (mut expected, mut depth) = ([0.0f64; 3], [0.0f64; 3]);
        for i in 0..steps {
            let p = Vec3::new(((i as f64 + 0.5) * dt) as f32, y, 0.5);
            let (sigma_t, albedo) = (grid.sigma_t(p), grid.albedo_at(p));
            for c in 0..3 {
                let mid = depth[c] + 0.5 * sigma_t[c] as f64 * dt;
                expected[c] += (sigma_t[c] * albedo[c]) as f64 * (-mid).exp() * dt;
                depth[c] += sigma_t[c] as f64 * dt;
            }
        }
        let mut rng = Rng::new(11, 5);
        let n = 400_000;
        let (mut sum, mut sum2) = ([0.0f64; 3], [0.0f64; 3]);
        for _ in 0..n {
            if let Flight::Scattered { weight, t } = grid.flight(origin, Vec3::X, t_max, &mut rng) {
                assert!(t < t_max);
                let point = origin + t * Vec3::X;
                let weight = weight * grid.sigma_t(point) * grid.albedo_at(point);
                for c in 0..3 {
                    sum[c] += weight[c] as f64;
                    sum2[c] += (weight[c] as f64).powi(2);
                }
            }
        }
        for c in 0..3 {
            let mean = sum[c] / n as f64;
            let error = ((sum2[c] / n as f64 - mean * mean) / n as f64).sqrt();
            assert!(
                (mean - expected[c]).abs() < 4.0 * error + 1e-5,
                "channel {c}: {mean} vs {} ± {error}",
                expected[c]
            );
        }
    }
}
