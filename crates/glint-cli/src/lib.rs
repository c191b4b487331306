//! The library under every front end of glint (the `glint` command, the Python module) and
//! the pieces tests and other tools (the fuzzer) reuse: the render job (`job`: load, checks,
//! limits, identity, run, warnings as values), image output, checkpoints, partial renders and
//! their merge, the limits every render is held to, scene descriptions built in memory, and
//! the errors.

pub mod checkpoint;
pub mod compare;
pub mod description;
pub mod error;
pub mod job;
pub mod limits;
pub mod output;
pub mod partial;
