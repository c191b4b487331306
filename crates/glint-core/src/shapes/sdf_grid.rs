//! Signed-distance grid (Mitsuba's `sdfgrid`): the surface where the trilinear interpolation
//! F of distances sampled on a regular grid over the unit cube changes sign, placed by the
//! object's transform. Sample (i, j, k) sits at (i/(nx−1), j/(ny−1), k/(nz−1)); negative is
//! inside, and the surface normal is ∇F, pointing toward positive distances.
//!
//! Each voxel whose eight corners do not all share a sign is one primitive, so the scene's
//! BVH culls voxels as it culls triangles. Within a voxel F along the ray is a cubic in t;
//! its first sign change is isolated between the roots of its derivative and then narrowed by
//! Newton's method kept in the bracket (Marmitt et al. 2004, "Fast and accurate ray-voxel intersection techniques for
//! iso-surface ray tracing"). A ray that grazes the surface without crossing it misses, as in
//! Mitsuba. The grid's faces are not a surface: a solid cut by the cube's boundary is open
//! there.
//!
//! Normals: the geometric normal is ∇F in the voxel hit (continuous in position within a
//! voxel, not across voxels). Shading normals are that (`analytic`) or, by default, `smooth`:
//! the unit gradients of the eight voxels around the nearest grid vertex, blended trilinearly,
//! which is continuous across voxels (Mitsuba's blend). uv is (0, 0).

use glam::{Vec2, Vec3};

use super::{PrimHit, SurfaceGeometry};
use crate::geometry::{gamma, Aabb, Ray};
use crate::Named;

/// Which normal an SDF grid shades with.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SdfNormals {
    /// The gradient of the voxel hit: facets show at voxel faces.
    Analytic,
    /// The voxels' unit gradients blended across voxel faces.
    #[default]
    Smooth,
}

impl Named for SdfNormals {
    const ALL: &'static [Self] = &[SdfNormals::Analytic, SdfNormals::Smooth];

    fn name(self) -> &'static str {
        match self {
            SdfNormals::Analytic => "analytic",
            SdfNormals::Smooth => "smooth",
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct SdfGrid {
    /// Samples along x, y and z (each at least 2).
    size: [usize; 3],
    /// The samples, x fastest, then y, then z.
    values: Vec<f32>,
    /// The voxels the surface may pass through (index x + y·(nx−1) + z·(nx−1)(ny−1)): one
    /// primitive each.
    voxels: Vec<u32>,
    normals: SdfNormals,
}

impl SdfGrid {
    /// The grid of `size` samples (x fastest), or what is wrong with it.
    pub fn new(size: [usize; 3], values: Vec<f32>, normals: SdfNormals) -> Result<Self, String> {
        if size.iter().any(|&n| n < 2) {
            return Err(format!("an SDF grid needs at least 2 samples along each axis, not {size:?}"));
        }
        if values.len() != size[0] * size[1] * size[2] {
            return Err(format!("a {size:?} grid holds {} values, not {}", size[0] * size[1] * size[2], values.len()));
        }
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(format!("value {i} of the SDF grid is not a finite number"));
        }
        if (values.len() as u64) >= u32::MAX as u64 {
            return Err("an SDF grid holds fewer than 2³² values".into());
        }
        let mut grid = SdfGrid { size, values, voxels: Vec::new(), normals };
        let [cx, cy, cz] = grid.cells();
        for z in 0..cz {
            for y in 0..cy {
                for x in 0..cx {
                    let c = grid.corners([x, y, z]);
                    // A voxel whose corners all share a strict sign holds no surface.
                    if !(c.iter().all(|&v| v > 0.0) || c.iter().all(|&v| v < 0.0)) {
                        grid.voxels.push((x + cx * (y + cy * z)) as u32);
                    }
                }
            }
        }
        if grid.voxels.is_empty() {
            return Err("the SDF grid has no surface: no voxel's corners change sign".into());
        }
        Ok(grid)
    }

    pub fn normals(&self) -> SdfNormals {
        self.normals
    }

    /// Voxels along each axis.
    fn cells(&self) -> [usize; 3] {
        self.size.map(|n| n - 1)
    }

    /// Voxels per unit length along each axis.
    fn scale(&self) -> Vec3 {
        Vec3::new(self.size[0] as f32 - 1.0, self.size[1] as f32 - 1.0, self.size[2] as f32 - 1.0)
    }

    pub fn primitive_count(&self) -> u32 {
        self.voxels.len() as u32
    }

    fn voxel(&self, prim: u32) -> [usize; 3] {
        let [cx, cy, _] = self.cells();
        let i = self.voxels[prim as usize] as usize;
        [i % cx, (i / cx) % cy, i / (cx * cy)]
    }

    fn sample(&self, x: usize, y: usize, z: usize) -> f32 {
        self.values[x + self.size[0] * (y + self.size[1] * z)]
    }

    /// A voxel's corner samples, index dx + 2·dy + 4·dz.
    fn corners(&self, [x, y, z]: [usize; 3]) -> [f32; 8] {
        std::array::from_fn(|i| self.sample(x + (i & 1), y + ((i >> 1) & 1), z + (i >> 2)))
    }

    fn voxel_box(&self, v: [usize; 3]) -> Aabb {
        let scale = self.scale();
        let min = Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32);
        Aabb::new(min / scale, (min + Vec3::ONE) / scale)
    }

