//! Acceleration structures. The trees know boxes and item indices, never shapes: the caller
//! passes a closure that intersects leaf item `i` (a primitive, or a block of eight; tinybvh,
//! obvhs). `aggregate.rs` is that caller: the scene's objects over the trees.

mod aggregate;
mod bvh;
mod triangle8;
mod wide;

pub use aggregate::{Geometry, Object, PrimitiveHit};
pub use bvh::{Bvh, BvhStats};
pub use triangle8::{Hits8, Triangle8, WatertightRay8, EMPTY, GENERIC, LANES};
pub use wide::{Bvh8, NoCounter, TraversalCounter, TraversalCounts, INTERLEAVED as INTERLEAVED_RAYS};
