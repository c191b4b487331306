//! Shapes: meshes from files, Mitsuba's analytic shapes (rectangle, cube, sphere, disk,
//! cylinder, as meshes carrying Mitsuba's uv where glint's own parametrization differs),
//! sdfgrid, and shape groups placed by instances.

use glam::Vec3;

use super::{Result, Translator};
use crate::located::Located;
use crate::mesh::parametric::grid;
use crate::mitsuba::xml::Element;
use crate::native::schema::*;

impl<'a> Translator<'a> {
    pub(super) fn shape(&mut self, shape: &'a Element) -> Result<()> {
        let kind = shape.attribute("type").unwrap_or("");
        match kind {
            "shapegroup" => return self.shape_group(shape),
            "instance" => return self.instance(shape),
            _ => {}
        }
        let p = self.properties(shape);
        let name = shape.attribute("id").map(str::to_string).or(Some(format!("{kind}@{}", shape.position.line)));
        let transform_matrix = p.transform(self, "to_world")?;
        let transform: Vec<TransformOp> =
            transform_matrix.map(|m| vec![TransformOp::Matrix(m.transpose().to_cols_array_2d())]).unwrap_or_default();
        let face_normals = p.boolean(self, "face_normals")?.unwrap_or(false);
        let flip_normals = p.boolean(self, "flip_normals")?.unwrap_or(false);

        let mut bsdf = None;
        let mut emission = None;
        let (mut interior, mut exterior) = (None, None);
        for child in &shape.children {
            let target = match child.tag.as_str() {
                "ref" => self.resolve(child)?,
                _ => child,
            };
            match (target.tag.as_str(), child.attribute("name")) {
                ("emitter", _) => {
                    if emission.is_some() {
                        return Err(self.error(&child.position, "a shape can have only one emitter"));
                    }
                    // An emitter with an id (a top-level one by reference): Mitsuba attaches it
                    // to one shape.
                    if let Some(id) = target.attribute("id") {
                        if !self.attached_emitters.insert(id.to_string()) {
                            return Err(self.error(
                                &child.position,
                                format!("the area emitter `{id}` is already attached to another shape; Mitsuba attaches an emitter to a single shape"),
                            ));
                        }
                    }
                    emission = Some(self.area_emitter(target)?);
                }
                ("bsdf", name) => {
                    bsdf = Some(target);
                    if let Some(name) = name {
                        p.used.borrow_mut().insert(name.to_string()); // `<ref name="bsdf" …/>`
                    }
                }
                ("medium", Some(side @ ("interior" | "exterior"))) => {
                    let medium = Some(self.medium(target)?);
                    *if side == "interior" { &mut interior } else { &mut exterior } = medium;
                    p.used.borrow_mut().insert(side.to_string());
                }
                ("medium", _) => {
                    return Err(self.error(&child.position, "a shape's medium is named `interior` or `exterior`"))
                }
                (other, _) if child.tag == "ref" => {
                    return Err(self.error(
                        &child.position,
                        format!(
                            "a shape can refer to a <bsdf> or a <medium>, not to <{other}> `{}`",
                            child.attribute("id").unwrap_or("")
                        ),
                    ))
                }
                _ => {}
            }
        }
        let has_media = interior.is_some() || exterior.is_some();
        if flip_normals && (emission.is_some() || has_media || bsdf.is_some_and(|b| self.is_dielectric(b))) {
            return Err(self.error(
                &shape.position,
                "`flip_normals` on an emitter, a dielectric or a medium's boundary is not supported (it would swap the emitting side or the inside)",
            ));
        }
        let emits = emission.is_some();
        let material = self.material_for(bsdf, emission, &shape.position)?;
        let span = shape.position.span.clone();
        // A shape Mitsuba parametrizes analytically, as a mesh carrying Mitsuba's uv.
        let parametric = |data: MeshData, smooth: bool| ShapeDesc::Mesh {
            interior: interior.clone(),
            exterior: exterior.clone(),
            file: None,
            data: Some(data),
            shape_index: 0,
            smooth,
            flip_v: false,
            compute_normals: false,
            material: material.clone(),
            transform: transform.clone(),
            name: name.clone(),
        };
        let desc = match kind {
            "obj" | "ply" | "serialized" => {
                let file = p.string(self, "filename")?.ok_or_else(|| {
                    self.error(&shape.position, format!("<shape type=\"{kind}\"> needs a `filename`"))
                })?;
                let shape_index = match (kind, p.integer(self, "shape_index")?) {
                    (_, None) => 0,
                    ("serialized", Some(i)) => u32::try_from(i).map_err(|_| {
                        self.error(&shape.position, format!("`shape_index` must be ≥ 0, got {i}"))
                    })?,
                    (_, Some(_)) => {
                        return Err(self.error(&shape.position, "`shape_index` belongs to serialized meshes"))
                    }
                };
                // Mitsuba's OBJ loader turns v over (v ← 1 − v) unless told not to; its PLY
                // loader only when told to, its serialized loader never (checked against
                // Mitsuba 3.9).
                let flip_v = match kind {
                    "obj" => p.boolean(self, "flip_tex_coords")?.unwrap_or(true),
                    "ply" => p.boolean(self, "flip_tex_coords")?.unwrap_or(false),
                    _ => false,
                };
                // Mitsuba makes smooth normals for a file without them.
                ShapeDesc::Mesh {
                    interior,
                    exterior,
                    file: Some(file),
                    data: None,
                    shape_index,
                    smooth: !face_normals,
                    flip_v,
                    compute_normals: true,
                    material,
                    transform,
                    name,
                }
            }
            "rectangle" => ShapeDesc::Quad {
                interior,
                exterior,
                vertices: [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]],
                material,
                transform,
                name,
            },
            "cube" => parametric(mitsuba_cube(), false),
            "sphere" => {
                let center = p.point(self, "center")?.unwrap_or(Vec3::ZERO);
                let radius = p.float(self, "radius")?.unwrap_or(1.0);
                // Mitsuba's sphere has its poles on its local z axis (u = φ/2π from +x toward
                // +y, v = θ/π from +z); glint's on y (v = 1 at +y). Turning the sphere by −90°
                // about x first maps glint's parametrization onto Mitsuba's.
                let mut placed = vec![
                    TransformOp::Rotate(RotateDesc { axis: [1.0, 0.0, 0.0], angle: -90.0 }),
                    TransformOp::Translate(center.to_array()),
                ];
                placed.extend(transform);
                ShapeDesc::Sphere {
                    interior,
                    exterior,
                    center: [0.0; 3],
                    radius,
                    material,
                    transform: placed,
                    name,
                }
            }
            "disk" | "cylinder" if has_media => {
                return Err(self.error(
                    &shape.position,
                    format!("media on a <shape type=\"{kind}\"> are not supported: bound a medium by a closed mesh, cube or sphere"),
                ))
            }
            "disk" => parametric(mitsuba_disk(), false),
            "cylinder" => {
                let p0 = p.point(self, "p0")?.unwrap_or(Vec3::ZERO);
                let p1 = p.point(self, "p1")?.unwrap_or(Vec3::Z);
                let radius = p.float(self, "radius")?.unwrap_or(1.0);
                if (p1 - p0).length() <= 0.0 || radius <= 0.0 {
                    return Err(self.error(&shape.position, "a cylinder needs p0 ≠ p1 and a radius > 0"));
                }
                parametric(mitsuba_cylinder(p0, p1, radius), !face_normals)
            }
            "sdfgrid" => {
                if emits || has_media || flip_normals {
                    return Err(self.error(
                        &shape.position,
                        "an sdfgrid can be neither an emitter (it has no sampling routine, in Mitsuba either) nor a medium's boundary, nor have its normals flipped",
                    ));
                }
                let file = p.string(self, "filename")?.ok_or_else(|| {
                    self.error(&shape.position, "<shape type=\"sdfgrid\"> needs a `filename` (a .vol file of one channel)")
                })?;
                let normals = p.string(self, "normals")?;
                if let Some(n) = normals.as_deref().filter(|n| !matches!(*n, "smooth" | "analytic")) {
                    return Err(self.error(
                        &shape.position,
                        format!("an sdfgrid's `normals` is `smooth` or `analytic`, not `{n}`"),
                    ));
                }
                ShapeDesc::SdfGrid { file, normals, material, transform, name }
            }
            "linearcurve" | "bsplinecurve" => {
                if emits || has_media || flip_normals {
                    return Err(self.error(
                        &shape.position,
                        format!("a {kind} can be neither an emitter (it has no sampling routine) nor a medium's boundary, nor have its normals flipped"),
                    ));
                }
                let file = p.string(self, "filename")?.ok_or_else(|| {
                    self.error(&shape.position, format!("<shape type=\"{kind}\"> needs a `filename` (a curve file)"))
                })?;
                let basis = Some(if kind == "linearcurve" { "linear" } else { "bspline" }.to_string());
                ShapeDesc::Curves { basis, file: Some(file), data: None, material, transform, name }
            }
            _ => {
                let why = match kind {
                    "ellipsoids" | "ellipsoidsmesh" => " (glint has no ellipsoid primitives)",
                    _ => "",
                };
                return Err(self.error(
                    &shape.position,
                    format!(
                        "<shape type=\"{kind}\"> is not supported{why}; glint reads obj, ply, serialized, rectangle, cube, sphere, disk, cylinder, sdfgrid, linearcurve and bsplinecurve"
                    ),
                ))
            }
        };
        self.scene.shapes.push(Located { value: desc, span });
        self.unused(&p);
        Ok(())
    }

    /// A `shapegroup`: its shapes made, kept aside under its id until instances place them.
    /// Its meshes become instanced meshes (loaded once however many instances there are).
    fn shape_group(&mut self, group: &'a Element) -> Result<()> {
        let id = group
            .attribute("id")
            .ok_or_else(|| self.error(&group.position, "a shapegroup needs an `id` for its instances to refer to"))?;
        let first = self.scene.shapes.len();
        for child in group.children.iter().filter(|c| c.tag == "shape") {
            if matches!(child.attribute("type"), Some("shapegroup" | "instance")) {
                return Err(self.error(&child.position, "a shapegroup holds plain shapes, not groups or instances"));
            }
            let is_emitter = |c: &Element| {
                c.tag == "emitter"
                    || (c.tag == "ref"
                        && c.attribute("id").and_then(|id| self.ids.get(id)).is_some_and(|t| t.tag == "emitter"))
            };
            if let Some(emitter) = child.children.iter().find(|c| is_emitter(c)) {
                return Err(self.error(&emitter.position, "an emitter inside a shapegroup is not supported"));
            }
            self.shape(child)?;
        }
        let shapes: Vec<Located<ShapeDesc>> = self.scene.shapes.drain(first..).collect();
        let mut members = Vec::with_capacity(shapes.len());
        for (i, member) in shapes.into_iter().enumerate() {
            let name = format!("{id}#{i}");
            let (value, mesh) = member.value.into_instance(&name);
            if let Some(mesh) = mesh {
                self.scene.meshes.insert(name, Located { value: mesh, span: member.span.clone() });
            }
            members.push(Located { value, span: member.span });
        }
        self.unused(&self.properties(group));
        self.groups.insert(id.to_string(), members);
        Ok(())
    }

    /// An `instance` of a shapegroup: each of the group's shapes, moved by its `to_world`.
    fn instance(&mut self, instance: &'a Element) -> Result<()> {
        let p = self.properties(instance);
        let to_world = p.transform(self, "to_world")?;
        let reference = instance
            .children
            .iter()
            .find(|c| c.tag == "ref")
            .ok_or_else(|| self.error(&instance.position, "an instance needs a <ref> to its shapegroup"))?;
        let id = reference.attribute("id").unwrap_or("");
        let Some(members) = self.groups.get(id) else {
            let hint = crate::error::did_you_mean_among_keys(id, self.groups.keys());
            return Err(
                self.error(&reference.position, format!("no shapegroup `{id}` declared before this instance{hint}"))
            );
        };
        let mut placed = members.clone();
        for member in &mut placed {
            let (transform, name) = member.value.placement_mut();
            if let Some(m) = to_world {
                transform.push(TransformOp::Matrix(m.transpose().to_cols_array_2d()));
            }
            *name = name.as_ref().map(|n| format!("{n}@instance:{}", instance.position.line));
        }
        self.scene.shapes.extend(placed);
        self.unused(&p);
        Ok(())
    }
}

