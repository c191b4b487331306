//! The course's mixed material read by the Monte Carlo integrators: the lobes of an evaluated
//! `Phong` (`PhongPoint`) chosen by roulette. The same evaluated material Whitted uses.
//!
//! Lobes: Lambert diffuse k_d; Phong's highlight k_s as the normalised modified Phong lobe
//! (Lafortune & Willems 1994: f = k_s (n + 2)/(2π) cos^n α, α between the light and the
//! viewer's mirror direction, sampled exactly by cos^n α about that direction), so that the
//! highlight Whitted draws is there under every integrator and passes on at most k_s;
//! reflection k_r (a perfect mirror, or GGX microfacets when the material has a roughness, see
//! `microfacet.rs`) and refraction k_t (smooth, or GGX microfacet refraction (Walter et al.
//! 2007) when the material has a roughness: rough glass), with Fresnel splitting k_t as for
//! Whitted; the Fresnel factor is taken at the macro-surface angle. At each hit one lobe is
//! chosen by roulette with probability proportional to its weight: the course's mixed material
//! (say 30 % mirror, 20 % refraction, 50 % diffuse), and exact importance sampling for a
//! single-lobe material. The material is two-sided: the shading frame is turned to the side
//! `wo` is on. The scene parameters are Phong's (`phong.rs`).

use glam::{Vec2, Vec3};

use super::bsdf::{luminance, BsdfSample, Frame, Lobes};
use super::{Microfacet, PhongPoint};
use crate::geometry::{reflect, refract};
use crate::sampling::warp::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};
use crate::Rgb;

#[derive(Clone, Copy, Debug)]
pub struct MixedBsdf {
    frame: Frame,
    diffuse: Rgb,
    /// The Phong lobe's k_s and exponent n, about the viewer's mirror direction.
    specular: Rgb,
    shininess: f32,
    reflection: Rgb,
    transmission: Rgb,
    /// n_incident / n_transmitted for this side.
    eta: f32,
    /// GGX for a rough reflection lobe; `None`: a perfect mirror.
    glossy: Option<Microfacet>,
    /// Refraction through GGX microfacets (rough glass) rather than a perfect refraction.
    rough_transmission: bool,
    /// Lobe selection probabilities: diffuse, Phong, reflection, then transmission (sum 1, or
    /// all 0).
    p_diffuse: f32,
    p_specular: f32,
    p_reflection: f32,
    refracted: Option<Vec3>,
}

impl MixedBsdf {
    /// The lobes of `material` seen from `wo`, in `frame`.
    pub fn new(material: &PhongPoint, wo: Vec3, frame: Frame) -> Self {
        let (normal, outside) = (frame.normal, frame.outside);
        let eta = if outside { 1.0 / material.ior } else { material.ior };
        let diffuse = material.diffuse;
        let specular = material.specular.max(Rgb::ZERO);
        let alone = material.reflection == Rgb::ZERO && material.transmission == Rgb::ZERO && specular == Rgb::ZERO;
        let (reflection, transmission, refracted, p_diffuse, p_specular, p_reflection) = if alone {
            // Diffuse alone, the common case: every Fresnel split of zero weights is zero,
            // and p_d = l_d / l_d = 1 exactly, so skip the arithmetic that would say so.
            let p_diffuse = if luminance(diffuse) > 0.0 { 1.0 } else { 0.0 };
            (Rgb::ZERO, Rgb::ZERO, None, p_diffuse, 0.0, 0.0)
        } else {
            let (mut reflection, mut transmission) = material.ray_weights(wo.dot(normal).max(0.0), eta);
            let refracted = if transmission != Rgb::ZERO { refract(-wo, normal, eta) } else { None };
            if refracted.is_none() {
                reflection += transmission; // total internal reflection
                transmission = Rgb::ZERO;
            }
            let (ld, lr, lt) = (luminance(diffuse), luminance(reflection), luminance(transmission));
            let ls = if specular == Rgb::ZERO { 0.0 } else { luminance(specular) };
            let total = ld + ls + lr + lt;
            let (p_diffuse, p_specular, p_reflection) =
                if total > 0.0 { (ld / total, ls / total, lr / total) } else { (0.0, 0.0, 0.0) };
            (reflection, transmission, refracted, p_diffuse, p_specular, p_reflection)
        };
        let glossy = (material.roughness > 0.0)
            .then(|| Microfacet::isotropic((material.roughness * material.roughness).max(1e-4)));
        let rough_transmission = glossy.is_some() && transmission != Rgb::ZERO;
        Self {
            rough_transmission,
            frame,
            glossy,
            diffuse,
            specular,
            shininess: material.shininess.max(0.0),
            reflection,
            transmission,
            eta,
            p_diffuse,
            p_specular,
            p_reflection,
            refracted,
        }
    }

