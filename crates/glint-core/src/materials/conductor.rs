//! A smooth metal, Mitsuba's `conductor`: a perfect mirror weighted by the Fresnel reflectance
//! of a conductor, whose index of refraction is complex, η + ik, per RGB channel (pbrt-v4
//! §9.3.6); and the indices of common metals. One-sided (black from behind).
//!
//! Scene parameters: `metal` (a name from `METAL_NAMES`; default "Al" in the native format,
//! a perfect mirror, η = 0 and k = 1, in Mitsuba's) or `eta` and `k` (colours);
//! `specular_reflectance` (colour or texture, a factor, default 1); `two_sided` (native
//! format, default true).
//! ```toml
//! [materials.gold]
//! type = "conductor"
//! metal = "Au"
//! ```
//!
//! F(θ) = ½ (|r∥|² + |r⊥|²) with r∥ = (η cos θ − cos θ_t) / (η cos θ + cos θ_t),
//! r⊥ = (cos θ − η cos θ_t) / (cos θ + η cos θ_t), cos θ_t = √(1 − sin² θ / η²), all complex.
//! At normal incidence it is ((n − 1)² + k²) / ((n + 1)² + k²); toward grazing it rises to 1.

use glam::{Vec2, Vec3};
use wide::f32x4;

use super::bsdf::{BsdfSample, Frame, LaneBsdfSample, LaneFrame, Leaf, Lobes};
use super::PhongPoint;
use crate::lanes::{self, LaneVec3, Lanes};
use crate::textures::{Texture, TextureQuery};
use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct Conductor {
    pub eta: Rgb,
    pub k: Rgb,
    pub specular: Texture,
}

impl Conductor {
    pub(super) fn bsdf(&self, query: &TextureQuery, frame: Frame) -> Leaf<'static> {
        Leaf::Conductor(ConductorBsdf { frame, eta: self.eta, k: self.k, specular: self.specular.evaluate(query) })
    }

    /// Whitted's view: the mirror ray, weighted as the BSDF weighs it: the specular factor
    /// times the conductor's Fresnel reflectance at the viewer's angle (cosine `cos`). Black
    /// from behind, as the BSDF.
    pub(super) fn whitted(&self, query: &TextureQuery, outside: bool, cos: f32) -> PhongPoint {
        if !outside {
            return PhongPoint::BLACK;
        }
        let reflection = self.specular.evaluate(query) * fresnel_conductor(cos, self.eta, self.k);
        PhongPoint { reflection, ..PhongPoint::BLACK }
    }
}

#[derive(Clone, Copy, Debug)]
pub(super) struct ConductorBsdf {
    frame: Frame,
    eta: Rgb,
    k: Rgb,
    specular: Rgb,
}

/// A smooth conductor at a hit, in lanes: the one body of its mirror, which the scalar BSDF
/// runs at one lane and the wavefront at eight.
#[derive(Clone, Debug)]
pub(crate) struct ConductorLanes<L: Lanes> {
    pub frame: LaneFrame<L>,
    pub eta: LaneVec3<L>,
    pub k: LaneVec3<L>,
    pub specular: LaneVec3<L>,
}

impl<L: Lanes> ConductorLanes<L> {
    /// The mirror direction, weighted by specular · F(cos θ_o); none from behind.
    #[inline(always)]
    pub fn sample(&self, wo: LaneVec3<L>) -> LaneBsdfSample<L> {
        let cos = wo.dot(self.frame.normal);
        LaneBsdfSample {
            wi: lanes::reflect(-wo, self.frame.normal),
            weight: self.specular.mul_lanes(fresnel_conductor_rgb(cos, self.eta, self.k)),
            pdf: L::ONE,
            valid: self.frame.outside & cos.gt(L::ZERO),
            eta_squared: L::ONE,
            delta: !L::Mask::default(),
        }
    }
}

impl Lobes for ConductorBsdf {
    fn sample(&self, wo: Vec3, _u_lobe: f32, _u: Vec2) -> Option<BsdfSample> {
        let lanes = ConductorLanes::<f32> {
            frame: LaneFrame::from(&self.frame),
            eta: self.eta.into(),
            k: self.k.into(),
            specular: self.specular.into(),
        };
        lanes.sample(wo.into()).scalar()
    }

    fn frame(&self) -> &Frame {
        &self.frame
    }
    fn frame_mut(&mut self) -> &mut Frame {
        &mut self.frame
    }
}

