//! Which of the shipped scenes the path tracer runs as a wavefront in SIMD lanes (its
//! agreement with the path tracer bit for bit is glint-core's tests/wavefront.rs): the Cornell
//! boxes must, or they silently lose their speed.

use std::path::Path;

use glint_core::integrators::PathTracer;

fn runs_as_wavefront(name: &str) -> bool {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name);
    let loaded = glint_scene::load_scene(&path).expect("the scene loads");
    PathTracer::new(&loaded.render.integrator_settings).runs_as_wavefront(&loaded.scene)
}

#[test]
fn the_cornell_boxes_run_as_a_wavefront_and_a_sky_does_not() {
    assert!(runs_as_wavefront("cornell-box.toml"));
    // Mirrors and glass: those bounces are the scalar code's, the rest stays in lanes.
    assert!(runs_as_wavefront("cornell-box-mixed.toml"));
    assert!(runs_as_wavefront("cornell-box-glass.toml"));
    // An environment light is not sampled in the lanes.
    assert!(!runs_as_wavefront("sky.toml"));
}
