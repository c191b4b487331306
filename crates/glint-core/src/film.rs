//! The film: per-pixel sums of linear RGB radiance in f32 and the weights they carry, so that
//! the image is the weighted mean (with the box filter, the plain average of the pixel's
//! samples). Row 0 is the top row.

use crate::Rgb;

/// Rows `y0..y0 + rows` of a film (`Film::bands_mut`).
pub struct FilmBand<'a> {
    width: u32,
    y0: u32,
    rows: u32,
    sum: &'a mut [Rgb],
    weight: &'a mut [f32],
}

impl FilmBand<'_> {
    /// `Film::add_samples` for pixel (x, y) of the film, which must lie in this band.
    pub fn add_samples(&mut self, x: u32, y: u32, radiance_sum: Rgb, count: f32) {
        debug_assert!(x < self.width && (self.y0..self.y0 + self.rows).contains(&y), "({x}, {y}) outside the band");
        let i = ((y - self.y0) * self.width + x) as usize;
        self.sum[i] += radiance_sum;
        self.weight[i] += count;
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    sum: Vec<Rgb>,
    weight: Vec<f32>,
}

impl Film {
    pub fn new(width: u32, height: u32) -> Self {
        let n = (width * height) as usize;
        Self { width, height, sum: vec![Rgb::ZERO; n], weight: vec![0.0; n] }
    }

    /// Adds `count` samples whose radiances sum to `radiance_sum` (box filter: weight 1 each).
    pub fn add_samples(&mut self, x: u32, y: u32, radiance_sum: Rgb, count: f32) {
        let i = (y * self.width + x) as usize;
        self.sum[i] += radiance_sum;
        self.weight[i] += count;
    }

    /// The film as bands of `rows` rows (the last may have fewer), each writable on its own:
    /// parallel tiles add their samples to the band they lie in.
    pub fn bands_mut(&mut self, rows: u32) -> Vec<FilmBand<'_>> {
        // `max(1)`: an empty film has no bands (and chunks of none would panic).
        let (width, len) = (self.width, (self.width * rows).max(1) as usize);
        self.sum
            .chunks_mut(len)
            .zip(self.weight.chunks_mut(len))
            .enumerate()
            .map(|(b, (sum, weight))| {
                // The last band may be shorter.
                let band_rows = (sum.len() / width as usize) as u32;
                FilmBand { width, y0: b as u32 * rows, rows: band_rows, sum, weight }
            })
            .collect()
    }

    /// Adds radiance to a pixel's sum without adding weight (light tracing's splats; the
    /// pass adds its weight to every pixel with `add_weight_everywhere`).
    pub fn add_splat(&mut self, x: u32, y: u32, radiance: Rgb) {
        self.sum[(y * self.width + x) as usize] += radiance;
    }

    pub fn add_weight_everywhere(&mut self, weight: f32) {
        self.weight.iter_mut().for_each(|w| *w += weight);
    }

    /// The raw accumulators (for checkpoints): per-pixel radiance sums and weights.
    pub fn accumulators(&self) -> (&[Rgb], &[f32]) {
        (&self.sum, &self.weight)
    }

    /// A film from saved accumulators; `None` if their sizes do not match the resolution.
    pub fn from_accumulators(width: u32, height: u32, sum: Vec<Rgb>, weight: Vec<f32>) -> Option<Self> {
        let n = (width * height) as usize;
        (sum.len() == n && weight.len() == n).then_some(Self { width, height, sum, weight })
    }

    /// The pixel's estimate (black if it has no samples yet).
    pub fn pixel(&self, x: u32, y: u32) -> Rgb {
        let i = (y * self.width + x) as usize;
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
}
