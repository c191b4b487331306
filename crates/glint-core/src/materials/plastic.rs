//! Smooth plastic, Mitsuba's `plastic`: a diffuse base under a smooth dielectric coat. The coat
//! reflects F(cos θ) as a mirror; the rest enters, scatters in the base, and is reflected
//! inside the coat again and again (the internal-scattering model Mitsuba documents: the base's
//! albedo divided by 1 − F_dr, the coat's diffuse internal reflectance), leaving through the
//! coat with (1 − F) and the 1/η² of radiance leaving a denser medium. One-sided.
//!
//! Scene parameters: `diffuse_reflectance` (default 0.5), `specular_reflectance` (a factor,
//! default 1), `int_ior` (default 1.49, polypropylene), `ext_ior` (default 1.000277),
//! `nonlinear` (default false: the base's colour as given; true: 1 − k_d·F_dr in the
//! denominator, darker saturated colours, as wet materials look).
//! ```toml
//! [materials.red_plastic]
//! type = "plastic"
//! diffuse_reflectance = [0.6, 0.1, 0.1]
//! ```
//! f·cos θ_i = k_d / (1 − F_dr) · (cos θ_i / π) · (1/η²) · (1 − F(cos θ_o)) (1 − F(cos θ_i)).
//! The coat is chosen with probability ∝ F(cos θ_o)·w_s against (1 − F(cos θ_o))·(1 − w_s), w_s
//! the specular colour's mean over both colours' means.

use glam::{Vec2, Vec3};

use super::bsdf::{BsdfSample, Frame, LaneBsdfSample, LaneFrame, Leaf, Lobes};
use super::phong::fresnel_dielectric_lanes;
use super::{fresnel_dielectric, PhongPoint};
use crate::lanes::{self, LaneVec3, Lanes};
use crate::sampling::warp::square_to_cosine_hemisphere_lanes;
use crate::textures::{Texture, TextureQuery};
use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct Plastic {
    pub diffuse: Texture,
    pub specular: Texture,
    /// int_ior / ext_ior.
    pub eta: f32,
    pub nonlinear: bool,
}

/// The part of a plastic both its smooth and rough forms evaluate the same way.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Coat {
    pub diffuse: Rgb,
    pub specular: Rgb,
    /// int_ior / ext_ior.
    pub eta: f32,
    /// The specular colour's share of the lobe choice, w_s.
    pub specular_weight: f32,
}

impl Coat {
    /// The base's colours at a hit: k_d divided by 1 − F_dr (or 1 − k_d·F_dr, `nonlinear`).
    pub fn new(diffuse: Rgb, specular: Rgb, eta: f32, nonlinear: bool, internal_reflectance: f32) -> Self {
        let denominator =
            if nonlinear { Rgb::ONE - diffuse * internal_reflectance } else { Rgb::splat(1.0 - internal_reflectance) };
        let (d_mean, s_mean) = (diffuse.element_sum() / 3.0, specular.element_sum() / 3.0);
        let specular_weight = if d_mean + s_mean > 0.0 { s_mean / (d_mean + s_mean) } else { 0.0 };
        Self { diffuse: diffuse / denominator, specular, eta, specular_weight }
    }

    /// The probability of choosing the coat's reflection, for the coat's weight `coat` of the
    /// light from `wo` (F or 1 − its transmittance).
    pub(crate) fn specular_probability(&self, coat: f32) -> f32 {
        specular_probability(coat, self.specular_weight)
    }
}

/// `Coat::specular_probability` in lanes, for the coat's weights `coat` and specular shares
/// `specular_weight`.
#[inline(always)]
fn specular_probability<L: Lanes>(coat: L, specular_weight: L) -> L {
    let (s, d) = (coat * specular_weight, (L::ONE - coat) * (L::ONE - specular_weight));
    L::select((s + d).gt(L::ZERO), s / (s + d), L::ZERO)
}

