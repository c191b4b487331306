//! BVH leaf blocks: eight primitives per block, their triangles stored lane by lane (SoA) so
//! that one watertight test (Woop, Benthin, Wald 2013) runs on all eight at once in 256-bit
//! SIMD (AVX; `wide`'s `f32x8`, two SSE halves where AVX is not compiled in).
//!
//! Lane by lane the arithmetic is the scalar test's (`shapes::WatertightRay::intersect`),
//! operation for operation and in the same order, so both give bit-identical hits; only exact
//! zeros of the edge functions leave the SIMD path, for the same f64 recomputation.

use glam::Vec3;
use wide::{f32x8, CmpEq, CmpGt, CmpLt, CmpNe};

use crate::geometry::{gamma, Ray};
use crate::shapes::{plane_distance, PrimHit, WatertightRay};

pub const LANES: usize = 8;

/// Eight lanes of f32.
type Lanes = f32x8;

/// Lane id of a primitive that is not a plain triangle (sphere, box, polygon, instance, a
/// transformed triangle): the low bits index the caller's table of such primitives, and the
/// lane's vertices are NaN so the SIMD test never reports it.
pub const GENERIC: u32 = 1 << 31;
/// Lane id of an unused lane (NaN vertices). Not flagged `GENERIC`, so that OR-ing a block's
/// ids tells at once whether any lane needs the scalar path.
pub const EMPTY: u32 = GENERIC - 1;

/// 320 bytes: eight triangles' vertices by vertex, axis and lane, and the eight lane ids.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub struct Triangle8 {
    /// `vertices[k][axis]`: vertex `k` of the eight triangles on that axis.
    pub vertices: [[Lanes; 3]; 3],
    /// Per lane: a triangle's id (below `EMPTY`), `GENERIC | index`, or `EMPTY`.
    pub ids: [u32; LANES],
}

impl Triangle8 {
    pub fn empty() -> Self {
        Self { vertices: [[Lanes::splat(f32::NAN); 3]; 3], ids: [EMPTY; LANES] }
    }

    /// Puts a triangle into `lane`. Triangles take the first lanes of a block (see
    /// `has_triangles`).
    pub fn set_triangle(&mut self, lane: usize, id: u32, [a, b, c]: [Vec3; 3]) {
        debug_assert!(id < EMPTY);
        debug_assert!(self.ids[..lane].iter().all(|&id| id < EMPTY), "triangles come first in a block");
        for (k, v) in [a, b, c].into_iter().enumerate() {
            for axis in 0..3 {
                self.vertices[k][axis].as_array_mut()[lane] = v[axis];
            }
        }
        self.ids[lane] = id;
    }

    /// Puts a primitive that is tested by the scalar path into `lane`.
    pub fn set_generic(&mut self, lane: usize, index: u32) {
        debug_assert!(index < EMPTY);
        self.ids[lane] = GENERIC | index;
    }

    /// Whether some lane holds a triangle (triangles come first, so lane 0 does): a block of
    /// other primitives only skips the SIMD test.
    #[inline(always)]
    pub fn has_triangles(&self) -> bool {
        self.ids[0] < EMPTY
    }

    /// Whether some lane holds a generic primitive.
    #[inline(always)]
    pub fn has_generic(&self) -> bool {
        self.ids.iter().fold(0, |all, id| all | id) & GENERIC != 0
    }

    /// The filled lanes and their ids (empty lanes come last).
    #[inline(always)]
    pub fn lanes(&self) -> impl Iterator<Item = (usize, u32)> + '_ {
        self.ids.iter().copied().enumerate().take_while(|&(_, id)| id != EMPTY)
    }

    /// The vertices of the triangle in `lane`.
    pub fn triangle(&self, lane: usize) -> [Vec3; 3] {
        [0, 1, 2].map(|k| self.vertex(lane, k))
    }

    /// Vertex `k` of the triangle in `lane`.
    #[inline(always)]
    pub fn vertex(&self, lane: usize, k: usize) -> Vec3 {
        let v = &self.vertices[k];
        Vec3::new(v[0].as_array_ref()[lane], v[1].as_array_ref()[lane], v[2].as_array_ref()[lane])
    }
}

/// The results of one block test: lanes hit (bit k for lane k), and per lane the distance and
/// the barycentric weights of the second and third vertex.
#[derive(Clone, Copy, Debug)]
pub struct Hits8 {
    pub mask: u32,
    pub t: [f32; LANES],
    pub u: Lanes,
    pub v: Lanes,
}

