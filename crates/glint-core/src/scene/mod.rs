//! The scene and its query interface: closest hit and any hit. Integrators reach geometry only
//! through these, so every integrator runs on every scene whichever reader built it.

mod darkness;
mod hit;

pub use darkness::{black_image_warning, Darkness};
pub use hit::SurfaceHit;
pub(crate) use hit::{Spawn, SHADOW_EPSILON};

pub use crate::accel::{Geometry, Object, PrimitiveHit};
use crate::camera::Camera;
use crate::geometry::Ray;
use crate::lights::{Environment, Light, LightSelection, Lights, TriangleSampling};
use crate::materials::Material;
use crate::media::{Medium, MediumInterface};
use crate::shapes::IntersectMethods;
use crate::Rgb;

/// Everything a render needs: geometry, materials, lights, camera and environment. The lights
/// and the BVH are derived from the rest (emitting materials make area lights, the environment
/// one more), so the fields are private and change only through the setters, which derive
/// them again. A scene is made by [`SceneBuilder`].
pub struct Scene {
    camera: Camera,
    geometry: Geometry,
    materials: Vec<Material>,
    material_names: Vec<String>,
    lights: Lights,
    environment: Environment,
    /// Participating media, the media on either side of each object (by object; empty when
    /// the scene has no media) and the camera's.
    media: Vec<Medium>,
    medium_interfaces: Vec<MediumInterface>,
    camera_medium: Option<u32>,
}

/// A scene's parts, gathered before the BVH and the lights are derived from them. Nothing
/// but the camera is required: no objects, no materials, no listed lights, a black
/// environment and the default intersection methods.
pub struct SceneBuilder {
    camera: Camera,
    objects: Vec<Object>,
    materials: Vec<(String, Material)>,
    lights: Vec<Light>,
    environment: Environment,
    methods: IntersectMethods,
    triangle_sampling: Option<TriangleSampling>,
    light_selection: LightSelection,
    media: Vec<Medium>,
    medium_interfaces: Vec<MediumInterface>,
    camera_medium: Option<u32>,
}

impl SceneBuilder {
    pub fn new(camera: Camera) -> Self {
        Self {
            camera,
            objects: Vec::new(),
            materials: Vec::new(),
            lights: Vec::new(),
            environment: Environment { background: Rgb::ZERO, ambient_light: Rgb::ZERO, map: None },
            methods: IntersectMethods::default(),
            triangle_sampling: None,
            light_selection: LightSelection::default(),
            media: Vec::new(),
            medium_interfaces: Vec::new(),
            camera_medium: None,
        }
    }

    pub fn objects(mut self, objects: Vec<Object>) -> Self {
        self.objects = objects;
        self
    }

    pub fn object(mut self, object: Object) -> Self {
        self.objects.push(object);
        self
    }

    /// The materials with their names; objects refer to them by index.
    pub fn materials(mut self, materials: Vec<(String, Material)>) -> Self {
        self.materials = materials;
        self
    }

    pub fn material(mut self, name: impl Into<String>, material: Material) -> Self {
        self.materials.push((name.into(), material));
        self
    }

    /// The listed lights: point, spot and directional.
    pub fn lights(mut self, lights: Vec<Light>) -> Self {
        self.lights = lights;
        self
    }

    pub fn light(mut self, light: Light) -> Self {
        self.lights.push(light);
        self
    }

    pub fn environment(mut self, environment: Environment) -> Self {
        self.environment = environment;
        self
    }

    pub fn methods(mut self, methods: IntersectMethods) -> Self {
        self.methods = methods;
        self
    }

    /// How triangle lights are sampled (by area unless said).
    pub fn triangle_sampling(mut self, strategy: TriangleSampling) -> Self {
        self.triangle_sampling = Some(strategy);
        self
    }

    /// How lights are chosen (by power unless said).
    pub fn light_selection(mut self, selection: LightSelection) -> Self {
        self.light_selection = selection;
        self
    }

    /// Participating media, the media on either side of each object (by object index) and
    /// the camera's medium.
    pub fn media(mut self, media: Vec<Medium>, interfaces: Vec<MediumInterface>, camera: Option<u32>) -> Self {
        self.media = media;
        self.medium_interfaces = interfaces;
        self.camera_medium = camera;
        self
    }

    /// The BVH built and the lights derived.
    pub fn build(self) -> Scene {
        let (material_names, materials): (Vec<String>, Vec<Material>) = self.materials.into_iter().unzip();
        let geometry = Geometry::new(self.objects, self.methods);
        let mut lights = Lights::new(self.lights, &self.environment, geometry.objects(), &materials, geometry.bounds());
        if let Some(strategy) = self.triangle_sampling {
            lights.set_triangle_sampling(strategy);
        }
        lights.set_selection(self.light_selection);
        Scene {
            camera: self.camera,
            geometry,
            materials,
            material_names,
            lights,
            environment: self.environment,
            media: self.media,
            medium_interfaces: self.medium_interfaces,
            camera_medium: self.camera_medium,
        }
    }
}

impl Scene {
    pub fn media(&self) -> &[Medium] {
        &self.media
    }

