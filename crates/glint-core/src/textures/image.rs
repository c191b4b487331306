//! Image texture, bilinearly filtered (or the nearest texel).
//!
//! Scene parameters: `type = "image"`, `file` (PNG, JPEG or EXR, relative to the scene; PNG and
//! JPEG are decoded from sRGB to linear, EXR is taken as linear), `wrap` (`"repeat"`, default,
//! `"clamp"` or `"mirror"`), `filter` (`"bilinear"`, default, or `"nearest"`), `scale`
//! (repeats per unit of u and v, a number or [su, sv], default 1), `uv_transform` (an affine
//! map of uv after the scale, two rows [a, b, c]: u' = a·u + b·v + c).
//!
//! uv (0, 0) is the bottom-left of the image and (1, 1) the top-right; texel centres sit at
//! half-integer positions, so the four nearest texels are blended by their distances (the
//! course's bilinear interpolation).

use glam::{Affine2, Vec2};

use crate::Rgb;

/// What lies beyond the image's edges.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Wrap {
    /// The image again (tiles).
    #[default]
    Repeat,
    /// The edge texel.
    Clamp,
    /// The image reflected at each edge, so neighbouring tiles meet without a seam.
    Mirror,
}

/// How texels are blended at a lookup.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TexelFilter {
    /// The four nearest texels, weighted by their distances.
    #[default]
    Bilinear,
    /// The texel the point falls in.
    Nearest,
}

#[derive(Clone, Debug, PartialEq)]
pub struct ImageTexture {
    pub width: u32,
    pub height: u32,
    /// Row-major, row 0 = top of the image, linear RGB.
    pub pixels: Vec<Rgb>,
    pub wrap: Wrap,
    pub filter: TexelFilter,
    /// The surface's uv to the image's (0, 0 bottom-left, 1, 1 top-right).
    pub uv_transform: Affine2,
}

impl ImageTexture {
    /// A texture that repeats the image once over the unit square, filtered bilinearly.
    pub fn new(width: u32, height: u32, pixels: Vec<Rgb>) -> Self {
        Self {
            width,
            height,
            pixels,
            wrap: Wrap::Repeat,
            filter: TexelFilter::Bilinear,
            uv_transform: Affine2::IDENTITY,
        }
    }

    /// Texel (x, y), row 0 the top, wrapped by the texture's mode.
    pub(crate) fn texel(&self, x: i64, y: i64) -> Rgb {
        let (w, h) = (self.width as i64, self.height as i64);
        let mirror = |i: i64, n: i64| {
            let i = i.rem_euclid(2 * n);
            if i < n {
                i
            } else {
                2 * n - 1 - i
            }
        };
        let (x, y) = match self.wrap {
            Wrap::Repeat => (x.rem_euclid(w), y.rem_euclid(h)),
            Wrap::Clamp => (x.clamp(0, w - 1), y.clamp(0, h - 1)),
            Wrap::Mirror => (mirror(x, w), mirror(y, h)),
        };
        self.pixels[(y * w + x) as usize]
    }

    /// Continuous texel coordinates of `uv` (x right, y down; texel centres at integer + ½).
    fn texel_position(&self, uv: Vec2) -> Vec2 {
        let uv = self.uv_transform.transform_point2(uv);
        Vec2::new(uv.x * self.width as f32, (1.0 - uv.y) * self.height as f32)
    }

    /// The texel left of and above `uv`'s texel position less ½ and the distances past it.
    fn footprint(&self, uv: Vec2) -> (i64, i64, f32, f32) {
        let p = self.texel_position(uv) - Vec2::splat(0.5);
        let (x0, y0) = (p.x.floor(), p.y.floor());
        (x0 as i64, y0 as i64, p.x - x0, p.y - y0)
    }

    pub fn evaluate(&self, uv: Vec2) -> Rgb {
        if self.filter == TexelFilter::Nearest {
            let p = self.texel_position(uv).floor();
            return self.texel(p.x as i64, p.y as i64);
        }
        let (x0, y0, fx, fy) = self.footprint(uv);
        let top = self.texel(x0, y0) * (1.0 - fx) + self.texel(x0 + 1, y0) * fx;
        let bottom = self.texel(x0, y0 + 1) * (1.0 - fx) + self.texel(x0 + 1, y0 + 1) * fx;
        top * (1.0 - fy) + bottom * fy
    }

