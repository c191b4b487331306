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

    fn is_isotropic(&self) -> bool {
        self.alpha_x == self.alpha_y
    }

    /// D(h): the density of micro-normals, normalised so ∫ D(h) cos θ_h dω_h = 1.
    pub fn d(&self, h: Vec3) -> f32 {
        if h.z <= 0.0 {
            return 0.0;
        }
        if self.distribution == Distribution::Beckmann {
            // exp(−tan²θ (cos²φ/α_x² + sin²φ/α_y²)) / (π α_x α_y cos⁴θ).
            let (x, y) = (h.x / self.alpha_x, h.y / self.alpha_y);
            let cos2 = h.z * h.z;
            let d = (-(x * x + y * y) / cos2).exp() / (PI * self.alpha_x * self.alpha_y * cos2 * cos2);
            return if d * h.z > 1e-20 { d } else { 0.0 };
        }
        if self.is_isotropic() {
            let a2 = self.alpha_x * self.alpha_x;
            let t = (a2 - 1.0) * h.z * h.z + 1.0;
            return a2 / (PI * t * t);
        }
        let (x, y) = (h.x / self.alpha_x, h.y / self.alpha_y);
        let t = x * x + y * y + h.z * h.z;
        1.0 / (PI * self.alpha_x * self.alpha_y * t * t)
    }

    /// Smith's Λ(w).
    fn lambda(&self, w: Vec3) -> f32 {
        let cos2 = w.z * w.z;
        if cos2 <= 0.0 {
            return f32::INFINITY;
        }
        let alpha2_tan2 = if self.is_isotropic() {
            let tan2 = (1.0 - cos2).max(0.0) / cos2;
            self.alpha_x * self.alpha_x * tan2
        } else {
            let (x, y) = (self.alpha_x * w.x, self.alpha_y * w.y);
            (x * x + y * y) / cos2
        };
        if self.distribution == Distribution::Beckmann {
            // Λ = 1/G1 − 1 with G1 the rational fit in a = 1/(α tan θ), within 0.4 % of exact.
            let a = 1.0 / alpha2_tan2.sqrt();
            if a >= 1.6 {
                return 0.0;
            }
            let g1 = (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a);
            return 1.0 / g1 - 1.0;
        }
        0.5 * (-1.0 + (1.0 + alpha2_tan2).sqrt())
    }

    pub fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// Masking-shadowing G2(wo, wi): height-correlated, or separable (`separable`).
    pub fn g2(&self, wo: Vec3, wi: Vec3) -> f32 {
        if self.separable {
            return self.g1(wo) * self.g1(wi);
        }
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }

    /// A visible micro-normal for `wo` (wo.z > 0), from two uniform numbers: by Heitz's
    /// hemisphere construction for GGX (2018), by inverting the visible slopes' distribution
    /// for Beckmann (Heitz & d'Eon 2014, with Jakob's numerical inversion).
    pub fn sample_normal(&self, wo: Vec3, u: Vec2) -> Vec3 {
        if self.distribution == Distribution::Beckmann {
            return self.sample_beckmann_visible(wo, u);
        }
        let v = Vec3::new(self.alpha_x * wo.x, self.alpha_y * wo.y, wo.z).normalize();
        let length2 = v.x * v.x + v.y * v.y;
        let t1 = if length2 > 0.0 { Vec3::new(-v.y, v.x, 0.0) / length2.sqrt() } else { Vec3::X };
        let t2 = v.cross(t1);
        let r = u.x.sqrt();
        let phi = 2.0 * PI * u.y;
        let p1 = r * phi.cos();
        let s = 0.5 * (1.0 + v.z);
        let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * phi.sin();
        let n = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * v;
        Vec3::new(self.alpha_x * n.x, self.alpha_y * n.y, n.z.max(1e-7)).normalize()
    }

    /// Beckmann's visible normals: `wo` stretched to unit roughness, a visible slope drawn
    /// there (`beckmann_visible_slope`, with the view along +x), turned to `wo`'s azimuth and
    /// stretched back.
    fn sample_beckmann_visible(&self, wo: Vec3, u: Vec2) -> Vec3 {
        let stretched = Vec3::new(self.alpha_x * wo.x, self.alpha_y * wo.y, wo.z).normalize();
        let sin_theta = (1.0 - stretched.z * stretched.z).max(0.0).sqrt();
        let (cos_phi, sin_phi) =
            if sin_theta > 1e-7 { (stretched.x / sin_theta, stretched.y / sin_theta) } else { (1.0, 0.0) };
        let (x, y) = beckmann_visible_slope(stretched.z, u);
        let (x, y) = (cos_phi * x - sin_phi * y, sin_phi * x + cos_phi * y);
        Vec3::new(-self.alpha_x * x, -self.alpha_y * y, 1.0).normalize()
    }

    /// Smith's G1 for the density of visible normals: GGX's, and for Beckmann the exact
    /// 2 / (1 + erf a + e^(−a²) / (a √π)) (its samples are exact; the rational fit `g1`
    /// evaluates the BSDF, as Mitsuba's does).
    fn visible_g1(&self, wo: Vec3) -> f32 {
        if self.distribution != Distribution::Beckmann {
            return self.g1(wo);
        }
        let cos2 = wo.z * wo.z;
        if cos2 <= 0.0 {
            return 0.0;
        }
        let (x, y) = (self.alpha_x * wo.x, self.alpha_y * wo.y);
        let alpha_tan = ((x * x + y * y) / cos2).sqrt();
        if alpha_tan <= 0.0 {
            return 1.0;
        }
        let a = 1.0 / alpha_tan;
        2.0 / (1.0 + erf(a) + (-a * a).exp() / (a * PI.sqrt()))
    }

    /// Density per solid angle of `sample_normal`'s micro-normal `h` for `wo`: the visible
    /// normals' G1(wo)·max(0, wo·h)·D(h) / cos θ_o.
    fn normal_pdf(&self, wo: Vec3, h: Vec3) -> f32 {
        if wo.z <= 0.0 {
            return 0.0;
        }
        self.visible_g1(wo) * wo.dot(h).max(0.0) * self.d(h) / wo.z
    }

    /// Density per solid angle of the reflected direction `wi` when `h` is sampled by
    /// `sample_normal`: the normal's density / (4 wo·h) = G1(wo)·D(h) / (4 cos θ_o).
    pub fn reflection_pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let h = (wo + wi).normalize();
        self.visible_g1(wo) * self.d(h) / (4.0 * wo.z)
    }

    /// f(wo, wi)·cos θ_i without the Fresnel factor: D·G2 / (4 cos θ_o).
    pub fn reflection_eval(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let h = (wo + wi).normalize();
        self.d(h) * self.g2(wo, wi) / (4.0 * wo.z)
    }
    /// The refraction half vector for `wo` (wo.z > 0) and `wi` below the surface (wi.z < 0),
    /// with `eta` = n(wo's side) / n(wi's side): h ∝ −(η_o wo + η_i wi), turned to +z; `None`
    /// if the pair cannot refract through any microfacet.
    pub(super) fn refraction_half_vector(wo: Vec3, wi: Vec3, eta: f32) -> Option<Vec3> {
        if wo.z <= 0.0 || wi.z >= 0.0 {
            return None;
        }
        let h = -(wo + wi / eta);
        let h = h.try_normalize()?;
        let h = if h.z < 0.0 { -h } else { h };
        (wo.dot(h) > 0.0 && wi.dot(h) < 0.0).then_some(h)
    }

    /// Density per solid angle of the refracted direction `wi` when `h` is sampled by
    /// `sample_normal` and `wo` refracted through it (Walter et al. 2007, eq. 17):
    /// D_wo(h) · |dh/dwi|, with |dh/dwi| = η_i² |wi·h| / (η_o wo·h + η_i wi·h)².
    pub fn transmission_pdf(&self, wo: Vec3, wi: Vec3, eta: f32) -> f32 {
        let Some(h) = Self::refraction_half_vector(wo, wi, eta) else { return 0.0 };
        let ratio = 1.0 / eta; // η_i / η_o
        let denominator = wo.dot(h) + ratio * wi.dot(h);
        let jacobian = ratio * ratio * wi.dot(h).abs() / (denominator * denominator);
        self.normal_pdf(wo, h) * jacobian
    }

    /// f(wo, wi)·|cos θ_i| of rough refraction without the Fresnel factor, in the form without
    /// the radiance's η² scaling (the form the smooth refraction lobe uses, so that rough and
    /// smooth glass agree as the roughness vanishes): its sampling weight is G2 / G1(wo).
    pub fn transmission_eval(&self, wo: Vec3, wi: Vec3, eta: f32) -> f32 {
        let Some(h) = Self::refraction_half_vector(wo, wi, eta) else { return 0.0 };
        let ratio = 1.0 / eta;
        let denominator = wo.dot(h) + ratio * wi.dot(h);
        wi.dot(h).abs() * wo.dot(h) * ratio * ratio * self.d(h) * self.g2(wo, wi) / (wo.z * denominator * denominator)
    }
}

