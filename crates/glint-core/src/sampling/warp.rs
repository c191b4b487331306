//! Warps from the unit square to the domains rendering samples: each with its pdf and its
//! inverse (round-trip tests check one against the other, as pbrt-v4 and Mitsuba 3 do).
//! Directions are in the local shading frame, where cos θ = z.

use std::f32::consts::{FRAC_1_PI, FRAC_PI_2, FRAC_PI_4, PI};

use crate::lanes::{sin_cos_quarter, LaneVec3, Lanes};
use glam::{Vec2, Vec3};

/// Shirley–Chiu concentric map of [0,1)² onto the unit disk (area-preserving, low distortion).
pub fn square_to_disk(u: Vec2) -> Vec2 {
    let (x, y) = square_to_disk_lanes(u.x, u.y);
    Vec2::new(x, y)
}

/// `square_to_disk` in lanes.
#[inline(always)]
fn square_to_disk_lanes<L: Lanes>(u: L, v: L) -> (L, L) {
    let two = L::splat(2.0);
    let (px, py) = (two * u - L::ONE, two * v - L::ONE);
    // θ = φ in the left and right quadrants, π/2 − φ in the others, with |φ| ≤ π/4; there
    // cos θ = sin φ and sin θ = cos φ. Selects, not branches: which quadrant is random.
    let sideways = px.abs().gt(py.abs());
    let (r, q) = (L::select(sideways, px, py), L::select(sideways, py, px));
    let (sin, cos) = sin_cos_quarter(L::splat(FRAC_PI_4) * (q / r));
    let (x, y) = (L::select(sideways, cos, sin), L::select(sideways, sin, cos));
    // |r| = max(|x|, |y|) is 0 at the centre.
    let centre = r.eq(L::ZERO);
    (L::select(centre, L::ZERO, r * x), L::select(centre, L::ZERO, r * y))
}

pub fn disk_to_square(d: Vec2) -> Vec2 {
    let r = d.length();
    let mut phi = d.y.atan2(d.x);
    if phi < -FRAC_PI_4 {
        phi += 2.0 * PI;
    }
    let (a, b) = if phi < FRAC_PI_4 {
        (r, phi * r / FRAC_PI_4)
    } else if phi < 3.0 * FRAC_PI_4 {
        (-(phi - FRAC_PI_2) * r / FRAC_PI_4, r)
    } else if phi < 5.0 * FRAC_PI_4 {
        (-r, -(phi - PI) * r / FRAC_PI_4)
    } else {
        ((phi - 3.0 * FRAC_PI_2) * r / FRAC_PI_4, -r)
    };
    0.5 * (Vec2::new(a, b) + Vec2::ONE)
}

/// Cosine-weighted hemisphere (Malley's method: project the disk up).
pub fn square_to_cosine_hemisphere(u: Vec2) -> Vec3 {
    square_to_cosine_hemisphere_lanes(u.x, u.y).into()
}

/// `square_to_cosine_hemisphere` in lanes: Shirley and Chiu's concentric disk, lifted.
#[inline(always)]
pub(crate) fn square_to_cosine_hemisphere_lanes<L: Lanes>(u: L, v: L) -> LaneVec3<L> {
    let (x, y) = square_to_disk_lanes(u, v);
    let z = (L::ONE - (x * x + y * y)).max(L::ZERO).sqrt();
    LaneVec3::new(x, y, z)
}

pub fn cosine_hemisphere_pdf(w: Vec3) -> f32 {
    if w.z > 0.0 {
        w.z * FRAC_1_PI
    } else {
        0.0
    }
}

pub fn cosine_hemisphere_to_square(w: Vec3) -> Vec2 {
    disk_to_square(Vec2::new(w.x, w.y))
}

/// Uniform over the unit sphere.
pub fn square_to_uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

pub const UNIFORM_SPHERE_PDF: f32 = 1.0 / (4.0 * PI);

