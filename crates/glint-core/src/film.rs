//! The film: per-pixel sums of linear RGB radiance in f32 and the weights they carry, so that
//! the image is the weighted mean (with the box filter, the plain average of the pixel's
//! samples). Row 0 is the top row.

use crate::Rgb;

/// A pixel's sums kept exactly, for renders split by sample range and merged: each value added
/// (a sample's radiance times its weight, per channel, and the weight) is rounded once, to a
/// multiple of 2⁻⁶⁴, and summed as an integer, so the sums do not depend on how the samples
/// were grouped: ranges rendered apart and added give the sums of one render of them all, bit
/// for bit. (f32 sums round after every addition, so their grouping shows in the last bits.)
/// Values below 2⁻⁶⁴ ≈ 5·10⁻²⁰ count as 0; a sum saturates at ±2⁶³ ≈ 9·10¹⁸.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ExactPixel {
    pub sum: [i128; 3],
    pub weight: i128,
}

impl ExactPixel {
    /// The fixed point's unit, 2⁶⁴.
    const ONE: f64 = 18_446_744_073_709_551_616.0;

    /// `value` in units of 2⁻⁶⁴, rounded toward zero (exact: f32 → f64 and the power of two
    /// are exact, the one rounding is the conversion); NaN is 0.
    fn fixed(value: f32) -> i128 {
        (value as f64 * Self::ONE) as i128
    }

    #[inline]
    fn add(&mut self, weighted: Rgb, weight: f32) {
        for (sum, v) in self.sum.iter_mut().zip(weighted.to_array()) {
            *sum = sum.saturating_add(Self::fixed(v));
        }
        self.weight = self.weight.saturating_add(Self::fixed(weight));
    }

    /// Another part's sums added.
    pub fn merge(&mut self, other: &ExactPixel) {
        for (sum, v) in self.sum.iter_mut().zip(other.sum) {
            *sum = sum.saturating_add(v);
        }
        self.weight = self.weight.saturating_add(other.weight);
    }

    /// The weighted mean (zero without weight), each sum and the weight rounded to f64 once.
    pub fn value(&self) -> Rgb {
        if self.weight <= 0 {
            return Rgb::ZERO;
        }
        let w = self.weight as f64;
        Rgb::new((self.sum[0] as f64 / w) as f32, (self.sum[1] as f64 / w) as f32, (self.sum[2] as f64 / w) as f32)
    }
}

/// Adds to pixel `i` of a film's (or band's) accumulators: `weighted` (radiance × weight) and
/// `weight` to the sums, exactly too where kept, and `weight`·L² to the second moment where
/// kept and the sample's radiance `radiance` is given. The one place a sample lands.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn accumulate(
    sum: &mut [Rgb],
    weights: &mut [f32],
    squares: Option<&mut [Rgb]>,
    exact: Option<&mut [ExactPixel]>,
    i: usize,
    weighted: Rgb,
    weight: f32,
    radiance: Option<Rgb>,
) {
    sum[i] += weighted;
    weights[i] += weight;
    if let (Some(squares), Some(radiance)) = (squares, radiance) {
        squares[i] += radiance * radiance * weight;
    }
    if let Some(exact) = exact {
        exact[i].add(weighted, weight);
    }
}

/// Rows `y0..y0 + rows` of a film (`Film::bands_mut`).
pub struct FilmBand<'a> {
    width: u32,
    y0: u32,
    rows: u32,
    sum: &'a mut [Rgb],
    weight: &'a mut [f32],
    squares: Option<&'a mut [Rgb]>,
    exact: Option<&'a mut [ExactPixel]>,
}

