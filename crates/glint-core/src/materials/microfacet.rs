//! Microfacet distributions for rough reflection and refraction (Walter et al. 2007): GGX
//! (Trowbridge–Reitz), with Smith masking-shadowing (height-correlated or separable) and sampling
//! of the visible normals (Heitz 2018, "Sampling the GGX Distribution of Visible Normals", JCGT
//! 7(4)); and Beckmann (Mitsuba's default), whose Smith G1 is the rational fit Walter et al. give
//! (as Mitsuba evaluates it) and whose visible normals are sampled by inverting their slope
//! distribution (Heitz & d'Eon 2014, "Importance Sampling Microfacet-Based BSDFs using the
//! Distribution of Visible Normals", with Jakob's numerical inversion). Directions are
//! in the local frame, where the macro-surface normal is +z. `alpha_x`, `alpha_y` are the widths
//! along the frame's tangent and bitangent (equal: isotropic; the usual perceptual `roughness`
//! squared). The isotropic case keeps its own arithmetic, which the course's materials were
//! measured with.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use crate::geometry::reflect;
use crate::lanes::{acos, exp, ln, sin_cos_turns, LaneVec3, Lanes};
use crate::sampling::warp::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Microfacet {
    pub alpha_x: f32,
    pub alpha_y: f32,
    /// Masking and shadowing as the product G1(wo)·G1(wi) (Mitsuba's rough BSDFs), rather than
    /// height-correlated (the course's mixed material).
    pub separable: bool,
    pub distribution: Distribution,
}

/// The shape of the micro-normals' density.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Distribution {
    #[default]
    Ggx,
    Beckmann,
}

impl crate::Named for Distribution {
    const ALL: &'static [Self] = &[Distribution::Ggx, Distribution::Beckmann];

    fn name(self) -> &'static str {
        match self {
            Distribution::Ggx => "ggx",
            Distribution::Beckmann => "beckmann",
        }
    }
}

impl Microfacet {
    /// The course's mixed material's lobe: isotropic, height-correlated masking.
    pub fn isotropic(alpha: f32) -> Self {
        Self { alpha_x: alpha, alpha_y: alpha, separable: false, distribution: Distribution::Ggx }
    }

    /// The rough BSDFs' lobe, as Mitsuba defines it: widths at least 1e-4, separable masking.
    pub fn separable(alpha_x: f32, alpha_y: f32) -> Self {
        Self {
            alpha_x: alpha_x.max(1e-4),
            alpha_y: alpha_y.max(1e-4),
            separable: true,
            distribution: Distribution::Ggx,
        }
    }

    /// The same widths and masking, another distribution.
    pub fn with(self, distribution: Distribution) -> Self {
        Self { distribution, ..self }
    }

    /// The one body of this lobe's arithmetic (`MicrofacetLanes`), at one lane.
    #[inline(always)]
    fn lanes(&self) -> MicrofacetLanes<f32> {
        MicrofacetLanes::from(self)
    }

    /// D(h): the density of micro-normals, normalised so ∫ D(h) cos θ_h dω_h = 1.
    pub fn d(&self, h: Vec3) -> f32 {
        self.lanes().d(h.into())
    }

    pub fn g1(&self, w: Vec3) -> f32 {
        self.lanes().g1(w.into())
    }

    /// Masking-shadowing G2(wo, wi): height-correlated, or separable (`separable`).
    pub fn g2(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.lanes().g2(wo.into(), wi.into())
    }

    /// A visible micro-normal for `wo` (wo.z > 0), from two uniform numbers: by Heitz's
    /// hemisphere construction for GGX (2018), by inverting the visible slopes' distribution
    /// for Beckmann (Heitz & d'Eon 2014, with Jakob's numerical inversion).
    pub fn sample_normal(&self, wo: Vec3, u: Vec2) -> Vec3 {
        self.lanes().sample_normal(wo.into(), u.x, u.y).into()
    }

