//! Mitsuba's XML, read into a plain element tree: `<default>` parameters substituted into
//! every `$name` (command-line `-D name=value` first), `<include>` files spliced in where they
//! stand, and every element tagged with its file, line and column for messages.

use std::collections::HashMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

use crate::error::{Location, SceneError};

/// One XML element after substitution.
#[derive(Clone, Debug)]
pub(super) struct Element {
    pub tag: String,
    pub attributes: Vec<(String, String)>,
    pub children: Vec<Element>,
    pub position: Position,
}

/// Where an element starts: the file (an index into `Files`), line and column, and its byte
/// range when it is in the main file (the native builder points its own errors there).
#[derive(Clone, Debug)]
pub(super) struct Position {
    pub file: usize,
    pub line: u32,
    pub column: u32,
    pub span: Option<Range<usize>>,
}

/// The files read: the main scene first, then includes.
#[derive(Debug, Default)]
pub(super) struct Files {
    pub files: Vec<(PathBuf, String)>,
    /// The names the files' `<default>`s declare, for checking the command line's -D names.
    pub declared: Vec<String>,
    /// Mitsuba's file resolver: the main scene's directory, then each `<path>` in the order
    /// read. Includes, meshes and textures are looked up in them in turn.
    pub search_path: Vec<PathBuf>,
    /// What reading the files found amiss without refusing the scene.
    pub warnings: Vec<String>,
}

impl Files {
    /// A warning's text: file, line and column, then the message.
    pub fn warning(&self, at: &Position, message: impl AsRef<str>) -> String {
        let (path, _) = &self.files[at.file];
        format!("{}:{}:{}: {}", path.display(), at.line, at.column, message.as_ref())
    }

    pub fn error(&self, at: &Position, message: impl Into<String>) -> SceneError {
        let (path, text) = &self.files[at.file];
        SceneError::new(path, Some(Location::from_line_column(text, at.line as usize, at.column as usize)), message)
    }
}

impl Element {
    pub fn attribute(&self, name: &str) -> Option<&str> {
        self.attributes.iter().find(|(n, _)| n == name).map(|(_, v)| v.as_str())
    }

    /// `<tag type="…">` for messages.
    pub fn describe(&self) -> String {
        match self.attribute("type") {
            Some(t) => format!("<{} type=\"{t}\">", self.tag),
            None => format!("<{}>", self.tag),
        }
    }
}

/// Reads `path` and everything it includes. `defines` are the command line's `-D` values,
/// which take precedence over the file's `<default>`s.
pub(super) fn read_scene(
    path: &Path,
    defines: &[(String, String)],
    search_path: &[PathBuf],
) -> Result<(Element, Files), SceneError> {
    let (bytes, directories) = crate::reader::read_scene_file(path, search_path)?;
    let mut files = Files { search_path: directories, ..Files::default() };
    let mut parameters: HashMap<String, String> = defines.iter().cloned().collect();
    let text = crate::source::utf8_text(path, bytes)?;
    let root = parse_file(path, text, &mut files, &mut parameters, 0)?;
    if root.tag != "scene" {
        return Err(files.error(&root.position, format!("expected a <scene> root element, found <{}>", root.tag)));
    }
    match root.attribute("version") {
        Some(v) if v.starts_with("3.") || v.starts_with("2.") => {}
        Some(v) => {
            return Err(files.error(
                &root.position,
                format!("scene version {v} is not supported; glint reads Mitsuba 3 scenes (version 3.x)"),
            ))
        }
        None => return Err(files.error(&root.position, "the <scene> element needs a version attribute (3.0.0)")),
    }
    Ok((root, files))
}

const MAX_INCLUDE_DEPTH: u32 = 16;
/// How deeply elements may nest. Mitsuba's scenes nest a handful deep; the limit keeps the
/// readers' recursion (and the tree's drop) far from the stack's end, which 10,000 levels hit.
const MAX_NESTING: u32 = 256;

