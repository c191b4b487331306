//! Textures: colours that vary over a surface. 2D textures read the hit's uv; solid (3D)
//! textures read the hit point in the object's own space, so they move with the object.
//! Any colour parameter of a material can be a texture.

mod attribute;
mod checker;
mod image;
mod mapped;
mod mix;
mod noise;
mod procedural;
mod solid;

pub use attribute::AttributeTexture;
pub use checker::{Checker, SolidChecker};
pub use image::{ImageTexture, TexelFilter, Wrap};
pub use mapped::{Mapped, Projection};
pub use mix::{fraction, DirectionMix, Mix, Product};
pub use noise::{fbm, perlin_noise, turbulence};
pub use procedural::{Bilerp, Dots, Noise, NoisePattern};
pub use solid::{Marble, Wood};

use std::sync::Arc;

use glam::{Vec2, Vec3};

use crate::shapes::Mesh;
use crate::Rgb;

/// Where a texture is looked up.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TextureQuery<'a> {
    pub uv: Vec2,
    /// The hit point in object space (world space for shapes without a transform).
    pub point: Vec3,
    /// The hit point in world space, for textures mapped from a space of their own.
    pub world_point: Vec3,
    /// The surface's geometric normal in world space (zero if unknown), for textures that
    /// depend on which way the surface faces (pbrt's `directionmix`).
    pub normal: Vec3,
    /// The surface's ∂p/∂u in world space (zero if unknown): the tangent anisotropic
    /// materials align with.
    pub dpdu: Vec3,
    /// The surface's ∂p/∂v in world space (zero if unknown): with ∂p/∂u, what a bump map
    /// tilts.
    pub dpdv: Vec3,
    /// The point on a mesh with attributes, for `AttributeTexture` (none elsewhere).
    pub mesh: Option<MeshPoint<'a>>,
}

/// A point on a mesh's triangle, in the space of the mesh's vertices (its barycentric
/// coordinates are found only by the textures that read attributes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshPoint<'a> {
    pub mesh: &'a Mesh,
    pub triangle: u32,
    pub point: Vec3,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Texture {
    Constant(Rgb),
    /// Boxed: its uv map would make every texture (a material holds several) larger.
    Checker(Box<Checker>),
    SolidChecker(SolidChecker),
    Image(Arc<ImageTexture>),
    Marble(Marble),
    Wood(Wood),
    /// Boxed: its name would make every texture larger.
    Attribute(Box<AttributeTexture>),
    /// A texture read at coordinates made from the point (pbrt's spherical, cylindrical and
    /// planar mappings).
    Mapped(Box<Mapped>),
    Mix(Box<Mix>),
    Product(Box<Product>),
    DirectionMix(Box<DirectionMix>),
    /// pbrt's solid textures from noise. Boxed: its transform would make every texture larger.
    Noise(Box<Noise>),
    Dots(Box<Dots>),
    Bilerp(Box<Bilerp>),
}

impl Texture {
    /// The constant case inline (every material without a texture, five times a hit), the
    /// others a call each.
    #[inline(always)]
    pub fn evaluate(&self, query: &TextureQuery) -> Rgb {
        match self {
            Texture::Constant(c) => *c,
            _ => self.evaluate_varying(query),
        }
    }

    #[inline(never)]
    fn evaluate_varying(&self, query: &TextureQuery) -> Rgb {
        match self {
            Texture::Constant(c) => *c,
            Texture::Checker(t) => t.evaluate(query.uv),
            Texture::SolidChecker(t) => t.evaluate(query.point),
            Texture::Image(t) => t.evaluate(query.uv),
            Texture::Marble(t) => t.evaluate(query.point),
            Texture::Wood(t) => t.evaluate(query.point),
            Texture::Attribute(t) => t.evaluate(query),
            Texture::Mix(t) => t.evaluate(query),
            Texture::Product(t) => t.evaluate(query),
            Texture::DirectionMix(t) => t.evaluate(query),
            Texture::Mapped(t) => t.evaluate(query),
            Texture::Noise(t) => t.evaluate(query),
            Texture::Dots(t) => t.evaluate(query.uv),
            Texture::Bilerp(t) => t.evaluate(query.uv),
        }
    }
}

/// A colour's luminance with the sRGB primaries' weights (as Mitsuba reads a colour texture
/// as a scalar, for a bump map's height).
pub fn luminance(c: Rgb) -> f32 {
    c.dot(Rgb::new(0.212_671, 0.715_160, 0.072_169))
}

