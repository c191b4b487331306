//! The native scene format as serde types: exactly the fields docs/scene-format.md lists.
//! Every struct denies unknown fields, so a typo is an error, never silently ignored. This
//! file holds the file's top level and the values every table uses (colours, fractions,
//! vectors); each table's types are in the file named after it.

mod camera;
mod environment;
mod lights;
mod materials;
mod media;
mod render;
mod shapes;
mod textures;
mod transform;

use std::collections::BTreeMap;

use serde::Deserialize;

pub use self::camera::*;
pub use self::environment::*;
pub use self::lights::*;
pub use self::materials::*;
pub use self::media::*;
pub use self::render::*;
pub use self::shapes::*;
pub use self::textures::*;
pub use self::transform::*;
use crate::located::Located;

pub type Vector = [f32; 3];

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    pub camera: Located<CameraDesc>,
    #[serde(default)]
    pub render: RenderDesc,
    #[serde(default)]
    pub intersection: IntersectionDesc,
    #[serde(default)]
    pub environment: EnvironmentDesc,
    #[serde(default)]
    pub textures: BTreeMap<String, Located<TextureDesc>>,
    #[serde(default)]
    pub materials: BTreeMap<String, Located<MaterialDesc>>,
    #[serde(default)]
    pub meshes: BTreeMap<String, Located<MeshDesc>>,
    #[serde(default)]
    pub lights: Vec<Located<LightDesc>>,
    #[serde(default)]
    pub shapes: Vec<Located<ShapeDesc>>,
    /// Participating media, by name: shapes bound them (`interior`, `exterior`), the camera
    /// may be in one (`medium`).
    #[serde(default)]
    pub media: BTreeMap<String, Located<MediumDesc>>,
}

impl SceneFile {
    /// A scene of nothing but `camera` and `render` (what the other formats' readers fill).
    pub fn new(camera: CameraDesc, render: RenderDesc) -> Self {
        Self {
            camera: Located { value: camera, span: None },
            render,
            intersection: IntersectionDesc::default(),
            environment: EnvironmentDesc::default(),
            textures: BTreeMap::new(),
            materials: BTreeMap::new(),
            meshes: BTreeMap::new(),
            lights: Vec::new(),
            shapes: Vec::new(),
            media: BTreeMap::new(),
        }
    }
}

/// A fraction in [0, 1]: a number, or the name of a texture (its luminance).
#[derive(Deserialize, Debug, Clone)]
#[serde(untagged)]
pub enum FractionDesc {
    Number(f32),
    Texture(String),
}

/// A colour, or the name of a texture in `[textures]`.
#[derive(Deserialize, Debug, Clone)]
#[serde(untagged)]
pub enum ColorDesc {
    Rgb(Vector),
    Texture(String),
}

/// The default of parameters that scale (`scale`, `intensity`).
fn one() -> f32 {
    1.0
}
