//! Rough plastic, Mitsuba's `roughplastic`: a diffuse base under a rough dielectric coat (GGX
//! or Beckmann).
//! The coat reflects as a rough dielectric does; the base's light passes the coat in and out
//! with the coat's transmittance t(cos θ) = 1 − (the rough coat's directional albedo), computed
//! once per material by quadrature over visible microfacets (Mitsuba's model), and is reflected
//! inside with the coat's internal diffuse reflectance F_dr' (the same quadrature, from inside).
//!
//! Scene parameters: those of `plastic`, `alpha` (default 0.1) and `distribution` (`ggx`, the
//! default, or `beckmann`, Mitsuba's default).
//! ```toml
//! [materials.satin]
//! type = "rough-plastic"
//! diffuse_reflectance = [0.1, 0.3, 0.6]
//! alpha = 0.2
//! ```
//! f·cos θ_i = specular · F(wo·h) D(h) G1(wo) G1(wi) / (4 cos θ_o)
//!           + k_d / (1 − F_dr') · (cos θ_i / π) · (1/η²) · t(cos θ_o) t(cos θ_i).
//! The coat is chosen with probability ∝ (1 − t(cos θ_o))·w_s against t(cos θ_o)·(1 − w_s).

use std::sync::Arc;

use glam::{Vec2, Vec3};

use super::bsdf::{BsdfSample, Frame, LaneBsdfSample, LaneFrame, Leaf, Lobes};
use super::microfacet::{Distribution, GlossyOrDiffuse, MicrofacetLanes};
use super::phong::fresnel_dielectric_lanes;
use super::plastic::Coat;
use super::{fresnel_dielectric, Microfacet, PhongPoint, Plastic};
use crate::geometry::{reflect, refract};
use crate::lanes::{self, LaneVec3, Lanes};
use crate::sampling::warp::square_to_cosine_hemisphere_lanes;
use crate::textures::TextureQuery;
use crate::Rgb;
use std::f32::consts::FRAC_1_PI;

/// Entries of the transmittance table, cos θ from 0 to 1.
const TABLE_SIZE: usize = 64;

#[derive(Clone, Debug, PartialEq)]
pub struct RoughPlastic {
    pub plastic: Plastic,
    pub alpha: f32,
    pub distribution: Distribution,
    coat: Arc<CoatTables>,
}

/// The rough coat's transmittance from outside by cos θ, and its internal diffuse reflectance.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct CoatTables {
    transmittance: [f32; TABLE_SIZE],
    internal_reflectance: f32,
}

impl RoughPlastic {
    pub fn new(plastic: Plastic, alpha: f32, distribution: Distribution) -> Self {
        let coat = Arc::new(CoatTables::new(Microfacet::separable(alpha, alpha).with(distribution), plastic.eta));
        Self { plastic, alpha, distribution, coat }
    }

    pub(super) fn bsdf<'a>(&'a self, query: &TextureQuery, wo: Vec3, frame: Frame) -> Leaf<'a> {
        let p = &self.plastic;
        let coat = Coat::new(
            p.diffuse.evaluate(query),
            p.specular.evaluate(query),
            p.eta,
            p.nonlinear,
            self.coat.internal_reflectance,
        );
        let t_o = self.coat.lookup(wo.dot(frame.normal));
        let p_specular = if frame.outside { coat.specular_probability(1.0 - t_o) } else { 0.0 };
        Leaf::RoughPlastic(RoughPlasticBsdf {
            frame,
            coat,
            lobes: GlossyOrDiffuse {
                microfacet: Microfacet::separable(self.alpha, self.alpha).with(self.distribution),
                p_glossy: p_specular,
            },
            tables: &self.coat,
            t_o,
        })
    }

    /// The coat's colours at a point (`Coat`) and its transmittance table, as `bsdf` makes
    /// them: for the lanes.
    pub(crate) fn coat_at(&self, query: &TextureQuery) -> (Coat, &CoatTables) {
        let p = &self.plastic;
        let (diffuse, specular) = (p.diffuse.evaluate(query), p.specular.evaluate(query));
        (Coat::new(diffuse, specular, p.eta, p.nonlinear, self.coat.internal_reflectance), &self.coat)
    }

    /// Whitted's view: the coat's smooth limit, smooth plastic's (`plastic.rs`; Whitted traces
    /// no glossy rays).
    pub(super) fn whitted(&self, query: &TextureQuery, outside: bool, cos: f32) -> PhongPoint {
        self.plastic.whitted(query, outside, cos)
    }
}

