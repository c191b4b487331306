//! No self-intersection acne at any scale: the same Whitted scene built at 1, 1e-3 and 1e5
//! renders the same image (secondary rays are offset by floating-point error bounds, which
//! scale with the scene, never by a fixed epsilon).

use glint_core::integrators::IntegratorKind;
use glint_core::render::{render, RenderSettings};
use glint_scene::native::Format;
use glint_scene::{parse_scene, Source};

/// Every length in the scene multiplied by `s` (light positions too; point lights without
/// falloff, so radiance does not depend on scale).
fn scene_text(s: f64) -> String {
    let v = |x: f64, y: f64, z: f64| format!("[{:e}, {:e}, {:e}]", x * s, y * s, z * s);
    format!(
        r#"
[camera]
position = {cam}
look_at = {target}
fov = 40
resolution = [96, 72]

[render]
integrator = "whitted"
max_depth = 4
transparent_shadows = true

[environment]
background = [0.3, 0.5, 0.9]
ambient = [0.1, 0.1, 0.1]

[textures.board]
type = "checker"
even = [0.9, 0.1, 0.1]
odd = [0.9, 0.9, 0.1]
scale = {checks:e}

[materials.board]
type = "phong"
diffuse = "board"

[materials.mirror]
type = "phong"
diffuse = [0.1, 0.1, 0.1]
specular = [0.5, 0.5, 0.5]
reflection = [0.8, 0.8, 0.8]

[materials.glass]
type = "phong"
diffuse = [0, 0, 0]
transmission = [0.9, 0.9, 0.9]
fresnel = "exact"

[[lights]]
type = "point"
position = {light}

[[shapes]]
type = "polygon"
vertices = [{a}, {b}, {c}, {d}]
uvs = [[0, 0], [1, 0], [1, 1], [0, 1]]
material = "board"

[[shapes]]
type = "sphere"
center = {s1}
radius = {r1:e}
material = "mirror"

[[shapes]]
type = "sphere"
center = {s2}
radius = {r2:e}
material = "glass"

[[shapes]]
type = "box"
min = {bmin}
max = {bmax}
material = "mirror"
transform = [{{ rotate = {{ axis = [0, 1, 0], angle = 25 }} }}]
"#,
        cam = v(0.0, 1.5, -6.0),
        target = v(0.0, 0.8, 0.0),
        checks = 8.0,
        light = v(-3.0, 6.0, -4.0),
        a = v(-5.0, 0.0, -3.0),
        b = v(5.0, 0.0, -3.0),
        c = v(5.0, 0.0, 7.0),
        d = v(-5.0, 0.0, 7.0),
        s1 = v(-1.0, 1.0, 1.0),
        r1 = 1.0 * s,
        s2 = v(1.2, 0.7, -0.5),
        r2 = 0.7 * s,
        bmin = v(2.0, 0.0, 1.5),
        bmax = v(3.0, 1.5, 2.5),
    )
}

fn render_at(scale: f64) -> Vec<glint_core::Rgb> {
    let loaded = parse_scene(&scene_text(scale), Format::Toml, "scaled.toml", &Source::directory(".".into())).unwrap();
    let integrator = IntegratorKind::Whitted.create(&loaded.render.integrator_settings).expect("a camera integrator");
    render(&loaded.scene, integrator.as_ref(), &RenderSettings { spp: 1, seed: 0, ..Default::default() }, &|| {})
        .film
        .to_rgb()
}

#[test]
fn the_same_scene_at_1e_minus_3_and_1e5_renders_the_same() {
    let reference = render_at(1.0);
    for scale in [1e-3, 1e5] {
        let image = render_at(scale);
        // Rounding differs with the scale, so a ray grazing a silhouette or a checker edge may
        // land on the other side; acne would instead darken whole regions.
        let differing = reference.iter().zip(&image).filter(|(a, b)| (**a - **b).abs().max_element() > 1e-3).count();
        assert!(differing * 100 <= reference.len(), "scale {scale}: {differing} of {} pixels differ", reference.len());
        let mean = |img: &[glint_core::Rgb]| img.iter().map(|p| p.x + p.y + p.z).sum::<f32>() / img.len() as f32;
        assert!((mean(&reference) - mean(&image)).abs() < 2e-3 * mean(&reference), "scale {scale}: mean differs");
    }
}
