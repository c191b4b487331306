//! Instancing: a mesh placed by transforms shares one BVH (a two-level BVH).

use std::path::Path;
use std::sync::Arc;

use glint_core::integrators::IntegratorKind;
use glint_core::render::{render, RenderSettings};
use glint_core::shapes::Shape;
use glint_scene::native::Format;
use glint_scene::{parse_scene, LoadedScene, Source};

fn load(text: &str, dir: &Path) -> LoadedScene {
    parse_scene(text, Format::Toml, "instances.toml", &Source::directory(dir.to_path_buf()))
        .unwrap_or_else(|e| panic!("{e}"))
}

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
specular = [0.5, 0.5, 0.5]

[[lights]]
type = "directional"
direction = [1, -1, 1]
"#;

fn image(scene: &LoadedScene) -> Vec<glint_core::Rgb> {
    let integrator = IntegratorKind::Raycast.create(&Default::default()).expect("a camera integrator");
    render(&scene.scene, integrator.as_ref(), &RenderSettings { spp: 1, seed: 0, ..Default::default() }, &|| {})
        .film
        .to_rgb()
}

/// The same torus, as an instance and as a baked mesh, under the same transform: one image.
/// (A uniform scale: under a non-uniform one, interpolating transformed vertex normals and
/// transforming interpolated ones differ slightly, and both are reasonable.)
#[test]
fn an_instance_renders_like_the_baked_mesh() {
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let transform = r#"transform = [{ rotate = { axis = [1, 0, 0], angle = 50 } }, { scale = 1.5 }, { translate = [0.3, 0.8, 0] }]"#;
    let instanced = format!(
        "{HEADER}\n[meshes.torus]\nfile = \"meshes/torus.obj\"\n\n[[shapes]]\ntype = \"instance\"\nmesh = \"torus\"\nmaterial = \"gold\"\n{transform}\n"
    );
    let baked = format!(
        "{HEADER}\n[[shapes]]\ntype = \"mesh\"\nfile = \"meshes/torus.obj\"\nmaterial = \"gold\"\n{transform}\n"
    );
    let (a, b) = (image(&load(&instanced, &scenes)), image(&load(&baked, &scenes)));
    let differing = a.iter().zip(&b).filter(|(x, y)| (**x - **y).abs().max_element() > 1e-3).count();
    assert!(differing <= a.len() / 100, "{differing} pixels differ");
    assert!(a.iter().filter(|p| p.x > 0.3).count() > 100, "the torus is not in view");
}

#[test]
fn unknown_mesh_name_is_an_error_with_a_suggestion() {
    let text = format!("{HEADER}\n[meshes.torus]\nfile = \"meshes/torus.obj\"\n\n[[shapes]]\ntype = \"instance\"\nmesh = \"tors\"\nmaterial = \"gold\"\n");
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let e = parse_scene(&text, Format::Toml, "i.toml", &Source::directory(scenes)).err().unwrap();
    assert!(e.to_string().contains("did you mean `torus`?"), "{e}");
}

/// A thousand dragons (871,414 triangles each, 871 million in all) fit in memory because they
/// share one mesh and one BVH, and render.
#[test]
fn a_thousand_dragons_share_one_bvh_and_render() {
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/meshes");
    assert!(
        shared.join("stanford_dragon.ply.gz").exists(),
        "the dragon must be in {} (../shared/meshes)",
        shared.display()
    );
    let mut text = format!("{HEADER}\n[meshes.dragon]\nfile = \"stanford_dragon.ply.gz\"\n");
    text = text
        .replace("position = [0, 2, -6]", "position = [0, 4, -7]")
        .replace("look_at = [0, 0.5, 0]", "look_at = [0, 0, 2]");
    for i in 0..1000 {
        let (x, z) = ((i % 40) as f32 * 0.4 - 8.0, (i / 40) as f32 * 0.4);
        text += &format!(
            "\n[[shapes]]\ntype = \"instance\"\nmesh = \"dragon\"\nmaterial = \"gold\"\ntransform = [{{ scale = 2 }}, {{ rotate = {{ axis = [0, 1, 0], angle = {} }} }}, {{ translate = [{x}, 0, {z}] }}]\n",
            i * 37 % 360
        );
    }
    let scene = load(&text, &shared);
    let objects = scene.scene.objects();
    assert_eq!(objects.len(), 1000);
    let Shape::Instance(first) = &objects[0].shape else { panic!("not an instance") };
    // One geometry: the 1000 objects and nothing else hold it.
    assert_eq!(Arc::strong_count(&first.geometry), 1000);
    assert_eq!(first.geometry.primitive_count(), 871_414);
    let pixels = image(&scene);
    let background = glint_core::Rgb::new(0.2, 0.3, 0.5);
    let covered = pixels.iter().filter(|p| **p != background).count();
    assert!(covered > pixels.len() / 4, "only {covered} pixels show dragons");
}

