//! The render settings: pbrt's sampler, pixel filter and integrator mapped onto glint's.

use super::{Result, Translator};
use crate::pbrt::parse::Directive;

impl Translator<'_> {
    pub(super) fn sampler(&mut self, d: &Directive) -> Result<()> {
        let p = self.params(d);
        let kind = d.args[0].as_str();
        let spp = match kind {
            "stratified" => {
                let xs = p.int("xsamples", 4).map_err(|f| self.fail(f))?;
                let ys = p.int("ysamples", 4).map_err(|f| self.fail(f))?;
                p.ignore(&["jitter"]);
                xs.checked_mul(ys).unwrap_or(0)
            }
            _ => p.int("pixelsamples", 16).map_err(|f| self.fail(f))?,
        };
        if !(1..=1 << 24).contains(&spp) {
            return Err(self.parser.error(d.at, format!("samples per pixel must be 1 to 16777216, got {spp}")));
        }
        self.scene.render.spp = spp as u32;
        self.scene.render.seed = p.int("seed", 0).map_err(|f| self.fail(f))?.max(0) as u64;
        self.scene.render.sampler = match kind {
            "independent" => "independent",
            "stratified" => "stratified",
            "halton" | "sobol" | "zsobol" | "paddedsobol" | "pmj02bn" => "sobol",
            other => return Err(self.parser.error(d.at, format!("sampler `{other}` is not known"))),
        }
        .into();
        p.ignore(&["randomization"]);
        Ok(())
    }

    pub(super) fn filter(&mut self, d: &Directive) -> Result<()> {
        let p = self.params(d);
        let name = match d.args[0].as_str() {
            "box" => "box",
            "triangle" => "tent",
            "gaussian" => "gaussian",
            "mitchell" => "mitchell",
            "sinc" => {
                self.warn(d.at, "the sinc filter is not available: using gaussian");
                "gaussian"
            }
            other => return Err(self.parser.error(d.at, format!("pixel filter `{other}` is not known"))),
        };
        let names: Vec<&str> = p.list.iter().map(|x| x.name.as_str()).collect();
        if !names.is_empty() {
            p.ignore(&names);
            self.warn(d.at, "the filter's radius and shape parameters are ignored: glint's filters have fixed widths");
        }
        self.scene.render.filter = name.into();
        Ok(())
    }

    pub(super) fn integrator(&mut self, d: &Directive) -> Result<()> {
        let p = self.params(d);
        let kind = d.args[0].as_str();
        self.follows_media = matches!(kind, "volpath" | "simplevolpath" | "bdpt" | "mlt");
        self.scene.render.integrator = match kind {
            "path" | "volpath" | "simplepath" | "simplevolpath" => "path",
            "lightpath" => "light",
            "sppm" => "sppm",
            "bdpt" | "mlt" | "randomwalk" => {
                self.warn(d.at, format!("the `{kind}` integrator is not available: glint's path tracer renders the same image"));
                "path"
            }
            other => return Err(self.parser.error(d.at, format!("integrator `{other}` is not supported; glint maps path, volpath, simplepath, lightpath, sppm, bdpt and mlt"))),
        }
        .into();
        let depth = p.int("maxdepth", 5).map_err(|f| self.fail(f))?;
        // pbrt counts bounces; glint (as Mitsuba) counts path segments: one more.
        self.scene.render.max_depth = if depth < 0 { -1 } else { depth + 1 };
        match p.string("lightsampler").map_err(|f| self.fail(f))?.as_deref() {
            Some("uniform") => self.scene.render.light_selection = "uniform".into(),
            Some("power") | Some("bvh") | None => self.scene.render.light_selection = "power".into(),
            Some(other) => return Err(self.parser.error(d.at, format!("light sampler `{other}` is not known"))),
        }
        if p.bool("regularize", false).map_err(|f| self.fail(f))? {
            self.warn(d.at, "`regularize` is not available: paths are not regularized");
        }
        p.ignore(&["samplelights", "samplebsdf", "photonsperiteration", "radius", "iterations", "seed"]);
        Ok(())
    }
}