    pub fn bounds(&self, prim: u32) -> Aabb {
        self.voxel_box(self.voxel(prim))
    }

    /// The bounds of the whole grid: the unit cube.
    pub fn grid_bounds(&self) -> Aabb {
        Aabb::new(Vec3::ZERO, Vec3::ONE)
    }

    /// F at `p`, clamped to the unit cube (what lies outside reads its nearest face).
    pub fn eval(&self, p: Vec3) -> f32 {
        let s = (p.clamp(Vec3::ZERO, Vec3::ONE)) * self.scale();
        let v = self.voxel_of(s);
        let f = s - Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32);
        trilinear(&self.corners(v), f)
    }

    /// The voxel holding grid coordinates `s` (∈ [0, n−1] per axis), the last one on the far
    /// faces.
    fn voxel_of(&self, s: Vec3) -> [usize; 3] {
        let cells = self.cells();
        std::array::from_fn(|a| (s[a].max(0.0) as usize).min(cells[a] - 1))
    }

    /// The first sign change of F along `ray` within voxel `prim` and `(t_min, t_max)`.
    ///
    /// F at the voxel's entry and exit is read on the face the ray crosses, that coordinate
    /// set exactly to 0 or 1: the neighbour across the face computes the same point (the
    /// planes and their t are shared bit for bit) and, with lerps exact at 0 and 1, the same
    /// value. Read off each voxel's own cubic instead, the two could differ in sign where the
    /// surface meets the face, and a ray would slip between them.
    pub fn intersect(&self, prim: u32, ray: &Ray) -> Option<PrimHit> {
        let v = self.voxel(prim);
        let bounds = self.voxel_box(v);
        let inv = ray.direction.recip();
        let (to_min, to_max) = ((bounds.min - ray.origin) * inv, (bounds.max - ray.origin) * inv);
        let undefined = to_min.is_nan_mask() | to_max.is_nan_mask();
        let near = Vec3::select(undefined, Vec3::NEG_INFINITY, to_min.min(to_max));
        let far = Vec3::select(undefined, Vec3::INFINITY, to_min.max(to_max));
        let (entry_axis, exit_axis) = (arg_max(near), arg_min(far));
        let (mut t0, mut t1) = (near[entry_axis], far[exit_axis]);
        // The face crossed on entry and exit (none where the ray's own ends cut the voxel).
        let (mut entry_face, mut exit_face) = (Some(entry_axis), Some(exit_axis));
        if t0 <= ray.t_min {
            (t0, entry_face) = (ray.t_min, None);
        }
        if t1 >= ray.t_max {
            (t1, exit_face) = (ray.t_max, None);
        }
        if t0.is_nan() || t1.is_nan() || t0 > t1 {
            return None;
        }
        let scale = self.scale();
        let corner = Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32);
        let corners = self.corners(v);
        let local = |t: f32, face: Option<usize>, side_of: fn(f32) -> bool| {
            let mut q = ((ray.origin + t * ray.direction) * scale - corner).clamp(Vec3::ZERO, Vec3::ONE);
            if let Some(axis) = face {
                // The face the ray crosses: 1 on the voxel's far side along the axis.
                q[axis] = if side_of(ray.direction[axis]) { 1.0 } else { 0.0 };
            }
            q
        };
        let a = local(t0, entry_face, |d| d < 0.0);
        let exit = local(t1, exit_face, |d| d > 0.0);
        // Voxel coordinates along the ray from its entry: q(s) = a + s·b, s = t − t0.
        let cubic = along_ray(&corners, a, ray.direction * scale);
        let mut ends = (trilinear(&corners, a), trilinear(&corners, exit));
        if ends.0 == 0.0 && entry_face.is_none() {
            // The ray starts on the surface (t_min excludes that crossing): the sign just
            // after it decides the next.
            ends.0 = cubic_at(&cubic, (t1 - t0) * 1e-6);
        }
        let s = first_sign_change(&cubic, t1 - t0, ends)?;
        let t = t0 + s;
        (t > ray.t_min && t < ray.t_max).then_some(PrimHit::at(t))
    }

    /// ∇F in voxel `v` at grid coordinates `s` (object space: per unit length).
    fn gradient(&self, v: [usize; 3], s: Vec3) -> Vec3 {
        let c = self.corners(v);
        let f = (s - Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32)).clamp(Vec3::ZERO, Vec3::ONE);
        trilinear_gradient(&c, f) * self.scale()
    }

    /// Mitsuba's smooth normal at grid coordinates `s`: the unit gradients of the eight voxels
    /// around the nearest grid vertex (each read at `s`'s other coordinates on its two faces
    /// along an axis, clamped to the grid), blended trilinearly; voxels before the grid's start
    /// count as zero and the blend gives the inner ones full weight there.
    ///
    /// A voxel's gradient along an axis depends on its index along that axis only (F is one
    /// continuous function, read on the voxel's two faces at `s`'s other coordinates), so the
    /// eight gradients come from F on three planes per axis: nine reads, not forty-eight.
    fn smooth_normal(&self, s: Vec3) -> Vec3 {
        let rounded = s.round();
        let first = rounded - Vec3::ONE;
        let mut w = s - rounded + Vec3::splat(0.5);
        for a in 0..3 {
            if first[a] < 0.0 {
                w[a] = 1.0;
            }
        }
        let scale = self.scale();
        // slope[a][i]: ∂F/∂a in the voxel first[a] + i along a.
        let slope: [[f32; 2]; 3] = std::array::from_fn(|a| {
            let plane = |k: f32| {
                let mut q = s;
                q[a] = k;
                self.eval(q / scale)
            };
            let f = [plane(first[a]), plane(first[a] + 1.0), plane(first[a] + 2.0)];
            [(f[1] - f[0]) * scale[a], (f[2] - f[1]) * scale[a]]
        });
        let mut blend = Vec3::ZERO;
        for i in 0..8 {
            let offset = [i & 1, (i >> 1) & 1, i >> 2];
            if (0..3).any(|a| first[a] + (offset[a] as f32) < 0.0) {
                continue;
            }
            let g = Vec3::new(slope[0][offset[0]], slope[1][offset[1]], slope[2][offset[2]]);
            let weight: f32 = (0..3).map(|a| if offset[a] == 0 { 1.0 - w[a] } else { w[a] }).product();
            blend += weight * g.normalize_or_zero();
        }
        blend
    }

    pub fn surface(&self, prim: u32, ray: &Ray, hit: &PrimHit) -> SurfaceGeometry {
        let v = self.voxel(prim);
        let box_ = self.voxel_box(v);
        let point = ray.at(hit.t).clamp(box_.min, box_.max);
        let s = point * self.scale();
        let gradient = self.gradient(v, s);
        let geometric_normal = gradient.normalize_or(Vec3::Z);
        let shading_normal = match self.normals {
            SdfNormals::Analytic => geometric_normal,
            SdfNormals::Smooth => {
                let n = self.smooth_normal(s).normalize_or_zero();
                // Kept on the surface's side: a blend can tip past it at a sharp crease.
                if n.dot(geometric_normal) > 0.0 {
                    n
                } else {
                    geometric_normal
                }
            }
        };
        // The root is as good as F's rounding: |δF| / |∇F| along the normal, where δF is a
        // few roundings of the corners' sizes; the point adds those of O + tD.
        let corners = self.corners(v);
        let size: f32 = corners.iter().map(|c| c.abs()).sum();
        let along = gamma(8) * size / gradient.length().max(f32::MIN_POSITIVE);
        // (At most a voxel: where the gradient vanishes, the root says nothing finer.)
        let voxel = 1.0 / self.scale().max_element();
        let error = gamma(4) * (ray.origin.abs() + (hit.t * ray.direction).abs()) + Vec3::splat(along.min(voxel));
        SurfaceGeometry { point, geometric_normal, shading_normal, uv: Vec2::ZERO, error }
    }
}

