//! Lights: pbrt's point, spot, distant and infinite lights (an infinite light's map resampled
//! into glint's environment), and diffuse area lights, which the shapes after them carry.

use glam::{Mat3, Vec3};

use super::{Result, Translator};
use crate::located::Located;
use crate::native::schema::*;
use crate::pbrt::params::Params;
use crate::pbrt::parse::{At, Directive};
use crate::pbrt::spectra;
use crate::source::MadeFile;

#[derive(Clone)]
pub(super) struct AreaLight {
    pub(super) radiance: [f32; 3],
    pub(super) two_sided: bool,
}

impl Translator<'_> {
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

    pub(super) fn light(&mut self, d: &Directive) -> Result<()> {
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
        let (width, height, pixels) = crate::pbrt::envmap::resample(w, h, &pixels, light_to_world)
            .map_err(|m| self.parser.error(at, format!("`{file}`: {m}")))?;
        // Handed over decoded (it was encoded as EXR and decoded again).
        let name = format!("pbrt-environment:{file}");
        self.made.push((name.clone(), MadeFile::Image { width, height, pixels }));
        self.scene.environment.map = Some(name);
        self.scene.environment.map_scale = Some(scale);
        Ok(())
    }

    pub(super) fn area_light(&mut self, d: &Directive) -> Result<()> {
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
}
