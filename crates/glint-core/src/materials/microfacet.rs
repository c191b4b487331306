//! Microfacet distributions for rough reflection and refraction (Walter et al. 2007): GGX
//! (Trowbridge–Reitz), with Smith masking-shadowing (height-correlated or separable) and sampling
//! of the visible normals (Heitz 2018, "Sampling the GGX Distribution of Visible Normals", JCGT
//! 7(4)); and Beckmann (Mitsuba's default), whose Smith G1 is the rational fit Walter et al. give
//! (as Mitsuba evaluates it) and whose normals are sampled by D(h) cos θ_h. Directions are
//! in the local frame, where the macro-surface normal is +z. `alpha_x`, `alpha_y` are the widths
//! along the frame's tangent and bitangent (equal: isotropic; the usual perceptual `roughness`
//! squared). The isotropic case keeps its own arithmetic, which the course's materials were
//! measured with.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

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

    /// A micro-normal for `wo` (wo.z > 0), from two uniform numbers: a visible one (GGX), or by
    /// D(h) cos θ_h (Beckmann: then it may face away from `wo`, and callers drop such samples).
    pub fn sample_normal(&self, wo: Vec3, u: Vec2) -> Vec3 {
        if self.distribution == Distribution::Beckmann {
            return self.sample_beckmann(u);
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

    /// Beckmann normals by D(h) cos θ_h: tan²θ = −α² ln(1 − u₁), φ from u₂ stretched by the
    /// widths (α² the width in that azimuth).
    fn sample_beckmann(&self, u: Vec2) -> Vec3 {
        let (ax, ay) = (self.alpha_x, self.alpha_y);
        let (phi, alpha2) = if self.is_isotropic() {
            (2.0 * PI * u.y, ax * ax)
        } else {
            let mut phi = (ay / ax * (2.0 * PI * u.y + 0.5 * PI).tan()).atan();
            if u.y > 0.5 {
                phi += PI;
            }
            let (sin, cos) = phi.sin_cos();
            (phi, 1.0 / (cos * cos / (ax * ax) + sin * sin / (ay * ay)))
        };
        let tan2 = -alpha2 * (1.0 - u.x).max(f32::MIN_POSITIVE).ln();
        let cos = 1.0 / (1.0 + tan2).sqrt();
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        Vec3::new(sin * phi.cos(), sin * phi.sin(), cos)
    }

    /// Density per solid angle of `sample_normal`'s micro-normal `h` for `wo`: the visible
    /// normals' G1(wo)·max(0, wo·h)·D(h) / cos θ_o, or Beckmann's D(h) cos θ_h.
    fn normal_pdf(&self, wo: Vec3, h: Vec3) -> f32 {
        match self.distribution {
            Distribution::Ggx => self.g1(wo) * wo.dot(h).max(0.0) * self.d(h) / wo.z,
            Distribution::Beckmann => self.d(h) * h.z,
        }
    }

    /// Density per solid angle of the reflected direction `wi` when `h` is sampled by
    /// `sample_normal`: the normal's density / (4 wo·h) (for GGX, G1(wo)·D(h) / (4 cos θ_o)).
    pub fn reflection_pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let h = (wo + wi).normalize();
        match self.distribution {
            Distribution::Ggx => self.g1(wo) * self.d(h) / (4.0 * wo.z),
            Distribution::Beckmann => self.normal_pdf(wo, h) / (4.0 * wo.dot(h)),
        }
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
