//! One pixel explained (`glint explain`): the integrator made as a render makes it
//! (`IntegratorKind::build_until`) and asked what its estimate of the pixel is made of, by the
//! code that renders. What each kind tells: Whitted its ray tree, the path tracers and the
//! photon mappers a camera path's events, light tracing its first pass's particles that land
//! in the pixel, SPPM its first pass's camera path and gather.

use std::sync::atomic::AtomicBool;

use super::passes::{pixel_sample, Pass};
use super::path_record::PathLog;
use super::recorder::RayTree;
use super::{Built, IntegratorKind, IntegratorSettings, ParticleExplanation, SampleContext, SppmExplanation};
use crate::geometry::Ray;
use crate::sampling::Rng;
use crate::scene::Scene;
use crate::{Named, RenderError, Rgb};

/// What the estimate along one camera ray is made of (`Integrator::explain`).
#[derive(Clone, Debug)]
pub enum CameraExplanation {
    /// Whitted's ray tree, the colour it adds up to, and whether a ceiling
    /// (`whitted::DEPTH_CEILING`, `whitted::TREE_RAY_LIMIT`) cut it.
    Tree { tree: RayTree, colour: Rgb, cut: bool },
    /// A camera path's events and the radiance they add up to, bit for bit.
    Path { radiance: Rgb, log: PathLog },
}

/// One pixel's explanation, by integrator kind.
#[derive(Clone, Debug)]
pub enum PixelExplanation {
    /// The camera ray through the pixel (the pass's sample; Whitted's through the centre) and
    /// what its estimate is made of.
    Camera { ray: Ray, explanation: CameraExplanation },
    /// Light tracing's first pass: the particles that land in the pixel.
    Particles(ParticleExplanation),
    /// SPPM's first pass: the camera ray, its path to the visible point, and the gather there.
    Sppm { ray: Ray, explanation: SppmExplanation },
}

impl IntegratorKind {
    /// Pixel (x, y) of `scene` explained by this integrator, made with `settings` and
    /// `pass.seed` as a render makes it; the camera sample is `pass`'s. An error where the
    /// render would refuse (no physical light), or for an integrator that explains nothing
    /// (`explains`).
    pub fn explain_pixel(
        self,
        settings: &IntegratorSettings,
        scene: &Scene,
        pass: &Pass,
        (x, y): (u32, u32),
    ) -> Result<PixelExplanation, RenderError> {
        let camera = |integrator: &dyn super::Integrator| {
            let (ray, mut context) = if self == IntegratorKind::Whitted {
                // Whitted draws no random numbers: the pixel centre's ray, as `--spp 1` takes it.
                let ray = scene.camera().generate_ray(x as f32 + 0.5, y as f32 + 0.5);
                (ray, SampleContext::new(Rng::new(0, 0)))
            } else {
                pixel_sample(scene, pass, x, y)
            };
            let explanation = integrator
                .explain(scene, &ray, &mut context)
                .ok_or(RenderError::NothingToExplain { integrator: self.name() })?;
            Ok(PixelExplanation::Camera { ray, explanation })
        };
        match self.build_until(settings, scene, pass.seed, &AtomicBool::new(false))? {
            Built::Camera(integrator) => camera(integrator.as_ref()),
            Built::Photon(mapper) => camera(&mapper),
            Built::Light(tracer) => Ok(PixelExplanation::Particles(tracer.explain_pixel(scene, pass.seed, (x, y)))),
            Built::Sppm(sppm) => {
                let explanation = sppm.explain_pixel(scene, pass, (x, y));
                let (ray, _) = pixel_sample(scene, pass, x, y);
                Ok(PixelExplanation::Sppm { ray, explanation })
            }
        }
    }
}
