//! A rough metal, Mitsuba's `roughconductor`: GGX microfacets (anisotropic widths α_u along the
//! shading frame's tangent, α_v along its bitangent) with the conductor's Fresnel reflectance
//! at the microfacet, sampled by visible normals. One-sided.
//!
//! Scene parameters: those of `conductor` (`metal`, or `eta` and `k`; `specular_reflectance`),
//! and `alpha` (default 0.1), or `alpha_u` and `alpha_v`: each a number or a texture's name
//! (read as its luminance, so the width may vary over the surface).
//! ```toml
//! [materials.brushed]
//! type = "rough-conductor"
//! metal = "Al"
//! alpha_u = 0.05
//! alpha_v = 0.3
//! ```
//! f·cos θ_i = specular · F(wo·h) · D(h) · G1(wo) G1(wi) / (4 cos θ_o), h = (wo + wi)/|wo + wi|,
//! with GGX's D (glint's default) or Beckmann's (Mitsuba's). α_u lies along the surface's
//! ∂p/∂u (`Frame::along`), as in Mitsuba.

use glam::{Vec2, Vec3};

use super::bsdf::{BsdfSample, Frame, LaneBsdfSample, LaneFrame, Leaf, Lobes};
use super::conductor::fresnel_conductor_rgb;
use super::microfacet::MicrofacetLanes;
use super::{Conductor, Distribution, Microfacet, PhongPoint};
use crate::lanes::{reflect, LaneVec3, Lanes};
use crate::textures::{luminance, Texture, TextureQuery};
use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct RoughConductor {
    pub conductor: Conductor,
    /// The widths along ∂p/∂u and across it, constant or textured.
    pub alpha_u: Texture,
    pub alpha_v: Texture,
    /// GGX (glint's default) or Beckmann (Mitsuba's).
    pub distribution: Distribution,
}

impl RoughConductor {
    pub(super) fn bsdf(&self, query: &TextureQuery, frame: Frame) -> Leaf<'static> {
        let c = &self.conductor;
        let (alpha_u, alpha_v) = (width(&self.alpha_u, query), width(&self.alpha_v, query));
        Leaf::RoughConductor(RoughConductorBsdf {
            // Anisotropic widths lie along the surface's ∂p/∂u.
            frame: if alpha_u != alpha_v { frame.along(query.dpdu) } else { frame },
            eta: c.eta,
            k: c.k,
            specular: c.specular.evaluate(query),
            microfacet: Microfacet::separable(alpha_u, alpha_v).with(self.distribution),
        })
    }

    /// Its widths along ∂p/∂u and across it and its specular colour at a point, as `bsdf`
    /// reads them.
    pub(crate) fn widths_and_specular(&self, query: &TextureQuery) -> (f32, f32, Rgb) {
        (width(&self.alpha_u, query), width(&self.alpha_v, query), self.conductor.specular.evaluate(query))
    }

    /// Whitted's view: the lobe's smooth limit, the smooth conductor's mirror weighted by the
    /// Fresnel reflectance at the viewer's angle (Whitted traces no glossy rays).
    pub(super) fn whitted(&self, query: &TextureQuery, outside: bool, cos: f32) -> PhongPoint {
        self.conductor.whitted(query, outside, cos)
    }
}

/// A microfacet width from a texture: a constant's value, a varying texture's luminance (as
/// Mitsuba reads a texture as one number), kept above 10⁻⁴ where the lobe is still finite.
pub(super) fn width(texture: &Texture, query: &TextureQuery) -> f32 {
    let alpha = match texture {
        Texture::Constant(c) => c.x,
        varying => luminance(varying.evaluate(query)),
    };
    alpha.max(1e-4)
}

/// The rough conductor at a hit, in lanes: the one body of its `eval`, `pdf` and `sample`,
/// which the scalar BSDF runs at one lane and the wavefront at eight.
#[derive(Clone, Debug)]
pub(crate) struct RoughConductorLanes<L: Lanes> {
    pub frame: LaneFrame<L>,
    pub eta: LaneVec3<L>,
    pub k: LaneVec3<L>,
    pub specular: LaneVec3<L>,
    pub microfacet: MicrofacetLanes<L>,
}

impl<L: Lanes> RoughConductorLanes<L> {
    /// specular · F(wo·h) · D G / (4 cos θ_o) where `wi` reflects on the viewer's side of a
    /// front face, else 0.
    #[inline(always)]
    pub fn eval(&self, wo: LaneVec3<L>, wi: LaneVec3<L>) -> LaneVec3<L> {
        let (o, i) = (self.frame.to_local(wo), self.frame.to_local(wi));
        let h = (o + i).normalize();
        let cos = o.dot(h);
        let fresnel = fresnel_conductor_rgb(cos, self.eta, self.k);
        let value = self.specular.mul_lanes(fresnel) * self.microfacet.reflection_eval(o, i);
        LaneVec3::select(self.frame.outside & self.frame.reflects(wi), value, LaneVec3::ZERO)
    }

