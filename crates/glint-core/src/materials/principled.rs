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

use super::bsdf::{BsdfSample, Frame, Leaf, Lobes};
use super::{fresnel_dielectric, Distribution, Microfacet, PhongPoint};
use crate::geometry::{reflect, refract};
use crate::sampling::warp::square_to_cosine_hemisphere;
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

    fn evaluate(&self, query: &TextureQuery, frame: Frame) -> PrincipledBsdf {
        let scalar = |t: &Texture| t.evaluate(query).dot(LUMINANCE);
        let (roughness, anisotropic) = (scalar(&self.roughness), scalar(&self.anisotropic));
        let microfacet = disney_microfacet(roughness, anisotropic);
        let gloss = scalar(&self.clearcoat_gloss);
        PrincipledBsdf {
            // Anisotropic widths lie along the surface's ∂p/∂u.
            frame: if microfacet.alpha_x != microfacet.alpha_y { frame.along(query.dpdu) } else { frame },
            base: self.base_color.evaluate(query),
            roughness,
            metallic: scalar(&self.metallic),
            spec_trans: scalar(&self.spec_trans),
            spec_tint: scalar(&self.spec_tint),
            sheen: scalar(&self.sheen),
            sheen_tint: scalar(&self.sheen_tint),
            flatness: scalar(&self.flatness),
            clearcoat: scalar(&self.clearcoat),
            microfacet,
            clearcoat_alpha: 0.1 + gloss * (0.001 - 0.1),
            eta: self.eta,
        }
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
        let b = self.evaluate(query, frame);
        if b.inactive() {
            return PhongPoint::BLACK;
        }
        let f = b.fresnel(cos);
        let mut reflection = b.principled_fresnel(f, cos);
        let refracted = b.base.max(Rgb::ZERO).powf(0.5) * (b.bsdf_weight() * (1.0 - f));
        if !outside {
            return PhongPoint { reflection, transmission: refracted, ior: self.eta, ..PhongPoint::BLACK };
        }
        if b.clearcoat > 0.0 {
            reflection += Rgb::splat(b.clearcoat * schlick(Rgb::splat(0.04), cos, b.eta).x * cos * cos);
        }
        let diffuse = b.base * b.brdf();
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
pub(super) fn tint(base: Rgb) -> Rgb {
    let lum = base.dot(LUMINANCE);
    if lum > 0.0 {
        base / lum
    } else {
        Rgb::ONE
    }
}

/// Burley's diffuse with retro-reflection, leaning by `flatness` toward the Hanrahan–Krueger
/// fake subsurface: the factor of base/π·cos θ_i for a reflection between `o` and `i` (local,
/// both above) with half vector `h`.
pub(super) fn burley_diffuse(o: Vec3, i: Vec3, h: Vec3, roughness: f32, flatness: f32) -> f32 {
    let (fo, fi) = (schlick_weight(o.z), schlick_weight(i.z));
    let cos_d = h.dot(i);
    let diffuse = (1.0 - 0.5 * fo) * (1.0 - 0.5 * fi);
    let rr = 2.0 * roughness * cos_d * cos_d;
    let retro = rr * (fo + fi + fo * fi * (rr - 1.0));
    let lobe = diffuse + retro;
    if flatness == 0.0 {
        return lobe;
    }
    let fss90 = rr / 2.0;
    let fss = (1.0 + (fss90 - 1.0) * fi) * (1.0 + (fss90 - 1.0) * fo);
    let subsurface = 1.25 * (fss * (1.0 / (i.z + o.z) - 0.5) + 0.5);
    lobe + flatness * (subsurface - lobe)
}

/// The sheen's colour and Fresnel-like rise toward grazing, for a reflection whose half vector
/// makes cosine `cos_d` with the light: the factor of sheen·cos θ_i.
pub(super) fn sheen(base: Rgb, sheen_tint: f32, cos_d: f32) -> Rgb {
    (Rgb::ONE + (tint(base) - Rgb::ONE) * sheen_tint) * schlick_weight(cos_d.abs())
}

#[derive(Clone, Copy, Debug)]
pub(super) struct PrincipledBsdf {
    frame: Frame,
    base: Rgb,
    roughness: f32,
    metallic: f32,
    spec_trans: f32,
    spec_tint: f32,
    sheen: f32,
    sheen_tint: f32,
    flatness: f32,
    clearcoat: f32,
    microfacet: Microfacet,
    clearcoat_alpha: f32,
    /// n_interior / n_exterior.
    eta: f32,
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
pub(super) fn schlick_weight(cos: f32) -> f32 {
    let m = (1.0 - cos).clamp(0.0, 1.0);
    (m * m) * (m * m) * m
}

/// Schlick's Fresnel from the front of an interface of relative index `eta` (n_t / n_i): with
/// the incident cosine when η > 1, else with the transmitted one (1 past the critical angle).
pub(super) fn schlick(r0: Rgb, cos_i: f32, eta: f32) -> Rgb {
    let cos = if eta > 1.0 { cos_i.abs() } else { (1.0 - (1.0 - cos_i * cos_i) / (eta * eta)).max(0.0).sqrt() };
    r0 + (Rgb::ONE - r0) * schlick_weight(cos)
}

/// Smith's G1 for isotropic GGX of width `alpha`, 0 where `v` sees the back of the microfacet
/// `h` (the clearcoat's masking).
fn smith_g1(v: Vec3, h: Vec3, alpha: f32) -> f32 {
    if v.dot(h) * v.z <= 0.0 {
        return 0.0;
    }
    let cos2 = v.z * v.z;
    if cos2 >= 1.0 {
        return 1.0;
    }
    let tan2 = (1.0 - cos2) / cos2;
    2.0 / (1.0 + (1.0 + alpha * alpha * tan2).sqrt())
}

/// The clearcoat's micro-normals: Burley's GTR with γ = 1 (Berry's distribution), sampled
/// exactly by its cos θ_h-weighted density (not by visible normals: its lobe is weak).
#[derive(Clone, Copy, Debug)]
struct Gtr1 {
    alpha: f32,
}

impl Gtr1 {
    fn d(self, h: Vec3) -> f32 {
        let a2 = self.alpha * self.alpha;
        let d = (a2 - 1.0) / (PI * a2.ln() * (1.0 + (a2 - 1.0) * h.z * h.z));
        if d * h.z > 1e-20 {
            d
        } else {
            0.0
        }
    }

    /// Density of `sample`'s micro-normal per solid angle: D(h) cos θ_h.
    fn pdf(self, h: Vec3) -> f32 {
        if h.z < 0.0 {
            0.0
        } else {
            h.z * self.d(h)
        }
    }

    fn sample(self, u: Vec2) -> Vec3 {
        let a2 = self.alpha * self.alpha;
        let cos2 = ((1.0 - a2.powf(1.0 - u.y)) / (1.0 - a2)).clamp(0.0, 1.0);
        let (sin, cos) = ((1.0 - cos2).sqrt(), cos2.sqrt());
        let phi = 2.0 * PI * u.x;
        Vec3::new(phi.cos() * sin, phi.sin() * sin, cos)
    }
}

/// The lobe probabilities at one micro-normal's Fresnel reflectance `f`.
struct Choice {
    diffuse: f32,
    clearcoat: f32,
    reflection: f32,
    transmission: f32,
}

impl PrincipledBsdf {
    fn brdf(&self) -> f32 {
        (1.0 - self.metallic) * (1.0 - self.spec_trans)
    }

    fn bsdf_weight(&self) -> f32 {
        (1.0 - self.metallic) * self.spec_trans
    }

    /// Nothing to sample or evaluate: from behind without transmission.
    fn inactive(&self) -> bool {
        !self.frame.outside && self.bsdf_weight() <= 0.0
    }

    /// n(the other side) / n(the viewer's side).
    fn eta_path(&self) -> f32 {
        if self.frame.outside {
            self.eta
        } else {
            1.0 / self.eta
        }
    }

    /// The diffuse lobe's sampling weight: brdf, or the sheen's where brdf is 0.
    fn diffuse_weight(&self) -> f32 {
        let brdf = self.brdf();
        if brdf > 0.0 {
            brdf
        } else {
            self.sheen.max(0.0) * (1.0 - self.metallic).max(0.0)
        }
    }

    fn choice(&self, f: f32) -> Choice {
        let bsdf = self.bsdf_weight();
        if !self.frame.outside {
            return Choice { diffuse: 0.0, clearcoat: 0.0, reflection: f, transmission: 1.0 - f };
        }
        let (diffuse, clearcoat) = (self.diffuse_weight(), 0.25 * self.clearcoat.max(0.0));
        let total = 1.0 + diffuse + clearcoat;
        let transmission = bsdf * (1.0 - f);
        Choice {
            diffuse: diffuse / total,
            clearcoat: clearcoat / total,
            reflection: (1.0 - transmission) / total,
            transmission: transmission / total,
        }
    }

    /// The dielectric Fresnel reflectance at a micro-normal seen at cosine `cos` from the
    /// viewer's side.
    fn fresnel(&self, cos: f32) -> f32 {
        fresnel_dielectric(cos, 1.0 / self.eta_path())
    }

    /// The main reflection's Fresnel term: the dielectric one blended with Schlick's for the
    /// metallic part and for the part tinted toward the base colour; from behind, bsdf·F.
    fn principled_fresnel(&self, f: f32, cos: f32) -> Rgb {
        if !self.frame.outside {
            return Rgb::splat(self.bsdf_weight() * f);
        }
        let m = self.metallic;
        let tint = tint(self.base);
        let r0 = ((self.eta - 1.0) / (self.eta + 1.0)).powi(2);
        Rgb::splat((1.0 - m) * (1.0 - self.spec_tint) * f)
            + m * schlick(self.base, cos, self.eta)
            + (1.0 - m) * self.spec_tint * schlick(tint * r0, cos, self.eta)
    }

    /// Burley's diffuse, retro-reflection and fake subsurface, and the sheen (both ·cos θ_i),
    /// for a reflection with half vector `h` (front only).
    fn diffuse_and_sheen(&self, o: Vec3, i: Vec3, h: Vec3) -> Rgb {
        let mut value = Rgb::ZERO;
        let brdf = self.brdf();
        if brdf > 0.0 {
            value += self.base * (brdf * i.z / PI * burley_diffuse(o, i, h, self.roughness, self.flatness));
        }
        if self.sheen > 0.0 && self.metallic < 1.0 {
            value += sheen(self.base, self.sheen_tint, h.dot(i)) * (self.sheen * (1.0 - self.metallic) * i.z);
        }
        value
    }

    fn clearcoat_value(&self, o: Vec3, i: Vec3, h: Vec3) -> f32 {
        if self.clearcoat <= 0.0 {
            return 0.0;
        }
        let f = schlick(Rgb::splat(0.04), o.dot(h), self.eta).x;
        let g = smith_g1(o, h, 0.25) * smith_g1(i, h, 0.25);
        0.25 * self.clearcoat * f * Gtr1 { alpha: self.clearcoat_alpha }.d(h) * g * i.z
    }
}

impl Lobes for PrincipledBsdf {
    fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        let (o, i) = (self.frame.to_local(wo), self.frame.to_local(wi));
        if self.inactive() || o.z <= 0.0 {
            return Rgb::ZERO;
        }
        if self.frame.reflects(wi) {
            let h = (o + i).normalize();
            let f = self.fresnel(o.dot(h));
            let mut value = self.principled_fresnel(f, o.dot(h)) * self.microfacet.reflection_eval(o, i);
            if self.frame.outside {
                value += self.diffuse_and_sheen(o, i, h) + Rgb::splat(self.clearcoat_value(o, i, h));
            }
            return value;
        }
        let bsdf = self.bsdf_weight();
        if !self.frame.transmits(wi) || bsdf <= 0.0 {
            return Rgb::ZERO;
        }
        let eta = 1.0 / self.eta_path();
        let Some(h) = Microfacet::refraction_half_vector(o, i, eta) else { return Rgb::ZERO };
        let f = self.fresnel(o.dot(h));
        self.base.max(Rgb::ZERO).powf(0.5) * (bsdf * (1.0 - f) * self.microfacet.transmission_eval(o, i, eta))
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let (o, i) = (self.frame.to_local(wo), self.frame.to_local(wi));
        if self.inactive() || o.z <= 0.0 {
            return 0.0;
        }
        if self.frame.reflects(wi) {
            let h = (o + i).normalize();
            let p = self.choice(self.fresnel(o.dot(h)));
            let mut pdf = p.reflection * self.microfacet.reflection_pdf(o, i);
            if self.frame.outside {
                pdf += p.diffuse * i.z / PI;
                pdf += p.clearcoat * Gtr1 { alpha: self.clearcoat_alpha }.pdf(h) / (4.0 * i.dot(h));
            }
            return pdf;
        }
        if !self.frame.transmits(wi) {
            return 0.0;
        }
        let eta = 1.0 / self.eta_path();
        let Some(h) = Microfacet::refraction_half_vector(o, i, eta) else { return 0.0 };
        self.choice(self.fresnel(o.dot(h))).transmission * self.microfacet.transmission_pdf(o, i, eta)
    }

    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        let o = self.frame.to_local(wo);
        if self.inactive() || o.z <= 0.0 {
            return None;
        }
        // The lobe-independent part of the choice (any Fresnel value gives the same sums).
        let p = self.choice(0.0);
        let (local, reflected) = if u_lobe < p.diffuse {
            (square_to_cosine_hemisphere(u), true)
        } else if u_lobe < p.diffuse + p.clearcoat {
            (reflect(-o, Gtr1 { alpha: self.clearcoat_alpha }.sample(u)), true)
        } else {
            let h = self.microfacet.sample_normal(o, u);
            let specular = 1.0 - p.diffuse - p.clearcoat;
            let at = self.choice(self.fresnel(o.dot(h)));
            // The rest of `u_lobe` splits the specular share by this micro-normal's Fresnel.
            if u_lobe - p.diffuse - p.clearcoat < at.reflection.min(specular) {
                (reflect(-o, h), true)
            } else {
                (refract(-o, h, 1.0 / self.eta_path())?, false)
            }
        };
        let wi = self.frame.to_world(local);
        // A microfacet's reflection below the surface (or refraction above it) is lost light,
        // not a sample of another lobe.
        if reflected && !self.frame.reflects(wi) || !reflected && !self.frame.transmits(wi) {
            return None;
        }
        let eta_squared = if self.frame.transmits(wi) { self.eta_path() * self.eta_path() } else { 1.0 };
        self.weighed(wo, wi, eta_squared)
    }

    fn non_delta_probability(&self) -> f32 {
        if self.inactive() {
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
            let d = Gtr1 { alpha };
            // Quadrature in z = cos θ_h, fine enough near z = 1 for the peak: substitute
            // z = 1 − s³, so the nodes crowd toward the pole.
            let n = 400_000;
            let (mut integral, mut mean) = (0.0f64, 0.0f64);
            for k in 0..n {
                let s = (k as f64 + 0.5) / n as f64;
                let z = 1.0 - s * s * s;
                let dz = 3.0 * s * s / n as f64;
                let w = (d.pdf(Vec3::new((1.0 - z * z).max(0.0).sqrt() as f32, 0.0, z as f32)) as f64)
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
                let z = d.sample(Vec2::new(rng.next_f32(), rng.next_f32())).z as f64;
                sum += z;
                sum2 += z * z;
            }
            let sampled = sum / samples as f64;
            let error = ((sum2 / samples as f64 - sampled * sampled) / samples as f64).sqrt();
            assert!((sampled - mean).abs() < 5.0 * error + 1e-5, "alpha {alpha}: {sampled} vs {mean}");
            if alpha >= 0.1 {
                let r = crate::sampling::chi2::chi2_test_with_resolution(
                    |u| Some(d.sample(u)),
                    |w| d.pdf(w) as f64,
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