/// Segments of a full turn of Mitsuba's disk and cylinder: the chord's sag is 0.03 % of the
/// radius.
const SEGMENTS: usize = 128;
/// Rings of the disk: its uv's angle is exact along the rings' edges and interpolated across
/// the centre's fan only, inside radius 1/16.
const DISK_RINGS: usize = 16;

/// Mitsuba's disk: radius 1 in the z = 0 plane, facing +z, with its uv (r, φ/2π), φ from +x
/// toward +y.
fn mitsuba_disk() -> MeshData {
    let mut data = grid(SEGMENTS, DISK_RINGS, |s, r| {
        let phi = std::f32::consts::TAU * s;
        (Vec3::new(r * phi.cos(), r * phi.sin(), 0.0), Vec3::Z)
    });
    data.normals = None; // flat
    if let Some(uvs) = &mut data.uvs {
        uvs.iter_mut().for_each(|uv| uv.swap(0, 1));
    }
    data
}

/// Mitsuba's cylinder from `p0` to `p1` (open, no caps) with smooth outward normals and its
/// uv (φ/2π, the fraction of the way from p0 to p1), φ measured in the frame Mitsuba builds
/// around the axis (from +x toward +y for an axis along +z).
fn mitsuba_cylinder(p0: Vec3, p1: Vec3, radius: f32) -> MeshData {
    let axis = p1 - p0;
    let (x, y) = glint_core::geometry::orthonormal_basis(axis.normalize());
    grid(SEGMENTS, 1, |s, h| {
        let phi = std::f32::consts::TAU * s;
        let n = phi.cos() * x + phi.sin() * y;
        (p0 + h * axis + radius * n, n)
    })
}

