//! The path tracer's wavefront (eight paths at a time in SIMD lanes) against the path tracer
//! one path at a time: the same radiance bit for bit and the same rays traced, for every
//! pixel, sampler, seed and depth setting tried. The scalar path tracer is what the ground
//! truth tests (cornell_box.rs) check against Mitsuba; this carries their verdict over.

use std::path::Path;

use glint_core::geometry::Ray;
use glint_core::integrators::{Integrator, IntegratorSettings, PathTracer, SampleContext};
use glint_core::lights::TriangleSampling;
use glint_core::sampling::{Sampler, SamplerKind};
use glint_core::scene::Scene;
use glint_core::Rgb;

fn load(name: &str, size: u32) -> (Scene, IntegratorSettings) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name);
    let loaded = glint_scene::load_scene(&path).expect("the scene loads");
    let mut scene = loaded.scene;
    scene.camera = scene.camera.with_resolution(size, size);
    (scene, loaded.render.integrator_settings)
}

/// Every pixel's camera sample `index`: rays and contexts as the render loop makes them.
fn camera_samples(scene: &Scene, sampler: SamplerKind, seed: u64, index: u32) -> (Vec<Ray>, Vec<SampleContext>) {
    let (w, h) = (scene.camera.width, scene.camera.height);
    (0..w * h)
        .map(|i| {
            let mut context = SampleContext::with_sampler(Sampler::new(sampler, seed, i as u64, index, 64));
            let (fx, fy) = ((i % w) as f32 + context.sampler.next_f32(), (i / w) as f32 + context.sampler.next_f32());
            (scene.camera.generate_ray(fx, fy), context)
        })
        .unzip()
}

/// Renders sample `index` of every pixel both ways and asserts they agree exactly; returns
/// the number of pixels that saw light (so a test can tell it compared something).
fn assert_same(scene: &Scene, tracer: &PathTracer, sampler: SamplerKind, seed: u64, index: u32) -> usize {
    let (rays, contexts) = camera_samples(scene, sampler, seed, index);
    let mut one_by_one = contexts.clone();
    let expected: Vec<Rgb> =
        rays.iter().zip(one_by_one.iter_mut()).map(|(ray, context)| tracer.radiance(scene, ray, context)).collect();
    let mut together = contexts;
    let mut got = vec![Rgb::ZERO; rays.len()];
    // In tile-sized batches, as the render loop hands them over.
    for ((rays, contexts), out) in rays.chunks(256).zip(together.chunks_mut(256)).zip(got.chunks_mut(256)) {
        tracer.radiance_tile(scene, rays, contexts, out);
    }
    for i in 0..rays.len() {
        assert_eq!(
            got[i].to_array().map(f32::to_bits),
            expected[i].to_array().map(f32::to_bits),
            "pixel {i}, sample {index}, seed {seed}: {} against {}",
            got[i],
            expected[i]
        );
        assert_eq!(together[i].rays, one_by_one[i].rays, "rays traced for pixel {i}");
    }
    expected.iter().filter(|r| r.max_element() > 0.0).count()
}

#[test]
fn the_wavefront_renders_the_cornell_box_bit_for_bit_as_the_path_tracer() {
    let (scene, settings) = load("cornell-box.toml", 48);
    let tracer = PathTracer { max_depth: settings.max_depth, rr_depth: settings.rr_depth };
    assert!(tracer.runs_as_wavefront(&scene), "the Cornell box is a wavefront scene");
    for sampler in SamplerKind::ALL {
        for (seed, index) in [(0, 0), (7, 3), (123, 41)] {
            let lit = assert_same(&scene, &tracer, sampler, seed, index);
            assert!(lit > 48 * 48 / 2, "{lit} pixels lit");
        }
    }
}

/// A smooth mesh (vertex normals) in the box: the lanes' shading normals, the BSDF frame
/// turned to the viewer and the fallback to the geometric normal.
#[test]
fn the_wavefront_shades_smooth_meshes_as_the_path_tracer() {
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let mut text = std::fs::read_to_string(scenes.join("cornell-box.toml")).expect("the Cornell box reads");
    text.push_str(&format!(
        "\n[[shapes]]\ntype = \"mesh\"\nname = \"torus\"\nfile = {:?}\nmaterial = \"white\"\n\
         transform = [{{ rotate = {{ axis = [1, 0, 0], angle = 60 }} }}, {{ scale = 110 }}, \
         {{ translate = [278, 330, 200] }}]\n",
        scenes.join("meshes/torus.obj").display().to_string()
    ));
    let dir = std::env::temp_dir().join(format!("glint-wavefront-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let path = dir.join("smooth.toml");
    std::fs::write(&path, text).expect("the scene writes");
    let loaded = glint_scene::load_scene(&path).expect("the scene loads");
    std::fs::remove_dir_all(&dir).ok();
    let mut scene = loaded.scene;
    scene.camera = scene.camera.with_resolution(48, 48);
    let settings = loaded.render.integrator_settings;
    let tracer = PathTracer { max_depth: settings.max_depth, rr_depth: settings.rr_depth };
    assert!(tracer.runs_as_wavefront(&scene), "a diffuse smooth mesh is a wavefront scene");
    for (seed, index) in [(0, 0), (5, 2), (9, 17)] {
        assert_same(&scene, &tracer, SamplerKind::Sobol, seed, index);
    }
}

/// Depth limits and roulette from the first bounce: paths that end at every stage.
#[test]
fn the_wavefront_ends_paths_as_the_path_tracer_does() {
    let (scene, _) = load("cornell-box.toml", 32);
    for (max_depth, rr_depth) in [(0, 5), (1, 5), (2, 1), (u32::MAX, 1), (6, 3)] {
        let tracer = PathTracer { max_depth, rr_depth };
        for seed in 0..3 {
            assert_same(&scene, &tracer, SamplerKind::Sobol, seed, seed as u32);
        }
    }
}

/// Scenes the lanes do not serve go path by path, with the same result as ever.
#[test]
fn other_scenes_fall_back_to_one_path_at_a_time() {
    let (mut scene, settings) = load("cornell-box.toml", 24);
    let tracer = PathTracer { max_depth: settings.max_depth, rr_depth: settings.rr_depth };
    scene.area_lights.triangle_sampling = TriangleSampling::SolidAngle;
    assert!(!tracer.runs_as_wavefront(&scene), "solid-angle light sampling is not in the lanes");
    assert_same(&scene, &tracer, SamplerKind::Sobol, 1, 0);
    let (scene, settings) = load("cornell-box-mixed.toml", 24);
    let tracer = PathTracer { max_depth: settings.max_depth, rr_depth: settings.rr_depth };
    assert!(!tracer.runs_as_wavefront(&scene), "mirrors and glass are not in the lanes");
    assert_same(&scene, &tracer, SamplerKind::Sobol, 1, 0);
}
