//! The one BSDF contract every integrator reads, and the dispatch over the closed set.
//!
//! Convention (one place, as Mitsuba's): directions are in world space and point away from
//! the surface; `eval(wo, wi)` returns f(wo, wi)·|cos θ_i| (the cosine included); `sample`
//! returns wi with the weight f·|cos θ_i| / pdf, so the caller multiplies its throughput by it;
//! `pdf(wo, wi)` is the solid-angle density of `sample` for the non-delta part.
//!
//! Lobe choice: `sample(wo, u_lobe, u)` picks a non-delta lobe exactly when `u_lobe` is below
//! `non_delta_probability()`, so `sample_non_delta` and `sample_delta` (photon mapping follows
//! the delta lobes and estimates the rest from photons) work for every member, mixtures too.
//!
//! A BSDF at a hit is a `Leaf` (one member of the set, evaluated: colours looked up, its frame
//! turned to `wo`'s side) or a `Mixture` of up to `MAX_LEAVES` weighted leaves (blend and mask
//! flatten into one). A leaf lives on the stack; a mixture is boxed (see `Kind`).

use glam::{Vec2, Vec3};

use super::conductor::ConductorBsdf;
use super::dielectric::DielectricBsdf;
use super::diffuse::DiffuseBsdf;
use super::diffuse_transmission::DiffuseTransmissionBsdf;
use super::fresnel_plastic::FresnelPlasticBsdf;
use super::mask::NullBsdf;
use super::mixed::MixedBsdf;
use super::plastic::PlasticBsdf;
use super::principled::PrincipledBsdf;
use super::principled_thin::PrincipledThinBsdf;
use super::rough_conductor::RoughConductorBsdf;
use super::rough_dielectric::RoughDielectricBsdf;
use super::rough_plastic::RoughPlasticBsdf;
use super::thin_dielectric::ThinDielectricBsdf;
use crate::geometry::orthonormal_basis_lanes;
use crate::lanes::{LaneVec3, Lanes};
use crate::Rgb;

/// The most leaves one BSDF flattens into (a blend of blends, masks): the scene builder refuses
/// materials that need more.
pub const MAX_LEAVES: usize = 4;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    pub wi: Vec3,
    /// f·|cos θ_i| / pdf (for a delta lobe: its weight / its selection probability).
    pub weight: Rgb,
    /// Solid-angle pdf for a non-delta lobe; the selection probability for a delta lobe.
    pub pdf: f32,
    /// Mirror or refraction: a direction no light sampling could have produced.
    pub delta: bool,
    /// η² picked up by refraction (for Russian roulette on radiance, as Mitsuba does).
    pub eta_squared: f32,
}

/// The weight of a lobe's colour in choosing it (never 0 for a colour that is not black).
pub(crate) fn luminance(c: Rgb) -> f32 {
    c.dot(Rgb::new(0.2126, 0.7152, 0.0722)).max(c.max_element() * 1e-3)
}

/// The shading frame at a hit, turned to the side `wo` is on.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    /// Shading normal on `wo`'s side (the geometric normal where the shading normal faces away
    /// from the viewer), and the tangents completing the frame.
    pub normal: Vec3,
    pub tangent: Vec3,
    pub bitangent: Vec3,
    /// Geometric normal on `wo`'s side (light may not leak through the surface).
    pub geometric: Vec3,
    /// `wo` is on the side the geometric normal points to (as the shape defines it): the
    /// front of one-sided BSDFs, the outside of dielectrics.
    pub outside: bool,
    /// Where a normal or bump map tilted `normal`: the shading normal it tilted (on `normal`'s
    /// side) and the shadowing's α² (0: no map, no shadowing). See `terminator_shadowing`.
    pub unmapped: Vec3,
    pub shadowing_alpha2: f32,
}

impl Frame {
    /// The frame at a hit: `wo` toward the viewer, `shading_normal` and `geometric_normal` as
    /// the shape defines them (not yet turned).
    pub fn new(wo: Vec3, shading_normal: Vec3, geometric_normal: Vec3) -> Self {
        let frame = LaneFrame::<f32>::new(wo.into(), shading_normal.into(), geometric_normal.into());
        Self {
            normal: frame.normal.into(),
            tangent: frame.tangent.into(),
            bitangent: frame.bitangent.into(),
            geometric: frame.geometric.into(),
            outside: frame.outside,
            unmapped: Vec3::ZERO,
            shadowing_alpha2: 0.0,
        }
    }

