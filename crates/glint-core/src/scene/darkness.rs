//! Why an image came out black: what a render says when every pixel is zero, so that a scene
//! with no light, a camera shut inside an object or a light facing the wrong way is named
//! rather than left for the user to guess.
//!
//! The scene is probed from the camera: rays through a grid of pixel centres find what the
//! camera sees, and light samples from those points (every light, by spreading the selection
//! numbers over [0, 1)) tell whether light arrives there and whether something blocks it. The
//! first cause that explains the whole probe is the answer.

use glam::Vec2;

use super::Scene;
use crate::film::Film;
use crate::integrators::IntegratorKind;
use crate::Rgb;

/// Camera rays per side of the probe's grid.
const GRID: u32 = 16;
/// Light samples from each point the camera sees.
const LIGHT_SAMPLES: u32 = 16;

/// Why a scene renders black, found by probing it.
#[derive(Clone, Debug, PartialEq)]
pub enum Darkness {
    /// No light at all: no emitter, no light source, a black environment and no ambient.
    NoLight,
    /// The integrator reads point, spot and directional lights only (the course's ray casting
    /// and Whitted), and the scene has none.
    NoDeltaLight { area_lights: usize, environment: bool },
    /// Every camera ray meets the inside of a surface: the camera is in a closed object.
    CameraInside { object: String },
    /// Light arrives at no point the camera sees, though nothing blocks it: each light turns
    /// its back to them (a one-sided emitter shines on the side its normal points to) or its
    /// cone misses them.
    LightsFaceAway,
    /// Light would arrive, but every shadow ray toward it is blocked.
    LightsBlocked,
    /// Light reaches what the camera sees, and still nothing comes back (black materials, or
    /// paths cut too short).
    NothingReflected,
    /// Every camera ray leaves the scene into a black environment.
    NothingInView,
}

impl std::fmt::Display for Darkness {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Darkness::NoLight => write!(f, "the scene has no light: no emitting surface, no light source, and a black environment"),
            Darkness::NoDeltaLight { area_lights, environment } => {
                let mut lights = Vec::new();
                if *area_lights > 0 {
                    lights.push(format!("{area_lights} emitting surface{}", if *area_lights == 1 { "" } else { "s" }));
                }
                if *environment {
                    lights.push("an environment".to_string());
                }
                write!(
                    f,
                    "this integrator shades with point, spot and directional lights only, and the scene is lit by {}: render it with `--integrator path`",
                    lights.join(" and ")
                )
            }
            Darkness::CameraInside { object } => write!(
                f,
                "the camera is inside a closed object (`{object}`): every ray from it meets the inside of a surface"
            ),
            Darkness::LightsFaceAway => write!(
                f,
                "no light falls on what the camera sees: the lights face away from it (an emitting surface shines only on the side its normal points to, unless two-sided) or their cones miss it"
            ),
            Darkness::LightsBlocked => {
                write!(f, "every light is hidden from what the camera sees: each shadow ray toward a light is blocked")
            }
            Darkness::NothingReflected => write!(
                f,
                "light reaches what the camera sees, but none of it comes back toward the camera (black materials, or a path depth too small)"
            ),
            Darkness::NothingInView => write!(f, "the camera sees nothing: every ray leaves the scene into a black environment"),
        }
    }
}

impl Scene {
    /// Why this scene renders black, for an integrator that reads only point, spot and
    /// directional lights (`delta_lights_only`: ray casting, Whitted) or every light.
    pub fn why_dark(&self, delta_lights_only: bool) -> Darkness {
        let lights = self.lights().all();
        let ambient = self.environment().ambient_light != Rgb::ZERO;
        if lights.is_empty() && !ambient {
            return Darkness::NoLight;
        }
        if delta_lights_only && !ambient && !lights.iter().any(|l| l.is_delta()) {
            let area_lights = lights.iter().filter(|l| matches!(l, crate::lights::Light::Area(_))).count();
            return Darkness::NoDeltaLight { area_lights, environment: self.lights().has_environment() };
        }
        let camera = self.camera();
        // What the camera sees, with the direction back toward the camera.
        let mut seen = Vec::new();
        let (mut rays, mut back_faces, mut inside_of) = (0u32, 0u32, None);
        for j in 0..GRID {
            for i in 0..GRID {
                let x = (i as f32 + 0.5) / GRID as f32 * camera.width as f32;
                let y = (j as f32 + 0.5) / GRID as f32 * camera.height as f32;
                let ray = camera.generate_ray(x, y);
                rays += 1;
                let Some(hit) = self.intersect(&ray) else { continue };
                if ray.direction.dot(hit.geometry.geometric_normal) > 0.0 {
                    back_faces += 1;
                    inside_of.get_or_insert(hit.object);
                }
                seen.push((hit, -ray.direction));
            }
        }
        if back_faces == rays {
            let object = inside_of.map_or(String::new(), |o| self.objects()[o as usize].name.clone());
            return Darkness::CameraInside { object };
        }
        if seen.is_empty() {
            return Darkness::NothingInView;
        }
        let (mut arriving, mut unblocked) = (0u32, 0u32);
        for (hit, toward_camera) in &seen {
            let normal = hit.geometry.geometric_normal;
            let viewed_side = toward_camera.dot(normal).signum();
            for k in 0..LIGHT_SAMPLES {
                let u_select = (k as f32 + 0.5) / LIGHT_SAMPLES as f32;
                let u = Vec2::new((k as f32 * 0.618_034).fract(), (k as f32 * 0.381_966 + 0.25).fract());
                let receiver = Some(hit.geometry.shading_normal);
                let Some(light) = self.lights().sample_li(hit.geometry.point, receiver, u_select, u) else { continue };
                // Light on the far side of the surface from the camera does not reflect to it.
                let same_side = light.direction.dot(normal) * viewed_side > 0.0;
                if light.radiance == Rgb::ZERO || light.pdf <= 0.0 || !same_side {
                    continue;
                }
                arriving += 1;
                if !self.occluded(&hit.spawn_shadow_ray(&light)) {
                    unblocked += 1;
                }
            }
        }
        match (arriving, unblocked) {
            (0, _) => Darkness::LightsFaceAway,
            (_, 0) => Darkness::LightsBlocked,
            _ => Darkness::NothingReflected,
        }
    }
}

/// The warning for a render whose image is black in every pixel, with the cause `why_dark`
/// finds; `None` when some pixel is not black (and for the BVH heat map, which shows no light).
pub fn black_image_warning(scene: &Scene, kind: IntegratorKind, film: &Film) -> Option<String> {
    let (sums, _) = film.accumulators();
    if kind == IntegratorKind::BvhHeat || sums.iter().any(|s| *s != Rgb::ZERO) {
        return None;
    }
    let delta_lights_only = matches!(kind, IntegratorKind::Raycast | IntegratorKind::Whitted);
    Some(format!("the image is black in every pixel: {}", scene.why_dark(delta_lights_only)))
}
