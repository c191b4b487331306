//! The thin principled BSDF (Burley 2015's thin-surface mode) as Mitsuba 3 defines it
//! (`principledthin`): a sheet with no inside, such as a leaf, paper or a curtain, the same from
//! both sides. It reflects and transmits diffusely and through rough microfacets, and light
//! leaves the other side without bending.
//!
//! Scene parameters (each a number or a texture's luminance, except `base_color`, a colour or
//! texture): `base_color` (0.5), `roughness` (0.5), `anisotropic` (0), `spec_trans` (0),
//! `diff_trans` (0, in [0, 2]: the share of the diffuse light sent through, ×2), `eta` (1.5),
//! `spec_tint` (0), `sheen` (0), `sheen_tint` (0), `flatness` (0), and the lobes' sampling rates
//! `diffuse_reflectance_sampling_rate`, `specular_reflectance_sampling_rate`,
//! `specular_transmittance_sampling_rate`, `diffuse_transmittance_sampling_rate` (1 each).
//! ```toml
//! [materials.leaf]
//! type = "principled-thin"
//! base_color = [0.2, 0.6, 0.1]
//! roughness = 0.4
//! spec_trans = 0.3
//! diff_trans = 0.8
//! eta = 1.33
//! ```
//! Lobes, with diffuse transmission dt = diff_trans / 2 (each ·|cos θ_i|):
//! * specular reflection, spec_trans·F·D·G / (4 cos θ_o): GGX of width roughness² (stretched
//!   by anisotropy), F the dielectric Fresnel at η leaning by `spec_tint` to Schlick's tinted
//!   by the base colour. As Mitsuba's, it is weighed by `spec_trans`: without transmission
//!   there is no glossy reflection;
//! * specular transmission, spec_trans·base·(1 − F)·D′·G′ / (4 cos θ_o) at the mirror image
//!   through the sheet of a reflection, with widths scaled by (0.65η − 0.35) (Burley 2015,
//!   fig. 15), where the image still sees its microfacet from behind;
//! * Burley's diffuse and retro-reflection (toward the fake subsurface by `flatness`) and the
//!   sheen, (1 − spec_trans)(1 − dt);
//! * Lambert's transmission, (1 − spec_trans)·dt·base/π.
//!
//! Sampling: the four lobes with Mitsuba's probabilities (∝ rate × spec_trans/2,
//! spec_trans/2, (1 − spec_trans)(1 − dt), (1 − spec_trans)·dt), the glossy ones by visible
//! normals; a microfacet sample that lands on the wrong side is lost light (as in Mitsuba), not
//! a sample of another lobe. The pdf is the same mixture, so sampling and pdf agree exactly.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use super::bsdf::{BsdfSample, Frame, LaneBsdfSample, LaneFrame, Leaf, Lobes};
use super::microfacet::MicrofacetLanes;
use super::phong::fresnel_dielectric_lanes;
use super::principled::{burley_diffuse_lanes, disney_microfacet, schlick_lanes, sheen_lanes, tint_lanes, LUMINANCE};
use super::{fresnel_dielectric, Distribution, PhongPoint};
use crate::lanes::{self, LaneVec3, Lanes};
use crate::sampling::warp::square_to_cosine_hemisphere_lanes;
use crate::textures::{Texture, TextureQuery};
use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct PrincipledThin {
    pub base_color: Texture,
    pub roughness: Texture,
    pub anisotropic: Texture,
    pub spec_trans: Texture,
    /// In [0, 2]: 0 reflects all the diffuse light, 2 transmits it all.
    pub diff_trans: Texture,
    /// The sheet's index relative to its surroundings.
    pub eta: Texture,
    pub spec_tint: Texture,
    pub sheen: Texture,
    pub sheen_tint: Texture,
    pub flatness: Texture,
    /// The lobes' relative sampling rates (they change the noise, not the image).
    pub rates: SamplingRates,
}

/// How often each lobe is drawn, relative to Mitsuba's default split.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SamplingRates {
    pub diffuse_reflection: f32,
    pub specular_reflection: f32,
    pub specular_transmission: f32,
    pub diffuse_transmission: f32,
}

