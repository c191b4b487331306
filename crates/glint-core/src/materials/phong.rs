//! The course's local illumination model: ambient + Lambert diffuse + Phong specular.
//!
//! Scene parameters (RGB colours in [0, 1], linear):
//! - `diffuse` k_d, default [0.8, 0.8, 0.8];
//! - `ambient` k_a, default = `diffuse` (the usual choice: ambient light tinted like the surface);
//! - `specular` k_s, default [0, 0, 0];
//! - `shininess` n (Phong exponent, ≥ 0), default 32.
//! ```toml
//! [materials.red_plastic]
//! type = "phong"
//! diffuse = [0.8, 0.1, 0.1]
//! specular = [0.5, 0.5, 0.5]
//! shininess = 64
//! ```
//! For one light: I · (k_d max(0, N·L) + k_s max(0, R·V)^n), R = 2(N·L)N − L, the specular
//! term only where the light is in front of the surface.

use glam::Vec3;

use crate::geometry::reflect;
use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct Phong {
    pub ambient: Rgb,
    pub diffuse: Rgb,
    pub specular: Rgb,
    pub shininess: f32,
}

impl Default for Phong {
    fn default() -> Self {
        let diffuse = Rgb::splat(0.8);
        Self { ambient: diffuse, diffuse, specular: Rgb::ZERO, shininess: 32.0 }
    }
}

impl Phong {
    pub fn local(&self, normal: Vec3, wo: Vec3, wi: Vec3, intensity: Rgb) -> Rgb {
        let cos_light = normal.dot(wi);
        if cos_light <= 0.0 {
            return Rgb::ZERO;
        }
        let mut reflectance = self.diffuse * cos_light;
        if self.specular != Rgb::ZERO {
            let mirror = reflect(-wi, normal);
            let cos_view = mirror.dot(wo).max(0.0);
            reflectance += self.specular * cos_view.powf(self.shininess);
        }
        intensity * reflectance
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lambert_and_phong_terms_by_hand() {
        let m = Phong { ambient: Rgb::ZERO, diffuse: Rgb::splat(0.5), specular: Rgb::splat(0.25), shininess: 2.0 };
        let n = Vec3::Y;
        let wi = Vec3::new(1.0, 1.0, 0.0).normalize(); // N·L = cos 45°
                                                       // Viewer exactly along the mirror direction: (R·V)^n = 1.
        let wo = Vec3::new(-1.0, 1.0, 0.0).normalize();
        let c = 0.5 * std::f32::consts::FRAC_1_SQRT_2 + 0.25;
        assert!((m.local(n, wo, wi, Rgb::ONE) - Rgb::splat(c)).length() < 1e-6);
        // Viewer straight above: R·V = cos 45°, squared = 0.5.
        let c = 0.5 * std::f32::consts::FRAC_1_SQRT_2 + 0.25 * 0.5;
        assert!((m.local(n, Vec3::Y, wi, Rgb::ONE) - Rgb::splat(c)).length() < 1e-6);
        // Light below the surface contributes nothing.
        assert_eq!(m.local(n, wo, -wi, Rgb::ONE), Rgb::ZERO);
    }
}
