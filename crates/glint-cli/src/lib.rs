//! The pieces of the `glint` command that tests and other tools (the fuzzer) reuse: image
//! output, checkpoints and the command's errors.

pub mod checkpoint;
pub mod error;
pub mod output;