impl Hits8 {
    /// No lane hit.
    const NONE: Hits8 = Hits8 { mask: 0, t: [0.0; LANES], u: Lanes::ZERO, v: Lanes::ZERO };

    /// The nearest hit lane; of equal distances the first lane, as a sequential test keeps the
    /// first of equal hits.
    #[inline(always)]
    pub fn nearest(&self) -> Option<(usize, PrimHit)> {
        if self.mask == 0 {
            return None;
        }
        let t = &self.t;
        let mut best = self.mask.trailing_zeros() as usize;
        let mut rest = self.mask & (self.mask - 1);
        while rest != 0 {
            let k = rest.trailing_zeros() as usize;
            if t[k] < t[best] {
                best = k;
            }
            rest &= rest - 1;
        }
        Some((best, PrimHit { t: t[best], u: self.u.as_array_ref()[best], v: self.v.as_array_ref()[best], inner: 0 }))
    }
}

/// A ray prepared for the eight-lane watertight test.
pub struct WatertightRay8 {
    axes: [usize; 3],
    /// The ray origin on the permuted axes (kx, ky, kz).
    origin: [Lanes; 3],
    /// The shear (dx/dz, dy/dz, 1/dz).
    shear: [Lanes; 3],
    /// The ray itself, for the distance of each hit (`plane_distance`).
    ray: Ray,
}

impl WatertightRay8 {
    /// For `ray`, through its scalar set-up.
    #[inline]
    pub fn for_ray(ray: &Ray) -> Self {
        Self::new(ray, &WatertightRay::new(ray))
    }

    pub fn new(ray: &Ray, scalar: &WatertightRay) -> Self {
        let axes = scalar.axes;
        let origin = ray.origin.to_array();
        Self {
            axes,
            origin: axes.map(|a| Lanes::splat(origin[a])),
            shear: [0, 1, 2].map(|i| Lanes::splat(scalar.shear[i])),
            ray: *ray,
        }
    }

