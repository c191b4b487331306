//! The `[[shapes]]` array: spheres, planes, triangles, polygons, boxes, quads, meshes,
//! instances of named meshes, CSG trees (`csg.rs`) and SDF grids, each checked, given its
//! material and placed; meshes loaded once and shared through the mesh library.

use std::sync::Arc;

use glam::{Vec2, Vec3};
use glint_core::materials::Material;
use glint_core::scene::{Geometry, Object};
use glint_core::shapes::{
    AaBox, Csg, CurveBasis, Curves, Instance, IntersectMethods, Mesh, Plane, Polygon, SdfGrid, SdfNormals, Shape,
    Sphere, Triangle,
};
use glint_core::Named;

use super::checks::{finite, positive, quoted, MAX_COORDINATE};
use super::csg::{csg_tree, OperandContext};
use super::transform::build_transform;
use super::Context;
use crate::error::{did_you_mean, SceneError};
use crate::located::Located;
use crate::native::schema::*;
use crate::source::Source;

pub(super) fn build_object(
    cx: &Context,
    index: usize,
    entry: &Located<ShapeDesc>,
    materials: &[(String, Material)],
    library: &mut MeshLibrary,
    source: &Source,
    warnings: &mut Vec<String>,
) -> Result<Object, SceneError> {
    let desc = &entry.value;
    let (material_name, transform_ops, name) = desc.common();
    let label = match name {
        Some(n) => format!("shapes[{index}] ({} `{n}`)", desc.kind()),
        None => format!("shapes[{index}] ({})", desc.kind()),
    };
    let at = |key: &str, m: String| cx.error(&entry.span, Some(key), format!("{label}: {m}"));

    let material = material_index(materials, material_name).map_err(|m| at("material", m))?;

    let transform = build_transform(transform_ops).map_err(|m| at("transform", m))?;

    let shape = match desc {
        ShapeDesc::Sphere { center, radius, .. } => sphere_shape(*center, *radius).map_err(|(k, m)| at(k, m))?,
        ShapeDesc::Plane { normal, offset, point, .. } => {
            let n = finite(*normal).map_err(|m| at("normal", m))?;
            if n.length_squared() == 0.0 {
                return Err(at("normal", "`normal` must not be the zero vector".into()));
            }
            match (offset, point) {
                (Some(_), Some(_)) => {
                    return Err(at("point", "give either `offset` (D of n·P + D = 0) or `point`, not both".into()))
                }
                (_, Some(p)) => Shape::Plane(Plane::through_point(n, finite(*p).map_err(|m| at("point", m))?)),
                (d, None) => {
                    let d = d.unwrap_or(0.0);
                    if !d.is_finite() {
                        return Err(at("offset", format!("`offset` must be finite, got {d}")));
                    }
                    Shape::Plane(Plane::new(n, d))
                }
            }
        }
        ShapeDesc::Triangle { vertices, normals, uvs, .. } => {
            let mut points = [Vec3::ZERO; 3];
            for (p, v) in points.iter_mut().zip(vertices) {
                *p = finite(*v).map_err(|m| at("vertices", m))?;
            }
            let mut triangle = Triangle::new(points[0], points[1], points[2]);
            if triangle.double_area() == 0.0 {
                return Err(at(
                    "vertices",
                    "the triangle has zero area (its vertices are collinear or coincide)".into(),
                ));
            }
            if let Some(ns) = normals {
                let mut out = [Vec3::ZERO; 3];
                for (o, n) in out.iter_mut().zip(ns) {
                    *o = finite(*n)
                        .map_err(|m| at("normals", m))?
                        .try_normalize()
                        .ok_or_else(|| at("normals", "vertex normals must not be zero vectors".into()))?;
                }
                triangle.normals = Some(out);
            }
            triangle.uvs = uvs.map(|t| t.map(Vec2::from));
            Shape::Triangle(triangle)
        }
        ShapeDesc::Polygon { vertices, uvs, .. } => {
            if vertices.len() < 3 {
                return Err(at("vertices", format!("a polygon needs at least 3 vertices, got {}", vertices.len())));
            }
            let points =
                vertices.iter().map(|p| finite(*p)).collect::<Result<Vec<_>, _>>().map_err(|m| at("vertices", m))?;
            let mut polygon = Polygon::new(points)
                .ok_or_else(|| at("vertices", "the polygon has zero area (its vertices are collinear)".into()))?;
            // The even-odd and winding tests work in the polygon's plane: a vertex off it
            // would be hit somewhere else than where it is drawn.
            // Beyond 1e-4 of its size, and beyond what rounding coordinates this far from the
            // origin makes of a flat one.
            let (vertex, off) = polygon.farthest_off_plane();
            let magnitude = vertices.iter().map(|v| Vec3::from(*v).abs().max_element()).fold(0.0f32, f32::max);
            let size = vertices
                .iter()
                .map(|v| (Vec3::from(*v) - Vec3::from(vertices[0])).length())
                .fold(f32::MIN_POSITIVE, f32::max);
            if off > 1e-4 + 8.0 * f32::EPSILON * magnitude / size {
                return Err(at(
                    "vertices",
                    format!("the polygon is not planar: vertex {vertex} lies {off:.2e} of the polygon's size off its plane (a polygon must be flat; split it into triangles)"),
                ));
            }
            if let Some(uvs) = uvs {
                polygon = polygon
                    .with_uvs(uvs.iter().map(|&t| Vec2::from(t)).collect())
                    .map_err(|e| at("uvs", e.to_string()))?;
            }
            Shape::Polygon(polygon)
        }
        ShapeDesc::Box { min, max, .. } => box_shape(*min, *max).map_err(|(k, m)| at(k, m))?,
        ShapeDesc::Quad { vertices, .. } => {
            let mut positions = Vec::with_capacity(4);
            for v in vertices {
                positions.push(finite(*v).map_err(|m| at("vertices", m))?);
            }
            let mesh = Mesh {
                positions,
                normals: None,
                uvs: Some(vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y]),
                indices: vec![[0, 1, 2], [0, 2, 3]],
                ..Mesh::default()
            };
            if mesh.degenerate_triangles().count() > 0 {
                return Err(at("vertices", "the quad has a zero-area half (three collinear corners)".into()));
            }
            Shape::Mesh(mesh)
        }
        ShapeDesc::Instance { mesh, .. } => {
            let geometry = library.get(cx, mesh, source, warnings, |m| at("mesh", m))?;
            Shape::Instance(Instance { geometry })
        }
        ShapeDesc::Csg { operation, operands, .. } => {
            let mut oc = OperandContext { cx, materials, library, source, warnings, label: &label };
            let tree = csg_tree(&mut oc, &entry.span, operation, operands, None, None, "")?;
            Shape::Csg(Box::new(Csg::new(tree).map_err(|e| at("operands", e.to_string()))?))
        }
        ShapeDesc::SdfGrid { file, normals, .. } => {
            let normals = match normals.as_deref() {
                None => SdfNormals::default(),
                Some(name) => SdfNormals::from_name(name).ok_or_else(|| {
                    at("normals", format!("unknown normals `{name}`: expected {}", SdfNormals::names()))
                })?,
            };
            let key = (file.clone(), normals);
            match library.sdf_grids.iter().find(|(k, _)| *k == key) {
                Some((_, grid)) => Shape::SdfGrid(grid.clone()),
                None => {
                    let bytes = source.read(file).map_err(|m| at("file", format!("SDF grid file: {m}")))?;
                    let grid = crate::volume::read_vol(&bytes).map_err(|m| at("file", format!("`{file}`: {m}")))?;
                    if grid.channels != 1 {
                        return Err(at(
                            "file",
                            format!("`{file}` has {} channels; an SDF grid has one", grid.channels),
                        ));
                    }
                    let sdf = SdfGrid::new(grid.resolution, grid.values, normals)
                        .map_err(|m| at("file", format!("`{file}`: {m}")))?;
                    let sdf = Arc::new(sdf);
                    library.sdf_grids.push((key, sdf.clone()));
                    Shape::SdfGrid(sdf)
                }
            }
        }
        ShapeDesc::Curves { basis, file, data, .. } => {
            let basis = match basis.as_deref() {
                None => CurveBasis::default(),
                Some(name) => CurveBasis::from_name(name)
                    .ok_or_else(|| at("basis", format!("unknown basis `{name}`: expected {}", CurveBasis::names())))?,
            };
            let mut curves = match (file, data) {
                (Some(file), None) => {
                    let bytes = source.read(file).map_err(|m| at("file", format!("curve file: {m}")))?;
                    crate::mesh::read_curves(&bytes).map_err(|m| at("file", format!("`{file}`: {m}")))?
                }
                (None, Some(data)) => data.clone(),
                (Some(_), Some(_)) => {
                    return Err(at("data", "give the curves' `file` or their `data`, not both".into()))
                }
                (None, None) => return Err(at("file", "curves need a `file` (or their points in `data`)".into())),
            };
            // In world space, as meshes: the transform places the points; radii stay as given.
            if let Some(t) = &transform {
                for point in curves.iter_mut().flatten() {
                    let p = t.point(Vec3::new(point[0], point[1], point[2]));
                    point[..3].copy_from_slice(&p.to_array());
                }
            }
            let curves = Curves::new(basis, &curves).map_err(|m| at("data", m))?;
            let label = name.map_or(label, str::to_string);
            return Ok(Object { name: label, shape: Shape::Curves(Arc::new(curves)), transform: None, material });
        }
        ShapeDesc::Mesh { file, data, shape_index, smooth, flip_v, compute_normals, .. } => {
            let (mut mesh, origin) =
                mesh_of(file.as_deref(), data.as_ref(), *shape_index, source).map_err(|(k, m)| at(k, m))?;
            shade(&mut mesh, *smooth, *compute_normals);
            if let (true, Some(uvs)) = (*flip_v, &mut mesh.uvs) {
                uvs.iter_mut().for_each(|uv| uv.y = 1.0 - uv.y);
            }
            let degenerate = mesh.degenerate_triangles().count();
            if degenerate > 0 {
                warnings.push(format!("{label}: {origin} has {degenerate} zero-area triangles; they can never be hit"));
            }
            // Meshes are stored in world space: the BVH then sees their triangles directly.
            if let Some(t) = &transform {
                mesh.transform(t);
            }
            return Ok(Object { name: label, shape: Shape::Mesh(mesh), transform: None, material });
        }
    };
    // A mesh made here (a quad) is stored in world space too, so the BVH tests its
    // triangles in its blocks, not through the transform (Mitsuba's rectangles, floors and
    // area lights, all carry one; through it, the rays of its projector test spent a quarter
    // of their time setting up the two triangles' tests).
    let (shape, transform) = match (shape, transform) {
        (Shape::Mesh(mut mesh), Some(t)) => {
            mesh.transform(&t);
            (Shape::Mesh(mesh), None)
        }
        placed => placed,
    };
    Ok(Object { name: name.map_or(label, str::to_string), shape, transform, material })
}

