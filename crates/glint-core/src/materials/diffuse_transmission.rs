//! A diffuse reflector and transmitter (pbrt-v4's `diffusetransmission`): Lambert's lobe on
//! the viewer's side with `reflectance`, and on the far side with `transmittance`; the same
//! from either side, as paper, leaves and lampshades are.
//!
//! Scene parameters: `reflectance` and `transmittance` (colours or textures, default
//! [0.25, 0.25, 0.25] each).
//! ```toml
//! [materials.paper]
//! type = "diffuse-transmission"
//! reflectance = [0.6, 0.6, 0.55]
//! transmittance = [0.3, 0.3, 0.25]
//! ```
//! f = reflectance / π toward the viewer's side, transmittance / π through. Sampled by
//! choosing a side in proportion to the two albedos' luminance, then a cosine-weighted
//! direction there: weight = albedo / P(side).

use glam::{Vec2, Vec3};

use super::bsdf::{BsdfSample, Frame, LaneBsdfSample, LaneFrame, Leaf, Lobes};
use super::PhongPoint;
use crate::lanes::{LaneVec3, Lanes};
use crate::sampling::warp::square_to_cosine_hemisphere_lanes;
use crate::textures::{luminance, Texture, TextureQuery};
use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct DiffuseTransmission {
    pub reflectance: Texture,
    pub transmittance: Texture,
}

impl DiffuseTransmission {
    pub(super) fn bsdf(&self, query: &TextureQuery, frame: Frame) -> Leaf<'static> {
        let (reflectance, transmittance) = (self.reflectance.evaluate(query), self.transmittance.evaluate(query));
        let (r, t) = (luminance(reflectance).max(0.0), luminance(transmittance).max(0.0));
        let p_reflect = if r + t > 0.0 { r / (r + t) } else { 0.0 };
        Leaf::DiffuseTransmission(DiffuseTransmissionBsdf {
            frame,
            reflectance,
            transmittance,
            p_reflect,
            lit: r + t > 0.0,
        })
    }

    /// Whitted's view: the BSDF's two Lambert lobes as the course's Lambert term, k_d = the
    /// reflectance for lights on the viewer's side and `translucency` = the transmittance for
    /// lights on the far side (each an albedo, as `diffuse` reads its own); ambient light
    /// arrives on both sides, k_a = reflectance + transmittance. No child ray: light through
    /// the sheet is scattered, never seen through.
    pub(super) fn whitted(&self, query: &TextureQuery) -> PhongPoint {
        let (reflectance, transmittance) = (self.reflectance.evaluate(query), self.transmittance.evaluate(query));
        PhongPoint {
            ambient: reflectance + transmittance,
            diffuse: reflectance,
            translucency: transmittance,
            ..PhongPoint::BLACK
        }
    }
}

#[derive(Clone, Copy, Debug)]
pub(super) struct DiffuseTransmissionBsdf {
    frame: Frame,
    reflectance: Rgb,
    transmittance: Rgb,
    /// The probability of sampling the reflected side.
    p_reflect: f32,
    lit: bool,
}

impl DiffuseTransmissionBsdf {
    /// The lobe as its one body reads it.
    #[inline(always)]
    fn lanes(&self) -> DiffuseTransmissionLanes<f32> {
        DiffuseTransmissionLanes {
            frame: LaneFrame::from(&self.frame),
            reflectance: self.reflectance.into(),
            transmittance: self.transmittance.into(),
            p_reflect: self.p_reflect,
            lit: self.lit,
        }
    }
}

/// Diffuse reflection and transmission at a hit, in lanes: the one body of its `eval`, `pdf`
/// and `sample`, which the scalar BSDF runs at one lane and the wavefront at eight.
#[derive(Clone, Debug)]
pub(crate) struct DiffuseTransmissionLanes<L: Lanes> {
    pub frame: LaneFrame<L>,
    pub reflectance: LaneVec3<L>,
    pub transmittance: LaneVec3<L>,
    /// The probability of sampling the reflected side.
    pub p_reflect: L,
    /// The lanes with an albedo that is not black.
    pub lit: L::Mask,
}

/// The cosine-weighted hemisphere's density at a direction of cosine `cos` (0 below).
#[inline(always)]
fn cosine_density<L: Lanes>(cos: L) -> L {
    L::select(cos.gt(L::ZERO), cos * L::splat(std::f32::consts::FRAC_1_PI), L::ZERO)
}

impl<L: Lanes> DiffuseTransmissionLanes<L> {
    #[inline(always)]
    pub fn eval(&self, wi: LaneVec3<L>) -> LaneVec3<L> {
        let cos = wi.dot(self.frame.normal).abs() * L::splat(std::f32::consts::FRAC_1_PI);
        let through = LaneVec3::select(self.frame.transmits(wi), self.transmittance * cos, LaneVec3::ZERO);
        LaneVec3::select(self.frame.reflects(wi), self.reflectance * cos, through)
    }

    #[inline(always)]
    pub fn pdf(&self, wi: LaneVec3<L>) -> L {
        let cos = self.frame.to_local(wi).z;
        let through =
            L::select(self.frame.transmits(wi), (L::ONE - self.p_reflect) * cosine_density(cos.negate()), L::ZERO);
        L::select(self.frame.reflects(wi), self.p_reflect * cosine_density(cos), through)
    }

