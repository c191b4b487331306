//! Perlin's gradient noise (Perlin 1985, "An Image Synthesizer"; the quintic fade and the
//! reference permutation of "Improving Noise", 2002) with pbrt-v4's choice of the twelve
//! gradients, so that pbrt's procedural textures read the same noise as in pbrt; and the
//! sums of octaves built on it: fractional Brownian motion and turbulence.
//!
//! pbrt sums fewer octaves where a pixel's footprint spans many (it antialiases with ray
//! differentials); glint has no differentials, so every octave is summed: the same pattern,
//! with its finest detail where pbrt would blur it.

use glam::Vec3;

/// Ken Perlin's reference permutation of 0..256.
const PERMUTATION: [u8; 256] = [
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30, 69, 142, 8, 99, 37, 240,
    21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94, 252, 219, 203, 117, 35, 11, 32, 57, 177, 33, 88,
    237, 149, 56, 87, 174, 20, 125, 136, 171, 168, 68, 175, 74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83,
    111, 229, 122, 60, 211, 133, 230, 220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1, 216,
    80, 73, 209, 76, 132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86, 164, 100, 109, 198, 173, 186,
    3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82, 85, 212, 207, 206, 59, 227, 47, 16, 58, 17,
    182, 189, 28, 42, 223, 183, 170, 213, 119, 248, 152, 2, 44, 154, 163, 70, 221, 153, 101, 155, 167, 43, 172, 9, 129,
    22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232, 178, 185, 112, 104, 218, 246, 97, 228, 251, 34, 242, 193, 238,
    210, 144, 12, 191, 179, 162, 241, 81, 51, 145, 235, 249, 14, 239, 107, 49, 192, 214, 31, 181, 199, 106, 157, 184,
    84, 204, 176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141, 128, 195,
    78, 66, 215, 61, 156, 180,
];

/// Each octave's frequency over the last's: just under 2, so that the octaves' lattices do
/// not line up (pbrt's 1.99).
const LACUNARITY: f32 = 1.99;

fn hash(i: usize) -> usize {
    PERMUTATION[i & 255] as usize
}