/// Trilinear interpolation of corners (index dx + 2·dy + 4·dz) at `f` ∈ [0, 1]³.
fn trilinear(c: &[f32; 8], f: Vec3) -> f32 {
    // (1 − t)·a + t·b: exactly a at t = 0 and b at t = 1, so voxels sharing a face agree on it.
    let lerp = |a: f32, b: f32, t: f32| (1.0 - t) * a + t * b;
    let x: [f32; 4] = std::array::from_fn(|i| lerp(c[2 * i], c[2 * i + 1], f.x));
    let y = [lerp(x[0], x[1], f.y), lerp(x[2], x[3], f.y)];
    lerp(y[0], y[1], f.z)
}

/// The gradient of the trilinear interpolant at `f`, per unit of voxel.
fn trilinear_gradient(c: &[f32; 8], f: Vec3) -> Vec3 {
    // Along each axis: the difference of the two faces' bilinear values at f's other two
    // coordinates.
    let face = |axis: usize, side: usize| {
        let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
        let corner = |da: usize, db: usize| c[(side << axis) | (da << a) | (db << b)];
        let lerp = |p: f32, q: f32, t: f32| p + (q - p) * t;
        lerp(lerp(corner(0, 0), corner(1, 0), f[a]), lerp(corner(0, 1), corner(1, 1), f[a]), f[b])
    };
    Vec3::new(face(0, 1) - face(0, 0), face(1, 1) - face(1, 0), face(2, 1) - face(2, 0))
}