    /// A side by `u_lobe` (in proportion to the albedos' luminance), then a cosine-weighted
    /// direction on it.
    #[inline(always)]
    pub fn sample(&self, u_lobe: L, u1: L, u2: L) -> LaneBsdfSample<L> {
        let local = square_to_cosine_hemisphere_lanes(u1, u2);
        let reflected = u_lobe.lt(self.p_reflect);
        let wi = LaneVec3::select(reflected, self.frame.to_world(local), self.frame.to_world(-local));
        let p = L::select(reflected, self.p_reflect, L::ONE - self.p_reflect);
        let weight = LaneVec3::select(
            reflected,
            self.reflectance.divided_by(self.p_reflect),
            self.transmittance.divided_by(L::ONE - self.p_reflect),
        );
        let on_its_side = (reflected & self.frame.reflects(wi)) | (!reflected & self.frame.transmits(wi));
        LaneBsdfSample {
            wi,
            weight,
            pdf: p * cosine_density(local.z),
            valid: self.lit & local.z.gt(L::ZERO) & on_its_side,
            eta_squared: L::ONE,
            delta: L::Mask::default(),
        }
    }
}

impl Lobes for DiffuseTransmissionBsdf {
    fn eval(&self, _wo: Vec3, wi: Vec3) -> Rgb {
        self.lanes().eval(wi.into()).into()
    }

    fn pdf(&self, _wo: Vec3, wi: Vec3) -> f32 {
        self.lanes().pdf(wi.into())
    }

    fn sample(&self, _wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        self.lanes().sample(u_lobe, u.x, u.y).scalar()
    }

    fn non_delta_probability(&self) -> f32 {
        if self.lit {
            1.0
        } else {
            0.0
        }
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
    use crate::materials::testing::{at, check_sampling, check_whitted_local, frame_toward, furnace};

    fn sheet(r: f32, t: f32) -> DiffuseTransmission {
        DiffuseTransmission {
            reflectance: Texture::Constant(Rgb::splat(r)),
            transmittance: Texture::Constant(Rgb::splat(t)),
        }
    }

    #[test]
    fn lambert_on_each_side_by_hand() {
        let wo = Vec3::new(0.2, 0.1, 0.9).normalize();
        let wi = Vec3::new(0.6, 0.0, 0.8);
        let bsdf = at(&sheet(0.6, 0.3).bsdf(&Default::default(), frame_toward(wo, Vec3::Z)));
        let pi = std::f32::consts::PI;
        assert!((bsdf.eval(wo, wi) - Rgb::splat(0.6 * 0.8 / pi)).abs().max_element() < 1e-6);
        assert!((bsdf.eval(wo, -wi) - Rgb::splat(0.3 * 0.8 / pi)).abs().max_element() < 1e-6);
        // Sides chosen 2 : 1.
        assert!((bsdf.pdf(wo, wi) - 2.0 / 3.0 * 0.8 / pi).abs() < 1e-6);
        assert!((bsdf.pdf(wo, -wi) - 1.0 / 3.0 * 0.8 / pi).abs() < 1e-6);
        // From behind the same: the sheet has no front.
        let behind = at(&sheet(0.6, 0.3).bsdf(&Default::default(), frame_toward(-wo, Vec3::Z)));
        assert!((behind.eval(-wo, -wi) - Rgb::splat(0.6 * 0.8 / pi)).abs().max_element() < 1e-6);
        assert!(at(&sheet(0.0, 0.0).bsdf(&Default::default(), frame_toward(wo, Vec3::Z)))
            .sample(wo, 0.5, Vec2::splat(0.3))
            .is_none());
    }

    #[test]
    fn sampling_matches_pdf_and_a_lossless_sheet_passes_everything_on() {
        let n = Vec3::new(0.2, -0.3, 0.9).normalize();
        let wo = Vec3::new(0.5, 0.1, 0.7).normalize();
        for (r, t) in [(0.7, 0.3), (0.1, 0.9), (1.0, 0.0), (0.0, 1.0)] {
            let bsdf = at(&sheet(r, t).bsdf(&Default::default(), frame_toward(wo, n)));
            check_sampling(&bsdf, wo, n, 41);
            let a = furnace(&bsdf, wo, 5);
            assert!((a.mean - 1.0).abs() < 1e-5, "r + t = 1 passes all light on: {a:?}");
        }
    }

    /// Whitted's Lambert terms are π times the BSDF's on both sides: the reflectance for lights
    /// on the viewer's side, the transmittance (the translucency) for lights behind; no child
    /// ray.
    #[test]
    fn whitted_reads_the_bsdf() {
        let paper = crate::materials::Material::DiffuseTransmission(sheet(0.6, 0.3));
        let wo = Vec3::new(0.3, 0.2, 0.9).normalize();
        check_whitted_local(&paper, wo, &[Vec3::Z, Vec3::new(0.6, -0.3, 0.2).normalize(), -Vec3::Z, -wo]);
        let w = paper.whitted_at(&TextureQuery::default(), true, wo.z);
        assert_eq!((w.reflection, w.transmission, w.straight), (Rgb::ZERO, Rgb::ZERO, Rgb::ZERO));
    }
}
