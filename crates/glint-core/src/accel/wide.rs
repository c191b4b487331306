//! An 8-wide BVH for traversal, converted from the binary SAH build (tinybvh's "build apart from
//! traversal"): each node holds the boxes of up to eight children in SIMD-friendly order, all
//! eight tested at once (`wide`'s `f32x8`: one AVX register, two SSE halves without AVX).
//! Eight beat four on the bunny by 4 % (primary rays) to 20 % (random rays): half the levels,
//! so fewer dependent loads per ray (docs/performance.md).
//!
//! The box test chooses each axis's near and far plane by the sign of the ray direction (the
//! ray's octant), so it needs no min/max per axis, an empty slot (min = +∞, max = −∞) can never
//! be entered, and the NaN of 0 · ∞ (a ray in a slab's plane) is dropped by the max/min
//! ordering, which keeps the test conservative.

use std::mem::MaybeUninit;

use glam::Vec3;
use wide::{f32x8, CmpGt, CmpLe, CmpLt};

use super::bvh::{Bvh, Node};
use crate::geometry::{gamma, Ray};

/// Children a node holds, all eight boxes tested at once (AVX lanes).
pub(super) const WIDTH: usize = 8;
/// Each wide level pushes at most WIDTH - 1 entries; the binary build bounds the depth (see
/// bvh.rs).
const STACK_SIZE: usize = (WIDTH - 1) * 128;
const EMPTY: u32 = u32::MAX;
/// Leaf references: the high bit set, the item count in the next 4 bits, the first item in
/// the low 27 (items are primitives, or whatever `from_binary_with_leaves` maps leaves to).
const LEAF_BIT: u32 = 1 << 31;
const COUNT_SHIFT: u32 = 27;
const FIRST_MASK: u32 = (1 << COUNT_SHIFT) - 1;

/// 224 bytes, 32-byte aligned for the SIMD loads (aligning the former 4-wide nodes to cache
/// lines gained nothing measurable).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
struct Node8 {
    /// `bounds[axis][0]` = the minima on that axis of the eight children, `[1]` the maxima.
    bounds: [[f32x8; 2]; 3],
    children: [u32; WIDTH],
}

/// A tree whose root is a leaf (a few primitives) gets a root node with that one child, so
/// that each traversal reaches leaves from one place in its loop (where the compiler inlines
/// the leaf test) and rays that miss the leaf's box skip its test.
#[derive(Clone, Debug, Default)]
pub struct Bvh8 {
    nodes: Vec<Node8>,
}

