//! Random numbers for rendering. Every pixel sample draws from a generator seeded by
//! (render seed, pixel, sample index), so an image is bit-identical at any thread count.

pub mod chi2;
pub mod distribution;
mod rng;
mod sampler;
mod sobol;
pub mod spherical;
pub mod warp;

pub use rng::Rng;
pub use sampler::{Sampler, SamplerKind};
