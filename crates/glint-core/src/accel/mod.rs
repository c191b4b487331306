//! Acceleration structures. They know boxes and primitive indices, never shapes: the caller
//! passes a closure that intersects primitive `i` (tinybvh, obvhs).

mod bvh;
mod wide;

pub use bvh::{Bvh, BvhStats};
pub use wide::{Bvh4, NoCounter, TraversalCounter, TraversalCounts};
