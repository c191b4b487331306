//! The pbrt-v4 reader on scene files written for it: every supported directive and its
//! mapping onto glint, orientation, an analytic render, and the errors.

mod common;

use std::path::{Path, PathBuf};

use glint_core::camera::Lens;
use glint_core::filter::Filter;
use glint_core::geometry::Ray;
use glint_core::integrators::IntegratorKind;
use glint_core::lights::Light;
use glint_core::materials::Material;
use glint_core::render::{render, RenderSettings};
use glint_core::sampling::SamplerKind;
use glint_core::shapes::Shape;
use glint_core::{Rgb, Vec3};
use glint_scene::load_scene;

/// A fresh directory holding `files` (name, bytes); returns the path of the first.
fn scene_dir(test: &str, files: &[(&str, &[u8])]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("glint-pbrt-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (name, bytes) in files {
        std::fs::write(dir.join(name), bytes).unwrap();
    }
    dir.join(files[0].0)
}

const PLY: &str = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";

const EVERY_DIRECTIVE: &str = r#"# Every directive glint reads.
Scale -1 1 1
LookAt 0 2 -8  0 2 0  0 1 0
Camera "perspective" "float fov" [ 30 ] "float lensradius" 0.1 "float focaldistance" 8
Film "rgb" "integer xresolution" 32 "integer yresolution" 64 "string filename" "out.exr"
Sampler "zsobol" "integer pixelsamples" 8 "integer seed" 3
PixelFilter "triangle"
Integrator "volpath" "integer maxdepth" [ 7 ]
ColorSpace "srgb"
WorldBegin
LightSource "point" "rgb I" [ 1 2 3 ] "point3 from" [ 0 5 0 ]
LightSource "spot" "blackbody I" 3000 "point3 from" [ 0 4 0 ] "point3 to" [ 0 0 0 ] "float coneangle" 40 "float conedeltaangle" 10
LightSource "distant" "rgb L" [ 0.5 0.5 0.5 ] "point3 from" [ 0 1 0 ] "point3 to" [ 0 0 0 ]
LightSource "infinite" "rgb L" [ 0.1 0.2 0.3 ]
Texture "checks" "spectrum" "checkerboard" "rgb tex1" [ 1 0 0 ] "rgb tex2" [ 0 0 1 ] "float uscale" 4 "float vscale" 4
Texture "half" "float" "constant" "float value" 0.5
Texture "grid" "spectrum" "imagemap" "string filename" "grid.png" "string wrap" "clamp"
Texture "dim-grid" "spectrum" "scale" "texture tex" "grid" "float scale" 0.25
MakeNamedMaterial "gold" "string type" "conductor" "spectrum eta" "metal-Au-eta" "spectrum k" "metal-Au-k" "float roughness" 0.04
MakeNamedMaterial "glass" "string type" "dielectric" "spectrum eta" "glass-BK7"
MakeNamedMaterial "checked" "string type" "diffuse" "texture reflectance" "checks"
MakeNamedMaterial "either" "string type" "mix" "string materials" [ "gold" "checked" ] "texture amount" "half"
Include "include.pbrt"
AttributeBegin
  Translate 0 1 0
  CoordinateSystem "lifted"
  NamedMaterial "gold"
  Shape "sphere" "float radius" 0.5
AttributeEnd
AttributeBegin
  CoordSysTransform "lifted"
  Translate 2 0 0
  Rotate 90 1 0 0
  Material "diffuse" "texture reflectance" "dim-grid"
  Shape "disk" "float radius" 1
  Shape "cylinder" "float radius" 0.25 "float zmin" 0 "float zmax" 1
AttributeEnd
AttributeBegin
  NamedMaterial "glass"
  ConcatTransform [ 1 0 0 0  0 1 0 0  0 0 1 0  -2 0 0 1 ]
  Shape "plymesh" "string filename" "quad.ply"
  Shape "sphere" "float radius" 1 "float zmax" 0.5
AttributeEnd
ObjectBegin "pair"
  NamedMaterial "either"
  Shape "trianglemesh" "integer indices" [ 0 1 2 ] "point3 P" [ 0 0 0  1 0 0  0 1 0 ]
  Shape "bilinearmesh" "point3 P" [ 0 0 1  1 0 1  0 1 1  1 1 2 ] "integer indices" [ 0 1 2 3 ]
ObjectEnd
AttributeBegin
  Translate 0 0 5
  ObjectInstance "pair"
  Translate 0 0 5
  ObjectInstance "pair"
AttributeEnd
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 4 4 4 ] "bool twosided" true
  Transform [ 1 0 0 0  0 1 0 0  0 0 1 0  0 6 0 1 ]
  Shape "loopsubdiv" "integer levels" 1 "integer indices" [ 0 1 2  0 2 3  0 3 1  1 3 2 ] "point3 P" [ 1 1 1  1 -1 -1  -1 1 -1  -1 -1 1 ]
AttributeEnd
"#;

const INCLUDE: &str = "AttributeBegin\n  Translate 0 -1 0\n  Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point3 P\" [ -10 0 -10  10 0 -10  10 0 10  -10 0 10 ] \"point2 uv\" [ 0 0 1 0 1 1 0 1 ]\nAttributeEnd\n";

fn grid_png() -> Vec<u8> {
    let image =
        image::RgbImage::from_fn(2, 2, |x, y| image::Rgb(if (x + y) % 2 == 0 { [255, 255, 255] } else { [0, 0, 0] }));
    let mut bytes = Vec::new();
    image.write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Png).unwrap();
    bytes
}

#[test]
fn every_directive_maps_onto_glint() {
    let png = grid_png();
    let path = scene_dir(
        "every",
        &[
            ("every.pbrt", EVERY_DIRECTIVE.as_bytes()),
            ("include.pbrt", INCLUDE.as_bytes()),
            ("quad.ply", PLY.as_bytes()),
            ("grid.png", &png),
        ],
    );
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let scene = &loaded.scene;
    let warnings = loaded.warnings.join("\n");
    assert!(warnings.is_empty(), "{warnings}");
    // Film, sampler, filter, integrator: pbrt's maxdepth 7 is 8 path segments.
    assert_eq!((scene.camera().width, scene.camera().height), (32, 64));
    assert_eq!((loaded.render.spp, loaded.render.seed), (8, 3));
    assert_eq!(loaded.render.sampler, SamplerKind::Sobol);
    assert_eq!(loaded.render.filter, Filter::Tent);
    assert_eq!(loaded.render.integrator, IntegratorKind::Path);
    assert_eq!(loaded.render.integrator_settings.max_depth, 8);
    // On a portrait film pbrt's fov spans the width: 2·atan(tan 15° · 64/32) vertically.
    let vertical = 2.0 * (15f32.to_radians().tan() * 2.0).atan().to_degrees();
    assert!((scene.camera().fov_degrees - vertical).abs() < 1e-3, "{}", scene.camera().fov_degrees);
    assert_eq!(scene.camera().position, Vec3::new(0.0, 2.0, -8.0));
    assert!(
        matches!(scene.camera().lens, Lens::Thin { radius, focus_distance } if radius == 0.1 && focus_distance == 8.0)
    );
    // `Scale -1 1 1` then LookAt: pbrt's image right is world +x… mirrored back to −x, as
    // glint's own camera (forward × up = z × y = −x): a point at −x projects right of centre.
    let ray = scene.camera().generate_ray(31.0, 32.0);
    assert!(ray.direction.x < 0.0, "{:?}", ray.direction);

    // Lights: point, spot (a blackbody: luminance 1, reddish), distant; the infinite light
    // is the background; the loop-subdivided blob emits.
    let kinds: Vec<&str> = scene.listed_lights().map(Light::kind).collect();
    assert_eq!(kinds, ["point", "spot", "directional"]);
    assert_eq!(scene.environment().background, Rgb::new(0.1, 0.2, 0.3));
    assert!(scene.lights().area_count() > 0);
    match &scene.listed_lights().collect::<Vec<_>>()[1] {
        Light::Spot(spot) => {
            assert!((spot.direction - -Vec3::Y).length() < 1e-6);
            assert!((spot.cos_cone - 40f32.to_radians().cos()).abs() < 1e-6);
            assert!((spot.cos_full - 30f32.to_radians().cos()).abs() < 1e-6);
            let i: Rgb = spot.light.intensity;
            assert!(i.x > i.y && i.y > i.z, "3000 K is red: {i}");
            assert!((0.2126 * i.x + 0.7152 * i.y + 0.0722 * i.z - 1.0).abs() < 0.01, "{i}");
        }
        other => panic!("{other:?}"),
    }
    match &scene.listed_lights().collect::<Vec<_>>()[2] {
        Light::Directional(sun) => assert!((sun.direction - -Vec3::Y).length() < 1e-6, "travels from `from` to `to`"),
        other => panic!("{other:?}"),
    }

    // Geometry, by rays: the gold ball at (0, 1, 0) (radius ½), the floor from the include
    // at y = −1, the quad of the PLY file moved to x = −2.
    let hit = |origin: Vec3, direction: Vec3| scene.intersect(&Ray::new(origin, direction));
    let ball = hit(Vec3::new(0.0, 1.0, -5.0), Vec3::Z).expect("the ball");
    assert!((ball.t - 4.5).abs() < 1e-4, "{}", ball.t);
    let floor = hit(Vec3::new(3.0, 5.0, -3.0), -Vec3::Y).expect("the floor");
    assert!((floor.t - 6.0).abs() < 1e-4);
    let quad = hit(Vec3::new(-1.1, 0.9, -1.0), Vec3::Z).expect("the ply quad");
    assert!((quad.t - 1.0).abs() < 1e-4);
    // The disk at (2, 1, 0) turned by 90° about x: it lies in the plane y = 1.
    let disk = hit(Vec3::new(2.5, 3.0, 0.0), -Vec3::Y).expect("the disk");
    assert!((disk.t - 2.0).abs() < 1e-4, "{}", disk.t);
    // Two instances of the object's triangle, at z = 5 and z = 10.
    for z in [5.0, 10.0] {
        let t = hit(Vec3::new(0.2, 0.2, z - 1.0), Vec3::Z).expect("an instance").t;
        assert!((t - 1.0).abs() < 1e-4, "{t}");
    }

    // Materials: gold (GGX, α = √0.04), glass (BK7's n_d), the textured diffuse, the mix.
    let material = |name: &str| {
        let i = scene
            .material_names()
            .iter()
            .position(|n| n == name)
            .unwrap_or_else(|| panic!("{name}: {:?}", scene.material_names()));
        &scene.materials()[i]
    };
    let (eta, k) = glint_core::materials::named_metal("Au").unwrap();
    match material("named:gold") {
        Material::TwoSided(two) => match &two.front {
            Material::RoughConductor(gold) => {
                assert_eq!((gold.conductor.eta, gold.conductor.k), (eta, k));
                assert_eq!(gold.alpha_u, 0.2.into());
            }
            other => panic!("{other:?}"),
        },
        Material::RoughConductor(gold) => {
            assert_eq!((gold.conductor.eta, gold.conductor.k), (eta, k));
            assert_eq!(gold.alpha_u, 0.2.into());
        }
        other => panic!("{other:?}"),
    }
    match material("named:glass") {
        Material::Dielectric(glass) => assert!((glass.eta - 1.5168).abs() < 1e-6),
        other => panic!("{other:?}"),
    }
    assert!(matches!(material("named:either"), Material::Blend(_)), "{:?}", material("named:either"));
}

