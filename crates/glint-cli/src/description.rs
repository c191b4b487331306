//! Native scene descriptions built in memory rather than read from a file: the Python module's
//! `load_dict` turns a dict of the TOML format's schema into a [`Description`], and
//! [`Description::to_json`] and [`DescriptionJson::load`] make it a scene through the native
//! reader, as a `.json` file would be read.
//!
//! The JSON text is written one key or element a line, and each line remembers the key path
//! it holds, so that an error the reader reports at a line and column is reported at the
//! dict's key path instead (`shapes[0].radius: invalid type: string "big", expected f32`):
//! the text is the reader's, not the user's.
//!
//! ```python
//! glint.load_dict({"camera": {"position": [0, 1, -5], "look_at": [0, 0, 0]},
//!                  "shapes": [{"type": "sphere", "radius": np.float32(0.5), "material": "m"}], ...})
//! ```

use glint_scene::native::Format;
use glint_scene::{LoadedScene, SceneError, Source};
use thiserror::Error;

/// The name the reader gives the description in its messages (replaced by key paths).
pub const NAME: &str = "<dict>";

/// Tables and lists nested deeper than this are refused (a dict that contains itself).
pub const MAX_DEPTH: usize = 100;

/// A scene description: the values JSON holds, tables keeping their keys' order.
#[derive(Clone, Debug, PartialEq)]
pub enum Description {
    Null,
    Bool(bool),
    Integer(i128),
    Float(f64),
    Text(String),
    List(Vec<Description>),
    Table(Vec<(String, Description)>),
}

/// A description the reader refused, or that JSON cannot hold, at its key path (empty for
/// the whole description).
#[derive(Clone, Debug, PartialEq, Eq, Error)]
#[error("{}{message}", if path.is_empty() { String::new() } else { format!("{path}: ") })]
pub struct DescriptionError {
    pub path: String,
    pub message: String,
}

impl DescriptionError {
    pub fn new(path: &str, message: impl Into<String>) -> Self {
        Self { path: path.to_string(), message: message.into() }
    }
}

/// The key path of `key` inside the table at `path`: `shapes[0].radius`, `materials["my glass"]`.
pub fn key_path(path: &str, key: &str) -> String {
    let plain = !key.is_empty() && key.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    match (path.is_empty(), plain) {
        (true, true) => key.to_string(),
        (false, true) => format!("{path}.{key}"),
        (_, false) => format!("{path}[{key:?}]"),
    }
}

/// The key path of element `index` of the list at `path`.
pub fn index_path(path: &str, index: usize) -> String {
    format!("{path}[{index}]")
}

impl Description {
    /// A description from JSON text (tables in serde_json's key order, sorted).
    pub fn from_json(text: &[u8]) -> Result<Self, serde_json::Error> {
        serde_json::from_slice::<serde_json::Value>(text).map(Description::from)
    }
}

impl From<serde_json::Value> for Description {
    fn from(value: serde_json::Value) -> Self {
        use serde_json::Value;
        match value {
            Value::Null => Description::Null,
            Value::Bool(b) => Description::Bool(b),
            Value::Number(n) => match (n.as_i64(), n.as_u64()) {
                (Some(i), _) => Description::Integer(i.into()),
                (_, Some(u)) => Description::Integer(u.into()),
                _ => Description::Float(n.as_f64().unwrap_or(f64::NAN)),
            },
            Value::String(s) => Description::Text(s),
            Value::Array(items) => Description::List(items.into_iter().map(Description::from).collect()),
            Value::Object(map) => Description::Table(map.into_iter().map(|(k, v)| (k, Description::from(v))).collect()),
        }
    }
}

/// The JSON text of a description, and where each of its values is in it.
#[derive(Clone, Debug)]
pub struct DescriptionJson {
    /// What the reader reads (and what a render's identity hashes).
    pub text: String,
    /// Every value: its key path and the lines it spans.
    nodes: Vec<Node>,
}

#[derive(Clone, Debug)]
struct Node {
    path: String,
    /// Its key, in a table.
    key: Option<String>,
    /// 1-based, inclusive.
    first_line: usize,
    last_line: usize,
    /// A scalar as serde's messages name it ("string \"big\"", "integer `5`").
    unexpected: Option<String>,
    /// A string's value.
    text: Option<String>,
    /// A table with a `type` (a tagged value, which serde_json buffers before reading).
    tagged: bool,
}

