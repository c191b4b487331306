//! The course's material: ambient + Lambert diffuse + Phong specular for local light, plus the
//! Whitted terms, mirror reflection k_r and transmission k_t with an index of refraction.
//!
//! Scene parameters (colours are linear RGB, or the name of a texture):
//! - `diffuse` k_d, default [0.8, 0.8, 0.8];
//! - `ambient` k_a, default = `diffuse` (ambient light tinted like the surface);
//! - `specular` k_s, default [0, 0, 0]; `shininess` n (Phong exponent ≥ 0), default 32;
//! - `reflection` k_r, default [0, 0, 0]; `transmission` k_t, default [0, 0, 0];
//! - `ior`, index of refraction (> 0) of the inside, default 1.5 (glass);
//! - `fresnel`: `"none"` (k_r, k_t used as given, the course's default), `"schlick"` or
//!   `"exact"` (the dielectric Fresnel equations split k_t between reflection and
//!   transmission by the angle of incidence).
//! ```toml
//! [materials.glass]
//! type = "phong"
//! diffuse = [0, 0, 0]
//! specular = [1, 1, 1]
//! shininess = 200
//! transmission = [0.9, 0.9, 0.9]
//! ior = 1.5
//! fresnel = "exact"
//! ```
//! For one light: I · (k_d max(0, N·L) + k_s max(0, R·V)^n), R = 2(N·L)N − L, the specular
//! term only where the light is in front of the surface.

use glam::Vec3;

use crate::geometry::reflect;
use crate::lanes::Lanes;
use crate::textures::{Texture, TextureQuery};
use crate::Rgb;

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Fresnel {
    #[default]
    None,
    Schlick,
    Exact,
    /// A metal: k_r is multiplied by the conductor Fresnel reflectance of η + ik (per channel).
    Conductor {
        eta: Rgb,
        k: Rgb,
    },
}

#[derive(Clone, Debug, PartialEq)]
pub struct Phong {
    /// `None`: the same as `diffuse`.
    pub ambient: Option<Texture>,
    pub diffuse: Texture,
    pub specular: Texture,
    pub shininess: f32,
    pub reflection: Texture,
    pub transmission: Texture,
    pub ior: f32,
    pub fresnel: Fresnel,
    /// Roughness of the reflection lobe for the path tracers (0 = perfect mirror; GGX with
    /// α = roughness² otherwise). Whitted always reflects as a perfect mirror.
    pub roughness: f32,
    /// Emitted radiance (an area light on whatever shape wears the material).
    pub emission: Rgb,
    /// Emit from both sides (default: only the side the geometric normal points to).
    pub two_sided_emission: bool,
}

impl Default for Phong {
    fn default() -> Self {
        Self {
            ambient: None,
            diffuse: Texture::Constant(Rgb::splat(0.8)),
            specular: Texture::Constant(Rgb::ZERO),
            shininess: 32.0,
            reflection: Texture::Constant(Rgb::ZERO),
            transmission: Texture::Constant(Rgb::ZERO),
            ior: 1.5,
            fresnel: Fresnel::None,
            roughness: 0.0,
            emission: Rgb::ZERO,
            two_sided_emission: false,
        }
    }
}

impl Phong {
    /// The material's values at one point (textures looked up once per hit).
    pub fn evaluate(&self, query: &TextureQuery) -> PhongPoint {
        let diffuse = self.diffuse.evaluate(query);
        PhongPoint {
            ambient: self.ambient.as_ref().map_or(diffuse, |t| t.evaluate(query)),
            diffuse,
            specular: self.specular.evaluate(query),
            shininess: self.shininess,
            reflection: self.reflection.evaluate(query),
            transmission: self.transmission.evaluate(query),
            ior: self.ior,
            fresnel: self.fresnel,
            roughness: self.roughness,
            emission: self.emission,
            two_sided_emission: self.two_sided_emission,
            straight: Rgb::ZERO,
            translucency: Rgb::ZERO,
            coat_ior: 1.0,
        }
    }
}

/// A Phong material evaluated at a point: plain colours on the stack. The last three fields
/// are not the course's: they let Whitted read members of the BSDF set faithfully (`Material::
/// whitted_at`), and are zero (the coat's index 1) for the course's material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhongPoint {
    pub ambient: Rgb,
    pub diffuse: Rgb,
    pub specular: Rgb,
    pub shininess: f32,
    pub reflection: Rgb,
    pub transmission: Rgb,
    pub ior: f32,
    pub fresnel: Fresnel,
    pub roughness: f32,
    pub emission: Rgb,
    pub two_sided_emission: bool,
    /// Weight of a child ray that goes on unbent, whatever `ior` says: light through a thin
    /// sheet or a mask's clear part.
    pub straight: Rgb,
    /// Lambert's term through the surface (diffuse transmission): a light on the far side
    /// adds translucency·|N·L|·I.
    pub translucency: Rgb,
    /// Index of a smooth dielectric coat over the Lambert term (a plastic): light reaches the
    /// base through it, so k_d is weighed by the coat's transmittance 1 − F(N·L). 1: no coat.
    pub coat_ior: f32,
}

