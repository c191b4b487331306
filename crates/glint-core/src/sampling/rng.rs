/// PCG32 (O'Neill 2014, XSH-RR variant): small state, good statistics, fast.
#[derive(Clone, Debug)]
pub struct Rng {
    state: u64,
    increment: u64,
}

const MULTIPLIER: u64 = 6364136223846793005;

impl Rng {
    /// A generator that is never drawn from (a Sobol sampler's): no seeding work.
    pub const UNSEEDED: Rng = Rng { state: 0, increment: 1 };

    pub fn new(seed: u64, stream: u64) -> Self {
        let mut rng = Rng { state: 0, increment: (stream << 1) | 1 };
        rng.next_u32();
        rng.state = rng.state.wrapping_add(seed);
        rng.next_u32();
        rng
    }

    /// A generator for one pixel sample, independent of any other (seed, pixel, sample).
    pub fn for_sample(seed: u64, pixel: u64, sample: u64) -> Self {
        Rng::new(mix(seed ^ mix(pixel)), mix(sample.wrapping_add(0x5851_F42D_4C95_7F2D)))
    }

    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(MULTIPLIER).wrapping_add(self.increment);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        xorshifted.rotate_right((old >> 59) as u32)
    }

    /// Uniform in [0, 1): 24 random bits, so 1.0 is never returned.
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
    }
}

/// SplitMix64's finaliser: a bijective 64-bit hash.
pub(super) fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_floats_have_the_right_moments() {
        let mut rng = Rng::new(42, 1);
        let n = 1_000_000;
        let (mut sum, mut sum2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let x = rng.next_f32() as f64;
            assert!((0.0..1.0).contains(&x));
            sum += x;
            sum2 += x * x;
        }
        let mean = sum / n as f64;
        let var = sum2 / n as f64 - mean * mean;
        // Standard error of the mean is sqrt(1/12/n) ≈ 2.9e-4; allow 5σ.
        assert!((mean - 0.5).abs() < 1.5e-3, "{mean}");
        assert!((var - 1.0 / 12.0).abs() < 1e-3, "{var}");
    }

    #[test]
    fn streams_differ_and_repeat() {
        let a: Vec<u32> = (0..4).map(|_| Rng::for_sample(1, 2, 3).next_u32()).collect();
        assert!(a.windows(2).all(|w| w[0] == w[1]));
        assert_ne!(Rng::for_sample(1, 2, 3).next_u32(), Rng::for_sample(1, 3, 3).next_u32());
        assert_ne!(Rng::for_sample(1, 2, 3).next_u32(), Rng::for_sample(1, 2, 4).next_u32());
    }
}
