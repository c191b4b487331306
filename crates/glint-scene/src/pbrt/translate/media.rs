//! Participating media: pbrt's named media onto glint's, and the medium interface that shapes
//! and the camera take from the graphics state.
//!
//! `homogeneous` maps one to one. pbrt's grids (`uniformgrid`: a density times σ_a and σ_s;
//! `rgbgrid`: σ_a and σ_s per voxel) become glint grid media whose extinction, and for
//! `rgbgrid` albedo, are handed to the builder as `.vol` grids made in memory, placed by the
//! medium's transform over its box `p0`–`p1`. pbrt reads a grid at voxel centres and fades it
//! to zero over the outer half voxel; glint clamps at the edges, so the grid gains a layer of
//! zero voxels on every side (the medium then reaches half a voxel past the box, fading out).
//! `cloud` (procedural noise) and `nanovdb` (files glint has no reader for) are refused.

use glam::{Mat4, Vec3};

use super::state::matrix_op;
use super::{Result, Translator};
use crate::located::Located;
use crate::native::schema::*;
use crate::pbrt::params::Params;
use crate::pbrt::parse::Directive;
use crate::pbrt::spectra;
use crate::source::MadeFile;
use crate::volume::{write_vol, VolumeGrid};

impl Translator<'_> {
    /// `MakeNamedMedium "name" "string type" "…"`.
    pub(super) fn make_named_medium(&mut self, d: &Directive) -> Result<()> {
        let p = self.params(d);
        let name = d.args[0].clone();
        if self.scene.media.contains_key(&name) {
            return Err(self.parser.error(d.at, format!("the medium `{name}` is defined twice")));
        }
        let kind = p
            .string("type")
            .map_err(|f| self.fail(f))?
            .ok_or_else(|| self.parser.error(d.at, "a medium needs its `\"string type\"`"))?;
        let g = p.float("g", 0.0).map_err(|f| self.fail(f))?;
        if !(g > -1.0 && g < 1.0) {
            return Err(self.parser.error(self.param_at(&p, "g"), format!("`g` must lie in (−1, 1), got {g}")));
        }
        let phase = Some(if g == 0.0 { PhaseDesc::Isotropic } else { PhaseDesc::Hg { g } });
        let scale = Some(p.float("scale", 1.0).map_err(|f| self.fail(f))?);
        let desc = match kind.as_str() {
            "homogeneous" => {
                if p.list.iter().any(|x| x.name == "preset") {
                    return Err(self.parser.error(
                        self.param_at(&p, "preset"),
                        "a medium `preset` (pbrt's table of measured media) is not read: give `sigma_a` and `sigma_s`",
                    ));
                }
                let emission = self.medium_emission(&p)?;
                MediumDesc::Homogeneous {
                    sigma_a: Some(self.coefficient(&p, "sigma_a")?),
                    sigma_s: Some(self.coefficient(&p, "sigma_s")?),
                    sigma_t: None,
                    albedo: None,
                    scale,
                    phase,
                    emission,
                }
            }
            "uniformgrid" => {
                let (resolution, placement) = self.grid_placement(&p)?;
                let density = self.grid_values(&p, "density", resolution, &["float"])?;
                let varying = if p.list.iter().any(|x| x.name == "temperature") {
                    Some("temperature")
                } else {
                    self.lescale_is_a_grid(&p).then_some("Lescale")
                };
                if let Some(key) = varying {
                    return Err(self.parser.error(
                        self.param_at(&p, key),
                        format!("a grid of `{key}` (emission that varies over the grid) is not supported"),
                    ));
                }
                let (sigma_a, sigma_s) = (self.coefficient(&p, "sigma_a")?, self.coefficient(&p, "sigma_s")?);
                let sigma_t: [f32; 3] = std::array::from_fn(|c| sigma_a[c] + sigma_s[c]);
                let albedo = std::array::from_fn(|c| if sigma_t[c] > 0.0 { sigma_s[c] / sigma_t[c] } else { 0.0 });
                // Extinction per voxel: the density times σ_a + σ_s (σ_t's colour in the grid).
                let values = density.iter().flat_map(|d| sigma_t.map(|s| d * s)).collect();
                let file = self.made_grid(&name, "sigma_t", resolution, 3, values, false);
                let emission = self.medium_emission(&p)?;
                grid_medium(file, placement, AlbedoDesc::Constant(albedo), scale, phase, emission)
            }
            "rgbgrid" => {
                let (resolution, placement) = self.grid_placement(&p)?;
                let sigma_a = self.grid_values(&p, "sigma_a", resolution, &["rgb"])?;
                let sigma_s = self.grid_values(&p, "sigma_s", resolution, &["rgb"])?;
                if p.list.iter().any(|x| x.name == "Le") {
                    return Err(self.parser.error(
                        self.param_at(&p, "Le"),
                        "a grid of `Le` (emission that varies over the grid) is not supported",
                    ));
                }
                let sigma_t: Vec<f32> = sigma_a.iter().zip(&sigma_s).map(|(a, s)| a + s).collect();
                let albedo = sigma_s.iter().zip(&sigma_t).map(|(s, t)| if *t > 0.0 { s / t } else { 0.0 }).collect();
                let albedo_file = self.made_grid(&name, "albedo", resolution, 3, albedo, true);
                let file = self.made_grid(&name, "sigma_t", resolution, 3, sigma_t, false);
                let albedo =
                    AlbedoField { file: albedo_file, min: None, max: None, transform: placement.clone(), wrap: None };
                grid_medium(file, placement, AlbedoDesc::Field(albedo), scale, phase, None)
            }
            "cloud" => {
                return Err(self.parser.error(
                    d.at,
                    "the `cloud` medium (pbrt's procedural noise) is not supported; give its density as a `uniformgrid`",
                ))
            }
            "nanovdb" => {
                return Err(self.parser.error(
                    d.at,
                    "`nanovdb` media are not supported: glint has no NanoVDB reader (convert the grid to a `uniformgrid` or a Mitsuba .vol)",
                ))
            }
            other => {
                return Err(self.parser.error(
                    d.at,
                    format!("medium `{other}` is not supported; glint reads homogeneous, uniformgrid and rgbgrid"),
                ))
            }
        };
        self.scene.media.insert(name, Located { value: desc, span: None });
        Ok(())
    }

    /// `MediumInterface "inside" "outside"` (one name: both sides; "": no medium).
    pub(super) fn medium_interface(&mut self, d: &Directive) -> Result<()> {
        let named = |i: usize| d.args.get(i).filter(|n| !n.is_empty()).cloned();
        let (inside, outside) = match d.args.len() {
            1 => (named(0), named(0)),
            _ => (named(0), named(1)),
        };
        for name in [&inside, &outside].into_iter().flatten() {
            self.medium_references.push((name.clone(), d.at));
        }
        self.state.media = (inside, outside);
        Ok(())
    }

    /// Every medium a `MediumInterface` names exists (pbrt's names are resolved at the end: a
    /// medium may be made after the interface that names it).
    pub(super) fn check_medium_references(&self) -> Result<()> {
        for (name, at) in &self.medium_references {
            if !self.scene.media.contains_key(name) {
                let hint = crate::error::did_you_mean_among_keys(name, self.scene.media.keys());
                return Err(self.parser.error(*at, format!("no medium named `{name}`{hint}")));
            }
        }
        Ok(())
    }

    /// σ_a or σ_s: an RGB (or other) spectrum as RGB, 1 by default as in pbrt.
    fn coefficient(&self, p: &Params, key: &str) -> Result<[f32; 3]> {
        match p.spectrum(key).map_err(|f| self.fail(f))? {
            None => Ok([1.0; 3]),
            Some(s) => {
                spectra::unbounded(&s).map_err(|m| self.parser.error(self.param_at(p, key), format!("`{key}`: {m}")))
            }
        }
    }

    /// A medium's `Le` times `Lescale` (a single value), the radiance it emits where it
    /// absorbs; `None` where it emits nothing.
    fn medium_emission(&self, p: &Params) -> Result<Option<[f32; 3]>> {
        let Some(le) = p.spectrum("Le").map_err(|f| self.fail(f))? else { return Ok(None) };
        let le = spectra::emission(&le).map_err(|m| self.parser.error(self.param_at(p, "Le"), format!("`Le`: {m}")))?;
        let scale = if self.lescale_is_a_grid(p) { 1.0 } else { p.float("Lescale", 1.0).map_err(|f| self.fail(f))? };
        let le = le.map(|c| c * scale);
        Ok((le != [0.0; 3]).then_some(le))
    }

    /// Whether `Lescale` is given as more than one value (pbrt's per-voxel scale).
    fn lescale_is_a_grid(&self, p: &Params) -> bool {
        p.list
            .iter()
            .any(|x| x.name == "Lescale" && matches!(&x.values, crate::pbrt::parse::Values::Numbers(n) if n.len() > 1))
    }

    /// A grid's resolution (`nx`, `ny`, `nz`) and the transform that puts glint's unit cube
    /// over it: the box `p0`–`p1` grown by a voxel on every side (the layer of zeros
    /// `made_grid` adds), in the medium's space, placed by the current transform.
    fn grid_placement(&self, p: &Params) -> Result<([usize; 3], Vec<TransformOp>)> {
        let mut resolution = [0usize; 3];
        for (i, key) in ["nx", "ny", "nz"].iter().enumerate() {
            let n = p.int(key, 1).map_err(|f| self.fail(f))?;
            if !(1..=1 << 16).contains(&n) {
                return Err(self.parser.error(self.param_at(p, key), format!("`{key}` must be 1 to 65536, got {n}")));
            }
            resolution[i] = n as usize;
        }
        let p0 = Vec3::from(p.triple("p0", [0.0; 3]).map_err(|f| self.fail(f))?);
        let p1 = Vec3::from(p.triple("p1", [1.0; 3]).map_err(|f| self.fail(f))?);
        if !(p0.is_finite() && p1.is_finite() && p0.cmplt(p1).all()) {
            return Err(self.parser.error(p.at, format!("the grid's box {p0} – {p1} is empty")));
        }
        let voxel = (p1 - p0) / Vec3::from(resolution.map(|n| n as f32));
        let (min, max) = (p0 - voxel, p1 + voxel);
        let to_box = Mat4::from_translation(min) * Mat4::from_scale(max - min);
        Ok((resolution, vec![matrix_op(self.state.ctm * to_box)]))
    }

    /// A grid parameter's values (x fastest, then y, then z; an `rgb` grid's three channels
    /// each), `nx · ny · nz` of them, each finite and ≥ 0.
    fn grid_values(&self, p: &Params, key: &str, [nx, ny, nz]: [usize; 3], types: &[&str]) -> Result<Vec<f32>> {
        let param = p
            .list
            .iter()
            .find(|x| x.name == key)
            .ok_or_else(|| self.parser.error(p.at, format!("the grid needs its `{key}` values")))?;
        param.used.set(true);
        if !types.contains(&param.ty.as_str()) {
            return Err(self
                .parser
                .error(param.at, format!("`{key}` is given as `{}`; expected `{}`", param.ty, types[0])));
        }
        let crate::pbrt::parse::Values::Numbers(values) = &param.values else {
            return Err(self.parser.error(param.at, format!("`{key}` takes numbers")));
        };
        let channels = if param.ty == "rgb" { 3 } else { 1 };
        let expected = nx * ny * nz * channels;
        if values.len() != expected {
            return Err(self.parser.error(
                param.at,
                format!("`{key}` has {} values; nx · ny · nz = {nx} · {ny} · {nz} asks for {expected}", values.len()),
            ));
        }
        if let Some(bad) = values.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
            return Err(self.parser.error(param.at, format!("`{key}` values must be finite and ≥ 0, got {bad}")));
        }
        Ok(values.iter().map(|&v| v as f32).collect())
    }

    /// A grid of `channels` as a `.vol` file among the made files, with a layer of voxels
    /// around it: zeros (an extinction, which pbrt fades to zero at the box), or with `edges`
    /// copies of the edge (an albedo, which pbrt's ratio of σ_s to σ_t keeps up to the box's
    /// faces); returns its name.
    fn made_grid(
        &mut self,
        medium: &str,
        what: &str,
        [nx, ny, nz]: [usize; 3],
        channels: usize,
        values: Vec<f32>,
        edges: bool,
    ) -> String {
        let padded = [nx + 2, ny + 2, nz + 2];
        let mut out = Vec::with_capacity(padded.iter().product::<usize>() * channels);
        // Voxel i of the padded axis is voxel i − 1 of the grid's, if it has one.
        let source = |i: usize, n: usize| if (1..=n).contains(&i) || edges { Some(i.clamp(1, n) - 1) } else { None };
        for z in 0..padded[2] {
            for y in 0..padded[1] {
                for x in 0..padded[0] {
                    match (source(x, nx), source(y, ny), source(z, nz)) {
                        (Some(x), Some(y), Some(z)) => {
                            let from = ((z * ny + y) * nx + x) * channels;
                            out.extend_from_slice(&values[from..from + channels]);
                        }
                        _ => out.extend(std::iter::repeat_n(0.0, channels)),
                    }
                }
            }
        }
        let grid = VolumeGrid { resolution: padded, channels, min: Vec3::ZERO, max: Vec3::ONE, values: out };
        let name = format!("pbrt-medium:{medium}:{what}.vol");
        self.made.push((name.clone(), MadeFile::Bytes(write_vol(&grid))));
        name
    }
}

/// A grid medium of the extinction grid `file`, placed by `placement` over glint's unit cube.
fn grid_medium(
    file: String,
    placement: Vec<TransformOp>,
    albedo: AlbedoDesc,
    scale: Option<f32>,
    phase: Option<PhaseDesc>,
    emission: Option<[f32; 3]>,
) -> MediumDesc {
    MediumDesc::Grid {
        file: Some(file),
        value: None,
        min: None,
        max: None,
        transform: placement,
        albedo: Some(albedo),
        scale,
        phase,
        emission,
    }
}
