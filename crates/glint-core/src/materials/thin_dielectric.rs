//! A thin sheet of glass (a window pane), Mitsuba's `thindielectric`: light reflects, or passes
//! straight through (no displacement, no bending), the reflectance summed over the sheet's
//! internal reflections, R' = R + T²R / (1 − R²) = 2R / (1 + R) with R = F(cos θ). Two-sided.
//!
//! Scene parameters: `int_ior` (default 1.5046), `ext_ior` (default 1.000277),
//! `specular_reflectance`, `specular_transmittance` (factors, default 1).
//! ```toml
//! [materials.window]
//! type = "thin-dielectric"
//! ```

use glam::{Vec2, Vec3};

use super::bsdf::{BsdfSample, Frame, LaneBsdfSample, LaneFrame, Leaf, Lobes};
use super::phong::fresnel_dielectric_lanes;
use super::{Dielectric, PhongPoint};
use crate::lanes::{self, LaneVec3, Lanes};
use crate::textures::TextureQuery;
use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct ThinDielectric {
    pub sheet: Dielectric,
}

impl ThinDielectric {
    pub(super) fn bsdf(&self, query: &TextureQuery, frame: Frame) -> Leaf<'static> {
        Leaf::ThinDielectric(ThinDielectricBsdf {
            frame,
            eta: 1.0 / self.sheet.eta,
            reflectance: self.sheet.specular_reflectance.evaluate(query),
            transmittance: self.sheet.specular_transmittance.evaluate(query),
        })
    }

    /// Whitted's view, the BSDF's: the sheet's reflectance R' at the viewer's angle (cosine
    /// `cos`) as the mirror's weight, specular_reflectance·R', and the rest passed straight on
    /// (unbent), specular_transmittance·(1 − R'). Both sides.
    pub(super) fn whitted(&self, query: &TextureQuery, cos: f32) -> PhongPoint {
        let r = sheet_reflectance(cos, 1.0 / self.sheet.eta);
        PhongPoint {
            reflection: self.sheet.specular_reflectance.evaluate(query) * r,
            straight: self.sheet.specular_transmittance.evaluate(query) * (1.0 - r),
            ..PhongPoint::BLACK
        }
    }
}

/// R' = 2R / (1 + R): the sheet's reflectance with its internal reflections.
fn sheet_reflectance(cos: f32, eta: f32) -> f32 {
    sheet_reflectance_lanes(cos, eta)
}

/// `sheet_reflectance` in lanes.
#[inline(always)]
fn sheet_reflectance_lanes<L: Lanes>(cos: L, eta: L) -> L {
    let r = fresnel_dielectric_lanes(cos, eta);
    L::select(r.lt(L::ONE), L::splat(2.0) * r / (L::ONE + r), L::ONE)
}

/// A thin sheet of glass at a hit, in lanes: the one body of its sampling, which the scalar
/// BSDF runs at one lane and the wavefront at eight. Delta lobes alone.
#[derive(Clone, Debug)]
pub(crate) struct ThinDielectricLanes<L: Lanes> {
    pub frame: LaneFrame<L>,
    /// n_ext / n_int.
    pub eta: L,
    pub reflectance: LaneVec3<L>,
    pub transmittance: LaneVec3<L>,
}

impl<L: Lanes> ThinDielectricLanes<L> {
    /// The mirror with probability R', else straight on.
    #[inline(always)]
    pub fn sample(&self, wo: LaneVec3<L>, u_lobe: L) -> LaneBsdfSample<L> {
        let r = sheet_reflectance_lanes(wo.dot(self.frame.normal).max(L::ZERO), self.eta);
        let reflected = u_lobe.lt(r);
        let all = !L::Mask::default();
        LaneBsdfSample {
            wi: LaneVec3::select(reflected, lanes::reflect(-wo, self.frame.normal), -wo),
            weight: LaneVec3::select(reflected, self.reflectance, self.transmittance),
            pdf: L::select(reflected, r, L::ONE - r),
            valid: all,
            eta_squared: L::ONE,
            delta: all,
        }
    }
}

#[derive(Clone, Copy, Debug)]
pub(super) struct ThinDielectricBsdf {
    frame: Frame,
    /// n_ext / n_int.
    eta: f32,
    reflectance: Rgb,
    transmittance: Rgb,
}

impl Lobes for ThinDielectricBsdf {
    fn sample(&self, wo: Vec3, u_lobe: f32, _u: Vec2) -> Option<BsdfSample> {
        let lanes = ThinDielectricLanes {
            frame: LaneFrame::from(&self.frame),
            eta: self.eta,
            reflectance: self.reflectance.into(),
            transmittance: self.transmittance.into(),
        };
        lanes.sample(wo.into(), u_lobe).scalar()
    }

    fn null_transmission(&self, wo: Vec3) -> Rgb {
        self.transmittance * (1.0 - sheet_reflectance(wo.dot(self.frame.normal).abs(), self.eta))
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
    use crate::materials::testing::{albedo, at, frame_toward};
    use crate::textures::Texture;

    #[test]
    fn interreflection_sum_and_straight_transmission() {
        // R = 0.04 at normal incidence on n = 1.5: R' = 0.08 / 1.04.
        assert!((sheet_reflectance(1.0, 1.0 / 1.5) - 0.08 / 1.04).abs() < 1e-6);
        let pane = ThinDielectric {
            sheet: Dielectric {
                eta: 1.5,
                specular_reflectance: Texture::Constant(Rgb::ONE),
                specular_transmittance: Texture::Constant(Rgb::ONE),
            },
        };
        let wo = Vec3::new(0.0, 0.6, -0.8);
        let bsdf = at(&pane.bsdf(&Default::default(), frame_toward(wo, Vec3::Z)));
        let through = bsdf.sample(wo, 0.999, Vec2::ZERO).unwrap();
        assert!(through.delta && through.wi == -wo && through.eta_squared == 1.0);
        let a = albedo(&bsdf, wo, 10_000, 2);
        assert!((a.mean - 1.0).abs() < 1e-6, "white furnace: {a:?}");
    }

    /// Whitted's mirror carries the sheet's reflectance R' at the angle and the straight ray
    /// the rest, as the BSDF's two delta lobes.
    #[test]
    fn whitted_reads_the_bsdf() {
        let pane = crate::materials::Material::ThinDielectric(ThinDielectric {
            sheet: Dielectric {
                eta: 1.5,
                specular_reflectance: Texture::Constant(Rgb::new(1.0, 0.8, 0.6)),
                specular_transmittance: Texture::Constant(Rgb::new(0.6, 0.9, 1.0)),
            },
        });
        for (outside, degrees) in [(true, 0.0), (true, 60.0), (false, 80.0)] {
            crate::materials::testing::check_whitted(&pane, outside, degrees, 7);
        }
    }
}