pub fn uniform_sphere_to_square(w: Vec3) -> Vec2 {
    let phi = w.y.atan2(w.x).rem_euclid(2.0 * PI);
    Vec2::new(0.5 * (1.0 - w.z), phi / (2.0 * PI))
}

/// Uniform barycentrics (b1, b2) over a triangle (the square-root warp).
pub fn square_to_triangle(u: Vec2) -> Vec2 {
    let s = u.x.sqrt();
    Vec2::new(1.0 - s, u.y * s)
}

pub fn triangle_to_square(b: Vec2) -> Vec2 {
    let s = 1.0 - b.x;
    Vec2::new(s * s, if s > 0.0 { b.y / s } else { 0.0 })
}

/// x in [0, 1) with density proportional to the line from `a` at 0 to `b` at 1 (a, b ≥ 0):
/// the inverse of F(x) = x (2a + (b − a) x) / (a + b), in the form that does not cancel when
/// a ≈ b.
fn square_to_linear(u: f32, a: f32, b: f32) -> f32 {
    if a + b == 0.0 {
        return u;
    }
    if u == 0.0 {
        return 0.0; // with a = 0 the formula below is 0 / 0
    }
    let x = u * (a + b) / (a + ((1.0 - u) * a * a + u * b * b).sqrt());
    x.min(ONE_BELOW)
}

fn linear_to_square(x: f32, a: f32, b: f32) -> f32 {
    if a + b == 0.0 {
        return x;
    }
    x * (a * (2.0 - x) + b * x) / (a + b)
}

const ONE_BELOW: f32 = 1.0 - f32::EPSILON / 2.0;

/// A point of the unit square with density proportional to the bilinear interpolation of the
/// corner values `w` = [w(0,0), w(1,0), w(0,1), w(1,1)] (all ≥ 0): y from its marginal, then x
/// given y. Used to fold a receiver's cos θ into solid-angle light sampling.
pub fn square_to_bilinear(u: Vec2, w: [f32; 4]) -> Vec2 {
    let y = square_to_linear(u.y, w[0] + w[1], w[2] + w[3]);
    let x = square_to_linear(u.x, w[0] + (w[2] - w[0]) * y, w[1] + (w[3] - w[1]) * y);
    Vec2::new(x, y)
}

pub fn bilinear_pdf(p: Vec2, w: [f32; 4]) -> f32 {
    let sum = w[0] + w[1] + w[2] + w[3];
    if sum == 0.0 {
        return 1.0;
    }
    let (x, y) = (p.x, p.y);
    4.0 * ((1.0 - x) * (1.0 - y) * w[0] + x * (1.0 - y) * w[1] + (1.0 - x) * y * w[2] + x * y * w[3]) / sum
}

