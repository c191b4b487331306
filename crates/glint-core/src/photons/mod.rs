//! Photons and the photon map (Jensen 1996): what photon mapping and SPPM store where light
//! lands, and the kd-tree that finds the photons near a point.

mod kdtree;
mod photon;

pub use kdtree::{NearestPhotons, PhotonMap};
pub use photon::Photon;
