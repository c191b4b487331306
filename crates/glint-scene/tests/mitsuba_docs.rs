//! Constructs of Mitsuba 3's documentation scenes (mitsuba-data's `docs/scenes`, issue 52),
//! each in a small scene of our own: an environment map placed with a translation, an area
//! emitter declared at the top level and attached by reference, a sampler and a film declared
//! at the top level and referred to by the sensor.

use std::path::{Path, PathBuf};

use glint_core::sampling::SamplerKind;
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
/// shape"). One no shape refers to emits nothing: Mitsuba 3.9 drops it in silence, glint warns.
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
    let alone = scene_file(
        "area-alone",
        &format!("<scene version=\"3.0.0\">\n{SENSOR}\n<emitter type=\"area\" id=\"lamp\"/>\n<emitter type=\"area\"/>\n</scene>\n"),
    );
    let loaded = load_scene(&alone).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(loaded.scene.lights().area_count(), 0);
    let warnings = loaded.warnings.join("\n");
    for line in ["area-alone.xml:3:", "area-alone.xml:4:"] {
        assert!(warnings.contains(line) && warnings.contains("not attached to any shape"), "{warnings}");
    }
}

/// The documentation's sampler scenes declare the sampler at the top level with an id and
/// the sensor refers to it; Mitsuba renders with it, as with a film declared the same way. A
/// top-level sampler no sensor refers to is one Mitsuba creates and never uses: a warning.
#[test]
fn a_top_level_sampler_and_film_serve_the_sensor_that_refers_to_them() {
    let path = scene_file(
        "sampler-by-ref",
        r#"<scene version="3.0.0">
<sampler type="independent" id="my_sampler">
    <integer name="sample_count" value="25"/>
</sampler>
<film type="hdrfilm" id="my_film">
    <integer name="width" value="40"/>
    <integer name="height" value="20"/>
    <rfilter type="box"/>
</film>
<sensor type="perspective">
    <ref id="my_sampler"/>
    <ref id="my_film"/>
</sensor>
<shape type="sphere"/>
</scene>
"#,
    );
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(loaded.render.spp, 25);
    assert_eq!(loaded.render.sampler, SamplerKind::Independent);
    assert_eq!((loaded.scene.camera().width, loaded.scene.camera().height), (40, 20));
    assert_eq!(loaded.render.filter, glint_core::filter::Filter::Box);
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);

    let unused = scene_file(
        "sampler-unused",
        &format!(
            "<scene version=\"3.0.0\">\n<sampler type=\"independent\" id=\"spare\">\n<integer name=\"sample_count\" value=\"7\"/>\n</sampler>\n{SENSOR}\n</scene>\n"
        ),
    );
    let loaded = load_scene(&unused).unwrap_or_else(|e| panic!("{e}"));
    assert_ne!(loaded.render.spp, 7);
    let warnings = loaded.warnings.join("\n");
    assert!(warnings.contains("sampler-unused.xml:2:") && warnings.contains("no sensor refers to it"), "{warnings}");
    // A sensor referring to something that is not a sampler, film or medium.
    let e = error_of(
        "sensor-ref",
        "<scene version=\"3.0.0\">\n<bsdf type=\"diffuse\" id=\"white\"/>\n<sensor type=\"perspective\">\n<ref id=\"white\"/>\n</sensor>\n</scene>\n",
    );
    assert!(e.contains("sensor-ref.xml:4:") && e.contains("<bsdf>"), "{e}");
}