/// A mesh's shading normals: none (flat) unless `smooth`; then the file's, or, where it has
/// none and `compute` asks, smooth ones made from the faces.
fn shade(mesh: &mut Mesh, smooth: bool, compute: bool) {
    if !smooth {
        mesh.normals = None;
    } else if compute && mesh.normals.is_none() {
        mesh.compute_vertex_normals();
    }
}

/// A mesh from its file or from the scene's own `data`, checked, and how to name it in
/// messages.
fn mesh_of(
    file: Option<&str>,
    data: Option<&MeshData>,
    shape_index: u32,
    source: &Source,
) -> Result<(Mesh, String), (&'static str, String)> {
    match (file, data) {
        (Some(file), None) => {
            let bytes = source.read(file).map_err(|m| ("file", format!("mesh file: {m}")))?;
            let mesh = crate::mesh::read_mesh_part(file, &bytes, shape_index)
                .map_err(|m| ("file", format!("mesh file `{file}`: {m}")))?;
            Ok((mesh, format!("`{file}`")))
        }
        (None, Some(data)) => {
            if shape_index != 0 {
                return Err(("shape_index", "`shape_index` picks a mesh of a file; `data` is one mesh".into()));
            }
            Ok((crate::mesh::from_data(data).map_err(|m| ("data", m))?, "its data".into()))
        }
        (Some(_), Some(_)) => Err(("data", "give a mesh's `file` or its `data`, not both".into())),
        (None, None) => Err(("file", "a mesh needs a `file` (or its triangles in `data`)".into())),
    }
}