impl PhongPoint {
    /// Nothing: no light reflected, transmitted or emitted (what a member's Whitted terms
    /// start from).
    pub const BLACK: Self = Self {
        ambient: Rgb::ZERO,
        diffuse: Rgb::ZERO,
        specular: Rgb::ZERO,
        shininess: 32.0,
        reflection: Rgb::ZERO,
        transmission: Rgb::ZERO,
        ior: 1.5,
        fresnel: Fresnel::None,
        roughness: 0.0,
        emission: Rgb::ZERO,
        two_sided_emission: false,
        straight: Rgb::ZERO,
        translucency: Rgb::ZERO,
        coat_ior: 1.0,
    };

    /// (1 − w)·self + w·other for the colours; the index, Fresnel rule, coat and exponent of
    /// the one weighed more (Whitted's reading of a blend). Exact for the child rays' weights
    /// when both points' Fresnel factors are already applied (`Fresnel::None`, as
    /// `Material::whitted_at` gives them): a blend of BSDFs is linear in its members.
    pub fn blend(&self, other: &Self, w: f32) -> Self {
        let mix = |a: Rgb, b: Rgb| a * (1.0 - w) + b * w;
        let major = if w > 0.5 { other } else { self };
        Self {
            ambient: mix(self.ambient, other.ambient),
            diffuse: mix(self.diffuse, other.diffuse),
            specular: mix(self.specular, other.specular),
            reflection: mix(self.reflection, other.reflection),
            transmission: mix(self.transmission, other.transmission),
            emission: mix(self.emission, other.emission),
            straight: mix(self.straight, other.straight),
            translucency: mix(self.translucency, other.translucency),
            ..*major
        }
    }

    /// Radiance emitted toward `wo` from a surface with geometric normal `geometric_normal`.
    pub fn emitted(&self, wo: Vec3, geometric_normal: Vec3) -> Rgb {
        if self.two_sided_emission || wo.dot(geometric_normal) > 0.0 {
            self.emission
        } else {
            Rgb::ZERO
        }
    }

    /// k_d (N·L) + k_s (R·V)^n times the light's intensity; `normal` faces the viewer. A light
    /// behind the surface adds only the translucency's |N·L|.
    pub fn local(&self, normal: Vec3, wo: Vec3, wi: Vec3, intensity: Rgb) -> Rgb {
        let cos_light = normal.dot(wi);
        if cos_light <= 0.0 {
            if self.translucency == Rgb::ZERO {
                return Rgb::ZERO;
            }
            return intensity * self.translucency * -cos_light;
        }
        let mut reflectance = self.diffuse * cos_light;
        if self.coat_ior != 1.0 {
            reflectance *= 1.0 - fresnel_dielectric(cos_light, 1.0 / self.coat_ior);
        }
        if self.specular != Rgb::ZERO {
            let mirror = reflect(-wi, normal);
            let cos_view = mirror.dot(wo).max(0.0);
            reflectance += self.specular * cos_view.powf(self.shininess);
        }
        intensity * reflectance
    }

    /// Weights of the reflected and transmitted rays for incidence `cos_incident` (> 0) and
    /// index ratio `eta` = n_incident / n_transmitted. With Fresnel, k_t is split into F·k_t
    /// reflected and (1 − F)·k_t transmitted; the caller moves all of the transmitted weight to
    /// reflection on total internal reflection.
    pub fn ray_weights(&self, cos_incident: f32, eta: f32) -> (Rgb, Rgb) {
        let f = match self.fresnel {
            Fresnel::None => return (self.reflection, self.transmission),
            Fresnel::Conductor { eta, k } => {
                return (self.reflection * super::fresnel_conductor(cos_incident, eta, k), self.transmission)
            }
            Fresnel::Schlick => fresnel_schlick(cos_incident, eta),
            Fresnel::Exact => fresnel_dielectric(cos_incident, eta),
        };
        (self.reflection + self.transmission * f, self.transmission * (1.0 - f))
    }
}

/// Unpolarised Fresnel reflectance of a dielectric interface (Hecht, Optics §4.6), for the
/// cosine of the incident angle and η = n_incident / n_transmitted; 1 past the critical angle.
pub fn fresnel_dielectric(cos_incident: f32, eta: f32) -> f32 {
    let cos_i = cos_incident.clamp(0.0, 1.0);
    if eta * eta * (1.0 - cos_i * cos_i) >= 1.0 {
        return 1.0; // total internal reflection
    }
    fresnel_dielectric_lanes(cos_i, eta)
}

