//! A glTF document's default scene walked node by node: each mesh primitive placed by its
//! node's world transform (a mesh placed more than once goes into the mesh library and is
//! instanced, unless it emits light: glint samples emitting meshes, not instances), the first
//! camera met (or, without one, a camera that frames the scene), and KHR_lights_punctual (or,
//! without a punctual light, the default environment).

use std::collections::{BTreeSet, HashMap};
use std::path::Path;

use glam::{Mat4, Vec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::khr_lights_punctual::Kind;

use super::accessors::{self, Allowed};
use super::materials::{self, MaterialInfo};
use super::GltfOptions;
use crate::located::Located;
use crate::native::schema::*;
use crate::reader::MadeFiles;

/// glTF's photometric units (candela, lux) to glint's radiometric ones: 683 lm/W.
const LUMENS_PER_WATT: f32 = 683.0;

/// The image width glint gives a glTF camera (glTF gives only the aspect ratio).
const WIDTH: u32 = 960;

pub struct Reader<'a> {
    document: &'a gltf::Document,
    buffers: &'a [Vec<u8>],
    images: &'a [String],
    name: &'a Path,
    options: GltfOptions,
}

/// One primitive's triangles in its mesh's space.
struct Primitive {
    data: MeshData,
    material: usize,
}

impl<'a> Reader<'a> {
    pub fn new(
        document: &'a gltf::Document,
        buffers: &'a [Vec<u8>],
        images: &'a [String],
        name: &'a Path,
        options: GltfOptions,
    ) -> Self {
        Self { document, buffers, images, name, options }
    }