impl CoatTables {
    /// Gauss–Legendre quadrature over the visible-normal samples of each direction, 32 × 32
    /// nodes (128 × 128 for η < 1, where total internal reflection makes the integrand sharp).
    fn new(microfacet: Microfacet, eta: f32) -> Self {
        let nodes = gauss_legendre(if eta > 1.0 { 32 } else { 128 });
        let cosine = |j: usize| (j as f32 / (TABLE_SIZE - 1) as f32).max(1e-6);
        let direction = |mu: f32| Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
        // ∫ over visible normals of `term(wo, h)`.
        let integrate = |wo: Vec3, term: &dyn Fn(Vec3, Vec3) -> f32| -> f32 {
            let mut sum = 0.0f64;
            for &(x, wx) in &nodes {
                for &(y, wy) in &nodes {
                    let u = Vec2::new(0.5 * x as f32 + 0.5, 0.5 * y as f32 + 0.5);
                    let h = microfacet.sample_normal(wo, u);
                    sum += 0.25 * wx * wy * term(wo, h) as f64;
                }
            }
            sum as f32
        };
        // G1 with Mitsuba's side test: zero where w and h are on different sides of the surface.
        let g1 = |w: Vec3, h: Vec3| if w.dot(h) * w.z > 0.0 { microfacet.g1(w) } else { 0.0 };
        let transmittance = std::array::from_fn(|j| {
            integrate(direction(cosine(j)), &|wo, h| {
                let Some(wt) = refract(-wo, h, 1.0 / eta) else { return 0.0 };
                if wt.z * wo.z >= 0.0 {
                    return 0.0;
                }
                (1.0 - fresnel_dielectric(wo.dot(h), 1.0 / eta)) * g1(wt, h)
            })
        });
        let mut internal = 0.0f32;
        for j in 0..TABLE_SIZE {
            let mu = cosine(j);
            let reflectance = integrate(direction(mu), &|wo, h| {
                let wr = reflect(-wo, h);
                if wr.z <= 0.0 || wo.z <= 0.0 {
                    return 0.0;
                }
                fresnel_dielectric(wo.dot(h), eta) * g1(wr, h)
            });
            internal += reflectance * mu;
        }
        Self { transmittance, internal_reflectance: 2.0 * internal / TABLE_SIZE as f32 }
    }

    /// t(cos θ), linear between the table's entries.
    pub(crate) fn lookup(&self, cos: f32) -> f32 {
        let x = cos.clamp(0.0, 1.0) * (TABLE_SIZE - 1) as f32;
        let i = (x as usize).min(TABLE_SIZE - 2);
        let f = x - i as f32;
        self.transmittance[i] * (1.0 - f) + self.transmittance[i + 1] * f
    }
}

/// The nodes and weights of n-point Gauss–Legendre quadrature on [−1, 1] (Newton's method on
/// the Legendre polynomial from Chebyshev's first guesses).
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut derivative = 0.0;
            for _ in 0..100 {
                // P_n(x) and P_n'(x) by the three-term recurrence.
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                let p = if n == 0 { 1.0 } else { p1 };
                derivative = n as f64 * (x * p - p0) / (x * x - 1.0);
                let step = p / derivative;
                x -= step;
                if step.abs() < 1e-15 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * derivative * derivative))
        })
        .collect()
}

