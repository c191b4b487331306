//! The `[[shapes]]` array, CSG operands, and the `[meshes]` table that instances place.

use serde::Deserialize;

use super::{TransformOp, Vector};

/// Shapes. `material` names an entry of `[materials]`; `transform` is a list of operations
/// applied in order (the first one is applied to the shape first); `name` is for messages.
#[derive(Deserialize, Debug, Clone)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
pub enum ShapeDesc {
    Sphere {
        #[serde(default)]
        center: Vector,
        radius: f32,
        material: String,
        /// Media inside (behind the normals) and outside (names in `[media]`).
        interior: Option<String>,
        exterior: Option<String>,
        #[serde(default)]
        transform: Vec<TransformOp>,
        name: Option<String>,
    },
    Plane {
        normal: Vector,
        offset: Option<f32>,
        point: Option<Vector>,
        material: String,
        #[serde(default)]
        transform: Vec<TransformOp>,
        name: Option<String>,
    },
    Triangle {
        vertices: [Vector; 3],
        normals: Option<[Vector; 3]>,
        uvs: Option<[[f32; 2]; 3]>,
        material: String,
        #[serde(default)]
        transform: Vec<TransformOp>,
        name: Option<String>,
    },
    Polygon {
        vertices: Vec<Vector>,
        uvs: Option<Vec<[f32; 2]>>,
        material: String,
        #[serde(default)]
        transform: Vec<TransformOp>,
        name: Option<String>,
    },
    Box {
        min: Vector,
        max: Vector,
        material: String,
        /// Media inside (behind the normals) and outside (names in `[media]`).
        interior: Option<String>,
        exterior: Option<String>,
        #[serde(default)]
        transform: Vec<TransformOp>,
        name: Option<String>,
    },
    /// A mesh file, or the mesh itself in `data`.
    Mesh {
        file: Option<String>,
        data: Option<MeshData>,
        /// Which mesh of a file that holds several (a Mitsuba `.serialized` file).
        #[serde(default)]
        shape_index: u32,
        #[serde(default = "yes")]
        smooth: bool,
        /// v ← 1 − v for the file's texture coordinates (files whose v runs down the image).
        #[serde(default)]
        flip_v: bool,
        /// Where the file has no normals (and `smooth`), make smooth ones as Mitsuba does.
        #[serde(default)]
        compute_normals: bool,
        material: String,
        /// Media inside (behind the normals) and outside (names in `[media]`).
        interior: Option<String>,
        exterior: Option<String>,
        #[serde(default)]
        transform: Vec<TransformOp>,
        name: Option<String>,
    },
    /// Four corners v0..v3, split into triangles (v0, v1, v2) and (v0, v2, v3); flat-shaded with
    /// the normal (v1 − v0) × (v2 − v0); uv (0,0), (1,0), (1,1), (0,1) at the corners.
    Quad {
        vertices: [Vector; 4],
        material: String,
        /// Media inside (behind the normals) and outside (names in `[media]`).
        interior: Option<String>,
        exterior: Option<String>,
        #[serde(default)]
        transform: Vec<TransformOp>,
        name: Option<String>,
    },
    Instance {
        mesh: String,
        material: String,
        /// Media inside (behind the normals) and outside (names in `[media]`).
        interior: Option<String>,
        exterior: Option<String>,
        #[serde(default)]
        transform: Vec<TransformOp>,
        name: Option<String>,
    },
    /// The surface where a grid of signed distances over the unit cube changes sign (a
    /// Mitsuba `.vol` file of one channel, its own box ignored: the grid spans [0, 1]³, placed
    /// by `transform`); `normals` `smooth` (default) or `analytic`.
    SdfGrid {
        file: String,
        normals: Option<String>,
        material: String,
        #[serde(default)]
        transform: Vec<TransformOp>,
        name: Option<String>,
    },
    /// Tubes along curves (hair, fur, wires): `basis` `linear` (straight segments, round
    /// joints and ends; the default), `bspline` (uniform cubic B-spline, open ends) or
    /// `bezier` (cubic Bézier segments); the control points (x, y, z, radius) from `file`
    /// (Mitsuba's curve files: one point a line, a blank line between curves) or `data` (a
    /// list of curves, each a list of points). `transform` places the points; radii are in
    /// world units, as given.
    Curves {
        basis: Option<String>,
        file: Option<String>,
        data: Option<Vec<Vec<[f32; 4]>>>,
        material: String,
        #[serde(default)]
        transform: Vec<TransformOp>,
        name: Option<String>,
    },
    /// Constructive solid geometry: `operation` (`union`, `intersection`, or `difference`: the
    /// first operand less the others) over two or more closed `operands`.
    Csg {
        operation: String,
        operands: Vec<OperandDesc>,
        material: String,
        #[serde(default)]
        transform: Vec<TransformOp>,
        name: Option<String>,
    },
}

