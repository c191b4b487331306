//! The pieces of the `glint` command that tests and other tools reuse: image output.

pub mod output;
