//! Which of the shipped scenes the path tracer runs as a wavefront in SIMD lanes (its
//! agreement with the path tracer bit for bit is glint-core's tests/wavefront.rs): every one
//! does, with every kind of light, or it silently loses its speed.

use std::path::Path;

use glint_core::integrators::PathTracer;

fn runs_as_wavefront(name: &str) -> bool {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name);
    let loaded = glint_scene::load_scene(&path).expect("the scene loads");
    PathTracer::new(&loaded.render.integrator_settings).runs_as_wavefront(&loaded.scene)
}

#[test]
fn every_shipped_scene_runs_as_a_wavefront() {
    assert!(runs_as_wavefront("cornell-box.toml"));
    // Mirrors and glass: those bounces are the scalar code's, the rest stays in lanes.
    assert!(runs_as_wavefront("cornell-box-mixed.toml"));
    assert!(runs_as_wavefront("cornell-box-glass.toml"));
    // An environment light, point lights: sampled by the scalar code lane by lane.
    assert!(runs_as_wavefront("sky.toml"));
    assert!(runs_as_wavefront("whitted-1980.toml"));
    assert!(runs_as_wavefront("caustic-point-light.toml"));
}