/// `fresnel_dielectric` in lanes.
#[inline(always)]
pub(crate) fn fresnel_dielectric_lanes<L: Lanes>(cos_incident: L, eta: L) -> L {
    let cos_i = cos_incident.max(L::ZERO).min(L::ONE);
    let sin2_t = eta * eta * (L::ONE - cos_i * cos_i);
    let cos_t = (L::ONE - sin2_t).sqrt();
    // With n_i/n_t = η: r_s = (η cos_i − cos_t)/(η cos_i + cos_t), r_p = (cos_i − η cos_t)/(cos_i + η cos_t).
    let r_s = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_p = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    L::select(sin2_t.ge(L::ONE), L::ONE, L::splat(0.5) * (r_s * r_s + r_p * r_p))
}

/// Schlick's approximation; inside the denser medium it uses the transmitted angle's cosine,
/// and it is 1 past the critical angle, as the exact equations are.
pub fn fresnel_schlick(cos_incident: f32, eta: f32) -> f32 {
    let cos_i = cos_incident.clamp(0.0, 1.0);
    let r0 = ((1.0 - eta) / (1.0 + eta)).powi(2);
    let cos = if eta > 1.0 {
        let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
        if sin2_t >= 1.0 {
            return 1.0;
        }
        (1.0 - sin2_t).sqrt()
    } else {
        cos_i
    };
    r0 + (1.0 - r0) * (1.0 - cos).powi(5)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point() -> PhongPoint {
        Phong::default().evaluate(&TextureQuery::default())
    }

    #[test]
    fn lambert_and_phong_terms_by_hand() {
        let m = PhongPoint { diffuse: Rgb::splat(0.5), specular: Rgb::splat(0.25), shininess: 2.0, ..point() };
        let n = Vec3::Y;
        let wi = Vec3::new(1.0, 1.0, 0.0).normalize(); // N·L = cos 45°
                                                       // Viewer exactly along the mirror direction: (R·V)^n = 1.
        let wo = Vec3::new(-1.0, 1.0, 0.0).normalize();
        let c = 0.5 * std::f32::consts::FRAC_1_SQRT_2 + 0.25;
        assert!((m.local(n, wo, wi, Rgb::ONE) - Rgb::splat(c)).length() < 1e-6);
        // Viewer straight above: R·V = cos 45°, squared = 0.5.
        let c = 0.5 * std::f32::consts::FRAC_1_SQRT_2 + 0.25 * 0.5;
        assert!((m.local(n, Vec3::Y, wi, Rgb::ONE) - Rgb::splat(c)).length() < 1e-6);
        assert_eq!(m.local(n, wo, -wi, Rgb::ONE), Rgb::ZERO);
    }

    #[test]
    fn fresnel_by_hand() {
        // Normal incidence on glass: ((1 − 1.5)/(1 + 1.5))² = 0.04, for both formulas.
        assert!((fresnel_dielectric(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6);
        assert!((fresnel_schlick(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6);
        // Grazing: everything reflects.
        assert!(fresnel_dielectric(0.0, 1.0 / 1.5) > 0.999);
        // Past the critical angle from inside: total internal reflection.
        assert_eq!(fresnel_dielectric(0.5, 1.5), 1.0);
        assert_eq!(fresnel_schlick(0.5, 1.5), 1.0);
        // Brewster's angle (tan θ = 1.5): r_p = 0, so F = r_s²/2 ≈ 0.0739.
        let brewster = 1.5f32.atan();
        assert!((fresnel_dielectric(brewster.cos(), 1.0 / 1.5) - 0.0739).abs() < 1e-3);
        // Schlick stays close to exact.
        for i in 0..=20 {
            let c = i as f32 / 20.0;
            assert!((fresnel_schlick(c, 1.0 / 1.5) - fresnel_dielectric(c, 1.0 / 1.5)).abs() < 0.04);
        }
    }

    #[test]
    fn fresnel_splits_transmission() {
        let m = PhongPoint { transmission: Rgb::ONE, fresnel: Fresnel::Exact, ..point() };
        let (r, t) = m.ray_weights(1.0, 1.0 / 1.5);
        assert!((r - Rgb::splat(0.04)).abs().max_element() < 1e-6);
        assert!((r + t - Rgb::ONE).abs().max_element() < 1e-6);
        let plain = PhongPoint { reflection: Rgb::splat(0.3), transmission: Rgb::splat(0.5), ..point() };
        assert_eq!(plain.ray_weights(0.2, 0.5), (Rgb::splat(0.3), Rgb::splat(0.5)));
    }
}