impl Bvh8 {
    /// Collapses a binary BVH: each wide node adopts the children of its largest interior
    /// children until it has eight. Each leaf's range of primitives (first, count) becomes the
    /// range of items `leaf` returns for it (at most 15 items, the first below 2²⁷). Leaves are
    /// visited in the order the wide tree is laid out, so items allocated in that order sit
    /// near the nodes that reference them.
    pub fn from_binary_with_leaves(bvh: &Bvh, mut leaf: impl FnMut(u32, u32) -> (u32, u32)) -> Self {
        let nodes = &bvh.nodes;
        let mut leaf_reference = |n: &Node| {
            let (first, count) = leaf(n.first, n.count);
            assert!(count < 16 && first <= FIRST_MASK, "leaf of {count} items at {first} does not fit a reference");
            LEAF_BIT | (count << COUNT_SHIFT) | first
        };
        if nodes.is_empty() {
            return Self::default();
        }
        if nodes[0].count > 0 {
            let mut root = empty_node();
            set_child(&mut root, 0, &nodes[0], leaf_reference(&nodes[0]));
            return Self { nodes: vec![root] };
        }
        let mut wide = Vec::with_capacity(nodes.len() / 2);
        wide.push(empty_node());
        let mut work = vec![(0usize, 0usize)]; // (binary node, wide slot)
        while let Some((binary, slot)) = work.pop() {
            let mut children: Vec<usize> = vec![nodes[binary].first as usize, nodes[binary].first as usize + 1];
            while children.len() < WIDTH {
                // Open the interior child with the largest surface area.
                let best = children
                    .iter()
                    .enumerate()
                    .filter(|(_, &c)| nodes[c].count == 0)
                    .max_by(|a, b| area(&nodes[*a.1]).total_cmp(&area(&nodes[*b.1])))
                    .map(|(i, _)| i);
                let Some(i) = best else { break };
                let c = children.swap_remove(i);
                children.push(nodes[c].first as usize);
                children.push(nodes[c].first as usize + 1);
            }
            let mut node = empty_node();
            for (k, &c) in children.iter().enumerate() {
                let n = &nodes[c];
                let child = if n.count > 0 {
                    leaf_reference(n)
                } else {
                    wide.push(empty_node());
                    work.push((c, wide.len() - 1));
                    (wide.len() - 1) as u32
                };
                set_child(&mut node, k, n, child);
            }
            wide[slot] = node;
        }
        Self { nodes: wide }
    }

    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    pub fn bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<Node8>()
    }

    /// Closest hit, as `Bvh::closest`: `hit(i, ray)` returns the distance of a hit within the
    /// ray's range, which then shrinks `ray.t_max`. Every node visited is reported to
    /// `counter` (`NoCounter` for none).
    ///
    /// `ONE_NODE`, for a tree of one node (`is_one_node`), visits the entered leaves straight
    /// off the root with no stack. Either way the leaf test is inlined into the loop: in the
    /// dragon's deep tree that runs as fast as calling it (unlike `any`'s).
    #[inline]
    pub fn closest_counted<const ONE_NODE: bool, C: TraversalCounter>(
        &self,
        ray: &mut Ray,
        mut hit: impl FnMut(u32, &Ray) -> Option<f32>,
        prefetch_leaf: impl Fn(u32),
        counter: &mut C,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        if ONE_NODE {
            debug_assert!(self.is_one_node());
            return self.closest_in_one_node(ray, hit, counter);
        }
        let query = Query::new(ray);
        let mut stack = Stack::<(u32, f32)>::new();
        let mut current = 0u32;
        loop {
            if current & LEAF_BIT != 0 {
                closest_in_leaf(current, ray, &mut hit);
            } else {
                counter.node();
                let node = &self.nodes[current as usize];
                let (t_near, mask) = query.test(node, ray.t_min, ray.t_max);
                if mask != 0 {
                    // Push the entered children far to near, then continue with the nearest:
                    // leaves and subtrees alike are visited in order of entry distance.
                    let mut hits = [(0f32, 0u32); WIDTH];
                    let n = sort_entered(t_near, node.children, mask, &mut hits);
                    for &(t, child) in &hits[..n - 1] {
                        self.prefetch(child, &prefetch_leaf);
                        stack.push((child, t));
                    }
                    current = hits[n - 1].1;
                    continue;
                }
            }
            // Pop the nearest pending child that still starts before the closest hit so far.
            loop {
                let Some((child, t)) = stack.pop() else { return };
                if t < ray.t_max {
                    current = child;
                    break;
                }
            }
        }
    }

    /// Closest hits of many rays, each exactly as `closest_counted` finds it (the same nodes and
    /// leaves in the same order, so the same answer to the bit), but `INTERLEAVED` rays walked
    /// at once, one step (a node or a leaf) of each in turn: the step's next node or leaf is
    /// prefetched, and by the time the walk comes back to that ray it has arrived. A single
    /// incoherent ray spends most of its time waiting for memory (the dragon's random rays:
    /// half their time at the first load of a node or a leaf block); interleaved, the waits of
    /// several rays overlap, as a GPU's warps overlap theirs in hardware.
    ///
    /// `start(i, ray)` makes ray `i`'s per-walk state (the leaf test's prepared ray, say),
    /// `hit(state, item, ray)` tests a leaf item as `closest_counted`'s `hit` does, and
    /// `finish(i, state, ray)` hands back the state and ray `i`'s narrowed copy when it is
    /// done, whose `t_max` (which `finish` may still set) becomes `rays[i]`'s.
    #[inline]
    pub fn closest_interleaved<S>(
        &self,
        rays: &mut [Ray],
        mut start: impl FnMut(usize, &Ray) -> S,
        mut hit: impl FnMut(&mut S, u32, &Ray) -> Option<f32>,
        mut finish: impl FnMut(usize, S, &mut Ray),
        prefetch_leaf: impl Fn(u32),
    ) {
        if self.nodes.is_empty() {
            for (i, ray) in rays.iter_mut().enumerate() {
                let state = start(i, ray);
                finish(i, state, ray);
            }
            return;
        }
        // The walks stay in place (each holds a stack of a few kilobytes): a finished one is
        // restarted on the next ray.
        let mut walks: [Walk<S>; INTERLEAVED] = std::array::from_fn(|_| Walk::idle());
        let mut next = 0;
        let mut active = 0;
        for walk in walks.iter_mut().take(rays.len()) {
            walk.begin(next, &rays[next], start(next, &rays[next]));
            next += 1;
            active += 1;
        }
        while active > 0 {
            for walk in walks.iter_mut() {
                if walk.state.is_none() || self.step(walk, &mut hit, &prefetch_leaf) {
                    continue;
                }
                finish(walk.index, walk.state.take().unwrap(), &mut walk.ray);
                rays[walk.index].t_max = walk.ray.t_max;
                if next < rays.len() {
                    walk.begin(next, &rays[next], start(next, &rays[next]));
                    next += 1;
                } else {
                    active -= 1;
                }
            }
        }
    }

    /// One step of an interleaved walk: the current leaf's test or the current node's, then
    /// the next node or leaf chosen as `closest_counted` chooses it, and prefetched. False
    /// when the walk is over.
    #[inline(always)]
    fn step<S>(
        &self,
        walk: &mut Walk<S>,
        hit: &mut impl FnMut(&mut S, u32, &Ray) -> Option<f32>,
        prefetch_leaf: &impl Fn(u32),
    ) -> bool {
        let current = walk.current;
        if current & LEAF_BIT != 0 {
            let (first, count) = leaf_range(current);
            let state = walk.state.as_mut().expect("a walk in progress has its state");
            for i in first..first + count {
                if let Some(t) = hit(state, i, &walk.ray) {
                    walk.ray.t_max = t;
                }
            }
        } else {
            let node = &self.nodes[current as usize];
            let (t_near, mask) = walk.query.test(node, walk.ray.t_min, walk.ray.t_max);
            if mask != 0 {
                let mut hits = [(0f32, 0u32); WIDTH];
                let n = sort_entered(t_near, node.children, mask, &mut hits);
                for &(t, child) in &hits[..n - 1] {
                    walk.stack.push((child, t));
                }
                walk.current = hits[n - 1].1;
                self.prefetch(walk.current, prefetch_leaf);
                return true;
            }
        }
        while let Some((child, t)) = walk.stack.pop() {
            if t < walk.ray.t_max {
                walk.current = child;
                self.prefetch(child, prefetch_leaf);
                return true;
            }
        }
        false
    }

    /// Asks the memory system for a child that the traversal will probably visit soon: a
    /// node's four cache lines, or through `prefetch_leaf` a leaf's first item.
    #[inline(always)]
    fn prefetch(&self, child: u32, prefetch_leaf: &impl Fn(u32)) {
        if child & LEAF_BIT != 0 {
            prefetch_leaf(leaf_range(child).0);
        } else {
            prefetch_lines(&self.nodes[child as usize]);
        }
    }

    /// Whether the tree is one node, its children all leaves: the Cornell box's 32 triangles,
    /// whose queries skip the stack (`closest_counted`, `any`).
    pub fn is_one_node(&self) -> bool {
        self.nodes.len() == 1
    }

    /// `closest_counted` in a tree of one node: its entered leaves near to far, the nearest
    /// always and the others while they start before the closest hit so far, as the general
    /// loop visits them, but with no stack.
    #[inline(always)]
    fn closest_in_one_node<C: TraversalCounter>(
        &self,
        ray: &mut Ray,
        mut hit: impl FnMut(u32, &Ray) -> Option<f32>,
        counter: &mut C,
    ) {
        counter.node();
        let node = &self.nodes[0];
        let (t_near, mask) = Query::new(ray).test(node, ray.t_min, ray.t_max);
        let mut hits = [(0f32, 0u32); WIDTH];
        let n = sort_entered(t_near, node.children, mask, &mut hits);
        for (j, &(t, leaf)) in hits[..n].iter().rev().enumerate() {
            if j > 0 && t >= ray.t_max {
                break;
            }
            closest_in_leaf(leaf, ray, &mut hit);
        }
    }

    /// Any hit: stops at the first primitive for which `hit(i, ray)` is true.
    ///
    /// `ONE_NODE`, for a tree of one node (`is_one_node`), tests the entered leaves straight
    /// off the root with no stack, the leaf test inlined into the loop. In a deep tree the
    /// leaf test is a call: inlined there, it cost the dragon's diffuse rays 9 % of their
    /// any-hit speed. The two need two closures, as a closure is inlined at one call only.
    #[inline]
    pub fn any<const ONE_NODE: bool>(&self, ray: &Ray, mut hit: impl FnMut(u32, &Ray) -> bool) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        if ONE_NODE {
            debug_assert!(self.is_one_node());
            let (_, mask) = Query::new(ray).test(&self.nodes[0], ray.t_min, ray.t_max);
            let children = self.nodes[0].children;
            return children
                .into_iter()
                .enumerate()
                .any(|(k, child)| mask & (1 << k) != 0 && any_in_leaf_inline(child, ray, &mut hit));
        }
        let query = Query::new(ray);
        let mut stack = Stack::<u32>::new();
        stack.push(0);
        while let Some(index) = stack.pop() {
            let node = &self.nodes[index as usize];
            let (_, mask) = query.test(node, ray.t_min, ray.t_max);
            for k in 0..WIDTH {
                if mask & (1 << k) != 0 {
                    let child = node.children[k];
                    if child & LEAF_BIT == 0 {
                        stack.push(child);
                    } else if any_in_leaf(child, ray, &mut hit) {
                        return true;
                    }
                }
            }
        }
        false
    }
}