/// Properties every documentation scene has, which Mitsuba reads and glint used to report as
/// unused: a BSDF referred to by name (`<ref name="bsdf" id="…"/>`), a perspective sensor's
/// `focus_distance` (read by Mitsuba's projective cameras, used only by `thinlens`) and a
/// medium's `has_spectral_extinction` (which changes only how Mitsuba samples distances).
#[test]
fn properties_mitsuba_reads_are_not_reported_unused() {
    let path = scene_file(
        "read-properties",
        r#"<scene version="3.0.0">
<sensor type="perspective">
    <float name="focus_distance" value="6.0"/>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
</sensor>
<bsdf type="diffuse" id="white"/>
<medium type="homogeneous" id="fog">
    <boolean name="has_spectral_extinction" value="false"/>
</medium>
<shape type="sphere">
    <ref name="bsdf" id="white"/>
</shape>
<shape type="cube">
    <bsdf type="null"/>
    <ref name="interior" id="fog"/>
</shape>
</scene>
"#,
    );
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
}

/// Mitsuba's `aov` integrator renders its nested integrator's image with extra channels
/// beside it: glint renders that image, and says the named channels are not written. Without
/// a nested integrator there is no image to render.
#[test]
fn an_aov_integrator_renders_its_nested_integrators_image() {
    let path = scene_file(
        "aov",
        &format!(
            "<scene version=\"3.0.0\">\n{SENSOR}\n<integrator type=\"aov\">\n<string name=\"aovs\" value=\"nn:sh_normal, depth.y:depth\"/>\n<integrator type=\"path\" name=\"image\">\n<integer name=\"max_depth\" value=\"3\"/>\n</integrator>\n</integrator>\n</scene>\n"
        ),
    );
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(loaded.render.integrator, glint_core::integrators::IntegratorKind::Path);
    assert_eq!(loaded.render.integrator_settings.max_depth, 2);
    let warnings = loaded.warnings.join("\n");
    assert!(warnings.contains("aov.xml:3:") && warnings.contains("nn:sh_normal, depth.y:depth"), "{warnings}");
    let e = error_of(
        "aov-alone",
        &format!(
            "<scene version=\"3.0.0\">\n{SENSOR}\n<integrator type=\"aov\">\n<string name=\"aovs\" value=\"dd.y:depth\"/>\n</integrator>\n</scene>\n"
        ),
    );
    assert!(e.contains("aov-alone.xml:3:") && e.contains("no nested <integrator>"), "{e}");
}

/// Mitsuba's polarizer and pplastic render as its RGB variants render them, with a warning
/// that polarization is not simulated: the polarizer a clear sheet passing half the light
/// (half its transmittance, textured too), pplastic glint's Fresnel plastic (Beckmann, η 1.49
/// over air by default).
#[test]
fn polarizers_and_pplastic_render_as_without_polarization() {
    let load = |name: &str, bsdf: &str| {
        let text =
            format!("<scene version=\"3.0.0\">\n{SENSOR}\n<shape type=\"sphere\">\n{bsdf}\n</shape>\n</scene>\n");
        let loaded = glint_scene::load_scene(&scene_file(name, &text)).unwrap_or_else(|e| panic!("{e}"));
        let material = format!("{:?}", loaded.scene.materials()[loaded.scene.objects()[0].material as usize]);
        (material, loaded.warnings)
    };
    let (polarizer, warnings) = load(
        "polarizer",
        r#"<bsdf type="polarizer"><float name="theta" value="45"/><rgb name="transmittance" value="0.8"/></bsdf>"#,
    );
    assert!(polarizer.contains("ThinDielectric") && polarizer.contains("Vec3(0.4, 0.4, 0.4)"), "{polarizer}");
    assert!(warnings.iter().any(|w| w.contains("half of the light")), "{warnings:?}");
    let (plastic, warnings) = load(
        "pplastic",
        r#"<bsdf type="pplastic"><rgb name="diffuse_reflectance" value="0.05, 0.03, 0.1"/><float name="alpha" value="0.06"/></bsdf>"#,
    );
    assert!(
        plastic.contains("FresnelPlastic") && plastic.contains("Beckmann") && plastic.contains("alpha_u: 0.06"),
        "{plastic}"
    );
    assert!(plastic.contains(&format!("eta: {}", 1.49f32 / 1.000277)), "{plastic}");
    assert!(warnings.iter().any(|w| w.contains("without polarization")), "{warnings:?}");
}

