//! Rough glass, Mitsuba's `roughdielectric`: GGX microfacets that reflect and refract (Walter
//! et al. 2007), the Fresnel reflectance taken at each microfacet, a visible normal sampled
//! and then reflection or refraction chosen with probability F(wo·h). Two-sided.
//!
//! Scene parameters: those of `dielectric`, and `alpha` (default 0.1), or `alpha_u`, `alpha_v`:
//! each a number or a texture's name (read as its luminance).
//! ```toml
//! [materials.frosted]
//! type = "rough-dielectric"
//! int_ior = 1.5
//! alpha = 0.2
//! ```
//! Reflection: F · D · G1(wo) G1(wi) / (4 cos θ_o); refraction: (1 − F) times `Microfacet`'s
//! transmission term (without the radiance's η², as `dielectric.rs` says).

use glam::{Vec2, Vec3};

use super::bsdf::{BsdfSample, Frame, LaneBsdfSample, LaneFrame, Leaf, Lobes};
use super::dielectric::side_eta;
use super::microfacet::{refraction_half_vector, MicrofacetLanes};
use super::phong::fresnel_dielectric_lanes;
use super::rough_conductor::width;
use super::{Dielectric, Distribution, Microfacet, PhongPoint};
use crate::lanes::{self, LaneVec3, Lanes};
use crate::textures::{Texture, TextureQuery};
use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct RoughDielectric {
    pub dielectric: Dielectric,
    /// The widths along ∂p/∂u and across it, constant or textured.
    pub alpha_u: Texture,
    pub alpha_v: Texture,
    /// GGX (glint's default) or Beckmann (Mitsuba's).
    pub distribution: Distribution,
}

impl RoughDielectric {
    pub(super) fn bsdf(&self, query: &TextureQuery, frame: Frame) -> Leaf<'static> {
        let d = &self.dielectric;
        let (alpha_u, alpha_v) = (width(&self.alpha_u, query), width(&self.alpha_v, query));
        Leaf::RoughDielectric(RoughDielectricBsdf {
            // Anisotropic widths lie along the surface's ∂p/∂u.
            frame: if alpha_u != alpha_v { frame.along(query.dpdu) } else { frame },
            eta: side_eta(d.eta, &frame),
            reflectance: d.specular_reflectance.evaluate(query),
            transmittance: d.specular_transmittance.evaluate(query),
            microfacet: Microfacet::separable(alpha_u, alpha_v).with(self.distribution),
        })
    }

    /// Its widths along ∂p/∂u and across it, reflectance and transmittance at a point, as
    /// `bsdf` reads them.
    pub(crate) fn widths_and_colours(&self, query: &TextureQuery) -> (f32, f32, Rgb, Rgb) {
        let d = &self.dielectric;
        let (reflectance, transmittance) =
            (d.specular_reflectance.evaluate(query), d.specular_transmittance.evaluate(query));
        (width(&self.alpha_u, query), width(&self.alpha_v, query), reflectance, transmittance)
    }

    /// Whitted's view: the lobes' smooth limit, smooth glass of the same index (Whitted traces
    /// no glossy rays): each microfacet lobe's weight goes to the mirror or the refraction.
    pub(super) fn whitted(&self, query: &TextureQuery, outside: bool, cos: f32) -> PhongPoint {
        self.dielectric.whitted(query, outside, cos)
    }
}

/// Rough glass at a hit, in lanes: the one body of its `eval`, `pdf` and `sample`, which the
/// scalar BSDF runs at one lane and the wavefront at eight.
#[derive(Clone, Debug)]
pub(crate) struct RoughDielectricLanes<L: Lanes> {
    pub frame: LaneFrame<L>,
    /// n(wo's side) / n(the other side).
    pub eta: L,
    pub reflectance: LaneVec3<L>,
    pub transmittance: LaneVec3<L>,
    pub microfacet: MicrofacetLanes<L>,
}

