//! The pieces of the `glint` command that tests and other tools (the fuzzer) reuse: image
//! output and checkpoints.

pub mod checkpoint;
pub mod output;
