//! Participating media, the parts that do not depend on an integrator: phase functions,
//! homogeneous media (Beer–Lambert transmittance, free flights with spectral MIS) and
//! heterogeneous grid media (trilinear density, delta and ratio tracking against a majorant).
//!
//! The volumetric path tracer and photon mapping in media that will use them are not written
//! yet (issue 29); each part here is tested on its own against analytic answers and
//! quadrature.

mod grid;
mod homogeneous;
mod phase;

pub use grid::{Collision, GridMedium};
pub use homogeneous::{Flight, Homogeneous};
pub use phase::{PhaseFunction, PhaseSample};
