//! The scene's lights as one distribution: every light, chosen in proportion to its power (or
//! each emitter equally, Mitsuba's choice: see [`LightSelection`]), for next-event estimation
//! (`sample_li`) and for particles leaving the lights (`sample_le`, in `emission.rs`) alike.
//!
//! The order is the scene's listed lights (point, spot, directional; Whitted's and `explain`'s
//! light indices), then the environment if light arrives from outside, then each emitting
//! primitive. Powers: area light L_e·π·A (twice that if two-sided), point light 4π·I, spot
//! light 2π·I·(1 − (cos θ_full + cos θ_cone)/2) (the smooth edge counted half), directional
//! light E·π·R² over a disk that covers the scene's bounding sphere of radius R, the
//! environment π·R²·∫L dω.

use crate::Rgb;
use glam::{Vec2, Vec3};

use super::area::area_lights;
use super::{Asked, Environment, Light, LightEnd, LightSample, TriangleEmitter, TriangleSampling};
use crate::accel::Object;
use crate::geometry::Aabb;
use crate::lanes::LANES;
use crate::materials::Material;
use crate::Named;
use wide::f32x8;

const NONE: u32 = u32::MAX;

/// How next-event estimation and particle tracing choose among the scene's emitters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum LightSelection {
    /// Each light in proportion to its power: fewer samples wasted on dim lights.
    #[default]
    Power,
    /// Each emitter (a listed light, the environment, an emitting object) equally, and an
    /// object's primitives by their power within it: Mitsuba 3's choice, whose noise its
    /// reference variances measure.
    Uniform,
}

impl Named for LightSelection {
    const ALL: &'static [Self] = &[LightSelection::Power, LightSelection::Uniform];

    fn name(self) -> &'static str {
        match self {
            LightSelection::Power => "power",
            LightSelection::Uniform => "uniform",
        }
    }
}