    #[inline(always)]
    pub fn pdf(&self, wo: LaneVec3<L>, wi: LaneVec3<L>) -> L {
        let pdf = self.microfacet.reflection_pdf(self.frame.to_local(wo), self.frame.to_local(wi));
        L::select(self.frame.outside & self.frame.reflects(wi), pdf, L::ZERO)
    }

    /// `wo` reflected about a visible micro-normal, weighed by eval / pdf.
    #[inline(always)]
    pub fn sample(&self, wo: LaneVec3<L>, u1: L, u2: L) -> LaneBsdfSample<L> {
        let o = self.frame.to_local(wo);
        let h = self.microfacet.sample_normal(o, u1, u2);
        // A Beckmann normal may face away from the viewer.
        let facing = o.dot(h).gt(L::ZERO);
        let wi = self.frame.to_world(reflect(-o, h));
        let valid = self.frame.outside & facing & self.frame.reflects(wi);
        LaneBsdfSample::weighed(wi, self.eval(wo, wi), self.pdf(wo, wi), valid, L::ONE)
    }
}

#[derive(Clone, Copy, Debug)]
pub(super) struct RoughConductorBsdf {
    frame: Frame,
    eta: Rgb,
    k: Rgb,
    specular: Rgb,
    microfacet: Microfacet,
}

impl RoughConductorBsdf {
    /// The lobe as its one body reads it.
    #[inline(always)]
    fn lanes(&self) -> RoughConductorLanes<f32> {
        RoughConductorLanes {
            frame: LaneFrame::from(&self.frame),
            eta: self.eta.into(),
            k: self.k.into(),
            specular: self.specular.into(),
            microfacet: MicrofacetLanes::from(&self.microfacet),
        }
    }
}

