//! Elementary functions for any width (`Lanes`): one body, so a lane computes the bits the
//! scalar code computes, where the platform's libm (scalar) and `wide` (lanes) differ. The
//! polynomials are Moshier's Cephes single-precision ones (a few ulps); each is tested against
//! f64.

use super::Lanes;

/// (sin x, cos x) for |x| ≤ π/4 by their Taylor polynomials to x⁹ and x¹⁰, whose remainders
/// there (below 2·10⁻⁹) are under half an ulp of the result: the range needs no reduction, so
/// this is a few multiply-adds instead of a call to the library's sincos (2.7 % of a path
/// tracer's time, for the concentric map of every diffuse bounce).
#[inline(always)]
pub(crate) fn sin_cos_quarter<L: Lanes>(x: L) -> (L, L) {
    let c = L::splat;
    let x2 = x * x;
    let sin =
        x * (c(1.0) + x2 * (c(-1.0 / 6.0) + x2 * (c(1.0 / 120.0) + x2 * (c(-1.0 / 5040.0) + x2 * c(1.0 / 362_880.0)))));
    let cos = c(1.0)
        + x2 * (c(-0.5)
            + x2 * (c(1.0 / 24.0) + x2 * (c(-1.0 / 720.0) + x2 * (c(1.0 / 40_320.0) + x2 * c(-1.0 / 3_628_800.0)))));
    (sin, cos)
}

/// (sin φ, cos φ) of φ = 2π·`turns` for `turns` in [0, 1] (an angle drawn uniformly): the
/// nearest quarter turn taken off exactly (Sterbenz: the difference of two floats within a
/// factor 2 of each other is exact), the rest, within ±π/4, by `sin_cos_quarter`, and the
/// quarter's rotation by selects. The same bits at every width, where the library's sin and
/// cos (scalar) and `wide`'s (lanes) differ; and 2π·turns is never rounded to a float first.
#[inline(always)]
pub(crate) fn sin_cos_turns<L: Lanes>(turns: L) -> (L, L) {
    let c = L::splat;
    let (q1, q2, q3, q4) = (turns.ge(c(0.125)), turns.ge(c(0.375)), turns.ge(c(0.625)), turns.ge(c(0.875)));
    let quarter = L::select(q4, c(1.0), L::select(q3, c(0.75), L::select(q2, c(0.5), L::select(q1, c(0.25), c(0.0)))));
    let (s, co) = sin_cos_quarter(c(std::f32::consts::TAU) * (turns - quarter));
    // sin and cos of a quarter turn plus x: (cos x, −sin x), (−sin x, −cos x), (−cos x, sin x).
    let sin = L::select(q4, s, L::select(q3, co.negate(), L::select(q2, s.negate(), L::select(q1, co, s))));
    let cos = L::select(q4, co, L::select(q3, s, L::select(q2, co.negate(), L::select(q1, s.negate(), co))));
    (sin, cos)
}

/// eˣ (Cephes `expf`): x = n ln 2 + r with |r| ≤ ½ ln 2 (ln 2 split in two so that n ln 2 is
/// exact), a degree-7 polynomial for eʳ, times 2ⁿ. 0 below −87.3 (where the result would be
/// subnormal), ∞ above 88.7.
#[inline(always)]
pub(crate) fn exp<L: Lanes>(x: L) -> L {
    let c = L::splat;
    let clamped = x.max(c(-87.336_54)).min(c(88.722_83));
    let n = (clamped * c(std::f32::consts::LOG2_E) + c(0.5)).floor();
    let r = clamped - n * c(0.693_359_4) - n * c(-2.121_944_4e-4);
    let z = r * r;
    let p = c(1.987_569_1e-4) * r + c(1.398_2e-3);
    let p = ((((p * r + c(8.333_452e-3)) * r + c(4.166_579_6e-2)) * r + c(0.166_666_65)) * r + c(0.5)) * z + r + c(1.0);
    let value = p * L::pow2i(n.min(c(127.0)));
    // e^88.72… is past 2¹²⁷ by a fraction: one more doubling reaches the largest floats.
    let value = L::select(n.gt(c(127.0)), value * c(2.0), value);
    L::select(x.lt(c(-87.336_54)), L::ZERO, L::select(x.gt(c(88.722_83)), c(f32::INFINITY), value))
}