pub fn bilinear_to_square(p: Vec2, w: [f32; 4]) -> Vec2 {
    let x = linear_to_square(p.x, w[0] + (w[2] - w[0]) * p.y, w[1] + (w[3] - w[1]) * p.y);
    Vec2::new(x, linear_to_square(p.y, w[0] + w[1], w[2] + w[3]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lanes::testing::{assert_lanes_equal, random_floats};
    use crate::lanes::LANES;
    use crate::sampling::Rng;

    /// The bilinear warp against its pdf: a 2D histogram (chi-square over 10 × 10 cells, the
    /// pdf integrated exactly: it is bilinear), and the round trip through its inverse.
    #[test]
    fn bilinear_sampling_matches_its_pdf_and_round_trips() {
        for w in [[1.0, 1.0, 1.0, 1.0], [0.2, 1.0, 0.5, 0.05], [0.0, 0.0, 1.0, 3.0], [0.01, 0.9, 0.9, 0.01]] {
            let n = 200_000;
            let mut counts = [[0f64; 10]; 10];
            let mut rng = Rng::new(7, 3);
            for _ in 0..n {
                let u = Vec2::new(rng.next_f32(), rng.next_f32());
                let p = square_to_bilinear(u, w);
                assert!((0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y));
                counts[(p.y * 10.0) as usize][(p.x * 10.0) as usize] += 1.0;
                let back = bilinear_to_square(p, w);
                assert!((back - u).abs().max_element() < 1e-3, "{w:?}: {u} -> {p} -> {back}");
            }
            let mut chi2 = 0.0;
            for (j, row) in counts.iter().enumerate() {
                for (i, &observed) in row.iter().enumerate() {
                    // The midpoint rule is exact for a bilinear function over a cell.
                    let centre = Vec2::new((i as f32 + 0.5) / 10.0, (j as f32 + 0.5) / 10.0);
                    let expected = bilinear_pdf(centre, w) as f64 / 100.0 * n as f64;
                    if expected > 0.0 {
                        chi2 += (observed - expected).powi(2) / expected;
                    }
                }
            }
            // 99 degrees of freedom: P(χ² > 148) ≈ 0.001.
            assert!(chi2 < 148.0, "{w:?}: χ² = {chi2}");
            // The square's corner maps to the corner, zero weights or not.
            assert_eq!(square_to_bilinear(Vec2::ZERO, w), Vec2::ZERO, "{w:?}");
        }
    }

    fn squares() -> impl Iterator<Item = Vec2> {
        let mut rng = Rng::new(5, 9);
        (0..20_000).map(move |_| Vec2::new(rng.next_f32(), rng.next_f32()))
    }

    #[test]
    fn round_trips() {
        for u in squares() {
            let back = disk_to_square(square_to_disk(u));
            assert!((back - u).length() < 1e-4, "disk {u} -> {back}");
            let w = square_to_cosine_hemisphere(u);
            assert!((w.length() - 1.0).abs() < 1e-4 && w.z >= 0.0);
            assert!((cosine_hemisphere_to_square(w) - u).length() < 1e-3, "cosine {u}");
            let s = square_to_uniform_sphere(u);
            assert!((uniform_sphere_to_square(s) - u).length() < 1e-3, "sphere {u}");
            let b = square_to_triangle(u);
            assert!(b.x >= 0.0 && b.y >= 0.0 && b.x + b.y <= 1.0 + 1e-6);
            assert!((triangle_to_square(b) - u).length() < 1e-3, "triangle {u}");
        }
    }

    /// The cosine pdf integrates to 1 over the hemisphere (midpoint rule in θ, φ).
    #[test]
    fn cosine_pdf_integrates_to_one() {
        let (nt, np) = (400, 400);
        let mut sum = 0.0f64;
        for i in 0..nt {
            let theta = (i as f32 + 0.5) / nt as f32 * FRAC_PI_2;
            for j in 0..np {
                let phi = (j as f32 + 0.5) / np as f32 * 2.0 * PI;
                let w = Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
                sum += (cosine_hemisphere_pdf(w) * theta.sin()) as f64;
            }
        }
        sum *= (FRAC_PI_2 / nt as f32 * 2.0 * PI / np as f32) as f64;
        assert!((sum - 1.0).abs() < 1e-3, "{sum}");
    }

    /// Eight lanes compute one lane's bits, at random and at the disk's centre and
    /// the diagonals where the quadrant choice flips.
    #[test]
    fn square_to_cosine_hemisphere_in_eight_lanes_equals_one_lane() {
        let check = |u: [f32; LANES], v: [f32; LANES], what: &str| {
            let scalar = std::array::from_fn(|k| square_to_cosine_hemisphere(Vec2::new(u[k], v[k])));
            assert_lanes_equal(
                square_to_cosine_hemisphere_lanes(wide::f32x8::from(u), wide::f32x8::from(v)),
                scalar,
                what,
            );
        };
        let mut rng = Rng::new(11, 5);
        for _ in 0..2_000 {
            check(random_floats(&mut rng, 1.0), random_floats(&mut rng, 1.0), "cosine hemisphere");
        }
        check(
            [0.5, 0.5, 0.0, 1.0, 0.25, 0.75, 0.5, 0.0],
            [0.5, 0.0, 0.0, 1.0, 0.25, 0.25, 1.0, 1.0],
            "centre, diagonals",
        );
    }
}
