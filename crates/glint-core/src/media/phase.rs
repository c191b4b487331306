//! Phase functions: how a medium scatters light at a point, as a density over outgoing
//! directions (they integrate to 1 over the sphere, so sampling one exactly has weight 1).
//!
//! Directions are directions of travel: `incoming` is the way the light (or the path) was
//! going, `outgoing` the way it goes on; cos θ = incoming · outgoing, so θ = 0 is no change
//! of direction. Henyey and Greenstein's phase function with g > 0 scatters forward.

use glam::{Vec2, Vec3};

use crate::geometry::orthonormal_basis;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PhaseFunction {
    /// 1 / 4π in every direction.
    Isotropic,
    /// Henyey–Greenstein with mean cosine `g` in (−1, 1).
    HenyeyGreenstein { g: f32 },
}

/// A sampled outgoing direction; its weight (value / pdf) is 1 for these exactly sampled
/// phase functions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhaseSample {
    pub outgoing: Vec3,
    pub pdf: f32,
}

const INV_4PI: f32 = 0.25 * std::f32::consts::FRAC_1_PI;

impl PhaseFunction {
    /// The density of scattering from `incoming` into `outgoing` (both unit directions of
    /// travel), per steradian.
    pub fn eval(&self, incoming: Vec3, outgoing: Vec3) -> f32 {
        match *self {
            PhaseFunction::Isotropic => INV_4PI,
            PhaseFunction::HenyeyGreenstein { g } => henyey_greenstein(incoming.dot(outgoing), g),
        }
    }

    /// An outgoing direction drawn in proportion to `eval` from two uniform numbers.
    pub fn sample(&self, incoming: Vec3, u: Vec2) -> PhaseSample {
        let cos_theta = match *self {
            PhaseFunction::Isotropic => 1.0 - 2.0 * u.x,
            PhaseFunction::HenyeyGreenstein { g } => {
                if g.abs() < 1e-3 {
                    1.0 - 2.0 * u.x
                } else {
                    // The inverse of HG's distribution of cos θ.
                    let s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u.x);
                    ((1.0 + g * g - s * s) / (2.0 * g)).clamp(-1.0, 1.0)
                }
            }
        };
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        let phi = 2.0 * std::f32::consts::PI * u.y;
        let (t, b) = orthonormal_basis(incoming);
        let outgoing = (sin_theta * phi.cos()) * t + (sin_theta * phi.sin()) * b + cos_theta * incoming;
        let outgoing = outgoing.normalize();
        PhaseSample { outgoing, pdf: self.eval(incoming, outgoing) }
    }

    /// The mean cosine of the scattering angle.
    pub fn mean_cosine(&self) -> f32 {
        match *self {
            PhaseFunction::Isotropic => 0.0,
            PhaseFunction::HenyeyGreenstein { g } => g,
        }
    }
}

/// p(cos θ) = (1 − g²) / (4π (1 + g² − 2g cos θ)^{3/2}).
fn henyey_greenstein(cos_theta: f32, g: f32) -> f32 {
    let denominator = 1.0 + g * g - 2.0 * g * cos_theta;
    INV_4PI * (1.0 - g * g) / (denominator * denominator.max(0.0).sqrt()).max(1e-12)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::chi2::chi2_test;
    use crate::sampling::Rng;

    #[test]
    fn henyey_greenstein_by_hand_and_isotropic_at_g_zero() {
        // g = 0.5, θ = 0: 0.75 / (4π · 0.25^{3/2}) = 0.75 / (4π · 0.125) = 6 / 4π.
        assert!((henyey_greenstein(1.0, 0.5) - 6.0 * INV_4PI).abs() < 1e-6);
        // Backward: 0.75 / (4π · 2.25^{3/2}) = 0.75 / (4π · 3.375).
        assert!((henyey_greenstein(-1.0, 0.5) - 0.75 / 3.375 * INV_4PI).abs() < 1e-7);
        assert!((henyey_greenstein(0.3, 0.0) - INV_4PI).abs() < 1e-9);
    }

    #[test]
    fn each_integrates_to_one_with_its_mean_cosine() {
        // Midpoint quadrature over cos θ (the density depends on it alone).
        for phase in [
            PhaseFunction::Isotropic,
            PhaseFunction::HenyeyGreenstein { g: 0.7 },
            PhaseFunction::HenyeyGreenstein { g: -0.4 },
        ] {
            let n = 200_000;
            let (mut total, mut mean) = (0.0f64, 0.0f64);
            for i in 0..n {
                let c = -1.0 + 2.0 * (i as f64 + 0.5) / n as f64;
                let s = (1.0 - c * c).sqrt() as f32;
                let p = phase.eval(Vec3::Z, Vec3::new(s, 0.0, c as f32)) as f64 * 2.0 * std::f64::consts::PI * 2.0
                    / n as f64;
                total += p;
                mean += p * c;
            }
            assert!((total - 1.0).abs() < 1e-3, "{phase:?}: {total}");
            assert!((mean - phase.mean_cosine() as f64).abs() < 2e-3, "{phase:?}: {mean}");
        }
    }

    #[test]
    fn sampling_matches_the_density_by_chi_square() {
        let incoming = Vec3::new(0.3, -0.5, 0.8).normalize();
        for (seed, phase) in [
            PhaseFunction::Isotropic,
            PhaseFunction::HenyeyGreenstein { g: 0.8 },
            PhaseFunction::HenyeyGreenstein { g: -0.3 },
        ]
        .into_iter()
        .enumerate()
        {
            let r = chi2_test(
                |u| Some(phase.sample(incoming, u).outgoing),
                |w| phase.eval(incoming, w) as f64,
                400_000,
                21,
                41,
                seed as u64 + 1,
            );
            assert!(r.p_value > 0.01 / 3.0, "{phase:?}: p = {}", r.p_value);
            let mut rng = Rng::new(9, 1);
            for _ in 0..1000 {
                let s = phase.sample(incoming, Vec2::new(rng.next_f32(), rng.next_f32()));
                assert!((s.outgoing.length() - 1.0).abs() < 1e-5);
                assert!((s.pdf - phase.eval(incoming, s.outgoing)).abs() <= 1e-5 * s.pdf);
            }
        }
    }
}
