//! Bounding volume hierarchy: binned SAH build (Wald 2007, "On fast construction of SAH-based
//! bounding volume hierarchies") into a flat array of 32-byte nodes, traversed near child first.
//! The SAH prices leaves in blocks of eight triangles, the width of the leaf test, and each
//! primitive tested alone (a sphere, a box, an instance) as a block of its own.
//!
//! The build reorders nothing the caller owns: it returns `primitive_order`, the permutation
//! the leaves index into, and the caller lays its primitives out in that order.

use glam::Vec3;

use crate::geometry::{Aabb, Ray};

const BINS: usize = 16;
const MAX_LEAF_SIZE: usize = 8;
/// Primitives a leaf test handles at once (the SIMD width of `Triangle8`): the SAH prices a
/// leaf by its number of blocks (a primitive tested alone takes one), so leaves fill their
/// blocks.
const LEAF_BLOCK: usize = super::LANES;
/// Cost of one traversal step (one wide node's box tests) relative to one leaf-block test
/// (eight triangle tests), for the SAH. On the dragon, 0.5 to 2 trace within noise of each
/// other; 1 keeps the traversal data smallest among the fast ones (56 bytes per triangle).
/// Measurements in docs/performance.md.
const TRAVERSAL_COST: f32 = 1.0;
/// Children of the root wide node (`Bvh8`), into which the top of the binary tree collapses.
const ROOT_CHILDREN: usize = super::wide::WIDTH;
/// The SAH cost in `BvhStats` counts a traversal step as one primitive test, whatever cost the
/// build used, so costs of different trees compare.
const REPORTED_TRAVERSAL_COST: f32 = 1.0;
/// Below this depth the SAH chooses splits; deeper, subtrees split at the median, so the tree's
/// depth stays under SAH_DEPTH + log2(n) and the fixed traversal stacks cannot overflow.
const SAH_DEPTH: usize = 40;
const STACK_SIZE: usize = 128;

/// A node: bounds, and either two children (`count == 0`; left child at `first`, right child
/// right after it) or a leaf of `count` primitives starting at `first`.
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub(super) struct Node {
    pub(super) min: Vec3,
    pub(super) first: u32,
    pub(super) max: Vec3,
    pub(super) count: u32,
}

#[derive(Clone, Debug, Default)]
pub struct Bvh {
    pub(super) nodes: Vec<Node>,
}

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BvhStats {
    pub nodes: usize,
    pub leaves: usize,
    pub depth: usize,
    /// SAH cost of the tree (traversal steps + primitive tests, expected per random ray), with
    /// a traversal step counted as one primitive test and every primitive counted (the build
    /// itself prices leaves per block of eight), so that trees of any build compare.
    pub sah_cost: f32,
    /// Memory of the traversal structures in bytes.
    pub bytes: usize,
    /// Nodes of the 8-wide traversal BVH (0 when only the binary tree is built).
    pub wide_nodes: usize,
    /// Leaf blocks of up to eight primitives (0 when only the binary tree is built).
    pub leaf_blocks: usize,
}

struct BuildPrim {
    bounds: Aabb,
    centroid: Vec3,
    index: u32,
    /// Tested on its own, not eight at a time with others (see `leaf_cost`).
    alone: bool,
}

impl Bvh {
    /// Builds over the given primitive bounds, all of them tested eight at a time. Returns the
    /// tree and the order in which the leaves reference the primitives.
    pub fn build(bounds: &[Aabb]) -> (Self, Vec<u32>) {
        Self::build_mixed(bounds, |_| false)
    }

    /// `build`, where `alone(i)` tells the primitives a leaf tests one by one (spheres, boxes,
    /// instances, …) rather than eight at a time (plain triangles): the SAH prices each such
    /// primitive as a block.
    pub fn build_mixed(bounds: &[Aabb], alone: impl Fn(usize) -> bool) -> (Self, Vec<u32>) {
        let mut prims = build_prims(bounds, alone);
        if prims.is_empty() {
            return (Self { nodes: Vec::new() }, Vec::new());
        }
        let mut nodes = Vec::with_capacity(2 * prims.len());
        nodes.push(Node { min: Vec3::ZERO, first: 0, max: Vec3::ZERO, count: 0 });
        build_root(&mut nodes, &mut prims);
        let order = prims.iter().map(|p| p.index).collect();
        (Self { nodes }, order)
    }

