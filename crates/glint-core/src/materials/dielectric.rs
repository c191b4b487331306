//! Smooth glass, Mitsuba's `dielectric`: a perfect mirror and a perfect refraction split by the
//! exact Fresnel reflectance, the split chosen by roulette with the Fresnel probability.
//! Two-sided: from inside, the index ratio inverts and total internal reflection follows.
//!
//! Scene parameters: `int_ior` (default 1.5046, BK7 glass), `ext_ior` (default 1.000277,
//! air), `specular_reflectance`, `specular_transmittance` (factors, default 1).
//! ```toml
//! [materials.glass]
//! type = "dielectric"
//! int_ior = 1.5
//! ```
//! The refracted weight leaves out the radiance's η² (glint's convention for every refraction;
//! it cancels along a path that enters and leaves a closed object) and reports η² for Russian
//! roulette, as Mitsuba's roulette does.

use glam::{Vec2, Vec3};

use super::bsdf::{BsdfSample, Frame, LaneBsdfSample, LaneFrame, Leaf, Lobes};
use super::phong::fresnel_dielectric_lanes;
use super::{fresnel_dielectric, PhongPoint};
use crate::lanes::{self, LaneVec3, Lanes};
use crate::textures::{Texture, TextureQuery};
use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct Dielectric {
    /// int_ior / ext_ior.
    pub eta: f32,
    pub specular_reflectance: Texture,
    pub specular_transmittance: Texture,
}

impl Dielectric {
    pub(super) fn bsdf(&self, query: &TextureQuery, frame: Frame) -> Leaf<'static> {
        Leaf::Dielectric(DielectricBsdf {
            frame,
            eta: side_eta(self.eta, &frame),
            reflectance: self.specular_reflectance.evaluate(query),
            transmittance: self.specular_transmittance.evaluate(query),
        })
    }

    /// Whitted's view: the mirror and the refraction, weighted as the BSDF weighs them at the
    /// viewer's angle (cosine `cos`): specular_reflectance·F and specular_transmittance·(1 − F),
    /// F the exact Fresnel reflectance from the viewer's side (1 past the critical angle, where
    /// everything is reflected). Both sides.
    pub(super) fn whitted(&self, query: &TextureQuery, outside: bool, cos: f32) -> PhongPoint {
        let f = fresnel_dielectric(cos, if outside { 1.0 / self.eta } else { self.eta });
        PhongPoint {
            reflection: self.specular_reflectance.evaluate(query) * f,
            transmission: self.specular_transmittance.evaluate(query) * (1.0 - f),
            ior: self.eta,
            ..PhongPoint::BLACK
        }
    }
}

/// n(wo's side) / n(the other side), for an interface of relative index `eta` = n_int / n_ext.
pub(super) fn side_eta(eta: f32, frame: &Frame) -> f32 {
    if frame.outside {
        1.0 / eta
    } else {
        eta
    }
}

#[derive(Clone, Copy, Debug)]
pub(super) struct DielectricBsdf {
    frame: Frame,
    eta: f32,
    reflectance: Rgb,
    transmittance: Rgb,
}

/// Smooth glass at a hit, in lanes: the one body of its mirror and refraction, which the
/// scalar BSDF runs at one lane and the wavefront at eight.
#[derive(Clone, Debug)]
pub(crate) struct DielectricLanes<L: Lanes> {
    pub frame: LaneFrame<L>,
    /// n(wo's side) / n(the other side).
    pub eta: L,
    pub reflectance: LaneVec3<L>,
    pub transmittance: LaneVec3<L>,
}

impl<L: Lanes> DielectricLanes<L> {
    /// The refraction where `u_lobe` ≥ F (and it exists), else the mirror, each weighted by
    /// its colour with the probability of its choice as its pdf.
    #[inline(always)]
    pub fn sample(&self, wo: LaneVec3<L>, u_lobe: L) -> LaneBsdfSample<L> {
        let normal = self.frame.normal;
        let cos = wo.dot(normal).max(L::ZERO);
        let f = fresnel_dielectric_lanes(cos, self.eta);
        let (refracted, exists) = lanes::refract(-wo, normal, self.eta);
        let can_refract = f.lt(L::ONE) & exists;
        let through = can_refract & u_lobe.ge(f);
        LaneBsdfSample {
            wi: LaneVec3::select(through, refracted, lanes::reflect(-wo, normal)),
            weight: LaneVec3::select(through, self.transmittance, self.reflectance),
            pdf: L::select(through, L::ONE - f, L::select(can_refract, f, L::ONE)),
            valid: !L::Mask::default(),
            eta_squared: L::select(through, L::ONE / (self.eta * self.eta), L::ONE),
            delta: !L::Mask::default(),
        }
    }
}

