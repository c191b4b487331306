//! Planar polygon with n ≥ 3 vertices, convex or concave, by the course's two
//! point-in-polygon tests.
//!
//! Scene parameters: `vertices` (n points in one plane, counter-clockwise seen from the
//! front; the normal is Newell's, so slightly non-planar input still gets a sensible plane).
//! ```toml
//! [[shapes]]
//! type = "polygon"
//! vertices = [[0, 0, 0], [2, 0, 0], [2, 2, 0], [1, 1, 0], [0, 2, 0]]
//! material = "blue"
//! ```
//! The ray meets the polygon's plane; the hit and the vertices are projected onto the
//! coordinate plane where the polygon is largest (dropping the normal's dominant axis), and a
//! 2D test decides inside or outside:
//! - **crossing** (even–odd rule): count the edges a half-line from the point crosses;
//! - **winding** (sign pairs / quadrants): sum the quadrant changes of the vertices seen from
//!   the point; a non-zero total (a multiple of 4, the winding number times 4) is inside.
//!
//! They agree on every simple polygon. On a self-intersecting one (a pentagram) they differ
//! by design: the centre of a pentagram is outside by the even–odd rule and inside by winding.

use glam::{Vec2, Vec3};

use super::SurfaceGeometry;
use crate::geometry::{gamma, orthonormal_basis, Aabb, Ray};
use crate::Named;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum PolygonTest {
    #[default]
    Crossing,
    Winding,
}

impl Named for PolygonTest {
    const ALL: &'static [Self] = &[PolygonTest::Crossing, PolygonTest::Winding];

    fn name(self) -> &'static str {
        match self {
            PolygonTest::Crossing => "crossing",
            PolygonTest::Winding => "winding",
        }
    }
}

/// Per-vertex uvs a polygon cannot take.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum PolygonUvError {
    #[error("`uvs` needs one [u, v] per vertex: {vertices} vertices, {uvs} uvs")]
    Count { vertices: usize, uvs: usize },
    #[error("`uvs` are supported on polygons with 3 or 4 vertices")]
    TooManyVertices,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Polygon {
    vertices: Vec<Vec3>,
    normal: Vec3,
    offset: f32,
    /// Indices of the two axes kept by the projection.
    axes: (usize, usize),
    projected: Vec<Vec2>,
    /// Per-vertex texture coordinates (triangles and quads only).
    uvs: Option<Vec<Vec2>>,
}

impl Polygon {
    /// `None` if there are fewer than 3 vertices or the polygon has no area.
    pub fn new(vertices: Vec<Vec3>) -> Option<Self> {
        if vertices.len() < 3 {
            return None;
        }
        let newell: Vec3 = (0..vertices.len())
            .map(|i| {
                let (a, b) = (vertices[i], vertices[(i + 1) % vertices.len()]);
                Vec3::new((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y))
            })
            .sum();
        let normal = newell.try_normalize()?;
        let centroid = vertices.iter().sum::<Vec3>() / vertices.len() as f32;
        let abs = normal.abs();
        let axes = if abs.x >= abs.y && abs.x >= abs.z {
            (1, 2)
        } else if abs.y >= abs.z {
            (2, 0)
        } else {
            (0, 1)
        };
        let projected = vertices.iter().map(|v| Vec2::new(v[axes.0], v[axes.1])).collect();
        Some(Self { offset: -normal.dot(centroid), normal, axes, projected, vertices, uvs: None })
    }

    /// The vertex farthest from the polygon's plane (Newell's normal through the centroid) and
    /// that distance relative to the polygon's size: 0 for a flat polygon, in rounding for one
    /// whose vertices were written flat.
    pub fn farthest_off_plane(&self) -> (usize, f32) {
        let size = self.vertices.iter().map(|v| (*v - self.vertices[0]).length()).fold(f32::MIN_POSITIVE, f32::max);
        let distance = |v: &Vec3| (self.normal.dot(*v) + self.offset).abs() / size;
        self.vertices.iter().enumerate().map(|(i, v)| (i, distance(v))).fold((0, 0.0), |best, candidate| {
            if candidate.1 > best.1 {
                candidate
            } else {
                best
            }
        })
    }