    /// The scene description and the warnings; `made` holds the images as files, and takes
    /// the opacity images that alpha makes.
    pub fn translate(&self, made: &mut MadeFiles) -> Result<(SceneFile, Vec<String>), String> {
        let mut warnings = Vec::new();
        let mut scene = SceneFile::new(
            framing_camera(None, 4.0 / 3.0),
            RenderDesc { integrator: "path".into(), spp: 64, max_depth: -1, ..RenderDesc::default() },
        );
        // The materials some primitive with vertex colours uses (0: glTF's default), which
        // get a variant whose base colour is multiplied by them.
        let coloured: BTreeSet<usize> = self
            .document
            .meshes()
            .flat_map(|m| m.primitives())
            .filter(|p| p.get(&gltf::Semantic::Colors(0)).is_some())
            .map(|p| p.material().index().map_or(0, |i| i + 1))
            .collect();
        let materials = materials::translate(self.document, self.images, &coloured, made, &mut scene, &mut warnings)?;
        // Shadow rays pass a cut-out or blended surface only under volpath (the path tracer
        // stops them at any surface, so a punctual light would cast a cut-out's whole quad).
        // So do media (KHR_materials_volume's attenuation).
        if materials.iter().any(|m| m.alpha || m.interior.is_some()) {
            scene.render.integrator = "volpath".into();
        }

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
            let world = parent * self.local_transform(&node, &mut warnings)?;
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

        // EXT_mesh_gpu_instancing: a node's mesh placed once per instance, each by its own
        // translation, rotation and scale within the node.
        let mut instanced: HashMap<usize, Vec<Mat4>> = HashMap::new();
        for (node, _) in &placed {
            if let (Some(_), Some(extension)) = (node.mesh(), node.extension_value("EXT_mesh_gpu_instancing")) {
                instanced.insert(node.index(), self.gpu_instances(node.index(), extension)?);
            }
        }
        let mut primitives: HashMap<usize, Vec<Primitive>> = HashMap::new();
        let mut uses: HashMap<usize, usize> = HashMap::new();
        for (node, _) in &placed {
            if let Some(mesh) = node.mesh() {
                *uses.entry(mesh.index()).or_default() += instanced.get(&node.index()).map_or(1, Vec::len);
                if let std::collections::hash_map::Entry::Vacant(entry) = primitives.entry(mesh.index()) {
                    entry.insert(self.primitives(&mesh, &materials, &mut warnings)?);
                }
            }
        }

        let mut bounds = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        let mut camera = None;
        let mut hidden = 0;
        for (node, node_world) in &placed {
            if !node_world.is_finite() {
                return Err(format!("node {}: its transform is not finite", node.index()));
            }
            let one = [Mat4::IDENTITY];
            let instances = instanced.get(&node.index()).map_or(&one[..], Vec::as_slice);
            for world in instances.iter().map(|instance| *node_world * *instance) {
                let world = &world;
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
                        let material = match (&primitive.data.colors, &info.vertex_coloured) {
                            (Some(_), Some(coloured)) => coloured.clone(),
                            _ => info.name.clone(),
                        };
                        let transform = vec![TransformOp::Matrix(world.transpose().to_cols_array_2d())];
                        let name = Some(
                            node.name()
                                .or(mesh.name())
                                .map_or_else(|| format!("node {}", node.index()), str::to_string),
                        );
                        let smooth = primitive.data.normals.is_some();
                        // Vertex colours are read through the mesh's own attributes, so a coloured
                        // primitive is placed as a mesh of its own.
                        let desc = if uses[&mesh.index()] > 1 && !info.emits && primitive.data.colors.is_none() {
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
                                interior: info.interior.clone(),
                                exterior: None,
                                mesh: library,
                                material,
                                transform,
                                name,
                            }
                        } else {
                            ShapeDesc::Mesh {
                                interior: info.interior.clone(),
                                exterior: None,
                                file: None,
                                data: Some(primitive.data.clone()),
                                shape_index: 0,
                                smooth,
                                flip_v: false,
                                compute_normals: false,
                                material,
                                transform,
                                name,
                            }
                        };
                        scene.shapes.push(Located { value: desc, span: None });
                    }
                }
            }
            let world = node_world;
            if let (Some(c), None) = (node.camera(), &camera) {
                camera = Some(self.camera(&c, world)?);
            }
            if let Some(light) = node.light() {
                scene
                    .lights
                    .push(Located { value: punctual_light(&light, world, self.name, &mut warnings), span: None });
            }
        }
        if hidden > 0 {
            warnings.push(format!("{}: {hidden} nodes or instances scaled to zero are left out", self.name.display()));
        }
        let framed = (bounds.0.cmple(bounds.1).all()).then_some(bounds);
        scene.camera.value = match camera {
            Some(c) => c,
            None => framing_camera(framed, 4.0 / 3.0),
        };
        if scene.lights.is_empty() && !self.options.no_default_light {
            // glTF leaves lighting to the viewer, and viewers light a model with an
            // environment even when it has emitters: glint's is a uniform white sky.
            scene.environment.background = [1.0; 3];
            warnings.push(format!(
                "{}: the file has no punctual light: lit by the default environment, a uniform white sky of radiance 1 (--no-default-light leaves it out)",
                self.name.display()
            ));
        }
        Ok((scene, warnings))
    }

    /// The instances of EXT_mesh_gpu_instancing on node `node`: each a transform from its
    /// `TRANSLATION`, `ROTATION` (a unit quaternion) and `SCALE` accessors (any of them may be
    /// missing), all of one count.
    fn gpu_instances(&self, node: usize, extension: &serde_json::Value) -> Result<Vec<Mat4>, String> {
        let at = format!("node {node}: EXT_mesh_gpu_instancing");
        let attribute = |name: &str, allowed: &Allowed| -> Result<Option<Vec<f32>>, String> {
            let Some(index) = extension.get("attributes").and_then(|a| a.get(name)) else { return Ok(None) };
            let accessor = index
                .as_u64()
                .and_then(|i| self.document.accessors().nth(i as usize))
                .ok_or_else(|| format!("{at}: {name} names no accessor"))?;
            accessors::read(&accessor, self.buffers, allowed, |x| x as f32)
                .map(Some)
                .map_err(|m| format!("{at}: {name}: {m}"))
        };
        let translations = attribute("TRANSLATION", &INSTANCE_VECTORS)?;
        let rotations = attribute("ROTATION", &INSTANCE_ROTATIONS)?;
        let scales = attribute("SCALE", &INSTANCE_VECTORS)?;
        let counts = [(&translations, 3), (&rotations, 4), (&scales, 3)].map(|(v, n)| v.as_ref().map(|v| v.len() / n));
        let count = counts.iter().flatten().copied().max().ok_or_else(|| format!("{at}: no attributes"))?;
        if counts.iter().flatten().any(|&c| c != count) {
            return Err(format!("{at}: its attributes hold different numbers of instances ({counts:?})"));
        }
        let instances: Vec<Mat4> = (0..count)
            .map(|i| {
                let t = translations.as_ref().map_or(Vec3::ZERO, |v| Vec3::from_slice(&v[3 * i..]));
                let r = rotations.as_ref().map_or(glam::Quat::IDENTITY, |v| {
                    glam::Quat::from_xyzw(v[4 * i], v[4 * i + 1], v[4 * i + 2], v[4 * i + 3]).normalize()
                });
                let s = scales.as_ref().map_or(Vec3::ONE, |v| Vec3::from_slice(&v[3 * i..]));
                Mat4::from_scale_rotation_translation(s, r, t)
            })
            .collect();
        match instances.iter().position(|m| !m.is_finite()) {
            Some(i) => {
                Err(format!("{at}: instance {i}'s transform is not finite (a zero rotation, or a value past f32)"))
            }
            None => Ok(instances),
        }
    }

    fn primitives(
        &self,
        mesh: &gltf::Mesh,
        materials: &[MaterialInfo],
        warnings: &mut Vec<String>,
    ) -> Result<Vec<Primitive>, String> {
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
            if primitive.get(&gltf::Semantic::Tangents).is_some() {
                warnings.push(format!(
                    "{}: {at}: TANGENT is not read: normal maps use the frame of ∂p/∂u",
                    self.name.display()
                ));
            }

            if primitive.morph_targets().next().is_some() {
                warnings.push(format!("{}: {at}: morph targets are not read", self.name.display()));
            }
            let read = |semantic: gltf::Semantic, allowed: &Allowed| -> Result<Option<Vec<f32>>, String> {
                primitive
                    .get(&semantic)
                    .map(|a| accessors::read(&a, self.buffers, allowed, |x| x as f32))
                    .transpose()
                    .map_err(|m| format!("{at}: {semantic:?}: {m}"))
            };
            let Some(positions) = read(gltf::Semantic::Positions, &POSITIONS)? else {
                return Err(format!("{at}: no POSITION attribute"));
            };
            let positions: Vec<[f32; 3]> = positions.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
            // Quantized normals are unit only to within their precision; float ones are kept
            // as stored.
            let quantized = primitive.get(&gltf::Semantic::Normals).is_some_and(|a| a.data_type() != DataType::F32);
            let normals: Option<Vec<[f32; 3]>> = read(gltf::Semantic::Normals, &NORMALS)?.map(|n| {
                n.chunks_exact(3)
                    .map(|n| {
                        let n = Vec3::new(n[0], n[1], n[2]);
                        if quantized { n.normalize_or_zero() } else { n }.to_array()
                    })
                    .collect()
            });
            let material = primitive.material().index().map_or(0, |i| i + 1);
            // The set its material's textures read. glTF's v runs down the image; glint's up.
            let uv_set = materials.get(material).map_or(0, |m| m.uv_set);
            let uvs: Option<Vec<[f32; 2]>> = read(gltf::Semantic::TexCoords(uv_set), &TEXCOORDS)?
                .map(|t| t.chunks_exact(2).map(|t| [t[0], 1.0 - t[1]]).collect());
            // Linear RGB, multiplying the base colour (their alpha, glTF's, is not read).
            let colors: Option<Vec<[f32; 3]>> = match primitive.get(&gltf::Semantic::Colors(0)) {
                None => None,
                Some(accessor) => {
                    if accessor.data_type() != DataType::F32 && !accessor.normalized() {
                        return Err(format!("{at}: COLOR_0 of integers must be `normalized` (glTF requires it)"));
                    }
                    let dim = if accessor.dimensions() == Dimensions::Vec4 { 4 } else { 3 };
                    let values = accessors::read(&accessor, self.buffers, &COLORS, |x| x as f32)
                        .map_err(|m| format!("{at}: COLOR_0: {m}"))?;
                    if dim == 4 && values.chunks_exact(4).any(|c| c[3] < 1.0) {
                        warnings.push(format!(
                            "{}: {at}: the vertex colours' alpha is not read (their colours are)",
                            self.name.display()
                        ));
                    }
                    Some(values.chunks_exact(dim).map(|c| [c[0], c[1], c[2]]).collect())
                }
            };
            let indices: Vec<u32> = match primitive.indices() {
                Some(a) => accessors::read(&a, self.buffers, &INDICES, |x| x as u32)
                    .map_err(|m| format!("{at}: indices: {m}"))?,
                None => (0..positions.len() as u32).collect(),
            };
            if primitive.mode() == gltf::mesh::Mode::Triangles && !indices.len().is_multiple_of(3) {
                warnings.push(format!(
                    "{}: {at}: TRIANGLES with {} {}, not a multiple of 3 (glTF requires one): the last {} left out",
                    self.name.display(),
                    indices.len(),
                    if primitive.indices().is_some() { "indices" } else { "vertices" },
                    indices.len() % 3
                ));
            }
            let triangles = triangles_of(indices);
            if triangles.is_empty() {
                warnings.push(format!("{}: {at}: no triangles; left out", self.name.display()));
                continue;
            }
            out.push(Primitive { data: MeshData { positions, indices: triangles, normals, uvs, colors }, material });
        }
        Ok(out)
    }

    /// A node's own transform from its raw JSON: `matrix` (affine, as glTF requires) or
    /// translation · rotation · scale. A node with both is warned of (glTF allows one): the
    /// matrix is used, as the `gltf` crate does.
    fn local_transform(&self, node: &gltf::Node, warnings: &mut Vec<String>) -> Result<Mat4, String> {
        let Some(json) = self.document.as_json().nodes.get(node.index()) else {
            return Ok(Mat4::from_cols_array_2d(&node.transform().matrix()));
        };
        if let Some(m) = json.matrix {
            let trs: Vec<&str> = [
                ("translation", json.translation.is_some()),
                ("rotation", json.rotation.is_some()),
                ("scale", json.scale.is_some()),
            ]
            .into_iter()
            .filter_map(|(name, given)| given.then_some(name))
            .collect();
            if !trs.is_empty() {
                warnings.push(format!(
                    "{}: node {}: has both `matrix` and `{}` (glTF allows one or the other): `matrix` is used",
                    self.name.display(),
                    node.index(),
                    trs.join("`, `")
                ));
            }
            // Column-major: the bottom row is elements 3, 7, 11, 15.
            let bottom = [m[3], m[7], m[11], m[15]];
            if bottom != [0.0, 0.0, 0.0, 1.0] {
                return Err(format!(
                    "node {}: its `matrix` is not affine: its bottom row is {bottom:?}, where glTF requires [0, 0, 0, 1]",
                    node.index()
                ));
            }
            return Ok(Mat4::from_cols_array(&m));
        }
        Ok(Mat4::from_cols_array_2d(&node.transform().matrix()))
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
            crop: None,
        })
    }
}

