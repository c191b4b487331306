//! The path tracer as a wavefront: a tile's paths advance together, one bounce at a time, and
//! the stages between the ray queries run eight paths at once in SIMD lanes. The lane routines
//! are the scalar code's own, written once against `crate::lanes::Lanes` (the scalar code runs
//! them at one lane): the ray offsets, the frame, the warps, the MIS weights, and the BSDFs
//! the lanes shade (Lambert's lobe, the rough conductor: `RoughConductorLanes`).
//!
//! It serves every scene: any geometry, any material, every kind of light. Where the scene
//! allows, the lanes do everything: the surface of flat or smooth triangles with constant
//! colours, and lights that are all triangles sampled by area (the Cornell box). Otherwise
//! each lane asks the scalar code for what differs (the surface of a sphere or a textured
//! mesh; the light sample, `Lights::sample_li`, and its shadow ray, when some light is a
//! point, spot, directional, environment or sphere light, or triangles are sampled by solid
//! angle) and the rest stays in lanes. A round's paths are grouped by their BSDF's lane kind
//! (`LaneKind`: Lambert's lobe; rough conductors, GGX or Beckmann, of any widths); a path on
//! any other surface (mirror, glass, the plastics, principled, the course's mixed material, a
//! normal or bump map) takes that bounce from the scalar code, `PathTracer::bounce`, while the
//! others take theirs in lanes.
//!
//! It is that same estimator, operation for operation: each lane computes the bits the scalar
//! code computes and, while its path goes on, draws the same numbers in the same order (a path
//! that ends may leave a number undrawn that the scalar code draws, or the reverse, which
//! nothing reads: every pixel sample has its own sampler). So the image is bit-identical
//! (tests/wavefront.rs) and every test of the path tracer holds for both. The closest-hit and
//! shadow queries stay one path at a time (the BVH's own SIMD runs across a node's children).

use glam::{Vec2, Vec3};
use wide::{f32x8, i32x8, CmpEq, CmpGe, CmpGt, CmpLe, CmpLt};

use super::estimators::{escaped_lanes, power_heuristic_lanes, Scatter};
use super::path::{BounceDraws, PathState, PathTracer};
use super::{CameraExplanation, Integrator, RayCounts, SampleContext};
use crate::geometry::{offset_ray_origin_lanes, Ray};
use crate::lanes::{Lanes, Vec3x8, LANES};
use crate::lights::{area_to_solid_angle_lanes, TriangleEmitter, TriangleSampling};
use crate::materials::{
    luminance, tangent_along_lanes, Coat, CoatTables, CoatTransmittance, ConductorLanes, DielectricLanes, DiffuseLanes,
    DiffuseTransmissionLanes, Distribution, LaneBsdfSample, LaneFrame, MapShadowing, Material, MicrofacetLanes,
    PlasticLanes, PrincipledLanes, PrincipledPoint, PrincipledThinLanes, PrincipledThinPoint, RoughConductorLanes,
    RoughDielectricLanes, RoughPlasticLanes, ThinDielectricLanes,
};
use crate::sampling::Sampler;
use crate::scene::{PrimitiveHit, Scene, Spawn, SHADOW_EPSILON};
use crate::shapes::barycentric_point_lanes;
use crate::textures::{Texture, TextureQuery};
use crate::Rgb;

/// A bounce's numbers, at the scalar path tracer's offsets (`BounceDraws`).
const LIGHT: usize = BounceDraws::LIGHT;
const LIGHT_POINT: usize = BounceDraws::LIGHT_POINT;
const LOBE: usize = BounceDraws::LOBE;
const DIRECTION: usize = BounceDraws::DIRECTION;
const ROULETTE: usize = BounceDraws::ROULETTE;
const DRAWS: usize = BounceDraws::COUNT;

/// Lights up to this many are chosen in the lanes by counting, more (or a CDF that is not
/// sorted, from negative powers) by binary search.
const SHORT_CDF: usize = 32;
/// Triangle emitters up to this many (with the black one) are blended into the lanes that
/// chose them, more gathered lane by lane.
const BLENDED_EMITTERS: usize = 8;

/// The BSDFs the lanes shade themselves; a path on any other surface takes its bounce from
/// the scalar code. A round's paths are grouped by kind, so the eight lanes of a bounce share
/// one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum LaneKind {
    /// Lambert's lobe alone (`Material::lambert`).
    Lambert,
    /// A rough conductor (`RoughConductorLanes`) of one microfacet distribution.
    RoughConductor(Distribution),
    /// A rough plastic (`RoughPlasticLanes`) of one microfacet distribution.
    RoughPlastic(Distribution),
    /// Rough glass (`RoughDielectricLanes`) of one microfacet distribution.
    RoughDielectric(Distribution),
    /// A smooth conductor's mirror (`ConductorLanes`).
    Conductor,
    /// Smooth glass (`DielectricLanes`).
    Dielectric,
    /// Disney's principled BSDF as Mitsuba defines it (`PrincipledLanes`).
    Principled,
    /// Its thin sheet (`PrincipledThinLanes`).
    PrincipledThin,
    /// Smooth plastic (`PlasticLanes`): a mirror and a diffuse base, chosen lane by lane.
    Plastic,
    /// A thin sheet of glass (`ThinDielectricLanes`).
    ThinDielectric,
    /// Lambert's lobe on both sides (`DiffuseTransmissionLanes`).
    DiffuseTransmission,
    /// Anything else: the scalar code's bounce.
    Scalar,
}

impl LaneKind {
    /// The kinds of the lanes' own bounces, in the order a round takes them.
    const IN_LANES: [LaneKind; 14] = [
        LaneKind::Lambert,
        LaneKind::RoughConductor(Distribution::Ggx),
        LaneKind::RoughConductor(Distribution::Beckmann),
        LaneKind::RoughPlastic(Distribution::Ggx),
        LaneKind::RoughPlastic(Distribution::Beckmann),
        LaneKind::RoughDielectric(Distribution::Ggx),
        LaneKind::RoughDielectric(Distribution::Beckmann),
        LaneKind::Conductor,
        LaneKind::Dielectric,
        LaneKind::Principled,
        LaneKind::PrincipledThin,
        LaneKind::Plastic,
        LaneKind::ThinDielectric,
        LaneKind::DiffuseTransmission,
    ];

    fn of(material: &Material) -> Self {
        match material {
            _ if material.lambert().is_some() => LaneKind::Lambert,
            Material::RoughConductor(m) => LaneKind::RoughConductor(m.distribution),
            Material::RoughPlastic(m) => LaneKind::RoughPlastic(m.distribution),
            Material::RoughDielectric(m) => LaneKind::RoughDielectric(m.distribution),
            Material::Conductor(_) => LaneKind::Conductor,
            Material::Dielectric(_) => LaneKind::Dielectric,
            Material::Principled(_) => LaneKind::Principled,
            Material::PrincipledThin(_) => LaneKind::PrincipledThin,
            Material::Plastic(_) => LaneKind::Plastic,
            Material::ThinDielectric(_) => LaneKind::ThinDielectric,
            Material::DiffuseTransmission(_) => LaneKind::DiffuseTransmission,
            // A map over a material of a lane kind: the lanes tilt its frame (one map: a map
            // inside a map keeps the inner one's shadowing).
            Material::NormalMap(_) | Material::BumpMap(_) => {
                let inner = material.unmapped();
                match std::ptr::eq(inner.unmapped(), inner) {
                    true => LaneKind::of(inner),
                    false => LaneKind::Scalar,
                }
            }
            _ => LaneKind::Scalar,
        }
    }

    /// The place of a lane kind in `IN_LANES`.
    fn group(self) -> usize {
        match self {
            LaneKind::Lambert | LaneKind::Scalar => 0,
            LaneKind::RoughConductor(Distribution::Ggx) => 1,
            LaneKind::RoughConductor(Distribution::Beckmann) => 2,
            LaneKind::RoughPlastic(Distribution::Ggx) => 3,
            LaneKind::RoughPlastic(Distribution::Beckmann) => 4,
            LaneKind::RoughDielectric(Distribution::Ggx) => 5,
            LaneKind::RoughDielectric(Distribution::Beckmann) => 6,
            LaneKind::Conductor => 7,
            LaneKind::Dielectric => 8,
            LaneKind::Principled => 9,
            LaneKind::PrincipledThin => 10,
            LaneKind::Plastic => 11,
            LaneKind::ThinDielectric => 12,
            LaneKind::DiffuseTransmission => 13,
        }
    }
}

