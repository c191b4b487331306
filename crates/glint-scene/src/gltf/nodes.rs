//! A glTF document's default scene walked node by node: each mesh primitive placed by its
//! node's world transform (a mesh placed more than once goes into the mesh library and is
//! instanced, unless it emits light: glint samples emitting meshes, not instances), the first
//! camera met (or, without one, a camera that frames the scene), and KHR_lights_punctual.

use std::collections::HashMap;
use std::path::Path;

use glam::{Mat4, Vec3};
use gltf::khr_lights_punctual::Kind;

use super::materials::{self, MaterialInfo};
use crate::located::Located;
use crate::native::schema::*;

/// glTF's photometric units (candela, lux) to glint's radiometric ones: 683 lm/W.
const LUMENS_PER_WATT: f32 = 683.0;

/// The image width glint gives a glTF camera (glTF gives only the aspect ratio).
const WIDTH: u32 = 960;

pub struct Reader<'a> {
    document: &'a gltf::Document,
    buffers: &'a [Vec<u8>],
    images: &'a [String],
    name: &'a Path,
}

/// One primitive's triangles in its mesh's space.
struct Primitive {
    data: MeshData,
    material: usize,
}

impl<'a> Reader<'a> {
    pub fn new(document: &'a gltf::Document, buffers: &'a [Vec<u8>], images: &'a [String], name: &'a Path) -> Self {
        Self { document, buffers, images, name }
    }

