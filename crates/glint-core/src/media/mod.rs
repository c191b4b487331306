//! Participating media, the parts that do not depend on an integrator: phase functions,
//! homogeneous media (Beer–Lambert transmittance, free flights with spectral MIS) and
//! heterogeneous grid media (trilinear density, delta and ratio tracking against a majorant).
//!
//! `volpath` (integrators/volpath.rs) traces paths through them; photon mapping in media is
//! not written yet (issue 29). Each part here is tested on its own against analytic answers
//! and quadrature.

mod grid;
mod homogeneous;
mod phase;
mod voxels;

pub use grid::{Albedo, GridMedium};
pub use homogeneous::{Flight, Homogeneous};
pub use phase::{PhaseFunction, PhaseSample};
pub use voxels::{box_to_world, VoxelField};

use glam::Vec3;

use crate::sampling::Rng;
use crate::Rgb;

/// A medium of the scene: what fills it and how it scatters.
#[derive(Clone, Debug, PartialEq)]
pub struct Medium {
    pub kind: MediumKind,
    pub phase: PhaseFunction,
    /// The radiance L_e the medium emits where it absorbs: σ_a L_e per unit length (pbrt's
    /// `Le`; zero for most media).
    pub emission: Rgb,
}

#[derive(Clone, Debug, PartialEq)]
pub enum MediumKind {
    Homogeneous(Homogeneous),
    /// Boxed: a grid holds its voxels.
    Grid(Box<GridMedium>),
}

/// The media on either side of a surface: `inside` behind its geometric normal, `outside`
/// in front (`None`: no medium, vacuum).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MediumInterface {
    pub inside: Option<u32>,
    pub outside: Option<u32>,
}

impl MediumInterface {
    /// The medium a direction `w` leaving the surface goes into.
    pub fn toward(&self, w: Vec3, geometric_normal: Vec3) -> Option<u32> {
        // As ray origins are offset: outside unless strictly behind the normal.
        if w.dot(geometric_normal) >= 0.0 {
            self.outside
        } else {
            self.inside
        }
    }
}

impl Medium {
    /// The transmittance over `distance` from `origin` along the unit `direction`: exact for
    /// a homogeneous medium, ratio tracking's unbiased estimate in a grid (its numbers from
    /// `rng`).
    pub fn transmittance(&self, origin: Vec3, direction: Vec3, distance: f32, rng: &mut Rng) -> Rgb {
        match &self.kind {
            MediumKind::Homogeneous(m) => m.transmittance(distance),
            MediumKind::Grid(g) => g.ratio_track(origin, direction, distance, rng),
        }
    }

    /// σ_s and σ_a at a point (a grid's are zero outside its box).
    pub fn coefficients(&self, p: Vec3) -> (Rgb, Rgb) {
        match &self.kind {
            MediumKind::Homogeneous(m) => (m.sigma_s, m.sigma_a),
            MediumKind::Grid(g) => {
                let (sigma_t, albedo) = (g.sigma_t(p), g.albedo_at(p));
                (sigma_t * albedo, sigma_t * (Rgb::ONE - albedo))
            }
        }
    }

    /// A free flight from `origin` along the unit `direction`, ending before `t_max` in a
    /// real collision or passing the segment (the weight is transmittance over density: see
    /// `Flight`).
    pub fn flight(&self, origin: Vec3, direction: Vec3, t_max: f32, rng: &mut Rng) -> Flight {
        match &self.kind {
            MediumKind::Homogeneous(m) => m.sample_flight(t_max, rng.next_f32(), rng.next_f32()),
            MediumKind::Grid(g) => g.flight(origin, direction, t_max, rng),
        }
    }
}
