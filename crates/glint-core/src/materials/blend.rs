//! A linear blend of two materials, Mitsuba's `blendbsdf`: (1 − w)·first + w·second, the weight
//! a number or a texture (its luminance, clamped to [0, 1]). A wrapper: the two materials may
//! be any, blends and masks too (up to `MAX_LEAVES` members in all).
//!
//! Scene parameters: `weight` (default 0.5), `first`, `second` (material names).
//! ```toml
//! [materials.worn]
//! type = "blend"
//! weight = "rust_mask"     # a texture
//! first = "steel"
//! second = "rust"
//! ```
//! Sampling chooses a member by its weight; a non-delta sample is weighed by the whole blend.

use super::Material;
use crate::textures::Texture;

#[derive(Clone, Debug, PartialEq)]
pub struct Blend {
    pub weight: Texture,
    pub first: Material,
    pub second: Material,
}
