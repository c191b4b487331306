//! The integrator: Mitsuba's names mapped onto glint's, its depth counted glint's way, and
//! the `moment` and `aov` wrappers.

use super::{polarized, Result, Translator};
use crate::mitsuba::xml::Element;

impl Translator<'_> {
    pub(super) fn integrator(&mut self, integrator: &Element) -> Result<()> {
        let kind = integrator.attribute("type").unwrap_or("");
        match kind {
            "moment" => return self.moment(integrator),
            "aov" => return self.aov(integrator),
            "stokes" => return Err(self.error(&integrator.position, polarized("<integrator type=\"stokes\">"))),
            _ => {}
        }
        let p = self.properties(integrator);
        let max_depth = p.integer(self, "max_depth")?.unwrap_or(-1);
        let rr_depth = p.integer(self, "rr_depth")?.unwrap_or(5);
        p.boolean(self, "hide_emitters")?;
        let name = match kind {
            "path" => "path",
            // volpathmis weighs the channels of a chromatic medium by MIS along the path; glint's
            // volpath weighs them at each free flight: the same image, each without bias.
            "volpath" | "volpathmis" => "volpath",
            "direct" => "path",
            "ptracer" => "light",
            "photonmapper" => "photon",
            "sppm" => "sppm",
            _ => {
                return Err(self.error(
                    &integrator.position,
                    format!(
                        "<integrator type=\"{kind}\"> is not supported; glint maps path, volpath, volpathmis, direct, ptracer, photonmapper and sppm"
                    ),
                ))
            }
        };
        self.scene.render.integrator = name.into();
        // Mitsuba counts path vertices (1: emitters seen directly); glint counts scattering
        // events (0: emitters seen directly).
        self.scene.render.max_depth = match (kind, max_depth) {
            ("direct", _) => 1,
            (_, d) if d < 0 => -1,
            (_, 0) => {
                self.warn(&integrator.position, "max_depth 0 renders nothing in Mitsuba; glint shows emitters only");
                0
            }
            (_, d) => d - 1,
        };
        self.scene.render.rr_depth = u32::try_from(rr_depth.max(0)).unwrap_or(5);
        if kind == "direct" {
            p.integer(self, "emitter_samples")?;
            p.integer(self, "bsdf_samples")?;
        }
        self.unused(&p);
        Ok(())
    }

    /// Mitsuba's `moment` wraps integrators and adds each one's second moment as extra film
    /// channels: glint renders its first nested integrator keeping each pixel's second moment
    /// (written as the EXR layer `m2`).
    fn moment(&mut self, moment: &Element) -> Result<()> {
        let nested: Vec<&Element> = moment.children.iter().filter(|c| c.tag == "integrator").collect();
        let Some(first) = nested.first() else {
            return Err(self.error(&moment.position, "<integrator type=\"moment\"> needs a nested <integrator>"));
        };
        for extra in &nested[1..] {
            self.warn(&extra.position, "a second integrator inside `moment`: glint renders the first one only");
        }
        self.unused(&self.properties(moment));
        self.scene.render.moment = true;
        self.integrator(first)
    }

    /// Mitsuba's `aov` renders its nested integrator's image and writes the listed channels
    /// (depth, normals, …) beside it: glint renders the image and says the channels are not
    /// written (`--aovs` writes glint's own: albedo, normal, depth).
    fn aov(&mut self, aov: &Element) -> Result<()> {
        let p = self.properties(aov);
        let channels = p.string(self, "aovs")?.unwrap_or_default();
        let nested: Vec<&Element> = aov.children.iter().filter(|c| c.tag == "integrator").collect();
        let Some(first) = nested.first() else {
            return Err(self.error(
                &aov.position,
                format!("<integrator type=\"aov\"> with no nested <integrator> renders only its channels (`{channels}`), which glint does not write"),
            ));
        };
        for extra in &nested[1..] {
            self.warn(&extra.position, "a second integrator inside `aov`: glint renders the first one only");
        }
        self.warn(
            &aov.position,
            format!("<integrator type=\"aov\">: glint renders the nested integrator's image but not the channels `{channels}` (its --aovs writes albedo, normal and depth layers)"),
        );
        self.unused(&p);
        self.integrator(first)
    }
}