    /// The media on either side of object `object` (none where the scene gave none).
    pub fn medium_interface(&self, object: u32) -> MediumInterface {
        self.medium_interfaces.get(object as usize).copied().unwrap_or_default()
    }

    /// The medium the camera is in.
    pub fn camera_medium(&self) -> Option<u32> {
        self.camera_medium
    }

    /// The medium at `origin`, found by following the ray `origin + t·direction`, then the
    /// opposite ray, to the first surface that bounds media: the medium on `origin`'s side of
    /// it. Surfaces that bound none are passed. A point from which neither ray meets one is
    /// in the camera's medium (the medium that fills the world when no surface bounds it).
    /// For particles leaving lights, which do not say which medium they are in.
    pub fn medium_at(&self, origin: glam::Vec3, direction: glam::Vec3) -> Option<u32> {
        if self.media.is_empty() {
            return None;
        }
        for way in [direction, -direction] {
            let mut ray = crate::geometry::Ray::new(origin, way);
            for _ in 0..256 {
                let Some(hit) = self.intersect(&ray) else { break };
                let interface = self.medium_interface(hit.object);
                if interface != MediumInterface::default() {
                    // `origin` lies on the side the ray arrives from.
                    return interface.toward(-way, hit.geometry.geometric_normal);
                }
                ray = hit.spawn_ray(way);
            }
        }
        self.camera_medium
    }

    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// Another view of the same scene (a new resolution, a moved eye): nothing derived changes.
    pub fn set_camera(&mut self, camera: Camera) {
        self.camera = camera;
    }

    /// The objects in their BVH, and the queries on them.
    pub fn geometry(&self) -> &Geometry {
        &self.geometry
    }

    /// New objects: the BVH is built again (with the same intersection methods) and the lights
    /// derived again.
    pub fn set_objects(&mut self, objects: Vec<Object>) {
        self.geometry = Geometry::new(objects, self.geometry.methods());
        self.relight();
    }

    /// Which algorithm each shape's intersection uses; the BVH does not depend on it.
    pub fn set_methods(&mut self, methods: IntersectMethods) {
        self.geometry.set_methods(methods);
    }

    pub fn objects(&self) -> &[Object] {
        self.geometry.objects()
    }

    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    pub fn material_names(&self) -> &[String] {
        &self.material_names
    }

    /// Every light, as one distribution (by power unless said).
    pub fn lights(&self) -> &Lights {
        &self.lights
    }

    pub fn environment(&self) -> &Environment {
        &self.environment
    }

    /// New materials (the names kept where there are as many), and the lights they make.
    pub fn set_materials(&mut self, materials: Vec<Material>) {
        if materials.len() != self.material_names.len() {
            self.material_names = (1..=materials.len()).map(|i| format!("material {i}")).collect();
        }
        self.materials = materials;
        self.relight();
    }

    /// New materials with their names, and the lights they make.
    pub fn set_named_materials(&mut self, materials: Vec<(String, Material)>) {
        (self.material_names, self.materials) = materials.into_iter().unzip();
        self.relight();
    }

    /// One material replaced, and the lights it makes.
    pub fn set_material(&mut self, index: usize, material: Material) {
        self.materials[index] = material;
        self.relight();
    }

    /// New listed lights (point, spot and directional).
    pub fn set_lights(&mut self, listed: Vec<Light>) {
        let (strategy, selection) = (self.lights.triangle_sampling(), self.lights.selection());
        self.lights =
            Lights::new(listed, &self.environment, self.geometry.objects(), &self.materials, self.geometry.bounds());
        self.lights.set_triangle_sampling(strategy);
        self.lights.set_selection(selection);
    }

    /// One more listed light.
    pub fn add_light(&mut self, light: Light) {
        let mut listed: Vec<Light> = self.listed_lights().cloned().collect();
        listed.push(light);
        self.set_lights(listed);
    }

    /// The point, spot and directional lights, in the scene's order.
    pub fn listed_lights(&self) -> impl Iterator<Item = &Light> {
        self.lights.all().iter().filter(|l| l.is_delta())
    }

    pub fn set_environment(&mut self, environment: Environment) {
        self.environment = environment;
        self.relight();
    }

    /// How triangle lights are sampled (`--light-sampling`).
    pub fn set_triangle_sampling(&mut self, strategy: TriangleSampling) {
        self.lights.set_triangle_sampling(strategy);
    }

    /// How lights are chosen (`--light-selection`).
    pub fn set_light_selection(&mut self, selection: LightSelection) {
        self.lights.set_selection(selection);
    }

    /// The lights derived again from what they depend on.
    fn relight(&mut self) {
        self.set_lights(self.listed_lights().cloned().collect());
    }

    pub fn intersect(&self, ray: &Ray) -> Option<SurfaceHit> {
        self.geometry.intersect(ray)
    }

    pub fn occluded(&self, ray: &Ray) -> bool {
        self.geometry.occluded(ray)
    }

    pub fn intersect_brute_force(&self, ray: &Ray) -> Option<SurfaceHit> {
        self.geometry.intersect_brute_force(ray)
    }
}