    /// Density per solid angle of the reflected direction `wi` when `h` is sampled by
    /// `sample_normal`: the normal's density / (4 wo·h) = G1(wo)·D(h) / (4 cos θ_o).
    pub fn reflection_pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.lanes().reflection_pdf(wo.into(), wi.into())
    }

    /// f(wo, wi)·cos θ_i without the Fresnel factor: D·G2 / (4 cos θ_o).
    pub fn reflection_eval(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.lanes().reflection_eval(wo.into(), wi.into())
    }

    /// Density per solid angle of the refracted direction `wi` when `h` is sampled by
    /// `sample_normal` and `wo` refracted through it (Walter et al. 2007, eq. 17):
    /// D_wo(h) · |dh/dwi|, with |dh/dwi| = η_i² |wi·h| / (η_o wo·h + η_i wi·h)².
    pub fn transmission_pdf(&self, wo: Vec3, wi: Vec3, eta: f32) -> f32 {
        self.lanes().transmission_pdf(wo.into(), wi.into(), eta)
    }

    /// f(wo, wi)·|cos θ_i| of rough refraction without the Fresnel factor, in the form without
    /// the radiance's η² scaling (the form the smooth refraction lobe uses, so that rough and
    /// smooth glass agree as the roughness vanishes): its sampling weight is G2 / G1(wo).
    pub fn transmission_eval(&self, wo: Vec3, wi: Vec3, eta: f32) -> f32 {
        self.lanes().transmission_eval(wo.into(), wi.into(), eta)
    }
}

/// A microfacet lobe in lanes: the one body of `Microfacet`'s arithmetic, which the scalar
/// code runs at one lane and the wavefront at eight. The widths vary by lane; the masking and
/// the distribution are the same in every lane (the wavefront groups paths by them). Where
/// α_x = α_y the isotropic arithmetic is used (which the course's materials were measured
/// with), lane by lane.
#[derive(Clone, Copy, Debug)]
pub(crate) struct MicrofacetLanes<L> {
    pub alpha_x: L,
    pub alpha_y: L,
    pub separable: bool,
    pub distribution: Distribution,
}

impl From<&Microfacet> for MicrofacetLanes<f32> {
    #[inline(always)]
    fn from(m: &Microfacet) -> Self {
        Self { alpha_x: m.alpha_x, alpha_y: m.alpha_y, separable: m.separable, distribution: m.distribution }
    }
}

impl<L: Lanes> MicrofacetLanes<L> {
    /// `isotropic` in the lanes with α_x = α_y, `anisotropic` in the others, each computed only
    /// if some lane needs it.
    #[inline(always)]
    fn by_isotropy(&self, isotropic: impl Fn() -> L, anisotropic: impl Fn() -> L) -> L {
        let same = self.alpha_x.eq(self.alpha_y);
        match (L::any(same), L::any(!same)) {
            (true, false) => isotropic(),
            (false, _) => anisotropic(),
            (true, true) => L::select(same, isotropic(), anisotropic()),
        }
    }

    /// D(h): the density of micro-normals, normalised so ∫ D(h) cos θ_h dω_h = 1.
    #[inline(always)]
    pub fn d(&self, h: LaneVec3<L>) -> L {
        let c = L::splat;
        let (ax, ay) = (self.alpha_x, self.alpha_y);
        let d = if self.distribution == Distribution::Beckmann {
            // exp(−tan²θ (cos²φ/α_x² + sin²φ/α_y²)) / (π α_x α_y cos⁴θ).
            let (x, y) = (h.x / ax, h.y / ay);
            let cos2 = h.z * h.z;
            let d = exp((x * x + y * y).negate() / cos2) / (c(PI) * ax * ay * cos2 * cos2);
            L::select((d * h.z).gt(c(1e-20)), d, L::ZERO)
        } else {
            self.by_isotropy(
                || {
                    let a2 = ax * ax;
                    let t = (a2 - L::ONE) * h.z * h.z + L::ONE;
                    a2 / (c(PI) * t * t)
                },
                || {
                    let (x, y) = (h.x / ax, h.y / ay);
                    let t = x * x + y * y + h.z * h.z;
                    L::ONE / (c(PI) * ax * ay * t * t)
                },
            )
        };
        L::select(h.z.le(L::ZERO), L::ZERO, d)
    }

