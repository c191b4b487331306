//! `Located<T>`: a value with the byte range it came from, when the format can tell.
//!
//! TOML can (through `toml::Spanned`); JSON cannot. serde gives no way to ask a deserializer
//! which format it is, so the reader sets a thread-local flag around the TOML parse.

use std::cell::Cell;
use std::ops::Range;

use serde::{Deserialize, Deserializer};

thread_local! {
    static SPANS: Cell<bool> = const { Cell::new(false) };
}

/// Runs `parse` with span capture on (for TOML).
pub(crate) fn with_spans<R>(parse: impl FnOnce() -> R) -> R {
    SPANS.with(|s| s.set(true));
    let result = parse();
    SPANS.with(|s| s.set(false));
    result
}

#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Located<T> {
    pub value: T,
    pub span: Option<Range<usize>>,
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for Located<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        if SPANS.with(Cell::get) {
            let spanned = toml::Spanned::<T>::deserialize(deserializer)?;
            let span = spanned.span();
            Ok(Located { value: spanned.into_inner(), span: Some(span) })
        } else {
            Ok(Located { value: T::deserialize(deserializer)?, span: None })
        }
    }
}
