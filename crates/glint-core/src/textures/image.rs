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

    /// The texel left of and above `uv` (x right, y down) and the distances past it.
    fn footprint(&self, uv: Vec2) -> (i64, i64, f32, f32) {
        let uv = uv * self.scale;
        // Continuous texel coordinates, with texel centres at integer + ½.
        let x = uv.x * self.width as f32 - 0.5;
        let y = (1.0 - uv.y) * self.height as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        (x0 as i64, y0 as i64, x - x0, y - y0)
    }

    pub fn evaluate(&self, uv: Vec2) -> Rgb {
        let (x0, y0, fx, fy) = self.footprint(uv);
        let top = self.texel(x0, y0) * (1.0 - fx) + self.texel(x0 + 1, y0) * fx;
        let bottom = self.texel(x0, y0 + 1) * (1.0 - fx) + self.texel(x0 + 1, y0 + 1) * fx;
        top * (1.0 - fy) + bottom * fy
    }

    /// The gradient in uv of the bilinear interpolant of the texels' luminance (what Mitsuba's
    /// bitmap gives a bump map): the interpolant's slope within the texel square, scaled by
    /// the texels per unit of u and v (v runs up, the rows down).
    pub fn luminance_gradient(&self, uv: Vec2) -> Vec2 {
        let (x0, y0, fx, fy) = self.footprint(uv);
        let l = |dx, dy| super::luminance(self.texel(x0 + dx, y0 + dy));
        let (l00, l10, l01, l11) = (l(0, 0), l(1, 0), l(0, 1), l(1, 1));
        let along_x = (1.0 - fy) * (l10 - l00) + fy * (l11 - l01);
        let along_y = (1.0 - fx) * (l01 - l00) + fx * (l11 - l10);
        Vec2::new(along_x * self.width as f32 * self.scale.x, -along_y * self.height as f32 * self.scale.y)
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

    /// The gradient is the interpolant's: central differences of the luminance inside texel
    /// squares agree, for a scaled, repeating texture.
    #[test]
    fn the_luminance_gradient_is_the_slope_of_the_interpolant() {
        let pixels = (0..12).map(|i| Rgb::new((i * 7 % 5) as f32, (i * 3 % 4) as f32, (i % 3) as f32) * 0.2).collect();
        let t = ImageTexture { width: 4, height: 3, pixels, wrap: Wrap::Repeat, scale: Vec2::new(2.0, 0.5) };
        let lum = |uv: Vec2| super::super::luminance(t.evaluate(uv));
        let h = 1e-3;
        for (u, v) in [(0.07, 0.3), (0.2, 0.55), (0.33, 0.9), (0.41, 1.7), (-0.3, 0.1)] {
            let uv = Vec2::new(u, v);
            let expected = Vec2::new(
                (lum(uv + Vec2::X * h) - lum(uv - Vec2::X * h)) / (2.0 * h),
                (lum(uv + Vec2::Y * h) - lum(uv - Vec2::Y * h)) / (2.0 * h),
            );
            let g = t.luminance_gradient(uv);
            assert!(
                (g - expected).abs().max_element() < 2e-3 * (1.0 + expected.abs().max_element()),
                "{uv}: {g} vs {expected}"
            );
        }
        // By hand: across the 2 × 1 ramp from black to white, one unit of luminance per half
        // of u (two texels over u's unit), at any v.
        let ramp = two_by_one(Wrap::Clamp);
        assert!((ramp.luminance_gradient(Vec2::new(0.5, 0.5)) - Vec2::new(2.0, 0.0)).length() < 1e-5);
    }

    #[test]
    fn repeat_wraps_around() {
        let t = two_by_one(Wrap::Repeat);
        // At u = 0 the left texel's centre is ½ texel away, the wrapped right one too.
        assert_eq!(t.evaluate(Vec2::new(0.0, 0.5)), Rgb::splat(0.5));
        assert_eq!(t.evaluate(Vec2::new(1.25, 0.5)), Rgb::ZERO);
    }
}