    /// The frame of a normal mapped from `unmapped` (the surface's own shading normal), with
    /// the map's shadowing (Conty Estevez et al. 2019, "A Microfacet-Based Shadowing Function
    /// to Solve the Bump Terminator Problem", as Mitsuba's `normalmap` and `bumpmap` apply
    /// it): a mapped normal tilted by θ_d from `unmapped` stands for microfacets of GGX
    /// roughness α² = min(1, tan²θ_d / 8), and light arriving at θ_i from `unmapped` is
    /// shadowed by their G1 = 2 / (1 + √(1 + α² tan²θ_i)). Smooth maps lose nothing (α² = 0);
    /// steep ones no longer light the surface past its terminator.
    pub fn with_map_shadowing(mut self, unmapped: Vec3) -> Self {
        let shadowing = MapShadowing::<f32>::new(self.normal.into(), unmapped.into());
        self.unmapped = shadowing.unmapped.into();
        self.shadowing_alpha2 = shadowing.alpha2;
        self
    }

    /// The map's shadowing of light from `wi` (1 where there is no map).
    #[inline(always)]
    pub fn terminator_shadowing(&self, wi: Vec3) -> f32 {
        if self.shadowing_alpha2 == 0.0 {
            return 1.0;
        }
        MapShadowing { unmapped: self.unmapped.into(), alpha2: self.shadowing_alpha2 }.of(wi.into())
    }

    /// The same frame with its tangent along `dpdu` projected onto the plane of the normal
    /// (Gram–Schmidt, as Mitsuba's shading frame), the bitangent n × tangent; unchanged where
    /// `dpdu` is zero or along the normal.
    pub fn along(mut self, dpdu: Vec3) -> Self {
        if let Some(tangent) = tangent_along(self.normal, dpdu) {
            self.tangent = tangent;
            self.bitangent = self.normal.cross(tangent);
        }
        self
    }

    pub fn to_local(&self, w: Vec3) -> Vec3 {
        Vec3::new(w.dot(self.tangent), w.dot(self.bitangent), w.dot(self.normal))
    }

    pub fn to_world(&self, v: Vec3) -> Vec3 {
        v.x * self.tangent + v.y * self.bitangent + v.z * self.normal
    }

    /// `wi` leaves on the viewer's side of both normals (a reflection, not a leak).
    pub fn reflects(&self, wi: Vec3) -> bool {
        wi.dot(self.normal) > 0.0 && wi.dot(self.geometric) > 0.0
    }

    /// The probability a one-sided member's sampling picks its non-delta lobes when they are
    /// all it has: 1 from the front, 0 from behind (where it is black).
    pub fn front_only(&self) -> f32 {
        if self.outside {
            1.0
        } else {
            0.0
        }
    }

    /// `wi` goes through to the other side of both normals.
    pub fn transmits(&self, wi: Vec3) -> bool {
        wi.dot(self.normal) < 0.0 && wi.dot(self.geometric) < 0.0
    }
}

/// The unit part of `dpdu` in the plane of `normal` (Gram–Schmidt); `None` where `dpdu` is
/// zero or along the normal.
/// A shading frame in lanes: `Frame`'s frame (turned to `wo`'s side) as the lane bodies of the
/// BSDFs read it, with `outside` a mask. (Not `Copy`: eight lanes of it are 416 bytes.)
#[derive(Clone, Debug)]
pub(crate) struct LaneFrame<L: Lanes> {
    pub normal: LaneVec3<L>,
    pub tangent: LaneVec3<L>,
    pub bitangent: LaneVec3<L>,
    pub geometric: LaneVec3<L>,
    pub outside: L::Mask,
}

