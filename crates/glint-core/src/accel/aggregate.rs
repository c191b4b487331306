//! The scene's objects and the acceleration structure over them: the closest-primitive and
//! any-hit queries on which every integrator's rays run (`scene::hit` turns a closest
//! primitive into the surface record integrators shade).

use glam::Vec3;

use super::{
    Bvh, Bvh8, BvhStats, NoCounter, TraversalCounter, TraversalCounts, Triangle8, WatertightRay8, EMPTY, GENERIC, LANES,
};
use crate::geometry::{Aabb, Ray, Transform};
use crate::lanes::Vec3x8;
use crate::shapes::{
    intersect_cramer, moller_trumbore_edges, InstancedGeometry, IntersectMethods, PrimHit, Shape, SurfaceGeometry,
    TriangleMethod,
};
use crate::textures::{MeshPoint, TextureQuery};

/// A shape placed in the scene with a material and, optionally, a transform (object → world).
#[derive(Clone, Debug)]
pub struct Object {
    pub name: String,
    pub shape: Shape,
    pub transform: Option<Transform>,
    pub material: u32,
}

impl Object {
    fn world_bounds(&self, prim: u32) -> Option<Aabb> {
        let b = self.shape.bounds(prim)?;
        Some(match &self.transform {
            None => b,
            Some(t) => Aabb::from_points(b.corners().map(|c| t.point(c))),
        })
    }

    #[inline]
    pub(crate) fn intersect(&self, prim: u32, ray: &Ray, methods: &IntersectMethods) -> Option<PrimHit> {
        match &self.transform {
            None => self.shape.intersect(prim, ray, methods),
            Some(t) => self.shape.intersect(prim, &t.ray_to_object(ray), methods),
        }
    }

    /// The material where a hit's inner primitive is `inner`: a CSG solid's own, if it has
    /// one, else the object's.
    #[inline]
    pub fn material_at(&self, inner: u32) -> u32 {
        match &self.shape {
            Shape::Csg(csg) => csg.solid_material(inner).unwrap_or(self.material),
            _ => self.material,
        }
    }

    /// (∂p/∂u, ∂p/∂v) in world space at a point of primitive `prim` (`Shape::tangents`).
    pub(crate) fn tangents(&self, prim: u32, surface: &SurfaceGeometry) -> (Vec3, Vec3) {
        match &self.transform {
            None => self.shape.tangents(prim, surface.point, surface.geometric_normal),
            Some(t) => {
                let local_normal = glam::Mat3::from_mat4(t.to_world).transpose() * surface.geometric_normal;
                let local_point = t.to_object.transform_point3(surface.point);
                let (dpdu, dpdv) = self.shape.tangents(prim, local_point, local_normal);
                (t.vector(dpdu), t.vector(dpdv))
            }
        }
    }

    /// What a texture reads at `point` (world space) on primitive `prim`, a point no ray found
    /// (one sampled on a light); a triangle's point also by its barycentric coordinates (of
    /// its second and third corners) in `hit`. `None` for an instance.
    pub(crate) fn texture_query_at(&self, prim: u32, point: Vec3, hit: &PrimHit) -> Option<TextureQuery<'_>> {
        let (local, object_point) = match (&self.transform, &self.shape) {
            (Some(t), _) => {
                let local = t.to_object.transform_point3(point);
                (local, local)
            }
            (None, Shape::Mesh(m)) => (point, m.object_point(point)),
            (None, _) => (point, point),
        };
        let surface = match &self.shape {
            // The instanced geometry is one object (a mesh), its primitive `prim`.
            Shape::Instance(i) => i.geometry.surface_at(0, prim, local, hit)?,
            shape => shape.surface_at(prim, local, hit)?,
        };
        let mesh = self.mesh_point(prim, || local);
        let normal = match &self.transform {
            Some(t) => t.normal(surface.geometric_normal),
            None => surface.geometric_normal,
        };
        Some(TextureQuery {
            uv: surface.uv,
            point: object_point,
            world_point: point,
            normal,
            dpdu: Vec3::ZERO,
            dpdv: Vec3::ZERO,
            mesh,
        })
    }

    /// The point on triangle `prim` of a mesh with attributes (in the space of its vertices,
    /// from `local`, asked only then), for `mesh-attribute` textures; `None` on other shapes.
    #[inline]
    pub(crate) fn mesh_point(&self, prim: u32, local: impl FnOnce() -> Vec3) -> Option<MeshPoint<'_>> {
        match &self.shape {
            Shape::Mesh(m) if !m.attributes.is_empty() => Some(MeshPoint { mesh: m, triangle: prim, point: local() }),
            _ => None,
        }
    }

    pub(crate) fn surface(&self, prim: u32, ray: &Ray, hit: &PrimHit) -> SurfaceGeometry {
        match &self.transform {
            None => self.shape.surface(prim, ray, hit),
            Some(t) => {
                let local_ray = t.ray_to_object(ray);
                let local = match &self.shape {
                    Shape::AaBox(b) => b.surface_within(local_ray.at(hit.t), t.round_trip_margin(local_ray.at(hit.t))),
                    shape => shape.surface(prim, &local_ray, hit),
                };
                local.placed(t)
            }
        }
    }
}

