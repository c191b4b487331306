//! Textures: bitmap, checkerboard and mesh_attribute as native textures, and `rawconstant`'s
//! value as it is.

use glam::{Affine2, Vec2};

use super::properties::{parse_number, parse_numbers};
use super::{Result, Translator};
use crate::located::Located;
use crate::mitsuba::xml::Element;
use crate::native::schema::*;

impl Translator<'_> {
    /// A texture element as a native texture; returns its name.
    pub(super) fn texture(&mut self, texture: &Element) -> Result<String> {
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
                    mapping: None,
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
                    mapping: None,
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
}

/// A `rawconstant` texture's `value` (a float, a vector or an RGB triple), as it is: no
/// spectral conversion, no clamping (normal maps, data).
pub(super) fn raw_constant(t: &mut Translator, texture: &Element) -> Result<[f32; 3]> {
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
