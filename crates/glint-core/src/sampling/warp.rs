//! Warps from the unit square to the domains rendering samples: each with its pdf and its
//! inverse (round-trip tests check one against the other, as pbrt-v4 and Mitsuba 3 do).
//! Directions are in the local shading frame, where cos θ = z.

use std::f32::consts::{FRAC_1_PI, FRAC_PI_2, FRAC_PI_4, PI};

use glam::{Vec2, Vec3};

/// Shirley–Chiu concentric map of [0,1)² onto the unit disk (area-preserving, low distortion).
pub fn square_to_disk(u: Vec2) -> Vec2 {
    let p = 2.0 * u - Vec2::ONE;
    if p == Vec2::ZERO {
        return Vec2::ZERO;
    }
    let (r, theta) =
        if p.x.abs() > p.y.abs() { (p.x, FRAC_PI_4 * (p.y / p.x)) } else { (p.y, FRAC_PI_2 - FRAC_PI_4 * (p.x / p.y)) };
    r * Vec2::new(theta.cos(), theta.sin())
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
    let d = square_to_disk(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

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
}
