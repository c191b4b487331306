//! Constructive solid geometry: union, intersection and difference of closed solids, nested to
//! any depth, by ray-interval algebra (Roth 1982).
//!
//! Each solid says where along the ray it is entered and left; a node merges its two
//! operands' lists, keeping a crossing only where it changes the node's own inside-ness. The
//! first crossing the root keeps is the hit. Only the part of the ray after its origin is
//! computed: a list is whether the origin is inside, then the crossings past it, so rays that
//! start inside a solid (refraction through a lens) need no crossing behind them.
//!
//! The hit's surface is the solid's that bounds the result there, with its material; a
//! difference's second operand bounds the result with its inside, so its normals are flipped
//! (twice flipped, as C in A − (B − C), they point out again).
//!
//! Solids: spheres, boxes (by slabs, whichever box method is chosen: Woo's method finds only
//! the entry) and closed, consistently wound meshes through their own BVH (an instance's
//! geometry). A mesh's crossings are counted by winding (each crossing enters or leaves by the
//! sign of d·n; two of one sign at the same distance are one crossing met on a shared edge),
//! its inside where the count is positive. Planes, polygons, lone triangles and open meshes
//! bound no solid and are refused.
//!
//! Scene parameters (`docs/scene-format.md`):
//! ```toml
//! [[shapes]]
//! type = "csg"
//! operation = "difference"      # union | intersection | difference (the first minus the rest)
//! material = "ivory"
//! operands = [
//!   { type = "box", min = [-1, -1, -1], max = [1, 1, 1] },
//!   { type = "sphere", center = [0, 0, 1], radius = 0.3, material = "black" },
//! ]
//! ```

use glam::{Mat3, Vec3};
use smallvec::SmallVec;

use super::{IntersectMethods, PrimHit, Shape, SurfaceGeometry};
use crate::geometry::{Aabb, Ray, Transform};

/// How a node combines its two operands.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CsgOperation {
    Union,
    Intersection,
    /// The first operand without the second.
    Difference,
}

impl crate::Named for CsgOperation {
    const ALL: &'static [Self] = &[CsgOperation::Union, CsgOperation::Intersection, CsgOperation::Difference];

    fn name(self) -> &'static str {
        match self {
            CsgOperation::Union => "union",
            CsgOperation::Intersection => "intersection",
            CsgOperation::Difference => "difference",
        }
    }
}

impl CsgOperation {
    /// Whether a point is inside the result, given whether it is inside each operand.
    #[inline]
    fn contains(self, in_first: bool, in_second: bool) -> bool {
        match self {
            CsgOperation::Union => in_first || in_second,
            CsgOperation::Intersection => in_first && in_second,
            CsgOperation::Difference => in_first && !in_second,
        }
    }
}

/// A closed shape as an operand: placed by its own transform (into the CSG's space), with its
/// own material or, if `None`, the object's.
#[derive(Clone, Debug)]
pub struct CsgSolid {
    pub shape: Shape,
    pub transform: Option<Transform>,
    pub material: Option<u32>,
}

impl CsgSolid {
    pub fn new(shape: Shape) -> Self {
        Self { shape, transform: None, material: None }
    }
}

/// A CSG expression as written: solids, and operations over two or more operands (a union or
/// intersection of all of them, the first minus all the others).
#[derive(Clone, Debug)]
pub enum CsgTree {
    Solid(Box<CsgSolid>),
    Combine(CsgOperation, Vec<CsgTree>),
}

impl CsgTree {
    /// A shape as an operand, in the CSG's space, with the object's material.
    pub fn solid(shape: Shape) -> Self {
        CsgTree::Solid(Box::new(CsgSolid::new(shape)))
    }
}

/// Why a CSG expression was refused.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum CsgError {
    #[error("a {0} bounds no solid (CSG takes spheres, boxes, closed meshes and other CSG nodes)")]
    OpenShape(&'static str),
    #[error(
        "a mesh in CSG must be closed and consistently wound (every edge shared by two triangles that turn the same way)"
    )]
    OpenMesh,
    #[error("a mesh in CSG needs its own BVH: give it as an instance of a named mesh")]
    BareMesh,
    #[error("a {0} needs at least one operand")]
    NoOperands(&'static str),
    #[error("CSG nested deeper than {MAX_DEPTH} levels")]
    TooDeep,
}

/// How deep the evaluation may recurse: N operands of one operation make a balanced tree of
/// depth log₂ N, so only expressions written nested this deep reach it.
pub const MAX_DEPTH: usize = 64;

#[derive(Clone, Copy, Debug)]
enum Node {
    Solid(u32),
    Combine { operation: CsgOperation, first: u32, second: u32 },
}

/// A solid as the evaluation reads it.
#[derive(Clone, Debug)]
struct Placed {
    solid: CsgSolid,
    /// Its normals point into the result: it is the second operand of an odd number of
    /// differences, or else a mesh wound inward.
    flipped: bool,
    /// A mesh wound inward: a crossing along its normal enters it.
    inward: bool,
}

/// A CSG object: the solids, the binary tree over them (root last), and each node's bounds.
#[derive(Clone, Debug)]
pub struct Csg {
    solids: Vec<Placed>,
    nodes: Vec<Node>,
    bounds: Vec<Aabb>,
}

