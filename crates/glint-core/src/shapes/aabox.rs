//! Axis-aligned box, by slabs (Kay & Kajiya 1986, as Haines presents it) and by Woo's method
//! (Graphics Gems I, 1990). Oriented boxes are axis-aligned boxes under a transform.
//!
//! Scene parameters: `min`, `max` (opposite corners, min < max on every axis).
//! ```toml
//! [[shapes]]
//! type = "box"
//! min = [-1, 0, -1]
//! max = [1, 2, 1]
//! material = "white"
//! transform = [{ rotate = { axis = [0, 1, 0], angle = 30 } }]
//! ```
//! - **slabs**: intersect the ray with the three pairs of parallel planes; the box is hit iff
//!   the largest entry distance is below the smallest exit distance.
//! - **Woo**: from the origin's position, pick on each axis the one candidate plane the ray can
//!   enter by; the largest candidate distance is the only possible entry; check that point
//!   lies within the other two slabs.
//!
//! Both return the entry distance, or the exit distance when the origin is inside (or the
//! entry is before `t_min`). Points on the faces count as inside: a ray that runs along a face
//! hits it.

use glam::{Vec2, Vec3};

use super::SurfaceGeometry;
use crate::geometry::{gamma, next_float_down, next_float_up, Aabb, Ray};
use crate::Named;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum BoxMethod {
    #[default]
    Slabs,
    Woo,
}

impl Named for BoxMethod {
    const ALL: &'static [Self] = &[BoxMethod::Slabs, BoxMethod::Woo];