/// Rays `Bvh8::closest_interleaved` walks at once: enough steps of the others to cover a
/// load from memory (a few hundred cycles) before a ray's prefetched node is used.
pub const INTERLEAVED: usize = 8;

/// One ray's closest-hit walk in `Bvh8::closest_interleaved`: where it stands and what is
/// pending, as `closest_counted` keeps them in its locals.
struct Walk<S> {
    index: usize,
    ray: Ray,
    query: Query,
    current: u32,
    stack: Stack<(u32, f32)>,
    /// The caller's state of the ray in progress; `None` when the walk is idle.
    state: Option<S>,
}

impl<S> Walk<S> {
    fn idle() -> Self {
        let ray = Ray::new(Vec3::ZERO, Vec3::X);
        Self { index: 0, ray, query: Query::new(&ray), current: 0, stack: Stack::new(), state: None }
    }

    /// Starts the walk of ray `index` from the root.
    #[inline(always)]
    fn begin(&mut self, index: usize, ray: &Ray, state: S) {
        self.index = index;
        self.ray = *ray;
        self.query = Query::new(ray);
        self.current = 0;
        self.stack.top = 0;
        self.state = Some(state);
    }
}

/// Writes the children in `mask` with their entry distances into `hits`, far to near
/// (insertion sort; of equal distances the later slot first, so that popping visits the
/// earlier slot first), and returns how many. (Returned as an array instead, the sorted
/// children cost the dragon's primary rays a quarter of their closest-hit speed.)
#[inline(always)]
fn sort_entered(t_near: [f32; WIDTH], children: [u32; WIDTH], mask: u32, hits: &mut [(f32, u32); WIDTH]) -> usize {
    let mut n = 0;
    for (k, entry) in t_near.into_iter().zip(children).enumerate() {
        if mask & (1 << k) != 0 {
            let mut j = n;
            while j > 0 && hits[j - 1].0 < entry.0 {
                hits[j] = hits[j - 1];
                j -= 1;
            }
            hits[j] = entry;
            n += 1;
        }
    }
    n
}

