//! The glTF 2.0 reader on files made here: every material feature and its mapping onto the
//! principled BSDF, the node hierarchy and instancing, cameras and lights, binary and
//! external buffers, an analytic render, and the errors.

mod common;

use std::path::PathBuf;

use base64::Engine;
use glint_core::camera::Lens;
use glint_core::geometry::Ray;
use glint_core::integrators::IntegratorKind;
use glint_core::lights::Light;
use glint_core::materials::Material;
use glint_core::render::{render, RenderSettings};
use glint_core::scene::Darkness;
use glint_core::shapes::Shape;
use glint_core::textures::Texture;
use glint_core::{Rgb, Vec3};
use glint_scene::{load_scene, load_scene_with_options, LoadOptions};
use serde_json::{json, Value};

/// A glTF document under construction: one buffer holding every accessor's data.
#[derive(Default)]
struct Builder {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Builder {
    fn accessor(
        &mut self,
        bytes: &[u8],
        count: usize,
        kind: &str,
        component: u32,
        minmax: Option<(Vec<f32>, Vec<f32>)>,
    ) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        self.views.push(json!({ "buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len() }));
        self.bin.extend_from_slice(bytes);
        let mut accessor =
            json!({ "bufferView": self.views.len() - 1, "componentType": component, "count": count, "type": kind });
        if let Some((min, max)) = minmax {
            accessor["min"] = json!(min);
            accessor["max"] = json!(max);
        }
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    fn floats(&mut self, values: &[[f32; 3]]) -> usize {
        let bytes: Vec<u8> = values.iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
        let min = (0..3).map(|c| values.iter().map(|v| v[c]).fold(f32::INFINITY, f32::min)).collect();
        let max = (0..3).map(|c| values.iter().map(|v| v[c]).fold(f32::NEG_INFINITY, f32::max)).collect();
        self.accessor(&bytes, values.len(), "VEC3", 5126, Some((min, max)))
    }

    fn pairs(&mut self, values: &[[f32; 2]]) -> usize {
        let bytes: Vec<u8> = values.iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
        self.accessor(&bytes, values.len(), "VEC2", 5126, None)
    }

    fn indices(&mut self, values: &[u16]) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|x| x.to_le_bytes()).collect();
        self.accessor(&bytes, values.len(), "SCALAR", 5123, None)
    }

    /// A unit quad in the xy plane facing +z, uv (0, 0) at its top-left as glTF's images.
    fn quad(&mut self) -> Value {
        let p = self.floats(&[[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]]);
        let n = self.floats(&[[0.0, 0.0, 1.0]; 4]);
        let t = self.pairs(&[[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]]);
        let i = self.indices(&[0, 1, 2, 0, 2, 3]);
        json!({ "attributes": { "POSITION": p, "NORMAL": n, "TEXCOORD_0": t }, "indices": i })
    }

    fn finish(self, mut document: Value, uri: Option<&str>) -> (Value, Vec<u8>) {
        let mut buffer = json!({ "byteLength": self.bin.len() });
        match uri {
            Some("data") => {
                buffer["uri"] = json!(format!(
                    "data:application/octet-stream;base64,{}",
                    base64::engine::general_purpose::STANDARD.encode(&self.bin)
                ))
            }
            Some(file) => buffer["uri"] = json!(file),
            None => {}
        }
        document["asset"] = json!({ "version": "2.0" });
        document["buffers"] = json!([buffer]);
        document["bufferViews"] = json!(self.views);
        document["accessors"] = json!(self.accessors);
        (document, self.bin)
    }
}

fn png(width: u32, height: u32, pixel: impl Fn(u32, u32) -> [u8; 3]) -> Vec<u8> {
    let image = image::RgbImage::from_fn(width, height, |x, y| image::Rgb(pixel(x, y)));
    let mut bytes = Vec::new();
    image.write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Png).unwrap();
    bytes
}

fn dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("glint-gltf-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A .glb: the JSON chunk and the binary chunk.
fn glb(document: &Value, bin: &[u8]) -> Vec<u8> {
    let mut json = serde_json::to_vec(document).unwrap();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut bin = bin.to_vec();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let mut out = Vec::new();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&((12 + 8 + json.len() + 8 + bin.len()) as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}

/// Every material feature, each on its own quad, with a camera, three lights and an
/// instanced mesh under a parent node.
fn every_feature() -> (Value, Vec<u8>) {
    const H: f32 = std::f32::consts::FRAC_1_SQRT_2; // cos 45°, sin 45°: quaternions of quarter turns
    let mut b = Builder::default();
    let quad = b.quad();
    let primitive = |material: usize| {
        let mut p = quad.clone();
        p["material"] = json!(material);
        p
    };
    let materials = json!([
        // 0: base colour factor × texture (sRGB) with a texture transform, metallic and
        // roughness from their channels, a normal map, an occlusion map (not read), blended.
        {
            "name": "textured",
            "pbrMetallicRoughness": {
                "baseColorFactor": [0.5, 1.0, 1.0, 1.0],
                "baseColorTexture": { "index": 0, "extensions": { "KHR_texture_transform": { "offset": [0.5, 0.0], "scale": [2.0, 2.0] } } },
                "metallicFactor": 0.5,
                "roughnessFactor": 0.8,
                "metallicRoughnessTexture": { "index": 1 }
            },
            "normalTexture": { "index": 2 },
            "occlusionTexture": { "index": 1 },
            "alphaMode": "BLEND"
        },
        // 1: glass with a volume (solid principled), index 1.4.
        {
            "name": "glass",
            "pbrMetallicRoughness": { "metallicFactor": 0.0, "roughnessFactor": 0.1 },
            "extensions": {
                "KHR_materials_transmission": { "transmissionFactor": 1.0 },
                "KHR_materials_ior": { "ior": 1.4 },
                "KHR_materials_volume": { "thicknessFactor": 0.5 }
            }
        },
        // 2: thin transmission (no volume): the thin principled BSDF.
        {
            "name": "film",
            "pbrMetallicRoughness": { "metallicFactor": 0.0 },
            "extensions": { "KHR_materials_transmission": { "transmissionFactor": 0.7 } }
        },
        // 3: clear-coated red paint.
        {
            "name": "paint",
            "doubleSided": true,
            "pbrMetallicRoughness": { "baseColorFactor": [0.8, 0.1, 0.1, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.5 },
            "extensions": { "KHR_materials_clearcoat": { "clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.1 } }
        },
        // 4: an emitter, strength 4, double-sided.
        {
            "name": "lamp",
            "emissiveFactor": [1.0, 0.5, 0.25],
            "doubleSided": true,
            "extensions": { "KHR_materials_emissive_strength": { "emissiveStrength": 4.0 } }
        }
    ]);
    let meshes = json!([
        { "primitives": [primitive(0)] },
        { "primitives": [primitive(1)] },
        { "primitives": [primitive(2)] },
        { "primitives": [primitive(3)] },
        { "primitives": [primitive(4)] },
        { "primitives": [quad.clone()] }
    ]);
    let nodes = json!([
        { "name": "camera", "camera": 0, "translation": [0.0, 0.0, 10.0] },
        { "name": "textured", "mesh": 0, "translation": [-4.0, 0.0, 0.0] },
        { "name": "glass", "mesh": 1, "translation": [-2.0, 0.0, 0.0] },
        { "name": "film", "mesh": 2 },
        { "name": "paint", "mesh": 3, "translation": [2.0, 0.0, 0.0] },
        { "name": "lamp", "mesh": 4, "translation": [0.0, 4.0, 0.0], "rotation": [H, 0.0, 0.0, H] },
        // A parent moved down by 5 and turned 90° about y; its children share mesh 5.
        { "name": "parent", "translation": [0.0, -5.0, 0.0], "rotation": [0.0, H, 0.0, H], "children": [7, 8] },
        { "name": "left", "mesh": 5, "translation": [-3.0, 0.0, 0.0] },
        { "name": "right", "mesh": 5, "translation": [3.0, 0.0, 0.0], "scale": [2.0, 2.0, 2.0] },
        { "name": "sun", "extensions": { "KHR_lights_punctual": { "light": 0 } }, "rotation": [-H, 0.0, 0.0, H] },
        { "name": "bulb", "extensions": { "KHR_lights_punctual": { "light": 1 } }, "translation": [0.0, 3.0, 3.0] },
        { "name": "spot", "extensions": { "KHR_lights_punctual": { "light": 2 } }, "translation": [0.0, 6.0, 0.0], "rotation": [-H, 0.0, 0.0, H] }
    ]);
    let document = json!({
        "extensionsUsed": ["KHR_texture_transform", "KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume", "KHR_materials_clearcoat", "KHR_materials_emissive_strength", "KHR_lights_punctual", "KHR_materials_sheen"],
        "scene": 0,
        "scenes": [{ "nodes": [0, 1, 2, 3, 4, 5, 6, 9, 10, 11] }],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "cameras": [{ "type": "perspective", "perspective": { "yfov": 0.5, "aspectRatio": 2.0, "znear": 0.1 } }],
        "textures": [
            { "source": 0, "sampler": 0 },
            { "source": 1 },
            { "source": 2 }
        ],
        "samplers": [{ "magFilter": 9728, "wrapS": 33071, "wrapT": 33071 }],
        "images": [
            { "uri": "colour.png" },
            { "uri": format!("data:image/png;base64,{}", base64::engine::general_purpose::STANDARD.encode(png(2, 2, |x, _| [0, 255, if x == 0 { 0 } else { 255 }]))) },
            { "uri": "normals.png" }
        ],
        "extensions": { "KHR_lights_punctual": { "lights": [
            { "type": "directional", "color": [1.0, 1.0, 1.0], "intensity": 683.0 },
            { "type": "point", "color": [1.0, 0.5, 0.5], "intensity": 1366.0 },
            { "type": "spot", "intensity": 683.0, "spot": { "innerConeAngle": 0.3, "outerConeAngle": 0.5 } }
        ] } }
    });
    b.finish(document, None)
}

fn write_every_feature(test: &str, binary: bool) -> PathBuf {
    let dir = dir(test);
    std::fs::write(dir.join("colour.png"), png(4, 2, |x, y| [(x * 60) as u8, (y * 200) as u8, 50])).unwrap();
    std::fs::write(dir.join("normals.png"), png(1, 1, |_, _| [128, 128, 255])).unwrap();
    let (mut document, bin) = every_feature();
    if binary {
        let path = dir.join("every.glb");
        std::fs::write(&path, glb(&document, &bin)).unwrap();
        path
    } else {
        // An external .bin beside the .gltf.
        document["buffers"][0]["uri"] = json!("every%20feature.bin");
        std::fs::write(dir.join("every feature.bin"), &bin).unwrap();
        let path = dir.join("every.gltf");
        std::fs::write(&path, serde_json::to_vec_pretty(&document).unwrap()).unwrap();
        path
    }
}

#[test]
fn every_feature_maps_onto_glint() {
    for binary in [false, true] {
        let path = write_every_feature(if binary { "every-glb" } else { "every-gltf" }, binary);
        let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
        let scene = &loaded.scene;
        let warnings = loaded.warnings.join("\n");
        for expected in ["KHR_materials_sheen is not read", "occlusion map is not read"] {
            assert!(warnings.contains(expected), "{expected}: {warnings}");
        }
        // The camera: at z = 10 looking down −z, 0.5 rad vertically, 2:1.
        let camera = scene.camera();
        assert_eq!((camera.width, camera.height), (960, 480));
        assert!((camera.fov_degrees - 0.5f32.to_degrees()).abs() < 1e-4);
        assert_eq!(camera.position, Vec3::new(0.0, 0.0, 10.0));
        assert!(matches!(camera.lens, Lens::Pinhole));
        // Its image right is +x (glTF is right-handed, as glint).
        assert!(camera.generate_ray(959.0, 240.0).direction.x > 0.0);

        // Geometry by rays: the quads at x = −4, −2, 0, 2 (z = 0, facing +z).
        let hit = |origin: Vec3, direction: Vec3| scene.intersect(&Ray::new(origin, direction));
        for x in [-4.0, -2.0, 0.0, 2.0] {
            let h = hit(Vec3::new(x + 0.5, 0.5, 5.0), -Vec3::Z).expect("a quad");
            assert!((h.t - 5.0).abs() < 1e-4);
        }
        // glTF's uv (0, 0) at the top-left corner is glint's (0, 1).
        let h = hit(Vec3::new(-4.0 - 0.999, 0.999, 5.0), -Vec3::Z).unwrap();
        assert!((h.geometry.uv - glam::Vec2::new(0.0, 1.0)).length() < 1e-3, "{}", h.geometry.uv);
        // The instanced quads: turned 90° about y and moved down by 5, so they face +x;
        // `left` at world z = 3, `right` at z = −3 and twice as large.
        let left = hit(Vec3::new(5.0, -5.0, 3.0), -Vec3::X).expect("left");
        assert!((left.t - 5.0).abs() < 1e-4, "{}", left.t);
        assert!(hit(Vec3::new(5.0, -6.5, -3.0), -Vec3::X).is_some(), "right is scaled by 2");
        assert!(hit(Vec3::new(5.0, -6.5, 3.0), -Vec3::X).is_none(), "left is not");
        let instances = scene.objects().iter().filter(|o| matches!(o.shape, Shape::Instance(_))).count();
        assert_eq!(instances, 2, "mesh 5 is placed twice: instanced");
        // The lamp emits (an area light), turned to face +y at y = 4.
        assert!(scene.lights().area_count() > 0);

        // Lights: 683 lm/W: the sun's 683 lux is 1 W/m², travelling down.
        let lights: Vec<&Light> = scene.listed_lights().collect();
        assert_eq!(lights.iter().map(|l| l.kind()).collect::<Vec<_>>(), ["directional", "point", "spot"]);
        match lights[0] {
            Light::Directional(sun) => {
                assert!((sun.direction - -Vec3::Y).length() < 1e-5, "{}", sun.direction);
                assert!((sun.intensity - Rgb::ONE).abs().max_element() < 1e-6);
            }
            other => panic!("{other:?}"),
        }
        match lights[1] {
            Light::Point(bulb) => {
                assert_eq!(bulb.position, Vec3::new(0.0, 3.0, 3.0));
                assert!((bulb.intensity - Rgb::new(2.0, 1.0, 1.0)).abs().max_element() < 1e-5);
            }
            other => panic!("{other:?}"),
        }
        match lights[2] {
            Light::Spot(spot) => {
                assert!((spot.direction - -Vec3::Y).length() < 1e-5);
                assert!((spot.cos_cone - 0.5f32.cos()).abs() < 1e-5 && (spot.cos_full - 0.3f32.cos()).abs() < 1e-5);
            }
            other => panic!("{other:?}"),
        }

        // Materials.
        let material = |name: &str| {
            let i = scene
                .material_names()
                .iter()
                .position(|n| n == name)
                .unwrap_or_else(|| panic!("{name}: {:?}", scene.material_names()));
            &scene.materials()[i]
        };
        let Material::NormalMap(mapped) = material("material 0 (textured): normal-mapped") else {
            panic!("a normal map")
        };
        let Material::Principled(textured) = &mapped.material else { panic!("{:?}", mapped.material) };
        // Base colour: the sRGB texture × (0.5, 1, 1), clamped (sampler 0), nearest texels,
        // through the transform: glint's (0.1, 0.8) is glTF's (0.1, 0.2), → (0.7, 0.4), the
        // image's column 2 (of 4), row 0 (of 2).
        let Texture::Image(image) = &textured.base_color else { panic!("{:?}", textured.base_color) };
        assert_eq!(image.filter, glint_core::textures::TexelFilter::Nearest);
        let seen = image.evaluate(glam::Vec2::new(0.1, 0.8));
        let srgb = |c: f32| if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) };
        let expected = Rgb::new(0.5 * srgb(120.0 / 255.0), 0.0, srgb(50.0 / 255.0));
        assert!((seen - expected).abs().max_element() < 1e-5, "{seen} vs {expected}");
        // Metallic from blue × 0.5 (the data image is raw: 0 or 1), roughness from green × 0.8.
        let (Texture::Image(metal), Texture::Image(rough)) = (&textured.metallic, &textured.roughness) else {
            panic!()
        };
        // (Texel centres: column 0 at u = ¼, column 1 at ¾.)
        assert_eq!(metal.evaluate(glam::Vec2::new(0.25, 0.5)), Rgb::splat(0.0));
        assert_eq!(metal.evaluate(glam::Vec2::new(0.75, 0.5)), Rgb::splat(0.5));
        assert!((rough.evaluate(glam::Vec2::new(0.25, 0.5)) - Rgb::splat(0.8)).abs().max_element() < 1e-6);
        match material("material 1 (glass): surface") {
            Material::Principled(glass) => {
                assert!((glass.eta - 1.4).abs() < 1e-6);
                assert_eq!(glass.spec_trans, Texture::from(1.0));
            }
            other => panic!("{other:?}"),
        }
        assert!(matches!(material("material 2 (film): surface"), Material::PrincipledThin(_)));
        // Double-sided: shaded from behind as from the front.
        assert!(matches!(material("material 3 (paint): double-sided"), Material::TwoSided(_)));
        match material("material 3 (paint): surface") {
            Material::Principled(paint) => {
                assert_eq!(paint.clearcoat, Texture::from(1.0));
                // α = 0.1² = 0.01 = lerp(0.1, 0.001, gloss): gloss = 0.09 / 0.099.
                let Texture::Constant(gloss) = paint.clearcoat_gloss else { panic!() };
                assert!((gloss.x - 0.09 / 0.099).abs() < 1e-6);
                assert_eq!(paint.base_color, Texture::Constant(Rgb::new(0.8, 0.1, 0.1)));
            }
            other => panic!("{other:?}"),
        }
        match material("material 4 (lamp): emitting") {
            Material::Emitter(lamp) => {
                assert_eq!(lamp.radiance, Texture::Constant(Rgb::new(4.0, 2.0, 1.0)));
                assert!(lamp.two_sided);
            }
            other => panic!("{other:?}"),
        }
    }
}

/// A scene without camera or lights: a framing camera that sees all of it, under a white
/// sky of radiance 1, so a white diffuse-like (rough, non-metal) quad seen head-on reflects
/// about its albedo.
#[test]
fn a_scene_without_camera_or_lights_is_framed_and_lit_by_a_white_sky() {
    let mut b = Builder::default();
    let mut quad = b.quad();
    quad["material"] = json!(0);
    let document = json!({
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0, "scale": [3.0, 3.0, 3.0] }],
        "meshes": [{ "primitives": [quad] }],
        "materials": [{ "pbrMetallicRoughness": { "baseColorFactor": [0.5, 0.5, 0.5, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0 } }]
    });
    let (document, _) = b.finish(document, Some("data"));
    let dir = dir("framed");
    let path = dir.join("framed.gltf");
    std::fs::write(&path, serde_json::to_vec(&document).unwrap()).unwrap();
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.warnings.join("\n").contains("uniform white sky of radiance 1"), "{:?}", loaded.warnings);
    assert_eq!(loaded.scene.environment().background, Rgb::ONE);
    let camera = loaded.scene.camera();
    // The quad's corners are in view.
    for corner in [Vec3::new(-3.0, -3.0, 0.0), Vec3::new(3.0, 3.0, 0.0)] {
        assert!(camera.project(corner).is_some(), "{corner} out of view");
    }
    // The centre pixel sees the quad; a rough dielectric of albedo ½ under a uniform sky
    // of 1 reflects between ½ and ½ + its specular share (about 0.04 to 0.1).
    let integrator = loaded.render.integrator.create(&loaded.render.integrator_settings).unwrap();
    let mut scene = loaded.scene;
    scene.set_camera(scene.camera().with_resolution(8, 6));
    let settings = RenderSettings { spp: 256, seed: 1, filter: loaded.render.filter, sampler: loaded.render.sampler };
    let image = render(&scene, integrator.as_ref(), &settings, &|| {}).film.to_rgb();
    let centre = image[3 * 8 + 4];
    assert!(centre.x > 0.5 && centre.x < 0.62, "{centre}");
}

#[test]
fn errors_name_the_file_and_what_is_wrong() {
    let dir = dir("errors");
    let write = |name: &str, bytes: &[u8]| {
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        match load_scene(&path) {
            Ok(_) => panic!("{name}: expected an error"),
            Err(e) => e.to_string(),
        }
    };
    assert!(write("broken.gltf", b"{ not json").contains("broken.gltf: not a valid glTF 2.0 file"));
    // A buffer shorter than it says.
    let mut b = Builder::default();
    let quad = b.quad();
    let (mut document, bin) = b.finish(
        json!({ "scenes": [{ "nodes": [0] }], "nodes": [{ "mesh": 0 }], "meshes": [{ "primitives": [quad] }] }),
        Some("data"),
    );
    document["buffers"][0]["byteLength"] = json!(4096);
    let e = write("short.gltf", &serde_json::to_vec(&document).unwrap());
    assert!(e.contains("buffer 0 declares 4096 bytes but holds"), "{e}");
    // An accessor past its view.
    document["buffers"][0]["byteLength"] = json!(bin.len());
    document["accessors"][0]["count"] = json!(400);
    let e = write("past.gltf", &serde_json::to_vec(&document).unwrap());
    assert!(e.contains("past.gltf") && e.contains("accessor"), "{e}");
    // A node that is two parents' child (glTF's hierarchy is disjoint trees).
    let mut shared = document.clone();
    shared["nodes"] = json!([{ "children": [2] }, { "children": [2] }, { "mesh": 0 }]);
    shared["scenes"] = json!([{ "nodes": [0, 1] }]);
    let e = write("shared.gltf", &serde_json::to_vec(&shared).unwrap());
    assert!(e.contains("node 2 is reached twice"), "{e}");
    // A stride shorter than the element, and an empty accessor.
    let mut strided = document.clone();
    strided["bufferViews"][0]["byteStride"] = json!(4);
    let e = write("stride.gltf", &serde_json::to_vec(&strided).unwrap());
    assert!(e.contains("stride (4) is shorter than an element (12)"), "{e}");
    let mut empty = document.clone();
    empty["accessors"][0]["count"] = json!(0);
    let e = write("empty.gltf", &serde_json::to_vec(&empty).unwrap());
    assert!(e.contains("has no elements"), "{e}");
    // A key given twice: the last counts, as in the `gltf` crate (whose own validation
    // would index accessor 99 unchecked).
    let text = String::from_utf8(serde_json::to_vec(&document).unwrap()).unwrap().replacen(
        "\"POSITION\":0",
        "\"POSITION\":0,\"POSITION\":99",
        1,
    );
    assert!(text.contains("\"POSITION\":99"), "{text}");
    let e = write("twice.gltf", text.as_bytes());
    assert!(e.contains("POSITION is accessor 99"), "{e}");
    // A missing external buffer.
    let (missing, _) = Builder::default().finish(json!({ "scenes": [{ "nodes": [] }] }), Some("gone.bin"));
    let e = write("missing.gltf", &serde_json::to_vec(&missing).unwrap());
    assert!(e.contains("buffer 0") && e.contains("gone.bin"), "{e}");
}

#[test]
fn mutated_files_never_panic() {
    let (document, bin) = every_feature();
    let original = glb(&document, &bin);
    let text = serde_json::to_vec(&document).unwrap();
    let dir = dir("mutants");
    std::fs::write(dir.join("colour.png"), png(4, 2, |_, _| [1, 2, 3])).unwrap();
    std::fs::write(dir.join("normals.png"), png(1, 1, |_, _| [128, 128, 255])).unwrap();
    for (kind, original, specials) in
        [("glb", &original, &b"\x00\xff{}[]\"0"[..]), ("gltf", &text, &b"{}[]\",:0-e9"[..])]
    {
        for (i, bytes) in common::mutants(original, specials, 300, 5).into_iter().enumerate() {
            let path = dir.join(format!("m{i}.{kind}"));
            std::fs::write(&path, &bytes).unwrap();
            let result = std::panic::catch_unwind(|| load_scene(&path).map(|_| ()));
            assert!(result.is_ok(), "{kind} mutant {i} panicked");
        }
    }
}

/// The examples of scenes/gltf/ (made by scripts/gltf_models.py) load as the README shows
/// them: the knots' copper mesh instanced twice, the glowing one an area light, the file's
/// camera and lights; the spheres framed and lit by the default sky.
#[test]
fn the_example_scenes_load() {
    let scenes = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/gltf");
    let knots = load_scene(&scenes.join("knots.gltf")).unwrap_or_else(|e| panic!("{e}"));
    assert!(knots.warnings.is_empty(), "{:?}", knots.warnings);
    let instances = knots.scene.objects().iter().filter(|o| matches!(o.shape, Shape::Instance(_))).count();
    assert_eq!(instances, 2);
    assert!(knots.scene.lights().area_count() > 0);
    assert_eq!(knots.scene.listed_lights().map(Light::kind).collect::<Vec<_>>(), ["spot", "point"]);
    assert_eq!((knots.scene.camera().width, knots.scene.camera().height), (960, 540));
    let spheres = load_scene(&scenes.join("spheres.glb")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(spheres.warnings.len(), 1, "{:?}", spheres.warnings);
    assert_eq!(spheres.scene.environment().background, Rgb::ONE);
    assert_eq!(spheres.scene.objects().len(), 6);
}

fn write_json(test: &str, document: &Value) -> PathBuf {
    let path = dir(test).join(format!("{test}.gltf"));
    std::fs::write(&path, serde_json::to_vec(document).unwrap()).unwrap();
    path
}

fn without_default_light() -> LoadOptions {
    LoadOptions { no_default_light: true, ..LoadOptions::default() }
}

/// A model with emitters but no punctual light is lit by the default environment, as a
/// viewer lights it; the option leaves it out, and then a model without emitters is
/// explained as having no light.
#[test]
fn the_default_environment_lights_a_model_without_punctual_lights_unless_turned_off() {
    let mut b = Builder::default();
    let mut quad = b.quad();
    quad["material"] = json!(0);
    let document = json!({
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0 }],
        "meshes": [{ "primitives": [quad] }],
        "materials": [{ "emissiveFactor": [1.0, 1.0, 1.0] }]
    });
    let (document, _) = b.finish(document, Some("data"));
    let path = write_json("emissive-unlit", &document);
    let lit = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(lit.scene.environment().background, Rgb::ONE);
    assert!(
        lit.warnings.join("\n").contains("no punctual light: lit by the default environment"),
        "{:?}",
        lit.warnings
    );
    let dark = load_scene_with_options(&path, &without_default_light()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(dark.scene.environment().background, Rgb::ZERO);
    assert!(dark.warnings.is_empty(), "{:?}", dark.warnings);
    assert!(dark.scene.lights().area_count() > 0, "the emitter still lights");

    let mut plain = document.clone();
    plain["materials"] = json!([{}]);
    let path = write_json("plain-unlit", &plain);
    let dark = load_scene_with_options(&path, &without_default_light()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(dark.scene.why_dark(false), Darkness::NoLight);
}

/// Spec violations are warned of, naming the field (or refused where nothing sensible can be
/// drawn: a projective node matrix).
#[test]
fn spec_violations_are_warned_of_naming_the_field() {
    let mut b = Builder::default();
    let mut quad = b.quad();
    quad["material"] = json!(0);
    let mut seven = b.quad();
    seven["indices"] = json!(b.indices(&[0, 1, 2, 0, 2, 3, 0]));
    let document = json!({
        "extensionsUsed": ["KHR_lights_punctual"],
        "scenes": [{ "nodes": [0, 1, 2] }],
        "nodes": [
            { "mesh": 0, "matrix": [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0], "translation": [1.0, 0.0, 0.0] },
            { "mesh": 1, "translation": [0.0, 0.0, -5.0] },
            { "extensions": { "KHR_lights_punctual": { "light": 0 } }, "translation": [0.0, 0.0, 3.0] }
        ],
        "meshes": [{ "primitives": [quad] }, { "primitives": [seven] }],
        "materials": [{
            "emissiveFactor": [-1.0, 0.5, 0.0],
            "pbrMetallicRoughness": { "roughnessFactor": 5.0, "metallicFactor": -2.0 }
        }],
        "extensions": { "KHR_lights_punctual": { "lights": [
            { "type": "spot", "intensity": 683.0, "spot": { "innerConeAngle": 0.6, "outerConeAngle": 0.5 } }
        ] } }
    });
    let (document, _) = b.finish(document, Some("data"));
    let path = write_json("violations", &document);
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let warnings = loaded.warnings.join("\n");
    for expected in [
        "node 0: has both `matrix` and `translation`",
        "mesh 1 primitive 0: TRIANGLES with 7 indices, not a multiple of 3",
        "material 0: emissiveFactor is [-1.0, 0.5, 0.0], negative",
        "material 0: pbrMetallicRoughness.roughnessFactor is 5, outside [0, 1] as glTF requires: taken as 1",
        "material 0: pbrMetallicRoughness.metallicFactor is -2, outside [0, 1] as glTF requires: taken as 0",
        "light 0: spot.innerConeAngle (0.6) is not less than spot.outerConeAngle (0.5)",
    ] {
        assert!(warnings.contains(expected), "{expected}: {warnings}");
    }
    let scene = &loaded.scene;
    // The matrix is used: the quad spans x ∈ [−1, 1], not [0, 2].
    assert!(scene.intersect(&Ray::new(Vec3::new(-0.5, 0.0, 2.0), -Vec3::Z)).is_some_and(|h| (h.t - 2.0).abs() < 1e-4));
    let index = |name: &str| scene.material_names().iter().position(|n| n == name).unwrap();
    match &scene.materials()[index("material 0: emitting")] {
        Material::Emitter(e) => assert_eq!(e.radiance, Texture::Constant(Rgb::new(0.0, 0.5, 0.0))),
        other => panic!("{other:?}"),
    }
    match &scene.materials()[index("material 0: surface")] {
        Material::Principled(p) => {
            assert_eq!(p.roughness, Texture::from(1.0));
            assert_eq!(p.metallic, Texture::from(0.0));
        }
        other => panic!("{other:?}"),
    }

    let mut projective = document.clone();
    projective["nodes"][0] = json!({ "mesh": 0, "matrix": [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.5, 0.0, 0.0, 0.0, 1.0] });
    let e = load_scene(&write_json("projective", &projective)).err().expect("an error").to_string();
    assert!(e.contains("node 0: its `matrix` is not affine: its bottom row is [0.0, 0.0, 0.5, 1.0]"), "{e}");
}

/// KHR_mesh_quantization: positions as 16-bit integers scaled by their node, normals as
/// normalised bytes, uvs as normalised 16- and 8-bit integers; and a sparse accessor with no
/// buffer view (zeros with three vertices given).
#[test]
fn quantized_and_sparse_accessors_are_read() {
    let mut b = Builder::default();
    // Elements of vertex attributes start on 4-byte boundaries: strides 8 and 4.
    let padded = |elements: Vec<Vec<u8>>, stride: usize| -> Vec<u8> {
        elements
            .into_iter()
            .flat_map(|mut e| {
                e.resize(stride, 0);
                e
            })
            .collect()
    };
    let i16s = |v: [i16; 3]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    let positions =
        padded([[-1000, -1000, 0], [1000, -1000, 0], [1000, 1000, 0], [-1000, 1000, 0]].map(i16s).to_vec(), 8);
    let p = b.accessor(&positions, 4, "VEC3", 5122, Some((vec![-1000.0, -1000.0, 0.0], vec![1000.0, 1000.0, 0.0])));
    let normals = padded(vec![vec![0, 0, 127]; 4], 4);
    let n = b.accessor(&normals, 4, "VEC3", 5120, None);
    let uv16: Vec<u8> =
        [[0u16, 65535], [65535, 65535], [65535, 0], [0, 0]].iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
    let t = b.accessor(&uv16, 4, "VEC2", 5123, None);
    let i = b.accessor(&[0, 1, 2, 0, 2, 3], 6, "SCALAR", 5121, None);
    b.views[0]["byteStride"] = json!(8);
    b.views[1]["byteStride"] = json!(4);
    b.accessors[n]["normalized"] = json!(true);
    b.accessors[t]["normalized"] = json!(true);
    // The sparse square: vertex 0 at the origin (no view: zeros), 1 to 3 given as floats.
    let sparse_indices = b.accessor(&[1, 2, 3, 0], 1, "SCALAR", 5121, None);
    let values: Vec<u8> =
        [[2.0f32, 0.0, 0.0], [2.0, 2.0, 0.0], [0.0, 2.0, 0.0]].iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
    let sparse_values = b.accessor(&values, 1, "VEC3", 5126, None);
    let square = b.accessors.len();
    b.accessors.push(json!({
        "componentType": 5126, "count": 4, "type": "VEC3", "min": [0.0, 0.0, 0.0], "max": [2.0, 2.0, 0.0],
        "sparse": { "count": 3,
            "indices": { "bufferView": b.accessors[sparse_indices]["bufferView"], "componentType": 5121 },
            "values": { "bufferView": b.accessors[sparse_values]["bufferView"] } }
    }));
    let uv8 = padded(vec![vec![0, 255], vec![255, 255], vec![255, 0], vec![0, 0]], 4);
    let t8 = b.accessor(&uv8, 4, "VEC2", 5121, None);
    let last = b.views.len() - 1;
    b.views[last]["byteStride"] = json!(4);
    b.accessors[t8]["normalized"] = json!(true);
    let document = json!({
        "extensionsUsed": ["KHR_mesh_quantization"],
        "extensionsRequired": ["KHR_mesh_quantization"],
        "scenes": [{ "nodes": [0, 1] }],
        "nodes": [
            { "mesh": 0, "scale": [0.001, 0.001, 0.001] },
            { "mesh": 1, "translation": [5.0, 0.0, 0.0] }
        ],
        "meshes": [
            { "primitives": [{ "attributes": { "POSITION": p, "NORMAL": n, "TEXCOORD_0": t }, "indices": i }] },
            { "primitives": [{ "attributes": { "POSITION": square, "TEXCOORD_0": t8 }, "indices": i }] }
        ]
    });
    let (document, _) = b.finish(document, Some("data"));
    let loaded = load_scene(&write_json("quantized", &document)).unwrap_or_else(|e| panic!("{e}"));
    assert!(!loaded.warnings.join("\n").contains("KHR_mesh_quantization"), "{:?}", loaded.warnings);
    let scene = &loaded.scene;
    // The i16 quad dequantized by its node: ±1000 × 0.001 = ±1; glTF's uv (0, 1) at its
    // bottom-left corner is glint's (0, 0); its normal +z.
    let h = scene.intersect(&Ray::new(Vec3::new(-0.998, -0.998, 3.0), -Vec3::Z)).expect("the quantized quad");
    assert!((h.t - 3.0).abs() < 1e-5);
    assert!((h.geometry.uv - glam::Vec2::new(0.001, 0.001)).length() < 1e-4, "{}", h.geometry.uv);
    assert!((h.geometry.shading_normal - Vec3::Z).length() < 1e-5, "{}", h.geometry.shading_normal);
    assert!(scene.intersect(&Ray::new(Vec3::new(-1.01, 0.0, 3.0), -Vec3::Z)).is_none());
    // The sparse square spans [5, 7] × [0, 2]; its centre has u8 uv (½, ½).
    let h = scene.intersect(&Ray::new(Vec3::new(6.0, 1.0, 3.0), -Vec3::Z)).expect("the sparse square");
    assert!((h.geometry.uv - glam::Vec2::new(0.5, 0.5)).length() < 1e-5, "{}", h.geometry.uv);
    assert!(scene.intersect(&Ray::new(Vec3::new(6.9, 1.9, 3.0), -Vec3::Z)).is_some());
    assert!(scene.intersect(&Ray::new(Vec3::new(7.1, 1.0, 3.0), -Vec3::Z)).is_none());

    // A sparse index past the accessor's elements is an error naming it.
    let mut bad = document.clone();
    bad["accessors"][square]["count"] = json!(3);
    let e = load_scene(&write_json("sparse-past", &bad)).err().expect("an error").to_string();
    assert!(e.contains(&format!("accessor {square}: sparse index 3 is past its 3 elements")), "{e}");
}

/// A required extension glint cannot read is refused by name; one it reads loads.
#[test]
fn required_extensions_glint_cannot_read_are_refused_by_name() {
    let mut b = Builder::default();
    let quad = b.quad();
    let (document, _) = b.finish(
        json!({ "scenes": [{ "nodes": [0] }], "nodes": [{ "mesh": 0 }], "meshes": [{ "primitives": [quad] }] }),
        Some("data"),
    );
    for (extension, why) in [
        ("KHR_draco_mesh_compression", "no decoder"),
        ("EXT_meshopt_compression", "no decoder"),
        ("KHR_texture_basisu", "KTX2/Basis"),
        ("KHR_materials_pbrSpecularGlossiness", "does not read"),
    ] {
        let mut required = document.clone();
        required["extensionsUsed"] = json!([extension]);
        required["extensionsRequired"] = json!([extension]);
        let e = load_scene(&write_json("required", &required)).err().expect("an error").to_string();
        assert!(e.contains(&format!("requires the extension {extension}")) && e.contains(why), "{e}");
    }
    let mut read = document.clone();
    read["extensionsUsed"] = json!(["KHR_materials_clearcoat"]);
    read["extensionsRequired"] = json!(["KHR_materials_clearcoat"]);
    load_scene(&write_json("required-read", &read)).unwrap_or_else(|e| panic!("{e}"));
}

/// Alpha: MASK cuts out by the base colour texture's alpha against the cutoff, or by the
/// factor's alpha; BLEND makes the surface present with probability alpha; the scene renders
/// with volpath, whose shadow rays pass masks. A surface cut away entirely shows the sky.
#[test]
fn alpha_masks_and_blends_the_surface() {
    let mut b = Builder::default();
    let quad = b.quad();
    let primitive = |material: usize| {
        let mut p = quad.clone();
        p["material"] = json!(material);
        json!({ "primitives": [p] })
    };
    let rgba = image::RgbaImage::from_fn(2, 1, |x, _| image::Rgba([200, 100, 50, if x == 0 { 0 } else { 255 }]));
    let mut png = Vec::new();
    rgba.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png).unwrap();
    let document = json!({
        "scenes": [{ "nodes": [0, 1, 2, 3] }],
        "nodes": [
            { "mesh": 0, "translation": [-6.0, 0.0, 0.0] },
            { "mesh": 1, "translation": [-3.0, 0.0, 0.0] },
            { "mesh": 2 },
            { "mesh": 3, "translation": [3.0, 0.0, 0.0] }
        ],
        "meshes": [primitive(0), primitive(1), primitive(2), primitive(3)],
        "materials": [
            { "alphaMode": "MASK", "pbrMetallicRoughness": { "baseColorTexture": { "index": 0 } } },
            { "alphaMode": "BLEND", "pbrMetallicRoughness": { "baseColorFactor": [1.0, 1.0, 1.0, 0.25] } },
            { "alphaMode": "MASK", "pbrMetallicRoughness": { "baseColorFactor": [1.0, 1.0, 1.0, 0.4] } },
            { "alphaMode": "MASK", "alphaCutoff": 0.3, "pbrMetallicRoughness": { "baseColorFactor": [1.0, 1.0, 1.0, 0.4] } }
        ],
        "textures": [{ "source": 0 }],
        "images": [{ "uri": format!("data:image/png;base64,{}", base64::engine::general_purpose::STANDARD.encode(&png)) }]
    });
    let (document, _) = b.finish(document, Some("data"));
    let loaded = load_scene(&write_json("alpha", &document)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(loaded.render.integrator, IntegratorKind::VolPath);
    let scene = &loaded.scene;
    let material = |name: &str| {
        let i = scene
            .material_names()
            .iter()
            .position(|n| n == name)
            .unwrap_or_else(|| panic!("{name}: {:?}", scene.material_names()));
        &scene.materials()[i]
    };
    let Material::Mask(cut) = material("material 0: alpha") else { panic!() };
    let Texture::Image(opacity) = &cut.opacity else { panic!("{:?}", cut.opacity) };
    assert_eq!(opacity.evaluate(glam::Vec2::new(0.25, 0.5)), Rgb::ZERO);
    assert_eq!(opacity.evaluate(glam::Vec2::new(0.75, 0.5)), Rgb::ONE);
    let Material::Mask(blend) = material("material 1: alpha") else { panic!() };
    assert_eq!(blend.opacity, Texture::from(0.25));
    let Material::Mask(gone) = material("material 2: alpha") else { panic!() };
    assert_eq!(gone.opacity, Texture::from(0.0));
    assert!(!scene.material_names().iter().any(|n| n == "material 3: alpha"), "0.4 reaches the cutoff 0.3: opaque");

    // The quad cut away entirely, alone under the default sky: every pixel is the sky.
    let mut alone = document.clone();
    alone["scenes"] = json!([{ "nodes": [2] }]);
    let loaded = load_scene(&write_json("alpha-gone", &alone)).unwrap_or_else(|e| panic!("{e}"));
    let integrator = loaded.render.integrator.create(&loaded.render.integrator_settings).unwrap();
    let mut scene = loaded.scene;
    scene.set_camera(scene.camera().with_resolution(8, 6));
    let settings = RenderSettings { spp: 4, seed: 1, filter: loaded.render.filter, sampler: loaded.render.sampler };
    let image = render(&scene, integrator.as_ref(), &settings, &|| {}).film.to_rgb();
    for pixel in image {
        assert!((pixel - Rgb::ONE).abs().max_element() < 1e-5, "{pixel}");
    }
}

/// KHR_materials_unlit shows the base colour whatever the light: an emitter of it over a
/// surface that scatters nothing (one-sided unless the material is double-sided).
#[test]
fn an_unlit_material_shows_its_base_colour() {
    let mut b = Builder::default();
    let mut quad = b.quad();
    quad["material"] = json!(0);
    let document = json!({
        "extensionsUsed": ["KHR_materials_unlit"],
        "extensionsRequired": ["KHR_materials_unlit"],
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0 }],
        "meshes": [{ "primitives": [quad] }],
        "materials": [{ "pbrMetallicRoughness": { "baseColorFactor": [0.2, 0.4, 0.6, 1.0] }, "extensions": { "KHR_materials_unlit": {} } }]
    });
    let (document, _) = b.finish(document, Some("data"));
    let loaded = load_scene(&write_json("unlit", &document)).unwrap_or_else(|e| panic!("{e}"));
    assert!(!loaded.warnings.join("\n").contains("KHR_materials_unlit"), "{:?}", loaded.warnings);
    let scene = &loaded.scene;
    let i = scene.material_names().iter().position(|n| n == "material 0: emitting").unwrap();
    let Material::Emitter(emitter) = &scene.materials()[i] else { panic!("{:?}", scene.materials()[i]) };
    let shown = format!("{emitter:?}");
    assert!(shown.contains("Constant(Vec3(0.2, 0.4, 0.6))"), "{shown}");
    assert!(shown.contains("Diffuse { reflectance: Constant(Vec3(0.0, 0.0, 0.0)) }"), "{shown}");
}

/// A normal map's `scale` tilts its normals as glTF defines: normalize(s·x, s·y, z).
#[test]
fn a_normal_maps_scale_tilts_its_normals() {
    let mut b = Builder::default();
    let mut quad = b.quad();
    quad["material"] = json!(0);
    let texel = [204u8, 140, 230];
    let normals = png(1, 1, |_, _| texel);
    let document = json!({
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0 }],
        "meshes": [{ "primitives": [quad] }],
        "materials": [{ "normalTexture": { "index": 0, "scale": 2.0 } }],
        "textures": [{ "source": 0 }],
        "images": [{ "uri": format!("data:image/png;base64,{}", base64::engine::general_purpose::STANDARD.encode(&normals)) }]
    });
    let (document, _) = b.finish(document, Some("data"));
    let loaded = load_scene(&write_json("normal-scale", &document)).unwrap_or_else(|e| panic!("{e}"));
    assert!(!loaded.warnings.join("\n").contains("`scale`"), "{:?}", loaded.warnings);
    let scene = &loaded.scene;
    let i = scene.material_names().iter().position(|n| n == "material 0: normal-mapped").unwrap();
    let Material::NormalMap(mapped) = &scene.materials()[i] else { panic!() };
    let Texture::Image(image) = &mapped.normals else { panic!("{:?}", mapped.normals) };
    let stored = 2.0 * image.evaluate(glam::Vec2::new(0.5, 0.5)) - Vec3::ONE;
    let n = texel.map(|c| 2.0 * c as f32 / 255.0 - 1.0);
    let expected = Vec3::new(2.0 * n[0], 2.0 * n[1], n[2]).normalize();
    assert!((stored.normalize() - expected).length() < 1e-4, "{stored} vs {expected}");
}

