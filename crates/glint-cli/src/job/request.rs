//! What a front end asks of a render ([`Request`]: the overrides of the scene's settings),
//! its checks, and the [`Plan`] the job makes of it with the scene: the integrator and its
//! settings, the samples, the identity, the memory estimate held to the limit, the threads.

use std::time::Duration;

use glint_core::filter::Filter;
use glint_core::integrators::{IntegratorKind, IntegratorSettings};
use glint_core::render::{Progressive, RenderSettings};
use glint_core::sampling::SamplerKind;
use glint_core::Named;

use super::{identity::RenderIdentity, Job};
use crate::error::CliError;
use crate::limits;

/// Which front end asks, for the names its messages give the settings: the command's flags
/// (`--samples`) or the Python module's arguments (`samples`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FrontEnd {
    #[default]
    Command,
    Python,
}

impl FrontEnd {
    /// A setting, named as the command's flag without its dashes (`min-contribution`), as
    /// this front end names it: `--min-contribution`, or `min_contribution`.
    pub fn name(self, setting: &str) -> String {
        match self {
            FrontEnd::Command => format!("--{setting}"),
            FrontEnd::Python => setting.replace('-', "_"),
        }
    }
}

/// Overrides of the integrator's settings (`None`, `false`: the scene's). Checked by
/// [`IntegratorOverrides::apply`], for `glint render` and `glint explain` alike.
#[derive(Clone, Copy, Debug, Default)]
pub struct IntegratorOverrides {
    pub max_depth: Option<u32>,
    pub min_contribution: Option<f32>,
    pub transparent_shadows: bool,
    pub no_wavefront: bool,
    pub photons: Option<u32>,
    pub caustic_photons: Option<u32>,
    pub photon_nearest: Option<u32>,
    pub photon_radius: Option<f32>,
    pub final_gather: Option<u32>,
    pub sppm_radius: Option<f32>,
    pub photons_per_pass: Option<u32>,
}

impl IntegratorOverrides {
    /// The values no integrator takes: a negative or non-finite contribution or radius.
    pub fn check(&self, names: FrontEnd) -> Result<(), CliError> {
        if let Some(c) = self.min_contribution {
            if !(c.is_finite() && c >= 0.0) {
                return Err(CliError::Setting(format!(
                    "{} must be a number ≥ 0, got {c}",
                    names.name("min-contribution")
                )));
            }
        }
        for (setting, value) in [("photon-radius", self.photon_radius), ("sppm-radius", self.sppm_radius)] {
            if let Some(v) = value.filter(|v| !(v.is_finite() && *v >= 0.0)) {
                return Err(CliError::Setting(format!(
                    "{} must be a length ≥ 0 (0: automatic), got {v}",
                    names.name(setting)
                )));
            }
        }
        Ok(())
    }

    /// The scene's settings with these overrides, checked.
    pub fn apply(&self, from_scene: &IntegratorSettings, names: FrontEnd) -> Result<IntegratorSettings, CliError> {
        self.check(names)?;
        let mut s = *from_scene;
        s.max_depth = self.max_depth.unwrap_or(s.max_depth);
        s.min_contribution = self.min_contribution.unwrap_or(s.min_contribution);
        s.transparent_shadows |= self.transparent_shadows;
        s.wavefront &= !self.no_wavefront;
        let p = &mut s.photon;
        p.global_photons = self.photons.unwrap_or(p.global_photons);
        p.caustic_photons = self.caustic_photons.unwrap_or(p.caustic_photons);
        p.nearest = self.photon_nearest.unwrap_or(p.nearest);
        p.max_radius = self.photon_radius.unwrap_or(p.max_radius);
        p.final_gather = self.final_gather.unwrap_or(p.final_gather);
        s.sppm_radius = self.sppm_radius.unwrap_or(s.sppm_radius);
        s.photons_per_pass = self.photons_per_pass.unwrap_or(s.photons_per_pass);
        Ok(s)
    }
}

/// What a front end asks of one render of a [`Job`]'s scene: overrides of its settings
/// (`None`, `false`: the scene's) and what the render must keep.
#[derive(Clone, Debug, Default)]
pub struct Request {
    /// Whose names the messages use.
    pub front_end: FrontEnd,
    pub integrator: Option<IntegratorKind>,
    pub settings: IntegratorOverrides,
    pub spp: Option<u32>,
    pub seed: Option<u64>,
    pub filter: Option<Filter>,
    pub sampler: Option<SamplerKind>,
    /// Samples a to b − 1 of every pixel alone, as a part to merge.
    pub samples: Option<(u32, u32)>,
    /// Seconds to render for (then `spp` is an upper bound).
    pub time: Option<f64>,
    /// Keep each pixel's second moment (asked by the user; the scene may ask too).
    pub moment: bool,
    /// The AOVs, and a camera render's variance, beside the image.
    pub aovs: bool,
    /// Checkpoints will be written (the identity is needed).
    pub checkpoint: bool,
    /// The render resumes from a checkpoint.
    pub resume: bool,
    /// Worker threads, 1 to `limits::MAX_THREADS` (`None`: every core).
    pub threads: Option<usize>,
}