impl Default for SamplingRates {
    fn default() -> Self {
        Self {
            diffuse_reflection: 1.0,
            specular_reflection: 1.0,
            specular_transmission: 1.0,
            diffuse_transmission: 1.0,
        }
    }
}

impl Default for PrincipledThin {
    /// Mitsuba's defaults.
    fn default() -> Self {
        let grey = |v: f32| Texture::Constant(Rgb::splat(v));
        Self {
            base_color: grey(0.5),
            roughness: grey(0.5),
            anisotropic: grey(0.0),
            spec_trans: grey(0.0),
            diff_trans: grey(0.0),
            eta: grey(1.5),
            spec_tint: grey(0.0),
            sheen: grey(0.0),
            sheen_tint: grey(0.0),
            flatness: grey(0.0),
            rates: SamplingRates::default(),
        }
    }
}

impl PrincipledThin {
    pub(super) fn bsdf(&self, query: &TextureQuery, frame: Frame) -> Leaf<'static> {
        Leaf::PrincipledThin(self.evaluate(query, frame))
    }

    /// Its parameters where the query is (its textures read there).
    pub(crate) fn point(&self, query: &TextureQuery) -> PrincipledThinPoint {
        let scalar = |t: &Texture| t.evaluate(query).dot(LUMINANCE);
        let (roughness, anisotropic) = (scalar(&self.roughness), scalar(&self.anisotropic));
        let eta = scalar(&self.eta);
        let (spec_trans, diff_trans) = (scalar(&self.spec_trans), 0.5 * scalar(&self.diff_trans));
        let reflection = disney_microfacet(roughness, anisotropic);
        let transmission = disney_microfacet((0.65 * eta - 0.35) * roughness, anisotropic);
        let rates = self.rates;
        let mut probabilities = [
            rates.specular_reflection * spec_trans / 2.0,
            rates.specular_transmission * spec_trans / 2.0,
            rates.diffuse_reflection * (1.0 - spec_trans) * (1.0 - diff_trans),
            rates.diffuse_transmission * (1.0 - spec_trans) * diff_trans,
        ];
        let total: f32 = probabilities.iter().sum();
        for p in &mut probabilities {
            *p /= total;
        }
        PrincipledThinPoint {
            base: self.base_color.evaluate(query),
            roughness,
            spec_trans,
            diff_trans,
            eta,
            spec_tint: scalar(&self.spec_tint),
            sheen: scalar(&self.sheen),
            sheen_tint: scalar(&self.sheen_tint),
            flatness: scalar(&self.flatness),
            reflection: (reflection.alpha_x, reflection.alpha_y),
            transmission: (transmission.alpha_x, transmission.alpha_y),
            probabilities,
        }
    }

    fn evaluate(&self, query: &TextureQuery, frame: Frame) -> PrincipledThinBsdf {
        let point = self.point(query);
        let (alpha_x, alpha_y) = point.reflection;
        // Anisotropic widths lie along the surface's ∂p/∂u.
        PrincipledThinBsdf { frame: if alpha_x != alpha_y { frame.along(query.dpdu) } else { frame }, point }
    }

    /// Whitted's view: the sheet's lobes in their smooth limit (Whitted traces no glossy
    /// rays) at the viewer's angle θ (cosine `cos`), each weighed as the BSDF weighs it, the
    /// same from both sides:
    /// * the mirror: spec_trans·F'(θ), F' the dielectric Fresnel reflectance at η leaning by
    ///   spec_tint toward Schlick's tinted by the base colour;
    /// * straight through, unbent (the sheet's transmission is the mirror image of its
    ///   reflection): spec_trans·base·(1 − F(θ));
    /// * Burley's diffuse as Lambert's term, k_d = base·(1 − spec_trans)(1 − dt) (exact head-on;
    ///   retro-reflection and sheen, which lean toward grazing angles, left out);
    /// * Lambert's transmission as the translucency, base·(1 − spec_trans)·dt, lit by lights
    ///   on the far side; ambient light arrives on both sides, k_a = k_d + translucency.
    pub(super) fn whitted(&self, query: &TextureQuery, cos: f32) -> PhongPoint {
        // The frame only tells the evaluated BSDF which side the viewer is on: its own.
        let b = self.evaluate(query, Frame::new(Vec3::Z, Vec3::Z, Vec3::Z));
        let p = &b.point;
        let (st, dt) = (p.spec_trans, p.diff_trans);
        let f = fresnel_dielectric(cos, 1.0 / p.eta);
        let (diffuse, translucency) = (p.base * ((1.0 - st) * (1.0 - dt)), p.base * ((1.0 - st) * dt));
        let reflectance: Rgb = b.lanes().reflectance(cos).into();
        PhongPoint {
            ambient: diffuse + translucency,
            diffuse,
            translucency,
            reflection: reflectance * st,
            straight: p.base * (st * (1.0 - f)),
            ..PhongPoint::BLACK
        }
    }
}