/// The Fresnel reflectance of a conductor of index η + ik, unpolarized, for the cosine of the
/// incident angle, in lanes: the closed form without complex numbers (Moeller's "Optics", as
/// pbrt-v3's `FrConductor` and Mitsuba 3's `fresnel_conductor` write it), with a² = ½(|z| + t₀)
/// taken as 2η²k² / (|z| − t₀) where t₀ < 0 (metals, k > η), so that it does not cancel.
#[inline(always)]
pub(crate) fn fresnel_conductor_lanes<L: Lanes>(cos_incident: L, eta: L, k: L) -> L {
    let cos = cos_incident.max(L::ZERO).min(L::ONE);
    let cos2 = cos * cos;
    let sin2 = L::ONE - cos2;
    let (eta2, k2) = (eta * eta, k * k);
    // (η + ik)² − sin²θ = t₀ + 2iηk, and its modulus |z| = a² + b².
    let t0 = eta2 - k2 - sin2;
    let modulus = (t0 * t0 + L::splat(4.0) * eta2 * k2).sqrt();
    let half = L::splat(0.5);
    let a2 = L::select(t0.lt(L::ZERO), L::splat(2.0) * eta2 * k2 / (modulus - t0), half * (modulus + t0));
    let a = a2.sqrt();
    let (t1, t2) = (modulus + cos2, L::splat(2.0) * cos * a);
    // Grazing light, or a matched index at grazing (0/0): all of it is reflected.
    let ratio = |n: L, d: L| L::select(d.gt(L::ZERO), n / d, L::ONE);
    let r_perpendicular = ratio(t1 - t2, t1 + t2);
    let (t3, t4) = (modulus * cos2 + sin2 * sin2, t2 * sin2);
    let r_parallel = r_perpendicular * ratio(t3 - t4, t3 + t4);
    (half * (r_parallel + r_perpendicular)).max(L::ZERO).min(L::ONE)
}

/// The Fresnel reflectance of a conductor per channel, each channel's η and k in its own
/// vector of lanes.
#[inline(always)]
pub(crate) fn fresnel_conductor_rgb<L: Lanes>(cos_incident: L, eta: LaneVec3<L>, k: LaneVec3<L>) -> LaneVec3<L> {
    LaneVec3::new(
        fresnel_conductor_lanes(cos_incident, eta.x, k.x),
        fresnel_conductor_lanes(cos_incident, eta.y, k.y),
        fresnel_conductor_lanes(cos_incident, eta.z, k.z),
    )
}

/// The Fresnel reflectance of a conductor per channel (the three channels in lanes).
pub fn fresnel_conductor(cos_incident: f32, eta: Rgb, k: Rgb) -> Rgb {
    let channels = |c: Rgb| f32x4::from([c.x, c.y, c.z, 0.0]);
    let f = fresnel_conductor_lanes(f32x4::splat(cos_incident), channels(eta), channels(k)).to_array();
    Rgb::new(f[0], f[1], f[2])
}

/// η and k of common metals at the red, green and blue wavelengths (RGB fits of measured data,
/// as RGB renderers tabulate them); for Fe, Ni, Ti and Pt, derived from the normal-incidence
/// reflectance with Gulbrandsen's fit (2014), edge tint = reflectance.
pub fn named_metal(name: &str) -> Option<(Rgb, Rgb)> {
    let measured = |eta: [f32; 3], k: [f32; 3]| Some((Rgb::from(eta), Rgb::from(k)));
    match name {
        "Au" => measured([0.143119, 0.374957, 1.44248], [3.98316, 2.38572, 1.60322]),
        "Ag" => measured([0.155265, 0.116723, 0.138342], [4.82835, 3.12225, 2.14696]),
        "Al" => measured([1.65746, 0.880369, 0.521229], [9.22387, 6.26952, 4.837]),
        "Cu" => measured([0.200438, 0.924033, 1.10221], [3.91295, 2.45285, 2.14219]),
        "Cr" => measured([4.36968, 2.9167, 1.6547], [5.20643, 4.23136, 3.75495]),
        // Amorphous carbon, as Mitsuba 3's RGB variants convert its measured spectra.
        "a-C" => measured([2.94405, 2.22714, 1.96816], [0.887465, 0.799299, 0.81529]),
        "Fe" => Some(from_reflectance(Rgb::new(0.562, 0.565, 0.578))),
        "Ni" => Some(from_reflectance(Rgb::new(0.660, 0.609, 0.526))),
        "Ti" => Some(from_reflectance(Rgb::new(0.542, 0.497, 0.449))),
        "Pt" => Some(from_reflectance(Rgb::new(0.673, 0.637, 0.585))),
        _ => None,
    }
}