/// A mesh written in the scene (`data`), as a shape and as an instanced mesh; a mesh with
/// both a file and data, or neither, is refused.
#[test]
fn meshes_given_as_data_are_shapes_and_instances() {
    let data = r#"data = { positions = [[0, 0, 0], [1, 0, 0], [0, 1, 0]], indices = [[0, 1, 2]], uvs = [[0, 0], [1, 0], [0, 1]] }"#;
    let text = format!(
        "{HEADER}\n[meshes.tri]\n{data}\n\n[[shapes]]\ntype = \"mesh\"\nmaterial = \"gold\"\n{data}\n\n[[shapes]]\ntype = \"instance\"\nmesh = \"tri\"\nmaterial = \"gold\"\ntransform = [{{ translate = [0, 0, 2] }}]\n"
    );
    let loaded = load(&text, Path::new("."));
    let scene = &loaded.scene;
    for z in [0.0, 2.0] {
        let ray = glint_core::geometry::Ray::new(glint_core::Vec3::new(0.25, 0.25, z - 1.0), glint_core::Vec3::Z);
        let hit = scene.intersect(&ray).expect("the triangle");
        assert!((hit.t - 1.0).abs() < 1e-5 && (hit.geometry.uv - glam::Vec2::new(0.25, 0.25)).length() < 1e-5);
    }
    let refused = |mesh: &str| {
        let text = format!("{HEADER}\n[[shapes]]\ntype = \"mesh\"\nmaterial = \"gold\"\n{mesh}\n");
        match parse_scene(&text, Format::Toml, "m.toml", &Source::directory(".".into())) {
            Ok(_) => panic!("{mesh}: expected an error"),
            Err(e) => e.to_string(),
        }
    };
    assert!(refused(&format!("file = \"x.obj\"\n{data}")).contains("not both"));
    assert!(refused("").contains("needs a `file`"));
    let short =
        r#"data = { positions = [[0, 0, 0], [1, 0, 0], [0, 1, 0]], indices = [[0, 1, 2]], normals = [[0, 0, 1]] }"#;
    assert!(refused(short).contains("1 normals for 3 positions"));
    let bad = r#"data = { positions = [[0, 0, 0], [1, 0, 0], [0, 1, 0]], indices = [[0, 1, 3]] }"#;
    assert!(refused(bad).contains("refers to a vertex that does not exist"));
}

/// A quad under a transform is stored in world space, as meshes are (its two triangles then
/// sit in the BVH's blocks), and renders as the quad given by its corners in world space.
#[test]
fn a_transformed_quad_is_baked_into_world_space() {
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let placed = format!(
        "{HEADER}\n[[shapes]]\ntype = \"quad\"\nvertices = [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]]\nmaterial = \"gold\"\ntransform = [{{ rotate = {{ axis = [1, 0, 0], angle = 90 }} }}, {{ scale = 2 }}, {{ translate = [0, 0, 0.5] }}]\n"
    );
    // By hand: turning +90° about x takes (x, y, 0) to (x, 0, y); then doubled and moved.
    let world = format!(
        "{HEADER}\n[[shapes]]\ntype = \"quad\"\nvertices = [[-2, 0, -1.5], [2, 0, -1.5], [2, 0, 2.5], [-2, 0, 2.5]]\nmaterial = \"gold\"\n"
    );
    let (placed, world) = (load(&placed, &scenes), load(&world, &scenes));
    let object = &placed.scene.geometry().objects()[0];
    assert!(object.transform.is_none(), "the quad kept its transform");
    let Shape::Mesh(mesh) = &object.shape else { panic!("a quad is a mesh") };
    for (p, q) in mesh.positions.iter().zip([[-2.0, 0.0, -1.5], [2.0, 0.0, -1.5], [2.0, 0.0, 2.5], [-2.0, 0.0, 2.5]]) {
        assert!((*p - glint_core::Vec3::from(q)).abs().max_element() < 1e-6, "corner {p} instead of {q:?}");
    }
    let (a, b) = (image(&placed), image(&world));
    let differing = a.iter().zip(&b).filter(|(x, y)| (**x - **y).abs().max_element() > 1e-3).count();
    assert!(differing <= a.len() / 200, "{differing} pixels differ");
    assert!(a.iter().filter(|p| p.x > 0.3).count() > 100, "the quad is not in view");
}
