//! Textures made of others. `Mix`: two textures mixed by a third, (1 − w)·first + w·second,
//! w the weight's luminance clamped to [0, 1] (`fraction`), as a blend of two materials weighs
//! them; the scene readers make it of a `blend` of two Lambert materials, which is Lambert's
//! lobe with the mixed colour: the same BSDF and the same sampling density, which the path
//! tracer's lanes then shade. `Product`: two textures multiplied channel by channel (glTF's
//! base colour times its vertex colours). `DirectionMix`: two textures mixed by how squarely
//! the surface faces a direction (pbrt's `directionmix`).

use super::{Texture, TextureQuery};
use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct Mix {
    pub weight: Texture,
    pub first: Texture,
    pub second: Texture,
}

impl Mix {
    pub fn evaluate(&self, query: &TextureQuery) -> Rgb {
        let w = fraction(self.weight.evaluate(query));
        (1.0 - w) * self.first.evaluate(query) + w * self.second.evaluate(query)
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Product {
    pub factors: [Texture; 2],
}

impl Product {
    pub fn evaluate(&self, query: &TextureQuery) -> Rgb {
        self.factors[0].evaluate(query) * self.factors[1].evaluate(query)
    }
}

/// |n · direction|·first + (1 − |n · direction|)·second, n the surface's geometric normal: the
/// first texture where the surface faces `direction` (or its opposite), the second where it
/// lies along it.
#[derive(Clone, Debug, PartialEq)]
pub struct DirectionMix {
    /// A unit vector in world space.
    pub direction: glam::Vec3,
    pub first: Texture,
    pub second: Texture,
}

impl DirectionMix {
    pub fn evaluate(&self, query: &TextureQuery) -> Rgb {
        let w = query.normal.dot(self.direction).abs().min(1.0);
        w * self.first.evaluate(query) + (1.0 - w) * self.second.evaluate(query)
    }
}

/// A blend weight or an opacity read from a colour: its luminance, clamped to [0, 1].
pub fn fraction(value: Rgb) -> f32 {
    value.dot(Rgb::new(0.2126, 0.7152, 0.0722)).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// By hand: a weight of luminance ¼ mixes ¾ of the first with ¼ of the second; weights
    /// outside [0, 1] are clamped.
    #[test]
    fn mixes_by_the_weights_luminance() {
        let mix = |w: f32| Mix {
            weight: Texture::Constant(Rgb::splat(w)),
            first: Texture::Constant(Rgb::new(0.0, 0.5, 0.5)),
            second: Texture::Constant(Rgb::new(1.0, 1.0, 0.0)),
        };
        let q = TextureQuery::default();
        let close = |a: Rgb, b: Rgb| (a - b).abs().max_element() < 1e-6;
        assert!(close(mix(0.25).evaluate(&q), Rgb::new(0.25, 0.625, 0.375)));
        assert!(close(mix(-1.0).evaluate(&q), Rgb::new(0.0, 0.5, 0.5)));
        assert!(close(mix(3.0).evaluate(&q), Rgb::new(1.0, 1.0, 0.0)));
    }

    /// By hand: the channels multiply.
    #[test]
    fn products_multiply_channel_by_channel() {
        let product = Product {
            factors: [Texture::Constant(Rgb::new(0.5, 2.0, 0.0)), Texture::Constant(Rgb::new(0.5, 0.25, 9.0))],
        };
        assert_eq!(product.evaluate(&TextureQuery::default()), Rgb::new(0.25, 0.5, 0.0));
    }

    /// By hand: facing the direction, the first texture; square to it, the second; at 60°,
    /// half of each.
    #[test]
    fn direction_mixes_by_the_normals_cosine() {
        let mix = DirectionMix {
            direction: glam::Vec3::Z,
            first: Texture::Constant(Rgb::ONE),
            second: Texture::Constant(Rgb::ZERO),
        };
        let at = |n: glam::Vec3| mix.evaluate(&TextureQuery { normal: n, ..Default::default() }).x;
        assert_eq!(at(glam::Vec3::Z), 1.0);
        assert_eq!(at(-glam::Vec3::Z), 1.0);
        assert_eq!(at(glam::Vec3::X), 0.0);
        let tilted = glam::Vec3::new(3f32.sqrt() / 2.0, 0.0, 0.5);
        assert!((at(tilted) - 0.5).abs() < 1e-6);
    }
}
