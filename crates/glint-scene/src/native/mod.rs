//! The native scene format: TOML, or the same schema as JSON (chosen by the file extension).
//! Field by field in docs/scene-format.md.

mod build;
mod materials;
pub(crate) mod schema;

pub(crate) use build::environment_rotation;

use std::path::{Path, PathBuf};

use glint_core::filter::Filter;
use glint_core::integrators::{IntegratorKind, IntegratorSettings};
use glint_core::lights::{LightSelection, TriangleSampling};
use glint_core::sampling::SamplerKind;
use glint_core::scene::Scene;

use crate::error::{with_suggestion, Location, SceneError};
use crate::located::with_spans;
use crate::reader::{ReadScene, Translation};
use crate::source::Source;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Toml,
    Json,
}

/// Render settings a scene file carries; the CLI may override each.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderOptions {
    pub spp: u32,
    pub integrator: IntegratorKind,
    pub seed: u64,
    pub integrator_settings: IntegratorSettings,
    pub filter: Filter,
    pub sampler: SamplerKind,
    /// How the path tracer samples triangle lights (set on the scene's area lights too).
    pub light_sampling: TriangleSampling,
    /// How lights are chosen: by power, or each emitter equally (Mitsuba's scenes).
    pub light_selection: LightSelection,
    /// Keep each pixel's second moment (Mitsuba's `moment`), written beside the image.
    pub moment: bool,
}

pub struct LoadedScene {
    pub scene: Scene,
    pub render: RenderOptions,
    /// Things worth telling the user that do not stop the render (degenerate mesh triangles…).
    pub warnings: Vec<String>,
    /// Every file the scene was read from, the scene file first (for checkpoint fingerprints).
    pub inputs: Vec<PathBuf>,
}

/// Reads a native scene file (TOML, or JSON by its extension) into its description, with the
/// search path for the files it names: the scene's directory, then `search_path`.
pub(crate) fn read_file(path: &Path, search_path: &[PathBuf]) -> ReadScene {
    let (bytes, directories) = crate::reader::read_scene_file(path, search_path)?;
    let text = crate::source::utf8_text(path, bytes)?;
    let format = match path.extension().and_then(|e| e.to_str()) {
        Some(ext) if ext.eq_ignore_ascii_case("json") => Format::Json,
        _ => Format::Toml,
    };
    // The TOML reader holds a document of about 30 bytes per byte of text (a 95 MB scene of
    // a million lights took 2.8 GB); the JSON reader about 2.
    let needed = text.len() as u64 * if format == Format::Toml { TOML_BYTES_PER_BYTE } else { 2 };
    if needed > crate::limits::memory_limit() {
        return Err(SceneError::new(
            path,
            None,
            format!(
                "reading this {} scene takes about {}, more than the memory limit of {} ({}){}",
                if format == Format::Toml { "TOML" } else { "JSON" },
                crate::limits::describe(needed),
                crate::limits::describe(crate::limits::memory_limit()),
                crate::limits::RAISE,
                if format == Format::Toml {
                    "; the same scene as JSON (same schema) takes a fifteenth of that"
                } else {
                    ""
                }
            ),
        ));
    }
    Ok((translate(text, format, path)?, Source::search_path(directories)))
}

/// Memory the TOML reader takes per byte of text, measured (toml 0.8).
const TOML_BYTES_PER_BYTE: u64 = 32;

/// Parses scene text into its description; `file` is only used in messages.
pub(crate) fn translate(text: String, format: Format, file: &Path) -> Result<Translation, SceneError> {
    let parsed: schema::SceneFile = match format {
        Format::Toml => with_spans(|| toml::from_str(&text)).map_err(|e| {
            let message = with_suggestion(e.message());
            let location = e.span().map(|span| {
                // serde reports errors inside a table at the table; point at the key instead.
                let offset = crate::error::unknown_and_expected(e.message())
                    .and_then(|(key, _)| find_key(&text, span.clone(), &key))
                    .or_else(|| find_wrong_value(&text, span.clone(), e.message()))
                    .unwrap_or(span.start);
                Location::from_offset(&text, offset)
            });
            SceneError::new(file, location, message)
        })?,
        Format::Json => serde_json::from_str(&text).map_err(|e| {
            let message = with_suggestion(&strip_json_position(&e.to_string()));
            SceneError::new(file, Some(Location::from_line_column(&text, e.line(), e.column())), message)
        })?,
    };
    Ok(Translation::new(parsed, text))
}

/// Builds a scene from its native description, made by any reader: `text` is the file the
/// description's spans point into.
pub(crate) fn build_file(
    file: schema::SceneFile,
    text: &str,
    path: &Path,
    source: &Source,
) -> Result<LoadedScene, SceneError> {
    build::build(file, text, path, source)
}

/// serde_json appends " at line L column C" to its messages; the location is shown apart.
fn strip_json_position(message: &str) -> String {
    match message.rfind(" at line ") {
        Some(i) => message[..i].to_string(),
        None => message.to_string(),
    }
}

/// For serde's "invalid type: string \"one\", expected f32" inside a table (whose span it
/// reports): the offset of the one line within `range` that assigns that value, if exactly
/// one does.
fn find_wrong_value(text: &str, range: std::ops::Range<usize>, message: &str) -> Option<usize> {
    let rest = message.strip_prefix("invalid type: ").or_else(|| message.strip_prefix("invalid value: "))?;
    let (found, _) = rest.split_once(", expected")?;
    // `string "one"`, `integer `5``, `floating point `1.5``, `boolean `true``.
    let literal = match found.split_once(' ') {
        Some(("string", value)) => value.to_string(),
        _ => found.rsplit_once('`').and_then(|(before, _)| before.rsplit_once('`')).map(|(_, v)| v.to_string())?,
    };
    let range = range.start.min(text.len())..range.end.min(text.len());
    let mut matches = Vec::new();
    let mut offset = range.start;
    for line in text[range].split_inclusive('\n') {
        if let Some((key, value)) = line.split_once('=') {
            // The value, or an element of an array or inline table there.
            let mut words = value.split([',', '[', ']', '{', '}', '=']);
            let assigns =
                if literal.starts_with('"') { value.contains(&literal) } else { words.any(|w| w.trim() == literal) };
            if assigns {
                matches.push(offset + (key.len() - key.trim_start().len()));
            }
        }
        offset += line.len();
    }
    (matches.len() == 1).then(|| matches[0])
}

/// Byte offset of the line within `range` that assigns `key` (`key = …` in TOML,
/// `"key": …` in JSON).
pub(crate) fn find_key(text: &str, range: std::ops::Range<usize>, key: &str) -> Option<usize> {
    let range = range.start.min(text.len())..range.end.min(text.len());
    let mut offset = range.start;
    for line in text[range].split_inclusive('\n') {
        let trimmed = line.trim_start();
        let indent = line.len() - trimmed.len();
        let rest = trimmed.strip_prefix(key).or_else(|| trimmed.strip_prefix(&format!("\"{key}\"")));
        if let Some(rest) = rest {
            let rest = rest.trim_start();
            if rest.starts_with('=') || rest.starts_with(':') {
                return Some(offset + indent);
            }
        }
        offset += line.len();
    }
    None
}