    /// The gradient in uv of the bilinear interpolant of the texels' luminance (what Mitsuba's
    /// bitmap gives a bump map): the interpolant's slope within the texel square, in texels
    /// per unit of the image's u and v (v runs up, the rows down), carried back through the
    /// uv transform (its transpose). Zero for nearest-texel lookups, flat between edges.
    pub fn luminance_gradient(&self, uv: Vec2) -> Vec2 {
        if self.filter == TexelFilter::Nearest {
            return Vec2::ZERO;
        }
        let (x0, y0, fx, fy) = self.footprint(uv);
        let l = |dx, dy| super::luminance(self.texel(x0 + dx, y0 + dy));
        let (l00, l10, l01, l11) = (l(0, 0), l(1, 0), l(0, 1), l(1, 1));
        let along_x = (1.0 - fy) * (l10 - l00) + fy * (l11 - l01);
        let along_y = (1.0 - fx) * (l01 - l00) + fx * (l11 - l10);
        let in_image = Vec2::new(along_x * self.width as f32, -along_y * self.height as f32);
        self.uv_transform.matrix2.transpose() * in_image
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_by_one(wrap: Wrap) -> ImageTexture {
        ImageTexture { wrap, ..ImageTexture::new(2, 1, vec![Rgb::ZERO, Rgb::ONE]) }
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
        // A scale, a shear and a shift: the gradient goes back through the whole map.
        let uv_transform = Affine2::from_cols_array(&[2.0, 0.3, -0.2, 0.5, 0.25, -0.4]);
        let t = ImageTexture { uv_transform, ..ImageTexture::new(4, 3, pixels) };
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

    /// Mirroring reflects the texels at each edge: beyond u = 1 the right texel comes first;
    /// at the edge itself the texel meets its own reflection.
    #[test]
    fn mirror_reflects_at_the_edges() {
        let t = two_by_one(Wrap::Mirror);
        assert_eq!(t.evaluate(Vec2::new(1.0, 0.5)), Rgb::ONE);
        assert_eq!(t.evaluate(Vec2::new(1.25, 0.5)), Rgb::ONE);
        assert_eq!(t.evaluate(Vec2::new(1.75, 0.5)), Rgb::ZERO);
        assert_eq!(t.evaluate(Vec2::new(-0.25, 0.5)), Rgb::ZERO);
        assert_eq!(t.evaluate(Vec2::new(1.5, 0.5)), Rgb::splat(0.5));
    }

    /// Nearest: the texel the point is in, no blending; the uv transform applies first (a
    /// shift by half a texel moves the boundary).
    #[test]
    fn nearest_takes_the_texel_the_point_is_in() {
        let t = ImageTexture { filter: TexelFilter::Nearest, ..two_by_one(Wrap::Repeat) };
        assert_eq!(t.evaluate(Vec2::new(0.49, 0.5)), Rgb::ZERO);
        assert_eq!(t.evaluate(Vec2::new(0.51, 0.5)), Rgb::ONE);
        assert_eq!(t.evaluate(Vec2::new(1.2, 0.5)), Rgb::ZERO);
        let shifted = ImageTexture { uv_transform: Affine2::from_translation(Vec2::new(0.25, 0.0)), ..t };
        assert_eq!(shifted.evaluate(Vec2::new(0.3, 0.5)), Rgb::ONE);
        assert_eq!(shifted.luminance_gradient(Vec2::new(0.3, 0.5)), Vec2::ZERO);
    }

    /// Image rows run down, v up: row 0 is v = 1.
    #[test]
    fn the_first_row_is_the_top() {
        let t = ImageTexture::new(1, 2, vec![Rgb::ONE, Rgb::ZERO]);
        let t = ImageTexture { filter: TexelFilter::Nearest, ..t };
        assert_eq!(t.evaluate(Vec2::new(0.5, 0.9)), Rgb::ONE);
        assert_eq!(t.evaluate(Vec2::new(0.5, 0.1)), Rgb::ZERO);
    }
}
