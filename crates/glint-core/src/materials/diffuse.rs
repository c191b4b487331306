//! Lambert's diffuse reflector, one-sided (black from behind), as Mitsuba's `diffuse`; the
//! native format wraps it in `two_sided` unless told otherwise.
//!
//! Scene parameters: `reflectance` (colour or texture, default [0.5, 0.5, 0.5]).
//! ```toml
//! [materials.wall]
//! type = "diffuse"
//! reflectance = [0.7, 0.2, 0.2]
//! ```
//! f = reflectance / π; sampled by the cosine-weighted hemisphere, weight = reflectance.

use glam::{Vec2, Vec3};

use super::bsdf::{BsdfSample, Frame, LaneBsdfSample, LaneFrame, Leaf, Lobes};
use super::PhongPoint;
use crate::lanes::{LaneVec3, Lanes};
use crate::sampling::warp::square_to_cosine_hemisphere_lanes;
use crate::textures::{Texture, TextureQuery};
use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct Diffuse {
    pub reflectance: Texture,
}

impl Diffuse {
    pub(super) fn bsdf(&self, query: &TextureQuery, frame: Frame) -> Leaf<'static> {
        Leaf::Diffuse(DiffuseBsdf { frame, reflectance: self.reflectance.evaluate(query) })
    }

    /// Whitted's view: the course's Lambert term with k_a = k_d = the reflectance, the albedo.
    /// So a point or directional light gives k_d·(N·L)·I, π times the BSDF's ρ/π·(N·L)·I under
    /// the path tracers (the course's convention, the same for its own material), and an
    /// ambient light I_a, a uniform radiance, comes back as ρ·I_a, as the BSDF returns it.
    /// Black from behind, as the BSDF.
    pub(super) fn whitted(&self, query: &TextureQuery, outside: bool) -> PhongPoint {
        if !outside {
            return PhongPoint::BLACK;
        }
        let k_d = self.reflectance.evaluate(query);
        PhongPoint { ambient: k_d, diffuse: k_d, ..PhongPoint::BLACK }
    }
}

#[derive(Clone, Copy, Debug)]
pub(super) struct DiffuseBsdf {
    frame: Frame,
    reflectance: Rgb,
}

impl DiffuseBsdf {
    fn lit(&self) -> bool {
        self.frame.outside && self.reflectance != Rgb::ZERO
    }

    /// The lobe as its one body reads it, in `frame` (this BSDF's, at one lane).
    #[inline(always)]
    fn lanes<'f>(&self, frame: &'f LaneFrame<f32>) -> DiffuseLanes<'f, f32> {
        DiffuseLanes { frame, reflectance: self.reflectance.into(), lit: self.lit() }
    }
}

/// Lambert's lobe at a hit, in lanes: the one body of `DiffuseBsdf`'s `eval`, `pdf` and
/// `sample`, which the scalar BSDF runs at one lane and the wavefront at eight (for every lane
/// whose material is Lambert's lobe alone: Mitsuba's `diffuse`, two-sided or not, and the
/// course's material without its other lobes).
pub(crate) struct DiffuseLanes<'f, L: Lanes> {
    pub frame: &'f LaneFrame<L>,
    pub reflectance: LaneVec3<L>,
    /// Lanes that reflect: seen from the front of a one-sided lobe, and not black.
    pub lit: L::Mask,
}

impl<L: Lanes> DiffuseLanes<'_, L> {
    /// ρ/π · cos θ_i where `wi` reflects on the viewer's side.
    #[inline(always)]
    pub fn eval(&self, wi: LaneVec3<L>) -> LaneVec3<L> {
        let value = self.reflectance * (wi.dot(self.frame.normal) * L::splat(std::f32::consts::FRAC_1_PI));
        LaneVec3::select(self.lit & self.frame.reflects(wi), value, LaneVec3::ZERO)
    }

    /// cos θ_i / π where `wi` reflects on the viewer's side.
    #[inline(always)]
    pub fn pdf(&self, wi: LaneVec3<L>) -> L {
        let cos = wi.dot(self.frame.normal);
        L::select(self.lit & self.frame.reflects(wi), cos * L::splat(std::f32::consts::FRAC_1_PI), L::ZERO)
    }

    /// A cosine-weighted direction (Shirley and Chiu's concentric disk, lifted), weight ρ.
    #[inline(always)]
    pub fn sample(&self, u1: L, u2: L) -> LaneBsdfSample<L> {
        let local = square_to_cosine_hemisphere_lanes(u1, u2);
        let wi = self.frame.to_world(local);
        let valid = self.lit & !(local.z.le(L::ZERO) | wi.dot(self.frame.geometric).le(L::ZERO));
        let pdf = L::select(local.z.gt(L::ZERO), local.z * L::splat(std::f32::consts::FRAC_1_PI), L::ZERO);
        LaneBsdfSample { wi, weight: self.reflectance, pdf, valid, eta_squared: L::ONE, delta: L::Mask::default() }
    }
}

