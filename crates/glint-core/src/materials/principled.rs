//! Disney's principled BSDF (Burley 2012, 2015) as Mitsuba 3 defines it (`principled`): one
//! material that spans plastics, metals and glass by a handful of artist parameters.
//!
//! Scene parameters (each a number in [0, 1] or a texture's luminance, except `base_color`, a
//! colour or texture, and `eta`): `base_color` (0.5), `roughness` (0.5), `anisotropic` (0),
//! `metallic` (0), `spec_trans` (0), `specular` (0.5, which sets `eta` = 2 / (1 − √(0.08 ·
//! specular)) − 1) or `eta`, `spec_tint` (0), `sheen` (0), `sheen_tint` (0), `flatness` (0),
//! `clearcoat` (0), `clearcoat_gloss` (0).
//! ```toml
//! [materials.car-paint]
//! type = "principled"
//! base_color = [0.6, 0.05, 0.05]
//! metallic = 0.3
//! roughness = 0.35
//! clearcoat = 0.8
//! clearcoat_gloss = 0.9
//! ```
//! Lobes, weighted by brdf = (1 − metallic)(1 − spec_trans) and bsdf = (1 − metallic)·spec_trans:
//! * main specular reflection, GGX (α = roughness², stretched by √(1 − 0.9·anisotropic)) with
//!   separable masking, its Fresnel term the dielectric one blended with Schlick's for the
//!   metallic and tinted parts (from behind: bsdf·F, no tint);
//! * specular transmission, bsdf·√base_color·(1 − F) through the same microfacets (in glint's
//!   form without the radiance's η², as `rough_dielectric.rs`);
//! * clearcoat, 0.25·clearcoat·F_Schlick(0.04)·D_GTR1·G (α from 0.1 to 0.001 with the gloss,
//!   masking of width 0.25), front only;
//! * Burley's diffuse with retro-reflection (or, with `flatness`, toward the Hanrahan–Krueger
//!   fake subsurface), and sheen, front only.
//!
//! Sampling (Mitsuba's probabilities): diffuse ∝ brdf, clearcoat ∝ 0.25·clearcoat, specular
//! ∝ 1, split after its visible normal is drawn into reflection with 1 − bsdf·(1 − F) and
//! transmission with bsdf·(1 − F) (from behind: F and 1 − F). The same sums give the pdf, so
//! sampling and pdf agree exactly. Where brdf is 0 but sheen is not, the diffuse lobe keeps
//! the sheen's weight so that its directions can still be drawn. An anisotropic lobe's
//! tangent is the surface's ∂p/∂u (`Frame::along`).

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use super::bsdf::{BsdfSample, Frame, LaneBsdfSample, LaneFrame, Leaf, Lobes};
use super::microfacet::{refraction_half_vector, MicrofacetLanes};
use super::phong::fresnel_dielectric_lanes;
use super::{Distribution, Microfacet, PhongPoint};
use crate::lanes::{self, LaneVec3, Lanes};
use crate::sampling::warp::square_to_cosine_hemisphere_lanes;
use crate::textures::{Texture, TextureQuery};
use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct Principled {
    pub base_color: Texture,
    pub roughness: Texture,
    pub anisotropic: Texture,
    pub metallic: Texture,
    pub spec_trans: Texture,
    pub spec_tint: Texture,
    pub sheen: Texture,
    pub sheen_tint: Texture,
    pub flatness: Texture,
    pub clearcoat: Texture,
    pub clearcoat_gloss: Texture,
    /// n_interior / n_exterior.
    pub eta: f32,
}

impl Default for Principled {
    /// Mitsuba's defaults.
    fn default() -> Self {
        let grey = |v: f32| Texture::Constant(Rgb::splat(v));
        Self {
            base_color: grey(0.5),
            roughness: grey(0.5),
            anisotropic: grey(0.0),
            metallic: grey(0.0),
            spec_trans: grey(0.0),
            spec_tint: grey(0.0),
            sheen: grey(0.0),
            sheen_tint: grey(0.0),
            flatness: grey(0.0),
            clearcoat: grey(0.0),
            clearcoat_gloss: grey(0.0),
            eta: Self::eta_from_specular(0.5),
        }
    }
}

impl Principled {
    /// The index `specular` stands for: 0.5 is η = 1.5.
    pub fn eta_from_specular(specular: f32) -> f32 {
        2.0 / (1.0 - (0.08 * specular).sqrt()) - 1.0
    }