/// The corners of primitive `prim` of `object` if it is a triangle in world space (a mesh's or
/// a triangle's, without a transform).
#[inline]
fn world_triangle(object: &Object, prim: u32) -> Option<[Vec3; 3]> {
    match (&object.shape, &object.transform) {
        (Shape::Mesh(m), None) => Some(m.triangle_vertices(prim as usize)),
        (Shape::Triangle(t), None) => Some(t.vertices),
        _ => None,
    }
}

/// The vertex normals of primitive `prim` of `object` if it is a triangle in world space that
/// has them.
#[inline]
fn world_normals(object: &Object, prim: u32) -> Option<[Vec3; 3]> {
    match (&object.shape, &object.transform) {
        (Shape::Mesh(m), None) => m.triangle_normals(prim as usize),
        (Shape::Triangle(t), None) => t.normals,
        _ => None,
    }
}

/// Which primitive a ray hit (primitive `prim` of object `object`) and where on it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrimitiveHit {
    pub object: u32,
    pub prim: u32,
    pub at: PrimHit,
}

impl PrimitiveHit {
    /// A placeholder before a query.
    pub const NONE: Self = Self { object: u32::MAX, prim: u32::MAX, at: PrimHit { t: 0.0, u: 0.0, v: 0.0, inner: 0 } };

    /// The primitive that emits where the hit is an emitter's (the one inside an instance,
    /// which is one primitive of the scene's: as `SurfaceHit::prim` counts it).
    #[inline]
    pub fn emitting_prim(&self) -> u32 {
        self.prim + self.at.inner
    }
}

/// Objects and the acceleration structure over them: the closest-hit and any-hit queries.
///
/// Built once: a binned-SAH binary BVH, converted to an 8-wide BVH for traversal whose leaves
/// are blocks of eight primitives (`Triangle8`). Triangles without a transform (mesh triangles,
/// plain triangles) are copied into the blocks as their vertices, lane by lane, so a leaf test
/// reads contiguous records and tests eight triangles at once instead of chasing object → mesh
/// → index → vertex. (Vertices, not edges: the watertight test needs the exact vertices that
/// neighbouring triangles share.) Other primitives sit in the blocks as `GENERIC` lanes and
/// are tested one by one through their object.
pub struct Geometry {
    objects: Vec<Object>,
    methods: IntersectMethods,
    /// The BVH's leaf blocks, in the order the wide tree references them.
    blocks: Vec<Triangle8>,
    /// (object, primitive) of the `GENERIC` lanes, by the index in their lane id.
    generic: Vec<(u32, u32)>,
    /// The id of each object's first primitive: triangle lane ids number the primitives of all
    /// objects in order.
    object_first: Vec<u32>,
    /// The object of each id, when there is more than one object (4 bytes a primitive): one
    /// load instead of a binary search over `object_first`, whose dependent loads each closest
    /// hit waited on (about 2 % of the Cornell box's render time).
    object_of: Vec<u32>,
    /// Where each triangle sits in the blocks (block · 8 + lane), by its lane id (4 bytes a
    /// primitive, `u32::MAX` for those tested through their object): a hit triangle's corners
    /// are read from the block its query has just tested, not from its object (which sat
    /// outside the L1 cache in the Cornell box's wavefront).
    slot_of: Vec<u32>,
    /// Primitives without bounds (planes), tested on every ray.
    unbounded: Vec<(u32, u32)>,
    /// Every lane of every block is a triangle (or empty): with the watertight method a block
    /// is the SIMD test alone, with no lane for the scalar path to look at.
    triangles_only: bool,
    /// Some triangle in world space has vertex normals (`triangle_normals` can be `Some`).
    vertex_normals: bool,
    bvh: Bvh8,
    bounds: Aabb,
    stats: BvhStats,
    build_time: std::time::Duration,
}