/// A material's lobe at a point, as the lanes read it.
#[derive(Clone, Copy, Debug)]
enum LaneLobe<'s> {
    Lambert {
        diffuse: Rgb,
    },
    /// Widths along ∂p/∂u (`dpdu`, where they differ) and across it, η, k and the specular
    /// colour.
    RoughConductor {
        alpha_u: f32,
        alpha_v: f32,
        eta: Rgb,
        k: Rgb,
        specular: Rgb,
        dpdu: Vec3,
    },
    /// Widths along ∂p/∂u (`dpdu`, where they differ) and across it, the index inside over
    /// outside, the reflectance and the transmittance.
    RoughDielectric {
        alpha_u: f32,
        alpha_v: f32,
        eta: f32,
        reflectance: Rgb,
        transmittance: Rgb,
        dpdu: Vec3,
    },
    /// η, k and the specular colour.
    Conductor {
        eta: Rgb,
        k: Rgb,
        specular: Rgb,
    },
    /// The index inside over outside, the reflectance and the transmittance.
    Dielectric {
        eta: f32,
        reflectance: Rgb,
        transmittance: Rgb,
    },
    /// The parameters at the point, and ∂p/∂u (where the widths differ).
    Principled {
        point: PrincipledPoint,
        dpdu: Vec3,
    },
    /// The thin sheet's parameters at the point, and ∂p/∂u (where the widths differ).
    PrincipledThin {
        point: PrincipledThinPoint,
        dpdu: Vec3,
    },
    /// n_ext / n_int, the reflectance and the transmittance.
    ThinDielectric {
        eta: f32,
        reflectance: Rgb,
        transmittance: Rgb,
    },
    /// The two sides' albedos.
    DiffuseTransmission {
        reflectance: Rgb,
        transmittance: Rgb,
    },
    /// The coat's colours and index.
    Plastic {
        coat: Coat,
    },
    /// The coat's colours and index (`Coat`), its width and transmittance table.
    RoughPlastic {
        coat: Coat,
        alpha: f32,
        tables: &'s CoatTables,
    },
}

/// A material as the lanes read it.
#[derive(Clone, Copy, Debug)]
struct LaneMaterial<'s> {
    lobe: LaneLobe<'s>,
    /// The BSDF has a lobe that reflects; a black Lambert lobe ends the path.
    reflects: bool,
    /// Black from behind (Mitsuba's `diffuse`, every conductor): the path ends on the back.
    one_sided: bool,
    emission: Rgb,
    two_sided: bool,
}

impl<'s> LaneMaterial<'s> {
    /// What lanes without a hit read.
    const BLACK: Self = Self {
        lobe: LaneLobe::Lambert { diffuse: Rgb::ZERO },
        reflects: false,
        one_sided: false,
        emission: Rgb::ZERO,
        two_sided: false,
    };

    fn lambert(diffuse: Rgb, one_sided: bool, emission: Rgb, two_sided: bool) -> Self {
        Self { lobe: LaneLobe::Lambert { diffuse }, reflects: luminance(diffuse) > 0.0, one_sided, emission, two_sided }
    }

    /// A material of a lane kind evaluated at a point (black for the scalar code's: the lanes
    /// never read one), with the surface's ∂p/∂u and ∂p/∂v where the material needs them, as
    /// `Vertex::bsdf` queries it (the emission without them, as `Vertex::emitted`).
    fn at(material: &'s Material, query: &TextureQuery, (dpdu, dpdv): (Vec3, Vec3)) -> Self {
        if !std::ptr::eq(material.unmapped(), material) {
            // Under a map: the material's lobe (the lanes tilt its frame), no emission.
            let lobe = Self::at(material.unmapped(), query, (dpdu, dpdv));
            return Self { emission: Rgb::ZERO, two_sided: false, ..lobe };
        }
        let (emission, two_sided) = material.emission_at(|| *query);
        let query = &TextureQuery { dpdu, dpdv, ..*query };
        if let Some((diffuse, one_sided)) = material.lambert() {
            return Self::lambert(diffuse.evaluate(query), one_sided, emission, two_sided);
        }
        match material {
            Material::RoughConductor(m) => {
                let (alpha_u, alpha_v, specular) = m.widths_and_specular(query);
                let (eta, k, dpdu) = (m.conductor.eta, m.conductor.k, query.dpdu);
                let lobe = LaneLobe::RoughConductor { alpha_u, alpha_v, eta, k, specular, dpdu };
                Self { lobe, reflects: true, one_sided: true, emission, two_sided }
            }
            Material::Conductor(m) => {
                let lobe = LaneLobe::Conductor { eta: m.eta, k: m.k, specular: m.specular.evaluate(query) };
                Self { lobe, reflects: true, one_sided: true, emission, two_sided }
            }
            Material::Dielectric(m) => {
                let (reflectance, transmittance) =
                    (m.specular_reflectance.evaluate(query), m.specular_transmittance.evaluate(query));
                let lobe = LaneLobe::Dielectric { eta: m.eta, reflectance, transmittance };
                Self { lobe, reflects: true, one_sided: false, emission, two_sided }
            }
            Material::RoughDielectric(m) => {
                let (alpha_u, alpha_v, reflectance, transmittance) = m.widths_and_colours(query);
                let (eta, dpdu) = (m.dielectric.eta, query.dpdu);
                let lobe = LaneLobe::RoughDielectric { alpha_u, alpha_v, eta, reflectance, transmittance, dpdu };
                Self { lobe, reflects: true, one_sided: false, emission, two_sided }
            }
            Material::Principled(m) => {
                let point = m.point(query);
                // Black from behind where it does not transmit (`PrincipledLanes::inactive`):
                // the path ends there, as the scalar code's, which draws no light numbers there.
                let one_sided = (1.0 - point.metallic) * point.spec_trans <= 0.0;
                let lobe = LaneLobe::Principled { point, dpdu: query.dpdu };
                Self { lobe, reflects: true, one_sided, emission, two_sided }
            }
            Material::PrincipledThin(m) => {
                let lobe = LaneLobe::PrincipledThin { point: m.point(query), dpdu: query.dpdu };
                Self { lobe, reflects: true, one_sided: false, emission, two_sided }
            }
            Material::ThinDielectric(m) => {
                let d = &m.sheet;
                let (reflectance, transmittance) =
                    (d.specular_reflectance.evaluate(query), d.specular_transmittance.evaluate(query));
                let lobe = LaneLobe::ThinDielectric { eta: 1.0 / d.eta, reflectance, transmittance };
                Self { lobe, reflects: true, one_sided: false, emission, two_sided }
            }
            Material::DiffuseTransmission(m) => {
                let (reflectance, transmittance) = (m.reflectance.evaluate(query), m.transmittance.evaluate(query));
                // Black on both sides: no lobe, the path ends (`DiffuseTransmissionLanes::lit`).
                let albedo = |c: Rgb| crate::textures::luminance(c).max(0.0);
                let reflects = albedo(reflectance) + albedo(transmittance) > 0.0;
                let lobe = LaneLobe::DiffuseTransmission { reflectance, transmittance };
                Self { lobe, reflects, one_sided: false, emission, two_sided }
            }
            Material::Plastic(m) => {
                let lobe = LaneLobe::Plastic { coat: m.coat(query) };
                Self { lobe, reflects: true, one_sided: true, emission, two_sided }
            }
            Material::RoughPlastic(m) => {
                let (coat, tables) = m.coat_at(query);
                // `Microfacet::separable`'s floor on the width, as the scalar lobe has it.
                let lobe = LaneLobe::RoughPlastic { coat, alpha: m.alpha.max(1e-4), tables };
                Self { lobe, reflects: true, one_sided: true, emission, two_sided }
            }
            _ => Self::BLACK,
        }
    }

    /// A material of a lane kind whose colours and width are constant, evaluated once; black
    /// for the scalar code's (the lanes never read it); `None` for a textured one.
    fn constant(material: &'s Material) -> Option<Self> {
        let constant = |t: &Texture| matches!(t, Texture::Constant(_));
        match (LaneKind::of(material), material) {
            (LaneKind::Scalar, _) => Some(Self::BLACK),
            (LaneKind::RoughConductor(_), Material::RoughConductor(m)) => {
                // One width both ways: the frame does not turn to ∂p/∂u, which the lanes'
                // flat surfaces do not compute.
                let fixed = constant(&m.alpha_u) && m.alpha_v == m.alpha_u && constant(&m.conductor.specular);
                fixed.then(|| Self::at(material, &TextureQuery::default(), (Vec3::ZERO, Vec3::ZERO)))
            }
            (LaneKind::Conductor, Material::Conductor(m)) => {
                constant(&m.specular).then(|| Self::at(material, &TextureQuery::default(), (Vec3::ZERO, Vec3::ZERO)))
            }
            (LaneKind::Dielectric, Material::Dielectric(m)) => {
                let fixed = constant(&m.specular_reflectance) && constant(&m.specular_transmittance);
                fixed.then(|| Self::at(material, &TextureQuery::default(), (Vec3::ZERO, Vec3::ZERO)))
            }
            (LaneKind::RoughDielectric(_), Material::RoughDielectric(m)) => {
                let d = &m.dielectric;
                let fixed = constant(&m.alpha_u)
                    && m.alpha_v == m.alpha_u
                    && constant(&d.specular_reflectance)
                    && constant(&d.specular_transmittance);
                fixed.then(|| Self::at(material, &TextureQuery::default(), (Vec3::ZERO, Vec3::ZERO)))
            }
            (LaneKind::ThinDielectric, Material::ThinDielectric(m)) => {
                let fixed = constant(&m.sheet.specular_reflectance) && constant(&m.sheet.specular_transmittance);
                fixed.then(|| Self::at(material, &TextureQuery::default(), (Vec3::ZERO, Vec3::ZERO)))
            }
            (LaneKind::DiffuseTransmission, Material::DiffuseTransmission(m)) => {
                let fixed = constant(&m.reflectance) && constant(&m.transmittance);
                fixed.then(|| Self::at(material, &TextureQuery::default(), (Vec3::ZERO, Vec3::ZERO)))
            }
            (LaneKind::Plastic, Material::Plastic(m)) => {
                let fixed = constant(&m.diffuse) && constant(&m.specular);
                fixed.then(|| Self::at(material, &TextureQuery::default(), (Vec3::ZERO, Vec3::ZERO)))
            }
            (LaneKind::RoughPlastic(_), Material::RoughPlastic(m)) => {
                let fixed = constant(&m.plastic.diffuse) && constant(&m.plastic.specular);
                fixed.then(|| Self::at(material, &TextureQuery::default(), (Vec3::ZERO, Vec3::ZERO)))
            }
            (LaneKind::Principled, Material::Principled(m)) => {
                // Isotropic too: the flat surfaces' frames do not turn to ∂p/∂u.
                let textures = [
                    &m.base_color,
                    &m.roughness,
                    &m.anisotropic,
                    &m.metallic,
                    &m.spec_trans,
                    &m.spec_tint,
                    &m.sheen,
                    &m.sheen_tint,
                    &m.flatness,
                    &m.clearcoat,
                    &m.clearcoat_gloss,
                ];
                let fixed = textures.into_iter().all(constant) && m.anisotropic == Texture::Constant(Rgb::ZERO);
                fixed.then(|| Self::at(material, &TextureQuery::default(), (Vec3::ZERO, Vec3::ZERO)))
            }
            (LaneKind::PrincipledThin, Material::PrincipledThin(m)) => {
                let textures = [
                    &m.base_color,
                    &m.roughness,
                    &m.anisotropic,
                    &m.spec_trans,
                    &m.diff_trans,
                    &m.eta,
                    &m.spec_tint,
                    &m.sheen,
                    &m.sheen_tint,
                    &m.flatness,
                ];
                let fixed = textures.into_iter().all(constant) && m.anisotropic == Texture::Constant(Rgb::ZERO);
                fixed.then(|| Self::at(material, &TextureQuery::default(), (Vec3::ZERO, Vec3::ZERO)))
            }
            _ => {
                let (Texture::Constant(diffuse), one_sided) = material.lambert()? else { return None };
                if material.emission_texture().is_some() {
                    return None;
                }
                let (emission, two_sided) = material.emission();
                Some(Self::lambert(*diffuse, one_sided, emission, two_sided))
            }
        }
    }
}