/// Named meshes for instancing, each loaded and given its BVH on first use, then shared; and
/// SDF grids, each file read once however many shapes place it (a shapegroup's instances).
pub(super) struct MeshLibrary<'a> {
    pub(super) descs: &'a std::collections::BTreeMap<String, Located<MeshDesc>>,
    pub(super) built: Vec<(String, Arc<Geometry>)>,
    pub(super) sdf_grids: Vec<((String, SdfNormals), Arc<SdfGrid>)>,
}

impl MeshLibrary<'_> {
    /// The mesh's shared geometry; `unknown` makes the error for a name not in `[meshes]` (at
    /// the instance), problems with the file itself are reported at the mesh's entry.
    pub(super) fn get(
        &mut self,
        cx: &Context,
        name: &str,
        source: &Source,
        warnings: &mut Vec<String>,
        unknown: impl Fn(String) -> SceneError,
    ) -> Result<Arc<Geometry>, SceneError> {
        if let Some((_, g)) = self.built.iter().find(|(n, _)| n == name) {
            return Ok(g.clone());
        }
        let Some(entry) = self.descs.get(name) else {
            let hint = did_you_mean(name, self.descs.keys().map(String::as_str));
            return Err(unknown(format!("unknown mesh `{name}` (instances name a mesh defined in [meshes]){hint}")));
        };
        let desc = &entry.value;
        let (mut mesh, origin) = mesh_of(desc.file.as_deref(), desc.data.as_ref(), desc.shape_index, source)
            .map_err(|(key, m)| cx.error(&entry.span, Some(key), format!("mesh `{name}`: {m}")))?;
        shade(&mut mesh, desc.smooth, desc.compute_normals);
        if let (true, Some(uvs)) = (desc.flip_v, &mut mesh.uvs) {
            uvs.iter_mut().for_each(|uv| uv.y = 1.0 - uv.y);
        }
        let degenerate = mesh.degenerate_triangles().count();
        if degenerate > 0 {
            warnings
                .push(format!("mesh `{name}`: {origin} has {degenerate} zero-area triangles; they can never be hit"));
        }
        let object = Object { name: name.to_string(), shape: Shape::Mesh(mesh), transform: None, material: 0 };
        let geometry = Arc::new(Geometry::new(vec![object], IntersectMethods::default()));
        self.built.push((name.to_string(), geometry.clone()));
        Ok(geometry)
    }
}