    /// Adds per-vertex uvs, interpolated barycentrically over a triangle and bilinearly over a
    /// quad (the course's interpolation of a rectangle's corner uvs).
    pub fn with_uvs(mut self, uvs: Vec<Vec2>) -> Result<Self, PolygonUvError> {
        if uvs.len() != self.vertices.len() {
            return Err(PolygonUvError::Count { vertices: self.vertices.len(), uvs: uvs.len() });
        }
        if !(3..=4).contains(&uvs.len()) {
            return Err(PolygonUvError::TooManyVertices);
        }
        self.uvs = Some(uvs);
        Ok(self)
    }

    pub fn vertices(&self) -> &[Vec3] {
        &self.vertices
    }

    pub fn normal(&self) -> Vec3 {
        self.normal
    }

    /// The polygon cut into triangles on its plane, for sampling it by area as a light: ear
    /// clipping in the projected plane (O(n²)), each corner lifted back onto the plane along
    /// the dropped axis, so the triangles cover exactly the points the inside tests accept.
    /// `None` for a self-intersecting polygon, whose inside the two tests read differently.
    pub fn triangles(&self) -> Option<Vec<[Vec3; 3]>> {
        let p = &self.projected;
        let n = p.len();
        if edges_cross(p) {
            return None;
        }
        let cross = |a: Vec2, b: Vec2, c: Vec2| (b - a).perp_dot(c - a);
        let orientation = (0..n).map(|i| p[i].perp_dot(p[(i + 1) % n])).sum::<f32>().signum();
        let mut left: Vec<usize> = (0..n).collect();
        let mut corners = Vec::with_capacity(n - 2);
        while left.len() > 3 {
            let m = left.len();
            let around = |i: usize| (left[(i + m - 1) % m], left[i], left[(i + 1) % m]);
            let is_ear = |i: usize| {
                let (a, b, c) = around(i);
                cross(p[a], p[b], p[c]) * orientation > 0.0
                    && left.iter().all(|&j| {
                        j == a || j == b || j == c || p[j] == p[a] || p[j] == p[b] || p[j] == p[c] || {
                            let (x, y, z) = (cross(p[a], p[b], p[j]), cross(p[b], p[c], p[j]), cross(p[c], p[a], p[j]));
                            !(x * orientation >= 0.0 && y * orientation >= 0.0 && z * orientation >= 0.0)
                        }
                    })
            };
            if let Some(i) = (0..m).find(|&i| is_ear(i)) {
                let (a, b, c) = around(i);
                corners.push([a, b, c]);
                left.remove(i);
            } else if let Some(i) = (0..m).find(|&i| {
                let (a, b, c) = around(i);
                cross(p[a], p[b], p[c]) == 0.0
            }) {
                // A vertex on the line through its neighbours bounds no area: dropped.
                left.remove(i);
            } else {
                return None;
            }
        }
        corners.push([left[0], left[1], left[2]]);
        let dropped = 3 - self.axes.0 - self.axes.1;
        let lift = |q: Vec2| {
            let mut v = Vec3::ZERO;
            v[self.axes.0] = q.x;
            v[self.axes.1] = q.y;
            v[dropped] =
                -(self.offset + self.normal[self.axes.0] * q.x + self.normal[self.axes.1] * q.y) / self.normal[dropped];
            v
        };
        Some(corners.into_iter().map(|t| t.map(|i| lift(p[i]))).collect())
    }

    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(self.vertices.iter().copied())
    }

    pub fn intersect(&self, ray: &Ray, test: PolygonTest) -> Option<f32> {
        let denominator = self.normal.dot(ray.direction);
        if denominator == 0.0 {
            return None;
        }
        let t = -(self.normal.dot(ray.origin) + self.offset) / denominator;
        if !ray.contains(t) {
            return None;
        }
        let p = ray.at(t);
        let point = Vec2::new(p[self.axes.0], p[self.axes.1]);
        let inside = match test {
            PolygonTest::Crossing => crossing_test(&self.projected, point),
            PolygonTest::Winding => winding_number(&self.projected, point) != 0,
        };
        inside.then_some(t)
    }

    /// (∂p/∂u, ∂p/∂v): from the first three corners' uvs (exact for a triangle and a
    /// parallelogram; a quad's at its first corner otherwise), or the plane's two tangents
    /// without uvs.
    pub fn tangents(&self) -> (Vec3, Vec3) {
        match self.uvs.as_deref() {
            Some([ua, ub, uc, ..]) => super::triangle::triangle_tangents(
                [self.vertices[0], self.vertices[1], self.vertices[2]],
                Some([*ua, *ub, *uc]),
            ),
            _ => orthonormal_basis(self.normal),
        }
    }

    pub fn surface(&self, point: Vec3) -> SurfaceGeometry {
        let point = point - (self.normal.dot(point) + self.offset) * self.normal;
        let (s, t) = orthonormal_basis(self.normal);
        let projected = Vec2::new(point[self.axes.0], point[self.axes.1]);
        let uv = match self.uvs.as_deref() {
            Some([ua, ub, uc]) => {
                let [a, b, c] = [self.projected[0], self.projected[1], self.projected[2]];
                let area = (b - a).perp_dot(c - a);
                let beta = (projected - a).perp_dot(c - a) / area;
                let gamma = (b - a).perp_dot(projected - a) / area;
                (1.0 - beta - gamma) * *ua + beta * *ub + gamma * *uc
            }
            Some([ua, ub, uc, ud]) => {
                let corners = [self.projected[0], self.projected[1], self.projected[2], self.projected[3]];
                let st = inverse_bilinear(projected, corners);
                (1.0 - st.x) * (1.0 - st.y) * *ua
                    + st.x * (1.0 - st.y) * *ub
                    + st.x * st.y * *uc
                    + (1.0 - st.x) * st.y * *ud
            }
            _ => Vec2::new(point.dot(s), point.dot(t)),
        };

        SurfaceGeometry {
            point,
            geometric_normal: self.normal,
            shading_normal: self.normal,
            uv,
            // The projection onto the plane: a dot product and a multiply-add per axis.
            error: gamma(7) * (point.abs() + Vec3::splat(self.offset.abs())),
        }
    }
}