/// Where a ray crosses a solid's (or node's) boundary: `t`, the solid's own hit parameters
/// (`u`, `v`) and, in `inner`, the solid's index.
type Crossing = PrimHit;

/// A solid's or node's extent along a ray: whether the ray's origin (its `t_min`) is inside,
/// then where it is crossed after it, in ascending order. Inline for up to eight crossings,
/// which spheres and boxes never pass, so most rays allocate nothing.
#[derive(Default)]
struct Span {
    inside: bool,
    crossings: SmallVec<[Crossing; 8]>,
}

impl Span {
    fn is_empty(&self) -> bool {
        !self.inside && self.crossings.is_empty()
    }
}

impl Csg {
    pub fn new(tree: CsgTree) -> Result<Self, CsgError> {
        let mut csg = Csg { solids: Vec::new(), nodes: Vec::new(), bounds: Vec::new() };
        csg.add(tree, false, 0)?;
        Ok(csg)
    }

    /// Adds `tree`'s nodes (its root last) and returns the root's index.
    fn add(&mut self, tree: CsgTree, flipped: bool, depth: usize) -> Result<u32, CsgError> {
        if depth > MAX_DEPTH {
            return Err(CsgError::TooDeep);
        }
        match tree {
            CsgTree::Solid(solid) => {
                let inward = match &solid.shape {
                    Shape::Sphere(_) | Shape::AaBox(_) => false,
                    Shape::Instance(i) => match i.geometry.enclosed_volume() {
                        Some(volume) if volume != 0.0 => volume < 0.0,
                        _ => return Err(CsgError::OpenMesh),
                    },
                    Shape::Mesh(_) => return Err(CsgError::BareMesh),
                    other => return Err(CsgError::OpenShape(other.kind())),
                };
                let local = solid.shape.bounds(0).expect("closed shapes are bounded");
                let bounds = match &solid.transform {
                    None => local,
                    Some(t) => Aabb::from_points(local.corners().map(|c| t.point(c))),
                };
                // Crossings are classified, and normals made, in the solid's own space and
                // mapped out as normals: a mirroring transform changes neither's side.
                self.solids.push(Placed { solid: *solid, flipped: flipped ^ inward, inward });
                Ok(self.push(Node::Solid(self.solids.len() as u32 - 1), bounds))
            }
            CsgTree::Combine(operation, operands) => {
                let name = crate::Named::name(operation);
                if operands.is_empty() {
                    return Err(CsgError::NoOperands(name));
                }
                let mut operands = operands.into_iter();
                let first = operands.next().expect("not empty");
                let rest: Vec<CsgTree> = operands.collect();
                if rest.is_empty() {
                    return self.add(first, flipped, depth + 1);
                }
                let first = self.add(first, flipped, depth + 1)?;
                // A − B − C = A − (B ∪ C); unions and intersections are associative: either
                // way the rest become one balanced subtree.
                let rest_operation =
                    if operation == CsgOperation::Difference { CsgOperation::Union } else { operation };
                let second_flipped = flipped ^ (operation == CsgOperation::Difference);
                let second = self.add_balanced(rest_operation, rest, second_flipped, depth + 1)?;
                let bounds = match operation {
                    CsgOperation::Union => self.bounds[first as usize].union(self.bounds[second as usize]),
                    CsgOperation::Intersection => {
                        let (a, b) = (self.bounds[first as usize], self.bounds[second as usize]);
                        Aabb::new(a.min.max(b.min), a.max.min(b.max))
                    }
                    CsgOperation::Difference => self.bounds[first as usize],
                };
                Ok(self.push(Node::Combine { operation, first, second }, bounds))
            }
        }
    }

    /// `operands` combined by `operation` (associative) as a balanced tree.
    fn add_balanced(
        &mut self,
        operation: CsgOperation,
        mut operands: Vec<CsgTree>,
        flipped: bool,
        depth: usize,
    ) -> Result<u32, CsgError> {
        if operands.len() == 1 {
            return self.add(operands.pop().expect("one"), flipped, depth);
        }
        let second_half = operands.split_off(operands.len() / 2);
        let first = self.add_balanced(operation, operands, flipped, depth + 1)?;
        let second = self.add_balanced(operation, second_half, flipped, depth + 1)?;
        let (a, b) = (self.bounds[first as usize], self.bounds[second as usize]);
        let bounds = match operation {
            CsgOperation::Intersection => Aabb::new(a.min.max(b.min), a.max.min(b.max)),
            _ => a.union(b),
        };
        Ok(self.push(Node::Combine { operation, first, second }, bounds))
    }

    fn push(&mut self, node: Node, bounds: Aabb) -> u32 {
        self.nodes.push(node);
        self.bounds.push(bounds);
        self.nodes.len() as u32 - 1
    }

    fn root(&self) -> u32 {
        self.nodes.len() as u32 - 1
    }

    /// The bounds of the result (of the root: an intersection's are its operands' overlap,
    /// a difference's its first operand's). An empty result keeps a point's bounds.
    pub fn bounds(&self) -> Aabb {
        let b = self.bounds[self.root() as usize];
        if b.min.cmple(b.max).all() {
            b
        } else {
            Aabb::new(b.min, b.min)
        }
    }