/// ln x (Cephes `logf`): x = m·2ᵉ with m in [√½, √2), a degree-9 polynomial for ln m. −∞ at 0,
/// NaN below 0 and at NaN, ∞ at ∞; subnormals scaled into the normal range first.
#[inline(always)]
pub(crate) fn ln<L: Lanes>(x: L) -> L {
    let c = L::splat;
    let subnormal = x.lt(c(f32::MIN_POSITIVE));
    let scaled = L::select(subnormal, x * c(8_388_608.0), x); // 2²³
    let (m, e) = scaled.mantissa_and_exponent();
    let e = L::select(subnormal, e - c(23.0), e);
    let small = m.lt(c(std::f32::consts::FRAC_1_SQRT_2));
    let e = L::select(small, e - c(1.0), e);
    let m = L::select(small, m + m - c(1.0), m - c(1.0));
    let z = m * m;
    let p = c(7.037_683_6e-2) * m - c(0.115_146_1);
    let p = ((((((p * m + c(0.116_769_99)) * m - c(0.124_201_41)) * m + c(0.142_493_23)) * m - c(0.166_680_57)) * m
        + c(0.200_007_15))
        * m
        - c(0.249_999_94))
        * m
        + c(0.333_333_33);
    let y = p * m * z + e * c(-2.121_944_4e-4) - c(0.5) * z;
    let value = m + y + e * c(0.693_359_4);
    let value = L::select(x.eq(L::ZERO), c(f32::NEG_INFINITY), value);
    let value = L::select(x.eq(c(f32::INFINITY)), x, value);
    // Below zero, and NaN (which no comparison holds for): NaN.
    L::select(x.ge(L::ZERO), value, c(f32::NAN))
}

/// arccos x for x in [−1, 1] (Cephes `asinf`'s polynomial): near ±1 through
/// arcsin √((1 − |x|)/2), which keeps the small angles exact.
#[inline(always)]
pub(crate) fn acos<L: Lanes>(x: L) -> L {
    let c = L::splat;
    let a = x.abs();
    let near_one = a.gt(c(0.5));
    let z = L::select(near_one, c(0.5) * (c(1.0) - a), a * a);
    let s = L::select(near_one, z.sqrt(), a);
    let p = ((((c(4.216_32e-2) * z + c(2.418_131_2e-2)) * z + c(4.547_002_6e-2)) * z + c(7.495_300_3e-2)) * z
        + c(0.166_667_52))
        * z
        * s
        + s;
    // arccos |x| = 2 arcsin √((1 − |x|)/2) near 1, π/2 − arcsin |x| elsewhere.
    let acos_a = L::select(near_one, c(2.0) * p, c(std::f32::consts::FRAC_PI_2) - p);
    L::select(x.lt(L::ZERO), c(std::f32::consts::PI) - acos_a, acos_a)
}

/// arctan y/x in (−π, π], the angle of (x, y) (Cephes `atan2f` over `atanf`): |y/x| reduced
/// to [0, tan π/8] by arctan t = π/2 − arctan 1/t above tan 3π/8 and π/4 + arctan (t − 1)/(t + 1)
/// above tan π/8, a degree-9 odd polynomial there, and π added or taken off where x < 0. The
/// signed zeros as IEEE's atan2 has them: ±0 along +x (and at the origin with x = +0), ±π along
/// −x (and at the origin with x = −0). NaN where both are infinite (IEEE's ±π/4, ±3π/4): the
/// directions it serves are finite.
#[inline(always)]
pub(crate) fn atan2<L: Lanes>(y: L, x: L) -> L {
    let c = L::splat;
    let ratio = y / x;
    let t = ratio.abs();
    let beyond = t.gt(c(2.414_213_6)); // tan 3π/8
    let middle = t.gt(c(0.414_213_57)); // tan π/8
    let reduced = L::select(beyond, c(-1.0) / t, L::select(middle, (t - c(1.0)) / (t + c(1.0)), t));
    let base =
        L::select(beyond, c(std::f32::consts::FRAC_PI_2), L::select(middle, c(std::f32::consts::FRAC_PI_4), L::ZERO));
    let z = reduced * reduced;
    let p =
        (((c(8.053_744_5e-2) * z - c(0.138_776_86)) * z + c(0.199_777_1)) * z - c(0.333_329_5)) * z * reduced + reduced;
    let atan = (base + p).copysign(ratio);
    // Left of the y axis (x's sign bit set, −0 included) the ratio's angle is half a turn
    // off; the sign of the half turn is y's.
    let x_negative = c(1.0).copysign(x).lt(L::ZERO);
    let half_turn = c(std::f32::consts::PI).copysign(y);
    let angle = L::select(x_negative, atan + half_turn, atan);
    // 0/0 at the origin: the zero or half turn the signs give.
    let origin = x.eq(L::ZERO) & y.eq(L::ZERO);
    L::select(origin, L::select(x_negative, half_turn, L::ZERO.copysign(y)), angle)
}

