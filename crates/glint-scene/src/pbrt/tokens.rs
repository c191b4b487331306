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

/// A pbrt file's bytes as text and its tokens, or the offset and reason of the first thing
/// that is not a token, with the text to find its line in.
///
/// A leading UTF-8 byte-order mark is dropped (editors on Windows write one). Bytes that are
/// not UTF-8 are accepted inside comments, as pbrt-v4 accepts them (its tokenizer reads bytes
/// and skips a comment unread; files exported with Latin-1 comments exist), and replaced
/// there by `?` so the text stays UTF-8 with every offset unchanged; inside a token they are
/// refused at their place, since names, strings and file names are text.
pub fn decode(mut bytes: Vec<u8>) -> Result<(String, Vec<Token>), (String, usize, String)> {
    if bytes.starts_with(BYTE_ORDER_MARK) {
        bytes.drain(..BYTE_ORDER_MARK.len());
    }
    let lossy = |bytes: &[u8]| String::from_utf8_lossy(bytes).into_owned();
    let tokens = match tokenize(&bytes) {
        Ok(tokens) => tokens,
        Err((offset, message)) => return Err((lossy(&bytes), offset, message)),
    };
    let mut start = 0;
    while let Err(e) = std::str::from_utf8(&bytes[start..]) {
        let bad = start + e.valid_up_to();
        let end = e.error_len().map_or(bytes.len(), |n| bad + n);
        // Tokens are in order of their offsets; the last one starting at or before `bad`.
        let before = tokens.partition_point(|t| t.offset <= bad);
        if before > 0 && bad < tokens[before - 1].end {
            let message = format!(
                "byte 0x{:02X} is not UTF-8 text (pbrt files are UTF-8; other bytes may only be in comments)",
                bytes[bad]
            );
            return Err((lossy(&bytes), bad, message));
        }
        bytes[bad..end].fill(b'?');
        start = end;
    }
    match String::from_utf8(bytes) {
        Ok(text) => Ok((text, tokens)),
        // Not reached: every byte that was not UTF-8 was replaced or refused above.
        Err(e) => Err((lossy(e.as_bytes()), e.utf8_error().valid_up_to(), "not UTF-8 text".into())),
    }
}

const BYTE_ORDER_MARK: &[u8] = "\u{feff}".as_bytes();

/// The tokens of `bytes`, or the offset and reason of the first that is not one.
fn tokenize(bytes: &[u8]) -> Result<Vec<Token>, (usize, String)> {
    let mut tokens = Vec::new();
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
        let tokens = tokenize(text.as_bytes()).unwrap();
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
    fn a_byte_order_mark_is_not_part_of_the_first_directive() {
        let (text, tokens) = decode(b"\xef\xbb\xbfLookAt 0 0 0".to_vec()).unwrap();
        assert_eq!(tokens[0].text(&text), "LookAt");
        assert_eq!(tokens[0].offset, 0);
    }

    #[test]
    fn bytes_that_are_not_utf8_are_read_in_comments_only() {
        // Latin-1 `é` (0xE9) in a comment, and a cut UTF-8 sequence at the end of the file.
        let bytes = b"# caf\xe9\nShape \"sphere\" # \xe2\x82";
        let (text, tokens) = decode(bytes.to_vec()).unwrap();
        let seen: Vec<_> = tokens.iter().map(|t| t.text(&text)).collect();
        assert_eq!(seen, ["Shape", "sphere"]);
        assert_eq!(text.len(), bytes.len(), "offsets are kept");
        // In a quoted string, a word, and a string that holds a `#`.
        for (bytes, offset) in
            [(&b"Shape \"sph\xe9re\""[..], 10), (b"# fine\nSh\xe9pe", 9), (b"Shape \"a#\xe9\" # \xe9", 9)]
        {
            let (_, at, message) = decode(bytes.to_vec()).unwrap_err();
            assert_eq!(at, offset, "{message}");
            assert!(message.contains("0xE9"), "{message}");
        }
    }

    #[test]
    fn an_open_string_is_refused_at_its_start() {
        assert_eq!(tokenize(b"Shape\n  \"sphere").unwrap_err().0, 8);
    }
}