    pub(super) fn bsdf(&self, query: &TextureQuery, frame: Frame) -> Leaf<'static> {
        Leaf::Principled(self.evaluate(query, frame))
    }

    /// Its parameters where the query is (its textures read there).
    pub(crate) fn point(&self, query: &TextureQuery) -> PrincipledPoint {
        let scalar = |t: &Texture| t.evaluate(query).dot(LUMINANCE);
        let (roughness, anisotropic) = (scalar(&self.roughness), scalar(&self.anisotropic));
        let microfacet = disney_microfacet(roughness, anisotropic);
        let gloss = scalar(&self.clearcoat_gloss);
        PrincipledPoint {
            base: self.base_color.evaluate(query),
            roughness,
            metallic: scalar(&self.metallic),
            spec_trans: scalar(&self.spec_trans),
            spec_tint: scalar(&self.spec_tint),
            sheen: scalar(&self.sheen),
            sheen_tint: scalar(&self.sheen_tint),
            flatness: scalar(&self.flatness),
            clearcoat: scalar(&self.clearcoat),
            alpha_x: microfacet.alpha_x,
            alpha_y: microfacet.alpha_y,
            clearcoat_alpha: 0.1 + gloss * (0.001 - 0.1),
            eta: self.eta,
        }
    }

    fn evaluate(&self, query: &TextureQuery, frame: Frame) -> PrincipledBsdf {
        let point = self.point(query);
        // Anisotropic widths lie along the surface's ∂p/∂u.
        PrincipledBsdf { frame: if point.alpha_x != point.alpha_y { frame.along(query.dpdu) } else { frame }, point }
    }

    /// Whitted's view: the BSDF's lobes in their smooth limit (Whitted traces no glossy rays),
    /// at the viewer's angle θ (cosine `cos`), each weighed as the BSDF weighs it:
    /// * the mirror: the specular lobe's Fresnel term, the dielectric F(θ) at η blended with
    ///   Schlick's for the metallic and tinted parts, (1 − metallic)(1 − spec_tint)·F(θ) +
    ///   metallic·Schlick(base, θ) + (1 − metallic)·spec_tint·Schlick(tint·r₀, θ), plus the
    ///   clearcoat's albedo as its lobe narrows, clearcoat·Schlick(0.04, θ)·cos²θ;
    /// * the refraction, at index η: bsdf·√base·(1 − F(θ));
    /// * Burley's diffuse as Lambert's term, k_d = k_a = base·brdf (exact head-on, where
    ///   Burley's lobe is Lambert's; its retro-reflection, fake subsurface and the sheen, which
    ///   lean toward grazing angles, are left out).
    ///
    /// From behind (inside a transmitting principled material): bsdf·F reflected and
    /// bsdf·√base·(1 − F) refracted; black where it does not transmit. So a glTF material
    /// (metallic 0) is a diffuse base under a Fresnel mirror of 4 % head-on, not a mirror.
    pub(super) fn whitted(&self, query: &TextureQuery, outside: bool, cos: f32) -> PhongPoint {
        let cos = cos.clamp(0.0, 1.0);
        // The frame only tells the evaluated BSDF which side the viewer is on.
        let frame = Frame::new(Vec3::Z, Vec3::Z, if outside { Vec3::Z } else { -Vec3::Z });
        let b = self.evaluate(query, frame).lanes();
        if b.inactive() {
            return PhongPoint::BLACK;
        }
        let f = b.fresnel(cos);
        let mut reflection: Rgb = b.principled_fresnel(f, cos).into();
        let base: Rgb = b.base.into();
        let refracted = base.max(Rgb::ZERO).powf(0.5) * (b.bsdf_weight() * (1.0 - f));
        if !outside {
            return PhongPoint { reflection, transmission: refracted, ior: self.eta, ..PhongPoint::BLACK };
        }
        if b.clearcoat > 0.0 {
            reflection += Rgb::splat(b.clearcoat * schlick(Rgb::splat(0.04), cos, b.eta).x * cos * cos);
        }
        let diffuse = base * b.brdf();
        PhongPoint {
            ambient: diffuse,
            diffuse,
            reflection,
            transmission: refracted,
            ior: self.eta,
            ..PhongPoint::BLACK
        }
    }
}

/// Mitsuba's luminance of linear sRGB (its tints and scalar textures).
pub(super) const LUMINANCE: Rgb = Rgb::new(0.212671, 0.715160, 0.072169);

/// The base colour's hue at luminance 1 (white where it is black): what the tints lean to.
#[inline(always)]
pub(super) fn tint_lanes<L: Lanes>(base: LaneVec3<L>) -> LaneVec3<L> {
    let lum = base.dot(LaneVec3::splat(LUMINANCE));
    LaneVec3::select(lum.gt(L::ZERO), base.divided_by(lum), LaneVec3::splat(Rgb::ONE))
}

/// Burley's diffuse with retro-reflection, leaning by `flatness` toward the Hanrahan–Krueger
/// fake subsurface: the factor of base/π·cos θ_i for a reflection between `o` and `i` (local,
/// both above) with half vector `h`.
#[inline(always)]
pub(super) fn burley_diffuse_lanes<L: Lanes>(
    o: LaneVec3<L>,
    i: LaneVec3<L>,
    h: LaneVec3<L>,
    roughness: L,
    flatness: L,
) -> L {
    let c = L::splat;
    let (fo, fi) = (schlick_weight(o.z), schlick_weight(i.z));
    let cos_d = h.dot(i);
    let diffuse = (L::ONE - c(0.5) * fo) * (L::ONE - c(0.5) * fi);
    let rr = c(2.0) * roughness * cos_d * cos_d;
    let retro = rr * (fo + fi + fo * fi * (rr - L::ONE));
    let lobe = diffuse + retro;
    let fss90 = rr / c(2.0);
    let fss = (L::ONE + (fss90 - L::ONE) * fi) * (L::ONE + (fss90 - L::ONE) * fo);
    let subsurface = c(1.25) * (fss * (L::ONE / (i.z + o.z) - c(0.5)) + c(0.5));
    L::select(flatness.eq(L::ZERO), lobe, lobe + flatness * (subsurface - lobe))
}

