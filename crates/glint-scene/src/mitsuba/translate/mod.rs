//! Mitsuba 3 plugins mapped onto glint's native scene description, which the native builder
//! then checks and builds (so a Mitsuba scene and a TOML scene become the same `Scene`).
//! docs/mitsuba.md lists every element and what it becomes; anything glint cannot render
//! faithfully is an error naming the element and its line, or, where the image would only
//! differ in its noise or in a documented approximation, a warning.
//!
//! This file holds the translator, the scene's top level and `<ref>`; each plugin kind maps
//! in its own file: the sensor with its film, reconstruction filter and sampler in
//! `sensor.rs`, `integrator.rs`, `shapes.rs` (with shape groups and instances), `bsdfs.rs`
//! (with a shape's material), `emitters.rs`, `textures.rs` and `media.rs`; a plugin's
//! properties are read in `properties.rs`.

mod bsdfs;
mod emitters;
mod integrator;
mod media;
mod properties;
mod sensor;
mod shapes;
mod textures;

use std::cell::RefCell;
use std::collections::{HashMap, HashSet};

use self::properties::{Properties, PROPERTY_TAGS};
use super::xml::{Element, Files, Position};
use crate::error::SceneError;
use crate::located::Located;
use crate::native::schema::*;

type Result<T> = std::result::Result<T, SceneError>;

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
            crop: None,
        };
        let scene = SceneFile::new(
            camera,
            RenderDesc {
                integrator: "path".into(),
                max_depth: -1,
                spp: 4,
                // Mitsuba's default reconstruction filter: its gaussian, σ ½ out to 4σ.
                filter: "gaussian-wide".into(),
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
    fn resolve(&self, reference: &Element) -> Result<&'a Element> {
        let id = reference.attribute("id").ok_or_else(|| self.error(&reference.position, "<ref> needs an `id`"))?;
        self.ids.get(id).copied().ok_or_else(|| {
            let hint = crate::error::did_you_mean_among_keys(id, self.ids.keys());
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
