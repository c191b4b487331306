//! Materials: how a surface answers light. One closed set of BSDFs, a file each (Mitsuba's
//! plugin layout, dispatched by `match` as pbrt-v4 does), and the wrappers that combine them.
//! A material evaluated at a hit (`Material::bsdf`) is a small value on the stack, read through
//! one contract (`bsdf.rs`) by every Monte Carlo integrator; Whitted reads each member's
//! Whitted terms (`Material::whitted`), the course's local model and child rays.
//!
//! Conventions: colours are linear RGB; directions given to a material point *away* from the
//! surface (`wo` toward the viewer, `wi` toward the light). One-sided members (diffuse,
//! conductors, plastics) are black from behind, as Mitsuba's are; `two_sided` turns them.

mod blend;
mod bsdf;
mod bump_map;
mod conductor;
mod dielectric;
mod diffuse;
mod diffuse_transmission;
mod fresnel_plastic;
mod mask;
mod microfacet;
mod mixed;
mod normal_map;
mod phong;
mod plastic;
mod principled;
mod principled_thin;
mod rough_conductor;
mod rough_dielectric;
mod rough_plastic;
#[cfg(test)]
mod testing;
mod thin_dielectric;
mod two_sided;

pub use blend::Blend;
pub(crate) use bsdf::{luminance, tangent_along_lanes, LaneBsdfSample, LaneFrame, MapShadowing};
pub use bsdf::{Bsdf, BsdfSample, Frame, MAX_LEAVES};
pub use bump_map::BumpMap;
pub(crate) use conductor::ConductorLanes;
pub use conductor::{fresnel_conductor, named_metal, Conductor, METAL_NAMES};
pub use dielectric::Dielectric;
pub(crate) use dielectric::DielectricLanes;
pub use diffuse::Diffuse;
pub(crate) use diffuse::DiffuseLanes;
pub use diffuse_transmission::DiffuseTransmission;
pub(crate) use diffuse_transmission::DiffuseTransmissionLanes;
pub use fresnel_plastic::FresnelPlastic;
pub use mask::Mask;
pub(crate) use microfacet::MicrofacetLanes;
pub use microfacet::{Distribution, Microfacet};
pub use normal_map::NormalMap;
pub use phong::{fresnel_dielectric, fresnel_schlick, Fresnel, Phong, PhongPoint};
pub use plastic::{fresnel_diffuse_reflectance, Plastic};
pub(crate) use plastic::{Coat, PlasticLanes};
pub use principled::Principled;
pub(crate) use principled::{PrincipledLanes, PrincipledPoint};
pub use principled_thin::{PrincipledThin, SamplingRates};
pub(crate) use principled_thin::{PrincipledThinLanes, PrincipledThinPoint};
pub use rough_conductor::RoughConductor;
pub(crate) use rough_conductor::RoughConductorLanes;
pub use rough_dielectric::RoughDielectric;
pub(crate) use rough_dielectric::RoughDielectricLanes;
pub use rough_plastic::RoughPlastic;
pub(crate) use rough_plastic::{CoatTables, CoatTransmittance, RoughPlasticLanes};
pub use thin_dielectric::ThinDielectric;
pub(crate) use thin_dielectric::ThinDielectricLanes;
pub use two_sided::TwoSided;

use glam::Vec3;

use self::bsdf::{Leaf, Mixture};
use self::mask::NullBsdf;
use self::mixed::MixedBsdf;
use crate::textures::{Texture, TextureQuery};
use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub enum Material {
    /// The course's material: Phong's local model for Whitted, its k_d, k_r, k_t as the mixed
    /// material's lobes for the Monte Carlo integrators; it may emit.
    Phong(Phong),
    Diffuse(Diffuse),
    /// Lambert's lobe on both sides (pbrt's `diffusetransmission`).
    DiffuseTransmission(DiffuseTransmission),
    Conductor(Conductor),
    RoughConductor(RoughConductor),
    Dielectric(Dielectric),
    RoughDielectric(RoughDielectric),
    ThinDielectric(ThinDielectric),
    Plastic(Plastic),
    RoughPlastic(RoughPlastic),
    /// A rough specular reflection over a Fresnel-weighted Lambert term (Mitsuba's `pplastic`).
    FresnelPlastic(Box<FresnelPlastic>),
    Principled(Box<Principled>),
    PrincipledThin(Box<PrincipledThin>),
    Blend(Box<Blend>),
    Mask(Box<Mask>),
    TwoSided(Box<TwoSided>),
    /// A material about a shading normal from a texture (Mitsuba's `normalmap`).
    NormalMap(Box<NormalMap>),
    /// A material about a normal tilted by a height field (Mitsuba's `bumpmap`).
    BumpMap(Box<BumpMap>),
    /// Any material that also emits: Mitsuba's `area` emitter on a shape.
    Emitter(Box<Emitter>),
}

