//! The graphics state: the current transform and its named copies, the attribute stack
//! (material, area light, orientation), named materials, object definitions and their
//! instances; every directive is dispatched from here to the file of its kind.

use glam::{Mat4, Vec3};

use super::lights::AreaLight;
use super::{Result, Translator};
use crate::located::Located;
use crate::native::schema::*;
use crate::pbrt::parse::Directive;

#[derive(Clone)]
pub(super) struct GraphicsState {
    pub(super) ctm: Mat4,
    pub(super) reverse_orientation: bool,
    /// The glint material shapes get (`None`: pbrt's default, diffuse 0.5).
    pub(super) material: Option<String>,
    pub(super) area_light: Option<AreaLight>,
    /// The media inside and outside the shapes made now (`MediumInterface`); the camera is
    /// in the outside one.
    pub(super) media: (Option<String>, Option<String>),
}

pub(super) fn matrix_op(m: Mat4) -> TransformOp {
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

impl Translator<'_> {
    fn transform(&mut self, t: Mat4) {
        if !self.end_time_only {
            self.state.ctm *= t;
        }
    }

    pub(super) fn directive(&mut self, d: &Directive) -> Result<()> {
        self.check_block(d)?;
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
                self.in_world = true;
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
                let name = self.unique(&format!("material \"{}\"", d.args[0]), d.at);
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
            "NamedMaterial" => self.state.material = Some(self.named_material(&d.args[0], d.at)),
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
                    let hint = crate::error::did_you_mean_among_keys(&d.args[0], self.objects.keys());
                    return Err(self.parser.error(d.at, format!("no object named `{}`{hint}", d.args[0])));
                };
                let placement = matrix_op(self.state.ctm);
                for shape in shapes.clone() {
                    let mut shape = shape;
                    shape.value.placement_mut().0.push(placement.clone());
                    self.scene.shapes.push(shape);
                }
            }
            "MakeNamedMedium" => self.make_named_medium(d)?,
            "MediumInterface" => self.medium_interface(d)?,
            other => return Err(self.parser.error(d.at, format!("`{other}` is not supported"))),
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
}

/// Directives of pbrt's options block (before `WorldBegin`) only.
const OPTIONS_ONLY: [&str; 7] = ["Camera", "Film", "Sampler", "Integrator", "PixelFilter", "Accelerator", "WorldBegin"];
/// Directives of the world block (after `WorldBegin`) only.
const WORLD_ONLY: [&str; 14] = [
    "Shape",
    "LightSource",
    "AreaLightSource",
    "Material",
    "MakeNamedMaterial",
    "NamedMaterial",
    "Texture",
    "ObjectBegin",
    "ObjectEnd",
    "ObjectInstance",
    "AttributeBegin",
    "AttributeEnd",
    "Attribute",
    "ReverseOrientation",
];

impl Translator<'_> {
    /// pbrt's two blocks: the rendering options, then `WorldBegin` and the scene. pbrt refuses
    /// a directive in the wrong one (a camera after `WorldBegin` would render black, a shape
    /// before it would sit under the camera's transform).
    fn check_block(&self, d: &Directive) -> Result<()> {
        let name = d.name.as_str();
        if self.in_world && OPTIONS_ONLY.contains(&name) {
            let what = if name == "WorldBegin" { "a second `WorldBegin`".to_string() } else { format!("`{name}`") };
            return Err(self.parser.error(
                d.at,
                format!("{what} after `WorldBegin`: the rendering options (Camera, Film, Sampler, Integrator, PixelFilter) come before it"),
            ));
        }
        if !self.in_world && WORLD_ONLY.contains(&name) {
            return Err(self.parser.error(
                d.at,
                format!(
                    "`{name}` before `WorldBegin`: shapes, lights, materials, textures and attributes come after it"
                ),
            ));
        }
        Ok(())
    }
}
