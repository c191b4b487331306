//! Fresnel-weighted plastic, Mitsuba's `pplastic` (Baek et al. 2018, "Simultaneous Acquisition
//! of Polarimetric SVBRDF and Normals") as light without polarization sees it: a rough
//! specular reflection off the surface's microfacets, plus a Lambertian term for the light that
//! the surface lets in and out, weighed by the Fresnel transmittance each way. Unlike `plastic`
//! and `rough-plastic` it models no reflection inside the coat: it is not energy-conserving by
//! design, but never adds energy.
//!
//! Scene parameters: `diffuse_reflectance` (default 0.5), `specular_reflectance` (default 1),
//! `int_ior` / `ext_ior` (default 1.49, polypropylene, over air), `alpha` (default 0.1) or
//! `alpha_u` and `alpha_v`, `distribution` (`beckmann`, the default, or `ggx`).
//! ```toml
//! [materials.coated]
//! type = "fresnel-plastic"
//! diffuse_reflectance = [0.05, 0.03, 0.1]
//! alpha = 0.06
//! ```
//! f·cos θ_i = specular · F(wo·h) D(h) G1(wo) G1(wi) / (4 cos θ_o)
//!           + k_d (1 − F(cos θ_o)) (1 − F(cos θ_i)) cos θ_i / π,
//! one-sided (black from behind). The specular lobe is sampled by visible normals with
//! probability mean(specular) / (mean(diffuse) + mean(specular)) (the textures' means, as
//! Mitsuba's), the diffuse one by the cosine.

use glam::{Vec2, Vec3};

use super::bsdf::{BsdfSample, Frame, Leaf, Lobes};
use super::microfacet::{Distribution, GlossyOrDiffuse};
use super::{fresnel_dielectric, Microfacet, PhongPoint};
use crate::textures::{Texture, TextureQuery};
use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct FresnelPlastic {
    pub diffuse: Texture,
    pub specular: Texture,
    /// n_inside / n_outside.
    pub eta: f32,
    pub alpha_u: f32,
    pub alpha_v: f32,
    pub distribution: Distribution,
    /// The probability of sampling the specular lobe.
    specular_probability: f32,
}

impl FresnelPlastic {
    pub fn new(
        diffuse: Texture,
        specular: Texture,
        eta: f32,
        (alpha_u, alpha_v): (f32, f32),
        distribution: Distribution,
    ) -> Self {
        let mean = |t: &Texture| {
            let m = t.mean_value();
            (m.x + m.y + m.z) / 3.0
        };
        let (d, s) = (mean(&diffuse), mean(&specular));
        let specular_probability = if d + s > 0.0 { s / (d + s) } else { 0.5 };
        Self { diffuse, specular, eta, alpha_u, alpha_v, distribution, specular_probability }
    }

    pub(super) fn bsdf(&self, query: &TextureQuery, frame: Frame) -> Leaf<'static> {
        let anisotropic = self.alpha_u != self.alpha_v;
        Leaf::FresnelPlastic(FresnelPlasticBsdf {
            // α_u along ∂p/∂u, as the other anisotropic members.
            frame: if anisotropic { frame.along(query.dpdu) } else { frame },
            diffuse: self.diffuse.evaluate(query),
            specular: self.specular.evaluate(query),
            eta: self.eta,
            lobes: GlossyOrDiffuse {
                microfacet: Microfacet::separable(self.alpha_u, self.alpha_v).with(self.distribution),
                p_glossy: self.specular_probability,
            },
        })
    }

    /// Whitted's view: the specular lobe's smooth limit as a mirror of reflectance F, the
    /// diffuse term through the Fresnel transmittance (the coat's index weighs each light's).
    pub(super) fn whitted(&self, query: &TextureQuery, outside: bool, cos: f32) -> PhongPoint {
        if !outside {
            return PhongPoint::BLACK;
        }
        let f = fresnel_dielectric(cos, 1.0 / self.eta);
        let k_d = self.diffuse.evaluate(query) * (1.0 - f);
        PhongPoint {
            ambient: k_d,
            diffuse: k_d,
            reflection: self.specular.evaluate(query) * f,
            coat_ior: self.eta,
            ..PhongPoint::BLACK
        }
    }
}

#[derive(Clone, Copy, Debug)]
pub(super) struct FresnelPlasticBsdf {
    frame: Frame,
    diffuse: Rgb,
    specular: Rgb,
    eta: f32,
    lobes: GlossyOrDiffuse,
}