fn punctual_light(
    light: &gltf::khr_lights_punctual::Light,
    world: &Mat4,
    name: &Path,
    warnings: &mut Vec<String>,
) -> LightDesc {
    let colour = light.color().map(|c| c * light.intensity() / LUMENS_PER_WATT);
    let position = world.transform_point3(Vec3::ZERO).to_array();
    let direction = world.transform_vector3(-Vec3::Z).to_array();
    match light.kind() {
        Kind::Directional => LightDesc::Directional { direction, color: colour, intensity: 1.0 },
        Kind::Point => {
            LightDesc::Point { position, color: colour, intensity: 1.0, falloff: FalloffDesc::InverseSquare }
        }
        Kind::Spot { inner_cone_angle, outer_cone_angle } => {
            if inner_cone_angle >= outer_cone_angle {
                warnings.push(format!(
                    "{}: light {}: spot.innerConeAngle ({inner_cone_angle}) is not less than spot.outerConeAngle ({outer_cone_angle}), as glTF requires: the cone's edge is hard, at the outer angle",
                    name.display(),
                    light.index()
                ));
            }
            LightDesc::Spot {
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
            }
        }
    }
}

/// The accessor types glTF allows per use, KHR_mesh_quantization's included (positions and
/// uvs in 8- and 16-bit integers, as stored or normalised; normals normalised).
const POSITIONS: Allowed = Allowed {
    dimensions: &[Dimensions::Vec3],
    types: &[DataType::F32, DataType::I8, DataType::U8, DataType::I16, DataType::U16],
};
const NORMALS: Allowed =
    Allowed { dimensions: &[Dimensions::Vec3], types: &[DataType::F32, DataType::I8, DataType::I16] };
const TEXCOORDS: Allowed = Allowed {
    dimensions: &[Dimensions::Vec2],
    types: &[DataType::F32, DataType::I8, DataType::U8, DataType::I16, DataType::U16],
};
const COLORS: Allowed =
    Allowed { dimensions: &[Dimensions::Vec3, Dimensions::Vec4], types: &[DataType::F32, DataType::U8, DataType::U16] };
/// EXT_mesh_gpu_instancing's translations and scales (floats), and rotations (floats or
/// normalised integers).
const INSTANCE_VECTORS: Allowed = Allowed { dimensions: &[Dimensions::Vec3], types: &[DataType::F32] };
const INSTANCE_ROTATIONS: Allowed =
    Allowed { dimensions: &[Dimensions::Vec4], types: &[DataType::F32, DataType::I8, DataType::I16] };
const INDICES: Allowed =
    Allowed { dimensions: &[Dimensions::Scalar], types: &[DataType::U8, DataType::U16, DataType::U32] };

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
        crop: None,
    }
}
