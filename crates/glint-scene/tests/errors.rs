//! Bad input gets a clear error naming the file, the line and what was expected.

mod common;

use glint_scene::native::Format;
use glint_scene::{parse_scene, SceneError, Source};

const GOOD: &str = r#"[camera]
position = [0, 0, -5]
look_at = [0, 0, 0]
resolution = [32, 24]

[materials.green]
type = "phong"
diffuse = [0.1, 0.8, 0.1]

[[lights]]
type = "directional"
direction = [0, 0, 1]

[[shapes]]
type = "sphere"
radius = 1
material = "green"
"#;

fn parse(text: &str) -> Result<glint_scene::LoadedScene, SceneError> {
    parse_scene(text, Format::Toml, "test.toml", &Source::directory(std::env::temp_dir()))
}

fn error(text: &str) -> SceneError {
    match parse(text) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => e,
    }
}

fn line_of(e: &SceneError) -> usize {
    e.location.as_ref().unwrap_or_else(|| panic!("no location in: {e}")).line
}

#[test]
fn the_good_scene_loads() {
    let loaded = parse(GOOD).unwrap();
    assert_eq!(loaded.scene.objects().len(), 1);
    assert_eq!((loaded.scene.camera().width, loaded.scene.camera().height), (32, 24));
}

#[test]
fn malformed_toml_names_line_and_column() {
    let e = error(&GOOD.replace("radius = 1", "radius = = 1"));
    assert_eq!(line_of(&e), 16);
    let text = e.to_string();
    assert!(text.starts_with("test.toml:16:"), "{text}");
    assert!(text.contains("radius = = 1") && text.contains('^'), "snippet missing: {text}");
}

#[test]
fn malformed_json_names_line_and_column() {
    let json = "{\n  \"camera\": {\"position\": [0,0,-5], \"look_at\": [0,0,0]},\n  \"shapes\": [\n    {\"type\": \"sphere\" \"radius\": 1}\n  ]\n}";
    let e = parse_scene(json, Format::Json, "s.json", &Source::directory(".".into())).err().unwrap();
    assert_eq!(line_of(&e), 4);
    assert!(e.to_string().contains("expected"), "{e}");
}

#[test]
fn unknown_field_is_an_error_with_a_suggestion_at_its_line() {
    let e = error(&GOOD.replace("radius = 1", "radus = 1"));
    let text = e.to_string();
    assert!(text.contains("unknown field `radus`") && text.contains("did you mean `radius`?"), "{text}");
    assert_eq!(line_of(&e), 16);
}

#[test]
fn unknown_shape_type_suggests_the_closest() {
    let e = error(&GOOD.replace("type = \"sphere\"", "type = \"sphre\""));
    assert!(e.to_string().contains("did you mean `sphere`?"), "{e}");
    assert_eq!(line_of(&e), 15);
}

#[test]
fn unknown_top_level_table_is_an_error() {
    let e = error(&format!("{GOOD}\n[rendr]\nspp = 4\n"));
    assert!(e.to_string().contains("did you mean `render`?"), "{e}");
}

#[test]
fn unknown_material_suggests_the_closest_name() {
    let e = error(&GOOD.replace("material = \"green\"", "material = \"gren\""));
    let text = e.to_string();
    assert!(text.contains("unknown material `gren`") && text.contains("did you mean `green`?"), "{text}");
    assert_eq!(line_of(&e), 17);
}

#[test]
fn unknown_integrator_suggests_the_closest() {
    let e = error(&format!("[render]\nintegrator = \"raycats\"\n{GOOD}"));
    assert!(e.to_string().contains("did you mean `raycast`?"), "{e}");
    assert_eq!(line_of(&e), 2);
}

/// Intersection methods are the core's named choices: an unknown one lists them, with a guess.
#[test]
fn unknown_intersection_method_suggests_the_closest() {
    let e = error(&format!("[intersection]\ntriangle = \"watertite\"\n{GOOD}"));
    let text = e.to_string();
    assert!(text.contains("unknown triangle method `watertite`") && text.contains("`watertight`"), "{text}");
    assert!(text.contains("did you mean `watertight`?"), "{text}");
    assert_eq!(line_of(&e), 2);
}

