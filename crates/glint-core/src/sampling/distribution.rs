//! Piecewise-constant distributions in 1D and 2D (pbrt's `PiecewiseConstant1D/2D`): sampled by
//! inverting the cumulative distribution, continuous within each cell. The environment map
//! samples its pixels with the 2D one, in proportion to their brightness.

use glam::Vec2;

use crate::lanes::Lanes;

#[derive(Clone, Debug, PartialEq)]
pub struct Distribution1D {
    /// The function's cell values (non-negative).
    function: Vec<f32>,
    /// cdf[i] = ∫ over cells before i, normalised; n + 1 entries, the last 1.
    cdf: Vec<f32>,
    /// ∫ f over [0, 1).
    integral: f32,
}

impl Distribution1D {
    /// A distribution proportional to `function` over [0, 1), one cell per value. An all-zero
    /// function samples uniformly.
    pub fn new(function: Vec<f32>) -> Self {
        let n = function.len().max(1);
        let mut cdf = Vec::with_capacity(n + 1);
        cdf.push(0.0f32);
        let mut acc = 0.0f64;
        for &f in &function {
            acc += f.max(0.0) as f64 / n as f64;
            cdf.push(acc as f32);
        }
        let integral = acc as f32;
        if integral > 0.0 {
            cdf.iter_mut().for_each(|c| *c /= integral);
        } else {
            cdf.iter_mut().enumerate().for_each(|(i, c)| *c = i as f32 / n as f32);
        }
        *cdf.last_mut().expect("n + 1 entries") = 1.0;
        Self { function, cdf, integral }
    }

    pub fn integral(&self) -> f32 {
        self.integral
    }

    pub fn count(&self) -> usize {
        self.function.len()
    }

    /// A point x ∈ [0, 1) with density pdf(x), and its cell.
    pub fn sample(&self, u: f32) -> (f32, f32, usize) {
        let (x, pdf, cell) = Self::sample_lanes(|_| self, u);
        (x, pdf, cell as usize)
    }

    /// `sample` in lanes, lane k from distribution `of(k)` (all with as many cells): the points,
    /// their densities and their cells (as floats, exact below 2²⁴). The lanes search their
    /// cumulative distributions in step, so that each step's loads, one per lane, wait on
    /// memory together: a search is a chain of dependent loads, and one lane's chain at a time
    /// left the environment map's searches waiting on memory for 7 % of a render.
    #[inline(always)]
    pub(crate) fn sample_lanes<'d, L: Lanes>(of: impl Fn(usize) -> &'d Distribution1D, u: L) -> (L, L, L) {
        const MOST: usize = 16;
        debug_assert!(L::WIDTH <= MOST);
        let cdfs: [&[f32]; MOST] = std::array::from_fn(|k| if k < L::WIDTH { of(k).cdf.as_slice() } else { &[] });
        let us: [f32; MOST] = std::array::from_fn(|k| if k < L::WIDTH { u.lane(k) } else { 0.0 });
        let n = of(0).function.len().max(1);
        debug_assert!(cdfs[..L::WIDTH].iter().all(|c| c.len() == cdfs[0].len()), "the lanes' tables differ in length");
        // The number of entries ≤ u (`partition_point`), by halving a range that starts at the
        // whole table: entries before `base` are ≤ u, those from `base + size` on are not.
        // The indices stay integers: a float index's conversion before every load lengthened
        // each step's chain of latencies.
        let (mut base, mut size) = ([0usize; MOST], cdfs[0].len());
        while size > 1 {
            let half = size / 2;
            for k in 0..L::WIDTH {
                let middle = base[k] + half;
                base[k] = if cdfs[k][middle] <= us[k] { middle } else { base[k] };
            }
            size -= half;
        }
        let cells: [usize; MOST] = std::array::from_fn(|k| {
            let below = if k < L::WIDTH { base[k] + usize::from(cdfs[k][base[k]] <= us[k]) } else { 0 };
            below.saturating_sub(1).min(n - 1)
        });
        let lo = L::from_fn(|k| cdfs[k][cells[k]]);
        let hi = L::from_fn(|k| cdfs[k][cells[k] + 1]);
        let cell = L::from_fn(|k| cells[k] as f32);
        let offset = L::select(hi.gt(lo), (u - lo) / (hi - lo), L::splat(0.5));
        let x = ((cell + offset) / L::splat(n as f32)).min(L::splat(1.0 - f32::EPSILON));
        (x, Self::pdf_of_cell_lanes(&of, cell), cell)
    }

    /// Each lane's density in its cell (a float, exact).
    #[inline(always)]
    fn pdf_of_cell_lanes<'d, L: Lanes>(of: &impl Fn(usize) -> &'d Distribution1D, cell: L) -> L {
        let integral = L::from_fn(|k| of(k).integral);
        // The integral's lanes gathered once: a lane with none (all zero) reads no cell.
        let value = L::from_fn(|k| {
            let d = of(k);
            if d.integral > 0.0 {
                d.function[cell.lane(k) as usize]
            } else {
                0.0
            }
        });
        L::select(integral.gt(L::ZERO), value.max(L::ZERO) / integral, L::ONE)
    }

    /// The density at x ∈ [0, 1).
    pub fn pdf(&self, x: f32) -> f32 {
        Self::pdf_lanes(|_| self, x)
    }

    /// `pdf` in lanes, lane k's from distribution `of(k)` (all with as many cells).
    #[inline(always)]
    pub(crate) fn pdf_lanes<'d, L: Lanes>(of: impl Fn(usize) -> &'d Distribution1D, x: L) -> L {
        let n = of(0).function.len();
        if n == 0 {
            return L::ZERO;
        }
        // `as usize`: toward zero, and 0 below zero and for NaN (which `max` gives 0 too).
        let cell = (x * L::splat(n as f32)).max(L::ZERO).floor().min(L::splat((n - 1) as f32));
        Self::pdf_of_cell_lanes(&of, cell)
    }
}

