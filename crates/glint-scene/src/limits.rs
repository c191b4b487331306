//! How much memory a scene's files may take to read: `glint render --memory-limit` (8 GiB by
//! default) caps what a gzipped mesh inflates to and the TOML text a reader takes on, so that
//! a small or a hostile file cannot fill the memory before anything is checked.

use std::sync::atomic::{AtomicU64, Ordering};

static MEMORY_LIMIT: AtomicU64 = AtomicU64::new(8 << 30);

/// Sets the limit, in bytes, for every scene read after it.
pub fn set_memory_limit(bytes: u64) {
    MEMORY_LIMIT.store(bytes, Ordering::Relaxed);
}

/// The limit, in bytes.
pub fn memory_limit() -> u64 {
    MEMORY_LIMIT.load(Ordering::Relaxed)
}

/// How the limit is raised, for messages.
pub const RAISE: &str = "raise it with --memory-limit GIB or GLINT_MEMORY_LIMIT";

/// `bytes` in MiB or GiB, for messages.
pub fn describe(bytes: u64) -> String {
    if bytes >= 1 << 30 {
        format!("{:.1} GiB", bytes as f64 / (1u64 << 30) as f64)
    } else {
        format!("{:.0} MiB", bytes as f64 / (1u64 << 20) as f64)
    }
}
