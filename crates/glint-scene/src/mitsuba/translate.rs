//! Mitsuba 3 plugins mapped onto glint's native scene description, which the native builder
//! then checks and builds (so a Mitsuba scene and a TOML scene become the same `Scene`).
//! docs/mitsuba.md lists every element and what it becomes; anything glint cannot render
//! faithfully is an error naming the element and its line, or, where the image would only
//! differ in its noise or in a documented approximation, a warning.

mod media;

use std::cell::RefCell;
use std::collections::{HashMap, HashSet};

use glam::{Affine2, Mat3, Mat4, Vec2, Vec3};

use super::spectrum::{parse_sampled, sampled_to_rgb, SpectrumRole};
use super::xml::{Element, Files, Position};
use crate::error::SceneError;
use crate::located::Located;
use crate::mesh::parametric::grid;
use crate::native::schema::*;

type Result<T> = std::result::Result<T, SceneError>;

/// Tags that carry a named property rather than an object.
const PROPERTY_TAGS: [&str; 10] =
    ["float", "integer", "boolean", "string", "rgb", "spectrum", "point", "vector", "transform", "ref"];

pub(super) struct Translator<'a> {
    files: &'a Files,
    /// Objects declared with an `id`, for `<ref>`.
    ids: HashMap<String, &'a Element>,
    scene: SceneFile,
    warnings: RefCell<Vec<String>>,
    /// Materials already made for a BSDF element (by its position), so shapes share them.
    materials_by_element: HashMap<(usize, u32, u32), String>,
    /// Each `shapegroup`'s shapes by its id, placed by every `instance` of it.
    groups: HashMap<String, Vec<Located<ShapeDesc>>>,
    /// Media already made for a `<medium>` element (by its position), so references share them.
    media_by_element: HashMap<(usize, u32, u32), String>,
    /// Top-level area emitters attached to a shape by `<ref>`: each to one shape, as in Mitsuba.
    attached_emitters: HashSet<String>,
    /// Top-level samplers, films and filters the sensor (or its film) refers to.
    referenced: HashSet<String>,
}

/// The properties of one plugin element, recording which ones were read.
struct Properties<'e> {
    element: &'e Element,
    used: RefCell<HashSet<String>>,
}

impl<'a> Translator<'a> {
    pub fn new(files: &'a Files, root: &'a Element) -> Result<Self> {
        let mut ids = HashMap::new();
        collect_ids(root, &mut ids, files)?;
        let camera = CameraDesc {
            position: [0.0, 0.0, 0.0],
            look_at: [0.0, 0.0, 1.0],
            up: [0.0, 1.0, 0.0],
            fov: 39.6,
            resolution: [768, 576],
            aperture_radius: None,
            focus_distance: None,
            orthographic_height: None,
            mirror: false,
            medium: None,
        };
        let scene = SceneFile::new(
            camera,
            RenderDesc {
                integrator: "path".into(),
                max_depth: -1,
                spp: 4,
                filter: "gaussian".into(),
                // Mitsuba picks each emitter equally; its reference variances measure that.
                light_selection: "uniform".into(),
                ..RenderDesc::default()
            },
        );
        Ok(Self {
            files,
            ids,
            scene,
            warnings: RefCell::default(),
            materials_by_element: HashMap::new(),
            groups: HashMap::new(),
            media_by_element: HashMap::new(),
            attached_emitters: HashSet::new(),
            referenced: HashSet::new(),
        })
    }

    fn error(&self, at: &Position, message: impl Into<String>) -> SceneError {
        self.files.error(at, message)
    }

    fn warn(&self, at: &Position, message: impl AsRef<str>) {
        self.warnings.borrow_mut().push(self.files.warning(at, message));
    }

    /// The whole scene.
    pub fn translate(mut self, root: &'a Element) -> Result<(SceneFile, Vec<String>)> {
        let mut sensors = 0;
        let mut integrator = None;
        let mut area_emitters = Vec::new();
        let mut declared = Vec::new();
        for child in &root.children {
            match child.tag.as_str() {
                "sensor" => {
                    sensors += 1;
                    if sensors == 1 {
                        self.sensor(child)?;
                    } else {
                        self.warn(&child.position, "a second <sensor>: glint renders the first one only");
                    }
                }
                "integrator" => integrator = Some(child),
                "shape" => self.shape(child)?,
                // An area emitter at the top level emits from the shape that refers to it.
                "emitter" if child.attribute("type") == Some("area") => area_emitters.push(child),
                "emitter" => self.emitter(child)?,
                // Declared for <ref>; used where referenced.
                "bsdf" | "texture" | "medium" | "phase" | "volume" => {}
                // Declared for the sensor's (or its film's) <ref>; Mitsuba ignores them otherwise.
                "sampler" | "film" | "rfilter" => declared.push(child),
                other => {
                    return Err(self.error(&child.position, format!("unexpected <{other}> in <scene>")));
                }
            }
        }
        if sensors == 0 {
            return Err(self.error(&root.position, "the scene has no <sensor>: glint needs a camera"));
        }
        // An area emitter no shape took emits nothing; Mitsuba drops it in silence.
        for emitter in area_emitters {
            let id = emitter.attribute("id").unwrap_or("");
            if !self.attached_emitters.contains(id) {
                self.warn(
                    &emitter.position,
                    format!("the area emitter{} is not attached to any shape, so it emits nothing (as in Mitsuba); nest it in a <shape>, or give it an id and refer to it from one with <ref id=\"…\"/>", if id.is_empty() { String::new() } else { format!(" `{id}`") }),
                );
            }
        }
        if let Some(i) = integrator {
            self.integrator(i)?;
        }
        for element in declared {
            if !element.attribute("id").is_some_and(|id| self.referenced.contains(id)) {
                self.warn(
                    &element.position,
                    format!("<{}> at the top level is not used: no sensor refers to it (Mitsuba ignores it too; refer to it with <ref id=\"…\"/> inside the <sensor>)", element.tag),
                );
            }
        }
        Ok((self.scene, self.warnings.into_inner()))
    }