#[cfg(test)]
mod tests {
    use super::*;
    use wide::f32x8;

    /// Within two ulps of the correctly rounded sine and cosine over the whole quarter, and
    /// exact at 0.
    #[test]
    fn sin_cos_quarter_is_accurate() {
        use std::f32::consts::FRAC_PI_4;
        assert_eq!(sin_cos_quarter(0.0f32), (0.0, 1.0));
        // Floats between the two (the pair has one sign: sin x and its polynomial share x's).
        let ulps = |a: f32, b: f64| (i64::from(a.to_bits()) - i64::from((b as f32).to_bits())).abs();
        for i in -10_000..=10_000 {
            let x = FRAC_PI_4 * i as f32 / 10_000.0;
            let (sin, cos) = sin_cos_quarter(x);
            let (s64, c64) = (x as f64).sin_cos();
            assert!(ulps(sin, s64) <= 2, "sin {x}: {sin} against {s64}");
            assert!(ulps(cos, c64) <= 2, "cos {x}: {cos} against {c64}");
        }
    }

    /// A whole turn within 2.5·10⁻⁷ of sin and cos of 2π·turns in f64 (the turns exact), the
    /// quarter turns exact, and eight lanes equal to one.
    #[test]
    fn sin_cos_turns_is_accurate_over_the_turn() {
        let mut worst = 0f64;
        for i in 0..=200_000 {
            let turns = i as f32 / 200_000.0;
            let (sin, cos) = sin_cos_turns(turns);
            let (s64, c64) = (std::f64::consts::TAU * turns as f64).sin_cos();
            worst = worst.max((sin as f64 - s64).abs()).max((cos as f64 - c64).abs());
            let eight = sin_cos_turns(f32x8::splat(turns));
            assert_eq!(
                (eight.0.as_array_ref()[3].to_bits(), eight.1.as_array_ref()[3].to_bits()),
                (sin.to_bits(), cos.to_bits())
            );
        }
        assert!(worst < 2.5e-7, "worst error {worst}");
        assert_eq!(sin_cos_turns(0.25f32), (1.0, -0.0));
        assert_eq!(sin_cos_turns(0.5f32), (-0.0, -1.0));
        assert_eq!(sin_cos_turns(0.75f32), (-1.0, 0.0));
        assert_eq!(sin_cos_turns(1.0f32), (0.0, 1.0));
    }

    /// Eight lanes give one lane's bits for each function.
    fn assert_lanes_agree(f: impl Fn(f32) -> f32, f8: impl Fn(f32x8) -> f32x8, xs: &[f32]) {
        for chunk in xs.chunks_exact(8) {
            let lanes = f8(f32x8::from(<[f32; 8]>::try_from(chunk).unwrap())).to_array();
            for (x, got) in chunk.iter().zip(lanes) {
                assert_eq!(got.to_bits(), f(*x).to_bits(), "at {x:e}");
            }
        }
    }

    /// ulps between an f32 and the f64 value rounded to f32.
    fn ulps(a: f32, b: f64) -> i64 {
        (i64::from(a.to_bits() as i32) - i64::from((b as f32).to_bits() as i32)).abs()
    }

    #[test]
    fn exp_is_within_two_ulps_and_the_same_in_lanes() {
        let xs: Vec<f32> = (0..=80_000).map(|i| -87.3 + 176.0 * i as f32 / 80_000.0).collect();
        for &x in &xs {
            let e = exp(x);
            assert!(ulps(e, (x as f64).exp()) <= 2, "exp {x}: {e} against {}", (x as f64).exp());
        }
        assert_eq!(exp(0.0f32), 1.0);
        assert_eq!((exp(-100.0f32), exp(100.0f32)), (0.0, f32::INFINITY));
        assert!(exp(88.7f32).is_finite());
        assert_lanes_agree(exp::<f32>, exp::<f32x8>, &xs[..80_000]);
    }