    /// Smith's Λ(w); infinite at and below the horizon.
    #[inline(always)]
    fn lambda(&self, w: LaneVec3<L>) -> L {
        let c = L::splat;
        let cos2 = w.z * w.z;
        let alpha2_tan2 = self.by_isotropy(
            || {
                let tan2 = (L::ONE - cos2).max(L::ZERO) / cos2;
                self.alpha_x * self.alpha_x * tan2
            },
            || {
                let (x, y) = (self.alpha_x * w.x, self.alpha_y * w.y);
                (x * x + y * y) / cos2
            },
        );
        let lambda = if self.distribution == Distribution::Beckmann {
            // Λ = 1/G1 − 1 with G1 the rational fit in a = 1/(α tan θ), within 0.4 % of exact.
            let a = L::ONE / alpha2_tan2.sqrt();
            let g1 = (c(3.535) * a + c(2.181) * a * a) / (L::ONE + c(2.276) * a + c(2.577) * a * a);
            L::select(a.ge(c(1.6)), L::ZERO, L::ONE / g1 - L::ONE)
        } else {
            c(0.5) * (c(-1.0) + (L::ONE + alpha2_tan2).sqrt())
        };
        L::select(cos2.le(L::ZERO), c(f32::INFINITY), lambda)
    }

    #[inline(always)]
    pub fn g1(&self, w: LaneVec3<L>) -> L {
        L::ONE / (L::ONE + self.lambda(w))
    }

    /// Masking-shadowing G2(wo, wi): height-correlated, or separable.
    #[inline(always)]
    pub fn g2(&self, wo: LaneVec3<L>, wi: LaneVec3<L>) -> L {
        if self.separable {
            return self.g1(wo) * self.g1(wi);
        }
        L::ONE / (L::ONE + self.lambda(wo) + self.lambda(wi))
    }

    /// A visible micro-normal for `wo` (wo.z > 0), from two uniform numbers.
    #[inline(always)]
    pub fn sample_normal(&self, wo: LaneVec3<L>, u1: L, u2: L) -> LaneVec3<L> {
        match self.distribution {
            Distribution::Ggx => ggx_visible_normal(self.alpha_x, self.alpha_y, wo, u1, u2),
            Distribution::Beckmann => self.sample_beckmann_visible(wo, u1, u2),
        }
    }

    /// Beckmann's visible normals: `wo` stretched to unit roughness, a visible slope drawn
    /// there (`beckmann_visible_slope`, with the view along +x), turned to `wo`'s azimuth and
    /// stretched back.
    #[inline(always)]
    fn sample_beckmann_visible(&self, wo: LaneVec3<L>, u1: L, u2: L) -> LaneVec3<L> {
        let stretched = LaneVec3::new(self.alpha_x * wo.x, self.alpha_y * wo.y, wo.z).normalize();
        let sin_theta = (L::ONE - stretched.z * stretched.z).max(L::ZERO).sqrt();
        let turned = sin_theta.gt(L::splat(1e-7));
        let cos_phi = L::select(turned, stretched.x / sin_theta, L::ONE);
        let sin_phi = L::select(turned, stretched.y / sin_theta, L::ZERO);
        let (x, y) = beckmann_visible_slope(stretched.z, u1, u2);
        let (x, y) = (cos_phi * x - sin_phi * y, sin_phi * x + cos_phi * y);
        LaneVec3::new(self.alpha_x.negate() * x, self.alpha_y.negate() * y, L::ONE).normalize()
    }

    /// Smith's G1 for the density of visible normals: GGX's, and for Beckmann the exact
    /// 2 / (1 + erf a + e^(−a²) / (a √π)) (its samples are exact; the rational fit `g1`
    /// evaluates the BSDF, as Mitsuba's does).
    #[inline(always)]
    fn visible_g1(&self, wo: LaneVec3<L>) -> L {
        if self.distribution != Distribution::Beckmann {
            return self.g1(wo);
        }
        let cos2 = wo.z * wo.z;
        let (x, y) = (self.alpha_x * wo.x, self.alpha_y * wo.y);
        let alpha_tan = ((x * x + y * y) / cos2).sqrt();
        let a = L::ONE / alpha_tan;
        let g1 = L::splat(2.0) / (L::ONE + erf(a) + exp((a * a).negate()) / (a * L::splat(PI.sqrt())));
        L::select(cos2.le(L::ZERO), L::ZERO, L::select(alpha_tan.le(L::ZERO), L::ONE, g1))
    }