impl Lobes for DielectricBsdf {
    fn sample(&self, wo: Vec3, u_lobe: f32, _u: Vec2) -> Option<BsdfSample> {
        let lanes = DielectricLanes::<f32> {
            frame: LaneFrame::from(&self.frame),
            eta: self.eta,
            reflectance: self.reflectance.into(),
            transmittance: self.transmittance.into(),
        };
        lanes.sample(wo.into(), u_lobe).scalar()
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
    use crate::materials::testing::{albedo, at, check_whitted, frame_toward};

    fn glass() -> Dielectric {
        Dielectric {
            eta: 1.5,
            specular_reflectance: Texture::Constant(Rgb::ONE),
            specular_transmittance: Texture::Constant(Rgb::ONE),
        }
    }

    #[test]
    fn fresnel_split_snell_and_total_internal_reflection() {
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let bsdf = at(&glass().bsdf(&Default::default(), frame_toward(wo, Vec3::Z)));
        let f = fresnel_dielectric(0.8, 1.0 / 1.5);
        let mirror = bsdf.sample(wo, f * 0.5, Vec2::ZERO).unwrap();
        assert!(
            mirror.delta && (mirror.pdf - f).abs() < 1e-6 && (mirror.wi - Vec3::new(-0.6, 0.0, 0.8)).length() < 1e-6
        );
        let through = bsdf.sample(wo, 0.99, Vec2::ZERO).unwrap();
        // Snell: sin θ_t = sin θ_i / 1.5.
        assert!((through.wi.x + 0.6 / 1.5).abs() < 1e-6 && through.wi.z < 0.0, "{through:?}");
        assert!((through.pdf - (1.0 - f)).abs() < 1e-6 && (through.eta_squared - 2.25).abs() < 1e-5);
        // From inside past the critical angle (sin θ = 0.8 > 1/1.5): all reflects.
        let inside = Vec3::new(0.8, 0.0, -0.6);
        let bsdf = at(&glass().bsdf(&Default::default(), frame_toward(inside, Vec3::Z)));
        let s = bsdf.sample(inside, 0.99, Vec2::ZERO).unwrap();
        assert!(s.pdf == 1.0 && s.wi.z < 0.0 && s.weight == Rgb::ONE);
    }

    /// White furnace: clear glass passes on all the light, from either side.
    #[test]
    fn white_furnace() {
        for wo in [Vec3::new(0.3, 0.2, 0.9).normalize(), Vec3::new(0.7, 0.0, -0.714).normalize()] {
            let bsdf = at(&glass().bsdf(&Default::default(), frame_toward(wo, Vec3::Z)));
            let a = albedo(&bsdf, wo, 10_000, 8);
            assert!((a.mean - 1.0).abs() < 1e-6, "{a:?}");
        }
    }

    /// Whitted's mirror and refraction carry specular_reflectance·F and
    /// specular_transmittance·(1 − F) at the angle, from either side (all reflected past the
    /// critical angle inside), as the BSDF's two delta lobes.
    #[test]
    fn whitted_reads_the_bsdf() {
        let tinted = crate::materials::Material::Dielectric(Dielectric {
            specular_reflectance: Texture::Constant(Rgb::new(0.9, 0.7, 0.5)),
            specular_transmittance: Texture::Constant(Rgb::new(0.5, 0.8, 1.0)),
            ..glass()
        });
        for (outside, degrees) in [(true, 0.0), (true, 50.0), (true, 85.0), (false, 20.0), (false, 40.0), (false, 60.0)]
        {
            check_whitted(&tinted, outside, degrees, 5);
        }
    }
}