impl Lobes for RoughConductorBsdf {
    fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        self.lanes().eval(wo.into(), wi.into()).into()
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.lanes().pdf(wo.into(), wi.into())
    }

    fn sample(&self, wo: Vec3, _u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        self.lanes().sample(wo.into(), u.x, u.y).scalar()
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
    use crate::materials::testing::{albedo, at, check_sampling, frame_toward, furnace};
    use crate::materials::{fresnel_conductor, named_metal};
    use crate::textures::Texture;

    fn metal(alpha_u: f32, alpha_v: f32, eta: Rgb, k: Rgb) -> RoughConductor {
        RoughConductor {
            conductor: Conductor { eta, k, specular: Texture::Constant(Rgb::ONE) },
            alpha_u: alpha_u.into(),
            alpha_v: alpha_v.into(),
            distribution: Distribution::Ggx,
        }
    }

    /// Mitsuba's default distribution: Beckmann normals sampled by D cos θ_h match the pdf,
    /// isotropic and anisotropic, and a white metal loses energy only to single scattering.
    #[test]
    fn beckmann_sampling_matches_pdf_and_conserves_energy() {
        for (alpha_u, alpha_v) in [(0.3, 0.3), (0.1, 0.4)] {
            let m =
                RoughConductor { distribution: Distribution::Beckmann, ..metal(alpha_u, alpha_v, Rgb::ZERO, Rgb::ONE) };
            for wo in [Vec3::new(0.3, -0.2, 0.9), Vec3::new(0.8, 0.1, 0.3)] {
                let wo = wo.normalize();
                let bsdf = at(&m.bsdf(&Default::default(), frame_toward(wo, Vec3::Z)));
                check_sampling(&bsdf, wo, Vec3::Z, 81);
                let a = furnace(&bsdf, wo, 82);
                assert!(a.mean > 0.8, "{a:?}");
            }
        }
    }

    /// The narrow width α_u lies along the surface's ∂p/∂u, whichever way that points: seen
    /// head-on, the highlight falls off fast when the light tilts along ∂p/∂u and slowly
    /// across it; sampling in that frame still matches its pdf.
    #[test]
    fn anisotropy_follows_dpdu() {
        let m = metal(0.05, 0.4, Rgb::ZERO, Rgb::ONE);
        for dpdu in [Vec3::new(2.0, 0.0, 0.3), Vec3::new(1.0, 1.0, -0.5), Vec3::new(0.0, -3.0, 0.0)] {
            let query = TextureQuery { dpdu, ..Default::default() };
            let bsdf = at(&m.bsdf(&query, frame_toward(Vec3::Z, Vec3::Z)));
            let along = (dpdu - Vec3::Z * dpdu.z).normalize();
            let across = Vec3::Z.cross(along);
            let tilted = |t: Vec3| (Vec3::Z + 0.2 * t).normalize();
            let (narrow, wide) = (bsdf.eval(Vec3::Z, tilted(along)).x, bsdf.eval(Vec3::Z, tilted(across)).x);
            assert!(narrow < 0.05 * wide, "{dpdu}: {narrow} along vs {wide} across");
            let wo = Vec3::new(0.3, -0.2, 0.9).normalize();
            let bsdf = at(&m.bsdf(&query, frame_toward(wo, Vec3::Z)));
            check_sampling(&bsdf, wo, Vec3::Z, 77);
        }
    }

    /// Textured widths: on each check the BSDF is the constant metal with that check's
    /// widths (the tangent frame follows ∂p/∂u wherever they differ).
    #[test]
    fn textured_widths_are_read_where_the_hit_is() {
        let checks = |a: f32, b: f32| {
            Texture::Checker(Box::new(crate::textures::Checker::new(Rgb::splat(a), Rgb::splat(b), Vec2::splat(2.0))))
        };
        let textured = RoughConductor {
            alpha_u: checks(0.05, 0.3),
            alpha_v: checks(0.3, 0.05),
            ..metal(0.1, 0.1, Rgb::ZERO, Rgb::ONE)
        };
        let wo = Vec3::new(0.3, -0.2, 0.9).normalize();
        for (uv, (alpha_u, alpha_v)) in [(Vec2::new(0.2, 0.2), (0.05, 0.3)), (Vec2::new(0.7, 0.2), (0.3, 0.05))] {
            let query = TextureQuery { uv, dpdu: Vec3::new(1.0, 0.5, 0.0), ..Default::default() };
            let constant = metal(alpha_u, alpha_v, Rgb::ZERO, Rgb::ONE);
            let (a, b) = (
                at(&textured.bsdf(&query, frame_toward(wo, Vec3::Z))),
                at(&constant.bsdf(&query, frame_toward(wo, Vec3::Z))),
            );
            for wi in [Vec3::new(-0.3, 0.2, 0.9), Vec3::new(-0.1, 0.4, 0.9), Vec3::new(-0.5, -0.1, 0.8)] {
                let wi = wi.normalize();
                assert_eq!(a.eval(wo, wi), b.eval(wo, wi), "{uv}");
                assert_eq!(a.pdf(wo, wi), b.pdf(wo, wi), "{uv}");
            }
        }
    }

    #[test]
    fn sampling_matches_pdf_isotropic_and_anisotropic() {
        let (eta, k) = named_metal("Au").unwrap();
        let n = Vec3::new(0.1, 0.2, 1.0).normalize();
        for (alpha_u, alpha_v, seed) in [(0.3, 0.3, 41), (0.1, 0.5, 42), (0.8, 0.2, 43)] {
            for wo in [Vec3::new(0.3, -0.2, 0.9), Vec3::new(-0.8, 0.3, 0.3)] {
                let wo = wo.normalize();
                let bsdf = at(&metal(alpha_u, alpha_v, eta, k).bsdf(&Default::default(), frame_toward(wo, n)));
                check_sampling(&bsdf, wo, n, seed);
            }
        }
    }

    /// White furnace: with F = 1 (η = 0, k = 1, Mitsuba's default mirror) the albedo is the
    /// single-scattering GGX albedo: ≤ 1, near 1 when smooth, lower when rough (light that
    /// would reach a second microfacet is lost: about half at α = 0.8), sampling and quadrature
    /// agreeing.
    #[test]
    fn white_furnace() {
        let (eta, k) = (Rgb::ZERO, Rgb::ONE);
        assert!((fresnel_conductor(0.7, eta, k) - Rgb::ONE).abs().max_element() < 1e-5);
        let wo = Vec3::new(0.3, 0.0, 0.95).normalize();
        let smooth = at(&metal(0.02, 0.02, eta, k).bsdf(&Default::default(), frame_toward(wo, Vec3::Z)));
        let a = albedo(&smooth, wo, 100_000, 5);
        assert!(a.mean > 0.99 && a.mean < 1.0 + 3.0 * a.standard_error, "{a:?}");
        let rough = at(&metal(0.8, 0.8, eta, k).bsdf(&Default::default(), frame_toward(wo, Vec3::Z)));
        let a = furnace(&rough, wo, 6);
        assert!(a.mean > 0.35 && a.mean < 0.6, "{a:?}");
        let anisotropic = at(&metal(0.1, 0.5, eta, k).bsdf(&Default::default(), frame_toward(wo, Vec3::Z)));
        let a = furnace(&anisotropic, wo, 7);
        assert!(a.mean > 0.6 && a.mean < 0.98, "{a:?}");
    }
}