impl Plastic {
    pub(super) fn bsdf(&self, query: &TextureQuery, wo: Vec3, frame: Frame) -> Leaf<'static> {
        let coat = self.coat(query);
        let PlasticLanes { fresnel_o, p_diffuse, .. } = PlasticLanes::new(LaneFrame::from(&frame), wo.into(), |_| coat);
        Leaf::Plastic(PlasticBsdf { frame, coat, fresnel_o, p_diffuse })
    }

    /// Its coat at a hit (its textures read there).
    pub(crate) fn coat(&self, query: &TextureQuery) -> Coat {
        let internal = fresnel_diffuse_reflectance(1.0 / self.eta);
        Coat::new(self.diffuse.evaluate(query), self.specular.evaluate(query), self.eta, self.nonlinear, internal)
    }

    /// Whitted's view, the BSDF's at the viewer's angle θ_o (cosine `cos`): the coat as a
    /// mirror of weight specular·F(θ_o); the base as Lambert's term under the coat, k_d = the
    /// base's albedo after its internal scattering times (1 − F(θ_o))/η², each light's share
    /// further weighed by the coat's transmittance toward it, 1 − F(θ_i) (`coat_ior`), so that
    /// a light gives π times the BSDF's f·cos θ_i·I, as for `diffuse`; ambient light, uniform,
    /// comes back as k_d·(1 − F_dr), F_dr the coat's hemispherical reflectance from outside.
    /// Black from behind, as the BSDF.
    pub(super) fn whitted(&self, query: &TextureQuery, outside: bool, cos: f32) -> PhongPoint {
        if !outside {
            return PhongPoint::BLACK;
        }
        let internal = fresnel_diffuse_reflectance(1.0 / self.eta);
        let coat =
            Coat::new(self.diffuse.evaluate(query), self.specular.evaluate(query), self.eta, self.nonlinear, internal);
        let f = fresnel_dielectric(cos, 1.0 / self.eta);
        let k_d = coat.diffuse * ((1.0 - f) / (self.eta * self.eta));
        PhongPoint {
            ambient: k_d * (1.0 - fresnel_diffuse_reflectance(self.eta)),
            diffuse: k_d,
            reflection: coat.specular * f,
            coat_ior: self.eta,
            ..PhongPoint::BLACK
        }
    }
}

/// The diffuse (hemispherically averaged) Fresnel reflectance of an interface of relative
/// index `eta`: Egan & Hilgeman's fit (1973) below 1, d'Eon & Irving's (2011) from 1 on, the
/// fits Mitsuba uses.
pub fn fresnel_diffuse_reflectance(eta: f32) -> f32 {
    if eta < 1.0 {
        return -1.4399 * eta * eta + 0.7099 * eta + 0.6681 + 0.0636 / eta;
    }
    let inv = 1.0 / eta;
    let (inv2, inv3) = (inv * inv, inv * inv * inv);
    0.919317 - 3.4793 * inv + 6.75335 * inv2 - 7.80989 * inv3 + 4.98554 * inv2 * inv2 - 1.36881 * inv2 * inv3
}

/// Smooth plastic at a hit, in lanes: the one body of its `eval`, `pdf` and `sample`, which the
/// scalar BSDF runs at one lane and the wavefront at eight. Its lanes mix a delta lobe (the
/// coat's mirror) and a non-delta one (the base), chosen lane by lane.
#[derive(Clone, Debug)]
pub(crate) struct PlasticLanes<L: Lanes> {
    pub frame: LaneFrame<L>,
    /// The base's colour after its internal scattering (`Coat::diffuse`).
    pub diffuse: LaneVec3<L>,
    pub specular: LaneVec3<L>,
    /// int_ior / ext_ior.
    pub eta: L,
    /// The coat's reflectance toward the viewer, F(cos θ_o).
    pub fresnel_o: L,
    /// The probability of the diffuse lobe (0 from behind).
    pub p_diffuse: L,
}