    /// Density per solid angle of `sample_normal`'s micro-normal `h` for `wo`: the visible
    /// normals' G1(wo)·max(0, wo·h)·D(h) / cos θ_o.
    #[inline(always)]
    pub fn normal_pdf(&self, wo: LaneVec3<L>, h: LaneVec3<L>) -> L {
        let pdf = self.visible_g1(wo) * wo.dot(h).max(L::ZERO) * self.d(h) / wo.z;
        L::select(wo.z.le(L::ZERO), L::ZERO, pdf)
    }

    /// Density per solid angle of the reflected direction `wi` when `h` is sampled by
    /// `sample_normal`: G1(wo)·D(h) / (4 cos θ_o).
    #[inline(always)]
    pub fn reflection_pdf(&self, wo: LaneVec3<L>, wi: LaneVec3<L>) -> L {
        let h = (wo + wi).normalize();
        let pdf = self.visible_g1(wo) * self.d(h) / (L::splat(4.0) * wo.z);
        L::select(wo.z.le(L::ZERO) | wi.z.le(L::ZERO), L::ZERO, pdf)
    }

    /// f(wo, wi)·cos θ_i without the Fresnel factor: D·G2 / (4 cos θ_o).
    #[inline(always)]
    pub fn reflection_eval(&self, wo: LaneVec3<L>, wi: LaneVec3<L>) -> L {
        let h = (wo + wi).normalize();
        let value = self.d(h) * self.g2(wo, wi) / (L::splat(4.0) * wo.z);
        L::select(wo.z.le(L::ZERO) | wi.z.le(L::ZERO), L::ZERO, value)
    }
}

impl<L: Lanes> MicrofacetLanes<L> {
    /// `Microfacet::transmission_pdf` in lanes.
    #[inline(always)]
    pub fn transmission_pdf(&self, wo: LaneVec3<L>, wi: LaneVec3<L>, eta: L) -> L {
        let (h, exists) = refraction_half_vector(wo, wi, eta);
        let ratio = L::ONE / eta; // η_i / η_o
        let denominator = wo.dot(h) + ratio * wi.dot(h);
        let jacobian = ratio * ratio * wi.dot(h).abs() / (denominator * denominator);
        L::select(exists, self.normal_pdf(wo, h) * jacobian, L::ZERO)
    }

    /// `Microfacet::transmission_eval` in lanes.
    #[inline(always)]
    pub fn transmission_eval(&self, wo: LaneVec3<L>, wi: LaneVec3<L>, eta: L) -> L {
        let (h, exists) = refraction_half_vector(wo, wi, eta);
        let ratio = L::ONE / eta;
        let denominator = wo.dot(h) + ratio * wi.dot(h);
        let value = wi.dot(h).abs() * wo.dot(h) * ratio * ratio * self.d(h) * self.g2(wo, wi)
            / (wo.z * denominator * denominator);
        L::select(exists, value, L::ZERO)
    }
}

/// The refraction half vector in lanes (`Microfacet::refraction_half_vector`), and the lanes
/// where the pair refracts through it.
#[inline(always)]
pub(super) fn refraction_half_vector<L: Lanes>(wo: LaneVec3<L>, wi: LaneVec3<L>, eta: L) -> (LaneVec3<L>, L::Mask) {
    let (h, normalized) = (-(wo + wi.divided_by(eta))).try_normalize();
    let h = LaneVec3::select(h.z.lt(L::ZERO), -h, h);
    let exists = wo.z.gt(L::ZERO) & wi.z.lt(L::ZERO) & normalized & wo.dot(h).gt(L::ZERO) & wi.dot(h).lt(L::ZERO);
    (h, exists)
}