    fn p_transmission(&self) -> f32 {
        (1.0 - self.p_diffuse - self.p_specular - self.p_reflection).max(0.0)
    }

    /// The viewer's mirror direction, the Phong lobe's axis.
    fn mirror(&self, wo: Vec3) -> Vec3 {
        reflect(-wo, self.frame.normal)
    }

    /// cos^n α of `wi` about the mirror direction of `wo` (0 past 90°).
    fn phong_power(&self, wo: Vec3, wi: Vec3) -> f32 {
        let cos = wi.dot(self.mirror(wo));
        if cos > 0.0 {
            cos.powf(self.shininess)
        } else {
            0.0
        }
    }

    fn local_coordinates(&self, w: Vec3) -> Vec3 {
        Vec3::new(w.dot(self.frame.tangent), w.dot(self.frame.bitangent), w.dot(self.frame.normal))
    }

    /// A sample of a non-delta lobe, weighted by the whole non-delta BSDF over its whole pdf
    /// (so diffuse and glossy samples are one consistent strategy for MIS).
    fn non_delta_sample(&self, wo: Vec3, wi: Vec3) -> Option<BsdfSample> {
        let pdf = self.pdf(wo, wi);
        if pdf.is_nan() || pdf <= 0.0 || !pdf.is_finite() {
            return None;
        }
        let through = wi.dot(self.frame.geometric) < 0.0;
        let eta_squared = if through { 1.0 / (self.eta * self.eta) } else { 1.0 };
        Some(BsdfSample { wi, weight: self.eval(wo, wi) / pdf, pdf, delta: false, eta_squared })
    }

    /// Whether the non-delta part is Lambert alone (no rough reflection, no Phong lobe).
    fn is_lambertian(&self) -> bool {
        (self.glossy.is_none() || self.p_reflection == 0.0) && !self.rough_transmission && self.p_specular == 0.0
    }
}

