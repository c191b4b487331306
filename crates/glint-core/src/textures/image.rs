//! Image texture, bilinearly filtered.
//!
//! Scene parameters: `type = "image"`, `file` (PNG, JPEG or EXR, relative to the scene; PNG and
//! JPEG are decoded from sRGB to linear, EXR is taken as linear), `wrap` (`"repeat"`, default,
//! or `"clamp"`), `scale` (repeats per unit of u and v, a number or [su, sv], default 1).
//!
//! uv (0, 0) is the bottom-left of the image and (1, 1) the top-right; texel centres sit at
//! half-integer positions, so the four nearest texels are blended by their distances (the
//! course's bilinear interpolation).

use glam::Vec2;

use crate::Rgb;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Wrap {
    #[default]
    Repeat,
    Clamp,
}

#[derive(Clone, Debug, PartialEq)]
pub struct ImageTexture {
    pub width: u32,
    pub height: u32,
    /// Row-major, row 0 = top of the image, linear RGB.
    pub pixels: Vec<Rgb>,
    pub wrap: Wrap,
    pub scale: Vec2,
}

impl ImageTexture {
    fn texel(&self, x: i64, y: i64) -> Rgb {
        let (w, h) = (self.width as i64, self.height as i64);
        let (x, y) = match self.wrap {
            Wrap::Repeat => (x.rem_euclid(w), y.rem_euclid(h)),
            Wrap::Clamp => (x.clamp(0, w - 1), y.clamp(0, h - 1)),
        };
        self.pixels[(y * w + x) as usize]
    }

    pub fn evaluate(&self, uv: Vec2) -> Rgb {
        let uv = uv * self.scale;
        // Continuous texel coordinates, with texel centres at integer + ½.
        let x = uv.x * self.width as f32 - 0.5;
        let y = (1.0 - uv.y) * self.height as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let top = self.texel(x0, y0) * (1.0 - fx) + self.texel(x0 + 1, y0) * fx;
        let bottom = self.texel(x0, y0 + 1) * (1.0 - fx) + self.texel(x0 + 1, y0 + 1) * fx;
        top * (1.0 - fy) + bottom * fy
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_by_one(wrap: Wrap) -> ImageTexture {
        ImageTexture { width: 2, height: 1, pixels: vec![Rgb::ZERO, Rgb::ONE], wrap, scale: Vec2::ONE }
    }

    #[test]
    fn texel_centres_and_halfway() {
        let t = two_by_one(Wrap::Clamp);
        assert_eq!(t.evaluate(Vec2::new(0.25, 0.5)), Rgb::ZERO);
        assert_eq!(t.evaluate(Vec2::new(0.75, 0.5)), Rgb::ONE);
        assert_eq!(t.evaluate(Vec2::new(0.5, 0.5)), Rgb::splat(0.5));
        assert_eq!(t.evaluate(Vec2::new(0.0, 0.5)), Rgb::ZERO); // clamped at the edge
    }

    #[test]
    fn repeat_wraps_around() {
        let t = two_by_one(Wrap::Repeat);
        // At u = 0 the left texel's centre is ½ texel away, the wrapped right one too.
        assert_eq!(t.evaluate(Vec2::new(0.0, 0.5)), Rgb::splat(0.5));
        assert_eq!(t.evaluate(Vec2::new(1.25, 0.5)), Rgb::ZERO);
    }
}