/// The coat's transmittance table as the lane body reads it: one table at one lane, each
/// lane's own at eight.
pub(crate) trait CoatTransmittance<L> {
    /// t(cos θ) (`CoatTables::lookup`).
    fn transmittance(&self, cos: L) -> L;
}

impl CoatTransmittance<f32> for &CoatTables {
    #[inline(always)]
    fn transmittance(&self, cos: f32) -> f32 {
        self.lookup(cos)
    }
}

/// The rough plastic at a hit, in lanes: the one body of its `eval`, `pdf` and `sample`,
/// which the scalar BSDF runs at one lane and the wavefront at eight.
#[derive(Clone, Debug)]
pub(crate) struct RoughPlasticLanes<L: Lanes, T> {
    pub frame: LaneFrame<L>,
    /// The base's colour after its internal scattering (`Coat::diffuse`), the coat's colour,
    /// and its relative index.
    pub diffuse: LaneVec3<L>,
    pub specular: LaneVec3<L>,
    pub eta: L,
    /// The coat's transmittance toward the viewer, t(cos θ_o), and the probability of
    /// sampling its reflection (0 from behind).
    pub t_o: L,
    pub p_glossy: L,
    pub microfacet: MicrofacetLanes<L>,
    pub tables: T,
}

impl<L: Lanes, T: CoatTransmittance<L>> RoughPlasticLanes<L, T> {
    /// The coat's microfacet reflection plus the base seen through it, where `wi` reflects on
    /// the viewer's side of a front face, else 0.
    #[inline(always)]
    pub fn eval(&self, wo: LaneVec3<L>, wi: LaneVec3<L>) -> LaneVec3<L> {
        let (o, i) = (self.frame.to_local(wo), self.frame.to_local(wi));
        let h = (o + i).normalize();
        let coat = fresnel_dielectric_lanes(o.dot(h), L::ONE / self.eta) * self.microfacet.reflection_eval(o, i);
        let through = self.t_o * self.tables.transmittance(i.z) / (self.eta * self.eta);
        let value = self.specular * coat + self.diffuse * (i.z * L::splat(FRAC_1_PI) * through);
        LaneVec3::select(self.frame.outside & self.frame.reflects(wi), value, LaneVec3::ZERO)
    }

    /// The coat's reflection with probability `p_glossy`, else Lambert's lobe
    /// (`GlossyOrDiffuse::pdf`).
    #[inline(always)]
    pub fn pdf(&self, wo: LaneVec3<L>, wi: LaneVec3<L>) -> L {
        let (o, i) = (self.frame.to_local(wo), self.frame.to_local(wi));
        let cosine = L::select(i.z.gt(L::ZERO), i.z * L::splat(FRAC_1_PI), L::ZERO);
        let pdf = self.p_glossy * self.microfacet.reflection_pdf(o, i) + (L::ONE - self.p_glossy) * cosine;
        L::select(self.frame.outside & self.frame.reflects(wi), pdf, L::ZERO)
    }

    /// The coat's reflection about a visible normal where `u_lobe` < `p_glossy`, else the
    /// cosine-weighted base; weighed by eval / pdf.
    #[inline(always)]
    pub fn sample(&self, wo: LaneVec3<L>, u_lobe: L, u1: L, u2: L) -> LaneBsdfSample<L> {
        let o = self.frame.to_local(wo);
        let glossy = u_lobe.lt(self.p_glossy);
        let local = if !L::any(!glossy) {
            lanes::reflect(-o, self.microfacet.sample_normal(o, u1, u2))
        } else if !L::any(glossy) {
            square_to_cosine_hemisphere_lanes(u1, u2)
        } else {
            let reflected = lanes::reflect(-o, self.microfacet.sample_normal(o, u1, u2));
            LaneVec3::select(glossy, reflected, square_to_cosine_hemisphere_lanes(u1, u2))
        };
        let wi = self.frame.to_world(local);
        LaneBsdfSample::weighed(wi, self.eval(wo, wi), self.pdf(wo, wi), self.frame.outside, L::ONE)
    }
}