impl<L: Lanes> RoughDielectricLanes<L> {
    /// The microfacets' reflection where `wi` reflects on the viewer's side of both normals,
    /// their refraction where it leaves on the other side of both, else 0.
    #[inline(always)]
    pub fn eval(&self, wo: LaneVec3<L>, wi: LaneVec3<L>) -> LaneVec3<L> {
        let (o, i) = (self.frame.to_local(wo), self.frame.to_local(wi));
        let h = (o + i).normalize();
        let reflected =
            self.reflectance * (fresnel_dielectric_lanes(o.dot(h), self.eta) * self.microfacet.reflection_eval(o, i));
        let (h, through) = refraction_half_vector(o, i, self.eta);
        let refracted = self.transmittance
            * ((L::ONE - fresnel_dielectric_lanes(o.dot(h), self.eta))
                * self.microfacet.transmission_eval(o, i, self.eta));
        let refracted = LaneVec3::select(self.frame.transmits(wi) & through, refracted, LaneVec3::ZERO);
        LaneVec3::select(self.frame.reflects(wi), reflected, refracted)
    }

    #[inline(always)]
    pub fn pdf(&self, wo: LaneVec3<L>, wi: LaneVec3<L>) -> L {
        let (o, i) = (self.frame.to_local(wo), self.frame.to_local(wi));
        let h = (o + i).normalize();
        let reflected = fresnel_dielectric_lanes(o.dot(h), self.eta) * self.microfacet.reflection_pdf(o, i);
        let (h, through) = refraction_half_vector(o, i, self.eta);
        let refracted =
            (L::ONE - fresnel_dielectric_lanes(o.dot(h), self.eta)) * self.microfacet.transmission_pdf(o, i, self.eta);
        let refracted = L::select(self.frame.transmits(wi) & through, refracted, L::ZERO);
        L::select(self.frame.reflects(wi), reflected, refracted)
    }

    /// A visible micro-normal, then its reflection (with probability F) or refraction;
    /// weighed by eval / pdf. A microfacet's reflection below the surface (or refraction above
    /// it) is lost light, not a sample of the other lobe.
    #[inline(always)]
    pub fn sample(&self, wo: LaneVec3<L>, u_lobe: L, u1: L, u2: L) -> LaneBsdfSample<L> {
        let o = self.frame.to_local(wo);
        let h = self.microfacet.sample_normal(o, u1, u2);
        // A Beckmann normal may face away from the viewer.
        let facing = o.dot(h).gt(L::ZERO);
        let reflected = u_lobe.lt(fresnel_dielectric_lanes(o.dot(h), self.eta));
        let (refracted, exists) = lanes::refract(-o, h, self.eta);
        let local = LaneVec3::select(reflected, lanes::reflect(-o, h), refracted);
        let wi = self.frame.to_world(local);
        let (reflects, transmits) = (self.frame.reflects(wi), self.frame.transmits(wi));
        let kept = (reflected & reflects) | (!reflected & exists & transmits);
        let eta_squared = L::select(transmits, L::ONE / (self.eta * self.eta), L::ONE);
        LaneBsdfSample::weighed(wi, self.eval(wo, wi), self.pdf(wo, wi), facing & kept, eta_squared)
    }
}

#[derive(Clone, Copy, Debug)]
pub(super) struct RoughDielectricBsdf {
    frame: Frame,
    /// n(wo's side) / n(the other side).
    eta: f32,
    reflectance: Rgb,
    transmittance: Rgb,
    microfacet: Microfacet,
}

impl RoughDielectricBsdf {
    /// The lobe as its one body reads it.
    #[inline(always)]
    fn lanes(&self) -> RoughDielectricLanes<f32> {
        RoughDielectricLanes {
            frame: LaneFrame::from(&self.frame),
            eta: self.eta,
            reflectance: self.reflectance.into(),
            transmittance: self.transmittance.into(),
            microfacet: MicrofacetLanes::from(&self.microfacet),
        }
    }
}