#[test]
fn bad_numbers_are_refused() {
    for (bad, what) in
        [("radius = -1", "radius"), ("radius = 0", "radius"), ("radius = nan", "radius"), ("radius = inf", "radius")]
    {
        let e = error(&GOOD.replace("radius = 1", bad));
        assert!(e.to_string().contains(what), "{bad}: {e}");
        assert_eq!(line_of(&e), 16, "{bad}");
    }
    let e = error(&GOOD.replace("[0, 0, -5]", "[0, nan, -5]"));
    assert!(e.to_string().contains("finite"), "{e}");
    let e = error(&GOOD.replace("resolution = [32, 24]", "resolution = [0, 24]"));
    assert!(e.to_string().contains("resolution"), "{e}");
    let e = error(&GOOD.replace("resolution = [32, 24]", "resolution = [-3, 24]"));
    assert!(e.location.is_some(), "{e}");
}

#[test]
fn degenerate_shapes_are_refused() {
    let triangle = GOOD
        .replace("type = \"sphere\"\nradius = 1", "type = \"triangle\"\nvertices = [[0, 0, 0], [1, 1, 1], [2, 2, 2]]");
    assert!(error(&triangle).to_string().contains("zero area"));
    let polygon =
        GOOD.replace("type = \"sphere\"\nradius = 1", "type = \"polygon\"\nvertices = [[0, 0, 0], [1, 0, 0]]");
    assert!(error(&polygon).to_string().contains("at least 3 vertices"));
    let aabox = GOOD.replace("type = \"sphere\"\nradius = 1", "type = \"box\"\nmin = [0, 0, 0]\nmax = [1, 0, 1]");
    assert!(error(&aabox).to_string().contains("must exceed"));
    let singular = GOOD.replace("radius = 1", "radius = 1\ntransform = [{ scale = [1, 0, 1] }]");
    assert!(error(&singular).to_string().contains("singular"));
}

#[test]
fn missing_mesh_names_the_path_as_written() {
    let mesh = GOOD.replace("type = \"sphere\"\nradius = 1", "type = \"mesh\"\nfile = \"no/such/bunny.obj\"");
    let e = error(&mesh);
    assert!(e.to_string().contains("`no/such/bunny.obj`"), "{e}");
    assert_eq!(line_of(&e), 16);
}