/// Tests the items of the leaf `reference` for `Bvh8::closest_counted`, each hit narrowing the
/// ray.
#[inline(always)]
fn closest_in_leaf(reference: u32, ray: &mut Ray, hit: &mut impl FnMut(u32, &Ray) -> Option<f32>) {
    let (first, count) = leaf_range(reference);
    for i in first..first + count {
        if let Some(t) = hit(i, ray) {
            ray.t_max = t;
        }
    }
}

/// Whether `hit` is true for an item of the leaf `reference`.
#[inline(always)]
fn any_in_leaf_inline(reference: u32, ray: &Ray, hit: &mut impl FnMut(u32, &Ray) -> bool) -> bool {
    let (first, count) = leaf_range(reference);
    (first..first + count).any(|i| hit(i, ray))
}

/// `any_in_leaf_inline` out of line, for deep trees (see `Bvh8::any`).
#[inline(never)]
fn any_in_leaf(reference: u32, ray: &Ray, hit: &mut impl FnMut(u32, &Ray) -> bool) -> bool {
    any_in_leaf_inline(reference, ray, hit)
}

/// A fixed-capacity traversal stack that is not zeroed per ray (zeroing a few kilobytes per
/// ray cost a quarter of the throughput). Only entries below `top` are ever read.
struct Stack<T: Copy> {
    entries: [MaybeUninit<T>; STACK_SIZE],
    top: usize,
}