impl<L: Lanes> LaneFrame<L> {
    /// The frame at a hit seen from `wo`, as `Frame::new` makes it: the geometric normal turned
    /// to `wo`'s side (`facing`), the shading normal to its side, or `facing` where the shading
    /// normal faces away from the viewer.
    #[inline(always)]
    pub fn new(wo: LaneVec3<L>, shading_normal: LaneVec3<L>, geometric_normal: LaneVec3<L>) -> Self {
        let outside = wo.dot(geometric_normal).ge(L::ZERO);
        let geometric = LaneVec3::select(outside, geometric_normal, -geometric_normal);
        let normal = LaneVec3::select(shading_normal.dot(geometric).ge(L::ZERO), shading_normal, -shading_normal);
        let normal = LaneVec3::select(normal.dot(wo).le(L::ZERO), geometric, normal);
        let (tangent, bitangent) = orthonormal_basis_lanes(normal);
        Self { normal, tangent, bitangent, geometric, outside }
    }

    #[inline(always)]
    pub fn to_local(&self, w: LaneVec3<L>) -> LaneVec3<L> {
        LaneVec3::new(w.dot(self.tangent), w.dot(self.bitangent), w.dot(self.normal))
    }

    #[inline(always)]
    pub fn to_world(&self, v: LaneVec3<L>) -> LaneVec3<L> {
        self.tangent * v.x + self.bitangent * v.y + self.normal * v.z
    }

    /// `wi` leaves on the viewer's side of both normals.
    #[inline(always)]
    pub fn reflects(&self, wi: LaneVec3<L>) -> L::Mask {
        wi.dot(self.normal).gt(L::ZERO) & wi.dot(self.geometric).gt(L::ZERO)
    }

    /// `wi` leaves on the far side of both normals.
    #[inline(always)]
    pub fn transmits(&self, wi: LaneVec3<L>) -> L::Mask {
        wi.dot(self.normal).lt(L::ZERO) & wi.dot(self.geometric).lt(L::ZERO)
    }
}

/// A normal or bump map's shadowing (`Frame::with_map_shadowing`), in lanes: the surface's own
/// shading normal turned to the mapped normal's side, and the α² of the microfacets the map's
/// tilt stands for (0 where there is no map).
#[derive(Clone, Debug)]
pub(crate) struct MapShadowing<L: Lanes> {
    pub unmapped: LaneVec3<L>,
    pub alpha2: L,
}

impl<L: Lanes> MapShadowing<L> {
    /// No map: nothing shadowed.
    pub const NONE: Self = Self { unmapped: LaneVec3::ZERO, alpha2: L::ZERO };

    /// For the mapped shading `normal` of a surface whose own is `unmapped`.
    #[inline(always)]
    pub fn new(normal: LaneVec3<L>, unmapped: LaneVec3<L>) -> Self {
        let unmapped = LaneVec3::select(unmapped.dot(normal).ge(L::ZERO), unmapped, -unmapped);
        let cos_d = unmapped.dot(normal).max(L::splat(1e-6)).min(L::ONE);
        let alpha2 = (L::splat(0.125) * (L::ONE - cos_d * cos_d) / (cos_d * cos_d)).min(L::ONE);
        Self { unmapped, alpha2 }
    }

    /// The shadowing of light from `wi`: G1 = 2 / (1 + √(1 + α² tan²θ_i)), 1 where α² = 0.
    #[inline(always)]
    pub fn of(&self, wi: LaneVec3<L>) -> L {
        let cos = wi.dot(self.unmapped);
        let cos2 = (cos * cos).max(L::splat(1e-12));
        let tan2 = (L::ONE - cos2).max(L::ZERO) / cos2;
        let g1 = L::splat(2.0) / (L::ONE + (L::ONE + self.alpha2 * tan2).sqrt());
        L::select(self.alpha2.eq(L::ZERO), L::ONE, g1)
    }
}

/// A BSDF sample in lanes (`BsdfSample` of a non-delta lobe): the direction, f·|cos θ_i| / pdf,
/// the pdf, and the lanes where there is a sample.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LaneBsdfSample<L: Lanes> {
    pub wi: LaneVec3<L>,
    pub weight: LaneVec3<L>,
    pub pdf: L,
    pub valid: L::Mask,
    /// η² picked up by refraction (`BsdfSample::eta_squared`).
    pub eta_squared: L,
    /// The lanes whose sample is a mirror or a refraction (a delta lobe's).
    pub delta: L::Mask,
}