/// The sheen's colour and Fresnel-like rise toward grazing, for a reflection whose half vector
/// makes cosine `cos_d` with the light: the factor of sheen·cos θ_i.
#[inline(always)]
pub(super) fn sheen_lanes<L: Lanes>(base: LaneVec3<L>, sheen_tint: L, cos_d: L) -> LaneVec3<L> {
    let one = LaneVec3::splat(Rgb::ONE);
    (one + (tint_lanes(base) - one) * sheen_tint) * schlick_weight(cos_d.abs())
}

/// The principled BSDF's parameters at a point: its textures read there.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PrincipledPoint {
    pub base: Rgb,
    pub roughness: f32,
    pub metallic: f32,
    pub spec_trans: f32,
    pub spec_tint: f32,
    pub sheen: f32,
    pub sheen_tint: f32,
    pub flatness: f32,
    pub clearcoat: f32,
    /// The main lobe's widths along ∂p/∂u and across it (`disney_microfacet`).
    pub alpha_x: f32,
    pub alpha_y: f32,
    pub clearcoat_alpha: f32,
    /// n_interior / n_exterior.
    pub eta: f32,
}

#[derive(Clone, Copy, Debug)]
pub(super) struct PrincipledBsdf {
    frame: Frame,
    point: PrincipledPoint,
}

/// GGX of width roughness², stretched along ∂p/∂u by 1/√(1 − 0.9·anisotropic) and narrowed
/// across it by as much (Burley 2012), never below 10⁻³; separable masking, as Mitsuba's.
pub(super) fn disney_microfacet(roughness: f32, anisotropic: f32) -> Microfacet {
    let aspect = (1.0 - 0.9 * anisotropic).max(0.0).sqrt();
    let r2 = roughness * roughness;
    Microfacet {
        alpha_x: (r2 / aspect).max(1e-3),
        alpha_y: (r2 * aspect).max(1e-3),
        separable: true,
        distribution: Distribution::Ggx,
    }
}

/// (1 − cos)⁵, clamped: Schlick's weight.
#[inline(always)]
pub(super) fn schlick_weight<L: Lanes>(cos: L) -> L {
    let m = (L::ONE - cos).max(L::ZERO).min(L::ONE);
    (m * m) * (m * m) * m
}

/// Schlick's Fresnel from the front of an interface of relative index `eta` (n_t / n_i): with
/// the incident cosine when η > 1, else with the transmitted one (1 past the critical angle).
pub(super) fn schlick(r0: Rgb, cos_i: f32, eta: f32) -> Rgb {
    schlick_lanes(LaneVec3::<f32>::from(r0), cos_i, eta).into()
}

/// `schlick` in lanes.
#[inline(always)]
pub(super) fn schlick_lanes<L: Lanes>(r0: LaneVec3<L>, cos_i: L, eta: L) -> LaneVec3<L> {
    let transmitted = (L::ONE - (L::ONE - cos_i * cos_i) / (eta * eta)).max(L::ZERO).sqrt();
    let cos = L::select(eta.gt(L::ONE), cos_i.abs(), transmitted);
    r0 + (LaneVec3::splat(Rgb::ONE) - r0) * schlick_weight(cos)
}

/// Smith's G1 for isotropic GGX of width `alpha`, 0 where `v` sees the back of the microfacet
/// `h` (the clearcoat's masking).
#[inline(always)]
fn smith_g1<L: Lanes>(v: LaneVec3<L>, h: LaneVec3<L>, alpha: f32) -> L {
    let cos2 = v.z * v.z;
    let tan2 = (L::ONE - cos2) / cos2;
    let g1 = L::splat(2.0) / (L::ONE + (L::ONE + L::splat(alpha * alpha) * tan2).sqrt());
    L::select((v.dot(h) * v.z).le(L::ZERO), L::ZERO, L::select(cos2.ge(L::ONE), L::ONE, g1))
}

/// The clearcoat's micro-normals: Burley's GTR with γ = 1 (Berry's distribution), sampled
/// exactly by its cos θ_h-weighted density (not by visible normals: its lobe is weak).
#[derive(Clone, Copy, Debug)]
struct Gtr1<L> {
    alpha: L,
}

impl<L: Lanes> Gtr1<L> {
    #[inline(always)]
    fn d(self, h: LaneVec3<L>) -> L {
        let a2 = self.alpha * self.alpha;
        let d = (a2 - L::ONE) / (L::splat(PI) * lanes::ln(a2) * (L::ONE + (a2 - L::ONE) * h.z * h.z));
        L::select((d * h.z).gt(L::splat(1e-20)), d, L::ZERO)
    }

    /// Density of `sample`'s micro-normal per solid angle: D(h) cos θ_h.
    #[inline(always)]
    fn pdf(self, h: LaneVec3<L>) -> L {
        L::select(h.z.lt(L::ZERO), L::ZERO, h.z * self.d(h))
    }

