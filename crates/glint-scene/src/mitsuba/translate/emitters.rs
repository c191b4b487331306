//! Emitters: a shape's area emitter, point, spot, projector and directional lights, and the
//! constant and envmap environments.

use glam::{Mat3, Mat4, Vec3};

use super::properties::Properties;
use super::{Result, Translator};
use crate::located::Located;
use crate::mitsuba::xml::Element;
use crate::native::schema::*;

impl<'a> Translator<'a> {
    /// A shape's `area` emitter: its radiance, a colour or a texture over the shape's uv.
    pub(super) fn area_emitter(&mut self, emitter: &'a Element) -> Result<ColorDesc> {
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

    pub(super) fn emitter(&mut self, emitter: &'a Element) -> Result<()> {
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
}
