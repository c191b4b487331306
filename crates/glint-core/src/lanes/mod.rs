//! Numbers in lanes: the one type the shared routines of the scalar code and the wavefront
//! are written against. A routine written once for `L: Lanes` is the scalar code with `f32`
//! (one lane, where `Mask` is a `bool`) and eight paths at once with `f32x8` (`wide`'s AVX
//! vector where compiled in), as Mitsuba 3 writes one templated body for its scalar and
//! vectorised variants. Each operation computes, lane by lane, the bits the scalar operation
//! computes (glam's order of roundings for the vectors; tested), so a routine gives the same
//! image at every width.
//!
//! Branches become selects: a lane routine computes both sides and keeps one per lane (`select`),
//! which in scalar code is the `if` it replaces. The functions of `math` (sine and cosine,
//! exp, ln, acos) are written for any width too, so that they give the same bits everywhere
//! (the library's and `wide`'s differ).

mod math;

use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

use glam::Vec3;
pub(crate) use math::{acos, atan2, exp, ln, sin_cos_quarter, sin_cos_turns};
use wide::{f32x4, f32x8, i32x4, i32x8, CmpEq, CmpGe, CmpGt, CmpLe, CmpLt};

/// The wavefront's width: paths shaded together.
pub const LANES: usize = 8;

/// A float in each of `WIDTH` lanes, with the operations the shared routines use.
pub trait Lanes: Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self> {
    const WIDTH: usize;
    const ZERO: Self;
    const ONE: Self;
    /// A truth value per lane.
    type Mask: Copy
        + Default
        + std::fmt::Debug
        + BitAnd<Output = Self::Mask>
        + BitOr<Output = Self::Mask>
        + Not<Output = Self::Mask>;

    fn splat(x: f32) -> Self;
    /// −x as Rust negates a float: the sign bit flipped, so −0 stays −0 (`wide`'s `-x` is 0 − x).
    fn negate(self) -> Self;
    fn abs(self) -> Self;
    fn sqrt(self) -> Self;
    /// The magnitude of `self` with the sign of `sign`.
    fn copysign(self, sign: Self) -> Self;
    fn lt(self, o: Self) -> Self::Mask;
    fn le(self, o: Self) -> Self::Mask;
    fn gt(self, o: Self) -> Self::Mask;
    fn ge(self, o: Self) -> Self::Mask;
    fn eq(self, o: Self) -> Self::Mask;
    fn is_finite(self) -> Self::Mask;
    fn is_infinite(self) -> Self::Mask;
    /// `a` in the lanes where `mask` is set, else `b`.
    fn select(mask: Self::Mask, a: Self, b: Self) -> Self;
    /// Whether any lane of `mask` is set.
    fn any(mask: Self::Mask) -> bool;

    /// `self > o ? self : o`: the larger, and `o` where either is NaN (SSE's `max`; glam's
    /// `max` for the values the routines meet).
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        Self::select(self.gt(o), self, o)
    }

    /// `self < o ? self : o`: the smaller, and `o` where either is NaN.
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        Self::select(self.lt(o), self, o)
    }

    /// The largest integer not above `self`.
    fn floor(self) -> Self;
    /// 2ⁿ for an integer `n` in [−126, 127] (an exponent put in place).
    fn pow2i(n: Self) -> Self;
    /// For a positive normal float, its mantissa m in [½, 1) and exponent e: self = m·2ᵉ.
    fn mantissa_and_exponent(self) -> (Self, Self);

    /// Each coordinate of `x` one float up where `sign`'s is positive, down where it is
    /// negative, unchanged where it is 0 (`geometry::robust::step_toward`).
    fn step_toward(x: LaneVec3<Self>, sign: LaneVec3<Self>) -> LaneVec3<Self>;

    /// Lane `k`'s value.
    fn lane(self, k: usize) -> f32;
    /// Lane k is `f(k)`: a gather, each lane's load independent of the others', so that a
    /// lookup's memory latency is paid once for all the lanes rather than once per lane.
    fn from_fn(f: impl FnMut(usize) -> f32) -> Self;
}

impl Lanes for f32 {
    const WIDTH: usize = 1;
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    type Mask = bool;