    /// cos²θ_h = (1 − α^(2(1 − u₂))) / (1 − α²), φ = 2π u₁.
    #[inline(always)]
    fn sample(self, u1: L, u2: L) -> LaneVec3<L> {
        let a2 = self.alpha * self.alpha;
        let power = lanes::exp(lanes::ln(a2) * (L::ONE - u2));
        let cos2 = ((L::ONE - power) / (L::ONE - a2)).max(L::ZERO).min(L::ONE);
        let (sin, cos) = ((L::ONE - cos2).sqrt(), cos2.sqrt());
        let (sin_phi, cos_phi) = lanes::sin_cos_turns(u1);
        LaneVec3::new(cos_phi * sin, sin_phi * sin, cos)
    }
}

/// The lobe probabilities at one micro-normal's Fresnel reflectance `f`.
struct Choice<L> {
    diffuse: L,
    clearcoat: L,
    reflection: L,
    transmission: L,
}

/// The principled BSDF at a hit, in lanes: the one body of its `eval`, `pdf` and `sample`,
/// which the scalar BSDF runs at one lane and the wavefront at eight. The scalar code's
/// branches on the parameters (no clearcoat, no sheen, no flatness) are selects here.
#[derive(Clone, Debug)]
pub(crate) struct PrincipledLanes<L: Lanes> {
    pub frame: LaneFrame<L>,
    pub base: LaneVec3<L>,
    pub roughness: L,
    pub metallic: L,
    pub spec_trans: L,
    pub spec_tint: L,
    pub sheen: L,
    pub sheen_tint: L,
    pub flatness: L,
    pub clearcoat: L,
    pub microfacet: MicrofacetLanes<L>,
    pub clearcoat_alpha: L,
    /// n_interior / n_exterior.
    pub eta: L,
}