impl<L: Lanes> PlasticLanes<L> {
    /// The lanes' plastic seen from `wo`, from their coats (`coat(k)` for lane k).
    #[inline(always)]
    pub fn new(frame: LaneFrame<L>, wo: LaneVec3<L>, coat: impl Fn(usize) -> Coat) -> Self {
        let coats: [Coat; 16] = std::array::from_fn(|k| if k < L::WIDTH { coat(k) } else { coat(0) });
        let eta = L::from_fn(|k| coats[k].eta);
        let fresnel_o = fresnel_dielectric_lanes(wo.dot(frame.normal).max(L::ZERO), L::ONE / eta);
        let specular_weight = L::from_fn(|k| coats[k].specular_weight);
        let p_diffuse = L::select(frame.outside, L::ONE - specular_probability(fresnel_o, specular_weight), L::ZERO);
        Self {
            diffuse: LaneVec3::gather(|k| coats[k].diffuse),
            specular: LaneVec3::gather(|k| coats[k].specular),
            frame,
            eta,
            fresnel_o,
            p_diffuse,
        }
    }

    #[inline(always)]
    pub fn eval(&self, wi: LaneVec3<L>) -> LaneVec3<L> {
        let cos_i = wi.dot(self.frame.normal);
        let through = (L::ONE - self.fresnel_o) * (L::ONE - fresnel_dielectric_lanes(cos_i, L::ONE / self.eta));
        let eta2 = self.eta * self.eta;
        let value = self.diffuse * (cos_i * L::splat(std::f32::consts::FRAC_1_PI) * through / eta2);
        LaneVec3::select(self.frame.outside & self.frame.reflects(wi), value, LaneVec3::ZERO)
    }

    #[inline(always)]
    pub fn pdf(&self, wi: LaneVec3<L>) -> L {
        let cos = self.frame.to_local(wi).z;
        let cosine = L::select(cos.gt(L::ZERO), cos * L::splat(std::f32::consts::FRAC_1_PI), L::ZERO);
        L::select(self.frame.outside & self.frame.reflects(wi), self.p_diffuse * cosine, L::ZERO)
    }

    /// The base's cosine-weighted direction where `u_lobe` < p_diffuse, else the coat's mirror.
    #[inline(always)]
    pub fn sample(&self, wo: LaneVec3<L>, u_lobe: L, u1: L, u2: L) -> LaneBsdfSample<L> {
        let diffuse = u_lobe.lt(self.p_diffuse);
        let wi = self.frame.to_world(square_to_cosine_hemisphere_lanes(u1, u2));
        let base = LaneBsdfSample::weighed(wi, self.eval(wi), self.pdf(wi), !L::Mask::default(), L::ONE);
        let p_specular = L::ONE - self.p_diffuse;
        let mirror = lanes::reflect(-wo, self.frame.normal);
        LaneBsdfSample {
            wi: LaneVec3::select(diffuse, base.wi, mirror),
            weight: LaneVec3::select(diffuse, base.weight, self.specular * (self.fresnel_o / p_specular)),
            pdf: L::select(diffuse, base.pdf, p_specular),
            valid: self.frame.outside & ((diffuse & base.valid) | !diffuse),
            eta_squared: L::ONE,
            delta: !diffuse,
        }
    }
}

#[derive(Clone, Copy, Debug)]
pub(super) struct PlasticBsdf {
    frame: Frame,
    coat: Coat,
    /// The coat's reflectance toward the viewer, F(cos θ_o).
    fresnel_o: f32,
    /// The probability of the diffuse lobe (0 from behind).
    p_diffuse: f32,
}

impl PlasticBsdf {
    /// The lobe as its one body reads it.
    #[inline(always)]
    fn lanes(&self) -> PlasticLanes<f32> {
        PlasticLanes {
            frame: LaneFrame::from(&self.frame),
            diffuse: self.coat.diffuse.into(),
            specular: self.coat.specular.into(),
            eta: self.coat.eta,
            fresnel_o: self.fresnel_o,
            p_diffuse: self.p_diffuse,
        }
    }
}

impl Lobes for PlasticBsdf {
    fn eval(&self, _wo: Vec3, wi: Vec3) -> Rgb {
        self.lanes().eval(wi.into()).into()
    }