impl Lobes for FresnelPlasticBsdf {
    fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        if !self.frame.outside || !self.frame.reflects(wi) {
            return Rgb::ZERO;
        }
        let (o, i) = (self.frame.to_local(wo), self.frame.to_local(wi));
        let h = (o + i).normalize();
        let inverse = 1.0 / self.eta;
        let specular =
            self.specular * (fresnel_dielectric(o.dot(h), inverse) * self.lobes.microfacet.reflection_eval(o, i));
        let through = (1.0 - fresnel_dielectric(o.z, inverse)) * (1.0 - fresnel_dielectric(i.z, inverse));
        specular + self.diffuse * (through * i.z * std::f32::consts::FRAC_1_PI)
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if !self.frame.outside || !self.frame.reflects(wi) {
            return 0.0;
        }
        let (o, i) = (self.frame.to_local(wo), self.frame.to_local(wi));
        self.lobes.pdf(o, i)
    }

    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if !self.frame.outside {
            return None;
        }
        let wi = self.frame.to_world(self.lobes.sample(self.frame.to_local(wo), u_lobe, u));
        self.weighed(wo, wi, 1.0)
    }

    fn non_delta_probability(&self) -> f32 {
        self.frame.front_only()
    }

    fn frame(&self) -> &Frame {
        &self.frame
    }
    fn frame_mut(&mut self) -> &mut Frame {
        &mut self.frame
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::materials::testing::{at, check_sampling, frame_toward};

    fn plastic(diffuse: f32, specular: f32, alpha: f32, distribution: Distribution) -> FresnelPlastic {
        FresnelPlastic::new(Texture::from(diffuse), Texture::from(specular), 1.49, (alpha, alpha), distribution)
    }

    /// Sampling draws what `pdf` says and weighs by eval / pdf, for both distributions, both
    /// lobes alone and together, from several angles.
    #[test]
    fn sampling_matches_its_density() {
        let n = Vec3::Z;
        for distribution in [Distribution::Beckmann, Distribution::Ggx] {
            for (d, s) in [(0.5, 1.0), (0.0, 1.0), (0.8, 0.0)] {
                let m = plastic(d, s, 0.3, distribution);
                for (k, wo) in [Vec3::new(0.3, 0.1, 0.9), Vec3::new(0.8, -0.2, 0.3)].into_iter().enumerate() {
                    let wo = wo.normalize();
                    let leaf = m.bsdf(&TextureQuery::default(), frame_toward(wo, n));
                    check_sampling(&at(&leaf), wo, n, 11 + k as u64);
                }
            }
        }
    }

    /// By hand at normal incidence: F0 = ((1.49 − 1)/(1.49 + 1))² = 0.03873, so the diffuse
    /// term straight back is k_d (1 − F0)² / π; the specular term there is F0 D(n) G1² / 4
    /// with D(n) = 1 / (π α²) for both distributions.
    #[test]
    fn straight_back_by_hand() {
        let f0 = ((1.49f32 - 1.0) / (1.49 + 1.0)).powi(2);
        let (n, wo) = (Vec3::Z, Vec3::Z);
        let diffuse_only = plastic(0.6, 0.0, 0.1, Distribution::Beckmann);
        let leaf = diffuse_only.bsdf(&TextureQuery::default(), frame_toward(wo, n));
        let value = at(&leaf).eval(wo, wo).x;
        let expected = 0.6 * (1.0 - f0) * (1.0 - f0) * std::f32::consts::FRAC_1_PI;
        assert!((value - expected).abs() < 1e-5 * expected, "{value} against {expected}");
        let specular_only = plastic(0.0, 1.0, 0.2, Distribution::Ggx);
        let leaf = specular_only.bsdf(&TextureQuery::default(), frame_toward(wo, n));
        let microfacet = Microfacet::separable(0.2, 0.2).with(Distribution::Ggx);
        let expected = f0 * microfacet.g1(n) * microfacet.g1(n) / (4.0 * std::f32::consts::PI * 0.04);
        let value = at(&leaf).eval(wo, wo).x;
        assert!((value - expected).abs() < 1e-4 * expected, "{value} against {expected}");
    }

    /// Black from behind, and nothing transmitted.
    #[test]
    fn one_sided_and_opaque() {
        let m = plastic(0.5, 1.0, 0.2, Distribution::Beckmann);
        let n = Vec3::Z;
        let behind = Vec3::new(0.2, 0.0, -1.0).normalize();
        let leaf = m.bsdf(&TextureQuery::default(), frame_toward(behind, n));
        assert_eq!(at(&leaf).eval(behind, Vec3::new(0.1, 0.3, -0.9).normalize()), Rgb::ZERO);
        let front = Vec3::new(0.2, 0.0, 1.0).normalize();
        let leaf = m.bsdf(&TextureQuery::default(), frame_toward(front, n));
        assert_eq!(at(&leaf).eval(front, Vec3::new(0.1, 0.3, -0.9).normalize()), Rgb::ZERO);
    }
}