impl Request {
    /// The checks that need no scene: a front end makes them before loading one, so that a
    /// bad request is refused before any work ([`Job::plan`] makes them again).
    pub fn check(&self) -> Result<(), CliError> {
        let name = |setting: &str| self.front_end.name(setting);
        if let Some((a, b)) = self.samples {
            crate::partial::check_range(a, b).map_err(|e| CliError::Setting(format!("{}: {e}", name("samples"))))?;
            let conflicts = [
                ("spp", self.spp.is_some()),
                ("time", self.time.is_some()),
                ("checkpoint", self.checkpoint),
                ("resume", self.resume),
                ("moment", self.moment),
            ];
            if let Some((setting, _)) = conflicts.iter().find(|(_, given)| *given) {
                return Err(CliError::Setting(format!(
                    "{} renders exactly the samples it names: it cannot be combined with {}",
                    name("samples"),
                    name(setting)
                )));
            }
            if self.aovs {
                return Err(CliError::Setting(format!(
                    "{} writes a part to merge, whose sums alone merge exactly: leave {} to the merged render",
                    name("samples"),
                    name("aovs")
                )));
            }
        }
        if let Some(t) = self.time.filter(|t| !(t.is_finite() && *t > 0.0)) {
            return Err(CliError::Setting(format!("{} must be a positive number of seconds, got {t}", name("time"))));
        }
        if let Some(n) = self.threads {
            limits::thread_count(n as i128).map_err(CliError::Setting)?;
        }
        self.settings.check(self.front_end)
    }
}

/// What a render will do, decided from the scene and the request before any work.
#[derive(Clone, Debug)]
pub struct Plan {
    pub kind: IntegratorKind,
    pub integrator: IntegratorSettings,
    pub settings: RenderSettings,
    pub time_limit: Option<Duration>,
    pub sample_range: Option<(u32, u32)>,
    /// The render's identity ([`RenderIdentity`]) as a fingerprint, when a checkpoint or a
    /// part needs it (`None` otherwise: the scene's files are not read again for it).
    pub identity: Option<u64>,
    /// Keep each pixel's second moment, to write it (`--moment`, the scene's `moment`).
    pub moment: bool,
    /// Keep each pixel's second moment for its variance (with the AOVs, camera renders).
    pub variance: bool,
    /// Render the AOVs after the image.
    pub aovs: bool,
    pub threads: Option<usize>,
}

impl Plan {
    /// What the render loop is asked.
    pub fn progressive(&self) -> Progressive {
        Progressive {
            settings: self.settings,
            time_limit: self.time_limit,
            second_moment: self.moment || self.variance,
            sample_range: self.sample_range,
        }
    }
}

impl Job {
    /// The plan of a render of this scene with `request`'s overrides, checked, its memory
    /// estimate held to `memory_limit` bytes ([`super::memory_limit`]); and what is worth
    /// telling about it (the scene's `moment` that cannot be kept).
    pub fn plan(&self, request: &Request, memory_limit: u64) -> Result<(Plan, Vec<String>), CliError> {
        request.check()?;
        let names = request.front_end;
        let options = self.options();
        let scene = self.scene();
        let mut warnings = Vec::new();
        let kind = request.integrator.unwrap_or(options.integrator);
        if request.samples.is_some() && !kind.samples_pixels() {
            return Err(CliError::Setting(format!(
                "{}: `{}` does not take samples of its own per pixel (its passes share particles or photon statistics across pixels), so its passes cannot be rendered apart and merged; use a camera integrator",
                names.name("samples"),
                kind.name()
            )));
        }
        let integrator = request.settings.apply(&options.integrator_settings, names)?;
        let mut settings = RenderSettings {
            spp: request.spp.unwrap_or(options.spp),
            seed: request.seed.unwrap_or(options.seed),
            filter: request.filter.unwrap_or(options.filter),
            sampler: request.sampler.unwrap_or(options.sampler),
        };
        // Checked positive and finite; beyond what a Duration holds, unlimited in effect.
        let time_limit = request.time.map(|t| Duration::try_from_secs_f64(t).unwrap_or(Duration::MAX));
        if time_limit.is_some() && request.spp.is_none() {
            settings.spp = u32::MAX; // the time limit decides
        }
        let (width, height) = (scene.camera().width, scene.camera().height);
        let identity = (request.checkpoint || request.resume || request.samples.is_some()).then(|| {
            RenderIdentity {
                scene_contents: self.scene_contents(),
                defines: self.source().defines(),
                kind,
                integrator,
                methods: scene.geometry().methods(),
                width,
                height,
                filter: settings.filter,
                sampler: settings.sampler,
                strata_spp: (settings.sampler == SamplerKind::Stratified && request.samples.is_none())
                    .then_some(settings.spp),
                triangle_sampling: scene.lights().triangle_sampling(),
            }
            .fingerprint()
        });
        let moment = (request.moment || options.moment) && {
            match moment_impossible(request, kind) {
                None => true,
                Some(why) if request.moment => {
                    return Err(CliError::Setting(format!("{}: {why}", names.name("moment"))));
                }
                Some(why) => {
                    warnings
                        .push(format!("the scene asks for the second moment (`moment`), which is not written: {why}"));
                    false
                }
            }
        };
        // The variance needs the second moment, which only a fresh camera render keeps.
        let variance = request.aovs && kind.samples_pixels() && !request.resume;
        limits::check_memory(kind, &integrator, width, height, memory_limit)?;
        let plan = Plan {
            kind,
            integrator,
            settings,
            time_limit,
            sample_range: request.samples,
            identity,
            moment,
            variance,
            aovs: request.aovs,
            threads: request.threads,
        };
        Ok((plan, warnings))
    }
}