    /// The number of solids.
    pub fn solid_count(&self) -> usize {
        self.solids.len()
    }

    /// Solid `solid`'s own material, if it has one.
    #[inline]
    pub fn solid_material(&self, solid: u32) -> Option<u32> {
        self.solids.get(solid as usize).and_then(|s| s.solid.material)
    }

    /// The first crossing of the result's boundary within the ray's interval; `inner` is the
    /// solid whose surface it is.
    pub fn intersect(&self, ray: &Ray, methods: &IntersectMethods) -> Option<PrimHit> {
        let span = self.span(self.root(), ray, methods);
        span.crossings.into_iter().find(|c| ray.contains(c.t))
    }

    /// Every crossing of the result's boundary after the ray's origin, and whether the origin
    /// is inside (what a ray meets all along it, as the tests check it).
    pub fn crossings(&self, ray: &Ray, methods: &IntersectMethods) -> (bool, Vec<PrimHit>) {
        let span = self.span(self.root(), ray, methods);
        (span.inside, span.crossings.into_vec())
    }

    fn span(&self, node: u32, ray: &Ray, methods: &IntersectMethods) -> Span {
        // A ray that misses a node's bounds after its origin starts outside it and never
        // enters: the bounds hold every point inside.
        let inv = ray.direction.recip();
        if self.bounds[node as usize].hit_distance(ray.origin, inv, ray.t_min, f32::INFINITY).is_none() {
            return Span::default();
        }
        match self.nodes[node as usize] {
            Node::Solid(s) => self.solid_span(s, ray, methods),
            Node::Combine { operation, first, second } => {
                let a = self.span(first, ray, methods);
                // The rest is decided without the second operand where the first is empty
                // (an intersection or difference with nothing).
                if a.is_empty() && operation != CsgOperation::Union {
                    return Span::default();
                }
                let b = self.span(second, ray, methods);
                combine(operation, a, b)
            }
        }
    }

    /// Where the ray crosses solid `s`, the crossings' `inner` naming it.
    fn solid_span(&self, s: u32, ray: &Ray, methods: &IntersectMethods) -> Span {
        let solid = &self.solids[s as usize].solid;
        let local = match &solid.transform {
            None => *ray,
            Some(t) => t.ray_to_object(ray),
        };
        let interval = |roots: Option<(f32, f32)>| {
            let mut span = Span::default();
            if let Some((enter, exit)) = roots.filter(|(enter, exit)| enter <= exit) {
                span.inside = enter <= ray.t_min && ray.t_min < exit;
                for t in [enter, exit] {
                    if t > ray.t_min {
                        span.crossings.push(PrimHit { t, u: 0.0, v: 0.0, inner: s });
                    }
                }
            }
            span
        };
        match &solid.shape {
            Shape::Sphere(sphere) => interval(sphere.roots(&local, methods.sphere)),
            Shape::AaBox(b) => interval(Some(b.bounds().slab_interval(local.origin, local.direction.recip()))),
            Shape::Instance(instance) => {
                mesh_span(instance.geometry.as_ref(), &local, s, self.solids[s as usize].inward)
            }
            _ => unreachable!("Csg::new admits only closed solids"),
        }
    }

    /// The surface of the solid named by `hit.inner` where `ray` crossed it: its own surface,
    /// placed in the CSG's space, its normals flipped where it bounds the result with its
    /// inside.
    pub fn surface(&self, ray: &Ray, hit: &PrimHit) -> SurfaceGeometry {
        let placed = &self.solids[hit.inner as usize];
        let solid = &placed.solid;
        let local_ray = match &solid.transform {
            None => *ray,
            Some(t) => t.ray_to_object(ray),
        };
        let point = local_ray.at(hit.t);
        let local = match &solid.shape {
            Shape::AaBox(b) => match &solid.transform {
                None => b.surface(point),
                Some(t) => b.surface_within(point, t.round_trip_margin(point)),
            },
            Shape::Sphere(s) => s.surface(point),
            Shape::Instance(instance) => {
                // The triangle crossed at exactly this distance, found again (the crossing
                // list keeps only the solid): the same query on the same ray gives the same t.
                let mut found = None;
                let mut search = local_ray;
                search.t_max = f32::INFINITY;
                instance.geometry.crossings(&search, &mut |h, _| {
                    if h.t == hit.t && found.is_none() {
                        found = Some(h);
                    }
                });
                let at = found.unwrap_or(PrimHit { inner: 0, ..*hit });
                instance.surface(&local_ray, &at)
            }
            _ => unreachable!("Csg::new admits only closed solids"),
        };
        let mut surface = match &solid.transform {
            None => local,
            Some(t) => local.placed(t),
        };
        if placed.flipped {
            surface.geometric_normal = -surface.geometric_normal;
            surface.shading_normal = -surface.shading_normal;
        }
        surface
    }