/// A diffuse floor under pbrt's uniform infinite light reflects albedo × L (the upper
/// hemisphere is all sky), whatever the camera sees of it.
#[test]
fn a_diffuse_floor_under_a_uniform_sky_reflects_albedo_times_sky() {
    let text = r#"LookAt 0 1 0  0 0 0  0 0 1
Camera "perspective" "float fov" 40
Film "rgb" "integer xresolution" 16 "integer yresolution" 16
Integrator "path" "integer maxdepth" 5
WorldBegin
LightSource "infinite" "rgb L" [ 2 1 0.5 ]
Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.8 ]
Shape "bilinearmesh" "point3 P" [ -100 0 -100  100 0 -100  -100 0 100  100 0 100 ]
"#;
    let path = scene_dir("furnace", &[("furnace.pbrt", text.as_bytes())]);
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let integrator = loaded.render.integrator.create(&loaded.render.integrator_settings).unwrap();
    let settings = RenderSettings { spp: 64, seed: 1, filter: loaded.render.filter, sampler: loaded.render.sampler };
    let image = render(&loaded.scene, integrator.as_ref(), &settings, &|| {}).film.to_rgb();
    let mean = image.iter().sum::<Rgb>() / image.len() as f32;
    let expected = Rgb::new(1.0, 0.5, 0.4);
    assert!(((mean - expected) / expected).abs().max_element() < 0.01, "{mean} vs {expected}");
}

/// A one-sided area light emits on the side its winding (or its normals) faces; pbrt's
/// ReverseOrientation and a mirroring transform each turn it over.
#[test]
fn a_one_sided_light_emits_where_pbrt_says() {
    let seen = |prelude: &str, extra: &str| {
        let text = format!(
            r#"LookAt 0 0 -5  0 0 0  0 1 0
Camera "perspective" "float fov" 10
Film "rgb" "integer xresolution" 4 "integer yresolution" 4
Integrator "path" "integer maxdepth" 1
WorldBegin
AttributeBegin
{prelude}
AreaLightSource "diffuse" "rgb L" [ 1 1 1 ]
Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ] "point3 P" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ] {extra}
AttributeEnd
"#
        );
        let name = format!("light{}", prelude.len() + 7 * extra.len());
        let path = scene_dir(&name, &[("light.pbrt", text.as_bytes())]);
        let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
        let integrator = loaded.render.integrator.create(&loaded.render.integrator_settings).unwrap();
        let settings = RenderSettings { spp: 1, seed: 1, filter: Filter::Box, sampler: loaded.render.sampler };
        let image = render(&loaded.scene, integrator.as_ref(), &settings, &|| {}).film.to_rgb();
        image.iter().sum::<Rgb>().x / image.len() as f32
    };
    // Wound counter-clockwise seen from −z... from the camera at z = −5 the winding runs
    // clockwise: its normal (0, 0, 1) faces away, and the light is dark.
    assert_eq!(seen("", ""), 0.0);
    assert_eq!(seen("ReverseOrientation", ""), 1.0);
    assert_eq!(seen("Scale 1 1 -1", ""), 1.0, "a mirroring transform turns the face toward the camera");
    assert_eq!(seen("ReverseOrientation\nScale 1 1 -1", ""), 0.0);
    // Given normals decide the side (pbrt faces the surface to them); ReverseOrientation
    // negates them first.
    let toward = r#""normal N" [ 0 0 -1  0 0 -1  0 0 -1  0 0 -1 ]"#;
    assert_eq!(seen("", toward), 1.0);
    assert_eq!(seen("ReverseOrientation", toward), 0.0);
    assert_eq!(seen("Scale 1 1 -1", toward), 0.0, "mirrored, the normals face away");
}

fn error_of(test: &str, text: &str) -> String {
    let path = scene_dir(test, &[("scene.pbrt", text.as_bytes())]);
    match load_scene(&path) {
        Ok(_) => panic!("{test}: expected an error"),
        Err(e) => e.to_string(),
    }
}

/// Of eight names equally close to a misspelt one, the suggestion is the first in order,
/// however the reader's maps happen to order them: each scene is loaded several times, each
/// load with maps of its own.
#[test]
fn a_suggestion_among_equally_close_names_is_the_same_every_time() {
    let names = ["m8", "m3", "m6", "m1", "m7", "m2", "m5", "m4"];
    let materials: String =
        names.iter().map(|n| format!("MakeNamedMaterial \"{n}\" \"string type\" \"diffuse\"\n")).collect();
    let objects: String = names.iter().map(|n| format!("ObjectBegin \"{n}\"\nObjectEnd\n")).collect();
    let textures: String = names
        .iter()
        .map(|n| format!("Texture \"{n}\" \"spectrum\" \"constant\" \"rgb value\" [ 0.5 0.5 0.5 ]\n"))
        .collect();
    let cases = [
        ("material", format!("WorldBegin\n{materials}NamedMaterial \"m0\"\n"), "no material named `m0`"),
        ("object", format!("WorldBegin\n{objects}ObjectInstance \"m0\"\n"), "no object named `m0`"),
        (
            "texture",
            format!("WorldBegin\n{textures}Material \"diffuse\" \"texture reflectance\" \"m0\"\n"),
            "no texture named `m0`",
        ),
    ];
    for (test, text, expected) in cases {
        for _ in 0..4 {
            let e = error_of(&format!("suggestion-{test}"), &text);
            assert!(e.contains(&format!("{expected}; did you mean `m1`?")), "{test}: {e}");
        }
    }
}

