//! Normal mapping, Mitsuba's `normalmap`: a texture gives the shading normal in the surface's
//! tangent frame, and the wrapped material is evaluated about it. A wrapper: any material
//! inside.
//!
//! Scene parameters: `normals` (a texture, read raw: its RGB in [0, 1] is the normal
//! (2·rgb − 1) in the frame of ∂p/∂u, n × ∂p/∂u and the surface's shading normal), `material`.
//! ```toml
//! [textures.bumps]
//! type = "image"
//! file = "bumps-normal.png"
//! raw = true
//!
//! [materials.tiles]
//! type = "normal-map"
//! normals = "bumps"
//! material = "glaze"
//! ```
//! As in Mitsuba the tangent frame follows ∂p/∂u (an orthonormal one about the normal where a
//! surface has none). Light may still only leave on the geometric normal's side, as for every
//! shading normal (`Frame`). Whitted reads the wrapped material about the shape's own normal.

use glam::Vec3;

use super::bsdf::tangent_along;
use super::Material;
use crate::geometry::orthonormal_basis;
use crate::textures::{Texture, TextureQuery};

#[derive(Clone, Debug, PartialEq)]
pub struct NormalMap {
    pub normals: Texture,
    pub material: Material,
}

impl NormalMap {
    /// The mapped shading normal at `query` on a surface whose own shading normal is `shading`
    /// (world space): the texture's (2·rgb − 1), normalised, in the frame of ∂p/∂u. The
    /// shape's normal where the texture gives no direction.
    pub fn shading_normal(&self, query: &TextureQuery, shading: Vec3) -> Vec3 {
        let local = (2.0 * self.normals.evaluate(query) - Vec3::ONE).normalize_or_zero();
        if local == Vec3::ZERO {
            return shading;
        }
        let tangent = tangent_along(shading, query.dpdu).unwrap_or_else(|| orthonormal_basis(shading).0);
        let bitangent = shading.cross(tangent);
        (local.x * tangent + local.y * bitangent + local.z * shading).normalize_or(shading)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::materials::testing::check_sampling;
    use crate::materials::{Conductor, Diffuse, RoughConductor};
    use crate::Rgb;

    fn map(normal: Vec3, material: Material) -> Material {
        let rgb = (normal.normalize() + Vec3::ONE) * 0.5;
        Material::NormalMap(Box::new(NormalMap { normals: Texture::Constant(rgb), material }))
    }

    fn metal() -> Material {
        let conductor = Conductor { eta: Rgb::ZERO, k: Rgb::ONE, specular: Texture::Constant(Rgb::ONE) };
        Material::RoughConductor(RoughConductor {
            conductor,
            alpha_u: 0.2.into(),
            alpha_v: 0.2.into(),
            distribution: Default::default(),
        })
    }

    /// The flat map (0.5, 0.5, 1) changes nothing: the same values and pdf as the material
    /// alone, for every pair of directions.
    #[test]
    fn the_flat_map_is_the_material_itself() {
        let n = Vec3::new(0.1, 0.2, 1.0).normalize();
        let query = TextureQuery { dpdu: Vec3::new(1.0, 0.0, -0.1), ..Default::default() };
        let (plain, mapped) = (metal(), map(Vec3::Z, metal()));
        let mut rng = crate::sampling::Rng::new(5, 5);
        for _ in 0..500 {
            let mut sphere =
                || crate::sampling::warp::square_to_uniform_sphere(glam::Vec2::new(rng.next_f32(), rng.next_f32()));
            let (wo, wi) = (sphere(), sphere());
            let (a, b) = (plain.bsdf(&query, wo, n, n), mapped.bsdf(&query, wo, n, n));
            assert!((a.eval(wo, wi) - b.eval(wo, wi)).abs().max_element() < 1e-5);
            assert!((a.pdf(wo, wi) - b.pdf(wo, wi)).abs() < 1e-4 * a.pdf(wo, wi).max(1.0));
        }
    }

    /// Against Mitsuba 3.9's `normalmap` (its `eval` in the same frame, by hand: 2·(128, 200,
    /// 230)/255 − 1 tilts the normal 35° toward n × ∂p/∂u): light at θ_i from the surface's own
    /// normal is shadowed by G1 with α² = tan²35°/8 (at 80° to 0.731 of the mapped cosine), and
    /// a viewer behind the mapped normal sees it reflected about the surface's own (the values
    /// for ±y swap).
    #[test]
    fn grazing_light_is_shadowed_and_a_hidden_tilt_turns_as_in_mitsuba() {
        let rgb = Vec3::new(128.0, 200.0, 230.0) / 255.0;
        let white = Material::Diffuse(Diffuse { reflectance: Texture::Constant(Rgb::ONE) });
        let m = Material::NormalMap(Box::new(NormalMap { normals: Texture::Constant(rgb), material: white }));
        let query = TextureQuery { dpdu: Vec3::X, ..Default::default() };
        let a = 80f32.to_radians();
        let lights = [Vec3::Z, Vec3::new(0.0, 0.6, 0.8), Vec3::new(0.0, -0.6, 0.8), Vec3::new(0.0, a.sin(), a.cos())];
        let seen = |wo: Vec3| {
            let bsdf = m.bsdf(&query, wo.normalize(), Vec3::Z, Vec3::Z);
            lights.map(|wi| bsdf.eval(wo, wi).x * std::f32::consts::PI)
        };
        let mitsuba = [0.816_409_1, 0.990_963_5, 0.304_000_7, 0.519_458_4];
        for (ours, theirs) in seen(Vec3::new(-0.12, -0.08, 0.99)).iter().zip(mitsuba) {
            assert!((ours - theirs).abs() < 2e-5, "{ours} vs {theirs}");
        }
        let behind = seen(Vec3::new(0.0, -0.9, 0.436));
        assert!((behind[1] - mitsuba[2]).abs() < 2e-5 && (behind[2] - mitsuba[1]).abs() < 2e-5, "{behind:?}");
    }

    /// A normal tilted toward ∂p/∂u by 30° turns the shading normal that way about the shape's
    /// normal, whichever way ∂p/∂u points; the mirror lobe of a metal follows it, and its
    /// sampling still matches its pdf.
    #[test]
    fn a_tilted_map_turns_the_shading_normal_toward_dpdu() {
        let tilt = 30f32.to_radians();
        let mapped_normal = Vec3::new(tilt.sin(), 0.0, tilt.cos());
        let material = NormalMap { normals: Texture::Constant((mapped_normal + Vec3::ONE) * 0.5), material: metal() };
        for dpdu in [Vec3::X, Vec3::new(0.0, 2.0, 0.5), Vec3::new(-1.0, -1.0, 0.0)] {
            let query = TextureQuery { dpdu, ..Default::default() };
            let n = material.shading_normal(&query, Vec3::Z);
            let along = (dpdu - Vec3::Z * dpdu.z).normalize();
            let expected = tilt.sin() * along + tilt.cos() * Vec3::Z;
            assert!((n - expected).length() < 1e-5, "{dpdu}: {n} vs {expected}");
        }
        let query = TextureQuery { dpdu: Vec3::X, ..Default::default() };
        let mapped = map(mapped_normal, metal());
        let wo = Vec3::new(0.2, 0.1, 0.97).normalize();
        let bsdf = mapped.bsdf(&query, wo, Vec3::Z, Vec3::Z);
        let n = material.shading_normal(&query, Vec3::Z);
        let mirror = crate::geometry::reflect(-wo, n);
        let beside = crate::geometry::reflect(-wo, Vec3::Z);
        assert!(bsdf.eval(wo, mirror).x > 10.0 * bsdf.eval(wo, beside).x, "the highlight moved");
        // check_sampling evaluates the BSDF it is given; the query only matters at build time.
        check_sampling(&bsdf, wo, Vec3::Z, 95);
        let diffuse = map(mapped_normal, Material::Diffuse(Diffuse { reflectance: Texture::Constant(Rgb::ONE) }));
        check_sampling(&diffuse.bsdf(&query, wo, Vec3::Z, Vec3::Z), wo, Vec3::Z, 96);
    }
}