/// A sphere of the scene file (a shape or a CSG operand), checked: the key at fault and why.
pub(super) fn sphere_shape(center: Vector, radius: f32) -> Result<Shape, (&'static str, String)> {
    let center = finite(center).map_err(|m| ("center", m))?;
    positive(radius).map_err(|m| ("radius", format!("`radius` {m}")))?;
    if radius > MAX_COORDINATE {
        return Err((
            "radius",
            format!(
                "`radius` must be at most {MAX_COORDINATE:e} (its square must fit in 32-bit floats), got {radius:e}"
            ),
        ));
    }
    Ok(Shape::Sphere(Sphere::new(center, radius)))
}

/// An axis-aligned box of the scene file (a shape or a CSG operand), checked.
pub(super) fn box_shape(min: Vector, max: Vector) -> Result<Shape, (&'static str, String)> {
    let (lo, hi) = (finite(min).map_err(|m| ("min", m))?, finite(max).map_err(|m| ("max", m))?);
    if !lo.cmplt(hi).all() {
        return Err(("max", format!("`max` must exceed `min` on every axis, got min = {lo}, max = {hi}")));
    }
    Ok(Shape::AaBox(AaBox::new(lo, hi)))
}

/// The index of the material named `name`, or what names there are.
pub(super) fn material_index(materials: &[(String, Material)], name: &str) -> Result<u32, String> {
    let index = materials.iter().position(|(n, _)| n == name).ok_or_else(|| {
        let hint = did_you_mean(name, materials.iter().map(|(n, _)| n.as_str()));
        let known = if materials.is_empty() {
            "no materials are defined".to_string()
        } else {
            format!("defined materials: {}", quoted(&materials.iter().map(|(n, _)| n.as_str()).collect::<Vec<_>>()))
        };
        format!("unknown material `{name}` ({known}){hint}")
    })?;
    Ok(index as u32)
}