#[test]
fn corrupt_mesh_is_reported() {
    let dir = std::env::temp_dir().join(format!("glint-corrupt-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("broken.ply"),
        b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nend_header\n\x01",
    )
    .unwrap();
    let mesh = GOOD.replace("type = \"sphere\"\nradius = 1", "type = \"mesh\"\nfile = \"broken.ply\"");
    let e = parse_scene(&mesh, Format::Toml, "t.toml", &Source::directory(dir.clone())).err().unwrap();
    assert!(e.to_string().contains("`broken.ply`"), "{e}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn json_and_toml_read_the_same_scene() {
    let json = r#"{
      "camera": {"position": [0, 0, -5], "look_at": [0, 0, 0], "resolution": [32, 24]},
      "materials": {"green": {"type": "phong", "diffuse": [0.1, 0.8, 0.1]}},
      "lights": [{"type": "directional", "direction": [0, 0, 1]}],
      "shapes": [{"type": "sphere", "radius": 1, "material": "green"}]
    }"#;
    let a = parse_scene(json, Format::Json, "s.json", &Source::directory(".".into())).unwrap();
    let b = parse(GOOD).unwrap();
    assert_eq!(a.scene.camera(), b.scene.camera());
    assert_eq!(a.scene.materials(), b.scene.materials());
    assert_eq!(a.scene.lights().all(), b.scene.lights().all());
    assert_eq!(a.render, b.render);
    // JSON errors about an element name its path, as JSON has no spans to give.
    let bad = json.replace("\"material\": \"green\"", "\"material\": \"gren\"");
    let e = parse_scene(&bad, Format::Json, "s.json", &Source::directory(".".into())).err().unwrap();
    assert!(e.to_string().contains("shapes[0]") && e.to_string().contains("did you mean `green`?"), "{e}");
}

#[test]
fn every_example_scene_loads() {
    let scenes = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let mut count = 0;
    for entry in std::fs::read_dir(&scenes).unwrap() {
        let path = entry.unwrap().path();
        if matches!(path.extension().and_then(|e| e.to_str()), Some("toml" | "json" | "pbrt")) {
            glint_scene::load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
            count += 1;
        }
    }
    assert!(count >= 1);
    glint_scene::default_scene().unwrap();
}

/// Nothing a user writes makes the native reader panic: mutations of a real scene (bytes
/// deleted, duplicated, replaced by TOML's special characters; the file cut short) each give a
/// scene or an error naming the file.
#[test]
fn mutated_native_scenes_never_panic() {
    let scenes = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let original = std::fs::read_to_string(scenes.join("whitted-1980.toml")).unwrap().into_bytes();
    let (mut loaded, mut refused) = (0, 0);
    for bytes in common::mutants(&original, b"[]{}=\",.-#\n0123456789e", 1500, 0x2545_F491_4F6C_DD1D) {
        let Ok(text) = String::from_utf8(bytes) else { continue };
        // A source of its own each, made inside: it records the files it reads.
        let result = std::panic::catch_unwind(|| {
            let source = glint_scene::Source::directory(scenes.clone());
            glint_scene::parse_scene(&text, glint_scene::native::Format::Toml, "mutant.toml", &source)
        });
        match result {
            Ok(Ok(_)) => loaded += 1,
            Ok(Err(e)) => {
                assert!(e.to_string().starts_with("mutant.toml"), "{e}");
                refused += 1;
            }
            Err(_) => panic!("the reader panicked on:\n{text}"),
        }
    }
    assert!(loaded > 0 && refused > 0, "{loaded} loaded, {refused} refused");
}

/// `light_sampling` in `[render]` reaches the scene's area lights; a misspelt value is an
/// error at its line with the closest name.
#[test]
fn light_sampling_is_read_and_checked() {
    use glint_core::lights::TriangleSampling;
    let with = |value: &str| format!("[render]\nlight_sampling = \"{value}\"\n\n{GOOD}");
    let loaded = parse(&with("solid-angle")).unwrap();
    assert_eq!(loaded.scene.lights().triangle_sampling(), TriangleSampling::SolidAngle);
    assert_eq!(parse(GOOD).unwrap().scene.lights().triangle_sampling(), TriangleSampling::Area);
    let e = error(&with("solid-angel"));
    assert!(e.to_string().contains("did you mean `solid-angle`?"), "{e}");
    assert_eq!(line_of(&e), 2);
}

#[test]
fn a_polygon_off_its_plane_is_refused() {
    let flat = GOOD.replace(
        "[[shapes]]\ntype = \"sphere\"\nradius = 1",
        "[[shapes]]\ntype = \"polygon\"\nvertices = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]",
    );
    assert!(parse(&flat).is_ok());
    let bent = flat.replace("[1, 1, 0]", "[1, 1, 0.2]");
    let e = error(&bent);
    assert_eq!(line_of(&e), 16); // the `vertices` line
    assert!(e.to_string().contains("not planar"), "{e}");
}

#[test]
fn a_type_error_in_a_table_points_at_its_key() {
    let e = error(&GOOD.replace("radius = 1", "radius = \"one\""));
    assert_eq!(line_of(&e), 16, "{e}");
    let e = error(&GOOD.replace("radius = 1", "radius = 1\ncenter = [0, 0, true]"));
    assert_eq!(line_of(&e), 17, "{e}");
}

#[test]
fn coordinates_whose_squares_overflow_are_refused() {
    let e = error(&GOOD.replace("radius = 1", "radius = 1e38"));
    assert!(e.to_string().contains("at most 1e18"), "{e}");
    let e = error(&GOOD.replace("position = [0, 0, -5]", "position = [0, 0, -1e38]"));
    assert_eq!(line_of(&e), 2);
    assert!(e.to_string().contains("at most 1e18"), "{e}");
}