/// Plugins that exist only for Mitsuba's polarized variants are refused at their line, saying
/// so (glint renders RGB without polarization); so are other plugins glint lacks.
#[test]
fn polarization_plugins_are_refused_as_such() {
    for (name, element) in [
        ("measured-polarized", "<shape type=\"sphere\">\n<bsdf type=\"measured_polarized\"/>\n</shape>"),
        ("stokes", "<integrator type=\"stokes\">\n<integrator type=\"path\"/>\n</integrator>"),
    ] {
        let e = error_of(name, &format!("<scene version=\"3.0.0\">\n{SENSOR}\n{element}\n</scene>\n"));
        let line = if name == "stokes" { 3 } else { 4 };
        assert!(e.contains(&format!("{name}.xml:{line}:")) && e.contains("polariz"), "{e}");
    }
    // Other plugins glint lacks: named at their line, with what is missing.
    let e = error_of(
        "ellipsoids",
        &format!("<scene version=\"3.0.0\">\n{SENSOR}\n<shape type=\"ellipsoids\"/>\n</scene>\n"),
    );
    assert!(e.contains("ellipsoids.xml:3:") && e.contains("no ellipsoid"), "{e}");
    // A curve without its file: named at its line, with what it needs.
    let e =
        error_of("curve", &format!("<scene version=\"3.0.0\">\n{SENSOR}\n<shape type=\"linearcurve\"/>\n</scene>\n"));
    assert!(e.contains("curve.xml:3:") && e.contains("needs a `filename`"), "{e}");
}

/// Mitsuba gives a shape without a BSDF a diffuse 0.5, but an emitting one a black diffuse
/// (checked on Mitsuba 3.9.1): the documentation's sphere lights are such shapes, and glint's
/// grey emitters reflected the sky and the floor (their images were 0.4 % bright on average,
/// far more on the sphere itself).
#[test]
fn an_emitting_shape_without_a_bsdf_reflects_nothing() {
    let path = scene_file(
        "emitter-default-bsdf",
        &format!(
            "<scene version=\"3.0.0\">\n{SENSOR}\n<shape type=\"sphere\">\n<emitter type=\"area\"/>\n</shape>\n<shape type=\"sphere\"/>\n</scene>\n"
        ),
    );
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let mut reflectances: Vec<(bool, glint_core::textures::Texture)> = loaded
        .scene
        .materials()
        .iter()
        .map(|m| (m.emission().0 != Rgb::splat(0.0), m.lambert().expect("a diffuse material").0.clone()))
        .collect();
    reflectances.sort_by_key(|(emits, _)| *emits);
    use glint_core::textures::Texture::Constant;
    assert_eq!(reflectances, [(false, Constant(Rgb::splat(0.5))), (true, Constant(Rgb::splat(0.0)))]);
}

/// An environment map whose file is not on the search path is refused at the emitter's line
/// (it was reported with the scene's name only, not the included file and line that name it).
#[test]
fn a_missing_environment_map_is_refused_at_its_line() {
    let dir = scene_file("envmap-missing-include", "").parent().unwrap().to_path_buf();
    std::fs::create_dir_all(dir.join("include")).unwrap();
    std::fs::write(
        dir.join("include/sky.xml"),
        "<scene version=\"3.0.0\">\n\n<emitter type=\"envmap\">\n<string name=\"filename\" value=\"textures/museum.exr\"/>\n</emitter>\n</scene>\n",
    )
    .unwrap();
    let e = error_of(
        "envmap-missing",
        &format!("<scene version=\"3.0.0\">\n{SENSOR}\n<include filename=\"include/sky.xml\"/>\n</scene>\n")
            .replace("<include", &format!("<path value=\"{}\"/>\n<include", dir.display())),
    );
    assert!(e.contains("sky.xml:3:") && e.contains("textures/museum.exr") && e.contains("not found"), "{e}");
}
