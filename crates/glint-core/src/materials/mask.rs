//! Opacity, Mitsuba's `mask`: a surface present with probability `opacity` and otherwise
//! passed straight through (the null lobe: the direction unchanged, weight 1), for leaves and
//! cut-outs. A wrapper: any material inside.
//!
//! Scene parameters: `opacity` (a number or a texture, its luminance; default 0.5), `material`
//! (the name of the material where the surface is present).
//! ```toml
//! [materials.leaf]
//! type = "mask"
//! opacity = "leaf_alpha"   # a texture
//! material = "green"
//! ```
//! The null lobe is a delta lobe, so shadow rays stop at a masked surface as they do at glass
//! (Mitsuba's `path` does the same); paths pass through by sampling.

use glam::{Vec2, Vec3};

use super::bsdf::{BsdfSample, Frame, Lobes};
use super::Material;
use crate::textures::Texture;
use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct Mask {
    pub opacity: Texture,
    pub material: Material,
}

/// The surface not there: the direction goes on unchanged.
#[derive(Clone, Copy, Debug)]
pub(super) struct NullBsdf {
    pub frame: Frame,
}

impl Lobes for NullBsdf {
    fn sample(&self, wo: Vec3, _u_lobe: f32, _u: Vec2) -> Option<BsdfSample> {
        Some(BsdfSample { wi: -wo, weight: Rgb::ONE, pdf: 1.0, delta: true, eta_squared: 1.0 })
    }

    fn null_transmission(&self, _wo: Vec3) -> Rgb {
        Rgb::ONE
    }

    fn frame(&self) -> &Frame {
        &self.frame
    }
    fn frame_mut(&mut self) -> &mut Frame {
        &mut self.frame
    }
}