#[derive(Clone, Copy, Debug)]
pub(super) struct RoughPlasticBsdf<'a> {
    frame: Frame,
    coat: Coat,
    /// The coat's lobe and the base's, and how they are sampled (the coat's probability 0
    /// from behind: then nothing is sampled).
    lobes: GlossyOrDiffuse,
    tables: &'a CoatTables,
    /// The coat's transmittance toward the viewer, t(cos θ_o).
    t_o: f32,
}

impl<'a> RoughPlasticBsdf<'a> {
    /// The lobe as its one body reads it.
    #[inline(always)]
    fn lanes(&self) -> RoughPlasticLanes<f32, &'a CoatTables> {
        RoughPlasticLanes {
            frame: LaneFrame::from(&self.frame),
            diffuse: self.coat.diffuse.into(),
            specular: self.coat.specular.into(),
            eta: self.coat.eta,
            t_o: self.t_o,
            p_glossy: self.lobes.p_glossy,
            microfacet: MicrofacetLanes::from(&self.lobes.microfacet),
            tables: self.tables,
        }
    }
}

impl Lobes for RoughPlasticBsdf<'_> {
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
        self.frame.front_only()
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
    use crate::materials::testing::{albedo, at, check_sampling, frame_toward, furnace};
    use crate::materials::{fresnel_diffuse_reflectance, Plastic};
    use crate::textures::Texture;

    fn satin(diffuse: f32, alpha: f32) -> RoughPlastic {
        satin_with(diffuse, alpha, Distribution::Ggx)
    }

    fn satin_with(diffuse: f32, alpha: f32, distribution: Distribution) -> RoughPlastic {
        let plastic = Plastic {
            diffuse: Texture::Constant(Rgb::splat(diffuse)),
            specular: Texture::Constant(Rgb::ONE),
            eta: 1.49,
            nonlinear: false,
        };
        RoughPlastic::new(plastic, alpha, distribution)
    }

    #[test]
    fn gauss_legendre_integrates_polynomials_exactly() {
        let nodes = gauss_legendre(8);
        for k in 0..16 {
            let integral: f64 = nodes.iter().map(|&(x, w)| w * x.powi(k)).sum();
            let exact = if k % 2 == 0 { 2.0 / (k + 1) as f64 } else { 0.0 };
            assert!((integral - exact).abs() < 1e-12, "x^{k}: {integral}");
        }
    }

    /// As the coat smooths, its tables tend to the smooth coat's: t = 1 − F and F_dr' = F_dr.
    #[test]
    fn tables_tend_to_the_smooth_coat() {
        for distribution in [Distribution::Ggx, Distribution::Beckmann] {
            let tables = CoatTables::new(Microfacet::separable(0.01, 0.01).with(distribution), 1.49);
            for cos in [0.3f32, 0.6, 0.95] {
                let smooth = 1.0 - fresnel_dielectric(cos, 1.0 / 1.49);
                assert!((tables.lookup(cos) - smooth).abs() < 0.01, "cos {cos}: {} vs {smooth}", tables.lookup(cos));
            }
            let smooth = fresnel_diffuse_reflectance(1.0 / 1.49);
            let internal = tables.internal_reflectance;
            assert!((internal - smooth).abs() < 0.03, "{distribution:?}: {internal} vs {smooth}");
        }
    }

    /// The transmittance table against the integral itself, taken by the midpoint rule over
    /// the micro-normals' hemisphere (no sampling routine involved): t(wo) = ∫ D_wo(h)
    /// (1 − F(wo·h)) G1(wt) dh with the visible normals' density D_wo(h) = G1(wo) (wo·h)⁺ D(h)
    /// / cos θ_o, for both distributions at α = 0.1 and 0.4. (Beckmann's normals, once drawn
    /// by D cos θ_h rather than as visible normals, made a table 2–6 % off.)
    #[test]
    fn transmittance_tables_match_the_integral_by_quadrature() {
        for distribution in [Distribution::Ggx, Distribution::Beckmann] {
            for alpha in [0.1f32, 0.4] {
                let microfacet = Microfacet::separable(alpha, alpha).with(distribution);
                let eta = 1.49f32;
                let tables = CoatTables::new(microfacet, eta);
                // Entries of the table at cos θ = 0.21, 0.51 and 0.90.
                for j in [13usize, 32, 57] {
                    let cos = j as f32 / (TABLE_SIZE - 1) as f32;
                    let wo = Vec3::new((1.0 - cos * cos).sqrt(), 0.0, cos);
                    let (n_theta, n_phi) = (1200, 240);
                    let mut sum = 0.0f64;
                    for i in 0..n_theta {
                        let theta = (i as f64 + 0.5) * std::f64::consts::FRAC_PI_2 / n_theta as f64;
                        for j in 0..n_phi {
                            let phi = (j as f64 + 0.5) * std::f64::consts::TAU / n_phi as f64;
                            let h = Vec3::new(
                                (theta.sin() * phi.cos()) as f32,
                                (theta.sin() * phi.sin()) as f32,
                                theta.cos() as f32,
                            );
                            let visible = microfacet.g1(wo) * wo.dot(h).max(0.0) * microfacet.d(h) / wo.z;
                            let Some(wt) = refract(-wo, h, 1.0 / eta) else { continue };
                            let g1 = if wt.dot(h) * wt.z > 0.0 { microfacet.g1(wt) } else { 0.0 };
                            let term = visible * (1.0 - fresnel_dielectric(wo.dot(h), 1.0 / eta)) * g1;
                            let area = theta.sin()
                                * (std::f64::consts::FRAC_PI_2 / n_theta as f64)
                                * (std::f64::consts::TAU / n_phi as f64);
                            sum += term as f64 * area;
                        }
                    }
                    let table = tables.transmittance[j];
                    assert!(
                        (table as f64 - sum).abs() < 0.01,
                        "{distribution:?} α {alpha}, cos {cos}: table {table} vs quadrature {sum}"
                    );
                }
            }
        }
    }

    #[test]
    fn sampling_matches_pdf() {
        let n = Vec3::new(0.2, -0.1, 1.0).normalize();
        for (alpha, distribution, seed) in
            [(0.1, Distribution::Ggx, 71), (0.5, Distribution::Ggx, 72), (0.2, Distribution::Beckmann, 73)]
        {
            for wo in [Vec3::new(0.3, -0.2, 0.9), Vec3::new(-0.9, 0.3, 0.25)] {
                let wo = wo.normalize();
                let material = satin_with(0.5, alpha, distribution);
                let bsdf = at(&material.bsdf(&Default::default(), wo, frame_toward(wo, n)));
                check_sampling(&bsdf, wo, n, seed);
            }
        }
    }

    /// White furnace bounds: ≤ 1 within the model's approximations, and with a black base the
    /// rough coat's albedo alone (1 − t(cos θ_o) less the light single scattering misses).
    #[test]
    fn furnace_bounds() {
        let wo = Vec3::new(0.3, 0.0, 0.95).normalize();
        let white = satin(1.0, 0.3);
        let a = furnace(&at(&white.bsdf(&Default::default(), wo, frame_toward(wo, Vec3::Z))), wo, 14);
        assert!(a.mean > 0.6, "{a:?}");
        let black = satin(0.0, 0.3);
        let a = albedo(&at(&black.bsdf(&Default::default(), wo, frame_toward(wo, Vec3::Z))), wo, 200_000, 15);
        let coat = 1.0 - black.coat.lookup(wo.z) as f64;
        assert!(a.mean <= coat + 4.0 * a.standard_error && a.mean > coat - 0.05, "{a:?} vs {coat}");
    }
}