    pub fn translate(&self) -> Result<(SceneFile, Vec<String>), String> {
        let mut warnings = Vec::new();
        let mut scene = SceneFile::new(
            framing_camera(None, 4.0 / 3.0),
            RenderDesc { integrator: "path".into(), spp: 64, max_depth: -1, ..RenderDesc::default() },
        );
        let materials = materials::translate(self.document, self.images, &mut scene, &mut warnings)?;

        let Some(gltf_scene) = self.document.default_scene().or_else(|| self.document.scenes().next()) else {
            return Err("the file has no scene".into());
        };
        // The nodes with their world transforms, parents first.
        let mut placed: Vec<(gltf::Node, Mat4)> = Vec::new();
        // glTF's nodes form disjoint trees: a node reached twice is a cycle or a shared child.
        let mut reached = vec![false; self.document.nodes().len()];
        let mut stack: Vec<(gltf::Node, Mat4, usize)> =
            gltf_scene.nodes().map(|n| (n, Mat4::IDENTITY, 0)).collect::<Vec<_>>().into_iter().rev().collect();
        while let Some((node, parent, depth)) = stack.pop() {
            if depth > 256 || std::mem::replace(&mut reached[node.index()], true) {
                return Err(format!(
                    "node {} is reached twice (glTF's node hierarchy is a set of disjoint trees) or lies deeper than 256",
                    node.index()
                ));
            }
            let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
            for child in node.children().collect::<Vec<_>>().into_iter().rev() {
                stack.push((child, world, depth + 1));
            }
            placed.push((node, world));
        }
        if placed.iter().any(|(n, _)| n.skin().is_some()) || self.document.animations().next().is_some() {
            warnings.push(format!(
                "{}: skins and animations are not read: meshes are shown as stored",
                self.name.display()
            ));
        }

        let mut primitives: HashMap<usize, Vec<Primitive>> = HashMap::new();
        let mut uses: HashMap<usize, usize> = HashMap::new();
        for (node, _) in &placed {
            if let Some(mesh) = node.mesh() {
                *uses.entry(mesh.index()).or_default() += 1;
                if let std::collections::hash_map::Entry::Vacant(entry) = primitives.entry(mesh.index()) {
                    entry.insert(self.primitives(&mesh, &mut warnings)?);
                }
            }
        }

        let mut bounds = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        let mut camera = None;
        let mut hidden = 0;
        for (node, world) in &placed {
            if !world.is_finite() {
                return Err(format!("node {}: its transform is not finite", node.index()));
            }
            // A zero scale hides a node (a common way to switch parts off).
            if node.mesh().is_some() && world.determinant() == 0.0 {
                hidden += 1;
                continue;
            }
            if let Some(mesh) = node.mesh() {
                for (p, primitive) in primitives[&mesh.index()].iter().enumerate() {
                    for &q in &primitive.data.positions {
                        let w = world.transform_point3(Vec3::from(q));
                        bounds = (bounds.0.min(w), bounds.1.max(w));
                    }
                    let info: &MaterialInfo = &materials[primitive.material];
                    let transform = vec![TransformOp::Matrix(world.transpose().to_cols_array_2d())];
                    let name = Some(
                        node.name().or(mesh.name()).map_or_else(|| format!("node {}", node.index()), str::to_string),
                    );
                    let smooth = primitive.data.normals.is_some();
                    let desc = if uses[&mesh.index()] > 1 && !info.emits {
                        let library = format!("mesh {} primitive {p}", mesh.index());
                        scene.meshes.entry(library.clone()).or_insert_with(|| Located {
                            value: MeshDesc {
                                file: None,
                                data: Some(primitive.data.clone()),
                                shape_index: 0,
                                smooth,
                                flip_v: false,
                                compute_normals: false,
                            },
                            span: None,
                        });
                        ShapeDesc::Instance {
                            interior: None,
                            exterior: None,
                            mesh: library,
                            material: info.name.clone(),
                            transform,
                            name,
                        }
                    } else {
                        ShapeDesc::Mesh {
                            interior: None,
                            exterior: None,
                            file: None,
                            data: Some(primitive.data.clone()),
                            shape_index: 0,
                            smooth,
                            flip_v: false,
                            compute_normals: false,
                            material: info.name.clone(),
                            transform,
                            name,
                        }
                    };
                    scene.shapes.push(Located { value: desc, span: None });
                }
            }
            if let (Some(c), None) = (node.camera(), &camera) {
                camera = Some(self.camera(&c, world)?);
            }
            if let Some(light) = node.light() {
                scene.lights.push(Located { value: punctual_light(&light, world), span: None });
            }
        }
        if hidden > 0 {
            warnings.push(format!("{}: {hidden} nodes scaled to zero are left out", self.name.display()));
        }
        let framed = (bounds.0.cmple(bounds.1).all()).then_some(bounds);
        scene.camera.value = match camera {
            Some(c) => c,
            None => framing_camera(framed, 4.0 / 3.0),
        };
        if scene.lights.is_empty() && !materials.iter().any(|m| m.emits) {
            // glTF leaves lighting to the viewer: a uniform white sky, radiance 1.
            scene.environment.background = [1.0; 3];
            warnings.push(format!(
                "{}: the scene has no lights: lit by a uniform white sky of radiance 1",
                self.name.display()
            ));
        }
        Ok((scene, warnings))
    }

