//! Checkerboards: in uv (2D) and in space (3D, a solid texture).
//!
//! Scene parameters (`[textures.NAME]`):
//! - `type = "checker"`: `even`, `odd` (colours), `scale` (checks per unit of u and v, a
//!   number or [su, sv], default 8), `uv_transform` (an affine map of uv after the scale, two
//!   rows [a, b, c]: u' = a·u + b·v + c; the checks are unit squares of the result);
//! - `type = "solid-checker"`: `even`, `odd`, `scale` (cubes per scene unit, default 1).
//!
//! A cell (i, j) (or (i, j, k)) with an even sum of indices takes `even`.

use glam::{Affine2, Vec2, Vec3};

use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct Checker {
    pub even: Rgb,
    pub odd: Rgb,
    /// The surface's uv to the checks' (a unit square each).
    pub uv_transform: Affine2,
}

impl Checker {
    /// `scale` checks per unit of u and v.
    pub fn new(even: Rgb, odd: Rgb, scale: Vec2) -> Self {
        Self { even, odd, uv_transform: Affine2::from_scale(scale) }
    }

    pub fn evaluate(&self, uv: Vec2) -> Rgb {
        let cell = self.uv_transform.transform_point2(uv).floor();
        if (cell.x + cell.y).rem_euclid(2.0) < 1.0 {
            self.even
        } else {
            self.odd
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct SolidChecker {
    pub even: Rgb,
    pub odd: Rgb,
    pub scale: f32,
}

impl SolidChecker {
    pub fn evaluate(&self, p: Vec3) -> Rgb {
        let cell = (p * self.scale).floor();
        if (cell.x + cell.y + cell.z).rem_euclid(2.0) < 1.0 {
            self.even
        } else {
            self.odd
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_alternate() {
        let c = Checker::new(Rgb::ONE, Rgb::ZERO, Vec2::splat(2.0));
        assert_eq!(c.evaluate(Vec2::new(0.1, 0.1)), Rgb::ONE);
        assert_eq!(c.evaluate(Vec2::new(0.6, 0.1)), Rgb::ZERO);
        assert_eq!(c.evaluate(Vec2::new(0.6, 0.6)), Rgb::ONE);
        assert_eq!(c.evaluate(Vec2::new(-0.1, 0.1)), Rgb::ZERO); // negative cells continue the pattern
                                                                 // Shifted by half a check in u: the first check runs from u = −¼ to ¼.
        let shifted = Checker { uv_transform: Affine2::from_translation(Vec2::new(0.5, 0.0)) * c.uv_transform, ..c };
        assert_eq!(shifted.evaluate(Vec2::new(0.3, 0.1)), Rgb::ZERO);
        assert_eq!(shifted.evaluate(Vec2::new(-0.1, 0.1)), Rgb::ONE);
        let s = SolidChecker { even: Rgb::ONE, odd: Rgb::ZERO, scale: 1.0 };
        assert_eq!(s.evaluate(Vec3::new(0.5, 0.5, 0.5)), Rgb::ONE);
        assert_eq!(s.evaluate(Vec3::new(1.5, 0.5, 0.5)), Rgb::ZERO);
        assert_eq!(s.evaluate(Vec3::new(1.5, 1.5, -0.5)), Rgb::ZERO);
    }
}