#[derive(Clone, Debug, Default)]
pub struct Lights {
    lights: Vec<Light>,
    /// Cumulative selection probabilities, last = 1; empty if nothing emits.
    cdf: Vec<f32>,
    /// Each light's power (over π), and the end of each emitter's run of lights (an emitting
    /// object's primitives are one emitter): what the selection is made from.
    powers: Vec<f32>,
    emitter_ends: Vec<usize>,
    selection: LightSelection,
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
        let mut emitter_ends: Vec<usize> = (1..=lights.len()).collect();
        let environment_index = environment.emits().then(|| {
            lights.push(Light::Environment(environment.clone()));
            emitter_ends.push(lights.len());
            lights.len() - 1
        });
        let mut object_base = vec![NONE; objects.len()];
        for (object, area) in area_lights(objects, materials) {
            object_base[object] = lights.len() as u32;
            lights.extend(area.into_iter().map(Light::Area));
            emitter_ends.push(lights.len());
        }
        let (scene_center, scene_radius) =
            if bounds.is_empty() { (Vec3::ZERO, 1.0) } else { (bounds.centroid(), 0.5 * bounds.extent().length()) };
        let powers: Vec<f32> = lights.iter().map(|l| l.power_over_pi(scene_radius)).collect();
        let total: f32 = powers.iter().sum();
        let mut set = Self {
            lights,
            cdf: Vec::new(),
            powers,
            emitter_ends,
            selection: LightSelection::default(),
            object_base,
            environment: environment_index,
            triangle_sampling: TriangleSampling::default(),
            scene_center,
            scene_radius,
            total_power: if total.is_finite() { total.max(0.0) * std::f32::consts::PI } else { total },
            triangle_table: None,
        };
        set.set_selection(LightSelection::default());
        set
    }

    pub fn selection(&self) -> LightSelection {
        self.selection
    }

    /// The selection probabilities made again by `selection`.
    pub fn set_selection(&mut self, selection: LightSelection) {
        self.selection = selection;
        let weights: Vec<f32> = match selection {
            LightSelection::Power => self.powers.clone(),
            LightSelection::Uniform => {
                let mut weights = vec![0.0; self.powers.len()];
                let mut start = 0;
                for &end in &self.emitter_ends {
                    let run = &self.powers[start..end];
                    let power: f32 = run.iter().sum();
                    if power > 0.0 && power.is_finite() {
                        for (w, p) in weights[start..end].iter_mut().zip(run) {
                            *w = p / power;
                        }
                    }
                    start = end;
                }
                weights
            }
        };
        let total: f32 = weights.iter().sum();
        self.cdf.clear();
        let mut acc = 0.0;
        for w in &weights {
            acc += w / total;
            self.cdf.push(acc);
        }
        if let Some(last) = self.cdf.last_mut() {
            *last = 1.0;
        }
        let powered: f32 = self.powers.iter().sum();
        if !(total > 0.0 && total.is_finite() && powered > 0.0 && powered.is_finite()) {
            // Nothing to sample: no light is chosen, and no hit is a sampled light.
            self.cdf.clear();
            self.object_base.fill(NONE);
        }
        self.triangle_table = self.build_triangle_table();
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

    /// `sample_li` for each lane of a wavefront's bounce where `wanted[k]` (lane k from
    /// `from[k]` with receiver normal `receiver[k]`, drawing `u_select[k]` and `u[k]`). The lanes
    /// that choose the environment map draw from it together (`EnvironmentMap::sample_lanes`:
    /// their searches and texel loads wait on memory at once), the others one by one; each lane
    /// gets the bits `sample_li` gives it.
    pub(crate) fn sample_li_lanes(
        &self,
        wanted: &[bool; LANES],
        from: &[Vec3; LANES],
        receiver: &[Vec3; LANES],
        u_select: &[f32; LANES],
        u: &[Vec2; LANES],
    ) -> [Option<LightSample>; LANES] {
        let chosen: [Option<usize>; LANES] =
            std::array::from_fn(|k| if wanted[k] { self.choose(u_select[k]).map(|(i, _)| i) } else { None });
        let mapped = |i: usize| match &self.lights[i] {
            Light::Environment(Environment { map: Some(map), .. }) => Some(map),
            _ => None,
        };
        let map = chosen.iter().flatten().find_map(|&i| mapped(i));
        let drawn = map.map(|map| map.sample_lanes(f32x8::from(u.map(|u| u.x)), f32x8::from(u.map(|u| u.y))));
        std::array::from_fn(|k| {
            let i = chosen[k]?;
            match &drawn {
                Some(s) if mapped(i).is_some() => (s.valid.as_array_ref()[k] != 0.0).then(|| LightSample {
                    direction: s.direction.lane(k),
                    end: LightEnd::Infinite,
                    radiance: s.radiance.lane(k),
                    pdf: s.pdf.as_array_ref()[k] * self.selection_probability(i),
                    delta: false,
                }),
                _ => self.lights[i].sample_li(from[k], Some(receiver[k]), u[k], self.asked(i)),
            }
        })
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

    /// What a path that leaves the scene along `direction` sees of the environment, and the
    /// solid-angle density with which `sample_li` picks it there (`pdf_environment`), from one
    /// lookup; `None` if the environment is not one of the lights.
    #[inline]
    pub fn environment_seen(&self, direction: Vec3) -> Option<(Rgb, f32)> {
        match self.environment.map(|i| (i, &self.lights[i])) {
            Some((i, Light::Environment(e))) => {
                let (radiance, pdf) = e.radiance_and_pdf(direction);
                Some((radiance, pdf * self.selection_probability(i)))
            }
            _ => None,
        }
    }

    /// The probability with which `sample_li` chooses the environment, if it is one of the
    /// lights.
    pub(crate) fn environment_selection(&self) -> Option<f32> {
        self.environment.map(|i| self.selection_probability(i))
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

#[cfg(test)]
mod tests {
    use glam::Mat4;

    use super::super::area::EmitterShape;
    use super::super::{LightEnd, PointLight};
    use super::*;
    use crate::geometry::Transform;
    use crate::lights::Falloff;
    use crate::materials::Phong;
    use crate::shapes::{Shape, Sphere, Triangle};
    use crate::Rgb;

    fn emitting(radiance: f32) -> Material {
        Material::Phong(Phong { emission: Rgb::splat(radiance), ..Phong::default() })
    }

    fn object(shape: Shape, transform: Option<Transform>) -> Object {
        Object { name: "o".into(), shape, transform, material: 0 }
    }

    /// A point light (power/π 4·I = 4), a constant sky (R²·4π·L/π = 6 in a box of radius √3)
    /// and a one-sided triangle (L·A = 0.5): chosen 4 : 6 : 0.5, in the scene's order, and each
    /// sample says what it is.
    #[test]
    fn lights_of_every_kind_are_chosen_by_power() {
        let point = Light::Point(PointLight {
            position: Vec3::new(0.0, 0.5, 0.0),
            intensity: Rgb::ONE,
            falloff: Falloff::InverseSquare,
        });
        let sky = Environment { background: Rgb::splat(0.5), ..Environment::BLACK };
        let triangle = object(Shape::Triangle(Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y)), None);
        let bounds = Aabb::new(Vec3::splat(-1.0), Vec3::ONE);
        let lights = Lights::new(vec![point], &sky, &[triangle], &[emitting(1.0)], bounds);
        let kinds: Vec<&str> = lights.all().iter().map(Light::kind).collect();
        assert_eq!(kinds, ["point", "environment", "area"]);
        for (i, share) in [4.0, 6.0, 0.5].into_iter().enumerate() {
            let p = lights.selection_probability(i);
            assert!((p - share / 10.5).abs() < 1e-6, "light {i}: {p}");
        }
        assert!((lights.total_power() - 10.5 * std::f32::consts::PI).abs() < 1e-4);
        let from = Vec3::new(0.2, 0.2, 1.0);
        let u = Vec2::new(0.3, 0.7);
        let s = lights.sample_li(from, None, 0.1, u).unwrap();
        assert!(s.delta && s.end == LightEnd::Point(Vec3::new(0.0, 0.5, 0.0)));
        assert!((s.pdf - 4.0 / 10.5).abs() < 1e-6);
        let s = lights.sample_li(from, None, 0.5, u).unwrap();
        assert!(!s.delta && s.end == LightEnd::Infinite);
        assert!((s.pdf - lights.pdf_environment(s.direction)).abs() < 1e-7);
        assert!((lights.pdf_environment(Vec3::X) - 6.0 / 10.5 / (4.0 * std::f32::consts::PI)).abs() < 1e-6);
        let s = lights.sample_li(from, None, 0.99, u).unwrap();
        let LightEnd::Surface { point, normal, .. } = s.end else { panic!("the triangle is sampled on its surface") };
        assert_eq!(s.pdf, lights.pdf_area(from, None, 0, 0, point, normal));
        assert!(lights.has_environment() && lights.triangle_table().is_none());
    }

    /// Chosen uniformly, each emitter gets an equal share whatever its power, an emitting
    /// object's primitives sharing its share by power: a point light, the sky and two
    /// triangles (powers 0.5 and 3) of one emitting mesh object get ⅓, ⅓, ⅓·1/7, ⅓·6/7;
    /// the MIS densities follow, and power selection comes back.
    #[test]
    fn uniform_selection_gives_each_emitter_an_equal_share() {
        let point =
            Light::Point(PointLight { position: Vec3::Y, intensity: Rgb::ONE, falloff: Falloff::InverseSquare });
        let sky = Environment { background: Rgb::splat(0.5), ..Environment::BLACK };
        let mesh = crate::shapes::Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y, 2.0 * Vec3::X, 3.0 * Vec3::Y],
            indices: vec![[0, 1, 2], [0, 3, 4]],
            ..Default::default()
        };
        let objects = [object(Shape::Mesh(mesh), None)];
        let bounds = Aabb::new(Vec3::splat(-1.0), Vec3::ONE);
        let mut lights = Lights::new(vec![point], &sky, &objects, &[emitting(1.0)], bounds);
        let by_power: Vec<f32> = (0..4).map(|i| lights.selection_probability(i)).collect();
        lights.set_selection(LightSelection::Uniform);
        for (i, share) in [1.0 / 3.0, 1.0 / 3.0, 1.0 / 21.0, 6.0 / 21.0].into_iter().enumerate() {
            let p = lights.selection_probability(i);
            assert!((p - share).abs() < 1e-6, "light {i}: {p}");
        }
        assert!((lights.pdf_environment(Vec3::X) - 1.0 / 3.0 / (4.0 * std::f32::consts::PI)).abs() < 1e-6);
        let s = lights.sample_li(Vec3::new(0.2, 0.2, 1.0), None, 0.99, Vec2::new(0.3, 0.7)).unwrap();
        let LightEnd::Surface { point, normal, .. } = s.end else { panic!("the mesh is sampled on its surface") };
        assert_eq!(s.pdf, lights.pdf_area(Vec3::new(0.2, 0.2, 1.0), None, 0, 1, point, normal));
        lights.set_selection(LightSelection::Power);
        assert_eq!(by_power, (0..4).map(|i| lights.selection_probability(i)).collect::<Vec<_>>());
    }

    /// A scene lit by triangles alone keeps the selection it always had (L·A·sides over the
    /// sum), and the lanes' table of them.
    #[test]
    fn triangle_lights_alone_keep_their_selection_and_table() {
        let objects = [
            object(Shape::Triangle(Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y)), None),
            object(Shape::Triangle(Triangle::new(Vec3::ZERO, 2.0 * Vec3::X, 3.0 * Vec3::Y)), None),
        ];
        let lights = Lights::new(Vec::new(), &Environment::BLACK, &objects, &[emitting(2.0)], Aabb::EMPTY);
        let (a, b) = (2.0f32 * 0.5, 2.0f32 * 3.0);
        assert_eq!(lights.selection_cdf(), &[a / (a + b), 1.0]);
        let table = lights.triangle_table().expect("every light is a triangle");
        assert_eq!(table.len(), 3);
        assert_eq!(table[1].selection, 1.0 - a / (a + b));
    }

    /// A sphere under a similarity transform is sampled as the world sphere it is (by its
    /// cone, tested in area.rs); under a non-uniform scale (an ellipsoid), by area with the
    /// map's Jacobian. Either way light sampling finds the solid angle the light subtends
    /// (its estimate of ∫ L dω with L = 1 from the emitting outside): against directions
    /// uniform on the sphere counted where they meet it. And the ellipsoid's area against the
    /// prolate spheroid's formula.
    #[test]
    fn transformed_sphere_lights_are_sampled_without_bias() {
        let similar = Transform::from_matrix(
            Mat4::from_translation(Vec3::new(3.0, 0.2, 0.5))
                * Mat4::from_rotation_y(0.7)
                * Mat4::from_scale(Vec3::splat(1.5)),
        )
        .unwrap();
        let stretched = Transform::from_matrix(
            Mat4::from_translation(Vec3::new(4.0, -0.2, 0.3))
                * Mat4::from_rotation_z(0.4)
                * Mat4::from_scale(Vec3::new(2.0, 1.0, 1.0)),
        )
        .unwrap();
        let from = Vec3::new(0.1, 0.3, -0.5);
        for (transform, by_area) in [(similar, false), (stretched, true)] {
            let sphere = object(Shape::Sphere(Sphere::new(Vec3::ZERO, 0.8)), Some(transform));
            let lights = Lights::new(Vec::new(), &Environment::BLACK, &[sphere], &[emitting(1.0)], Aabb::EMPTY);
            let Light::Area(light) = &lights.all()[0] else { panic!("an area light") };
            match (&light.shape, by_area) {
                (EmitterShape::Sphere { center, radius }, false) => {
                    assert!((*center - Vec3::new(3.0, 0.2, 0.5)).length() < 1e-6 && (radius - 1.2).abs() < 1e-6);
                }
                (EmitterShape::Ellipsoid(e), true) => {
                    // Semi-axes 2·0.8 and 0.8: 2πb²(1 + a·asin(e)/(b·e)), e = √(1 − b²/a²).
                    let (a, b) = (1.6f64, 0.8f64);
                    let ecc = (1.0 - b * b / (a * a)).sqrt();
                    let area = 2.0 * std::f64::consts::PI * b * b * (1.0 + a * ecc.asin() / (b * ecc));
                    assert!((e.area as f64 / area - 1.0).abs() < 1e-4, "{} vs {area}", e.area);
                }
                (shape, _) => panic!("unexpected {shape:?}"),
            }
            let mut rng = crate::sampling::Rng::new(7, 3);
            let n = 400_000;
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let u = Vec2::new(rng.next_f32(), rng.next_f32());
                let x = lights.sample_li(from, None, 0.5, u).map_or(0.0, |s| (s.radiance.x / s.pdf) as f64);
                sum += x;
                sum2 += x * x;
            }
            let (mean, error) = (sum / n as f64, ((sum2 / n as f64 - (sum / n as f64).powi(2)) / n as f64).sqrt());
            let m = 2_000_000;
            let seen = (0..m)
                .filter(|_| {
                    let w = crate::sampling::warp::square_to_uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
                    meets_sphere(from, w, 0.8, &transform)
                })
                .count() as f64;
            let p = seen / m as f64;
            let omega = 4.0 * std::f64::consts::PI * p;
            let omega_error = 4.0 * std::f64::consts::PI * (p * (1.0 - p) / m as f64).sqrt();
            assert!(
                (mean - omega).abs() < 4.0 * (error + omega_error),
                "by area {by_area}: light sampling {mean} ± {error} against {omega} ± {omega_error} sr"
            );
        }
    }

    /// Whether the ray from `from` along `w` meets a sphere of `radius` about the origin under
    /// `transform`.
    fn meets_sphere(from: Vec3, w: Vec3, radius: f32, transform: &Transform) -> bool {
        let (o, d) = (transform.to_object.transform_point3(from), transform.to_object.transform_vector3(w));
        let (o, d) = (o.as_dvec3(), d.as_dvec3());
        let (a, b, c) = (d.dot(d), o.dot(d), o.dot(o) - (radius as f64).powi(2));
        b * b - a * c >= 0.0 && (-b + (b * b - a * c).sqrt()) > 0.0
    }

    /// A light stays about a triangle's size: a mesh light is a vector of them, one read per
    /// light sample.
    #[test]
    fn a_light_is_small() {
        assert!(std::mem::size_of::<Light>() <= 80, "{} bytes", std::mem::size_of::<Light>());
    }
}
