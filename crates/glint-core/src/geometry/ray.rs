use glam::Vec3;

/// A ray `origin + t·direction` for `t` in the open interval `(t_min, t_max)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: Vec3,
    pub direction: Vec3,
    pub t_min: f32,
    pub t_max: f32,
}

impl Ray {
    /// A ray over `(0, ∞)`.
    pub fn new(origin: Vec3, direction: Vec3) -> Self {
        Self { origin, direction, t_min: 0.0, t_max: f32::INFINITY }
    }

    pub fn with_range(origin: Vec3, direction: Vec3, t_min: f32, t_max: f32) -> Self {
        Self { origin, direction, t_min, t_max }
    }

    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.direction
    }

    /// Whether `t` lies strictly inside the ray's interval, as the course checks `t > t_min`.
    #[inline]
    pub fn contains(&self, t: f32) -> bool {
        t > self.t_min && t < self.t_max
    }
}
