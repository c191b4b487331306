//! pbrt's directives read one at a time from the scene file and the files it includes:
//! each directive's name, its positional arguments and its parameter list (`"type name"
//! value`), with where it was written. `Include` and `Import` are followed here, so the
//! translator sees one stream.

use std::cell::Cell;
use std::path::{Path, PathBuf};

use super::tokens::{decode, Kind, Token};
use crate::error::{Location, SceneError};
use crate::source::Source;

/// A file of the scene: the main one first, then each included one.
pub struct File {
    pub path: PathBuf,
    pub text: String,
    tokens: Vec<Token>,
}

/// Where something was written: a file (index into the parser's files) and a byte offset.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct At {
    pub file: usize,
    pub offset: usize,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Values {
    Numbers(Vec<f64>),
    Strings(Vec<String>),
    Bools(Vec<bool>),
}

/// One `"type name" value` of a parameter list; `used` records that the translator read it.
#[derive(Debug)]
pub struct Param {
    pub ty: String,
    pub name: String,
    pub values: Values,
    pub at: At,
    pub used: Cell<bool>,
}

#[derive(Debug)]
pub struct Directive {
    pub name: String,
    pub at: At,
    /// Positional arguments: quoted strings or numbers, as written.
    pub args: Vec<String>,
    pub params: Vec<Param>,
}

pub struct Parser<'s> {
    pub files: Vec<File>,
    /// The files being read, innermost last: (file, next token).
    stack: Vec<(usize, usize)>,
    source: &'s Source<'s>,
}

/// Number of positional arguments before a directive's parameter list, or `None` for the
/// directives that have none.
fn shape_of(name: &str) -> Option<(Arguments, bool)> {
    use Arguments::*;
    Some(match name {
        "AttributeBegin" | "AttributeEnd" | "TransformBegin" | "TransformEnd" | "WorldBegin" | "WorldEnd"
        | "ObjectEnd" | "ReverseOrientation" | "Identity" => (Numbers(0), false),
        "Translate" | "Scale" => (Numbers(3), false),
        "Rotate" => (Numbers(4), false),
        "LookAt" => (Numbers(9), false),
        "TransformTimes" => (Numbers(2), false),
        "Transform" | "ConcatTransform" => (Matrix, false),
        "CoordinateSystem" | "CoordSysTransform" | "NamedMaterial" | "ObjectBegin" | "ObjectInstance" | "Include"
        | "Import" | "ColorSpace" => (Strings(1), false),
        "ActiveTransform" => (Word, false),
        "Camera" | "Sampler" | "Film" | "PixelFilter" | "Integrator" | "Accelerator" | "Shape" | "Material"
        | "LightSource" | "AreaLightSource" | "MakeNamedMaterial" | "MakeNamedMedium" | "Attribute" => {
            (Strings(1), true)
        }
        "Texture" => (Strings(3), true),
        "Option" => (Strings(0), true),
        "MediumInterface" => (MediumNames, false),
        _ => return None,
    })
}

#[derive(Clone, Copy)]
enum Arguments {
    Numbers(usize),
    Strings(usize),
    /// 16 numbers, bracketed or not.
    Matrix,
    /// A bare word (`ActiveTransform StartTime`).
    Word,
    /// One or two quoted names.
    MediumNames,
}

/// A number glint can hold: finite in single precision, which glint computes in (pbrt too).
fn check_range(x: f64, text: &str) -> Result<(), String> {
    if x.is_finite() && (x as f32).is_finite() {
        Ok(())
    } else {
        Err(format!("the number `{text}` is beyond single precision's range (±3.4e38), which glint computes in"))
    }
}

impl<'s> Parser<'s> {
    /// A parser of the scene file at `path`, whose bytes are `bytes`.
    pub fn new(path: &Path, bytes: Vec<u8>, source: &'s Source<'s>) -> Result<Self, SceneError> {
        let mut parser = Self { files: Vec::new(), stack: Vec::new(), source };
        parser.push_file(path.to_path_buf(), bytes)?;
        Ok(parser)
    }

