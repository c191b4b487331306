//! pbrt's scene text as tokens: words (directives, bare numbers, `true`/`false`), quoted
//! strings, and brackets; `#` starts a comment to the end of the line. Every token keeps its
//! byte offset, from which a message finds its line and column (counting them as it goes
//! would scan a line per token, and pbrt meshes put a million numbers on one line).

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A directive's name, a number or a bare `true`/`false`.
    Word,
    /// A quoted string, without its quotes (pbrt has no escapes inside strings but `\"`).
    Quoted,
    Open,
    Close,
}

/// A token: its kind and where its text lies in the file (a quoted string's without its
/// quotes, `offset` at its opening quote).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Token {
    pub kind: Kind,
    pub offset: usize,
    pub start: usize,
    pub end: usize,
}

impl Token {
    pub fn text(self, file: &str) -> &str {
        &file[self.start..self.end]
    }
}

/// The tokens of `text`, or the offset and reason of the first that is not one.
pub fn tokenize(text: &str) -> Result<Vec<Token>, (usize, String)> {
    let mut tokens = Vec::new();
    let bytes = text.as_bytes();
    let mut i = 0usize;
    while i < bytes.len() {
        let token = |kind, start: usize, end: usize, offset| Token { kind, offset, start, end };
        match bytes[i] {
            b' ' | b'\t' | b'\r' | b'\n' => i += 1,
            b'#' => {
                while i < bytes.len() && bytes[i] != b'\n' {
                    i += 1;
                }
            }
            b'[' => {
                tokens.push(token(Kind::Open, i, i + 1, i));
                i += 1;
            }
            b']' => {
                tokens.push(token(Kind::Close, i, i + 1, i));
                i += 1;
            }
            b'"' => {
                let start = i + 1;
                let mut end = start;
                loop {
                    match bytes.get(end) {
                        None | Some(b'\n') => return Err((i, "a quoted string is not closed on its line".into())),
                        Some(b'"') => break,
                        Some(b'\\') => end += 2,
                        Some(_) => end += 1,
                    }
                }
                tokens.push(token(Kind::Quoted, start, end, i));
                i = end + 1;
            }
            _ => {
                let start = i;
                while i < bytes.len() && !matches!(bytes[i], b' ' | b'\t' | b'\r' | b'\n' | b'[' | b']' | b'"' | b'#') {
                    i += 1;
                }
                tokens.push(token(Kind::Word, start, i, start));
            }
        }
    }
    Ok(tokens)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_keep_their_kind_and_place() {
        let text = "Shape \"sphere\" # a ball\n  \"float radius\" [ 2.5 ]";
        let tokens = tokenize(text).unwrap();
        let seen: Vec<_> = tokens.iter().map(|t| (t.kind, t.text(text), t.offset)).collect();
        assert_eq!(
            seen,
            [
                (Kind::Word, "Shape", 0),
                (Kind::Quoted, "sphere", 6),
                (Kind::Quoted, "float radius", 26),
                (Kind::Open, "[", 41),
                (Kind::Word, "2.5", 43),
                (Kind::Close, "]", 47),
            ]
        );
    }

    #[test]
    fn an_open_string_is_refused_at_its_start() {
        assert_eq!(tokenize("Shape\n  \"sphere").unwrap_err().0, 8);
    }
}
