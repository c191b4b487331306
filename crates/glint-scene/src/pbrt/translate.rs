//! pbrt's graphics state machine run over the directives, writing glint's native scene
//! description: the current transform and its named copies, the attribute stack (material,
//! area light, orientation), named materials and textures, object definitions and their
//! instances, and the camera, film, sampler and integrator.

use std::collections::HashMap;
use std::path::Path;

use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};

use super::params::{Failure, Params, Textured};
use super::parse::{At, Directive, Parser};
use super::shapes;
use super::spectra::{self, Spectrum};
use crate::error::SceneError;
use crate::located::Located;
use crate::native::schema::*;
use crate::source::Source;

type Result<T> = std::result::Result<T, SceneError>;

/// Files a reader makes in memory: (name, bytes).
pub type MadeFiles = Vec<(String, Vec<u8>)>;

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
    let file = t.finish()?;
    Ok((file, t.made, t.warnings))
}

#[derive(Clone)]
struct GraphicsState {
    ctm: Mat4,
    reverse_orientation: bool,
    /// The glint material shapes get (`None`: pbrt's default, diffuse 0.5).
    material: Option<String>,
    area_light: Option<AreaLight>,
}

#[derive(Clone)]
struct AreaLight {
    radiance: [f32; 3],
    two_sided: bool,
}

/// A texture as the translator keeps it: a constant folds into the parameters that use it.
#[derive(Clone)]
enum Tex {
    Constant([f32; 3]),
    /// A glint texture, and its description when it is an image (to scale it).
    Glint(String, Option<TextureDesc>),
}

struct Camera {
    kind: String,
    camera_from_world: Mat4,
    fov: f32,
    lens_radius: f32,
    focal_distance: f32,
    /// A realistic camera's paraxial focal length (mm): its field of view follows from the
    /// film's size, known at the end.
    focal_length_mm: Option<f64>,
    at: At,
}

struct Translator<'s> {
    parser: Parser<'s>,
    source: &'s Source<'s>,
    scene: SceneFile,
    warnings: Vec<String>,
    made: Vec<(String, Vec<u8>)>,
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
    resolution: [u32; 2],
    /// The film's diagonal (mm), for a realistic camera.
    film_diagonal: f32,
    realistic_focal_length: Option<f64>,
    /// Transforms between `ActiveTransform EndTime` and `All` are for motion blur: skipped.
    end_time_only: bool,
    counter: usize,
}

fn matrix_op(m: Mat4) -> TransformOp {
    TransformOp::Matrix(m.transpose().to_cols_array_2d())
}

fn look_at(position: Vec3, target: Vec3, up: Vec3) -> Option<Mat4> {
    let dir = (target - position).try_normalize()?;
    let right = up.try_normalize()?.cross(dir).try_normalize()?;
    let new_up = dir.cross(right);
    let world_from_camera =
        Mat4::from_cols(right.extend(0.0), new_up.extend(0.0), dir.extend(0.0), position.extend(1.0));
    Some(world_from_camera.inverse())
}