impl Geometry {
    pub fn new(objects: Vec<Object>, methods: IntersectMethods) -> Self {
        let start = std::time::Instant::now();
        let mut bounded = Vec::new();
        let mut bounds = Vec::new();
        let mut unbounded = Vec::new();
        let mut object_first = Vec::with_capacity(objects.len());
        let mut ids = 0u64;
        for (o, object) in objects.iter().enumerate() {
            object_first.push(ids as u32);
            let count = object.shape.primitive_count();
            ids += u64::from(count);
            assert!(ids < u64::from(EMPTY), "more than 2^31 - 1 primitives in one scene");
            for p in 0..count {
                match object.world_bounds(p) {
                    Some(b) => {
                        bounded.push((o as u32, p));
                        bounds.push(b);
                    }
                    None => unbounded.push((o as u32, p)),
                }
            }
        }
        let object_of = if objects.len() > 1 {
            objects
                .iter()
                .enumerate()
                .flat_map(|(o, object)| std::iter::repeat_n(o as u32, object.shape.primitive_count() as usize))
                .collect()
        } else {
            Vec::new()
        };
        let world_bounds = bounds.iter().fold(Aabb::EMPTY, |a, b| a.union(*b));
        // The vertices of a plain triangle (no transform), which the blocks test eight at a time.
        let vertices = |(o, p): (u32, u32)| world_triangle(&objects[o as usize], p);
        let alone: Vec<bool> = bounded.iter().map(|&id| vertices(id).is_none()).collect();
        let (binary, mut order) = Bvh::build_mixed(&bounds, |i| alone[i]);
        drop(bounds);
        let mut stats = binary.stats();
        let mut blocks = Vec::with_capacity(order.len() / 3 + 1);
        let mut generic = Vec::new();
        let mut slot_of = vec![u32::MAX; ids as usize];
        let bvh = Bvh8::from_binary_with_leaves(&binary, |first, count| {
            let block_first = blocks.len() as u32;
            // Triangles first: a block with any triangle has one in lane 0, and a block of
            // other primitives only skips the SIMD test.
            let leaf = &mut order[first as usize..(first + count) as usize];
            leaf.sort_by_key(|&i| alone[i as usize]);
            for chunk in leaf.chunks(LANES) {
                let mut block = Triangle8::empty();
                for (lane, &i) in chunk.iter().enumerate() {
                    let (o, p) = bounded[i as usize];
                    match vertices((o, p)) {
                        Some(v) => {
                            let id = object_first[o as usize] + p;
                            block.set_triangle(lane, id, v);
                            slot_of[id as usize] =
                                u32::try_from(blocks.len() * LANES + lane).expect("fewer than 2^32 block lanes");
                        }
                        None => {
                            block.set_generic(lane, generic.len() as u32);
                            generic.push((o, p));
                        }
                    }
                }
                blocks.push(block);
            }
            (block_first, blocks.len() as u32 - block_first)
        });
        drop(binary);
        stats.wide_nodes = bvh.node_count();
        stats.leaf_blocks = blocks.len();
        stats.bytes = bvh.bytes()
            + blocks.len() * std::mem::size_of::<Triangle8>()
            + generic.len() * std::mem::size_of::<(u32, u32)>()
            + (object_first.len() + object_of.len() + slot_of.len()) * std::mem::size_of::<u32>();
        let triangles_only = generic.is_empty();
        // A mesh has normals at every vertex or at none: its first triangle tells.
        let vertex_normals = objects.iter().any(|o| o.shape.primitive_count() > 0 && world_normals(o, 0).is_some());
        Self {
            objects,
            methods,
            triangles_only,
            vertex_normals,
            blocks,
            generic,
            object_first,
            object_of,
            slot_of,
            unbounded,
            bvh,
            bounds: world_bounds,
            stats,
            build_time: start.elapsed(),
        }
    }

