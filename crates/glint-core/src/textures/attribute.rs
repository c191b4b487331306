//! A mesh's own values as a texture (Mitsuba's `mesh_attribute`): a colour or weight the mesh
//! file gives per vertex (interpolated across each triangle) or per face, times `scale`.
//!
//! Scene parameters: `name` (`vertex_NAME` or `face_NAME`, as the mesh reader names a PLY
//! file's properties: `vertex_color` for r, g, b or color_0, color_1, color_2), `scale` (1).
//! ```toml
//! [textures.paint]
//! type = "mesh-attribute"
//! name = "vertex_color"
//! ```
//! On a surface that is not a mesh, or a mesh without the attribute, it is black (the scene
//! readers refuse a name no mesh of the scene has).

use super::TextureQuery;
use crate::shapes::barycentrics;
use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct AttributeTexture {
    pub name: String,
    pub scale: f32,
}

impl AttributeTexture {
    pub fn evaluate(&self, query: &TextureQuery) -> Rgb {
        let Some(at) = query.mesh else { return Rgb::ZERO };
        let barycentrics = barycentrics(at.point, at.mesh.triangle_vertices(at.triangle as usize));
        at.mesh.attribute(&self.name, at.triangle as usize, barycentrics).map_or(Rgb::ZERO, |v| v * self.scale)
    }
}
