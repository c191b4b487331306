//! The checks every BSDF file runs (tests only): sampling against the pdf by chi-square over the
//! whole sphere, each sample's weight against eval / pdf, and the directional albedo (the white
//! furnace: the mean sample weight, ≤ 1 for a material that conserves energy).

use glam::{Vec2, Vec3};

use super::bsdf::{Bsdf, Frame, Leaf};
use crate::sampling::chi2::chi2_test_with_resolution;
use crate::sampling::Rng;

/// The frame a BSDF seen from `wo` gets on a surface of normal `n` (both normals `n`).
pub(super) fn frame_toward(wo: Vec3, n: Vec3) -> Frame {
    Frame::new(wo, n, n)
}

/// A leaf as a whole BSDF.
pub(super) fn at<'a>(leaf: &Leaf<'a>) -> Bsdf<'a> {
    Bsdf::leaf(*leaf)
}

/// The non-delta part's sampling from `wo` on a surface of normal `n` matches its pdf
/// (chi-square in the frame of `n`, so the horizon falls inside one ring of cells; threshold
/// shared by the suite: p > 0.01 / 8), and every non-delta sample weighs eval / pdf.
pub(super) fn check_sampling(bsdf: &Bsdf, wo: Vec3, n: Vec3, seed: u64) {
    let frame = Frame::new(n, n, n);
    let mut rng = Rng::new(seed, 1);
    // Each cell's pdf integrated on 24 × 24 points: grazing lobes of α = 0.1 are narrower
    // than a cell.
    let r = chi2_test_with_resolution(
        |u| bsdf.sample_non_delta(wo, rng.next_f32(), u).map(|s| frame.to_local(s.wi)),
        |w| (bsdf.pdf(wo, frame.to_world(w)) / bsdf.non_delta_probability()) as f64,
        500_000,
        21,
        41,
        seed,
        24,
    );
    assert!(r.p_value > 0.01 / 8.0, "wo {wo}: p = {} (chi2 {})", r.p_value, r.statistic);
    let mut rng = Rng::new(seed, 2);
    for _ in 0..2000 {
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        if let Some(s) = bsdf.sample(wo, rng.next_f32(), u) {
            assert!(s.weight.is_finite() && s.weight.min_element() >= 0.0, "{s:?}");
            if !s.delta {
                let expected = bsdf.eval(wo, s.wi) / bsdf.pdf(wo, s.wi);
                let tolerance = 1e-4 * expected.max_element().max(1.0);
                assert!((s.weight - expected).abs().max_element() < tolerance, "{s:?} vs {expected}");
                assert!((s.pdf - bsdf.pdf(wo, s.wi)).abs() <= 1e-4 * s.pdf, "{s:?}");
            }
        }
    }
}

#[derive(Clone, Copy, Debug)]
pub(super) struct Albedo {
    pub(super) mean: f64,
    pub(super) standard_error: f64,
}

/// The directional albedo from `wo` (first channel): the mean of `samples` sample weights.
pub(super) fn albedo(bsdf: &Bsdf, wo: Vec3, samples: usize, seed: u64) -> Albedo {
    let mut rng = Rng::new(seed, 3);
    let (mut sum, mut sum2) = (0.0f64, 0.0f64);
    for _ in 0..samples {
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        let w = bsdf.sample(wo, rng.next_f32(), u).map_or(0.0, |s| s.weight.x as f64);
        sum += w;
        sum2 += w * w;
    }
    let mean = sum / samples as f64;
    let variance = (sum2 / samples as f64 - mean * mean).max(0.0);
    Albedo { mean, standard_error: (variance / samples as f64).sqrt() }
}

/// The directional albedo of the non-delta part by quadrature of `eval` over the sphere
/// (midpoints of a 600 × 600 grid in cos θ and φ): the second method the furnace tests check
/// sampling against.
pub(super) fn albedo_by_quadrature(bsdf: &Bsdf, wo: Vec3) -> f64 {
    let (nz, nphi) = (600, 600);
    let mut sum = 0.0f64;
    for i in 0..nz {
        let z = -1.0 + 2.0 * (i as f32 + 0.5) / nz as f32;
        let r = (1.0 - z * z).max(0.0).sqrt();
        for j in 0..nphi {
            let phi = std::f32::consts::TAU * (j as f32 + 0.5) / nphi as f32;
            sum += bsdf.eval(wo, Vec3::new(r * phi.cos(), r * phi.sin(), z)).x as f64;
        }
    }
    sum * (2.0 * std::f64::consts::TAU) / (nz * nphi) as f64
}

/// Sampling and quadrature give the same albedo (within 5 standard errors and 1.5 % for the
/// quadrature of a peaked lobe), and it is at most 1: the white furnace of a rough BSDF.
pub(super) fn furnace(bsdf: &Bsdf, wo: Vec3, seed: u64) -> Albedo {
    let a = albedo(bsdf, wo, 200_000, seed);
    let q = albedo_by_quadrature(bsdf, wo);
    assert!((a.mean - q).abs() < 5.0 * a.standard_error + 0.015 * q, "sampled {a:?}, quadrature {q}");
    // A lossless lobe sums to 1 within rounding (with no spread at all: Lambert transmission).
    assert!(a.mean <= 1.0 + 1e-5 + 5.0 * a.standard_error, "gains energy: {a:?}");
    a
}