/// A visible normal of GGX with widths (α_x, α_y) for `wo` (wo.z > 0), by Heitz's hemisphere
/// construction (2018): `wo` stretched to unit roughness, a point on the disk warped toward
/// the visible half, lifted to the hemisphere and stretched back.
#[inline(always)]
fn ggx_visible_normal<L: Lanes>(alpha_x: L, alpha_y: L, wo: LaneVec3<L>, u1: L, u2: L) -> LaneVec3<L> {
    let v = LaneVec3::new(alpha_x * wo.x, alpha_y * wo.y, wo.z).normalize();
    let length2 = v.x * v.x + v.y * v.y;
    let length = length2.sqrt();
    let t1 = LaneVec3::select(
        length2.gt(L::ZERO),
        LaneVec3::new(v.y.negate() / length, v.x / length, L::ZERO / length),
        LaneVec3::new(L::ONE, L::ZERO, L::ZERO),
    );
    let t2 = v.cross(t1);
    let r = u1.sqrt();
    let (sin_phi, cos_phi) = sin_cos_turns(u2);
    let p1 = r * cos_phi;
    let s = L::splat(0.5) * (L::ONE + v.z);
    let p2 = (L::ONE - s) * (L::ONE - p1 * p1).max(L::ZERO).sqrt() + s * r * sin_phi;
    let n = t1 * p1 + t2 * p2 + v * (L::ONE - p1 * p1 - p2 * p2).max(L::ZERO).sqrt();
    LaneVec3::new(alpha_x * n.x, alpha_y * n.y, n.z.max(L::splat(1e-7))).normalize()
}

/// A slope (x, y) of Beckmann's distribution at unit roughness, visible from a direction of
/// cosine `cos_theta` in the xz plane (x toward it). y is Gaussian; x is found by inverting
/// its distribution function in the variable b = erf(x), where it reads
/// C(b) = (1 + b + tan θ e^(−erfinv(b)²) / √π) / (1 + erf(cot θ) + tan θ e^(−cot² θ) / √π),
/// by Newton's method kept inside a bisection bracket, from a fitted first guess. Lanes stop
/// as they converge (each keeps the bracket and guess it had when it did).
#[inline(always)]
fn beckmann_visible_slope<L: Lanes>(cos_theta: L, u1: L, u2: L) -> (L, L) {
    let c = L::splat;
    // Seen from straight above: the slopes' own Gaussian.
    let overhead = cos_theta.gt(c(0.9999));
    let (sin_phi, cos_phi) = sin_cos_turns(u2);
    let r = ln((L::ONE - u1).max(c(f32::MIN_POSITIVE))).negate().sqrt();
    let (overhead_x, overhead_y) = (r * cos_phi, r * sin_phi);
    if !L::any(!overhead) {
        return (overhead_x, overhead_y);
    }
    let sin_theta = (L::ONE - cos_theta * cos_theta).max(L::ZERO).sqrt();
    let tan_theta = sin_theta / cos_theta;
    let cot_theta = L::ONE / tan_theta;
    let inv_sqrt_pi = c(1.0 / PI.sqrt());
    let (mut low, mut high) = (c(-1.0), erf(cot_theta));
    let target = u1.max(c(1e-6));
    let theta = acos(cos_theta);
    let fit = L::ONE + theta * (c(-0.876) + theta * (c(0.4265) - c(0.0594) * theta));
    // (1 − target)^fit
    let mut b = high - (L::ONE + high) * exp(fit * ln(L::ONE - target));
    let normalization = L::ONE / (L::ONE + high + inv_sqrt_pi * tan_theta * exp((cot_theta * cot_theta).negate()));
    let mut done = overhead;
    for _ in 0..10 {
        let outside = !(b.ge(low) & b.le(high));
        b = L::select(done, b, L::select(outside, c(0.5) * (low + high), b));
        let x = erf_inv(b);
        let value = normalization * (L::ONE + b + inv_sqrt_pi * tan_theta * exp((x * x).negate())) - target;
        done = done | value.abs().lt(c(1e-5));
        if !L::any(!done) {
            break;
        }
        let above = value.gt(L::ZERO);
        high = L::select(done, high, L::select(above, b, high));
        low = L::select(done, low, L::select(above, low, b));
        let derivative = normalization * (L::ONE - x * tan_theta);
        b = L::select(done, b, b - value / derivative);
    }
    let x = erf_inv(b.max(low).min(high));
    let y = erf_inv(c(2.0) * u2.max(c(1e-6)) - L::ONE);
    (L::select(overhead, overhead_x, x), L::select(overhead, overhead_y, y))
}