impl FilmBand<'_> {
    /// The film's rows this band holds.
    pub fn rows(&self) -> std::ops::Range<u32> {
        self.y0..self.y0 + self.rows
    }

    /// `Film::add_samples` for pixel (x, y) of the film, which must lie in this band.
    pub fn add_samples(&mut self, x: u32, y: u32, radiance_sum: Rgb, count: f32) {
        debug_assert!(x < self.width && (self.y0..self.y0 + self.rows).contains(&y), "({x}, {y}) outside the band");
        let i = ((y - self.y0) * self.width + x) as usize;
        accumulate(self.sum, self.weight, None, self.exact.as_deref_mut(), i, radiance_sum, count, None);
    }

    /// `Film::add_sample` for pixel (x, y) of the film, which must lie in this band.
    #[inline]
    pub fn add_sample(&mut self, x: u32, y: u32, radiance: Rgb, weight: f32) {
        debug_assert!(x < self.width && (self.y0..self.y0 + self.rows).contains(&y), "({x}, {y}) outside the band");
        let i = ((y - self.y0) * self.width + x) as usize;
        let squares = self.squares.as_deref_mut();
        accumulate(
            self.sum,
            self.weight,
            squares,
            self.exact.as_deref_mut(),
            i,
            radiance * weight,
            weight,
            Some(radiance),
        );
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    sum: Vec<Rgb>,
    weight: Vec<f32>,
    /// Σ w·L² per pixel, where the render keeps the second moment (Mitsuba's `moment`).
    squares: Option<Vec<Rgb>>,
    /// The sums kept exactly, where the render is one part of a split (`with_exact_sums`):
    /// then the image is read from them.
    exact: Option<Vec<ExactPixel>>,
}

impl Film {
    pub fn new(width: u32, height: u32) -> Self {
        let n = (width * height) as usize;
        Self { width, height, sum: vec![Rgb::ZERO; n], weight: vec![0.0; n], squares: None, exact: None }
    }

    /// The same film keeping each pixel's second moment too (from now on: make it empty).
    pub fn with_second_moment(mut self) -> Self {
        self.squares = Some(vec![Rgb::ZERO; self.sum.len()]);
        self
    }

    /// One sample of radiance `radiance` with filter weight `weight` (1 for the box filter):
    /// into the pixel's weighted sum, and, where kept, its second moment.
    #[inline]
    pub fn add_sample(&mut self, x: u32, y: u32, radiance: Rgb, weight: f32) {
        let i = (y * self.width + x) as usize;
        let (squares, exact) = (self.squares.as_deref_mut(), self.exact.as_deref_mut());
        accumulate(&mut self.sum, &mut self.weight, squares, exact, i, radiance * weight, weight, Some(radiance));
    }

    /// Each pixel's second moment, the weighted mean of L² (row-major from the top-left), if
    /// the film keeps it: with the image's mean m, the variance of one sample is m2 − m², and
    /// of the pixel's estimate that over the sample count.
    pub fn second_moments(&self) -> Option<Vec<Rgb>> {
        let squares = self.squares.as_ref()?;
        Some(squares.iter().zip(&self.weight).map(|(s, &w)| if w > 0.0 { *s / w } else { Rgb::ZERO }).collect())
    }

    /// Adds `count` samples whose radiances sum to `radiance_sum` (box filter: weight 1 each).
    pub fn add_samples(&mut self, x: u32, y: u32, radiance_sum: Rgb, count: f32) {
        let i = (y * self.width + x) as usize;
        accumulate(&mut self.sum, &mut self.weight, None, self.exact.as_deref_mut(), i, radiance_sum, count, None);
    }

    /// The film, also keeping its sums exactly (`ExactPixel`): for a render that is one part
    /// of a split by sample range, to be merged with the others.
    pub fn with_exact_sums(mut self) -> Self {
        self.exact = Some(vec![ExactPixel::default(); self.sum.len()]);
        self
    }

    /// The exact sums, row-major from the top-left, if the film keeps them.
    pub fn exact_sums(&self) -> Option<&[ExactPixel]> {
        self.exact.as_deref()
    }

    /// A film of exact sums (parts merged): its image is read from them. `None` if their
    /// number does not match the resolution.
    pub fn from_exact_sums(width: u32, height: u32, exact: Vec<ExactPixel>) -> Option<Self> {
        let n = (width as usize) * (height as usize);
        if exact.len() != n {
            return None;
        }
        // The f32 accumulators hold the means, each with weight 1 (0 where nothing landed).
        let sum = exact.iter().map(ExactPixel::value).collect();
        let weight = exact.iter().map(|p| if p.weight > 0 { 1.0 } else { 0.0 }).collect();
        Some(Self { width, height, sum, weight, squares: None, exact: Some(exact) })
    }

