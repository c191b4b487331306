//! The pieces of the `glint` command that tests and other tools (the fuzzer) reuse: image
//! output, checkpoints, partial renders and their merge, and the command's errors.

pub mod checkpoint;
pub mod compare;
pub mod error;
pub mod output;
pub mod partial;