impl Lobes for DiffuseBsdf {
    fn eval(&self, _wo: Vec3, wi: Vec3) -> Rgb {
        self.lanes(&LaneFrame::from(&self.frame)).eval(wi.into()).into()
    }

    fn pdf(&self, _wo: Vec3, wi: Vec3) -> f32 {
        self.lanes(&LaneFrame::from(&self.frame)).pdf(wi.into())
    }

    fn sample(&self, _wo: Vec3, _u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        self.lanes(&LaneFrame::from(&self.frame)).sample(u.x, u.y).scalar()
    }

    fn non_delta_probability(&self) -> f32 {
        if self.lit() {
            1.0
        } else {
            0.0
        }
    }

    fn lambertian(&self) -> Option<Rgb> {
        Some(if self.frame.outside { self.reflectance } else { Rgb::ZERO })
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
    use crate::materials::testing::{albedo, at, check_sampling, check_whitted_local, frame_toward};

    fn diffuse(r: f32) -> Diffuse {
        Diffuse { reflectance: Texture::Constant(Rgb::splat(r)) }
    }

    #[test]
    fn lambert_by_hand_and_black_from_behind() {
        let wo = Vec3::new(0.2, 0.1, 0.9).normalize();
        let wi = Vec3::new(0.6, 0.0, 0.8);
        let bsdf = at(&diffuse(0.5).bsdf(&Default::default(), frame_toward(wo, Vec3::Z)));
        assert!((bsdf.eval(wo, wi) - Rgb::splat(0.5 * 0.8 / std::f32::consts::PI)).abs().max_element() < 1e-6);
        assert!((bsdf.pdf(wo, wi) - 0.8 / std::f32::consts::PI).abs() < 1e-6);
        assert_eq!(bsdf.eval(wo, -wi), Rgb::ZERO);
        let behind = at(&diffuse(0.5).bsdf(&Default::default(), frame_toward(-wo, Vec3::Z)));
        assert_eq!(behind.eval(-wo, -wi), Rgb::ZERO);
        assert!(behind.sample(-wo, 0.5, Vec2::splat(0.3)).is_none() && !behind.has_diffuse());
    }

    #[test]
    fn sampling_matches_pdf_and_white_furnace() {
        let n = Vec3::new(0.2, -0.3, 0.9).normalize();
        let wo = Vec3::new(0.5, 0.1, 0.7).normalize();
        let bsdf = at(&diffuse(1.0).bsdf(&Default::default(), frame_toward(wo, n)));
        check_sampling(&bsdf, wo, n, 31);
        let a = albedo(&bsdf, wo, 20_000, 3);
        assert!((a.mean - 1.0).abs() < 1e-5, "a white Lambertian reflects everything: {a:?}");
    }

    /// Whitted reads Lambert's term with k_d the albedo (π·f·cos for each light), k_a the
    /// same, and nothing from behind, as the BSDF.
    #[test]
    fn whitted_reads_the_bsdf() {
        let m = crate::materials::Material::Diffuse(diffuse(0.6));
        let wo = Vec3::new(0.4, -0.2, 0.9).normalize();
        check_whitted_local(&m, wo, &[Vec3::Z, Vec3::new(-0.7, 0.1, 0.3).normalize(), -wo]);
        let q = TextureQuery::default();
        assert_eq!(m.whitted_at(&q, true, 0.5).ambient, Rgb::splat(0.6));
        assert_eq!(m.whitted_at(&q, false, 0.5), PhongPoint::BLACK);
    }
}
