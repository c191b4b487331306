//! Which of the shipped scenes the path tracer runs as a wavefront in SIMD lanes (its
//! agreement with the path tracer bit for bit is glint-core's tests/wavefront.rs): the Cornell
//! box must, or it silently loses its speed.

use std::path::Path;

use glint_core::integrators::PathTracer;

fn runs_as_wavefront(name: &str) -> bool {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name);
    let loaded = glint_scene::load_scene(&path).expect("the scene loads");
    PathTracer::new(&loaded.render.integrator_settings).runs_as_wavefront(&loaded.scene)
}

#[test]
fn the_cornell_box_runs_as_a_wavefront_and_its_mirrors_and_glass_do_not() {
    assert!(runs_as_wavefront("cornell-box.toml"));
    assert!(!runs_as_wavefront("cornell-box-mixed.toml"));
    assert!(!runs_as_wavefront("cornell-box-glass.toml"));
}