/// A material whose textures name TEXCOORD_1 has its primitives' second uv set read; a
/// material whose textures name both sets is warned of and reads its base colour's.
#[test]
fn textures_on_the_second_uv_set_read_it() {
    let mut b = Builder::default();
    let mut quad = b.quad();
    // TEXCOORD_0 all at one point; TEXCOORD_1 the quad's own (quad() gives them as 0).
    quad["attributes"]["TEXCOORD_1"] = quad["attributes"]["TEXCOORD_0"].clone();
    quad["attributes"]["TEXCOORD_0"] = json!(b.pairs(&[[0.5, 0.5]; 4]));
    let mut mixed = quad.clone();
    quad["material"] = json!(0);
    mixed["material"] = json!(1);
    let image = png(1, 1, |_, _| [255, 255, 255]);
    let document = json!({
        "scenes": [{ "nodes": [0, 1] }],
        "nodes": [{ "mesh": 0 }, { "mesh": 1, "translation": [5.0, 0.0, 0.0] }],
        "meshes": [{ "primitives": [quad] }, { "primitives": [mixed] }],
        "materials": [
            { "pbrMetallicRoughness": { "baseColorTexture": { "index": 0, "texCoord": 1 } } },
            { "pbrMetallicRoughness": { "baseColorTexture": { "index": 0, "texCoord": 1 }, "metallicRoughnessTexture": { "index": 0 } } }
        ],
        "textures": [{ "source": 0 }],
        "images": [{ "uri": format!("data:image/png;base64,{}", base64::engine::general_purpose::STANDARD.encode(&image)) }]
    });
    let (document, _) = b.finish(document, Some("data"));
    let loaded = load_scene(&write_json("texcoord1", &document)).unwrap_or_else(|e| panic!("{e}"));
    let warnings = loaded.warnings.join("\n");
    assert!(!warnings.contains("material 0:"), "{warnings}");
    assert!(
        warnings.contains(
            "material 1: its textures read TEXCOORD_0 and TEXCOORD_1: glint reads one set per primitive, TEXCOORD_1"
        ),
        "{warnings}"
    );
    // glTF's uv (0, 1) at the bottom-left corner, glint's (0, 0): the second set's.
    for x in [0.0, 5.0] {
        let h = loaded.scene.intersect(&Ray::new(Vec3::new(x - 0.999, -0.999, 3.0), -Vec3::Z)).unwrap();
        assert!((h.geometry.uv - glam::Vec2::new(0.0005, 0.0005)).length() < 1e-3, "{}", h.geometry.uv);
    }
}