/// The path tracer, a tile's paths at a time as a wavefront (`--integrator path`): the same
/// image as `PathTracer` one path at a time, bit for bit.
#[derive(Clone, Copy, Debug)]
pub struct WavefrontPathTracer {
    pub tracer: PathTracer,
}

impl Integrator for WavefrontPathTracer {
    /// One path, by the scalar code.
    fn radiance(&self, scene: &Scene, ray: &Ray, context: &mut SampleContext) -> Rgb {
        self.tracer.radiance(scene, ray, context)
    }

    fn radiance_tile(&self, scene: &Scene, rays: &[Ray], contexts: &mut [SampleContext], out: &mut [Rgb]) {
        Wavefront::new(&self.tracer, scene).radiance_tile(rays, contexts, out);
    }

    /// The path by the scalar code, which the lanes follow bit for bit.
    fn explain(&self, scene: &Scene, ray: &Ray, context: &mut SampleContext) -> Option<CameraExplanation> {
        Integrator::explain(&self.tracer, scene, ray, context)
    }
}

/// The path tracer's wavefront over one scene.
struct Wavefront<'a> {
    scene: &'a Scene,
    /// Every material, when all are constant and every primitive is a triangle in world space:
    /// then the lanes compute the surfaces themselves.
    flat: Option<Vec<LaneMaterial<'a>>>,
    /// The lights as triangles, then a black one for lanes without a light, when all are
    /// triangles sampled by area: then the lanes sample them themselves.
    emitters: Option<&'a [TriangleEmitter]>,
    /// The lights' CDF, when the lanes choose among them by counting: at most `SHORT_CDF`
    /// entries, sorted.
    counted_cdf: Option<&'a [f32]>,
    /// For each material, the lanes' kind of its BSDF, when some material is not Lambert's.
    kinds: Option<Vec<LaneKind>>,
    /// For the scalar bounces, and the depth limits.
    tracer: PathTracer,
}

/// One path between bounces. Aligned to cache lines (128 bytes where 116 would do): a tile's
/// paths outgrow the L1 cache, and unaligned, half of them straddled three lines.
#[derive(Clone, Copy, Debug)]
#[repr(align(64))]
struct Path {
    /// The ray to trace next.
    ray: Ray,
    throughput: Rgb,
    radiance: Rgb,
    /// Bounces so far.
    depth: u32,
    /// The last scattering point, its shading normal, and the BSDF's density of the direction
    /// sampled there (for the MIS weight of emission found next), when `depth` > 0; the density
    /// is infinite after a delta lobe (a mirror or a refraction), which the power heuristic
    /// turns into weight 1, as the scalar code gives emission found through one.
    last_point: Vec3,
    last_normal: Vec3,
    last_pdf: f32,
    /// The closest hit of `ray`.
    hit: PrimitiveHit,
    /// The product of the refractions' relative η², for Russian roulette (last: the fields
    /// above keep the places the diffuse scenes' speed was measured with).
    eta_scale: f32,
}

impl Path {
    /// A path before its camera ray is traced (`ray` to be set).
    const FRESH: Path = Path {
        ray: Ray { origin: Vec3::ZERO, direction: Vec3::Z, t_min: 0.0, t_max: f32::INFINITY },
        throughput: Rgb::ONE,
        radiance: Rgb::ZERO,
        depth: 0,
        last_point: Vec3::ZERO,
        last_normal: Vec3::ZERO,
        last_pdf: 0.0,
        hit: PrimitiveHit::NONE,
        eta_scale: 1.0,
    };
}

/// The surfaces the lanes hit, as `SurfaceGeometry` has them, and the materials there.
struct Surfaces<'r, 's> {
    point: Vec3x8,
    error: Vec3x8,
    geometric: Vec3x8,
    shading: Vec3x8,
    material: LaneMaterials<'r, 's>,
    /// Where a normal or bump map tilts the shading normal: the lanes it does (a mask) and
    /// the normal it gives them (turned toward the viewer), for the BSDF's frame.
    mapped: Option<(f32x8, Vec3x8)>,
}