    fn pdf(&self, _wo: Vec3, wi: Vec3) -> f32 {
        self.lanes().pdf(wi.into())
    }

    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        self.lanes().sample(wo.into(), u_lobe, u.x, u.y).scalar()
    }

    fn non_delta_probability(&self) -> f32 {
        self.p_diffuse
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
    use crate::materials::testing::{albedo, at, check_sampling, check_whitted, check_whitted_local, frame_toward};

    fn plastic(diffuse: f32, nonlinear: bool) -> Plastic {
        Plastic {
            diffuse: Texture::Constant(Rgb::splat(diffuse)),
            specular: Texture::Constant(Rgb::ONE),
            eta: 1.49,
            nonlinear,
        }
    }

    #[test]
    fn diffuse_fresnel_reflectance_fits() {
        // F_dr of glass seen from inside (η = 1/1.5) is about 0.6; from outside about 0.09.
        assert!((fresnel_diffuse_reflectance(1.0 / 1.5) - 0.596).abs() < 0.01);
        assert!((fresnel_diffuse_reflectance(1.5) - 0.092).abs() < 0.005);
        // The hemispherical average of the exact Fresnel equations, 2∫F(μ)μ dμ, by quadrature.
        for eta in [1.2f32, 1.5, 2.0] {
            let n = 10_000;
            let quadrature: f32 = (0..n)
                .map(|i| (i as f32 + 0.5) / n as f32)
                .map(|mu| 2.0 * fresnel_dielectric(mu, 1.0 / eta) * mu)
                .sum::<f32>()
                / n as f32;
            assert!((fresnel_diffuse_reflectance(eta) - quadrature).abs() < 0.002, "η {eta}: {quadrature}");
        }
    }

    #[test]
    fn sampling_matches_pdf_and_the_coat_by_hand() {
        let n = Vec3::new(0.2, 0.1, 1.0).normalize();
        for wo in [Vec3::new(0.3, -0.2, 0.9), Vec3::new(-0.9, 0.3, 0.2)] {
            let wo = wo.normalize();
            let bsdf = at(&plastic(0.6, false).bsdf(&Default::default(), wo, frame_toward(wo, n)));
            check_sampling(&bsdf, wo, n, 61);
            let f = fresnel_dielectric(wo.dot(n), 1.0 / 1.49);
            let mirror = bsdf.sample(wo, 0.9999, Vec2::ZERO).unwrap();
            assert!(mirror.delta && ((mirror.weight.x * mirror.pdf) - f).abs() < 1e-5);
        }
    }

    /// White furnace: a white base under a clear coat loses no light in Mitsuba's model only
    /// in the limit its approximations allow; with k_d = 1 the albedo stays ≤ 1 + the fit's error
    /// and with k_d = 0 it is the coat's Fresnel reflectance exactly.
    #[test]
    fn furnace_bounds() {
        let wo = Vec3::new(0.3, 0.0, 0.95).normalize();
        let black = at(&plastic(0.0, false).bsdf(&Default::default(), wo, frame_toward(wo, Vec3::Z)));
        let a = albedo(&black, wo, 20_000, 12);
        assert!((a.mean - fresnel_dielectric(wo.z, 1.0 / 1.49) as f64).abs() < 1e-5, "{a:?}");
        let white = at(&plastic(1.0, true).bsdf(&Default::default(), wo, frame_toward(wo, Vec3::Z)));
        let a = albedo(&white, wo, 200_000, 13);
        assert!(a.mean > 0.9 && a.mean < 1.02, "{a:?}");
    }

    /// Whitted's mirror carries the coat's specular·F(θ_o), and its Lambert term under the coat
    /// is π times the BSDF's diffuse part for each light (the coat crossed both ways).
    #[test]
    fn whitted_reads_the_bsdf() {
        let red = crate::materials::Material::Plastic(Plastic {
            diffuse: Texture::Constant(Rgb::new(0.6, 0.1, 0.1)),
            specular: Texture::Constant(Rgb::splat(0.9)),
            eta: 1.49,
            nonlinear: true,
        });
        for degrees in [0.0, 45.0, 80.0] {
            check_whitted(&red, true, degrees, 9);
        }
        let wo = Vec3::new(0.5, 0.3, 0.6).normalize();
        check_whitted_local(&red, wo, &[Vec3::Z, Vec3::new(-0.7, 0.1, 0.3).normalize(), Vec3::new(0.1, 0.99, 0.05)]);
    }
}
