//! Eight 3-vectors in SIMD lanes (`wide`'s `f32x8`, AVX where compiled in): the vector
//! operations the scalar code takes from glam's `Vec3`, each in the same order of roundings,
//! so that a lane computes the same bits as the scalar code it stands for.

use std::ops::{Add, Mul, Neg, Sub};

use glam::Vec3;
use wide::{f32x8, CmpEq, CmpGt};

pub const LANES: usize = 8;

#[derive(Clone, Copy, Debug)]
pub struct Vec3x8 {
    pub x: f32x8,
    pub y: f32x8,
    pub z: f32x8,
}

impl Vec3x8 {
    pub const ZERO: Self = Self { x: f32x8::ZERO, y: f32x8::ZERO, z: f32x8::ZERO };

    pub fn splat(v: Vec3) -> Self {
        Self { x: f32x8::splat(v.x), y: f32x8::splat(v.y), z: f32x8::splat(v.z) }
    }

    /// Lane k is `f(k)`.
    #[inline(always)]
    pub fn from_fn(f: impl Fn(usize) -> Vec3) -> Self {
        // Straight into three columns: through an array of Vec3 and three maps, the compiler
        // kept the arrays' generic machinery (1.3 % of the Cornell box's instructions).
        let (mut x, mut y, mut z) = ([0f32; LANES], [0f32; LANES], [0f32; LANES]);
        for k in 0..LANES {
            let v = f(k);
            (x[k], y[k], z[k]) = (v.x, v.y, v.z);
        }
        Self { x: f32x8::from(x), y: f32x8::from(y), z: f32x8::from(z) }
    }

    #[inline(always)]
    pub fn lane(&self, k: usize) -> Vec3 {
        Vec3::new(self.x.as_array_ref()[k], self.y.as_array_ref()[k], self.z.as_array_ref()[k])
    }

    /// (x·x) + (y·y) + (z·z), as glam sums.
    #[inline(always)]
    pub fn dot(self, o: Self) -> f32x8 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    #[inline(always)]
    pub fn cross(self, o: Self) -> Self {
        Self { x: self.y * o.z - o.y * self.z, y: self.z * o.x - o.z * self.x, z: self.x * o.y - o.x * self.y }
    }

    /// glam's `normalize`: times the reciprocal of the length.
    #[inline(always)]
    pub fn normalize(self) -> Self {
        self * (f32x8::ONE / self.dot(self).sqrt())
    }

    /// glam's `normalize_or`: `fallback` where the reciprocal length is not finite and positive.
    #[inline(always)]
    pub fn normalize_or(self, fallback: Self) -> Self {
        let rcp = f32x8::ONE / self.dot(self).sqrt();
        let ok = rcp.is_finite() & rcp.cmp_gt(f32x8::ZERO);
        Self::select(ok, self * rcp, fallback)
    }

    #[inline(always)]
    pub fn abs(self) -> Self {
        Self { x: self.x.abs(), y: self.y.abs(), z: self.z.abs() }
    }

    /// Component-wise product (colours).
    #[inline(always)]
    pub fn mul_lanes(self, o: Self) -> Self {
        Self { x: self.x * o.x, y: self.y * o.y, z: self.z * o.z }
    }

    /// `a` where `mask` is set, else `b`.
    #[inline(always)]
    pub fn select(mask: f32x8, a: Self, b: Self) -> Self {
        Self { x: mask.blend(a.x, b.x), y: mask.blend(a.y, b.y), z: mask.blend(a.z, b.z) }
    }

    /// Lanes where some component is not zero (a colour that is not black).
    #[inline(always)]
    pub fn nonzero(self) -> f32x8 {
        !(self.x.cmp_eq(f32x8::ZERO) & self.y.cmp_eq(f32x8::ZERO) & self.z.cmp_eq(f32x8::ZERO))
    }

    /// glam's `max_element`: max(x, max(y, z)) with max(a, b) = a > b ? a : b, NaN and ±0
    /// included (on every target, which `fast_max` is not).
    #[inline(always)]
    pub fn max_element(self) -> f32x8 {
        let max = |a: f32x8, b: f32x8| a.cmp_gt(b).blend(a, b);
        max(self.x, max(self.y, self.z))
    }
}

impl Add for Vec3x8 {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Self { x: self.x + o.x, y: self.y + o.y, z: self.z + o.z }
    }
}

impl Sub for Vec3x8 {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Self { x: self.x - o.x, y: self.y - o.y, z: self.z - o.z }
    }
}

