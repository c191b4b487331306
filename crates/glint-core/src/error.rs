//! Why a render cannot start or resume: the core's errors, typed, each with the message a user
//! reads (the readers and the CLI add the file and the flag).

/// An integrator refusing a scene, a render interrupted before its first pass, or a
/// checkpoint's integrator state that does not fit the render.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum RenderError {
    #[error(
        "light {light} has falloff = \"none\", which no physical light has; light tracing, photon mapping and SPPM need falloff = \"inverse-square\""
    )]
    UnphysicalLight {
        /// Counted from 1, in the scene's order.
        light: usize,
    },
    #[error("the scene has no light that emits (light tracing and photon mapping start at the lights)")]
    NoEmittingLight,
    #[error(
        "light tracing connects to a single camera point: it needs a pinhole or orthographic camera, not a thin lens"
    )]
    ThinLensLightTracing,
    #[error("interrupted while the photon maps were built")]
    Interrupted,
    #[error(
        "volphoton shoots photons from lights only, and a medium of this scene emits light: render it with volpath"
    )]
    EmittingMedium,
    #[error("the checkpoint holds state this integrator does not have")]
    UnexpectedState,
    #[error("the checkpoint's SPPM state does not match this render")]
    StateMismatch,
    #[error("the checkpoint's SPPM state of pixel {pixel} is not finite and non-negative")]
    BadPixelState { pixel: usize },
    /// `glint explain` with an integrator that has no paths or ray trees to tell.
    #[error("`{integrator}` has no paths or ray trees to explain (it shows what the camera ray hits first)")]
    NothingToExplain { integrator: &'static str },
}