/// A distribution over [0, 1)², piecewise constant on a grid of `width × height` cells: a
/// marginal over rows, then the row's conditional over columns.
#[derive(Clone, Debug, PartialEq)]
pub struct Distribution2D {
    rows: Vec<Distribution1D>,
    marginal: Distribution1D,
}

impl Distribution2D {
    /// `function` is row-major, `width` values per row; row 0 is v ∈ [0, 1/height).
    pub fn new(function: &[f32], width: usize, height: usize) -> Self {
        let rows: Vec<Distribution1D> =
            (0..height).map(|r| Distribution1D::new(function[r * width..(r + 1) * width].to_vec())).collect();
        let marginal = Distribution1D::new(rows.iter().map(Distribution1D::integral).collect());
        Self { rows, marginal }
    }

    /// A point (u, v) and its density.
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        let (x, y, pdf) = self.sample_lanes(u.x, u.y);
        (Vec2::new(x, y), pdf)
    }

    /// `sample` in lanes (u, v): the points (x, y) and their densities, the lanes' searches of
    /// the marginal and then of their rows made in step (`Distribution1D::sample_lanes`).
    #[inline(always)]
    pub(crate) fn sample_lanes<L: Lanes>(&self, u: L, v: L) -> (L, L, L) {
        let (y, pdf_v, row) = Distribution1D::sample_lanes(|_| &self.marginal, v);
        let (x, pdf_u, _) = Distribution1D::sample_lanes(|k| &self.rows[row.lane(k) as usize], u);
        (x, y, pdf_v * pdf_u)
    }

    pub fn pdf(&self, p: Vec2) -> f32 {
        self.pdf_lanes(p.x, p.y)
    }

    /// `pdf` in lanes.
    #[inline(always)]
    pub(crate) fn pdf_lanes<L: Lanes>(&self, x: L, y: L) -> L {
        let height = self.rows.len();
        let row = (y * L::splat(height as f32)).max(L::ZERO).floor().min(L::splat((height - 1) as f32));
        Distribution1D::pdf_lanes(|_| &self.marginal, y)
            * Distribution1D::pdf_lanes(|k| &self.rows[row.lane(k) as usize], x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    #[test]
    fn one_d_by_hand() {
        let d = Distribution1D::new(vec![1.0, 3.0, 0.0, 4.0]);
        assert_eq!(d.integral(), 2.0);
        assert_eq!(d.pdf(0.1), 0.5);
        assert_eq!(d.pdf(0.3), 1.5);
        assert_eq!(d.pdf(0.6), 0.0);
        // u = 0.5 is the end of the second cell: 1/8 + 3/8.
        let (x, pdf, cell) = d.sample(0.5 - 1e-6);
        assert!((x - 0.5).abs() < 1e-5 && pdf == 1.5 && cell == 1);
        let (x, _, cell) = d.sample(0.0625);
        assert!((x - 0.125).abs() < 1e-6 && cell == 0);
        // The empty cell is never chosen.
        for i in 0..1000 {
            assert_ne!(d.sample(i as f32 / 1000.0).2, 2);
        }
        // All zero: uniform.
        let z = Distribution1D::new(vec![0.0; 4]);
        assert_eq!(z.pdf(0.7), 1.0);
        assert!((z.sample(0.3).0 - 0.3).abs() < 1e-6);
    }

    #[test]
    fn two_d_histogram_matches_the_pdf() {
        let (w, h) = (5, 4);
        let f: Vec<f32> = (0..w * h).map(|i| ((i * 7) % 11) as f32).collect();
        let d = Distribution2D::new(&f, w, h);
        let total: f32 = f.iter().sum::<f32>() / (w * h) as f32;
        let mut counts = vec![0usize; w * h];
        let mut rng = Rng::new(3, 4);
        let n = 400_000;
        for _ in 0..n {
            let (p, pdf) = d.sample(Vec2::new(rng.next_f32(), rng.next_f32()));
            let cell = (p.y * h as f32) as usize * w + (p.x * w as f32) as usize;
            assert!((pdf - f[cell] / total).abs() < 1e-4, "pdf {pdf} in cell {cell}");
            assert!((d.pdf(p) - pdf).abs() < 1e-4);
            counts[cell] += 1;
        }
        for (cell, &c) in counts.iter().enumerate() {
            let expected = n as f32 * f[cell] / total / (w * h) as f32;
            assert!((c as f32 - expected).abs() <= 5.0 * expected.sqrt().max(1.0), "cell {cell}: {c} vs {expected}");
        }
    }
}