    fn properties<'e>(&self, element: &'e Element) -> Properties<'e> {
        Properties { element, used: RefCell::new(HashSet::new()) }
    }

    /// Warns about the properties of `p` no mapping read.
    fn unused(&mut self, p: &Properties) {
        let used = p.used.borrow();
        let mut messages = Vec::new();
        for child in &p.element.children {
            if let Some(name) = child.attribute("name") {
                if PROPERTY_TAGS.contains(&child.tag.as_str()) && !used.contains(name) {
                    messages.push((
                        child.position.clone(),
                        format!(
                            "<{} name=\"{name}\"> of {} is not used by glint (ignored)",
                            child.tag,
                            p.element.describe()
                        ),
                    ));
                }
            }
        }
        for (at, m) in messages {
            self.warn(&at, m);
        }
    }

    // ----- sensor, film, sampler, integrator -------------------------------------------------

    fn sensor(&mut self, sensor: &'a Element) -> Result<()> {
        let kind = sensor.attribute("type").unwrap_or("");
        if !matches!(kind, "perspective" | "thinlens" | "orthographic") {
            return Err(self.error(
                &sensor.position,
                format!(
                    "<sensor type=\"{kind}\"> is not supported; glint reads perspective, thinlens and orthographic"
                ),
            ));
        }
        let p = self.properties(sensor);
        // Film first: the field of view's axis needs the aspect ratio.
        let (mut width, mut height) = (768u32, 576u32);
        let mut medium = None;
        for child in &sensor.children {
            // A sampler, film or medium declared at the top level, by reference.
            let target = match child.tag.as_str() {
                "ref" => {
                    let target = self.resolve(child)?;
                    if !matches!(target.tag.as_str(), "film" | "sampler" | "medium") {
                        return Err(self.error(
                            &child.position,
                            format!(
                                "a sensor can refer to a <sampler>, a <film> or a <medium>, not to <{}> `{}`",
                                target.tag,
                                child.attribute("id").unwrap_or("")
                            ),
                        ));
                    }
                    if let Some(id) = child.attribute("id") {
                        self.referenced.insert(id.to_string());
                    }
                    target
                }
                _ => child,
            };
            match target.tag.as_str() {
                "film" => {
                    let (w, h) = self.film(target)?;
                    width = w;
                    height = h;
                }
                "sampler" => self.sampler(target)?,
                // The sensor's medium, nested or by reference.
                "medium" => {
                    medium = Some(self.medium(target)?);
                    p.used.borrow_mut().insert("medium".into());
                }
                _ => {}
            }
        }
        let aspect = width as f32 / height as f32;
        let mut focal_diagonal = false;
        let fov = match p.float(self, "fov")? {
            Some(f) => f,
            None if kind == "orthographic" => 45.0, // unused
            None => {
                let focal = p.string(self, "focal_length")?.unwrap_or_else(|| "50mm".into());
                let mm: f32 = focal.trim_end_matches("mm").trim().parse().map_err(|_| {
                    self.error(&sensor.position, format!("`focal_length` must be like \"50mm\", got `{focal}`"))
                })?;
                // As Mitsuba: the field of view of a 35 mm film's diagonal (36 × 24 mm),
                // taken along the image's diagonal.
                let diagonal = 2.0 * ((36.0f32.hypot(24.0)) / (2.0 * mm)).atan().to_degrees();
                focal_diagonal = true;
                diagonal
            }
        };
        if !(fov > 0.0 && fov < 180.0) {
            return Err(self.error(&sensor.position, format!("`fov` must be between 0 and 180 degrees, got {fov}")));
        }
        let axis = if focal_diagonal {
            "diagonal".to_string()
        } else {
            p.string(self, "fov_axis")?.unwrap_or_else(|| "x".into())
        };
        let vertical = vertical_fov(fov, aspect, &axis).ok_or_else(|| {
            self.error(&sensor.position, format!("`fov_axis` must be x, y, diagonal, smaller or larger, got `{axis}`"))
        })?;
        for clip in ["near_clip", "far_clip"] {
            p.float(self, clip)?; // glint's rays are not clipped; the defaults rarely matter
        }
        if kind != "thinlens" {
            p.float(self, "focus_distance")?; // Mitsuba's projective cameras read it; a pinhole has no use for it
        }
        let (aperture_radius, focus_distance) = if kind == "thinlens" {
            let radius = p.float(self, "aperture_radius")?.unwrap_or(0.03);
            let focus = p
                .float(self, "focus_distance")?
                .ok_or_else(|| self.error(&sensor.position, "a thinlens sensor needs a `focus_distance`"))?;
            (Some(radius), Some(focus))
        } else {
            (None, None)
        };
        let matrix = p.transform(self, "to_world")?.unwrap_or(Mat4::IDENTITY);
        // Mitsuba's orthographic view spans x ∈ [−1, 1] across the width and
        // y ∈ [−1/aspect, 1/aspect] under to_world: its height is twice to_world's scale along
        // x over the aspect ratio.
        let orthographic_height =
            (kind == "orthographic").then(|| 2.0 * matrix.transform_vector3(Vec3::X).length() / aspect);
        let position = matrix.transform_point3(Vec3::ZERO);
        let forward = matrix.transform_vector3(Vec3::Z);
        let up = matrix.transform_vector3(Vec3::Y);
        // Mitsuba's image right is the camera's −x; glint's is forward × up, unless mirrored
        // (a to_world with a negative scale).
        let left = matrix.transform_vector3(Vec3::X);
        let mirror = (-left).dot(forward.cross(up)) < 0.0;
        let look_at = position + forward.normalize_or_zero();
        self.scene.camera = Located {
            value: CameraDesc {
                position: position.to_array(),
                look_at: look_at.to_array(),
                up: up.to_array(),
                fov: vertical,
                resolution: [width, height],
                aperture_radius,
                focus_distance,
                orthographic_height,
                mirror,
                medium,
            },
            span: sensor.position.span.clone(),
        };
        self.unused(&p);
        Ok(())
    }

    fn film(&mut self, film: &Element) -> Result<(u32, u32)> {
        let kind = film.attribute("type").unwrap_or("");
        if kind != "hdrfilm" && kind != "specfilm" {
            return Err(self.error(&film.position, format!("<film type=\"{kind}\"> is not supported; use hdrfilm")));
        }
        let p = self.properties(film);
        let width = p.integer(self, "width")?.unwrap_or(768);
        let height = p.integer(self, "height")?.unwrap_or(576);
        for ignored in ["pixel_format", "component_format", "file_format", "sample_border", "banner"] {
            p.string(self, ignored)?;
        }
        let mut filter = "gaussian".to_string(); // Mitsuba's default reconstruction filter
        for child in &film.children {
            let child = match child.tag.as_str() {
                "ref" => {
                    let target = self.resolve(child)?;
                    if target.tag != "rfilter" {
                        return Err(self.error(
                            &child.position,
                            format!("a film can refer to an <rfilter>, not to <{}>", target.tag),
                        ));
                    }
                    if let Some(id) = child.attribute("id") {
                        self.referenced.insert(id.to_string());
                    }
                    target
                }
                _ => child,
            };
            if child.tag == "rfilter" {
                let t = child.attribute("type").unwrap_or("");
                filter = match t {
                    "box" | "tent" | "gaussian" => t.to_string(),
                    "mitchell" => "mitchell".into(),
                    _ => {
                        self.warn(&child.position, format!("<rfilter type=\"{t}\"> is not available: using gaussian"));
                        "gaussian".into()
                    }
                };
                let fp = self.properties(child);
                if t == "gaussian" {
                    if let Some(s) = fp.float(self, "stddev")? {
                        if (s - 0.5).abs() > 1e-6 {
                            self.warn(&child.position, "gaussian `stddev` other than 0.5: glint's is fixed at 0.5");
                        }
                    }
                }
                self.unused(&fp);
            }
        }
        self.scene.render.filter = filter;
        self.unused(&p);
        let check = |v: i64, name: &str| -> Result<u32> {
            u32::try_from(v).ok().filter(|v| (1..=32768).contains(v)).ok_or_else(|| {
                self.error(&film.position, format!("film `{name}` must be between 1 and 32768, got {v}"))
            })
        };
        Ok((check(width, "width")?, check(height, "height")?))
    }

    fn sampler(&mut self, sampler: &Element) -> Result<()> {
        let kind = sampler.attribute("type").unwrap_or("");
        self.scene.render.sampler = match kind {
            "independent" => "independent",
            "stratified" | "multijitter" | "orthogonal" => "stratified",
            "ldsampler" => "sobol",
            _ => return Err(self.error(&sampler.position, format!("<sampler type=\"{kind}\"> is not known"))),
        }
        .into();
        let p = self.properties(sampler);
        if let Some(n) = p.integer(self, "sample_count")? {
            self.scene.render.spp = u32::try_from(n)
                .ok()
                .filter(|&n| n >= 1)
                .ok_or_else(|| self.error(&sampler.position, format!("`sample_count` must be ≥ 1, got {n}")))?;
        }
        if let Some(seed) = p.integer(self, "seed")? {
            self.scene.render.seed = seed as u64;
        }
        p.boolean(self, "jitter")?;
        p.integer(self, "dimension")?;
        self.unused(&p);
        Ok(())
    }

    fn integrator(&mut self, integrator: &Element) -> Result<()> {
        let kind = integrator.attribute("type").unwrap_or("");
        match kind {
            "moment" => return self.moment(integrator),
            "aov" => return self.aov(integrator),
            "stokes" => return Err(self.error(&integrator.position, polarized("<integrator type=\"stokes\">"))),
            _ => {}
        }
        let p = self.properties(integrator);
        let max_depth = p.integer(self, "max_depth")?.unwrap_or(-1);
        let rr_depth = p.integer(self, "rr_depth")?.unwrap_or(5);
        p.boolean(self, "hide_emitters")?;
        let name = match kind {
            "path" => "path",
            // volpathmis weighs the channels of a chromatic medium by MIS along the path; glint's
            // volpath weighs them at each free flight: the same image, each without bias.
            "volpath" | "volpathmis" => "volpath",
            "direct" => "path",
            "ptracer" => "light",
            "photonmapper" => "photon",
            "sppm" => "sppm",
            _ => {
                return Err(self.error(
                    &integrator.position,
                    format!(
                        "<integrator type=\"{kind}\"> is not supported; glint maps path, volpath, volpathmis, direct, ptracer, photonmapper and sppm"
                    ),
                ))
            }
        };
        self.scene.render.integrator = name.into();
        // Mitsuba counts path vertices (1: emitters seen directly); glint counts scattering
        // events (0: emitters seen directly).
        self.scene.render.max_depth = match (kind, max_depth) {
            ("direct", _) => 1,
            (_, d) if d < 0 => -1,
            (_, 0) => {
                self.warn(&integrator.position, "max_depth 0 renders nothing in Mitsuba; glint shows emitters only");
                0
            }
            (_, d) => d - 1,
        };
        self.scene.render.rr_depth = u32::try_from(rr_depth.max(0)).unwrap_or(5);
        if kind == "direct" {
            p.integer(self, "emitter_samples")?;
            p.integer(self, "bsdf_samples")?;
        }
        self.unused(&p);
        Ok(())
    }

    /// Mitsuba's `moment` wraps integrators and adds each one's second moment as extra film
    /// channels: glint renders its first nested integrator keeping each pixel's second moment
    /// (written as the EXR layer `m2`).
    fn moment(&mut self, moment: &Element) -> Result<()> {
        let nested: Vec<&Element> = moment.children.iter().filter(|c| c.tag == "integrator").collect();
        let Some(first) = nested.first() else {
            return Err(self.error(&moment.position, "<integrator type=\"moment\"> needs a nested <integrator>"));
        };
        for extra in &nested[1..] {
            self.warn(&extra.position, "a second integrator inside `moment`: glint renders the first one only");
        }
        self.unused(&self.properties(moment));
        self.scene.render.moment = true;
        self.integrator(first)
    }

    /// Mitsuba's `aov` renders its nested integrator's image and writes the listed channels
    /// (depth, normals, …) beside it: glint renders the image and says the channels are not
    /// written (`--aovs` writes glint's own: albedo, normal, depth).
    fn aov(&mut self, aov: &Element) -> Result<()> {
        let p = self.properties(aov);
        let channels = p.string(self, "aovs")?.unwrap_or_default();
        let nested: Vec<&Element> = aov.children.iter().filter(|c| c.tag == "integrator").collect();
        let Some(first) = nested.first() else {
            return Err(self.error(
                &aov.position,
                format!("<integrator type=\"aov\"> with no nested <integrator> renders only its channels (`{channels}`), which glint does not write"),
            ));
        };
        for extra in &nested[1..] {
            self.warn(&extra.position, "a second integrator inside `aov`: glint renders the first one only");
        }
        self.warn(
            &aov.position,
            format!("<integrator type=\"aov\">: glint renders the nested integrator's image but not the channels `{channels}` (its --aovs writes albedo, normal and depth layers)"),
        );
        self.unused(&p);
        self.integrator(first)
    }

    // ----- shapes ----------------------------------------------------------------------------

    fn shape(&mut self, shape: &'a Element) -> Result<()> {
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
            _ => {
                let why = match kind {
                    "bsplinecurve" | "linearcurve" => " (glint has no curve primitive)",
                    "ellipsoids" | "ellipsoidsmesh" => " (glint has no ellipsoid primitives)",
                    _ => "",
                };
                return Err(self.error(
                    &shape.position,
                    format!(
                        "<shape type=\"{kind}\"> is not supported{why}; glint reads obj, ply, serialized, rectangle, cube, sphere, disk, cylinder and sdfgrid"
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
            let hint = crate::error::did_you_mean(id, self.groups.keys().map(String::as_str));
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

    /// The material of a shape: its BSDF (Mitsuba's default: diffuse 0.5, or black diffuse on
    /// an emitter) plus its emission.
    fn material_for(
        &mut self,
        bsdf: Option<&'a Element>,
        emission: Option<ColorDesc>,
        at: &Position,
    ) -> Result<String> {
        let key = bsdf.map(|b| (b.position.file, b.position.line, b.position.column));
        if emission.is_none() {
            if let Some(name) = key.and_then(|k| self.materials_by_element.get(&k)) {
                return Ok(name.clone());
            }
        }
        // Mitsuba's shapes without a BSDF are diffuse 0.5, but emitting ones black (checked on
        // Mitsuba 3.9.1): an area light reflects nothing unless it is given a BSDF.
        let default_reflectance = if emission.is_some() { 0.0 } else { 0.5 };
        let mut desc = match bsdf {
            Some(b) => self.bsdf(b)?,
            None => MaterialDesc::Diffuse {
                reflectance: Some(ColorDesc::Rgb([default_reflectance; 3])),
                emission: None,
                two_sided_emission: false,
                two_sided: Some(false),
            },
        };
        let base = match bsdf {
            Some(b) => b.attribute("id").map(str::to_string).unwrap_or(format!("bsdf@{}", b.position.line)),
            None if emission.is_some() => "default-black-diffuse".into(),
            None => "default-diffuse".into(),
        };
        let emits = emission.is_some();
        let name = match emission {
            Some(e) => {
                match (&mut desc, e) {
                    (MaterialDesc::Diffuse { emission, .. }, e) => *emission = Some(e),
                    (MaterialDesc::Phong { emission, .. }, ColorDesc::Rgb(e)) => *emission = Some(e),
                    (_, e) => {
                        // Any other BSDF: the surface under its own name, wrapped by the emitter.
                        let surface = format!("{base}+surface@{}", at.line);
                        let span = bsdf.and_then(|b| b.position.span.clone());
                        let surface_desc = std::mem::replace(
                            &mut desc,
                            MaterialDesc::Emitter { radiance: e, two_sided: false, material: surface.clone() },
                        );
                        self.scene.materials.insert(surface, Located { value: surface_desc, span });
                    }
                }
                format!("{base}+emitter@{}", at.line)
            }
            None => base,
        };
        let span = bsdf.and_then(|b| b.position.span.clone());
        self.scene.materials.insert(name.clone(), Located { value: desc, span });
        if !emits {
            if let Some(k) = key {
                self.materials_by_element.insert(k, name.clone());
            }
        }
        Ok(name)
    }

    fn is_dielectric(&self, bsdf: &Element) -> bool {
        match bsdf.attribute("type") {
            Some("dielectric" | "roughdielectric") => true,
            Some("twosided" | "bumpmap" | "normalmap") => {
                bsdf.children.iter().filter(|c| c.tag == "bsdf").any(|c| self.is_dielectric(c))
            }
            _ => false,
        }
    }

    // ----- BSDFs -----------------------------------------------------------------------------

    fn bsdf(&mut self, bsdf: &'a Element) -> Result<MaterialDesc> {
        let kind = bsdf.attribute("type").unwrap_or("");
        let p = self.properties(bsdf);
        // Nested BSDFs, inline or by reference (a reference to a texture is a parameter).
        let refers_to_bsdf =
            |c: &Element| c.attribute("id").and_then(|id| self.ids.get(id)).is_none_or(|target| target.tag == "bsdf");
        let nested: Vec<&'a Element> =
            bsdf.children.iter().filter(|c| c.tag == "bsdf" || (c.tag == "ref" && refers_to_bsdf(c))).collect();
        let needs = |t: &Self, n: usize| -> Result<()> {
            if nested.len() != n {
                let what = if n == 1 { "one nested <bsdf>".to_string() } else { format!("{n} nested <bsdf>s") };
                return Err(
                    t.error(&bsdf.position, format!("{} needs {what}, found {}", bsdf.describe(), nested.len()))
                );
            }
            Ok(())
        };
        let one_sided = Some(false);
        let desc = match kind {
            "twosided" => {
                if nested.is_empty() || nested.len() > 2 {
                    needs(self, 1)?;
                }
                let front = self.nested_material(bsdf, nested[0], "front")?;
                let back = match nested.get(1) {
                    Some(b) => Some(self.nested_material(bsdf, b, "back")?),
                    None => None,
                };
                MaterialDesc::TwoSided { front, back }
            }
            "normalmap" => {
                needs(self, 1)?;
                let Some(normals) = p.color(self, "normalmap")? else {
                    return Err(self.error(&bsdf.position, "a normalmap needs a `normalmap` texture (a raw bitmap)"));
                };
                let material = self.nested_material(bsdf, nested[0], "material")?;
                MaterialDesc::NormalMap { normals, material }
            }
            "bumpmap" => {
                // One nested BSDF and one texture of any name, either of them a reference.
                let mut materials = Vec::new();
                let mut heights = Vec::new();
                for child in bsdf.children.iter().filter(|c| matches!(c.tag.as_str(), "bsdf" | "texture" | "ref")) {
                    let target = if child.tag == "ref" { self.resolve(child)? } else { child };
                    match target.tag.as_str() {
                        "bsdf" => materials.push(child),
                        "texture" => {
                            if let Some(name) = child.attribute("name") {
                                p.used.borrow_mut().insert(name.to_string());
                            }
                            heights.push(target)
                        }
                        other => {
                            return Err(self.error(
                                &child.position,
                                format!("{} takes a <bsdf> and a <texture>, not a <{other}>", bsdf.describe()),
                            ))
                        }
                    }
                }
                if materials.len() != 1 || heights.len() != 1 {
                    return Err(self.error(
                        &bsdf.position,
                        format!(
                            "{} needs one nested <bsdf> and one <texture> (the height), found {} and {}",
                            bsdf.describe(),
                            materials.len(),
                            heights.len()
                        ),
                    ));
                }
                let height = self.texture(heights[0])?;
                let scale = p.float(self, "scale")?.unwrap_or(1.0);
                let material = self.nested_material(bsdf, materials[0], "material")?;
                MaterialDesc::BumpMap { height, scale, material }
            }
            "blendbsdf" => {
                needs(self, 2)?;
                let weight = self.fraction(&p, "weight")?;
                let first = self.nested_material(bsdf, nested[0], "first")?;
                let second = self.nested_material(bsdf, nested[1], "second")?;
                MaterialDesc::Blend { weight, first, second }
            }
            "mask" => {
                needs(self, 1)?;
                let opacity = self.fraction(&p, "opacity")?;
                let material = self.nested_material(bsdf, nested[0], "material")?;
                MaterialDesc::Mask { opacity, material }
            }
            // A medium's boundary, crossed without a bounce.
            "null" => MaterialDesc::Null,
            "diffuse" => MaterialDesc::Diffuse {
                reflectance: Some(p.color(self, "reflectance")?.unwrap_or(ColorDesc::Rgb([0.5; 3]))),
                emission: None,
                two_sided_emission: false,
                two_sided: one_sided,
            },
            "conductor" | "roughconductor" => {
                let specular_reflectance = p.color(self, "specular_reflectance")?;
                let eta = p.rgb(self, "eta")?;
                let k = p.rgb(self, "k")?;
                let (metal, eta, k) = match eta {
                    Some(eta) => (None, Some(eta), Some(k.unwrap_or([0.0; 3]))),
                    None => match p.string(self, "material")?.as_deref() {
                        // Mitsuba's default: a perfect mirror (η = 0, k = 1: F = 1).
                        None | Some("none") => (None, Some([0.0; 3]), Some([1.0; 3])),
                        Some(name) => {
                            if glint_core::materials::named_metal(name).is_none() {
                                return Err(self.error(
                                    &bsdf.position,
                                    format!(
                                        "unknown conductor material `{name}`; glint knows none, {}",
                                        glint_core::materials::METAL_NAMES.join(", ")
                                    ),
                                ));
                            }
                            (Some(name.to_string()), None, None)
                        }
                    },
                };
                if kind == "conductor" {
                    MaterialDesc::Conductor { metal, eta, k, specular_reflectance, two_sided: one_sided }
                } else {
                    let TexturedRoughness { alpha, alpha_u, alpha_v, distribution } = self.textured_alphas(&p)?;
                    MaterialDesc::RoughConductor {
                        metal,
                        eta,
                        k,
                        specular_reflectance,
                        alpha,
                        alpha_u,
                        alpha_v,
                        distribution: Some(distribution),
                        two_sided: one_sided,
                    }
                }
            }
            "dielectric" | "roughdielectric" | "thindielectric" => {
                let int_ior = Some(self.ior_ratio(&p, 1.5046)?);
                let ext_ior = Some(1.0);
                let specular_reflectance = p.color(self, "specular_reflectance")?;
                let specular_transmittance = p.color(self, "specular_transmittance")?;
                match kind {
                    "dielectric" => {
                        MaterialDesc::Dielectric { int_ior, ext_ior, specular_reflectance, specular_transmittance }
                    }
                    "thindielectric" => {
                        MaterialDesc::ThinDielectric { int_ior, ext_ior, specular_reflectance, specular_transmittance }
                    }
                    _ => {
                        let TexturedRoughness { alpha, alpha_u, alpha_v, distribution } = self.textured_alphas(&p)?;
                        MaterialDesc::RoughDielectric {
                            int_ior,
                            ext_ior,
                            specular_reflectance,
                            specular_transmittance,
                            alpha,
                            alpha_u,
                            alpha_v,
                            distribution: Some(distribution),
                        }
                    }
                }
            }
            "principled" => {
                let mut weight = |name: &str| self.fraction(&p, name);
                MaterialDesc::Principled {
                    roughness: weight("roughness")?,
                    anisotropic: weight("anisotropic")?,
                    metallic: weight("metallic")?,
                    spec_trans: weight("spec_trans")?,
                    spec_tint: weight("spec_tint")?,
                    sheen: weight("sheen")?,
                    sheen_tint: weight("sheen_tint")?,
                    flatness: weight("flatness")?,
                    clearcoat: weight("clearcoat")?,
                    clearcoat_gloss: weight("clearcoat_gloss")?,
                    base_color: p.color(self, "base_color")?,
                    specular: p.float(self, "specular")?,
                    eta: p.float(self, "eta")?,
                }
            }
            "principledthin" => {
                let mut weight = |name: &str| self.fraction(&p, name);
                let (roughness, anisotropic, spec_trans) =
                    (weight("roughness")?, weight("anisotropic")?, weight("spec_trans")?);
                let (spec_tint, sheen, sheen_tint, flatness) =
                    (weight("spec_tint")?, weight("sheen")?, weight("sheen_tint")?, weight("flatness")?);
                MaterialDesc::PrincipledThin {
                    base_color: p.color(self, "base_color")?,
                    roughness,
                    anisotropic,
                    spec_trans,
                    diff_trans: self.scalar(&p, "diff_trans")?,
                    eta: self.scalar(&p, "eta")?,
                    spec_tint,
                    sheen,
                    sheen_tint,
                    flatness,
                    diffuse_reflectance_sampling_rate: p.float(self, "diffuse_reflectance_sampling_rate")?,
                    specular_reflectance_sampling_rate: p.float(self, "specular_reflectance_sampling_rate")?,
                    specular_transmittance_sampling_rate: p.float(self, "specular_transmittance_sampling_rate")?,
                    diffuse_transmittance_sampling_rate: p.float(self, "diffuse_transmittance_sampling_rate")?,
                }
            }
            "plastic" | "roughplastic" => {
                let diffuse_reflectance =
                    Some(p.color(self, "diffuse_reflectance")?.unwrap_or(ColorDesc::Rgb([0.5; 3])));
                let specular_reflectance = p.color(self, "specular_reflectance")?;
                let int_ior = Some(self.ior_ratio(&p, 1.49)?);
                let ext_ior = Some(1.0);
                let nonlinear = p.boolean(self, "nonlinear")?.unwrap_or(false);
                if kind == "plastic" {
                    MaterialDesc::Plastic {
                        diffuse_reflectance,
                        specular_reflectance,
                        int_ior,
                        ext_ior,
                        nonlinear,
                        two_sided: one_sided,
                    }
                } else {
                    let distribution = self.distribution(&p)?;
                    let alpha = p.float(self, "alpha")?;
                    if p.find("alpha_u").is_some() || p.find("alpha_v").is_some() {
                        return Err(self.error(
                            &bsdf.position,
                            "roughplastic is isotropic: give `alpha`, not `alpha_u`/`alpha_v` (as Mitsuba requires)",
                        ));
                    }
                    MaterialDesc::RoughPlastic {
                        diffuse_reflectance,
                        specular_reflectance,
                        int_ior,
                        ext_ior,
                        nonlinear,
                        alpha,
                        distribution: Some(distribution),
                        two_sided: one_sided,
                    }
                }
            }
            "pplastic" | "polarizer" | "measured_polarized" | "retarder" => {
                return Err(self.error(&bsdf.position, polarized(&format!("<bsdf type=\"{kind}\">"))))
            }
            _ => {
                let why = match kind {
                    "hair" => " (glint has no hair fibre model)",
                    "measured" => " (glint reads no measured BSDF data)",
                    _ => "",
                };
                return Err(self.error(
                    &bsdf.position,
                    format!(
                        "<bsdf type=\"{kind}\"> is not supported{why}; glint reads diffuse, conductor, roughconductor, dielectric, thindielectric, roughdielectric, plastic, roughplastic, principled, principledthin, twosided, blendbsdf, mask, bumpmap, normalmap and null"
                    ),
                ));
            }
        };
        self.unused(&p);
        Ok(desc)
    }

    /// A nested <bsdf> (or a <ref> to one) as a named material of its own, for a wrapper.
    fn nested_material(&mut self, parent: &'a Element, child: &'a Element, role: &str) -> Result<String> {
        let element = if child.tag == "ref" { self.resolve(child)? } else { child };
        let key = (element.position.file, element.position.line, element.position.column);
        if let Some(name) = self.materials_by_element.get(&key) {
            return Ok(name.clone());
        }
        let name = match element.attribute("id") {
            Some(id) => id.to_string(),
            None => format!("bsdf@{}/{role}", parent.position.line),
        };
        let desc = self.bsdf(element)?;
        self.scene.materials.insert(name.clone(), Located { value: desc, span: element.position.span.clone() });
        self.materials_by_element.insert(key, name.clone());
        Ok(name)
    }

    /// A blend weight or an opacity: a number or a texture (default: unset, glint's 0.5).
    fn fraction(&mut self, p: &Properties<'a>, name: &str) -> Result<Option<FractionDesc>> {
        Ok(self.scalar(p, name)?.map(|f| match f {
            FractionDesc::Number(x) => FractionDesc::Number(x.clamp(0.0, 1.0)),
            texture => texture,
        }))
    }

    /// Property `name` where Mitsuba reads one number of a texture (`eval_1`), unbounded.
    fn scalar(&mut self, p: &Properties<'a>, name: &str) -> Result<Option<FractionDesc>> {
        Ok(match p.color(self, name)? {
            None => None,
            Some(ColorDesc::Texture(t)) => Some(FractionDesc::Texture(self.scalar_texture(&t))),
            Some(ColorDesc::Rgb(c)) => Some(FractionDesc::Number((c[0] + c[1] + c[2]) / 3.0)),
        })
    }

    /// Texture `name` where Mitsuba reads it as one number (`eval_1`: weights, opacities,
    /// the principled parameters). Mitsuba's checkerboard swaps its colours there (`color0`
    /// where the half-checks differ), which its references show; the checker is copied with
    /// them swapped.
    fn scalar_texture(&mut self, name: &str) -> String {
        let Some(Located { value: TextureDesc::Checker { even, odd, scale, uv_transform }, span }) =
            self.scene.textures.get(name)
        else {
            return name.to_string();
        };
        let swapped = TextureDesc::Checker { even: *odd, odd: *even, scale: *scale, uv_transform: *uv_transform };
        let scalar = format!("{name}@scalar");
        let span = span.clone();
        self.scene.textures.insert(scalar.clone(), Located { value: swapped, span });
        scalar
    }

    /// The microfacet `distribution` (`beckmann` unless given, as in Mitsuba).
    fn distribution(&mut self, p: &Properties) -> Result<String> {
        let distribution = p.string(self, "distribution")?.unwrap_or_else(|| "beckmann".into());
        if distribution != "ggx" && distribution != "beckmann" {
            return Err(self.error(
                &p.element.position,
                format!("microfacet distribution `{distribution}`: glint has `beckmann` and `ggx`"),
            ));
        }
        // Visible-normal sampling or not changes only the noise.
        p.boolean(self, "sample_visible")?;
        Ok(distribution)
    }

    /// Roughness that may be textured (a conductor's, a dielectric's): `alpha`, or `alpha_u`
    /// and `alpha_v`, each a number or a texture, and the `distribution`.
    fn textured_alphas(&mut self, p: &Properties<'a>) -> Result<TexturedRoughness> {
        let distribution = self.distribution(p)?;
        let (alpha, alpha_u, alpha_v) =
            (self.textured_alpha(p, "alpha")?, self.textured_alpha(p, "alpha_u")?, self.textured_alpha(p, "alpha_v")?);
        if alpha.is_some() && (alpha_u.is_some() || alpha_v.is_some()) {
            return Err(self.error(&p.element.position, "give `alpha`, or `alpha_u` and `alpha_v`, not both"));
        }
        if alpha_u.is_some() != alpha_v.is_some() {
            return Err(self.error(&p.element.position, "`alpha_u` and `alpha_v` go together"));
        }
        Ok(TexturedRoughness { alpha, alpha_u, alpha_v, distribution })
    }

    /// A roughness that may be a texture (a conductor's): a number, or the texture as Mitsuba
    /// reads it as one number.
    fn textured_alpha(&mut self, p: &Properties<'a>, name: &str) -> Result<Option<FractionDesc>> {
        Ok(match p.color(self, name)? {
            None => None,
            Some(ColorDesc::Texture(t)) => Some(FractionDesc::Texture(self.scalar_texture(&t))),
            Some(ColorDesc::Rgb(c)) => Some(FractionDesc::Number(c[0])),
        })
    }

    /// int_ior / ext_ior, each a number or a named material.
    fn ior_ratio(&mut self, p: &Properties, default_inside: f32) -> Result<f32> {
        let ior = |name: &str, default: f32| -> Result<f32> {
            match p.string_or_number(self, name)? {
                None => Ok(default),
                Some(v) => v.parse::<f32>().ok().or_else(|| named_ior(&v)).ok_or_else(|| {
                    self.error(&p.element.position, format!("`{name}`: unknown index of refraction `{v}`"))
                }),
            }
        };
        let inside = ior("int_ior", default_inside)?;
        let outside = ior("ext_ior", 1.000277)?;
        Ok(inside / outside)
    }

    // ----- emitters and textures ------------------------------------------------------------

    /// A shape's `area` emitter: its radiance, a colour or a texture over the shape's uv.
    fn area_emitter(&mut self, emitter: &'a Element) -> Result<ColorDesc> {
        let kind = emitter.attribute("type").unwrap_or("");
        if kind != "area" {
            return Err(self
                .error(&emitter.position, format!("a shape's emitter must be `area`, got <emitter type=\"{kind}\">")));
        }
        let p = self.properties(emitter);
        let radiance = p.color(self, "radiance")?.unwrap_or(ColorDesc::Rgb([1.0; 3]));
        self.unused(&p);
        Ok(radiance)
    }

    fn emitter(&mut self, emitter: &'a Element) -> Result<()> {
        let kind = emitter.attribute("type").unwrap_or("");
        let p = self.properties(emitter);
        let at = &emitter.position;
        let light = match kind {
            "point" => {
                let matrix = p.transform(self, "to_world")?;
                let position = match p.point(self, "position")? {
                    Some(position) => position,
                    None => matrix.unwrap_or(Mat4::IDENTITY).transform_point3(Vec3::ZERO),
                };
                let intensity = p.rgb(self, "intensity")?.unwrap_or([1.0; 3]);
                LightDesc::Point {
                    position: position.to_array(),
                    color: intensity,
                    intensity: 1.0,
                    falloff: FalloffDesc::InverseSquare,
                }
            }
            "projector" => {
                // glint's projector spot: its slide is the irradiance E on the plane at unit
                // distance, π·E/cos³θ inside the square frustum (Mitsuba's, whatever the
                // texture's aspect: measured on Mitsuba 3.9).
                let matrix = p.transform(self, "to_world")?.unwrap_or(Mat4::IDENTITY);
                // Without `fov`, Mitsuba's 50 mm lens on 35 mm film spans the slide's diagonal.
                let fov = p.float(self, "fov")?;
                if let Some(fov) = fov.filter(|fov| !(*fov > 0.0 && *fov < 180.0)) {
                    return Err(self.error(&emitter.position, format!("projector `fov` must be in (0, 180) degrees, got {fov}")));
                }
                let focal_length = match p.string(self, "focal_length")? {
                    None => fov.is_none().then_some(50.0),
                    Some(_) if fov.is_some() => {
                        return Err(self.error(&emitter.position, "give a projector `fov` or `focal_length`, not both"))
                    }
                    Some(f) => Some(f.trim_end_matches("mm").trim().parse::<f32>().map_err(|_| {
                        self.error(&emitter.position, format!("`focal_length` must be like \"50mm\", got `{f}`"))
                    })?),
                };
                let scale = p.float(self, "scale")?.unwrap_or(1.0);
                let (texture, tint) = self.slide_or_tint(&p, "irradiance")?;
                LightDesc::Spot {
                    position: matrix.transform_point3(Vec3::ZERO).to_array(),
                    direction: matrix.transform_vector3(Vec3::Z).to_array(),
                    cone_angle: fov.map(|fov| 0.5 * fov),
                    focal_length,
                    edge: 0.0,
                    profile: Some("projector".into()),
                    texture,
                    // u runs along local −x = direction × local +y, v along +y (turned over by
                    // `slide`), as Mitsuba projects.
                    up: Some(matrix.transform_vector3(Vec3::Y).to_array()),
                    color: tint.map(|c| c * scale),
                    intensity: 1.0,
                    falloff: FalloffDesc::InverseSquare,
                }
            }
            "spot" => {
                let matrix = p.transform(self, "to_world")?.unwrap_or(Mat4::IDENTITY);
                let intensity = p.rgb(self, "intensity")?.unwrap_or([1.0; 3]);
                let cutoff = p.float(self, "cutoff_angle")?.unwrap_or(20.0);
                let beam = p.float(self, "beam_width")?.unwrap_or(cutoff * 0.75);
                let (texture, tint) = self.slide_or_tint(&p, "texture")?;
                LightDesc::Spot {
                    position: matrix.transform_point3(Vec3::ZERO).to_array(),
                    direction: matrix.transform_vector3(Vec3::Z).to_array(),
                    cone_angle: Some(cutoff),
                    focal_length: None,
                    edge: (cutoff - beam).max(0.0),
                    profile: Some("linear".into()),
                    texture,
                    // glint's slide runs u along `right` = direction × up: local +x when up
                    // is local −y, as Mitsuba's u runs. Its v then runs along local −y, and
                    // `slide` turns the texture's v over to match.
                    up: Some((-matrix.transform_vector3(Vec3::Y)).to_array()),
                    color: [intensity[0] * tint[0], intensity[1] * tint[1], intensity[2] * tint[2]],
                    intensity: 1.0,
                    falloff: FalloffDesc::InverseSquare,
                }
            }
            "directional" => {
                let direction = match p.vector(self, "direction")? {
                    Some(d) => d,
                    None => p.transform(self, "to_world")?.unwrap_or(Mat4::IDENTITY).transform_vector3(Vec3::Z),
                };
                let irradiance = p.rgb(self, "irradiance")?.unwrap_or([1.0; 3]);
                LightDesc::Directional { direction: direction.to_array(), color: irradiance, intensity: 1.0 }
            }
            "constant" => {
                self.scene.environment.background = p.rgb(self, "radiance")?.unwrap_or([1.0; 3]);
                self.unused(&p);
                return Ok(());
            }
            "envmap" => {
                let file = p.string(self, "filename")?.ok_or_else(|| self.error(at, "an envmap needs a `filename`"))?;
                // Mitsuba turns directions by to_world's linear part alone (`Transform *
                // Vector`), so a translation changes nothing; the documentation's scenes place
                // their maps with one. A scale stays an error: Mitsuba would look the map up by
                // an unnormalised direction, which its own sampling does not match.
                let matrix = p.transform(self, "to_world")?.map(|m| Mat4::from_mat3(Mat3::from_mat4(m)));
                let ops: Vec<TransformOp> =
                    matrix.map(|m| vec![TransformOp::Matrix(m.transpose().to_cols_array_2d())]).unwrap_or_default();
                crate::native::environment_rotation(&ops).map_err(|m| {
                    let message = if m.contains("must be a rotation") {
                        "must be a rotation (a scale or a mirror is not supported; a translation is ignored, as in Mitsuba)"
                    } else {
                        &m
                    };
                    self.error(at, format!("envmap `to_world`: {message}"))
                })?;
                // Found here so that a missing file is reported at this line.
                let found = crate::source::resolve(&self.files.search_path, std::path::Path::new(&file));
                if !found.exists() {
                    return Err(self.error(at, format!("envmap `filename` `{file}` not found ({})", found.display())));
                }
                self.scene.environment.map = Some(file);
                self.scene.environment.map_scale = p.float(self, "scale")?;
                self.scene.environment.map_transform = ops;
                p.string(self, "filter_type")?;
                self.unused(&p);
                return Ok(());
            }
            _ => {
                return Err(self.error(
                    at,
                    format!("<emitter type=\"{kind}\"> is not supported; glint reads area, point, spot, projector, directional, constant and envmap"),
                ))
            }
        };
        self.scene.lights.push(Located { value: light, span: at.span.clone() });
        self.unused(&p);
        Ok(())
    }

    /// A light's projected colour `name`: a texture becomes its slide (`slide`), a constant
    /// colour a tint to fold into its intensity.
    fn slide_or_tint(&mut self, p: &Properties<'a>, name: &str) -> Result<(Option<String>, [f32; 3])> {
        Ok(match p.color(self, name)? {
            Some(ColorDesc::Texture(texture)) => (Some(self.slide(&texture)), [1.0; 3]),
            Some(ColorDesc::Rgb(rgb)) => (None, rgb),
            None => (None, [1.0; 3]),
        })
    }

    /// Texture `name` as a spot light's slide: looked up at (u, 1 − v). Mitsuba's slide
    /// coordinates (u along the light's local +x, v along +y) are mirrored against glint's,
    /// whose (right, up, direction) turn the other way.
    fn slide(&mut self, name: &str) -> String {
        let mirrored = format!("{name}@slide");
        let Some(texture) = self.scene.textures.get(name) else { return name.to_string() };
        {
            let mut desc = texture.value.clone();
            if let TextureDesc::Image { uv_transform: Some(rows), .. }
            | TextureDesc::Checker { uv_transform: Some(rows), .. } = &mut desc
            {
                // [a b c; d e f] · (u, 1 − v, 1) = [a −b b+c; d −e e+f] · (u, v, 1).
                for row in rows.iter_mut() {
                    *row = [row[0], -row[1], row[1] + row[2]];
                }
            }
            let span = texture.span.clone();
            self.scene.textures.insert(mirrored.clone(), Located { value: desc, span });
        }
        mirrored
    }

    /// A texture element as a native texture; returns its name.
    fn texture(&mut self, texture: &Element) -> Result<String> {
        let name = texture
            .attribute("id")
            .map(str::to_string)
            .unwrap_or(format!("texture@{}:{}", texture.position.line, texture.position.column));
        if self.scene.textures.contains_key(&name) {
            return Ok(name);
        }
        let kind = texture.attribute("type").unwrap_or("");
        let p = self.properties(texture);
        // Mitsuba's `to_uv`: the 2 × 2 part and the translation of its 4 × 4 matrix.
        let to_uv = p.transform(self, "to_uv")?.map_or(Affine2::IDENTITY, |m| {
            Affine2::from_cols_array(&[m.x_axis.x, m.x_axis.y, m.y_axis.x, m.y_axis.y, m.w_axis.x, m.w_axis.y])
        });
        let rows = |a: Affine2| {
            let [c0, c1, c2] = [a.matrix2.x_axis, a.matrix2.y_axis, a.translation];
            [[c0.x, c1.x, c2.x], [c0.y, c1.y, c2.y]]
        };
        let desc = match kind {
            "bitmap" => {
                let file = p
                    .string(self, "filename")?
                    .ok_or_else(|| self.error(&texture.position, "a bitmap needs a `filename`"))?;
                let wrap = match p.string(self, "wrap_mode")?.as_deref() {
                    None | Some("repeat") => WrapDesc::Repeat,
                    Some("clamp") => WrapDesc::Clamp,
                    Some("mirror") => WrapDesc::Mirror,
                    Some(other) => {
                        return Err(self.error(
                            &texture.position,
                            format!("bitmap `wrap_mode` `{other}`: expected repeat, mirror or clamp"),
                        ))
                    }
                };
                let filter = match p.string(self, "filter_type")?.as_deref() {
                    None | Some("bilinear") => TexelFilterDesc::Bilinear,
                    Some("nearest") => TexelFilterDesc::Nearest,
                    Some(other) => {
                        return Err(self.error(
                            &texture.position,
                            format!("bitmap `filter_type` `{other}`: expected bilinear or nearest"),
                        ))
                    }
                };
                let raw = p.boolean(self, "raw")?.unwrap_or(false);
                // Mitsuba's bitmaps put v = 0 on the first (top) row; glint's images put it on
                // the bottom one.
                let flip_v = Affine2::from_cols_array(&[1.0, 0.0, 0.0, -1.0, 0.0, 1.0]);
                TextureDesc::Image {
                    file,
                    wrap,
                    filter,
                    scale: None,
                    uv_transform: Some(rows(flip_v * to_uv)),
                    raw,
                    channel: None,
                    tint: None,
                }
            }
            "checkerboard" => {
                let even = p.rgb(self, "color0")?.unwrap_or([0.4; 3]);
                let odd = p.rgb(self, "color1")?.unwrap_or([0.2; 3]);
                // Mitsuba's checkerboard has 2 × 2 checks over the unit square.
                let checks = Affine2::from_scale(Vec2::splat(2.0)) * to_uv;
                TextureDesc::Checker {
                    even,
                    odd,
                    scale: Some(Scale2Desc::Uniform(1.0)),
                    uv_transform: Some(rows(checks)),
                }
            }
            "mesh_attribute" => {
                let attribute = p.string(self, "name")?.ok_or_else(|| {
                    self.error(&texture.position, "a mesh_attribute needs a `name` (vertex_… or face_…)")
                })?;
                TextureDesc::MeshAttribute { name: attribute, scale: p.float(self, "scale")? }
            }
            _ => {
                return Err(self.error(
                    &texture.position,
                    format!(
                    "<texture type=\"{kind}\"> is not supported; glint reads bitmap, checkerboard and mesh_attribute"
                ),
                ))
            }
        };
        self.scene.textures.insert(name.clone(), Located { value: desc, span: texture.position.span.clone() });
        self.unused(&p);
        Ok(name)
    }

    fn resolve(&self, reference: &Element) -> Result<&'a Element> {
        let id = reference.attribute("id").ok_or_else(|| self.error(&reference.position, "<ref> needs an `id`"))?;
        self.ids.get(id).copied().ok_or_else(|| {
            let known: Vec<&String> = self.ids.keys().collect();
            let hint = crate::error::did_you_mean(id, known.iter().map(|s| s.as_str()));
            self.error(&reference.position, format!("no object with id `{id}`{hint}"))
        })
    }
}

/// The message for a plugin of Mitsuba's polarized variants.
fn polarized(element: &str) -> String {
    format!("{element} is not supported: it needs Mitsuba's polarized variants, and glint renders light without polarization")
}

/// Every object with an `id`, anywhere in the tree; a repeated id is an error.
fn collect_ids<'a>(element: &'a Element, ids: &mut HashMap<String, &'a Element>, files: &Files) -> Result<()> {
    for child in &element.children {
        if !PROPERTY_TAGS.contains(&child.tag.as_str()) {
            if let Some(id) = child.attribute("id") {
                if ids.insert(id.to_string(), child).is_some() {
                    return Err(files.error(&child.position, format!("the id `{id}` is used twice")));
                }
            }
        }
        collect_ids(child, ids, files)?;
    }
    Ok(())
}

/// The vertical field of view for `fov` degrees along `axis` of an image of this aspect ratio.
fn vertical_fov(fov: f32, aspect: f32, axis: &str) -> Option<f32> {
    let t = (0.5 * fov.to_radians()).tan();
    let vertical_tan = match axis {
        "y" => t,
        "x" => t / aspect,
        "diagonal" => t / (1.0 + aspect * aspect).sqrt(),
        "smaller" => {
            if aspect >= 1.0 {
                t
            } else {
                t / aspect
            }
        }
        "larger" => {
            if aspect >= 1.0 {
                t / aspect
            } else {
                t
            }
        }
        _ => return None,
    };
    Some(2.0 * vertical_tan.atan().to_degrees())
}

/// Mitsuba's named indices of refraction.
fn named_ior(name: &str) -> Option<f32> {
    Some(match name {
        "vacuum" => 1.0,
        "helium" => 1.000036,
        "hydrogen" => 1.000132,
        "air" => 1.000277,
        "carbon dioxide" => 1.00045,
        "water" => 1.333,
        "acetone" => 1.36,
        "ethanol" => 1.361,
        "carbon tetrachloride" => 1.461,
        "glycerol" => 1.4729,
        "benzene" => 1.501,
        "silicone oil" => 1.52045,
        "bromine" => 1.661,
        "water ice" => 1.31,
        "fused quartz" => 1.458,
        "pyrex" => 1.470,
        "acrylic glass" => 1.49,
        "polypropylene" => 1.49,
        "bk7" => 1.5046,
        "sodium chloride" => 1.544,
        "amber" => 1.55,
        "pet" => 1.5750,
        "diamond" => 2.419,
        _ => return None,
    })
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

/// x, y, z attributes (each defaulting to `default`), or a `value` of one or three numbers.
fn xyz(t: &Translator, e: &Element, default: f32) -> Result<Vec3> {
    if let Some(v) = e.attribute("value") {
        let numbers = parse_numbers(v).map_err(|m| t.error(&e.position, m))?;
        return match numbers.as_slice() {
            [x] => Ok(Vec3::splat(*x)),
            [x, y, z] => Ok(Vec3::new(*x, *y, *z)),
            _ => Err(t.error(&e.position, format!("expected one or three numbers, got `{v}`"))),
        };
    }
    let mut out = Vec3::splat(default);
    for (i, axis) in ["x", "y", "z"].iter().enumerate() {
        if let Some(s) = e.attribute(axis) {
            out[i] = parse_number(s).map_err(|m| t.error(&e.position, m))?;
        }
    }
    Ok(out)
}

fn parse_number(s: &str) -> std::result::Result<f32, String> {
    s.trim().parse::<f32>().map_err(|_| format!("`{s}` is not a number"))
}

/// Numbers separated by commas and/or spaces.
fn parse_numbers(s: &str) -> std::result::Result<Vec<f32>, String> {
    s.split(|c: char| c == ',' || c.is_whitespace()).filter(|p| !p.is_empty()).map(parse_number).collect()
}

impl<'e> Properties<'e> {
    /// The property child named `name`, marked as used.
    fn find(&self, name: &str) -> Option<&'e Element> {
        let found = self
            .element
            .children
            .iter()
            .find(|c| PROPERTY_TAGS.contains(&c.tag.as_str()) && c.attribute("name") == Some(name))
            .or_else(|| self.element.children.iter().find(|c| c.tag == "texture" && c.attribute("name") == Some(name)));
        if found.is_some() {
            self.used.borrow_mut().insert(name.to_string());
        }
        found
    }

    fn value<'t>(&self, t: &Translator, e: &'t Element) -> Result<&'t str> {
        e.attribute("value").ok_or_else(|| t.error(&e.position, format!("<{}> needs a `value`", e.tag)))
    }

    fn float(&self, t: &Translator, name: &str) -> Result<Option<f32>> {
        let Some(e) = self.find(name) else { return Ok(None) };
        let v = self.value(t, e)?;
        parse_number(v).map(Some).map_err(|m| t.error(&e.position, format!("`{name}`: {m}")))
    }

    fn integer(&self, t: &Translator, name: &str) -> Result<Option<i64>> {
        let Some(e) = self.find(name) else { return Ok(None) };
        let v = self.value(t, e)?;
        v.trim()
            .parse::<i64>()
            .map(Some)
            .map_err(|_| t.error(&e.position, format!("`{name}`: `{v}` is not an integer")))
    }

    fn boolean(&self, t: &Translator, name: &str) -> Result<Option<bool>> {
        let Some(e) = self.find(name) else { return Ok(None) };
        match self.value(t, e)?.trim() {
            "true" => Ok(Some(true)),
            "false" => Ok(Some(false)),
            v => Err(t.error(&e.position, format!("`{name}`: expected true or false, got `{v}`"))),
        }
    }

    fn string(&self, t: &Translator, name: &str) -> Result<Option<String>> {
        let Some(e) = self.find(name) else { return Ok(None) };
        Ok(Some(self.value(t, e)?.to_string()))
    }

    /// A `<string>` or `<float>` (indices of refraction come as either).
    fn string_or_number(&self, t: &Translator, name: &str) -> Result<Option<String>> {
        let Some(e) = self.find(name) else { return Ok(None) };
        Ok(Some(self.value(t, e)?.trim().to_string()))
    }

    fn point(&self, t: &Translator, name: &str) -> Result<Option<Vec3>> {
        let Some(e) = self.find(name) else { return Ok(None) };
        xyz(t, e, 0.0).map(Some)
    }

    fn vector(&self, t: &Translator, name: &str) -> Result<Option<Vec3>> {
        self.point(t, name)
    }

    /// A constant colour: `<rgb>`, a uniform `<spectrum>` or a `<float>`.
    fn rgb(&self, t: &Translator, name: &str) -> Result<Option<[f32; 3]>> {
        let Some(e) = self.find(name) else { return Ok(None) };
        if e.tag == "spectrum" && e.attribute("value").is_none() {
            return self.spectrum_file(t, name, e).map(Some);
        }
        let v = match e.tag.as_str() {
            "rgb" | "spectrum" | "float" => self.value(t, e)?,
            "texture" | "ref" => {
                return Err(t.error(&e.position, format!("`{name}` must be a constant colour here, not a texture")))
            }
            other => return Err(t.error(&e.position, format!("`{name}` must be a colour, got <{other}>"))),
        };
        if e.tag == "spectrum" && v.contains(':') {
            let samples = parse_sampled(v).map_err(|m| t.error(&e.position, format!("`{name}`: {m}")))?;
            return Ok(Some(self.spectrum_rgb(t, name, e, &samples)));
        }
        let numbers = parse_numbers(v).map_err(|m| t.error(&e.position, format!("`{name}`: {m}")))?;
        match numbers.as_slice() {
            [x] => Ok(Some([*x; 3])),
            [r, g, b] => Ok(Some([*r, *g, *b])),
            _ => Err(t.error(&e.position, format!("`{name}`: expected one or three numbers, got `{v}`"))),
        }
    }

    /// A `<spectrum>` without a `value`: a `filename` of wavelength–value lines (Mitsuba's
    /// `.spd`: "λ value" per line, `#` comments), converted as an inline sampled spectrum; a
    /// `blackbody` is refused, as Mitsuba's RGB variants refuse it.
    fn spectrum_file(&self, t: &Translator, name: &str, e: &Element) -> Result<[f32; 3]> {
        if e.attribute("type") == Some("blackbody") {
            return Err(t.error(
                &e.position,
                format!("`{name}`: a blackbody spectrum has no RGB value (Mitsuba's RGB variants refuse it too); give an <rgb>"),
            ));
        }
        let Some(filename) = e.attribute("filename") else {
            return Err(t.error(&e.position, format!("`{name}`: a <spectrum> needs a `value` or a `filename`")));
        };
        let path = crate::source::resolve(&t.files.search_path, std::path::Path::new(filename));
        let bytes = crate::source::read_file(&path, u64::MAX).map_err(|err| {
            t.error(&e.position, format!("`{name}`: spectrum file `{filename}` ({}): {err}", path.display()))
        })?;
        let text = String::from_utf8_lossy(&bytes);
        let mut samples = Vec::new();
        for (number, line) in text.lines().enumerate() {
            let line = line.split('#').next().unwrap_or_default().trim();
            if line.is_empty() {
                continue;
            }
            let pair: Vec<f64> = line.split_whitespace().filter_map(|x| x.parse().ok()).collect();
            match pair.as_slice() {
                [lambda, value] if lambda.is_finite() && value.is_finite() => samples.push((*lambda, *value)),
                _ => {
                    return Err(t.error(
                        &e.position,
                        format!(
                            "`{name}`: {}:{}: expected a wavelength and a value, got `{line}`",
                            path.display(),
                            number + 1
                        ),
                    ))
                }
            }
        }
        if samples.len() < 2 || samples.windows(2).any(|w| w[1].0 <= w[0].0) {
            return Err(t.error(
                &e.position,
                format!("`{name}`: spectrum file `{filename}` needs two or more wavelengths, increasing"),
            ));
        }
        Ok(self.spectrum_rgb(t, name, e, &samples))
    }

    /// A sampled spectrum's RGB as parameter `name` uses it (a reflectance or a radiance),
    /// with a warning where its colour was clamped.
    fn spectrum_rgb(&self, t: &Translator, name: &str, e: &Element, samples: &[(f64, f64)]) -> [f32; 3] {
        let role = SpectrumRole::of(name, self.element.tag == "emitter");
        let (rgb, clamped) = sampled_to_rgb(samples, role);
        if clamped {
            t.warn(
                &e.position,
                format!("`{name}`: the spectrum's colour lies outside sRGB and was clamped, as Mitsuba does"),
            );
        }
        rgb
    }

    /// A colour or a texture (nested, or by `<ref name="…" id="…"/>`).
    fn color(&self, t: &mut Translator<'e>, name: &str) -> Result<Option<ColorDesc>> {
        let Some(e) = self.find(name) else { return Ok(None) };
        match e.tag.as_str() {
            "texture" if e.attribute("type") == Some("rawconstant") => Ok(Some(ColorDesc::Rgb(raw_constant(t, e)?))),
            "texture" => Ok(Some(ColorDesc::Texture(t.texture(e)?))),
            "ref" => {
                let target = t.resolve(e)?;
                if target.tag != "texture" {
                    return Err(t.error(&e.position, format!("`{name}` refers to a <{}>, not a texture", target.tag)));
                }
                if target.attribute("type") == Some("rawconstant") {
                    return Ok(Some(ColorDesc::Rgb(raw_constant(t, target)?)));
                }
                Ok(Some(ColorDesc::Texture(t.texture(target)?)))
            }
            _ => Ok(self.rgb(t, name)?.map(ColorDesc::Rgb)),
        }
    }

    /// A `<transform name="…">` composed in Mitsuba's order (each operation applied after
    /// the ones before it).
    fn transform(&self, t: &Translator, name: &str) -> Result<Option<Mat4>> {
        let Some(e) = self.find(name) else { return Ok(None) };
        if e.tag != "transform" {
            return Err(t.error(&e.position, format!("`{name}` must be a <transform>")));
        }
        let mut matrix = Mat4::IDENTITY;
        for op in &e.children {
            let m = match op.tag.as_str() {
                "translate" => Mat4::from_translation(xyz(t, op, 0.0)?),
                "scale" => Mat4::from_scale(xyz(t, op, 1.0)?),
                "rotate" => {
                    let axis = xyz(t, op, 0.0)?;
                    let angle = op
                        .attribute("angle")
                        .ok_or_else(|| t.error(&op.position, "<rotate> needs an `angle` (degrees)"))
                        .and_then(|a| parse_number(a).map_err(|m| t.error(&op.position, m)))?;
                    let axis =
                        axis.try_normalize().ok_or_else(|| t.error(&op.position, "<rotate> needs a non-zero axis"))?;
                    Mat4::from_axis_angle(axis, angle.to_radians())
                }
                "matrix" => {
                    let v = op.attribute("value").ok_or_else(|| t.error(&op.position, "<matrix> needs a `value`"))?;
                    let n = parse_numbers(v).map_err(|m| t.error(&op.position, m))?;
                    match n.len() {
                        16 => Mat4::from_cols_slice(&n).transpose(),
                        9 => {
                            let m3 = glam::Mat3::from_cols_slice(&n).transpose();
                            Mat4::from_mat3(m3)
                        }
                        _ => {
                            return Err(
                                t.error(&op.position, format!("<matrix> needs 16 (or 9) numbers, got {}", n.len()))
                            )
                        }
                    }
                }
                "lookat" => {
                    let get = |a: &str| -> Result<Vec3> {
                        let v =
                            op.attribute(a).ok_or_else(|| t.error(&op.position, format!("<lookat> needs `{a}`")))?;
                        let n = parse_numbers(v).map_err(|m| t.error(&op.position, m))?;
                        match n.as_slice() {
                            [x, y, z] => Ok(Vec3::new(*x, *y, *z)),
                            _ => Err(t.error(&op.position, format!("<lookat> `{a}` needs three numbers"))),
                        }
                    };
                    let origin = get("origin")?;
                    let target = get("target")?;
                    let up = match op.attribute("up") {
                        Some(_) => get("up")?,
                        // Unspecified: any perpendicular will do (Mitsuba picks one too).
                        None => {
                            let dir = (target - origin).normalize_or_zero();
                            if dir.cross(Vec3::Y).length() > 1e-3 {
                                Vec3::Y
                            } else {
                                Vec3::Z
                            }
                        }
                    };
                    look_at(origin, target, up).ok_or_else(|| {
                        t.error(&op.position, "<lookat>: target equals origin, or up is parallel to the view")
                    })?
                }
                other => {
                    return Err(t.error(&op.position, format!("unknown transform operation <{other}>")));
                }
            };
            matrix = m * matrix;
        }
        Ok(Some(matrix))
    }
}

