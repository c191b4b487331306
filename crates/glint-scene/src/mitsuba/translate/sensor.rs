//! The sensor (perspective, thinlens, orthographic) and what it holds: its film and the
//! film's reconstruction filter, its sampler, and its medium (`media.rs`).

use glam::{Mat4, Vec3};

use super::{Result, Translator};
use crate::located::Located;
use crate::mitsuba::xml::Element;
use crate::native::schema::CameraDesc;

impl<'a> Translator<'a> {
    pub(super) fn sensor(&mut self, sensor: &'a Element) -> Result<()> {
        let kind = sensor.attribute("type").unwrap_or("");
        if !matches!(kind, "perspective" | "thinlens" | "orthographic") {
            return Err(self.error(
                &sensor.position,
                format!(
                    "<sensor type=\"{kind}\"> is not supported; glint reads perspective, thinlens and orthographic"
                ),
            ));
        }
        let p = self.properties(sensor);
        // Film first: the field of view's axis needs the aspect ratio.
        let (mut width, mut height) = (768u32, 576u32);
        let mut crop = None;
        let mut medium = None;
        for child in &sensor.children {
            // A sampler, film or medium declared at the top level, by reference.
            let target = match child.tag.as_str() {
                "ref" => {
                    let target = self.resolve(child)?;
                    if !matches!(target.tag.as_str(), "film" | "sampler" | "medium") {
                        return Err(self.error(
                            &child.position,
                            format!(
                                "a sensor can refer to a <sampler>, a <film> or a <medium>, not to <{}> `{}`",
                                target.tag,
                                child.attribute("id").unwrap_or("")
                            ),
                        ));
                    }
                    if let Some(id) = child.attribute("id") {
                        self.referenced.insert(id.to_string());
                    }
                    target
                }
                _ => child,
            };
            match target.tag.as_str() {
                "film" => {
                    let (w, h, film_crop) = self.film(target)?;
                    width = w;
                    height = h;
                    crop = film_crop;
                }
                "sampler" => self.sampler(target)?,
                // The sensor's medium, nested or by reference.
                "medium" => {
                    medium = Some(self.medium(target)?);
                    p.used.borrow_mut().insert("medium".into());
                }
                _ => {}
            }
        }
        let aspect = width as f32 / height as f32;
        let mut focal_diagonal = false;
        let fov = match p.float(self, "fov")? {
            Some(f) => f,
            None if kind == "orthographic" => 45.0, // unused
            None => {
                let focal = p.string(self, "focal_length")?.unwrap_or_else(|| "50mm".into());
                let mm: f32 = focal.trim_end_matches("mm").trim().parse().map_err(|_| {
                    self.error(&sensor.position, format!("`focal_length` must be like \"50mm\", got `{focal}`"))
                })?;
                // As Mitsuba: the field of view of a 35 mm film's diagonal (36 × 24 mm),
                // taken along the image's diagonal.
                let diagonal = 2.0 * ((36.0f32.hypot(24.0)) / (2.0 * mm)).atan().to_degrees();
                focal_diagonal = true;
                diagonal
            }
        };
        if !(fov > 0.0 && fov < 180.0) {
            return Err(self.error(&sensor.position, format!("`fov` must be between 0 and 180 degrees, got {fov}")));
        }
        let axis = if focal_diagonal {
            "diagonal".to_string()
        } else {
            p.string(self, "fov_axis")?.unwrap_or_else(|| "x".into())
        };
        let vertical = vertical_fov(fov, aspect, &axis).ok_or_else(|| {
            self.error(&sensor.position, format!("`fov_axis` must be x, y, diagonal, smaller or larger, got `{axis}`"))
        })?;
        for clip in ["near_clip", "far_clip"] {
            p.float(self, clip)?; // glint's rays are not clipped; the defaults rarely matter
        }
        if kind != "thinlens" {
            p.float(self, "focus_distance")?; // Mitsuba's projective cameras read it; a pinhole has no use for it
        }
        let (aperture_radius, focus_distance) = if kind == "thinlens" {
            let radius = p.float(self, "aperture_radius")?.unwrap_or(0.03);
            let focus = p
                .float(self, "focus_distance")?
                .ok_or_else(|| self.error(&sensor.position, "a thinlens sensor needs a `focus_distance`"))?;
            (Some(radius), Some(focus))
        } else {
            (None, None)
        };
        let matrix = p.transform(self, "to_world")?.unwrap_or(Mat4::IDENTITY);
        // Mitsuba's orthographic view spans x ∈ [−1, 1] across the width and
        // y ∈ [−1/aspect, 1/aspect] under to_world: its height is twice to_world's scale along
        // x over the aspect ratio.
        let orthographic_height =
            (kind == "orthographic").then(|| 2.0 * matrix.transform_vector3(Vec3::X).length() / aspect);
        let position = matrix.transform_point3(Vec3::ZERO);
        let forward = matrix.transform_vector3(Vec3::Z);
        let up = matrix.transform_vector3(Vec3::Y);
        // Mitsuba's image right is the camera's −x; glint's is forward × up, unless mirrored
        // (a to_world with a negative scale).
        let left = matrix.transform_vector3(Vec3::X);
        let mirror = (-left).dot(forward.cross(up)) < 0.0;
        let look_at = position + forward.normalize_or_zero();
        self.scene.camera = Located {
            value: CameraDesc {
                position: position.to_array(),
                look_at: look_at.to_array(),
                up: up.to_array(),
                fov: vertical,
                resolution: [width, height],
                aperture_radius,
                focus_distance,
                orthographic_height,
                mirror,
                medium,
                crop,
            },
            span: sensor.position.span.clone(),
        };
        self.unused(&p);
        Ok(())
    }