    /// Tests the eight lanes of `block` within the open interval (t_min, t_max).
    #[inline(always)]
    pub fn intersect(&self, block: &Triangle8, t_min: f32, t_max: f32) -> Hits8 {
        let [kx, ky, kz] = self.axes;
        let [ox, oy, oz] = self.origin;
        let [sx, sy, sz] = self.shear;
        let v = &block.vertices;
        // Vertices relative to the origin on the permuted axes, then sheared.
        let relative = |k: usize| (v[k][kx] - ox, v[k][ky] - oy, v[k][kz] - oz);
        let (a_x, a_y, a_z) = relative(0);
        let (b_x, b_y, b_z) = relative(1);
        let (c_x, c_y, c_z) = relative(2);
        let (ax, ay) = (a_x - sx * a_z, a_y - sy * a_z);
        let (bx, by) = (b_x - sx * b_z, b_y - sy * b_z);
        let (cx, cy) = (c_x - sx * c_z, c_y - sy * c_z);
        let mut u = cx * by - cy * bx;
        let mut v_ = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        let zero = Lanes::ZERO;
        let exact_zero = u.cmp_eq(zero) | v_.cmp_eq(zero) | w.cmp_eq(zero);
        // Some edge function negative and another positive: the ray passes outside.
        let outside = if exact_zero.any() {
            (u, v_, w) = recompute_in_f64(exact_zero.move_mask() as u32, [ax, ay, bx, by, cx, cy], (u, v_, w));
            let negative = u.cmp_lt(zero) | v_.cmp_lt(zero) | w.cmp_lt(zero);
            let positive = u.cmp_gt(zero) | v_.cmp_gt(zero) | w.cmp_gt(zero);
            negative & positive
        } else {
            // No zeros: the same test is whether the three sign bits differ (the sign bit of
            // (u ^ v) | (u ^ w)); a NaN lane's answer does not matter, `det` drops it below.
            ((u ^ v_) | (u ^ w)).sign_bit()
        };
        let det = u + v_ + w;
        // `det == det` drops the NaN lanes (empty and generic ones), which `cmp_ne` keeps on
        // SSE (unordered compare) though not on AVX.
        let inside = !outside & det.cmp_ne(zero) & det.cmp_eq(det);
        if inside.none() {
            // Most blocks a ray reaches it misses: skip the distance and its error bound.
            return Hits8::NONE;
        }
        let (az, bz, cz) = (sz * a_z, sz * b_z, sz * c_z);
        let t_scaled = u * az + v_ * bz + w * cz;
        let inv_det = Lanes::ONE / det;
        let t = t_scaled * inv_det;
        let in_range = inside & t.cmp_gt(Lanes::splat(t_min)) & t.cmp_lt(Lanes::splat(t_max));
        if in_range.none() {
            // The ray's line meets a triangle behind the origin or past t_max (a wall behind a
            // ray in a room, say): skip the error bound.
            return Hits8::NONE;
        }
        // The scalar test's bound on the error of t (pbrt-v4 §6.8.4, the shear's error in
        // lengths: see `WatertightRay::intersect`), lane-wise.
        let max_z = az.abs().fast_max(bz.abs()).fast_max(cz.abs());
        let max_z_length = a_z.abs().fast_max(b_z.abs()).fast_max(c_z.abs());
        let max_x = ax.abs().fast_max(bx.abs()).fast_max(cx.abs());
        let max_y = ay.abs().fast_max(by.abs()).fast_max(cy.abs());
        let delta_z = Lanes::splat(gamma(3)) * max_z;
        let delta_x = Lanes::splat(gamma(5)) * (max_x + max_z_length);
        let delta_y = Lanes::splat(gamma(5)) * (max_y + max_z_length);
        let delta_e = Lanes::splat(2.0) * (Lanes::splat(gamma(2)) * max_x * max_y + delta_y * max_x + delta_x * max_y);
        let max_e = u.abs().fast_max(v_.abs()).fast_max(w.abs());
        let delta_t = Lanes::splat(3.0)
            * (Lanes::splat(gamma(3)) * max_e * max_z + delta_e * max_z + delta_z * max_e)
            * inv_det.abs();
        // As the scalar test: the bound only where a vertex is not ahead of the origin.
        let ahead = az.fast_min(bz).fast_min(cz).cmp_gt(zero);
        let hit = in_range & (ahead | t.cmp_gt(delta_t));
        Hits8 { mask: hit.move_mask() as u32, t: t.to_array(), u: v_ * inv_det, v: w * inv_det }
    }

    /// A hit lane at its distance from the triangle's plane, as the scalar test reports it
    /// (`plane_distance`), or None if that distance leaves (t_min, t_max), as the scalar test
    /// then drops the hit. The f64 arithmetic is for the hit a query keeps, not every lane.
    #[inline]
    pub fn refined(&self, block: &Triangle8, lane: usize, hit: PrimHit, t_min: f32, t_max: f32) -> Option<PrimHit> {
        let t = plane_distance(block.triangle(lane), &self.ray, hit.t);
        (t > t_min && t < t_max).then_some(PrimHit { t, ..hit })
    }
}

