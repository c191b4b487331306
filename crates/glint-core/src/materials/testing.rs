//! The checks every BSDF file runs (tests only): sampling against the pdf by chi-square over the
//! whole sphere, each sample's weight against eval / pdf, the directional albedo (the white
//! furnace: the mean sample weight, ≤ 1 for a material that conserves energy), and Whitted's
//! reading of a member against its BSDF.

use glam::{Vec2, Vec3};

use super::bsdf::{Bsdf, Frame, Leaf};
use super::Material;
use crate::geometry::{reflect, refract};
use crate::sampling::chi2::chi2_test_with_resolution;
use crate::sampling::Rng;
use crate::textures::TextureQuery;
use crate::Rgb;

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

/// The mean weight of `samples` BSDF samples from `wo`, counting only those that leave within
/// 3° of `toward` (a delta lobe's weight; a narrow lobe's albedo in that direction), and the
/// mean's standard error, per channel.
fn albedo_toward(bsdf: &Bsdf, wo: Vec3, toward: Vec3, samples: usize, seed: u64) -> (Rgb, Rgb) {
    let cone = 3f32.to_radians().cos();
    let mut rng = Rng::new(seed, 4);
    // Summed in f64: 200 000 weights near 1 would lose a part in 10³ in f32.
    let (mut sum, mut sum2) = (glam::DVec3::ZERO, glam::DVec3::ZERO);
    for _ in 0..samples {
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        if let Some(s) = bsdf.sample(wo, rng.next_f32(), u) {
            if s.wi.dot(toward) >= cone {
                let w = s.weight.as_dvec3();
                sum += w;
                sum2 += w * w;
            }
        }
    }
    let n = samples as f64;
    let mean = sum / n;
    let error = ((sum2 / n - mean * mean).max(glam::DVec3::ZERO) / n).powf(0.5);
    (mean.as_vec3(), error.as_vec3())
}

/// Whitted's reading of `material` (`Material::whitted_at`) against its BSDF, seen at `degrees`
/// from the normal from the outside (the side the geometric normal points to) or not: the
/// weight of each child ray, mirror, refraction (at the reading's index) and straight on, is
/// the mean weight of the BSDF's samples that leave that way (within 5 standard errors, and
/// 2·10⁻³ for a smooth limit's tails), the refraction's going to the mirror where Snell's law
/// has no solution, as Whitted's integrator moves it.
pub(super) fn check_whitted(material: &Material, outside: bool, degrees: f32, seed: u64) {
    let n = Vec3::Z;
    let theta = degrees.to_radians();
    let wo = Vec3::new(theta.sin(), 0.0, theta.cos());
    let q = TextureQuery::default();
    let geometric = if outside { n } else { -n };
    let bsdf = material.bsdf(&q, wo, geometric, geometric);
    let w = material.whitted_at(&q, outside, wo.z);
    let eta = if outside { 1.0 / w.ior } else { w.ior };
    let refracted = refract(-wo, n, eta);
    let (mirror, transmission) =
        if refracted.is_some() { (w.reflection, w.transmission) } else { (w.reflection + w.transmission, Rgb::ZERO) };
    let mut expected = vec![("mirror", reflect(-wo, n), mirror), ("straight", -wo, w.straight)];
    if let Some(direction) = refracted {
        // Straight on and refracted coincide head-on: one expectation for both.
        if direction.dot(-wo) < 0.999 {
            expected.push(("refraction", direction, transmission));
        } else {
            expected[1].2 += transmission;
        }
    }
    for (name, direction, weight) in expected {
        let (mean, error) = albedo_toward(&bsdf, wo, direction, 200_000, seed);
        let tolerance = error * 5.0 + Rgb::splat(2e-3);
        assert!(
            (mean - weight).abs().cmple(tolerance).all(),
            "{name} at {degrees}° ({}): Whitted {weight}, BSDF {mean} ± {error}",
            if outside { "outside" } else { "inside" }
        );
    }
}

/// Whitted's local term for a light of intensity 1 from each of `lights` is π times the
/// BSDF's f·|cos θ_i| (the course's convention: k_d is the albedo), seen from `wo` on the side
/// the normal z points to.
pub(super) fn check_whitted_local(material: &Material, wo: Vec3, lights: &[Vec3]) {
    let q = TextureQuery::default();
    let bsdf = material.bsdf(&q, wo, Vec3::Z, Vec3::Z);
    let w = material.whitted_at(&q, true, wo.z);
    for &wi in lights {
        let (whitted, path) = (w.local(Vec3::Z, wo, wi, Rgb::ONE), bsdf.eval(wo, wi) * std::f32::consts::PI);
        assert!((whitted - path).abs().max_element() < 1e-5, "light from {wi}: Whitted {whitted}, π·f·cos {path}");
    }
}