impl<L: Lanes> PrincipledLanes<L> {
    /// The lanes' BSDF from their points (`point(k)` for lane k) in `frame` (already turned to
    /// ∂p/∂u where the widths differ).
    #[inline(always)]
    pub fn gather<'p>(frame: LaneFrame<L>, point: impl Fn(usize) -> &'p PrincipledPoint) -> Self {
        let each = |f: fn(&PrincipledPoint) -> f32| L::from_fn(|k| f(point(k)));
        Self {
            frame,
            base: LaneVec3::gather(|k| point(k).base),
            roughness: each(|p| p.roughness),
            metallic: each(|p| p.metallic),
            spec_trans: each(|p| p.spec_trans),
            spec_tint: each(|p| p.spec_tint),
            sheen: each(|p| p.sheen),
            sheen_tint: each(|p| p.sheen_tint),
            flatness: each(|p| p.flatness),
            clearcoat: each(|p| p.clearcoat),
            microfacet: MicrofacetLanes {
                alpha_x: each(|p| p.alpha_x),
                alpha_y: each(|p| p.alpha_y),
                separable: true,
                distribution: Distribution::Ggx,
            },
            clearcoat_alpha: each(|p| p.clearcoat_alpha),
            eta: each(|p| p.eta),
        }
    }

    #[inline(always)]
    fn brdf(&self) -> L {
        (L::ONE - self.metallic) * (L::ONE - self.spec_trans)
    }

    #[inline(always)]
    fn bsdf_weight(&self) -> L {
        (L::ONE - self.metallic) * self.spec_trans
    }

    /// Nothing to sample or evaluate: from behind without transmission.
    #[inline(always)]
    pub fn inactive(&self) -> L::Mask {
        !self.frame.outside & self.bsdf_weight().le(L::ZERO)
    }

    /// n(the other side) / n(the viewer's side).
    #[inline(always)]
    fn eta_path(&self) -> L {
        L::select(self.frame.outside, self.eta, L::ONE / self.eta)
    }

    /// The diffuse lobe's sampling weight: brdf, or the sheen's where brdf is 0.
    #[inline(always)]
    fn diffuse_weight(&self) -> L {
        let brdf = self.brdf();
        L::select(brdf.gt(L::ZERO), brdf, self.sheen.max(L::ZERO) * (L::ONE - self.metallic).max(L::ZERO))
    }

    #[inline(always)]
    fn choice(&self, f: L) -> Choice<L> {
        let bsdf = self.bsdf_weight();
        let (diffuse, clearcoat) = (self.diffuse_weight(), L::splat(0.25) * self.clearcoat.max(L::ZERO));
        let total = L::ONE + diffuse + clearcoat;
        let transmission = bsdf * (L::ONE - f);
        let outside = self.frame.outside;
        Choice {
            diffuse: L::select(outside, diffuse / total, L::ZERO),
            clearcoat: L::select(outside, clearcoat / total, L::ZERO),
            reflection: L::select(outside, (L::ONE - transmission) / total, f),
            transmission: L::select(outside, transmission / total, L::ONE - f),
        }
    }

    /// The dielectric Fresnel reflectance at a micro-normal seen at cosine `cos` from the
    /// viewer's side.
    #[inline(always)]
    pub fn fresnel(&self, cos: L) -> L {
        fresnel_dielectric_lanes(cos, L::ONE / self.eta_path())
    }

    /// The main reflection's Fresnel term: the dielectric one blended with Schlick's for the
    /// metallic part and for the part tinted toward the base colour; from behind, bsdf·F.
    #[inline(always)]
    pub fn principled_fresnel(&self, f: L, cos: L) -> LaneVec3<L> {
        let m = self.metallic;
        let tint = tint_lanes(self.base);
        let r0 = (self.eta - L::ONE) / (self.eta + L::ONE);
        let r0 = r0 * r0;
        let front = LaneVec3::new(L::ONE, L::ONE, L::ONE) * ((L::ONE - m) * (L::ONE - self.spec_tint) * f)
            + schlick_lanes(self.base, cos, self.eta) * m
            + schlick_lanes(tint * r0, cos, self.eta) * ((L::ONE - m) * self.spec_tint);
        let behind = self.bsdf_weight() * f;
        LaneVec3::select(self.frame.outside, front, LaneVec3::new(behind, behind, behind))
    }

    /// Burley's diffuse, retro-reflection and fake subsurface, and the sheen (both ·cos θ_i),
    /// for a reflection with half vector `h` (front only).
    #[inline(always)]
    fn diffuse_and_sheen(&self, o: LaneVec3<L>, i: LaneVec3<L>, h: LaneVec3<L>) -> LaneVec3<L> {
        let brdf = self.brdf();
        let burley = burley_diffuse_lanes(o, i, h, self.roughness, self.flatness);
        let diffuse = self.base * (brdf * i.z / L::splat(PI) * burley);
        let value = LaneVec3::select(brdf.gt(L::ZERO), LaneVec3::ZERO + diffuse, LaneVec3::ZERO);
        let sheen = sheen_lanes(self.base, self.sheen_tint, h.dot(i)) * (self.sheen * (L::ONE - self.metallic) * i.z);
        let sheened = self.sheen.gt(L::ZERO) & self.metallic.lt(L::ONE);
        LaneVec3::select(sheened, value + sheen, value)
    }

    #[inline(always)]
    fn clearcoat_value(&self, o: LaneVec3<L>, i: LaneVec3<L>, h: LaneVec3<L>) -> L {
        let c = L::splat;
        let f = schlick_lanes(LaneVec3::new(c(0.04), c(0.04), c(0.04)), o.dot(h), self.eta).x;
        let g = smith_g1(o, h, 0.25) * smith_g1(i, h, 0.25);
        let value = c(0.25) * self.clearcoat * f * Gtr1 { alpha: self.clearcoat_alpha }.d(h) * g * i.z;
        L::select(self.clearcoat.le(L::ZERO), L::ZERO, value)
    }

    #[inline(always)]
    pub fn eval(&self, wo: LaneVec3<L>, wi: LaneVec3<L>) -> LaneVec3<L> {
        let (o, i) = (self.frame.to_local(wo), self.frame.to_local(wi));
        let h = (o + i).normalize();
        let f = self.fresnel(o.dot(h));
        let glossy = self.principled_fresnel(f, o.dot(h)) * self.microfacet.reflection_eval(o, i);
        let clearcoat = self.clearcoat_value(o, i, h);
        let front = glossy + (self.diffuse_and_sheen(o, i, h) + LaneVec3::new(clearcoat, clearcoat, clearcoat));
        let reflected = LaneVec3::select(self.frame.outside, front, glossy);
        let bsdf = self.bsdf_weight();
        let eta = L::ONE / self.eta_path();
        let (h, through) = refraction_half_vector(o, i, eta);
        let f = self.fresnel(o.dot(h));
        let root = LaneVec3::new(
            self.base.x.max(L::ZERO).sqrt(),
            self.base.y.max(L::ZERO).sqrt(),
            self.base.z.max(L::ZERO).sqrt(),
        );
        let refracted = root * (bsdf * (L::ONE - f) * self.microfacet.transmission_eval(o, i, eta));
        let refracted =
            LaneVec3::select(self.frame.transmits(wi) & bsdf.gt(L::ZERO) & through, refracted, LaneVec3::ZERO);
        let value = LaneVec3::select(self.frame.reflects(wi), reflected, refracted);
        LaneVec3::select(self.inactive() | o.z.le(L::ZERO), LaneVec3::ZERO, value)
    }

    #[inline(always)]
    pub fn pdf(&self, wo: LaneVec3<L>, wi: LaneVec3<L>) -> L {
        let (o, i) = (self.frame.to_local(wo), self.frame.to_local(wi));
        let h = (o + i).normalize();
        let p = self.choice(self.fresnel(o.dot(h)));
        let glossy = p.reflection * self.microfacet.reflection_pdf(o, i);
        let front = glossy + p.diffuse * i.z / L::splat(PI);
        let front = front + p.clearcoat * Gtr1 { alpha: self.clearcoat_alpha }.pdf(h) / (L::splat(4.0) * i.dot(h));
        let reflected = L::select(self.frame.outside, front, glossy);
        let eta = L::ONE / self.eta_path();
        let (h, through) = refraction_half_vector(o, i, eta);
        let refracted = self.choice(self.fresnel(o.dot(h))).transmission * self.microfacet.transmission_pdf(o, i, eta);
        let refracted = L::select(self.frame.transmits(wi) & through, refracted, L::ZERO);
        let pdf = L::select(self.frame.reflects(wi), reflected, refracted);
        L::select(self.inactive() | o.z.le(L::ZERO), L::ZERO, pdf)
    }

    /// The diffuse lobe, the clearcoat or the main lobe by `u_lobe`; the main lobe's visible
    /// micro-normal then reflects or refracts by the rest of `u_lobe` against its Fresnel
    /// term. A microfacet's reflection below the surface (or refraction above it) is lost
    /// light, not a sample of another lobe.
    #[inline(always)]
    pub fn sample(&self, wo: LaneVec3<L>, u_lobe: L, u1: L, u2: L) -> LaneBsdfSample<L> {
        let o = self.frame.to_local(wo);
        // The lobe-independent part of the choice (any Fresnel value gives the same sums).
        let p = self.choice(L::ZERO);
        let diffuse = u_lobe.lt(p.diffuse);
        let clearcoat = !diffuse & u_lobe.lt(p.diffuse + p.clearcoat);
        let h = self.microfacet.sample_normal(o, u1, u2);
        let specular = L::ONE - p.diffuse - p.clearcoat;
        let at = self.choice(self.fresnel(o.dot(h)));
        // The rest of `u_lobe` splits the specular share by this micro-normal's Fresnel.
        let mirrored = (u_lobe - p.diffuse - p.clearcoat).lt(at.reflection.min(specular));
        let (refracted, refracts) = lanes::refract(-o, h, L::ONE / self.eta_path());
        let glossy = LaneVec3::select(mirrored, lanes::reflect(-o, h), refracted);
        let coat = lanes::reflect(-o, Gtr1 { alpha: self.clearcoat_alpha }.sample(u1, u2));
        let local = LaneVec3::select(
            diffuse,
            square_to_cosine_hemisphere_lanes(u1, u2),
            LaneVec3::select(clearcoat, coat, glossy),
        );
        let reflected = diffuse | clearcoat | mirrored;
        let wi = self.frame.to_world(local);
        let transmits = self.frame.transmits(wi);
        let kept = (reflected & self.frame.reflects(wi)) | (!reflected & refracts & transmits);
        let valid = !(self.inactive() | o.z.le(L::ZERO)) & kept;
        let eta_path = self.eta_path();
        let eta_squared = L::select(transmits, eta_path * eta_path, L::ONE);
        LaneBsdfSample::weighed(wi, self.eval(wo, wi), self.pdf(wo, wi), valid, eta_squared)
    }
}

