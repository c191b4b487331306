//! A voxel field: values of one or three channels on a regular grid over the unit cube, placed
//! in the world by an affine map, and looked up by trilinear interpolation between voxel
//! centres with clamping at the edges (Mitsuba's `gridvolume` under its defaults). Grid media
//! hold their extinction in one and may hold their albedo in another.

use glam::{Affine3A, Vec3};

use crate::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub struct VoxelField {
    /// Voxels along x, y and z.
    resolution: [usize; 3],
    /// 1 (grey) or 3 (RGB).
    channels: usize,
    /// Channel fastest, then x, then y, then z.
    values: Vec<f32>,
    /// World → the field's unit cube.
    to_local: Affine3A,
    /// The largest value of any channel.
    max: f32,
    /// Lookups outside the box read the field repeated (Mitsuba's `wrap_mode` `repeat`),
    /// rather than its nearest edge.
    repeat: bool,
}

impl VoxelField {
    /// `None` if the sizes disagree, a value is negative or not finite, the channel count is
    /// neither 1 nor 3, or `to_world` cannot be inverted.
    pub fn new(resolution: [usize; 3], channels: usize, values: Vec<f32>, to_world: Affine3A) -> Option<Self> {
        let count = resolution.iter().try_fold(channels, |n, &r| n.checked_mul(r).filter(|_| r > 0))?;
        let determinant = to_world.matrix3.determinant();
        if !matches!(channels, 1 | 3)
            || count != values.len()
            || values.iter().any(|v| !(v.is_finite() && *v >= 0.0))
            || !(determinant.is_finite() && determinant != 0.0 && to_world.translation.is_finite())
        {
            return None;
        }
        let max = values.iter().fold(0.0f32, |m, &v| m.max(v));
        Some(Self { resolution, channels, values, to_local: to_world.inverse(), max, repeat: false })
    }

    /// One value everywhere in the box `to_world` places (Mitsuba's `constvolume`).
    pub fn constant(value: Rgb, to_world: Affine3A) -> Option<Self> {
        Self::new([1, 1, 1], 3, value.to_array().to_vec(), to_world)
    }

    /// The same field, repeated past its box in every direction, voxels interpolated across
    /// the seams with the opposite side's.
    pub fn repeating(self) -> Self {
        Self { repeat: true, ..self }
    }

    pub fn max(&self) -> f32 {
        self.max
    }

    /// Whether the world point `p` lies in the field's box.
    pub fn contains(&self, p: Vec3) -> bool {
        let local = self.to_local.transform_point3(p);
        local.min_element() >= 0.0 && local.max_element() <= 1.0
    }

    /// The value at the world point `p`: trilinear between voxel centres, clamped to the
    /// nearest edge outside them (and outside the box), or read from the repeated field.
    pub fn eval(&self, p: Vec3) -> Rgb {
        let local = self.to_local.transform_point3(p);
        let [nx, ny, nz] = self.resolution;
        let repeat = self.repeat;
        let at = |axis: f32, n: usize| {
            if repeat {
                let x = axis * n as f32 - 0.5;
                // NaN (a point at infinity) reads the first voxel.
                let x = if x.is_finite() { x } else { 0.0 };
                let floor = x.floor();
                let i = (floor as i64).rem_euclid(n as i64) as usize;
                return (i, (i + 1) % n, x - floor);
            }
            let x = (axis * n as f32 - 0.5).clamp(0.0, (n - 1) as f32);
            // NaN (a point at infinity) clamps to the first voxel.
            let x = if x.is_nan() { 0.0 } else { x };
            let i = (x as usize).min(n.saturating_sub(2));
            (i, (i + 1).min(n - 1), x - i as f32)
        };
        let ((x0, x1, fx), (y0, y1, fy), (z0, z1, fz)) = (at(local.x, nx), at(local.y, ny), at(local.z, nz));
        let voxel = |x: usize, y: usize, z: usize| {
            let i = ((z * ny + y) * nx + x) * self.channels;
            if self.channels == 1 {
                Rgb::splat(self.values[i])
            } else {
                Rgb::new(self.values[i], self.values[i + 1], self.values[i + 2])
            }
        };
        let lerp = |a: Rgb, b: Rgb, t: f32| a + (b - a) * t;
        let bottom =
            lerp(lerp(voxel(x0, y0, z0), voxel(x1, y0, z0), fx), lerp(voxel(x0, y1, z0), voxel(x1, y1, z0), fx), fy);
        let top =
            lerp(lerp(voxel(x0, y0, z1), voxel(x1, y0, z1), fx), lerp(voxel(x0, y1, z1), voxel(x1, y1, z1), fx), fy);
        lerp(bottom, top, fz)
    }

    /// The part of [0, t_max] where the ray `origin + t·direction` is inside the field's box.
    /// (An affine map keeps a line's parameter, so the box is clipped in its own space.)
    /// `None` if the ray misses the box or the part is not finite.
    pub fn span(&self, origin: Vec3, direction: Vec3, t_max: f32) -> Option<(f32, f32)> {
        let (o, d) = (self.to_local.transform_point3(origin), self.to_local.transform_vector3(direction));
        let (mut enter, mut exit) = (0.0f32, t_max);
        for axis in 0..3 {
            if d[axis] == 0.0 {
                // Parallel to this axis's faces: inside the slab (faces included) or a miss.
                if !(0.0..=1.0).contains(&o[axis]) {
                    return None;
                }
                continue;
            }
            let (a, b) = (-o[axis] / d[axis], (1.0 - o[axis]) / d[axis]);
            enter = enter.max(a.min(b));
            exit = exit.min(a.max(b));
        }
        (enter < exit && exit.is_finite()).then_some((enter, exit))
    }
}

