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

use super::bsdf::{BsdfSample, Frame, Leaf, Lobes};
use super::PhongPoint;
use crate::geometry::reflect;
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

impl Lobes for ConductorBsdf {
    fn sample(&self, wo: Vec3, _u_lobe: f32, _u: Vec2) -> Option<BsdfSample> {
        let cos = wo.dot(self.frame.normal);
        if !self.frame.outside || cos <= 0.0 {
            return None;
        }
        let weight = self.specular * fresnel_conductor(cos, self.eta, self.k);
        let wi = reflect(-wo, self.frame.normal);
        Some(BsdfSample { wi, weight, pdf: 1.0, delta: true, eta_squared: 1.0 })
    }

    fn frame(&self) -> &Frame {
        &self.frame
    }
    fn frame_mut(&mut self) -> &mut Frame {
        &mut self.frame
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Complex {
    re: f32,
    im: f32,
}

impl Complex {
    fn new(re: f32, im: f32) -> Self {
        Self { re, im }
    }
    fn add(self, o: Self) -> Self {
        Self::new(self.re + o.re, self.im + o.im)
    }
    fn sub(self, o: Self) -> Self {
        Self::new(self.re - o.re, self.im - o.im)
    }
    fn mul(self, o: Self) -> Self {
        Self::new(self.re * o.re - self.im * o.im, self.re * o.im + self.im * o.re)
    }
    fn div(self, o: Self) -> Self {
        let d = o.re * o.re + o.im * o.im;
        Self::new((self.re * o.re + self.im * o.im) / d, (self.im * o.re - self.re * o.im) / d)
    }
    fn norm(self) -> f32 {
        self.re * self.re + self.im * self.im
    }
    /// The principal square root.
    fn sqrt(self) -> Self {
        let r = self.norm().sqrt();
        if r == 0.0 {
            return Self::new(0.0, 0.0);
        }
        let re = (0.5 * (r + self.re)).max(0.0).sqrt();
        let im = (0.5 * (r - self.re)).max(0.0).sqrt();
        Self::new(re, if self.im < 0.0 { -im } else { im })
    }
}

/// The reflectance of one channel, for the cosine of the incident angle and η + ik.
fn fresnel_complex(cos_incident: f32, eta: f32, k: f32) -> f32 {
    let cos_i = cos_incident.clamp(0.0, 1.0);
    let eta = Complex::new(eta, k);
    let sin2_i = Complex::new(1.0 - cos_i * cos_i, 0.0);
    let sin2_t = sin2_i.div(eta.mul(eta));
    let cos_t = Complex::new(1.0, 0.0).sub(sin2_t).sqrt();
    let ci = Complex::new(cos_i, 0.0);
    let r_parallel = eta.mul(ci).sub(cos_t).div(eta.mul(ci).add(cos_t));
    let r_perpendicular = ci.sub(eta.mul(cos_t)).div(ci.add(eta.mul(cos_t)));
    (0.5 * (r_parallel.norm() + r_perpendicular.norm())).clamp(0.0, 1.0)
}

/// The Fresnel reflectance of a conductor per channel.
pub fn fresnel_conductor(cos_incident: f32, eta: Rgb, k: Rgb) -> Rgb {
    Rgb::new(
        fresnel_complex(cos_incident, eta.x, k.x),
        fresnel_complex(cos_incident, eta.y, k.y),
        fresnel_complex(cos_incident, eta.z, k.z),
    )
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

    #[test]
    fn normal_incidence_by_hand_and_grazing_is_total() {
        let f = fresnel_complex(1.0, 0.2, 3.9);
        let expected = ((0.2f32 - 1.0).powi(2) + 3.9 * 3.9) / ((0.2f32 + 1.0).powi(2) + 3.9 * 3.9);
        assert!((f - expected).abs() < 1e-5, "{f} vs {expected}");
        assert!(fresnel_complex(1e-4, 0.2, 3.9) > 0.999);
    }

    #[test]
    fn without_absorption_it_is_the_dielectric_fresnel() {
        for cos in [1.0f32, 0.8, 0.5, 0.2, 0.05] {
            let conductor = fresnel_complex(cos, 1.5, 0.0);
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