/// The elements of `text`, read from `path`, with its includes.
fn parse_file(
    path: &Path,
    text: String,
    files: &mut Files,
    parameters: &mut HashMap<String, String>,
    depth: u32,
) -> Result<Element, SceneError> {
    let index = files.files.len();
    files.files.push((path.to_path_buf(), text));
    let text = files.files[index].1.clone();
    // Before the XML parser, whose recursion a deep enough nesting overflows.
    if let Some(offset) = nesting_beyond(&text, MAX_NESTING) {
        return Err(SceneError::new(
            path,
            Some(Location::from_offset(&text, offset)),
            format!("elements nested more than {MAX_NESTING} deep"),
        ));
    }
    let document = roxmltree::Document::parse(&text).map_err(|e| {
        let p = e.pos();
        SceneError::new(
            path,
            Some(Location::from_line_column(&text, p.row as usize, p.col as usize)),
            format!("malformed XML: {e}"),
        )
    })?;
    let directory = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let reader = Reader { document: &document, file: index, directory, main: index == 0 };
    reader.element(document.root_element(), files, parameters, depth, 0)
}

struct Reader<'d, 'input> {
    document: &'d roxmltree::Document<'input>,
    file: usize,
    directory: PathBuf,
    main: bool,
}

impl Reader<'_, '_> {
    fn position(&self, node: roxmltree::Node) -> Position {
        let p = self.document.text_pos_at(node.range().start);
        Position { file: self.file, line: p.row, column: p.col, span: self.main.then(|| node.range()) }
    }

    fn element(
        &self,
        node: roxmltree::Node,
        files: &mut Files,
        parameters: &mut HashMap<String, String>,
        depth: u32,
        nesting: u32,
    ) -> Result<Element, SceneError> {
        let position = self.position(node);
        if nesting >= MAX_NESTING {
            return Err(files.error(&position, format!("elements nested more than {MAX_NESTING} deep")));
        }
        let mut attributes = Vec::new();
        for a in node.attributes() {
            let value = substitute(a.value(), parameters).map_err(|m| files.error(&position, m))?;
            attributes.push((a.name().to_string(), value));
        }
        let mut element =
            Element { tag: node.tag_name().name().to_string(), attributes, children: Vec::new(), position };
        for child in node.children().filter(|c| c.is_element()) {
            let child_position = self.position(child);
            match child.tag_name().name() {
                "default" => {
                    let name = child.attribute("name");
                    let value = child.attribute("value");
                    let (Some(name), Some(value)) = (name, value) else {
                        return Err(files.error(&child_position, "<default> needs `name` and `value` attributes"));
                    };
                    // The command line's -D wins; the first <default> of a name counts.
                    parameters.entry(name.to_string()).or_insert_with(|| value.to_string());
                    files.declared.push(name.to_string());
                }
                "include" => {
                    let Some(filename) = child.attribute("filename") else {
                        return Err(files.error(&child_position, "<include> needs a `filename` attribute"));
                    };
                    let filename = substitute(filename, parameters).map_err(|m| files.error(&child_position, m))?;
                    if depth >= MAX_INCLUDE_DEPTH {
                        return Err(files.error(&child_position, "includes nested too deeply (an include cycle?)"));
                    }
                    // Mitsuba resolves includes against its search path; glint also tries the
                    // including file's own directory last.
                    let mut directories = files.search_path.clone();
                    directories.push(self.directory.clone());
                    let path = crate::source::resolve(&directories, Path::new(&filename));
                    if !path.exists() {
                        return Err(files.error(
                            &child_position,
                            format!("included file `{filename}` not found ({})", path.display()),
                        ));
                    }
                    let bytes = crate::source::read_file(&path, u64::MAX).map_err(|m| {
                        files.error(&child_position, format!("cannot read `{filename}` ({}): {m}", path.display()))
                    })?;
                    let text = crate::source::utf8_text(&path, bytes)?;
                    let included = parse_file(&path, text, files, parameters, depth + 1)?;
                    // An included <scene>'s children stand where the <include> was.
                    if included.tag == "scene" {
                        element.children.extend(included.children);
                    } else {
                        element.children.push(included);
                    }
                }
                "path" => {
                    let Some(value) = child.attribute("value") else {
                        return Err(files.error(&child_position, "<path> needs a `value` attribute"));
                    };
                    let value = substitute(value, parameters).map_err(|m| files.error(&child_position, m))?;
                    // Relative to the file that names it, else found on the search path; it
                    // goes first, as Mitsuba prepends it. A folder that is not there is
                    // reported and skipped (a scene moved out of its collection often names
                    // one; the search path given to glint may hold its files instead).
                    let mut directory = self.directory.join(&value);
                    if !directory.is_dir() {
                        directory = crate::source::resolve(&files.search_path, Path::new(&value));
                    }
                    if directory.is_dir() {
                        files.search_path.insert(0, directory);
                    } else {
                        let message =
                            format!("<path>: folder `{value}` not found ({}); not searched", directory.display());
                        files.warnings.push(files.warning(&child_position, message));
                    }
                }
                _ => element.children.push(self.element(child, files, parameters, depth, nesting + 1)?),
            }
        }
        Ok(element)
    }
}

