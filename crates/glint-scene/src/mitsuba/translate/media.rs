//! Mitsuba's participating media: `homogeneous` and `heterogeneous` media, their `gridvolume`
//! and `constvolume` data, `isotropic` and `hg` phase functions, and the `interior`,
//! `exterior` and sensor `medium` references that place them, mapped onto the native
//! `[media]` entries with Mitsuba's semantics:
//! * a heterogeneous medium is empty outside its σ_t volume's box (the unit cube under the
//!   volume's `to_world`, even for a constant σ_t), while its albedo is read clamped to its
//!   own volume's edges;
//! * σ_t and the albedo default to 1 and 0.75, `hg`'s g to 0.8; sampled spectra become RGB
//!   as reflectances, clamped, as Mitsuba's RGB variants make them.

use glam::Mat4;

use super::{Properties, Result, Translator};
use crate::located::Located;
use crate::mitsuba::xml::Element;
use crate::native::schema::{AlbedoDesc, AlbedoField, MediumDesc, PhaseDesc, TransformOp};

/// A medium parameter as Mitsuba gives it: a constant, or a volume.
enum Value {
    /// A number or colour; a `constvolume` keeps its box.
    Constant([f32; 3], Option<Mat4>),
    /// A `gridvolume`'s file, placed by its `to_world` (`None`: the file's own box), and
    /// whether it repeats past its box (`wrap_mode` `repeat`).
    Grid(String, Option<Mat4>, bool),
}

/// Half the side of the box a homogeneous medium with an albedo volume fills: the medium is
/// unbounded, the grid medium that renders it is not, and any shape it lies in is far smaller.
const UNBOUNDED: f32 = 1e6;

impl<'a> Translator<'a> {
    /// The native medium made for a `<medium>` element (once per element), by name.
    pub(super) fn medium(&mut self, element: &'a Element) -> Result<String> {
        let key = (element.position.file, element.position.line, element.position.column);
        if let Some(name) = self.media_by_element.get(&key) {
            return Ok(name.clone());
        }
        let kind = element.attribute("type").unwrap_or("");
        let p = self.properties(element);
        let scale = p.float(self, "scale")?;
        if p.boolean(self, "sample_emitters")? == Some(false) {
            self.warn(
                &element.position,
                "`sample_emitters` false: glint samples the emitters from media anyway (only the noise differs)",
            );
        }
        // Whether Mitsuba samples distances by one channel's extinction or by each channel's:
        // the same image, different noise.
        p.boolean(self, "has_spectral_extinction")?;
        let phase = self.phase(element)?;
        let sigma_t = self.medium_value(&p, element, "sigma_t")?;
        let albedo = self.medium_value(&p, element, "albedo")?;
        let desc = match kind {
            // σ_t constant and the albedo a volume (Mitsuba reads it at each collision): a grid
            // medium of one density over a box holding the scene, the albedo its field.
            "homogeneous" if matches!(albedo, Some(Value::Grid(..))) => {
                let sigma_t = match sigma_t {
                    None => [1.0; 3],
                    Some(Value::Constant(v, _)) => v,
                    Some(Value::Grid(..)) => {
                        return Err(self.error(
                            &element.position,
                            "a homogeneous medium's `sigma_t` is a constant, not a grid volume",
                        ))
                    }
                };
                let Some(Value::Grid(file, to_world, repeat)) = albedo else { unreachable!("matched above") };
                let wrap = Some(if repeat { "repeat" } else { "clamp" }.to_string());
                MediumDesc::Grid {
                    file: None,
                    value: Some(sigma_t),
                    min: Some([-UNBOUNDED; 3]),
                    max: Some([UNBOUNDED; 3]),
                    transform: Vec::new(),
                    albedo: Some(AlbedoDesc::Field(AlbedoField {
                        file,
                        min: None,
                        max: None,
                        transform: ops(to_world),
                        wrap,
                    })),
                    scale,
                    phase: Some(phase),
                    emission: None,
                }
            }
            "homogeneous" => {
                let constant = |value: Option<Value>, name: &str, default: f32| match value {
                    None => Ok([default; 3]),
                    Some(Value::Constant(v, _)) => Ok(v),
                    Some(Value::Grid(..)) => Err(self.error(
                        &element.position,
                        format!("a homogeneous medium's `{name}` is a constant, not a grid volume"),
                    )),
                };
                MediumDesc::Homogeneous {
                    sigma_a: None,
                    sigma_s: None,
                    sigma_t: Some(constant(sigma_t, "sigma_t", 1.0)?),
                    albedo: Some(constant(albedo, "albedo", 0.75)?),
                    scale,
                    phase: Some(phase),
                    emission: None,
                }
            }
            "heterogeneous" => {
                // A constant σ_t is a constvolume over the unit cube, as Mitsuba makes it.
                let (file, value, to_world) = match sigma_t.unwrap_or(Value::Constant([1.0; 3], None)) {
                    Value::Constant(v, to_world) => (None, Some(v), Some(to_world.unwrap_or(Mat4::IDENTITY))),
                    Value::Grid(file, to_world, _) => (Some(file), None, to_world),
                };
                let albedo = match albedo.unwrap_or(Value::Constant([0.75; 3], None)) {
                    Value::Constant(v, _) => AlbedoDesc::Constant(v),
                    Value::Grid(file, to_world, repeat) => AlbedoDesc::Field(AlbedoField {
                        file,
                        min: None,
                        max: None,
                        transform: ops(to_world),
                        wrap: repeat.then(|| "repeat".to_string()),
                    }),
                };
                MediumDesc::Grid {
                    file,
                    value,
                    min: None,
                    max: None,
                    transform: ops(to_world),
                    albedo: Some(albedo),
                    scale,
                    phase: Some(phase),
                    emission: None,
                }
            }
            _ => {
                return Err(self.error(
                    &element.position,
                    format!("<medium type=\"{kind}\"> is not supported; glint reads homogeneous and heterogeneous"),
                ))
            }
        };
        let name = element.attribute("id").map(str::to_string).unwrap_or(format!("medium@{}", element.position.line));
        self.scene.media.insert(name.clone(), Located { value: desc, span: element.position.span.clone() });
        self.media_by_element.insert(key, name.clone());
        self.unused(&p);
        Ok(name)
    }

