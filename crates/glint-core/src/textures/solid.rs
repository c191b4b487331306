//! Solid textures from noise: marble and wood (Perlin 1985, "An Image Synthesizer").
//!
//! Scene parameters:
//! - `type = "marble"`: `base`, `vein` (colours), `scale` (stripes per unit, default 4),
//!   `turbulence` (strength of the distortion, default 5), `octaves` (default 6). The colour is
//!   mixed by ½ + ½ sin(scale·x + turbulence·turb(p)): stripes across x, bent by turbulence.
//! - `type = "wood"`: `light`, `dark` (colours), `rings` (rings per unit of radius, default
//!   8), `turbulence` (default 0.3). Rings are concentric about the object's y axis, their
//!   radius perturbed by noise.

use glam::Vec3;

use super::noise::{perlin_noise, turbulence};
use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct Marble {
    pub base: Rgb,
    pub vein: Rgb,
    pub scale: f32,
    pub turbulence: f32,
    pub octaves: u32,
}

impl Marble {
    pub fn evaluate(&self, p: Vec3) -> Rgb {
        let phase = self.scale * p.x + self.turbulence * turbulence(p * self.scale * 0.5, 0.5, self.octaves);
        let t = 0.5 + 0.5 * phase.sin();
        self.base.lerp(self.vein, t * t)
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Wood {
    pub light: Rgb,
    pub dark: Rgb,
    pub rings: f32,
    pub turbulence: f32,
}

impl Wood {
    pub fn evaluate(&self, p: Vec3) -> Rgb {
        let radius = (p.x * p.x + p.z * p.z).sqrt();
        let r = radius * self.rings + self.turbulence * perlin_noise(p * 2.0) * self.rings;
        let ring = r - r.floor();
        // Sharp dark edge, gradual light wood across each ring.
        let t = (ring * 2.0).min(1.0).powf(0.5);
        self.dark.lerp(self.light, t)
    }
}
