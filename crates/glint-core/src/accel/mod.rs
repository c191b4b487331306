//! Acceleration structures. They know boxes and item indices, never shapes: the caller passes
//! a closure that intersects leaf item `i` (a primitive, or a block of four; tinybvh, obvhs).

mod bvh;
mod triangle4;
mod wide;

pub use bvh::{Bvh, BvhStats};
pub use triangle4::{Hits4, Triangle4, WatertightRay4, EMPTY, GENERIC, LANES};
pub use wide::{Bvh8, NoCounter, TraversalCounter, TraversalCounts};