impl Description {
    /// The JSON text the reader reads, one key or element a line. Refuses numbers JSON cannot
    /// hold (NaN, infinities) and nesting deeper than [`MAX_DEPTH`].
    pub fn to_json(&self) -> Result<DescriptionJson, DescriptionError> {
        let mut writer = Writer { text: String::new(), line: 1, nodes: Vec::new() };
        writer.value(self, String::new(), None, 0)?;
        writer.text.push('\n');
        Ok(DescriptionJson { text: writer.text, nodes: writer.nodes })
    }
}

struct Writer {
    text: String,
    line: usize,
    nodes: Vec<Node>,
}

impl Writer {
    fn newline(&mut self, depth: usize) {
        self.text.push('\n');
        self.text.push_str(&"  ".repeat(depth));
        self.line += 1;
    }

    fn value(
        &mut self,
        value: &Description,
        path: String,
        key: Option<&str>,
        depth: usize,
    ) -> Result<(), DescriptionError> {
        if depth > MAX_DEPTH {
            return Err(DescriptionError::new(
                &path,
                format!("nested more than {MAX_DEPTH} levels deep (a dict or list that contains itself?)"),
            ));
        }
        let index = self.nodes.len();
        let first_line = self.line;
        self.nodes.push(Node {
            path: path.clone(),
            key: key.map(str::to_string),
            first_line,
            last_line: first_line,
            unexpected: None,
            text: None,
            tagged: matches!(value, Description::Table(entries) if entries.iter().any(|(k, _)| k == "type")),
        });
        let (unexpected, text) = match value {
            Description::Null => {
                self.text.push_str("null");
                (Some("null".to_string()), None)
            }
            Description::Bool(b) => {
                self.text.push_str(if *b { "true" } else { "false" });
                (Some(format!("boolean `{b}`")), None)
            }
            Description::Integer(i) => {
                self.text.push_str(&i.to_string());
                (Some(format!("integer `{i}`")), None)
            }
            Description::Float(f) => {
                if !f.is_finite() {
                    return Err(DescriptionError::new(
                        &path,
                        format!("{f} is not a number a scene description can hold (finite numbers only)"),
                    ));
                }
                self.text.push_str(&serde_json::to_string(f).map_err(|e| DescriptionError::new(&path, e.to_string()))?);
                // serde writes a float with a decimal point.
                let shown = f.to_string();
                let shown = if shown.contains('.') { shown } else { shown + ".0" };
                (Some(format!("floating point `{shown}`")), None)
            }
            Description::Text(s) => {
                self.text.push_str(&serde_json::to_string(s).map_err(|e| DescriptionError::new(&path, e.to_string()))?);
                (Some(format!("string {s:?}")), Some(s.clone()))
            }
            Description::List(items) => {
                self.text.push('[');
                for (k, item) in items.iter().enumerate() {
                    self.newline(depth + 1);
                    self.value(item, index_path(&path, k), None, depth + 1)?;
                    if k + 1 < items.len() {
                        self.text.push(',');
                    }
                }
                if !items.is_empty() {
                    self.newline(depth);
                }
                self.text.push(']');
                (None, None)
            }
            Description::Table(entries) => {
                self.text.push('{');
                for (k, (name, item)) in entries.iter().enumerate() {
                    self.newline(depth + 1);
                    self.text.push_str(
                        &serde_json::to_string(name).map_err(|e| DescriptionError::new(&path, e.to_string()))?,
                    );
                    self.text.push_str(": ");
                    self.value(item, key_path(&path, name), Some(name), depth + 1)?;
                    if k + 1 < entries.len() {
                        self.text.push(',');
                    }
                }
                if !entries.is_empty() {
                    self.newline(depth);
                }
                self.text.push('}');
                (None, None)
            }
        };
        let node = &mut self.nodes[index];
        node.last_line = self.line;
        node.unexpected = unexpected;
        node.text = text;
        Ok(())
    }
}

impl DescriptionJson {
    /// The scene the description makes; the files it names come from `source`. An error is
    /// reported at the key path it concerns, where that can be told.
    pub fn load(&self, source: &Source) -> Result<LoadedScene, DescriptionError> {
        glint_scene::parse_scene(&self.text, Format::Json, NAME, source).map_err(|e| self.error(e))
    }