/// A slope (x, y) of Beckmann's distribution at unit roughness, visible from a direction of
/// cosine `cos_theta` in the xz plane (x toward it). y is Gaussian; x is found by inverting
/// its distribution function in the variable b = erf(x), where it reads
/// C(b) = (1 + b + tan θ e^(−erfinv(b)²) / √π) / (1 + erf(cot θ) + tan θ e^(−cot² θ) / √π),
/// by Newton's method kept inside a bisection bracket, from a fitted first guess.
fn beckmann_visible_slope(cos_theta: f32, u: Vec2) -> (f32, f32) {
    if cos_theta > 0.9999 {
        // Seen from straight above: the slopes' own Gaussian.
        let r = (-(1.0 - u.x).max(f32::MIN_POSITIVE).ln()).sqrt();
        let phi = 2.0 * PI * u.y;
        return (r * phi.cos(), r * phi.sin());
    }
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let tan_theta = sin_theta / cos_theta;
    let cot_theta = 1.0 / tan_theta;
    let inv_sqrt_pi = 1.0 / PI.sqrt();
    let (mut low, mut high) = (-1.0f32, erf(cot_theta));
    let target = u.x.max(1e-6);
    let theta = cos_theta.acos();
    let fit = 1.0 + theta * (-0.876 + theta * (0.4265 - 0.0594 * theta));
    let mut b = high - (1.0 + high) * (1.0 - target).powf(fit);
    let normalization = 1.0 / (1.0 + high + inv_sqrt_pi * tan_theta * (-cot_theta * cot_theta).exp());
    for _ in 0..10 {
        if !(b >= low && b <= high) {
            b = 0.5 * (low + high);
        }
        let x = erf_inv(b);
        let value = normalization * (1.0 + b + inv_sqrt_pi * tan_theta * (-x * x).exp()) - target;
        if value.abs() < 1e-5 {
            break;
        }
        if value > 0.0 {
            high = b;
        } else {
            low = b;
        }
        let derivative = normalization * (1.0 - x * tan_theta);
        b -= value / derivative;
    }
    (erf_inv(b.clamp(low, high)), erf_inv(2.0 * u.y.max(1e-6) - 1.0))
}