impl<L: Lanes> LaneBsdfSample<L> {
    /// `wi`, drawn by a non-delta lobe, as a sample of it where `valid` (`Lobes::weighed`): its
    /// density `pdf` and the weight `f` / pdf, the lanes without a positive, finite density
    /// dropped.
    #[inline(always)]
    pub fn weighed(wi: LaneVec3<L>, f: LaneVec3<L>, pdf: L, valid: L::Mask, eta_squared: L) -> Self {
        let valid = valid & pdf.gt(L::ZERO) & pdf.is_finite();
        Self { wi, weight: f.divided_by(pdf), pdf, valid, eta_squared, delta: L::Mask::default() }
    }
}

impl LaneBsdfSample<f32> {
    /// The scalar code's sample, where there is one.
    #[inline(always)]
    pub fn scalar(self) -> Option<BsdfSample> {
        self.valid.then(|| BsdfSample {
            wi: self.wi.into(),
            weight: self.weight.into(),
            pdf: self.pdf,
            delta: self.delta,
            eta_squared: self.eta_squared,
        })
    }
}

impl From<&Frame> for LaneFrame<f32> {
    #[inline(always)]
    fn from(f: &Frame) -> Self {
        Self {
            normal: f.normal.into(),
            tangent: f.tangent.into(),
            bitangent: f.bitangent.into(),
            geometric: f.geometric.into(),
            outside: f.outside,
        }
    }
}

pub(super) fn tangent_along(normal: Vec3, dpdu: Vec3) -> Option<Vec3> {
    let (tangent, found) = tangent_along_lanes(LaneVec3::<f32>::from(normal), dpdu.into());
    found.then(|| tangent.into())
}

/// `tangent_along` in lanes: `dpdu` projected onto the plane of `normal` and normalised, and
/// the lanes where that is a direction (not too short against `dpdu`).
#[inline(always)]
pub(crate) fn tangent_along_lanes<L: Lanes>(normal: LaneVec3<L>, dpdu: LaneVec3<L>) -> (LaneVec3<L>, L::Mask) {
    let projected = dpdu - normal * normal.dot(dpdu);
    let (tangent, normalized) = projected.try_normalize();
    let long_enough = projected.dot(projected).gt(L::splat(1e-12) * dpdu.dot(dpdu));
    (tangent, normalized & long_enough)
}

/// What each member of the set answers (its file documents its lobes).
/// The defaults of `eval`, `pdf` and `non_delta_probability` are those of a member with delta
/// lobes only (mirrors, smooth refraction, the null lobe).
pub(super) trait Lobes {
    fn eval(&self, _wo: Vec3, _wi: Vec3) -> Rgb {
        Rgb::ZERO
    }
    fn pdf(&self, _wo: Vec3, _wi: Vec3) -> f32 {
        0.0
    }
    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample>;
    /// The probability that `sample` picks a non-delta lobe (those `u_lobe` below it).
    fn non_delta_probability(&self) -> f32 {
        0.0
    }
    /// k_d when the non-delta part is Lambert's lobe alone (photon mapping caches its
    /// irradiance there); `None` otherwise.
    fn lambertian(&self) -> Option<Rgb> {
        None
    }
    /// The weight of light passing straight through, unbent (Mitsuba's null transmission:
    /// a null surface's 1, a thin sheet's transmittance); zero for the rest of the set.
    fn null_transmission(&self, _wo: Vec3) -> Rgb {
        Rgb::ZERO
    }
    fn frame(&self) -> &Frame;
    fn frame_mut(&mut self) -> &mut Frame;

    /// `wi`, drawn by a non-delta lobe, as a sample of the whole non-delta part: its pdf and
    /// the weight eval / pdf (`None` where the pdf vanishes).
    fn weighed(&self, wo: Vec3, wi: Vec3, eta_squared: f32) -> Option<BsdfSample> {
        let pdf = self.pdf(wo, wi);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        Some(BsdfSample { wi, weight: self.eval(wo, wi) / pdf, pdf, delta: false, eta_squared })
    }
}