/// The thin principled BSDF's parameters at a point: its textures read there.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PrincipledThinPoint {
    pub base: Rgb,
    pub roughness: f32,
    pub spec_trans: f32,
    /// Halved: in [0, 1].
    pub diff_trans: f32,
    pub eta: f32,
    pub spec_tint: f32,
    pub sheen: f32,
    pub sheen_tint: f32,
    pub flatness: f32,
    /// The reflection's widths along ∂p/∂u and across it (`disney_microfacet`).
    pub reflection: (f32, f32),
    /// The reflection's widths scaled by (0.65η − 0.35).
    pub transmission: (f32, f32),
    /// Specular reflection, specular transmission, diffuse reflection, diffuse transmission.
    pub probabilities: [f32; 4],
}

#[derive(Clone, Copy, Debug)]
pub(super) struct PrincipledThinBsdf {
    frame: Frame,
    point: PrincipledThinPoint,
}

/// `v` mirrored through the sheet's plane (local).
#[inline(always)]
fn through<L: Lanes>(v: LaneVec3<L>) -> LaneVec3<L> {
    LaneVec3::new(v.x, v.y, v.z.negate())
}

/// The thin principled BSDF at a hit, in lanes: the one body of its `eval`, `pdf` and `sample`,
/// which the scalar BSDF runs at one lane and the wavefront at eight. The scalar code's branches
/// on the parameters are selects here.
#[derive(Clone, Debug)]
pub(crate) struct PrincipledThinLanes<L: Lanes> {
    pub frame: LaneFrame<L>,
    pub base: LaneVec3<L>,
    pub roughness: L,
    pub spec_trans: L,
    pub diff_trans: L,
    pub eta: L,
    pub spec_tint: L,
    pub sheen: L,
    pub sheen_tint: L,
    pub flatness: L,
    pub reflection: MicrofacetLanes<L>,
    pub transmission: MicrofacetLanes<L>,
    pub probabilities: [L; 4],
}

