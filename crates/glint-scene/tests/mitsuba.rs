//! The Mitsuba 3 reader on scene files written for it (tests/mitsuba/): every supported
//! element, its mapping onto glint, an analytic render, and the errors.

mod common;

use std::path::{Path, PathBuf};

use glint_core::camera::Lens;
use glint_core::filter::Filter;
use glint_core::integrators::IntegratorKind;
use glint_core::lights::Light;
use glint_core::materials::{Fresnel, Material};
use glint_core::render::{render, RenderSettings};
use glint_core::textures::Texture;
use glint_core::{Rgb, Vec3};
use glint_scene::{load_scene, load_scene_with};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/mitsuba").join(name)
}

/// Writes `text` as a scene in a fresh directory beside the fixtures' meshes.
fn scene_file(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("glint-mitsuba-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.xml"));
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn every_element_maps_onto_glint() {
    let loaded = load_scene(&fixture("every-element.xml")).unwrap_or_else(|e| panic!("{e}"));
    let scene = &loaded.scene;
    // Film, sampler and integrator: $spp from <default>, Mitsuba's max_depth 5 = glint's 4.
    assert_eq!((scene.camera().width, scene.camera().height), (64, 32));
    assert_eq!(loaded.render.spp, 16);
    assert_eq!(loaded.render.seed, 7);
    assert_eq!(loaded.render.filter, Filter::Tent);
    assert_eq!(loaded.render.integrator, IntegratorKind::Path);
    assert_eq!(loaded.render.integrator_settings.max_depth, 4);
    assert_eq!(loaded.render.integrator_settings.rr_depth, 3);
    // A 60° horizontal field of view on a 2:1 image is 2·atan(tan 30° / 2) vertically.
    let vertical = 2.0 * ((30f32).to_radians().tan() / 2.0).atan().to_degrees();
    assert!((scene.camera().fov_degrees - vertical).abs() < 1e-3, "{}", scene.camera().fov_degrees);
    assert_eq!(scene.camera().position, Vec3::new(0.0, 2.0, -8.0));
    // Shapes: obj, ply, rectangle, cube, two spheres, a disk and a cylinder (the last three
    // meshes).
    assert_eq!(scene.objects().len(), 8);
    // The cube: scaled by ½, turned 30° about y, then moved by (2, 0.5, 0) (Mitsuba's order).
    // Mitsuba's cube is a mesh, stored in world space.
    let cube = scene.objects().iter().find(|o| o.name.contains("`unit-cube`")).expect("the cube keeps its id");
    let glint_core::shapes::Shape::Mesh(mesh) = &cube.shape else { panic!("{:?}", cube.shape) };
    let centre = mesh.positions.iter().sum::<Vec3>() / mesh.positions.len() as f32;
    assert!((centre - Vec3::new(2.0, 0.5, 0.0)).length() < 1e-6);
    for corner in &mesh.positions {
        assert!(((*corner - centre).length() - 0.5 * 3f32.sqrt()).abs() < 1e-5);
    }
    // Lights: point, spot, directional; the constant emitter is the background; the disk
    // emits (an area light of its mesh's triangles).
    let kinds: Vec<&str> = scene.listed_lights().map(Light::kind).collect();
    assert_eq!(kinds, ["point", "spot", "directional"]);
    assert_eq!(scene.environment().background, Rgb::new(0.1, 0.2, 0.3));
    assert!(scene.lights().area_count() > 0);
    if let Light::Spot(spot) = &scene.lights().all()[1] {
        assert!((spot.direction - -Vec3::Y).length() < 1e-6);
        assert!((spot.cos_cone - 30f32.to_radians().cos()).abs() < 1e-6);
        assert!((spot.cos_full - 20f32.to_radians().cos()).abs() < 1e-6);
    } else {
        panic!("the second light is the spot");
    }
    // Materials: the gold conductor, plastic, dielectric and the textured ones are there.
    for name in ["gold", "checkered"] {
        assert!(scene.material_names().iter().any(|n| n == name), "{name}: {:?}", scene.material_names());
    }
    // The stratified sampler maps to glint's; the rough dielectric to rough glass.
    assert_eq!(loaded.render.sampler, glint_core::sampling::SamplerKind::Stratified);
    let warnings = loaded.warnings.join("\n");

    assert!(!warnings.contains("near_clip"), "read, so not reported: {warnings}");
    // Mappings onto the BSDF set, one-sided as Mitsuba's are: gold and a roughconductor (from
    // eta and k, GGX with the same alpha), BK7 in air, the plastic, the rough dielectric.
    let material = |name: &str| {
        let i = scene.material_names().iter().position(|n| n == name).unwrap_or_else(|| panic!("{name}"));
        &scene.materials()[i]
    };
    let constant = |t: &Texture| match t {
        Texture::Constant(c) => *c,
        other => panic!("{other:?}"),
    };
    let (eta, k) = glint_core::materials::named_metal("Au").unwrap();
    match material("gold") {
        Material::Conductor(gold) => {
            assert_eq!((gold.eta, gold.k), (eta, k));
            assert_eq!(constant(&gold.specular), Rgb::ONE);
        }
        other => panic!("gold: {other:?}"),
    }
    let by_line = |line: u32| {
        let name = scene.material_names().iter().find(|n| n.ends_with(&format!("@{line}"))).unwrap();
        material(name)
    };
    match by_line(40) {
        Material::RoughConductor(rough) => {
            assert_eq!((&rough.alpha_u, &rough.alpha_v), (&Texture::from(0.09), &Texture::from(0.09)));
            assert_eq!((rough.conductor.eta, rough.conductor.k), (Rgb::new(0.2, 0.9, 1.1), Rgb::new(3.9, 2.4, 2.2)));
            // Mitsuba's default distribution, read as such (no warning).
            assert_eq!(rough.distribution, glint_core::materials::Distribution::Beckmann);
        }
        other => panic!("{other:?}"),
    }
    assert!(!warnings.contains("Beckmann") && !warnings.contains("beckmann"), "{warnings}");
    match by_line(67) {
        Material::Dielectric(glass) => {
            assert!((glass.eta - 1.5046 / 1.000277).abs() < 1e-6);
            assert_eq!(constant(&glass.specular_transmittance), Rgb::ONE);
        }
        other => panic!("{other:?}"),
    }
    match by_line(76) {
        Material::RoughDielectric(frosted) => {
            assert_eq!((&frosted.alpha_u, &frosted.alpha_v), (&0.2.into(), &0.2.into()))
        }
        other => panic!("{other:?}"),
    }
    match by_line(59) {
        Material::Plastic(plastic) => {
            assert_eq!(constant(&plastic.diffuse), Rgb::new(0.2, 0.4, 0.8));
            assert!((plastic.eta - 1.5 / 1.000277).abs() < 1e-6 && !plastic.nonlinear);
        }
        other => panic!("{other:?}"),
    }
}

/// Mitsuba's wrappers: `twosided` with one or two BSDFs, `blendbsdf`, `mask`, and an area
/// emitter on a BSDF other than diffuse; and `principled` with a textured weight.
#[test]
fn wrappers_map_onto_the_bsdf_set() {
    let path = scene_file(
        "wrappers",
        &format!(
            r#"<scene version="3.0.0">
{SENSOR}
<bsdf type="twosided" id="card"><bsdf type="diffuse" id="red"><rgb name="reflectance" value="0.8, 0.1, 0.1"/></bsdf><bsdf type="diffuse" id="blue"><rgb name="reflectance" value="0.1, 0.1, 0.8"/></bsdf></bsdf>
<bsdf type="blendbsdf" id="worn"><float name="weight" value="0.25"/><bsdf type="conductor"/><ref id="red"/></bsdf>
<bsdf type="mask" id="leaf"><float name="opacity" value="0.3"/><bsdf type="roughplastic"><float name="alpha" value="0.2"/><string name="distribution" value="ggx"/></bsdf></bsdf>
<shape type="sphere"><ref id="card"/></shape>
<shape type="sphere"><ref id="worn"/></shape>
<shape type="sphere"><ref id="leaf"/></shape>
<shape type="sphere"><bsdf type="plastic"/><emitter type="area"><rgb name="radiance" value="2, 2, 2"/></emitter></shape>
<bsdf type="principled" id="paint"><rgb name="base_color" value="0.2, 0.8, 0.1"/><float name="roughness" value="0.15"/><texture name="sheen" type="checkerboard"><float name="color0" value="0.2"/><float name="color1" value="0.9"/></texture><float name="specular" value="0.7"/></bsdf>
<shape type="sphere"><ref id="paint"/></shape>
<bsdf type="principledthin" id="sheet"><float name="spec_trans" value="0.3"/><texture name="diff_trans" type="checkerboard"><float name="color0" value="0.4"/><float name="color1" value="1.4"/></texture><float name="eta" value="1.33"/><float name="diffuse_transmittance_sampling_rate" value="2"/></bsdf>
<shape type="sphere"><ref id="sheet"/></shape>
</scene>
"#
        ),
    );
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let scene = &loaded.scene;
    let material = |name: &str| {
        let i = scene.material_names().iter().position(|n| n == name).unwrap_or_else(|| panic!("{name}"));
        &scene.materials()[i]
    };
    match material("card") {
        Material::TwoSided(t) => {
            assert!(matches!((&t.front, &t.back), (Material::Diffuse(_), Material::Diffuse(_))) && t.front != t.back)
        }
        other => panic!("{other:?}"),
    }
    match material("worn") {
        Material::Blend(b) => {
            assert!(matches!((&b.first, &b.second), (Material::Conductor(_), Material::Diffuse(_))));
            assert_eq!(b.weight, Texture::Constant(Rgb::splat(0.25)));
        }
        other => panic!("{other:?}"),
    }
    match material("leaf") {
        Material::Mask(m) => {
            assert!(matches!(m.material, Material::RoughPlastic(_)) && m.opacity == Texture::Constant(Rgb::splat(0.3)))
        }
        other => panic!("{other:?}"),
    }
    match material("paint") {
        Material::Principled(p) => {
            assert_eq!(p.base_color, Texture::Constant(Rgb::new(0.2, 0.8, 0.1)));
            assert_eq!(p.roughness, Texture::Constant(Rgb::splat(0.15)));
            assert!(matches!(p.sheen, Texture::Checker(_)), "{:?}", p.sheen);
            assert!((p.eta - glint_core::materials::Principled::eta_from_specular(0.7)).abs() < 1e-6);
        }
        other => panic!("{other:?}"),
    }
    match material("sheet") {
        // `diff_trans` keeps its range of [0, 2] (no clamping to a fraction).
        Material::PrincipledThin(p) => {
            assert_eq!((&p.spec_trans, &p.eta), (&Texture::from(0.3), &Texture::from(1.33)));
            assert_eq!(p.diff_trans.max_value(), Rgb::splat(1.4));
            assert_eq!((p.rates.diffuse_transmission, p.rates.diffuse_reflection), (2.0, 1.0));
        }
        other => panic!("{other:?}"),
    }
    let emitters: Vec<&Material> = scene.materials().iter().filter(|m| matches!(m, Material::Emitter(_))).collect();
    match emitters.as_slice() {
        [Material::Emitter(e)] => {
            assert!(
                matches!(e.surface, Material::Plastic(_))
                    && e.radiance == Texture::Constant(Rgb::splat(2.0))
                    && !e.two_sided
            )
        }
        other => panic!("{other:?}"),
    }
    assert!(scene.lights().area_count() > 0, "the emitting plastic is an area light");
}

