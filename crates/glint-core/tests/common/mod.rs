//! Helpers shared by the core's integration tests.
#![allow(dead_code)]

use glint_core::camera::Camera;
use glint_core::materials::{Material, Phong};
use glint_core::scene::{Object, Scene, SceneBuilder};
use glint_core::shapes::{IntersectMethods, Shape};
use glint_core::{Rgb, Vec3};

/// SplitMix64: deterministic random numbers for tests.
pub struct TestRng(pub u64);

impl TestRng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * ((self.next_u64() >> 40) as f32 / (1u64 << 24) as f32)
    }
    pub fn vec3(&mut self, lo: f32, hi: f32) -> Vec3 {
        Vec3::new(self.range(lo, hi), self.range(lo, hi), self.range(lo, hi))
    }
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }
}

pub fn object(shape: Shape) -> Object {
    Object { name: shape.kind().into(), shape, transform: None, material: 0 }
}

pub fn object_with(shape: Shape, material: u32) -> Object {
    Object { material, ..object(shape) }
}

pub fn white() -> Vec<(String, Material)> {
    vec![(
        "white".into(),
        Material::Phong(Phong {
            ambient: Some(glint_core::textures::Texture::Constant(Rgb::ZERO)),
            ..Phong::default()
        }),
    )]
}

pub fn scene(objects: Vec<Object>) -> Scene {
    scene_with_methods(objects, IntersectMethods::default())
}

pub fn scene_with_methods(objects: Vec<Object>, methods: IntersectMethods) -> Scene {
    let camera = Camera::new(Vec3::new(0.0, 0.0, -5.0), Vec3::ZERO, Vec3::Y, 45.0, 16, 16).unwrap();
    SceneBuilder::new(camera).objects(objects).materials(white()).methods(methods).build()
}
