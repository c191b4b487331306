//! Bump mapping, Mitsuba's `bumpmap`: a height field tilts the shading normal, and the wrapped
//! material is evaluated about it. A wrapper: any material inside.
//!
//! Scene parameters: `height` (a texture of uv, read as its luminance: an image, best read
//! `raw`, a checkerboard or a constant), `scale` (what a unit of height is in scene units per
//! unit of uv, default 1), `material`.
//! ```toml
//! [textures.tiles-height]
//! type = "image"
//! file = "tiles-height.png"
//! raw = true
//!
//! [materials.tiles]
//! type = "bump-map"
//! height = "tiles-height"
//! scale = 0.02
//! material = "glaze"
//! ```
//! As in Mitsuba (and Blinn 1978, without the usually negligible term of the normal's own
//! derivative), the surface is displaced by h·n: its tangents become ∂p/∂u + n (s ∂h/∂u −
//! n·∂p/∂u) and the same for v, and the bumped normal is their cross product, turned to the
//! geometric normal's side. Only changes of height matter, not its level. The tangent frame
//! still follows ∂p/∂u; light may only leave on the geometric normal's side, as for every
//! shading normal (`Frame`). Whitted reads the wrapped material about the shape's own normal.

use glam::Vec3;

use super::Material;
use crate::textures::{Texture, TextureQuery};

#[derive(Clone, Debug, PartialEq)]
pub struct BumpMap {
    pub height: Texture,
    pub scale: f32,
    pub material: Material,
}

impl BumpMap {
    /// The bumped shading normal at `query` on a surface whose own shading normal is `shading`
    /// and geometric normal `geometric` (world space). The shape's normal where the surface
    /// has no uv tangents (instances, degenerate uvs, a sphere's poles).
    pub fn shading_normal(&self, query: &TextureQuery, shading: Vec3, geometric: Vec3) -> Vec3 {
        let (dpdu, dpdv) = (query.dpdu, query.dpdv);
        if dpdu == Vec3::ZERO || dpdv == Vec3::ZERO {
            return shading;
        }
        let slope = self.scale * self.height.luminance_gradient(query);
        let along_u = dpdu + shading * (slope.x - shading.dot(dpdu));
        let along_v = dpdv + shading * (slope.y - shading.dot(dpdv));
        let normal = along_u.cross(along_v).normalize_or_zero();
        match normal.dot(geometric) {
            d if d > 0.0 => normal,
            d if d < 0.0 => -normal,
            _ => shading,
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec2;

    use super::*;
    use crate::materials::testing::check_sampling;
    use crate::materials::{Conductor, Diffuse, RoughConductor};
    use crate::textures::{ImageTexture, Wrap};
    use crate::Rgb;

    fn metal() -> Material {
        let conductor = Conductor { eta: Rgb::ZERO, k: Rgb::ONE, specular: Texture::Constant(Rgb::ONE) };
        Material::RoughConductor(RoughConductor {
            conductor,
            alpha_u: 0.2.into(),
            alpha_v: 0.2.into(),
            distribution: Default::default(),
        })
    }

    /// Heights from black to white across two texels: at the middle, luminance rises by 2 per
    /// unit of u and not at all along v.
    fn ramp() -> Texture {
        Texture::Image(std::sync::Arc::new(ImageTexture {
            wrap: Wrap::Clamp,
            ..ImageTexture::new(2, 1, vec![Rgb::ZERO, Rgb::ONE])
        }))
    }

    fn bumped(height: Texture, scale: f32, material: Material) -> BumpMap {
        BumpMap { height, scale, material }
    }

    /// A constant height changes nothing: the same values and pdf as the material alone.
    #[test]
    fn a_level_height_is_the_material_itself() {
        let n = Vec3::new(0.1, 0.2, 1.0).normalize();
        let query =
            TextureQuery { dpdu: Vec3::new(1.0, 0.0, -0.1), dpdv: Vec3::new(0.1, 2.0, 0.3), ..Default::default() };
        let plain = metal();
        let map = Material::BumpMap(Box::new(bumped(Texture::Constant(Rgb::splat(0.7)), 3.0, metal())));
        let mut rng = crate::sampling::Rng::new(5, 5);
        for _ in 0..500 {
            let mut sphere =
                || crate::sampling::warp::square_to_uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
            let (wo, wi) = (sphere(), sphere());
            let (a, b) = (plain.bsdf(&query, wo, n, n), map.bsdf(&query, wo, n, n));
            assert!((a.eval(wo, wi) - b.eval(wo, wi)).abs().max_element() < 1e-5);
            assert!((a.pdf(wo, wi) - b.pdf(wo, wi)).abs() < 1e-4 * a.pdf(wo, wi).max(1.0));
        }
    }

    /// By hand, on the plane z = 0 with ∂p/∂u = a·x̂ and ∂p/∂v = ŷ: the height rises by
    /// s·2 per unit of u, so by 2s/a per unit of length along x, and the normal is
    /// (−2s/a, 0, 1) normalised. Either orientation of v gives the same normal (it is turned
    /// to the geometric side).
    #[test]
    fn a_ramp_tilts_the_normal_against_its_slope() {
        let uv = Vec2::new(0.5, 0.5);
        for (scale, a) in [(0.25, 1.0), (0.25, 2.0), (1.0, 0.5), (-0.1, 1.0)] {
            for dpdv in [Vec3::Y, -Vec3::Y] {
                let query = TextureQuery { uv, dpdu: a * Vec3::X, dpdv, ..Default::default() };
                let n = bumped(ramp(), scale, metal()).shading_normal(&query, Vec3::Z, Vec3::Z);
                let expected = Vec3::new(-2.0 * scale / a, 0.0, 1.0).normalize();
                assert!((n - expected).length() < 1e-5, "scale {scale}, |∂p/∂u| {a}, ∂p/∂v {dpdv}: {n} vs {expected}");
            }
        }
        // Without tangents there is nothing to tilt.
        let query = TextureQuery { uv, ..Default::default() };
        assert_eq!(bumped(ramp(), 1.0, metal()).shading_normal(&query, Vec3::Z, Vec3::Z), Vec3::Z);
    }

    /// The metal's highlight follows the bumped normal, and sampling about it still matches
    /// the pdf, for a metal and a diffuse surface.
    #[test]
    fn the_bumped_lobe_moves_and_samples_by_its_pdf() {
        let query = TextureQuery { uv: Vec2::new(0.5, 0.5), dpdu: Vec3::X, dpdv: Vec3::Y, ..Default::default() };
        let wo = Vec3::new(0.2, 0.1, 0.97).normalize();
        let map = bumped(ramp(), 0.3, metal());
        let n = map.shading_normal(&query, Vec3::Z, Vec3::Z);
        let material = Material::BumpMap(Box::new(map));
        let bsdf = material.bsdf(&query, wo, Vec3::Z, Vec3::Z);
        let mirror = crate::geometry::reflect(-wo, n);
        let beside = crate::geometry::reflect(-wo, Vec3::Z);
        assert!(bsdf.eval(wo, mirror).x > 10.0 * bsdf.eval(wo, beside).x, "the highlight moved");
        check_sampling(&bsdf, wo, Vec3::Z, 97);
        let diffuse = Material::Diffuse(Diffuse { reflectance: Texture::Constant(Rgb::ONE) });
        let diffuse = Material::BumpMap(Box::new(bumped(ramp(), 0.3, diffuse)));
        check_sampling(&diffuse.bsdf(&query, wo, Vec3::Z, Vec3::Z), wo, Vec3::Z, 98);
    }
}