/// COLOR_0 multiplies the base colour, as glTF defines: an unlit quad whose base colour
/// (0.5, 1, 1) meets vertex colours (0.8, 0.4, 0.2) in floats shows (0.4, 0.4, 0.2); a
/// primitive without a material gets glTF's default material with its normalised 8-bit colours
/// as the base colour (the alpha is warned of); a primitive without colours keeps the plain
/// material.
#[test]
fn vertex_colours_multiply_the_base_colour() {
    let mut b = Builder::default();
    let mut unlit = b.quad();
    let colours = b.floats(&[[0.8, 0.4, 0.2]; 4]);
    unlit["attributes"]["COLOR_0"] = json!(colours);
    unlit["material"] = json!(0);
    let mut plain = b.quad();
    plain["material"] = json!(0);
    let mut default = b.quad();
    let bytes: Vec<u8> = [255u8, 128, 0, 100].repeat(4);
    let rgba = b.accessor(&bytes, 4, "VEC4", 5121, None);
    b.accessors[rgba]["normalized"] = json!(true);
    default["attributes"]["COLOR_0"] = json!(rgba);
    let document = json!({
        "extensionsUsed": ["KHR_materials_unlit"],
        "scenes": [{ "nodes": [0, 1, 2, 3] }],
        "nodes": [
            { "mesh": 0 },
            { "mesh": 1, "translation": [0, 0, -50] },
            { "mesh": 2, "translation": [0, 0, -60] },
            { "camera": 0, "translation": [0, 0, 5] }
        ],
        "cameras": [{ "type": "perspective", "perspective": { "yfov": 0.5, "znear": 0.1 } }],
        "meshes": [{ "primitives": [unlit] }, { "primitives": [default] }, { "primitives": [plain] }],
        "materials": [{ "pbrMetallicRoughness": { "baseColorFactor": [0.5, 1.0, 1.0, 1.0] }, "extensions": { "KHR_materials_unlit": {} } }]
    });
    let (document, _) = b.finish(document, Some("data"));
    let loaded = load_scene(&write_json("vertex-colours", &document)).unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.warnings.iter().any(|w| w.contains("alpha is not read")), "{:?}", loaded.warnings);
    let scene = &loaded.scene;
    let material_of = |o: usize| scene.material_names()[scene.objects()[o].material as usize].clone();
    assert_eq!(material_of(0), "material 0 × vertex colours: emitting");
    assert_eq!(material_of(1), "glTF default × vertex colours");
    assert_eq!(material_of(2), "material 0: emitting");
    let Shape::Mesh(mesh) = &scene.objects()[1].shape else { panic!("a mesh") };
    let attribute = mesh.attributes.iter().find(|a| a.name == "vertex_color").expect("the colours");
    assert_eq!(&attribute.values[..3], &[1.0, 128.0 / 255.0, 0.0]);

    // The unlit quad seen head-on at the image's centre: its emission, base × vertex colour.
    let integrator = loaded.render.integrator.create(&loaded.render.integrator_settings).unwrap();
    let settings = RenderSettings { spp: 4, ..RenderSettings::default() };
    let film = render(scene, integrator.as_ref(), &settings, &|| {}).film;
    let centre = film.pixel(film.width / 2, film.height / 2);
    assert!((centre - Rgb::new(0.4, 0.4, 0.2)).abs().max_element() < 1e-4, "{centre}");
}

