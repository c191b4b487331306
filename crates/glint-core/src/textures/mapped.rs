//! Texture coordinates made from the hit point instead of the surface's uv: pbrt's
//! spherical, cylindrical and planar mappings, each in a texture space placed in the world
//! (pbrt's: the transform in force where the texture is made). The coordinates are then the
//! 2D texture's uv, its own uv map applied as at any uv.

use glam::{Affine3A, Vec2, Vec3};

use super::{Texture, TextureQuery};
use crate::Rgb;

/// How a point of texture space becomes coordinates (s, t).
#[derive(Clone, Debug, PartialEq)]
pub enum Projection {
    /// s = θ / π from +z, t = φ / 2π about +z from +x, φ in [0, 2π).
    Spherical,
    /// s = (π + atan2(y, x)) / 2π about +z, t = z.
    Cylindrical,
    /// s = s_offset + p · s_axis, t = t_offset + p · t_axis.
    Planar { s_axis: Vec3, t_axis: Vec3, s_offset: f32, t_offset: f32 },
}

/// A 2D texture read at the coordinates its projection makes of the point.
#[derive(Clone, Debug, PartialEq)]
pub struct Mapped {
    /// World space → texture space.
    pub to_texture: Affine3A,
    pub projection: Projection,
    pub texture: Texture,
}

impl Mapped {
    /// The coordinates of the world point `point`.
    pub fn coordinates(&self, point: Vec3) -> Vec2 {
        let p = self.to_texture.transform_point3(point);
        match self.projection {
            Projection::Spherical => {
                let d = p.normalize_or_zero();
                let theta = d.z.clamp(-1.0, 1.0).acos();
                let phi = d.y.atan2(d.x);
                let phi = if phi < 0.0 { phi + std::f32::consts::TAU } else { phi };
                Vec2::new(theta * std::f32::consts::FRAC_1_PI, phi / std::f32::consts::TAU)
            }
            Projection::Cylindrical => Vec2::new((std::f32::consts::PI + p.y.atan2(p.x)) / std::f32::consts::TAU, p.z),
            Projection::Planar { s_axis, t_axis, s_offset, t_offset } => {
                Vec2::new(s_offset + p.dot(s_axis), t_offset + p.dot(t_axis))
            }
        }
    }

    pub fn evaluate(&self, query: &TextureQuery) -> Rgb {
        self.texture.evaluate(&TextureQuery { uv: self.coordinates(query.world_point), ..*query })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mapped(projection: Projection, to_texture: Affine3A) -> Mapped {
        Mapped { to_texture, projection, texture: Texture::Constant(Rgb::ONE) }
    }

    /// Each projection by hand, through a texture space moved by 5 along x and scaled by 2
    /// (world → texture: x' = (x − 5) / 2).
    #[test]
    fn projections_by_hand() {
        let to_texture = Affine3A::from_scale(Vec3::splat(0.5)) * Affine3A::from_translation(Vec3::new(-5.0, 0.0, 0.0));
        let close = |a: Vec2, b: Vec2| (a - b).abs().max_element() < 1e-6;
        let sphere = mapped(Projection::Spherical, to_texture);
        // +z: θ = 0; +x: θ = π/2, φ = 0; +y: φ = π/2; −y: φ = 3π/2.
        assert!(close(sphere.coordinates(Vec3::new(5.0, 0.0, 3.0)), Vec2::new(0.0, 0.0)));
        assert!(close(sphere.coordinates(Vec3::new(7.0, 0.0, 0.0)), Vec2::new(0.5, 0.0)));
        assert!(close(sphere.coordinates(Vec3::new(5.0, 4.0, 0.0)), Vec2::new(0.5, 0.25)));
        assert!(close(sphere.coordinates(Vec3::new(5.0, -4.0, 0.0)), Vec2::new(0.5, 0.75)));
        assert!(close(sphere.coordinates(Vec3::new(5.0, 0.0, -1.0)), Vec2::new(1.0, 0.0)));
        let cylinder = mapped(Projection::Cylindrical, to_texture);
        // atan2 of +x is 0: s = ½; of +y, π/2: s = ¾; t is the texture space's z.
        assert!(close(cylinder.coordinates(Vec3::new(7.0, 0.0, 6.0)), Vec2::new(0.5, 3.0)));
        assert!(close(cylinder.coordinates(Vec3::new(5.0, 2.0, -2.0)), Vec2::new(0.75, -1.0)));
        let plane =
            Projection::Planar { s_axis: Vec3::X, t_axis: Vec3::new(0.0, 1.0, 1.0), s_offset: 0.25, t_offset: -1.0 };
        let plane = mapped(plane, to_texture);
        // p' = (1, 2, 3): s = 0.25 + 1, t = −1 + 5.
        assert!(close(plane.coordinates(Vec3::new(7.0, 4.0, 6.0)), Vec2::new(1.25, 4.0)));
    }

    /// The texture inside is read at the mapped coordinates, whatever uv the surface has.
    #[test]
    fn the_inner_texture_reads_the_mapped_coordinates() {
        let checker = super::super::Checker {
            even: Rgb::ZERO,
            odd: Rgb::ONE,
            uv_transform: glam::Affine2::from_scale(Vec2::splat(2.0)),
        };
        let planar = Projection::Planar { s_axis: Vec3::X, t_axis: Vec3::Y, s_offset: 0.0, t_offset: 0.0 };
        let m = Mapped {
            to_texture: Affine3A::IDENTITY,
            projection: planar,
            texture: Texture::Checker(Box::new(checker.clone())),
        };
        for (x, y) in [(0.1f32, 0.1f32), (0.6, 0.1), (0.3, 0.8), (0.9, 0.9)] {
            let query =
                TextureQuery { uv: Vec2::new(0.77, 0.33), world_point: Vec3::new(x, y, 4.0), ..Default::default() };
            assert_eq!(m.evaluate(&query), checker.evaluate(Vec2::new(x, y)), "({x}, {y})");
        }
    }
}