    /// Bounds of every bounded primitive (planes are not included).
    pub fn objects(&self) -> &[Object] {
        &self.objects
    }

    pub fn methods(&self) -> IntersectMethods {
        self.methods
    }

    /// Which algorithm each shape's intersection uses; the tree does not depend on it.
    pub fn set_methods(&mut self, methods: IntersectMethods) {
        self.methods = methods;
    }

    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// (∂p/∂u, ∂p/∂v) in world space at `surface` on primitive `prim` of object `object`.
    pub fn tangents(&self, object: u32, prim: u32, surface: &SurfaceGeometry) -> (Vec3, Vec3) {
        self.objects[object as usize].tangents(prim, surface)
    }

    /// The surface of primitive `prim` of object `object` for a hit found on `ray`.
    pub fn primitive_surface(&self, object: u32, prim: u32, ray: &Ray, hit: &PrimHit) -> SurfaceGeometry {
        self.objects[object as usize].surface(prim, ray, hit)
    }

    pub fn primitive_count(&self) -> usize {
        self.objects.iter().map(|o| o.shape.primitive_count() as usize).sum()
    }

    /// Shape of the binary build (nodes, leaves, depth, SAH cost) and the memory of the
    /// traversal structures (wide nodes + leaf records).
    pub fn bvh_stats(&self) -> BvhStats {
        self.stats
    }

    /// Time taken to gather primitive bounds, build the BVH and lay out the leaves.
    pub fn build_time(&self) -> std::time::Duration {
        self.build_time
    }

    /// Whether every primitive is a triangle in world space (mesh triangles and triangle
    /// shapes without a transform): then `triangle` gives the corners of any hit.
    pub fn all_triangles(&self) -> bool {
        self.triangles_only && self.unbounded.is_empty()
    }

    /// The corners of primitive `prim` of `object`, if it is a triangle in world space (read
    /// from its leaf block, see `slot_of`).
    #[inline]
    pub fn triangle(&self, object: u32, prim: u32) -> Option<[Vec3; 3]> {
        let slot = self.slot(object, prim)?;
        Some([0, 1, 2].map(|corner| self.slot_corner(slot, corner)))
    }

    /// Where primitive `prim` of `object` lies in the leaf blocks, if it is a triangle in world
    /// space (block `slot / LANES`, lane `slot % LANES`).
    #[inline(always)]
    fn slot(&self, object: u32, prim: u32) -> Option<usize> {
        let slot = self.slot_of[(self.object_first[object as usize] + prim) as usize];
        (slot != u32::MAX).then_some(slot as usize)
    }

    /// Corner `corner` of the triangle at `slot`.
    #[inline(always)]
    fn slot_corner(&self, slot: usize, corner: usize) -> Vec3 {
        self.blocks[slot / LANES].vertex(slot % LANES, corner)
    }

    /// The corners of eight triangles in world space, primitive `prims[k].1` of object
    /// `prims[k].0` in lane k, read from their leaf blocks straight into the lanes; `None` if
    /// one is not such a triangle.
    #[inline]
    pub(crate) fn triangles8(&self, prims: [(u32, u32); LANES]) -> Option<[Vec3x8; 3]> {
        let slots = prims.map(|(object, prim)| self.slot(object, prim));
        if slots.contains(&None) {
            return None;
        }
        let slots = slots.map(|slot| slot.unwrap_or_default());
        Some([0, 1, 2].map(|corner| Vec3x8::from_fn(|k| self.slot_corner(slots[k], corner))))
    }

    /// Whether some triangle in world space has vertex normals (else `triangle_normals` is
    /// always `None`).
    pub fn has_vertex_normals(&self) -> bool {
        self.vertex_normals
    }

    /// The vertex normals of primitive `prim` of `object`, if it is a triangle in world space
    /// with them.
    #[inline]
    pub fn triangle_normals(&self, object: u32, prim: u32) -> Option<[Vec3; 3]> {
        world_normals(&self.objects[object as usize], prim)
    }

    /// Whether a block is the SIMD test alone. Asked per query, not fixed at build: the
    /// triangle method can be changed after (`--triangle-method`).
    #[inline(always)]
    fn simd_only(&self) -> bool {
        self.triangles_only && self.methods.triangle == TriangleMethod::Watertight
    }