/// The coefficients (constant first) of the cubic F(a + s·b) within a voxel with corners `c`,
/// built by the same three lerps as `trilinear`, on polynomials in s.
fn along_ray(c: &[f32; 8], a: Vec3, b: Vec3) -> [f32; 4] {
    // x: four edges, each linear in s.
    let x: [[f32; 2]; 4] = std::array::from_fn(|i| {
        let (c0, d) = (c[2 * i], c[2 * i + 1] - c[2 * i]);
        [c0 + d * a.x, d * b.x]
    });
    // y: two faces, each quadratic: e0 + (e1 − e0)(a.y + b.y s).
    let y: [[f32; 3]; 2] = std::array::from_fn(|k| {
        let (e0, e1) = (x[2 * k], x[2 * k + 1]);
        let d = [e1[0] - e0[0], e1[1] - e0[1]];
        [e0[0] + d[0] * a.y, e0[1] + d[0] * b.y + d[1] * a.y, d[1] * b.y]
    });
    // z: one cubic.
    let (f0, f1) = (y[0], y[1]);
    let d = [f1[0] - f0[0], f1[1] - f0[1], f1[2] - f0[2]];
    [f0[0] + d[0] * a.z, f0[1] + d[0] * b.z + d[1] * a.z, f0[2] + d[1] * b.z + d[2] * a.z, d[2] * b.z]
}

fn arg_max(v: Vec3) -> usize {
    if v.x >= v.y && v.x >= v.z {
        0
    } else if v.y >= v.z {
        1
    } else {
        2
    }
}

fn arg_min(v: Vec3) -> usize {
    arg_max(-v)
}

fn cubic_at(c: &[f32; 4], s: f32) -> f32 {
    ((c[3] * s + c[2]) * s + c[1]) * s + c[0]
}

/// The first s ∈ [0, length] where the cubic changes sign (or is zero), if any: the roots of
/// its derivative split [0, length] into pieces where it is monotonic, and the first piece
/// whose ends differ in sign holds the root, narrowed by `refine`. `ends` are
/// F at s = 0 and s = `length` as read directly, which decide the signs there.
fn first_sign_change(c: &[f32; 4], length: f32, ends_f: (f32, f32)) -> Option<f32> {
    let mut ends = [0.0, length, length, length];
    let mut count = 1;
    // F'(s) = c1 + 2 c2 s + 3 c3 s².
    let critical = if c[3] != 0.0 {
        super::solve_quadratic(3.0 * c[3], c[2], c[1]).map(|(r0, r1)| [r0, r1])
    } else if c[2] != 0.0 {
        let r = -c[1] / (2.0 * c[2]);
        Some([r, r])
    } else {
        None
    };
    if let Some(roots) = critical {
        for r in roots {
            if r > ends[count - 1] && r < length {
                ends[count] = r;
                count += 1;
            }
        }
    }
    ends[count] = length;
    let mut near = 0.0;
    let mut f_near = ends_f.0;
    for (i, &far) in ends[1..=count].iter().enumerate() {
        let f_far = if i + 1 == count { ends_f.1 } else { cubic_at(c, far) };
        if f_near == 0.0 {
            return Some(near);
        }
        if f_near * f_far <= 0.0 {
            return Some(refine(c, near, far, f_near));
        }
        (near, f_near) = (far, f_far);
    }
    None
}