/// An `area` emitter with a textured `radiance`, on Mitsuba's default diffuse and on a
/// plastic: the texture becomes the emitter's radiance, and the shape an area light.
#[test]
fn a_textured_area_emitter_keeps_its_texture() {
    let path = scene_file(
        "textured-emitter",
        &format!(
            r#"<scene version="3.0.0">
{SENSOR}
<shape type="rectangle"><emitter type="area"><texture name="radiance" type="checkerboard"><rgb name="color0" value="1, 2, 3"/></texture></emitter></shape>
<shape type="sphere"><bsdf type="plastic"/><emitter type="area"><texture name="radiance" type="checkerboard"/></emitter></shape>
</scene>
"#
        ),
    );
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let scene = &loaded.scene;
    let emitters: Vec<&Material> = scene.materials().iter().filter(|m| matches!(m, Material::Emitter(_))).collect();
    assert_eq!(emitters.len(), 2, "{emitters:?}");
    for m in emitters {
        let Material::Emitter(e) = m else { unreachable!() };
        let Texture::Checker(checker) = &e.radiance else { panic!("{:?}", e.radiance) };
        assert!(checker.even == Rgb::new(1.0, 2.0, 3.0) || checker.even == Rgb::splat(0.4), "{checker:?}");
    }
    assert_eq!(scene.lights().area_count(), 2 + 1, "the rectangle's two triangles and the sphere");
}

/// A mesh file without normals is shaded smooth, its normals made as Mitsuba makes them;
/// `face_normals` keeps it flat.
#[test]
fn meshes_without_normals_get_mitsubas_smooth_normals() {
    let scene_with = |face_normals: bool| {
        let path = scene_file(
            &format!("normals-{face_normals}"),
            &format!(
                "<scene version=\"3.0.0\">\n{SENSOR}\n<shape type=\"obj\"><string name=\"filename\" value=\"pyramid.obj\"/><boolean name=\"face_normals\" value=\"{face_normals}\"/></shape>\n</scene>\n"
            ),
        );
        std::fs::write(
            path.with_file_name("pyramid.obj"),
            "v 0 0 0\nv 2 0 0\nv 0 1 0\nv 0 0 3\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
        )
        .unwrap();
        let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
        match &loaded.scene.objects()[0].shape {
            glint_core::shapes::Shape::Mesh(m) => m.normals.clone(),
            other => panic!("{other:?}"),
        }
    };
    let normals = scene_with(false).expect("made");
    let corner = normals[0];
    assert!((corner - Vec3::splat(-1.0 / 3f32.sqrt())).length() < 1e-5, "{corner}");
    assert!(scene_with(true).is_none());
}

/// `serialized` meshes with `shape_index` (the suite's `matpreview.serialized`, whose second
/// mesh has 3936 triangles, as Mitsuba 3.9 reads it); `shape_index` on another format is
/// refused.
#[test]
fn serialized_meshes_load_by_shape_index() {
    let file =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/mitsuba-data/common/meshes/matpreview.serialized");
    assert!(file.exists(), "{} must be there (../shared/mitsuba-data)", file.display());
    let path = scene_file(
        "serialized",
        &format!(
            "<scene version=\"3.0.0\">\n{SENSOR}\n<shape type=\"serialized\"><string name=\"filename\" value=\"{}\"/><integer name=\"shape_index\" value=\"1\"/></shape>\n</scene>\n",
            file.display()
        ),
    );
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let meshes: Vec<usize> = loaded
        .scene
        .objects()
        .iter()
        .filter_map(|o| match &o.shape {
            glint_core::shapes::Shape::Mesh(m) => Some(m.triangle_count()),
            _ => None,
        })
        .collect();
    assert_eq!(meshes, [3936]);
    let e = error_of(
        "index-on-obj",
        &format!("<scene version=\"3.0.0\">\n{SENSOR}\n<shape type=\"obj\"><string name=\"filename\" value=\"x.obj\"/><integer name=\"shape_index\" value=\"1\"/></shape>\n</scene>\n"),
    );
    assert!(e.contains("index-on-obj.xml:3:") && e.contains("`shape_index` belongs to serialized meshes"), "{e}");
}

/// `mesh_attribute` textures read a PLY file's colours where a ray hits: per face as they
/// are, per vertex interpolated; a name no mesh has is refused at the texture's line.
#[test]
fn mesh_attribute_textures_read_the_ply_files_values_where_rays_hit() {
    // A quad in z = 0 facing the camera (at z = −5, looking along +z), corners red, green,
    // blue and white; its two triangles' face colours differ.
    let ply = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty float color_0\nproperty float color_1\nproperty float color_2\nelement face 2\nproperty list uchar int vertex_indices\nproperty float color_0\nproperty float color_1\nproperty float color_2\nend_header\n-1 -1 0 1 0 0\n1 -1 0 0 1 0\n1 1 0 0 0 1\n-1 1 0 1 1 1\n3 0 1 2 0.1 0.2 0.3\n3 0 2 3 0.6 0.5 0.4\n";
    let scene_with = |attribute: &str| {
        let path = scene_file(
            &format!("attributes-{attribute}"),
            &format!(
                r#"<scene version="3.0.0">
<sensor type="perspective"><transform name="to_world"><lookat origin="0, 0, -5" target="0, 0, 0" up="0, 1, 0"/></transform><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>
<texture type="mesh_attribute" id="tex"><string name="name" value="{attribute}"/></texture>
<bsdf type="diffuse" id="painted"><ref name="reflectance" id="tex"/></bsdf>
<shape type="ply"><string name="filename" value="quad.ply"/><ref id="painted"/></shape>
</scene>
"#
            ),
        );
        std::fs::write(path.with_file_name("quad.ply"), ply).unwrap();
        load_scene(&path)
    };
    let colour_at = |scene: &glint_core::scene::Scene, x: f32, y: f32| {
        let ray = glint_core::geometry::Ray::new(Vec3::new(x, y, -5.0), Vec3::Z);
        let hit = scene.intersect(&ray).expect("the quad");
        scene.materials()[hit.material as usize].whitted(&hit.texture_query(scene.geometry()), true).diffuse
    };
    let faces = scene_with("face_color").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(colour_at(&faces.scene, 0.5, -0.5), Rgb::new(0.1, 0.2, 0.3));
    assert_eq!(colour_at(&faces.scene, -0.5, 0.5), Rgb::new(0.6, 0.5, 0.4));
    let vertices = scene_with("vertex_color").unwrap_or_else(|e| panic!("{e}"));
    // (0.5, −0.5) on triangle 0, 1, 2: barycentrics ½ of corner 1 and ¼ each of corners 0, 2.
    let mixed = colour_at(&vertices.scene, 0.5, -0.5);
    assert!((mixed - Rgb::new(0.25, 0.5, 0.25)).abs().max_element() < 1e-5, "{mixed}");
    let e = scene_with("vertex_colour").err().unwrap().to_string();
    assert!(
        e.contains("attributes-vertex_colour.xml:3:")
            && e.contains("no mesh of the scene has the attribute `vertex_colour`"),
        "{e}"
    );
}

