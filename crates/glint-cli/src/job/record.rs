//! What a render's outputs record of it: the image's metadata, a partial render's header (its
//! identity, which parts merge by), and what a checkpoint must hold to resume it.

use glint_core::filter::Filter;
use glint_core::integrators::IntegratorKind;
use glint_core::render::RenderOutput;
use glint_core::Named;

use super::{Job, Plan};
use crate::{checkpoint, partial};

impl Job {
    /// The image's metadata: `glint:spp`, `seed`, `integrator`, `version`, `render_seconds`,
    /// `camera_to_world` (row-major 4×4; camera space x right, y up, z forward), `fov`.
    pub fn metadata(&self, plan: &Plan, output: &RenderOutput) -> Vec<(&'static str, String)> {
        let camera = self.scene().camera();
        let matrix = camera.camera_to_world().iter().flatten().map(|v| v.to_string()).collect::<Vec<_>>().join(" ");
        vec![
            ("glint:spp", output.spp_done.to_string()),
            ("glint:seed", plan.settings.seed.to_string()),
            ("glint:integrator", plan.kind.name().to_string()),
            ("glint:version", env!("CARGO_PKG_VERSION").to_string()),
            ("glint:render_seconds", output.elapsed.as_secs_f64().to_string()),
            ("glint:camera_to_world", matrix),
            ("glint:fov", camera.fov_degrees.to_string()),
        ]
    }

    /// A sample range's header: the metadata, the samples it holds (a render stopped early
    /// holds the passes it finished), and what it is part of (`partial::IDENTITY_KEYS`).
    /// `None` for a render that is not a sample range.
    pub fn partial_attributes(&self, plan: &Plan, output: &RenderOutput) -> Option<Vec<(&'static str, String)>> {
        let (first, _) = plan.sample_range?;
        let identity = plan.identity.expect("a sample range's plan has its identity");
        let mut attributes = self.metadata(plan, output);
        attributes.extend([
            (partial::SAMPLES_KEY, partial::format_ranges(&[(first, first + output.spp_done)])),
            ("glint:sampler", plan.settings.sampler.name().to_string()),
            ("glint:filter", plan.settings.filter.name().to_string()),
            ("glint:identity", format!("{identity:016x}")),
            ("glint:scene", self.source().display_name()),
        ]);
        Some(attributes)
    }

    /// What a checkpoint must hold to resume this render: its size, seed, identity and sample
    /// count, and each pixel's weight as the integrator and filter make it.
    pub fn expected_checkpoint(&self, plan: &Plan) -> checkpoint::Expected {
        let filter = plan.settings.filter;
        checkpoint::Expected {
            width: self.scene().camera().width,
            height: self.scene().camera().height,
            seed: plan.settings.seed,
            fingerprint: plan.identity.expect("a resumed render's plan has its identity"),
            spp: plan.settings.spp,
            weights: match plan.kind {
                IntegratorKind::Sppm => checkpoint::WeightRule::One,
                IntegratorKind::Light => checkpoint::WeightRule::PerPass,
                _ if filter == Filter::Box => checkpoint::WeightRule::PerPass,
                _ => checkpoint::WeightRule::Finite,
            },
            nonnegative: filter != Filter::Mitchell,
        }
    }
}