/// Emitted radiance on a surface of any material.
#[derive(Clone, Debug, PartialEq)]
pub struct Emitter {
    /// L_e, a constant or a texture over the surface's uv (Mitsuba's textured `radiance`).
    pub radiance: Texture,
    /// Emit from both sides (default: only the side the geometric normal points to).
    pub two_sided: bool,
    pub surface: Material,
}

/// A blend weight or an opacity: a texture's luminance, clamped to [0, 1].
fn fraction(texture: &Texture, query: &TextureQuery) -> f32 {
    crate::textures::fraction(texture.evaluate(query))
}

/// A mapped normal the viewer `wo` is behind, reflected about the surface's own shading normal
/// (its tilt turned the other way), as Mitsuba 3 does: the map then shades what is seen
/// rather than leaving it black.
fn toward_viewer(mapped: Vec3, unmapped: Vec3, wo: Vec3) -> Vec3 {
    if mapped.dot(wo) * unmapped.dot(wo) > 0.0 {
        return mapped;
    }
    2.0 * mapped.dot(unmapped) * unmapped - mapped
}

/// The leaves a normal or bump map made, shadowed against the surface's own shading normal
/// `unmapped` (`Frame::with_map_shadowing`). A map inside a map keeps the inner one's.
fn shadow_mapped(leaves: &mut [Leaf], unmapped: Vec3) {
    for leaf in leaves {
        let frame = leaf.frame_mut();
        if frame.shadowing_alpha2 == 0.0 {
            *frame = frame.with_map_shadowing(unmapped);
        }
    }
}