#[test]
fn errors_name_the_file_line_and_what_was_expected() {
    let cases: &[(&str, &str, &str)] = &[
        (
            "directive",
            "WorldBegin\nShpe \"sphere\"\n",
            "scene.pbrt:2:1: unknown directive `Shpe`; did you mean `Shape`?",
        ),
        (
            "type",
            "WorldBegin\nShape \"sphere\" \"integer radius\" 2\n",
            "scene.pbrt:2:16: `radius` of Shape \"sphere\" is given as `integer`; expected `float`",
        ),
        ("number", "WorldBegin\nTranslate 1 x 2\n", "scene.pbrt:2:13: `Translate` expects a number here, found `x`"),
        ("string", "WorldBegin\nShape \"sphere\n", "scene.pbrt:2:7: a quoted string is not closed on its line"),
        (
            "bracket",
            "WorldBegin\nShape \"trianglemesh\" \"point3 P\" [ 0 0 0\n",
            "scene.pbrt:2:22: the values of `P` are not closed by `]`",
        ),
        (
            "material",
            "WorldBegin\nNamedMaterial \"glod\"\nMakeNamedMaterial \"gold\" \"string type\" \"conductor\"\n",
            "scene.pbrt:2:1: no material named `glod`",
        ),
        ("shape", "WorldBegin\nShape \"cone\" \"float radius\" 1\n", "shape `cone` is not supported"),
        ("curve", "WorldBegin\nShape \"curve\" \"point3 P\" [ 0 0 0 ]\n", "`P` holds 1 point(s), which make no bezier segments"),
        (
            "medium",
            "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\nMakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\n",
            "scene.pbrt:2:1: the medium `fog` is defined twice",
        ),
        (
            "unclosed",
            "WorldBegin\nAttributeBegin\nShape \"sphere\"\n",
            "scene.pbrt:2:1: this AttributeBegin is never closed",
        ),
        ("end", "WorldBegin\nAttributeEnd\n", "scene.pbrt:2:1: `AttributeEnd` without a matching begin"),
        ("nesting", "WorldBegin\nTransformBegin\nAttributeEnd\n", "scene.pbrt:3:1: `AttributeEnd` closes what was not opened by AttributeBegin"),
        ("twice", "WorldBegin\nMakeNamedMaterial \"a\" \"string type\" \"diffuse\"\nMakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n", "scene.pbrt:3:1: the material `a` is defined twice"),
        ("instance", "WorldBegin\nObjectBegin \"a\"\nObjectInstance \"a\"\n", "scene.pbrt:3:1: `ObjectInstance` inside an object's definition"),
        (
            "index",
            "WorldBegin\nShape \"trianglemesh\" \"integer indices\" [ 0 1 3 ] \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ]\n",
            "index 3 refers to no vertex (there are 3)",
        ),
        ("include", "Include \"missing.pbrt\"\n", "scene.pbrt:1:1: cannot read `missing.pbrt`"),
        (
            "albedo",
            "WorldBegin\nMaterial \"diffuse\" \"rgb reflectance\" [ 2 0 0 ]\nShape \"sphere\"\n",
            "reflectance's rgb must lie in [0, 1]",
        ),
        (
            "metal",
            "WorldBegin\nMaterial \"conductor\" \"spectrum eta\" \"metal-TiO2-eta\" \"spectrum k\" \"metal-TiO2-k\"\n",
            "no measured data for the metal `TiO2`",
        ),
    ];
    let wrong: Vec<String> = cases
        .iter()
        .map(|(test, text, expected)| (test, error_of(test, text), expected))
        .filter(|(_, e, expected)| !e.contains(*expected))
        .map(|(test, e, expected)| format!("{test}: expected `{expected}` in\n{e}"))
        .collect();
    assert!(wrong.is_empty(), "{}", wrong.join("\n\n"));
}

#[test]
fn parameters_glint_does_not_read_are_named_in_a_warning() {
    let text = "WorldBegin\nLightSource \"point\" \"float radius\" 3\n";
    let path = scene_dir("unused", &[("scene.pbrt", text.as_bytes())]);
    let loaded = load_scene(&path).unwrap();
    let warnings = loaded.warnings.join("\n");
    assert!(
        warnings.contains("scene.pbrt:2:21: parameter `radius` of LightSource \"point\" is not read"),
        "{warnings}"
    );
}

/// An equal-area octahedral map bright toward its +z, turned by pbrt's usual
/// `Rotate -90 1 0 0`: glint's environment is bright overhead (+y) and dark below.
#[test]
fn an_octahedral_environment_map_is_resampled_with_its_transform() {
    let n = 16u32;
    let image = image::Rgb32FImage::from_fn(n, n, |x, y| {
        // The centre of the square is +z; its corners −z.
        let (u, v) = ((x as f32 + 0.5) / n as f32 * 2.0 - 1.0, (y as f32 + 0.5) / n as f32 * 2.0 - 1.0);
        let bright = if u.abs() + v.abs() < 0.5 { 4.0 } else { 0.0 };
        image::Rgb([bright, bright, bright])
    });
    let mut exr = Vec::new();
    image::DynamicImage::ImageRgb32F(image)
        .write_to(&mut std::io::Cursor::new(&mut exr), image::ImageFormat::OpenExr)
        .unwrap();
    let text = "WorldBegin\nAttributeBegin\nRotate -90 1 0 0\nLightSource \"infinite\" \"string filename\" \"sky.exr\" \"float scale\" 2\nAttributeEnd\n";
    let path = scene_dir("octahedral", &[("scene.pbrt", text.as_bytes()), ("sky.exr", &exr)]);
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let map = loaded.scene.environment().map.as_ref().expect("a map");
    assert_eq!(map.radiance(Vec3::Y), Rgb::splat(8.0));
    assert_eq!(map.radiance(-Vec3::Y), Rgb::ZERO);
    assert_eq!(map.radiance(Vec3::X), Rgb::ZERO);
    assert!(loaded.inputs.iter().any(|p| p.ends_with("sky.exr")), "{:?}", loaded.inputs);
}

/// An equal-area map (EXR bytes) of `n`² texels whose radiance is `f` of the texel's
/// direction in the light's frame.
fn octahedral_exr(n: u32, f: impl Fn(Vec3) -> f32) -> Vec<u8> {
    let image = image::Rgb32FImage::from_fn(n, n, |x, y| {
        let st = glam::Vec2::new((x as f32 + 0.5) / n as f32, (y as f32 + 0.5) / n as f32);
        // pbrt's equal-area square to sphere (the reader's own is crate-private).
        let (u, v) = (2.0 * st.x - 1.0, 2.0 * st.y - 1.0);
        let (up, vp) = (u.abs(), v.abs());
        let signed = 1.0 - (up + vp);
        let r = 1.0 - signed.abs();
        let phi = if r == 0.0 { 1.0 } else { (vp - up) / r + 1.0 } * std::f32::consts::FRAC_PI_4;
        let z = (1.0 - r * r).copysign(signed);
        let scale = r * (2.0 - r * r).max(0.0).sqrt();
        let d = Vec3::new((phi.cos() * scale).copysign(u), (phi.sin() * scale).copysign(v), z);
        let value = f(d);
        image::Rgb([value, value, value])
    });
    let mut exr = Vec::new();
    image::DynamicImage::ImageRgb32F(image)
        .write_to(&mut std::io::Cursor::new(&mut exr), image::ImageFormat::OpenExr)
        .unwrap();
    exr
}

/// pbrt adds up every infinite light: two maps turned opposite ways and a constant make one
/// map bright above and below, with the constant everywhere; its importance sampling follows
/// the sum.
#[test]
fn several_infinite_lights_add_up() {
    let upper = octahedral_exr(16, |d| if d.z > 0.5 { 2.0 } else { 0.0 });
    let text = "WorldBegin
AttributeBegin
Rotate -90 1 0 0
LightSource \"infinite\" \"string filename\" \"upper.exr\" \"float scale\" 3
AttributeEnd
AttributeBegin
Rotate 90 1 0 0
LightSource \"infinite\" \"string filename\" \"upper.exr\"
AttributeEnd
LightSource \"infinite\" \"rgb L\" [0.25 0.5 1]
";
    let path = scene_dir("several-infinite", &[("scene.pbrt", text.as_bytes()), ("upper.exr", &upper)]);
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let environment = loaded.scene.environment();
    let map = environment.map.as_ref().expect("one map of the sum");
    let constant = Rgb::new(0.25, 0.5, 1.0);
    let close = |a: Rgb, b: Rgb| (a - b).abs().max_element() < 1e-5;
    assert!(close(map.radiance(Vec3::Y), Rgb::splat(6.0) + constant), "{}", map.radiance(Vec3::Y));
    assert!(close(map.radiance(-Vec3::Y), Rgb::splat(2.0) + constant), "{}", map.radiance(-Vec3::Y));
    assert!(close(map.radiance(Vec3::X), constant), "{}", map.radiance(Vec3::X));
    // Sampled by the sum: most samples go toward the two bright caps, the upper one three
    // times as often as the lower (their radiance is 6 + ⅔·… against 2 + …, the constant's
    // luminance 0.6 spread over the rest).
    let (mut up, mut down, n) = (0, 0, 4000);
    for i in 0..n {
        let u = glam::Vec2::new((i as f32 + 0.5) / n as f32, (((i * 7919) % n) as f32 + 0.5) / n as f32);
        let sample = environment.sample(u).expect("a direction");
        if sample.direction.y > 0.5 {
            up += 1;
        } else if sample.direction.y < -0.5 {
            down += 1;
        }
    }
    assert!(up > 2 * down && down > n / 10, "up {up}, down {down}");
}