    /// The film as bands of `rows` rows (the last may have fewer), each writable on its own:
    /// parallel tiles add their samples to the band they lie in.
    pub fn bands_mut(&mut self, rows: u32) -> Vec<FilmBand<'_>> {
        // `max(1)`: an empty film has no bands (and chunks of none would panic).
        let (width, len) = (self.width, (self.width * rows).max(1) as usize);
        let bands = self.sum.len().div_ceil(len);
        let mut squares: Vec<Option<&mut [Rgb]>> = match &mut self.squares {
            Some(s) => s.chunks_mut(len).map(Some).collect(),
            None => Vec::new(),
        };
        squares.resize_with(bands, || None);
        let mut exact: Vec<Option<&mut [ExactPixel]>> = match &mut self.exact {
            Some(e) => e.chunks_mut(len).map(Some).collect(),
            None => Vec::new(),
        };
        exact.resize_with(bands, || None);
        self.sum
            .chunks_mut(len)
            .zip(self.weight.chunks_mut(len))
            .zip(squares.into_iter().zip(exact))
            .enumerate()
            .map(|(b, ((sum, weight), (squares, exact)))| {
                // The last band may be shorter.
                let band_rows = (sum.len() / width as usize) as u32;
                FilmBand { width, y0: b as u32 * rows, rows: band_rows, sum, weight, squares, exact }
            })
            .collect()
    }

    /// Adds radiance to a pixel's sum without adding weight (light tracing's splats; the
    /// pass adds its weight to every pixel with `add_weight_everywhere`).
    pub fn add_splat(&mut self, x: u32, y: u32, radiance: Rgb) {
        let i = (y * self.width + x) as usize;
        self.sum[i] += radiance;
        if let Some(exact) = &mut self.exact {
            exact[i].add(radiance, 0.0);
        }
    }

    pub fn add_weight_everywhere(&mut self, weight: f32) {
        self.weight.iter_mut().for_each(|w| *w += weight);
        if let Some(exact) = &mut self.exact {
            exact.iter_mut().for_each(|p| p.add(Rgb::ZERO, weight));
        }
    }

    /// The raw accumulators (for checkpoints): per-pixel radiance sums and weights (not the
    /// second moments).
    pub fn accumulators(&self) -> (&[Rgb], &[f32]) {
        (&self.sum, &self.weight)
    }

    /// A film from saved accumulators; `None` if their sizes do not match the resolution.
    pub fn from_accumulators(width: u32, height: u32, sum: Vec<Rgb>, weight: Vec<f32>) -> Option<Self> {
        let n = (width * height) as usize;
        (sum.len() == n && weight.len() == n).then_some(Self { width, height, sum, weight, squares: None, exact: None })
    }

    /// The pixel's estimate (black if it has no samples yet); from the exact sums where the
    /// film keeps them.
    pub fn pixel(&self, x: u32, y: u32) -> Rgb {
        let i = (y * self.width + x) as usize;
        if let Some(exact) = &self.exact {
            return exact[i].value();
        }
        if self.weight[i] > 0.0 {
            self.sum[i] / self.weight[i]
        } else {
            Rgb::ZERO
        }
    }

    /// All pixel estimates, row-major from the top-left.
    pub fn to_rgb(&self) -> Vec<Rgb> {
        (0..self.height).flat_map(|y| (0..self.width).map(move |x| (x, y))).map(|(x, y)| self.pixel(x, y)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Exact sums do not depend on grouping: 10⁸ + 1 − 10⁸ is 1 in any order or split (in f32
    /// it is 0 added left to right), and a split film's parts merged equal the whole film.
    #[test]
    fn exact_sums_are_the_same_however_the_samples_are_grouped() {
        let samples = [1e8f32, 1.0, -1e8, 0.3, 2.5e-7, 7.0];
        let mut whole = Film::new(1, 1).with_exact_sums();
        for &v in &samples {
            whole.add_sample(0, 0, Rgb::splat(v), 1.0);
        }
        let f32_sum = samples.iter().fold(0.0f32, |s, v| s + v);
        assert_ne!(f32_sum, 1.0 + 0.3 + 2.5e-7 + 7.0);
        for split in 0..=samples.len() {
            let (mut a, mut b) = (Film::new(1, 1).with_exact_sums(), Film::new(1, 1).with_exact_sums());
            samples[..split].iter().rev().for_each(|&v| a.add_sample(0, 0, Rgb::splat(v), 1.0));
            samples[split..].iter().for_each(|&v| b.add_sample(0, 0, Rgb::splat(v), 1.0));
            let mut merged = a.exact_sums().unwrap()[0];
            merged.merge(&b.exact_sums().unwrap()[0]);
            assert_eq!(merged, whole.exact_sums().unwrap()[0], "split at {split}");
        }
        // (1 + 0.3 + 2.5e-7 + 7) / 6, each value rounded to 2⁻⁶⁴ once.
        let expected = ((1.0f64 + 0.3f32 as f64 + 2.5e-7f32 as f64 + 7.0) / 6.0) as f32;
        assert_eq!(whole.pixel(0, 0), Rgb::splat(expected));
        let rebuilt = Film::from_exact_sums(1, 1, whole.exact_sums().unwrap().to_vec()).unwrap();
        assert_eq!(rebuilt.pixel(0, 0), whole.pixel(0, 0));
    }

    /// Splats and weights added to every pixel (light tracing's way) land in the exact sums
    /// too: the exact image is the f32 one's.
    #[test]
    fn splats_reach_the_exact_sums() {
        let mut film = Film::new(2, 1).with_exact_sums();
        film.add_splat(1, 0, Rgb::new(3.0, 1.5, 0.25));
        film.add_weight_everywhere(2.0);
        assert_eq!(film.pixel(1, 0), Rgb::new(1.5, 0.75, 0.125));
        assert_eq!(film.pixel(0, 0), Rgb::ZERO);
        assert_eq!(film.exact_sums().unwrap()[0].weight, 2 * (1i128 << 64));
    }

    /// Samples added through the bands land where `add_samples` puts them, the last band
    /// shorter than the others.
    #[test]
    fn bands_write_their_own_rows() {
        let (width, height) = (5, 7);
        let mut direct = Film::new(width, height);
        let mut banded = Film::new(width, height);
        let mut bands = banded.bands_mut(3);
        assert_eq!(bands.len(), 3);
        for y in 0..height {
            for x in 0..width {
                let radiance = Rgb::new(x as f32, y as f32, (x * y) as f32 + 0.5);
                direct.add_samples(x, y, radiance, 1.0 + y as f32);
                bands[(y / 3) as usize].add_samples(x, y, radiance, 1.0 + y as f32);
            }
        }
        drop(bands);
        assert_eq!(banded, direct);
        assert!(Film::new(0, 4).bands_mut(3).is_empty() && Film::new(4, 0).bands_mut(3).is_empty());
        assert_eq!(banded.pixel(4, 6), Rgb::new(4.0, 6.0, 24.5) / 7.0);
    }

    /// The second moment by hand: samples 1 and 3 (weights 1 and 3) have mean 2.5 and mean
    /// square (1 + 27) / 4 = 7; through the bands as directly; absent unless asked for.
    #[test]
    fn the_second_moment_is_the_weighted_mean_square() {
        let mut direct = Film::new(2, 3).with_second_moment();
        let mut banded = Film::new(2, 3).with_second_moment();
        let mut bands = banded.bands_mut(2);
        for (radiance, weight) in [(1.0, 1.0), (3.0, 3.0)] {
            direct.add_sample(1, 2, Rgb::splat(radiance), weight);
            bands[1].add_sample(1, 2, Rgb::splat(radiance), weight);
        }
        drop(bands);
        assert_eq!(banded, direct);
        assert_eq!(direct.pixel(1, 2), Rgb::splat(2.5));
        let moments = direct.second_moments().unwrap();
        assert_eq!((moments[5], moments[0]), (Rgb::splat(7.0), Rgb::ZERO));
        assert!(Film::new(2, 3).second_moments().is_none());
    }
}
