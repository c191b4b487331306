//! pbrt-v4's procedural textures: the solid ones from noise (`fbm`, `wrinkled`, `windy`,
//! `marble`), read at the hit point in a texture space placed in the world (pbrt's: the
//! transform in force where the texture is made), and the 2D ones at uv (`dots`, `bilerp`).
//! Each is pbrt's formula; the noise sums every octave (see `noise`).

use glam::{Affine2, Affine3A, Vec2, Vec3};

use super::noise::{fbm, octave_weights, perlin_noise, turbulence};
use super::TextureQuery;
use crate::Rgb;

/// A solid pattern from noise.
#[derive(Clone, Debug, PartialEq)]
pub enum NoisePattern {
    /// Fractional Brownian motion, Σ ωⁱ noise(1.99ⁱ p) (pbrt's `fbm`; ω its `roughness`).
    Fbm { omega: f32, octaves: u32 },
    /// Turbulence, Σ ωⁱ |noise(1.99ⁱ p)| (pbrt's `wrinkled`).
    Wrinkled { omega: f32, octaves: u32 },
    /// Waves whose height is fbm(p) over six octaves, scaled by the wind's strength, |fbm|
    /// of the point at a tenth of the scale over three (pbrt's `windy`).
    Windy,
    /// Layers along y bent by fbm: t = ½ + ½ sin(y + variation · fbm(p)) at p scaled by
    /// `scale`, through pbrt's spline of nine greys and a blue-grey, times 1.5 (pbrt's
    /// `marble`).
    Marble { omega: f32, octaves: u32, scale: f32, variation: f32 },
}

/// The control points of pbrt's marble: a cubic Bézier per segment of four.
const MARBLE_COLOURS: [[f32; 3]; 9] = [
    [0.58, 0.58, 0.6],
    [0.58, 0.58, 0.6],
    [0.58, 0.58, 0.6],
    [0.5, 0.5, 0.5],
    [0.6, 0.59, 0.58],
    [0.58, 0.58, 0.6],
    [0.58, 0.58, 0.6],
    [0.2, 0.2, 0.33],
    [0.58, 0.58, 0.6],
];

/// A noise pattern in a texture space of its own.
#[derive(Clone, Debug, PartialEq)]
pub struct Noise {
    /// World space → texture space.
    pub to_texture: Affine3A,
    pub pattern: NoisePattern,
}

impl Noise {
    pub fn evaluate(&self, query: &TextureQuery) -> Rgb {
        let p = self.to_texture.transform_point3(query.world_point);
        match self.pattern {
            NoisePattern::Fbm { omega, octaves } => Rgb::splat(fbm(p, omega, octaves)),
            NoisePattern::Wrinkled { omega, octaves } => Rgb::splat(turbulence(p, omega, octaves)),
            NoisePattern::Windy => Rgb::splat(fbm(0.1 * p, 0.5, 3).abs() * fbm(p, 0.5, 6)),
            NoisePattern::Marble { omega, octaves, scale, variation } => marble(p * scale, omega, octaves, variation),
        }
    }

    /// The largest value each channel can take.
    pub fn max_value(&self) -> Rgb {
        Rgb::splat(match self.pattern {
            NoisePattern::Fbm { omega, octaves } => octave_weights(omega, octaves),
            NoisePattern::Wrinkled { omega, octaves } => {
                octave_weights(omega, octaves) + 0.2 * omega.abs().powi(octaves as i32)
            }
            NoisePattern::Windy => octave_weights(0.5, 3) * octave_weights(0.5, 6),
            NoisePattern::Marble { .. } => 1.5 * 0.6,
        })
    }
}

fn marble(p: Vec3, omega: f32, octaves: u32, variation: f32) -> Rgb {
    let t = 0.5 + 0.5 * (p.y + variation * fbm(p, omega, octaves)).sin();
    let segments = MARBLE_COLOURS.len() - 3;
    let first = ((t * segments as f32).floor() as usize).min(segments - 1);
    let t = t * segments as f32 - first as f32;
    let [c0, c1, c2, c3] = [0, 1, 2, 3].map(|k| Rgb::from(MARBLE_COLOURS[first + k]));
    let s = 1.0 - t;
    1.5 * (s * s * s * c0 + 3.0 * s * s * t * c1 + 3.0 * s * t * t * c2 + t * t * t * c3)
}