    /// (object, primitive) of a lane id.
    #[inline]
    fn locate(&self, id: u32) -> (u32, u32) {
        if id & GENERIC != 0 {
            return self.generic[(id & !GENERIC) as usize];
        }
        let o = self.object_of.get(id as usize).map_or(0, |&o| o as usize);
        (o as u32, id - self.object_first[o])
    }

    /// The nearest hit among the lanes of leaf block `b`: its lane id and hit, and the lane
    /// when the eight-lane watertight test found it (its distance still the test's own; see
    /// `refine_kept_hit`).
    #[inline(always)]
    fn closest_in_block(&self, b: u32, ray: &Ray, prepared: &WatertightRay8) -> Option<(u32, PrimHit, Option<usize>)> {
        let block = &self.blocks[b as usize];
        if self.simd_only() {
            let (lane, hit) = prepared.intersect(block, ray.t_min, ray.t_max).nearest()?;
            return Some((block.ids[lane], hit, Some(lane)));
        }
        let mut best = None;
        let mut ray = *ray;
        if self.methods.triangle == TriangleMethod::Watertight && block.has_triangles() {
            if let Some((lane, hit)) = prepared.intersect(block, ray.t_min, ray.t_max).nearest() {
                ray.t_max = hit.t;
                best = Some((block.ids[lane], hit, Some(lane)));
            }
            if !block.has_generic() {
                return best;
            }
        }
        for (lane, id) in block.lanes() {
            if let Some(hit) = self.intersect_lane(block, lane, id, &ray) {
                ray.t_max = hit.t;
                best = Some((id, hit, None));
            }
        }
        best
    }

    /// The hit a closest-hit query keeps, at its distance from the triangle's plane where the
    /// eight-lane test found it (`WatertightRay8::refined`: the edge functions' own distance
    /// is ill-conditioned on needles), if that lies within (t_min, t_max), the ray's range when
    /// the query began; else as it is. Once per query: per block with a hit, the f64
    /// arithmetic cost the dragon's primary rays 7 % of their speed.
    #[inline(always)]
    fn refine_kept_hit(
        &self,
        prepared: &WatertightRay8,
        (b, lane): (u32, Option<usize>),
        hit: PrimHit,
        (t_min, t_max): (f32, f32),
    ) -> PrimHit {
        match lane {
            Some(lane) => prepared.refined(&self.blocks[b as usize], lane, hit, t_min, t_max).unwrap_or(hit),
            None => hit,
        }
    }

    /// Whether some lane of leaf block `b` is hit.
    #[inline(always)]
    fn any_in_block(&self, b: u32, ray: &Ray, prepared: &WatertightRay8) -> bool {
        let block = &self.blocks[b as usize];
        if self.simd_only() {
            return prepared.intersect(block, ray.t_min, ray.t_max).mask != 0;
        }
        if self.methods.triangle == TriangleMethod::Watertight && block.has_triangles() {
            if prepared.intersect(block, ray.t_min, ray.t_max).mask != 0 {
                return true;
            }
            if !block.has_generic() {
                return false;
            }
        }
        block.lanes().any(|(lane, id)| self.intersect_lane(block, lane, id, ray).is_some())
    }

    /// One lane by the scalar path: generic primitives always, triangles only when the chosen
    /// triangle method is not the watertight test (which the SIMD path has already run).
    fn intersect_lane(&self, block: &Triangle8, lane: usize, id: u32, ray: &Ray) -> Option<PrimHit> {
        if id & GENERIC != 0 {
            let (o, p) = self.generic[(id & !GENERIC) as usize];
            return self.objects[o as usize].intersect(p, ray, &self.methods);
        }
        match self.methods.triangle {
            TriangleMethod::Watertight => None,
            TriangleMethod::MollerTrumbore => {
                let [a, b, c] = block.triangle(lane);
                moller_trumbore_edges(a, b - a, c - a, ray)
            }
            TriangleMethod::Cramer => {
                let [a, b, c] = block.triangle(lane);
                intersect_cramer(a, b, c, ray)
            }
        }
    }