impl Lobes for RoughDielectricBsdf {
    fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        self.lanes().eval(wo.into(), wi.into()).into()
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.lanes().pdf(wo.into(), wi.into())
    }

    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        self.lanes().sample(wo.into(), u_lobe, u.x, u.y).scalar()
    }

    fn non_delta_probability(&self) -> f32 {
        1.0
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
    use crate::materials::testing::{albedo, at, check_sampling, frame_toward, furnace};

    fn frosted(alpha: f32) -> RoughDielectric {
        let dielectric = Dielectric {
            eta: 1.5,
            specular_reflectance: Texture::Constant(Rgb::ONE),
            specular_transmittance: Texture::Constant(Rgb::ONE),
        };
        RoughDielectric { dielectric, alpha_u: alpha.into(), alpha_v: alpha.into(), distribution: Distribution::Ggx }
    }

    /// Textured widths: on each check the BSDF (reflection and refraction) is the constant
    /// glass with that check's widths.
    #[test]
    fn textured_widths_are_read_where_the_hit_is() {
        let checks = |a: f32, b: f32| {
            Texture::Checker(Box::new(crate::textures::Checker::new(Rgb::splat(a), Rgb::splat(b), Vec2::splat(2.0))))
        };
        let textured = RoughDielectric { alpha_u: checks(0.05, 0.3), alpha_v: checks(0.3, 0.05), ..frosted(0.1) };
        let wo = Vec3::new(0.3, -0.2, 0.9).normalize();
        for (uv, (alpha_u, alpha_v)) in [(Vec2::new(0.2, 0.2), (0.05, 0.3)), (Vec2::new(0.7, 0.2), (0.3, 0.05))] {
            let query = TextureQuery { uv, dpdu: Vec3::new(1.0, 0.5, 0.0), ..Default::default() };
            let constant = RoughDielectric { alpha_u: alpha_u.into(), alpha_v: alpha_v.into(), ..frosted(0.1) };
            let (a, b) = (
                at(&textured.bsdf(&query, frame_toward(wo, Vec3::Z))),
                at(&constant.bsdf(&query, frame_toward(wo, Vec3::Z))),
            );
            for wi in [Vec3::new(-0.3, 0.2, 0.9), Vec3::new(-0.2, 0.3, -0.9), Vec3::new(-0.5, -0.1, -0.8)] {
                let wi = wi.normalize();
                assert_eq!(a.eval(wo, wi), b.eval(wo, wi), "{uv}");
                assert_eq!(a.pdf(wo, wi), b.pdf(wo, wi), "{uv}");
            }
        }
    }

    /// Over the whole sphere, from outside and from inside (where total internal reflection
    /// sends some microfacets' light back).
    #[test]
    fn sampling_matches_pdf_from_both_sides() {
        let n = Vec3::new(0.1, 0.2, 1.0).normalize();
        for (alpha, seed) in [(0.2, 51), (0.6, 52)] {
            for wo in [Vec3::new(0.4, -0.3, 0.8), Vec3::new(-0.3, 0.2, -0.9), Vec3::new(0.8, 0.1, -0.3)] {
                let wo = wo.normalize();
                let bsdf = at(&frosted(alpha).bsdf(&Default::default(), frame_toward(wo, n)));
                check_sampling(&bsdf, wo, n, seed);
            }
        }
    }

    /// Beckmann glass, from outside and inside: sampling against the pdf, and the albedo by
    /// sampling against quadrature (≤ 1).
    #[test]
    fn beckmann_glass_matches_its_pdf_and_conserves_energy() {
        let glass = RoughDielectric { distribution: Distribution::Beckmann, ..frosted(0.3) };
        for wo in [Vec3::new(0.4, -0.3, 0.8), Vec3::new(-0.3, 0.2, -0.9)] {
            let wo = wo.normalize();
            let bsdf = at(&glass.bsdf(&Default::default(), frame_toward(wo, Vec3::Z)));
            check_sampling(&bsdf, wo, Vec3::Z, 91);
            furnace(&bsdf, wo, 92);
        }
    }

    /// White furnace: a rough interface loses only what single scattering misses (light that
    /// would hit a second microfacet), so its albedo is ≤ 1 and near 1 when nearly smooth.
    #[test]
    fn white_furnace() {
        for wo in [Vec3::new(0.3, 0.0, 0.95), Vec3::new(0.2, 0.1, -0.97)] {
            let wo = wo.normalize();
            let smooth = at(&frosted(0.01).bsdf(&Default::default(), frame_toward(wo, Vec3::Z)));
            let a = albedo(&smooth, wo, 100_000, 9);
            assert!((a.mean - 1.0).abs() < 0.01, "{a:?}");
            let rough = at(&frosted(0.7).bsdf(&Default::default(), frame_toward(wo, Vec3::Z)));
            let a = furnace(&rough, wo, 10);
            assert!(a.mean > 0.5, "{a:?}");
        }
    }
}