    /// The film's resolution and its crop window ([x0, y0, x1, y1], if it has one).
    fn film(&mut self, film: &Element) -> Result<(u32, u32, Option<[u32; 4]>)> {
        let kind = film.attribute("type").unwrap_or("");
        if kind != "hdrfilm" && kind != "specfilm" {
            return Err(self.error(&film.position, format!("<film type=\"{kind}\"> is not supported; use hdrfilm")));
        }
        let p = self.properties(film);
        let width = p.integer(self, "width")?.unwrap_or(768);
        let height = p.integer(self, "height")?.unwrap_or(576);
        for ignored in ["pixel_format", "component_format", "file_format", "sample_border", "banner"] {
            p.string(self, ignored)?;
        }
        // Mitsuba's default reconstruction filter: its gaussian (σ ½ out to 4σ), glint's
        // `gaussian-wide` (glint's own `gaussian` is pbrt-v4's, cut off at 3σ).
        let mut filter = "gaussian-wide".to_string();
        for child in &film.children {
            let child = match child.tag.as_str() {
                "ref" => {
                    let target = self.resolve(child)?;
                    if target.tag != "rfilter" {
                        return Err(self.error(
                            &child.position,
                            format!("a film can refer to an <rfilter>, not to <{}>", target.tag),
                        ));
                    }
                    if let Some(id) = child.attribute("id") {
                        self.referenced.insert(id.to_string());
                    }
                    target
                }
                _ => child,
            };
            if child.tag == "rfilter" {
                let t = child.attribute("type").unwrap_or("");
                filter = match t {
                    "box" | "tent" | "mitchell" => t.to_string(),
                    "gaussian" => "gaussian-wide".into(),
                    _ => {
                        self.warn(&child.position, format!("<rfilter type=\"{t}\"> is not available: using gaussian"));
                        "gaussian-wide".into()
                    }
                };
                let fp = self.properties(child);
                if t == "gaussian" {
                    if let Some(s) = fp.float(self, "stddev")? {
                        if (s - 0.5).abs() > 1e-6 {
                            self.warn(&child.position, "gaussian `stddev` other than 0.5: glint's is fixed at 0.5");
                        }
                    }
                }
                self.unused(&fp);
            }
        }
        self.scene.render.filter = filter;
        // Mitsuba's crop: the offset 0 and the size the film's unless given.
        let offset_x = p.integer(self, "crop_offset_x")?;
        let offset_y = p.integer(self, "crop_offset_y")?;
        let crop_width = p.integer(self, "crop_width")?;
        let crop_height = p.integer(self, "crop_height")?;
        self.unused(&p);
        let check = |v: i64, name: &str, least: u32| -> Result<u32> {
            u32::try_from(v).ok().filter(|v| (least..=32768).contains(v)).ok_or_else(|| {
                self.error(&film.position, format!("film `{name}` must be between {least} and 32768, got {v}"))
            })
        };
        let (width, height) = (check(width, "width", 1)?, check(height, "height", 1)?);
        let crop = if [offset_x, offset_y, crop_width, crop_height].iter().any(Option::is_some) {
            let (x0, y0) =
                (check(offset_x.unwrap_or(0), "crop_offset_x", 0)?, check(offset_y.unwrap_or(0), "crop_offset_y", 0)?);
            let w = check(crop_width.unwrap_or(i64::from(width)), "crop_width", 1)?;
            let h = check(crop_height.unwrap_or(i64::from(height)), "crop_height", 1)?;
            if x0 + w > width || y0 + h > height {
                return Err(self.error(
                    &film.position,
                    format!("the film's crop ({w}×{h} at {x0}, {y0}) reaches past its {width}×{height} pixels"),
                ));
            }
            Some([x0, y0, x0 + w, y0 + h])
        } else {
            None
        };
        Ok((width, height, crop))
    }