impl PrincipledBsdf {
    /// The lobe as its one body reads it.
    #[inline(always)]
    fn lanes(&self) -> PrincipledLanes<f32> {
        PrincipledLanes::gather(LaneFrame::from(&self.frame), |_| &self.point)
    }
}

impl Lobes for PrincipledBsdf {
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
        if self.lanes().inactive() {
            0.0
        } else {
            1.0
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
    use crate::materials::testing::{albedo, albedo_by_quadrature, at, check_sampling, check_whitted, frame_toward};
    use crate::materials::{Dielectric, Material, RoughDielectric};

    fn grey(v: f32) -> Texture {
        Texture::Constant(Rgb::splat(v))
    }

    /// A plastic with every front lobe, a tinted anisotropic half-metal, and a glass.
    fn members() -> Vec<(&'static str, Principled)> {
        vec![
            (
                "coated plastic",
                Principled {
                    base_color: Texture::Constant(Rgb::new(0.2, 0.8, 0.1)),
                    roughness: grey(0.3),
                    clearcoat: grey(0.9),
                    clearcoat_gloss: grey(0.5),
                    sheen: grey(0.6),
                    sheen_tint: grey(0.5),
                    flatness: grey(0.3),
                    ..Principled::default()
                },
            ),
            (
                "brushed half-metal",
                Principled {
                    base_color: Texture::Constant(Rgb::new(0.9, 0.6, 0.3)),
                    roughness: grey(0.4),
                    anisotropic: grey(0.7),
                    metallic: grey(0.6),
                    spec_tint: grey(0.4),
                    ..Principled::default()
                },
            ),
            (
                "frosted glass",
                Principled {
                    base_color: Texture::Constant(Rgb::new(0.8, 0.9, 1.0)),
                    roughness: grey(0.5),
                    spec_trans: grey(0.7),
                    clearcoat: grey(0.5),
                    ..Principled::default()
                },
            ),
        ]
    }

    /// Over the whole sphere, from the front and (where it transmits) from behind.
    #[test]
    fn sampling_matches_pdf() {
        let n = Vec3::new(0.1, -0.2, 1.0).normalize();
        for (k, (name, m)) in members().into_iter().enumerate() {
            let mut views = vec![Vec3::new(0.4, -0.3, 0.8), Vec3::new(0.9, 0.1, 0.2)];
            if name == "frosted glass" {
                views.push(Vec3::new(-0.3, 0.2, -0.9));
            }
            for wo in views {
                let wo = wo.normalize();
                let bsdf = at(&m.bsdf(&Default::default(), frame_toward(wo, n)));
                check_sampling(&bsdf, wo, n, 61 + k as u64);
            }
        }
    }

    /// The albedo by sampling equals the albedo by quadrature of `eval` (the two agree only if
    /// sampling, pdf and eval do); a white metal and a clear glass lose energy only to single
    /// scattering (≤ 1, near 1 when smooth).
    #[test]
    fn albedo_by_sampling_equals_quadrature_and_white_members_conserve_energy() {
        let wo = Vec3::new(0.3, 0.0, 0.95).normalize();
        for (name, m) in members() {
            let bsdf = at(&m.bsdf(&Default::default(), frame_toward(wo, Vec3::Z)));
            let a = albedo(&bsdf, wo, 200_000, 7);
            let q = albedo_by_quadrature(&bsdf, wo);
            assert!((a.mean - q).abs() < 5.0 * a.standard_error + 0.015 * q, "{name}: sampled {a:?}, quadrature {q}");
        }
        let metal =
            Principled { base_color: grey(1.0), metallic: grey(1.0), roughness: grey(0.2), ..Default::default() };
        let glass =
            Principled { base_color: grey(1.0), spec_trans: grey(1.0), roughness: grey(0.2), ..Default::default() };
        for (name, m) in [("metal", metal), ("glass", glass)] {
            for wo in [wo, Vec3::new(0.2, 0.1, -0.97).normalize()] {
                if name == "metal" && wo.z < 0.0 {
                    continue;
                }
                let bsdf = at(&m.bsdf(&Default::default(), frame_toward(wo, Vec3::Z)));
                let a = albedo(&bsdf, wo, 200_000, 8);
                assert!(a.mean < 1.0 + 4.0 * a.standard_error && a.mean > 0.95, "{name} from {wo}: {a:?}");
            }
        }
    }

    /// With only transmission turned on, white and untinted, the principled BSDF is rough glass
    /// of width roughness²: its value and pdf equal `RoughDielectric`'s for every pair of
    /// directions, from outside and from inside.
    #[test]
    fn full_transmission_is_rough_dielectric() {
        let m = Principled { base_color: grey(1.0), spec_trans: grey(1.0), roughness: grey(0.6), ..Default::default() };
        let glass = RoughDielectric {
            dielectric: Dielectric { eta: m.eta, specular_reflectance: grey(1.0), specular_transmittance: grey(1.0) },
            alpha_u: 0.36.into(),
            alpha_v: 0.36.into(),
            distribution: Distribution::Ggx,
        };
        let mut rng = crate::sampling::Rng::new(3, 3);
        let mut sphere = || {
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            crate::sampling::warp::square_to_uniform_sphere(u)
        };
        for _ in 0..2000 {
            let (wo, wi) = (sphere(), sphere());
            let frame = frame_toward(wo, Vec3::Z);
            let (a, b) = (at(&m.bsdf(&Default::default(), frame)), at(&glass.bsdf(&Default::default(), frame)));
            let (fa, fb) = (a.eval(wo, wi), b.eval(wo, wi));
            assert!((fa - fb).abs().max_element() <= 1e-4 * fb.max_element().max(1e-3), "{wo} {wi}: {fa} vs {fb}");
            let (pa, pb) = (a.pdf(wo, wi), b.pdf(wo, wi));
            assert!((pa - pb).abs() <= 1e-4 * pb.max(1e-3), "{wo} {wi}: pdf {pa} vs {pb}");
        }
    }

    /// Values by hand. A smooth (roughness 0) dielectric seen head-on, lit from 60°: the
    /// microfacet lobe is a spike elsewhere, Rr = 0, F_i = 0, F_o = (1 − ½)⁵ = 1/32, so
    /// f·cos = base/π·(1 − 1/64)·½. A metal (F = base by Schlick head-on) seen and lit head-on:
    /// D(z) = 1/(πα²), G = 1, so f·cos = base/(4πα²).
    #[test]
    fn diffuse_and_metal_values_by_hand() {
        let base = Rgb::new(0.2, 0.5, 0.7);
        let plastic = Principled { base_color: Texture::Constant(base), roughness: grey(0.0), ..Default::default() };
        let frame = frame_toward(Vec3::Z, Vec3::Z);
        let wi = Vec3::new(60f32.to_radians().sin(), 0.0, 0.5);
        let value = at(&plastic.bsdf(&Default::default(), frame)).eval(Vec3::Z, wi);
        let expected = base / PI * (63.0 / 64.0) * 0.5;
        assert!((value - expected).abs().max_element() < 1e-5, "{value} vs {expected}");

        let metal = Principled {
            base_color: Texture::Constant(base),
            roughness: grey(0.5),
            metallic: grey(1.0),
            ..Default::default()
        };
        let value = at(&metal.bsdf(&Default::default(), frame)).eval(Vec3::Z, Vec3::Z);
        let alpha = 0.25;
        let expected = base / (4.0 * PI * alpha * alpha);
        assert!((value - expected).abs().max_element() < 1e-4 * expected.max_element(), "{value} vs {expected}");
    }

    /// Mitsuba's map from `specular` to η.
    #[test]
    fn specular_half_is_eta_one_and_a_half() {
        assert!((Principled::eta_from_specular(0.5) - 1.5).abs() < 1e-6);
        assert!(Principled::eta_from_specular(1.0) > Principled::eta_from_specular(0.5));
    }

    /// The clearcoat's GTR1 is normalised (∫ D cos θ_h dω_h = 1) and sampled by its pdf: by
    /// chi-square where the cells resolve the peak, and, for the glossiest coat (α = 0.001,
    /// a peak 10⁻⁶ wide in cos θ), by the mean of cos θ_h against quadrature.
    #[test]
    fn gtr1_is_normalised_and_sampled_by_its_pdf() {
        for alpha in [0.1f32, 0.01, 0.001] {
            let gtr1 = Gtr1 { alpha };
            let d = (|h: Vec3| gtr1.pdf(h.into()), |u: Vec2| -> Vec3 { gtr1.sample(u.x, u.y).into() });
            // Quadrature in z = cos θ_h, fine enough near z = 1 for the peak: substitute
            // z = 1 − s³, so the nodes crowd toward the pole.
            let n = 400_000;
            let (mut integral, mut mean) = (0.0f64, 0.0f64);
            for k in 0..n {
                let s = (k as f64 + 0.5) / n as f64;
                let z = 1.0 - s * s * s;
                let dz = 3.0 * s * s / n as f64;
                let w = ((d.0)(Vec3::new((1.0 - z * z).max(0.0).sqrt() as f32, 0.0, z as f32)) as f64)
                    * 2.0
                    * std::f64::consts::PI
                    * dz;
                integral += w;
                mean += w * z;
            }
            assert!((integral - 1.0).abs() < 2e-3, "alpha {alpha}: {integral}");
            let mut rng = crate::sampling::Rng::new(6, 1);
            let samples = 200_000;
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for _ in 0..samples {
                let z = (d.1)(Vec2::new(rng.next_f32(), rng.next_f32())).z as f64;
                sum += z;
                sum2 += z * z;
            }
            let sampled = sum / samples as f64;
            let error = ((sum2 / samples as f64 - sampled * sampled) / samples as f64).sqrt();
            assert!((sampled - mean).abs() < 5.0 * error + 1e-5, "alpha {alpha}: {sampled} vs {mean}");
            if alpha >= 0.1 {
                let r = crate::sampling::chi2::chi2_test_with_resolution(
                    |u| Some((d.1)(u)),
                    |w| (d.0)(w) as f64,
                    300_000,
                    21,
                    41,
                    5,
                    24,
                );
                assert!(r.p_value > 0.01, "alpha {alpha}: p = {}", r.p_value);
            }
        }
    }

    /// Whitted reads the BSDF's smooth limit (roughness 0): the mirror with the specular lobe's
    /// blended Fresnel term, the refraction with bsdf·√base·(1 − F), from outside and inside.
    /// With metallic 0 and no transmission (glTF's default material) the mirror carries the
    /// dielectric F(θ), 4 % head-on: not 1.
    #[test]
    fn whitted_reads_the_bsdfs_smooth_limit() {
        let smooth = |p: Principled| Material::Principled(Box::new(Principled { roughness: grey(0.0), ..p }));
        let cases = [
            // glTF's default material, its base black to leave the mirror alone.
            smooth(Principled { base_color: grey(0.0), ..Default::default() }),
            smooth(Principled {
                base_color: Texture::Constant(Rgb::new(0.9, 0.6, 0.3)),
                metallic: grey(1.0),
                ..Default::default()
            }),
            // Tinted, part metal, part glass.
            smooth(Principled {
                base_color: Texture::Constant(Rgb::new(0.2, 0.5, 0.9)),
                metallic: grey(0.4),
                spec_tint: grey(0.7),
                spec_trans: grey(1.0),
                ..Default::default()
            }),
            smooth(Principled {
                base_color: Texture::Constant(Rgb::new(0.9, 1.0, 0.8)),
                spec_trans: grey(1.0),
                ..Default::default()
            }),
        ];
        for m in &cases {
            for degrees in [0.0, 40.0, 75.0] {
                check_whitted(m, true, degrees, 11);
            }
            // From inside, past the critical angle too (41.8°).
            for degrees in [0.0, 30.0, 60.0] {
                check_whitted(m, false, degrees, 12);
            }
        }
        // The clearcoat's GTR1 lobe narrows only logarithmically (at the glossiest, α = 10⁻³,
        // half its light leaves beyond 3°): its mirror weight, clearcoat·F(θ)·cos²θ, is the
        // limit its albedo approaches from below, 87 % of it reached at that gloss.
        for degrees in [0.0f32, 30.0, 60.0] {
            let wo = Vec3::new(degrees.to_radians().sin(), 0.0, degrees.to_radians().cos());
            let coated = |clearcoat: f32| Principled {
                base_color: grey(0.0),
                roughness: grey(0.0),
                clearcoat: grey(clearcoat),
                clearcoat_gloss: grey(1.0),
                ..Default::default()
            };
            let q = TextureQuery::default();
            let albedo_of = |p: &Principled| albedo(&at(&p.bsdf(&q, frame_toward(wo, Vec3::Z))), wo, 200_000, 14).mean;
            let lobe = albedo_of(&coated(1.0)) - albedo_of(&coated(0.0));
            let whitted = |p: Principled| p.whitted(&q, true, wo.z).reflection.x as f64;
            let mirror = whitted(coated(1.0)) - whitted(coated(0.0));
            assert!(lobe < mirror && lobe > 0.8 * mirror, "at {degrees}°: albedo {lobe}, Whitted's mirror {mirror}");
        }
        let coat = Material::Principled(Box::new(Principled { roughness: grey(1.0), ..Default::default() }));
        let w = coat.whitted_at(&TextureQuery::default(), true, 1.0);
        assert!((w.reflection - Rgb::splat(0.04)).abs().max_element() < 1e-6, "{w:?}");
        assert_eq!((w.diffuse, w.ambient), (Rgb::splat(0.5), Rgb::splat(0.5)));
    }
}
