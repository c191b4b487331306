//! The pieces of the `glint` command that tests and other tools (the fuzzer, the Python
//! module) reuse: image output, checkpoints, partial renders and their merge, the limits every
//! render is held to, scene descriptions built in memory, and the command's errors.

pub mod checkpoint;
pub mod compare;
pub mod description;
pub mod error;
pub mod limits;
pub mod output;
pub mod partial;