impl Material {
    /// The BSDF at a hit seen from `wo`, with the normals as the shape defines them.
    #[inline]
    pub fn bsdf<'a>(
        &'a self,
        query: &TextureQuery,
        wo: Vec3,
        shading_normal: Vec3,
        geometric_normal: Vec3,
    ) -> Bsdf<'a> {
        if let Material::Phong(p) = self {
            let frame = Frame::new(wo, shading_normal, geometric_normal);
            return Bsdf::leaf(Leaf::Mixed(MixedBsdf::new(&p.evaluate(query), wo, frame)));
        }
        let unused = Leaf::Null(NullBsdf { frame: Frame::new(wo, shading_normal, geometric_normal) });
        let mut mixture = Mixture { leaves: [unused; MAX_LEAVES], weights: [0.0; MAX_LEAVES], count: 0 };
        self.gather(query, wo, shading_normal, geometric_normal, 1.0, &mut mixture);
        if mixture.count == 1 && mixture.weights[0] == 1.0 {
            return Bsdf::leaf(mixture.leaves[0]);
        }
        Bsdf::mixture(mixture)
    }

    /// Adds this material's leaves, each weighed by `weight`, to `mixture`.
    fn gather<'a>(
        &'a self,
        query: &TextureQuery,
        wo: Vec3,
        shading: Vec3,
        geometric: Vec3,
        weight: f32,
        mixture: &mut Mixture<'a>,
    ) {
        let frame = || Frame::new(wo, shading, geometric);
        let (leaf, weight) = match self {
            Material::Phong(p) => (Leaf::Mixed(MixedBsdf::new(&p.evaluate(query), wo, frame())), weight),
            Material::Diffuse(m) => (m.bsdf(query, frame()), weight),
            Material::DiffuseTransmission(m) => (m.bsdf(query, frame()), weight),
            Material::Conductor(m) => (m.bsdf(query, frame()), weight),
            Material::RoughConductor(m) => (m.bsdf(query, frame()), weight),
            Material::Dielectric(m) => (m.bsdf(query, frame()), weight),
            Material::RoughDielectric(m) => (m.bsdf(query, frame()), weight),
            Material::ThinDielectric(m) => (m.bsdf(query, frame()), weight),
            Material::Plastic(m) => (m.bsdf(query, wo, frame()), weight),
            Material::RoughPlastic(m) => (m.bsdf(query, wo, frame()), weight),
            Material::FresnelPlastic(m) => (m.bsdf(query, frame()), weight),
            Material::Principled(m) => (m.bsdf(query, frame()), weight),
            Material::PrincipledThin(m) => (m.bsdf(query, frame()), weight),
            Material::Blend(b) => {
                let w = fraction(&b.weight, query);
                if w < 1.0 {
                    b.first.gather(query, wo, shading, geometric, weight * (1.0 - w), mixture);
                }
                if w > 0.0 {
                    b.second.gather(query, wo, shading, geometric, weight * w, mixture);
                }
                return;
            }
            Material::Mask(m) => {
                let opacity = fraction(&m.opacity, query);
                if opacity > 0.0 {
                    m.material.gather(query, wo, shading, geometric, weight * opacity, mixture);
                }
                if opacity == 1.0 {
                    return;
                }
                (Leaf::Null(NullBsdf { frame: frame() }), weight * (1.0 - opacity))
            }
            Material::TwoSided(t) => {
                if wo.dot(geometric) >= 0.0 {
                    t.front.gather(query, wo, shading, geometric, weight, mixture);
                } else {
                    t.back.gather(query, wo, -shading, -geometric, weight, mixture);
                }
                return;
            }
            Material::NormalMap(m) => {
                let mapped = toward_viewer(m.shading_normal(query, shading), shading, wo);
                let first = mixture.count;
                m.material.gather(query, wo, mapped, geometric, weight, mixture);
                return shadow_mapped(&mut mixture.leaves[first..mixture.count], shading);
            }
            Material::BumpMap(m) => {
                let bumped = toward_viewer(m.shading_normal(query, shading, geometric), shading, wo);
                let first = mixture.count;
                m.material.gather(query, wo, bumped, geometric, weight, mixture);
                return shadow_mapped(&mut mixture.leaves[first..mixture.count], shading);
            }
            Material::Emitter(e) => return e.surface.gather(query, wo, shading, geometric, weight, mixture),
        };
        if mixture.count < MAX_LEAVES {
            mixture.leaves[mixture.count] = leaf;
            mixture.weights[mixture.count] = weight;
            mixture.count += 1;
        }
    }

    /// A normal or bump map's shading normal for the viewer `wo`, turned toward the viewer as
    /// the BSDF takes it, on a surface with shading normal `shading` and geometric normal
    /// `geometric` (the query with ∂p/∂u and ∂p/∂v); `None` for any other material.
    pub(crate) fn mapped_normal(&self, query: &TextureQuery, wo: Vec3, shading: Vec3, geometric: Vec3) -> Option<Vec3> {
        let mapped = match self {
            Material::NormalMap(m) => m.shading_normal(query, shading),
            Material::BumpMap(m) => m.shading_normal(query, shading, geometric),
            _ => return None,
        };
        Some(toward_viewer(mapped, shading, wo))
    }

    /// The material under a normal or bump map (itself for any other).
    pub(crate) fn unmapped(&self) -> &Material {
        match self {
            Material::NormalMap(m) => &m.material,
            Material::BumpMap(m) => &m.material,
            _ => self,
        }
    }

    /// The material reads the surface's ∂p/∂u (`TextureQuery::dpdu`; only these make a hit
    /// find it): a lobe with different widths along and across it, or a normal map.
    pub fn needs_tangent(&self) -> bool {
        match self {
            Material::RoughConductor(m) => m.alpha_u != m.alpha_v,
            Material::RoughDielectric(m) => m.alpha_u != m.alpha_v,
            Material::FresnelPlastic(m) => m.alpha_u != m.alpha_v,
            Material::Principled(m) => m.anisotropic != Texture::Constant(Rgb::ZERO),
            Material::PrincipledThin(m) => m.anisotropic != Texture::Constant(Rgb::ZERO),
            Material::Blend(b) => b.first.needs_tangent() || b.second.needs_tangent(),
            Material::Mask(m) => m.material.needs_tangent(),
            Material::TwoSided(t) => t.front.needs_tangent() || t.back.needs_tangent(),
            Material::Emitter(e) => e.surface.needs_tangent(),
            Material::NormalMap(_) | Material::BumpMap(_) => true,
            _ => false,
        }
    }

    /// The number of leaves the material's BSDF flattens into, at most (the scene builder
    /// refuses more than `MAX_LEAVES`).
    pub fn leaf_count(&self) -> usize {
        match self {
            Material::Blend(b) => b.first.leaf_count() + b.second.leaf_count(),
            Material::Mask(m) => m.material.leaf_count() + 1,
            Material::TwoSided(t) => t.front.leaf_count().max(t.back.leaf_count()),
            Material::Emitter(e) => e.surface.leaf_count(),
            Material::NormalMap(m) => m.material.leaf_count(),
            Material::BumpMap(m) => m.material.leaf_count(),
            _ => 1,
        }
    }

    /// The material's Whitted terms at a point seen from its `outside` (the side its geometric
    /// normal points to) or not, by a viewer at cosine `cos_incident` to the shading normal
    /// turned toward it: the course's local model, and the weights of the child rays at that
    /// angle with every Fresnel factor applied (the point's `fresnel` is `None`). The course's
    /// material applies its own rule (`PhongPoint::ray_weights`). Each member of the BSDF set
    /// gives its nearest course reading, documented in its file: its smooth lobes as mirror,
    /// refracted and straight-through rays weighted as the BSDF weighs them at this angle,
    /// rough lobes as their smooth limit (Whitted traces no glossy rays), its diffuse part as
    /// Lambert's term with k_d = k_a = its albedo. So Whitted's direct light from a point or
    /// directional light is π times the path tracers' (k_d·cos·I against ρ/π·cos·I) for every
    /// material alike, the course's convention, while what the child rays carry agrees.
    pub fn whitted_at(&self, query: &TextureQuery, outside: bool, cos_incident: f32) -> PhongPoint {
        let cos = cos_incident;
        match self {
            Material::Phong(p) => {
                let point = p.evaluate(query);
                let eta = if outside { 1.0 / point.ior } else { point.ior };
                let (reflection, transmission) = point.ray_weights(cos, eta);
                PhongPoint { reflection, transmission, fresnel: Fresnel::None, ..point }
            }
            Material::Diffuse(m) => m.whitted(query, outside),
            Material::DiffuseTransmission(m) => m.whitted(query),
            Material::Conductor(m) => m.whitted(query, outside, cos),
            Material::RoughConductor(m) => m.whitted(query, outside, cos),
            Material::Dielectric(m) => m.whitted(query, outside, cos),
            Material::RoughDielectric(m) => m.whitted(query, outside, cos),
            Material::ThinDielectric(m) => m.whitted(query, cos),
            Material::Plastic(m) => m.whitted(query, outside, cos),
            Material::RoughPlastic(m) => m.whitted(query, outside, cos),
            Material::FresnelPlastic(m) => m.whitted(query, outside, cos),
            Material::Principled(m) => m.whitted(query, outside, cos),
            Material::PrincipledThin(m) => m.whitted(query, cos),
            Material::Blend(b) => {
                let w = fraction(&b.weight, query);
                let first = b.first.whitted_at(query, outside, cos);
                first.blend(&b.second.whitted_at(query, outside, cos), w)
            }
            Material::Mask(m) => {
                let inner = m.material.whitted_at(query, outside, cos);
                // Where the surface is absent, light goes on unbent; the inner material keeps
                // its index and coat whichever part is larger.
                let clear = PhongPoint { straight: Rgb::ONE, ..PhongPoint::BLACK };
                let mixed = clear.blend(&inner, fraction(&m.opacity, query));
                PhongPoint { ior: inner.ior, coat_ior: inner.coat_ior, shininess: inner.shininess, ..mixed }
            }
            Material::TwoSided(t) => if outside { &t.front } else { &t.back }.whitted_at(query, true, cos),
            Material::NormalMap(m) => m.material.whitted_at(query, outside, cos),
            Material::BumpMap(m) => m.material.whitted_at(query, outside, cos),
            Material::Emitter(e) => PhongPoint {
                emission: e.radiance.evaluate(query),
                two_sided_emission: e.two_sided,
                ..e.surface.whitted_at(query, outside, cos)
            },
        }
    }

    /// `whitted_at` seen head-on (cos θ = 1): the local model's terms (which do not depend on
    /// the viewer's angle but for a coat's transmittance), as ray casting reads them.
    pub fn whitted(&self, query: &TextureQuery, outside: bool) -> PhongPoint {
        self.whitted_at(query, outside, 1.0)
    }

    /// What a shadow ray crossing the surface at cosine `cos_incident` lets through, for
    /// Whitted's transparent shadows (the course's approximation: no refraction): the course's
    /// material its k_t as given; any other what its Whitted terms pass on at that angle,
    /// refracted or straight (a dielectric's (1 − F)·transmittance, a mask's clear part).
    pub fn shadow_transmission(&self, query: &TextureQuery, outside: bool, cos_incident: f32) -> Rgb {
        match self {
            Material::Phong(p) => p.transmission.evaluate(query),
            Material::Emitter(e) => e.surface.shadow_transmission(query, outside, cos_incident),
            _ => {
                let point = self.whitted_at(query, outside, cos_incident);
                point.transmission + point.straight
            }
        }
    }

    /// The radiance the material emits (its mean over the uv square where it is a texture:
    /// what decides whether it emits and how much power), and whether from both sides.
    pub fn emission(&self) -> (Rgb, bool) {
        match self {
            Material::Phong(p) => (p.emission, p.two_sided_emission),
            Material::Emitter(e) => (e.radiance.mean_value(), e.two_sided),
            _ => (Rgb::ZERO, false),
        }
    }

    /// The emitted radiance where it is a texture (it varies over the surface).
    pub fn emission_texture(&self) -> Option<&Texture> {
        match self {
            Material::Emitter(e) if !matches!(e.radiance, Texture::Constant(_)) => Some(&e.radiance),
            _ => None,
        }
    }

    /// The radiance the material emits at the point `query` describes (asked only where the
    /// emission is a texture), and whether from both sides.
    #[inline]
    pub fn emission_at<'q>(&self, query: impl FnOnce() -> TextureQuery<'q>) -> (Rgb, bool) {
        match self {
            Material::Emitter(e) => match &e.radiance {
                Texture::Constant(c) => (*c, e.two_sided),
                texture => (texture.evaluate(&query()), e.two_sided),
            },
            _ => self.emission(),
        }
    }

    /// Radiance emitted toward `wo` from a surface with geometric normal `geometric_normal`, at
    /// the point `query` describes.
    #[inline]
    pub fn emitted<'q>(&self, wo: Vec3, geometric_normal: Vec3, query: impl FnOnce() -> TextureQuery<'q>) -> Rgb {
        let (radiance, two_sided) = self.emission_at(query);
        if two_sided || wo.dot(geometric_normal) > 0.0 {
            radiance
        } else {
            Rgb::ZERO
        }
    }

    /// A surface that is nowhere there (a mask of opacity 0: Mitsuba's `null` BSDF): a medium's
    /// boundary, which light crosses unchanged.
    pub fn is_null(&self) -> bool {
        matches!(self, Material::Mask(m) if m.opacity.max_value() == Rgb::ZERO)
    }

    /// Whether light may pass the material straight through, unbent (a thin sheet, a mask,
    /// or a wrapper or blend that may hold one): a cheap test before building its BSDF.
    pub fn may_pass_straight(&self) -> bool {
        !matches!(
            self,
            Material::Phong(_)
                | Material::Diffuse(_)
                | Material::DiffuseTransmission(_)
                | Material::Conductor(_)
                | Material::RoughConductor(_)
                | Material::Dielectric(_)
                | Material::RoughDielectric(_)
                | Material::Plastic(_)
                | Material::RoughPlastic(_)
                | Material::FresnelPlastic(_)
                | Material::Principled(_)
                | Material::PrincipledThin(_)
        )
    }

    /// Lambert's reflectance when the material is a Lambert reflector and nothing else (what
    /// the wavefront's lanes model), and whether it is one-sided (black from behind).
    pub fn lambert(&self) -> Option<(&Texture, bool)> {
        match self {
            Material::Phong(p) => {
                // MixedBsdf's own test for a glossy lobe (a NaN roughness has none).
                let glossy = p.roughness > 0.0;
                let plain = p.reflection == Texture::Constant(Rgb::ZERO)
                    && p.transmission == Texture::Constant(Rgb::ZERO)
                    && p.specular == Texture::Constant(Rgb::ZERO)
                    && !glossy;
                plain.then_some((&p.diffuse, false))
            }
            Material::Diffuse(d) => Some((&d.reflectance, true)),
            Material::TwoSided(t) => match (&t.front, &t.back) {
                (Material::Diffuse(front), Material::Diffuse(back)) if front == back => {
                    Some((&front.reflectance, false))
                }
                _ => None,
            },
            Material::Emitter(e) => e.surface.lambert(),
            _ => None,
        }
    }

    /// A warning if the material passes on more light than it receives somewhere, per channel:
    /// for the course's material, k_d + k_r + k_t above 1 (the lobes every integrator that
    /// recurses follows), or k_r + k_t above 1 (the weights of Whitted's child rays). Phong's
    /// highlight k_s is the Monte Carlo integrators' alone: `highlight_warning`. For the other
    /// members, a reflectance or transmittance above 1.
    pub fn energy_warning(&self, name: &str) -> Option<String> {
        let p = match self {
            Material::Phong(p) => p,
            Material::Emitter(e) => return e.surface.energy_warning(name),
            _ => {
                let largest = self.largest_factor();
                return (largest > 1.0).then(|| format!(
                    "material `{name}` reflects or transmits more light than it receives (a colour factor of {largest}): every bounce off it adds light and pixel values can grow without bound. Keep colours ≤ 1"
                ));
            }
        };
        let (diffuse, reflection, transmission) =
            (p.diffuse.max_value(), p.reflection.max_value(), p.transmission.max_value());
        let all = (diffuse + reflection + transmission).max_element();
        let children = (reflection + transmission).max_element();
        if all <= 1.0 {
            return None;
        }
        let whitted = if children > 1.0 {
            format!("Whitted's child rays gain weight at each surface (k_r + k_t = {children}), so no `min_contribution` ends a tree through it: depth and the ray ceilings do")
        } else {
            "Whitted's recursion still loses weight at each surface (k_r + k_t ≤ 1)".to_string()
        };
        Some(format!(
            "material `{name}` passes on more light than it receives (k_d + k_r + k_t = {all} on some channel): the path tracers, light tracing and photon mapping follow it as given, so each bounce off it adds light and pixel values can grow without bound (Russian roulette survives at most 0.95 a bounce); {whitted}. Keep k_d + k_r + k_t ≤ 1 on every channel"
        ))
    }

    /// A warning for the Monte Carlo integrators if the course's material passes on more
    /// light than it receives once Phong's highlight is one of its lobes (k_d + k_s + k_r + k_t
    /// above 1 where k_d + k_r + k_t alone is not, which `energy_warning` says). Whitted's
    /// local model reads k_s once per light and does not recurse through it: classic scenes
    /// made for it often sum above 1, so this is asked only when a Monte Carlo integrator
    /// renders.
    pub fn highlight_warning(&self, name: &str) -> Option<String> {
        let p = match self {
            Material::Phong(p) => p,
            Material::Emitter(e) => return e.surface.highlight_warning(name),
            _ => return None,
        };
        let others = p.diffuse.max_value() + p.reflection.max_value() + p.transmission.max_value();
        let all = (others + p.specular.max_value()).max_element();
        (all > 1.0 && others.max_element() <= 1.0).then(|| format!(
            "material `{name}` passes on more light than it receives with Phong's highlight as a lobe (k_d + k_s + k_r + k_t = {all} on some channel): the Monte Carlo integrators sample the highlight (the normalised Phong lobe), so each bounce off it adds light; Whitted's model, which does not recurse through the highlight, is unaffected. Keep k_d + k_s + k_r + k_t ≤ 1 for them"
        ))
    }

    /// The largest colour factor of a member other than the course's material, anywhere.
    fn largest_factor(&self) -> f32 {
        let max = |t: &Texture| t.max_value().max_element();
        match self {
            Material::Phong(_) => 0.0,
            Material::Diffuse(m) => max(&m.reflectance),
            Material::DiffuseTransmission(m) => {
                let (r, t) = (m.reflectance.max_value(), m.transmittance.max_value());
                (r + t).max_element()
            }
            Material::Conductor(m) => max(&m.specular),
            Material::RoughConductor(m) => max(&m.conductor.specular),
            Material::Dielectric(m) => max(&m.specular_reflectance).max(max(&m.specular_transmittance)),
            Material::RoughDielectric(m) => {
                max(&m.dielectric.specular_reflectance).max(max(&m.dielectric.specular_transmittance))
            }
            Material::ThinDielectric(m) => max(&m.sheet.specular_reflectance).max(max(&m.sheet.specular_transmittance)),
            Material::Plastic(m) => max(&m.diffuse).max(max(&m.specular)),
            Material::RoughPlastic(m) => max(&m.plastic.diffuse).max(max(&m.plastic.specular)),
            Material::FresnelPlastic(m) => max(&m.diffuse).max(max(&m.specular)),
            Material::Principled(m) => max(&m.base_color),
            Material::PrincipledThin(m) => max(&m.base_color),
            Material::Blend(b) => b.first.largest_factor().max(b.second.largest_factor()),
            Material::Mask(m) => m.material.largest_factor(),
            Material::TwoSided(t) => t.front.largest_factor().max(t.back.largest_factor()),
            Material::Emitter(e) => e.surface.largest_factor(),
            Material::NormalMap(m) => m.material.largest_factor(),
            Material::BumpMap(m) => m.material.largest_factor(),
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec2;

    use super::testing::{albedo, check_sampling, check_whitted};
    use super::*;

    fn diffuse(r: f32) -> Material {
        Material::Diffuse(Diffuse { reflectance: Texture::Constant(Rgb::splat(r)) })
    }

    fn rough_metal() -> Material {
        let conductor = Conductor { eta: Rgb::ZERO, k: Rgb::ONE, specular: Texture::Constant(Rgb::ONE) };
        Material::RoughConductor(RoughConductor {
            conductor,
            alpha_u: 0.3.into(),
            alpha_v: 0.3.into(),
            distribution: Default::default(),
        })
    }

    const N: Vec3 = Vec3::Z;

    /// A blend evaluates as the weighted sum of its members, samples as their mixture (chi-
    /// square), and its albedo is the weighted sum of theirs.
    #[test]
    fn blend_is_the_weighted_mixture() {
        let wo = Vec3::new(0.3, 0.2, 0.9).normalize();
        let q = TextureQuery::default();
        let blend = |first: Material, second: Material, w: f32| {
            Material::Blend(Box::new(Blend { weight: Texture::Constant(Rgb::splat(w)), first, second }))
        };
        let m = blend(diffuse(0.2), diffuse(0.8), 0.25);
        let (b, a, c) = (m.bsdf(&q, wo, N, N), diffuse(0.2), diffuse(0.8));
        let wi = Vec3::new(-0.5, 0.1, 0.86).normalize();
        let expected = a.bsdf(&q, wo, N, N).eval(wo, wi) * 0.75 + c.bsdf(&q, wo, N, N).eval(wo, wi) * 0.25;
        assert!((b.eval(wo, wi) - expected).abs().max_element() < 1e-6);
        let albedo = albedo(&b, wo, 20_000, 4);
        assert!((albedo.mean - 0.35).abs() < 1e-5, "{albedo:?}");
        let glossy = blend(diffuse(0.5), rough_metal(), 0.6);
        check_sampling(&glossy.bsdf(&q, wo, N, N), wo, N, 81);
        // Its Whitted terms blend too.
        assert!((m.whitted(&q, true).diffuse - Rgb::splat(0.35)).abs().max_element() < 1e-6);
    }

    /// A mask passes light straight on with probability 1 − opacity; photon mapping's delta
    /// sampling finds that null lobe, its non-delta sampling the surface.
    #[test]
    fn mask_passes_light_through() {
        let wo = Vec3::new(0.3, 0.2, 0.9).normalize();
        let q = TextureQuery::default();
        let m = Material::Mask(Box::new(Mask { opacity: Texture::Constant(Rgb::splat(0.3)), material: diffuse(0.5) }));
        let b = m.bsdf(&q, wo, N, N);
        assert!((b.non_delta_probability() - 0.3).abs() < 1e-6);
        let through = b.sample_delta(wo, 0.5, Vec2::splat(0.5)).unwrap();
        assert!(through.delta && through.wi == -wo && (through.weight - Rgb::splat(0.7)).abs().max_element() < 1e-6);
        let surface = b.sample_non_delta(wo, 0.5, Vec2::splat(0.5)).unwrap();
        assert!(!surface.delta && (surface.weight - Rgb::splat(0.5 * 0.3)).abs().max_element() < 1e-6);
        let albedo = albedo(&b, wo, 50_000, 5);
        assert!((albedo.mean - (0.7 + 0.3 * 0.5)).abs() < 5.0 * albedo.standard_error, "{albedo:?}");
        assert_eq!(m.leaf_count(), 2);
    }

    /// Two sides: each side answers with its own material, seen from its front; a one-sided
    /// member alone is black from behind.
    #[test]
    fn two_sided_picks_the_viewers_side() {
        let q = TextureQuery::default();
        let card = Material::TwoSided(Box::new(TwoSided { front: diffuse(0.8), back: diffuse(0.2) }));
        let (front, back) = (Vec3::new(0.2, 0.1, 0.9).normalize(), Vec3::new(0.2, 0.1, -0.9).normalize());
        let lit = |wo: Vec3| albedo(&card.bsdf(&q, wo, N, N), wo, 1000, 6).mean;
        assert!((lit(front) - 0.8).abs() < 1e-5 && (lit(back) - 0.2).abs() < 1e-5);
        let wi = Vec3::new(0.0, 0.0, -1.0);
        assert!(card.bsdf(&q, back, N, N).eval(back, wi).x > 0.0);
        assert_eq!(diffuse(0.8).bsdf(&q, back, N, N).eval(back, wi), Rgb::ZERO);
        assert!(card.lambert().is_none() && diffuse(0.8).lambert().is_some_and(|(_, one_sided)| one_sided));
        let both = Material::TwoSided(Box::new(TwoSided { front: diffuse(0.8), back: diffuse(0.8) }));
        assert!(both.lambert().is_some_and(|(_, one_sided)| !one_sided), "the wavefront serves both");
    }

    #[test]
    fn emitters_emit_on_their_side() {
        let lamp = Material::Emitter(Box::new(Emitter {
            radiance: Texture::from(1.0),
            two_sided: false,
            surface: diffuse(0.5),
        }));
        let query = TextureQuery::default;
        assert_eq!(lamp.emitted(N, N, query), Rgb::ONE);
        assert_eq!(lamp.emitted(-N, N, query), Rgb::ZERO);
        assert_eq!(lamp.emission(), (Rgb::ONE, false));
        assert!(lamp.emission_texture().is_none());
    }

    /// Phong's highlight counts toward the Monte Carlo integrators' energy, not Whitted's:
    /// k_d 0.8 with k_s 0.5 gains light as a lobe (`highlight_warning`) though its recursing
    /// lobes do not (`energy_warning`); k_d 0.5 with k_s 0.3 is sound.
    #[test]
    fn the_highlight_counts_for_the_monte_carlo_integrators_alone() {
        let phong = |kd: f32, ks: f32| {
            Material::Phong(Phong { diffuse: Texture::from(kd), specular: Texture::from(ks), ..Phong::default() })
        };
        let bright = phong(0.8, 0.5);
        assert!(bright.energy_warning("m").is_none());
        let w = bright.highlight_warning("m").expect("1.3 > 1");
        assert!(w.contains("k_d + k_s + k_r + k_t = 1.3"), "{w}");
        assert!(phong(0.5, 0.3).highlight_warning("m").is_none());
        // Both sums above 1: `energy_warning` says it, once.
        assert!(phong(1.2, 0.3).highlight_warning("m").is_none() && phong(1.2, 0.3).energy_warning("m").is_some());
    }

    /// A textured radiance is read where the query says; its mean stands for it in the light's
    /// power.
    #[test]
    fn a_textured_emitter_emits_its_texture() {
        let checker = crate::textures::Checker::new(Rgb::splat(1.0), Rgb::splat(3.0), glam::Vec2::splat(2.0));
        let radiance = Texture::Checker(Box::new(checker));
        let lamp = Material::Emitter(Box::new(Emitter { radiance, two_sided: true, surface: diffuse(0.5) }));
        let at = |u: f32, v: f32| move || TextureQuery { uv: glam::Vec2::new(u, v), ..Default::default() };
        assert_eq!(lamp.emitted(N, N, at(0.25, 0.25)), Rgb::splat(1.0));
        assert_eq!(lamp.emitted(-N, N, at(0.75, 0.25)), Rgb::splat(3.0), "two-sided");
        assert_eq!(lamp.emission(), (Rgb::splat(2.0), true));
        assert!(lamp.emission_texture().is_some());
    }

    /// Whitted reads the wrappers as their BSDFs combine members: a blend's child rays are
    /// the members' weighed by the blend (each with its own Fresnel factor: a metal and glass,
    /// not glass's rule applied to the metal's colour), a mask's clear part goes on unbent
    /// beside its glass's refraction, and each side of a two-sided material is its own.
    #[test]
    fn whitted_reads_the_wrappers_as_their_bsdfs() {
        let (eta, k) = named_metal("Au").unwrap();
        let gold = || Material::Conductor(Conductor { eta, k, specular: Texture::Constant(Rgb::ONE) });
        let glass = || {
            Material::Dielectric(Dielectric {
                eta: 1.5,
                specular_reflectance: Texture::Constant(Rgb::ONE),
                specular_transmittance: Texture::Constant(Rgb::new(0.6, 0.9, 1.0)),
            })
        };
        let blend =
            |w: f32| Material::Blend(Box::new(Blend { weight: Texture::from(w), first: gold(), second: glass() }));
        let mask = Material::Mask(Box::new(Mask { opacity: Texture::from(0.7), material: glass() }));
        let card = Material::TwoSided(Box::new(TwoSided { front: diffuse(0.5), back: gold() }));
        for degrees in [0.0, 50.0, 80.0] {
            check_whitted(&blend(0.3), true, degrees, 21);
            check_whitted(&blend(0.8), true, degrees, 22);
            check_whitted(&mask, true, degrees, 23);
            check_whitted(&card, false, degrees, 24);
        }
        // Inside the masked glass: its own index, whatever the clear part's share.
        let thin = Material::Mask(Box::new(Mask { opacity: Texture::from(0.3), material: glass() }));
        check_whitted(&thin, false, 30.0, 25);
        assert_eq!(thin.whitted_at(&TextureQuery::default(), false, 0.8).ior, 1.5);
    }
}