    /// The reader's error at the key path it points to. serde_json reports an error at the
    /// character it stands at: in the value at fault for most, but after it for a value it
    /// buffers first (one tagged by its `type`, or untagged), where it stands at the next
    /// element's first line or the closing bracket after it. So the candidates are the
    /// innermost value at the error's line and the value that ended on the line before; within
    /// them the key or scalar the message names, if exactly one matches, is the place.
    fn error(&self, e: SceneError) -> DescriptionError {
        if e.file.as_os_str() != NAME {
            // An error in a file the description names (a mesh, a texture): its own location.
            return DescriptionError::new("", e.to_string());
        }
        let message = e.message;
        let Some(line) = e.location.as_ref().map(|l| l.line) else {
            // No location (the reader cannot tell one in JSON for what it checks after
            // parsing): a name the message quotes, if exactly one string value is that name.
            let path = quoted_names(&message)
                .find_map(|name| unique(self.nodes.iter().filter(|n| n.text.as_deref() == Some(name))))
                .map_or("", |n| n.path.as_str());
            return DescriptionError::new(path, message);
        };
        let at = self.nodes.iter().filter(|n| (n.first_line..=n.last_line).contains(&line)).min_by_key(|n| n.span());
        let before = self.nodes.iter().filter(|n| n.last_line + 1 == line).max_by_key(|n| n.span());
        let buffered = before.filter(|n| n.tagged || message.contains("untagged enum"));
        let named = |region: Option<&Node>| {
            let region = region?;
            let inside: Vec<&Node> = self
                .nodes
                .iter()
                .filter(|n| n.first_line >= region.first_line && n.last_line <= region.last_line)
                .collect();
            named_in_message(&message, &inside)
        };
        let path = at
            .filter(|n| n.unexpected.is_some())
            .and_then(|n| named(Some(n)))
            .or_else(|| named(before))
            .or_else(|| named(at))
            .or_else(|| named(self.nodes.first()))
            .or_else(|| buffered.or(at).map(|n| n.path.as_str()))
            .unwrap_or("");
        DescriptionError::new(path, message)
    }
}

impl Node {
    fn span(&self) -> usize {
        self.last_line - self.first_line
    }
}

/// Among `nodes`, the one key (serde's "unknown field `x`") or scalar ("invalid type: string
/// \"big\", expected …") that the message names, if exactly one is.
fn named_in_message<'a>(message: &str, nodes: &[&'a Node]) -> Option<&'a str> {
    if let Some(rest) = message.strip_prefix("unknown field `") {
        let key = rest.split('`').next()?;
        return unique(nodes.iter().copied().filter(|n| n.key.as_deref() == Some(key))).map(|n| n.path.as_str());
    }
    let rest = message.strip_prefix("invalid type: ").or_else(|| message.strip_prefix("invalid value: "))?;
    let (found, _) = rest.split_once(", expected")?;
    let found = if found == "unit value" { "null" } else { found };
    unique(nodes.iter().copied().filter(|n| n.unexpected.as_deref() == Some(found))).map(|n| n.path.as_str())
}

/// The names a message quotes in backquotes, in order.
fn quoted_names(message: &str) -> impl Iterator<Item = &str> {
    message.split('`').skip(1).step_by(2)
}