/// The map from the unit cube onto the box `min`–`max`.
pub fn box_to_world(min: Vec3, max: Vec3) -> Affine3A {
    Affine3A::from_scale_rotation_translation(max - min, glam::Quat::IDENTITY, min)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lookups_interpolate_per_channel_and_clamp_outside() {
        // 2 × 1 × 1 RGB voxels over [0, 2] × [0, 1]²: centres at x = ½ and 1½.
        let field = VoxelField::new(
            [2, 1, 1],
            3,
            vec![0.0, 1.0, 2.0, 4.0, 1.0, 0.0],
            box_to_world(Vec3::ZERO, Vec3::new(2.0, 1.0, 1.0)),
        )
        .unwrap();
        let at = |x: f32| field.eval(Vec3::new(x, 0.5, 0.5));
        assert_eq!(at(1.0), Rgb::new(2.0, 1.0, 1.0));
        assert_eq!(at(0.75), Rgb::new(1.0, 1.0, 1.5));
        // Clamped beyond the centres, and outside the box.
        assert_eq!(at(0.2), Rgb::new(0.0, 1.0, 2.0));
        assert_eq!(at(-3.0), Rgb::new(0.0, 1.0, 2.0));
        assert_eq!(at(7.0), Rgb::new(4.0, 1.0, 0.0));
        assert_eq!(field.max(), 4.0);
        assert!(field.contains(Vec3::new(1.9, 0.1, 0.9)) && !field.contains(Vec3::new(2.1, 0.5, 0.5)));
    }

    /// Repeated, the field reads the same one box over, and between the last voxel's centre
    /// and the next box's first it blends the two.
    #[test]
    fn a_repeated_field_wraps_around() {
        let field = VoxelField::new(
            [2, 1, 1],
            3,
            vec![0.0, 1.0, 2.0, 4.0, 1.0, 0.0],
            box_to_world(Vec3::ZERO, Vec3::new(2.0, 1.0, 1.0)),
        )
        .unwrap()
        .repeating();
        let at = |x: f32| field.eval(Vec3::new(x, 0.5, 0.5));
        assert_eq!(at(0.75), Rgb::new(1.0, 1.0, 1.5));
        assert_eq!(at(0.75 + 2.0), at(0.75));
        assert_eq!(at(0.75 - 4.0), at(0.75));
        // Halfway between the second voxel's centre (x = 1½) and the next box's first (2½).
        assert_eq!(at(2.0), Rgb::new(2.0, 1.0, 1.0));
        // A point at infinity reads a voxel, not NaN.
        assert!(field.eval(Vec3::new(f32::INFINITY, 0.5, 0.5)).is_finite());
    }

    #[test]
    fn a_rotated_box_is_clipped_in_its_own_space() {
        // The unit cube scaled by 2 and turned 45° about z: a ray along x through its centre
        // crosses it over the diagonal of a 2 × 2 square, 2√2 long.
        let to_world = Affine3A::from_rotation_z(std::f32::consts::FRAC_PI_4)
            * Affine3A::from_scale(Vec3::splat(2.0))
            * Affine3A::from_translation(Vec3::splat(-0.5));
        let field = VoxelField::constant(Rgb::ONE, to_world).unwrap();
        let (enter, exit) = field.span(Vec3::new(-5.0, 0.0, 0.0), Vec3::X, 100.0).unwrap();
        assert!((enter - (5.0 - 2f32.sqrt())).abs() < 1e-5 && (exit - (5.0 + 2f32.sqrt())).abs() < 1e-5);
        // Clipped by t_max, and missed.
        assert_eq!(field.span(Vec3::new(-5.0, 0.0, 0.0), Vec3::X, 4.0).map(|s| s.1), Some(4.0));
        assert_eq!(field.span(Vec3::new(-5.0, 3.0, 0.0), Vec3::X, 100.0), None);
        // Along a face: both faces of a slab count as inside it.
        let unit = VoxelField::constant(Rgb::ONE, box_to_world(Vec3::splat(-1.0), Vec3::ONE)).unwrap();
        for x in [-1.0f32, 1.0] {
            let span = unit.span(Vec3::new(x, 0.0, -5.0), Vec3::Z, 100.0);
            assert!(span.is_some_and(|(a, b)| (a - 4.0).abs() < 1e-5 && (b - 6.0).abs() < 1e-5), "x = {x}: {span:?}");
        }
        assert_eq!(unit.span(Vec3::new(1.5, 0.0, -5.0), Vec3::Z, 100.0), None);
    }

    #[test]
    fn bad_fields_are_refused() {
        let unit = Affine3A::IDENTITY;
        assert!(VoxelField::new([2, 1, 1], 1, vec![1.0], unit).is_none());
        assert!(VoxelField::new([1, 1, 1], 1, vec![-1.0], unit).is_none());
        assert!(VoxelField::new([1, 1, 1], 2, vec![1.0, 1.0], unit).is_none());
        assert!(VoxelField::new([1, 1, 1], 1, vec![1.0], Affine3A::from_scale(Vec3::new(1.0, 0.0, 1.0))).is_none());
        assert!(VoxelField::new([usize::MAX, 2, 1], 1, vec![1.0], unit).is_none());
    }
}