impl<T: Copy> Stack<T> {
    #[inline(always)]
    fn new() -> Self {
        Self { entries: [const { MaybeUninit::uninit() }; STACK_SIZE], top: 0 }
    }

    /// Panics (index out of bounds) rather than overflow; the build bounds the depth so that
    /// this cannot happen.
    #[inline(always)]
    fn push(&mut self, value: T) {
        self.entries[self.top].write(value);
        self.top += 1;
    }

    #[inline(always)]
    fn pop(&mut self) -> Option<T> {
        if self.top == 0 {
            return None;
        }
        self.top -= 1;
        // SAFETY: every entry below the old `top` was written by `push`, and `top` only grows
        // through `push`.
        Some(unsafe { self.entries[self.top].assume_init() })
    }
}

/// Receives the work a traversal does; `NoCounter` compiles to nothing. The tree counts the
/// nodes it visits; what a leaf item holds is the caller's to count (`primitives`).
pub trait TraversalCounter {
    /// Whether counting does anything (callers skip work that only feeds the counter).
    const ACTIVE: bool;
    fn node(&mut self);
    fn primitives(&mut self, n: u32);
}

pub struct NoCounter;

impl TraversalCounter for NoCounter {
    const ACTIVE: bool = false;
    #[inline(always)]
    fn node(&mut self) {}
    #[inline(always)]
    fn primitives(&mut self, _: u32) {}
}

/// Nodes visited and primitives tested by one or more traversals.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TraversalCounts {
    pub nodes: u32,
    pub primitives: u32,
}

impl TraversalCounter for TraversalCounts {
    const ACTIVE: bool = true;
    fn node(&mut self) {
        self.nodes += 1;
    }
    fn primitives(&mut self, n: u32) {
        self.primitives += n;
    }
}