fn unique<'a>(mut nodes: impl Iterator<Item = &'a Node>) -> Option<&'a Node> {
    let first = nodes.next()?;
    nodes.next().is_none().then_some(first)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(entries: Vec<(&str, Description)>) -> Description {
        Description::Table(entries.into_iter().map(|(k, v)| (k.to_string(), v)).collect())
    }

    fn numbers(values: &[f64]) -> Description {
        Description::List(values.iter().map(|v| Description::Float(*v)).collect())
    }

    fn scene(shape: Description) -> Description {
        scenes(vec![shape])
    }

    fn scenes(shapes: Vec<Description>) -> Description {
        table(vec![
            (
                "camera",
                table(vec![
                    ("position", numbers(&[0.0, 1.0, -5.0])),
                    ("look_at", numbers(&[0.0, 0.5, 0.0])),
                    ("resolution", Description::List(vec![Description::Integer(8), Description::Integer(8)])),
                ]),
            ),
            ("materials", table(vec![("white", table(vec![("type", Description::Text("diffuse".into()))]))])),
            ("shapes", Description::List(shapes)),
        ])
    }

    fn sphere(radius: Description) -> Description {
        table(vec![
            ("type", Description::Text("sphere".into())),
            ("center", numbers(&[0.0, 0.0, 0.0])),
            ("radius", radius),
            ("material", Description::Text("white".into())),
        ])
    }

    fn load(d: &Description) -> Result<LoadedScene, DescriptionError> {
        d.to_json()?.load(&Source::embedded(&[]))
    }

    fn refused(d: &Description) -> DescriptionError {
        match load(d) {
            Ok(_) => panic!("accepted: {}", d.to_json().map(|j| j.text).unwrap_or_default()),
            Err(e) => e,
        }
    }

    #[test]
    fn a_description_loads_as_its_json_file_would() {
        let d = scene(sphere(Description::Float(0.5)));
        let loaded = load(&d).expect("a valid scene");
        assert_eq!((loaded.scene.camera().width, loaded.scene.camera().height), (8, 8));
        let text = d.to_json().unwrap().text;
        let parsed: serde_json::Value = serde_json::from_str(&text).unwrap();
        // serde_json's own maps sort their keys.
        fn sorted(d: Description) -> Description {
            match d {
                Description::Table(mut entries) => {
                    entries.sort_by(|a, b| a.0.cmp(&b.0));
                    Description::Table(entries.into_iter().map(|(k, v)| (k, sorted(v))).collect())
                }
                Description::List(items) => Description::List(items.into_iter().map(sorted).collect()),
                other => other,
            }
        }
        assert_eq!(Description::from(parsed), sorted(d), "the text holds the description");
    }

    #[test]
    fn errors_name_the_key_path() {
        let wrong_type = refused(&scene(sphere(Description::Text("big".into()))));
        assert_eq!(wrong_type.path, "shapes[0].radius", "{wrong_type}");
        assert!(wrong_type.to_string().starts_with("shapes[0].radius: invalid type: string \"big\""), "{wrong_type}");

        let mut typo = sphere(Description::Float(0.5));
        if let Description::Table(entries) = &mut typo {
            entries[2].0 = "radus".into();
        }
        let typo = refused(&scene(typo));
        assert_eq!(typo.path, "shapes[0].radus", "{typo}");
        assert!(typo.message.contains("did you mean `radius`"), "{typo}");

        let mut missing = scene(sphere(Description::Float(0.5)));
        if let Description::Table(entries) = &mut missing {
            if let Description::Table(camera) = &mut entries[0].1 {
                camera.remove(1);
            }
        }
        let missing = refused(&missing);
        assert_eq!((missing.path.as_str(), missing.message.as_str()), ("camera", "missing field `look_at`"));

        let mut unknown = sphere(Description::Float(0.5));
        if let Description::Table(entries) = &mut unknown {
            entries[3].1 = Description::Text("whit".into());
        }
        let unknown = refused(&scene(unknown));
        assert_eq!(unknown.path, "shapes[0].material", "{unknown}");
        assert!(unknown.message.contains("did you mean `white`"), "{unknown}");
    }

    #[test]
    fn errors_in_tagged_values_are_placed_in_them_not_after() {
        // serde_json reads a shape (tagged by its `type`) whole before checking it, and
        // reports its errors where it then stands: at the next shape, or the list's end.
        let good = || sphere(Description::Float(0.5));
        let first = refused(&scenes(vec![sphere(Description::Text("big".into())), good(), good()]));
        assert_eq!(first.path, "shapes[0].radius", "{first}");
        let middle = refused(&scenes(vec![good(), sphere(Description::Bool(true)), good()]));
        assert_eq!(middle.path, "shapes[1].radius", "{middle}");
        let mut without_radius = good();
        if let Description::Table(entries) = &mut without_radius {
            entries.remove(2);
        }
        let last = refused(&scenes(vec![good(), without_radius.clone()]));
        assert_eq!((last.path.as_str(), last.message.as_str()), ("shapes[1]", "missing field `radius`"));
        let not_last = refused(&scenes(vec![without_radius, good()]));
        assert_eq!(not_last.path, "shapes[0]", "{not_last}");
    }

    #[test]
    fn values_json_cannot_hold_are_refused_at_their_path() {
        let nan = refused(&scene(sphere(Description::Float(f64::NAN))));
        assert_eq!(nan.path, "shapes[0].radius");
        assert!(nan.message.contains("finite"), "{nan}");
        let mut deep = Description::Null;
        for _ in 0..=MAX_DEPTH + 1 {
            deep = Description::List(vec![deep]);
        }
        let deep = refused(&table(vec![("camera", deep)]));
        assert!(deep.message.contains("levels deep"), "{deep}");
        assert_eq!(key_path("materials", "my glass"), "materials[\"my glass\"]");
        assert_eq!(key_path("", "camera"), "camera");
    }
}