    #[inline(always)]
    fn splat(x: f32) -> Self {
        x
    }
    #[inline(always)]
    fn negate(self) -> Self {
        -self
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f32::abs(self)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f32::sqrt(self)
    }
    #[inline(always)]
    fn copysign(self, sign: Self) -> Self {
        f32::copysign(self, sign)
    }
    #[inline(always)]
    fn lt(self, o: Self) -> bool {
        self < o
    }
    #[inline(always)]
    fn le(self, o: Self) -> bool {
        self <= o
    }
    #[inline(always)]
    fn gt(self, o: Self) -> bool {
        self > o
    }
    #[inline(always)]
    fn ge(self, o: Self) -> bool {
        self >= o
    }
    #[inline(always)]
    fn eq(self, o: Self) -> bool {
        self == o
    }
    #[inline(always)]
    fn is_finite(self) -> bool {
        f32::is_finite(self)
    }
    #[inline(always)]
    fn is_infinite(self) -> bool {
        f32::is_infinite(self)
    }
    #[inline(always)]
    fn select(mask: bool, a: Self, b: Self) -> Self {
        if mask {
            a
        } else {
            b
        }
    }
    #[inline(always)]
    fn any(mask: bool) -> bool {
        mask
    }

    #[inline(always)]
    fn floor(self) -> Self {
        f32::floor(self)
    }
    #[inline(always)]
    fn pow2i(n: Self) -> Self {
        f32::from_bits(((n as i32 + 127) << 23) as u32)
    }
    #[inline(always)]
    fn mantissa_and_exponent(self) -> (Self, Self) {
        let bits = self.to_bits();
        (f32::from_bits((bits & 0x807F_FFFF) | 0x3F00_0000), (((bits >> 23) & 0xFF) as i32 - 126) as f32)
    }

    /// Three coordinates in three lanes of the eight-lane step: the scalar step's branches on
    /// random signs mispredicted (`offset_ray_origin` was 5 % of a path tracer's time).
    #[inline(always)]
    fn step_toward(x: LaneVec3<f32>, sign: LaneVec3<f32>) -> LaneVec3<f32> {
        let lanes = |v: LaneVec3<f32>| f32x8::from([v.x, v.y, v.z, 0.0, 0.0, 0.0, 0.0, 0.0]);
        let stepped = step_toward8(lanes(x), lanes(sign)).to_array();
        LaneVec3 { x: stepped[0], y: stepped[1], z: stepped[2] }
    }

    #[inline(always)]
    fn lane(self, _k: usize) -> f32 {
        self
    }
    #[inline(always)]
    fn from_fn(mut f: impl FnMut(usize) -> f32) -> Self {
        f(0)
    }
}

/// `wide`'s vectors: eight lanes for the wavefront's paths, four for a colour's channels.
macro_rules! wide_lanes {
    ($float:ident, $int:ident, $width:literal) => {
        impl Lanes for $float {
            const WIDTH: usize = $width;
            const ZERO: Self = $float::ZERO;
            const ONE: Self = $float::ONE;
            /// All ones in a set lane, as the comparisons give it.
            type Mask = $float;

            #[inline(always)]
            fn splat(x: f32) -> Self {
                $float::splat(x)
            }
            #[inline(always)]
            fn negate(self) -> Self {
                self ^ $float::splat(-0.0)
            }
            #[inline(always)]
            fn abs(self) -> Self {
                $float::abs(self)
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                $float::sqrt(self)
            }
            #[inline(always)]
            fn copysign(self, sign: Self) -> Self {
                $float::copysign(self, sign)
            }
            #[inline(always)]
            fn lt(self, o: Self) -> Self {
                self.cmp_lt(o)
            }
            #[inline(always)]
            fn le(self, o: Self) -> Self {
                self.cmp_le(o)
            }
            #[inline(always)]
            fn gt(self, o: Self) -> Self {
                self.cmp_gt(o)
            }
            #[inline(always)]
            fn ge(self, o: Self) -> Self {
                self.cmp_ge(o)
            }
            #[inline(always)]
            fn eq(self, o: Self) -> Self {
                self.cmp_eq(o)
            }
            #[inline(always)]
            fn is_finite(self) -> Self {
                $float::is_finite(self)
            }
            #[inline(always)]
            fn is_infinite(self) -> Self {
                $float::is_inf(self)
            }
            #[inline(always)]
            fn select(mask: Self, a: Self, b: Self) -> Self {
                mask.blend(a, b)
            }
            #[inline(always)]
            fn any(mask: Self) -> bool {
                mask.any()
            }
            #[inline(always)]
            fn floor(self) -> Self {
                $float::floor(self)
            }
            #[inline(always)]
            fn pow2i(n: Self) -> Self {
                bytemuck::cast((n.round_int() + $int::splat(127)) << 23)
            }
            #[inline(always)]
            fn mantissa_and_exponent(self) -> (Self, Self) {
                let bits: $int = bytemuck::cast(self);
                let mantissa = bytemuck::cast((bits & $int::splat(0x807F_FFFFu32 as i32)) | $int::splat(0x3F00_0000));
                let exponent: $int = ((bits >> 23) & $int::splat(0xFF)) - $int::splat(126);
                (mantissa, exponent.round_float())
            }
            #[inline(always)]
            fn step_toward(x: LaneVec3<Self>, sign: LaneVec3<Self>) -> LaneVec3<Self> {
                LaneVec3 {
                    x: step_toward_lanes!($float, $int, x.x, sign.x),
                    y: step_toward_lanes!($float, $int, x.y, sign.y),
                    z: step_toward_lanes!($float, $int, x.z, sign.z),
                }
            }

            #[inline(always)]
            fn lane(self, k: usize) -> f32 {
                self.as_array_ref()[k]
            }
            #[inline(always)]
            fn from_fn(f: impl FnMut(usize) -> f32) -> Self {
                $float::from(std::array::from_fn::<f32, $width, _>(f))
            }
        }
    };
}

