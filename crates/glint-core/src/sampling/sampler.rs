//! Samplers: where a pixel sample's random numbers come from. Every call to `next_f32` is the
//! next dimension of the sample (the film position first, then whatever the integrator draws).
//!
//! * `independent`: uniform random numbers (PCG32), the reference.
//! * `stratified`: each dimension cut into as many strata as the pixel has samples, every
//!   stratum used once over the pixel's samples in an order shuffled per dimension (padded
//!   1D stratification, a Latin hypercube per dimension) and jittered within it. It needs the
//!   sample count up front; with a time limit and no `--spp` it falls back to independent.
//! * `sobol`: the Owen-scrambled Sobol sequence (Burley 2020: the `sobol_burley` crate's
//!   numbers, computed faster by `sobol.rs`), one scramble seed per pixel: well stratified
//!   in every dimension and every 2ᵏ prefix, so it is progressive (each pass adds the next
//!   point) and resumable. Beyond 256 dimensions and 65,536 samples the scramble seed
//!   changes, as the crate advises.
//!
//! All three are deterministic in (seed, pixel, sample index), so images do not depend on
//! the thread count.

use super::rng::mix;
use super::{sobol, Rng};
use crate::Named;
use wide::{f32x8, CmpLt};

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SamplerKind {
    Independent,
    Stratified,
    /// The default: at equal time it reaches 1.75× lower error than `independent` on the
    /// Cornell box (docs/performance.md).
    #[default]
    Sobol,
}

impl Named for SamplerKind {
    const ALL: &'static [Self] = &[SamplerKind::Independent, SamplerKind::Stratified, SamplerKind::Sobol];

    fn name(self) -> &'static str {
        match self {
            SamplerKind::Independent => "independent",
            SamplerKind::Stratified => "stratified",
            SamplerKind::Sobol => "sobol",
        }
    }
}

/// The random numbers of one pixel sample.
#[derive(Clone, Debug)]
pub struct Sampler {
    kind: SamplerKind,
    /// Jitter within strata, and every number of `independent` (`Rng::UNSEEDED` for Sobol).
    rng: Rng,
    /// Per (render seed, pixel): the scramble or shuffle seed.
    pixel_seed: u64,
    /// This sample's index within its pixel, and the pixel's sample count (stratified).
    index: u32,
    count: u32,
    dimension: u32,
    /// Sobol: the four dimensions of the current set, computed together (SIMD), each below 1.
    sobol: [f32; 4],
    /// Sobol: the scramble seed of this sample's first 256 dimensions.
    seed: u32,
    /// Sobol: this sample's index shuffled under `seed`.
    shuffled: u32,
}

impl Sampler {
    /// The samplers `next_f32_lanes` draws for at once (one 256-bit vector of f32).
    pub const LANES: usize = 8;

    /// Sample `index` of pixel `pixel` (of `count` in all; `u32::MAX` if unknown).
    pub fn new(kind: SamplerKind, seed: u64, pixel: u64, index: u32, count: u32) -> Self {
        let kind = if kind == SamplerKind::Stratified && count == u32::MAX { SamplerKind::Independent } else { kind };
        let pixel_seed = pixel_seed(seed, pixel);
        if kind == SamplerKind::Sobol {
            let seed = sobol_seed(pixel_seed, index, 0);
            return Self::sobol(pixel_seed, seed, sobol::shuffled_index(index & 0xFFFF, seed), index, count);
        }
        Self {
            kind,
            rng: Rng::for_sample(seed, pixel, index as u64),
            pixel_seed,
            index,
            count: count.max(1),
            dimension: 0,
            sobol: [0.0; 4],
            seed: 0,
            shuffled: 0,
        }
    }

    /// `new` for the same sample index of eight pixels: what eight calls give, with Sobol's
    /// index shuffles computed together in lanes.
    pub fn new_eight(
        kind: SamplerKind,
        seed: u64,
        pixels: [u64; Self::LANES],
        index: u32,
        count: u32,
    ) -> [Self; Self::LANES] {
        if kind != SamplerKind::Sobol {
            return pixels.map(|pixel| Self::new(kind, seed, pixel, index, count));
        }
        let pixel_seeds = pixels.map(|pixel| pixel_seed(seed, pixel));
        let seeds = pixel_seeds.map(|p| sobol_seed(p, index, 0));
        let shuffled = sobol::shuffled_index_lanes(index & 0xFFFF, seeds);
        std::array::from_fn(|k| Self::sobol(pixel_seeds[k], seeds[k], shuffled[k], index, count))
    }

