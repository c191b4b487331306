use std::fmt;
use std::path::PathBuf;

/// Where in a scene file something is.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Location {
    pub line: usize,
    pub column: usize,
    /// The text of that line, for a caret under the column.
    pub source_line: String,
}

impl Location {
    /// From a byte offset into `text` (1-based line and column, columns in characters).
    pub fn from_offset(text: &str, offset: usize) -> Self {
        let offset = offset.min(text.len());
        let before = &text[..offset];
        let line = before.matches('\n').count() + 1;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let column = text[line_start..offset].chars().count() + 1;
        let source_line = text[line_start..].lines().next().unwrap_or("").to_string();
        Self { line, column, source_line }
    }

    pub fn from_line_column(text: &str, line: usize, column: usize) -> Self {
        let source_line = text.lines().nth(line.saturating_sub(1)).unwrap_or("").to_string();
        Self { line, column, source_line }
    }
}

/// A scene that cannot be read, with everything a user needs to fix it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SceneError {
    pub file: PathBuf,
    pub location: Option<Location>,
    pub message: String,
}

impl SceneError {
    pub fn new(file: impl Into<PathBuf>, location: Option<Location>, message: impl Into<String>) -> Self {
        Self { file: file.into(), location, message: message.into() }
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.location {
            Some(loc) => {
                write!(f, "{}:{}:{}: {}", self.file.display(), loc.line, loc.column, self.message)?;
                if !loc.source_line.trim().is_empty() {
                    let gutter = loc.line.to_string().len();
                    write!(f, "\n{:gutter$} |\n{} | {}", "", loc.line, loc.source_line)?;
                    write!(f, "\n{:gutter$} | {:>col$}", "", "^", col = loc.column)?;
                }
                Ok(())
            }
            None => write!(f, "{}: {}", self.file.display(), self.message),
        }
    }
}

impl std::error::Error for SceneError {}

/// Adds "did you mean `x`?" to serde's "unknown field/variant `y`, expected ..." messages.
pub(crate) fn with_suggestion(message: &str) -> String {
    let Some((unknown, expected)) = unknown_and_expected(message) else {
        return message.to_string();
    };
    format!("{message}{}", did_you_mean(&unknown, expected.iter().map(String::as_str)))
}

/// The unknown name and the valid ones from a serde message, if it is of that kind.
pub(crate) fn unknown_and_expected(message: &str) -> Option<(String, Vec<String>)> {
    let rest = message.strip_prefix("unknown field `").or_else(|| message.strip_prefix("unknown variant `"))?;
    let (unknown, rest) = rest.split_once('`')?;
    let expected = rest.split('`').skip(1).step_by(2).map(str::to_string).collect();
    Some((unknown.to_string(), expected))
}

/// "; did you mean `x`?" for the closest of `names` to `name`, or nothing if none is close.
pub(crate) fn did_you_mean<'a>(name: &str, names: impl IntoIterator<Item = &'a str>) -> String {
    closest_name(name, names).map(|n| format!("; did you mean `{n}`?")).unwrap_or_default()
}

/// `did_you_mean` over the keys of a map (a `HashMap`'s come in an order that changes from
/// run to run): sorted first, so that of names equally close to `name` the same one is
/// suggested every time.
pub(crate) fn did_you_mean_among_keys<'a>(name: &str, keys: impl IntoIterator<Item = &'a String>) -> String {
    let mut keys: Vec<&str> = keys.into_iter().map(String::as_str).collect();
    keys.sort_unstable();
    did_you_mean(name, keys)
}

/// The closest of `names` to `name`, if any is close enough to be a likely typo.
pub(crate) fn closest_name<'a>(name: &str, names: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    names
        .into_iter()
        .map(|n| (strsim::damerau_levenshtein(name, n), n))
        .filter(|(d, _)| *d <= 2.max(name.len() / 3))
        .min_by_key(|(d, _)| *d)
        .map(|(_, n)| n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggestions_for_typos() {
        let m = with_suggestion("unknown field `radus`, expected `radius` or `material`");
        assert!(m.ends_with("did you mean `radius`?"), "{m}");
        let m = with_suggestion("unknown variant `sphre`, expected one of `sphere`, `plane`, `box`");
        assert!(m.ends_with("did you mean `sphere`?"), "{m}");
        let m = with_suggestion("unknown field `zzzzzzzz`, expected `radius` or `material`");
        assert!(!m.contains("did you mean"));
        assert_eq!(closest_name("gren", ["red", "green", "blue"]), Some("green"));
    }

    #[test]
    fn locations_from_offsets() {
        let text = "a = 1\nbb = 2\n";
        let loc = Location::from_offset(text, 8);
        assert_eq!((loc.line, loc.column, loc.source_line.as_str()), (2, 3, "bb = 2"));
    }
}
