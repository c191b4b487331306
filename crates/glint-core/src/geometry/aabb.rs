use glam::Vec3;

/// An axis-aligned bounding box. The empty box has `min = +∞`, `max = −∞`, so that
/// growing it by any point or box gives that point or box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Default for Aabb {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl Aabb {
    pub const EMPTY: Aabb = Aabb { min: Vec3::INFINITY, max: Vec3::NEG_INFINITY };

    pub fn new(min: Vec3, max: Vec3) -> Self {
        Self { min, max }
    }

    pub fn from_points(points: impl IntoIterator<Item = Vec3>) -> Self {
        points.into_iter().fold(Self::EMPTY, |b, p| b.grow_point(p))
    }

    pub fn grow_point(self, p: Vec3) -> Self {
        Self { min: self.min.min(p), max: self.max.max(p) }
    }

    pub fn union(self, o: Aabb) -> Self {
        Self { min: self.min.min(o.min), max: self.max.max(o.max) }
    }

    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y || self.min.z > self.max.z
    }

    pub fn extent(&self) -> Vec3 {
        self.max - self.min
    }

    pub fn centroid(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// Surface area, 0 for the empty box (the SAH's measure).
    pub fn surface_area(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let e = self.extent();
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }

    /// The box's 8 corners.
    pub fn corners(&self) -> [Vec3; 8] {
        std::array::from_fn(|i| {
            Vec3::new(
                if i & 1 == 0 { self.min.x } else { self.max.x },
                if i & 2 == 0 { self.min.y } else { self.max.y },
                if i & 4 == 0 { self.min.z } else { self.max.z },
            )
        })
    }

    /// The interval (t_enter, t_exit) over which the ray `origin + t·dir` is inside the box's
    /// three slabs (unbounded by `t_min`/`t_max`); empty when `t_enter > t_exit`.
    ///
    /// A ray parallel to a slab with its origin exactly on one of the slab's planes gives
    /// 0 · ∞ = NaN for that plane; that slab then does not limit the ray (the face counts as
    /// inside), so NaN lanes are replaced by (−∞, +∞) before the min/max.
    #[inline(always)]
    pub fn slab_interval(&self, origin: Vec3, inv_dir: Vec3) -> (f32, f32) {
        let t0 = (self.min - origin) * inv_dir;
        let t1 = (self.max - origin) * inv_dir;
        let undefined = t0.is_nan_mask() | t1.is_nan_mask();
        let near = Vec3::select(undefined, Vec3::NEG_INFINITY, t0.min(t1));
        let far = Vec3::select(undefined, Vec3::INFINITY, t0.max(t1));
        (near.max_element(), far.min_element())
    }

    /// Slab test over `[t_min, t_max]`, given the reciprocal direction; the entry distance.
    /// Conservative (pbrt-v4's Bounds3::IntersectP): the exit distance is widened by its
    /// rounding error, 1 + 2γ₃, so no ray that meets the box is culled.
    #[inline(always)]
    pub fn hit_distance(&self, origin: Vec3, inv_dir: Vec3, t_min: f32, t_max: f32) -> Option<f32> {
        let (t_enter, t_exit) = self.slab_interval(origin, inv_dir);
        let t_exit = t_exit * (1.0 + 2.0 * super::gamma(3));
        let (t_enter, t_exit) = (t_enter.max(t_min), t_exit.min(t_max));
        (t_enter <= t_exit).then_some(t_enter)
    }
}