/// `illuminance` scales as pbrt-v4 does: a constant L to the illuminance E = π L on a surface
/// facing it; an equal-area map so that pbrt's estimate of its upper hemisphere's (half the
/// illuminance) is the value given.
#[test]
fn an_infinite_lights_illuminance_scales_it_as_pbrt_does() {
    let text = "WorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1 1] \"float illuminance\" 6.2831853\n";
    let path = scene_dir("illuminance-constant", &[("scene.pbrt", text.as_bytes())]);
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let background = loaded.scene.environment().background;
    assert!((background - Rgb::splat(2.0)).abs().max_element() < 1e-5, "{background}");

    // A uniform map of radiance 4: pbrt's estimate is 4 · (π/2) (at 32² texel centres, within
    // 1 %), so illuminance π gives radiance 2, times the scale 3.
    let uniform = octahedral_exr(32, |_| 4.0);
    let text = "WorldBegin\nLightSource \"infinite\" \"string filename\" \"u.exr\" \"float illuminance\" 3.14159265 \"float scale\" 3\n";
    let path = scene_dir("illuminance-map", &[("scene.pbrt", text.as_bytes()), ("u.exr", &uniform)]);
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let map = loaded.scene.environment().map.as_ref().expect("a map");
    let radiance = map.radiance(Vec3::new(0.3, 0.5, 0.2).normalize());
    assert!((radiance - Rgb::splat(6.0)).abs().max_element() < 0.06, "{radiance}");

    let refused = [
        ("\"rgb L\" [1 1 1] \"string filename\" \"u.exr\"", "`L` or `filename`, not both"),
        ("\"float power\" 3", "not `power`"),
    ];
    for (params, expected) in refused {
        let text = format!("WorldBegin\nLightSource \"infinite\" {params}\n");
        let path = scene_dir("infinite-refused", &[("scene.pbrt", text.as_bytes()), ("u.exr", &uniform)]);
        let error = load_scene(&path).err().expect("refused").to_string();
        assert!(error.contains(expected) && error.contains("scene.pbrt:2:"), "{error}");
    }
}

/// pbrt's media onto glint's: a homogeneous medium inside an `interface` sphere and around
/// the camera, a density grid and an RGB grid (σ_t and albedo where pbrt's lookup gives them,
/// its fade to zero at the box's edge included).
#[test]
fn named_media_map_onto_glints() {
    let text = r#"MakeNamedMedium "fog" "string type" "homogeneous" "rgb sigma_a" [0.1 0.2 0.3] "rgb sigma_s" [0.5 0.5 0.5] "float scale" 2 "float g" 0.4
MediumInterface "" "fog"
LookAt 0 0 -5  0 0 0  0 1 0
Camera "perspective"
WorldBegin
MakeNamedMedium "smoke" "string type" "uniformgrid" "integer nx" 2 "integer ny" 1 "integer nz" 1
    "float density" [1 3] "point3 p0" [0 0 0] "point3 p1" [2 1 1] "rgb sigma_a" [0.5 0.5 0.5] "rgb sigma_s" [1.5 1.5 1.5] "float scale" 2
AttributeBegin
Translate 10 0 0
MakeNamedMedium "tint" "string type" "rgbgrid" "point3 p0" [0 0 0] "point3 p1" [1 1 1]
    "rgb sigma_a" [0.1 0.2 0.3] "rgb sigma_s" [0.3 0.2 0.1]
AttributeEnd
AttributeBegin
MediumInterface "smoke" "fog"
Material "interface"
Shape "sphere" "float radius" 1
AttributeEnd
LightSource "point" "rgb I" [1 1 1]
"#;
    let path = scene_dir("media", &[("scene.pbrt", text.as_bytes())]);
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let scene = &loaded.scene;
    let index = |name: &str| ["fog", "smoke", "tint"].iter().position(|n| *n == name).unwrap() as u32;
    assert_eq!(scene.media().len(), 3);
    assert_eq!(scene.camera_medium(), Some(index("fog")));
    let interface = scene.medium_interface(0);
    assert_eq!((interface.inside, interface.outside), (Some(index("smoke")), Some(index("fog"))));

    let fog = &scene.media()[index("fog") as usize];
    assert_eq!(fog.coefficients(Vec3::ZERO), (Rgb::splat(1.0), Rgb::new(0.2, 0.4, 0.6)));
    assert!(matches!(fog.phase, glint_core::media::PhaseFunction::HenyeyGreenstein { g } if g == 0.4));

    // σ_t = scale · (σ_a + σ_s) · density = 4 · density; albedo ¾. pbrt reads voxel centres
    // (x = 0.5 and 1.5) and fades to 0 at the box's edge: at x = 0.1, 0.6 of the first.
    let smoke = &scene.media()[index("smoke") as usize];
    let sigma_t = |x: f32| {
        let (s, a) = smoke.coefficients(Vec3::new(x, 0.5, 0.5));
        s + a
    };
    for (x, expected) in [(0.5, 4.0), (1.5, 12.0), (1.0, 8.0), (0.1, 2.4), (1.9, 7.2)] {
        assert!((sigma_t(x) - Rgb::splat(expected)).abs().max_element() < 1e-4, "σ_t({x}) = {}", sigma_t(x));
    }
    let (s, a) = smoke.coefficients(Vec3::new(1.5, 0.5, 0.5));
    assert!((s / (s + a) - Rgb::splat(0.75)).abs().max_element() < 1e-6);
    assert_eq!(sigma_t(-1.0), Rgb::ZERO);

    // Placed by the transform at its definition: its centre at x = 10.5.
    let tint = &scene.media()[index("tint") as usize];
    let (s, a) = tint.coefficients(Vec3::new(10.5, 0.5, 0.5));
    assert!((s + a - Rgb::splat(0.4)).abs().max_element() < 1e-6, "{}", s + a);
    assert!((s / (s + a) - Rgb::new(0.75, 0.5, 0.25)).abs().max_element() < 1e-6);
    // Near a face the extinction fades as pbrt's does (at x = 0.05 of the one voxel, 0.55 of
    // it), and the albedo, a ratio of the two coefficients there, stays what it is.
    let (s, a) = tint.coefficients(Vec3::new(10.05, 0.5, 0.5));
    assert!((s + a - Rgb::splat(0.4 * 0.55)).abs().max_element() < 1e-5, "{}", s + a);
    assert!((s / (s + a) - Rgb::new(0.75, 0.5, 0.25)).abs().max_element() < 1e-5, "{}", s / (s + a));
}

/// A camera inside an absorbing medium sees an emitter through it dimmed by exp(−σ_a d).
#[test]
fn a_light_seen_through_an_absorbing_medium_is_dimmed_by_beers_law() {
    let text = r#"MakeNamedMedium "ink" "string type" "homogeneous" "rgb sigma_a" [0.25 0.5 1] "rgb sigma_s" [0 0 0]
MediumInterface "" "ink"
LookAt 0 0 0  0 0 1  0 1 0
Camera "perspective" "float fov" 1
Film "rgb" "integer xresolution" 4 "integer yresolution" 4
Integrator "volpath" "integer maxdepth" 4
WorldBegin
AreaLightSource "diffuse" "rgb L" [1 1 1]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point3 P" [-10 -10 2  -10 10 2  10 10 2  10 -10 2]
"#;
    let path = scene_dir("beer", &[("scene.pbrt", text.as_bytes())]);
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let integrator = loaded.render.integrator.create(&loaded.render.integrator_settings).unwrap();
    let settings = RenderSettings { spp: 16, seed: 1, filter: Filter::Box, sampler: loaded.render.sampler };
    let image = render(&loaded.scene, integrator.as_ref(), &settings, &|| {}).film.to_rgb();
    let mean = image.iter().sum::<Rgb>() / image.len() as f32;
    // Over 2 units (the 1° view is straight on: 1/cos < 1.0001).
    let expected = Rgb::new((-0.5f32).exp(), (-1.0f32).exp(), (-2.0f32).exp());
    assert!(((mean - expected) / expected).abs().max_element() < 0.03, "{mean} vs {expected}");
}