/// The edge functions of the lanes in `lanes` (a bit mask) recomputed in f64, as the scalar
/// test does when one of them is exactly zero (the ray through an edge or a vertex).
#[cold]
#[inline(never)]
fn recompute_in_f64(
    lanes: u32,
    [ax, ay, bx, by, cx, cy]: [Lanes; 6],
    (u, v, w): (Lanes, Lanes, Lanes),
) -> (Lanes, Lanes, Lanes) {
    let f = |p: f32, q: f32, r: f32, s: f32| (p as f64 * q as f64 - r as f64 * s as f64) as f32;
    let [ax, ay, bx, by, cx, cy] = [ax, ay, bx, by, cx, cy].map(Lanes::to_array);
    let (mut u, mut v, mut w) = (u.to_array(), v.to_array(), w.to_array());
    for k in 0..LANES {
        if lanes & (1 << k) != 0 {
            u[k] = f(cx[k], by[k], cy[k], bx[k]);
            v[k] = f(ax[k], cy[k], ay[k], cx[k]);
            w[k] = f(bx[k], ay[k], by[k], ax[k]);
        }
    }
    (Lanes::new(u), Lanes::new(v), Lanes::new(w))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    fn random_vec(rng: &mut Rng, scale: f32) -> Vec3 {
        Vec3::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, rng.next_f32() - 0.5) * scale
    }

    /// Every lane, its distance refined as a query's kept hit is, agrees bit for bit with the
    /// scalar watertight test, including rays through
    /// shared edges and vertices (the f64 path) and empty lanes.
    #[test]
    fn lanes_equal_the_scalar_test() {
        let mut rng = Rng::new(7, 0);
        let (mut hits, mut edge_hits) = (0, 0);
        for case in 0..20_000 {
            let mut block = Triangle8::empty();
            let mut triangles = [None; LANES];
            for (lane, slot) in triangles.iter_mut().enumerate() {
                if lane + case % 3 >= LANES {
                    continue; // empty lanes, after the triangles as the blocks keep them
                }
                // Integer-grid vertices make rays through edges and vertices common.
                let grid = |rng: &mut Rng| random_vec(rng, 8.0).round();
                let tri = if case % 3 == 0 {
                    [grid(&mut rng), grid(&mut rng), grid(&mut rng)]
                } else {
                    [random_vec(&mut rng, 2.0), random_vec(&mut rng, 2.0), random_vec(&mut rng, 2.0)]
                };
                block.set_triangle(lane, lane as u32, tri);
                *slot = Some(tri);
            }
            let origin = if case % 3 == 0 { random_vec(&mut rng, 20.0).round() } else { random_vec(&mut rng, 6.0) };
            let target = if case % 3 == 0 { random_vec(&mut rng, 8.0).round() } else { random_vec(&mut rng, 1.0) };
            let ray = Ray::new(origin, (target - origin).normalize_or(Vec3::X));
            let scalar = WatertightRay::new(&ray);
            let result = WatertightRay8::new(&ray, &scalar).intersect(&block, ray.t_min, ray.t_max);
            for (lane, tri) in triangles.iter().enumerate() {
                let expected = tri.and_then(|[a, b, c]| scalar.intersect(a, b, c, &ray));
                let prepared = WatertightRay8::new(&ray, &scalar);
                let got = (result.mask & (1 << lane) != 0)
                    .then(|| {
                        let hit = PrimHit {
                            t: result.t[lane],
                            u: result.u.as_array_ref()[lane],
                            v: result.v.as_array_ref()[lane],
                            inner: 0,
                        };
                        prepared.refined(&block, lane, hit, ray.t_min, ray.t_max)
                    })
                    .flatten();
                assert_eq!(
                    got.map(|h| (h.t.to_bits(), h.u.to_bits(), h.v.to_bits())),
                    expected.map(|h| (h.t.to_bits(), h.u.to_bits(), h.v.to_bits())),
                    "case {case} lane {lane}"
                );
                hits += usize::from(expected.is_some());
                edge_hits += usize::from(expected.is_some_and(|h| h.u == 0.0 || h.v == 0.0));
            }
        }
        assert!(hits > 5_000, "too few hits ({hits}) to mean anything");
        assert!(edge_hits > 50, "too few hits on edges ({edge_hits}) to test the f64 path");
    }

    #[test]
    fn nearest_lane_and_ties() {
        let hits = Hits8 {
            mask: 0b0100_1110,
            t: [0.5, 3.0, 2.0, 2.0, 9.0, 9.0, 2.0, 9.0],
            u: Lanes::new([0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7]),
            v: Lanes::ZERO,
        };
        let (lane, hit) = hits.nearest().unwrap();
        assert_eq!((lane, hit.t, hit.u), (2, 2.0, 0.2));
        assert!(Hits8 { mask: 0, ..hits }.nearest().is_none());
    }

    #[test]
    fn generic_and_empty_lanes() {
        let mut block = Triangle8::empty();
        assert!(!block.has_generic() && !block.has_triangles());
        block.set_triangle(0, 5, [Vec3::ZERO, Vec3::X, Vec3::Y]);
        assert!(!block.has_generic());
        block.set_generic(2, 9);
        assert!(block.has_generic() && block.has_triangles());
        assert_eq!(block.triangle(0), [Vec3::ZERO, Vec3::X, Vec3::Y]);
        // A ray straight through every lane's position hits only the triangle.
        let ray = Ray::new(Vec3::new(0.25, 0.25, 1.0), -Vec3::Z);
        let hits = WatertightRay8::for_ray(&ray).intersect(&block, ray.t_min, ray.t_max);
        assert_eq!(hits.mask, 1);
        assert_eq!(hits.t[0], 1.0);
        assert_eq!(std::mem::size_of::<Triangle8>(), 320);
    }
}