    /// The nearest primitive and its distance, without building the surface record; `ray.t_max`
    /// becomes the hit's distance.
    #[inline]
    pub fn closest_primitive(&self, ray: &mut Ray) -> Option<((u32, u32), PrimHit)> {
        let mut found = PrimitiveHit::NONE;
        self.closest_primitive_into(ray, &mut found).then_some(((found.object, found.prim), found.at))
    }

    /// `closest_primitive` written into `found` (left as it was if nothing is hit), for callers
    /// that keep the answer: a returned answer is copied from the query's stack, and that
    /// copy's loads spanned the query's narrower stores, a stall (store forwarding fails) of
    /// every query.
    #[inline]
    pub fn closest_primitive_into(&self, ray: &mut Ray, found: &mut PrimitiveHit) -> bool {
        if self.bvh.is_one_node() {
            self.closest_primitive_counted::<true, _>(ray, &mut NoCounter, found)
        } else {
            self.closest_primitive_counted::<false, _>(ray, &mut NoCounter, found)
        }
    }

    /// `closest_primitive_into` for each ray, the same answers to the bit, with several rays'
    /// traversals interleaved so that their waits for memory overlap
    /// (`Bvh8::closest_interleaved`): for batches of incoherent rays. `found[i]` receives ray
    /// `i`'s hit, or `PrimitiveHit::NONE`, and each ray's `t_max` becomes its hit's distance.
    pub fn closest_primitives(&self, rays: &mut [Ray], found: &mut [PrimitiveHit]) {
        assert_eq!(rays.len(), found.len(), "one answer per ray");
        if self.bvh.is_one_node() || !self.unbounded.is_empty() {
            for (ray, found) in rays.iter_mut().zip(found.iter_mut()) {
                *found = PrimitiveHit::NONE;
                self.closest_primitive_into(ray, found);
            }
            return;
        }
        self.bvh.closest_interleaved(
            rays,
            |_, ray| (WatertightRay8::for_ray(ray), (ray.t_min, ray.t_max), None),
            |(prepared, _, best_lane), b, ray| {
                let (id, h, lane) = self.closest_in_block(b, ray, prepared)?;
                *best_lane = Some((id, h, (b, lane)));
                Some(h.t)
            },
            |i, (prepared, range, best_lane), ray| {
                found[i] = match best_lane {
                    Some((id, h, at)) => {
                        let at = self.refine_kept_hit(&prepared, at, h, range);
                        ray.t_max = at.t;
                        let (object, prim) = self.locate(id);
                        PrimitiveHit { object, prim, at }
                    }
                    None => PrimitiveHit::NONE,
                }
            },
            |b| super::wide::prefetch_lines(&self.blocks[b as usize]),
        );
    }

    /// The traversal work of a closest-hit query (for the BVH heat map and `bench-rays`).
    pub fn traversal_counts(&self, ray: &Ray) -> TraversalCounts {
        let mut counts = TraversalCounts::default();
        let (mut ray, mut found) = (*ray, PrimitiveHit::NONE);
        self.closest_primitive_counted::<false, _>(&mut ray, &mut counts, &mut found);
        counts
    }

    /// The nearest primitive, its traversal counted (`ONE_NODE` as for `Bvh8::any`).
    #[inline]
    fn closest_primitive_counted<const ONE_NODE: bool, C: TraversalCounter>(
        &self,
        ray: &mut Ray,
        counter: &mut C,
        found: &mut PrimitiveHit,
    ) -> bool {
        counter.primitives(self.unbounded.len() as u32);
        let mut best: Option<((u32, u32), PrimHit)> = None;
        for &(o, p) in &self.unbounded {
            if let Some(h) = self.objects[o as usize].intersect(p, ray, &self.methods) {
                ray.t_max = h.t;
                best = Some(((o, p), h));
            }
        }
        let mut best_lane = None;
        let mut tested = 0;
        let prepared = WatertightRay8::for_ray(ray);
        let range = (ray.t_min, ray.t_max);
        self.bvh.closest_counted::<ONE_NODE, C>(
            ray,
            |b, ray| {
                if C::ACTIVE {
                    tested += self.blocks[b as usize].lanes().count() as u32;
                }
                let (id, h, lane) = self.closest_in_block(b, ray, &prepared)?;
                best_lane = Some((id, h, (b, lane)));
                Some(h.t)
            },
            |b| super::wide::prefetch_lines(&self.blocks[b as usize]),
            counter,
        );
        counter.primitives(tested);
        if let Some((id, h, at)) = best_lane {
            let h = self.refine_kept_hit(&prepared, at, h, range);
            ray.t_max = h.t;
            best = Some((self.locate(id), h));
        }
        let Some(((object, prim), at)) = best else { return false };
        *found = PrimitiveHit { object, prim, at };
        true
    }