impl<L: Lanes> PrincipledThinLanes<L> {
    /// The lanes' BSDF from their points (`point(k)` for lane k) in `frame` (already turned to
    /// ∂p/∂u where the widths differ).
    #[inline(always)]
    pub fn gather<'p>(frame: LaneFrame<L>, point: impl Fn(usize) -> &'p PrincipledThinPoint) -> Self {
        let each = |f: &dyn Fn(&PrincipledThinPoint) -> f32| L::from_fn(|k| f(point(k)));
        let ggx = |widths: fn(&PrincipledThinPoint) -> (f32, f32)| MicrofacetLanes {
            alpha_x: each(&|p| widths(p).0),
            alpha_y: each(&|p| widths(p).1),
            separable: true,
            distribution: Distribution::Ggx,
        };
        Self {
            frame,
            base: LaneVec3::gather(|k| point(k).base),
            roughness: each(&|p| p.roughness),
            spec_trans: each(&|p| p.spec_trans),
            diff_trans: each(&|p| p.diff_trans),
            eta: each(&|p| p.eta),
            spec_tint: each(&|p| p.spec_tint),
            sheen: each(&|p| p.sheen),
            sheen_tint: each(&|p| p.sheen_tint),
            flatness: each(&|p| p.flatness),
            reflection: ggx(|p| p.reflection),
            transmission: ggx(|p| p.transmission),
            probabilities: [0, 1, 2, 3].map(|j| each(&|p| p.probabilities[j])),
        }
    }

    /// The dielectric Fresnel reflectance at a micro-normal seen at cosine `cos`, leaning by
    /// `spec_tint` toward Schlick's tinted by the base colour.
    #[inline(always)]
    pub fn reflectance(&self, cos: L) -> LaneVec3<L> {
        let f = fresnel_dielectric_lanes(cos, L::ONE / self.eta);
        let plain = LaneVec3::new(f, f, f);
        let r0 = (self.eta - L::ONE) / (self.eta + L::ONE);
        let tinted = schlick_lanes(tint_lanes(self.base) * (r0 * r0), cos, self.eta);
        LaneVec3::select(self.spec_tint.eq(L::ZERO), plain, plain + (tinted - plain) * self.spec_tint)
    }

    /// The half vector of a transmission to `i` (below): that of the reflection `i` mirrors,
    /// and the lanes where the transmitted direction still sees its microfacet from behind
    /// (Mitsuba's macro–micro compatibility).
    #[inline(always)]
    fn transmission_half_vector(o: LaneVec3<L>, i: LaneVec3<L>) -> (LaneVec3<L>, L::Mask) {
        let (h, normalized) = (o + through(i)).try_normalize();
        (h, normalized & o.dot(h).gt(L::ZERO) & i.dot(h).lt(L::ZERO))
    }

    #[inline(always)]
    pub fn eval(&self, wo: LaneVec3<L>, wi: LaneVec3<L>) -> LaneVec3<L> {
        let (o, i) = (self.frame.to_local(wo), self.frame.to_local(wi));
        let (st, dt) = (self.spec_trans, self.diff_trans);
        let pi = L::splat(PI);
        // Reflection: the glossy lobe, then the diffuse one and the sheen.
        let h = (o + i).normalize();
        let glossy = self.reflectance(o.dot(h)) * (st * self.reflection.reflection_eval(o, i));
        let reflected = LaneVec3::select(st.gt(L::ZERO), LaneVec3::ZERO + glossy, LaneVec3::ZERO);
        let diffuse = self.base * (i.z / pi * burley_diffuse_lanes(o, i, h, self.roughness, self.flatness));
        let sheen = sheen_lanes(self.base, self.sheen_tint, h.dot(i)) * (self.sheen * i.z);
        let diffuse = (diffuse + sheen) * ((L::ONE - st) * (L::ONE - dt));
        let reflected = LaneVec3::select(st.lt(L::ONE) & dt.lt(L::ONE), reflected + diffuse, reflected);
        // Transmission: the glossy lobe through the sheet, then Lambert's.
        let (h, seen) = Self::transmission_half_vector(o, i);
        let f = fresnel_dielectric_lanes(o.dot(h), L::ONE / self.eta);
        let glossy = self.base * (st * (L::ONE - f) * self.transmission.reflection_eval(o, through(i)));
        let transmitted = LaneVec3::select(st.gt(L::ZERO) & seen, LaneVec3::ZERO + glossy, LaneVec3::ZERO);
        let lambert = self.base * ((L::ONE - st) * dt * i.z.negate() / pi);
        let transmitted = LaneVec3::select(st.lt(L::ONE) & dt.gt(L::ZERO), transmitted + lambert, transmitted);
        let value = LaneVec3::select(
            self.frame.reflects(wi),
            reflected,
            LaneVec3::select(self.frame.transmits(wi), transmitted, LaneVec3::ZERO),
        );
        LaneVec3::select(o.z.le(L::ZERO), LaneVec3::ZERO, value)
    }

    #[inline(always)]
    pub fn pdf(&self, wo: LaneVec3<L>, wi: LaneVec3<L>) -> L {
        let (o, i) = (self.frame.to_local(wo), self.frame.to_local(wi));
        let [specular_reflection, specular_transmission, diffuse_reflection, diffuse_transmission] = self.probabilities;
        let pi = L::splat(PI);
        let glossy = L::select(specular_reflection.gt(L::ZERO), self.reflection.reflection_pdf(o, i), L::ZERO);
        let reflected = specular_reflection * glossy + diffuse_reflection * i.z / pi;
        let (_, seen) = Self::transmission_half_vector(o, i);
        let glossy = self.transmission.reflection_pdf(o, through(i));
        let glossy = L::select(seen & specular_transmission.gt(L::ZERO), glossy, L::ZERO);
        let transmitted = specular_transmission * glossy + diffuse_transmission * i.z.negate() / pi;
        let pdf =
            L::select(self.frame.reflects(wi), reflected, L::select(self.frame.transmits(wi), transmitted, L::ZERO));
        L::select(o.z.le(L::ZERO), L::ZERO, pdf)
    }

    /// One of the four lobes by `u_lobe` (Mitsuba's probabilities), the glossy ones by visible
    /// normals; a microfacet sample on the wrong side is lost light, not another lobe's.
    #[inline(always)]
    pub fn sample(&self, wo: LaneVec3<L>, u_lobe: L, u1: L, u2: L) -> LaneBsdfSample<L> {
        let o = self.frame.to_local(wo);
        let [specular_reflection, specular_transmission, diffuse_reflection, _] = self.probabilities;
        let mirrored = u_lobe.lt(specular_reflection);
        let through_sheet = !mirrored & u_lobe.lt(specular_reflection + specular_transmission);
        let diffused =
            !mirrored & !through_sheet & u_lobe.lt(specular_reflection + specular_transmission + diffuse_reflection);
        let reflected = lanes::reflect(-o, self.reflection.sample_normal(o, u1, u2));
        let h = self.transmission.sample_normal(o, u1, u2);
        let transmitted = through(lanes::reflect(-o, h));
        let transmitted_lost = transmitted.z.ge(L::ZERO) | transmitted.dot(h).ge(L::ZERO) | o.dot(h).le(L::ZERO);
        let cosine = square_to_cosine_hemisphere_lanes(u1, u2);
        let local = LaneVec3::select(
            mirrored,
            reflected,
            LaneVec3::select(through_sheet, transmitted, LaneVec3::select(diffused, cosine, through(cosine))),
        );
        let lost = (mirrored & reflected.z.le(L::ZERO)) | (through_sheet & transmitted_lost);
        let wi = self.frame.to_world(local);
        let wrong_side =
            (local.z.gt(L::ZERO) & !self.frame.reflects(wi)) | (local.z.lt(L::ZERO) & !self.frame.transmits(wi));
        let valid = o.z.gt(L::ZERO) & !lost & !wrong_side;
        LaneBsdfSample::weighed(wi, self.eval(wo, wi), self.pdf(wo, wi), valid, L::ONE)
    }
}