/// The lanes' materials: references into a flat scene's table (no copies on the way), or
/// evaluated at the hits. (A value on the stack for one bounce: the variants' sizes may
/// differ.)
#[allow(clippy::large_enum_variant)]
enum LaneMaterials<'r, 's> {
    Flat([&'r LaneMaterial<'s>; LANES]),
    Evaluated([LaneMaterial<'s>; LANES]),
}

/// The lights the lanes sampled, as `LightSample` has them, and the shadow rays toward them.
struct LightPoints {
    /// Lanes with a sample (`Lights::sample_li` gave one).
    sampled: f32x8,
    direction: Vec3x8,
    radiance: Vec3x8,
    pdf: f32x8,
    /// Lanes whose light is a delta light: not weighed against BSDF sampling.
    delta: f32x8,
    shadow_rays: [Ray; LANES],
}

impl<'a> Wavefront<'a> {
    /// The wavefront for `scene`. It runs once per tile, so it looks at the materials but not
    /// at every object.
    fn new(tracer: &PathTracer, scene: &'a Scene) -> Self {
        let kinds: Vec<LaneKind> = scene.materials().iter().map(LaneKind::of).collect();
        let kinds = kinds.iter().any(|&k| k != LaneKind::Lambert).then_some(kinds);
        let flat = if scene.geometry().all_triangles() {
            scene.materials().iter().map(LaneMaterial::constant).collect::<Option<Vec<_>>>()
        } else {
            None
        };
        let lights = scene.lights();
        let emitters = lights.triangle_table().filter(|_| lights.triangle_sampling() == TriangleSampling::Area);
        let cdf = lights.selection_cdf();
        let counted_cdf = (!cdf.is_empty() && cdf.len() <= SHORT_CDF && cdf.is_sorted()).then_some(cdf);
        Self { scene, flat, emitters, counted_cdf, kinds, tracer: *tracer }
    }

    /// The radiance along each camera ray, `out[i]` for `rays[i]` drawing from `contexts[i]`.
    fn radiance_tile(&self, rays: &[Ray], contexts: &mut [SampleContext], out: &mut [Rgb]) {
        // Each path's ray written into a fresh path in place: a path built whole and then
        // moved into the vector was copied with loads wider than the stores that had just
        // built it, a stall (store forwarding fails) per camera sample.
        let mut paths = vec![Path::FRESH; rays.len()];
        for (path, &ray) in paths.iter_mut().zip(rays) {
            path.ray = ray;
        }
        let mut active: Vec<u32> = (0..paths.len() as u32).collect();
        let mut hits = Vec::with_capacity(paths.len());
        let mut escaped = Vec::new();
        let mut other_kinds: [Vec<u32>; LaneKind::IN_LANES.len() - 1] = Default::default();
        // The rays traced, counted for the tile: each path's own count was another cache line
        // touched per query.
        let mut counts = RayCounts::default();
        while !active.is_empty() {
            hits.clear();
            // The paths stand at the same depth: camera rays in the first round.
            let depth = paths[active[0] as usize].depth;
            match depth {
                0 => counts.camera += active.len() as u64,
                _ => counts.reflection += active.len() as u64,
            }
            escaped.clear();
            for &i in &active {
                let path = &mut paths[i as usize];
                // The query narrows the path's own ray, as the scalar code narrows the copy it
                // then hands to the surface. A fresh copy's fields would still be in the store
                // buffer when the query loads them as a vector: a stall (store forwarding
                // fails) of every closest hit.
                if self.scene.geometry().closest_primitive_into(&mut path.ray, &mut path.hit) {
                    hits.push(i);
                } else {
                    escaped.push(i);
                }
            }
            for chunk in escaped.chunks(LANES) {
                self.add_escaped(chunk, &mut paths);
            }
            active.clear();
            if let Some(kinds) = &self.kinds {
                // Paths on surfaces the lanes do not model take their bounce from the scalar
                // code; the others are grouped by kind (Lambert's stay in `hits`).
                let objects = self.scene.geometry().objects();
                other_kinds.iter_mut().for_each(Vec::clear);
                hits.retain(|&i| {
                    let (path, context) = (&mut paths[i as usize], &mut contexts[i as usize]);
                    match kinds[objects[path.hit.object as usize].material_at(path.hit.at.inner) as usize] {
                        LaneKind::Lambert => return true,
                        LaneKind::Scalar => {
                            if self.scalar_bounce(path, context) {
                                active.push(i);
                            }
                        }
                        kind => other_kinds[kind.group() - 1].push(i),
                    }
                    false
                });
            }
            for (kind, group) in LaneKind::IN_LANES.into_iter().zip(std::iter::once(&hits).chain(&other_kinds)) {
                for chunk in group.chunks(LANES) {
                    counts.shadow += self.bounce(chunk, depth, kind, &mut paths, contexts, &mut active);
                }
            }
        }
        for (out, path) in out.iter_mut().zip(&paths) {
            *out = path.radiance;
        }
        if let Some(first) = contexts.first_mut() {
            first.rays.add(&counts);
        }
    }

    /// What the (up to eight) paths `chunk`, which left the scene, find there, added to their
    /// radiance: weighed against light sampling from the last bounce, as the scalar code weighs
    /// it (a delta bounce's density is infinite), and read for the eight at once.
    fn add_escaped(&self, chunk: &[u32], paths: &mut [Path]) {
        let path = |k: usize| &paths[chunk[if k < chunk.len() { k } else { 0 }] as usize];
        let weighed = mask(|k| path(k).depth > 0 && path(k).last_pdf != f32::INFINITY);
        let direction = Vec3x8::from_fn(|k| path(k).ray.direction);
        let (radiance, weight) = escaped_lanes(self.scene, direction, per_lane(|k| path(k).last_pdf), weighed);
        for (k, &i) in chunk.iter().enumerate() {
            let path = &mut paths[i as usize];
            path.radiance += path.throughput * radiance.lane(k) * weight.as_array_ref()[k];
        }
    }

    /// One bounce of the (up to eight) paths `chunk`, which hit something: emission found,
    /// next-event estimation, the BSDF sample and Russian roulette. The paths that go on are
    /// added to `active`. Returns the number of shadow rays traced. The paths have all taken
    /// `depth` bounces (they start together and take one per round).
    fn bounce(
        &self,
        chunk: &[u32],
        depth: u32,
        kind: LaneKind,
        paths: &mut [Path],
        contexts: &mut [SampleContext],
        active: &mut Vec<u32>,
    ) -> u64 {
        let scene = self.scene;
        let n = chunk.len();
        // Lanes past the chunk's end repeat its first path; nothing of theirs is kept.
        let index: [usize; LANES] = std::array::from_fn(|k| chunk[if k < n { k } else { 0 }] as usize);
        // Read in place: a copy of the eight paths cost more than the reads. Each lane's
        // reference is found (and bounds-checked) once.
        let lane_paths: [&Path; LANES] = index.map(|i| &paths[i]);
        let path = |k: usize| lane_paths[k];
        debug_assert!((0..n).all(|k| path(k).depth == depth), "the paths of a round stand at the same depth");
        let zero = f32x8::ZERO;

        let wo = -Vec3x8::from_fn(|k| path(k).ray.direction).normalize();
        let Surfaces { point, error, geometric, shading, material: materials, mapped } = match &self.flat {
            Some(materials) => self.flat_surfaces(&path, materials),
            None => self.surfaces(&path, n),
        };
        let material: [&LaneMaterial; LANES] = match &materials {
            LaneMaterials::Flat(flat) => *flat,
            LaneMaterials::Evaluated(evaluated) => evaluated.each_ref(),
        };
        let mut throughput = Vec3x8::from_fn(|k| path(k).throughput);
        let mut radiance = Vec3x8::from_fn(|k| path(k).radiance);

        // Emission found, weighed against light sampling from the last bounce (not at the first).
        let wo_dot_n = wo.dot(geometric);
        let emits_toward = mask(|k| material[k].two_sided) | wo_dot_n.cmp_gt(zero);
        let emitted = Vec3x8::select(emits_toward, Vec3x8::from_fn(|k| material[k].emission), Vec3x8::ZERO);
        let found = emitted.nonzero();
        if found.any() {
            // At the first hit the camera found it (weight 1): no light sample to weigh against.
            let weight = if depth == 0 {
                f32x8::ONE
            } else {
                let light_pdf = match self.emitters {
                    Some(emitters) => {
                        let none = emitters.len() - 1;
                        let emitter: [&TriangleEmitter; LANES] = std::array::from_fn(|k| {
                            &emitters[scene
                                .lights()
                                .emitter_index(path(k).hit.object, path(k).hit.emitting_prim())
                                .unwrap_or(none)]
                        });
                        let to_light = point - Vec3x8::from_fn(|k| path(k).last_point);
                        let (pdf, seen) = area_to_solid_angle_lanes(
                            per_lane(|k| emitter[k].selection),
                            per_lane(|k| emitter[k].area),
                            to_light,
                            geometric,
                        );
                        (mask(|k| !std::ptr::eq(emitter[k], &emitters[none])) & seen).blend(pdf, zero)
                    }
                    None => per_lane(|k| {
                        let p = path(k);
                        let (hit_point, hit_normal) = (point.lane(k), geometric.lane(k));
                        scene.lights().pdf_area(
                            p.last_point,
                            Some(p.last_normal),
                            p.hit.object,
                            p.hit.emitting_prim(),
                            hit_point,
                            hit_normal,
                        )
                    }),
                };
                power_heuristic_lanes(per_lane(|k| path(k).last_pdf), light_pdf)
            };
            radiance = Vec3x8::select(found, radiance + throughput.mul_lanes(emitted) * weight, radiance);
        }

        // Paths at the maximum depth, on black surfaces and on the backs of one-sided ones end here
        // (the frame's `outside` is wo·n ≥ 0).
        let behind = wo_dot_n.cmp_lt(zero).move_mask();
        let goes_on: [bool; LANES] = std::array::from_fn(|k| {
            let lit = material[k].reflects && !(material[k].one_sided && behind & (1 << k) != 0);
            k < n && depth < self.tracer.max_depth && lit
        });
        // The BSDF's frame (`Frame::new`): both normals turned to wo's side, and the geometric
        // one where the shading normal would face away from the viewer.
        // A map's normal tilts the frame, and shadows the light its tilt would let in past the
        // terminator (`Frame::with_map_shadowing`, after the lobe's own frame is set).
        let frame = LaneFrame::new(wo, mapped.map_or(shading, |(_, normals)| normals), geometric);
        let bsdf = ChunkBsdf::new(kind, &material, &frame, wo);
        let shadowing = match mapped {
            Some((lanes, _)) => {
                let MapShadowing { unmapped, alpha2 } = MapShadowing::new(frame.normal, shading);
                MapShadowing { unmapped, alpha2: lanes.blend(alpha2, zero) }
            }
            None => MapShadowing::NONE,
        };

        // draws[j]: draw j of each lane, at the offsets of `BounceDraws`; where the BSDF has
        // delta lobes alone, the scalar code draws no light numbers, and the lobe's come first.
        let non_delta = bsdf.non_delta();
        let slots_of = |k: usize| -> &[usize] {
            match non_delta[k] {
                true => &[LIGHT, LIGHT_POINT, LIGHT_POINT + 1, LOBE, DIRECTION, DIRECTION + 1, ROULETTE],
                false => &[LOBE, DIRECTION, DIRECTION + 1, ROULETTE],
            }
        };
        let roulette_comes = depth + 1 >= self.tracer.rr_depth;
        let count_of = |slots: &[usize]| if roulette_comes { slots.len() } else { slots.len() - 1 };
        // The lanes that go on draw alike (the paths that end draw what they like, unread).
        let first = goes_on.iter().position(|&on| on);
        let alike = first.filter(|&f| (0..n).all(|k| !goes_on[k] || non_delta[k] == non_delta[f]));
        let mut draws = [f32x8::ZERO; DRAWS];
        match alike {
            Some(f) if n == LANES => {
                // All eight at once (the numbers of paths that end are drawn too, unread).
                let samplers = contexts.get_disjoint_mut(index).expect("eight distinct paths").map(|c| &mut c.sampler);
                let mut drawn = [f32x8::ZERO; DRAWS];
                let (slots, count) = (slots_of(f), count_of(slots_of(f)));
                match count {
                    DRAWS => drawn = Sampler::next_f32_lanes::<DRAWS>(samplers),
                    6 => drawn[..6].copy_from_slice(&Sampler::next_f32_lanes::<6>(samplers)),
                    4 => drawn[..4].copy_from_slice(&Sampler::next_f32_lanes::<4>(samplers)),
                    _ => drawn[..3].copy_from_slice(&Sampler::next_f32_lanes::<3>(samplers)),
                }
                for (&slot, &numbers) in slots.iter().zip(&drawn[..count]) {
                    draws[slot] = numbers;
                }
            }
            _ => {
                let mut columns = [[0f32; LANES]; DRAWS];
                for k in (0..n).filter(|&k| goes_on[k]) {
                    let sampler = &mut contexts[index[k]].sampler;
                    let slots = slots_of(k);
                    for &slot in &slots[..count_of(slots)] {
                        columns[slot][k] = sampler.next_f32();
                    }
                }
                draws = columns.map(f32x8::from);
            }
        }
        debug_assert!(draws[LOBE].cmp_lt(f32x8::ONE).all(), "u_lobe < p_diffuse = 1: the diffuse lobe");
        let draw = |j: usize| draws[j];
        let on = mask(|k| goes_on[k]);

        // Next-event estimation: one light chosen by power, where the BSDF has more than delta
        // lobes.
        let lit: [bool; LANES] = std::array::from_fn(|k| goes_on[k] && non_delta[k]);
        let light = match self.emitters {
            _ if !lit.contains(&true) => None,
            Some(emitters) => self.triangle_light_points(emitters, &lit, &draws, point, error, geometric),
            None => self.light_points(&lit, &draws, [point, error, geometric], shading),
        };
        let mut direct = Vec3x8::ZERO;
        let mut shadow_rays_traced = 0;
        if let Some(LightPoints { sampled, direction: wi, radiance: light_radiance, pdf, delta, shadow_rays }) = light {
            let (f, bsdf_pdf) = bsdf.eval_and_pdf(&frame, wo, wi);
            let f = if mapped.is_some() { f * shadowing.of(wi) } else { f };
            let traced = (sampled & light_radiance.nonzero() & f.nonzero() & pdf.cmp_gt(zero)).move_mask();
            let weight = delta.blend(f32x8::ONE, power_heuristic_lanes(pdf, bsdf_pdf));
            let contribution = Vec3x8::ZERO + f.mul_lanes(light_radiance) * (weight / pdf);
            shadow_rays_traced = traced.count_ones();
            let unoccluded = mask(|k| traced & (1 << k) != 0 && !scene.occluded(&shadow_rays[k]));
            direct = Vec3x8::select(unoccluded, contribution, Vec3x8::ZERO);
        }
        radiance = Vec3x8::select(on, radiance + throughput.mul_lanes(direct), radiance);

        // The BSDF sample.
        let LaneBsdfSample { wi, weight, pdf, valid: scattered, eta_squared, delta } =
            bsdf.sample(&frame, wo, draw(LOBE), draw(DIRECTION), draw(DIRECTION + 1));
        let delta = delta.move_mask();
        let weight = if mapped.is_some() { weight * shadowing.of(wi) } else { weight };
        throughput = throughput.mul_lanes(weight);
        // η² picked up by refraction, for the roulette.
        let eta_scale = per_lane(|k| path(k).eta_scale) * eta_squared;
        // Russian roulette (Mitsuba's rule), from rr_depth bounces on.
        let roulette = if roulette_comes { mask(|_| true) } else { zero };
        let max = match self.kinds {
            // Scaled by η², as the scalar code does: paths that went through glass.
            Some(_) => throughput.max_element() * eta_scale,
            None => throughput.max_element(),
        };
        let survival = max.cmp_lt(f32x8::splat(0.95)).blend(max, f32x8::splat(0.95));
        let killed = roulette & (survival.cmp_le(zero) | draw(ROULETTE).cmp_ge(survival));
        let survivor = Vec3x8 { x: throughput.x / survival, y: throughput.y / survival, z: throughput.z / survival };
        throughput = Vec3x8::select(roulette, survivor, throughput);
        let continues = (on & scattered & !killed & throughput.nonzero()).move_mask();
        let origin = offset_ray_origin_lanes(point, error, geometric, wi);

        for (k, &i) in index.iter().enumerate().take(n) {
            let path = &mut paths[i];
            path.radiance = radiance.lane(k);
            if continues & (1 << k) != 0 {
                path.throughput = throughput.lane(k);
                path.eta_scale = eta_scale.as_array_ref()[k];
                path.ray = Ray::new(origin.lane(k), wi.lane(k));
                path.last_point = point.lane(k);
                path.last_normal = shading.lane(k);
                // A delta lobe's density is infinite (weight 1 for the emission found next).
                path.last_pdf = if delta & (1 << k) != 0 { f32::INFINITY } else { pdf.as_array_ref()[k] };
                path.depth += 1;
                active.push(i as u32);
            }
        }
        shadow_rays_traced as u64
    }

    /// The bounce of a path on a surface whose BSDF is more than Lambert's lobe, whole, from the
    /// scalar code (`PathTracer::bounce`). Returns whether the path goes on; its next ray is
    /// then set. (Out of line: the round loop of a diffuse scene never calls it.)
    #[inline(never)]
    fn scalar_bounce(&self, path: &mut Path, context: &mut SampleContext) -> bool {
        let scene = self.scene;
        let hit = scene.geometry().surface_hit((path.hit.object, path.hit.prim), &path.ray, &path.hit.at);
        let previous = (path.depth > 0).then_some(Scatter {
            point: path.last_point,
            normal: Some(path.last_normal),
            pdf: path.last_pdf,
            delta: path.last_pdf == f32::INFINITY,
        });
        let mut state = PathState {
            radiance: path.radiance,
            throughput: path.throughput,
            eta_scale: path.eta_scale,
            depth: path.depth,
            previous,
        };
        let next = self.tracer.bounce(scene, &path.ray, &hit, &mut state, context);
        path.radiance = state.radiance;
        let (Some(ray), Some(scatter)) = (next, state.previous) else { return false };
        path.ray = ray;
        path.throughput = state.throughput;
        path.eta_scale = state.eta_scale;
        path.depth = state.depth;
        path.last_point = scatter.point;
        path.last_normal = scatter.normal.unwrap_or(path.last_normal);
        path.last_pdf = if scatter.delta { f32::INFINITY } else { scatter.pdf };
        true
    }

    /// The surfaces of triangles in world space with constant materials, computed in the lanes
    /// (triangle_surface): point, error bound, geometric normal, and the shading normal from
    /// the vertex normals where the mesh has them.
    #[inline(always)]
    fn flat_surfaces<'p, 'r>(
        &self,
        path: &impl Fn(usize) -> &'p Path,
        materials: &'r [LaneMaterial<'a>],
    ) -> Surfaces<'r, 'a> {
        let geometry = &self.scene.geometry();
        let [a, b, c] = geometry
            .triangles8(std::array::from_fn(|k| (path(k).hit.object, path(k).hit.prim)))
            .expect("flat surfaces are triangles");
        let (b1, b2) = (per_lane(|k| path(k).hit.at.u), per_lane(|k| path(k).hit.at.v));
        let (point, error) = barycentric_point_lanes([a, b, c], b1, b2);
        let geometric = (b - a).cross(c - a).normalize_or(Vec3x8::splat(Vec3::Z));
        let shading =
            if geometry.has_vertex_normals() { self.smooth_normals(path, (b1, b2), geometric) } else { geometric };
        let material = LaneMaterials::Flat(std::array::from_fn(|k| {
            &materials[geometry.objects()[path(k).hit.object as usize].material as usize]
        }));
        Surfaces { point, error, geometric, shading, material, mapped: None }
    }

    /// The shading normals of lanes on triangles with vertex normals, interpolated at the
    /// barycentric weights (b1, b2); `geometric` elsewhere.
    fn smooth_normals<'p>(
        &self,
        path: &impl Fn(usize) -> &'p Path,
        (b1, b2): (f32x8, f32x8),
        geometric: Vec3x8,
    ) -> Vec3x8 {
        let geometry = &self.scene.geometry();
        let vertex_normals: [Option<[Vec3; 3]>; LANES] =
            std::array::from_fn(|k| geometry.triangle_normals(path(k).hit.object, path(k).hit.prim));
        let smooth = mask(|k| vertex_normals[k].is_some());
        if smooth.any() {
            let [na, nb, nc] = [0, 1, 2].map(|j| Vec3x8::from_fn(|k| vertex_normals[k].map_or(Vec3::ZERO, |n| n[j])));
            let n = (na * (f32x8::ONE - b1 - b2) + nb * b1 + nc * b2).normalize_or(geometric);
            let turned = Vec3x8::select(n.dot(geometric).cmp_lt(f32x8::ZERO), -n, n);
            Vec3x8::select(smooth, turned, geometric)
        } else {
            geometric
        }
    }