/// The error function (Abramowitz & Stegun 7.1.26, absolute error below 1.5·10⁻⁷).
#[inline(always)]
fn erf<L: Lanes>(x: L) -> L {
    let c = L::splat;
    let t = L::ONE / (L::ONE + c(0.327_591_1) * x.abs());
    let poly =
        t * (c(0.254_829_6) + t * (c(-0.284_496_74) + t * (c(1.421_413_7) + t * (c(-1.453_152) + t * c(1.061_405_4)))));
    (L::ONE - poly * exp((x.negate()) * x)).copysign(x)
}

/// The inverse error function on (−1, 1) (Giles' single-precision polynomials, 2010).
#[inline(always)]
fn erf_inv<L: Lanes>(x: L) -> L {
    let c = L::splat;
    // Within the polynomials' range: ±1 itself saturates at the largest finite answer.
    let x = x.max(c(-0.999_999_9)).min(c(0.999_999_9));
    let w = ln((L::ONE - x) * (L::ONE + x)).negate();
    let horner = |coefficients: &[f32], w: L| coefficients.iter().fold(L::ZERO, |p, &k| c(k) + p * w);
    let central = || {
        horner(
            &[
                2.810_226_4e-8,
                3.432_739_4e-7,
                -3.523_387_7e-6,
                -4.391_506_5e-6,
                2.185_808_7e-4,
                -1.253_725e-3,
                -4.177_681_6e-3,
                0.246_640_73,
                1.501_409_4,
            ],
            w - c(2.5),
        )
    };
    let tail = || {
        horner(
            &[
                -2.002_142_6e-4,
                1.009_505_6e-4,
                1.349_343_2e-3,
                -3.673_428_4e-3,
                5.739_507_7e-3,
                -7.622_461e-3,
                9.438_870_5e-3,
                1.001_674,
                2.832_976_8,
            ],
            w.sqrt() - c(3.0),
        )
    };
    let in_centre = w.lt(c(5.0));
    let p = match (L::any(in_centre), L::any(!in_centre)) {
        (true, false) => central(),
        (false, _) => tail(),
        (true, true) => L::select(in_centre, central(), tail()),
    };
    p * x
}

/// How the plastics sample: a glossy reflection off the microfacets with probability
/// `p_glossy` (by visible normals), else Lambert's lobe (by the cosine). Local directions.
#[derive(Clone, Copy, Debug)]
pub(super) struct GlossyOrDiffuse {
    pub microfacet: Microfacet,
    pub p_glossy: f32,
}

impl GlossyOrDiffuse {
    /// The density of `i` drawn for `o`.
    pub(super) fn pdf(&self, o: Vec3, i: Vec3) -> f32 {
        self.p_glossy * self.microfacet.reflection_pdf(o, i) + (1.0 - self.p_glossy) * cosine_hemisphere_pdf(i)
    }