impl PrincipledThinBsdf {
    /// The lobe as its one body reads it.
    #[inline(always)]
    fn lanes(&self) -> PrincipledThinLanes<f32> {
        PrincipledThinLanes::gather(LaneFrame::from(&self.frame), |_| &self.point)
    }
}

impl Lobes for PrincipledThinBsdf {
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

    fn through(v: Vec3) -> Vec3 {
        Vec3::new(v.x, v.y, -v.z)
    }
    use crate::materials::testing::{at, check_sampling, check_whitted, check_whitted_local, frame_toward, furnace};

    /// A leaf with every lobe, a brushed sheet (anisotropic, tinted, skewed sampling rates),
    /// and a mostly transmitting film.
    fn members() -> Vec<(&'static str, PrincipledThin)> {
        vec![
            (
                "leaf",
                PrincipledThin {
                    base_color: Texture::Constant(Rgb::new(0.2, 0.7, 0.1)),
                    roughness: Texture::from(0.4),
                    spec_trans: Texture::from(0.3),
                    diff_trans: Texture::from(0.8),
                    eta: Texture::from(1.33),
                    sheen: Texture::from(0.5),
                    sheen_tint: Texture::from(0.4),
                    flatness: Texture::from(0.3),
                    ..Default::default()
                },
            ),
            (
                "brushed sheet",
                PrincipledThin {
                    base_color: Texture::Constant(Rgb::new(0.9, 0.5, 0.3)),
                    roughness: Texture::from(0.5),
                    anisotropic: Texture::from(0.8),
                    spec_trans: Texture::from(0.6),
                    diff_trans: Texture::from(1.4),
                    spec_tint: Texture::from(0.5),
                    rates: SamplingRates {
                        diffuse_reflection: 0.5,
                        specular_reflection: 2.0,
                        specular_transmission: 1.0,
                        diffuse_transmission: 3.0,
                    },
                    ..Default::default()
                },
            ),
            (
                "film",
                PrincipledThin {
                    base_color: Texture::from(0.9),
                    roughness: Texture::from(0.3),
                    spec_trans: Texture::from(0.9),
                    diff_trans: Texture::from(0.2),
                    eta: Texture::from(1.6),
                    ..Default::default()
                },
            ),
        ]
    }