/// One member of the set, evaluated at a hit.
#[derive(Clone, Copy, Debug)]
pub(super) enum Leaf<'a> {
    Mixed(MixedBsdf),
    Diffuse(DiffuseBsdf),
    DiffuseTransmission(DiffuseTransmissionBsdf),
    Conductor(ConductorBsdf),
    RoughConductor(RoughConductorBsdf),
    Dielectric(DielectricBsdf),
    RoughDielectric(RoughDielectricBsdf),
    ThinDielectric(ThinDielectricBsdf),
    Plastic(PlasticBsdf),
    RoughPlastic(RoughPlasticBsdf<'a>),
    FresnelPlastic(FresnelPlasticBsdf),
    Principled(PrincipledBsdf),
    PrincipledThin(PrincipledThinBsdf),
    Null(NullBsdf),
}

macro_rules! dispatch {
    ($leaf:expr, $b:ident => $call:expr) => {
        match $leaf {
            Leaf::Mixed($b) => $call,
            Leaf::Diffuse($b) => $call,
            Leaf::DiffuseTransmission($b) => $call,
            Leaf::Conductor($b) => $call,
            Leaf::RoughConductor($b) => $call,
            Leaf::Dielectric($b) => $call,
            Leaf::RoughDielectric($b) => $call,
            Leaf::ThinDielectric($b) => $call,
            Leaf::Plastic($b) => $call,
            Leaf::RoughPlastic($b) => $call,
            Leaf::FresnelPlastic($b) => $call,
            Leaf::Principled($b) => $call,
            Leaf::PrincipledThin($b) => $call,
            Leaf::Null($b) => $call,
        }
    };
}

impl Leaf<'_> {
    /// f·|cos θ_i|, times a normal map's shadowing.
    #[inline(always)]
    fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        let value = dispatch!(self, b => b.eval(wo, wi));
        value * self.frame().terminator_shadowing(wi)
    }
    #[inline(always)]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        dispatch!(self, b => b.pdf(wo, wi))
    }
    /// A direction from the lobes; the weight carries a normal map's shadowing (the pdf
    /// does not: the shadowing is not sampled).
    #[inline(always)]
    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        let mut sample = dispatch!(self, b => b.sample(wo, u_lobe, u))?;
        sample.weight *= self.frame().terminator_shadowing(sample.wi);
        Some(sample)
    }
    #[inline(always)]
    fn non_delta_probability(&self) -> f32 {
        dispatch!(self, b => b.non_delta_probability())
    }
    fn null_transmission(&self, wo: Vec3) -> Rgb {
        dispatch!(self, b => b.null_transmission(wo))
    }
    /// Lambert's k_d; `None` under a map's shadowing, which Lambert's lobe does not have.
    fn lambertian(&self) -> Option<Rgb> {
        if self.frame().shadowing_alpha2 > 0.0 {
            return None;
        }
        dispatch!(self, b => b.lambertian())
    }
    fn frame(&self) -> &Frame {
        dispatch!(self, b => b.frame())
    }
    pub(super) fn frame_mut(&mut self) -> &mut Frame {
        dispatch!(self, b => b.frame_mut())
    }
}

/// Weighted leaves (weights summing to 1): Mitsuba's `blendbsdf` and `mask`, flattened.
#[derive(Clone, Copy, Debug)]
pub(super) struct Mixture<'a> {
    pub leaves: [Leaf<'a>; MAX_LEAVES],
    pub weights: [f32; MAX_LEAVES],
    pub count: usize,
}

impl<'a> Mixture<'a> {
    fn parts(&self) -> impl Iterator<Item = (&Leaf<'a>, f32)> {
        self.leaves[..self.count].iter().zip(self.weights[..self.count].iter().copied())
    }

    fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        self.parts().fold(Rgb::ZERO, |sum, (leaf, w)| if w > 0.0 { sum + leaf.eval(wo, wi) * w } else { sum })
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.parts().map(|(leaf, w)| if w > 0.0 { leaf.pdf(wo, wi) * w } else { 0.0 }).sum()
    }

    fn non_delta_probability(&self) -> f32 {
        self.parts().map(|(leaf, w)| leaf.non_delta_probability() * w).sum()
    }

    fn null_transmission(&self, wo: Vec3) -> Rgb {
        self.parts().fold(Rgb::ZERO, |sum, (leaf, w)| sum + leaf.null_transmission(wo) * w)
    }

    /// The leaves' non-delta parts come first in `u_lobe`'s range, each `w_i · p_i` wide, then
    /// their delta parts, each `w_i · (1 − p_i)` wide; the chosen leaf is handed `u_lobe` mapped
    /// into its own part. A non-delta sample is weighed by the whole mixture (one strategy for
    /// MIS); a delta one keeps its leaf's weight, its pdf the mixture's selection probability.
    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        let non_delta = self.non_delta_probability();
        let (mut start, delta) = if u_lobe < non_delta { (0.0, false) } else { (non_delta, true) };
        let mut chosen = None;
        for (i, (leaf, w)) in self.parts().enumerate() {
            let p = leaf.non_delta_probability();
            let width = if delta { w * (1.0 - p) } else { w * p };
            if width > 0.0 && (u_lobe < start + width || i + 1 == self.count) {
                let t = ((u_lobe - start) / width).clamp(0.0, 1.0 - f32::EPSILON / 2.0);
                chosen = Some((leaf, w, if delta { p + t * (1.0 - p) } else { t * p }));
                break;
            }
            start += width;
        }
        let (leaf, w, u_leaf) = chosen?;
        let sample = leaf.sample(wo, u_leaf, u)?;
        if sample.delta {
            return Some(BsdfSample { pdf: sample.pdf * w, ..sample });
        }
        let pdf = self.pdf(wo, sample.wi);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        Some(BsdfSample { weight: self.eval(wo, sample.wi) / pdf, pdf, ..sample })
    }

    fn lambertian(&self) -> Option<Rgb> {
        let mut sum = Rgb::ZERO;
        for (leaf, w) in self.parts() {
            if leaf.non_delta_probability() > 0.0 {
                sum += leaf.lambertian()? * w;
            }
        }
        Some(sum)
    }
}

/// One leaf on the stack; a mixture (blend, mask: the only materials that allocate, once per
/// hit) boxed, so that a BSDF stays a leaf's size where integrators keep one per pixel (SPPM's
/// visible points: at four leaves inline, SPPM ran 1.8× slower).
#[derive(Clone, Debug)]
enum Kind<'a> {
    One(Leaf<'a>),
    Mixture(Box<Mixture<'a>>),
}

/// The BSDF at a hit, as `Material::bsdf` makes it (borrowing the material's tables).
#[derive(Clone, Debug)]
pub struct Bsdf<'a> {
    kind: Kind<'a>,
}

impl<'a> Bsdf<'a> {
    pub(super) fn leaf(leaf: Leaf<'a>) -> Self {
        Self { kind: Kind::One(leaf) }
    }

    pub(super) fn mixture(mixture: Mixture<'a>) -> Self {
        Self { kind: Kind::Mixture(Box::new(mixture)) }
    }

