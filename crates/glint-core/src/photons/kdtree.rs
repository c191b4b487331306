//! The photon map: a balanced kd-tree stored implicitly in the photon array (Jensen 1996).
//! Every range of the array is a subtree whose node is its middle element, split on the axis
//! where the range's photons spread most; so the tree needs no pointers and no memory beyond
//! the photons, and it is built in O(n log n) by median selection (in parallel for large maps).
//!
//! Queries: every photon within a radius (SPPM), and the k nearest within a maximum radius
//! (photon mapping's radiance estimate), each descending the near side first and the far side
//! only when the splitting plane is within the search radius.

use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::ops::Range;

use glam::Vec3;

use super::Photon;
use crate::geometry::Aabb;

/// Ranges shorter than this are built on the calling thread.
const PARALLEL_BUILD_MIN: usize = 1 << 15;

#[derive(Clone, Debug, Default)]
pub struct PhotonMap {
    photons: Vec<Photon>,
    /// Photons emitted from the lights to make this map (stored or not): the estimate divides
    /// by it.
    emitted: u64,
}

impl PhotonMap {
    pub fn build(mut photons: Vec<Photon>, emitted: u64) -> Self {
        build_range(&mut photons);
        Self { photons, emitted }
    }

    pub fn len(&self) -> usize {
        self.photons.len()
    }

    pub fn is_empty(&self) -> bool {
        self.photons.is_empty()
    }

    pub fn emitted(&self) -> u64 {
        self.emitted
    }

    pub fn photon(&self, index: u32) -> &Photon {
        &self.photons[index as usize]
    }

    /// Calls `f(photon, squared distance)` for every photon within `radius` of `p`.
    pub fn for_each_within(&self, p: Vec3, radius: f32, mut f: impl FnMut(&Photon, f32)) {
        within(&self.photons, p, radius * radius, &mut f);
    }

    /// The `k` photons nearest to `p` within `max_radius`, into `out` (cleared first).
    pub fn k_nearest(&self, p: Vec3, k: usize, max_radius: f32, out: &mut NearestPhotons) {
        out.heap.clear();
        out.k = k;
        out.radius_squared = max_radius * max_radius;
        if k > 0 {
            nearest(&self.photons, 0, p, out);
        }
    }
}

/// The result of a k-nearest query, reused between queries (it keeps its allocation).
#[derive(Clone, Debug, Default)]
pub struct NearestPhotons {
    heap: BinaryHeap<Candidate>,
    k: usize,
    /// The search radius²: the maximum until k photons are found, then the k-th distance².
    radius_squared: f32,
}

impl NearestPhotons {
    pub fn len(&self) -> usize {
        self.heap.len()
    }

    pub fn is_empty(&self) -> bool {
        self.heap.is_empty()
    }

    /// (squared distance, photon index) of each photon found, in no particular order.
    pub fn iter(&self) -> impl Iterator<Item = (f32, u32)> + '_ {
        self.heap.iter().map(|c| (c.distance_squared, c.index))
    }

    /// The squared distance of the farthest photon found (0 if none).
    pub fn max_distance_squared(&self) -> f32 {
        self.heap.peek().map_or(0.0, |c| c.distance_squared)
    }
}

#[derive(Clone, Copy, Debug)]
struct Candidate {
    distance_squared: f32,
    index: u32,
}