/// pbrt's `RoughnessToAlpha` (with `remaproughness`): α = √roughness.
fn alpha_of(roughness: f32, remap: bool) -> f32 {
    if remap {
        roughness.max(0.0).sqrt()
    } else {
        roughness
    }
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
            state: GraphicsState { ctm: Mat4::IDENTITY, reverse_orientation: false, material: None, area_light: None },
            stack: Vec::new(),
            coordinate_systems: HashMap::new(),
            named_materials: HashMap::new(),
            float_textures: HashMap::new(),
            spectrum_textures: HashMap::new(),
            objects: HashMap::new(),
            defining: None,
            camera: None,
            resolution: [1280, 720],
            film_diagonal: 35.0,
            realistic_focal_length: None,
            end_time_only: false,
            counter: 0,
        }
    }

    fn fail(&self, (at, message): Failure) -> SceneError {
        self.parser.error(at, message)
    }

    fn warn(&mut self, at: At, message: impl std::fmt::Display) {
        let place = self.parser.place(at);
        self.warnings.push(format!("{place}: {message}"));
    }

    fn unique(&mut self, prefix: &str) -> String {
        self.counter += 1;
        format!("{prefix}#{}", self.counter)
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

    fn transform(&mut self, t: Mat4) {
        if !self.end_time_only {
            self.state.ctm *= t;
        }
    }

    fn directive(&mut self, d: &Directive) -> Result<()> {
        let n = self.numbers(d);
        match d.name.as_str() {
            "Translate" => self.transform(Mat4::from_translation(Vec3::new(n[0], n[1], n[2]))),
            "Scale" => self.transform(Mat4::from_scale(Vec3::new(n[0], n[1], n[2]))),
            "Rotate" => {
                let axis = Vec3::new(n[1], n[2], n[3])
                    .try_normalize()
                    .ok_or_else(|| self.parser.error(d.at, "`Rotate` needs an axis that is not zero"))?;
                self.transform(Mat4::from_axis_angle(axis, n[0].to_radians()));
            }
            "LookAt" => {
                let v = |i: usize| Vec3::new(n[i], n[i + 1], n[i + 2]);
                let m = look_at(v(0), v(3), v(6)).ok_or_else(|| {
                    self.parser.error(d.at, "`LookAt`: the eye and the target coincide, or up is parallel to the view")
                })?;
                self.transform(m);
            }
            "Transform" | "ConcatTransform" => {
                let mut a = [0.0f32; 16];
                a.copy_from_slice(&n);
                // pbrt's 16 numbers are the matrix column by column.
                let m = Mat4::from_cols_array(&a);
                if !m.is_finite() || m.determinant() == 0.0 {
                    return Err(self.parser.error(d.at, format!("`{}`: the matrix is singular", d.name)));
                }
                if d.name == "Transform" {
                    if !self.end_time_only {
                        self.state.ctm = m;
                    }
                } else {
                    self.transform(m);
                }
            }
            "Identity" => {
                if !self.end_time_only {
                    self.state.ctm = Mat4::IDENTITY;
                }
            }
            "CoordinateSystem" => {
                self.coordinate_systems.insert(d.args[0].clone(), self.state.ctm);
            }
            "CoordSysTransform" => match self.coordinate_systems.get(&d.args[0]) {
                Some(m) => self.state.ctm = *m,
                None => self.warn(d.at, format!("no coordinate system named `{}`: the transform is unchanged", d.args[0])),
            },
            "TransformTimes" => {}
            "ActiveTransform" => match d.args[0].as_str() {
                "StartTime" | "All" => self.end_time_only = false,
                "EndTime" => {
                    self.end_time_only = true;
                    self.warn(d.at, "glint has no motion blur: transforms for the end time are ignored");
                }
                other => return Err(self.parser.error(d.at, format!("`ActiveTransform` takes StartTime, EndTime or All, not `{other}`"))),
            },
            "ReverseOrientation" => self.state.reverse_orientation = !self.state.reverse_orientation,
            "WorldBegin" => {
                self.state.ctm = Mat4::IDENTITY;
                self.coordinate_systems.insert("world".into(), Mat4::IDENTITY);
            }
            "WorldEnd" => {}
            "AttributeBegin" | "TransformBegin" => self.stack.push((self.state.clone(), d.at)),
            "AttributeEnd" | "TransformEnd" => {
                let (state, begun) = self
                    .stack
                    .pop()
                    .ok_or_else(|| self.parser.error(d.at, format!("`{}` without a matching begin", d.name)))?;
                let opened = &self.parser.files[begun.file].text[begun.offset..];
                let expected = if d.name == "AttributeEnd" { "AttributeBegin" } else { "TransformBegin" };
                if !opened.starts_with(expected) {
                    return Err(self.parser.error(d.at, format!("`{}` closes what was not opened by {expected}", d.name)));
                }
                if d.name == "TransformEnd" {
                    self.state.ctm = state.ctm;
                } else {
                    self.state = state;
                }
            }
            "Attribute" => {
                return Err(self.parser.error(
                    d.at,
                    "`Attribute` (default parameters for later directives) is not supported; give the parameters on each directive",
                ))
            }
            "Option" => {
                let p = self.params(d);
                p.ignore(&p.list.iter().map(|x| x.name.as_str()).collect::<Vec<_>>());
                self.warn(d.at, "`Option` settings are pbrt's own and are ignored");
            }
            "ColorSpace" => {
                if d.args[0] != "srgb" {
                    return Err(self.parser.error(d.at, format!("color space `{}`: glint renders in linear sRGB only", d.args[0])));
                }
            }
            "Accelerator" => {
                let p = self.params(d);
                p.ignore(&p.list.iter().map(|x| x.name.as_str()).collect::<Vec<_>>());
            }
            "Camera" => self.camera(d)?,
            "Film" => self.film(d)?,
            "Sampler" => self.sampler(d)?,
            "PixelFilter" => self.filter(d)?,
            "Integrator" => self.integrator(d)?,
            "Material" => {
                let name = self.unique("material");
                self.material(d, &d.args[0], name.clone())?;
                self.state.material = Some(name);
            }
            "MakeNamedMaterial" => {
                let p = self.params(d);
                let kind = p.string("type").map_err(|f| self.fail(f))?.ok_or_else(|| {
                    self.parser.error(d.at, "`MakeNamedMaterial` needs a `\"string type\"` (diffuse, conductor, …)")
                })?;
                let name = format!("named:{}", d.args[0]);
                if self.named_materials.contains_key(&d.args[0]) {
                    return Err(self.parser.error(d.at, format!("the material `{}` is defined twice", d.args[0])));
                }
                self.material(d, &kind, name.clone())?;
                self.named_materials.insert(d.args[0].clone(), name);
            }
            "NamedMaterial" => match self.named_materials.get(&d.args[0]) {
                Some(name) => self.state.material = Some(name.clone()),
                None => {
                    let hint = crate::error::did_you_mean(&d.args[0], self.named_materials.keys().map(String::as_str));
                    return Err(self.parser.error(d.at, format!("no material named `{}`{hint}", d.args[0])));
                }
            },
            "Texture" => self.texture(d)?,
            "LightSource" => self.light(d)?,
            "AreaLightSource" => self.area_light(d)?,
            "Shape" => self.shape(d)?,
            "ObjectBegin" => {
                if self.defining.is_some() {
                    return Err(self.parser.error(d.at, "`ObjectBegin` inside another object's definition"));
                }
                self.stack.push((self.state.clone(), d.at));
                self.defining = Some((d.args[0].clone(), Vec::new(), d.at));
            }
            "ObjectEnd" => {
                let Some((name, shapes, _)) = self.defining.take() else {
                    return Err(self.parser.error(d.at, "`ObjectEnd` without `ObjectBegin`"));
                };
                let shapes = self.instanceable(&name, shapes);
                self.objects.insert(name, shapes);
                match self.stack.pop() {
                    Some((state, begun)) if self.parser.files[begun.file].text[begun.offset..].starts_with("ObjectBegin") => {
                        self.state = state
                    }
                    _ => return Err(self.parser.error(d.at, "`ObjectEnd` while an AttributeBegin inside the object is still open")),
                }
            }
            "ObjectInstance" if self.defining.is_some() => {
                return Err(self.parser.error(d.at, "`ObjectInstance` inside an object's definition"));
            }
            "ObjectInstance" => {
                let Some(shapes) = self.objects.get(&d.args[0]) else {
                    let hint = crate::error::did_you_mean(&d.args[0], self.objects.keys().map(String::as_str));
                    return Err(self.parser.error(d.at, format!("no object named `{}`{hint}", d.args[0])));
                };
                let placement = matrix_op(self.state.ctm);
                for shape in shapes.clone() {
                    let mut shape = shape;
                    shape.value.placement_mut().0.push(placement.clone());
                    self.scene.shapes.push(shape);
                }
            }
            "MakeNamedMedium" => {
                return Err(self.parser.error(d.at, "participating media are not supported yet (`MakeNamedMedium`)"))
            }
            "MediumInterface" => {
                if d.args.iter().any(|a| !a.is_empty()) {
                    return Err(self.parser.error(d.at, "participating media are not supported yet (`MediumInterface`)"));
                }
            }
            other => return Err(self.parser.error(d.at, format!("`{other}` is not supported"))),
        }
        Ok(())
    }

    // --- camera, film, sampler, filter, integrator ---------------------------------------

    fn camera(&mut self, d: &Directive) -> Result<()> {
        let p = self.params(d);
        let kind = d.args[0].clone();
        let f = |r: std::result::Result<f32, Failure>| r.map_err(|x| self.fail(x));
        let (fov, lens_radius, focal_distance) = match kind.as_str() {
            "perspective" => {
                (f(p.float("fov", 90.0))?, f(p.float("lensradius", 0.0))?, f(p.float("focaldistance", 1e6))?)
            }
            "orthographic" => {
                let lens = f(p.float("lensradius", 0.0))?;
                if lens > 0.0 {
                    self.warn(d.at, "an orthographic camera's `lensradius` is ignored (glint's has no lens)");
                }
                (90.0, 0.0, 1e6)
            }
            "realistic" => {
                let file = p
                    .string("lensfile")
                    .map_err(|x| self.fail(x))?
                    .ok_or_else(|| self.parser.error(d.at, "a realistic camera needs a `lensfile`"))?;
                let bytes = self.source.read(&file).map_err(|m| self.parser.error(self.param_at(&p, "lensfile"), m))?;
                let table = String::from_utf8_lossy(&bytes);
                let focal = super::lens::focal_length(&table)
                    .map_err(|m| self.parser.error(self.param_at(&p, "lensfile"), format!("`{file}`: {m}")))?;
                // pbrt's lens tables are in millimetres, its scenes in metres.
                let aperture = f(p.float("aperturediameter", 1.0))?;
                let focus = f(p.float("focusdistance", 10.0))?;
                if !(aperture >= 0.0 && focus > 0.0) {
                    return Err(self
                        .parser
                        .error(d.at, "a realistic camera needs `aperturediameter` ≥ 0 and `focusdistance` > 0"));
                }
                if p.list.iter().any(|x| x.name == "aperture") {
                    p.ignore(&["aperture"]);
                    self.warn(
                        d.at,
                        "a realistic camera's custom `aperture` shape is not read: the thin lens's aperture is round",
                    );
                }
                self.warn(d.at, format!("the realistic camera is approximated by a thin lens of its paraxial focal length ({focal:.1} mm) and its aperture: no aberrations or vignetting"));
                self.realistic_focal_length = Some(focal);
                (0.0, 0.5 * aperture * 1e-3, focus)
            }
            other => {
                return Err(self.parser.error(
                    d.at,
                    format!("camera `{other}` is not supported; glint reads perspective and orthographic"),
                ))
            }
        };
        for refused in ["screenwindow", "frameaspectratio"] {
            if p.list.iter().any(|x| x.name == refused) {
                return Err(self.parser.error(d.at, format!("the camera's `{refused}` is not supported")));
            }
        }
        let shutter = p.float("shutterclose", 1.0).map_err(|x| self.fail(x))?
            - p.float("shutteropen", 0.0).map_err(|x| self.fail(x))?;
        if (shutter - 1.0).abs() > 1e-6 {
            self.warn(d.at, "pbrt scales the image by the shutter's open time; glint records radiance as it is");
        }
        self.coordinate_systems.insert("camera".into(), self.state.ctm.inverse());
        let focal_length_mm = self.realistic_focal_length.take();
        self.camera = Some(Camera {
            kind,
            camera_from_world: self.state.ctm,
            fov,
            lens_radius,
            focal_distance,
            focal_length_mm,
            at: d.at,
        });
        Ok(())
    }

    fn film(&mut self, d: &Directive) -> Result<()> {
        let p = self.params(d);
        if !matches!(d.args[0].as_str(), "rgb" | "gbuffer" | "spectral") {
            return Err(self.parser.error(d.at, format!("film `{}` is not supported; glint reads rgb", d.args[0])));
        }
        let x = p.int("xresolution", 1280).map_err(|f| self.fail(f))?;
        let y = p.int("yresolution", 720).map_err(|f| self.fail(f))?;
        if !(1..=32768).contains(&x) || !(1..=32768).contains(&y) {
            return Err(self.parser.error(d.at, format!("the film's resolution must be 1 to 32768 each, got {x}x{y}")));
        }
        self.resolution = [x as u32, y as u32];
        p.ignore(&["filename", "savefp16"]);
        self.film_diagonal = p.float("diagonal", 35.0).map_err(|f| self.fail(f))?;
        if !(self.film_diagonal > 0.0 && self.film_diagonal.is_finite()) {
            return Err(self.parser.error(self.param_at(&p, "diagonal"), "the film's `diagonal` must be > 0 (mm)"));
        }
        if p.string("sensor").map_err(|f| self.fail(f))?.is_some_and(|s| s != "cie1931") {
            self.warn(d.at, "camera sensor spectra are not available: the film records CIE 1931 XYZ as sRGB (pbrt's default sensor)");
        }
        let iso = p.float("iso", 100.0).map_err(|f| self.fail(f))?;
        let exposure = p.float("exposuretime", 1.0).map_err(|f| self.fail(f))?;
        let white = p.float("whitebalance", 0.0).map_err(|f| self.fail(f))?;
        if iso != 100.0 || exposure != 1.0 || white != 0.0 {
            self.warn(
                d.at,
                "the film's iso, exposuretime and whitebalance are ignored: glint records radiance as it is",
            );
        }
        for refused in ["cropwindow", "pixelbounds"] {
            if p.list.iter().any(|x| x.name == refused) {
                return Err(self
                    .parser
                    .error(d.at, format!("the film's `{refused}` is not supported (glint renders the whole image)")));
            }
        }
        Ok(())
    }

    fn sampler(&mut self, d: &Directive) -> Result<()> {
        let p = self.params(d);
        let kind = d.args[0].as_str();
        let spp = match kind {
            "stratified" => {
                let xs = p.int("xsamples", 4).map_err(|f| self.fail(f))?;
                let ys = p.int("ysamples", 4).map_err(|f| self.fail(f))?;
                p.ignore(&["jitter"]);
                xs.checked_mul(ys).unwrap_or(0)
            }
            _ => p.int("pixelsamples", 16).map_err(|f| self.fail(f))?,
        };
        if !(1..=1 << 24).contains(&spp) {
            return Err(self.parser.error(d.at, format!("samples per pixel must be 1 to 16777216, got {spp}")));
        }
        self.scene.render.spp = spp as u32;
        self.scene.render.seed = p.int("seed", 0).map_err(|f| self.fail(f))?.max(0) as u64;
        self.scene.render.sampler = match kind {
            "independent" => "independent",
            "stratified" => "stratified",
            "halton" | "sobol" | "zsobol" | "paddedsobol" | "pmj02bn" => "sobol",
            other => return Err(self.parser.error(d.at, format!("sampler `{other}` is not known"))),
        }
        .into();
        p.ignore(&["randomization"]);
        Ok(())
    }

    fn filter(&mut self, d: &Directive) -> Result<()> {
        let p = self.params(d);
        let name = match d.args[0].as_str() {
            "box" => "box",
            "triangle" => "tent",
            "gaussian" => "gaussian",
            "mitchell" => "mitchell",
            "sinc" => {
                self.warn(d.at, "the sinc filter is not available: using gaussian");
                "gaussian"
            }
            other => return Err(self.parser.error(d.at, format!("pixel filter `{other}` is not known"))),
        };
        let names: Vec<&str> = p.list.iter().map(|x| x.name.as_str()).collect();
        if !names.is_empty() {
            p.ignore(&names);
            self.warn(d.at, "the filter's radius and shape parameters are ignored: glint's filters have fixed widths");
        }
        self.scene.render.filter = name.into();
        Ok(())
    }

    fn integrator(&mut self, d: &Directive) -> Result<()> {
        let p = self.params(d);
        let kind = d.args[0].as_str();
        self.scene.render.integrator = match kind {
            "path" | "volpath" | "simplepath" | "simplevolpath" => "path",
            "lightpath" => "light",
            "sppm" => "sppm",
            "bdpt" | "mlt" | "randomwalk" => {
                self.warn(d.at, format!("the `{kind}` integrator is not available: glint's path tracer renders the same image"));
                "path"
            }
            other => return Err(self.parser.error(d.at, format!("integrator `{other}` is not supported; glint maps path, volpath, simplepath, lightpath, sppm, bdpt and mlt"))),
        }
        .into();
        let depth = p.int("maxdepth", 5).map_err(|f| self.fail(f))?;
        // pbrt counts bounces; glint (as Mitsuba) counts path segments: one more.
        self.scene.render.max_depth = if depth < 0 { -1 } else { depth + 1 };
        match p.string("lightsampler").map_err(|f| self.fail(f))?.as_deref() {
            Some("uniform") => self.scene.render.light_selection = "uniform".into(),
            Some("power") | Some("bvh") | None => self.scene.render.light_selection = "power".into(),
            Some(other) => return Err(self.parser.error(d.at, format!("light sampler `{other}` is not known"))),
        }
        if p.bool("regularize", false).map_err(|f| self.fail(f))? {
            self.warn(d.at, "`regularize` is not available: paths are not regularized");
        }
        p.ignore(&["samplelights", "samplebsdf", "photonsperiteration", "radius", "iterations", "seed"]);
        Ok(())
    }

    /// The scene's camera, from the `Camera` directive and the film.
    fn finish(&mut self) -> Result<SceneFile> {
        let [w, h] = self.resolution;
        let camera = self.camera.take().unwrap_or(Camera {
            kind: "perspective".into(),
            camera_from_world: Mat4::IDENTITY,
            fov: 90.0,
            lens_radius: 0.0,
            focal_distance: 1e6,
            focal_length_mm: None,
            at: At { file: 0, offset: 0 },
        });
        let mut camera = camera;
        if let Some(focal) = camera.focal_length_mm {
            // The shorter side of a film of this diagonal and aspect.
            let shorter = self.film_diagonal as f64 * (w.min(h) as f64) / (w as f64).hypot(h as f64);
            let fov = super::lens::field_of_view(focal, camera.focal_distance as f64 * 1e3, shorter)
                .map_err(|m| self.parser.error(camera.at, m))?;
            camera.fov = fov as f32;
        }
        let world_from_camera = camera.camera_from_world.inverse();
        if !world_from_camera.is_finite() {
            return Err(self.parser.error(camera.at, "the camera's transform is singular"));
        }
        let position = world_from_camera.transform_point3(Vec3::ZERO);
        let forward = world_from_camera.transform_vector3(Vec3::Z);
        let up = world_from_camera.transform_vector3(Vec3::Y);
        let right = world_from_camera.transform_vector3(Vec3::X);
        // pbrt's image right is camera +x; glint's is forward × up unless mirrored.
        let mirror = right.dot(forward.cross(up)) < 0.0;
        // pbrt's fov spans the shorter image axis; glint's is vertical.
        let aspect = w as f32 / h as f32;
        let vertical = if aspect >= 1.0 {
            camera.fov
        } else {
            2.0 * ((0.5 * camera.fov.to_radians()).tan() / aspect).atan().to_degrees()
        };
        let orthographic_height = (camera.kind == "orthographic").then(|| {
            // The screen window spans [−1, 1] on the shorter axis.
            let shorter = if aspect >= 1.0 { 2.0 } else { 2.0 / aspect };
            shorter * up.length()
        });
        let (aperture_radius, focus_distance) = if camera.lens_radius > 0.0 {
            (Some(camera.lens_radius), Some(camera.focal_distance))
        } else {
            (None, None)
        };
        self.scene.camera = Located {
            value: CameraDesc {
                position: position.to_array(),
                look_at: (position + forward.normalize_or_zero()).to_array(),
                up: up.to_array(),
                fov: vertical,
                resolution: [w, h],
                aperture_radius,
                focus_distance,
                orthographic_height,
                mirror,
                medium: None,
            },
            span: None,
        };
        if self.scene.materials.is_empty() && !self.scene.shapes.is_empty() {
            self.default_material();
        }
        let file = std::mem::replace(&mut self.scene, SceneFile::new(default_camera(), RenderDesc::default()));
        if file.lights.is_empty() && file.environment.map.is_none() && file.environment.background == [0.0; 3] {
            let emitters = file.materials.values().any(|m| matches!(m.value, MaterialDesc::Emitter { .. }));
            if !emitters {
                self.warnings.push("the scene has no lights: it renders black".into());
            }
        }
        Ok(file)
    }

    // --- materials and textures ----------------------------------------------------------

    fn default_material(&mut self) -> String {
        let name = "pbrt-default".to_string();
        self.scene.materials.entry(name.clone()).or_insert_with(|| Located {
            value: MaterialDesc::Diffuse {
                reflectance: Some(ColorDesc::Rgb([0.5; 3])),
                emission: None,
                two_sided_emission: false,
                two_sided: None,
            },
            span: None,
        });
        name
    }

    fn current_material(&mut self) -> String {
        match self.state.material.clone() {
            Some(m) => m,
            None => self.default_material(),
        }
    }

    /// A colour parameter: a value, or a texture (a constant one folded in).
    fn colour(&self, p: &Params, name: &str, default: [f32; 3], albedo: bool) -> Result<ColorDesc> {
        match p.spectrum_or_texture(name, true).map_err(|f| self.fail(f))? {
            None => Ok(ColorDesc::Rgb(default)),
            Some(Textured::Value(s)) => {
                let rgb = if albedo { spectra::albedo(&s) } else { spectra::unbounded(&s) };
                rgb.map(ColorDesc::Rgb).map_err(|m| self.parser.error(self.param_at(p, name), format!("`{name}`: {m}")))
            }
            Some(Textured::Texture(t)) => {
                match self.spectrum_textures.get(&t).or_else(|| self.float_textures.get(&t)) {
                    Some(Tex::Constant(c)) => Ok(ColorDesc::Rgb(*c)),
                    Some(Tex::Glint(g, _)) => Ok(ColorDesc::Texture(g.clone())),
                    None => Err(self.unknown_texture(p, name, &t)),
                }
            }
        }
    }

    fn fraction(&self, p: &Params, name: &str) -> Result<Option<FractionDesc>> {
        Ok(match p.float_or_texture(name).map_err(|f| self.fail(f))? {
            None => None,
            Some(Textured::Value(x)) => Some(FractionDesc::Number(x)),
            Some(Textured::Texture(t)) => match self.float_textures.get(&t) {
                Some(Tex::Constant(c)) => Some(FractionDesc::Number(c[0])),
                Some(Tex::Glint(g, _)) => Some(FractionDesc::Texture(g.clone())),
                None => return Err(self.unknown_texture(p, name, &t)),
            },
        })
    }

    fn unknown_texture(&self, p: &Params, name: &str, texture: &str) -> SceneError {
        let names = self.float_textures.keys().chain(self.spectrum_textures.keys()).map(String::as_str);
        let hint = crate::error::did_you_mean(texture, names);
        self.parser.error(self.param_at(p, name), format!("`{name}`: no texture named `{texture}`{hint}"))
    }

    fn param_at(&self, p: &Params, name: &str) -> At {
        p.list.iter().find(|x| x.name == name).map_or(p.at, |x| x.at)
    }

    /// Roughness as glint's α: `None` for a smooth surface; (α_u, α_v) when anisotropic.
    fn roughness(&mut self, p: &Params, prefix: &str) -> Result<Option<(FractionDesc, Option<FractionDesc>)>> {
        let key = |k: &str| format!("{prefix}{k}");
        let remap = p.bool("remaproughness", true).map_err(|f| self.fail(f))?;
        let r = self.fraction(p, &key("roughness"))?;
        let u = self.fraction(p, &key("uroughness"))?.or_else(|| r.clone());
        let v = self.fraction(p, &key("vroughness"))?.or_else(|| r.clone());
        let alpha = |f: FractionDesc, this: &mut Self| match f {
            FractionDesc::Number(x) => FractionDesc::Number(alpha_of(x, remap)),
            FractionDesc::Texture(t) => {
                if remap {
                    this.warn(
                        p.at,
                        "a roughness texture is used as α directly (`remaproughness` applies to numbers only)",
                    );
                }
                FractionDesc::Texture(t)
            }
        };
        Ok(match (u, v) {
            (None, None) => None,
            (Some(FractionDesc::Number(a)), Some(FractionDesc::Number(b))) if a == 0.0 && b == 0.0 => None,
            (u, v) => {
                let u = alpha(u.unwrap_or(FractionDesc::Number(0.0)), self);
                let v = alpha(v.unwrap_or(FractionDesc::Number(0.0)), self);
                let isotropic = matches!((&u, &v), (FractionDesc::Number(a), FractionDesc::Number(b)) if a == b)
                    || matches!((&u, &v), (FractionDesc::Texture(a), FractionDesc::Texture(b)) if a == b);
                Some(if isotropic { (u, None) } else { (u, Some(v)) })
            }
        })
    }

    fn index(&self, p: &Params, name: &str, default: f32) -> Result<f32> {
        let at = self.param_at(p, name);
        if p.list.iter().any(|x| x.name == name && x.ty == "float") {
            return p.float(name, default).map_err(|f| self.fail(f));
        }
        match p.spectrum(name).map_err(|f| self.fail(f))? {
            None => Ok(default),
            Some(s) => spectra::index(&s).map_err(|m| self.parser.error(at, format!("`{name}`: {m}"))),
        }
    }

    /// Conductor η and k, from names, values or an artist's `reflectance`.
    fn conductor_optics(&self, p: &Params, prefix: &str) -> Result<(Option<String>, [f32; 3], [f32; 3])> {
        let (eta_key, k_key) = (format!("{prefix}eta"), format!("{prefix}k"));
        let eta = p.spectrum(&eta_key).map_err(|f| self.fail(f))?;
        let k = p.spectrum(&k_key).map_err(|f| self.fail(f))?;
        if let Some(r) = p.spectrum("reflectance").map_err(|f| self.fail(f))? {
            if eta.is_some() || k.is_some() {
                return Err(self.parser.error(p.at, "give a conductor `reflectance` or its η and k, not both"));
            }
            let r = spectra::albedo(&r).map_err(|m| self.parser.error(self.param_at(p, "reflectance"), m))?;
            // pbrt: η = 1, k = 2√r / √(1 − r), the metal whose normal reflectance is r.
            let k = r.map(|r| {
                let r = r.min(0.9999);
                2.0 * r.sqrt() / (1.0 - r).sqrt()
            });
            return Ok((None, [1.0; 3], k));
        }
        let copper = glint_core::materials::named_metal("Cu").expect("glint knows copper");
        let named = |s: &Option<Spectrum>| match s {
            Some(Spectrum::Named(n)) => Some(n.clone()),
            _ => None,
        };
        if let (Some(a), Some(b)) = (named(&eta), named(&k)) {
            let metal = spectra::metal(&a, &b).map_err(|m| self.parser.error(self.param_at(p, &eta_key), m))?;
            return Ok((Some(metal.to_string()), [0.0; 3], [0.0; 3]));
        }
        let value = |s: &Option<Spectrum>, key: &str, default: Vec3| -> Result<[f32; 3]> {
            match s {
                None => Ok(default.to_array()),
                Some(Spectrum::Named(n)) => Err(self.parser.error(
                    self.param_at(p, key),
                    format!("`{n}`: a named metal needs both its η and k spectra (metal-Cu-eta with metal-Cu-k)"),
                )),
                Some(s) => spectra::unbounded(s).map_err(|m| self.parser.error(self.param_at(p, key), m)),
            }
        };
        if eta.is_none() && k.is_none() {
            return Ok((Some("Cu".into()), [0.0; 3], [0.0; 3]));
        }
        Ok((None, value(&eta, &eta_key, copper.0)?, value(&k, &k_key, copper.1)?))
    }

    fn material(&mut self, d: &Directive, kind: &str, name: String) -> Result<()> {
        let p = self.params(d);
        p.ignore(&["type"]);
        if p.list.iter().any(|x| x.name == "displacement") {
            return Err(self.parser.error(self.param_at(&p, "displacement"), "displacement is not supported"));
        }
        let desc = match kind {
            "diffuse" => MaterialDesc::Diffuse {
                reflectance: Some(self.colour(&p, "reflectance", [0.5; 3], true)?),
                emission: None,
                two_sided_emission: false,
                two_sided: None,
            },
            "conductor" => {
                let (metal, eta, k) = self.conductor_optics(&p, "")?;
                let (eta, k) = if metal.is_some() { (None, None) } else { (Some(eta), Some(k)) };
                conductor(metal, eta, k, self.roughness(&p, "")?)
            }
            "dielectric" | "thindielectric" => {
                let eta = self.index(&p, "eta", 1.5)?;
                if !(eta.is_finite() && eta > 0.0) {
                    return Err(self.parser.error(self.param_at(&p, "eta"), format!("`eta` must be > 0, got {eta}")));
                }
                if kind == "thindielectric" {
                    MaterialDesc::ThinDielectric { int_ior: Some(eta), ext_ior: Some(1.0), specular_reflectance: None, specular_transmittance: None }
                } else {
                    match self.roughness(&p, "")? {
                        None => MaterialDesc::Dielectric { int_ior: Some(eta), ext_ior: Some(1.0), specular_reflectance: None, specular_transmittance: None },
                        Some((u, v)) => MaterialDesc::RoughDielectric {
                            int_ior: Some(eta),
                            ext_ior: Some(1.0),
                            specular_reflectance: None,
                            specular_transmittance: None,
                            alpha: if v.is_none() { Some(u.clone()) } else { None },
                            alpha_u: v.is_some().then(|| u.clone()),
                            alpha_v: v,
                            distribution: None,
                        },
                    }
                }
            }
            "coateddiffuse" => {
                let reflectance = self.colour(&p, "reflectance", [0.5; 3], true)?;
                let eta = self.index(&p, "eta", 1.5)?;
                let alpha = match self.roughness(&p, "")? {
                    None => None,
                    Some((FractionDesc::Number(a), None)) => Some(a),
                    Some(_) => {
                        return Err(self.parser.error(d.at, "a coateddiffuse's roughness must be one number (glint's rough plastic is isotropic and untextured)"))
                    }
                };
                p.ignore(&["thickness", "g", "maxdepth", "nsamples"]);
                if p.spectrum("albedo").map_err(|f| self.fail(f))?.is_some_and(|a| a != Spectrum::Rgb([0.0; 3])) {
                    self.warn(d.at, "coateddiffuse: the layer's `albedo` is ignored (glint's coat holds no medium)");
                }
                self.warn(d.at, "coateddiffuse is approximated by glint's plastic (a diffuse base under a dielectric coat, Mitsuba's model): no layer thickness, and the coat's inter-reflection is Mitsuba's closed form rather than pbrt's random walk");
                match alpha {
                    None => MaterialDesc::Plastic { diffuse_reflectance: Some(reflectance), specular_reflectance: None, int_ior: Some(eta), ext_ior: Some(1.0), nonlinear: false, two_sided: None },
                    Some(a) => MaterialDesc::RoughPlastic { diffuse_reflectance: Some(reflectance), specular_reflectance: None, int_ior: Some(eta), ext_ior: Some(1.0), nonlinear: false, alpha: Some(a), distribution: None, two_sided: None },
                }
            }
            "coatedconductor" => {
                let interface_eta = self.index(&p, "interface.eta", 1.5)?;
                let (metal, eta, k) = self.conductor_optics(&p, "conductor.")?;
                let (eta, k) = match metal {
                    Some(m) => glint_core::materials::named_metal(&m).map(|(e, k)| (e.to_array(), k.to_array())).unwrap_or((eta, k)),
                    None => (eta, k),
                };
                // Seen through the coat, the metal's indices are relative to the coat's.
                let (eta, k) = (eta.map(|x| x / interface_eta), k.map(|x| x / interface_eta));
                let _ = self.roughness(&p, "interface.")?;
                let roughness = self.roughness(&p, "conductor.")?;
                p.ignore(&["thickness", "g", "maxdepth", "nsamples", "albedo"]);
                self.warn(d.at, "coatedconductor is approximated by its conductor alone, its η and k taken relative to the coat's index: the coat's own reflection and roughness are left out");
                conductor(None, Some(eta), Some(k), roughness)
            }
            "diffusetransmission" => {
                let scale = p.float("scale", 1.0).map_err(|f| self.fail(f))?;
                let scaled = |c: ColorDesc| match c {
                    ColorDesc::Rgb(rgb) => Ok(ColorDesc::Rgb(rgb.map(|x| (x * scale).clamp(0.0, 1.0)))),
                    texture if scale == 1.0 => Ok(texture),
                    ColorDesc::Texture(_) => Err(self.parser.error(self.param_at(&p, "scale"), "a diffusetransmission's `scale` with a textured albedo is not supported")),
                };
                MaterialDesc::DiffuseTransmission {
                    reflectance: Some(scaled(self.colour(&p, "reflectance", [0.25; 3], true)?)?),
                    transmittance: Some(scaled(self.colour(&p, "transmittance", [0.25; 3], true)?)?),
                }
            }
            "mix" => {
                let names = p.strings("materials", &["string"]).map_err(|f| self.fail(f))?;
                let [first, second] = names.unwrap_or_default() else {
                    return Err(self.parser.error(d.at, "a mix material needs `\"string materials\" [ \"a\" \"b\" ]`, two named materials"));
                };
                let lookup = |n: &String| {
                    self.named_materials.get(n).cloned().ok_or_else(|| self.parser.error(self.param_at(&p, "materials"), format!("no material named `{n}`")))
                };
                let (first, second) = (lookup(first)?, lookup(second)?);
                MaterialDesc::Blend { weight: Some(self.fraction(&p, "amount")?.unwrap_or(FractionDesc::Number(0.5))), first, second }
            }
            "interface" | "none" | "" => {
                let inner = self.default_material();
                MaterialDesc::Mask { opacity: Some(FractionDesc::Number(0.0)), material: inner }
            }
            other => {
                return Err(self.parser.error(
                    d.at,
                    format!("material `{other}` is not supported; glint reads diffuse, diffusetransmission, conductor, dielectric, thindielectric, coateddiffuse, coatedconductor, mix and interface"),
                ))
            }
        };
        let desc = match p.string("normalmap").map_err(|f| self.fail(f))? {
            None => desc,
            Some(file) => {
                let inner = format!("{name}:base");
                self.scene.materials.insert(inner.clone(), Located { value: desc, span: None });
                let texture = self.unique("normalmap");
                let image = TextureDesc::Image {
                    file,
                    wrap: WrapDesc::Repeat,
                    filter: TexelFilterDesc::Bilinear,
                    scale: None,
                    uv_transform: None,
                    raw: true,
                    channel: None,
                    tint: None,
                };
                self.scene.textures.insert(texture.clone(), Located { value: image, span: None });
                MaterialDesc::NormalMap { normals: ColorDesc::Texture(texture), material: inner }
            }
        };
        self.scene.materials.insert(name, Located { value: desc, span: None });
        Ok(())
    }

    fn texture(&mut self, d: &Directive) -> Result<()> {
        let p = self.params(d);
        let (name, class, kind) = (d.args[0].clone(), d.args[1].as_str(), d.args[2].as_str());
        let float = match class {
            "float" => true,
            "spectrum" | "color" => false,
            other => {
                return Err(self.parser.error(d.at, format!("a texture is \"float\" or \"spectrum\", not `{other}`")))
            }
        };
        let constant_of = |this: &Self, key: &str, default: f32| -> Result<Tex> {
            if float {
                match p.float_or_texture(key).map_err(|f| this.fail(f))? {
                    None => Ok(Tex::Constant([default; 3])),
                    Some(Textured::Value(x)) => Ok(Tex::Constant([x; 3])),
                    Some(Textured::Texture(t)) => {
                        this.float_textures.get(&t).cloned().ok_or_else(|| this.unknown_texture(&p, key, &t))
                    }
                }
            } else {
                match p.spectrum_or_texture(key, true).map_err(|f| this.fail(f))? {
                    None => Ok(Tex::Constant([default; 3])),
                    Some(Textured::Value(s)) => spectra::unbounded(&s)
                        .map(Tex::Constant)
                        .map_err(|m| this.parser.error(this.param_at(&p, key), m)),
                    Some(Textured::Texture(t)) => {
                        this.spectrum_textures.get(&t).cloned().ok_or_else(|| this.unknown_texture(&p, key, &t))
                    }
                }
            }
        };
        let uv_transform = |this: &Self| -> Result<[[f32; 3]; 2]> {
            let mapping = p.string("mapping").map_err(|f| this.fail(f))?.unwrap_or_else(|| "uv".into());
            if mapping != "uv" {
                return Err(this.parser.error(
                    this.param_at(&p, "mapping"),
                    format!("texture mapping `{mapping}` is not supported; glint maps by uv"),
                ));
            }
            let g = |k: &str, dflt: f32| p.float(k, dflt).map_err(|f| this.fail(f));
            Ok([[g("uscale", 1.0)?, 0.0, g("udelta", 0.0)?], [0.0, g("vscale", 1.0)?, g("vdelta", 0.0)?]])
        };
        let tex = match kind {
            "constant" => constant_of(self, "value", 1.0)?,
            "imagemap" => {
                let file = p
                    .string("filename")
                    .map_err(|f| self.fail(f))?
                    .ok_or_else(|| self.parser.error(d.at, "an imagemap needs a `filename`"))?;
                let wrap = match p.string("wrap").map_err(|f| self.fail(f))?.as_deref() {
                    None | Some("repeat") => WrapDesc::Repeat,
                    Some("clamp") => WrapDesc::Clamp,
                    Some("black") => {
                        self.warn(d.at, "wrap mode `black` is not available: clamping instead");
                        WrapDesc::Clamp
                    }
                    Some(other) => {
                        return Err(self
                            .parser
                            .error(self.param_at(&p, "wrap"), format!("wrap mode `{other}` is not known")))
                    }
                };
                let filter = match p.string("filter").map_err(|f| self.fail(f))?.as_deref() {
                    Some("point") => TexelFilterDesc::Nearest,
                    _ => TexelFilterDesc::Bilinear,
                };
                let raw = match p.string("encoding").map_err(|f| self.fail(f))?.as_deref() {
                    // pbrt-v4: PNG files are sRGB, others linear unless told (float files are
                    // linear either way).
                    None => !file.to_ascii_lowercase().ends_with(".png"),
                    Some("sRGB") => false,
                    Some("linear") => true,
                    Some(other) => {
                        return Err(self.parser.error(
                            self.param_at(&p, "encoding"),
                            format!("encoding `{other}` is not supported; glint reads sRGB and linear"),
                        ))
                    }
                };
                if p.bool("invert", false).map_err(|f| self.fail(f))? {
                    return Err(self.parser.error(self.param_at(&p, "invert"), "`invert` is not supported"));
                }
                let scale = p.float("scale", 1.0).map_err(|f| self.fail(f))?;
                p.ignore(&["maxanisotropy"]);
                let desc = TextureDesc::Image {
                    file,
                    wrap,
                    filter,
                    scale: None,
                    uv_transform: Some(uv_transform(self)?),
                    raw,
                    channel: None,
                    tint: (scale != 1.0).then_some([scale; 3]),
                };
                let glint = self.unique(&format!("texture:{name}"));
                self.scene.textures.insert(glint.clone(), Located { value: desc.clone(), span: None });
                Tex::Glint(glint, Some(desc))
            }
            "checkerboard" => {
                let dimension = p.int("dimension", 2).map_err(|f| self.fail(f))?;
                let (Tex::Constant(even), Tex::Constant(odd)) =
                    (constant_of(self, "tex1", 1.0)?, constant_of(self, "tex2", 0.0)?)
                else {
                    return Err(self
                        .parser
                        .error(d.at, "a checkerboard of textures is not supported: give tex1 and tex2 as values"));
                };
                let desc = match dimension {
                    2 => TextureDesc::Checker {
                        even,
                        odd,
                        scale: Some(Scale2Desc::Uniform(1.0)),
                        uv_transform: Some(uv_transform(self)?),
                    },
                    3 => {
                        if self.state.ctm != Mat4::IDENTITY {
                            self.warn(d.at, "a solid checkerboard's checks lie in the shape's own space, not the texture's transform");
                        }
                        TextureDesc::SolidChecker { even, odd, scale: Some(1.0) }
                    }
                    other => {
                        return Err(self
                            .parser
                            .error(d.at, format!("a checkerboard's dimension is 2 or 3, not {other}")))
                    }
                };
                let glint = self.unique(&format!("texture:{name}"));
                self.scene.textures.insert(glint.clone(), Located { value: desc, span: None });
                Tex::Glint(glint, None)
            }
            "scale" => {
                let a = constant_of(self, "tex", 1.0)?;
                let b = match p.float_or_texture("scale").map_err(|f| self.fail(f))? {
                    None => Tex::Constant([1.0; 3]),
                    Some(Textured::Value(x)) => Tex::Constant([x; 3]),
                    Some(Textured::Texture(t)) => {
                        self.float_textures.get(&t).cloned().ok_or_else(|| self.unknown_texture(&p, "scale", &t))?
                    }
                };
                match (a, b) {
                    (Tex::Constant(x), Tex::Constant(y)) => Tex::Constant([x[0] * y[0], x[1] * y[1], x[2] * y[2]]),
                    (Tex::Glint(_, Some(image)), Tex::Constant(k)) | (Tex::Constant(k), Tex::Glint(_, Some(image))) => {
                        let TextureDesc::Image { file, wrap, filter, scale, uv_transform, raw, channel, tint } = image
                        else {
                            unreachable!("only images keep their description")
                        };
                        let tint = tint.unwrap_or([1.0; 3]);
                        let desc = TextureDesc::Image {
                            file,
                            wrap,
                            filter,
                            scale,
                            uv_transform,
                            raw,
                            channel,
                            tint: Some([tint[0] * k[0], tint[1] * k[1], tint[2] * k[2]]),
                        };
                        let glint = self.unique(&format!("texture:{name}"));
                        self.scene.textures.insert(glint.clone(), Located { value: desc.clone(), span: None });
                        Tex::Glint(glint, Some(desc))
                    }
                    _ => {
                        return Err(self.parser.error(
                            d.at,
                            "a scale texture is supported for a value times a value or an image, not of two textures",
                        ))
                    }
                }
            }
            "mix" => {
                let (a, b) = (constant_of(self, "tex1", 0.0)?, constant_of(self, "tex2", 1.0)?);
                let amount = p.float("amount", 0.5).map_err(|f| self.fail(f))?;
                match (a, b) {
                    (Tex::Constant(x), Tex::Constant(y)) => {
                        Tex::Constant([0, 1, 2].map(|i| (1.0 - amount) * x[i] + amount * y[i]))
                    }
                    _ => {
                        return Err(self
                            .parser
                            .error(d.at, "a mix texture is supported for two values (glint's textures do not blend)"))
                    }
                }
            }
            other => {
                return Err(self.parser.error(
                    d.at,
                    format!(
                    "texture `{other}` is not supported; glint reads imagemap, checkerboard, scale, mix and constant"
                ),
                ))
            }
        };
        if float {
            self.float_textures.insert(name, tex);
        } else {
            self.spectrum_textures.insert(name, tex);
        }
        Ok(())
    }

    // --- lights ----------------------------------------------------------------------------

    fn light_colour(&self, p: &Params, key: &str) -> Result<[f32; 3]> {
        let scale = p.float("scale", 1.0).map_err(|f| self.fail(f))?;
        let colour = match p.spectrum(key).map_err(|f| self.fail(f))? {
            None => [1.0; 3], // the colour space's illuminant: D65, white
            Some(s) => {
                spectra::emission(&s).map_err(|m| self.parser.error(self.param_at(p, key), format!("`{key}`: {m}")))?
            }
        };
        Ok(colour.map(|c| c * scale))
    }

    fn light(&mut self, d: &Directive) -> Result<()> {
        let p = self.params(d);
        let ctm = self.state.ctm;
        let power = p.float("power", -1.0).map_err(|f| self.fail(f))?;
        let desc = match d.args[0].as_str() {
            "point" => {
                let mut colour = self.light_colour(&p, "I")?;
                if power > 0.0 {
                    colour = colour.map(|c| c * power / (4.0 * std::f32::consts::PI));
                }
                let from = Vec3::from(p.triple("from", [0.0; 3]).map_err(|f| self.fail(f))?);
                LightDesc::Point { position: ctm.transform_point3(from).to_array(), color: colour, intensity: 1.0, falloff: FalloffDesc::InverseSquare }
            }
            "spot" => {
                let mut colour = self.light_colour(&p, "I")?;
                let from = Vec3::from(p.triple("from", [0.0; 3]).map_err(|f| self.fail(f))?);
                let to = Vec3::from(p.triple("to", [0.0, 0.0, 1.0]).map_err(|f| self.fail(f))?);
                let cone = p.float("coneangle", 30.0).map_err(|f| self.fail(f))?;
                let delta = p.float("conedeltaangle", 5.0).map_err(|f| self.fail(f))?;
                if power > 0.0 {
                    let (cos_end, cos_start) = (cone.to_radians().cos(), (cone - delta).to_radians().cos());
                    let k = 2.0 * std::f32::consts::PI * ((1.0 - cos_start) + 0.5 * (cos_start - cos_end));
                    colour = colour.map(|c| c * power / k);
                }
                let position = ctm.transform_point3(from);
                let direction = ctm.transform_vector3(to - from);
                LightDesc::Spot {
                    position: position.to_array(),
                    direction: direction.to_array(),
                    cone_angle: Some(cone),
                    focal_length: None,
                    edge: delta,
                    profile: Some("smooth".into()),
                    texture: None,
                    up: None,
                    color: colour,
                    intensity: 1.0,
                    falloff: FalloffDesc::InverseSquare,
                }
            }
            "distant" => {
                let mut colour = self.light_colour(&p, "L")?;
                let from = Vec3::from(p.triple("from", [0.0; 3]).map_err(|f| self.fail(f))?);
                let to = Vec3::from(p.triple("to", [0.0, 0.0, 1.0]).map_err(|f| self.fail(f))?);
                let illuminance = p.float("illuminance", -1.0).map_err(|f| self.fail(f))?;
                if illuminance > 0.0 {
                    colour = colour.map(|c| c * illuminance);
                }
                LightDesc::Directional { direction: ctm.transform_vector3(to - from).to_array(), color: colour, intensity: 1.0 }
            }
            "infinite" => {
                let scale = p.float("scale", 1.0).map_err(|f| self.fail(f))?;
                for refused in ["illuminance", "power"] {
                    if p.float(refused, -1.0).map_err(|f| self.fail(f))? > 0.0 {
                        return Err(self.parser.error(self.param_at(&p, refused), format!("an infinite light's `{refused}` is not supported; give `scale`")));
                    }
                }
                if self.scene.environment.map.is_some() || (p.list.iter().any(|x| x.name == "filename") && self.scene.environment.background != [0.0; 3]) {
                    return Err(self.parser.error(d.at, "glint's environment is one map or one constant: this infinite light would replace another"));
                }
                match p.string("filename").map_err(|f| self.fail(f))? {
                    Some(file) => self.environment_map(d.at, &file, scale, Mat3::from_mat4(ctm))?,
                    None => {
                        let colour = self.light_colour(&p, "L")?;
                        let bg = &mut self.scene.environment.background;
                        *bg = [bg[0] + colour[0], bg[1] + colour[1], bg[2] + colour[2]];
                    }
                }
                return Ok(());
            }
            other => {
                return Err(self.parser.error(
                    d.at,
                    format!("light `{other}` is not supported; glint reads point, spot, distant and infinite (and diffuse area lights)"),
                ))
            }
        };
        if power > 0.0 && d.args[0] == "distant" {
            return Err(self
                .parser
                .error(self.param_at(&p, "power"), "a distant light takes `illuminance`, not `power`"));
        }
        self.scene.lights.push(Located { value: desc, span: None });
        Ok(())
    }

    fn environment_map(&mut self, at: At, file: &str, scale: f32, light_to_world: Mat3) -> Result<()> {
        if self.scene.environment.map.is_some() {
            return Err(self.parser.error(at, "glint takes one environment map per scene"));
        }
        let bytes = self.source.read(file).map_err(|m| self.parser.error(at, m))?;
        let (w, h, pixels) =
            crate::image::decode(file, &bytes, false).map_err(|m| self.parser.error(at, format!("`{file}`: {m}")))?;
        let (w, h, resampled) = super::envmap::resample(w, h, &pixels, light_to_world)
            .map_err(|m| self.parser.error(at, format!("`{file}`: {m}")))?;
        let image = image::Rgb32FImage::from_raw(w, h, resampled.iter().flat_map(|p| p.to_array()).collect())
            .ok_or_else(|| self.parser.error(at, "the resampled map has the wrong size"))?;
        let mut bytes = Vec::new();
        image::DynamicImage::ImageRgb32F(image)
            .write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::OpenExr)
            .map_err(|e| self.parser.error(at, format!("cannot keep the resampled map: {e}")))?;
        let name = format!("pbrt-environment:{file}.exr");
        self.made.push((name.clone(), bytes));
        self.scene.environment.map = Some(name);
        self.scene.environment.map_scale = Some(scale);
        Ok(())
    }

    fn area_light(&mut self, d: &Directive) -> Result<()> {
        let p = self.params(d);
        if d.args[0] != "diffuse" {
            return Err(self
                .parser
                .error(d.at, format!("area light `{}` is not supported; glint reads diffuse", d.args[0])));
        }
        if p.list.iter().any(|x| x.name == "filename") {
            return Err(self.parser.error(self.param_at(&p, "filename"), "an image on an area light is not supported"));
        }
        if p.float("power", -1.0).map_err(|f| self.fail(f))? > 0.0 {
            return Err(self
                .parser
                .error(self.param_at(&p, "power"), "an area light's `power` is not supported; give `L` and `scale`"));
        }
        let radiance = self.light_colour(&p, "L")?;
        let two_sided = p.bool("twosided", false).map_err(|f| self.fail(f))?;
        self.state.area_light = Some(AreaLight { radiance, two_sided });
        Ok(())
    }

    // --- shapes ----------------------------------------------------------------------------

    fn shape(&mut self, d: &Directive) -> Result<()> {
        let p = self.params(d);
        let kind = d.args[0].as_str();
        if let Some(alpha) = p.list.iter().find(|x| x.name == "alpha") {
            let opaque = matches!(&alpha.values, super::parse::Values::Numbers(n) if n == &[1.0]);
            alpha.used.set(true);
            if !opaque {
                return Err(self.parser.error(alpha.at, "alpha cut-outs (`alpha`) are not supported"));
            }
        }
        p.ignore(&["emissionfilename"]);
        let f = |r: std::result::Result<f32, Failure>| r.map_err(|x| self.fail(x));
        let (ctm, reverse) = (self.state.ctm, self.state.reverse_orientation);
        // Shapes are made in their own space and placed by the current transform.
        let mut data = match kind {
            "sphere" => {
                let radius = f(p.float("radius", 1.0))?;
                let (z0, z1) = (f(p.float("zmin", -radius))?, f(p.float("zmax", radius))?);
                let (z_min, z_max) = (z0.min(z1).max(-radius), z0.max(z1).min(radius));
                let phi_max = f(p.float("phimax", 360.0))?.clamp(0.0, 360.0);
                if !(radius > 0.0 && radius.is_finite()) {
                    return Err(self.parser.error(d.at, format!("a sphere's radius must be > 0, got {radius}")));
                }
                if z_min <= -radius && z_max >= radius && phi_max >= 360.0 {
                    if reverse {
                        self.warn(d.at, "ReverseOrientation on a sphere is ignored (glint's spheres face out)");
                    }
                    let material = self.shape_material();
                    // glint's sphere has its pole on +y (u about +y from +x); pbrt's on +z (u
                    // about +z from +x): swapping y and z gives pbrt's uv, hence its textures.
                    let swap = Mat4::from_cols(Vec4::X, Vec4::Z, Vec4::Y, Vec4::W);
                    let desc = ShapeDesc::Sphere { interior: None, exterior: None, center: [0.0; 3], radius, material, transform: vec![matrix_op(swap), matrix_op(ctm)], name: None };
                    return self.push_shape(d.at, desc);
                }
                shapes::partial_sphere(radius, z_min, z_max, phi_max.to_radians())
            }
            "disk" => {
                let (h, r, inner, phi) = (f(p.float("height", 0.0))?, f(p.float("radius", 1.0))?, f(p.float("innerradius", 0.0))?, f(p.float("phimax", 360.0))?);
                if !(r > 0.0 && inner >= 0.0 && inner < r) {
                    return Err(self.parser.error(d.at, format!("a disk needs 0 ≤ innerradius < radius, got {inner} and {r}")));
                }
                shapes::disk(h, r, inner, phi.clamp(0.0, 360.0).to_radians())
            }
            "cylinder" => {
                let (r, z0, z1, phi) = (f(p.float("radius", 1.0))?, f(p.float("zmin", -1.0))?, f(p.float("zmax", 1.0))?, f(p.float("phimax", 360.0))?);
                if !(r > 0.0 && z0 != z1) {
                    return Err(self.parser.error(d.at, "a cylinder needs radius > 0 and zmin ≠ zmax"));
                }
                shapes::cylinder(r, z0.min(z1), z0.max(z1), phi.clamp(0.0, 360.0).to_radians())
            }
            "trianglemesh" => self.triangle_mesh(&p)?,
            "bilinearmesh" => self.bilinear_mesh(&p)?,
            "loopsubdiv" => {
                let levels = p.int("levels", 3).map_err(|f| self.fail(f))?;
                if !(0..=8).contains(&levels) {
                    return Err(self.parser.error(self.param_at(&p, "levels"), format!("`levels` must be 0 to 8, got {levels}")));
                }
                let mesh = self.triangle_mesh(&p)?;
                if mesh.normals.is_some() || mesh.uvs.is_some() {
                    self.warn(d.at, "a loopsubdiv's `N` and `uv` are not carried through subdivision (as in pbrt)");
                }
                // Each level quadruples the triangles; about 100 bytes each while subdividing.
                let needed = (mesh.indices.len() as u64).saturating_mul(100 << (2 * levels));
                if needed > crate::limits::memory_limit() {
                    return Err(self.parser.error(
                        self.param_at(&p, "levels"),
                        format!(
                            "{} levels of subdivision of {} triangles take about {}, more than the memory limit of {} ({})",
                            levels,
                            mesh.indices.len(),
                            crate::limits::describe(needed),
                            crate::limits::describe(crate::limits::memory_limit()),
                            crate::limits::RAISE
                        ),
                    ));
                }
                let positions: Vec<Vec3> = mesh.positions.iter().map(|&q| q.into()).collect();
                shapes::loop_subdivide(&positions, &mesh.indices, levels as u32).map_err(|m| self.parser.error(d.at, m))?
            }
            "plymesh" => {
                let file = p.string("filename").map_err(|f| self.fail(f))?.ok_or_else(|| self.parser.error(d.at, "a plymesh needs a `filename`"))?;
                if p.list.iter().any(|x| x.name == "displacement") {
                    return Err(self.parser.error(self.param_at(&p, "displacement"), "displacement is not supported"));
                }
                p.ignore(&["edgelength"]);
                // Read here rather than by the builder: pbrt faces a mesh to its normals.
                let bytes = self.source.read(&file).map_err(|m| self.parser.error(d.at, m))?;
                let mesh = crate::mesh::read_mesh(&file, &bytes).map_err(|m| self.parser.error(d.at, format!("`{file}`: {m}")))?;
                MeshData {
                    positions: mesh.positions.iter().map(|q| q.to_array()).collect(),
                    indices: mesh.indices,
                    normals: mesh.normals.map(|ns| ns.iter().map(|n| n.to_array()).collect()),
                    uvs: mesh.uvs.map(|uv| uv.iter().map(|t| t.to_array()).collect()),
                }
            }
            other => {
                return Err(self.parser.error(
                    d.at,
                    format!("shape `{other}` is not supported; glint reads trianglemesh, plymesh, sphere, disk, cylinder, bilinearmesh and loopsubdiv"),
                ))
            }
        };
        if data.indices.is_empty() {
            self.warn(d.at, format!("the {kind} has no triangles and is left out"));
            return Ok(());
        }
        // pbrt negates a shape's normals under ReverseOrientation, then faces the surface to
        // them. Its Loop surfaces face the way their limit normals Cross(S, T) point, and it
        // walks each one-ring clockwise about the winding: against the winding.
        let reverse = reverse ^ (kind == "loopsubdiv");
        if reverse {
            data.normals.iter_mut().flatten().for_each(|n| *n = (-Vec3::from(*n)).to_array());
        }
        orient(&mut data, reverse);
        let smooth = data.normals.is_some() || kind == "loopsubdiv";
        let material = self.shape_material();
        let desc = ShapeDesc::Mesh {
            interior: None,
            exterior: None,
            file: None,
            data: Some(data),
            shape_index: 0,
            smooth,
            flip_v: false,
            compute_normals: kind == "loopsubdiv",
            material,
            transform: vec![matrix_op(ctm)],
            name: None,
        };
        self.push_shape(d.at, desc)
    }

    /// The current material, wrapped as an emitter under an area light.
    fn shape_material(&mut self) -> String {
        let material = self.current_material();
        match self.state.area_light.clone() {
            Some(light) if self.defining.is_none() => {
                let name = self.unique("emitter");
                let desc = MaterialDesc::Emitter {
                    radiance: ColorDesc::Rgb(light.radiance),
                    two_sided: light.two_sided,
                    material,
                };
                self.scene.materials.insert(name.clone(), Located { value: desc, span: None });
                name
            }
            _ => material,
        }
    }

    fn push_shape(&mut self, at: At, desc: ShapeDesc) -> Result<()> {
        let shape = Located { value: desc, span: None };
        match &mut self.defining {
            Some((_, shapes, _)) => {
                shapes.push(shape);
                if self.state.area_light.is_some() {
                    self.warn(
                        at,
                        "an area light on a shape inside an object definition is ignored (as pbrt ignores it)",
                    );
                }
            }
            None => self.scene.shapes.push(shape),
        }
        Ok(())
    }

    /// An object's meshes moved to the scene's mesh library, so that each instance shares
    /// one BVH; other shapes are copied per instance.
    fn instanceable(&mut self, object: &str, shapes: Vec<Located<ShapeDesc>>) -> Vec<Located<ShapeDesc>> {
        shapes
            .into_iter()
            .enumerate()
            .map(|(i, shape)| {
                let name = format!("object {object} #{i}");
                let (value, mesh) = shape.value.into_instance(&name);
                if let Some(mesh) = mesh {
                    self.scene.meshes.insert(name, Located { value: mesh, span: None });
                }
                Located { value, span: shape.span }
            })
            .collect()
    }

    fn triangle_mesh(&self, p: &Params) -> Result<MeshData> {
        let positions = p
            .triples("P")
            .map_err(|f| self.fail(f))?
            .ok_or_else(|| self.parser.error(p.at, "a triangle mesh needs its vertices `\"point3 P\"`"))?;
        let indices = match p.ints("indices").map_err(|f| self.fail(f))? {
            Some((ints, at)) => {
                if ints.len() % 3 != 0 {
                    return Err(self
                        .parser
                        .error(at, format!("`indices` holds triangles: a multiple of 3 numbers, got {}", ints.len())));
                }
                let n = positions.len() as i64;
                if let Some(bad) = ints.iter().find(|&&i| i < 0 || i >= n) {
                    return Err(self.parser.error(at, format!("index {bad} refers to no vertex (there are {n})")));
                }
                ints.chunks_exact(3).map(|c| [c[0] as u32, c[1] as u32, c[2] as u32]).collect()
            }
            None if positions.len() == 3 => vec![[0, 1, 2]],
            None => {
                return Err(self.parser.error(
                    p.at,
                    "a triangle mesh needs `\"integer indices\"` (only a single triangle may leave them out)",
                ))
            }
        };
        let normals = p.triples("N").map_err(|f| self.fail(f))?;
        let uvs = p.pairs("uv").map_err(|f| self.fail(f))?.or(p.pairs("st").map_err(|f| self.fail(f))?);
        p.ignore(&["S", "faceIndices"]);
        for (what, len) in [("N", normals.as_ref().map(Vec::len)), ("uv", uvs.as_ref().map(Vec::len))] {
            if let Some(len) = len {
                if len != positions.len() {
                    return Err(self.parser.error(
                        self.param_at(p, what),
                        format!("`{what}` has {len} entries for {} vertices", positions.len()),
                    ));
                }
            }
        }
        Ok(MeshData { positions, indices, normals, uvs })
    }

    fn bilinear_mesh(&self, p: &Params) -> Result<MeshData> {
        let positions = p
            .triples("P")
            .map_err(|f| self.fail(f))?
            .ok_or_else(|| self.parser.error(p.at, "a bilinear mesh needs `\"point3 P\"`"))?;
        let indices: Vec<i64> = match p.ints("indices").map_err(|f| self.fail(f))? {
            Some((ints, _)) => ints,
            None if positions.len() == 4 => vec![0, 1, 2, 3],
            None => return Err(self.parser.error(p.at, "a bilinear mesh needs `\"integer indices\"`, four per patch")),
        };
        if !indices.len().is_multiple_of(4) || indices.iter().any(|&i| i < 0 || i as usize >= positions.len()) {
            return Err(self.parser.error(
                self.param_at(p, "indices"),
                "`indices` must be four vertex numbers per patch, each naming a vertex",
            ));
        }
        let normals = p.triples("N").map_err(|f| self.fail(f))?;
        let uvs = p.pairs("uv").map_err(|f| self.fail(f))?;
        for (what, len) in [("N", normals.as_ref().map(Vec::len)), ("uv", uvs.as_ref().map(Vec::len))] {
            if let Some(len) = len {
                if len != positions.len() {
                    return Err(self.parser.error(
                        self.param_at(p, what),
                        format!("`{what}` has {len} entries for {} vertices", positions.len()),
                    ));
                }
            }
        }
        // Curved patches are cut finer the fewer there are: 16 × 16 cells each up to 8,192
        // patches, then fewer, about four million triangles in all.
        let patches = indices.len() / 4;
        let cells = ((2_097_152 / patches.max(1)) as f64).sqrt().clamp(1.0, 16.0) as usize;
        let mut data = MeshData::default();
        for patch in indices.chunks_exact(4) {
            let at = |k: usize| patch[k] as usize;
            let corners = [0, 1, 2, 3].map(|k| Vec3::from(positions[at(k)]));
            let patch_uvs = match &uvs {
                Some(uv) => [0, 1, 2, 3].map(|k| Vec2::from(uv.get(at(k)).copied().unwrap_or_default())),
                None => [Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::ONE],
            };
            let patch_normals = normals
                .as_ref()
                .map(|n| [0, 1, 2, 3].map(|k| Vec3::from(n.get(at(k)).copied().unwrap_or([0.0, 0.0, 1.0]))));
            shapes::append(&mut data, shapes::bilinear_patch(corners, patch_uvs, patch_normals, cells));
        }
        Ok(data)
    }
}

