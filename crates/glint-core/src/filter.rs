//! Pixel reconstruction filters. A sample at film position (x, y) adds its radiance, weighted
//! by w(centre − sample), to every pixel whose centre lies within the filter's radius; a pixel
//! is the weighted mean of what it received (pbrt-v3's film). All filters here are separable:
//! w(dx, dy) = w(dx)·w(dy).
//!
//! - `box` (default, radius ½): the plain average of the samples inside the pixel, the
//!   convention of the Mitsuba reference renders;
//! - `tent` (radius 1): w = 1 − |x|;
//! - `gaussian` (radius 1.5, σ = 0.5; pbrt-v4's): exp(−x²/2σ²) minus its value at the radius;
//! - `gaussian-wide` (radius 2 = 4σ, σ = 0.5; Mitsuba 3's `gaussian`): the same bell, cut off
//!   further out, so an edge spreads over one more pixel;
//! - `mitchell` (radius 2, B = C = ⅓; Mitchell & Netravali 1988): sharper, with small negative
//!   lobes (the normalisation by the summed weights keeps flat regions exact).

use crate::Named;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Filter {
    #[default]
    Box,
    Tent,
    Gaussian,
    GaussianWide,
    Mitchell,
}

impl Named for Filter {
    const ALL: &'static [Self] = &[Filter::Box, Filter::Tent, Filter::Gaussian, Filter::GaussianWide, Filter::Mitchell];

    fn name(self) -> &'static str {
        match self {
            Filter::Box => "box",
            Filter::Tent => "tent",
            Filter::Gaussian => "gaussian",
            Filter::GaussianWide => "gaussian-wide",
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
            Filter::GaussianWide | Filter::Mitchell => 2.0,
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
            Filter::Gaussian | Filter::GaussianWide => (bell(x) - bell(self.radius())).max(0.0),
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
}

/// The Gaussian bell of σ = ½, e^(−2x²), for 0 ≤ x ≤ 2, read from a table by linear
/// interpolation (within 10⁻⁶ of it; exact at the table's points, so at both radii): a
/// sample reaches up to 25 pixels, and an exponential per column and row was a tenth of the
/// render time of a small image.
fn bell(x: f32) -> f32 {
    /// Table entries per pixel of offset.
    const STEPS: f32 = 1024.0;
    const LEN: usize = 2 * STEPS as usize + 2;
    static TABLE: std::sync::LazyLock<[f32; LEN]> = std::sync::LazyLock::new(|| {
        std::array::from_fn(|i| {
            let v = i as f32 / STEPS;
            (-2.0 * v * v).exp()
        })
    });
    let at = (x * STEPS).min(2.0 * STEPS);
    let i = at as usize;
    let fraction = at - i as f32;
    let (a, b) = (TABLE[i], TABLE[i + 1]);
    a + (b - a) * fraction
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
        // Mitsuba 3's gaussian (σ ½ to 4σ), by hand: e^(−2x²) − e^(−8) at x = 0, 1, 1.5, 1.9
        // (Mitsuba's own `eval`, whose exponential is an approximation, is within 5e-4 of each).
        for (x, w) in [(0.0, 0.999_664_5), (1.0, 0.134_999_8), (1.5, 0.010_773_4), (1.9, 0.000_396_3)] {
            assert!((Filter::GaussianWide.weight_1d(x) - w).abs() < 1e-6, "{x}: {}", Filter::GaussianWide.weight_1d(x));
        }
        assert_eq!(Filter::GaussianWide.weight_1d(2.0), 0.0);
        // The bell's table against the exponential it holds, between its points too.
        for i in 0..=4000 {
            let x = i as f32 * 0.0005;
            let exact = (-2.0 * f64::from(x) * f64::from(x)).exp();
            assert!((f64::from(bell(x)) - exact).abs() < 1e-6, "{x}: {} against {exact}", bell(x));
        }
        for &f in Filter::ALL {
            assert_eq!(Filter::from_name(f.name()), Some(f));
            assert_eq!(f.weight_1d(f.radius() + 0.01), 0.0);
        }
    }
}
