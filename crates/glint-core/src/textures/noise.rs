//! Perlin's gradient noise ("Improving Noise", SIGGRAPH 2002): a smooth pseudo-random function
//! of space in [−1, 1], and its turbulence sum. The permutation is generated from a fixed seed,
//! so every render sees the same noise.

use std::sync::OnceLock;

use glam::Vec3;

fn permutation() -> &'static [u8; 512] {
    static TABLE: OnceLock<[u8; 512]> = OnceLock::new();
    TABLE.get_or_init(|| {
        let mut p: [u8; 256] = std::array::from_fn(|i| i as u8);
        // Fisher–Yates with a fixed xorshift sequence.
        let mut state = 0x2545_F491_4F6C_DD1Du64;
        for i in (1..256).rev() {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            p.swap(i, (state % (i as u64 + 1)) as usize);
        }
        std::array::from_fn(|i| p[i & 255])
    })
}

fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// Dot product of the offset with one of 12 cube-edge gradients chosen by the hash.
fn gradient(hash: u8, x: f32, y: f32, z: f32) -> f32 {
    let h = hash & 15;
    let u = if h < 8 { x } else { y };
    let v = if h < 4 {
        y
    } else if h == 12 || h == 14 {
        x
    } else {
        z
    };
    (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
}

pub fn perlin_noise(p: Vec3) -> f32 {
    let perm = permutation();
    let cell = p.floor();
    let f = p - cell;
    let (xi, yi, zi) = ((cell.x as i32 & 255) as usize, (cell.y as i32 & 255) as usize, (cell.z as i32 & 255) as usize);
    let (u, v, w) = (fade(f.x), fade(f.y), fade(f.z));
    let a = perm[xi] as usize + yi;
    let (aa, ab) = (perm[a] as usize + zi, perm[a + 1] as usize + zi);
    let b = perm[xi + 1] as usize + yi;
    let (ba, bb) = (perm[b] as usize + zi, perm[b + 1] as usize + zi);
    let lerp = |t: f32, a: f32, b: f32| a + t * (b - a);
    let (x, y, z) = (f.x, f.y, f.z);
    lerp(
        w,
        lerp(
            v,
            lerp(u, gradient(perm[aa], x, y, z), gradient(perm[ba], x - 1.0, y, z)),
            lerp(u, gradient(perm[ab], x, y - 1.0, z), gradient(perm[bb], x - 1.0, y - 1.0, z)),
        ),
        lerp(
            v,
            lerp(u, gradient(perm[aa + 1], x, y, z - 1.0), gradient(perm[ba + 1], x - 1.0, y, z - 1.0)),
            lerp(u, gradient(perm[ab + 1], x, y - 1.0, z - 1.0), gradient(perm[bb + 1], x - 1.0, y - 1.0, z - 1.0)),
        ),
    )
}

/// Σ |noise(2^i p)| / 2^i over `octaves` octaves (Perlin 1985).
pub fn turbulence(p: Vec3, octaves: u32) -> f32 {
    (0..octaves).map(|i| perlin_noise(p * (1u32 << i) as f32).abs() / (1u32 << i) as f32).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
