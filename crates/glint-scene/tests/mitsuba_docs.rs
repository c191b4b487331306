//! Constructs of Mitsuba 3's documentation scenes (mitsuba-data's `docs/scenes`, issue 52),
//! each in a small scene of our own: an environment map placed with a translation, an area
//! emitter declared at the top level and attached by reference, a sampler and a film declared
//! at the top level and referred to by the sensor.

use std::path::{Path, PathBuf};

use glint_core::{Rgb, Vec3};
use glint_scene::load_scene;

/// Writes `text` as a scene in a fresh directory of its own.
fn scene_file(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("glint-mitsuba-docs-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.xml"));
    std::fs::write(&path, text).unwrap();
    path
}

fn error_of(name: &str, text: &str) -> String {
    match load_scene(&scene_file(name, text)) {
        Ok(_) => panic!("{name}: expected an error"),
        Err(e) => e.to_string(),
    }
}

const SENSOR: &str = r#"<sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>"#;

/// An equirectangular EXR: a warm upper half, a dark lower half.
fn write_sky(dir: &Path) {
    let sky = image::Rgb32FImage::from_fn(8, 4, |_, y| {
        if y < 2 {
            image::Rgb([2.0, 1.5, 1.0])
        } else {
            image::Rgb([0.1, 0.1, 0.1])
        }
    });
    image::DynamicImage::ImageRgb32F(sky).save(dir.join("sky.exr")).unwrap();
}

fn envmap_scene(name: &str, transform: &str) -> PathBuf {
    let path = scene_file(
        name,
        &format!(
            "<scene version=\"3.0.0\">\n{SENSOR}\n<emitter type=\"envmap\">\n<string name=\"filename\" value=\"sky.exr\"/>\n<transform name=\"to_world\">{transform}</transform>\n</emitter>\n</scene>\n"
        ),
    );
    write_sky(path.parent().unwrap());
    path
}

/// Mitsuba's envmap maps directions by to_world's linear part alone (`Transform * Vector`),
/// so a translation changes nothing: the documentation's matpreview and shape-scene includes
/// both place theirs with one. A scale is still refused: Mitsuba would look its texture up
/// with an unnormalised direction, which maps the sphere onto the image unevenly and
/// disagrees with its own sampling.
#[test]
fn an_environment_maps_translation_is_ignored_as_mitsuba_ignores_it() {
    // Turned upside down and moved: the warm half is below, as without the move.
    let moved = envmap_scene("envmap-moved", r#"<rotate x="1" angle="180"/><translate x="5" y="-3" z="8.87"/>"#);
    let loaded = load_scene(&moved).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(loaded.scene.environment().radiance(-Vec3::Y), Rgb::new(2.0, 1.5, 1.0));
    assert_eq!(loaded.scene.environment().radiance(Vec3::Y), Rgb::splat(0.1));
    // The same as a 4 × 4 matrix whose last column is the translation (as matpreview.xml has).
    let matrix = envmap_scene("envmap-matrix", r#"<matrix value="1 0 0 2  0 -1 0 0  0 0 -1 8.87  0 0 0 1"/>"#);
    let loaded = load_scene(&matrix).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(loaded.scene.environment().radiance(-Vec3::Y), Rgb::new(2.0, 1.5, 1.0));
    // A scale is refused at the emitter's line.
    let scaled = envmap_scene("envmap-scaled", r#"<scale value="2"/><translate y="1"/>"#);
    let e = load_scene(&scaled).err().unwrap().to_string();
    assert!(e.contains("envmap-scaled.xml:3:") && e.contains("rotation"), "{e}");
}

/// Mitsuba attaches an area emitter declared at the top level with an id to the one shape
/// that refers to it (the documentation's Cornell boxes declare theirs after the shape); a
/// second shape referring to it is an error in Mitsuba ("can be only be attached to a single
/// shape"), and so is one no shape refers to.
#[test]
fn a_shape_takes_a_top_level_area_emitter_by_reference() {
    let path = scene_file(
        "area-by-ref",
        &format!(
            r#"<scene version="3.0.0">
{SENSOR}
<bsdf type="diffuse" id="white"/>
<shape type="rectangle">
    <ref id="white"/>
    <ref id="lamp"/>
</shape>
<shape type="sphere"><ref id="white"/></shape>
<emitter type="area" id="lamp">
    <rgb name="radiance" value="3, 2, 1"/>
</emitter>
</scene>
"#
        ),
    );
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let scene = &loaded.scene;
    assert_eq!(scene.lights().area_count(), 2, "the rectangle's two triangles, not the sphere");
    let emissions: Vec<Rgb> =
        scene.materials().iter().map(|m| m.emission().0).filter(|e| *e != Rgb::splat(0.0)).collect();
    assert_eq!(emissions, [Rgb::new(3.0, 2.0, 1.0)]);

    let twice = error_of(
        "area-twice",
        &format!(
            "<scene version=\"3.0.0\">\n{SENSOR}\n<emitter type=\"area\" id=\"lamp\"/>\n<shape type=\"sphere\"><ref id=\"lamp\"/></shape>\n<shape type=\"rectangle\">\n<ref id=\"lamp\"/>\n</shape>\n</scene>\n"
        ),
    );
    assert!(twice.contains("area-twice.xml:6:") && twice.contains("single shape"), "{twice}");
    let both = error_of(
        "area-both",
        &format!(
            "<scene version=\"3.0.0\">\n{SENSOR}\n<emitter type=\"area\" id=\"lamp\"/>\n<shape type=\"sphere\">\n<emitter type=\"area\"/>\n<ref id=\"lamp\"/>\n</shape>\n</scene>\n"
        ),
    );
    assert!(both.contains("area-both.xml:6:") && both.contains("one emitter"), "{both}");
    let alone = error_of(
        "area-alone",
        &format!("<scene version=\"3.0.0\">\n{SENSOR}\n<emitter type=\"area\" id=\"lamp\"/>\n</scene>\n"),
    );
    assert!(alone.contains("area-alone.xml:3:") && alone.contains("not attached to any shape"), "{alone}");
}