/// Mitsuba's look-at matrix: columns left = up × dir, up' = dir × left, dir, origin.
fn look_at(origin: Vec3, target: Vec3, up: Vec3) -> Option<Mat4> {
    let dir = (target - origin).try_normalize()?;
    let left = up.cross(dir).try_normalize()?;
    let new_up = dir.cross(left);
    Some(Mat4::from_cols(left.extend(0.0), new_up.extend(0.0), dir.extend(0.0), origin.extend(1.0)))
}

/// Microfacet widths, each a number or a texture, and the distribution's name.
struct TexturedRoughness {
    alpha: Option<FractionDesc>,
    alpha_u: Option<FractionDesc>,
    alpha_v: Option<FractionDesc>,
    distribution: String,
}

/// A `rawconstant` texture's `value` (a float, a vector or an RGB triple), as it is: no
/// spectral conversion, no clamping (normal maps, data).
fn raw_constant(t: &mut Translator, texture: &Element) -> Result<[f32; 3]> {
    let p = t.properties(texture);
    let value = p.element.children.iter().find(|c| c.attribute("name") == Some("value"));
    let Some(value) = value else {
        return Err(t.error(&texture.position, "a rawconstant texture needs a `value`"));
    };
    p.used.borrow_mut().insert("value".into());
    let v = match value.tag.as_str() {
        "float" => {
            let x = value.attribute("value").ok_or_else(|| t.error(&value.position, "<float> needs a `value`"))?;
            let x = parse_number(x).map_err(|m| t.error(&value.position, m))?;
            [x; 3]
        }
        "vector" | "point" | "rgb" => {
            let v = value.attribute("value").ok_or_else(|| t.error(&value.position, "needs a `value`"))?;
            match parse_numbers(v).map_err(|m| t.error(&value.position, m))?.as_slice() {
                [x] => [*x; 3],
                [x, y, z] => [*x, *y, *z],
                _ => return Err(t.error(&value.position, "a rawconstant `value` needs one or three numbers")),
            }
        }
        other => {
            return Err(t.error(&value.position, format!("a rawconstant `value` is a float or a vector, not <{other}>")))
        }
    };
    t.unused(&p);
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn field_of_view_axes() {
        let close = |a: f32, b: f32| (a - b).abs() < 1e-3;
        assert!(close(vertical_fov(40.0, 2.0, "y").unwrap(), 40.0));
        // Horizontal 90° on a 2:1 image: tan(v/2) = 1/2.
        assert!(close(vertical_fov(90.0, 2.0, "x").unwrap(), 2.0 * 0.5f32.atan().to_degrees()));
        assert!(close(vertical_fov(90.0, 2.0, "larger").unwrap(), vertical_fov(90.0, 2.0, "x").unwrap()));
        assert!(close(vertical_fov(90.0, 2.0, "smaller").unwrap(), 90.0));
        assert!(close(vertical_fov(90.0, 1.0, "diagonal").unwrap(), 2.0 * (1.0 / 2f32.sqrt()).atan().to_degrees()));
        assert!(vertical_fov(40.0, 1.0, "z").is_none());
    }

    #[test]
    fn look_at_puts_z_along_the_view() {
        let m = look_at(Vec3::new(1.0, 2.0, 3.0), Vec3::new(1.0, 2.0, 4.0), Vec3::Y).unwrap();
        assert!((m.transform_vector3(Vec3::Z) - Vec3::Z).length() < 1e-6);
        assert!((m.transform_point3(Vec3::ZERO) - Vec3::new(1.0, 2.0, 3.0)).length() < 1e-6);
        // left = up × dir = y × z = x.
        assert!((m.transform_vector3(Vec3::X) - Vec3::X).length() < 1e-6);
    }

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

    #[test]
    fn named_indices_of_refraction() {
        assert_eq!(named_ior("bk7"), Some(1.5046));
    }
}
