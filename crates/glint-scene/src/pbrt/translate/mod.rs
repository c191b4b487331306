//! pbrt's graphics state machine run over the directives, writing glint's native scene
//! description. This file holds the translator and its entry; each kind of directive maps in
//! its own file: the graphics state (transforms, attributes, named copies, object
//! definitions and instances) in `state.rs`, the camera and film in `camera.rs`, the sampler,
//! pixel filter and integrator in `render.rs`, and `materials.rs`, `textures.rs`, `lights.rs`
//! and `shapes.rs`.

mod camera;
mod lights;
mod materials;
mod media;
mod render;
mod shapes;
mod state;
mod textures;

use std::collections::HashMap;
use std::path::Path;

use glam::Mat4;

use self::camera::{default_camera, Camera};
use self::state::GraphicsState;
use self::textures::Tex;
use super::params::{Failure, Params};
use super::parse::{At, Directive, Parser};
use crate::error::SceneError;
use crate::located::Located;
use crate::native::schema::*;
use crate::reader::MadeFiles;
use crate::source::Source;

type Result<T> = std::result::Result<T, SceneError>;

/// The scene description, the files made in memory (resampled maps), and warnings.
pub fn translate(path: &Path, bytes: Vec<u8>, source: &Source) -> Result<(SceneFile, MadeFiles, Vec<String>)> {
    let parser = Parser::new(path, bytes, source)?;
    let mut t = Translator::new(parser, source);
    while let Some(directive) = t.parser.next()? {
        t.directive(&directive)?;
        for param in directive.params.iter().filter(|p| !p.used.get()) {
            let place = t.parser.place(param.at);
            t.warnings.push(format!(
                "{place}: parameter `{}` of {} {} is not read by glint and has no effect",
                param.name,
                directive.name,
                directive.args.first().map(|a| format!("\"{a}\"")).unwrap_or_default()
            ));
        }
    }
    if !t.stack.is_empty() {
        let (_, at) = t.stack.last().unwrap().clone();
        let opened: String =
            t.parser.files[at.file].text[at.offset..].chars().take_while(|c| c.is_alphanumeric()).collect();
        return Err(t.parser.error(at, format!("this {opened} is never closed")));
    }
    t.environment()?;
    t.check_medium_references()?;
    t.check_material_references()?;
    if t.follows_media && !t.scene.media.is_empty() && t.scene.render.integrator == "path" {
        t.scene.render.integrator = "volpath".into();
    }
    let file = t.finish()?;
    Ok((file, t.made, t.warnings))
}

struct Translator<'s> {
    parser: Parser<'s>,
    source: &'s Source<'s>,
    scene: SceneFile,
    warnings: Vec<String>,
    made: MadeFiles,
    state: GraphicsState,
    stack: Vec<(GraphicsState, At)>,
    coordinate_systems: HashMap<String, Mat4>,
    named_materials: HashMap<String, String>,
    float_textures: HashMap<String, Tex>,
    spectrum_textures: HashMap<String, Tex>,
    /// Shapes of object definitions, by name; the one being defined.
    objects: HashMap<String, Vec<Located<ShapeDesc>>>,
    defining: Option<(String, Vec<Located<ShapeDesc>>, At)>,
    camera: Option<Camera>,
    /// The integrator asked for follows paths through media (pbrt's `volpath`, its default):
    /// glint's `volpath` where the scene has media, its faster `path` (the same image) where
    /// it has none.
    follows_media: bool,
    /// The media `MediumInterface`s name, checked at the end (a medium may come later).
    medium_references: Vec<(String, At)>,
    /// The infinite lights' maps, added up into the environment at the end.
    infinite_maps: Vec<lights::InfiniteMap>,
    resolution: [u32; 2],
    /// The named materials used, and where, checked at the end (pbrt resolves them then).
    material_references: Vec<(String, At)>,
    /// Masks made for `alpha`, by material and opacity.
    alpha_masks: HashMap<(String, String), String>,
    /// After `WorldBegin`: the scene, no more rendering options.
    in_world: bool,
    /// The film's crop window, [x0, y0, x1, y1] in pixels.
    crop: Option<[u32; 4]>,
    /// The film's diagonal (mm), for a realistic camera.
    film_diagonal: f32,
    realistic_focal_length: Option<f64>,
    /// Transforms between `ActiveTransform EndTime` and `All` are for motion blur: skipped.
    end_time_only: bool,
    /// The names `unique` made, and how often each.
    made_names: HashMap<String, usize>,
}

impl<'s> Translator<'s> {
    fn new(parser: Parser<'s>, source: &'s Source<'s>) -> Self {
        let scene = SceneFile::new(
            default_camera(),
            RenderDesc {
                integrator: "path".into(),
                spp: 16,
                max_depth: 6,
                filter: "gaussian".into(),
                ..RenderDesc::default()
            },
        );
        Self {
            parser,
            source,
            scene,
            warnings: Vec::new(),
            made: Vec::new(),
            state: GraphicsState {
                ctm: Mat4::IDENTITY,
                reverse_orientation: false,
                material: None,
                area_light: None,
                media: (None, None),
            },
            stack: Vec::new(),
            coordinate_systems: HashMap::new(),
            named_materials: HashMap::new(),
            float_textures: HashMap::new(),
            spectrum_textures: HashMap::new(),
            objects: HashMap::new(),
            defining: None,
            camera: None,
            infinite_maps: Vec::new(),
            medium_references: Vec::new(),
            follows_media: true,
            resolution: [1280, 720],
            crop: None,
            in_world: false,
            alpha_masks: HashMap::new(),
            material_references: Vec::new(),
            film_diagonal: 35.0,
            realistic_focal_length: None,
            end_time_only: false,
            made_names: HashMap::new(),
        }
    }

    fn fail(&self, (at, message): Failure) -> SceneError {
        self.parser.error(at, message)
    }

    fn warn(&mut self, at: At, message: impl std::fmt::Display) {
        let place = self.parser.place(at);
        self.warnings.push(format!("{place}: {message}"));
    }

    /// A name for what the translator makes, saying what it is and where it comes from, since
    /// messages name it: `material at scene.pbrt:12:1` (with a count where a file included
    /// twice makes the same place twice).
    fn unique(&mut self, what: &str, at: At) -> String {
        let name = format!("{what} at {}", self.parser.place(at));
        let made = self.made_names.entry(name.clone()).or_insert(0);
        *made += 1;
        if *made == 1 {
            name
        } else {
            format!("{name} ({made})")
        }
    }

    fn params<'d>(&self, d: &'d Directive) -> Params<'d> {
        let what = match d.args.first() {
            Some(a) => format!("{} \"{a}\"", d.name),
            None => d.name.clone(),
        };
        Params { list: &d.params, what, at: d.at }
    }

    fn numbers(&self, d: &Directive) -> Vec<f32> {
        // The parser has checked that these parse.
        d.args.iter().map(|a| a.parse::<f64>().unwrap_or(0.0) as f32).collect()
    }

    fn param_at(&self, p: &Params, name: &str) -> At {
        p.list.iter().find(|x| x.name == name).map_or(p.at, |x| x.at)
    }
}