/// A CSG operand (not `Located`: serde buffers a tagged enum's fields, and a span cannot be
/// read back from the buffer; errors name the operand's path instead): a closed solid (planes, polygons, triangles and open meshes bound none), its
/// material its own or, if not given, the enclosing node's.
#[derive(Deserialize, Debug, Clone)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
pub enum OperandDesc {
    Sphere {
        #[serde(default)]
        center: Vector,
        radius: f32,
        material: Option<String>,
        #[serde(default)]
        transform: Vec<TransformOp>,
    },
    Box {
        min: Vector,
        max: Vector,
        material: Option<String>,
        #[serde(default)]
        transform: Vec<TransformOp>,
    },
    /// A closed mesh of `[meshes]`, through its own BVH.
    Instance {
        mesh: String,
        material: Option<String>,
        #[serde(default)]
        transform: Vec<TransformOp>,
    },
    Csg {
        operation: String,
        operands: Vec<OperandDesc>,
        material: Option<String>,
        #[serde(default)]
        transform: Vec<TransformOp>,
    },
}

fn yes() -> bool {
    true
}

impl ShapeDesc {
    pub fn common(&self) -> (&str, &[TransformOp], Option<&str>) {
        match self {
            ShapeDesc::Sphere { material, transform, name, .. }
            | ShapeDesc::Plane { material, transform, name, .. }
            | ShapeDesc::Triangle { material, transform, name, .. }
            | ShapeDesc::Polygon { material, transform, name, .. }
            | ShapeDesc::Box { material, transform, name, .. }
            | ShapeDesc::Mesh { material, transform, name, .. }
            | ShapeDesc::Quad { material, transform, name, .. }
            | ShapeDesc::Instance { material, transform, name, .. }
            | ShapeDesc::Csg { material, transform, name, .. }
            | ShapeDesc::SdfGrid { material, transform, name, .. }
            | ShapeDesc::Curves { material, transform, name, .. } => (material, transform, name.as_deref()),
        }
    }

    /// The shape's transform and name, to place a copy of it elsewhere.
    pub fn placement_mut(&mut self) -> (&mut Vec<TransformOp>, &mut Option<String>) {
        match self {
            ShapeDesc::Sphere { transform, name, .. }
            | ShapeDesc::Plane { transform, name, .. }
            | ShapeDesc::Triangle { transform, name, .. }
            | ShapeDesc::Polygon { transform, name, .. }
            | ShapeDesc::Box { transform, name, .. }
            | ShapeDesc::Mesh { transform, name, .. }
            | ShapeDesc::Quad { transform, name, .. }
            | ShapeDesc::Instance { transform, name, .. }
            | ShapeDesc::Csg { transform, name, .. }
            | ShapeDesc::SdfGrid { transform, name, .. }
            | ShapeDesc::Curves { transform, name, .. } => (transform, name),
        }
    }