/// Why this render cannot keep the second moment, if it cannot: a camera integrator's samples
/// each land in the film (particles' splats do not), from a fresh film (checkpoints keep no
/// second moment). Asked by the user, such a render is refused; asked by the scene, it goes
/// on without, with a warning.
fn moment_impossible(request: &Request, kind: IntegratorKind) -> Option<String> {
    if !kind.samples_pixels() {
        Some(format!("`{}` splats particles into the film, so its pixels have no samples of their own", kind.name()))
    } else if request.resume {
        Some("a checkpoint keeps no second moment, so a resumed render cannot write one".to_string())
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn refused(request: Request) -> String {
        request.check().unwrap_err().to_string()
    }

    /// Each front end's names for the same check.
    #[test]
    fn conflicts_are_named_as_each_front_end_names_them() {
        let request = Request { samples: Some((0, 4)), spp: Some(4), ..Default::default() };
        assert_eq!(
            refused(request.clone()),
            "--samples renders exactly the samples it names: it cannot be combined with --spp"
        );
        let python = Request { front_end: FrontEnd::Python, ..request };
        assert_eq!(refused(python), "samples renders exactly the samples it names: it cannot be combined with spp");
        for (request, flag) in [
            (Request { time: Some(1.0), ..Default::default() }, "--time"),
            (Request { checkpoint: true, ..Default::default() }, "--checkpoint"),
            (Request { resume: true, ..Default::default() }, "--resume"),
            (Request { moment: true, ..Default::default() }, "--moment"),
        ] {
            let message = refused(Request { samples: Some((2, 3)), ..request });
            assert!(message.ends_with(&format!("cannot be combined with {flag}")), "{message}");
        }
        let aovs = refused(Request { samples: Some((0, 1)), aovs: true, ..Default::default() });
        assert!(aovs.contains("leave --aovs to the merged render"), "{aovs}");
        let empty = refused(Request { front_end: FrontEnd::Python, samples: Some((4, 4)), ..Default::default() });
        assert!(empty.starts_with("samples: the range 4..4 is empty"), "{empty}");
    }

    #[test]
    fn out_of_range_values_are_refused_before_any_work() {
        assert_eq!(
            refused(Request { time: Some(-1.0), ..Default::default() }),
            "--time must be a positive number of seconds, got -1"
        );
        assert!(refused(Request { time: Some(f64::NAN), ..Default::default() }).contains("got NaN"));
        assert_eq!(
            refused(Request { threads: Some(100_000), ..Default::default() }),
            "the number of worker threads must be from 1 to 1024, got 100000"
        );
        assert!(Request { threads: Some(0), ..Default::default() }.check().is_err());
        let settings = IntegratorOverrides { min_contribution: Some(-0.5), ..Default::default() };
        assert_eq!(
            refused(Request { settings, ..Default::default() }),
            "--min-contribution must be a number ≥ 0, got -0.5"
        );
        let python = Request { front_end: FrontEnd::Python, settings, ..Default::default() };
        assert_eq!(refused(python), "min_contribution must be a number ≥ 0, got -0.5");
        for settings in [
            IntegratorOverrides { photon_radius: Some(f32::INFINITY), ..Default::default() },
            IntegratorOverrides { sppm_radius: Some(-1.0), ..Default::default() },
        ] {
            assert!(refused(Request { settings, ..Default::default() }).contains("must be a length ≥ 0"));
        }
        assert!(Request { samples: Some((0, 4)), time: None, threads: Some(8), ..Default::default() }.check().is_ok());
    }

    #[test]
    fn overrides_replace_the_scenes_settings_and_leave_the_rest() {
        let scene = IntegratorSettings::default();
        let overrides = IntegratorOverrides {
            max_depth: Some(u32::MAX),
            min_contribution: Some(0.0),
            transparent_shadows: true,
            no_wavefront: true,
            photons: Some(7),
            sppm_radius: Some(0.5),
            ..Default::default()
        };
        let s = overrides.apply(&scene, FrontEnd::Command).unwrap();
        assert_eq!((s.max_depth, s.min_contribution, s.transparent_shadows, s.wavefront), (u32::MAX, 0.0, true, false));
        assert_eq!((s.photon.global_photons, s.sppm_radius), (7, 0.5));
        assert_eq!((s.rr_depth, s.photon.caustic_photons), (scene.rr_depth, scene.photon.caustic_photons));
        assert_eq!(IntegratorOverrides::default().apply(&scene, FrontEnd::Command).unwrap(), scene);
    }
}
