//! CSG in the native format: nodes nested in operands, operands' own materials and
//! transforms, closed meshes through `[meshes]`, and the errors for what bounds no solid.

use std::path::Path;

use glint_core::integrators::IntegratorKind;
use glint_core::render::{render, RenderSettings};
use glint_core::shapes::Shape;
use glint_scene::native::Format;
use glint_scene::{parse_scene, LoadedScene, SceneError, Source};

const HEADER: &str = r#"
[camera]
position = [0, 2, -6]
look_at = [0, 0.5, 0]
resolution = [64, 48]

[environment]
background = [0.2, 0.3, 0.5]
ambient = [0.2, 0.2, 0.2]

[materials.gold]
type = "phong"
diffuse = [0.9, 0.6, 0.2]

[materials.black]
type = "phong"
diffuse = [0.02, 0.02, 0.02]

[[lights]]
type = "directional"
direction = [1, -1, 1]
"#;

fn scenes() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

fn parse(body: &str, dir: &Path) -> Result<LoadedScene, SceneError> {
    parse_scene(&format!("{HEADER}\n{body}"), Format::Toml, "csg.toml", &Source::directory(dir.to_path_buf()))
}

fn error(body: &str) -> SceneError {
    match parse(body, &scenes()) {
        Ok(_) => panic!("expected an error for:\n{body}"),
        Err(e) => e,
    }
}

fn image(scene: &LoadedScene) -> Vec<glint_core::Rgb> {
    let integrator = IntegratorKind::Raycast.create(&Default::default()).expect("a camera integrator");
    render(&scene.scene, integrator.as_ref(), &RenderSettings { spp: 1, seed: 0, ..Default::default() }, &|| {})
        .film
        .to_rgb()
}

#[test]
fn the_example_scene_loads_its_three_pieces() {
    let loaded = glint_scene::load_scene(&scenes().join("csg.toml")).unwrap_or_else(|e| panic!("{e}"));
    let pieces: Vec<&str> =
        loaded.scene.objects().iter().filter(|o| matches!(o.shape, Shape::Csg(_))).map(|o| o.name.as_str()).collect();
    assert_eq!(pieces, ["lens", "die", "hollow block"]);
    let Shape::Csg(die) = &loaded.scene.objects()[2].shape else { unreachable!() };
    assert_eq!(die.solid_count(), 8);
    let pit = loaded.scene.material_names().iter().position(|n| n == "pit").unwrap() as u32;
    assert_eq!((0..8).map(|s| die.solid_material(s)).filter(|&m| m == Some(pit)).count(), 6);
}

/// A box less a ball far from it, placed by the node's transform and its own, renders as the
/// box alone placed by both.
#[test]
fn a_difference_with_nothing_in_common_renders_as_its_first_operand() {
    let turn = r#"{ rotate = { axis = [0, 1, 0], angle = 35 } }"#;
    let node = format!(
        r#"[[shapes]]
type = "csg"
operation = "difference"
material = "gold"
transform = [{turn}]
operands = [
  {{ type = "box", min = [-1, 0, -1], max = [1, 1.5, 1], transform = [{{ translate = [0, 0.1, 0] }}] }},
  {{ type = "sphere", center = [20, 0, 0], radius = 1, material = "black" }},
]
"#
    );
    let plain = format!(
        r#"[[shapes]]
type = "box"
min = [-1, 0, -1]
max = [1, 1.5, 1]
material = "gold"
transform = [{{ translate = [0, 0.1, 0] }}, {turn}]
"#
    );
    let (a, b) = (image(&parse(&node, &scenes()).unwrap()), image(&parse(&plain, &scenes()).unwrap()));
    let differing = a.iter().zip(&b).filter(|(x, y)| (**x - **y).abs().max_element() > 1e-4).count();
    assert!(differing <= 2, "{differing} pixels differ");
    assert!(a.iter().filter(|p| p.x > 0.3).count() > 200, "the box is not in view");
}

/// The torus (a closed mesh) less a ball: the ball's hollow shows in the torus's ring, black.
#[test]
fn a_closed_mesh_is_an_operand_through_its_bvh() {
    let body = r#"
[meshes.torus]
file = "meshes/torus.obj"

[[shapes]]
type = "csg"
operation = "difference"
material = "gold"
operands = [
  { type = "instance", mesh = "torus", transform = [{ rotate = { axis = [1, 0, 0], angle = -60 } }, { translate = [0, 0.8, 0] }] },
  { type = "box", min = [-3, -1, -3], max = [3, 0.8, -0.2], material = "black" },
]
"#;
    let loaded = parse(body, &scenes()).unwrap_or_else(|e| panic!("{e}"));
    let pixels = image(&loaded);
    let gold = pixels.iter().filter(|p| p.x > 0.3 && p.z < 0.5 * p.x).count();
    let black = pixels.iter().filter(|p| p.max_element() < 0.05).count();
    assert!(gold > 50 && black > 20, "gold {gold}, black {black}");
}

#[test]
fn an_open_shape_is_refused_with_the_operand_named() {
    let e = error(
        r#"[[shapes]]
type = "csg"
operation = "union"
material = "gold"
operands = [{ type = "sphere", radius = 1 }, { type = "plane", normal = [0, 1, 0] }]
"#,
    );
    let message = e.to_string();
    assert!(message.contains("unknown variant `plane`") && message.contains("`sphere`"), "{message}");
    assert!(e.location.is_some(), "{message}");
}

#[test]
fn an_open_mesh_is_refused() {
    let dir = std::env::temp_dir().join(format!("glint-csg-open-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("sheet.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n").unwrap();
    let body = r#"
[meshes.sheet]
file = "sheet.obj"

[[shapes]]
type = "csg"
operation = "intersection"
material = "gold"
operands = [{ type = "sphere", radius = 1 }, { type = "instance", mesh = "sheet" }]
"#;
    let e = parse(body, &dir).err().expect("an open mesh is refused");
    let message = e.to_string();
    assert!(message.contains("operands[1]: mesh `sheet` is not closed"), "{message}");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn bad_operations_operand_counts_and_materials_are_named() {
    let node = |operation: &str, operands: &str| {
        format!(
            "[[shapes]]\ntype = \"csg\"\noperation = \"{operation}\"\nmaterial = \"gold\"\noperands = [{operands}]\n"
        )
    };
    let ball = r#"{ type = "sphere", radius = 1 }"#;
    let message = error(&node("unoin", &format!("{ball}, {ball}"))).to_string();
    assert!(message.contains("unknown CSG operation `unoin`") && message.contains("did you mean `union`"), "{message}");
    let message = error(&node("difference", ball)).to_string();
    assert!(message.contains("a difference needs at least two operands, got 1"), "{message}");
    let nested = format!(
        r#"{ball}, {{ type = "csg", operation = "union", operands = [{ball}, {{ type = "box", min = [0, 0, 0], max = [1, 1, 1], material = "golden" }}] }}"#
    );
    let message = error(&node("intersection", &nested)).to_string();
    assert!(message.contains("operands[1]: operands[1]: unknown material `golden`"), "{message}");
    let flat = format!(r#"{ball}, {{ type = "box", min = [0, 0, 0], max = [1, -1, 1] }}"#);
    let message = error(&node("union", &flat)).to_string();
    assert!(message.contains("operands[1]: `max` must exceed `min`"), "{message}");
}