    /// A mesh shape as an instance named `mesh`, with the mesh it places (for `[meshes]`), so
    /// that every placement shares one BVH (Mitsuba's shapegroups, pbrt's objects); any other
    /// shape as it is, with no mesh.
    pub fn into_instance(self, mesh: &str) -> (ShapeDesc, Option<MeshDesc>) {
        match self {
            ShapeDesc::Mesh {
                file,
                data,
                shape_index,
                smooth,
                flip_v,
                compute_normals,
                material,
                transform,
                name,
                interior,
                exterior,
            } => (
                ShapeDesc::Instance { interior, exterior, mesh: mesh.to_string(), material, transform, name },
                Some(MeshDesc { file, data, shape_index, smooth, flip_v, compute_normals }),
            ),
            other => (other, None),
        }
    }

    /// The media inside and outside the shape, where it bounds any.
    pub fn media(&self) -> (Option<&str>, Option<&str>) {
        match self {
            ShapeDesc::Sphere { interior, exterior, .. }
            | ShapeDesc::Box { interior, exterior, .. }
            | ShapeDesc::Mesh { interior, exterior, .. }
            | ShapeDesc::Quad { interior, exterior, .. }
            | ShapeDesc::Instance { interior, exterior, .. } => (interior.as_deref(), exterior.as_deref()),
            _ => (None, None),
        }
    }

    /// The media inside and outside, to set; `None` for a shape that cannot bound media.
    pub fn media_mut(&mut self) -> Option<(&mut Option<String>, &mut Option<String>)> {
        match self {
            ShapeDesc::Sphere { interior, exterior, .. }
            | ShapeDesc::Box { interior, exterior, .. }
            | ShapeDesc::Mesh { interior, exterior, .. }
            | ShapeDesc::Quad { interior, exterior, .. }
            | ShapeDesc::Instance { interior, exterior, .. } => Some((interior, exterior)),
            _ => None,
        }
    }

    pub fn kind(&self) -> &'static str {
        match self {
            ShapeDesc::Sphere { .. } => "sphere",
            ShapeDesc::Plane { .. } => "plane",
            ShapeDesc::Triangle { .. } => "triangle",
            ShapeDesc::Polygon { .. } => "polygon",
            ShapeDesc::Box { .. } => "box",
            ShapeDesc::Mesh { .. } => "mesh",
            ShapeDesc::Quad { .. } => "quad",
            ShapeDesc::Instance { .. } => "instance",
            ShapeDesc::Csg { .. } => "csg",
            ShapeDesc::SdfGrid { .. } => "sdf-grid",
            ShapeDesc::Curves { .. } => "curves",
        }
    }
}

/// A mesh loaded once and placed any number of times by `instance` shapes.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct MeshDesc {
    /// A mesh file, or else `data`.
    pub file: Option<String>,
    pub data: Option<MeshData>,
    /// Which mesh of a file that holds several, as for a `mesh` shape.
    #[serde(default)]
    pub shape_index: u32,
    #[serde(default = "yes")]
    pub smooth: bool,
    /// v ← 1 − v for the file's texture coordinates, as for a `mesh` shape.
    #[serde(default)]
    pub flip_v: bool,
    /// Smooth normals where the file has none, as for a `mesh` shape.
    #[serde(default)]
    pub compute_normals: bool,
}

/// A triangle mesh written in the scene itself (pbrt's `trianglemesh`, glTF's primitives):
/// `normals`, `uvs` and `colors`, if given, one per position; the colours are the mesh's
/// `vertex_color` attribute (a `mesh-attribute` texture reads them).
#[derive(Deserialize, Debug, Clone, Default)]
#[serde(deny_unknown_fields)]
pub struct MeshData {
    pub positions: Vec<Vector>,
    pub indices: Vec<[u32; 3]>,
    pub normals: Option<Vec<Vector>>,
    pub uvs: Option<Vec<[f32; 2]>>,
    pub colors: Option<Vec<Vector>>,
}