/// What glint cannot read of pbrt's media is refused at its line, by name.
#[test]
fn media_glint_cannot_read_are_refused_by_name() {
    let cases = [
        ("MakeNamedMedium \"c\" \"string type\" \"cloud\"", "procedural noise"),
        ("MakeNamedMedium \"v\" \"string type\" \"nanovdb\" \"string filename\" \"a.nvdb\"", "NanoVDB"),
        ("MakeNamedMedium \"p\" \"string type\" \"homogeneous\" \"string preset\" \"Ketchup\"", "`preset`"),
        (
            "MakeNamedMedium \"g\" \"string type\" \"uniformgrid\" \"integer nx\" 2 \"float density\" [1]",
            "has 1 values",
        ),
        ("MediumInterface \"nowhere\" \"\"", "no medium named `nowhere`"),
    ];
    for (directive, expected) in cases {
        let text = format!("WorldBegin\n{directive}\n");
        let path = scene_dir("media-refused", &[("scene.pbrt", text.as_bytes())]);
        let error = load_scene(&path).err().expect("refused").to_string();
        assert!(error.contains(expected) && error.contains("scene.pbrt:2:"), "{error}");
    }
}

/// pbrt's `cropwindow` renders the film's pixels in the window (its bounds rounded up as
/// pbrt rounds them), each as the whole film's render has it; `pixelbounds` gives them in
/// pixels.
#[test]
fn a_crop_window_renders_the_films_pixels_there() {
    let scene = |film: &str| {
        format!(
            r#"LookAt 0 0 -6  0 0 0  0 1 0
Camera "perspective" "float fov" 50
Film "rgb" "integer xresolution" 32 "integer yresolution" 24 {film}
WorldBegin
LightSource "point" "rgb I" [5 5 5] "point3 from" [2 3 -4]
Material "diffuse" "rgb reflectance" [0.7 0.4 0.2]
Shape "sphere" "float radius" 1.5
Translate 1 -1 1
Shape "sphere" "float radius" 1
"#
        )
    };
    let render_of = |film: &str, test: &str| {
        let text = scene(film);
        let path = scene_dir(test, &[("scene.pbrt", text.as_bytes())]);
        let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
        let integrator = IntegratorKind::Whitted.create(&loaded.render.integrator_settings).unwrap();
        let settings = RenderSettings { spp: 1, seed: 1, filter: Filter::Box, sampler: SamplerKind::Independent };
        let film = render(&loaded.scene, integrator.as_ref(), &settings, &|| {}).film;
        (loaded.scene.camera().crop_window(), film)
    };
    let (none, whole) = render_of("", "crop-whole");
    assert_eq!(none, None);
    // x: ⌈32 · 0.25⌉ = 8 to ⌈32 · 0.75⌉ = 24; y: ⌈24 · 0.1⌉ = 3 to ⌈24 · 0.5⌉ = 12.
    let (window, crop) = render_of(r#""float cropwindow" [0.25 0.75 0.1 0.5]"#, "crop-window");
    assert_eq!(window, Some((8, 3, 24, 12)));
    assert_eq!((crop.width, crop.height), (16, 9));
    for y in 0..9 {
        for x in 0..16 {
            assert_eq!(crop.pixel(x, y), whole.pixel(x + 8, y + 3), "pixel ({x}, {y})");
        }
    }
    assert!(crop.to_rgb().iter().any(|p| p.max_element() > 0.0), "the window sees the spheres");
    let (window, _) = render_of(r#""integer pixelbounds" [4 20 0 24]"#, "crop-bounds");
    assert_eq!(window, Some((4, 0, 20, 24)));
    // Rounded in single precision, as pbrt rounds: 0.1 · 32 is 3.2000000476837158 in f32 →
    // 4, and 0.75 · 24 = 18 exactly.
    let (window, _) = render_of(r#""float cropwindow" [0.1 1 0 0.75]"#, "crop-f32");
    assert_eq!(window, Some((4, 0, 32, 18)));
    let error = {
        let text = scene(r#""float cropwindow" [0.5 0.25 0 1]"#);
        let path = scene_dir("crop-bad", &[("scene.pbrt", text.as_bytes())]);
        load_scene(&path).err().expect("refused").to_string()
    };
    assert!(error.contains("scene.pbrt:3:") && error.contains("0 ≤ x0 < x1 ≤ 1"), "{error}");
}

/// pbrt's two blocks: options before `WorldBegin`, the scene after it, each directive in its
/// own (pbrt refuses the others; glint rendered them black or misplaced).
#[test]
fn directives_in_the_wrong_block_are_refused_as_pbrt_refuses_them() {
    let cases = [
        ("WorldBegin\nCamera \"perspective\"\n", "scene.pbrt:2:1: `Camera` after `WorldBegin`"),
        ("WorldBegin\nWorldBegin\n", "scene.pbrt:2:1: a second `WorldBegin` after `WorldBegin`"),
        ("Shape \"sphere\"\n", "scene.pbrt:1:1: `Shape` before `WorldBegin`"),
        ("LightSource \"point\"\nWorldBegin\n", "scene.pbrt:1:1: `LightSource` before `WorldBegin`"),
    ];
    for (text, expected) in cases {
        let error = error_of("blocks", text);
        assert!(error.contains(expected), "{error}");
    }
}

/// Gzipped scene files and includes (`.pbrt.gz`) are read as pbrt reads them.
#[test]
fn gzipped_scene_files_and_includes_are_read() {
    let gzip = |text: &str| {
        use std::io::Write;
        let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
        encoder.write_all(text.as_bytes()).unwrap();
        encoder.finish().unwrap()
    };
    let main = gzip("WorldBegin\nInclude \"part.pbrt.gz\"\n");
    let part = gzip("LightSource \"point\" \"rgb I\" [1 2 3]\nShape \"sphere\" \"float radius\" 2\n");
    let path = scene_dir("gzip", &[("scene.pbrt.gz", &main), ("part.pbrt.gz", &part)]);
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(loaded.scene.objects().len(), 1);
    assert!(loaded.inputs.iter().any(|p| p.ends_with("part.pbrt.gz")), "{:?}", loaded.inputs);
    let path = scene_dir("gzip-bad", &[("scene.pbrt.gz", b"not gzip")]);
    let error = load_scene(&path).err().expect("refused").to_string();
    assert!(error.contains("scene.pbrt.gz") && error.contains("gzip"), "{error}");
}

/// A shape's `alpha` cuts it out as pbrt does: present with that probability, so a black
/// screen of alpha ¼ before a light lets ¾ of it through (0: none of it stops light; an
/// alpha texture is read where the ray hits).
#[test]
fn alpha_cuts_shapes_out() {
    let seen = |alpha: &str, test: &str| {
        let text = format!(
            r#"LookAt 0 0 0  0 0 1  0 1 0
Camera "perspective" "float fov" 20
Film "rgb" "integer xresolution" 8 "integer yresolution" 8
Integrator "path" "integer maxdepth" 2
WorldBegin
Texture "quarter" "float" "constant" "float value" 0.25
AttributeBegin
AreaLightSource "diffuse" "rgb L" [2 2 2]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point3 P" [-10 -10 4  -10 10 4  10 10 4  10 -10 4]
AttributeEnd
Material "diffuse" "rgb reflectance" [0 0 0]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point3 P" [-10 -10 2  -10 10 2  10 10 2  10 -10 2] {alpha}
"#
        );
        let path = scene_dir(test, &[("scene.pbrt", text.as_bytes())]);
        let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
        let integrator = loaded.render.integrator.create(&loaded.render.integrator_settings).unwrap();
        let settings = RenderSettings { spp: 64, seed: 3, filter: Filter::Box, sampler: SamplerKind::Independent };
        let image = render(&loaded.scene, integrator.as_ref(), &settings, &|| {}).film.to_rgb();
        image.iter().sum::<Rgb>().x / image.len() as f32
    };
    assert_eq!(seen("", "alpha-none"), 0.0);
    assert_eq!(seen(r#""float alpha" 1"#, "alpha-one"), 0.0);
    assert_eq!(seen(r#""float alpha" 0"#, "alpha-zero"), 2.0);
    // 4096 rays, each through with probability ¾: a standard deviation of 2 · 0.0068.
    let quarter = seen(r#""float alpha" 0.25"#, "alpha-quarter");
    assert!((quarter - 1.5).abs() < 0.05, "{quarter}");
    let textured = seen(r#""texture alpha" "quarter""#, "alpha-texture");
    assert!((textured - 1.5).abs() < 0.05, "{textured}");
}

/// pbrt resolves material names when the scene is complete: a shape may use a named
/// material that a file included later makes (contemporary-bathroom's order), and a mix may
/// name materials made after it.
#[test]
fn named_materials_may_be_made_after_their_use() {
    let main = "WorldBegin\nNamedMaterial \"tiles\"\nShape \"sphere\"\nMakeNamedMaterial \"either\" \"string type\" \"mix\" \"string materials\" [\"tiles\" \"grout\"]\nInclude \"materials.pbrt\"\n";
    let materials = "MakeNamedMaterial \"tiles\" \"string type\" \"diffuse\" \"rgb reflectance\" [0.8 0.1 0.1]\nMakeNamedMaterial \"grout\" \"string type\" \"conductor\"\n";
    let path =
        scene_dir("late-materials", &[("scene.pbrt", main.as_bytes()), ("materials.pbrt", materials.as_bytes())]);
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let sphere = &loaded.scene.objects()[0];
    let material = &loaded.scene.materials()[sphere.material as usize];
    assert!(format!("{material:?}").contains("reflectance: Constant(Vec3(0.8, 0.1, 0.1))"), "{material:?}");
}

/// Messages about what the translator made name the user's directive and line, not internal
/// names; numbers beyond single precision are refused where they are written.
#[test]
fn messages_name_the_users_directives() {
    let cases = [
        ("WorldBegin\nShape \"sphere\" \"float radius\" 1e300\n", vec!["scene.pbrt:2:31: the number `1e300` is beyond single precision"]),
        (
            "WorldBegin\nScale 1e30 1e30 1e30\nShape \"sphere\"\n",
            vec!["Shape \"sphere\" at ", "scene.pbrt:3:1", "more than single precision holds"],
        ),
        (
            "WorldBegin\nTexture \"wood\" \"spectrum\" \"imagemap\" \"string filename\" \"missing.png\"\nMaterial \"diffuse\" \"texture reflectance\" \"wood\"\nShape \"sphere\"\n",
            vec!["texture `texture \"wood\" at ", "scene.pbrt:2:1`", "missing.png"],
        ),
    ];
    for (text, expected) in cases {
        let error = error_of("messages", text);
        for part in expected {
            assert!(error.contains(part), "{part:?} not in: {error}");
        }
    }
}

/// A spectrum given as a `.spd` file (killeroos' gold) reads as the same pairs written inline;
/// a file that is not pairs of numbers is refused at the parameter.
#[test]
fn spd_files_are_the_spectra_they_hold() {
    let eta = "# gold-ish\n400 1.5\n500 0.9 # green\n600 0.3\n700 0.2\n";
    let k = "400 1.9 500 2.0\n600 3.0 700 4.0\n";
    let conductor = |params: &str, test: &str| {
        let text = format!("WorldBegin\nMaterial \"conductor\" {params}\nShape \"sphere\"\n");
        let path = scene_dir(
            test,
            &[
                ("scene.pbrt", text.as_bytes()),
                ("eta.spd", eta.as_bytes()),
                ("k.spd", k.as_bytes()),
                ("bad.spd", b"400 1.5 500"),
            ],
        );
        load_scene(&path).map(|loaded| format!("{:?}", loaded.scene.materials()[0]))
    };
    let from_files =
        conductor(r#""spectrum eta" "eta.spd" "spectrum k" "k.spd""#, "spd-files").unwrap_or_else(|e| panic!("{e}"));
    let inline = conductor(
        r#""spectrum eta" [400 1.5 500 0.9 600 0.3 700 0.2] "spectrum k" [400 1.9 500 2.0 600 3.0 700 4.0]"#,
        "spd-inline",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(from_files, inline);
    let error =
        conductor(r#""spectrum eta" "bad.spd" "spectrum k" "k.spd""#, "spd-bad").expect_err("refused").to_string();
    assert!(error.contains("scene.pbrt:2:") && error.contains("`bad.spd`: expected wavelength–value pairs"), "{error}");
}

/// pbrt's planar mapping reads a texture at the point's coordinates in the texture's space,
/// whatever the surface's uv: a checkerboard of half-unit checks across a floor seen from
/// above, under a uniform sky (each pixel is the check's albedo).
#[test]
fn a_planar_mapping_lays_a_checkerboard_by_position() {
    let text = r#"LookAt 0 0 5  0 0 0  0 1 0
Camera "orthographic"
Film "rgb" "integer xresolution" 8 "integer yresolution" 8
Integrator "path" "integer maxdepth" 1
Sampler "independent" "integer pixelsamples" 1
WorldBegin
LightSource "infinite" "rgb L" [1 1 1]
Texture "checks" "spectrum" "checkerboard" "string mapping" "planar" "vector3 v1" [2 0 0] "vector3 v2" [0 2 0] "rgb tex1" [0.9 0.9 0.9] "rgb tex2" [0.1 0.1 0.1]
Material "diffuse" "texture reflectance" "checks"
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point3 P" [-5 -5 0  5 -5 0  5 5 0  -5 5 0] "point2 uv" [0 0 0 0 0 0 0 0]
"#;
    let path = scene_dir("planar", &[("scene.pbrt", text.as_bytes())]);
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let integrator = loaded.render.integrator.create(&loaded.render.integrator_settings).unwrap();
    let settings = RenderSettings { spp: 256, seed: 5, filter: Filter::Box, sampler: SamplerKind::Independent };
    let film = render(&loaded.scene, integrator.as_ref(), &settings, &|| {}).film;
    // 8 pixels across 2 units: each check (half a unit) is 2 × 2 pixels.
    let bright = |x: u32, y: u32| film.pixel(x, y).x > 0.5;
    for y in 0..8u32 {
        for x in 0..8u32 {
            let value = film.pixel(x, y).x;
            assert!((value - 0.9).abs() < 0.15 || (value - 0.1).abs() < 0.05, "({x}, {y}): {value}");
            assert_eq!(bright(x, y), bright(x ^ 1, y ^ 1), "({x}, {y}) within its check");
            if x + 2 < 8 {
                assert_ne!(bright(x, y), bright(x + 2, y), "({x}, {y}) against the next check");
            }
        }
    }
}

/// A material's `displacement` bump-maps it, as pbrt-v4's does: the material about a normal
/// tilted by the height texture's slope; a constant height tilts nothing, and a normal map
/// wins over it (with a warning).
#[test]
fn a_materials_displacement_bump_maps_it() {
    let mut png = Vec::new();
    image::GrayImage::from_fn(4, 4, |x, _| image::Luma([(x * 60) as u8]))
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    let load = |material: &str, test: &str| {
        let text = format!(
            "WorldBegin\nTexture \"bumps\" \"float\" \"imagemap\" \"string filename\" \"bumps.png\"\n{material}\nShape \"sphere\"\n"
        );
        let path = scene_dir(test, &[("scene.pbrt", text.as_bytes()), ("bumps.png", &png), ("normals.png", &png)]);
        let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
        let sphere = &loaded.scene.objects()[0];
        (loaded.scene.materials()[sphere.material as usize].clone(), loaded.warnings)
    };
    let (bumped, _) = load("Material \"diffuse\" \"texture displacement\" \"bumps\"", "bump");
    let Material::BumpMap(bump) = &bumped else { panic!("{bumped:?}") };
    assert!(format!("{:?}", bump.material).contains("Diffuse"), "{:?}", bump.material);
    let (flat, _) = load("Material \"diffuse\" \"float displacement\" 0.3", "bump-constant");
    assert!(!format!("{flat:?}").contains("Bump"), "{flat:?}");
    let (normal, warnings) = load(
        "Material \"diffuse\" \"texture displacement\" \"bumps\" \"string normalmap\" \"normals.png\"",
        "bump-normal",
    );
    assert!(matches!(normal, Material::NormalMap(_)), "{normal:?}");
    assert!(warnings.iter().any(|w| w.contains("ignores its `displacement`")), "{warnings:?}");
}

/// A coateddiffuse's roughness that glint's one-α coat cannot hold is approximated, with a
/// warning: an anisotropic pair by its geometric mean, a texture by its mean value.
#[test]
fn a_coated_diffuses_anisotropic_or_textured_roughness_becomes_one_alpha() {
    let alpha = |params: &str, test: &str| {
        let text = format!(
            "WorldBegin\nTexture \"r\" \"float\" \"checkerboard\" \"float tex1\" 0.1 \"float tex2\" 0.3\nMaterial \"coateddiffuse\" \"bool remaproughness\" false {params}\nShape \"sphere\"\n"
        );
        let path = scene_dir(test, &[("scene.pbrt", text.as_bytes())]);
        let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
        let sphere = &loaded.scene.objects()[0];
        let material = format!("{:?}", loaded.scene.materials()[sphere.material as usize]);
        let alpha =
            material.split("alpha: ").nth(1).and_then(|s| s.split(',').next()).map(|s| s.parse::<f32>().unwrap());
        (alpha.unwrap_or_else(|| panic!("{material}")), loaded.warnings.join("\n"))
    };
    let (a, warnings) = alpha("\"float uroughness\" 0.04 \"float vroughness\" 0.16", "coat-aniso");
    assert!((a - 0.08).abs() < 1e-6, "{a}");
    assert!(warnings.contains("geometric mean"), "{warnings}");
    let (a, warnings) = alpha("\"texture roughness\" \"r\"", "coat-texture");
    assert!((a - 0.2).abs() < 1e-6, "{a}");
    assert!(warnings.contains("the texture's mean 0.2, α = 0.2"), "{warnings}");
}

#[test]
fn quadrics_and_patches_are_meshes_of_their_shape() {
    let text = "WorldBegin\nShape \"disk\" \"float radius\" 2 \"float innerradius\" 1\nShape \"sphere\" \"float radius\" 1 \"float phimax\" 180\n";
    let path = scene_dir("quadrics", &[("scene.pbrt", text.as_bytes())]);
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let objects = loaded.scene.objects();
    assert_eq!(objects.len(), 2);
    for object in objects {
        assert!(matches!(object.shape, Shape::Mesh(_)), "{}", object.name);
    }
    // Below y = 0 (where the half ball is not): the annulus's hole lets a ray through, its
    // ring stops one at z = 0.
    let scene = &loaded.scene;
    let hit = |x: f32, y: f32| scene.intersect(&Ray::new(Vec3::new(x, y, 5.0), -Vec3::Z)).map(|h| h.t);
    assert_eq!(hit(0.5, -0.3), None);
    assert!((hit(1.5, -0.3).unwrap() - 5.0).abs() < 1e-4);
    // Above, the half ball (φ from 0 to 180°): z = √(1 − 0.34) on its surface, within the
    // 64-gon's sag.
    let t = hit(0.5, 0.3).unwrap();
    assert!((t - (5.0 - 0.66f32.sqrt())).abs() < 2e-3, "{t}");
}

/// pbrt's sphere has its pole on +z and u about +z from +x; glint's own sphere is turned to
/// match, so textures land where pbrt puts them.
#[test]
fn a_full_sphere_has_pbrts_texture_coordinates() {
    let text = "WorldBegin\nShape \"sphere\" \"float radius\" 2\n";
    let path = scene_dir("sphere-uv", &[("scene.pbrt", text.as_bytes())]);
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let uv = |origin: Vec3| {
        let hit = loaded.scene.intersect(&Ray::new(origin, -origin.normalize())).expect("the ball");
        hit.geometry.uv
    };
    // +y (φ = 90°) on the equator: u = ¼, v = ½; the top (+z): v = 1; the bottom: v = 0.
    let side = uv(Vec3::new(0.0, 5.0, 0.0));
    assert!((side - glam::Vec2::new(0.25, 0.5)).length() < 1e-5, "{side}");
    assert!((uv(Vec3::new(0.0, 0.01, 5.0)).y - 1.0).abs() < 1e-2);
    assert!(uv(Vec3::new(0.0, 0.01, -5.0)).y.abs() < 1e-2);
}

/// Loop subdivision numbers its vertices in a fixed order: the same mesh every time.
#[test]
fn loop_subdivision_is_deterministic() {
    let text = "WorldBegin\nShape \"loopsubdiv\" \"integer levels\" 3 \"integer indices\" [ 0 1 2  0 2 3  0 3 1  1 3 2 ] \"point3 P\" [ 1 1 1  1 -1 -1  -1 1 -1  -1 -1 1 ]\n";
    let path = scene_dir("loop", &[("scene.pbrt", text.as_bytes())]);
    let mesh = |_: usize| match &load_scene(&path).unwrap().scene.objects()[0].shape {
        Shape::Mesh(m) => (m.positions.clone(), m.indices.clone()),
        other => panic!("{other:?}"),
    };
    let first = mesh(0);
    for i in 1..4 {
        assert!(mesh(i) == first, "run {i} differs");
    }
}

#[test]
fn mutated_scenes_never_panic() {
    let original = std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cbox.pbrt")).unwrap();
    let dir = std::env::temp_dir().join(format!("glint-pbrt-mutants-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (i, bytes) in common::mutants(&original, b"[]\"# 0.-e\nxAS", 300, 11).into_iter().enumerate() {
        let path = dir.join(format!("m{i}.pbrt"));
        std::fs::write(&path, &bytes).unwrap();
        let result = std::panic::catch_unwind(|| load_scene(&path).map(|_| ()));
        assert!(result.is_ok(), "mutant {i} panicked:\n{}", String::from_utf8_lossy(&bytes));
    }
}

/// The realistic camera as a thin lens: a single biconvex element of f = 100 mm focused at
/// 10 m puts the film at 100·10⁴/(10⁴ − 100) mm, and a 35 mm diagonal square film's side
/// (24.75 mm) spans 2·atan(12.37/101.01) there.
#[test]
fn a_realistic_camera_is_the_thin_lens_of_its_focal_length() {
    let text = "Camera \"realistic\" \"string lensfile\" \"thin.dat\" \"float aperturediameter\" 8 \"float focusdistance\" 10\nFilm \"rgb\" \"integer xresolution\" 64 \"integer yresolution\" 64\nWorldBegin\nMaterial \"diffusetransmission\" \"rgb reflectance\" [ 0.4 0.4 0.4 ] \"float scale\" 0.5\nShape \"sphere\"\n";
    let lens = "# radius thickness index aperture\n100 0 1.5 20\n-100 100 0 20\n";
    let path = scene_dir("realistic", &[("scene.pbrt", text.as_bytes()), ("thin.dat", lens.as_bytes())]);
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.warnings.join("\n").contains("paraxial focal length (100.0 mm)"), "{:?}", loaded.warnings);
    let camera = loaded.scene.camera();
    let image = 100.0 * 1e4 / (1e4 - 100.0);
    let side = 35.0 / 2f32.sqrt();
    let expected = 2.0 * (0.5 * side / image).atan().to_degrees();
    assert!((camera.fov_degrees - expected).abs() < 1e-3, "{} vs {expected}", camera.fov_degrees);
    assert!(
        matches!(camera.lens, Lens::Thin { radius, focus_distance } if (radius - 0.004).abs() < 1e-7 && focus_distance == 10.0)
    );
    // The diffuse transmitter: pbrt's default transmittance 0.25 and the reflectance, each
    // times `scale`.
    match &loaded.scene.materials()[loaded.scene.objects()[0].material as usize] {
        Material::DiffuseTransmission(m) => {
            assert_eq!(m.reflectance, glint_core::textures::Texture::Constant(Rgb::splat(0.2)));
            assert_eq!(m.transmittance, glint_core::textures::Texture::Constant(Rgb::splat(0.125)));
        }
        other => panic!("{other:?}"),
    }
}

/// pbrt's procedural textures load as glint's: a bilerp of four values across a floor seen
/// from above renders each pixel as the blend at its uv (an analytic check through the whole
/// reader and renderer), every noise texture makes a material (marble's colour, fbm and
/// windy as a roughness-free reflectance scale, wrinkled as a bump), and ptex is refused by
/// name.
#[test]
fn pbrts_procedural_textures_load_and_bilerp_renders_its_blend() {
    let text = r#"LookAt 0 0 5  0 0 0  0 1 0
Camera "orthographic"
Film "rgb" "integer xresolution" 4 "integer yresolution" 4
Integrator "path" "integer maxdepth" 1
Sampler "independent" "integer pixelsamples" 1
WorldBegin
LightSource "infinite" "rgb L" [1 1 1]
Texture "blend" "spectrum" "bilerp" "rgb v00" [0.1 0.1 0.1] "rgb v10" [0.9 0.9 0.9] "rgb v01" [0.1 0.1 0.1] "rgb v11" [0.9 0.9 0.9]
Material "diffuse" "texture reflectance" "blend"
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point3 P" [-1 -1 0  1 -1 0  1 1 0  -1 1 0] "point2 uv" [0 0 1 0 1 1 0 1]
"#;
    let path = scene_dir("bilerp", &[("scene.pbrt", text.as_bytes())]);
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let integrator = loaded.render.integrator.create(&loaded.render.integrator_settings).unwrap();
    let settings = RenderSettings { spp: 64, seed: 5, filter: Filter::Box, sampler: SamplerKind::Independent };
    let film = render(&loaded.scene, integrator.as_ref(), &settings, &|| {}).film;
    // Under a white sky of radiance 1, a diffuse floor returns its albedo: 0.1 + 0.8 s, s the
    // pixel's mean u. pbrt's LookAt from +z with y up puts the camera's +x along world −x
    // (right = up × view), so the image's first column sees u = 7/8 and its last u = 1/8.
    let columns: Vec<f32> = (0..4).map(|x| (0..4).map(|y| film.pixel(x, y).x).sum::<f32>() / 4.0).collect();
    let expected: Vec<f32> = [7.0, 5.0, 3.0, 1.0].iter().map(|s| 0.1 + 0.8 * s / 8.0).collect();
    assert!(columns.iter().zip(&expected).all(|(a, b)| (a - b).abs() < 0.03), "{columns:?} against {expected:?}");

    let load = |texture: &str, material: &str, test: &str| {
        let text = format!("WorldBegin\nTranslate 1 2 3\n{texture}\nMaterial {material}\nShape \"sphere\"\n");
        let path = scene_dir(test, &[("scene.pbrt", text.as_bytes())]);
        load_scene(&path).map(|loaded| format!("{:?}", loaded.scene.materials()[0]))
    };
    let marble = load(
        r#"Texture "m" "spectrum" "marble" "float scale" 4 "float variation" 0.5 "integer octaves" 5"#,
        r#""diffuse" "texture reflectance" "m""#,
        "marble",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert!(marble.contains("Marble { omega: 0.5, octaves: 5, scale: 4.0, variation: 0.5 }"), "{marble}");
    // The texture's space is the one in force where it is made: the translation's inverse.
    assert!(marble.contains("-1.0, -2.0, -3.0"), "{marble}");
    let wrinkled = load(
        r#"Texture "w" "float" "wrinkled" "float roughness" 0.7"#,
        r#""diffuse" "texture displacement" "w""#,
        "wrinkled",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert!(wrinkled.starts_with("BumpMap") && wrinkled.contains("Wrinkled { omega: 0.7, octaves: 8 }"), "{wrinkled}");
    for (kind, pattern) in [("fbm", "Fbm { omega: 0.5, octaves: 8 }"), ("windy", "Windy")] {
        let material =
            load(&format!(r#"Texture "t" "float" "{kind}""#), r#""diffuse" "texture displacement" "t""#, kind)
                .unwrap_or_else(|e| panic!("{e}"));
        assert!(material.contains(pattern), "{kind}: {material}");
    }
    let dots = load(
        r#"Texture "d" "spectrum" "dots" "float uscale" 8 "rgb inside" [0.8 0.1 0.1] "rgb outside" [0.9 0.9 0.9]"#,
        r#""diffuse" "texture reflectance" "d""#,
        "dots",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert!(dots.contains("Dots") && dots.contains("8.0"), "{dots}");
    let ptex = load(r#"Texture "p" "spectrum" "ptex" "string filename" "a.ptx""#, r#""diffuse""#, "ptex")
        .expect_err("refused");
    assert!(ptex.to_string().contains("scene.pbrt:3:") && ptex.to_string().contains("no Ptex reader"), "{ptex}");
}

/// pbrt's curves load as round tubes of their width: a straight cubic Bézier along x, width
/// 0.5 growing to 1 under a transform that doubles it (widths scale too), is hit from above
/// at its radius; a B-spline and a quadratic load; a flat curve warns that it is rendered
/// round; points that make no segments are refused at their line.
#[test]
fn pbrts_curves_load_as_tubes_of_their_width() {
    let load = |shape: &str, test: &str| {
        let text = format!("WorldBegin\nScale 2 2 2\n{shape}\n");
        let path = scene_dir(test, &[("scene.pbrt", text.as_bytes())]);
        load_scene(&path)
    };
    let loaded = load(
        r#"Shape "curve" "string type" "cylinder" "point3 P" [0 0 0  1 0 0  2 0 0  3 0 0] "float width0" 0.5 "float width1" 1"#,
        "curve",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert!(!loaded.warnings.iter().any(|w| w.contains("curve")), "{:?}", loaded.warnings);
    let Shape::Curves(curves) = &loaded.scene.objects()[0].shape else { panic!("curves") };
    assert_eq!(curves.segment_count(), 1);
    // At x = 3 (u = ½ after the scale by 2) the width is 0.75, scaled to 1.5: radius 0.75.
    // The swept sphere's surface over a radius that grows by k = 0.5 / 6 per unit stands
    // √(1 + k²) farther out than the radius at the point below it.
    let ray = Ray::new(Vec3::new(3.0, 0.0, 10.0), -Vec3::Z);
    let hit = loaded.scene.intersect(&ray).expect("the tube");
    let expected = 0.75 * (1.0f32 + (0.5f32 / 6.0).powi(2)).sqrt();
    assert!((hit.t - (10.0 - expected)).abs() < 1e-4, "{}", hit.t);

    let flat =
        load(r#"Shape "curve" "point3 P" [0 0 0  1 1 0  2 -1 0  3 0 0  4 1 0] "string basis" "bspline""#, "flat")
            .unwrap_or_else(|e| panic!("{e}"));
    assert!(
        flat.warnings.iter().any(|w| w.contains("`flat` curve is rendered as a round tube")),
        "{:?}",
        flat.warnings
    );
    let Shape::Curves(curves) = &flat.scene.objects()[0].shape else { panic!("curves") };
    assert_eq!(curves.segment_count(), 2);
    let quadratic = load(
        r#"Shape "curve" "string type" "cylinder" "integer degree" 2 "point3 P" [0 0 0  1 1 0  2 0 0]"#,
        "quadratic",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert!(matches!(quadratic.scene.objects()[0].shape, Shape::Curves(_)));
    let Err(error) = load(r#"Shape "curve" "point3 P" [0 0 0  1 1 0  2 0 0  3 0 0  4 0 0]"#, "bad-curve") else {
        panic!("five points make no cubic Bézier segments")
    };
    assert!(
        error.to_string().contains("scene.pbrt:3:") && error.to_string().contains("which make no bezier segments"),
        "{error}"
    );
}

/// Textures of textures: `scale` of two textures is their product, `mix` of textures by a
/// textured amount a mix, `directionmix` a mix by |n · dir| with `dir` in the texture's space
/// (turned here by a rotation of 90° about z: +y becomes −x). A floor facing +z under a white
/// sky, dir along +z after no rotation, shows the first texture (an analytic render).
#[test]
fn textures_of_textures_load_and_directionmix_picks_by_the_normal() {
    let text = r#"WorldBegin
Texture "checks" "spectrum" "checkerboard" "float uscale" 4 "float vscale" 4 "rgb tex1" [0.2 0.2 0.2] "rgb tex2" [0.6 0.6 0.6]
Texture "bumps" "float" "fbm"
Texture "scaled" "spectrum" "scale" "texture tex" "checks" "texture scale" "bumps"
Texture "mixed" "spectrum" "mix" "texture tex1" "checks" "rgb tex2" [1 0 0] "texture amount" "bumps"
Rotate 90 0 0 1
Texture "facing" "spectrum" "directionmix" "texture tex1" "checks" "rgb tex2" [0 0 1]
Material "diffuse" "texture reflectance" "scaled"
Shape "sphere"
Material "diffuse" "texture reflectance" "mixed"
Shape "sphere"
Material "diffuse" "texture reflectance" "facing"
Shape "sphere"
"#;
    let path = scene_dir("texture-of-textures", &[("scene.pbrt", text.as_bytes())]);
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let material = |o: usize| format!("{:?}", loaded.scene.materials()[loaded.scene.objects()[o].material as usize]);
    assert!(material(0).contains("Product") && material(0).contains("Noise"), "{}", material(0));
    assert!(material(1).contains("Mix") && material(1).contains("Fbm"), "{}", material(1));
    let facing = material(2);
    assert!(facing.contains("DirectionMix") && facing.contains("direction: Vec3(-1.0, "), "{facing}");

    // dir +z (no rotation) on a floor facing +z: all of the first texture, grey 0.5.
    let floor = r#"LookAt 0 0 5  0 0 0  0 1 0
Camera "orthographic"
Film "rgb" "integer xresolution" 4 "integer yresolution" 4
Integrator "path" "integer maxdepth" 1
Sampler "independent" "integer pixelsamples" 1
WorldBegin
LightSource "infinite" "rgb L" [1 1 1]
Texture "facing" "spectrum" "directionmix" "rgb tex1" [0.5 0.5 0.5] "rgb tex2" [0 0 1] "vector3 dir" [0 0 1]
Material "diffuse" "texture reflectance" "facing"
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point3 P" [-5 -5 0  5 -5 0  5 5 0  -5 5 0]
"#;
    let path = scene_dir("directionmix-floor", &[("scene.pbrt", floor.as_bytes())]);
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let integrator = loaded.render.integrator.create(&loaded.render.integrator_settings).unwrap();
    let settings = RenderSettings { spp: 64, seed: 5, filter: Filter::Box, sampler: SamplerKind::Independent };
    let film = render(&loaded.scene, integrator.as_ref(), &settings, &|| {}).film;
    // Grey within the noise, and no blue of the second texture in it.
    let pixel = film.pixel(1, 2);
    assert!((pixel.x - 0.5).abs() < 0.03 && pixel.z == pixel.x, "{pixel}");
}