    /// f·|cos θ_i| for the non-delta part.
    #[inline(always)]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        match &self.kind {
            Kind::One(leaf) => leaf.eval(wo, wi),
            Kind::Mixture(m) => m.eval(wo, wi),
        }
    }

    /// The solid-angle density of `sample` for `wi` (its non-delta part).
    #[inline(always)]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match &self.kind {
            Kind::One(leaf) => leaf.pdf(wo, wi),
            Kind::Mixture(m) => m.pdf(wo, wi),
        }
    }

    /// Chooses a lobe with `u_lobe`, then a direction with `u`.
    #[inline(always)]
    pub fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        match &self.kind {
            Kind::One(leaf) => leaf.sample(wo, u_lobe, u),
            Kind::Mixture(m) => m.sample(wo, u_lobe, u),
        }
    }

    /// The probability that `sample` picks a non-delta lobe (diffuse, glossy, rough).
    #[inline(always)]
    pub fn non_delta_probability(&self) -> f32 {
        match &self.kind {
            Kind::One(leaf) => leaf.non_delta_probability(),
            Kind::Mixture(m) => m.non_delta_probability(),
        }
    }

    /// The weight with which light passes the surface straight through, unbent (null
    /// surfaces, masks, thin sheets): volumetric path tracing crosses such surfaces as media
    /// boundaries rather than bounces, and lets shadow rays through them.
    pub fn null_transmission(&self, wo: Vec3) -> Rgb {
        match &self.kind {
            Kind::One(leaf) => leaf.null_transmission(wo),
            Kind::Mixture(m) => m.null_transmission(wo),
        }
    }

    /// Whether `sample`, drawn for `wo`, passed straight through a null-transmitting lobe.
    pub fn is_null_event(&self, wo: Vec3, sample: &BsdfSample) -> bool {
        sample.delta && sample.wi == -wo && self.null_transmission(wo) != Rgb::ZERO
    }

    /// Whether light sampling can contribute (a non-delta lobe exists).
    #[inline(always)]
    pub fn has_diffuse(&self) -> bool {
        self.non_delta_probability() > 0.0
    }

    /// k_d when the non-delta part is Lambert's lobe alone.
    pub fn lambertian(&self) -> Option<Rgb> {
        match &self.kind {
            Kind::One(leaf) => leaf.lambertian(),
            Kind::Mixture(m) => m.lambertian(),
        }
    }

    /// f without the cosine, for photon density estimates (Σ f·Φ / area): the non-delta part.
    /// Light arriving from below the surface (through it) is not counted.
    pub fn eval_without_cosine(&self, wo: Vec3, wi: Vec3) -> Rgb {
        let normal = match &self.kind {
            Kind::One(leaf) => leaf.frame().normal,
            Kind::Mixture(m) => m.leaves[0].frame().normal,
        };
        let cos = wi.dot(normal);
        if cos <= 0.0 {
            return Rgb::ZERO;
        }
        self.eval(wo, wi) / cos.max(1e-4)
    }

    /// `sample` restricted to the non-delta lobes (final gathering); weight and pdf are those of
    /// that restricted choice.
    pub fn sample_non_delta(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        let p = self.non_delta_probability();
        if p <= 0.0 {
            return None;
        }
        let mut s = self.sample(wo, u_lobe * p, u)?;
        s.weight *= p;
        s.pdf /= p;
        Some(s)
    }

    /// `sample` restricted to the delta lobes (mirror, refraction): photon mapping follows them
    /// while it estimates the rest from photons.
    pub fn sample_delta(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        let p = self.non_delta_probability();
        let q = 1.0 - p;
        if q <= 0.0 {
            return None;
        }
        let mut s = self.sample(wo, p + u_lobe * q, u)?;
        s.weight *= q;
        s.pdf /= q;
        Some(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `along` keeps the normal, makes the tangent the part of ∂p/∂u in the normal's plane and
    /// the frame orthonormal and right-handed; a zero or normal-parallel ∂p/∂u changes nothing.
    #[test]
    fn a_frame_along_dpdu_is_orthonormal_with_the_tangent_on_dpdu() {
        let n = Vec3::new(0.2, -0.3, 0.9).normalize();
        let frame = Frame::new(Vec3::new(0.1, 0.0, 1.0).normalize(), n, n);
        let dpdu = Vec3::new(1.5, 0.4, 0.2);
        let f = frame.along(dpdu);
        assert_eq!(f.normal, frame.normal);
        let projected = (dpdu - n * n.dot(dpdu)).normalize();
        assert!((f.tangent - projected).length() < 1e-6);
        assert!(f.tangent.dot(f.normal).abs() < 1e-6 && f.bitangent.dot(f.tangent).abs() < 1e-6);
        assert!((f.tangent.cross(f.bitangent) - f.normal).length() < 1e-6);
        for unknown in [Vec3::ZERO, 3.0 * n] {
            let same = frame.along(unknown);
            assert_eq!((same.tangent, same.bitangent), (frame.tangent, frame.bitangent), "{unknown}");
        }
    }
}