/// Whether two edges of the closed polygon `vertices` that share no vertex cross (properly:
/// each edge's ends strictly on either side of the other's line).
fn edges_cross(vertices: &[Vec2]) -> bool {
    let n = vertices.len();
    let edge = |i: usize| (vertices[i], vertices[(i + 1) % n]);
    let side = |(a, b): (Vec2, Vec2), p: Vec2| (b - a).perp_dot(p - a);
    (0..n).any(|i| {
        (i + 2..n).filter(|&j| (j + 1) % n != i).any(|j| {
            let (e, f) = (edge(i), edge(j));
            side(e, f.0) * side(e, f.1) < 0.0 && side(f, e.0) * side(f, e.1) < 0.0
        })
    })
}

/// The (s, t) ∈ [0,1]² with p = bilerp(a, b, c, d; s, t) for the quad a→b→c→d (a at (0,0),
/// b at (1,0), c at (1,1), d at (0,1)): the inverse of bilinear interpolation, a quadratic in t.
pub fn inverse_bilinear(p: Vec2, [a, b, c, d]: [Vec2; 4]) -> Vec2 {
    let (e, f, g, h) = (b - a, d - a, a - b + c - d, p - a);
    let k2 = g.perp_dot(f);
    let k1 = e.perp_dot(f) + h.perp_dot(g);
    let k0 = h.perp_dot(e);
    let t = if k2.abs() < 1e-6 * k1.abs().max(f32::MIN_POSITIVE) {
        -k0 / k1 // a parallelogram: linear in t
    } else {
        let root = (k1 * k1 - 4.0 * k0 * k2).max(0.0).sqrt();
        let t0 = (-k1 - root) / (2.0 * k2);
        if (-1e-4..=1.0 + 1e-4).contains(&t0) {
            t0
        } else {
            (-k1 + root) / (2.0 * k2)
        }
    };
    // s from whichever coordinate is better conditioned.
    let denominator = e + g * t;
    let s = if denominator.x.abs() > denominator.y.abs() {
        (h.x - f.x * t) / denominator.x
    } else {
        (h.y - f.y * t) / denominator.y
    };
    Vec2::new(s, t)
}