    /// Reads a scene file's text (gzipped where its name ends in `.gz`, as pbrt reads it).
    fn push_file(&mut self, path: PathBuf, bytes: Vec<u8>) -> Result<(), SceneError> {
        let gzipped = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("gz"));
        let bytes =
            if gzipped { crate::source::gunzip(&bytes).map_err(|m| SceneError::new(&path, None, m))? } else { bytes };
        let (text, tokens) = decode(bytes)
            .map_err(|(text, offset, m)| SceneError::new(&path, Some(Location::from_offset(&text, offset)), m))?;
        self.files.push(File { path, text, tokens });
        self.stack.push((self.files.len() - 1, 0));
        Ok(())
    }

    /// An error at `at`, naming its file, line and column.
    pub fn error(&self, at: At, message: impl Into<String>) -> SceneError {
        let file = &self.files[at.file];
        SceneError::new(&file.path, Some(Location::from_offset(&file.text, at.offset)), message)
    }

    /// `path:line:column` of `at`, for warnings.
    pub fn place(&self, at: At) -> String {
        let file = &self.files[at.file];
        let location = Location::from_offset(&file.text, at.offset);
        format!("{}:{}:{}", file.path.display(), location.line, location.column)
    }

    fn peek(&self) -> Option<(usize, Token)> {
        let &(file, pos) = self.stack.last()?;
        self.files[file].tokens.get(pos).map(|&t| (file, t))
    }

    fn advance(&mut self) {
        if let Some(top) = self.stack.last_mut() {
            top.1 += 1;
        }
    }

    fn text(&self, file: usize, token: Token) -> &str {
        token.text(&self.files[file].text)
    }

    /// The next directive, following `Include` and `Import`; `None` at the end of the scene.
    pub fn next(&mut self) -> Result<Option<Directive>, SceneError> {
        loop {
            let Some((file, token)) = self.peek() else {
                if self.stack.pop().is_none() || self.stack.is_empty() {
                    return Ok(None);
                }
                continue;
            };
            let at = At { file, offset: token.offset };
            let name = self.text(file, token).to_string();
            if token.kind != Kind::Word {
                return Err(self.error(at, format!("expected a directive (Shape, Material, …), found `{name}`")));
            }
            let Some((arguments, has_params)) = shape_of(&name) else {
                let known = [
                    "AttributeBegin",
                    "AttributeEnd",
                    "Shape",
                    "Material",
                    "Texture",
                    "LightSource",
                    "LookAt",
                    "Translate",
                    "Rotate",
                    "Scale",
                    "Transform",
                    "ConcatTransform",
                    "Camera",
                    "Film",
                    "Sampler",
                    "Integrator",
                    "WorldBegin",
                    "Include",
                    "Import",
                    "ObjectBegin",
                    "ObjectInstance",
                ];
                let hint = crate::error::did_you_mean(&name, known);
                return Err(self.error(at, format!("unknown directive `{name}`{hint}")));
            };
            self.advance();
            let args = self.arguments(at, &name, arguments)?;
            let params = if has_params { self.parameters()? } else { Vec::new() };
            if name == "Include" || name == "Import" {
                self.include(at, &args[0])?;
                continue;
            }
            return Ok(Some(Directive { name, at, args, params }));
        }
    }

    fn include(&mut self, at: At, path: &str) -> Result<(), SceneError> {
        if self.stack.len() > 64 {
            return Err(self.error(at, "includes nest more than 64 deep (does a file include itself?)"));
        }
        let bytes = self.source.read(path).map_err(|m| self.error(at, m))?;
        // Where the source found it (nested includes are relative to the main scene's
        // directory, as in pbrt); a built-in file by its name.
        let full = match self.source.files_read().last() {
            Some(found) if found.ends_with(path) => found.clone(),
            _ => self.files[0].path.parent().map_or_else(|| PathBuf::from(path), |d| d.join(path)),
        };
        self.push_file(full, bytes)
    }

    fn arguments(&mut self, at: At, name: &str, arguments: Arguments) -> Result<Vec<String>, SceneError> {
        let mut args = Vec::new();
        match arguments {
            Arguments::Numbers(n) => {
                for _ in 0..n {
                    args.push(self.number_token(at, name)?);
                }
            }
            Arguments::Matrix => {
                let bracketed = matches!(self.peek(), Some((_, t)) if t.kind == Kind::Open);
                if bracketed {
                    self.advance();
                }
                for _ in 0..16 {
                    args.push(self.number_token(at, name)?);
                }
                if bracketed {
                    match self.peek() {
                        Some((_, t)) if t.kind == Kind::Close => self.advance(),
                        _ => return Err(self.error(at, format!("`{name}` takes [ 16 numbers ]"))),
                    }
                }
            }
            Arguments::Strings(n) => {
                for _ in 0..n {
                    match self.peek() {
                        Some((file, t)) if t.kind == Kind::Quoted => {
                            args.push(self.text(file, t).to_string());
                            self.advance();
                        }
                        _ => {
                            return Err(self.error(
                                at,
                                format!("`{name}` takes {n} quoted string{} first", if n > 1 { "s" } else { "" }),
                            ))
                        }
                    }
                }
            }
            Arguments::Word => match self.peek() {
                Some((file, t)) if t.kind == Kind::Word => {
                    args.push(self.text(file, t).to_string());
                    self.advance();
                }
                _ => return Err(self.error(at, format!("`{name}` takes StartTime, EndTime or All"))),
            },
            Arguments::MediumNames => {
                while let Some((file, t)) = self.peek() {
                    if t.kind != Kind::Quoted || args.len() == 2 {
                        break;
                    }
                    args.push(self.text(file, t).to_string());
                    self.advance();
                }
                if args.is_empty() {
                    return Err(self.error(at, "`MediumInterface` takes one or two quoted medium names"));
                }
            }
        }
        Ok(args)
    }

    fn number_token(&mut self, at: At, name: &str) -> Result<String, SceneError> {
        match self.peek() {
            Some((file, t)) if t.kind == Kind::Word && self.text(file, t).parse::<f64>().is_ok() => {
                let text = self.text(file, t).to_string();
                check_range(text.parse::<f64>().unwrap_or(0.0), &text)
                    .map_err(|m| self.error(At { file, offset: t.offset }, m))?;
                self.advance();
                Ok(text)
            }
            Some((file, t)) => Err(self.error(
                At { file, offset: t.offset },
                format!("`{name}` expects a number here, found `{}`", self.text(file, t)),
            )),
            None => Err(self.error(at, format!("`{name}` ends before all its numbers"))),
        }
    }

    /// `"type name" value` pairs until the next directive.
    fn parameters(&mut self) -> Result<Vec<Param>, SceneError> {
        let mut params: Vec<Param> = Vec::new();
        while let Some((file, t)) = self.peek() {
            if t.kind != Kind::Quoted {
                break;
            }
            let at = At { file, offset: t.offset };
            let declaration = self.text(file, t).to_string();
            let mut words = declaration.split_whitespace();
            let (Some(ty), Some(name), None) = (words.next(), words.next(), words.next()) else {
                return Err(self.error(at, format!("expected a parameter `\"type name\"`, found `\"{declaration}\"`")));
            };
            let (ty, name) = (ty.to_string(), name.to_string());
            self.advance();
            let values = self.values(at, &ty, &name)?;
            if params.iter().any(|p| p.name == name) {
                return Err(self.error(at, format!("parameter `{name}` is given twice")));
            }
            params.push(Param { ty, name, values, at, used: Cell::new(false) });
        }
        Ok(params)
    }

    /// A parameter's value: one token or a bracketed list, read as the type says.
    fn values(&mut self, at: At, ty: &str, name: &str) -> Result<Values, SceneError> {
        let mut tokens = Vec::new();
        match self.peek() {
            Some((_, t)) if t.kind == Kind::Open => {
                self.advance();
                loop {
                    match self.peek() {
                        Some((_, t)) if t.kind == Kind::Close => {
                            self.advance();
                            break;
                        }
                        Some((file, t)) if matches!(t.kind, Kind::Word | Kind::Quoted) => {
                            tokens.push((file, t));
                            self.advance();
                        }
                        _ => return Err(self.error(at, format!("the values of `{name}` are not closed by `]`"))),
                    }
                }
            }
            Some((file, t)) if matches!(t.kind, Kind::Word | Kind::Quoted) => {
                tokens.push((file, t));
                self.advance();
            }
            _ => return Err(self.error(at, format!("parameter `{name}` has no value"))),
        }
        let quoted = tokens.iter().all(|(_, t)| t.kind == Kind::Quoted);
        let kind = match ty {
            "string" | "texture" => "string",
            "bool" => "bool",
            "spectrum" if quoted => "string",
            "integer" | "float" | "point2" | "vector2" | "point3" | "vector3" | "normal3" | "normal" | "point"
            | "vector" | "rgb" | "color" | "blackbody" | "spectrum" => "number",
            _ => return Err(self.error(at, format!("unknown parameter type `{ty}` (of `{name}`)"))),
        };
        Ok(match kind {
            "string" => {
                let mut strings = Vec::new();
                for (file, t) in tokens {
                    if t.kind != Kind::Quoted {
                        return Err(self.error(at, format!("`{name}` is a {ty}: its values are quoted")));
                    }
                    strings.push(self.text(file, t).to_string());
                }
                Values::Strings(strings)
            }
            "bool" => {
                let mut bools = Vec::new();
                for (file, t) in tokens {
                    bools.push(match self.text(file, t) {
                        "true" => true,
                        "false" => false,
                        other => {
                            return Err(self.error(at, format!("`{name}` is a bool: true or false, not `{other}`")))
                        }
                    });
                }
                Values::Bools(bools)
            }
            _ => {
                let mut numbers = Vec::with_capacity(tokens.len());
                for (file, t) in tokens {
                    let text = self.text(file, t);
                    match (t.kind, text.parse::<f64>()) {
                        (Kind::Word, Ok(x)) => {
                            check_range(x, text).map_err(|m| self.error(At { file, offset: t.offset }, m))?;
                            numbers.push(x)
                        }
                        _ => {
                            return Err(self.error(
                                At { file, offset: t.offset },
                                format!("`{name}` is a {ty}: expected a number, found `{text}`"),
                            ))
                        }
                    }
                }
                Values::Numbers(numbers)
            }
        })
    }
}
