//! What the `glint` command refuses, by cause, so that a caller (a test, a script driving the
//! library, the Python binding later) can tell a bad scene from a bad flag or a full disk.
//! The messages are the ones the command prints after `error: `.

use std::path::PathBuf;

use glint_core::RenderError;
use glint_scene::SceneError;
use thiserror::Error;

use crate::checkpoint::CheckpointError;
use crate::output::OutputError;
use crate::partial::MergeError;

#[derive(Debug, Error)]
pub enum CliError {
    /// The scene (or a file it names) could not be read.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The integrator refused the scene.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// An image or checkpoint could not be written.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// `--resume`'s checkpoint is unreadable, damaged or another render's.
    #[error(transparent)]
    Checkpoint(#[from] CheckpointError),
    /// `--resume`'s checkpoint is sound but its integrator state does not restore.
    #[error("`{}`: {source}", path.display())]
    Resume { path: PathBuf, source: RenderError },
    /// A flag or environment variable out of its range (found before any work).
    #[error("{0}")]
    Setting(String),
    /// The render would not fit the memory limit.
    #[error("{0}")]
    TooLarge(String),
    #[error("cannot start worker threads: {0}")]
    Threads(#[from] rayon::ThreadPoolBuildError),
    /// Stopped (by --time or a signal) before any pass finished.
    #[error("the render was stopped before its first pass: nothing to write")]
    NothingRendered,
    /// Partial renders that cannot be merged.
    #[error(transparent)]
    Merge(#[from] MergeError),
    /// A scene description built in memory (Python's `load_dict`), at its key path.
    #[error(transparent)]
    Description(#[from] crate::description::DescriptionError),
    /// A benchmark's input file (mesh, rays, hits) that cannot be read or is malformed.
    #[error("{0}")]
    Input(String),
}