/// The sign change of the cubic in [lo, hi] (F(lo) = `f_lo` ≠ 0 and F(hi) of the other sign
/// or zero, F monotonic between): Newton's steps, kept inside the shrinking bracket by
/// bisection where a step would leave it, until a step moves less than 2⁻²² of the bracket
/// it started from (a few steps: the cubic is smooth and monotonic there).
fn refine(c: &[f32; 4], mut lo: f32, mut hi: f32, f_lo: f32) -> f32 {
    let tolerance = (hi - lo) * 2f32.powi(-22);
    let mut s = 0.5 * (lo + hi);
    for _ in 0..64 {
        let f = cubic_at(c, s);
        if f == 0.0 {
            return s;
        }
        if (f > 0.0) == (f_lo > 0.0) {
            lo = s;
        } else {
            hi = s;
        }
        let slope = (3.0 * c[3] * s + 2.0 * c[2]) * s + c[1];
        let mut next = s - f / slope;
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        if (next - s).abs() <= tolerance || next <= lo || next >= hi {
            return next;
        }
        s = next;
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::test_util::TestRng;

    /// A grid of `n`³ samples of `f` over the unit cube.
    fn sampled(n: usize, normals: SdfNormals, f: impl Fn(Vec3) -> f32) -> SdfGrid {
        sampled_sized([n; 3], normals, f)
    }

    /// A grid of `size` samples of `f` over the unit cube.
    fn sampled_sized(size: [usize; 3], normals: SdfNormals, f: impl Fn(Vec3) -> f32) -> SdfGrid {
        let mut values = Vec::with_capacity(size.iter().product());
        let step = Vec3::new(size[0] as f32 - 1.0, size[1] as f32 - 1.0, size[2] as f32 - 1.0);
        for z in 0..size[2] {
            for y in 0..size[1] {
                for x in 0..size[0] {
                    values.push(f(Vec3::new(x as f32, y as f32, z as f32) / step));
                }
            }
        }
        SdfGrid::new(size, values, normals).unwrap()
    }

    fn sphere_grid(n: usize, normals: SdfNormals) -> SdfGrid {
        sampled(n, normals, |p| (p - Vec3::splat(0.5)).length() - 0.3)
    }

    /// The nearest hit over all voxels, as the BVH would find it.
    fn closest(grid: &SdfGrid, ray: &Ray) -> Option<(u32, PrimHit)> {
        (0..grid.primitive_count())
            .filter_map(|p| grid.intersect(p, ray).map(|h| (p, h)))
            .min_by(|a, b| a.1.t.total_cmp(&b.1.t))
    }

    /// The first sign change of F along the ray by fine marching: the independent check.
    fn marched(grid: &SdfGrid, ray: &Ray, t_end: f32) -> Option<f32> {
        let steps = 200_000;
        let mut previous = grid.eval(ray.at(ray.t_min.max(0.0)));
        for i in 1..=steps {
            let t = ray.t_min.max(0.0) + (t_end - ray.t_min.max(0.0)) * i as f32 / steps as f32;
            let p = ray.at(t);
            if p.cmplt(Vec3::ZERO).any() || p.cmpgt(Vec3::ONE).any() {
                previous = f32::NAN;
                continue;
            }
            let f = grid.eval(p);
            if previous.is_finite() && (f > 0.0) != (previous > 0.0) {
                return Some(t);
            }
            previous = f;
        }
        None
    }

    #[test]
    fn the_cubic_along_a_ray_is_the_trilinear_interpolant() {
        let mut rng = TestRng(3);
        for _ in 0..100 {
            let c: [f32; 8] = std::array::from_fn(|_| rng.range(-1.0, 1.0));
            let (a, b) = (rng.vec3(0.0, 1.0), rng.vec3(-1.0, 1.0));
            let cubic = along_ray(&c, a, b);
            for s in [0.0, 0.1, 0.37, 0.5] {
                let direct = trilinear(&c, a + s * b);
                assert!((cubic_at(&cubic, s) - direct).abs() < 1e-5, "{} {direct}", cubic_at(&cubic, s));
            }
        }
    }

    #[test]
    fn the_gradient_is_the_interpolants_derivative() {
        let mut rng = TestRng(4);
        for _ in 0..100 {
            let c: [f32; 8] = std::array::from_fn(|_| rng.range(-1.0, 1.0));
            let f = rng.vec3(0.1, 0.9);
            let h = 1e-3;
            let numeric = Vec3::new(
                trilinear(&c, f + Vec3::X * h) - trilinear(&c, f - Vec3::X * h),
                trilinear(&c, f + Vec3::Y * h) - trilinear(&c, f - Vec3::Y * h),
                trilinear(&c, f + Vec3::Z * h) - trilinear(&c, f - Vec3::Z * h),
            ) / (2.0 * h);
            assert!((trilinear_gradient(&c, f) - numeric).length() < 1e-3);
        }
    }

    #[test]
    fn the_first_sign_change_is_found_even_with_three_roots() {
        // (s − 0.2)(s − 0.5)(s − 0.8): the first root, not a later one.
        let ends = |c: &[f32; 4], length: f32| (cubic_at(c, 0.0), cubic_at(c, length));
        let c = [-0.08, 0.66, -1.5, 1.0];
        assert!((first_sign_change(&c, 1.0, ends(&c, 1.0)).unwrap() - 0.2).abs() < 1e-6);
        // Past the first root: the second.
        let shifted = [cubic_at(&c, 0.3), 3.0 * 0.09 - 3.0 * 0.3 + 0.66, 3.0 * 0.3 - 1.5, 1.0];
        assert!((first_sign_change(&shifted, 0.7, ends(&shifted, 0.7)).unwrap() - 0.2).abs() < 1e-5);
        // A double root that does not cross: (s − 0.5)² + 0.01 never changes sign.
        let never = [0.26, -1.0, 1.0, 0.0];
        assert_eq!(first_sign_change(&never, 1.0, ends(&never, 1.0)), None);
        // Two close crossings either side of the minimum that splits them: (s − 0.49)(s − 0.51).
        let close = [0.49 * 0.51, -1.0, 1.0, 0.0];
        assert!((first_sign_change(&close, 1.0, ends(&close, 1.0)).unwrap() - 0.49).abs() < 1e-6);
    }

    /// On a grid whose sides differ (9 × 11 × 7), so that a voxel decoded along the wrong axis
    /// shows.
    #[test]
    fn hits_agree_with_marching_the_interpolant() {
        let grid = sampled_sized([9, 11, 7], SdfNormals::Analytic, |p| {
            // A torus about z: major radius 0.28, minor 0.1, centred in the cube.
            let q = p - Vec3::splat(0.5);
            Vec2::new(Vec2::new(q.x, q.y).length() - 0.28, q.z).length() - 0.1
        });
        let mut rng = TestRng(11);
        let mut hits = 0;
        for _ in 0..300 {
            let origin = Vec3::splat(0.5) + 1.5 * rng.unit_vector();
            let target = rng.vec3(0.2, 0.8);
            let ray = Ray::new(origin, target - origin);
            let found = closest(&grid, &ray).map(|(_, h)| h.t);
            let expected = marched(&grid, &ray, 2.0);
            match (found, expected) {
                (Some(t), Some(m)) => {
                    hits += 1;
                    assert!((t - m).abs() < 2e-5 * (1.0 + t), "{t} vs {m}");
                    assert!(grid.eval(ray.at(t)).abs() < 1e-5, "F = {}", grid.eval(ray.at(t)));
                }
                (None, None) => {}
                other => panic!("{other:?} for {ray:?}"),
            }
        }
        assert!(hits > 50, "{hits}");
    }

    #[test]
    fn a_sampled_sphere_is_hit_near_the_sphere_and_from_inside() {
        let grid = sphere_grid(33, SdfNormals::Smooth);
        let mut rng = TestRng(5);
        for _ in 0..200 {
            let d = rng.unit_vector();
            // From outside toward the centre: the near side, within the grid's resolution.
            let outside = Ray::new(Vec3::splat(0.5) + 2.0 * d, -d);
            let (prim, hit) = closest(&grid, &outside).expect("the sphere");
            let surface = grid.surface(prim, &outside, &hit);
            assert!(((surface.point - Vec3::splat(0.5)).length() - 0.3).abs() < 2e-3);
            assert!(surface.geometric_normal.dot(d) > 0.99 && surface.shading_normal.dot(d) > 0.999);
            // From the centre: the exit wall, its normal still outward.
            let inside = Ray::new(Vec3::splat(0.5), d);
            let (prim, hit) = closest(&grid, &inside).expect("the wall from inside");
            assert!((hit.t - 0.3).abs() < 2e-3);
            assert!(grid.surface(prim, &inside, &hit).geometric_normal.dot(d) > 0.99);
        }
    }

    /// Where the surface meets a voxel face, the two voxels must agree on F's sign there, or
    /// a ray slips between them; far-off origins (a small grid scaled down in a big scene)
    /// round the two voxels' entry and exit points apart. Each ray comes from outside toward a
    /// point of the surface lying on a face, so its first hit is that point.
    #[test]
    fn rays_meeting_the_surface_on_a_voxel_face_do_not_slip_through() {
        let grid = sphere_grid(33, SdfNormals::Smooth);
        let centre = Vec3::splat(0.5);
        let mut rng = TestRng(21);
        for i in 0..1200 {
            // The face z = k/32 through the ball, and the surface on it by bisection on F
            // along a line from the ball's axis outward.
            let z = rng.range(10.0, 23.0).floor() / 32.0;
            let angle = rng.range(0.0, std::f32::consts::TAU);
            let (mut inside, mut outside) = (0.0f32, 0.45f32);
            let on_face = |r: f32| Vec3::new(0.5 + r * angle.cos(), 0.5 + r * angle.sin(), z);
            for _ in 0..60 {
                let mid = 0.5 * (inside + outside);
                if grid.eval(on_face(mid)) < 0.0 {
                    inside = mid;
                } else {
                    outside = mid;
                }
            }
            let p = on_face(outside);
            let outward = (p - centre).normalize();
            let d = -(outward + 0.4 * rng.unit_vector()).normalize();
            if d.dot(outward) > -0.5 {
                continue;
            }
            let distance = [30.0, 300.0, 1000.0][i % 3];
            let ray = Ray::new(p - distance * d, d);
            let hit = closest(&grid, &ray).map(|(_, h)| h.t);
            // Slipping through would hit the far side, some 0.2 further on, or nothing.
            assert!(hit.is_some_and(|t| (t - distance).abs() < 1e-3 * distance.max(1.0)), "{hit:?} vs {distance}");
        }
    }

    #[test]
    fn smooth_normals_are_continuous_across_voxel_faces_and_analytic_ones_are_not() {
        let smooth = sphere_grid(9, SdfNormals::Smooth);
        let analytic = sphere_grid(9, SdfNormals::Analytic);
        // Two rays a hair apart on either side of the voxel face x = 4/8 = 0.5, from +z.
        let jump = |grid: &SdfGrid| {
            let normal = |x: f32| {
                let ray = Ray::new(Vec3::new(x, 0.43, 2.0), -Vec3::Z);
                let (prim, hit) = closest(grid, &ray).unwrap();
                grid.surface(prim, &ray, &hit).shading_normal
            };
            (normal(0.5 - 1e-4) - normal(0.5 + 1e-4)).length()
        };
        assert!(jump(&smooth) < 1e-3, "{}", jump(&smooth));
        assert!(jump(&analytic) > 1e-3, "{}", jump(&analytic));
    }

    #[test]
    fn a_spawned_ray_does_not_hit_the_surface_it_leaves() {
        let grid = sphere_grid(17, SdfNormals::Smooth);
        let mut rng = TestRng(8);
        for _ in 0..500 {
            let d = rng.unit_vector();
            let ray = Ray::new(Vec3::splat(0.5) + 2.0 * d, -d);
            let (prim, hit) = closest(&grid, &ray).unwrap();
            let s = grid.surface(prim, &ray, &hit);
            // Leave outward into the hemisphere away from the sphere: nothing to hit.
            let out = (s.geometric_normal + 0.5 * rng.unit_vector()).normalize();
            if out.dot(s.geometric_normal) <= 0.5 {
                continue;
            }
            let origin = crate::geometry::offset_ray_origin(s.point, s.error, s.geometric_normal, out);
            let next = Ray::new(origin, out);
            if let Some((_, again)) = closest(&grid, &next) {
                // Only a genuine far-side hit of the convex sphere is impossible here.
                panic!("self-hit at t = {} from {origin}", again.t);
            }
        }
    }

    /// A ray starting exactly on the surface (F = 0 at its origin, which `t_min` excludes)
    /// finds the next crossing in the same voxel, not none: F = 4(x − ½)(y − ½) − ¼ is zero at
    /// (¼, ¼) and (¾, ¾) along the diagonal.
    #[test]
    fn a_ray_starting_on_the_surface_finds_the_next_crossing_in_its_voxel() {
        let corners = [0.75, -1.25, -1.25, 0.75];
        let values = [corners, corners].concat();
        let grid = SdfGrid::new([2, 2, 2], values, SdfNormals::Analytic).unwrap();
        let ray = Ray::new(Vec3::new(0.25, 0.25, 0.5), Vec3::new(1.0, 1.0, 0.0));
        assert_eq!(grid.eval(ray.origin), 0.0);
        let hit = grid.intersect(0, &ray).expect("the crossing at (¾, ¾)");
        assert!((hit.t - 0.5).abs() < 1e-6, "{}", hit.t);
    }

    /// The smooth normal as Mitsuba states it, voxel by voxel: each of the eight voxels'
    /// gradient read on its own faces (48 reads of F).
    fn smooth_normal_by_voxels(grid: &SdfGrid, s: Vec3) -> Vec3 {
        let rounded = s.round();
        let first = rounded - Vec3::ONE;
        let w = Vec3::select(first.cmplt(Vec3::ZERO), Vec3::ONE, s - rounded + Vec3::splat(0.5));
        let scale = grid.scale();
        let mut blend = Vec3::ZERO;
        for i in 0..8 {
            let offset = Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, (i >> 2) as f32);
            let voxel = first + offset;
            if voxel.cmplt(Vec3::ZERO).any() {
                continue;
            }
            let g = Vec3::from_array(std::array::from_fn(|a| {
                let (mut near, mut far) = (s, s);
                near[a] = voxel[a];
                far[a] = voxel[a] + 1.0;
                (grid.eval(far / scale) - grid.eval(near / scale)) * scale[a]
            }));
            let weight: f32 = (0..3).map(|a| if offset[a] == 0.0 { 1.0 - w[a] } else { w[a] }).product();
            blend += weight * g.normalize_or_zero();
        }
        blend
    }

    /// The nine-read smooth normal is the voxel-by-voxel one, on a grid whose sides differ
    /// (so an axis mixed up anywhere shows), at points anywhere, the grid's faces included.
    #[test]
    fn smooth_normals_read_by_planes_are_mitsubas_voxel_by_voxel_blend() {
        let size = [7, 9, 5];
        let mut values = Vec::new();
        for z in 0..size[2] {
            for y in 0..size[1] {
                for x in 0..size[0] {
                    let p = Vec3::new(x as f32 / 6.0, y as f32 / 8.0, z as f32 / 4.0);
                    values.push((p - Vec3::new(0.4, 0.55, 0.5)).length() - 0.3 + 0.05 * (7.0 * p.x).sin());
                }
            }
        }
        let grid = SdfGrid::new(size, values, SdfNormals::Smooth).unwrap();
        let mut rng = TestRng(9);
        for i in 0..2000 {
            let mut p = rng.vec3(0.0, 1.0);
            if i % 4 == 0 {
                p[i % 3] = if i % 8 == 0 { 0.0 } else { 1.0 };
            }
            let s = p * grid.scale();
            let (fast, slow) = (grid.smooth_normal(s), smooth_normal_by_voxels(&grid, s));
            assert!((fast - slow).length() <= 1e-6 * (1.0 + slow.length()), "{p}: {fast} vs {slow}");
        }
    }

    #[test]
    fn bad_grids_are_refused() {
        assert!(SdfGrid::new([1, 2, 2], vec![0.0; 4], SdfNormals::Smooth).is_err());
        assert!(SdfGrid::new([2, 2, 2], vec![1.0; 7], SdfNormals::Smooth).is_err());
        assert!(SdfGrid::new([2, 2, 2], vec![1.0; 8], SdfNormals::Smooth).unwrap_err().contains("no surface"));
        let mut nan = vec![1.0; 8];
        nan[3] = f32::NAN;
        assert!(SdfGrid::new([2, 2, 2], nan, SdfNormals::Smooth).is_err());
    }
}
