//! Lights: pbrt's point, spot, distant and infinite lights, and diffuse area lights, which the
//! shapes after them carry. glint's environment is one map or one constant; pbrt's infinite
//! lights, as many as a scene has, add up into it: constants into the background, maps
//! (each resampled with its transform and scaled) and constants into one map, which glint
//! importance-samples by the sum's brightness.

use glam::{Mat3, Vec3};

use super::{Result, Translator};
use crate::located::Located;
use crate::native::schema::*;
use crate::pbrt::params::Params;
use crate::pbrt::parse::{At, Directive};
use crate::pbrt::spectra;
use crate::source::MadeFile;
use glint_core::Rgb;

/// An infinite light's map as read, kept until the scene's infinite lights are all known.
pub(super) struct InfiniteMap {
    file: String,
    at: At,
    width: u32,
    height: u32,
    /// Row 0 at the top, in pbrt's layout (equal-area square, or latitude–longitude).
    pixels: Vec<Rgb>,
    light_to_world: Mat3,
    scale: f32,
}

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
                if power > 0.0 {
                    return Err(self.parser.error(self.param_at(&p, "power"), "an infinite light takes `illuminance` or `scale`, not `power`"));
                }
                // pbrt-v4: the illuminance the light gives a surface facing its +z.
                let illuminance = p.float("illuminance", -1.0).map_err(|f| self.fail(f))?;
                match p.string("filename").map_err(|f| self.fail(f))? {
                    Some(file) => {
                        if p.list.iter().any(|x| x.name == "L") {
                            return Err(self.parser.error(self.param_at(&p, "L"), "an infinite light takes `L` or `filename`, not both"));
                        }
                        let scale = p.float("scale", 1.0).map_err(|f| self.fail(f))?;
                        self.infinite_map(d.at, &file, scale, illuminance, Mat3::from_mat4(ctm))?;
                    }
                    None => {
                        let mut colour = self.light_colour(&p, "L")?;
                        if illuminance > 0.0 {
                            colour = colour.map(|c| c * illuminance / std::f32::consts::PI);
                        }
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

    /// Reads an infinite light's map, kept for `environment` to add up with the others.
    fn infinite_map(
        &mut self,
        at: At,
        file: &str,
        mut scale: f32,
        illuminance: f32,
        light_to_world: Mat3,
    ) -> Result<()> {
        let bytes = self.source.read(file).map_err(|m| self.parser.error(at, m))?;
        let (width, height, pixels) =
            crate::image::decode(file, &bytes, false).map_err(|m| self.parser.error(at, format!("`{file}`: {m}")))?;
        crate::pbrt::envmap::check_layout(width, height)
            .map_err(|m| self.parser.error(at, format!("`{file}`: {m}")))?;
        if illuminance > 0.0 {
            let given = crate::pbrt::envmap::illuminance(width, height, &pixels)
                .map_err(|m| self.parser.error(at, format!("`{file}`: {m}")))?;
            if given.is_nan() || given <= 0.0 {
                return Err(self.parser.error(
                    at,
                    format!("`{file}`: the map is black above its horizon, so no scale gives it an illuminance"),
                ));
            }
            scale *= illuminance / given;
        }
        let file = file.to_string();
        self.infinite_maps.push(InfiniteMap { file, at, width, height, pixels, light_to_world, scale });
        Ok(())
    }

    /// glint's environment from the scene's infinite lights: a lone map as it is (with its
    /// scale); several maps, or maps and constants, summed into one map on the finest of
    /// their grids; constants alone stay the background they already add up to.
    pub(super) fn environment(&mut self) -> Result<()> {
        let maps = std::mem::take(&mut self.infinite_maps);
        let constant = Rgb::from(self.scene.environment.background);
        let resample = |m: &InfiniteMap, size: Option<(u32, u32)>| {
            crate::pbrt::envmap::resample(m.width, m.height, &m.pixels, m.light_to_world, size)
                .map_err(|e| self.parser.error(m.at, format!("`{}`: {e}", m.file)))
        };
        let (name, map_scale, (width, height, pixels)) = match maps.as_slice() {
            [] => return Ok(()),
            [only] if constant == Rgb::ZERO => {
                (format!("pbrt-environment:{}", only.file), only.scale, resample(only, None)?)
            }
            _ => {
                let size =
                    maps.iter().map(|m| crate::pbrt::envmap::resampled_size(m.width, m.height)).max().unwrap_or((2, 2));
                let mut sum = vec![constant; (size.0 * size.1) as usize];
                for m in &maps {
                    let (_, _, pixels) = resample(m, Some(size))?;
                    sum.iter_mut().zip(pixels).for_each(|(s, p)| *s += p * m.scale);
                }
                self.scene.environment.background = [0.0; 3];
                ("pbrt-environment:sum".to_string(), 1.0, (size.0, size.1, sum))
            }
        };
        // Handed over decoded.
        self.made.push((name.clone(), MadeFile::Image { width, height, pixels }));
        self.scene.environment.map = Some(name);
        self.scene.environment.map_scale = Some(map_scale);
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