    /// The surfaces of any shapes and materials, from the scalar code lane by lane (the lanes
    /// past `n` read black).
    fn surfaces<'p>(&self, path: &impl Fn(usize) -> &'p Path, n: usize) -> Surfaces<'a, 'a> {
        let scene = self.scene;
        let hits: [Option<crate::scene::SurfaceHit>; LANES] = std::array::from_fn(|k| {
            let p = path(k);
            (k < n).then(|| scene.geometry().surface_hit((p.hit.object, p.hit.prim), &p.ray, &p.hit.at))
        });
        let geometry = |k: usize| hits[k].map(|h| h.geometry);
        let mut mapped: [Option<Vec3>; LANES] = [None; LANES];
        let material = std::array::from_fn(|k| match &hits[k] {
            Some(h) => {
                let material = &scene.materials()[h.material as usize];
                let (dpdu, dpdv) = match material.needs_tangent() {
                    true => scene.geometry().tangents(h.object, h.prim, &h.geometry),
                    false => (Vec3::ZERO, Vec3::ZERO),
                };
                let query = h.texture_query(scene.geometry());
                let with_tangents = TextureQuery { dpdu, dpdv, ..query };
                let wo = -path(k).ray.direction.normalize();
                let g = &h.geometry;
                mapped[k] = material.mapped_normal(&with_tangents, wo, g.shading_normal, g.geometric_normal);
                LaneMaterial::at(material, &query, (dpdu, dpdv))
            }
            None => LaneMaterial::BLACK,
        });
        let shading = Vec3x8::from_fn(|k| geometry(k).map_or(Vec3::Z, |g| g.shading_normal));
        Surfaces {
            point: Vec3x8::from_fn(|k| geometry(k).map_or(Vec3::ZERO, |g| g.point)),
            error: Vec3x8::from_fn(|k| geometry(k).map_or(Vec3::ZERO, |g| g.error)),
            geometric: Vec3x8::from_fn(|k| geometry(k).map_or(Vec3::Z, |g| g.geometric_normal)),
            shading,
            material: LaneMaterials::Evaluated(material),
            mapped: mapped.iter().any(Option::is_some).then(|| {
                let normals = Vec3x8::from_fn(|k| mapped[k].unwrap_or(shading.lane(k)));
                (mask(|k| mapped[k].is_some()), normals)
            }),
        }
    }

    /// Points uniform on triangle lights chosen by power, sampled in the lanes
    /// (`Lights::sample_li` by area), and the shadow rays from `from` toward them; `None` if
    /// no lane chose one.
    #[inline(always)]
    fn triangle_light_points(
        &self,
        emitters: &[TriangleEmitter],
        goes_on: &[bool; LANES],
        draws: &[f32x8; DRAWS],
        from: Vec3x8,
        from_error: Vec3x8,
        from_normal: Vec3x8,
    ) -> Option<LightPoints> {
        let zero = f32x8::ZERO;
        let none = emitters.len() - 1;
        let lights = self.scene.lights();
        let on = bytemuck::cast::<f32x8, i32x8>(mask(|k| goes_on[k]));
        // Each lane's emitter (`none` where the path ends).
        let chosen: i32x8 = if let Some(cdf) = self.counted_cdf {
            // `choose_index` is a binary search of the CDF, here the count of its entries at
            // or below the number (the same index), counted in all lanes at once.
            let u = draws[LIGHT];
            let mut count = i32x8::ZERO;
            for &c in cdf {
                count -= bytemuck::cast::<f32x8, i32x8>(f32x8::splat(c).cmp_le(u));
            }
            on.blend(count.min(i32x8::splat(cdf.len() as i32 - 1)), i32x8::splat(none as i32))
        } else {
            i32x8::from(std::array::from_fn::<i32, LANES, _>(|k| match goes_on[k] {
                true => lights.choose_index(draws[LIGHT].as_array_ref()[k]).unwrap_or(none) as i32,
                false => none as i32,
            }))
        };
        let unchosen = bytemuck::cast::<i32x8, f32x8>(chosen.cmp_eq(i32x8::splat(none as i32)));
        if unchosen.all() {
            return None;
        }
        let EmitterLanes { corners: [la, lb, lc], normal, radiance, area, selection, two_sided } =
            EmitterLanes::chosen(emitters, chosen);
        // A one-sided light with every corner behind its plane sends nothing here.
        let behind = |corner: Vec3x8| normal.dot(corner - from).cmp_gt(zero);
        let hidden = !two_sided & behind(la) & behind(lb) & behind(lc);
        let s = draws[LIGHT_POINT].sqrt();
        let (point, error) = barycentric_point_lanes([la, lb, lc], f32x8::ONE - s, draws[LIGHT_POINT + 1] * s);
        let to_light = point - from;
        let (pdf, seen) = area_to_solid_angle_lanes(selection, area, to_light, normal);
        let cos_light = normal.dot(to_light).negate();
        let sampled = !unchosen
            & !hidden
            & !area.cmp_le(zero)
            & seen
            & pdf.cmp_gt(zero)
            & pdf.is_finite()
            & !cos_light.cmp_eq(zero);
        let radiance = Vec3x8::select(two_sided | cos_light.cmp_gt(zero), radiance, Vec3x8::ZERO);
        // The shadow ray, each end offset off its surface toward the other (`Spawn::ray_to_surface`).
        let origin = offset_ray_origin_lanes(from, from_error, from_normal, to_light);
        let end = offset_ray_origin_lanes(point, error, normal, from - point);
        let toward = end - origin;
        // All eight written before the first is traced: a query that loads a ray as vectors
        // while its fields' stores are still on their way to the cache stalls until they
        // arrive (store forwarding fails).
        let shadow_rays =
            std::array::from_fn(|k| Ray::with_range(origin.lane(k), toward.lane(k), 0.0, 1.0 - SHADOW_EPSILON));
        Some(LightPoints { sampled, direction: to_light.normalize(), radiance, pdf, delta: zero, shadow_rays })
    }

    /// Any lights, from `Lights::sample_li` lane by lane, and the shadow rays toward them from
    /// the surfaces at `[point, error, geometric normal]`, as the scalar code spawns them;
    /// `None` if no lane got one.
    fn light_points(
        &self,
        goes_on: &[bool; LANES],
        draws: &[f32x8; DRAWS],
        [from, from_error, from_normal]: [Vec3x8; 3],
        shading: Vec3x8,
    ) -> Option<LightPoints> {
        let u = std::array::from_fn(|k| {
            Vec2::new(draws[LIGHT_POINT].as_array_ref()[k], draws[LIGHT_POINT + 1].as_array_ref()[k])
        });
        let samples = self.scene.lights().sample_li_lanes(
            goes_on,
            &std::array::from_fn(|k| from.lane(k)),
            &std::array::from_fn(|k| shading.lane(k)),
            draws[LIGHT].as_array_ref(),
            &u,
        );
        if samples.iter().all(Option::is_none) {
            return None;
        }
        let shadow_rays = std::array::from_fn(|k| match &samples[k] {
            Some(sample) => {
                Spawn { point: from.lane(k), error: from_error.lane(k), normal: from_normal.lane(k) }.shadow_ray(sample)
            }
            None => Ray::new(Vec3::ZERO, Vec3::Z),
        });
        Some(LightPoints {
            sampled: mask(|k| samples[k].is_some()),
            direction: Vec3x8::from_fn(|k| samples[k].map_or(Vec3::Z, |s| s.direction)),
            radiance: Vec3x8::from_fn(|k| samples[k].map_or(Rgb::ZERO, |s| s.radiance)),
            pdf: per_lane(|k| samples[k].map_or(0.0, |s| s.pdf)),
            delta: mask(|k| samples[k].is_some_and(|s| s.delta)),
            shadow_rays,
        })
    }
}