/// `step_toward` in lanes of `$float` (bits in `$int`): `next_float_up(x)` where `sign > 0`,
/// `next_float_down(x)` where `sign < 0`, `x` where it is 0, bit for bit for every x but NaN
/// (whose bits step like any other's), by selects (tested against
/// `geometry::robust::step_toward`).
macro_rules! step_toward_lanes {
    ($float:ident, $int:ident, $x:expr, $sign:expr) => {{
        let (x, sign): ($float, $float) = ($x, $sign);
        let bits = |v: $float| -> $int { bytemuck::cast(v) };
        let zero = $float::ZERO;
        let up = sign.cmp_gt(zero);
        // A zero steps from the zero of the side it leaves: +0 going up, −0 going down.
        let from = x.cmp_eq(zero).blend(up.blend(zero, $float::splat(-0.0)), x);
        let from = bits(from);
        // Away from zero when `from` is positive going up or negative going down: all ones
        // where its sign mask (all ones for negative) differs from `up`.
        let away = (from >> 31) ^ bits(up);
        // +1 away from zero, −1 toward it: −1 − 2·away.
        let stepped = from + ($int::splat(-1) - (away + away));
        let infinite = (from & $int::splat(i32::MAX)).cmp_eq($int::splat(0x7F80_0000));
        // NaN: not equal to itself (`cmp_ne` is ordered on AVX, unordered on SSE).
        let keep: $int = bits(sign.cmp_eq(zero) | !sign.cmp_eq(sign)) | (infinite & away);
        let stepped: $float = bytemuck::cast(keep.blend(bits(x), stepped));
        stepped
    }};
}

wide_lanes!(f32x4, i32x4, 4);
wide_lanes!(f32x8, i32x8, 8);

/// `step_toward` in eight lanes (`Lanes::step_toward` of one coordinate).
#[inline(always)]
pub(crate) fn step_toward8(x: f32x8, sign: f32x8) -> f32x8 {
    step_toward_lanes!(f32x8, i32x8, x, sign)
}

/// A 3-vector with a number of lanes in each coordinate: glam's `Vec3` for `f32`, eight
/// vectors in columns for `f32x8`.
#[derive(Clone, Copy, Debug)]
pub struct LaneVec3<L> {
    pub x: L,
    pub y: L,
    pub z: L,
}

/// Eight 3-vectors in SIMD lanes.
pub type Vec3x8 = LaneVec3<f32x8>;

impl From<Vec3> for LaneVec3<f32> {
    #[inline(always)]
    fn from(v: Vec3) -> Self {
        Self { x: v.x, y: v.y, z: v.z }
    }
}

impl From<LaneVec3<f32>> for Vec3 {
    #[inline(always)]
    fn from(v: LaneVec3<f32>) -> Self {
        Vec3::new(v.x, v.y, v.z)
    }
}

impl<L: Lanes> LaneVec3<L> {
    pub const ZERO: Self = Self { x: L::ZERO, y: L::ZERO, z: L::ZERO };

    /// Lane k is `f(k)`, for up to sixteen lanes: a gather (`Lanes::from_fn`), one call of `f`
    /// per lane.
    #[inline(always)]
    pub fn gather(mut f: impl FnMut(usize) -> Vec3) -> Self {
        let (mut y, mut z) = ([0f32; 16], [0f32; 16]);
        let x = L::from_fn(|k| {
            let v = f(k);
            (y[k], z[k]) = (v.y, v.z);
            v.x
        });
        Self { x, y: L::from_fn(|k| y[k]), z: L::from_fn(|k| z[k]) }
    }