impl Lobes for MixedBsdf {
    /// f·|cos θ_i| for the non-delta part (Lambert, rough reflection), on the viewer's side.
    fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        let cos = wi.dot(self.frame.normal);
        if cos < 0.0 && wi.dot(self.frame.geometric) < 0.0 && self.rough_transmission {
            if let Some(microfacet) = &self.glossy {
                let local = (self.local_coordinates(wo), self.local_coordinates(wi));
                return self.transmission * microfacet.transmission_eval(local.0, local.1, self.eta);
            }
        }
        if cos <= 0.0 || wi.dot(self.frame.geometric) <= 0.0 {
            return Rgb::ZERO;
        }
        let mut f = self.diffuse * (cos * std::f32::consts::FRAC_1_PI);
        if self.p_specular > 0.0 {
            let normalisation = (self.shininess + 2.0) * 0.5 * std::f32::consts::FRAC_1_PI;
            f += self.specular * (normalisation * self.phong_power(wo, wi) * cos);
        }
        if let Some(microfacet) = &self.glossy {
            f += self.reflection * microfacet.reflection_eval(self.local_coordinates(wo), self.local_coordinates(wi));
        }
        f
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wi.dot(self.frame.geometric) <= 0.0 {
            return match (&self.glossy, self.rough_transmission) {
                (Some(microfacet), true) if wi.dot(self.frame.normal) < 0.0 => {
                    let local = (self.local_coordinates(wo), self.local_coordinates(wi));
                    self.p_transmission() * microfacet.transmission_pdf(local.0, local.1, self.eta)
                }
                _ => 0.0,
            };
        }
        let local = self.local_coordinates(wi);
        let mut pdf = self.p_diffuse * cosine_hemisphere_pdf(local);
        if self.p_specular > 0.0 {
            pdf +=
                self.p_specular * (self.shininess + 1.0) * 0.5 * std::f32::consts::FRAC_1_PI * self.phong_power(wo, wi);
        }
        if let Some(microfacet) = &self.glossy {
            pdf += self.p_reflection * microfacet.reflection_pdf(self.local_coordinates(wo), local);
        }
        pdf
    }

    /// The probability that `sample` picks a non-delta lobe (diffuse, Phong or rough
    /// reflection).
    fn non_delta_probability(&self) -> f32 {
        let glossy = if self.glossy.is_some() { self.p_reflection } else { 0.0 };
        let rough = if self.rough_transmission { self.p_transmission() } else { 0.0 };
        self.p_diffuse + self.p_specular + glossy + rough
    }

    /// Chooses a lobe with `u_lobe`, then a direction with `u` (diffuse only).
    #[inline(always)]
    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if u_lobe < self.p_diffuse {
            let local = square_to_cosine_hemisphere(u);
            let wi = local.x * self.frame.tangent + local.y * self.frame.bitangent + local.z * self.frame.normal;
            if self.glossy.is_some() || self.p_specular > 0.0 {
                return self.non_delta_sample(wo, wi);
            }
            // Diffuse the only non-delta lobe: f·cos/pdf = (k_d/π · cos) / (p_d · cos/π) = k_d / p_d,
            // without evaluating the whole BSDF (the hot path of every diffuse bounce).
            if local.z <= 0.0 || wi.dot(self.frame.geometric) <= 0.0 {
                return None;
            }
            let pdf = self.p_diffuse * cosine_hemisphere_pdf(local);
            return Some(BsdfSample { wi, weight: self.diffuse / self.p_diffuse, pdf, delta: false, eta_squared: 1.0 });
        }
        if u_lobe < self.p_diffuse + self.p_specular {
            // cos α = u₁^(1/(n+1)) about the mirror direction: density (n + 1)/(2π) cos^n α.
            let cos = u.x.powf(1.0 / (self.shininess + 1.0));
            let sin = (1.0 - cos * cos).max(0.0).sqrt();
            let phi = 2.0 * std::f32::consts::PI * u.y;
            let mirror = self.mirror(wo);
            let (tangent, bitangent) = crate::geometry::orthonormal_basis(mirror);
            let wi = (sin * phi.cos()) * tangent + (sin * phi.sin()) * bitangent + cos * mirror;
            return self.non_delta_sample(wo, wi);
        }
        if u_lobe < self.p_diffuse + self.p_specular + self.p_reflection {
            if let Some(microfacet) = &self.glossy {
                let h = microfacet.sample_normal(self.local_coordinates(wo), u);
                let h = h.x * self.frame.tangent + h.y * self.frame.bitangent + h.z * self.frame.normal;
                return self.non_delta_sample(wo, reflect(-wo, h));
            }
            let wi = reflect(-wo, self.frame.normal);
            return Some(BsdfSample {
                wi,
                weight: self.reflection / self.p_reflection,
                pdf: self.p_reflection,
                delta: true,
                eta_squared: 1.0,
            });
        }
        let p_transmission = 1.0 - self.p_diffuse - self.p_specular - self.p_reflection;
        if p_transmission <= 0.0 {
            return None;
        }
        if let (Some(microfacet), true) = (&self.glossy, self.rough_transmission) {
            let h = microfacet.sample_normal(self.local_coordinates(wo), u);
            let h = h.x * self.frame.tangent + h.y * self.frame.bitangent + h.z * self.frame.normal;
            return self.non_delta_sample(wo, refract(-wo, h, self.eta)?);
        }
        let wi = self.refracted?;
        Some(BsdfSample {
            wi,
            weight: self.transmission / p_transmission,
            pdf: p_transmission,
            delta: true,
            eta_squared: 1.0 / (self.eta * self.eta),
        })
    }

    fn lambertian(&self) -> Option<Rgb> {
        self.is_lambertian().then_some(self.diffuse)
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
    use crate::materials::{Fresnel, Phong};
    use crate::sampling::chi2::chi2_test;
    use crate::textures::TextureQuery;

    fn mixed(p: &PhongPoint, wo: Vec3, shading: Vec3, geometric: Vec3) -> MixedBsdf {
        MixedBsdf::new(p, wo, Frame::new(wo, shading, geometric))
    }

    fn point(diffuse: f32, reflection: f32, transmission: f32) -> PhongPoint {
        let mut p = Phong::default().evaluate(&TextureQuery::default());
        p.diffuse = Rgb::splat(diffuse);
        p.reflection = Rgb::splat(reflection);
        p.transmission = Rgb::splat(transmission);
        p
    }

    #[test]
    fn lambert_sampling_matches_its_pdf_from_both_sides() {
        let n = Vec3::new(0.3, 0.2, 0.9).normalize();
        for wo in [Vec3::new(0.1, 0.4, 1.0).normalize(), Vec3::new(0.2, -0.3, -1.0).normalize()] {
            let bsdf = mixed(&point(0.8, 0.0, 0.0), wo, n, n);
            // Rotate sampled directions into the frame where the chi2 cells sit: world space.
            let r =
                chi2_test(|u| bsdf.sample(wo, 0.0, u).map(|s| s.wi), |w| bsdf.pdf(wo, w) as f64, 500_000, 21, 41, 7);
            assert!(r.p_value > 0.01 / 8.0, "p = {} (wo {wo})", r.p_value);
        }
    }

    #[test]
    fn weights_equal_eval_over_pdf() {
        let n = Vec3::Z;
        let wo = Vec3::new(0.3, 0.1, 0.9).normalize();
        let bsdf = mixed(&point(0.5, 0.3, 0.0), wo, n, n);
        let mut rng = crate::sampling::Rng::new(1, 2);
        for _ in 0..1000 {
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            if let Some(s) = bsdf.sample(wo, rng.next_f32() * bsdf.p_diffuse, u) {
                let expected = bsdf.eval(wo, s.wi) / s.pdf;
                assert!((s.weight - expected).abs().max_element() < 1e-4, "{} vs {}", s.weight, expected);
            }
        }
    }

    /// The course's mixed material: lobes chosen in proportion to their weights; each sample's
    /// weight divided back by its probability keeps the estimate unbiased.
    #[test]
    fn mixed_material_roulette() {
        let n = Vec3::Z;
        let wo = Vec3::new(0.0, 0.6, 0.8);
        let bsdf = mixed(&point(0.5, 0.3, 0.2), wo, n, n);
        assert!((bsdf.p_diffuse - 0.5).abs() < 1e-6 && (bsdf.p_reflection - 0.3).abs() < 1e-6);
        let mirror = bsdf.sample(wo, 0.6, Vec2::splat(0.5)).unwrap();
        assert!(mirror.delta && (mirror.wi - Vec3::new(0.0, -0.6, 0.8)).length() < 1e-6);
        assert!((mirror.weight - Rgb::ONE).abs().max_element() < 1e-6); // 0.3 / 0.3
        let glass = bsdf.sample(wo, 0.9, Vec2::splat(0.5)).unwrap();
        assert!(glass.delta && glass.wi.z < 0.0);
        let diffuse = bsdf.sample(wo, 0.1, Vec2::new(0.3, 0.7)).unwrap();
        assert!(!diffuse.delta && (diffuse.weight - Rgb::ONE).abs().max_element() < 1e-6);
        // 0.5 / 0.5
    }

    /// Rough reflection mixed with diffuse: sampling matches the mixture pdf, and every
    /// sample's weight is eval / pdf.
    #[test]
    fn rough_reflection_mixture_matches_its_pdf() {
        let mut p = point(0.3, 0.5, 0.0);
        p.roughness = 0.5;
        let n = Vec3::new(0.1, -0.2, 1.0).normalize();
        let wo = Vec3::new(0.5, 0.3, 0.8).normalize();
        let bsdf = mixed(&p, wo, n, n);
        assert!(bsdf.non_delta_probability() > 0.0);
        let mut rng = crate::sampling::Rng::new(9, 9);
        sampling_matches_pdf(&bsdf, wo, &mut rng, 13, 1000, 1e-4);
    }

    /// Sampling `bsdf` from `wo` matches its pdf (chi-square, seed `chi2_seed`), and each of
    /// `checks` further samples weighs eval / pdf within `tolerance`; returns those samples.
    fn sampling_matches_pdf(
        bsdf: &MixedBsdf,
        wo: Vec3,
        rng: &mut crate::sampling::Rng,
        chi2_seed: u64,
        checks: usize,
        tolerance: f32,
    ) -> Vec<BsdfSample> {
        let r = chi2_test(
            |u| bsdf.sample(wo, rng.next_f32(), u).map(|s| s.wi),
            |w| bsdf.pdf(wo, w) as f64,
            500_000,
            21,
            41,
            chi2_seed,
        );
        assert!(r.p_value > 0.01 / 8.0, "wo {wo}: p = {}", r.p_value);
        let mut samples = Vec::new();
        for _ in 0..checks {
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            if let Some(s) = bsdf.sample(wo, rng.next_f32(), u) {
                let expected = bsdf.eval(wo, s.wi) / bsdf.pdf(wo, s.wi);
                assert!(!s.delta && (s.weight - expected).abs().max_element() < tolerance, "{s:?} vs {expected}");
                samples.push(s);
            }
        }
        samples
    }

    /// Phong's lobe beside Lambert's, wide and narrow: sampling matches the mixture pdf and
    /// every sample weighs eval / pdf; lit and seen along the normal, f·cos = k_s (n + 2)/(2π).
    #[test]
    fn the_phong_lobe_is_sampled_by_its_pdf_and_normalised() {
        let n = Vec3::new(0.1, -0.2, 1.0).normalize();
        let wo = Vec3::new(0.5, 0.3, 0.8).normalize();
        let mut rng = crate::sampling::Rng::new(4, 91);
        for shininess in [2.0, 40.0] {
            let mut p = point(0.3, 0.0, 0.0);
            (p.specular, p.shininess) = (Rgb::splat(0.5), shininess);
            let bsdf = mixed(&p, wo, n, n);
            assert!(bsdf.lambertian().is_none() && (bsdf.non_delta_probability() - 1.0).abs() < 1e-6);
            sampling_matches_pdf(&bsdf, wo, &mut rng, 17, 1000, 1e-3);
        }
        let mut p = point(0.0, 0.0, 0.0);
        (p.specular, p.shininess) = (Rgb::splat(0.8), 10.0);
        let head_on = mixed(&p, Vec3::Z, Vec3::Z, Vec3::Z).eval(Vec3::Z, Vec3::Z);
        let expected = 0.8 * 12.0 / (2.0 * std::f32::consts::PI);
        assert!((head_on - Rgb::splat(expected)).abs().max_element() < 1e-5, "{head_on} vs {expected}");
    }

    /// A white Phong lobe passes on at most what it receives (the modified Phong lobe's point),
    /// and sampling and quadrature agree on how much: the furnace, from near the normal and
    /// near grazing (where the lobe loses what falls below the horizon), for a wide and a
    /// narrow lobe; narrow and seen near the normal, it keeps nearly all, (n + 2)/(n + 1)·cos θ.
    #[test]
    fn a_white_phong_lobe_keeps_at_most_what_it_receives() {
        use crate::materials::bsdf::Leaf;
        use crate::materials::testing::{at, furnace};
        for shininess in [1.0, 10.0, 100.0] {
            let mut p = point(0.0, 0.0, 0.0);
            (p.specular, p.shininess) = (Rgb::ONE, shininess);
            for wo in [Vec3::new(0.2, 0.0, 0.98).normalize(), Vec3::new(0.9, 0.1, 0.2).normalize()] {
                let leaf = Leaf::Mixed(mixed(&p, wo, Vec3::Z, Vec3::Z));
                let a = furnace(&at(&leaf), wo, 11);
                if shininess == 100.0 && wo.z > 0.9 {
                    assert!(a.mean > 0.95, "n = {shininess} from {wo}: {a:?}");
                }
            }
        }
    }

    #[test]
    fn glass_with_fresnel_reflects_by_the_fresnel_factor() {
        let mut p = point(0.0, 0.0, 1.0);
        p.fresnel = Fresnel::Exact;
        let bsdf = mixed(&p, Vec3::Z, Vec3::Z, Vec3::Z);
        assert!((bsdf.p_reflection - 0.04).abs() < 1e-4, "{}", bsdf.p_reflection);
        // Inside glass past the critical angle: everything reflects.
        let wo = Vec3::new(0.8, 0.0, -0.6);
        let inside = mixed(&p, wo, Vec3::Z, Vec3::Z);
        assert_eq!(inside.p_reflection, 1.0);
    }

    /// Rough glass (GGX reflection and refraction, exact Fresnel), from outside and from
    /// inside: sampling matches the pdf over the whole sphere, every sample's weight is
    /// eval / pdf, and the refracted energy tends to the smooth glass's as the roughness
    /// vanishes.
    #[test]
    fn rough_glass_matches_its_pdf_from_both_sides() {
        let mut p = point(0.0, 0.0, 1.0);
        p.fresnel = Fresnel::Exact;
        p.roughness = 0.4;
        let n = Vec3::new(0.1, 0.2, 1.0).normalize();
        for wo in [Vec3::new(0.4, -0.3, 0.8).normalize(), Vec3::new(-0.3, 0.2, -0.9).normalize()] {
            let bsdf = mixed(&p, wo, n, n);
            assert!(bsdf.non_delta_probability() > 0.0 && bsdf.lambertian().is_none());
            let mut rng = crate::sampling::Rng::new(4, 4);
            let samples = sampling_matches_pdf(&bsdf, wo, &mut rng, 17, 2000, 1e-3);
            let through = samples.iter().filter(|s| s.wi.dot(n) * wo.dot(n) < 0.0).count();
            assert!(through > 100, "some samples refract ({through})");
        }
        // Nearly smooth: the mean refraction weight is the smooth lobe's, k_t (1 − F).
        p.roughness = 0.02;
        let wo = Vec3::new(0.3, 0.0, 0.95).normalize();
        let rough = mixed(&p, wo, Vec3::Z, Vec3::Z);
        let mut rng = crate::sampling::Rng::new(6, 6);
        let (mut sum, n_samples) = (0.0f64, 100_000);
        for _ in 0..n_samples {
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            if let Some(s) = rough.sample(wo, 0.999, u) {
                sum += s.weight.x as f64 * rough.p_transmission() as f64;
            }
        }
        let expected = rough.transmission.x as f64;
        assert!((sum / n_samples as f64 / expected - 1.0).abs() < 0.02, "{} vs {expected}", sum / n_samples as f64);
    }
}