    fn name(self) -> &'static str {
        match self {
            BoxMethod::Slabs => "slabs",
            BoxMethod::Woo => "woo",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AaBox {
    pub min: Vec3,
    pub max: Vec3,
}

impl AaBox {
    pub fn new(min: Vec3, max: Vec3) -> Self {
        Self { min, max }
    }

    pub fn bounds(&self) -> Aabb {
        Aabb::new(self.min, self.max)
    }

    /// The six faces as twelve triangles, each wound so that (b − a) × (c − a) points out of
    /// the box, for sampling the box by area as a light.
    pub fn triangles(&self) -> [[Vec3; 3]; 12] {
        let mut out = [[Vec3::ZERO; 3]; 12];
        for axis in 0..3 {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            for (side, level) in [(0, self.min[axis]), (1, self.max[axis])] {
                let corner = |cu: f32, cv: f32| {
                    let mut p = Vec3::ZERO;
                    p[axis] = level;
                    p[u] = cu;
                    p[v] = cv;
                    p
                };
                let (p00, p10) = (corner(self.min[u], self.min[v]), corner(self.max[u], self.min[v]));
                let (p11, p01) = (corner(self.max[u], self.max[v]), corner(self.min[u], self.max[v]));
                // e_u × e_v = e_axis: counter-clockwise in (u, v) faces +axis.
                let pair =
                    if side == 1 { [[p00, p10, p11], [p00, p11, p01]] } else { [[p00, p11, p10], [p00, p01, p11]] };
                out[4 * axis + 2 * side] = pair[0];
                out[4 * axis + 2 * side + 1] = pair[1];
            }
        }
        out
    }

    pub fn intersect(&self, ray: &Ray, method: BoxMethod) -> Option<f32> {
        match method {
            BoxMethod::Slabs => self.intersect_slabs(ray),
            BoxMethod::Woo => self.intersect_woo(ray),
        }
    }

    pub fn intersect_slabs(&self, ray: &Ray) -> Option<f32> {
        let (t_enter, t_exit) = self.bounds().slab_interval(ray.origin, ray.direction.recip());
        if t_enter > t_exit {
            return None;
        }
        if ray.contains(t_enter) {
            Some(t_enter)
        } else {
            ray.contains(t_exit).then_some(t_exit)
        }
    }

    pub fn intersect_woo(&self, ray: &Ray) -> Option<f32> {
        let (o, d) = (ray.origin, ray.direction);
        let mut inside = true;
        let mut candidate_t = [-1.0f32; 3];
        for axis in 0..3 {
            let plane = if o[axis] < self.min[axis] {
                self.min[axis]
            } else if o[axis] > self.max[axis] {
                self.max[axis]
            } else {
                continue; // between this axis's planes: no entry plane on it
            };
            inside = false;
            if d[axis] != 0.0 {
                candidate_t[axis] = (plane - o[axis]) / d[axis];
            }
        }
        if !inside {
            // The entry is on the plane with the largest candidate distance.
            let axis = (0..3).fold(0, |best, a| if candidate_t[a] > candidate_t[best] { a } else { best });
            let t = candidate_t[axis];
            if t < 0.0 {
                return None;
            }
            let within_other_slabs = (0..3).filter(|&a| a != axis).all(|a| {
                let coordinate = o[a] + t * d[a];
                coordinate >= self.min[a] && coordinate <= self.max[a]
            });
            if !within_other_slabs {
                return None;
            }
            if ray.contains(t) {
                return Some(t);
            }
        }
        // Origin inside, or the entry lies before t_min: the exit is the nearest far plane.
        let t_exit = (0..3)
            .filter(|&a| d[a] != 0.0)
            .map(|a| ((if d[a] > 0.0 { self.max[a] } else { self.min[a] }) - o[a]) / d[a])
            .fold(f32::INFINITY, f32::min);
        ray.contains(t_exit).then_some(t_exit)
    }

    /// The face is the one the point is nearest to, relative to the box's size; uv span
    /// [0,1]² on each face.
    ///
    /// The point is kept on the box and, on the face's other two axes, at least its rounding
    /// error inside the face's edges. A ray spawned from it then starts strictly inside every
    /// slab but the face's own, so a ray leaving a hit at an edge or corner toward the inside
    /// meets the next face at some t > 0 (a mirror box's corner then reflects it from each
    /// face in turn, as a corner reflector does). With the point on an edge, a ray leaving
    /// through the adjacent face met it at t = 0, which no ray contains: rays escaped closed
    /// mirror boxes at their edges.
    /// (∂p/∂u, ∂p/∂v) on the face of outward normal `normal`: u runs along the next axis over
    /// its size, v along the one after.
    pub fn tangents(&self, normal: Vec3) -> (Vec3, Vec3) {
        let axis = normal.abs().max_position();
        let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
        let (mut dpdu, mut dpdv) = (Vec3::ZERO, Vec3::ZERO);
        dpdu[a] = (self.max - self.min)[a];
        dpdv[b] = (self.max - self.min)[b];
        (dpdu, dpdv)
    }

    pub fn surface(&self, point: Vec3) -> SurfaceGeometry {
        self.surface_within(point, Vec3::ZERO)
    }

    /// `surface`, with the point kept `margin` further inside the face's edges: what a
    /// transform's round trip can move a spawned ray's origin by (a box placed by a transform:
    /// the ray's next query maps the world origin back into the box's space).
    pub fn surface_within(&self, point: Vec3, margin: Vec3) -> SurfaceGeometry {
        let size = (self.max - self.min).max(Vec3::splat(f32::MIN_POSITIVE));
        let mut point = point.clamp(self.min, self.max);
        let mut best = (f32::INFINITY, 0, 1.0f32);
        for axis in 0..3 {
            let to_min = (point[axis] - self.min[axis]).abs() / size[axis];
            let to_max = (point[axis] - self.max[axis]).abs() / size[axis];
            if to_min < best.0 {
                best = (to_min, axis, -1.0);
            }
            if to_max < best.0 {
                best = (to_max, axis, 1.0);
            }
        }
        let (_, axis, sign) = best;
        let mut normal = Vec3::ZERO;
        normal[axis] = sign;
        point[axis] = if sign > 0.0 { self.max[axis] } else { self.min[axis] };
        // The face coordinate is exact; the other two come from O + tD.
        let error = gamma(3) * point.abs();
        let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
        for other in [a, b] {
            point[other] = inside_by(point[other], self.min[other], self.max[other], error[other] + margin[other]);
        }
        let local = (point - self.min) / size;
        SurfaceGeometry {
            point,
            geometric_normal: normal,
            shading_normal: normal,
            uv: Vec2::new(local[a], local[b]),
            error,
        }
    }
}

/// `x` moved into [lo, hi] by at least `margin` and at least one ulp from each end (the
/// middle, if the interval is narrower than that).
fn inside_by(x: f32, lo: f32, hi: f32, margin: f32) -> f32 {
    let low = (lo + margin).max(next_float_up(lo));
    let high = (hi - margin).min(next_float_down(hi));
    if low > high {
        0.5 * (lo + hi)
    } else {
        x.clamp(low, high)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::test_util::TestRng;

    const METHODS: [BoxMethod; 2] = [BoxMethod::Slabs, BoxMethod::Woo];

    fn unit_box() -> AaBox {
        AaBox::new(Vec3::splat(-1.0), Vec3::splat(1.0))
    }

    #[test]
    fn hit_miss_behind() {
        for m in METHODS {
            let b = unit_box();
            assert_eq!(b.intersect(&Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z), m), Some(4.0));
            assert_eq!(b.intersect(&Ray::new(Vec3::new(0.0, 2.0, -5.0), Vec3::Z), m), None);
            assert_eq!(b.intersect(&Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::Z), m), None);
            let diagonal = Ray::new(Vec3::new(-3.0, -3.0, 0.0), Vec3::new(1.0, 1.0, 0.0));
            assert_eq!(b.intersect(&diagonal, m), Some(2.0), "corner edge {m:?}");
        }
    }

    #[test]
    fn origin_inside_returns_exit() {
        for m in METHODS {
            let ray = Ray::new(Vec3::new(0.0, 0.5, 0.0), Vec3::new(0.0, 1.0, 0.0));
            assert_eq!(unit_box().intersect(&ray, m), Some(0.5), "{m:?}");
        }
    }

    #[test]
    fn spawned_on_face_going_in_hits_far_face() {
        for m in METHODS {
            let ray = Ray::with_range(Vec3::new(0.0, 0.0, -1.0), Vec3::Z, 1e-4, f32::INFINITY);
            assert_eq!(unit_box().intersect(&ray, m), Some(2.0), "{m:?}");
        }
    }

    #[test]
    fn ray_along_a_face_hits() {
        for m in METHODS {
            let ray = Ray::new(Vec3::new(-5.0, 1.0, 0.0), Vec3::X);
            assert_eq!(unit_box().intersect(&ray, m), Some(4.0), "{m:?}");
        }
    }

    #[test]
    fn triangles_cover_the_surface_facing_out() {
        let b = AaBox::new(Vec3::new(-1.0, 0.0, 2.0), Vec3::new(1.0, 0.5, 5.0));
        let (mut area, mut centroid) = (0.0, Vec3::ZERO);
        for t in b.triangles() {
            let cross = (t[1] - t[0]).cross(t[2] - t[0]);
            let middle = (t[0] + t[1] + t[2]) / 3.0;
            // Outward: the face's surface normal, as a hit there reports it.
            assert_eq!(cross.normalize(), b.surface(middle).geometric_normal, "{t:?}");
            area += 0.5 * cross.length();
            centroid += 0.5 * cross.length() * middle;
        }
        assert!((area - 2.0 * (2.0 * 0.5 + 0.5 * 3.0 + 3.0 * 2.0)).abs() < 1e-5, "{area}");
        assert!((centroid / area - b.bounds().centroid()).length() < 1e-5);
    }

    #[test]
    fn surface_normals_point_out() {
        let b = unit_box();
        assert_eq!(b.surface(Vec3::new(0.2, 1.0, 0.3)).geometric_normal, Vec3::Y);
        assert_eq!(b.surface(Vec3::new(-1.0, 0.0, 0.3)).geometric_normal, -Vec3::X);
        let g = b.surface(Vec3::new(0.0, 0.0, -1.0));
        assert_eq!(g.geometric_normal, -Vec3::Z);
        assert_eq!(g.uv, Vec2::new(0.5, 0.5));
    }

    /// The box's surface where `ray` meets it, by `method`.
    fn hit_surface(b: &AaBox, ray: &Ray, method: BoxMethod) -> Option<SurfaceGeometry> {
        b.intersect(ray, method).map(|t| b.surface(ray.at(t)))
    }

    #[test]
    fn edge_and_corner_points_are_kept_inside_the_face() {
        let b = unit_box();
        // On the +x+y edge (and a little beyond it, as rounding may put it): on the face,
        // strictly inside the other slabs.
        for p in [Vec3::new(1.0, 1.0, 0.25), Vec3::new(1.0, next_float_up(1.0), 0.25), Vec3::ONE] {
            let g = b.surface(p);
            let (axis, _) = (0..3).map(|a| (a, g.geometric_normal[a])).find(|&(_, n)| n != 0.0).unwrap();
            assert_eq!(g.point[axis].abs(), 1.0, "{p} -> {}", g.point);
            for other in (0..3).filter(|&a| a != axis && p[a] >= 1.0) {
                assert!(g.point[other] < 1.0 && g.point[other] >= 1.0 - 1e-6, "{p} -> {}", g.point);
            }
        }
        // A mirror ray from inside into the edge comes back off both faces: a corner reflector.
        for m in METHODS {
            let d = Vec3::new(3.0, 3.0, 1.0);
            let mut ray = Ray::new(Vec3::new(-0.5, -0.5, 0.0), d);
            for _ in 0..2 {
                let g = hit_surface(&b, &ray, m).expect("the ray stays inside");
                let wi = crate::geometry::reflect(ray.direction, g.geometric_normal);
                ray = Ray::new(crate::geometry::offset_ray_origin(g.point, g.error, g.geometric_normal, wi), wi);
            }
            assert!((ray.direction - Vec3::new(-3.0, -3.0, 1.0)).length() < 1e-5, "{m:?}: {}", ray.direction);
        }
    }

    /// Rays from inside a closed mirror box aimed at its edges and corners, reflected again and
    /// again by both methods, must always hit the box again from inside: no ray leaks out.
    #[test]
    fn mirror_rays_at_edges_and_corners_stay_inside() {
        let mut rng = TestRng(11);
        let boxes = [
            unit_box(),
            AaBox::new(Vec3::splat(-2.0), Vec3::splat(2.0)),
            AaBox::new(Vec3::new(1e4, -3.0, 0.0), Vec3::new(1e4 + 7.0, 2.0, 0.75)),
        ];
        for b in boxes {
            for m in METHODS {
                for i in 0..3000 {
                    // A target on an edge (two coordinates on faces) or a corner (three).
                    let mut target = b.min + rng.vec3(0.0, 1.0) * (b.max - b.min);
                    let on_faces = 2 + (i % 2);
                    let first = (rng.next_u64() % 3) as usize;
                    for k in 0..on_faces {
                        let a = (first + k) % 3;
                        target[a] = if rng.next_u64().is_multiple_of(2) { b.min[a] } else { b.max[a] };
                    }
                    let origin = b.min + (0.1 + 0.8 * rng.vec3(0.0, 1.0)) * (b.max - b.min);
                    let mut ray = Ray::new(origin, target - origin);
                    for bounce in 0..50 {
                        let g = hit_surface(&b, &ray, m).unwrap_or_else(|| {
                            panic!("{m:?}: ray {ray:?} left {b:?} after {bounce} bounces (aimed at {target})")
                        });
                        // A mirror's ray, or now and then a diffuse one (any inward direction).
                        let mut wi = crate::geometry::reflect(ray.direction, g.geometric_normal);
                        if bounce % 3 == 2 {
                            wi = rng.unit_vector();
                            if wi.dot(g.geometric_normal) > 0.0 {
                                wi = -wi;
                            }
                        }
                        let o = crate::geometry::offset_ray_origin(g.point, g.error, g.geometric_normal, wi);
                        // Strictly inside the slabs of the face's edges; on the face's own
                        // plane only where its error bound is 0 (a face at coordinate 0).
                        let face_axis = g.geometric_normal.abs().max_position();
                        for a in 0..3 {
                            let inside = if a == face_axis {
                                o[a] >= b.min[a] && o[a] <= b.max[a]
                            } else {
                                o[a] > b.min[a] && o[a] < b.max[a]
                            };
                            assert!(inside, "{m:?}: spawned outside at {o} from {}", g.point);
                        }
                        ray = Ray::new(o, wi);
                    }
                }
            }
        }
    }

    #[test]
    fn slabs_and_woo_agree_on_a_million_rays() {
        let mut rng = TestRng(5);
        for _ in 0..1_000_000 {
            let a = rng.vec3(-2.0, 2.0);
            let b = a + rng.vec3(0.01, 3.0);
            let aabox = AaBox::new(a, b);
            let origin = rng.vec3(-4.0, 4.0);
            let ray = Ray::new(origin, rng.unit_vector());
            let (s, w) = (aabox.intersect_slabs(&ray), aabox.intersect_woo(&ray));
            match (s, w) {
                (Some(ts), Some(tw)) => assert!((ts - tw).abs() <= 1e-5 * (1.0 + ts), "{ts} {tw}"),
                (None, None) => {}
                _ => {
                    // Only a ray grazing an edge may come out either way.
                    let t = s.or(w).unwrap();
                    let p = ray.at(t);
                    let on_edge =
                        (0..3).filter(|&k| (p[k] - a[k]).abs() < 1e-4 || (p[k] - b[k]).abs() < 1e-4).count() >= 2;
                    assert!(on_edge, "hit/miss differ at {p} for {aabox:?} {ray:?}");
                }
            }
        }
    }
}
