//! A stored photon in 32 bytes: position, power (RGB, f32), the direction it arrived from
//! (octahedral, 2 × 16 bits), the surface normal on its side (octahedral, 2 × 8 bits: enough
//! to tell surfaces apart, and exact for the axes, so that the walls of a box are told apart
//! at any distance from its edges) and the kd-tree's split axis.

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
        let n = octahedral(normal);
        // 255 levels, 127 the middle: the square's centre and edges, where the axes land, exact.
        let q = |x: f32| ((x.clamp(-1.0, 1.0) + 1.0) * 127.0).round() as u8;
        Self { position, power, incoming: encode_octahedral(incoming), normal: [q(n.x), q(n.y)], axis: 0 }
    }

    /// The surface normal on the photon's side (within about 1°).
    pub fn normal(&self) -> Vec3 {
        let d = |b: u8| b.min(254) as f32 / 127.0 - 1.0;
        from_octahedral(Vec2::new(d(self.normal[0]), d(self.normal[1])))
    }

    /// Whether the photon can have landed on the surface at `point` whose normal on the
    /// viewer's side is `normal`, for a density estimate there: on that side of that surface
    /// (normals within about 25°), or on another surface that `point` is in front of (an
    /// inside corner). Photons within the search radius on the far side of a thin wall, or
    /// on the outside of a wall meeting it at a corner, cannot: their incoming directions may
    /// still face the near side, and the light outside a closed box leaked in.
    pub fn can_reach(&self, point: Vec3, normal: Vec3) -> bool {
        let photon_normal = self.normal();
        let cos = photon_normal.dot(normal);
        cos >= 0.9 || (cos > -0.5 && photon_normal.dot(point - self.position) >= 0.0)
    }

    /// The unit direction toward where the photon came from (within 1e-4).
    pub fn incoming(&self) -> Vec3 {
        decode_octahedral(self.incoming)
    }
}

/// Octahedral mapping of the unit sphere to the square (Meyer et al. 2010), quantised to
/// 16 bits per coordinate: an error below 1e-4 rad.
fn encode_octahedral(w: Vec3) -> [u16; 2] {
    let p = octahedral(w);
    let q = |x: f32| (((x.clamp(-1.0, 1.0) + 1.0) * 0.5) * 65535.0).round() as u16;
    [q(p.x), q(p.y)]
}

fn decode_octahedral(e: [u16; 2]) -> Vec3 {
    let d = |c: u16| c as f32 / 65535.0 * 2.0 - 1.0;
    from_octahedral(Vec2::new(d(e[0]), d(e[1])))
}

/// The point of [−1, 1]² that the octahedral mapping gives the unit vector `w`.
fn octahedral(w: Vec3) -> Vec2 {
    let w = w / (w.x.abs() + w.y.abs() + w.z.abs());
    let p = Vec2::new(w.x, w.y);
    if w.z < 0.0 {
        Vec2::new((1.0 - p.y.abs()) * p.x.signum(), (1.0 - p.x.abs()) * p.y.signum())
    } else {
        p
    }
}

fn from_octahedral(p: Vec2) -> Vec3 {
    let (x, y) = (p.x, p.y);
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
            // Exact: a photon on a box's wall is never in front of the adjacent wall.
            assert_eq!(Photon::new(Vec3::ZERO, w, w, Rgb::ONE).normal(), w);
        }
        assert!(worst < 1e-4, "{worst}");
    }
}