    /// (∂p/∂u, ∂p/∂v) at `point` of solid `solid` (a sphere's or a box's; zero on meshes).
    pub fn tangents(&self, solid: u32, point: Vec3, normal: Vec3) -> (Vec3, Vec3) {
        let Some(placed) = self.solids.get(solid as usize) else { return (Vec3::ZERO, Vec3::ZERO) };
        let normal = if placed.flipped { -normal } else { normal };
        let solid = &placed.solid;
        match &solid.transform {
            None => solid.shape.tangents(0, point, normal),
            Some(t) => {
                let local_normal = Mat3::from_mat4(t.to_world).transpose() * normal;
                let local_point = t.to_object.transform_point3(point);
                let (dpdu, dpdv) = solid.shape.tangents(0, local_point, local_normal);
                (t.vector(dpdu), t.vector(dpdv))
            }
        }
    }
}

/// A closed mesh's span: its crossings sorted, each entering or leaving by its normal's side,
/// the origin's winding number the count of leavings less enterings (past the last crossing
/// the ray is outside), and a crossing kept where the winding number passes zero.
///
/// Crossings at (almost) one distance are one event, counted by the sign of enterings less
/// leavings: two of one sense are one crossing on the edge two triangles share, found in
/// both; a mixed group is a ray grazing a silhouette edge or vertex, which neither enters nor
/// leaves (or, if one sense outnumbers the other, does that once).
fn mesh_span(geometry: &dyn super::InstancedGeometry, ray: &Ray, solid: u32, inward: bool) -> Span {
    let mut all: SmallVec<[(PrimHit, bool); 16]> = SmallVec::new();
    let mut forward = *ray;
    forward.t_max = f32::INFINITY;
    geometry.crossings(&forward, &mut |hit, along_normal| all.push((hit, along_normal != inward)));
    all.sort_unstable_by(|a, b| a.0.t.total_cmp(&b.0.t));
    // Each event: its first crossing and its effect on the winding number (+1 entering).
    let mut events: SmallVec<[(PrimHit, i32); 16]> = SmallVec::new();
    let mut k = 0;
    while k < all.len() {
        let first = all[k].0;
        let mut balance = 0i32;
        while k < all.len() && all[k].0.t - first.t <= 1e-6 * all[k].0.t.abs().max(first.t.abs()) {
            balance += if all[k].1 { -1 } else { 1 };
            k += 1;
        }
        if balance != 0 {
            events.push((first, balance.signum()));
        }
    }
    let mut winding: i32 = -events.iter().map(|&(_, step)| step).sum::<i32>();
    winding = winding.max(0);
    let mut span = Span { inside: winding > 0, crossings: SmallVec::new() };
    for (hit, step) in events {
        let was_inside = winding > 0;
        winding += step;
        if (winding > 0) != was_inside {
            span.crossings.push(PrimHit { inner: solid, ..hit });
        }
    }
    span
}