/// The error function (Abramowitz & Stegun 7.1.26, absolute error below 1.5·10⁻⁷).
fn erf(x: f32) -> f32 {
    let t = 1.0 / (1.0 + 0.327_591_1 * x.abs());
    let poly = t * (0.254_829_6 + t * (-0.284_496_74 + t * (1.421_413_7 + t * (-1.453_152 + t * 1.061_405_4))));
    (1.0 - poly * (-x * x).exp()).copysign(x)
}

/// The inverse error function on (−1, 1) (Giles' single-precision polynomials, 2010).
fn erf_inv(x: f32) -> f32 {
    // Within the polynomials' range: ±1 itself saturates at the largest finite answer.
    let x = x.clamp(-0.999_999_9, 0.999_999_9);
    let w = -((1.0 - x) * (1.0 + x)).ln();
    let p = if w < 5.0 {
        let w = w - 2.5;
        [
            2.810_226_4e-8,
            3.432_739_4e-7,
            -3.523_387_7e-6,
            -4.391_506_5e-6,
            2.185_808_7e-4,
            -1.253_725e-3,
            -4.177_681_6e-3,
            0.246_640_73,
            1.501_409_4,
        ]
        .iter()
        .fold(0.0, |p, c| c + p * w)
    } else {
        let w = w.sqrt() - 3.0;
        [
            -2.002_142_6e-4,
            1.009_505_6e-4,
            1.349_343_2e-3,
            -3.673_428_4e-3,
            5.739_507_7e-3,
            -7.622_461e-3,
            9.438_870_5e-3,
            1.001_674,
            2.832_976_8,
        ]
        .iter()
        .fold(0.0, |p, c| c + p * w)
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