pub const METAL_NAMES: [&str; 10] = ["Au", "Ag", "Al", "Cu", "Cr", "a-C", "Fe", "Ni", "Ti", "Pt"];

/// η and k with normal-incidence reflectance `r` (Gulbrandsen, "Artist Friendly Metallic
/// Fresnel", JCGT 3(4), 2014, with the edge tint g = r).
fn from_reflectance(r: Rgb) -> (Rgb, Rgb) {
    let channel = |r: f32| {
        let r = r.clamp(0.0, 0.99);
        let g = r;
        let sqrt_r = r.sqrt();
        let n = g * (1.0 - r) / (1.0 + r) + (1.0 - g) * (1.0 + sqrt_r) / (1.0 - sqrt_r);
        let k2 = (r * (n + 1.0).powi(2) - (n - 1.0).powi(2)) / (1.0 - r);
        (n, k2.max(0.0).sqrt())
    };
    let (a, b, c) = (channel(r.x), channel(r.y), channel(r.z));
    (Rgb::new(a.0, b.0, c.0), Rgb::new(a.1, b.1, c.1))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::materials::fresnel_dielectric;

    /// The reflectance by the Fresnel equations in complex arithmetic (the second algorithm the
    /// closed form is checked against): r_s and r_p from cos θ_t = √(1 − sin²θ_i / (η + ik)²).
    fn fresnel_complex(cos_incident: f32, eta: f32, k: f32) -> f32 {
        #[derive(Clone, Copy)]
        struct Complex(f64, f64);
        let add = |a: Complex, b: Complex| Complex(a.0 + b.0, a.1 + b.1);
        let sub = |a: Complex, b: Complex| Complex(a.0 - b.0, a.1 - b.1);
        let mul = |a: Complex, b: Complex| Complex(a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
        let norm = |a: Complex| a.0 * a.0 + a.1 * a.1;
        let div = |a: Complex, b: Complex| {
            let d = norm(b);
            Complex((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
        };
        let sqrt = |a: Complex| {
            let r = norm(a).sqrt();
            let (re, im) = ((0.5 * (r + a.0)).max(0.0).sqrt(), (0.5 * (r - a.0)).max(0.0).sqrt());
            Complex(re, if a.1 < 0.0 { -im } else { im })
        };
        let cos_i = (cos_incident as f64).clamp(0.0, 1.0);
        let eta = Complex(eta as f64, k as f64);
        let sin2_t = div(Complex(1.0 - cos_i * cos_i, 0.0), mul(eta, eta));
        let cos_t = sqrt(sub(Complex(1.0, 0.0), sin2_t));
        let ci = Complex(cos_i, 0.0);
        let r_parallel = div(sub(mul(eta, ci), cos_t), add(mul(eta, ci), cos_t));
        let r_perpendicular = div(sub(ci, mul(eta, cos_t)), add(ci, mul(eta, cos_t)));
        (0.5 * (norm(r_parallel) + norm(r_perpendicular))).clamp(0.0, 1.0) as f32
    }

    /// One channel through the lanes' closed form.
    fn fresnel_closed_form(cos: f32, eta: f32, k: f32) -> f32 {
        fresnel_conductor_lanes(cos, eta, k)
    }

    /// Two algorithms, one answer: the closed form in f32 (one lane, four, eight) against the
    /// complex Fresnel equations in f64, over metals, dielectrics and every angle (the worst,
    /// 4e-6, near the critical angle of η < 1 without absorption, where η² − sin²θ cancels).
    #[test]
    fn closed_form_equals_the_complex_equations() {
        let mut worst = 0f32;
        for eta in [0.05f32, 0.143, 0.2, 0.5, 1.0, 1.5, 2.9, 4.4] {
            for k in [0.0f32, 0.01, 0.8, 2.4, 3.9, 9.2] {
                for step in 0..=200 {
                    let cos = step as f32 / 200.0;
                    let (ours, theirs) = (fresnel_closed_form(cos, eta, k), fresnel_complex(cos, eta, k));
                    if theirs.is_nan() {
                        continue; // 0/0 at grazing through a matched index (checked below)
                    }
                    worst = worst.max((ours - theirs).abs());
                    assert!((ours - theirs).abs() < 1e-5, "η {eta}, k {k}, cos {cos}: {ours} vs {theirs}");
                    let four = fresnel_conductor_lanes(f32x4::splat(cos), f32x4::splat(eta), f32x4::splat(k));
                    let eight = fresnel_conductor_lanes(
                        wide::f32x8::splat(cos),
                        wide::f32x8::splat(eta),
                        wide::f32x8::splat(k),
                    );
                    assert!(four.to_array().iter().chain(eight.as_array_ref()).all(|f| f.to_bits() == ours.to_bits()));
                }
            }
        }
        assert!(worst > 0.0, "the two algorithms are not the same arithmetic");
        // Light at grazing is all reflected, and a matched index reflects nothing head on.
        assert_eq!(fresnel_closed_form(0.0, 1.0, 0.0), 1.0);
        assert_eq!(fresnel_closed_form(1.0, 1.0, 0.0), 0.0);
    }

    #[test]
    fn normal_incidence_by_hand_and_grazing_is_total() {
        let f = fresnel_closed_form(1.0, 0.2, 3.9);
        let expected = ((0.2f32 - 1.0).powi(2) + 3.9 * 3.9) / ((0.2f32 + 1.0).powi(2) + 3.9 * 3.9);
        assert!((f - expected).abs() < 1e-5, "{f} vs {expected}");
        assert!(fresnel_closed_form(1e-4, 0.2, 3.9) > 0.999);
    }

    #[test]
    fn without_absorption_it_is_the_dielectric_fresnel() {
        for cos in [1.0f32, 0.8, 0.5, 0.2, 0.05] {
            let conductor = fresnel_closed_form(cos, 1.5, 0.0);
            let dielectric = fresnel_dielectric(cos, 1.0 / 1.5);
            assert!((conductor - dielectric).abs() < 1e-5, "cos {cos}: {conductor} vs {dielectric}");
        }
    }

    #[test]
    fn the_mirror_is_weighted_by_fresnel_and_black_from_behind() {
        use crate::materials::testing::{at, frame_toward};
        let (eta, k) = named_metal("Au").unwrap();
        let gold = Conductor { eta, k, specular: Texture::Constant(Rgb::ONE) };
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let bsdf = at(&gold.bsdf(&Default::default(), frame_toward(wo, Vec3::Z)));
        let s = bsdf.sample(wo, 0.5, Vec2::splat(0.5)).unwrap();
        assert!(s.delta && (s.wi - Vec3::new(-0.6, 0.0, 0.8)).length() < 1e-6);
        assert!((s.weight - fresnel_conductor(0.8, eta, k)).abs().max_element() < 1e-6);
        assert!(!bsdf.has_diffuse() && bsdf.eval(wo, s.wi) == Rgb::ZERO);
        let behind = at(&gold.bsdf(&Default::default(), frame_toward(-wo, Vec3::Z)));
        assert!(behind.sample(-wo, 0.5, Vec2::splat(0.5)).is_none());
    }

    #[test]
    fn named_metals_reflect_as_expected() {
        // Gold: red-yellow at normal incidence.
        let (eta, k) = named_metal("Au").unwrap();
        let f = fresnel_conductor(1.0, eta, k);
        assert!(f.x > 0.9 && f.y > 0.75 && f.z < 0.45, "{f}");
        // Gulbrandsen's fit reproduces the normal-incidence reflectance it is given.
        let (eta, k) = named_metal("Ni").unwrap();
        let f = fresnel_conductor(1.0, eta, k);
        assert!((f - Rgb::new(0.660, 0.609, 0.526)).abs().max_element() < 1e-3, "{f}");
        for name in METAL_NAMES {
            assert!(named_metal(name).is_some());
        }
        assert!(named_metal("unobtainium").is_none());
    }

    /// Whitted's mirror carries the conductor's Fresnel reflectance at the angle (gold's
    /// colour head-on, white toward grazing), as the BSDF's delta lobe; nothing from behind.
    #[test]
    fn whitted_reads_the_bsdf() {
        let (eta, k) = named_metal("Au").unwrap();
        let gold = crate::materials::Material::Conductor(Conductor {
            eta,
            k,
            specular: Texture::Constant(Rgb::new(1.0, 0.9, 0.8)),
        });
        for degrees in [0.0, 45.0, 80.0] {
            crate::materials::testing::check_whitted(&gold, true, degrees, 3);
        }
        let q = TextureQuery::default();
        assert_eq!(gold.whitted_at(&q, false, 0.5), PhongPoint::BLACK);
    }
}
