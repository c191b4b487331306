//! glint's rendering core.
//!
//! Dependencies run one way: `integrators` → `scene` (shapes, materials, lights, accel)
//! → `geometry`. The core reads no files; scene readers live in `glint-scene`.
//! Conventions (handedness, normal orientation, units) are written once, in
//! `docs/architecture.md` and in the module docs of `geometry` and `shapes`.

pub mod accel;
pub mod camera;
pub mod error;
pub mod film;
pub mod filter;
pub mod geometry;
pub mod integrators;
pub mod lanes;
pub mod lights;
pub mod materials;
pub mod media;
pub mod named;
pub mod photons;
pub mod render;
pub mod sampling;
pub mod scene;
pub mod shapes;
pub mod textures;

pub use error::RenderError;
pub use glam::{Vec2, Vec3};
pub use named::Named;

/// Linear RGB radiance or reflectance. A plain `Vec3` keeps arithmetic cheap.
pub type Rgb = Vec3;