/// KHR_materials_volume's attenuation becomes an absorbing medium inside the material's
/// meshes: colour ½ over a distance 2 is σ_a = ln 2 / 2 per unit (and colour 1 absorbs
/// nothing); the scene is rendered with volpath, and a material without attenuation makes no
/// medium.
#[test]
fn volume_attenuation_is_an_absorbing_interior_medium() {
    let mut b = Builder::default();
    let mut glass = b.quad();
    glass["material"] = json!(0);
    let mut plain = b.quad();
    plain["material"] = json!(1);
    let transmissive = |attenuation: bool| {
        let mut volume = json!({ "thicknessFactor": 1.0 });
        if attenuation {
            volume["attenuationColor"] = json!([0.5, 0.25, 1.0]);
            volume["attenuationDistance"] = json!(2.0);
        }
        json!({
            "pbrMetallicRoughness": { "metallicFactor": 0.0 },
            "extensions": { "KHR_materials_transmission": { "transmissionFactor": 1.0 }, "KHR_materials_volume": volume }
        })
    };
    let document = json!({
        "extensionsUsed": ["KHR_materials_transmission", "KHR_materials_volume"],
        "scenes": [{ "nodes": [0, 1] }],
        "nodes": [{ "mesh": 0 }, { "mesh": 1, "translation": [3, 0, 0] }],
        "meshes": [{ "primitives": [glass] }, { "primitives": [plain] }],
        "materials": [transmissive(true), transmissive(false)]
    });
    let (document, _) = b.finish(document, Some("data"));
    let loaded = load_scene(&write_json("volume", &document)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(loaded.render.integrator, IntegratorKind::VolPath);
    let scene = &loaded.scene;
    assert_eq!(scene.media().len(), 1);
    let shown = format!("{:?}", scene.media()[0]);
    let sigma = |c: f32| (1.0 / c).ln() / 2.0;
    assert!(shown.contains(&format!("{:?}", Rgb::new(sigma(0.5), sigma(0.25), 0.0))), "{shown}");
}

/// EXT_mesh_gpu_instancing places a node's mesh once per instance, by each instance's
/// translation, rotation and scale within the node: three instances of a quad, the second
/// turned a quarter about x (edge-on to the view, facing y) and the third scaled by 2, under a
/// node moved along z.
#[test]
fn gpu_instancing_places_the_mesh_per_instance() {
    let mut b = Builder::default();
    let quad = b.quad();
    let translations = b.floats(&[[0.0, 0.0, 0.0], [5.0, 0.0, 0.0], [10.0, 0.0, 0.0]]);
    let half = std::f32::consts::FRAC_1_SQRT_2;
    let rotation_bytes: Vec<u8> = [[0.0, 0.0, 0.0, 1.0], [half, 0.0, 0.0, half], [0.0, 0.0, 0.0, 1.0]]
        .iter()
        .flatten()
        .flat_map(|x: &f32| x.to_le_bytes())
        .collect();
    let rotations = b.accessor(&rotation_bytes, 3, "VEC4", 5126, None);
    let scales = b.floats(&[[1.0; 3], [1.0; 3], [2.0; 3]]);
    let document = json!({
        "extensionsUsed": ["EXT_mesh_gpu_instancing"],
        "scenes": [{ "nodes": [0] }],
        "nodes": [{
            "mesh": 0,
            "translation": [0, 0, -3],
            "extensions": { "EXT_mesh_gpu_instancing": { "attributes": { "TRANSLATION": translations, "ROTATION": rotations, "SCALE": scales } } }
        }],
        "meshes": [{ "primitives": [quad] }]
    });
    let (document, _) = b.finish(document, Some("data"));
    let loaded = load_scene(&write_json("gpu-instancing", &document)).unwrap_or_else(|e| panic!("{e}"));
    assert!(!loaded.warnings.iter().any(|w| w.contains("EXT_mesh_gpu_instancing")), "{:?}", loaded.warnings);
    let scene = &loaded.scene;
    assert_eq!(scene.objects().len(), 3);
    // The quad spans ±1 in x and y: seen along −z through each instance's corner region.
    let hit_at = |x: f32, y: f32| scene.intersect(&Ray::new(Vec3::new(x, y, 5.0), -Vec3::Z)).map(|h| h.t);
    assert_eq!(hit_at(0.5, 0.5), Some(8.0));
    // Turned about x: edge-on along −z, met along −y at y = 0 (z from −4 to −2).
    assert!(hit_at(5.5, 0.9).is_none());
    let down = scene.intersect(&Ray::new(Vec3::new(5.5, 5.0, -3.5), -Vec3::Y)).map(|h| h.t);
    assert!(down.is_some_and(|t| (t - 5.0).abs() < 1e-4), "{down:?}");
    // Scaled by 2: reaches x = 10 + 1.9.
    assert!(hit_at(11.9, 0.0).is_some_and(|t| (t - 8.0).abs() < 1e-4));
    assert!(hit_at(2.5, 0.0).is_none());
}