/// t³(6t² − 15t + 10): the weight whose first and second derivatives vanish at 0 and 1.
fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// The gradient of lattice point (x, y, z), one of twelve cube edges, dotted with the offset
/// (dx, dy, dz) from that point.
fn gradient(x: usize, y: usize, z: usize, dx: f32, dy: f32, dz: f32) -> f32 {
    let h = hash(hash(hash(x) + y) + z) & 15;
    let u = if h < 8 || h == 12 || h == 13 { dx } else { dy };
    let v = if h < 4 || h == 12 || h == 13 { dy } else { dz };
    (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
}

/// Noise at `p`: zero at the lattice points, smooth, about [−1, 1].
pub fn perlin_noise(p: Vec3) -> f32 {
    // Coordinates folded below 2³⁰ first, so that the cell index fits an i32.
    let p = Vec3::new(p.x % (1 << 30) as f32, p.y % (1 << 30) as f32, p.z % (1 << 30) as f32);
    let cell = p.floor();
    let d = p - cell;
    let [x, y, z] = [cell.x, cell.y, cell.z].map(|c| (c as i32 & 255) as usize);
    let corner =
        |i: usize, j: usize, k: usize| gradient(x + i, y + j, z + k, d.x - i as f32, d.y - j as f32, d.z - k as f32);
    let lerp = |t: f32, a: f32, b: f32| (1.0 - t) * a + t * b;
    let (wx, wy, wz) = (fade(d.x), fade(d.y), fade(d.z));
    let y0 = lerp(wy, lerp(wx, corner(0, 0, 0), corner(1, 0, 0)), lerp(wx, corner(0, 1, 0), corner(1, 1, 0)));
    let y1 = lerp(wy, lerp(wx, corner(0, 0, 1), corner(1, 0, 1)), lerp(wx, corner(0, 1, 1), corner(1, 1, 1)));
    lerp(wz, y0, y1)
}

/// Fractional Brownian motion: Σ ωⁱ noise(λⁱ p) over `octaves` octaves (pbrt's `FBm`).
pub fn fbm(p: Vec3, omega: f32, octaves: u32) -> f32 {
    let (mut sum, mut lambda, mut weight) = (0.0, 1.0, 1.0);
    for _ in 0..octaves {
        sum += weight * perlin_noise(lambda * p);
        lambda *= LACUNARITY;
        weight *= omega;
    }
    sum
}

/// Turbulence: Σ ωⁱ |noise(λⁱ p)| over `octaves` octaves, plus the 0.2 ωⁿ that pbrt's
/// `Turbulence` adds for the octaves beyond the last (the mean |noise| it stands for).
pub fn turbulence(p: Vec3, omega: f32, octaves: u32) -> f32 {
    let (mut sum, mut lambda, mut weight) = (0.0, 1.0, 1.0);
    for _ in 0..octaves {
        sum += weight * perlin_noise(lambda * p).abs();
        lambda *= LACUNARITY;
        weight *= omega;
    }
    sum + weight * 0.2
}

/// Σ |ωⁱ| over `octaves`: a bound on `fbm`'s magnitude (|noise| ≤ 1); `turbulence` adds its
/// 0.2 ωⁿ.
pub fn octave_weights(omega: f32, octaves: u32) -> f32 {
    (0..octaves).map(|i| omega.abs().powi(i as i32)).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_permutation_is_one() {
        let mut seen = [false; 256];
        PERMUTATION.iter().for_each(|&p| seen[p as usize] = true);
        assert!(seen.iter().all(|&s| s));
    }

    #[test]
    fn zero_at_lattice_points_bounded_and_continuous() {
        assert_eq!(perlin_noise(Vec3::new(3.0, -2.0, 7.0)), 0.0);
        let mut max = 0.0f32;
        for i in 0..10_000 {
            let p = Vec3::new(i as f32 * 0.137, i as f32 * 0.071, i as f32 * -0.053);
            let n = perlin_noise(p);
            assert!(n.abs() <= 1.0);
            max = max.max(n.abs());
            let step = perlin_noise(p + Vec3::splat(1e-3));
            assert!((step - n).abs() < 1e-2, "not continuous at {p}");
        }
        assert!(max > 0.3, "noise is suspiciously flat: {max}");
    }

    /// By hand, at (0.5, 0.5, 0.5) (the fades all ½, so the mean of the eight corners'
    /// gradient dots): the corners' hashes from the permutation, their gradients' dots with
    /// (±½, ±½, ±½), averaged.
    #[test]
    fn the_cell_centre_by_hand() {
        let dot = |i: usize, j: usize, k: usize| {
            let h = PERMUTATION[(PERMUTATION[(PERMUTATION[i] as usize + j) & 255] as usize + k) & 255] & 15;
            let d = [0.5 - i as f32, 0.5 - j as f32, 0.5 - k as f32];
            let u = if h < 8 || h == 12 || h == 13 { d[0] } else { d[1] };
            let v = if h < 4 || h == 12 || h == 13 { d[1] } else { d[2] };
            (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
        };
        let mut mean = 0.0;
        for (i, j, k) in (0..8).map(|c| (c & 1, (c >> 1) & 1, c >> 2)) {
            mean += dot(i, j, k) / 8.0;
        }
        assert!((perlin_noise(Vec3::splat(0.5)) - mean).abs() < 1e-6);
        // And the first corner's hash read off the table by hand: P[0] = 151, P[151 + 0] = 17,
        // P[17 + 0] = 36, whose low four bits are 4: u = dx (h < 8), v = dz (h ≥ 4), both
        // signs positive, so dx + dz.
        assert_eq!((PERMUTATION[0], PERMUTATION[151], PERMUTATION[17]), (151, 17, 36));
        assert_eq!(gradient(0, 0, 0, 0.25, 0.75, 0.5), 0.25 + 0.5);
    }

    /// The noise's mean over space is zero, so fbm's is too; turbulence's is positive and
    /// about Σ ωⁱ E|noise| + 0.2 ωⁿ; both stay within their bounds.
    #[test]
    fn octave_sums_are_bounded_and_centred() {
        let n = 20_000;
        let (mut f_mean, mut t_mean) = (0.0f64, 0.0f64);
        for i in 0..n {
            let p = Vec3::new(i as f32 * 0.618_034, i as f32 * 0.381_966 + 0.3, (i % 97) as f32 * 1.31);
            let (f, t) = (fbm(p, 0.5, 8), turbulence(p, 0.5, 8));
            assert!(
                f.abs() <= octave_weights(0.5, 8) && t >= 0.0 && t <= octave_weights(0.5, 8) + 0.2 * 0.5f32.powi(8)
            );
            (f_mean, t_mean) = (f_mean + f as f64 / n as f64, t_mean + t as f64 / n as f64);
        }
        assert!(f_mean.abs() < 0.03, "fbm's mean {f_mean}");
        assert!(t_mean > 0.2 && t_mean < 0.8, "turbulence's mean {t_mean}");
    }
}