    fn sampler(&mut self, sampler: &Element) -> Result<()> {
        let kind = sampler.attribute("type").unwrap_or("");
        self.scene.render.sampler = match kind {
            "independent" => "independent",
            "stratified" | "multijitter" | "orthogonal" => "stratified",
            "ldsampler" => "sobol",
            _ => return Err(self.error(&sampler.position, format!("<sampler type=\"{kind}\"> is not known"))),
        }
        .into();
        let p = self.properties(sampler);
        if let Some(n) = p.integer(self, "sample_count")? {
            self.scene.render.spp = u32::try_from(n)
                .ok()
                .filter(|&n| n >= 1)
                .ok_or_else(|| self.error(&sampler.position, format!("`sample_count` must be ≥ 1, got {n}")))?;
        }
        if let Some(seed) = p.integer(self, "seed")? {
            self.scene.render.seed = seed as u64;
        }
        p.boolean(self, "jitter")?;
        p.integer(self, "dimension")?;
        self.unused(&p);
        Ok(())
    }
}

/// The vertical field of view for `fov` degrees along `axis` of an image of this aspect ratio.
fn vertical_fov(fov: f32, aspect: f32, axis: &str) -> Option<f32> {
    let t = (0.5 * fov.to_radians()).tan();
    let vertical_tan = match axis {
        "y" => t,
        "x" => t / aspect,
        "diagonal" => t / (1.0 + aspect * aspect).sqrt(),
        "smaller" => {
            if aspect >= 1.0 {
                t
            } else {
                t / aspect
            }
        }
        "larger" => {
            if aspect >= 1.0 {
                t / aspect
            } else {
                t
            }
        }
        _ => return None,
    };
    Some(2.0 * vertical_tan.atan().to_degrees())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn field_of_view_axes() {
        let close = |a: f32, b: f32| (a - b).abs() < 1e-3;
        assert!(close(vertical_fov(40.0, 2.0, "y").unwrap(), 40.0));
        // Horizontal 90° on a 2:1 image: tan(v/2) = 1/2.
        assert!(close(vertical_fov(90.0, 2.0, "x").unwrap(), 2.0 * 0.5f32.atan().to_degrees()));
        assert!(close(vertical_fov(90.0, 2.0, "larger").unwrap(), vertical_fov(90.0, 2.0, "x").unwrap()));
        assert!(close(vertical_fov(90.0, 2.0, "smaller").unwrap(), 90.0));
        assert!(close(vertical_fov(90.0, 1.0, "diagonal").unwrap(), 2.0 * (1.0 / 2f32.sqrt()).atan().to_degrees()));
        assert!(vertical_fov(40.0, 1.0, "z").is_none());
    }
}