    fn primitives(&self, mesh: &gltf::Mesh, warnings: &mut Vec<String>) -> Result<Vec<Primitive>, String> {
        let mut out = Vec::new();
        for primitive in mesh.primitives() {
            let at = format!("mesh {} primitive {}", mesh.index(), primitive.index());
            let triangles_of = |indices: Vec<u32>| -> Vec<[u32; 3]> {
                match primitive.mode() {
                    gltf::mesh::Mode::Triangles => indices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
                    gltf::mesh::Mode::TriangleStrip => (2..indices.len())
                        .map(|i| {
                            if i % 2 == 0 {
                                [indices[i - 2], indices[i - 1], indices[i]]
                            } else {
                                [indices[i - 1], indices[i - 2], indices[i]]
                            }
                        })
                        .collect(),
                    gltf::mesh::Mode::TriangleFan => {
                        (2..indices.len()).map(|i| [indices[0], indices[i - 1], indices[i]]).collect()
                    }
                    _ => Vec::new(),
                }
            };
            if !matches!(
                primitive.mode(),
                gltf::mesh::Mode::Triangles | gltf::mesh::Mode::TriangleStrip | gltf::mesh::Mode::TriangleFan
            ) {
                warnings.push(format!("{}: {at}: points and lines have no surface; left out", self.name.display()));
                continue;
            }
            use gltf::accessor::{DataType, Dimensions};
            let float = &[DataType::F32][..];
            let expected = [
                (gltf::Semantic::Positions, Dimensions::Vec3, float),
                (gltf::Semantic::Normals, Dimensions::Vec3, float),
                (gltf::Semantic::TexCoords(0), Dimensions::Vec2, &[DataType::F32, DataType::U8, DataType::U16][..]),
            ];
            for (semantic, dimensions, types) in expected {
                if let Some(accessor) = primitive.get(&semantic) {
                    self.check(&accessor, dimensions, types).map_err(|m| format!("{at}: {m}"))?;
                }
            }
            if let Some(accessor) = primitive.indices() {
                self.check(&accessor, Dimensions::Scalar, &[DataType::U8, DataType::U16, DataType::U32])
                    .map_err(|m| format!("{at}: {m}"))?;
            }
            if primitive.get(&gltf::Semantic::Tangents).is_some() {
                warnings.push(format!(
                    "{}: {at}: TANGENT is not read: normal maps use the frame of ∂p/∂u",
                    self.name.display()
                ));
            }
            if primitive.get(&gltf::Semantic::Colors(0)).is_some() {
                warnings.push(format!("{}: {at}: vertex colours (COLOR_0) are not read", self.name.display()));
            }
            if primitive.morph_targets().next().is_some() {
                warnings.push(format!("{}: {at}: morph targets are not read", self.name.display()));
            }
            let reader = primitive.reader(|buffer| self.buffers.get(buffer.index()).map(Vec::as_slice));
            let positions: Vec<[f32; 3]> = match reader.read_positions() {
                Some(p) => p.collect(),
                None => return Err(format!("{at}: no POSITION attribute")),
            };
            let normals: Option<Vec<[f32; 3]>> = reader.read_normals().map(Iterator::collect);
            // glTF's v runs down the image; glint's up.
            let uvs: Option<Vec<[f32; 2]>> =
                reader.read_tex_coords(0).map(|t| t.into_f32().map(|[u, v]| [u, 1.0 - v]).collect());
            let indices: Vec<u32> = match reader.read_indices() {
                Some(i) => i.into_u32().collect(),
                None => (0..positions.len() as u32).collect(),
            };
            let triangles = triangles_of(indices);
            if triangles.is_empty() {
                warnings.push(format!("{}: {at}: no triangles; left out", self.name.display()));
                continue;
            }
            let material = primitive.material().index().map_or(0, |i| i + 1);
            out.push(Primitive { data: MeshData { positions, indices: triangles, normals, uvs }, material });
        }
        Ok(out)
    }

    /// An accessor's elements are of the kind glTF allows where it is used and lie within its
    /// buffer (the `gltf` crate's reader would stop at `unreachable!` or index past it).
    fn check(
        &self,
        accessor: &gltf::Accessor,
        dimensions: gltf::accessor::Dimensions,
        types: &[gltf::accessor::DataType],
    ) -> Result<(), String> {
        if accessor.dimensions() != dimensions || !types.contains(&accessor.data_type()) {
            return Err(format!(
                "accessor {} holds {:?} of {:?}; here glTF expects {dimensions:?} of {types:?}",
                accessor.index(),
                accessor.dimensions(),
                accessor.data_type()
            ));
        }
        if accessor.sparse().is_some() {
            return Err(format!("accessor {}: sparse accessors are not supported", accessor.index()));
        }
        let Some(view) = accessor.view() else {
            return Err(format!("accessor {} has no buffer view", accessor.index()));
        };
        let buffer = &self.buffers[view.buffer().index()];
        let size = accessor.size();
        let stride = view.stride().unwrap_or(size);
        if stride < size {
            return Err(format!(
                "accessor {}: its view's stride ({stride}) is shorter than an element ({size})",
                accessor.index()
            ));
        }
        if accessor.count() == 0 {
            return Err(format!("accessor {} has no elements", accessor.index()));
        }
        let needed = (accessor.count() - 1)
            .checked_mul(stride)
            .and_then(|x| x.checked_add(size)?.checked_add(accessor.offset()));
        let fits = needed.is_some_and(|end| end <= view.length())
            && view.offset().checked_add(view.length()).is_some_and(|end| end <= buffer.len());
        if !fits {
            return Err(format!("accessor {} reads past the end of its buffer view or buffer", accessor.index()));
        }
        Ok(())
    }

