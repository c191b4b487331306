//! The `[camera]` table.

use serde::Deserialize;

use super::Vector;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct CameraDesc {
    pub position: Vector,
    pub look_at: Vector,
    #[serde(default = "default_up")]
    pub up: Vector,
    #[serde(default = "default_fov")]
    pub fov: f32,
    #[serde(default = "default_resolution")]
    pub resolution: [u32; 2],
    /// A thin lens: the aperture's radius and the distance in focus (scene units).
    pub aperture_radius: Option<f32>,
    pub focus_distance: Option<f32>,
    /// An orthographic camera: the view's height in scene units.
    pub orthographic_height: Option<f32>,
    /// The image mirrored left to right (its right is up × forward instead of forward × up):
    /// cameras of left-handed formats (pbrt's) and mirroring transforms.
    #[serde(default)]
    pub mirror: bool,
    /// The medium the camera is in (a name in `[media]`).
    pub medium: Option<String>,
    /// A crop window: render only the film's pixels [x0, x1) × [y0, y1), given as
    /// [x0, y0, x1, y1]; the image is that rectangle, seen as on the whole film.
    pub crop: Option<[u32; 4]>,
}

fn default_up() -> Vector {
    [0.0, 1.0, 0.0]
}
fn default_fov() -> f32 {
    45.0
}
fn default_resolution() -> [u32; 2] {
    [640, 480]
}