/// Even–odd rule: a half-line from `p` toward +x crosses the boundary an odd number of times
/// iff `p` is inside. Each edge is half-open in y, so a vertex on the half-line counts once.
pub fn crossing_test(vertices: &[Vec2], p: Vec2) -> bool {
    let mut inside = false;
    let mut previous = vertices[vertices.len() - 1];
    for &current in vertices {
        if (current.y > p.y) != (previous.y > p.y) {
            let x_cross = current.x + (p.y - current.y) * (previous.x - current.x) / (previous.y - current.y);
            if p.x < x_cross {
                inside = !inside;
            }
        }
        previous = current;
    }
    inside
}

/// Winding number by sign pairs: each vertex, seen from `p`, falls in the quadrant given by the
/// signs of its (x, y); walking the edges, a step to the next quadrant counts ±1 and a diagonal
/// step ±2 (its direction from the sign of the cross product). The total is 4 × winding number.
pub fn winding_number(vertices: &[Vec2], p: Vec2) -> i32 {
    let quadrant = |v: Vec2| -> i32 {
        match (v.x >= 0.0, v.y >= 0.0) {
            (true, true) => 0,
            (false, true) => 1,
            (false, false) => 2,
            (true, false) => 3,
        }
    };
    let mut previous = vertices[vertices.len() - 1] - p;
    let mut previous_quadrant = quadrant(previous);
    let mut total = 0;
    for &vertex in vertices {
        let current = vertex - p;
        let current_quadrant = quadrant(current);
        total += match (current_quadrant - previous_quadrant).rem_euclid(4) {
            0 => 0,
            1 => 1,
            3 => -1,
            _ => {
                // Diagonal: passes left or right of p depending on the edge's orientation.
                if previous.perp_dot(current) > 0.0 {
                    2
                } else {
                    -2
                }
            }
        };
        previous = current;
        previous_quadrant = current_quadrant;
    }
    total / 4
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flatness_by_hand() {
        let square = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        assert_eq!(Polygon::new(square.to_vec()).unwrap().farthest_off_plane(), (0, 0.0));
        // One corner raised by 0.1 of a unit square (size √2 from vertex 0): the plane through
        // the centroid is 0.025 from each vertex.
        let mut bent = square;
        bent[2].z = 0.1;
        let (_, off) = Polygon::new(bent.to_vec()).unwrap().farthest_off_plane();
        assert!((off - 0.025 / 2f32.sqrt()).abs() < 2e-3, "{off}");
    }
    use crate::shapes::test_util::TestRng;

    const TESTS: [PolygonTest; 2] = [PolygonTest::Crossing, PolygonTest::Winding];

    /// An L-shaped (concave) hexagon in the z = 1 plane.
    fn l_shape() -> Polygon {
        Polygon::new(
            [(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.0), (1.0, 2.0), (0.0, 2.0)]
                .iter()
                .map(|&(x, y)| Vec3::new(x, y, 1.0))
                .collect(),
        )
        .unwrap()
    }

    #[test]
    fn concave_polygon_inside_and_notch() {
        for test in TESTS {
            let hit = |x, y| l_shape().intersect(&Ray::new(Vec3::new(x, y, 0.0), Vec3::Z), test);
            assert_eq!(hit(0.5, 0.5), Some(1.0), "{test:?}");
            assert_eq!(hit(1.5, 0.5), Some(1.0), "{test:?}");
            assert_eq!(hit(0.5, 1.5), Some(1.0), "{test:?}");
            assert_eq!(hit(1.5, 1.5), None, "notch {test:?}");
            assert_eq!(hit(3.0, 0.5), None, "{test:?}");
        }
    }

    #[test]
    fn plane_misses() {
        for test in TESTS {
            assert!(l_shape().intersect(&Ray::new(Vec3::new(0.5, 0.5, 2.0), Vec3::Z), test).is_none());
            assert!(l_shape().intersect(&Ray::new(Vec3::new(0.5, 0.5, 1.0), Vec3::X), test).is_none());
        }
    }

    #[test]
    fn degenerate_polygons_are_refused() {
        assert!(Polygon::new(vec![Vec3::ZERO, Vec3::X]).is_none());
        assert!(Polygon::new(vec![Vec3::ZERO, Vec3::X, 2.0 * Vec3::X]).is_none());
    }

    #[test]
    fn normal_follows_winding_and_projection_handles_every_axis() {
        assert_eq!(l_shape().normal(), Vec3::Z);
        for n in [Vec3::X, Vec3::Y, -Vec3::Z] {
            let (s, t) = orthonormal_basis(n);
            let square = Polygon::new(vec![s + t, -s + t, -s - t, s - t]).unwrap();
            assert!((square.normal() - n).length() < 1e-6);
            for test in TESTS {
                let ray = Ray::new(3.0 * n + 0.5 * s, -n);
                assert_eq!(square.intersect(&ray, test), Some(3.0));
            }
        }
    }

    #[test]
    fn quad_uvs_interpolate_bilinearly() {
        // A trapezoid: the bottom edge twice as long as the top.
        let quad = Polygon::new(vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(4.0, 0.0, 0.0),
            Vec3::new(3.0, 2.0, 0.0),
            Vec3::new(1.0, 2.0, 0.0),
        ])
        .unwrap()
        .with_uvs(vec![Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0), Vec2::new(1.0, 1.0), Vec2::new(0.0, 1.0)])
        .unwrap();
        // The midpoint of the left edge is (s, t) = (0, ½); the centre of the top edge (½, 1).
        let uv = quad.surface(Vec3::new(0.5, 1.0, 0.0)).uv;
        assert!((uv - Vec2::new(0.0, 0.5)).length() < 1e-5, "{uv}");
        let uv = quad.surface(Vec3::new(2.0, 2.0, 0.0)).uv;
        assert!((uv - Vec2::new(0.5, 1.0)).length() < 1e-5, "{uv}");
        // Round trip on a skewed quad: bilerp then invert.
        let corners = [Vec2::new(0.0, 0.0), Vec2::new(3.0, 0.5), Vec2::new(2.5, 2.0), Vec2::new(-0.5, 1.5)];
        for (s, t) in [(0.2, 0.7), (0.9, 0.1), (0.5, 0.5)] {
            let p = (1.0 - s) * (1.0 - t) * corners[0]
                + s * (1.0 - t) * corners[1]
                + s * t * corners[2]
                + (1.0 - s) * t * corners[3];
            let st = inverse_bilinear(p, corners);
            assert!((st - Vec2::new(s, t)).length() < 1e-4, "{st} vs ({s}, {t})");
        }
    }

    #[test]
    fn pentagram_centre_differs_by_rule() {
        let star: Vec<Vec2> = (0..5)
            .map(|i| {
                let a = std::f32::consts::FRAC_PI_2 + i as f32 * 4.0 * std::f32::consts::PI / 5.0;
                Vec2::new(a.cos(), a.sin())
            })
            .collect();
        assert!(!crossing_test(&star, Vec2::ZERO));
        assert_eq!(winding_number(&star, Vec2::ZERO).abs(), 2);
        // A point in one of the star's tips is inside by both rules.
        let tip = 0.8 * star[0];
        assert!(crossing_test(&star, tip) && winding_number(&star, tip) != 0);
    }

    /// Random simple (star-shaped, hence non-self-intersecting) polygons, a million points:
    /// the two rules must agree except within rounding of an edge.
    #[test]
    fn crossing_and_winding_agree_on_a_million_rays() {
        let mut rng = TestRng(3);
        for _ in 0..2_000 {
            let n = 3 + (rng.next_u64() % 12) as usize;
            let mut angles: Vec<f32> = (0..n).map(|_| rng.range(0.0, std::f32::consts::TAU)).collect();
            angles.sort_by(f32::total_cmp);
            let poly: Vec<Vec2> = angles.iter().map(|a| rng.range(0.2, 1.0) * Vec2::new(a.cos(), a.sin())).collect();
            for _ in 0..500 {
                let p = Vec2::new(rng.range(-1.1, 1.1), rng.range(-1.1, 1.1));
                let even_odd = crossing_test(&poly, p);
                let winding = winding_number(&poly, p) != 0;
                if even_odd != winding {
                    let d = distance_to_boundary(&poly, p);
                    assert!(d < 1e-5, "rules differ at {p} ({d} from the boundary)");
                }
            }
        }
    }

    /// Random polygons (vertices by sorted angle) on a tilted plane cut into triangles: the triangles lie on
    /// the plane, keep the polygon's facing, add up to its area (shoelace) and cover each
    /// point the crossing test calls inside exactly once, and no point outside.
    #[test]
    fn triangles_tile_the_polygon_exactly() {
        let mut rng = TestRng(11);
        let height = |q: Vec2| 1.0 + 0.3 * q.x - 0.2 * q.y;
        for _ in 0..300 {
            let n = 3 + (rng.next_u64() % 12) as usize;
            let mut angles: Vec<f32> = (0..n).map(|_| rng.range(0.0, std::f32::consts::TAU)).collect();
            angles.sort_by(f32::total_cmp);
            let flat: Vec<Vec2> = angles.iter().map(|a| rng.range(0.2, 1.0) * Vec2::new(a.cos(), a.sin())).collect();
            let polygon = Polygon::new(flat.iter().map(|q| q.extend(height(*q))).collect()).unwrap();
            // Sorted angles with a gap over π can make a bow tie: no triangles for it.
            if edges_cross(&flat) {
                assert_eq!(polygon.triangles(), None);
                continue;
            }
            let triangles = polygon.triangles().expect("a simple polygon");
            assert!(triangles.len() <= n - 2);
            let shoelace: f32 = 0.5 * (0..n).map(|i| flat[i].perp_dot(flat[(i + 1) % n])).sum::<f32>();
            let mut projected_area = 0.0;
            for t in &triangles {
                for v in t {
                    assert!((v.z - height(v.truncate())).abs() < 1e-5, "{v} is off the plane");
                }
                let cross = (t[1] - t[0]).cross(t[2] - t[0]);
                assert!(cross.dot(polygon.normal()) >= 0.0, "a triangle faces the other way");
                projected_area += 0.5 * cross.z;
            }
            assert!((projected_area - shoelace).abs() < 1e-5, "{projected_area} vs {shoelace}");
            let covering = |p: Vec2| {
                triangles
                    .iter()
                    .filter(|t| {
                        let [a, b, c] = t.map(|v| v.truncate());
                        let (x, y, z) = ((b - a).perp_dot(p - a), (c - b).perp_dot(p - b), (a - c).perp_dot(p - c));
                        (x >= 0.0 && y >= 0.0 && z >= 0.0) || (x <= 0.0 && y <= 0.0 && z <= 0.0)
                    })
                    .count()
            };
            for _ in 0..200 {
                let p = Vec2::new(rng.range(-1.1, 1.1), rng.range(-1.1, 1.1));
                if distance_to_boundary(&flat, p) < 1e-4 {
                    continue;
                }
                let expected = usize::from(crossing_test(&flat, p));
                let found = covering(p);
                // On an inner diagonal a point lies on two triangles' shared edge.
                assert!(found == expected || (expected == 1 && found == 2), "{p}: {found} triangles, {expected}");
            }
        }
    }

    /// A concave hexagon by hand (the L: area 3), and a pentagram, which has no triangles.
    #[test]
    fn l_shape_triangles_and_no_triangles_for_a_pentagram() {
        let triangles = l_shape().triangles().unwrap();
        assert_eq!(triangles.len(), 4);
        let area: f32 = triangles.iter().map(|t| 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length()).sum();
        assert!((area - 3.0).abs() < 1e-6, "{area}");
        let star = (0..5).map(|i| {
            let a = std::f32::consts::FRAC_PI_2 + i as f32 * 4.0 * std::f32::consts::PI / 5.0;
            Vec3::new(a.cos(), a.sin(), 0.0)
        });
        assert_eq!(Polygon::new(star.collect()).unwrap().triangles(), None);
    }

    fn distance_to_boundary(poly: &[Vec2], p: Vec2) -> f32 {
        (0..poly.len())
            .map(|i| {
                let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
                let t = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
                (a + t * (b - a) - p).length()
            })
            .fold(f32::INFINITY, f32::min)
    }
}