    fn camera(&self, camera: &gltf::Camera, world: &Mat4) -> Result<CameraDesc, String> {
        let position = world.transform_point3(Vec3::ZERO);
        let forward = world.transform_vector3(-Vec3::Z);
        let up = world.transform_vector3(Vec3::Y);
        let right = world.transform_vector3(Vec3::X);
        let mirror = right.dot(forward.cross(up)) < 0.0;
        let (fov, aspect, orthographic_height) = match camera.projection() {
            gltf::camera::Projection::Perspective(p) => {
                (p.yfov().to_degrees(), p.aspect_ratio().unwrap_or(4.0 / 3.0), None)
            }
            gltf::camera::Projection::Orthographic(o) => {
                (45.0, (o.xmag() / o.ymag()).abs(), Some(2.0 * o.ymag().abs() * up.length()))
            }
        };
        if !(aspect.is_finite() && aspect > 0.0) {
            return Err(format!("camera {}: its aspect ratio must be positive", camera.index()));
        }
        Ok(CameraDesc {
            position: position.to_array(),
            look_at: (position + forward.normalize_or_zero()).to_array(),
            up: up.to_array(),
            fov,
            resolution: [WIDTH, ((WIDTH as f32 / aspect).round() as u32).clamp(1, 32768)],
            aperture_radius: None,
            focus_distance: None,
            orthographic_height,
            mirror,
            medium: None,
        })
    }
}

fn punctual_light(light: &gltf::khr_lights_punctual::Light, world: &Mat4) -> LightDesc {
    let colour = light.color().map(|c| c * light.intensity() / LUMENS_PER_WATT);
    let position = world.transform_point3(Vec3::ZERO).to_array();
    let direction = world.transform_vector3(-Vec3::Z).to_array();
    match light.kind() {
        Kind::Directional => LightDesc::Directional { direction, color: colour, intensity: 1.0 },
        Kind::Point => {
            LightDesc::Point { position, color: colour, intensity: 1.0, falloff: FalloffDesc::InverseSquare }
        }
        Kind::Spot { inner_cone_angle, outer_cone_angle } => LightDesc::Spot {
            position,
            direction,
            cone_angle: Some(outer_cone_angle.to_degrees()),
            focal_length: None,
            edge: (outer_cone_angle - inner_cone_angle).max(0.0).to_degrees(),
            profile: Some("smooth".into()),
            texture: None,
            up: None,
            color: colour,
            intensity: 1.0,
            falloff: FalloffDesc::InverseSquare,
        },
    }
}

/// A camera that frames `bounds`: from the front (+z, glTF's front) and a little above, its
/// 40° vertical view holding the bounding sphere.
fn framing_camera(bounds: Option<(Vec3, Vec3)>, aspect: f32) -> CameraDesc {
    let fov = 40.0f32;
    let (position, target) = match bounds {
        Some((lo, hi)) => {
            let centre = 0.5 * (lo + hi);
            let radius = (0.5 * (hi - lo).length()).max(1e-3);
            let distance = 1.1 * radius / (0.5 * fov.to_radians()).sin();
            (centre + Vec3::new(0.0, 0.25, 1.0).normalize() * distance, centre)
        }
        None => (Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO),
    };
    CameraDesc {
        position: position.to_array(),
        look_at: target.to_array(),
        up: [0.0, 1.0, 0.0],
        fov,
        resolution: [WIDTH, (WIDTH as f32 / aspect).round() as u32],
        aperture_radius: None,
        focus_distance: None,
        orthographic_height: None,
        mirror: false,
        medium: None,
    }
}
