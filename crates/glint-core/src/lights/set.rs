//! The scene's lights as one distribution: every light, chosen in proportion to its power, for
//! next-event estimation (`sample_li`) and for particles leaving the lights (`sample_le`, in
//! `emission.rs`) alike.
//!
//! The order is the scene's listed lights (point, spot, directional; Whitted's and `explain`'s
//! light indices), then the environment if light arrives from outside, then each emitting
//! primitive. Powers: area light L_e·π·A (twice that if two-sided), point light 4π·I, spot
//! light 2π·I·(1 − (cos θ_full + cos θ_cone)/2) (the smooth edge counted half), directional
//! light E·π·R² over a disk that covers the scene's bounding sphere of radius R, the
//! environment π·R²·∫L dω.

use glam::{Vec2, Vec3};

use super::area::area_lights;
use super::{Asked, Environment, Light, LightSample, TriangleEmitter, TriangleSampling};
use crate::geometry::Aabb;
use crate::materials::Material;
use crate::scene::Object;

const NONE: u32 = u32::MAX;

#[derive(Clone, Debug, Default)]
pub struct Lights {
    lights: Vec<Light>,
    /// Cumulative selection probabilities (by power), last = 1; empty if nothing emits.
    cdf: Vec<f32>,
    /// Per object: the index of the light its first primitive is (its primitive p is
    /// `base + p`), or `NONE`.
    object_base: Vec<u32>,
    /// The environment's index, if it emits.
    environment: Option<usize>,
    triangle_sampling: TriangleSampling,
    /// The scene's bounding sphere, over which light from infinity is sent as particles.
    pub(super) scene_center: Vec3,
    pub(super) scene_radius: f32,
    /// Emitted power (flux, mean over RGB).
    total_power: f32,
    /// Every light as a triangle, in order, then a black one no `choose_index` picks (for
    /// lanes without a light); `None` unless every light is a triangle. For the path tracer's
    /// lanes.
    triangle_table: Option<Vec<TriangleEmitter>>,
}

impl Lights {
    /// The lights of a scene: `listed` (point, spot and directional lights, in the scene's
    /// order), the environment, and every primitive of `objects` whose material emits.
    /// `bounds` are the scene's.
    pub fn new(
        listed: Vec<Light>,
        environment: &Environment,
        objects: &[Object],
        materials: &[Material],
        bounds: Aabb,
    ) -> Self {
        debug_assert!(listed.iter().all(Light::is_delta), "area lights and the environment come from the scene");
        let mut lights = listed;
        let environment_index = environment.emits().then(|| {
            lights.push(Light::Environment(environment.clone()));
            lights.len() - 1
        });
        let mut object_base = vec![NONE; objects.len()];
        for (object, area) in area_lights(objects, materials) {
            object_base[object] = lights.len() as u32;
            lights.extend(area.into_iter().map(Light::Area));
        }
        let (scene_center, scene_radius) =
            if bounds.is_empty() { (Vec3::ZERO, 1.0) } else { (bounds.centroid(), 0.5 * bounds.extent().length()) };
        let powers: Vec<f32> = lights.iter().map(|l| l.power_over_pi(scene_radius)).collect();
        let total: f32 = powers.iter().sum();
        let mut cdf = Vec::with_capacity(powers.len());
        let mut acc = 0.0;
        for p in &powers {
            acc += p / total;
            cdf.push(acc);
        }
        if let Some(last) = cdf.last_mut() {
            *last = 1.0;
        }
        if !(total > 0.0 && total.is_finite()) {
            // Nothing to sample: no light is chosen, and no hit is a sampled light.
            cdf.clear();
            object_base.fill(NONE);
        }
        let mut set = Self {
            lights,
            cdf,
            object_base,
            environment: environment_index,
            triangle_sampling: TriangleSampling::default(),
            scene_center,
            scene_radius,
            total_power: if total.is_finite() { total.max(0.0) * std::f32::consts::PI } else { total },
            triangle_table: None,
        };
        set.triangle_table = set.build_triangle_table();
        set
    }

    /// Every light, in order.
    pub fn all(&self) -> &[Light] {
        &self.lights
    }

    /// The number of lights (each triangle of an emissive mesh is one).
    pub fn len(&self) -> usize {
        self.lights.len()
    }

    pub fn is_empty(&self) -> bool {
        self.lights.is_empty()
    }

    /// The number of area lights.
    pub fn area_count(&self) -> usize {
        self.lights.iter().filter(|l| matches!(l, Light::Area(_))).count()
    }

    /// Whether anything is sampled: some light has power.
    pub fn emits(&self) -> bool {
        !self.cdf.is_empty()
    }

    /// Emitted power (flux, mean over RGB).
    pub fn total_power(&self) -> f32 {
        self.total_power
    }