    /// Over the whole sphere, from both sides: the sheet has no inside.
    #[test]
    fn sampling_matches_pdf_from_both_sides() {
        let n = Vec3::new(0.1, -0.2, 1.0).normalize();
        for (k, (_, m)) in members().into_iter().enumerate() {
            for wo in [Vec3::new(0.4, -0.3, 0.8), Vec3::new(0.9, 0.1, 0.2), Vec3::new(-0.3, 0.2, -0.9)] {
                let wo = wo.normalize();
                let bsdf = at(&m.bsdf(&Default::default(), frame_toward(wo, n)));
                check_sampling(&bsdf, wo, n, 71 + k as u64);
            }
        }
    }

    /// The albedo by sampling equals the albedo by quadrature of `eval` and is at most 1 (the
    /// furnace), for each member and for white sheets that transmit by either lobe, from both
    /// sides; all Lambert transmission keeps exactly what it receives.
    #[test]
    fn albedo_by_sampling_equals_quadrature_and_a_white_sheet_conserves_energy() {
        let wo = Vec3::new(0.3, 0.0, 0.95).normalize();
        for (_, m) in members() {
            furnace(&at(&m.bsdf(&Default::default(), frame_toward(wo, Vec3::Z))), wo, 9);
        }
        for (spec_trans, diff_trans) in [(1.0, 0.0), (0.0, 2.0), (0.5, 1.0)] {
            let white = PrincipledThin {
                base_color: Texture::from(1.0),
                roughness: Texture::from(0.3),
                spec_trans: Texture::from(spec_trans),
                diff_trans: Texture::from(diff_trans),
                ..Default::default()
            };
            for wo in [wo, Vec3::new(0.5, 0.2, -0.8).normalize()] {
                let a = furnace(&at(&white.bsdf(&Default::default(), frame_toward(wo, Vec3::Z))), wo, 10);
                if diff_trans == 2.0 {
                    assert!((a.mean - 1.0).abs() < 1e-5, "Lambert transmission from {wo}: {a:?}");
                }
            }
        }
    }

