//! The camera and the film: pbrt's perspective, orthographic and realistic cameras (the last
//! as the thin lens of its focal length), the film's resolution and diagonal, and at the end
//! of the file the scene's camera made from them.

use glam::{Mat4, Vec3};

use super::{Result, Translator};
use crate::located::Located;
use crate::native::schema::*;
use crate::pbrt::params::{Failure, Params};
use crate::pbrt::parse::{At, Directive};

pub(super) struct Camera {
    kind: String,
    camera_from_world: Mat4,
    fov: f32,
    lens_radius: f32,
    focal_distance: f32,
    /// A realistic camera's paraxial focal length (mm): its field of view follows from the
    /// film's size, known at the end.
    focal_length_mm: Option<f64>,
    /// The medium the camera is in: the outside of the `MediumInterface` in force.
    medium: Option<String>,
    at: At,
}

impl Translator<'_> {
    pub(super) fn camera(&mut self, d: &Directive) -> Result<()> {
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
                let focal = crate::pbrt::lens::focal_length(&table)
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
            medium: self.state.media.1.clone(),
            at: d.at,
        });
        Ok(())
    }

    /// The film's crop, [x0, y0, x1, y1] in pixels: `cropwindow` (fractions x0 x1 y0 y1 of
    /// the image, each pixel bound rounded up as pbrt rounds it) over `pixelbounds` (pixels
    /// x0 x1 y0 y1), as in pbrt; `None` for the whole image.
    fn crop_of(&mut self, p: &Params) -> Result<Option<[u32; 4]>> {
        let [w, h] = self.resolution;
        let window = p.floats("cropwindow").map_err(|f| self.fail(f))?;
        let bounds = p.ints("pixelbounds").map_err(|f| self.fail(f))?;
        let crop = match (window, bounds) {
            (Some((c, at)), bounds) => {
                if bounds.is_some() {
                    self.warn(at, "both `cropwindow` and `pixelbounds` are given: the crop window is used, as in pbrt");
                }
                let [x0, x1, y0, y1] = <[f32; 4]>::try_from(c.as_slice()).map_err(|_| {
                    self.parser.error(at, format!("`cropwindow` takes four numbers x0 x1 y0 y1, got {}", c.len()))
                })?;
                if !(0.0 <= x0 && x0 < x1 && x1 <= 1.0 && 0.0 <= y0 && y0 < y1 && y1 <= 1.0) {
                    return Err(self.parser.error(at, format!("`cropwindow` x0 x1 y0 y1 must satisfy 0 ≤ x0 < x1 ≤ 1 and 0 ≤ y0 < y1 ≤ 1, got {x0} {x1} {y0} {y1}")));
                }
                // In single precision, as pbrt computes it (0.1 × 1000 is 100 there, not 101).
                let pixel = |f: f32, n: u32| ((n as f32 * f).ceil() as u32).min(n);
                [pixel(x0, w), pixel(y0, h), pixel(x1, w), pixel(y1, h)]
            }
            (None, Some((b, at))) => {
                let [x0, x1, y0, y1] = <[i64; 4]>::try_from(b.as_slice()).map_err(|_| {
                    self.parser.error(at, format!("`pixelbounds` takes four integers x0 x1 y0 y1, got {}", b.len()))
                })?;
                let clamp = |v: i64, n: u32| v.clamp(0, i64::from(n)) as u32;
                let clamped = [clamp(x0, w), clamp(y0, h), clamp(x1, w), clamp(y1, h)];
                if clamped.map(i64::from) != [x0, y0, x1, y1] {
                    self.warn(at, format!("`pixelbounds` reaches past the {w}×{h} image: cut to it"));
                }
                clamped
            }
            (None, None) => return Ok(None),
        };
        if crop[0] >= crop[2] || crop[1] >= crop[3] {
            return Err(self.parser.error(p.at, format!("the film's crop holds no pixel of the {w}×{h} image")));
        }
        Ok((crop != [0, 0, w, h]).then_some(crop))
    }

    pub(super) fn film(&mut self, d: &Directive) -> Result<()> {
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
        self.crop = self.crop_of(&p)?;
        Ok(())
    }

    /// The scene's camera, from the `Camera` directive and the film.
    pub(super) fn finish(&mut self) -> Result<SceneFile> {
        let [w, h] = self.resolution;
        let camera = self.camera.take().unwrap_or(Camera {
            kind: "perspective".into(),
            camera_from_world: Mat4::IDENTITY,
            fov: 90.0,
            lens_radius: 0.0,
            focal_distance: 1e6,
            focal_length_mm: None,
            medium: None,
            at: At { file: 0, offset: 0 },
        });
        let mut camera = camera;
        if let Some(focal) = camera.focal_length_mm {
            // The shorter side of a film of this diagonal and aspect.
            let shorter = self.film_diagonal as f64 * (w.min(h) as f64) / (w as f64).hypot(h as f64);
            let fov = crate::pbrt::lens::field_of_view(focal, camera.focal_distance as f64 * 1e3, shorter)
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
                medium: camera.medium.clone(),
                crop: self.crop,
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
}

pub(super) fn default_camera() -> CameraDesc {
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
        crop: None,
    }
}