    /// A Sobol sampler for sample `index` of the pixel with `pixel_seed`, the scramble seed of
    /// its first 256 dimensions `seed`, its index shuffled under it to `shuffled`.
    fn sobol(pixel_seed: u64, seed: u32, shuffled: u32, index: u32, count: u32) -> Self {
        Self {
            kind: SamplerKind::Sobol,
            // It draws nothing from it, and seeding it cost 0.7 % of the Cornell box's
            // instructions.
            rng: Rng::UNSEEDED,
            pixel_seed,
            index,
            count: count.max(1),
            dimension: 0,
            sobol: [0.0; 4],
            seed,
            shuffled,
        }
    }

    /// An independent sampler over a generator (for code that draws its own streams).
    pub fn independent(rng: Rng) -> Self {
        Self {
            kind: SamplerKind::Independent,
            rng,
            pixel_seed: 0,
            index: 0,
            count: 1,
            dimension: 0,
            sobol: [0.0; 4],
            seed: 0,
            shuffled: 0,
        }
    }

    /// The next dimension, uniform in [0, 1).
    #[inline(always)]
    pub fn next_f32(&mut self) -> f32 {
        let d = self.dimension;
        self.dimension += 1;
        // An independent draw, and three Sobol draws in four (which read the set already
        // computed), are inlined into every caller; the rest is a call.
        match self.kind {
            SamplerKind::Independent => self.rng.next_f32(),
            SamplerKind::Sobol if !d.is_multiple_of(4) => self.sobol[(d % 4) as usize],
            _ => self.draw(d),
        }
    }

    /// Dimension `d` of any kind: what `next_f32` does not inline, a stratified draw or the
    /// first of a Sobol set (which computes the set).
    #[inline(never)]
    fn draw(&mut self, d: u32) -> f32 {
        match self.kind {
            SamplerKind::Independent => self.rng.next_f32(),
            SamplerKind::Stratified => {
                let stratum = permute(self.index % self.count, self.count, mix(self.pixel_seed ^ d as u64) as u32);
                ((stratum as f32 + self.rng.next_f32()) / self.count as f32).min(ONE_BELOW)
            }
            SamplerKind::Sobol => {
                // `new` seeded and shuffled the first 256 dimensions; later ones anew.
                let (seed, shuffled) = if d < 256 {
                    (self.seed, self.shuffled)
                } else {
                    let seed = sobol_seed(self.pixel_seed, self.index, d);
                    (seed, sobol::shuffled_index(self.index & 0xFFFF, seed))
                };
                self.sobol = sobol::sample_4d(shuffled, (d % 256) / 4, seed).map(|x| x.min(ONE_BELOW));
                self.sobol[(d % 4) as usize]
            }
        }
    }

    /// The next `N` dimensions of eight samplers at once, as lane vectors: lane k of `out[j]`
    /// is what the `j`-th `next_f32` of `samplers[k]` would give. Sobol samplers standing at
    /// the same dimension (the path tracer's wavefront keeps its paths in step) compute each
    /// set of four dimensions for all eight together (`sobol::sample_4d_lanes`); others draw
    /// one by one.
    pub fn next_f32_lanes<const N: usize>(mut samplers: [&mut Sampler; Self::LANES]) -> [f32x8; N] {
        let first = samplers[0].dimension;
        // Below 256 dimensions every set uses the sample's cached shuffled index (`draw`).
        let in_step =
            first as usize + N <= 256 && samplers.iter().all(|s| s.kind == SamplerKind::Sobol && s.dimension == first);
        if !in_step {
            let mut out = [[0f32; Self::LANES]; N];
            for (k, sampler) in samplers.iter_mut().enumerate() {
                for column in &mut out {
                    column[k] = sampler.next_f32();
                }
            }
            return out.map(f32x8::from);
        }
        // Below 256 dimensions the scramble seed does not depend on the dimension.
        let shuffled = samplers.each_ref().map(|s| s.shuffled);
        let seed = samplers.each_ref().map(|s| s.seed);
        // The set the first dimension falls in: computed already, unless it begins a new one.
        let mut set: [f32x8; 4] = match first % 4 {
            0 => [f32x8::ZERO; 4],
            _ => std::array::from_fn(|i| f32x8::from(samplers.each_ref().map(|s| s.sobol[i]))),
        };
        let mut last_computed = None;
        let mut d = first;
        let out = std::array::from_fn(|_| {
            if d.is_multiple_of(4) {
                // No `min(ONE_BELOW)` as `draw` takes: the crate's floats have 23 bits below
                // 1, so they are at most 1 - 2⁻²³, below ONE_BELOW already.
                let sets = sobol::sample_4d_lanes(shuffled, d / 4, seed);
                set = sets.by_dimension;
                debug_assert!(set.iter().all(|v| v.cmp_lt(f32x8::splat(ONE_BELOW)).all()));
                last_computed = Some(sets.by_sample);
            }
            let column = set[(d % 4) as usize];
            d += 1;
            column
        });
        for (k, sampler) in samplers.iter_mut().enumerate() {
            if let Some(by_sample) = &last_computed {
                sampler.sobol = by_sample[k];
            }
            sampler.dimension = d;
        }
        out
    }
}