/// A ray prepared for box tests: origin and reciprocal direction splatted, planes by octant.
struct Query {
    origin: [f32x8; 3],
    inv_dir: [f32x8; 3],
    /// `inv_dir` widened for the far planes, so that the test is conservative, as pbrt-v4's
    /// Bounds3::IntersectP is: a far distance takes a subtraction and a multiply by the
    /// correctly rounded 1/d, so the exact one is at most (1 + 2γ₃) times the computed one;
    /// 1 + 2γ₅ covers that and the rounding of this product, at no cost per node. Without it
    /// a ray through a box's face within rounding culled the box whose triangle the
    /// watertight test would hit (rays at the vertices of a flat grid: leaves of zero
    /// thickness).
    inv_dir_far: [f32x8; 3],
    /// For each axis, which of `bounds[axis]` is the near plane (0 = min for a positive direction).
    near: [usize; 3],
}

impl Query {
    fn new(ray: &Ray) -> Self {
        // One vector division (glam's Vec3 divides lane by lane), rounded the same.
        let inv = Vec3::from(glam::Vec3A::from(ray.direction).recip());
        // The sign bit alone: −0 counts as negative, as a negative direction's does.
        let near = [0, 1, 2].map(|a| usize::from(ray.direction[a].is_sign_negative()));
        Self {
            origin: [0, 1, 2].map(|a| f32x8::splat(ray.origin[a])),
            inv_dir: [0, 1, 2].map(|a| f32x8::splat(inv[a])),
            inv_dir_far: [0, 1, 2].map(|a| f32x8::splat(inv[a] * (1.0 + 2.0 * gamma(5)))),
            near,
        }
    }

    /// Entry distances of the children and the mask of those entered within (t_min, t_max].
    #[inline(always)]
    fn test(&self, node: &Node8, t_min: f32, t_max: f32) -> ([f32; WIDTH], u32) {
        let mut t_near = f32x8::splat(t_min);
        let mut t_far = f32x8::splat(t_max);
        for axis in 0..3 {
            let bounds = &node.bounds[axis];
            let near = (bounds[self.near[axis]] - self.origin[axis]) * self.inv_dir[axis];
            let far = (bounds[1 - self.near[axis]] - self.origin[axis]) * self.inv_dir_far[axis];
            // A NaN distance (0 · ∞: a ray in a slab's plane) must leave the interval as it
            // is, so compare-and-select rather than `max`, whose NaN result `wide` leaves
            // unspecified (its scalar fallback returns the NaN, which would cull the child).
            t_near = near.cmp_gt(t_near).blend(near, t_near);
            t_far = far.cmp_lt(t_far).blend(far, t_far);
        }
        // An array, not a vector: indexing lanes by a variable compiles to a jump table.
        (t_near.to_array(), t_near.cmp_le(t_far).move_mask() as u32)
    }
}

/// Puts binary node `n` into slot `k` of `node` as `child` (a wide node's index or a leaf
/// reference).
fn set_child(node: &mut Node8, k: usize, n: &Node, child: u32) {
    for axis in 0..3 {
        node.bounds[axis][0].as_array_mut()[k] = n.min[axis];
        node.bounds[axis][1].as_array_mut()[k] = n.max[axis];
    }
    node.children[k] = child;
}

fn empty_node() -> Node8 {
    let min = f32x8::splat(f32::INFINITY);
    let max = f32x8::splat(f32::NEG_INFINITY);
    Node8 { bounds: [[min, max]; 3], children: [EMPTY; WIDTH] }
}

#[inline(always)]
fn leaf_range(reference: u32) -> (u32, u32) {
    (reference & FIRST_MASK, (reference >> COUNT_SHIFT) & 0xF)
}

fn area(n: &Node) -> f32 {
    let e = (n.max - n.min).max(Vec3::ZERO);
    e.x * e.y + e.y * e.z + e.z * e.x
}