impl Neg for Vec3x8 {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self { x: negate(self.x), y: negate(self.y), z: negate(self.z) }
    }
}

/// −x as Rust negates a float: the sign bit flipped (`wide`'s `-x` is 0 − x, which turns −0 into
/// +0 where the scalar code would keep −0).
#[inline(always)]
pub fn negate(x: f32x8) -> f32x8 {
    x ^ f32x8::splat(-0.0)
}

/// A vector times a scalar per lane.
impl Mul<f32x8> for Vec3x8 {
    type Output = Self;
    #[inline(always)]
    fn mul(self, s: f32x8) -> Self {
        Self { x: self.x * s, y: self.y * s, z: self.z * s }
    }
}

/// What the lane routines' tests share: random inputs and a bit-for-bit comparison.
#[cfg(test)]
pub(crate) mod testing {
    use super::{Vec3x8, LANES};
    use crate::sampling::Rng;
    use glam::Vec3;

    /// Eight vectors uniform in the cube of side `scale` about the origin.
    pub fn random_vectors(rng: &mut Rng, scale: f32) -> [Vec3; LANES] {
        std::array::from_fn(|_| Vec3::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, rng.next_f32() - 0.5) * scale)
    }

    pub fn random_floats(rng: &mut Rng, scale: f32) -> [f32; LANES] {
        std::array::from_fn(|_| rng.next_f32() * scale)
    }

    pub fn assert_lanes_equal(lanes: Vec3x8, scalar: [Vec3; LANES], what: &str) {
        for (k, s) in scalar.iter().enumerate() {
            let l = lanes.lane(k);
            assert_eq!(
                l.to_array().map(f32::to_bits),
                s.to_array().map(f32::to_bits),
                "{what}, lane {k}: {l} against {s}"
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::testing::{assert_lanes_equal, random_vectors};
    use super::*;
    use crate::sampling::Rng;

    /// The vector operations compute glam's bits, on random inputs of many scales.
    #[test]
    fn vector_operations_equal_glam_bit_for_bit() {
        let mut rng = Rng::new(11, 5);
        for round in 0..2_000 {
            let scale = 10f32.powi(round % 9 - 4);
            let (a, b) = (random_vectors(&mut rng, scale), random_vectors(&mut rng, 1.0));
            let (la, lb) = (Vec3x8::from_fn(|k| a[k]), Vec3x8::from_fn(|k| b[k]));
            assert_lanes_equal(la.cross(lb), std::array::from_fn(|k| a[k].cross(b[k])), "cross");
            assert_lanes_equal(la.normalize(), a.map(Vec3::normalize), "normalize");
            assert_lanes_equal(la.normalize_or(lb), std::array::from_fn(|k| a[k].normalize_or(b[k])), "normalize_or");
        }
        // normalize_or's fallback: zero, tiny and infinite vectors.
        let odd = [Vec3::ZERO, Vec3::splat(1e-30), Vec3::new(f32::INFINITY, 0.0, 0.0), Vec3::new(-0.0, 0.0, 0.0)];
        let a: [Vec3; LANES] = std::array::from_fn(|k| if k < 4 { odd[k] } else { Vec3::new(k as f32, 1.0, -2.0) });
        let fallback: [Vec3; LANES] = std::array::from_fn(|k| Vec3::new(0.0, k as f32, 1.0).normalize());
        let lanes_a = Vec3x8::from_fn(|k| a[k]);
        let scalar: [Vec3; LANES] = std::array::from_fn(|k| a[k].normalize_or(fallback[k]));
        assert_lanes_equal(lanes_a.normalize_or(Vec3x8::from_fn(|k| fallback[k])), scalar, "normalize_or fallback");
    }

    /// `max_element` against glam's, special values included (NaN, ±0, infinities).
    #[test]
    fn max_element_equals_glam_on_special_values() {
        let specials = [0.0, -0.0, 1.0, 0.5, f32::INFINITY, f32::NAN, 1e-30, 3.0e30, 2.0, -1.0];
        for (i, &x) in specials.iter().enumerate() {
            for &y in &specials {
                let lanes: [f32; LANES] = std::array::from_fn(|k| specials[(i + k) % specials.len()]);
                let v = Vec3x8 { x: f32x8::from(lanes), y: f32x8::splat(y), z: f32x8::splat(x) };
                let max = v.max_element().to_array();
                for k in 0..LANES {
                    let expected = Vec3::new(lanes[k], y, x).max_element();
                    assert_eq!(max[k].to_bits(), expected.to_bits(), "max of {}, {y}, {x}", lanes[k]);
                }
            }
        }
    }
}