impl PartialEq for Candidate {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Candidate {}
impl PartialOrd for Candidate {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Candidate {
    /// By distance, then index: a total order, so ties resolve the same way every time.
    fn cmp(&self, other: &Self) -> Ordering {
        self.distance_squared.total_cmp(&other.distance_squared).then(self.index.cmp(&other.index))
    }
}

fn build_range(photons: &mut [Photon]) {
    if photons.len() <= 1 {
        return;
    }
    let bounds = Aabb::from_points(photons.iter().map(|p| p.position));
    let extent = bounds.extent();
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    let middle = photons.len() / 2;
    photons.select_nth_unstable_by(middle, |a, b| a.position[axis].total_cmp(&b.position[axis]));
    photons[middle].axis = axis as u8;
    let (below, rest) = photons.split_at_mut(middle);
    let above = &mut rest[1..];
    if below.len() >= PARALLEL_BUILD_MIN {
        rayon::join(|| build_range(below), || build_range(above));
    } else {
        build_range(below);
        build_range(above);
    }
}

/// The node of a non-empty subtree, the query's signed distance to its splitting plane, and
/// the index ranges of the subtrees on the query's side (near) and the other (far).
fn split(photons: &[Photon], p: Vec3) -> (usize, f32, Range<usize>, Range<usize>) {
    let middle = photons.len() / 2;
    let node = &photons[middle];
    let axis = node.axis as usize;
    let d = p[axis] - node.position[axis];
    let (below, above) = (0..middle, middle + 1..photons.len());
    if d < 0.0 {
        (middle, d, below, above)
    } else {
        (middle, d, above, below)
    }
}

fn within(photons: &[Photon], p: Vec3, radius_squared: f32, f: &mut impl FnMut(&Photon, f32)) {
    if photons.is_empty() {
        return;
    }
    let (middle, d, near, far) = split(photons, p);
    within(&photons[near], p, radius_squared, f);
    let node = &photons[middle];
    let distance_squared = (node.position - p).length_squared();
    if distance_squared <= radius_squared {
        f(node, distance_squared);
    }
    if d * d <= radius_squared {
        within(&photons[far], p, radius_squared, f);
    }
}

/// `offset` is the index of `photons[0]` in the whole map.
fn nearest(photons: &[Photon], offset: usize, p: Vec3, out: &mut NearestPhotons) {
    if photons.is_empty() {
        return;
    }
    let (middle, d, near, far) = split(photons, p);
    let node = &photons[middle];
    nearest(&photons[near.clone()], offset + near.start, p, out);
    let distance_squared = (node.position - p).length_squared();
    if distance_squared <= out.radius_squared {
        out.heap.push(Candidate { distance_squared, index: (offset + middle) as u32 });
        if out.heap.len() > out.k {
            out.heap.pop();
        }
        if out.heap.len() == out.k {
            out.radius_squared = out.heap.peek().expect("k > 0 photons").distance_squared;
        }
    }
    if d * d <= out.radius_squared {
        nearest(&photons[far.clone()], offset + far.start, p, out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;
    use crate::Rgb;

    fn random_photons(n: usize, rng: &mut Rng) -> Vec<Photon> {
        (0..n)
            .map(|i| {
                let mut p = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32() * 0.3);
                if i % 7 == 0 {
                    p.x = 0.5; // coincident coordinates on the split axis
                }
                if i % 50 == 0 {
                    p = Vec3::splat(0.25); // coincident photons
                }
                Photon::new(p, Vec3::Z, Vec3::Z, Rgb::splat(i as f32))
            })
            .collect()
    }

    #[test]
    fn radius_and_k_nearest_queries_equal_brute_force() {
        let mut rng = Rng::new(5, 1);
        for n in [0usize, 1, 2, 3, 17, 1000, 40_000] {
            let photons = random_photons(n, &mut rng);
            let map = PhotonMap::build(photons.clone(), n as u64);
            let mut out = NearestPhotons::default();
            for _ in 0..50 {
                let q = Vec3::new(rng.next_f32() * 1.2 - 0.1, rng.next_f32() * 1.2 - 0.1, rng.next_f32() * 0.4);
                let radius = 0.02 + 0.2 * rng.next_f32();
                let mut expected: Vec<u32> = photons
                    .iter()
                    .filter(|p| (p.position - q).length_squared() <= radius * radius)
                    .map(|p| p.power.x as u32)
                    .collect();
                let mut found = Vec::new();
                map.for_each_within(q, radius, |p, d2| {
                    assert_eq!(d2, (p.position - q).length_squared());
                    found.push(p.power.x as u32)
                });
                expected.sort_unstable();
                found.sort_unstable();
                assert_eq!(found, expected, "radius query, n = {n}");

                let k = 1 + (rng.next_u32() % 30) as usize;
                map.k_nearest(q, k, radius, &mut out);
                let mut by_distance: Vec<f32> = photons
                    .iter()
                    .map(|p| (p.position - q).length_squared())
                    .filter(|&d2| d2 <= radius * radius)
                    .collect();
                by_distance.sort_by(f32::total_cmp);
                by_distance.truncate(k);
                let mut got: Vec<f32> = out.iter().map(|(d2, _)| d2).collect();
                got.sort_by(f32::total_cmp);
                assert_eq!(got, by_distance, "k = {k}, n = {n}");
                for (d2, i) in out.iter() {
                    assert_eq!((map.photon(i).position - q).length_squared(), d2);
                }
            }
        }
    }
}