    /// Values by hand. All diffuse transmission (diff_trans 2, spec_trans 0): Lambert's
    /// transmission base/π·|cos θ_i| and no reflection. All specular (spec_trans 1), seen and
    /// lit head-on: reflection F(1)·D(z)·G / 4 with D(z) = 1/(πα²), and through the sheet the
    /// same with the scaled width and 1 − F, times the base colour.
    #[test]
    fn lambert_transmission_and_head_on_specular_values_by_hand() {
        let base = Rgb::new(0.2, 0.5, 0.7);
        let frame = frame_toward(Vec3::Z, Vec3::Z);
        let wi = Vec3::new(0.6, 0.0, -0.8);
        let translucent = PrincipledThin {
            base_color: Texture::Constant(base),
            diff_trans: Texture::from(2.0),
            ..Default::default()
        };
        let bsdf = at(&translucent.bsdf(&Default::default(), frame));
        let value = bsdf.eval(Vec3::Z, wi);
        let expected = base / PI * 0.8;
        assert!((value - expected).abs().max_element() < 1e-6, "{value} vs {expected}");
        assert_eq!(bsdf.eval(Vec3::Z, Vec3::new(0.6, 0.0, 0.8)), Rgb::ZERO);

        let eta = 1.5f32;
        let specular = PrincipledThin {
            base_color: Texture::Constant(base),
            roughness: Texture::from(0.5),
            spec_trans: Texture::from(1.0),
            eta: Texture::from(eta),
            ..Default::default()
        };
        let bsdf = at(&specular.bsdf(&Default::default(), frame));
        let f = ((eta - 1.0) / (eta + 1.0)).powi(2);
        let alpha = 0.25f32;
        let reflected = bsdf.eval(Vec3::Z, Vec3::Z);
        let expected = f / (4.0 * PI * alpha * alpha);
        assert!((reflected - Rgb::splat(expected)).abs().max_element() < 1e-4 * expected, "{reflected} vs {expected}");
        let scaled = (0.65 * eta - 0.35) * 0.5;
        let alpha = scaled * scaled;
        let transmitted = bsdf.eval(Vec3::Z, -Vec3::Z);
        let expected = base * ((1.0 - f) / (4.0 * PI * alpha * alpha));
        assert!(
            (transmitted - expected).abs().max_element() < 1e-4 * expected.max_element(),
            "{transmitted} vs {expected}"
        );
    }

    /// The sheet has no inside: seen from behind, it answers as from the front mirrored.
    #[test]
    fn both_sides_are_alike() {
        let (_, m) = members().remove(0);
        let (wo, wi) = (Vec3::new(0.3, 0.4, 0.7).normalize(), Vec3::new(-0.5, 0.1, 0.6).normalize());
        let front = at(&m.bsdf(&Default::default(), frame_toward(wo, Vec3::Z)));
        let back = at(&m.bsdf(&Default::default(), frame_toward(through(wo), Vec3::Z)));
        for wi in [wi, through(wi)] {
            let (a, b) = (front.eval(wo, wi), back.eval(through(wo), through(wi)));
            assert!((a - b).abs().max_element() < 1e-6, "{a} vs {b}");
            let (a, b) = (front.pdf(wo, wi), back.pdf(through(wo), through(wi)));
            assert!((a - b).abs() < 1e-6, "{a} vs {b}");
        }
    }

    /// Whitted reads the sheet's smooth limit (roughness 0): the mirror spec_trans·F', straight
    /// through spec_trans·base·(1 − F), the same from both sides; and head-on, where Burley's
    /// diffuse is Lambert's, its Lambert terms are π times the BSDF's on both sides.
    #[test]
    fn whitted_reads_the_bsdfs_smooth_limit() {
        let film = crate::materials::Material::PrincipledThin(Box::new(PrincipledThin {
            base_color: Texture::Constant(Rgb::new(0.3, 0.8, 0.5)),
            roughness: Texture::from(0.0),
            spec_trans: Texture::from(0.7),
            spec_tint: Texture::from(0.4),
            eta: Texture::from(1.4),
            ..Default::default()
        }));
        for (outside, degrees) in [(true, 0.0), (true, 50.0), (false, 75.0)] {
            check_whitted(&film, outside, degrees, 13);
        }
        // No glossy lobe (spec_trans 0) to light the straight-through direction.
        let leaf = crate::materials::Material::PrincipledThin(Box::new(PrincipledThin {
            base_color: Texture::Constant(Rgb::new(0.2, 0.7, 0.1)),
            diff_trans: Texture::from(0.8),
            ..Default::default()
        }));
        check_whitted_local(&leaf, Vec3::Z, &[Vec3::Z, -Vec3::Z, Vec3::new(0.5, 0.2, -0.8).normalize()]);
    }
}
