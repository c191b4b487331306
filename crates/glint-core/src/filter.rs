//! Pixel reconstruction filters. A sample at film position (x, y) adds its radiance, weighted
//! by w(centre − sample), to every pixel whose centre lies within the filter's radius; a pixel
//! is the weighted mean of what it received (pbrt-v3's film). All filters here are separable:
//! w(dx, dy) = w(dx)·w(dy).
//!
//! - `box` (default, radius ½): the plain average of the samples inside the pixel, the
//!   convention of the Mitsuba reference renders;
//! - `tent` (radius 1): w = 1 − |x|;
//! - `gaussian` (radius 1.5, σ = 0.5): exp(−x²/2σ²) minus its value at the radius;
//! - `mitchell` (radius 2, B = C = ⅓; Mitchell & Netravali 1988): sharper, with small negative
//!   lobes (the normalisation by the summed weights keeps flat regions exact).

use crate::Named;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Filter {
    #[default]
    Box,
    Tent,
    Gaussian,
    Mitchell,
}

impl Named for Filter {
    const ALL: &'static [Self] = &[Filter::Box, Filter::Tent, Filter::Gaussian, Filter::Mitchell];

    fn name(self) -> &'static str {
        match self {
            Filter::Box => "box",
            Filter::Tent => "tent",
            Filter::Gaussian => "gaussian",
            Filter::Mitchell => "mitchell",
        }
    }
}

impl Filter {
    pub fn radius(self) -> f32 {
        match self {
            Filter::Box => 0.5,
            Filter::Tent => 1.0,
            Filter::Gaussian => 1.5,
            Filter::Mitchell => 2.0,
        }
    }

    /// The 1D weight at offset `x` (in pixels) from the pixel centre.
    pub fn weight_1d(self, x: f32) -> f32 {
        let x = x.abs();
        if x > self.radius() {
            return 0.0;
        }
        match self {
            Filter::Box => 1.0,
            Filter::Tent => 1.0 - x,
            Filter::Gaussian => {
                let g = |v: f32| (-v * v / (2.0 * 0.25)).exp();
                (g(x) - g(1.5)).max(0.0)
            }
            Filter::Mitchell => {
                const B: f32 = 1.0 / 3.0;
                const C: f32 = 1.0 / 3.0;
                let v = if x > 1.0 {
                    (-B - 6.0 * C) * x * x * x
                        + (6.0 * B + 30.0 * C) * x * x
                        + (-12.0 * B - 48.0 * C) * x
                        + (8.0 * B + 24.0 * C)
                } else {
                    (12.0 - 9.0 * B - 6.0 * C) * x * x * x + (-18.0 + 12.0 * B + 6.0 * C) * x * x + (6.0 - 2.0 * B)
                };
                v / 6.0
            }
        }
    }

    pub fn weight(self, dx: f32, dy: f32) -> f32 {
        self.weight_1d(dx) * self.weight_1d(dy)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn integral(f: Filter) -> f32 {
        let n = 4000;
        let r = f.radius();
        (0..n).map(|i| f.weight_1d(-r + (i as f32 + 0.5) / n as f32 * 2.0 * r)).sum::<f32>() * 2.0 * r / n as f32
    }

    #[test]
    fn filter_shapes_by_hand() {
        assert_eq!(Filter::Tent.weight_1d(0.25), 0.75);
        assert_eq!(Filter::Box.weight_1d(0.6), 0.0);
        // Mitchell with B = C = 1/3 integrates to 1, is 8/9 at the centre and has a negative lobe.
        assert!((integral(Filter::Mitchell) - 1.0).abs() < 1e-3);
        assert!((Filter::Mitchell.weight_1d(0.0) - 8.0 / 9.0).abs() < 1e-6);
        assert!(Filter::Mitchell.weight_1d(1.5) < 0.0);
        assert!((integral(Filter::Tent) - 1.0).abs() < 1e-3);
        assert!(Filter::Gaussian.weight_1d(1.5) == 0.0 && Filter::Gaussian.weight_1d(0.0) > 0.9);
        for &f in Filter::ALL {
            assert_eq!(Filter::from_name(f.name()), Some(f));
            assert_eq!(f.weight_1d(f.radius() + 0.01), 0.0);
        }
    }
}