    /// Whether some unbounded primitive lies along the ray. Out of line: inlined, its set-up
    /// ran before every shadow ray even in scenes without planes (2 % of the Cornell box's
    /// instructions). Closest hit keeps its loop inline: out of line, it cost the dragon's
    /// primary rays 8 % of their speed.
    #[inline(never)]
    fn unbounded_occludes(&self, ray: &Ray) -> bool {
        self.unbounded.iter().any(|&(o, p)| self.objects[o as usize].intersect(p, ray, &self.methods).is_some())
    }

    /// Whether anything lies along the ray within `(t_min, t_max)`; stops at the first hit.
    pub fn occluded(&self, ray: &Ray) -> bool {
        (!self.unbounded.is_empty() && self.unbounded_occludes(ray)) || {
            if self.bvh.is_one_node() {
                let prepared = WatertightRay8::for_ray(ray);
                self.bvh.any::<true>(ray, |b, ray| self.any_in_block(b, ray, &prepared))
            } else {
                self.occluded_in_tree(ray)
            }
        }
    }

    /// Every triangle in world space the ray meets within `(t_min, t_max)`, in no order: the
    /// hit (`inner` the primitive's index among the scene's, `object_first` counting) and
    /// whether the ray leaves along the winding's normal. The any-hit traversal, never told
    /// to stop.
    pub fn crossings(&self, ray: &Ray, found: &mut dyn FnMut(PrimHit, bool)) {
        let prepared = WatertightRay8::for_ray(ray);
        let mut report = |block: &Triangle8, lane: usize, id: u32, hit: PrimHit| {
            let [a, b, c] = block.triangle(lane);
            found(PrimHit { inner: id, ..hit }, (b - a).cross(c - a).dot(ray.direction) > 0.0);
        };
        self.bvh.any::<false>(ray, |b, ray| {
            let block = &self.blocks[b as usize];
            if self.methods.triangle == TriangleMethod::Watertight && block.has_triangles() {
                let hits = prepared.intersect(block, ray.t_min, ray.t_max);
                let mut mask = hits.mask;
                while mask != 0 {
                    let lane = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    let (u, v) = (hits.u.as_array_ref()[lane], hits.v.as_array_ref()[lane]);
                    let hit = PrimHit { t: hits.t[lane], u, v, inner: 0 };
                    if let Some(hit) = prepared.refined(block, lane, hit, ray.t_min, ray.t_max) {
                        report(block, lane, block.ids[lane], hit);
                    }
                }
            }
            for (lane, id) in block.lanes().filter(|&(_, id)| id & GENERIC == 0) {
                if let Some(hit) = self.intersect_lane(block, lane, id, ray) {
                    report(block, lane, id, hit);
                }
            }
            false
        });
    }

    /// `occluded` in a tree of more than one node (out of line, and so is its leaf test: see
    /// `Bvh8::any`).
    #[inline(never)]
    fn occluded_in_tree(&self, ray: &Ray) -> bool {
        let prepared = WatertightRay8::for_ray(ray);
        self.bvh.any::<false>(ray, |b, ray| self.any_in_block(b, ray, &prepared))
    }
}

/// What an instance places (`shapes::Instance`): the aggregate seen through the shapes' own
/// interface, so the shapes need not know it.
impl InstancedGeometry for Geometry {
    fn bounds(&self) -> Aabb {
        Geometry::bounds(self)
    }

    #[inline]
    fn closest_primitive(&self, ray: &mut Ray) -> Option<((u32, u32), PrimHit)> {
        Geometry::closest_primitive(self, ray)
    }

    fn primitive_surface(&self, object: u32, prim: u32, ray: &Ray, hit: &PrimHit) -> SurfaceGeometry {
        Geometry::primitive_surface(self, object, prim, ray, hit)
    }