    pub fn triangle_sampling(&self) -> TriangleSampling {
        self.triangle_sampling
    }

    pub fn set_triangle_sampling(&mut self, strategy: TriangleSampling) {
        self.triangle_sampling = strategy;
    }

    /// Whether the environment is a light (a map, or a background that is not black).
    pub fn has_environment(&self) -> bool {
        self.environment.is_some()
    }

    /// The light `u_select` picks, in proportion to power, and its index.
    #[inline]
    fn choose(&self, u_select: f32) -> Option<(usize, &Light)> {
        if self.cdf.is_empty() {
            return None;
        }
        let i = self.cdf.partition_point(|&c| c <= u_select).min(self.lights.len() - 1);
        Some((i, &self.lights[i]))
    }

    pub(super) fn selection_probability(&self, i: usize) -> f32 {
        probability_of(&self.cdf, i)
    }

    #[inline]
    fn asked(&self, i: usize) -> Asked {
        Asked { selection: self.selection_probability(i), triangle_sampling: self.triangle_sampling }
    }

    /// One light chosen by `u_select`, seen from the shading point `from` (the receiver's
    /// shading normal, which triangles sampled by solid angle follow): `u` picks the point.
    pub fn sample_li(&self, from: Vec3, receiver: Option<Vec3>, u_select: f32, u: Vec2) -> Option<LightSample> {
        let (i, light) = self.choose(u_select)?;
        light.sample_li(from, receiver, u, self.asked(i))
    }

    /// The solid-angle density with which `sample_li` from `from` would have produced the point
    /// `point` (geometric normal `normal`) on primitive `prim` of object `object`; 0 if that
    /// primitive is not a sampled light. For multiple importance sampling of BSDF-sampled hits;
    /// `receiver` as given to `sample_li`.
    pub fn pdf_area(
        &self,
        from: Vec3,
        receiver: Option<Vec3>,
        object: u32,
        prim: u32,
        point: Vec3,
        normal: Vec3,
    ) -> f32 {
        let Some(i) = self.emitter_index(object, prim) else { return 0.0 };
        match &self.lights[i] {
            Light::Area(a) => a.pdf_li(from, receiver, point, normal, self.asked(i)),
            _ => 0.0,
        }
    }

    /// The solid-angle density with which `sample_li` picks the environment in `direction`.
    pub fn pdf_environment(&self, direction: Vec3) -> f32 {
        match self.environment.map(|i| (i, &self.lights[i])) {
            Some((i, Light::Environment(e))) => e.pdf(direction) * self.selection_probability(i),
            _ => 0.0,
        }
    }

    /// The light that primitive `prim` of `object` is, if it is one (as `pdf_area` finds it).
    #[inline]
    pub(crate) fn emitter_index(&self, object: u32, prim: u32) -> Option<usize> {
        let base = self.object_base.get(object as usize).copied().unwrap_or(NONE);
        (base != NONE).then_some((base + prim) as usize)
    }

    /// Every light as a triangle, then a black one that is never chosen (its index is the
    /// number of lights); `None` unless every light is a triangle.
    pub(crate) fn triangle_table(&self) -> Option<&[TriangleEmitter]> {
        self.triangle_table.as_deref()
    }

    fn build_triangle_table(&self) -> Option<Vec<TriangleEmitter>> {
        let mut table: Vec<TriangleEmitter> = self
            .lights
            .iter()
            .enumerate()
            .map(|(i, light)| match light {
                Light::Area(a) => a.as_triangle(if self.cdf.is_empty() { 0.0 } else { self.selection_probability(i) }),
                _ => None,
            })
            .collect::<Option<_>>()?;
        table.push(TriangleEmitter::NONE);
        Some(table)
    }

    /// The index of the light `u_select` picks (by power), as `sample_li` picks it.
    #[inline]
    pub(crate) fn choose_index(&self, u_select: f32) -> Option<usize> {
        self.choose(u_select).map(|(i, _)| i)
    }

    /// The cumulative probabilities by which `choose_index` picks a light.
    pub(crate) fn selection_cdf(&self) -> &[f32] {
        &self.cdf
    }

    /// The light `u_select` picks and its selection probability, if that is not 0.
    pub(super) fn choose_for_particle(&self, u_select: f32) -> Option<(&Light, f32)> {
        let (i, light) = self.choose(u_select)?;
        let probability = self.selection_probability(i);
        (probability > 0.0).then_some((light, probability))
    }
}

/// The probability of entry `i` of a discrete distribution from its cumulative `cdf`.
fn probability_of(cdf: &[f32], i: usize) -> f32 {
    cdf[i] - if i == 0 { 0.0 } else { cdf[i - 1] }
}