/// pbrt's polka dots at uv: in each unit cell around an integer point, where the noise there
/// is positive, a dot of radius 0.35 shifted by noise up to 0.15 from the cell's centre.
#[derive(Clone, Debug, PartialEq)]
pub struct Dots {
    pub inside: Rgb,
    pub outside: Rgb,
    /// uv → (s, t).
    pub uv_transform: Affine2,
}

impl Dots {
    pub fn evaluate(&self, uv: Vec2) -> Rgb {
        if inside_dot(self.uv_transform.transform_point2(uv)) {
            self.inside
        } else {
            self.outside
        }
    }
}

fn inside_dot(st: Vec2) -> bool {
    let cell = (st + Vec2::splat(0.5)).floor();
    // pbrt's two-argument noise: z = ½.
    let noise = |ds: f32, dt: f32| perlin_noise(Vec3::new(cell.x + ds, cell.y + dt, 0.5));
    if noise(0.5, 0.5) <= 0.0 {
        return false;
    }
    let radius = 0.35;
    let shift = 0.5 - radius;
    let centre = cell + shift * Vec2::new(noise(1.5, 2.8), noise(4.5, 9.8));
    (st - centre).length_squared() < radius * radius
}

/// pbrt's `bilerp`: the bilinear blend of four values at the corners of the unit square of
/// (s, t) (and its extrapolation beyond).
#[derive(Clone, Debug, PartialEq)]
pub struct Bilerp {
    /// At (s, t) = (0, 0), (0, 1), (1, 0), (1, 1).
    pub v00: Rgb,
    pub v01: Rgb,
    pub v10: Rgb,
    pub v11: Rgb,
    /// uv → (s, t).
    pub uv_transform: Affine2,
}

impl Bilerp {
    pub fn evaluate(&self, uv: Vec2) -> Rgb {
        let Vec2 { x: s, y: t } = self.uv_transform.transform_point2(uv);
        (1.0 - s) * (1.0 - t) * self.v00 + s * (1.0 - t) * self.v10 + (1.0 - s) * t * self.v01 + s * t * self.v11
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(point: Vec3) -> TextureQuery<'static> {
        TextureQuery { world_point: point, ..Default::default() }
    }

    /// Windy and wrinkled by their formulas over the noise; the texture space's transform
    /// applied first (world → texture: x' = (x − 5) / 2).
    #[test]
    fn solid_patterns_by_their_formulas() {
        let to_texture = Affine3A::from_scale(Vec3::splat(0.5)) * Affine3A::from_translation(Vec3::new(-5.0, 0.0, 0.0));
        let world = Vec3::new(6.3, 0.7, -2.2);
        let p = Vec3::new(0.65, 0.35, -1.1);
        let noise = |pattern| Noise { to_texture, pattern }.evaluate(&at(world)).x;
        let close = |a: f32, b: f32| (a - b).abs() < 1e-5;
        let mut sum = 0.0;
        for i in 0..6 {
            sum += 0.5f32.powi(i) * perlin_noise(1.99f32.powi(i) * p);
        }
        let strength = perlin_noise(0.1 * p) + 0.5 * perlin_noise(0.199 * p) + 0.25 * perlin_noise(0.39601 * p);
        assert!(close(noise(NoisePattern::Windy), strength.abs() * sum), "windy");
        let wrinkled = (0..4).map(|i| 0.7f32.powi(i) * perlin_noise(1.99f32.powi(i) * p).abs()).sum::<f32>();
        assert!(close(noise(NoisePattern::Wrinkled { omega: 0.7, octaves: 4 }), wrinkled + 0.2 * 0.7f32.powi(4)));
    }

    /// With no variation, marble is the spline at t = ½ + ½ sin(y), over six segments: at
    /// y = 0, t = ½, the start of the fourth (its first control point, c3); at y = π/6,
    /// t = ¾, the middle of the fifth, (c4 + 3c5 + 3c6 + c7) / 8; each times 1.5.
    #[test]
    fn marble_follows_its_spline() {
        let m = Noise {
            to_texture: Affine3A::IDENTITY,
            pattern: NoisePattern::Marble { omega: 0.5, octaves: 8, scale: 1.0, variation: 0.0 },
        };
        let c = MARBLE_COLOURS.map(Rgb::from);
        let close = |a: Rgb, b: Rgb| (a - b).abs().max_element() < 1e-5;
        assert!(close(m.evaluate(&at(Vec3::new(0.3, 0.0, 0.9))), 1.5 * c[3]));
        let middle = 1.5 * (c[4] + 3.0 * c[5] + 3.0 * c[6] + c[7]) / 8.0;
        assert!(close(m.evaluate(&at(Vec3::new(0.0, std::f32::consts::FRAC_PI_6, 0.0))), middle));
        // At t = 1 (y = π/2) the last segment's end: its last control point.
        let end = m.evaluate(&at(Vec3::new(0.0, std::f32::consts::FRAC_PI_2, 0.0)));
        assert!((end - 1.5 * c[8]).abs().max_element() < 1e-5, "{end}");
        assert!(end.max_element() <= m.max_value().x);
    }