/// The merge of two operands' spans: each crossing in order of distance toggles its operand's
/// inside-ness, and is kept where it toggles the result's. The two operands' crossings at one
/// distance (faces flush with each other: boxes side by side, a notch cut level with a face)
/// toggle together, and make one crossing or none: two boxes joined face to face have no wall
/// between them.
fn combine(operation: CsgOperation, a: Span, b: Span) -> Span {
    let (mut in_a, mut in_b) = (a.inside, b.inside);
    let mut inside = operation.contains(in_a, in_b);
    let mut out = Span { inside, crossings: SmallVec::new() };
    let (mut i, mut j) = (0, 0);
    while i < a.crossings.len() || j < b.crossings.len() {
        let next_a = a.crossings.get(i).map(|c| c.t);
        let next_b = b.crossings.get(j).map(|c| c.t);
        let (from_a, from_b) = match (next_a, next_b) {
            (Some(ta), Some(tb)) if ta == tb => (true, true),
            (Some(ta), Some(tb)) => (ta < tb, tb < ta),
            (Some(_), None) => (true, false),
            _ => (false, true),
        };
        let was_b = in_b;
        in_a ^= from_a;
        in_b ^= from_b;
        let now = operation.contains(in_a, in_b);
        if now != inside {
            // The crossing whose own toggle changes the result (a's, where either would).
            let a_alone = from_a && operation.contains(in_a, was_b) != inside;
            out.crossings.push(if a_alone || !from_b { a.crossings[i] } else { b.crossings[j] });
            inside = now;
        }
        i += usize::from(from_a);
        j += usize::from(from_b);
    }
    out
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use glam::Mat4;

    use super::*;
    use crate::accel::{Geometry, Object};
    use crate::shapes::test_util::TestRng;
    use crate::shapes::{AaBox, Instance, Mesh, Plane, Sphere, SphereMethod};

    fn sphere(center: Vec3, radius: f32) -> CsgTree {
        CsgTree::solid(Shape::Sphere(Sphere::new(center, radius)))
    }

    fn cube(half: f32) -> CsgTree {
        CsgTree::solid(Shape::AaBox(AaBox::new(Vec3::splat(-half), Vec3::splat(half))))
    }

    fn with_material(tree: CsgTree, material: u32) -> CsgTree {
        match tree {
            CsgTree::Solid(mut s) => {
                s.material = Some(material);
                CsgTree::Solid(s)
            }
            other => other,
        }
    }

    /// A cube of half-size `half` as a closed mesh of twelve triangles in its own BVH, wound
    /// outward (or inward).
    fn cube_mesh(half: f32, outward: bool) -> CsgTree {
        let corners = AaBox::new(Vec3::splat(-half), Vec3::splat(half)).triangles();
        let mut positions = Vec::new();
        let mut indices = Vec::new();
        for [a, b, c] in corners {
            let n = positions.len() as u32;
            positions.extend(if outward { [a, b, c] } else { [a, c, b] });
            indices.push([n, n + 1, n + 2]);
        }
        let mesh = Mesh { positions, indices, ..Mesh::default() };
        let object = Object { name: "cube".into(), shape: Shape::Mesh(mesh), transform: None, material: 0 };
        let geometry = Arc::new(Geometry::new(vec![object], IntersectMethods::default()));
        CsgTree::solid(Shape::Instance(Instance { geometry }))
    }

    fn csg(operation: CsgOperation, operands: Vec<CsgTree>) -> Csg {
        Csg::new(CsgTree::Combine(operation, operands)).expect("a valid expression")
    }

    /// The result's first surface along a ray: distance, normal and solid.
    fn first_hit(c: &Csg, origin: Vec3, direction: Vec3) -> Option<(f32, Vec3, u32)> {
        let ray = Ray::new(origin, direction);
        let hit = c.intersect(&ray, &IntersectMethods::default())?;
        Some((hit.t, c.surface(&ray, &hit).geometric_normal, hit.inner))
    }

    fn close(a: f32, b: f32) -> bool {
        (a - b).abs() < 1e-5
    }

    /// The classic lens: two unit balls whose centres are 1.2 apart overlap in a lens 0.8
    /// thick on their axis and 2(√(1 − x²) − 0.6) at a distance x from it.
    #[test]
    fn lens_is_as_thick_as_its_spheres_overlap() {
        let lens = csg(
            CsgOperation::Intersection,
            vec![sphere(Vec3::new(0.0, 0.0, -0.6), 1.0), sphere(Vec3::new(0.0, 0.0, 0.6), 1.0)],
        );
        for x in [0.0f32, 0.3, 0.7] {
            let (t, normal, solid) = first_hit(&lens, Vec3::new(x, 0.0, -5.0), Vec3::Z).expect("the lens is hit");
            // The near face is the far sphere's (centre +0.6), facing the ray.
            let front = 0.6 - (1.0 - x * x).sqrt();
            assert!(close(t, 5.0 + front), "x = {x}: t = {t}");
            assert_eq!(solid, 1);
            assert!(normal.z < 0.0 && close(normal.length(), 1.0));
            let inside = Vec3::new(x, 0.0, 0.0);
            let (t, normal, solid) = first_hit(&lens, inside, Vec3::Z).expect("the back face from inside");
            assert!(close(t, -front), "x = {x}: from inside, t = {t} (thickness {})", -2.0 * front);
            assert_eq!(solid, 0);
            assert!(normal.z > 0.0);
        }
        // Beyond the rim (x ≥ 0.8) the balls do not overlap.
        assert!(first_hit(&lens, Vec3::new(0.81, 0.0, -5.0), Vec3::Z).is_none());
        let bounds = lens.bounds();
        assert!(bounds.min.abs_diff_eq(Vec3::new(-1.0, -1.0, -0.4), 1e-6), "{bounds:?}");
        assert!(bounds.max.abs_diff_eq(Vec3::new(1.0, 1.0, 0.4), 1e-6), "{bounds:?}");
    }

    /// A cube with a ball carved from its middle: a ray through the centre meets the cube's
    /// face, then the cavity's wall twice, its normals pointing into the cavity (out of the
    /// solid), then the far face.
    #[test]
    fn ray_through_cube_minus_ball_meets_the_cavity_walls_facing_out_of_the_solid() {
        let die = csg(CsgOperation::Difference, vec![cube(1.0), with_material(sphere(Vec3::ZERO, 0.5), 7)]);
        let methods = IntersectMethods::default();
        let ray = Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::X);
        let (inside, crossings) = die.crossings(&ray, &methods);
        assert!(!inside);
        let ts: Vec<f32> = crossings.iter().map(|c| c.t).collect();
        assert_eq!(ts, vec![4.0, 4.5, 5.5, 6.0]);
        let normals: Vec<Vec3> = crossings.iter().map(|c| die.surface(&ray, c).geometric_normal).collect();
        assert_eq!(normals, vec![-Vec3::X, Vec3::X, -Vec3::X, Vec3::X]);
        assert_eq!(
            crossings.iter().map(|c| die.solid_material(c.inner)).collect::<Vec<_>>(),
            [None, Some(7), Some(7), None]
        );
        // From inside the cavity the solid is not around the origin; from inside the wall it is.
        assert!(!die.crossings(&Ray::new(Vec3::ZERO, Vec3::X), &methods).0);
        assert!(die.crossings(&Ray::new(Vec3::new(0.75, 0.0, 0.0), Vec3::X), &methods).0);
        // A ball piercing the top face: straight down, the top is gone and the first surface
        // is the bowl's bottom.
        let bowl = csg(CsgOperation::Difference, vec![cube(1.0), sphere(Vec3::new(0.0, 0.0, 1.0), 0.5)]);
        let (t, normal, solid) = first_hit(&bowl, Vec3::new(0.0, 0.0, 3.0), -Vec3::Z).unwrap();
        assert!(close(t, 2.5) && solid == 1 && normal.abs_diff_eq(Vec3::Z, 1e-6));
    }

    #[test]
    fn union_hides_the_surfaces_inside_it() {
        let pair = csg(
            CsgOperation::Union,
            vec![sphere(Vec3::new(-0.5, 0.0, 0.0), 1.0), sphere(Vec3::new(0.5, 0.0, 0.0), 1.0)],
        );
        let (inside, crossings) =
            pair.crossings(&Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::X), &IntersectMethods::default());
        assert!(!inside);
        assert_eq!(crossings.iter().map(|c| (c.t, c.inner)).collect::<Vec<_>>(), [(3.5, 0), (6.5, 1)]);
    }

    /// A − (B − C): C bounds the result with its own outside, its normal flipped twice.
    #[test]
    fn nested_difference_flips_twice_back() {
        let nested = csg(
            CsgOperation::Difference,
            vec![cube(2.0), CsgTree::Combine(CsgOperation::Difference, vec![cube(1.0), sphere(Vec3::ZERO, 0.5)])],
        );
        let ray = Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::X);
        let (_, crossings) = nested.crossings(&ray, &IntersectMethods::default());
        let seen: Vec<(f32, Vec3)> =
            crossings.iter().map(|c| (c.t, nested.surface(&ray, c).geometric_normal)).collect();
        assert_eq!(
            seen,
            [
                (3.0, -Vec3::X), // the big cube's face
                (4.0, Vec3::X),  // the small cube's, flipped: out of the solid into the hollow
                (4.5, -Vec3::X), // the ball's, flipped twice: the ball is solid again
                (5.5, Vec3::X),
                (6.0, -Vec3::X),
                (7.0, Vec3::X)
            ]
        );
    }

    /// Faces flush with each other: a notch cut level with the cube's top leaves no lid over
    /// it, and two boxes joined face to face have no wall between them, seen from outside or
    /// from inside either.
    #[test]
    fn flush_faces_make_one_surface_or_none() {
        let boxed = |min: [f32; 3], max: [f32; 3]| CsgTree::solid(Shape::AaBox(AaBox::new(min.into(), max.into())));
        let notched = csg(CsgOperation::Difference, vec![cube(1.0), boxed([-0.5, -0.5, 0.5], [0.5, 0.5, 1.0])]);
        let (t, normal, solid) = first_hit(&notched, Vec3::new(0.0, 0.0, 3.0), -Vec3::Z).unwrap();
        assert!(close(t, 2.5) && solid == 1 && normal.abs_diff_eq(Vec3::Z, 1e-6), "{t} {normal} {solid}");
        let pair = csg(
            CsgOperation::Union,
            vec![boxed([-1.0, -1.0, -1.0], [0.0, 1.0, 1.0]), boxed([0.0, -1.0, -1.0], [1.0, 1.0, 1.0])],
        );
        let methods = IntersectMethods::default();
        for (origin, expected) in [(Vec3::new(-3.0, 0.1, 0.2), vec![2.0, 4.0]), (Vec3::new(-0.5, 0.1, 0.2), vec![1.5])]
        {
            let (_, crossings) = pair.crossings(&Ray::new(origin, Vec3::X), &methods);
            assert_eq!(crossings.iter().map(|c| c.t).collect::<Vec<_>>(), expected, "from {origin}");
        }
    }

    /// Operands beyond two: a union of many, and the first minus all the others, each as a
    /// balanced tree.
    #[test]
    fn many_operands_make_a_balanced_tree() {
        let row: Vec<CsgTree> = (0..9).map(|k| sphere(Vec3::new(k as f32 * 3.0, 0.0, 0.0), 1.0)).collect();
        let union = csg(CsgOperation::Union, row);
        let (_, crossings) =
            union.crossings(&Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::X), &IntersectMethods::default());
        assert_eq!(crossings.len(), 18);
        assert!(crossings.windows(2).all(|w| w[0].t < w[1].t));
        let mut operands = vec![cube(1.0)];
        operands.extend((0..5).map(|k| sphere(Vec3::new(-1.0 + 0.5 * k as f32, 1.0, 0.0), 0.2)));
        let notched = csg(CsgOperation::Difference, operands);
        let (t, normal, _) = first_hit(&notched, Vec3::new(0.0, 5.0, 0.0), -Vec3::Y).unwrap();
        assert!(close(t, 4.2) && normal.abs_diff_eq(Vec3::Y, 1e-6), "t = {t}");
        let depth = |csg: &Csg| {
            fn depth(c: &Csg, n: u32) -> usize {
                match c.nodes[n as usize] {
                    Node::Solid(_) => 1,
                    Node::Combine { first, second, .. } => 1 + depth(c, first).max(depth(c, second)),
                }
            }
            depth(csg, csg.root())
        };
        assert_eq!(depth(&union), 5);
    }

    /// A tangent ray grazes a ball in a CSG node exactly as it grazes the ball alone.
    #[test]
    fn tangent_rays_graze_as_the_solid_alone_does() {
        let ball = Sphere::new(Vec3::ZERO, 1.0);
        let node = csg(CsgOperation::Union, vec![sphere(Vec3::ZERO, 1.0), cube_far()]);
        let mut rng = TestRng(5);
        for _ in 0..2000 {
            let d = rng.unit_vector();
            let (s, _) = crate::geometry::orthonormal_basis(d);
            let origin = s - 4.0 * d + rng.range(-1e-6, 1e-6) * s;
            let ray = Ray::new(origin, d);
            for method in [SphereMethod::Algebraic, SphereMethod::Geometric] {
                let methods = IntersectMethods { sphere: method, ..IntersectMethods::default() };
                assert_eq!(node.intersect(&ray, &methods).map(|h| h.t), ball.intersect(&ray, method), "{ray:?}");
            }
        }
    }

    fn cube_far() -> CsgTree {
        CsgTree::solid(Shape::AaBox(AaBox::new(Vec3::splat(10.0), Vec3::splat(11.0))))
    }

    /// Whether `p` lies inside the solid tree: the classification the interval algebra must
    /// agree with, point by point.
    fn contains(tree: &CsgTree, p: Vec3) -> bool {
        match tree {
            CsgTree::Solid(s) => {
                let p = s.transform.map_or(p, |t| t.to_object.transform_point3(p));
                match &s.shape {
                    Shape::Sphere(b) => (p - b.center).length() < b.radius,
                    Shape::AaBox(b) => p.cmpgt(b.min).all() && p.cmplt(b.max).all(),
                    _ => unreachable!(),
                }
            }
            CsgTree::Combine(op, operands) => {
                let first = contains(&operands[0], p);
                let rest = operands[1..].iter().map(|o| contains(o, p));
                match op {
                    CsgOperation::Union => first || rest.into_iter().any(|x| x),
                    CsgOperation::Intersection => first && rest.into_iter().all(|x| x),
                    CsgOperation::Difference => first && !rest.into_iter().any(|x| x),
                }
            }
        }
    }

    fn random_tree(rng: &mut TestRng, depth: u32) -> CsgTree {
        if depth == 0 || rng.range(0.0, 1.0) < 0.3 {
            let c = rng.vec3(-1.0, 1.0);
            let mut solid = if rng.range(0.0, 1.0) < 0.5 {
                CsgSolid::new(Shape::Sphere(Sphere::new(c, rng.range(0.3, 1.0))))
            } else {
                CsgSolid::new(Shape::AaBox(AaBox::new(c - rng.vec3(0.2, 0.8), c + rng.vec3(0.2, 0.8))))
            };
            if rng.range(0.0, 1.0) < 0.3 {
                let turn = Mat4::from_axis_angle(rng.unit_vector(), rng.range(0.0, 3.0));
                solid.transform = Transform::from_matrix(turn * Mat4::from_scale(rng.vec3(0.6, 1.4)));
            }
            return CsgTree::Solid(Box::new(solid));
        }
        let op =
            [CsgOperation::Union, CsgOperation::Intersection, CsgOperation::Difference][(rng.next_u64() % 3) as usize];
        let n = 2 + (rng.next_u64() % 2) as usize;
        CsgTree::Combine(op, (0..n).map(|_| random_tree(rng, depth - 1)).collect())
    }

    /// Interval algebra against point classification on random nested trees: between the
    /// crossings the ray's points are in or out as the spans say, and each crossing's normal
    /// points from the inside out.
    #[test]
    fn crossings_agree_with_point_classification() {
        let mut rng = TestRng(11);
        let methods = IntersectMethods::default();
        let mut checked = 0;
        for _ in 0..300 {
            let tree = random_tree(&mut rng, 4);
            let node = Csg::new(tree.clone()).unwrap();
            for _ in 0..40 {
                let ray = Ray::new(rng.vec3(-2.5, 2.5), rng.unit_vector());
                let (inside, crossings) = node.crossings(&ray, &methods);
                let mut state = inside;
                let mut from = ray.t_min;
                let end = PrimHit::at(ray.t_min + 8.0);
                for (k, c) in crossings.iter().chain([&end]).enumerate() {
                    if c.t - from > 1e-3 {
                        for step in 1..8 {
                            let t = from + (c.t - from) * step as f32 / 8.0;
                            let p = ray.at(t);
                            assert_eq!(contains(&tree, p), state, "{ray:?} at t = {t}: {crossings:?}\n{tree:#?}");
                            checked += 1;
                        }
                    }
                    if k == crossings.len() {
                        break;
                    }
                    let normal = node.surface(&ray, c).geometric_normal;
                    // Entering, the normal faces the ray; leaving, it faces along it.
                    if normal.dot(ray.direction).abs() > 1e-3 {
                        assert_eq!(normal.dot(ray.direction) < 0.0, !state, "{ray:?} at {c:?}");
                    }
                    state = !state;
                    from = c.t;
                }
            }
        }
        assert!(checked > 20_000, "{checked} points checked");
    }

    /// A closed mesh is the same solid as the box it tessellates, wound either way.
    #[test]
    fn closed_mesh_solid_matches_the_box_it_tessellates() {
        let mut rng = TestRng(17);
        let methods = IntersectMethods::default();
        let ball = || sphere(Vec3::new(0.6, 0.2, 0.1), 0.7);
        let by_box = csg(CsgOperation::Difference, vec![cube(1.0), ball()]);
        for outward in [true, false] {
            let by_mesh = csg(CsgOperation::Difference, vec![cube_mesh(1.0, outward), ball()]);
            let mut hits = 0;
            for _ in 0..5000 {
                // Through the inside too: an origin within the solid counts its crossings ahead.
                let origin = rng.vec3(-3.0, 3.0);
                let ray = Ray::new(origin, (rng.vec3(-1.0, 1.0) - origin).normalize_or(Vec3::X));
                let (a, b) = (by_box.crossings(&ray, &methods), by_mesh.crossings(&ray, &methods));
                assert_eq!(a.0, b.0, "inside? {ray:?}");
                assert_eq!(a.1.len(), b.1.len(), "{ray:?}: {a:?} vs {b:?}");
                for (x, y) in a.1.iter().zip(&b.1) {
                    assert!((x.t - y.t).abs() < 1e-4 * x.t.abs().max(1.0), "{ray:?}: {x:?} vs {y:?}");
                    let (nx, ny) = (by_box.surface(&ray, x), by_mesh.surface(&ray, y));
                    assert!(nx.geometric_normal.abs_diff_eq(ny.geometric_normal, 1e-4), "{ray:?}: {nx:?} vs {ny:?}");
                    hits += 1;
                }
            }
            assert!(hits > 2000, "{hits} crossings compared");
        }
        // Rays through a face's diagonal, which its two triangles share (two hits of one sense:
        // one crossing each way), through the cube's corner and along a diagonal through two
        // opposite edges; and a ray grazing the cube's edge from outside (an entering and a
        // leaving face meet there): a touch, no crossing.
        let by_mesh = csg(CsgOperation::Union, vec![cube_mesh(1.0, true), cube_far()]);
        for (origin, direction, expected) in [
            (Vec3::new(0.0, 0.0, -5.0), Vec3::Z, 2),
            (Vec3::new(0.3, 0.3, -5.0), Vec3::Z, 2),
            // (on to the far box, which the diagonal meets too)
            (Vec3::new(-3.0, -3.0, -3.0), Vec3::ONE.normalize(), 4),
            (Vec3::new(-3.0, -3.0, 0.3), Vec3::new(1.0, 1.0, 0.0).normalize(), 2),
            (Vec3::new(-3.0, 1.0, 0.0), Vec3::new(1.0, -1.0, 0.0).normalize(), 0),
        ] {
            let (inside, crossings) = by_mesh.crossings(&Ray::new(origin, direction), &methods);
            assert_eq!((inside, crossings.len()), (false, expected), "{origin} {direction}: {crossings:?}");
        }
    }

    #[test]
    fn open_shapes_are_refused_by_name() {
        let plane = CsgTree::solid(Shape::Plane(Plane::new(Vec3::Y, 0.0)));
        let err = Csg::new(CsgTree::Combine(CsgOperation::Union, vec![cube(1.0), plane])).unwrap_err();
        assert_eq!(err, CsgError::OpenShape("plane"));
        assert!(err.to_string().contains("plane bounds no solid"));
        // A cube mesh missing a face.
        let corners = AaBox::new(Vec3::splat(-1.0), Vec3::ONE).triangles();
        let positions: Vec<Vec3> = corners[..10].iter().flatten().copied().collect();
        let indices = (0..10).map(|k| [3 * k, 3 * k + 1, 3 * k + 2]).collect();
        let open = Mesh { positions, indices, ..Mesh::default() };
        assert_eq!(open.enclosed_volume(), None);
        let object = Object { name: "open".into(), shape: Shape::Mesh(open), transform: None, material: 0 };
        let geometry = Arc::new(Geometry::new(vec![object], IntersectMethods::default()));
        let solid = CsgTree::solid(Shape::Instance(Instance { geometry }));
        assert_eq!(Csg::new(solid).unwrap_err(), CsgError::OpenMesh);
        assert_eq!(
            Csg::new(CsgTree::Combine(CsgOperation::Difference, vec![])).unwrap_err(),
            CsgError::NoOperands("difference")
        );
        let mut deep = cube(1.0);
        for _ in 0..=MAX_DEPTH {
            deep = CsgTree::Combine(CsgOperation::Union, vec![deep, cube_far()]);
        }
        assert_eq!(Csg::new(deep).unwrap_err(), CsgError::TooDeep);
    }

    #[test]
    fn enclosed_volume_of_a_welded_cube() {
        let volume = |tree: CsgTree| match tree {
            CsgTree::Solid(solid) => match solid.shape {
                Shape::Instance(i) => i.geometry.enclosed_volume().unwrap(),
                _ => unreachable!(),
            },
            _ => unreachable!(),
        };
        let outward = volume(cube_mesh(1.5, true));
        assert!((outward - 27.0).abs() < 1e-9, "{outward}");
        assert!((volume(cube_mesh(1.5, false)) + 27.0).abs() < 1e-9);
    }
}