    /// A medium's phase function (nested or by reference; isotropic when none is given).
    fn phase(&mut self, medium: &'a Element) -> Result<PhaseDesc> {
        let mut found = None;
        for child in &medium.children {
            let target = match child.tag.as_str() {
                "phase" => child,
                "ref" if self.resolve(child)?.tag == "phase" => self.resolve(child)?,
                _ => continue,
            };
            if found.replace(target).is_some() {
                return Err(self.error(&child.position, "a medium has one phase function"));
            }
        }
        let Some(phase) = found else { return Ok(PhaseDesc::Isotropic) };
        let p = self.properties(phase);
        let desc = match phase.attribute("type").unwrap_or("") {
            "isotropic" => PhaseDesc::Isotropic,
            "hg" => {
                let g = p.float(self, "g")?.unwrap_or(0.8);
                if g.is_nan() || g.abs() >= 1.0 {
                    return Err(self.error(&phase.position, format!("hg's `g` lies in (−1, 1), got {g}")));
                }
                PhaseDesc::Hg { g }
            }
            other => {
                return Err(self.error(
                    &phase.position,
                    format!("<phase type=\"{other}\"> is not supported; glint reads isotropic and hg"),
                ))
            }
        };
        self.unused(&p);
        Ok(desc)
    }

    /// `sigma_t` or `albedo` of a medium: a number, a colour, a spectrum or a `<volume>`.
    fn medium_value(&mut self, p: &Properties<'a>, medium: &'a Element, name: &str) -> Result<Option<Value>> {
        let volume = medium.children.iter().find(|c| c.attribute("name") == Some(name) && c.tag == "volume");
        let volume = match volume {
            Some(v) => Some(v),
            None => match medium.children.iter().find(|c| c.attribute("name") == Some(name) && c.tag == "ref") {
                Some(r) => Some(self.resolve(r)?),
                None => None,
            },
        };
        let Some(volume) = volume else { return Ok(p.rgb(self, name)?.map(|v| Value::Constant(v, None))) };
        p.used.borrow_mut().insert(name.to_string());
        if volume.tag != "volume" {
            return Err(self.error(&volume.position, format!("`{name}` must be a colour or a <volume>")));
        }
        let q = self.properties(volume);
        let to_world = q.transform(self, "to_world")?;
        let value = match volume.attribute("type").unwrap_or("") {
            "constvolume" => {
                let v = q.rgb(self, "value")?.unwrap_or([1.0; 3]);
                Value::Constant(v, to_world)
            }
            "gridvolume" => {
                let file = q
                    .string(self, "filename")?
                    .ok_or_else(|| self.error(&volume.position, "a gridvolume needs a `filename`"))?;
                let use_grid_bbox = q.boolean(self, "use_grid_bbox")?.unwrap_or(false);
                if let Some(v) = q.string(self, "filter_type")? {
                    if v != "trilinear" {
                        return Err(self.error(
                            &volume.position,
                            format!("`filter_type` `{v}` is not supported; glint reads grids trilinear"),
                        ));
                    }
                }
                let repeat = match q.string(self, "wrap_mode")?.as_deref() {
                    None | Some("clamp") => false,
                    // A repeated density would matter only in the half voxel at its box's
                    // faces; an albedo is read everywhere the medium is.
                    Some("repeat") if name == "albedo" => true,
                    Some(v) => {
                        return Err(self.error(
                            &volume.position,
                            format!("`wrap_mode` `{v}` is not supported here; glint reads grids clamped, and an albedo also repeated"),
                        ))
                    }
                };
                // Data in RGB variants either way; the accelerated lookup is the same lookup.
                q.boolean(self, "raw")?;
                q.boolean(self, "accel")?;
                match (use_grid_bbox, to_world) {
                    (true, None) => Value::Grid(file, None, repeat),
                    (true, Some(_)) => {
                        return Err(self.error(
                            &volume.position,
                            "`use_grid_bbox` with a `to_world` is not supported: give the box by `to_world` alone",
                        ))
                    }
                    (false, to_world) => Value::Grid(file, Some(to_world.unwrap_or(Mat4::IDENTITY)), repeat),
                }
            }
            other => {
                return Err(self.error(
                    &volume.position,
                    format!("<volume type=\"{other}\"> is not supported; glint reads gridvolume and constvolume"),
                ))
            }
        };
        self.unused(&q);
        Ok(Some(value))
    }
}

/// A `to_world` as the native transform list (none: the file's own box).
fn ops(to_world: Option<Mat4>) -> Vec<TransformOp> {
    to_world.map(|m| vec![TransformOp::Matrix(m.transpose().to_cols_array_2d())]).unwrap_or_default()
}