    /// Dots lie only in cells whose noise is positive, within 0.35 of a centre at most 0.15
    /// off the cell's; about half the cells have one, each covering π · 0.35² ≈ 0.385.
    #[test]
    fn dots_sit_in_their_cells() {
        let dots = Dots { inside: Rgb::ONE, outside: Rgb::ZERO, uv_transform: Affine2::IDENTITY };
        let n = 200;
        let mut covered = 0usize;
        for i in 0..n {
            for j in 0..n {
                let st = Vec2::new(i as f32 + 0.5, j as f32 + 0.5) * 0.1 - Vec2::splat(5.0);
                let inside = dots.evaluate(st).x == 1.0;
                let cell = (st + Vec2::splat(0.5)).floor();
                if inside {
                    assert!(perlin_noise(Vec3::new(cell.x + 0.5, cell.y + 0.5, 0.5)) > 0.0);
                    assert!((st - cell).length() < 0.35 + 0.15 * 2f32.sqrt() + 1e-6);
                }
                covered += usize::from(inside);
            }
        }
        let fraction = covered as f64 / (n * n) as f64;
        assert!(fraction > 0.05 && fraction < 0.385, "dots cover {fraction}");
    }

    /// Bilerp by hand: the corners, the centre (their mean), and a uv map applied first.
    #[test]
    fn bilerp_by_hand() {
        let b = Bilerp {
            v00: Rgb::splat(0.0),
            v01: Rgb::splat(1.0),
            v10: Rgb::splat(2.0),
            v11: Rgb::splat(4.0),
            uv_transform: Affine2::IDENTITY,
        };
        assert_eq!(b.evaluate(Vec2::new(0.0, 1.0)).x, 1.0);
        assert_eq!(b.evaluate(Vec2::new(1.0, 0.0)).x, 2.0);
        assert_eq!(b.evaluate(Vec2::new(0.5, 0.5)).x, 1.75);
        let scaled = Bilerp { uv_transform: Affine2::from_scale(Vec2::splat(2.0)), ..b };
        assert_eq!(scaled.evaluate(Vec2::new(0.25, 0.25)).x, 1.75);
    }

    /// A bump map's slope of a procedural texture, by finite differences: a bilerp's is its
    /// analytic derivative in uv; a noise texture's follows the point along ∂p/∂u (twice as
    /// long a ∂p/∂u, twice the slope, by the chain rule).
    #[test]
    fn slopes_by_finite_differences() {
        use crate::textures::{luminance, Texture};
        let grey = |v: f32| Rgb::splat(v);
        let b = Texture::Bilerp(Box::new(Bilerp {
            v00: grey(0.0),
            v01: grey(1.0),
            v10: grey(2.0),
            v11: grey(4.0),
            uv_transform: Affine2::IDENTITY,
        }));
        let query = |uv: Vec2, dpdu: Vec3| TextureQuery {
            uv,
            world_point: Vec3::new(0.3, 1.7, -0.4),
            dpdu,
            dpdv: Vec3::Y,
            ..Default::default()
        };
        let (u, v) = (0.3, 0.6);
        let slope = b.luminance_gradient(&query(Vec2::new(u, v), Vec3::X));
        let l = luminance(Rgb::ONE);
        let (du, dv) = (((1.0 - v) * 2.0 + v * 3.0) * l, ((1.0 - u) * 1.0 + u * 2.0) * l);
        assert!((slope - Vec2::new(du, dv)).abs().max_element() < 2e-3, "{slope} against ({du}, {dv})");
        let n = Texture::Noise(Box::new(Noise {
            to_texture: Affine3A::IDENTITY,
            pattern: NoisePattern::Fbm { omega: 0.5, octaves: 3 },
        }));
        let one = n.luminance_gradient(&query(Vec2::ZERO, Vec3::X)).x;
        let two = n.luminance_gradient(&query(Vec2::ZERO, 2.0 * Vec3::X)).x;
        assert!(one.abs() > 1e-3 && (two - 2.0 * one).abs() < 0.02 * one.abs().max(0.1), "{one} {two}");
    }
}