const ONE_BELOW: f32 = 1.0 - f32::EPSILON / 2.0;

/// The seed of every sample of a pixel, from the render's seed.
fn pixel_seed(seed: u64, pixel: u64) -> u64 {
    mix(seed ^ mix(pixel ^ 0x5A4D_504C_4552))
}

/// The Sobol scramble seed of dimension `d` of sample `index`: the pixel's own for the first
/// 256 dimensions of its first 2¹⁶ samples (the crate's limits), a new one past them.
fn sobol_seed(pixel_seed: u64, index: u32, d: u32) -> u32 {
    let block = (d / 256) as u64 | ((index >> 16) as u64) << 32;
    if block == 0 {
        pixel_seed as u32
    } else {
        mix(pixel_seed ^ block) as u32
    }
}

/// Kensler's hashed permutation (Correlated Multi-Jittered Sampling, 2013): the position of
/// `i` in a pseudo-random permutation of 0..l chosen by `p`, without storing it.
fn permute(mut i: u32, l: u32, p: u32) -> u32 {
    if l <= 1 {
        return 0;
    }
    let mut w = l - 1;
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    loop {
        i ^= p;
        i = i.wrapping_mul(0xe170_893d);
        i ^= p >> 16;
        i ^= (i & w) >> 4;
        i ^= p >> 8;
        i = i.wrapping_mul(0x0929_eb3f);
        i ^= p >> 23;
        i ^= (i & w) >> 1;
        i = i.wrapping_mul(1 | p >> 27);
        i = i.wrapping_mul(0x6935_fa69);
        i ^= (i & w) >> 11;
        i = i.wrapping_mul(0x74dc_b303);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0x9e50_1cc3);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0xc860_a3df);
        i &= w;
        i ^= i >> 5;
        if i < l {
            break;
        }
    }
    (i.wrapping_add(p)) % l
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn permutations_are_permutations() {
        for l in [1u32, 2, 3, 7, 16, 100, 1000] {
            for p in [0u32, 1, 0xdead_beef] {
                let mut seen = vec![false; l as usize];
                for i in 0..l {
                    let j = permute(i, l, p) as usize;
                    assert!(!seen[j], "l = {l}, p = {p}: {j} twice");
                    seen[j] = true;
                }
            }
        }
    }

    /// Over a pixel's N samples, every dimension puts exactly one sample in each of N strata.
    #[test]
    fn stratified_fills_every_stratum_once_per_dimension() {
        let n = 64;
        let samples: Vec<Vec<f32>> = (0..n)
            .map(|i| {
                let mut s = Sampler::new(SamplerKind::Stratified, 3, 17, i, n);
                (0..10).map(|_| s.next_f32()).collect()
            })
            .collect();
        for d in 0..10 {
            let mut strata: Vec<u32> = samples.iter().map(|s| (s[d] * n as f32) as u32).collect();
            strata.sort_unstable();
            assert_eq!(strata, (0..n).collect::<Vec<_>>(), "dimension {d}");
        }
    }

    /// Sobol draws are the crate's `sample_4d` under the documented seeds, past the first
    /// seed's 256 dimensions and 2¹⁶ samples too (where the shuffle is computed anew).
    #[test]
    fn sobol_draws_are_the_crates_points() {
        let (seed, pixel) = (11u64, 42u64);
        let pixel_seed = mix(seed ^ mix(pixel ^ 0x5A4D_504C_4552));
        for index in [0u32, 3, 65_535, 65_536, 70_001] {
            let mut sampler = Sampler::new(SamplerKind::Sobol, seed, pixel, index, u32::MAX);
            for d in 0..600u32 {
                let block = (d / 256) as u64 | ((index >> 16) as u64) << 32;
                let scramble = if block == 0 { pixel_seed as u32 } else { mix(pixel_seed ^ block) as u32 };
                let expected = sobol_burley::sample_4d(index & 0xFFFF, (d % 256) / 4, scramble)[(d % 4) as usize];
                let got = sampler.next_f32();
                assert_eq!(got.to_bits(), expected.min(ONE_BELOW).to_bits(), "index {index}, dimension {d}");
            }
        }
    }

    /// Every sampler is uniform: a histogram of many dimensions over many pixels (chi-square,
    /// 16 bins), and the Sobol points of one pixel are stratified in every power-of-two prefix.
    #[test]
    fn samplers_are_uniform_and_sobol_is_stratified() {
        for &kind in SamplerKind::ALL {
            let mut bins = [0f64; 16];
            let mut total = 0.0;
            for pixel in 0..64u64 {
                for i in 0..64u32 {
                    let mut s = Sampler::new(kind, 1, pixel, i, 64);
                    for _ in 0..300 {
                        let x = s.next_f32();
                        assert!((0.0..1.0).contains(&x));
                        bins[(x * 16.0) as usize] += 1.0;
                        total += 1.0;
                    }
                }
            }
            let expected = total / 16.0;
            let chi2: f64 = bins.iter().map(|b| (b - expected).powi(2) / expected).sum();
            // 15 degrees of freedom: P(χ² > 37.7) = 0.001.
            assert!(chi2 < 37.7, "{kind:?}: χ² = {chi2}");
        }
        for d in [0u32, 1, 5, 200, 300] {
            let mut strata: Vec<u32> = (0..32u32)
                .map(|i| {
                    let mut s = Sampler::new(SamplerKind::Sobol, 9, 4, i, u32::MAX);
                    (0..d).for_each(|_| {
                        s.next_f32();
                    });
                    (s.next_f32() * 32.0) as u32
                })
                .collect();
            strata.sort_unstable();
            assert_eq!(strata, (0..32).collect::<Vec<_>>(), "dimension {d}");
        }
    }

    /// Eight samplers drawn together give what each gives alone: in step from dimensions that
    /// are and are not multiples of four, with and without a new set, ending at the 256th
    /// dimension, for sample indices past 2¹⁶; out of step (staggered, mixed kinds, past 256).
    #[test]
    fn eight_samplers_at_once_draw_what_each_draws_alone() {
        // (first dimension, numbers drawn, staggered dimensions, one sampler of another kind)
        let cases = [
            (0, 7, false, false),
            (1, 7, false, false),
            (3, 7, false, false),
            (1, 2, false, false),
            (249, 7, false, false),
            (250, 7, false, false),
            (2, 7, true, false),
            (4, 7, false, true),
        ];
        for &kind in SamplerKind::ALL {
            for (first, count, stagger, mixed) in cases {
                for index_base in [5u32, 70_000] {
                    let make = |k: usize| {
                        let kind = if mixed && k == 7 { SamplerKind::Independent } else { kind };
                        let mut s = Sampler::new(kind, 9, 100 + k as u64, index_base + k as u32, 1 << 20);
                        for _ in 0..first + if stagger { k as u32 % 3 } else { 0 } {
                            s.next_f32();
                        }
                        s
                    };
                    let mut together: [Sampler; 8] = std::array::from_fn(make);
                    let mut alone = together.clone();
                    let drawn: Vec<f32x8> = match count {
                        7 => Sampler::next_f32_lanes::<7>(together.each_mut()).to_vec(),
                        _ => Sampler::next_f32_lanes::<2>(together.each_mut()).to_vec(),
                    };
                    let after = Sampler::next_f32_lanes::<3>(together.each_mut());
                    for (k, alone) in alone.iter_mut().enumerate() {
                        let expected: Vec<f32> = (0..count + 3).map(|_| alone.next_f32()).collect();
                        let got: Vec<f32> = drawn.iter().chain(&after).map(|column| column.as_array_ref()[k]).collect();
                        assert_eq!(
                            got,
                            expected,
                            "{} sampler {k}, from dimension {first}, index {index_base}",
                            kind.name()
                        );
                    }
                }
            }
        }
    }
}