/// A two-sided metal: smooth without roughness, else GGX of width α (or α_u, α_v).
fn conductor(
    metal: Option<String>,
    eta: Option<[f32; 3]>,
    k: Option<[f32; 3]>,
    roughness: Option<(FractionDesc, Option<FractionDesc>)>,
) -> MaterialDesc {
    match roughness {
        None => MaterialDesc::Conductor { metal, eta, k, specular_reflectance: None, two_sided: Some(true) },
        Some((u, v)) => MaterialDesc::RoughConductor {
            metal,
            eta,
            k,
            specular_reflectance: None,
            alpha: if v.is_none() { Some(u.clone()) } else { None },
            alpha_u: v.is_some().then(|| u.clone()),
            alpha_v: v,
            distribution: None,
            two_sided: Some(true),
        },
    }
}

/// Winds `data`'s triangles so that glint's normal ((p1 − p0) × (p2 − p0) in the shape's own
/// space, which glint keeps through any transform, mirroring or not) is pbrt's: with
/// per-vertex normals, the side they face; without, the winding's own, turned over by
/// `ReverseOrientation`. (pbrt flips a mirrored shape's normal back too: the same rule.)
fn orient(data: &mut MeshData, reverse: bool) {
    let p = |i: u32, data: &MeshData| Vec3::from(data.positions[i as usize]);
    for k in 0..data.indices.len() {
        let [a, b, c] = data.indices[k];
        let flip = match &data.normals {
            Some(normals) => {
                let cross = (p(b, data) - p(a, data)).cross(p(c, data) - p(a, data));
                let n: Vec3 = [a, b, c].iter().map(|&i| Vec3::from(normals[i as usize])).sum();
                cross.dot(n) < 0.0
            }
            None => reverse,
        };
        if flip {
            data.indices[k] = [a, c, b];
        }
    }
}

fn default_camera() -> CameraDesc {
    CameraDesc {
        position: [0.0; 3],
        look_at: [0.0, 0.0, 1.0],
        up: [0.0, 1.0, 0.0],
        fov: 90.0,
        resolution: [1280, 720],
        aperture_radius: None,
        focus_distance: None,
        orthographic_height: None,
        mirror: true,
        medium: None,
    }
}