/// The BSDF of a bounce's eight lanes, of one lane kind. (A value on the stack for one bounce:
/// the variants' sizes may differ.)
#[allow(clippy::large_enum_variant)]
enum ChunkBsdf<'s> {
    Lambert { diffuse: Vec3x8 },
    RoughConductor(RoughConductorLanes<f32x8>),
    RoughPlastic(RoughPlasticLanes<f32x8, [&'s CoatTables; LANES]>),
    RoughDielectric(RoughDielectricLanes<f32x8>),
    Principled(PrincipledLanes<f32x8>),
    PrincipledThin(PrincipledThinLanes<f32x8>),
    Plastic(PlasticLanes<f32x8>),
    ThinDielectric(ThinDielectricLanes<f32x8>),
    DiffuseTransmission(DiffuseTransmissionLanes<f32x8>),
    Conductor(ConductorLanes<f32x8>),
    Dielectric(DielectricLanes<f32x8>),
}

/// Each lane's coat table.
impl CoatTransmittance<f32x8> for [&CoatTables; LANES] {
    #[inline(always)]
    fn transmittance(&self, cos: f32x8) -> f32x8 {
        let cos = cos.as_array_ref();
        per_lane(|k| self[k].lookup(cos[k]))
    }
}

impl<'s> ChunkBsdf<'s> {
    /// The lanes' BSDF of `kind` from their materials (lanes of another kind, past the chunk's
    /// end, read black). A rough conductor's frame turns to ∂p/∂u in the lanes where its widths
    /// differ, as `RoughConductor::bsdf` turns it.
    #[inline(always)]
    fn new(kind: LaneKind, material: &[&LaneMaterial<'s>; LANES], frame: &LaneFrame<f32x8>, wo: Vec3x8) -> Self {
        match kind {
            LaneKind::RoughPlastic(distribution) => {
                return ChunkBsdf::RoughPlastic(Self::rough_plastic(distribution, material, frame, wo))
            }
            LaneKind::RoughDielectric(distribution) => {
                return ChunkBsdf::RoughDielectric(Self::rough_dielectric(distribution, material, frame))
            }
            LaneKind::Principled => return ChunkBsdf::Principled(Self::principled(material, frame)),
            LaneKind::PrincipledThin => return ChunkBsdf::PrincipledThin(Self::principled_thin(material, frame)),
            LaneKind::ThinDielectric => {
                let lobe: [_; LANES] = std::array::from_fn(|k| match material[k].lobe {
                    LaneLobe::ThinDielectric { eta, reflectance, transmittance } => (eta, reflectance, transmittance),
                    _ => (1.0, Rgb::ZERO, Rgb::ZERO),
                });
                return ChunkBsdf::ThinDielectric(ThinDielectricLanes {
                    frame: frame.clone(),
                    eta: per_lane(|k| lobe[k].0),
                    reflectance: Vec3x8::from_fn(|k| lobe[k].1),
                    transmittance: Vec3x8::from_fn(|k| lobe[k].2),
                });
            }
            LaneKind::DiffuseTransmission => {
                let lobe: [_; LANES] = std::array::from_fn(|k| match material[k].lobe {
                    LaneLobe::DiffuseTransmission { reflectance, transmittance } => (reflectance, transmittance),
                    _ => (Rgb::ZERO, Rgb::ZERO),
                });
                // `DiffuseTransmission::bsdf`: the sides chosen by their albedos' luminance.
                let albedo = |c: Rgb| crate::textures::luminance(c).max(0.0);
                let (r, t) = (per_lane(|k| albedo(lobe[k].0)), per_lane(|k| albedo(lobe[k].1)));
                let lit = (r + t).cmp_gt(f32x8::ZERO);
                return ChunkBsdf::DiffuseTransmission(DiffuseTransmissionLanes {
                    frame: frame.clone(),
                    reflectance: Vec3x8::from_fn(|k| lobe[k].0),
                    transmittance: Vec3x8::from_fn(|k| lobe[k].1),
                    p_reflect: lit.blend(r / (r + t), f32x8::ZERO),
                    lit,
                });
            }
            LaneKind::Plastic => {
                let black = Coat { diffuse: Rgb::ZERO, specular: Rgb::ZERO, eta: 1.5, specular_weight: 0.0 };
                let coat = |k: usize| match material[k].lobe {
                    LaneLobe::Plastic { coat } => coat,
                    _ => black,
                };
                return ChunkBsdf::Plastic(PlasticLanes::new(frame.clone(), wo, coat));
            }
            LaneKind::Conductor => {
                let lobe: [_; LANES] = std::array::from_fn(|k| match material[k].lobe {
                    LaneLobe::Conductor { eta, k, specular } => (eta, k, specular),
                    _ => (Rgb::ONE, Rgb::ZERO, Rgb::ZERO),
                });
                return ChunkBsdf::Conductor(ConductorLanes {
                    frame: frame.clone(),
                    eta: Vec3x8::from_fn(|k| lobe[k].0),
                    k: Vec3x8::from_fn(|k| lobe[k].1),
                    specular: Vec3x8::from_fn(|k| lobe[k].2),
                });
            }
            LaneKind::Dielectric => {
                let lobe: [_; LANES] = std::array::from_fn(|k| match material[k].lobe {
                    LaneLobe::Dielectric { eta, reflectance, transmittance } => (eta, reflectance, transmittance),
                    _ => (1.5, Rgb::ZERO, Rgb::ZERO),
                });
                // `side_eta`: 1/η from outside, η from inside.
                let eta = per_lane(|k| lobe[k].0);
                return ChunkBsdf::Dielectric(DielectricLanes {
                    frame: frame.clone(),
                    eta: frame.outside.blend(f32x8::ONE / eta, eta),
                    reflectance: Vec3x8::from_fn(|k| lobe[k].1),
                    transmittance: Vec3x8::from_fn(|k| lobe[k].2),
                });
            }
            _ => {}
        }
        let LaneKind::RoughConductor(distribution) = kind else {
            return ChunkBsdf::Lambert {
                diffuse: Vec3x8::from_fn(|k| match material[k].lobe {
                    LaneLobe::Lambert { diffuse } => diffuse,
                    _ => Rgb::ZERO,
                }),
            };
        };
        let black = (1.0, 1.0, Rgb::ONE, Rgb::ZERO, Rgb::ZERO, Vec3::ZERO);
        let lobe: [_; LANES] = std::array::from_fn(|k| match material[k].lobe {
            LaneLobe::RoughConductor { alpha_u, alpha_v, eta, k, specular, dpdu } => {
                (alpha_u, alpha_v, eta, k, specular, dpdu)
            }
            _ => black,
        });
        let (alpha_x, alpha_y) = (per_lane(|k| lobe[k].0), per_lane(|k| lobe[k].1));
        let frame = along_where_anisotropic(frame, alpha_x, alpha_y, || Vec3x8::from_fn(|k| lobe[k].5));
        ChunkBsdf::RoughConductor(RoughConductorLanes {
            frame,
            eta: Vec3x8::from_fn(|k| lobe[k].2),
            k: Vec3x8::from_fn(|k| lobe[k].3),
            specular: Vec3x8::from_fn(|k| lobe[k].4),
            microfacet: MicrofacetLanes { alpha_x, alpha_y, separable: true, distribution },
        })
    }

    /// The rough glass of the lanes (`RoughDielectric::bsdf`): η seen from each lane's side.
    #[inline(always)]
    fn rough_dielectric(
        distribution: Distribution,
        material: &[&LaneMaterial<'s>; LANES],
        frame: &LaneFrame<f32x8>,
    ) -> RoughDielectricLanes<f32x8> {
        let clear = (1.0, 1.0, 1.5, Rgb::ZERO, Rgb::ZERO, Vec3::ZERO);
        let lobe: [_; LANES] = std::array::from_fn(|k| match material[k].lobe {
            LaneLobe::RoughDielectric { alpha_u, alpha_v, eta, reflectance, transmittance, dpdu } => {
                (alpha_u, alpha_v, eta, reflectance, transmittance, dpdu)
            }
            _ => clear,
        });
        let (alpha_x, alpha_y) = (per_lane(|k| lobe[k].0), per_lane(|k| lobe[k].1));
        let frame = along_where_anisotropic(frame, alpha_x, alpha_y, || Vec3x8::from_fn(|k| lobe[k].5));
        // `side_eta`: 1/η from outside, η from inside.
        let eta = per_lane(|k| lobe[k].2);
        let eta = frame.outside.blend(f32x8::ONE / eta, eta);
        RoughDielectricLanes {
            frame,
            eta,
            reflectance: Vec3x8::from_fn(|k| lobe[k].3),
            transmittance: Vec3x8::from_fn(|k| lobe[k].4),
            microfacet: MicrofacetLanes { alpha_x, alpha_y, separable: true, distribution },
        }
    }

    /// The principled BSDF of the lanes (`Principled::bsdf`).
    #[inline(always)]
    fn principled(material: &[&LaneMaterial<'s>; LANES], frame: &LaneFrame<f32x8>) -> PrincipledLanes<f32x8> {
        fn point<'m>(lobe: &'m LaneLobe) -> Option<(&'m PrincipledPoint, Vec3)> {
            match lobe {
                LaneLobe::Principled { point, dpdu } => Some((point, *dpdu)),
                _ => None,
            }
        }
        let (points, frame) = Self::points_in_frame(material, frame, point, |p| (p.alpha_x, p.alpha_y));
        PrincipledLanes::gather(frame, |k| points[k])
    }

    /// The thin principled BSDF of the lanes (`PrincipledThin::bsdf`).
    #[inline(always)]
    fn principled_thin(material: &[&LaneMaterial<'s>; LANES], frame: &LaneFrame<f32x8>) -> PrincipledThinLanes<f32x8> {
        fn point<'m>(lobe: &'m LaneLobe) -> Option<(&'m PrincipledThinPoint, Vec3)> {
            match lobe {
                LaneLobe::PrincipledThin { point, dpdu } => Some((point, *dpdu)),
                _ => None,
            }
        }
        let (points, frame) = Self::points_in_frame(material, frame, point, |p| p.reflection);
        PrincipledThinLanes::gather(frame, |k| points[k])
    }

    /// Each lane's parameters at its point (`point` of its lobe; lanes of another kind read lane
    /// 0's, which is always of this kind), and the frame turned to ∂p/∂u where the point's
    /// widths (`widths`) differ.
    #[inline(always)]
    fn points_in_frame<'m, P>(
        material: &[&'m LaneMaterial<'s>; LANES],
        frame: &LaneFrame<f32x8>,
        point: impl Fn(&'m LaneLobe<'s>) -> Option<(&'m P, Vec3)>,
        widths: impl Fn(&P) -> (f32, f32),
    ) -> ([&'m P; LANES], LaneFrame<f32x8>) {
        let (first, _) = point(&material[0].lobe).expect("a bounce starts with a surface of its kind");
        let lobe: [(&P, Vec3); LANES] =
            std::array::from_fn(|k| point(&material[k].lobe).unwrap_or((first, Vec3::ZERO)));
        let (alpha_x, alpha_y) = (per_lane(|k| widths(lobe[k].0).0), per_lane(|k| widths(lobe[k].0).1));
        let frame = along_where_anisotropic(frame, alpha_x, alpha_y, || Vec3x8::from_fn(|k| lobe[k].1));
        (lobe.map(|l| l.0), frame)
    }

    /// The rough plastic of the lanes (`RoughPlastic::bsdf`): the coat's transmittance toward
    /// the viewer and the probability of its reflection, lane by lane from the tables.
    #[inline(always)]
    fn rough_plastic(
        distribution: Distribution,
        material: &[&LaneMaterial<'s>; LANES],
        frame: &LaneFrame<f32x8>,
        wo: Vec3x8,
    ) -> RoughPlasticLanes<f32x8, [&'s CoatTables; LANES]> {
        // Lane 0 is always a path of this kind: lanes of another read its table.
        let LaneLobe::RoughPlastic { tables: first, .. } = material[0].lobe else {
            unreachable!("a rough plastic's bounce starts with a rough plastic")
        };
        let black = Coat { diffuse: Rgb::ZERO, specular: Rgb::ZERO, eta: 1.5, specular_weight: 0.0 };
        let lobe: [_; LANES] = std::array::from_fn(|k| match material[k].lobe {
            LaneLobe::RoughPlastic { coat, alpha, tables } => (coat, alpha, tables),
            _ => (black, 1.0, first),
        });
        let cos_o = wo.dot(frame.normal).to_array();
        let outside = frame.outside.move_mask();
        let t_o: [f32; LANES] = std::array::from_fn(|k| lobe[k].2.lookup(cos_o[k]));
        let p_glossy = per_lane(|k| match outside & (1 << k) != 0 {
            true => lobe[k].0.specular_probability(1.0 - t_o[k]),
            false => 0.0,
        });
        let alpha = per_lane(|k| lobe[k].1);
        RoughPlasticLanes {
            frame: frame.clone(),
            diffuse: Vec3x8::from_fn(|k| lobe[k].0.diffuse),
            specular: Vec3x8::from_fn(|k| lobe[k].0.specular),
            eta: per_lane(|k| lobe[k].0.eta),
            t_o: f32x8::from(t_o),
            p_glossy,
            microfacet: MicrofacetLanes { alpha_x: alpha, alpha_y: alpha, separable: true, distribution },
            tables: lobe.map(|l| l.2),
        }
    }

    /// The lanes whose BSDF has a lobe that is not a delta (`Bsdf::has_diffuse`): where the
    /// scalar code samples a light.
    #[inline(always)]
    fn non_delta(&self) -> [bool; LANES] {
        match self {
            ChunkBsdf::Conductor(_) | ChunkBsdf::Dielectric(_) | ChunkBsdf::ThinDielectric(_) => [false; LANES],
            ChunkBsdf::Plastic(lobe) => lobe.p_diffuse.cmp_gt(f32x8::ZERO).to_array().map(|p| p != 0.0),
            _ => [true; LANES],
        }
    }

    /// f(wo, wi)·cos θ_i and the density of sampling `wi` (`Bsdf::eval`, `Bsdf::pdf`).
    #[inline(always)]
    fn eval_and_pdf(&self, frame: &LaneFrame<f32x8>, wo: Vec3x8, wi: Vec3x8) -> (Vec3x8, f32x8) {
        match self {
            ChunkBsdf::Lambert { diffuse } => {
                // Lanes that are not lit sample no light and end (`goes_on`).
                let lobe = DiffuseLanes { frame, reflectance: *diffuse, lit: all_lanes() };
                (lobe.eval(wi), lobe.pdf(wi))
            }
            ChunkBsdf::RoughConductor(lobe) => (lobe.eval(wo, wi), lobe.pdf(wo, wi)),
            ChunkBsdf::RoughPlastic(lobe) => (lobe.eval(wo, wi), lobe.pdf(wo, wi)),
            ChunkBsdf::RoughDielectric(lobe) => (lobe.eval(wo, wi), lobe.pdf(wo, wi)),
            ChunkBsdf::Principled(lobe) => (lobe.eval(wo, wi), lobe.pdf(wo, wi)),
            ChunkBsdf::PrincipledThin(lobe) => (lobe.eval(wo, wi), lobe.pdf(wo, wi)),
            ChunkBsdf::Plastic(lobe) => (lobe.eval(wi), lobe.pdf(wi)),
            ChunkBsdf::DiffuseTransmission(lobe) => (lobe.eval(wi), lobe.pdf(wi)),
            // Delta lobes alone: no light is sampled at them.
            ChunkBsdf::Conductor(_) | ChunkBsdf::Dielectric(_) | ChunkBsdf::ThinDielectric(_) => {
                (Vec3x8::ZERO, f32x8::ZERO)
            }
        }
    }

    /// A direction from the lobe's number and two more (`Bsdf::sample`).
    #[inline(always)]
    fn sample(
        &self,
        frame: &LaneFrame<f32x8>,
        wo: Vec3x8,
        u_lobe: f32x8,
        u1: f32x8,
        u2: f32x8,
    ) -> LaneBsdfSample<f32x8> {
        match self {
            ChunkBsdf::Lambert { diffuse } => {
                DiffuseLanes { frame, reflectance: *diffuse, lit: all_lanes() }.sample(u1, u2)
            }
            ChunkBsdf::RoughConductor(lobe) => lobe.sample(wo, u1, u2),
            ChunkBsdf::RoughPlastic(lobe) => lobe.sample(wo, u_lobe, u1, u2),
            ChunkBsdf::RoughDielectric(lobe) => lobe.sample(wo, u_lobe, u1, u2),
            ChunkBsdf::Principled(lobe) => lobe.sample(wo, u_lobe, u1, u2),
            ChunkBsdf::PrincipledThin(lobe) => lobe.sample(wo, u_lobe, u1, u2),
            ChunkBsdf::Plastic(lobe) => lobe.sample(wo, u_lobe, u1, u2),
            ChunkBsdf::ThinDielectric(lobe) => lobe.sample(wo, u_lobe),
            ChunkBsdf::DiffuseTransmission(lobe) => lobe.sample(u_lobe, u1, u2),
            ChunkBsdf::Conductor(lobe) => lobe.sample(wo),
            ChunkBsdf::Dielectric(lobe) => lobe.sample(wo, u_lobe),
        }
    }
}

/// `frame` with its tangent turned to ∂p/∂u (`dpdu`) in the lanes whose widths differ, as
/// `Frame::along` turns it.
#[inline(always)]
fn along_where_anisotropic(
    frame: &LaneFrame<f32x8>,
    alpha_x: f32x8,
    alpha_y: f32x8,
    dpdu: impl Fn() -> Vec3x8,
) -> LaneFrame<f32x8> {
    let mut frame = frame.clone();
    let anisotropic = !alpha_x.cmp_eq(alpha_y);
    if anisotropic.any() {
        let (tangent, found) = tangent_along_lanes(frame.normal, dpdu());
        let turned = anisotropic & found;
        frame.tangent = Vec3x8::select(turned, tangent, frame.tangent);
        frame.bitangent = Vec3x8::select(turned, frame.normal.cross(tangent), frame.bitangent);
    }
    frame
}

/// The triangle emitters the lanes chose, field by field.
struct EmitterLanes {
    corners: [Vec3x8; 3],
    normal: Vec3x8,
    radiance: Vec3x8,
    area: f32x8,
    selection: f32x8,
    /// A lane mask.
    two_sided: f32x8,
}

impl EmitterLanes {
    /// The emitters `chosen` (indices into `emitters`). A few emitters are each blended into
    /// the lanes that chose them, where a gather loads every field lane by lane.
    #[inline(always)]
    fn chosen(emitters: &[TriangleEmitter], chosen: i32x8) -> Self {
        if emitters.len() <= BLENDED_EMITTERS {
            let of = |e: &TriangleEmitter| Self {
                corners: e.corners.map(Vec3x8::splat),
                normal: Vec3x8::splat(e.normal),
                radiance: Vec3x8::splat(e.radiance),
                area: f32x8::splat(e.area),
                selection: f32x8::splat(e.selection),
                two_sided: mask(|_| e.two_sided),
            };
            let (last, rest) = emitters.split_last().expect("the table ends with the black emitter");
            let mut lanes = of(last);
            for (j, e) in rest.iter().enumerate() {
                let here = bytemuck::cast::<i32x8, f32x8>(chosen.cmp_eq(i32x8::splat(j as i32)));
                if here.any() {
                    let e = of(e);
                    lanes = Self {
                        corners: std::array::from_fn(|c| Vec3x8::select(here, e.corners[c], lanes.corners[c])),
                        normal: Vec3x8::select(here, e.normal, lanes.normal),
                        radiance: Vec3x8::select(here, e.radiance, lanes.radiance),
                        area: here.blend(e.area, lanes.area),
                        selection: here.blend(e.selection, lanes.selection),
                        two_sided: here.blend(e.two_sided, lanes.two_sided),
                    };
                }
            }
            return lanes;
        }
        let chosen = chosen.to_array();
        let light: [&TriangleEmitter; LANES] = std::array::from_fn(|k| &emitters[chosen[k] as usize]);
        Self {
            corners: [0, 1, 2].map(|j| Vec3x8::from_fn(|k| light[k].corners[j])),
            normal: Vec3x8::from_fn(|k| light[k].normal),
            radiance: Vec3x8::from_fn(|k| light[k].radiance),
            area: per_lane(|k| light[k].area),
            selection: per_lane(|k| light[k].selection),
            two_sided: mask(|k| light[k].two_sided),
        }
    }
}

/// Lane k is `f(k)`.
#[inline(always)]
fn per_lane(f: impl Fn(usize) -> f32) -> f32x8 {
    let mut lanes = [0f32; LANES];
    for (k, lane) in lanes.iter_mut().enumerate() {
        *lane = f(k);
    }
    f32x8::from(lanes)
}

/// A mask of every lane.
#[inline(always)]
fn all_lanes() -> f32x8 {
    f32x8::ZERO.cmp_eq(f32x8::ZERO)
}

/// A lane mask, set where `f(k)`.
#[inline(always)]
fn mask(mut f: impl FnMut(usize) -> bool) -> f32x8 {
    let all = f32::from_bits(u32::MAX);
    f32x8::from(std::array::from_fn::<f32, LANES, _>(|k| if f(k) { all } else { 0.0 }))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each lane kind's group is its place in `IN_LANES`, the order a round takes them.
    #[test]
    fn groups_are_the_places_in_the_round() {
        for (place, kind) in LaneKind::IN_LANES.into_iter().enumerate() {
            assert_eq!(kind.group(), place, "{kind:?}");
        }
    }
}