/// `normalmap` around a BSDF, its bitmap read raw: the stored (128, 128, 255) is the flat
/// normal (0, 0, 1) after 2·rgb − 1, up to 8-bit rounding.
#[test]
fn a_normal_map_wraps_its_bsdf_and_reads_its_bitmap_raw() {
    let path = scene_file(
        "normalmap",
        &format!(
            r#"<scene version="3.0.0">
{SENSOR}
<bsdf type="normalmap" id="bumpy"><texture name="normalmap" type="bitmap"><string name="filename" value="flat.png"/><boolean name="raw" value="true"/></texture><bsdf type="diffuse"/></bsdf>
<shape type="sphere"><ref id="bumpy"/></shape>
</scene>
"#
        ),
    );
    let png = path.with_file_name("flat.png");
    image::RgbImage::from_raw(1, 1, vec![128, 128, 255]).unwrap().save(&png).unwrap();
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let scene = &loaded.scene;
    let i = scene.material_names().iter().position(|n| n == "bumpy").unwrap();
    match &scene.materials()[i] {
        Material::NormalMap(m) => {
            assert!(matches!(m.material, Material::Diffuse(_)));
            let rgb = m.normals.evaluate(&Default::default());
            assert!((2.0 * rgb - Rgb::ONE - Rgb::Z).abs().max_element() < 0.01, "{rgb}");
        }
        other => panic!("{other:?}"),
    }
}

/// `bumpmap` with its height texture under any name, before or after its BSDF, either of them
/// by reference; `scale` read. Two BSDFs or no texture is an error at the element.
#[test]
fn a_bump_map_wraps_its_bsdf_with_its_height_texture() {
    let path = scene_file(
        "bumpmap",
        &format!(
            r#"<scene version="3.0.0">
{SENSOR}
<texture type="bitmap" id="heights"><string name="filename" value="ramp.png"/><boolean name="raw" value="true"/></texture>
<bsdf type="diffuse" id="paper"/>
<bsdf type="bumpmap" id="bumpy"><float name="scale" value="0.02"/><bsdf type="roughplastic"><string name="distribution" value="ggx"/></bsdf><texture name="anything" type="bitmap"><string name="filename" value="ramp.png"/><boolean name="raw" value="true"/></texture></bsdf>
<bsdf type="bumpmap" id="referring"><ref name="tiles" id="heights"/><ref id="paper"/></bsdf>
<shape type="sphere"><ref id="bumpy"/></shape>
<shape type="sphere"><ref id="referring"/><point name="center" x="3" y="0" z="0"/></shape>
</scene>
"#
        ),
    );
    image::RgbImage::from_raw(2, 1, vec![0, 0, 0, 255, 255, 255])
        .unwrap()
        .save(path.with_file_name("ramp.png"))
        .unwrap();
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let scene = &loaded.scene;
    let material = |name: &str| &scene.materials()[scene.material_names().iter().position(|n| n == name).unwrap()];
    let Material::BumpMap(m) = material("bumpy") else { panic!("{:?}", material("bumpy")) };
    assert!(matches!(m.material, Material::RoughPlastic(_)) && m.scale == 0.02, "{m:?}");
    // Raw: the white texel is 1, so the ramp's slope at the middle is 2 per unit of u.
    let query = glint_core::textures::TextureQuery { uv: glam::Vec2::new(0.5, 0.5), ..Default::default() };
    assert!((m.height.luminance_gradient(&query) - glam::Vec2::new(2.0, 0.0)).length() < 1e-5);
    let Material::BumpMap(m) = material("referring") else { panic!("{:?}", material("referring")) };
    assert!(matches!(m.material, Material::Diffuse(_)) && m.scale == 1.0, "{m:?}");

    let broken = scene_file(
        "bumpmap-broken",
        &format!("<scene version=\"3.0.0\">\n{SENSOR}\n<bsdf type=\"bumpmap\" id=\"b\"><bsdf type=\"diffuse\"/></bsdf>\n<shape type=\"sphere\"><ref id=\"b\"/></shape>\n</scene>\n"),
    );
    let e = load_scene(&broken).err().unwrap().to_string();
    assert!(e.contains("bumpmap-broken") && e.contains("one <texture>"), "{e}");
}

#[test]
fn command_line_parameters_override_defaults() {
    let defines = [("spp".to_string(), "3".to_string()), ("res".to_string(), "20".to_string())];
    let loaded = load_scene_with(&fixture("every-element.xml"), &defines).unwrap();
    assert_eq!(loaded.render.spp, 3);
    assert_eq!(loaded.scene.camera().width, 20);
    let err = load_scene_with(&fixture("every-element.xml"), &[("spp".into(), "many".into())]).err().unwrap();
    assert!(err.to_string().contains("`many` is not an integer"), "{err}");
}

#[test]
fn a_diffuse_rectangle_under_a_constant_sky_reflects_albedo_times_sky() {
    let loaded = load_scene(&fixture("furnace.xml")).unwrap();
    let integrator = loaded.render.integrator.create(&loaded.render.integrator_settings).expect("path");
    let settings = RenderSettings { spp: 64, seed: 1, filter: loaded.render.filter, sampler: loaded.render.sampler };
    let image = render(&loaded.scene, integrator.as_ref(), &settings, &|| {}).film.to_rgb();
    let mean = image.iter().sum::<Rgb>() / image.len() as f32;
    let expected = Rgb::new(0.8, 0.4, 0.2) * 0.25;
    assert!(((mean - expected) / expected).abs().max_element() < 0.01, "{mean} vs {expected}");
}

fn error_of(name: &str, text: &str) -> String {
    match load_scene(&scene_file(name, text)) {
        Ok(_) => panic!("{name}: expected an error"),
        Err(e) => e.to_string(),
    }
}

const SENSOR: &str = r#"<sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>"#;

#[test]
fn errors_name_the_file_line_and_what_was_expected() {
    // Malformed XML: line and column.
    let e = error_of("malformed", "<scene version=\"3.0.0\">\n  <shape type=\"sphere\">\n</scene>\n");
    assert!(e.contains("malformed.xml:3:") && e.contains("malformed XML"), "{e}");
    // An unsupported plugin, at its line.
    let e = error_of(
        "plugin",
        &format!("<scene version=\"3.0.0\">\n{SENSOR}\n<shape type=\"hair\">\n</shape>\n</scene>\n"),
    );
    assert!(e.contains("plugin.xml:3:") && e.contains("<shape type=\"hair\"> is not supported"), "{e}");
    // A missing mesh file.
    let e = error_of(
        "missing",
        &format!(
            "<scene version=\"3.0.0\">\n{SENSOR}\n<shape type=\"obj\">\n<string name=\"filename\" value=\"nowhere.obj\"/>\n</shape>\n</scene>\n"
        ),
    );
    assert!(e.contains("missing.xml:3:") && e.contains("nowhere.obj"), "{e}");
    // A missing include.
    let e = error_of("include", "<scene version=\"3.0.0\">\n<include filename=\"gone.xml\"/>\n</scene>\n");
    assert!(e.contains("include.xml:2:") && e.contains("gone.xml"), "{e}");
    // An undefined parameter.
    let e = error_of("param", "<scene version=\"3.0.0\">\n<integrator type=\"$kind\"/>\n</scene>\n");
    assert!(e.contains("param.xml:2:") && e.contains("`$kind` is not defined"), "{e}");
    // An unknown reference, with a suggestion.
    let e = error_of(
        "ref",
        &format!(
            "<scene version=\"3.0.0\">\n{SENSOR}\n<bsdf type=\"diffuse\" id=\"white\"/>\n<shape type=\"sphere\">\n<ref id=\"whte\"/>\n</shape>\n</scene>\n"
        ),
    );
    assert!(e.contains("ref.xml:5:") && e.contains("no object with id `whte`") && e.contains("white"), "{e}");
    // An environment map without its file.
    let e = error_of("envmap", &format!("<scene version=\"3.0.0\">\n{SENSOR}\n<emitter type=\"envmap\"/>\n</scene>\n"));
    assert!(e.contains("envmap.xml:3:") && e.contains("filename"), "{e}");
    // Media glint does not have: errors at their lines.
    let medium = |name: &str, inside: &str| {
        error_of(
            name,
            &format!(
                "<scene version=\"3.0.0\">\n{SENSOR}\n<shape type=\"cube\">\n<bsdf type=\"null\"/>\n{inside}\n</shape>\n</scene>\n"
            ),
        )
    };
    let e = medium("medium-kind", "<medium type=\"foggy\" name=\"interior\"/>");
    assert!(e.contains("medium-kind.xml:5:") && e.contains("<medium type=\"foggy\"> is not supported"), "{e}");
    let e = medium("phase", "<medium type=\"homogeneous\" name=\"interior\">\n<phase type=\"rayleigh\"/>\n</medium>");
    assert!(e.contains("phase.xml:6:") && e.contains("<phase type=\"rayleigh\"> is not supported"), "{e}");
    let e = medium(
        "volume",
        "<medium type=\"heterogeneous\" name=\"interior\">\n<volume type=\"gridvolume\" name=\"sigma_t\">\n<string name=\"filename\" value=\"a.vol\"/>\n<string name=\"wrap_mode\" value=\"repeat\"/>\n</volume>\n</medium>",
    );
    assert!(e.contains("volume.xml:6:") && e.contains("`wrap_mode` `repeat` is not supported"), "{e}");
    let e = medium(
        "homogeneous-grid",
        "<medium type=\"homogeneous\" name=\"interior\">\n<volume type=\"gridvolume\" name=\"sigma_t\">\n<string name=\"filename\" value=\"a.vol\"/>\n</volume>\n</medium>",
    );
    assert!(e.contains("homogeneous-grid.xml:5:") && e.contains("is a constant, not a grid volume"), "{e}");
    let e = medium("side", "<medium type=\"homogeneous\" name=\"inside\"/>");
    assert!(e.contains("side.xml:5:") && e.contains("`interior` or `exterior`"), "{e}");
    // Mitsuba's flip_normals would swap the medium's sides: refused.
    let e = medium(
        "flipped",
        "<boolean name=\"flip_normals\" value=\"true\"/>\n<medium type=\"homogeneous\" name=\"interior\"/>",
    );
    assert!(e.contains("flipped.xml:3:") && e.contains("medium's boundary"), "{e}");
    // Not Mitsuba 3.
    let e = error_of("version", "<scene version=\"0.6.0\">\n</scene>\n");
    assert!(e.contains("version 0.6.0"), "{e}");
    // A sensor is required.
    let e = error_of("nosensor", "<scene version=\"3.0.0\">\n</scene>\n");
    assert!(e.contains("no <sensor>"), "{e}");
}