/// Prefetches every cache line of `value` into all cache levels (a hint; nothing on targets
/// without a stable prefetch instruction).
#[inline(always)]
pub(crate) fn prefetch_lines<T>(value: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        let start = value as *const T as *const i8;
        for offset in (0..std::mem::size_of::<T>()).step_by(64) {
            // SAFETY: prefetching is a hint that never faults; the address lies within `value`.
            unsafe { std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(start.add(offset)) };
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = value;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Aabb;

    #[test]
    fn nan_lanes_are_dropped_conservatively() {
        // A row of boxes the ray runs along exactly in the plane of their bottom (or top)
        // faces, where 0 · ∞ makes the slab distances NaN, and a row above it the ray misses;
        // enough boxes for the tree to have nodes, so the box test runs.
        let row = |y: f32| {
            (0..12).map(move |k| {
                Aabb::new(Vec3::new(3.0 * k as f32, y, 0.0), Vec3::new(3.0 * k as f32 + 1.0, y + 1.0, 1.0))
            })
        };
        let boxes: Vec<Aabb> = row(0.0).chain(row(5.0)).collect();
        let (bvh, order) = Bvh::build(&boxes);
        let wide = Bvh8::from_binary_with_leaves(&bvh, |first, count| (first, count));
        assert!(wide.node_count() > 0, "the test needs a node to exercise the box test");
        for origin in [Vec3::new(-1.0, 0.0, 0.5), Vec3::new(-1.0, 1.0, 0.5)] {
            let ray = Ray::new(origin, Vec3::X);
            let mut seen = Vec::new();
            wide.any::<false>(&ray, |i, _| {
                seen.push(order[i as usize] as usize);
                false
            });
            for k in 0..12 {
                assert!(seen.contains(&k), "the ray along a face plane from {origin} missed box {k}");
            }
        }
    }

    #[test]
    fn a_tree_that_is_one_leaf_gets_a_root_node() {
        // Three boxes make one leaf: it becomes the only child of a root node, whose box test
        // culls a ray that passes beside them.
        let boxes: Vec<Aabb> =
            (0..3).map(|k| Aabb::new(Vec3::new(k as f32, 0.0, 0.0), Vec3::new(k as f32 + 0.5, 1.0, 1.0))).collect();
        let (bvh, order) = Bvh::build(&boxes);
        assert_eq!(bvh.stats().leaves, 1);
        let wide = Bvh8::from_binary_with_leaves(&bvh, |first, count| (first, count));
        assert_eq!(wide.node_count(), 1);
        let through = Ray::new(Vec3::new(-1.0, 0.5, 0.5), Vec3::X);
        let beside = Ray::new(Vec3::new(-1.0, 2.5, 0.5), Vec3::X);
        let mut seen = Vec::new();
        assert!(!wide.any::<false>(&through, |i, _| {
            seen.push(order[i as usize]);
            false
        }));
        seen.sort();
        assert_eq!(seen, [0, 1, 2]);
        assert!(wide.any::<false>(&through, |i, _| order[i as usize] == 2));
        assert!(wide.any::<true>(&through, |i, _| order[i as usize] == 2));
        for one_node in [false, true] {
            let closest = |ray: &mut Ray, hit: &mut dyn FnMut(u32, &Ray) -> Option<f32>| match one_node {
                true => wide.closest_counted::<true, _>(ray, hit, |_| (), &mut NoCounter),
                false => wide.closest_counted::<false, _>(ray, hit, |_| (), &mut NoCounter),
            };
            let mut ray = through;
            closest(&mut ray, &mut |i, _| (order[i as usize] == 1).then_some(1.5));
            assert_eq!(ray.t_max, 1.5);
            let mut ray = beside;
            closest(&mut ray, &mut |_, _| Some(1.0));
            assert_eq!(ray.t_max, beside.t_max);
        }
        assert!(!wide.any::<false>(&beside, |_, _| true) && !wide.any::<true>(&beside, |_, _| true));
    }

    /// The items a closest-hit query visits, in order, and the distance it ends with; item i
    /// is "hit" at a distance that depends on it, so that some leaves are skipped for starting
    /// beyond the closest hit so far.
    fn closest_visits<const ONE_NODE: bool>(wide: &Bvh8, mut ray: Ray) -> (Vec<u32>, u32) {
        let mut visits = Vec::new();
        let distance = |i: u32| 6.0 + (i % 7) as f32 * 2.5;
        wide.closest_counted::<ONE_NODE, _>(
            &mut ray,
            |i, r| {
                visits.push(i);
                Some(distance(i)).filter(|&t| t < r.t_max)
            },
            |_| (),
            &mut NoCounter,
        );
        (visits, ray.t_max.to_bits())
    }

    /// In a tree of one node, the stackless queries visit the leaves the general loop visits,
    /// in the same order, and find the same answers.
    #[test]
    fn one_node_queries_visit_as_the_general_loop() {
        // Forty boxes in a row: five leaves of eight under one root.
        let boxes: Vec<Aabb> = (0..40)
            .map(|k| {
                let p = Vec3::new((k % 10) as f32 * 1.5, (k / 10) as f32 * 1.5, 0.0);
                Aabb::new(p, p + Vec3::ONE)
            })
            .collect();
        let (bvh, _) = Bvh::build(&boxes);
        let wide = Bvh8::from_binary_with_leaves(&bvh, |first, count| (first, count));
        assert!(wide.is_one_node());
        let mut rng = crate::sampling::Rng::new(11, 0);
        let (mut multi_leaf, mut culled) = (0, 0);
        for _ in 0..2000 {
            let origin = Vec3::new(rng.next_f32() * 20.0 - 3.0, rng.next_f32() * 8.0 - 1.0, -2.0 + rng.next_f32());
            let target = Vec3::new(rng.next_f32() * 15.0, rng.next_f32() * 6.0, rng.next_f32());
            let ray = Ray::new(origin, (target - origin).normalize());
            let (general, one) = (closest_visits::<false>(&wide, ray), closest_visits::<true>(&wide, ray));
            assert_eq!(general, one);
            multi_leaf += usize::from(general.0.len() > 8);
            culled += usize::from(!general.0.is_empty() && general.0.len() < 40);
            for stop in [3u32, 17, 39] {
                let (mut a, mut b) = (Vec::new(), Vec::new());
                let found_a = wide.any::<false>(&ray, |i, _| {
                    a.push(i);
                    i == stop
                });
                let found_b = wide.any::<true>(&ray, |i, _| {
                    b.push(i);
                    i == stop
                });
                assert_eq!((found_a, &a), (found_b, &b));
            }
        }
        assert!(multi_leaf > 100 && culled > 100, "{multi_leaf} rays through several leaves, {culled} culled");
    }

    #[test]
    fn wide_tree_visits_what_the_binary_tree_visits() {
        let boxes: Vec<Aabb> = (0..500)
            .map(|i| {
                let p = Vec3::new((i % 8) as f32, ((i / 8) % 8) as f32, (i / 64) as f32) * 1.5;
                Aabb::new(p, p + Vec3::splat(1.0))
            })
            .collect();
        let (bvh, order) = Bvh::build(&boxes);
        let wide = Bvh8::from_binary_with_leaves(&bvh, |first, count| (first, count));
        assert!(wide.node_count() > 0 && wide.node_count() < bvh.stats().nodes);
        for k in 0..200 {
            let origin = Vec3::new(-3.0, k as f32 * 0.07, (k % 13) as f32 * 0.9);
            let ray = Ray::new(origin, Vec3::new(1.0, 0.11, 0.05 * (k % 5) as f32).normalize());
            // The reciprocals as `Query::new` computes them.
            let inv = Vec3::from(glam::Vec3A::from(ray.direction).recip());
            let entered =
                |i: u32| boxes[order[i as usize] as usize].hit_distance(ray.origin, inv, 0.0, f32::INFINITY).is_some();
            let (mut a, mut b) = (Vec::new(), Vec::new());
            bvh.any(&ray, |i, _| {
                if entered(i) {
                    a.push(i);
                }
                false
            });
            wide.any::<false>(&ray, |i, _| {
                if entered(i) {
                    b.push(i);
                }
                false
            });
            a.sort();
            b.sort();
            assert_eq!(a, b);
        }
    }
}
