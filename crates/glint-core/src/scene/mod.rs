//! The scene and its query interface: closest hit and any hit. Integrators reach geometry only
//! through these, so every integrator runs on every scene whichever reader built it.

mod hit;

pub use hit::SurfaceHit;
pub(crate) use hit::{Spawn, SHADOW_EPSILON};

pub use crate::accel::{Geometry, Object, PrimitiveHit};
use crate::camera::Camera;
use crate::geometry::Ray;
use crate::lights::{Environment, Light, Lights, TriangleSampling};
use crate::materials::Material;
use crate::shapes::IntersectMethods;

/// Everything a render needs: geometry, materials, lights, camera and environment. The lights
/// are derived from the rest (emitting materials make area lights, the environment one more),
/// so what they depend on changes only through the setters, which derive them again.
pub struct Scene {
    pub camera: Camera,
    pub geometry: Geometry,
    materials: Vec<Material>,
    material_names: Vec<String>,
    lights: Lights,
    environment: Environment,
}

impl Scene {
    /// `lights` are the scene's listed lights: point, spot and directional.
    pub fn new(
        camera: Camera,
        objects: Vec<Object>,
        materials: Vec<(String, Material)>,
        lights: Vec<Light>,
        environment: Environment,
        methods: IntersectMethods,
    ) -> Self {
        let (material_names, materials): (Vec<String>, Vec<Material>) = materials.into_iter().unzip();
        let geometry = Geometry::new(objects, methods);
        let lights = Lights::new(lights, &environment, &geometry.objects, &materials, geometry.bounds());
        Self { camera, geometry, materials, material_names, lights, environment }
    }

    pub fn objects(&self) -> &[Object] {
        &self.geometry.objects
    }

    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    pub fn material_names(&self) -> &[String] {
        &self.material_names
    }

    /// Every light, as one distribution by power.
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
        let strategy = self.lights.triangle_sampling();
        self.lights =
            Lights::new(listed, &self.environment, &self.geometry.objects, &self.materials, self.geometry.bounds());
        self.lights.set_triangle_sampling(strategy);
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