/// Mitsuba's media through the XML reader: an orthographic view down through a cube (null
/// walls, [−1, 1]³) of absorbing medium at a white sky, so each pixel sees the transmittance
/// of its column. A homogeneous medium fills the cube: exp(−2 σ_t scale). A heterogeneous
/// medium with a constant σ_t is, as in Mitsuba, a constvolume over the unit cube [0, 1]³: a
/// quarter of the view sees exp(−σ_t scale), the rest the sky unattenuated.
#[test]
fn media_read_from_mitsuba_xml_keep_mitsubas_semantics() {
    let scene = |name: &str, medium: &str| {
        scene_file(
            name,
            &format!(
                r#"<scene version="3.0.0">
    <integrator type="volpath"><integer name="max_depth" value="-1"/></integrator>
    <sensor type="orthographic">
        <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film>
    </sensor>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
    {medium}
    <shape type="cube">
        <bsdf type="null"/>
        <ref name="interior" id="fog"/>
    </shape>
</scene>"#
            ),
        )
    };
    let mean_of = |path: &Path| {
        let loaded = load_scene(path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(loaded.render.integrator, IntegratorKind::VolPath);
        let integrator = loaded.render.integrator.create(&loaded.render.integrator_settings).unwrap();
        let settings =
            RenderSettings { spp: 64, seed: 1, filter: loaded.render.filter, sampler: loaded.render.sampler };
        let image = render(&loaded.scene, integrator.as_ref(), &settings, &|| {}).film.to_rgb();
        image.iter().sum::<Rgb>() / image.len() as f32
    };
    let homogeneous = scene(
        "homogeneous",
        r#"<medium type="homogeneous" id="fog">
        <rgb name="sigma_t" value="0.25, 0.5, 1"/><float name="albedo" value="0"/><float name="scale" value="0.5"/>
        <phase type="isotropic"/>
    </medium>"#,
    );
    let mean = mean_of(&homogeneous);
    let expected = Rgb::new((-0.25f32).exp(), (-0.5f32).exp(), (-1.0f32).exp());
    assert!((mean - expected).abs().max_element() < 2e-3, "homogeneous: {mean} vs {expected}");
    let heterogeneous = scene(
        "heterogeneous",
        r#"<medium type="heterogeneous" id="fog">
        <rgb name="sigma_t" value="0.5, 1, 2"/><float name="albedo" value="0"/>
        <phase type="hg"><float name="g" value="0.3"/></phase>
    </medium>"#,
    );
    let mean = mean_of(&heterogeneous);
    let expected = Rgb::new((-0.5f32).exp(), (-1.0f32).exp(), (-2.0f32).exp()) * 0.25 + Rgb::splat(0.75);
    assert!((mean - expected).abs().max_element() < 5e-3, "heterogeneous: {mean} vs {expected}");
}

/// A film's crop (`crop_offset_x`, `crop_offset_y`, `crop_width`, `crop_height`) renders that
/// window of it, as Mitsuba does; one reaching past the film is refused at the film.
#[test]
fn a_films_crop_is_the_cameras_crop_window() {
    let film = |crop: &str| {
        format!(
            r#"<scene version="3.0.0"><sensor type="perspective"><film type="hdrfilm"><integer name="width" value="40"/><integer name="height" value="30"/>{crop}</film></sensor>
<emitter type="constant"/></scene>"#
        )
    };
    let crop = r#"<integer name="crop_offset_x" value="5"/><integer name="crop_offset_y" value="10"/><integer name="crop_width" value="20"/><integer name="crop_height" value="15"/>"#;
    let loaded = load_scene(&scene_file("crop", &film(crop))).unwrap_or_else(|e| panic!("{e}"));
    let camera = loaded.scene.camera();
    assert_eq!(camera.crop_window(), Some((5, 10, 25, 25)));
    assert_eq!((camera.width, camera.height), (20, 15));
    assert_eq!(camera.film_resolution(), (40, 30));
    let past = r#"<integer name="crop_offset_x" value="30"/><integer name="crop_width" value="20"/>"#;
    let error = load_scene(&scene_file("crop-past", &film(past))).err().expect("refused").to_string();
    assert!(error.contains("crop-past.xml:1:") && error.contains("reaches past its 40×30 pixels"), "{error}");
}

#[test]
fn unknown_properties_are_reported_not_silently_dropped() {
    let path = scene_file(
        "unused",
        &format!(
            "<scene version=\"3.0.0\">\n{SENSOR}\n<shape type=\"sphere\">\n<bsdf type=\"diffuse\">\n<float name=\"sheen\" value=\"1\"/>\n</bsdf>\n</shape>\n</scene>\n"
        ),
    );
    let loaded = load_scene(&path).unwrap();
    let warnings = loaded.warnings.join("\n");
    assert!(warnings.contains("unused.xml:5:") && warnings.contains("sheen"), "{warnings}");
}

/// The other sensors, samplers, integrators and emitter placements, one small scene each.
#[test]
fn sensor_sampler_integrator_and_emitter_variants() {
    let scene_with = |name: &str, sensor: &str, rest: &str| {
        let text = format!(
            "<scene version=\"3.0.0\">\n<sensor type=\"{sensor}\"><film type=\"hdrfilm\"><integer name=\"width\" value=\"8\"/><integer name=\"height\" value=\"8\"/></film></sensor>\n{rest}\n<shape type=\"sphere\"/>\n</scene>\n"
        );
        load_scene(&scene_file(name, &text))
    };
    // A thin lens needs its focus distance; then it is glint's thin lens.
    let e = scene_with("thinlens-nofocus", "thinlens", "").err().unwrap().to_string();
    assert!(e.contains("thinlens-nofocus.xml:2:") && e.contains("focus_distance"), "{e}");
    let thin = load_scene(&scene_file(
        "thinlens",
        r#"<scene version="3.0.0"><sensor type="thinlens"><float name="aperture_radius" value="0.2"/><float name="focus_distance" value="4"/><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor></scene>"#,
    ))
    .unwrap();
    assert_eq!(thin.scene.camera().lens, Lens::Thin { radius: 0.2, focus_distance: 4.0 });
    // Orthographic: the view's height is twice to_world's scale along y.
    let ortho = load_scene(&scene_file(
        "ortho",
        r#"<scene version="3.0.0"><sensor type="orthographic"><transform name="to_world"><scale value="3"/><lookat origin="0,0,-5" target="0,0,0" up="0,1,0"/></transform><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor></scene>"#,
    ))
    .unwrap();
    assert_eq!(ortho.scene.camera().lens, Lens::Orthographic { height: 6.0 });
    let e = scene_with("pano", "spherical", "").err().unwrap().to_string();
    assert!(e.contains("pano.xml:2:") && e.contains("spherical"), "{e}");
    for (kind, expected, depth) in [
        ("direct", IntegratorKind::Path, 1),
        ("ptracer", IntegratorKind::Light, 2),
        ("volpath", IntegratorKind::VolPath, 2),
        ("volpathmis", IntegratorKind::VolPath, 2),
        ("sppm", IntegratorKind::Sppm, 2),
    ] {
        let loaded = scene_with(
            kind,
            "perspective",
            &format!("<integrator type=\"{kind}\"><integer name=\"max_depth\" value=\"3\"/></integrator>"),
        )
        .unwrap();
        assert_eq!(loaded.render.integrator, expected, "{kind}");
        assert_eq!(loaded.render.integrator_settings.max_depth, depth, "{kind}");
    }
    let e = scene_with("bdpt", "perspective", "<integrator type=\"bdpt\"/>").err().unwrap().to_string();
    assert!(e.contains("bdpt.xml:3:") && e.contains("<integrator type=\"bdpt\"> is not supported"), "{e}");
    let ld = scene_with("ld", "perspective", "").unwrap();
    assert!(ld.warnings.is_empty(), "{:?}", ld.warnings);
    // A point light placed by to_world, a directional light along to_world's +z.
    let lights = scene_with(
        "lights",
        "perspective",
        r#"<emitter type="point"><transform name="to_world"><translate x="1" y="2" z="3"/></transform></emitter>
<emitter type="directional"><transform name="to_world"><lookat origin="0,0,0" target="0,-1,0" up="0,0,1"/></transform></emitter>"#,
    )
    .unwrap();
    match (&lights.scene.lights().all()[0], &lights.scene.lights().all()[1]) {
        (Light::Point(p), Light::Directional(d)) => {
            assert_eq!(p.position, Vec3::new(1.0, 2.0, 3.0));
            assert!((d.direction - -Vec3::Y).length() < 1e-6);
        }
        other => panic!("{other:?}"),
    }
}

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

#[test]
fn environment_maps_from_mitsuba_and_native_scenes() {
    let xml = scene_file(
        "envmap-ok",
        &format!(
            "<scene version=\"3.0.0\">\n{SENSOR}\n<emitter type=\"envmap\">\n<string name=\"filename\" value=\"sky.exr\"/>\n<float name=\"scale\" value=\"2\"/>\n<transform name=\"to_world\"><rotate y=\"1\" angle=\"90\"/></transform>\n</emitter>\n</scene>\n"
        ),
    );
    write_sky(xml.parent().unwrap());
    let loaded = load_scene(&xml).unwrap_or_else(|e| panic!("{e}"));
    let env = &loaded.scene.environment();
    assert!(env.map.is_some());
    // Up is the warm half, scaled by 2; down the dark one.
    assert_eq!(env.radiance(Vec3::Y), Rgb::new(4.0, 3.0, 2.0));
    assert_eq!(env.radiance(-Vec3::Y), Rgb::splat(0.2));
    // A mirroring to_world is refused at its line.
    let bad = scene_file(
        "envmap-mirror",
        &format!(
            "<scene version=\"3.0.0\">\n{SENSOR}\n<emitter type=\"envmap\">\n<string name=\"filename\" value=\"sky.exr\"/>\n<transform name=\"to_world\"><scale x=\"-1\"/></transform>\n</emitter>\n</scene>\n"
        ),
    );
    let e = load_scene(&bad).err().unwrap().to_string();
    assert!(e.contains("envmap-mirror.xml:3:") && e.contains("rotation"), "{e}");
    // The native format: [environment] map, map_scale, map_transform.
    let dir = xml.parent().unwrap();
    let toml = dir.join("sky.toml");
    std::fs::write(
        &toml,
        "[camera]\nposition = [0, 0, -5]\nlook_at = [0, 0, 0]\n[environment]\nmap = \"sky.exr\"\nmap_scale = 0.5\nmap_transform = [{ rotate = { axis = [1, 0, 0], angle = 180 } }]\n",
    )
    .unwrap();
    let native = load_scene(&toml).unwrap_or_else(|e| panic!("{e}"));
    // Turned upside down: the warm half is below.
    assert_eq!(native.scene.environment().radiance(-Vec3::Y), Rgb::new(1.0, 0.75, 0.5));
}

/// The native `metal` material: by name or by η and k, with clear errors.
#[test]
fn native_metals_by_name_or_index() {
    let dir = scene_file("metal", "").parent().unwrap().to_path_buf();
    let write = |name: &str, material: &str| {
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(
            &path,
            format!("[camera]\nposition = [0, 0, -5]\nlook_at = [0, 0, 0]\n\n[materials.m]\ntype = \"metal\"\n{material}\n\n[[shapes]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"m\"\n"),
        )
        .unwrap();
        load_scene(&path)
    };
    let copper = write("copper", "metal = \"Cu\"\nroughness = 0.2").unwrap();
    match &copper.scene.materials()[0] {
        Material::Phong(p) => {
            let (eta, k) = glint_core::materials::named_metal("Cu").unwrap();
            assert_eq!(p.fresnel, Fresnel::Conductor { eta, k });
            assert_eq!(p.roughness, 0.2);
        }
        other => panic!("{other:?}"),
    }
    assert!(write("by-index", "eta = [0.2, 0.9, 1.1]\nk = [3.9, 2.4, 2.2]").is_ok());
    let e = write("typo", "metal = \"Cuu\"").err().unwrap().to_string();
    assert!(e.contains("typo.toml:7:") && e.contains("unknown metal `Cuu`") && e.contains("`Cu`"), "{e}");
    let e = write("both", "metal = \"Au\"\neta = [1, 1, 1]\nk = [1, 1, 1]").err().unwrap().to_string();
    assert!(e.contains("either `metal`"), "{e}");
}

/// Nothing a user writes makes the reader panic: thousands of mutations of the every-element
/// scene (bytes deleted, duplicated, replaced by XML's special characters; the file cut short)
/// each give a scene or an error.
#[test]
fn mutated_scenes_never_panic() {
    let dir = std::env::temp_dir().join(format!("glint-mitsuba-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for file in ["tri.obj", "tri.ply", "materials.xml"] {
        std::fs::copy(fixture(file), dir.join(file)).unwrap();
    }
    let original = std::fs::read(fixture("every-element.xml")).unwrap();
    let path = dir.join("mutant.xml");
    let (mut loaded, mut refused) = (0, 0);
    for bytes in common::mutants(&original, b"<>/\"=&$ 0-9.e\n", 1500, 0x9E37_79B9_7F4A_7C15) {
        std::fs::write(&path, &bytes).unwrap();
        match std::panic::catch_unwind(|| load_scene(&path)) {
            Ok(Ok(_)) => loaded += 1,
            Ok(Err(e)) => {
                assert!(e.to_string().contains("mutant.xml") || e.to_string().contains(".xml"), "{e}");
                refused += 1;
            }
            Err(_) => panic!("the reader panicked on:\n{}", String::from_utf8_lossy(&bytes)),
        }
    }
    assert!(loaded > 0 && refused > 0, "{loaded} loaded, {refused} refused");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn deeply_nested_xml_is_refused_not_a_stack_overflow() {
    let depth = 10_000;
    let text = format!(
        "<scene version=\"3.0.0\">\n{SENSOR}\n{}{}</scene>\n",
        "<shape type=\"sphere\">".repeat(depth),
        "</shape>".repeat(depth)
    );
    let e = error_of("nested", &text);
    assert!(e.contains("nested.xml:3:") && e.contains("nested more than 256 deep"), "{e}");
}

#[test]
fn a_define_no_default_declares_is_reported_with_a_suggestion() {
    let defines = [("sppp".to_string(), "2".to_string())];
    let loaded = load_scene_with(&fixture("every-element.xml"), &defines).unwrap();
    let warning = loaded.warnings.iter().find(|w| w.contains("-D sppp")).expect("a warning for -D sppp");
    assert!(warning.contains("did you mean `spp`"), "{warning}");
    // A declared one is not reported.
    let loaded = load_scene_with(&fixture("every-element.xml"), &[("spp".into(), "2".into())]).unwrap();
    assert!(!loaded.warnings.iter().any(|w| w.contains("-D spp")), "{:?}", loaded.warnings);
}

#[test]
fn an_out_of_range_fov_is_reported_as_given() {
    let sensor = r#"<sensor type="perspective"><float name="fov" value="190"/><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="4"/></film></sensor>"#;
    let e = error_of("fov", &format!("<scene version=\"3.0.0\">\n{sensor}\n</scene>\n"));
    assert!(e.contains("got 190"), "{e}");
}

#[test]
fn environment_maps_with_infinite_or_negative_texels_are_refused() {
    for (name, bad) in [("inf", f32::INFINITY), ("negative", -5.0), ("nan", f32::NAN)] {
        let dir = std::env::temp_dir().join(format!("glint-envmap-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let sky = image::Rgb32FImage::from_fn(8, 4, |x, y| {
            if (x, y) == (5, 2) {
                image::Rgb([bad, 1.0, 1.0])
            } else {
                image::Rgb([1.0, 1.0, 1.0])
            }
        });
        image::DynamicImage::ImageRgb32F(sky).save(dir.join("sky.exr")).unwrap();
        let toml = dir.join("s.toml");
        std::fs::write(
            &toml,
            "[camera]\nposition = [0, 0, -5]\nlook_at = [0, 0, 0]\n[environment]\nmap = \"sky.exr\"\n",
        )
        .unwrap();
        let e = load_scene(&toml).err().unwrap_or_else(|| panic!("{name}: accepted")).to_string();
        assert!(e.contains("s.toml:5:") && e.contains("sky.exr") && e.contains("texel (5, 2)"), "{name}: {e}");
    }
}

/// Mitsuba's texture coordinates, checked against what Mitsuba 3.9 computes: its mesh loaders
/// turn v over (`flip_tex_coords`, default true), its bitmaps put v = 0 on the top row, `to_uv`
/// is a full affine map, its checkerboard read as one number (`eval_1`: here a principled
/// `metallic`) swaps its colours, and a spot light's slide runs u along the light's local +x
/// and v along +y.
#[test]
fn textures_see_mitsubas_uv() {
    let path = scene_file(
        "uv",
        &format!(
            r#"<scene version="3.0.0">
{SENSOR}
<texture type="bitmap" id="grid"><string name="filename" value="grid.png"/><string name="filter_type" value="nearest"/><boolean name="raw" value="true"/></texture>
<shape type="obj" id="flipped"><string name="filename" value="uv.obj"/><bsdf type="diffuse" id="gridded"><ref name="reflectance" id="grid"/></bsdf></shape>
<shape type="obj" id="kept"><string name="filename" value="uv.obj"/><boolean name="flip_tex_coords" value="false"/></shape>
<shape type="rectangle"><bsdf type="diffuse" id="shifted"><texture type="bitmap" name="reflectance">
  <string name="filename" value="grid.png"/><string name="filter_type" value="nearest"/><string name="wrap_mode" value="mirror"/><boolean name="raw" value="true"/>
  <transform name="to_uv"><scale value="2"/><translate x="0.25" y="-0.5"/></transform></texture></bsdf></shape>
<shape type="sphere"><bsdf type="principled" id="checked">
  <texture name="metallic" type="checkerboard"><float name="color0" value="0.7"/><float name="color1" value="0.1"/></texture>
  <texture name="base_color" type="checkerboard"><rgb name="color0" value="0.7"/><rgb name="color1" value="0.1"/></texture></bsdf></shape>
<emitter type="spot"><ref name="texture" id="grid"/><float name="cutoff_angle" value="20"/>
  <transform name="to_world"><lookat origin="0, 0, 0" target="0, 0, 1" up="0, 1, 0"/></transform></emitter>
</scene>
"#
        ),
    );
    std::fs::write(
        path.with_file_name("uv.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0.25\nvt 1 0.25\nvt 0 1\nf 1/1 2/2 3/3\n",
    )
    .unwrap();
    // 2 × 2 texels, row 0 on top: A = 0.1 (top left), B = 0.3, C = 0.5, D = 0.7 (bottom right).
    let texel = |v: f32| (v * 255.0).round() as u8;
    let pixels = [0.1, 0.3, 0.5, 0.7].iter().flat_map(|&v| [texel(v); 3]).collect();
    image::RgbImage::from_raw(2, 2, pixels).unwrap().save(path.with_file_name("grid.png")).unwrap();
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let scene = &loaded.scene;
    let uvs = |name: &str| match &scene.objects().iter().find(|o| o.name.contains(&format!("`{name}`"))).unwrap().shape
    {
        glint_core::shapes::Shape::Mesh(m) => m.uvs.clone().unwrap(),
        other => panic!("{other:?}"),
    };
    assert_eq!(uvs("flipped")[0], glam::Vec2::new(0.0, 0.75));
    assert_eq!(uvs("kept")[0], glam::Vec2::new(0.0, 0.25));
    let material = |name: &str| &scene.materials()[scene.material_names().iter().position(|n| n == name).unwrap()];
    let at = |texture: &Texture, u: f32, v: f32| {
        let query = glint_core::textures::TextureQuery { uv: glam::Vec2::new(u, v), ..Default::default() };
        (texture.evaluate(&query).x * 10.0).round() / 10.0
    };
    // v = 0.1 is the top row in Mitsuba.
    let Material::Diffuse(d) = material("gridded") else { panic!() };
    assert_eq!([at(&d.reflectance, 0.2, 0.1), at(&d.reflectance, 0.8, 0.1)], [0.1, 0.3]);
    assert_eq!([at(&d.reflectance, 0.2, 0.9), at(&d.reflectance, 0.8, 0.9)], [0.5, 0.7]);
    // uv' = 2·uv + (¼, −½), mirrored beyond the edges: (0.1, 0.4) → (0.45, 0.3), top left;
    // (0.4, 0.3) → (1.05, 0.1), just past the right edge, mirrored back onto B.
    let Material::Diffuse(d) = material("shifted") else { panic!() };
    assert_eq!([at(&d.reflectance, 0.1, 0.4), at(&d.reflectance, 0.4, 0.3)], [0.1, 0.3]);
    // (0.1, 0.2) → (0.45, −0.1): mirrored above the top row onto A again.
    assert_eq!(at(&d.reflectance, 0.1, 0.2), 0.1);
    // The colour checker: color0 where both half-checks agree; the number checker: color1.
    let Material::Principled(p) = material("checked") else { panic!() };
    assert_eq!([at(&p.base_color, 0.2, 0.2), at(&p.base_color, 0.7, 0.2)], [0.7, 0.1]);
    assert_eq!([at(&p.metallic, 0.2, 0.2), at(&p.metallic, 0.7, 0.2)], [0.1, 0.7]);
    // The spot: toward local (+x, +y) Mitsuba reads u > ½, v > ½: the bottom right texel.
    let Light::Spot(spot) = scene.listed_lights().next().unwrap() else { panic!() };
    let seen = |x: f32, y: f32| (spot.illuminate(Vec3::new(x, y, 1.0)).intensity.x * 10.0).round() / 10.0;
    assert_eq!([seen(0.05, 0.05), seen(-0.05, 0.05), seen(0.05, -0.05), seen(-0.05, -0.05)], [0.7, 0.5, 0.3, 0.1]);
}

/// Each shape's texture coordinates where Mitsuba 3.9 puts them (the expected values were read
/// from Mitsuba itself with these rays on this scene): a PLY file's v as it is (not turned
/// over, unlike an OBJ's), the sphere's poles on its local z, the cube's faces each mapped its
/// own way, the disk's (r, φ/2π) and the cylinder's (φ/2π, height). The disk and cylinder are
/// fine meshes, so their uv may stray by the chords' sag.
#[test]
fn shapes_carry_mitsubas_texture_coordinates() {
    let path = scene_file(
        "shape-uvs",
        &format!(
            r#"<scene version="3.0.0">
{SENSOR}
<shape type="ply"><string name="filename" value="quad.ply"/><transform name="to_world"><translate x="-10"/></transform></shape>
<shape type="sphere"><point name="center" x="-5" y="0" z="0"/><float name="radius" value="1.5"/></shape>
<shape type="cube"><transform name="to_world"><scale x="2" y="1" z="0.5"/></transform></shape>
<shape type="disk"><transform name="to_world"><scale value="2"/><translate x="5"/></transform></shape>
<shape type="cylinder"><float name="radius" value="0.5"/><point name="p1" x="0" y="0" z="2"/><transform name="to_world"><translate x="10"/></transform></shape>
</scene>
"#
        ),
    );
    let ply = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty float u\nproperty float v\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n-1 -1 0 0 0 1 0 0\n1 -1 0 0 0 1 1 0\n1 1 0 0 0 1 1 1\n-1 1 0 0 0 1 0 1\n3 0 1 2\n3 0 2 3\n";
    std::fs::write(path.with_file_name("quad.ply"), ply).unwrap();
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let (a, s) = (0.5f32.to_radians().cos(), 0.5f32.to_radians().sin());
    // (shape, origin, direction, Mitsuba's uv)
    type Probe = (&'static str, [f32; 3], [f32; 3], [f32; 2]);
    #[rustfmt::skip]
    let rays: [Probe; 18] = [
        ("ply", [-9.5, -0.5, 5.0], [0.0, 0.0, -1.0], [0.75, 0.25]),
        ("ply", [-10.8, 0.6, 5.0], [0.0, 0.0, -1.0], [0.1, 0.8]),
        ("sphere", [-4.7, 0.4, 5.0], [0.0, 0.0, -1.0], [0.147584, 0.108173]),
        ("sphere", [-5.5, -0.6, -5.0], [0.0, 0.0, 1.0], [0.639429, 0.825677]),
        ("sphere", [-10.0, 0.2, 0.9], [1.0, 0.0, 0.0], [0.473350, 0.295167]),
        ("cube", [0.6, -0.5, 5.0], [0.0, 0.0, -1.0], [0.25, 0.65]),
        ("cube", [0.6, -0.5, -5.0], [0.0, 0.0, 1.0], [0.75, 0.65]),
        ("cube", [5.0, 0.3, -0.25], [-1.0, 0.0, 0.0], [0.65, 0.75]),
        ("cube", [-3.5, 0.3, -0.25], [1.0, 0.0, 0.0], [0.65, 0.25]),
        ("cube", [0.6, 5.0, -0.25], [0.0, -1.0, 0.0], [0.35, 0.75]),
        ("cube", [0.6, -5.0, -0.25], [0.0, 1.0, 0.0], [0.25, 0.65]),
        ("cube", [-1.2, 0.7, 5.0], [0.0, 0.0, -1.0], [0.85, 0.2]),
        ("disk", [5.6, -0.8, 5.0], [0.0, 0.0, -1.0], [0.5, 0.852416]),
        ("disk", [4.0, 0.02, 5.0], [0.0, 0.0, -1.0], [0.5001, 0.496817]),
        ("disk", [5.1, 1.5, 5.0], [0.0, 0.0, -1.0], [0.751665, 0.239405]),
        ("cylinder", [10.0 - 3.0 * a, -3.0 * s, 1.5], [1.0, 0.0, 0.0], [0.508337, 0.75]),
        ("cylinder", [10.0, -3.0, 0.5], [0.0, 1.0, 0.0], [0.75, 0.25]),
        ("cylinder", [10.3, 3.0, 1.0], [0.0, -1.0, 0.0], [0.147583, 0.5]),
    ];
    for (shape, origin, direction, expected) in rays {
        let ray = glint_core::geometry::Ray::new(Vec3::from(origin), Vec3::from(direction));
        let hit = loaded.scene.intersect(&ray).unwrap_or_else(|| panic!("{shape} from {origin:?}"));
        let tolerance = if matches!(shape, "disk" | "cylinder") { 1e-3 } else { 1e-5 };
        let uv = hit.geometry.uv;
        assert!(
            (uv - glam::Vec2::from(expected)).abs().max_element() < tolerance,
            "{shape} from {origin:?}: glint {uv}, Mitsuba {expected:?}"
        );
    }
}

/// A Mitsuba `.vol` file of `n`³ samples of `f` over the unit cube, `channels` copies of each.
fn vol_file(n: usize, channels: usize, f: impl Fn(Vec3) -> f32) -> Vec<u8> {
    let mut bytes = b"VOL\x03".to_vec();
    for k in [1, n, n, n, channels] {
        bytes.extend_from_slice(&(k as i32).to_le_bytes());
    }
    // A box of its own, which Mitsuba (and glint) ignore for an sdfgrid.
    for b in [-3.0f32, -3.0, -3.0, 5.0, 5.0, 5.0] {
        bytes.extend_from_slice(&b.to_le_bytes());
    }
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let v = f(Vec3::new(x as f32, y as f32, z as f32) / (n - 1) as f32);
                (0..channels).for_each(|_| bytes.extend_from_slice(&v.to_le_bytes()));
            }
        }
    }
    bytes
}

/// An `sdfgrid` placed as the suite's `various_shapes` places its torus: in a shapegroup,
/// through an instance's `to_world`. The grid spans the unit cube whatever box its file
/// names; here it samples a sphere of radius 0.3 about the cube's centre, so the instance
/// (scaled by 2, moved by (3, 0, 0)) shows a sphere of radius 0.6 about (4, 1, 1).
#[test]
fn an_sdfgrid_is_the_zero_set_of_its_grid_placed_by_an_instance() {
    let scene_with = |name: &str, file: &str, shape_extra: &str| {
        let path = scene_file(
            name,
            &format!(
                r#"<scene version="3.0.0">
{SENSOR}
<shape type="shapegroup" id="group">
  <shape type="sdfgrid"><string name="filename" value="{file}"/>{shape_extra}</shape>
</shape>
<shape type="instance"><ref id="group"/><transform name="to_world"><scale value="2"/><translate x="3"/></transform></shape>
</scene>
"#
            ),
        );
        std::fs::write(path.with_file_name("ball.vol"), vol_file(17, 1, |p| (p - Vec3::splat(0.5)).length() - 0.3))
            .unwrap();
        std::fs::write(path.with_file_name("ball3.vol"), vol_file(5, 3, |p| p.x - 0.5)).unwrap();
        load_scene(&path)
    };
    let loaded = scene_with("sdfgrid", "ball.vol", "").unwrap_or_else(|e| panic!("{e}"));
    let centre = Vec3::new(4.0, 1.0, 1.0);
    for direction in [Vec3::X, -Vec3::Y, Vec3::new(1.0, 1.0, -1.0).normalize()] {
        let ray = glint_core::geometry::Ray::new(centre - 5.0 * direction, direction);
        let hit = loaded.scene.intersect(&ray).expect("the sdfgrid's sphere");
        let radius = (hit.geometry.point - centre).length();
        // Trilinear interpolation of a sphere's distances: within a tenth of a voxel (0.125).
        assert!((radius - 0.6).abs() < 0.0125, "{direction}: radius {radius}");
        // The geometric normal is one voxel's gradient (these rays run along voxel faces, where
        // the two sides' differ); the smooth shading normal blends them.
        assert!(hit.geometry.geometric_normal.dot(-direction) > 0.98, "{:?}", hit.geometry);
        assert!(hit.geometry.shading_normal.dot(-direction) > 0.999, "{:?}", hit.geometry);
    }
    // What glint cannot do with it is refused at the shape's line.
    let e = scene_with("sdfgrid-normals", "ball.vol", r#"<string name="normals" value="flat"/>"#)
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("sdfgrid-normals.xml:4:") && e.contains("`smooth` or `analytic`"), "{e}");
    let e = scene_with("sdfgrid-emitter", "ball.vol", r#"<emitter type="area"/>"#).err().unwrap().to_string();
    assert!(e.contains("sdfgrid-emitter.xml:4:") && e.contains("an emitter inside a shapegroup"), "{e}");
    let e = scene_with("sdfgrid-rgb", "ball3.vol", "").err().unwrap().to_string();
    assert!(e.contains("3 channels; an SDF grid has one"), "{e}");
}

/// `rawconstant`: the value as it is (a vector or a float, nothing clamped or converted),
/// here as a normal map's normals, inline or by reference.
#[test]
fn a_rawconstant_texture_is_its_value() {
    let path = scene_file(
        "rawconstant",
        &format!(
            r#"<scene version="3.0.0">
{SENSOR}
<texture type="rawconstant" id="flat"><float name="value" value="0.5"/></texture>
<bsdf type="normalmap" id="tilted"><texture name="normalmap" type="rawconstant"><vector name="value" value="0.25, 0.5, 1.5"/></texture><bsdf type="diffuse"/></bsdf>
<bsdf type="normalmap" id="referred"><ref name="normalmap" id="flat"/><bsdf type="diffuse"/></bsdf>
<shape type="sphere"><ref id="tilted"/></shape>
<shape type="sphere"><ref id="referred"/><point name="center" x="3" y="0" z="0"/></shape>
</scene>
"#
        ),
    );
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let scene = &loaded.scene;
    let material = |name: &str| &scene.materials()[scene.material_names().iter().position(|n| n == name).unwrap()];
    let Material::NormalMap(m) = material("tilted") else { panic!("{:?}", material("tilted")) };
    assert_eq!(m.normals, Texture::Constant(Rgb::new(0.25, 0.5, 1.5)));
    let Material::NormalMap(m) = material("referred") else { panic!("{:?}", material("referred")) };
    assert_eq!(m.normals, Texture::Constant(Rgb::splat(0.5)));
}

/// A rough conductor's and a rough dielectric's widths may be textures (read as numbers, so a
/// checkerboard's colours swap as Mitsuba's do), and `a-C` is among the named conductors.
#[test]
fn a_rough_conductor_takes_textured_widths_and_amorphous_carbon() {
    let path = scene_file(
        "textured-alpha",
        &format!(
            r#"<scene version="3.0.0">
{SENSOR}
<bsdf type="roughconductor" id="carbon"><string name="material" value="a-C"/>
  <texture name="alpha_u" type="checkerboard"><float name="color0" value="0.05"/><float name="color1" value="0.3"/></texture>
  <float name="alpha_v" value="0.2"/></bsdf>
<shape type="sphere"><ref id="carbon"/></shape>
<bsdf type="roughdielectric" id="frost"><texture name="alpha" type="checkerboard"><float name="color0" value="0.05"/><float name="color1" value="0.3"/></texture></bsdf>
<shape type="sphere"><ref id="frost"/></shape>
</scene>
"#
        ),
    );
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let scene = &loaded.scene;
    let Material::RoughConductor(m) = &scene.materials()[0] else { panic!("{:?}", scene.materials()[0]) };
    assert_eq!(m.alpha_v, Texture::Constant(Rgb::splat(0.2)));
    let at = |u: f32, v: f32| {
        m.alpha_u.evaluate(&glint_core::textures::TextureQuery { uv: glam::Vec2::new(u, v), ..Default::default() }).x
    };
    assert_eq!([at(0.2, 0.2), at(0.7, 0.2)], [0.3, 0.05]);
    assert_eq!(m.conductor.eta, Rgb::new(2.94405, 2.22714, 1.96816));
    let frost = scene.material_names().iter().position(|n| n == "frost").unwrap();
    let Material::RoughDielectric(g) = &scene.materials()[frost] else { panic!("{:?}", scene.materials()[frost]) };
    assert!(matches!(g.alpha_u, Texture::Checker(_)) && g.alpha_u == g.alpha_v, "{g:?}");
    let e = error_of(
        "alpha-twice",
        &format!("<scene version=\"3.0.0\">\n{SENSOR}\n<shape type=\"sphere\"><bsdf type=\"roughconductor\"><float name=\"alpha\" value=\"0.1\"/><float name=\"alpha_u\" value=\"0.1\"/><float name=\"alpha_v\" value=\"0.1\"/></bsdf></shape>\n</scene>\n"),
    );
    assert!(e.contains("alpha-twice.xml:3:") && e.contains("not both"), "{e}");
}

/// Of eight ids equally close to a misspelt one, the suggestion is the first in order,
/// however the reader's maps happen to order them: each scene is loaded several times, each
/// load with maps of its own.
#[test]
fn a_suggestion_among_equally_close_ids_is_the_same_every_time() {
    let names = ["m8", "m3", "m6", "m1", "m7", "m2", "m5", "m4"];
    let bsdfs: String = names.iter().map(|n| format!("<bsdf type=\"diffuse\" id=\"{n}\"/>\n")).collect();
    let groups: String = names
        .iter()
        .map(|n| format!("<shape type=\"shapegroup\" id=\"{n}\"><shape type=\"sphere\"/></shape>\n"))
        .collect();
    let cases = [
        (
            "reference",
            format!("<scene version=\"3.0.0\">\n{SENSOR}\n{bsdfs}<shape type=\"sphere\"><ref id=\"m0\"/></shape>\n</scene>\n"),
            "no object with id `m0`",
        ),
        (
            "group",
            format!("<scene version=\"3.0.0\">\n{SENSOR}\n{groups}<shape type=\"instance\"><ref id=\"m0\"/></shape>\n</scene>\n"),
            "no shapegroup `m0` declared before this instance",
        ),
    ];
    for (test, text, expected) in cases {
        for _ in 0..4 {
            let e = error_of(&format!("suggestion-{test}"), &text);
            assert!(e.contains(&format!("{expected}; did you mean `m1`?")), "{test}: {e}");
        }
    }
}

/// `shapegroup` + `instance`: every instance places each of the group's shapes under its own
/// `to_world` after the shape's; the group's mesh is loaded once and shared (glint's
/// instancing). An instance of an unknown group and an emitter in a group are errors.
#[test]
fn instances_place_a_shapegroup_shared() {
    let obj = fixture("tri.obj");
    let path = scene_file(
        "instances",
        &format!(
            r#"<scene version="3.0.0">
{SENSOR}
<shape type="shapegroup" id="pair">
  <shape type="obj"><string name="filename" value="{}"/></shape>
  <shape type="sphere"><transform name="to_world"><scale value="0.5"/><translate x="2"/></transform></shape>
</shape>
<shape type="instance"><ref id="pair"/></shape>
<shape type="instance"><ref id="pair"/><transform name="to_world"><translate z="5"/></transform></shape>
</scene>
"#,
            obj.display()
        ),
    );
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let objects = loaded.scene.objects();
    assert_eq!(objects.len(), 4, "{:?}", objects.iter().map(|o| &o.name).collect::<Vec<_>>());
    let instanced: Vec<_> = objects
        .iter()
        .filter_map(|o| match &o.shape {
            glint_core::shapes::Shape::Instance(i) => Some(i.geometry.clone()),
            _ => None,
        })
        .collect();
    assert_eq!(instanced.len(), 2);
    assert!(std::sync::Arc::ptr_eq(&instanced[0], &instanced[1]), "the group's mesh is loaded once");
    // The second sphere: scaled by ½, moved to x = 2, then by the instance to z = 5.
    let spheres: Vec<Vec3> = objects
        .iter()
        .filter(|o| matches!(o.shape, glint_core::shapes::Shape::Sphere(_)))
        .map(|o| o.transform.as_ref().map_or(Vec3::ZERO, |t| t.point(Vec3::ZERO)))
        .collect();
    assert_eq!(spheres.len(), 2);
    assert!(spheres.iter().any(|c| (*c - Vec3::new(2.0, 0.0, 5.0)).length() < 1e-6), "{spheres:?}");
    let e = error_of(
        "no-group",
        &format!(
            "<scene version=\"3.0.0\">\n{SENSOR}\n<shape type=\"instance\"><ref id=\"nothing\"/></shape>\n</scene>\n"
        ),
    );
    assert!(e.contains("no-group.xml:3:") && e.contains("no shapegroup `nothing`"), "{e}");
    let e = error_of(
        "group-emitter",
        &format!("<scene version=\"3.0.0\">\n{SENSOR}\n<shape type=\"shapegroup\" id=\"g\"><shape type=\"sphere\"><emitter type=\"area\"/></shape></shape>\n</scene>\n"),
    );
    assert!(e.contains("emitter inside a shapegroup"), "{e}");
}

/// `projector`: a spot light with the projector profile (irradiance π·E/cos³θ within the
/// frame of half-angle fov/2), its `irradiance` times `scale` as the colour, a white slide
/// setting the frame where no texture is given, an image's aspect where one is; no `fov` is
/// Mitsuba's 50 mm lens.
#[test]
fn a_projector_is_a_spot_with_the_projector_profile() {
    let path = scene_file(
        "projector",
        &format!(
            r#"<scene version="3.0.0">
{SENSOR}
<emitter type="projector"><float name="fov" value="60"/><float name="scale" value="2"/><rgb name="irradiance" value="0.5, 1, 1.5"/>
  <transform name="to_world"><lookat origin="0, 0, 1" target="0, 0, 0" up="0, 1, 0"/></transform></emitter>
<emitter type="projector"><float name="fov" value="60"/><texture type="bitmap" name="irradiance"><string name="filename" value="wide.png"/></texture></emitter>
</scene>
"#
        ),
    );
    image::RgbImage::from_raw(4, 2, vec![255; 24]).unwrap().save(path.with_file_name("wide.png")).unwrap();
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let spots: Vec<_> = loaded
        .scene
        .listed_lights()
        .map(|l| match l {
            Light::Spot(s) => s.clone(),
            other => panic!("{other:?}"),
        })
        .collect();
    let profile = glint_core::lights::SpotProfile::Projector;
    assert!(spots.iter().all(|s| s.profile == profile && (s.cos_cone - 30f32.to_radians().cos()).abs() < 1e-6));
    assert_eq!(spots[0].light.intensity, Rgb::new(1.0, 2.0, 3.0));
    assert!((spots[0].direction + Vec3::Z).length() < 1e-6);
    assert_eq!(spots[0].slide.as_ref().map(|s| s.aspect), Some(1.0));
    assert_eq!(spots[1].slide.as_ref().map(|s| s.aspect), Some(2.0));
    // Straight down from 1 above: E = 1 (times the colour), π·E/cos³0 at distance 1.
    let below = spots[0].illuminate(Vec3::ZERO).intensity;
    assert!((below - Rgb::new(1.0, 2.0, 3.0) * std::f32::consts::PI).abs().max_element() < 1e-5, "{below}");

    // Without `fov`, Mitsuba's 50 mm lens spans the slide's diagonal: the half-width of a
    // square frame is atan(21.63 / 50 / √2) = 17.011° (Mitsuba 3.9's x_fov: 34.0221°), of a
    // 2 : 1 frame atan(21.63 / 50 · 2 / √5) = 21.15°.
    let path = scene_file(
        "projector-lens",
        &format!(
            r#"<scene version="3.0.0">
{SENSOR}
<emitter type="projector"/>
<emitter type="projector"><texture type="bitmap" name="irradiance"><string name="filename" value="wide.png"/></texture></emitter>
<emitter type="projector"><string name="focal_length" value="25mm"/></emitter>
</scene>
"#
        ),
    );
    image::RgbImage::from_raw(4, 2, vec![255; 24]).unwrap().save(path.with_file_name("wide.png")).unwrap();
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let cones: Vec<f32> = loaded
        .scene
        .listed_lights()
        .map(|l| match l {
            Light::Spot(s) => s.cos_cone.acos().to_degrees(),
            other => panic!("{other:?}"),
        })
        .collect();
    let half_diagonal = 36f32.hypot(24.0) / 2.0;
    let expected = [
        (half_diagonal / 50.0 / 2f32.sqrt()).atan(),
        (half_diagonal / 50.0 * 2.0 / 5f32.sqrt()).atan(),
        (half_diagonal / 25.0 / 2f32.sqrt()).atan(),
    ]
    .map(f32::to_degrees);
    assert!((expected[0] - 34.0221 / 2.0).abs() < 1e-3, "{expected:?}");
    for (cone, expected) in cones.iter().zip(expected) {
        assert!((cone - expected).abs() < 1e-3, "{cones:?} vs {expected}");
    }
    let e = error_of(
        "fov-and-lens",
        &format!("<scene version=\"3.0.0\">\n{SENSOR}\n<emitter type=\"projector\"><float name=\"fov\" value=\"30\"/><string name=\"focal_length\" value=\"50mm\"/></emitter>\n</scene>\n"),
    );
    assert!(e.contains("fov-and-lens.xml:3:") && e.contains("not both"), "{e}");
}

/// `<spectrum filename="…"/>`: wavelength–value lines, converted as the same spectrum inline
/// (a point light's intensity here: Mitsuba 3.9's RGB variant gives (4.02061, 2.31368,
/// 1.24453) for this file). A malformed line names the file and line; a blackbody is refused
/// as Mitsuba's RGB variants refuse it.
#[test]
fn spectra_from_files_and_blackbodies() {
    let path = scene_file(
        "spectrum-file",
        &format!(
            r#"<scene version="3.0.0">
{SENSOR}
<emitter type="point"><spectrum name="intensity" filename="ramp.spd"/></emitter>
<emitter type="point"><spectrum name="intensity" value="400:1, 500:2, 600:3, 700:4"/></emitter>
</scene>
"#
        ),
    );
    std::fs::write(path.with_file_name("ramp.spd"), "# a ramp\n400 1.0\n500 2.0\n\n600 3.0 # comment\n700 4.0\n")
        .unwrap();
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let intensities: Vec<Rgb> = loaded
        .scene
        .listed_lights()
        .map(|l| match l {
            Light::Point(p) => p.intensity,
            other => panic!("{other:?}"),
        })
        .collect();
    assert_eq!(intensities[0], intensities[1]);
    let mitsuba = Rgb::new(4.02061, 2.31368, 1.24453);
    assert!(((intensities[0] - mitsuba) / mitsuba).abs().max_element() < 2e-3, "{}", intensities[0]);
    std::fs::write(path.with_file_name("ramp.spd"), "400 1.0\n500 two\n").unwrap();
    let e = load_scene(&path).err().unwrap().to_string();
    assert!(e.contains("ramp.spd:2") && e.contains("expected a wavelength and a value"), "{e}");
    let e = error_of(
        "blackbody",
        &format!("<scene version=\"3.0.0\">\n{SENSOR}\n<emitter type=\"point\"><spectrum name=\"intensity\" type=\"blackbody\"><float name=\"temperature\" value=\"3000\"/></spectrum></emitter>\n</scene>\n"),
    );
    assert!(e.contains("blackbody.xml:3:") && e.contains("blackbody spectrum has no RGB value"), "{e}");
}

/// A sensor whose `to_world` mirrors (a negative scale) gives a mirrored image, as Mitsuba
/// renders it: its right edge looks the other way than the same sensor's without the scale.
#[test]
fn a_mirroring_sensor_renders_mirrored() {
    let sensor = |scale: &str| {
        format!(
            r#"<scene version="3.0.0"><sensor type="perspective"><float name="fov" value="40"/>
<transform name="to_world">{scale}<lookat origin="0, 0, -5" target="0, 0, 0" up="0, 1, 0"/></transform>
<film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor></scene>"#
        )
    };
    let right_edge = |text: &str, name: &str| {
        let loaded = load_scene(&scene_file(name, text)).unwrap_or_else(|e| panic!("{e}"));
        loaded.scene.camera().generate_ray(8.0, 4.0).direction
    };
    let plain = right_edge(&sensor(""), "sensor-plain");
    let mirrored = right_edge(&sensor(r#"<scale x="-1"/>"#), "sensor-mirrored");
    // Mitsuba's image right is the camera's −x: looking down +z with up +y, world −x.
    assert!(plain.x < 0.0, "{plain}");
    assert!((mirrored - Vec3::new(-plain.x, plain.y, plain.z)).length() < 1e-5, "{mirrored} vs {plain}");
}

/// Mitsuba's gaussian reconstruction filter (its film's default, and `<rfilter type="gaussian">`)
/// is cut off at 4σ = 2 pixels: glint's `gaussian-wide`, not pbrt-v4's `gaussian` (1.5).
#[test]
fn mitsubas_gaussian_filter_reaches_two_pixels() {
    let film = |rfilter: &str| {
        format!(
            r#"<scene version="3.0.0"><sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/>{rfilter}</film></sensor></scene>"#
        )
    };
    for (name, rfilter) in [("default", ""), ("named", r#"<rfilter type="gaussian"/>"#)] {
        let loaded =
            load_scene(&scene_file(&format!("gaussian-{name}"), &film(rfilter))).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(loaded.render.filter, Filter::GaussianWide, "{name}");
        assert_eq!(loaded.render.filter.radius(), 2.0);
    }
}