/// Mitsuba's cube: [−1, 1]³ as 12 flat triangles, each face with the uv Mitsuba's own mesh
/// gives it (read off Mitsuba 3.9: each face's uv is its two other coordinates mapped to
/// [0, 1], swapped or turned over face by face).
fn mitsuba_cube() -> MeshData {
    let mut data = MeshData::default();
    let mut uvs = Vec::new();
    // (axis, side, uv of the face's point l ∈ [0, 1]³)
    type FaceUv = fn(Vec3) -> [f32; 2];
    let faces: [(usize, f32, FaceUv); 6] = [
        (2, 1.0, |l| [l.y, l.x]),
        (2, -1.0, |l| [1.0 - l.y, l.x]),
        (0, 1.0, |l| [l.y, 1.0 - l.z]),
        (0, -1.0, |l| [l.y, l.z]),
        (1, 1.0, |l| [1.0 - l.x, 1.0 - l.z]),
        (1, -1.0, |l| [l.z, l.x]),
    ];
    for (axis, side, uv) in faces {
        let first = data.positions.len() as u32;
        let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
        for (i, j) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
            let mut l = Vec3::splat(0.0);
            l[axis] = 0.5 + 0.5 * side;
            (l[a], l[b]) = (i, j);
            data.positions.push((2.0 * l - Vec3::ONE).to_array());
            uvs.push(uv(l));
        }
        // Corners go counter-clockwise about +axis (a, b, axis is right-handed): flip the
        // winding on the face looking down −axis.
        let [v0, v1, v2, v3] = [first, first + 1, first + 2, first + 3];
        data.indices.extend(if side > 0.0 { [[v0, v1, v2], [v0, v2, v3]] } else { [[v0, v2, v1], [v0, v3, v2]] });
    }
    data.uvs = Some(uvs);
    data
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each triangle of `data` with its corners, normal (unnormalized) and corner uvs.
    fn triangles(data: &MeshData) -> Vec<([Vec3; 3], Vec3, [[f32; 2]; 3])> {
        let uvs = data.uvs.as_ref().unwrap();
        data.indices
            .iter()
            .map(|t| {
                let p = t.map(|i| Vec3::from(data.positions[i as usize]));
                (p, (p[1] - p[0]).cross(p[2] - p[0]), t.map(|i| uvs[i as usize]))
            })
            .collect()
    }

    #[test]
    fn the_disk_faces_up_with_uv_radius_and_angle() {
        let disk = mitsuba_disk();
        let area: f32 = triangles(&disk).iter().map(|(_, n, _)| 0.5 * n.length()).sum();
        assert!((area / std::f32::consts::PI - 1.0).abs() < 1e-3, "{area}");
        for (p, n, uv) in triangles(&disk) {
            assert!(n.z > 0.0, "the disk faces +z");
            for (p, uv) in p.iter().zip(uv) {
                // u = r exactly; v = φ/2π wherever φ is defined (v = 1 closes the seam).
                assert!((uv[0] - p.length()).abs() < 1e-6, "{p} {uv:?}");
                let phi = p.y.atan2(p.x).rem_euclid(std::f32::consts::TAU) / std::f32::consts::TAU;
                assert!(p.length() < 1e-6 || (uv[1] - phi).abs() < 1e-5 || (uv[1] - 1.0).abs() < 1e-6, "{p} {uv:?}");
            }
        }
    }

    #[test]
    fn the_cylinder_faces_out_with_uv_angle_and_height() {
        let cylinder = mitsuba_cylinder(Vec3::ZERO, Vec3::new(0.0, 0.0, 2.0), 0.5);
        let area: f32 = triangles(&cylinder).iter().map(|(_, n, _)| 0.5 * n.length()).sum();
        assert!((area / (2.0 * std::f32::consts::PI) - 1.0).abs() < 1e-3, "{area}");
        for (p, n, uv) in triangles(&cylinder) {
            let centroid = (p[0] + p[1] + p[2]) / 3.0;
            assert!(n.dot(Vec3::new(centroid.x, centroid.y, 0.0)) > 0.0, "outward");
            for (p, uv) in p.iter().zip(uv) {
                assert!((uv[1] - p.z / 2.0).abs() < 1e-6, "{p} {uv:?}");
                let phi = p.y.atan2(p.x).rem_euclid(std::f32::consts::TAU) / std::f32::consts::TAU;
                assert!((uv[0] - phi).abs() < 1e-5 || (uv[0] - 1.0).abs() < 1e-6, "{p} {uv:?}");
            }
        }
        let normals = cylinder.normals.unwrap();
        assert!(normals.iter().all(|n| Vec3::from(*n).z == 0.0 && (Vec3::from(*n).length() - 1.0).abs() < 1e-6));
    }

    #[test]
    fn the_cube_is_closed_faces_out_and_maps_each_face_onto_the_unit_square() {
        let cube = mitsuba_cube();
        let found = triangles(&cube);
        assert_eq!(found.len(), 12);
        // The divergence theorem: Σ (centroid · n) / 3 over the faces is the volume, 8.
        let volume: f32 = found.iter().map(|(p, n, _)| (p[0] + p[1] + p[2]).dot(*n) / 18.0).sum();
        assert!((volume - 8.0).abs() < 1e-5, "{volume}");
        for (p, n, uv) in found {
            assert!(n.dot(p[0] + p[1] + p[2]) > 0.0, "outward");
            let corners = uv.iter().flatten().all(|&x| x == 0.0 || x == 1.0);
            assert!(corners, "{uv:?}");
        }
    }
}
