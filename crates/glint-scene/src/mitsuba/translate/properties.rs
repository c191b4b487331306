//! A plugin's properties: `<float>`, `<integer>`, `<boolean>`, `<string>`, `<rgb>`,
//! `<spectrum>`, `<point>`, `<vector>`, `<transform>` and textures by name, each read as the
//! plugin asks for it and marked as read, so that the ones no mapping reads are reported.

use std::cell::RefCell;
use std::collections::HashSet;

use glam::{Mat4, Vec3};

use super::textures::raw_constant;
use super::{Result, Translator};
use crate::mitsuba::spectrum::{parse_sampled, sampled_to_rgb, SpectrumRole};
use crate::mitsuba::xml::Element;
use crate::native::schema::ColorDesc;

/// Tags that carry a named property rather than an object.
pub(super) const PROPERTY_TAGS: [&str; 10] =
    ["float", "integer", "boolean", "string", "rgb", "spectrum", "point", "vector", "transform", "ref"];

/// The properties of one plugin element, recording which ones were read.
pub(super) struct Properties<'e> {
    pub(super) element: &'e Element,
    pub(super) used: RefCell<HashSet<String>>,
}

impl Translator<'_> {
    pub(super) fn properties<'e>(&self, element: &'e Element) -> Properties<'e> {
        Properties { element, used: RefCell::new(HashSet::new()) }
    }

    /// Warns about the properties of `p` no mapping read.
    pub(super) fn unused(&mut self, p: &Properties) {
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

pub(super) fn parse_number(s: &str) -> std::result::Result<f32, String> {
    s.trim().parse::<f32>().map_err(|_| format!("`{s}` is not a number"))
}

/// Numbers separated by commas and/or spaces.
pub(super) fn parse_numbers(s: &str) -> std::result::Result<Vec<f32>, String> {
    s.split(|c: char| c == ',' || c.is_whitespace()).filter(|p| !p.is_empty()).map(parse_number).collect()
}

impl<'e> Properties<'e> {
    /// The property child named `name`, marked as used.
    pub(super) fn find(&self, name: &str) -> Option<&'e Element> {
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

    pub(super) fn float(&self, t: &Translator, name: &str) -> Result<Option<f32>> {
        let Some(e) = self.find(name) else { return Ok(None) };
        let v = self.value(t, e)?;
        parse_number(v).map(Some).map_err(|m| t.error(&e.position, format!("`{name}`: {m}")))
    }

    pub(super) fn integer(&self, t: &Translator, name: &str) -> Result<Option<i64>> {
        let Some(e) = self.find(name) else { return Ok(None) };
        let v = self.value(t, e)?;
        v.trim()
            .parse::<i64>()
            .map(Some)
            .map_err(|_| t.error(&e.position, format!("`{name}`: `{v}` is not an integer")))
    }

    pub(super) fn boolean(&self, t: &Translator, name: &str) -> Result<Option<bool>> {
        let Some(e) = self.find(name) else { return Ok(None) };
        match self.value(t, e)?.trim() {
            "true" => Ok(Some(true)),
            "false" => Ok(Some(false)),
            v => Err(t.error(&e.position, format!("`{name}`: expected true or false, got `{v}`"))),
        }
    }

    pub(super) fn string(&self, t: &Translator, name: &str) -> Result<Option<String>> {
        let Some(e) = self.find(name) else { return Ok(None) };
        Ok(Some(self.value(t, e)?.to_string()))
    }

    /// A `<string>` or `<float>` (indices of refraction come as either).
    pub(super) fn string_or_number(&self, t: &Translator, name: &str) -> Result<Option<String>> {
        let Some(e) = self.find(name) else { return Ok(None) };
        Ok(Some(self.value(t, e)?.trim().to_string()))
    }

    pub(super) fn point(&self, t: &Translator, name: &str) -> Result<Option<Vec3>> {
        let Some(e) = self.find(name) else { return Ok(None) };
        xyz(t, e, 0.0).map(Some)
    }

    pub(super) fn vector(&self, t: &Translator, name: &str) -> Result<Option<Vec3>> {
        self.point(t, name)
    }

    /// A constant colour: `<rgb>`, a uniform `<spectrum>` or a `<float>`.
    pub(super) fn rgb(&self, t: &Translator, name: &str) -> Result<Option<[f32; 3]>> {
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
    pub(super) fn color(&self, t: &mut Translator<'e>, name: &str) -> Result<Option<ColorDesc>> {
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
    pub(super) fn transform(&self, t: &Translator, name: &str) -> Result<Option<Mat4>> {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn look_at_puts_z_along_the_view() {
        let m = look_at(Vec3::new(1.0, 2.0, 3.0), Vec3::new(1.0, 2.0, 4.0), Vec3::Y).unwrap();
        assert!((m.transform_vector3(Vec3::Z) - Vec3::Z).length() < 1e-6);
        assert!((m.transform_point3(Vec3::ZERO) - Vec3::new(1.0, 2.0, 3.0)).length() < 1e-6);
        // left = up × dir = y × z = x.
        assert!((m.transform_vector3(Vec3::X) - Vec3::X).length() < 1e-6);
    }
}