    pub fn bounds(&self) -> Aabb {
        self.nodes.first().map_or(Aabb::EMPTY, |n| Aabb::new(n.min, n.max))
    }

    /// Closest hit: calls `hit(i, ray)` for candidate primitives in roughly front-to-back
    /// order; `hit` returns the distance of a hit within the ray's range, which then shrinks
    /// `ray.t_max`.
    #[inline]
    pub fn closest(&self, ray: &mut Ray, mut hit: impl FnMut(u32, &Ray) -> Option<f32>) {
        let inv = ray.direction.recip();
        let mut stack = [0u32; STACK_SIZE];
        let mut top = 0;
        let mut index = 0usize;
        if self.nodes.is_empty() || node_hit(&self.nodes[0], ray, inv).is_none() {
            return;
        }
        loop {
            let node = &self.nodes[index];
            if node.count > 0 {
                for i in node.first..node.first + node.count {
                    if let Some(t) = hit(i, ray) {
                        ray.t_max = t;
                    }
                }
            } else {
                let left = node.first as usize;
                let t_left = node_hit(&self.nodes[left], ray, inv);
                let t_right = node_hit(&self.nodes[left + 1], ray, inv);
                match (t_left, t_right) {
                    (Some(tl), Some(tr)) => {
                        let (near, far) = if tl <= tr { (left, left + 1) } else { (left + 1, left) };
                        stack[top] = far as u32;
                        top += 1;
                        index = near;
                        continue;
                    }
                    (Some(_), None) => {
                        index = left;
                        continue;
                    }
                    (None, Some(_)) => {
                        index = left + 1;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            // Pop the next subtree; one that was pushed may since have moved beyond t_max.
            loop {
                if top == 0 {
                    return;
                }
                top -= 1;
                index = stack[top] as usize;
                if node_hit(&self.nodes[index], ray, inv).is_some() {
                    break;
                }
            }
        }
    }

    /// Any hit: stops at the first primitive for which `hit(i, ray)` is true.
    #[inline]
    pub fn any(&self, ray: &Ray, mut hit: impl FnMut(u32, &Ray) -> bool) -> bool {
        let inv = ray.direction.recip();
        let mut stack = [0u32; STACK_SIZE];
        let mut top = usize::from(!self.nodes.is_empty());
        while top > 0 {
            top -= 1;
            let node = &self.nodes[stack[top] as usize];
            if node_hit(node, ray, inv).is_none() {
                continue;
            }
            if node.count > 0 {
                if (node.first..node.first + node.count).any(|i| hit(i, ray)) {
                    return true;
                }
            } else {
                stack[top] = node.first;
                stack[top + 1] = node.first + 1;
                top += 2;
            }
        }
        false
    }

    pub fn stats(&self) -> BvhStats {
        let root_area = self.bounds().surface_area().max(f32::MIN_POSITIVE);
        let mut stats = BvhStats {
            nodes: self.nodes.len(),
            bytes: self.nodes.len() * std::mem::size_of::<Node>(),
            ..Default::default()
        };
        let mut stack = if self.nodes.is_empty() { vec![] } else { vec![(0usize, 1usize)] };
        while let Some((i, depth)) = stack.pop() {
            let n = &self.nodes[i];
            let area = Aabb::new(n.min, n.max).surface_area() / root_area;
            stats.depth = stats.depth.max(depth);
            if n.count > 0 {
                stats.leaves += 1;
                stats.sah_cost += area * n.count as f32;
            } else {
                stats.sah_cost += area * REPORTED_TRAVERSAL_COST;
                stack.push((n.first as usize, depth + 1));
                stack.push((n.first as usize + 1, depth + 1));
            }
        }
        stats
    }
}

#[inline(always)]
fn node_hit(node: &Node, ray: &Ray, inv: Vec3) -> Option<f32> {
    Aabb::new(node.min, node.max).hit_distance(ray.origin, inv, ray.t_min, ray.t_max)
}

/// The primitives to build over, in input order.
fn build_prims(bounds: &[Aabb], alone: impl Fn(usize) -> bool) -> Vec<BuildPrim> {
    bounds
        .iter()
        .enumerate()
        .map(|(i, b)| BuildPrim { bounds: *b, centroid: b.centroid(), index: i as u32, alone: alone(i) })
        .collect()
}

/// The bounds of `prims` and of their centroids.
fn bounds_of(prims: &[BuildPrim]) -> (Aabb, Aabb) {
    let bounds = prims.iter().fold(Aabb::EMPTY, |b, p| b.union(p.bounds));
    (bounds, prims.iter().fold(Aabb::EMPTY, |b, p| b.grow_point(p.centroid)))
}

/// The top of the tree: the subtrees the root wide node holds, split best first, then each
/// built by `build_node`.
///
/// Every ray tests the root's eight children at once, however they are laid out, so a split
/// that keeps them within eight adds no traversal. While there are fewer than eight subtrees,
/// the one whose split saves the most (by the SAH with traversal free) is split: first those
/// of more than `MAX_LEAF_SIZE` primitives, which split anyway, as `build_node` would split
/// them (so a large tree keeps its shape), then any that gains. A small scene so gets tight
/// leaves (the Cornell box's 32 triangles: eight leaves of about four instead of four of
/// eight), and a ray that hits a wall skips the leaves behind it, which the SAH does not see
/// (it prices rays that cross everything): the box's render ran 9 % fewer instructions and
/// took 13 % less time. (The eight become the root's children when `build_node` leaves them
/// as they are; the collapse into wide nodes opens the largest interior children first, so a
/// subtree split further below, as one of primitives tested alone can be, may take a root
/// slot instead.) Deeper, a split can add a wide node; making splits free there too (all but
/// every third level) gave the dragon 1.5 times the leaf blocks and cost its diffuse rays
/// 30 % (docs/performance.md).
fn build_root(nodes: &mut Vec<Node>, prims: &mut [BuildPrim]) {
    let mut subtrees = vec![RootSubtree::new(0, 0, prims.len(), 0, prims)];
    while subtrees.len() < ROOT_CHILDREN {
        let best = subtrees
            .iter()
            .enumerate()
            .filter_map(|(i, s)| match s.split {
                RootSplit::Forced => Some((i, f32::INFINITY)),
                RootSplit::Gains { gain, .. } if gain > 0.0 => Some((i, gain)),
                _ => None,
            })
            .max_by(|a, b| a.1.total_cmp(&b.1));
        let Some((i, _)) = best else { break };
        let RootSubtree { index, start, end, depth, split } = subtrees.swap_remove(i);
        let slice = &mut prims[start..end];
        let (bounds, centroid_bounds) = bounds_of(slice);
        let split = match split {
            RootSplit::Gains { axis, position, .. } => Some((axis, position)),
            // As `build_node` splits it (its traversal cost too, so that rounding breaks ties
            // between bins alike): the SAH's split, or the middle where the centroids coincide.
            _ => {
                find_split(slice, &bounds, &centroid_bounds, TRAVERSAL_COST).map(|(axis, position, _)| (axis, position))
            }
        };
        let mid = split_point(slice, split);
        let left = push_children(nodes, index, &bounds);
        subtrees.push(RootSubtree::new(left, start, start + mid, depth + 1, prims));
        subtrees.push(RootSubtree::new(left + 1, start + mid, end, depth + 1, prims));
    }
    for s in subtrees {
        build_node(nodes, s.index, prims, s.start, s.end, s.depth);
    }
}

/// A subtree of the root wide node while `build_root` fills it: `nodes[index]` over
/// `prims[start..end]`.
struct RootSubtree {
    index: usize,
    start: usize,
    end: usize,
    depth: usize,
    split: RootSplit,
}

/// What splitting a subtree of the root would do.
enum RootSplit {
    /// More than `MAX_LEAF_SIZE` primitives: it splits anyway (its split found when it is made,
    /// so that a large tree's last subtrees of the root are not binned twice).
    Forced,
    /// The SAH's split with traversal free, and what it saves (surface area × leaf blocks).
    Gains { gain: f32, axis: usize, position: f32 },
    /// None: too few primitives, or their centroids coincide.
    Leaf,
}

impl RootSubtree {
    fn new(index: usize, start: usize, end: usize, depth: usize, prims: &[BuildPrim]) -> Self {
        let prims = &prims[start..end];
        let split = if prims.len() > MAX_LEAF_SIZE {
            RootSplit::Forced
        } else if prims.len() <= 2 {
            RootSplit::Leaf
        } else {
            let (bounds, centroid_bounds) = bounds_of(prims);
            match find_split(prims, &bounds, &centroid_bounds, 0.0) {
                Some((axis, position, cost)) => {
                    let leaf = leaf_cost(prims.len(), prims.iter().filter(|p| p.alone).count());
                    RootSplit::Gains { gain: (leaf - cost) * bounds.surface_area(), axis, position }
                }
                None => RootSplit::Leaf,
            }
        };
        Self { index, start, end, depth, split }
    }
}

fn build_node(nodes: &mut Vec<Node>, index: usize, prims: &mut [BuildPrim], start: usize, end: usize, depth: usize) {
    let slice = &mut prims[start..end];
    let (bounds, centroid_bounds) = bounds_of(slice);
    let count = slice.len();
    let make_leaf = |nodes: &mut Vec<Node>| {
        nodes[index] = Node { min: bounds.min, first: start as u32, max: bounds.max, count: count as u32 };
    };
    if count <= 2 {
        return make_leaf(nodes);
    }
    if depth >= SAH_DEPTH {
        // Median split along the widest centroid axis: balanced, whatever the input.
        let axis = centroid_bounds.extent().max_position();
        let mid = count / 2;
        slice.select_nth_unstable_by(mid, |a, b| a.centroid[axis].total_cmp(&b.centroid[axis]));
        return split_node(nodes, index, prims, (start, mid, end), depth, &bounds);
    }
    let split = find_split(slice, &bounds, &centroid_bounds, TRAVERSAL_COST);
    let leaf_cost = leaf_cost(count, slice.iter().filter(|p| p.alone).count());
    let mid = match split {
        Some((axis, position, cost)) if cost < leaf_cost || count > MAX_LEAF_SIZE => {
            split_point(slice, Some((axis, position)))
        }
        None if count > MAX_LEAF_SIZE => split_point(slice, None),
        _ => return make_leaf(nodes),
    };
    split_node(nodes, index, prims, (start, mid, end), depth, &bounds);
}

fn split_node(
    nodes: &mut Vec<Node>,
    index: usize,
    prims: &mut [BuildPrim],
    (start, mid, end): (usize, usize, usize),
    depth: usize,
    bounds: &Aabb,
) {
    let left = push_children(nodes, index, bounds);
    build_node(nodes, left, prims, start, start + mid, depth + 1);
    build_node(nodes, left + 1, prims, start + mid, end, depth + 1);
}

/// Makes `nodes[index]` an interior node over `bounds` with two new children (to be built);
/// returns the first child's index.
fn push_children(nodes: &mut Vec<Node>, index: usize, bounds: &Aabb) -> usize {
    let left = nodes.len();
    nodes.push(Node { min: Vec3::ZERO, first: 0, max: Vec3::ZERO, count: 0 });
    nodes.push(Node { min: Vec3::ZERO, first: 0, max: Vec3::ZERO, count: 0 });
    nodes[index] = Node { min: bounds.min, first: left as u32, max: bounds.max, count: 0 };
    left
}

/// Puts the primitives whose centroids lie below `position` on `axis` first and returns how
/// many; the middle of the list where that leaves a side empty (all centroids in one bin) or
/// where there is no split (coincident centroids).
fn split_point(slice: &mut [BuildPrim], split: Option<(usize, f32)>) -> usize {
    let mid = split.map_or(0, |(axis, position)| partition(slice, |p| p.centroid[axis] < position));
    if mid == 0 || mid == slice.len() {
        slice.len() / 2
    } else {
        mid
    }
}

/// The best binned SAH split: (axis, centroid position, cost relative to one primitive test).
/// One pass over the primitives fills the bins of all three axes.
fn find_split(
    prims: &[BuildPrim],
    bounds: &Aabb,
    centroid_bounds: &Aabb,
    traversal_cost: f32,
) -> Option<(usize, f32, f32)> {
    let area = bounds.surface_area().max(f32::MIN_POSITIVE);
    let lo = centroid_bounds.min;
    let extent = centroid_bounds.extent();
    let scale = Vec3::select(extent.cmpgt(Vec3::ZERO), Vec3::splat(BINS as f32) / extent, Vec3::ZERO);
    let mut bin_bounds = [[Aabb::EMPTY; BINS]; 3];
    // Per bin: (primitives, those of them tested alone).
    let mut bin_count = [[(0usize, 0usize); BINS]; 3];
    for p in prims {
        let b = ((p.centroid - lo) * scale).as_uvec3().min(glam::UVec3::splat(BINS as u32 - 1));
        for axis in 0..3 {
            let k = b[axis] as usize;
            bin_bounds[axis][k] = bin_bounds[axis][k].union(p.bounds);
            bin_count[axis][k].0 += 1;
            bin_count[axis][k].1 += usize::from(p.alone);
        }
    }
    let mut best: Option<(usize, f32, f32)> = None;
    for axis in 0..3 {
        if extent[axis] <= 0.0 {
            continue;
        }
        // Sweep from the right to get the right-hand areas, then from the left.
        let mut right_area = [0.0f32; BINS];
        let mut right_count = [(0, 0); BINS];
        let (mut acc, mut n) = (Aabb::EMPTY, (0, 0));
        for b in (1..BINS).rev() {
            acc = acc.union(bin_bounds[axis][b]);
            n = (n.0 + bin_count[axis][b].0, n.1 + bin_count[axis][b].1);
            right_area[b] = acc.surface_area();
            right_count[b] = n;
        }
        let (mut acc, mut n) = (Aabb::EMPTY, (0, 0));
        for b in 0..BINS - 1 {
            acc = acc.union(bin_bounds[axis][b]);
            n = (n.0 + bin_count[axis][b].0, n.1 + bin_count[axis][b].1);
            let right = right_count[b + 1];
            if n.0 == 0 || right.0 == 0 {
                continue;
            }
            let cost = traversal_cost
                + (acc.surface_area() * leaf_cost(n.0, n.1) + right_area[b + 1] * leaf_cost(right.0, right.1)) / area;
            if best.is_none_or(|(_, _, c)| cost < c) {
                best = Some((axis, lo[axis] + (b + 1) as f32 / scale[axis], cost));
            }
        }
    }
    best
}

/// The cost of testing a leaf of `n` primitives, `alone` of which are tested one by one, in
/// block tests: the others go eight to a block.
#[inline(always)]
fn leaf_cost(n: usize, alone: usize) -> f32 {
    ((n - alone).div_ceil(LEAF_BLOCK) + alone) as f32
}

/// In-place partition; returns the number of elements for which `left` is true.
fn partition<T>(items: &mut [T], left: impl Fn(&T) -> bool) -> usize {
    let mut i = 0;
    for j in 0..items.len() {
        if left(&items[j]) {
            items.swap(i, j);
            i += 1;
        }
    }
    i
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn empty_and_single() {
        let (bvh, order) = Bvh::build(&[]);
        assert!(order.is_empty());
        let mut ray = Ray::new(Vec3::ZERO, Vec3::X);
        bvh.closest(&mut ray, |_, _| panic!("no primitive to test"));
        assert!(!bvh.any(&ray, |_, _| true));

        let (bvh, order) = Bvh::build(&[Aabb::new(Vec3::splat(1.0), Vec3::splat(2.0))]);
        assert_eq!(order, vec![0]);
        let mut ray = Ray::new(Vec3::ZERO, Vec3::ONE);
        let mut tested = 0;
        bvh.closest(&mut ray, |_, _| {
            tested += 1;
            None
        });
        assert_eq!(tested, 1);
    }

    #[test]
    fn depth_is_bounded_on_a_degenerate_input() {
        // Boxes growing geometrically along x: SAH alone peels one off per level.
        let boxes: Vec<Aabb> = (0..3000)
            .map(|i| {
                let x = 1.01f32.powi(i);
                Aabb::new(Vec3::new(x, 0.0, 0.0), Vec3::new(x * 1.001, 1.0, 1.0))
            })
            .collect();
        let (bvh, _) = Bvh::build(&boxes);
        assert!(bvh.stats().depth <= SAH_DEPTH + 13, "depth {}", bvh.stats().depth);
    }

    /// The tree `build_node` makes from the root, every split priced with its traversal.
    fn build_without_root_phase(boxes: &[Aabb]) -> (Bvh, Vec<u32>) {
        let mut nodes = vec![Node { min: Vec3::ZERO, first: 0, max: Vec3::ZERO, count: 0 }];
        let mut prims = build_prims(boxes, |_| false);
        build_node(&mut nodes, 0, &mut prims, 0, boxes.len(), 0);
        (Bvh { nodes }, prims.iter().map(|p| p.index).collect())
    }

    /// A small scene's splits within the root wide node are free: eight clusters of four boxes
    /// get a leaf each, where the SAH alone (a leaf priced per block of eight) put two clusters
    /// in each of four leaves.
    #[test]
    fn small_scenes_fill_the_root_with_tight_leaves() {
        let cluster = |c: usize| {
            (0..4).map(move |i| {
                let p = Vec3::new(10.0 * c as f32 + 0.2 * i as f32, 0.0, 0.0);
                Aabb::new(p, p + Vec3::splat(0.1))
            })
        };
        let boxes: Vec<Aabb> = (0..8).flat_map(cluster).collect();
        let (bvh, order) = Bvh::build(&boxes);
        assert_eq!(bvh.stats().leaves, 8);
        for leaf in bvh.nodes.iter().filter(|n| n.count > 0) {
            let clusters: Vec<u32> = (leaf.first..leaf.first + leaf.count).map(|i| order[i as usize] / 4).collect();
            assert_eq!(clusters, vec![clusters[0]; 4], "a leaf of one cluster");
        }
        assert_eq!(build_without_root_phase(&boxes).0.stats().leaves, 4);
    }

    /// A large input's top splits anyway: its tree is the one `build_node` alone makes, node
    /// for node (the array's order aside), on boxes placed at random so that the SAH's bins
    /// rarely tie.
    #[test]
    fn large_inputs_are_built_as_before() {
        let mut rng = crate::sampling::Rng::new(5, 0);
        for n in [65, 300, 2000] {
            let boxes: Vec<Aabb> = (0..n)
                .map(|_| {
                    let p = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 100.0;
                    let size = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 3.0;
                    Aabb::new(p, p + size)
                })
                .collect();
            let (bvh, order) = Bvh::build(&boxes);
            let (plain, plain_order) = build_without_root_phase(&boxes);
            assert_eq!(order, plain_order, "{n} boxes");
            fn same(a: &Bvh, i: usize, b: &Bvh, j: usize) -> bool {
                let (x, y) = (&a.nodes[i], &b.nodes[j]);
                let here = x.min == y.min && x.max == y.max && x.count == y.count;
                if x.count > 0 {
                    return here && x.first == y.first;
                }
                let (l, r) = (x.first as usize, y.first as usize);
                here && same(a, l, b, r) && same(a, l + 1, b, r + 1)
            }
            assert!(same(&bvh, 0, &plain, 0), "{n} boxes: the trees differ");
        }
    }

    #[test]
    fn stats_are_consistent() {
        let boxes: Vec<Aabb> = (0..1000)
            .map(|i| {
                let p = Vec3::new((i % 10) as f32, ((i / 10) % 10) as f32, (i / 100) as f32);
                Aabb::new(p, p + Vec3::splat(0.5))
            })
            .collect();
        let (bvh, order) = Bvh::build(&boxes);
        let mut sorted = order.clone();
        sorted.sort();
        assert_eq!(sorted, (0..1000).collect::<Vec<u32>>());
        let s = bvh.stats();
        assert_eq!(s.nodes, 2 * s.leaves - 1);
        assert!(s.depth >= 8 && s.depth < 40, "{s:?}");
        assert!(s.sah_cost > 1.0 && s.sah_cost < 100.0, "{s:?}");
    }
}