    fn primitive_count(&self) -> usize {
        Geometry::primitive_count(self)
    }

    fn triangle_corners(&self, object: u32, prim: u32) -> Option<[Vec3; 3]> {
        world_triangle(self.objects().get(object as usize)?, prim)
    }

    fn surface_at(&self, object: u32, prim: u32, point: Vec3, hit: &PrimHit) -> Option<SurfaceGeometry> {
        let object = self.objects().get(object as usize)?;
        match object.transform {
            None => object.shape.surface_at(prim, point, hit),
            Some(_) => None,
        }
    }

    fn crossings(&self, ray: &Ray, found: &mut dyn FnMut(PrimHit, bool)) {
        Geometry::crossings(self, ray, found);
    }

    fn enclosed_volume(&self) -> Option<f64> {
        match self.objects() {
            [Object { shape: Shape::Mesh(mesh), transform: None, .. }] => mesh.enclosed_volume(),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::{Mat4, Vec2};

    use super::*;
    use crate::shapes::{AaBox, IntersectMethods, Plane, Polygon, Sphere, Triangle};

    /// ∂p/∂u and ∂p/∂v mean what they say on every shape, with and without a transform: a step
    /// of h·∂p/∂u from a hit moves the uv by (h, 0) to first order, one of h·∂p/∂v by (0, h).
    /// Each shape is hit by a ray, then by a second ray aimed at the stepped point.
    #[test]
    fn tangents_are_the_derivatives_of_the_point_along_u_and_v() {
        let mut textured =
            Triangle::new(Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.2, -0.8, 0.1), Vec3::new(0.1, 1.0, -0.2));
        textured.uvs = Some([Vec2::new(0.1, 0.2), Vec2::new(0.9, 0.3), Vec2::new(0.4, 0.95)]);
        let polygon =
            Polygon::new(vec![Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.2), Vec3::new(0.0, 1.0, 0.1)])
                .unwrap()
                .with_uvs(vec![Vec2::new(0.0, 0.0), Vec2::new(2.0, 0.5), Vec2::new(0.5, 1.5)])
                .unwrap();
        let shapes = [
            ("sphere", Shape::Sphere(Sphere::new(Vec3::new(0.1, 0.2, 0.3), 1.2))),
            ("plain triangle", Shape::Triangle(Triangle::new(Vec3::new(-1.0, -1.0, 0.0), Vec3::X, Vec3::Y))),
            ("textured triangle", Shape::Triangle(textured)),
            ("plane", Shape::Plane(Plane::new(Vec3::new(0.0, 0.3, -1.0).normalize(), 0.5))),
            ("polygon with uvs", Shape::Polygon(polygon)),
            ("box", Shape::AaBox(AaBox::new(Vec3::splat(-0.7), Vec3::new(0.5, 0.8, 0.6)))),
        ];
        let placed = Transform::from_matrix(
            Mat4::from_rotation_y(0.4) * Mat4::from_scale(Vec3::new(1.3, 0.7, 1.1)) * Mat4::from_rotation_x(0.3),
        );
        let methods = IntersectMethods::default();
        let origin = Vec3::new(0.15, 0.1, -4.0);
        for (name, shape) in shapes {
            for transform in [None, placed] {
                let object = Object { name: name.into(), shape: shape.clone(), transform, material: 0 };
                let surface = |target: Vec3| {
                    let ray = Ray::new(origin, (target - origin).normalize());
                    let hit = object.intersect(0, &ray, &methods).expect("the ray hits");
                    object.surface(0, &ray, &hit)
                };
                let s = surface(Vec3::new(0.1, 0.05, 0.0));
                let (dpdu, dpdv) = object.tangents(0, &s);
                let placed = if transform.is_some() { "placed" } else { "as is" };
                for (along, tangent, expected) in [("u", dpdu, Vec2::X), ("v", dpdv, Vec2::Y)] {
                    assert!(tangent.length() > 0.0, "{name}, {along}");
                    let h = 1e-3 / tangent.length();
                    let stepped = surface(s.point + h * tangent);
                    let moved = (stepped.uv - s.uv) / h;
                    assert!(
                        (moved - expected).abs().max_element() < 0.02,
                        "{name}, {placed}: Δuv / h along {along} = {moved}"
                    );
                }
            }
        }
    }
}