impl Texture {
    /// The gradient in uv of the texture's luminance at `query`, for a bump map: an image's
    /// from its texels; zero for constants and for the 2D checkerboard (flat between its
    /// edges); for pbrt's procedural textures and mapped ones, a finite difference along u
    /// and v, the point moved along ∂p/∂u and ∂p/∂v with the uv (pbrt's bump mapping, whose
    /// step without ray differentials is this one). The solid textures of the object's own
    /// space and mesh attributes have none (`has_uv_gradient` says so, and the readers refuse
    /// them as heights).
    pub fn luminance_gradient(&self, query: &TextureQuery) -> Vec2 {
        match self {
            Texture::Image(t) => t.luminance_gradient(query.uv),
            Texture::Noise(_)
            | Texture::Dots(_)
            | Texture::Bilerp(_)
            | Texture::Mapped(_)
            | Texture::Mix(_)
            | Texture::Product(_)
            | Texture::DirectionMix(_) => {
                const STEP: f32 = 0.0005;
                let height = |uv: Vec2, along: Vec3| {
                    let moved = TextureQuery {
                        uv,
                        point: query.point + STEP * along,
                        world_point: query.world_point + STEP * along,
                        ..*query
                    };
                    luminance(self.evaluate(&moved))
                };
                let here = luminance(self.evaluate(query));
                Vec2::new(
                    (height(query.uv + Vec2::new(STEP, 0.0), query.dpdu) - here) / STEP,
                    (height(query.uv + Vec2::new(0.0, STEP), query.dpdv) - here) / STEP,
                )
            }
            _ => Vec2::ZERO,
        }
    }

    /// The texture is a function of uv or of the world point, so `luminance_gradient` is its
    /// slope.
    pub fn has_uv_gradient(&self) -> bool {
        match self {
            Texture::Constant(_) | Texture::Checker(_) | Texture::Image(_) => true,
            Texture::Noise(_) | Texture::Dots(_) | Texture::Bilerp(_) => true,
            Texture::Mapped(t) => t.texture.has_uv_gradient(),
            Texture::Mix(t) => [&t.weight, &t.first, &t.second].iter().all(|t| t.has_uv_gradient()),
            Texture::Product(t) => t.factors.iter().all(Texture::has_uv_gradient),
            Texture::DirectionMix(t) => t.first.has_uv_gradient() && t.second.has_uv_gradient(),
            _ => false,
        }
    }

    /// The mean over the unit uv square (an image's texels, a checker's two colours), or the
    /// largest value for the solid textures and mesh attributes, which have no square.
    pub fn mean_value(&self) -> Rgb {
        match self {
            Texture::Constant(c) => *c,
            Texture::Checker(t) => 0.5 * (t.even + t.odd),
            Texture::Image(t) => t.pixels.iter().fold(Rgb::ZERO, |m, p| m + *p) / t.pixels.len().max(1) as f32,
            _ => self.max_value(),
        }
    }

    /// The largest value of each channel anywhere (textures blend between their colours).
    pub fn max_value(&self) -> Rgb {
        match self {
            Texture::Constant(c) => *c,
            Texture::Checker(t) => t.even.max(t.odd),
            Texture::SolidChecker(t) => t.even.max(t.odd),
            Texture::Image(t) => t.pixels.iter().fold(Rgb::ZERO, |m, p| m.max(*p)),
            Texture::Marble(t) => t.base.max(t.vein),
            Texture::Wood(t) => t.light.max(t.dark),
            // Unknown until a mesh is hit: taken as colours are, at most 1 (times the scale).
            Texture::Attribute(t) => Rgb::splat(t.scale),
            Texture::Mix(t) => t.first.max_value().max(t.second.max_value()),
            Texture::Product(t) => t.factors[0].max_value() * t.factors[1].max_value(),
            Texture::DirectionMix(t) => t.first.max_value().max(t.second.max_value()),
            Texture::Mapped(t) => t.texture.max_value(),
            Texture::Noise(t) => t.max_value(),
            Texture::Dots(t) => t.inside.max(t.outside),
            // Within the unit square of (s, t), where the blend does not extrapolate.
            Texture::Bilerp(t) => t.v00.max(t.v01).max(t.v10).max(t.v11),
        }
    }
}

impl From<Rgb> for Texture {
    fn from(c: Rgb) -> Self {
        Texture::Constant(c)
    }
}

/// A grey constant.
impl From<f32> for Texture {
    fn from(v: f32) -> Self {
        Texture::Constant(Rgb::splat(v))
    }
}
