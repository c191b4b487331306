//! What an integrator reports about each ray, so one code path both renders and explains.
//! `NoRecorder` compiles to nothing; `RayTree` keeps the ray tree of one pixel.

use glam::Vec3;

use crate::geometry::Ray;
use crate::scene::SurfaceHit;
use crate::Rgb;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RayKind {
    Camera,
    Reflection,
    Refraction,
}

impl RayKind {
    pub fn name(self) -> &'static str {
        match self {
            RayKind::Camera => "camera",
            RayKind::Reflection => "reflection",
            RayKind::Refraction => "refraction",
        }
    }
}

/// One light's part in shading a point, including its shadow ray's result.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightRecord {
    pub index: usize,
    /// Unit direction toward the light.
    pub direction: Vec3,
    /// False when the light is behind the surface (no shadow ray is traced).
    pub facing: bool,
    /// What the shadow ray let through: 1 = unshadowed, 0 = blocked.
    pub visibility: Rgb,
    pub contribution: Rgb,
}

pub trait Recorder {
    fn begin_ray(&mut self, kind: RayKind, depth: u32, ray: &Ray, weight: Rgb);
    fn miss(&mut self, background: Rgb);
    fn hit(&mut self, hit: &SurfaceHit);
    fn ambient(&mut self, ambient: Rgb);
    fn light(&mut self, light: LightRecord);
    /// Ambient + direct light at the current ray's hit.
    fn local(&mut self, local: Rgb);
    /// The current ray's radiance; closes it.
    fn end_ray(&mut self, radiance: Rgb);
}

pub struct NoRecorder;

impl Recorder for NoRecorder {
    #[inline(always)]
    fn begin_ray(&mut self, _: RayKind, _: u32, _: &Ray, _: Rgb) {}
    #[inline(always)]
    fn miss(&mut self, _: Rgb) {}
    #[inline(always)]
    fn hit(&mut self, _: &SurfaceHit) {}
    #[inline(always)]
    fn ambient(&mut self, _: Rgb) {}
    #[inline(always)]
    fn light(&mut self, _: LightRecord) {}
    #[inline(always)]
    fn local(&mut self, _: Rgb) {}
    #[inline(always)]
    fn end_ray(&mut self, _: Rgb) {}
}

/// One ray of the tree, in the order traced (depth first).
#[derive(Clone, Debug, PartialEq)]
pub struct RayRecord {
    pub kind: RayKind,
    pub depth: u32,
    pub ray: Ray,
    pub weight: Rgb,
    pub hit: Option<SurfaceHit>,
    pub ambient: Rgb,
    pub lights: Vec<LightRecord>,
    pub local: Rgb,
    pub radiance: Rgb,
}

/// The ray tree of one sample: records in depth-first order, each with its depth.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RayTree {
    pub rays: Vec<RayRecord>,
    open: Vec<usize>,
}

impl RayTree {
    fn current(&mut self) -> &mut RayRecord {
        let i = *self.open.last().expect("a ray is open");
        &mut self.rays[i]
    }
}

impl Recorder for RayTree {
    fn begin_ray(&mut self, kind: RayKind, depth: u32, ray: &Ray, weight: Rgb) {
        self.open.push(self.rays.len());
        self.rays.push(RayRecord {
            kind,
            depth,
            ray: *ray,
            weight,
            hit: None,
            ambient: Rgb::ZERO,
            lights: Vec::new(),
            local: Rgb::ZERO,
            radiance: Rgb::ZERO,
        });
    }
    fn miss(&mut self, background: Rgb) {
        self.current().radiance = background;
        self.open.pop();
    }
    fn hit(&mut self, hit: &SurfaceHit) {
        self.current().hit = Some(*hit);
    }
    fn ambient(&mut self, ambient: Rgb) {
        self.current().ambient = ambient;
    }
    fn light(&mut self, light: LightRecord) {
        self.current().lights.push(light);
    }
    fn local(&mut self, local: Rgb) {
        self.current().local = local;
    }
    fn end_ray(&mut self, radiance: Rgb) {
        self.current().radiance = radiance;
        self.open.pop();
    }
}