    /// `m * v` in every lane, in glam's order of roundings (column by column).
    #[inline(always)]
    pub fn transformed_by(self, m: &glam::Mat3) -> Self {
        let column = |a: Vec3, s: L| Self::splat(a) * s;
        column(m.x_axis, self.x) + column(m.y_axis, self.y) + column(m.z_axis, self.z)
    }

    #[inline(always)]
    pub fn new(x: L, y: L, z: L) -> Self {
        Self { x, y, z }
    }

    /// `v` in every lane.
    #[inline(always)]
    pub fn splat(v: Vec3) -> Self {
        Self { x: L::splat(v.x), y: L::splat(v.y), z: L::splat(v.z) }
    }

    /// (x·x) + (y·y) + (z·z), as glam sums.
    #[inline(always)]
    pub fn dot(self, o: Self) -> L {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    #[inline(always)]
    pub fn cross(self, o: Self) -> Self {
        Self { x: self.y * o.z - o.y * self.z, y: self.z * o.x - o.z * self.x, z: self.x * o.y - o.x * self.y }
    }

    /// glam's `normalize`: times the reciprocal of the length.
    #[inline(always)]
    pub fn normalize(self) -> Self {
        self * (L::ONE / self.dot(self).sqrt())
    }

    /// glam's `try_normalize`: the vector times the reciprocal of its length, and the lanes
    /// where that reciprocal is finite and positive (a direction).
    #[inline(always)]
    pub fn try_normalize(self) -> (Self, L::Mask) {
        let rcp = L::ONE / self.dot(self).sqrt();
        (self * rcp, rcp.is_finite() & rcp.gt(L::ZERO))
    }

    /// glam's `normalize_or`: `fallback` where the reciprocal length is not finite and positive.
    #[inline(always)]
    pub fn normalize_or(self, fallback: Self) -> Self {
        let (normalized, ok) = self.try_normalize();
        Self::select(ok, normalized, fallback)
    }

    /// Each coordinate divided by `s` (not times its reciprocal: glam's `Vec3 / f32`).
    #[inline(always)]
    pub fn divided_by(self, s: L) -> Self {
        Self { x: self.x / s, y: self.y / s, z: self.z / s }
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
    pub fn select(mask: L::Mask, a: Self, b: Self) -> Self {
        Self { x: L::select(mask, a.x, b.x), y: L::select(mask, a.y, b.y), z: L::select(mask, a.z, b.z) }
    }

    /// Lanes where some component is not zero (a colour that is not black).
    #[inline(always)]
    pub fn nonzero(self) -> L::Mask {
        !(self.x.eq(L::ZERO) & self.y.eq(L::ZERO) & self.z.eq(L::ZERO))
    }

    /// glam's `max_element`: max(x, max(y, z)) with max(a, b) = a > b ? a : b, NaN and ±0
    /// included (on every target, which `fast_max` is not).
    #[inline(always)]
    pub fn max_element(self) -> L {
        self.x.max(self.y.max(self.z))
    }
}

impl Vec3x8 {
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
}

impl<L: Lanes> Add for LaneVec3<L> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Self { x: self.x + o.x, y: self.y + o.y, z: self.z + o.z }
    }
}

impl<L: Lanes> Sub for LaneVec3<L> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Self { x: self.x - o.x, y: self.y - o.y, z: self.z - o.z }
    }
}

impl<L: Lanes> Neg for LaneVec3<L> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self { x: self.x.negate(), y: self.y.negate(), z: self.z.negate() }
    }
}

/// A vector times a scalar per lane.
impl<L: Lanes> Mul<L> for LaneVec3<L> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, s: L) -> Self {
        Self { x: self.x * s, y: self.y * s, z: self.z * s }
    }
}

/// Refraction of the unit `incident` (toward the surface) through the unit normal `n` on its
/// side, for η = n_incident / n_transmitted (`geometry::refract`): the direction, and the lanes
/// where it exists (not total internal reflection).
#[inline(always)]
pub(crate) fn refract<L: Lanes>(incident: LaneVec3<L>, n: LaneVec3<L>, eta: L) -> (LaneVec3<L>, L::Mask) {
    let cos_i = incident.dot(n).negate();
    let sin2_t = eta * eta * (L::ONE - cos_i * cos_i).max(L::ZERO);
    let cos_t = (L::ONE - sin2_t).sqrt();
    (incident * eta + n * (eta * cos_i - cos_t), !sin2_t.gt(L::ONE))
}

/// Mirror reflection of `incident` about `n`: I − 2(I·N)N (`geometry::reflect`).
#[inline(always)]
pub(crate) fn reflect<L: Lanes>(incident: LaneVec3<L>, n: LaneVec3<L>) -> LaneVec3<L> {
    incident - n * (L::splat(2.0) * incident.dot(n))
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
