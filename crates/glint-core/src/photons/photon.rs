//! A stored photon in 32 bytes: position, power (RGB, f32), the direction it arrived from
//! (octahedral, 2 × 16 bits), the surface normal on its side (octahedral, 2 × 8 bits: enough
//! to tell surfaces apart) and the kd-tree's split axis.

use glam::{Vec2, Vec3};

use crate::Rgb;

#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct Photon {
    pub position: Vec3,
    /// Flux carried (per emitted photon of its map; the map divides by the count emitted).
    pub power: Rgb,
    /// Unit direction toward where the photon came from, octahedrally encoded.
    incoming: [u16; 2],
    /// Unit geometric normal on the side the photon arrived, octahedrally encoded.
    normal: [u8; 2],
    /// The kd-tree's split axis at this node (0, 1, 2), set when the map is built.
    pub(super) axis: u8,
}

impl Photon {
    /// `incoming` points away from the surface, toward where the photon came from; `normal`
    /// is the surface's normal on that side.
    pub fn new(position: Vec3, incoming: Vec3, normal: Vec3, power: Rgb) -> Self {
        let n = encode_octahedral(normal);
        Self {
            position,
            power,
            incoming: encode_octahedral(incoming),
            normal: [(n[0] >> 8) as u8, (n[1] >> 8) as u8],
            axis: 0,
        }
    }

    /// The surface normal on the photon's side (within about 1°).
    pub fn normal(&self) -> Vec3 {
        let widen = |b: u8| (b as u16) << 8 | b as u16; // 0 → 0, 255 → 65535
        decode_octahedral([widen(self.normal[0]), widen(self.normal[1])])
    }

    /// The unit direction toward where the photon came from (within 1e-4).
    pub fn incoming(&self) -> Vec3 {
        decode_octahedral(self.incoming)
    }
}

/// Octahedral mapping of the unit sphere to the square (Meyer et al. 2010), quantised to
/// 16 bits per coordinate: an error below 1e-4 rad.
fn encode_octahedral(w: Vec3) -> [u16; 2] {
    let w = w / (w.x.abs() + w.y.abs() + w.z.abs());
    let mut p = Vec2::new(w.x, w.y);
    if w.z < 0.0 {
        p = Vec2::new((1.0 - p.y.abs()) * p.x.signum(), (1.0 - p.x.abs()) * p.y.signum());
    }
    let q = |x: f32| (((x.clamp(-1.0, 1.0) + 1.0) * 0.5) * 65535.0).round() as u16;
    [q(p.x), q(p.y)]
}

fn decode_octahedral(e: [u16; 2]) -> Vec3 {
    let x = e[0] as f32 / 65535.0 * 2.0 - 1.0;
    let y = e[1] as f32 / 65535.0 * 2.0 - 1.0;
    let z = 1.0 - x.abs() - y.abs();
    let t = (-z).max(0.0);
    let x = x + if x >= 0.0 { -t } else { t };
    let y = y + if y >= 0.0 { -t } else { t };
    Vec3::new(x, y, z).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::warp::square_to_uniform_sphere;

    #[test]
    fn thirty_two_bytes() {
        assert_eq!(std::mem::size_of::<Photon>(), 32);
    }

    #[test]
    fn directions_survive_encoding() {
        let mut worst = 0.0f32;
        for i in 0..200 {
            for j in 0..200 {
                let w = square_to_uniform_sphere(Vec2::new((i as f32 + 0.5) / 200.0, (j as f32 + 0.5) / 200.0));
                let photon = Photon::new(Vec3::ZERO, w, w, Rgb::ONE);
                let back = photon.incoming();
                assert!(photon.normal().dot(w) > 0.999, "{w}");
                worst = worst.max(back.cross(w).length().atan2(back.dot(w))); // acos is too coarse near 1 in f32
            }
        }
        for w in [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z] {
            assert!(Photon::new(Vec3::ZERO, w, w, Rgb::ONE).incoming().dot(w) > 0.99999);
            assert!(Photon::new(Vec3::ZERO, w, w, Rgb::ONE).normal().dot(w) > 0.999);
        }
        assert!(worst < 1e-4, "{worst}");
    }
}