/// The byte offset of the first tag nested deeper than `limit`, if any: a scan of start and
/// end tags that skips comments, CDATA, processing instructions and declarations, and
/// counts `<a/>` as opening nothing.
fn nesting_beyond(text: &str, limit: u32) -> Option<usize> {
    let bytes = text.as_bytes();
    let (mut depth, mut i) = (0u32, 0usize);
    let skip_to = |from: usize, end: &str| text[from..].find(end).map_or(bytes.len(), |k| from + k + end.len());
    while let Some(k) = text[i..].find('<') {
        let start = i + k;
        let rest = &text[start..];
        i = if rest.starts_with("<!--") {
            skip_to(start, "-->")
        } else if rest.starts_with("<![CDATA[") {
            skip_to(start, "]]>")
        } else if rest.starts_with("<?") {
            skip_to(start, "?>")
        } else if rest.starts_with("<!") {
            skip_to(start, ">")
        } else if rest.starts_with("</") {
            depth = depth.saturating_sub(1);
            skip_to(start, ">")
        } else {
            let end = skip_to(start, ">");
            if !text[..end].ends_with("/>") {
                depth += 1;
                if depth > limit {
                    return Some(start);
                }
            }
            end
        };
    }
    None
}

/// Replaces every `$name` in `value` by its parameter.
fn substitute(value: &str, parameters: &HashMap<String, String>) -> Result<String, String> {
    if !value.contains('$') {
        return Ok(value.to_string());
    }
    let mut out = String::new();
    let mut rest = value;
    while let Some(i) = rest.find('$') {
        out.push_str(&rest[..i]);
        let after = &rest[i + 1..];
        let end = after.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(after.len());
        let name = &after[..end];
        if name.is_empty() {
            out.push('$');
        } else {
            let v = parameters.get(name).ok_or_else(|| {
                format!("`${name}` is not defined: add <default name=\"{name}\" value=\"…\"/> or pass -D {name}=…")
            })?;
            out.push_str(v);
        }
        rest = &after[end..];
    }
    out.push_str(rest);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn substitution() {
        let p: HashMap<String, String> = [("spp".to_string(), "64".to_string())].into();
        assert_eq!(substitute("$spp", &p).unwrap(), "64");
        assert_eq!(substitute("a $spp b", &p).unwrap(), "a 64 b");
        assert_eq!(substitute("no dollar", &p).unwrap(), "no dollar");
        assert!(substitute("$nope", &p).unwrap_err().contains("`$nope` is not defined"));
    }
}