    #[test]
    fn ln_is_within_two_ulps_and_the_same_in_lanes() {
        let mut xs: Vec<f32> = (1..=80_000).map(|i| (i as f32 / 4_000.0).powi(3)).collect();
        xs.extend([1e-40, f32::MIN_POSITIVE, 1e-30, 0.5, 1.0, 2.0, 1e30, f32::MAX]);
        for &x in &xs {
            let l = ln(x);
            assert!(ulps(l, (x as f64).ln()) <= 2, "ln {x:e}: {l} against {}", (x as f64).ln());
        }
        assert_eq!(ln(1.0f32), 0.0);
        assert_eq!((ln(0.0f32), ln(f32::INFINITY)), (f32::NEG_INFINITY, f32::INFINITY));
        assert!(ln(-1.0f32).is_nan() && ln(f32::NAN).is_nan());
        assert_lanes_agree(ln::<f32>, ln::<f32x8>, &xs[..80_000]);
    }

    #[test]
    fn acos_is_within_three_ulps_and_the_same_in_lanes() {
        let xs: Vec<f32> = (0..=80_000).map(|i| -1.0 + 2.0 * i as f32 / 80_000.0).collect();
        for &x in &xs {
            let a = acos(x);
            assert!(ulps(a, (x as f64).acos()) <= 3, "acos {x}: {a} against {}", (x as f64).acos());
        }
        assert_eq!((acos(1.0f32), acos(0.0f32)), (0.0, std::f32::consts::FRAC_PI_2));
        assert_lanes_agree(acos::<f32>, acos::<f32x8>, &xs[..80_000]);
    }
    #[test]
    fn atan2_is_within_three_ulps_on_every_side_and_the_same_in_lanes() {
        use std::f32::consts::FRAC_PI_2;
        let mut pairs = Vec::new();
        for i in 0..4_000 {
            let angle = std::f32::consts::TAU * i as f32 / 4_000.0 - std::f32::consts::PI;
            for r in [1e-3f32, 0.7, 1.0, 250.0] {
                pairs.push((r * angle.sin(), r * angle.cos()));
            }
        }
        pairs.extend([(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0), (1e-30, 1.0), (1.0, 1e-30), (3.0, -1e-20)]);
        for &(y, x) in &pairs {
            let a = atan2(y, x);
            let exact = (y as f64).atan2(x as f64);
            assert!(ulps(a, exact) <= 3 || (a as f64 - exact).abs() < 1e-37, "atan2({y}, {x}): {a} against {exact}");
        }
        // The zeros and half turns of IEEE's atan2 along the x axis and at the origin.
        let bits = |y: f32, x: f32| atan2(y, x).to_bits();
        assert_eq!(bits(0.0, 1.0), 0f32.to_bits());
        assert_eq!(bits(-0.0, 1.0), (-0f32).to_bits());
        assert_eq!(bits(0.0, -1.0), std::f32::consts::PI.to_bits());
        assert_eq!(bits(-0.0, -1.0), (-std::f32::consts::PI).to_bits());
        assert_eq!((bits(0.0, 0.0), bits(-0.0, 0.0)), (0f32.to_bits(), (-0f32).to_bits()));
        assert_eq!(bits(0.0, -0.0), std::f32::consts::PI.to_bits());
        assert_eq!((bits(1.0, -0.0), bits(-1.0, -0.0)), (FRAC_PI_2.to_bits(), (-FRAC_PI_2).to_bits()));
        assert_eq!((bits(1.0, 0.0), bits(-1.0, 0.0)), (FRAC_PI_2.to_bits(), (-FRAC_PI_2).to_bits()));
        for chunk in pairs.chunks_exact(8) {
            let ys = f32x8::from(std::array::from_fn::<f32, 8, _>(|k| chunk[k].0));
            let xs = f32x8::from(std::array::from_fn::<f32, 8, _>(|k| chunk[k].1));
            let lanes = atan2(ys, xs).to_array();
            for (k, &(y, x)) in chunk.iter().enumerate() {
                assert_eq!(lanes[k].to_bits(), atan2(y, x).to_bits(), "atan2({y}, {x})");
            }
        }
    }
}
