//! A directive's parameter list read by name and type. Every read marks the parameter used,
//! so that what the translator never reads is reported (pbrt refuses unused parameters;
//! glint names them in a warning or an error).

use super::parse::{At, Param, Values};
use super::spectra::Spectrum;

/// Where a parameter went wrong and why.
pub type Failure = (At, String);

pub struct Params<'d> {
    pub list: &'d [Param],
    /// The directive, for messages: `Shape "sphere"`.
    pub what: String,
    pub at: At,
}

/// A colour parameter that may also name a texture.
#[derive(Clone, Debug, PartialEq)]
pub enum Textured<T> {
    Value(T),
    Texture(String),
}

impl<'d> Params<'d> {
    fn find(&self, name: &str, types: &[&str]) -> Result<Option<&'d Param>, Failure> {
        let Some(param) = self.list.iter().find(|p| p.name == name) else { return Ok(None) };
        param.used.set(true);
        if !types.contains(&param.ty.as_str()) {
            return Err((
                param.at,
                format!(
                    "`{name}` of {} is given as `{}`; expected {}",
                    self.what,
                    param.ty,
                    types.iter().map(|t| format!("`{t}`")).collect::<Vec<_>>().join(" or ")
                ),
            ));
        }
        Ok(Some(param))
    }

    fn numbers(&self, name: &str, types: &[&str]) -> Result<Option<(&'d [f64], At)>, Failure> {
        Ok(match self.find(name, types)? {
            Some(Param { values: Values::Numbers(n), at, .. }) => Some((n.as_slice(), *at)),
            Some(p) => return Err((p.at, format!("`{name}` of {} takes numbers", self.what))),
            None => None,
        })
    }

    fn one(&self, name: &str, types: &[&str]) -> Result<Option<f64>, Failure> {
        match self.numbers(name, types)? {
            Some(([x], _)) => Ok(Some(*x)),
            Some((xs, at)) => Err((at, format!("`{name}` of {} takes one value, got {}", self.what, xs.len()))),
            None => Ok(None),
        }
    }

    /// Floats, as many as given.
    pub fn floats(&self, name: &str) -> Result<Option<(Vec<f32>, At)>, Failure> {
        Ok(self.numbers(name, &["float"])?.map(|(xs, at)| (xs.iter().map(|&x| x as f32).collect(), at)))
    }

    pub fn float(&self, name: &str, default: f32) -> Result<f32, Failure> {
        Ok(self.one(name, &["float"])?.map_or(default, |x| x as f32))
    }

    pub fn int(&self, name: &str, default: i64) -> Result<i64, Failure> {
        self.ints(name)?.map_or(Ok(default), |(v, at)| match v.as_slice() {
            [x] => Ok(*x),
            _ => Err((at, format!("`{name}` of {} takes one integer, got {}", self.what, v.len()))),
        })
    }

    pub fn ints(&self, name: &str) -> Result<Option<(Vec<i64>, At)>, Failure> {
        let Some((xs, at)) = self.numbers(name, &["integer"])? else { return Ok(None) };
        let ints = xs
            .iter()
            .map(|&x| {
                if x.fract() == 0.0 && x.abs() < 9.0e15 {
                    Ok(x as i64)
                } else {
                    Err((at, format!("`{name}` of {} takes integers, got {x}", self.what)))
                }
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Some((ints, at)))
    }

    pub fn strings(&self, name: &str, types: &[&str]) -> Result<Option<&'d [String]>, Failure> {
        Ok(match self.find(name, types)? {
            Some(Param { values: Values::Strings(s), .. }) => Some(s.as_slice()),
            Some(p) => return Err((p.at, format!("`{name}` of {} takes quoted strings", self.what))),
            None => None,
        })
    }

    pub fn string(&self, name: &str) -> Result<Option<String>, Failure> {
        match self.strings(name, &["string"])? {
            Some([s]) => Ok(Some(s.clone())),
            Some(s) => Err((self.at_of(name), format!("`{name}` of {} takes one string, got {}", self.what, s.len()))),
            None => Ok(None),
        }
    }

    pub fn bool(&self, name: &str, default: bool) -> Result<bool, Failure> {
        Ok(match self.find(name, &["bool"])? {
            Some(Param { values: Values::Bools(b), at, .. }) => match b.as_slice() {
                [x] => *x,
                _ => return Err((*at, format!("`{name}` of {} takes one bool", self.what))),
            },
            Some(p) => return Err((p.at, format!("`{name}` of {} takes true or false", self.what))),
            None => default,
        })
    }

    /// Triples: points, vectors or normals (pbrt-v3's `point` and `normal` too).
    pub fn triples(&self, name: &str) -> Result<Option<Vec<[f32; 3]>>, Failure> {
        let types = ["point3", "vector3", "normal3", "normal", "point", "vector"];
        let Some((xs, at)) = self.numbers(name, &types)? else { return Ok(None) };
        if xs.len() % 3 != 0 {
            return Err((at, format!("`{name}` of {} takes triples, got {} numbers", self.what, xs.len())));
        }
        Ok(Some(xs.chunks_exact(3).map(|c| [c[0] as f32, c[1] as f32, c[2] as f32]).collect()))
    }

    pub fn triple(&self, name: &str, default: [f32; 3]) -> Result<[f32; 3], Failure> {
        match self.triples(name)? {
            None => Ok(default),
            Some(v) if v.len() == 1 => Ok(v[0]),
            Some(v) => Err((self.at_of(name), format!("`{name}` of {} takes one triple, got {}", self.what, v.len()))),
        }
    }

    /// Pairs (texture coordinates): `point2`, or pbrt-v3's `float uv`.
    pub fn pairs(&self, name: &str) -> Result<Option<Vec<[f32; 2]>>, Failure> {
        let Some((xs, at)) = self.numbers(name, &["point2", "vector2", "float"])? else { return Ok(None) };
        if xs.len() % 2 != 0 {
            return Err((at, format!("`{name}` of {} takes pairs, got {} numbers", self.what, xs.len())));
        }
        Ok(Some(xs.chunks_exact(2).map(|c| [c[0] as f32, c[1] as f32]).collect()))
    }

    /// A spectrum: `rgb`, `blackbody` (a temperature), `spectrum` (a name or wavelength–value
    /// pairs).
    pub fn spectrum(&self, name: &str) -> Result<Option<Spectrum>, Failure> {
        Ok(self.spectrum_or_texture(name, false)?.map(|s| match s {
            Textured::Value(s) => s,
            Textured::Texture(_) => unreachable!("textures were not asked for"),
        }))
    }

    /// A spectrum or, where `textures` allows, a texture's name.
    pub fn spectrum_or_texture(&self, name: &str, textures: bool) -> Result<Option<Textured<Spectrum>>, Failure> {
        let types: &[&str] = if textures {
            &["rgb", "color", "blackbody", "spectrum", "texture"]
        } else {
            &["rgb", "color", "blackbody", "spectrum"]
        };
        let Some(param) = self.find(name, types)? else { return Ok(None) };
        let at = param.at;
        let bad = |m: String| Err((at, format!("`{name}` of {}: {m}", self.what)));
        Ok(Some(match (param.ty.as_str(), &param.values) {
            ("texture", Values::Strings(s)) if s.len() == 1 => Textured::Texture(s[0].clone()),
            ("rgb" | "color", Values::Numbers(n)) if n.len() == 3 => {
                Textured::Value(Spectrum::Rgb([n[0] as f32, n[1] as f32, n[2] as f32]))
            }
            ("rgb" | "color", _) => return bad("an rgb value is three numbers".into()),
            ("blackbody", Values::Numbers(n)) if n.len() == 1 => Textured::Value(Spectrum::Blackbody(n[0])),
            ("blackbody", _) => return bad("a blackbody is one temperature in kelvin".into()),
            ("spectrum", Values::Strings(s)) if s.len() == 1 => Textured::Value(Spectrum::Named(s[0].clone())),
            ("spectrum", Values::Numbers(n)) if n.len() >= 2 && n.len() % 2 == 0 => {
                let pairs: Vec<(f64, f64)> = n.chunks_exact(2).map(|c| (c[0], c[1])).collect();
                if pairs.windows(2).any(|w| w[1].0 <= w[0].0) {
                    return bad("a sampled spectrum's wavelengths must increase".into());
                }
                Textured::Value(Spectrum::Sampled(pairs))
            }
            ("spectrum", _) => {
                return bad("a spectrum is a name (\"metal-Cu-eta\") or wavelength–value pairs".into());
            }
            _ => return bad("takes one texture name".into()),
        }))
    }

    /// A float or the name of a float texture.
    pub fn float_or_texture(&self, name: &str) -> Result<Option<Textured<f32>>, Failure> {
        let Some(param) = self.find(name, &["float", "texture"])? else { return Ok(None) };
        match &param.values {
            Values::Numbers(n) if n.len() == 1 => Ok(Some(Textured::Value(n[0] as f32))),
            Values::Strings(s) if s.len() == 1 => Ok(Some(Textured::Texture(s[0].clone()))),
            _ => Err((param.at, format!("`{name}` of {} takes one number or one texture name", self.what))),
        }
    }

    fn at_of(&self, name: &str) -> At {
        self.list.iter().find(|p| p.name == name).map_or(self.at, |p| p.at)
    }

    /// Marks parameters glint reads no meaning from but that need no warning (a file name
    /// for the film, which glint's command line gives instead).
    pub fn ignore(&self, names: &[&str]) {
        self.list.iter().filter(|p| names.contains(&p.name.as_str())).for_each(|p| p.used.set(true));
    }
}