    /// A direction for `o`: the glossy lobe's where `u_lobe` < `p_glossy`.
    pub(super) fn sample(&self, o: Vec3, u_lobe: f32, u: Vec2) -> Vec3 {
        if u_lobe < self.p_glossy {
            reflect(-o, self.microfacet.sample_normal(o, u))
        } else {
            square_to_cosine_hemisphere(u)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::reflect;
    use crate::sampling::chi2::chi2_test;

    /// ∫ f dω over the upper hemisphere by the midpoint rule on an `nz` × `nphi` grid in
    /// (cos θ, φ).
    fn over_hemisphere(nz: usize, nphi: usize, f: impl Fn(Vec3) -> f32) -> f64 {
        let mut sum = 0.0f64;
        for i in 0..nz {
            let z = (i as f32 + 0.5) / nz as f32;
            for j in 0..nphi {
                let phi = 2.0 * PI * (j as f32 + 0.5) / nphi as f32;
                let r = (1.0 - z * z).sqrt();
                sum += f(Vec3::new(r * phi.cos(), r * phi.sin(), z)) as f64;
            }
        }
        sum * (2.0 * PI / (nz * nphi) as f32) as f64
    }

    #[test]
    fn distribution_is_normalised() {
        for alpha in [0.1f32, 0.4, 0.9] {
            let microfacet = Microfacet::isotropic(alpha);
            // ∫ D(h) cos θ_h dω over the hemisphere, midpoint rule in (cos θ, φ) (D is isotropic).
            let n = 20_000;
            let integral: f32 = (0..n)
                .map(|i| {
                    let z = (i as f32 + 0.5) / n as f32;
                    microfacet.d(Vec3::new((1.0 - z * z).sqrt(), 0.0, z)) * z
                })
                .sum::<f32>()
                * 2.0
                * PI
                / n as f32;
            assert!((integral - 1.0).abs() < 2e-3, "alpha {alpha}: {integral}");
        }
    }

    #[test]
    fn visible_normal_sampling_matches_its_pdf() {
        for (alpha, wo) in [(0.3f32, Vec3::new(0.3, 0.1, 0.9)), (0.7, Vec3::new(-0.8, 0.2, 0.3))] {
            let microfacet = Microfacet::isotropic(alpha);
            let wo = wo.normalize();
            let r = chi2_test(
                |u| {
                    let wi = reflect(-wo, microfacet.sample_normal(wo, u));
                    (wi.z > 0.0).then_some(wi)
                },
                |w| microfacet.reflection_pdf(wo, w) as f64,
                500_000,
                21,
                41,
                11,
            );
            assert!(r.p_value > 0.01 / 8.0, "alpha {alpha}: p = {} (chi2 {})", r.p_value, r.statistic);
        }
    }

    /// erf by hand-checked values (tables of the error function), and erfinv its inverse;
    /// Beckmann's visible normals always face the viewer.
    #[test]
    fn erf_and_its_inverse_and_visible_beckmann_normals() {
        for (x, expected) in
            [(0.0f32, 0.0f32), (0.5, 0.520_499_9), (1.0, 0.842_700_8), (2.0, 0.995_322_3), (-1.0, -0.842_700_8)]
        {
            assert!((erf(x) - expected).abs() < 3e-7, "erf({x}) = {} vs {expected}", erf(x));
        }
        for k in -30..=30 {
            let x = k as f32 / 10.0;
            let back = erf_inv(erf(x));
            // erf flattens beyond |x| ≈ 2.5, where f32 cannot tell its values apart.
            let tolerance = if x.abs() <= 2.0 { 2e-4 } else { 2e-2 };
            assert!((back - x).abs() < tolerance, "erfinv(erf({x})) = {back}");
        }
        // Saturated at ±1, with the sign kept.
        assert!(erf_inv(1.0) > 3.5 && erf_inv(1.0).is_finite() && erf_inv(-1.0) < -3.5);
        let m = Microfacet::separable(0.5, 0.2).with(Distribution::Beckmann);
        let mut rng = crate::sampling::Rng::new(9, 9);
        for _ in 0..20_000 {
            let wo = Vec3::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, rng.next_f32() * 0.99 + 0.01).normalize();
            let h = m.sample_normal(wo, Vec2::new(rng.next_f32(), rng.next_f32()));
            assert!(h.is_finite() && h.z > 0.0 && wo.dot(h) > -1e-4, "wo {wo}, h {h}");
        }
    }

    /// Beckmann, isotropic and anisotropic: D normalised (∫ D cos θ_h dω = 1, midpoint rule
    /// over the hemisphere), the sampled reflections distributed as `reflection_pdf` says
    /// (chi-square), and G1's rational fit within 0.4 % of the exact
    /// 2 / (1 + erf a + e^(−a²) / (a √π)).
    #[test]
    fn beckmann_is_normalised_sampled_by_its_pdf_and_its_g1_fit_is_close() {
        for (ax, ay, seed) in [(0.3f32, 0.3f32, 21), (0.15, 0.5, 22)] {
            let m = Microfacet::separable(ax, ay).with(Distribution::Beckmann);
            let integral = over_hemisphere(2000, 400, |h| m.d(h) * h.z);
            assert!((integral - 1.0).abs() < 3e-3, "α ({ax}, {ay}): ∫ D cos = {integral}");
            let wo = Vec3::new(0.4, -0.2, 0.85).normalize();
            let r = chi2_test(
                |u| {
                    let h = m.sample_normal(wo, u);
                    let wi = reflect(-wo, h);
                    (wo.dot(h) > 0.0 && wi.z > 0.0).then_some(wi)
                },
                |w| m.reflection_pdf(wo, w) as f64,
                500_000,
                21,
                41,
                seed,
            );
            assert!(r.p_value > 0.01 / 8.0, "α ({ax}, {ay}): p = {}", r.p_value);
        }
        // Abramowitz & Stegun 7.1.26 (error below 1.5·10⁻⁷).
        let erf = |x: f64| {
            let t = 1.0 / (1.0 + 0.3275911 * x);
            let poly =
                t * (0.254829592 + t * (-0.284496736 + t * (1.421413741 + t * (-1.453152027 + t * 1.061405429))));
            1.0 - poly * (-x * x).exp()
        };
        let m = Microfacet::separable(0.4, 0.4).with(Distribution::Beckmann);
        for k in 1..90 {
            let theta = (k as f32).to_radians();
            let w = Vec3::new(theta.sin(), 0.0, theta.cos());
            let a = 1.0 / (0.4 * theta.tan()) as f64;
            let exact = 2.0 / (1.0 + erf(a) + (-a * a).exp() / (a * std::f64::consts::PI.sqrt()));
            let fit = m.g1(w) as f64;
            assert!((fit - exact).abs() < 4e-3 * exact, "θ {k}°: fit {fit}, exact {exact}");
        }
    }

    /// Directional albedo ∫ f cos dω two ways: by quadrature of `reflection_eval` over the
    /// hemisphere, and by Monte Carlo with visible-normal samples weighted by eval / pdf. They
    /// must agree; the albedo is ≤ 1, near 1 when smooth, and falls as the surface roughens
    /// (single-scattering GGX loses the light that bounces between microfacets).
    #[test]
    fn albedo_by_quadrature_equals_albedo_by_sampling() {
        let wo = Vec3::new(0.3, 0.0, 0.95).normalize();
        let mut previous = f64::INFINITY;
        for alpha in [0.05f32, 0.2, 0.5, 1.0] {
            let microfacet = Microfacet::isotropic(alpha);
            let quadrature = over_hemisphere(600, 600, |wi| microfacet.reflection_eval(wo, wi));
            let mut rng = crate::sampling::Rng::new(4, 2);
            let n = 400_000;
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let wi = reflect(-wo, microfacet.sample_normal(wo, Vec2::new(rng.next_f32(), rng.next_f32())));
                let w = if wi.z > 0.0 {
                    (microfacet.reflection_eval(wo, wi) / microfacet.reflection_pdf(wo, wi)) as f64
                } else {
                    0.0
                };
                sum += w;
                sum2 += w * w;
            }
            let mean = sum / n as f64;
            let standard_error = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
            // Quadrature of a peaked lobe is only accurate to ~1 % for the smoothest case.
            let tolerance = 5.0 * standard_error + 0.01 * quadrature;
            assert!((mean - quadrature).abs() < tolerance, "alpha {alpha}: sampled {mean}, quadrature {quadrature}");
            assert!(mean <= 1.0 + 1e-3 && mean < previous + 1e-3, "alpha {alpha}: albedo {mean}");
            if alpha <= 0.05 {
                assert!(mean > 0.98, "a smooth surface reflects nearly everything: {mean}");
            }
            previous = mean;
        }
    }
}
