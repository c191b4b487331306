//! pbrt's environment maps resampled into glint's: pbrt-v4 stores an infinite light's
//! radiance as a square image in Clarberg's equal-area octahedral mapping (pbrt-v3 as a 2:1
//! latitude–longitude image about +z); glint's environment is a latitude–longitude image
//! about +y, sampled for next-event estimation over its own grid. Resampling once at load
//! keeps one map format in the core, and the light's transform is baked in on the way.

use glam::{Mat3, Vec2, Vec3};
use glint_core::Rgb;

/// pbrt's `EqualAreaSquareToSphere`: a point of [0, 1]² to a unit direction.
pub fn square_to_sphere(p: Vec2) -> Vec3 {
    let (u, v) = (2.0 * p.x - 1.0, 2.0 * p.y - 1.0);
    let (up, vp) = (u.abs(), v.abs());
    let signed_distance = 1.0 - (up + vp);
    let d = signed_distance.abs();
    let r = 1.0 - d;
    let phi = if r == 0.0 { 1.0 } else { (vp - up) / r + 1.0 } * std::f32::consts::FRAC_PI_4;
    let z = (1.0 - r * r).copysign(signed_distance);
    let (sin_phi, cos_phi) = phi.sin_cos();
    let scale = r * (2.0 - r * r).max(0.0).sqrt();
    Vec3::new((cos_phi * scale).copysign(u), (sin_phi * scale).copysign(v), z)
}

/// The inverse of `square_to_sphere` (exact atan, where pbrt approximates it).
pub fn sphere_to_square(d: Vec3) -> Vec2 {
    let (x, y, z) = (d.x.abs(), d.y.abs(), d.z.abs());
    let r = (1.0 - z).max(0.0).sqrt();
    let a = x.max(y);
    let b = x.min(y);
    let b_over_a = if a == 0.0 { 0.0 } else { b / a };
    let mut phi = b_over_a.atan() * 2.0 / std::f32::consts::PI;
    if x < y {
        phi = 1.0 - phi;
    }
    let mut v = phi * r;
    let mut u = r - v;
    if d.z < 0.0 {
        std::mem::swap(&mut u, &mut v);
        u = 1.0 - u;
        v = 1.0 - v;
    }
    u = u.copysign(d.x);
    v = v.copysign(d.y);
    Vec2::new(0.5 * (u + 1.0), 0.5 * (v + 1.0))
}

/// Whether a map's size is one of pbrt's layouts: square (pbrt-v4's equal-area octahedral
/// map) or twice as wide as high (latitude–longitude).
pub fn check_layout(width: u32, height: u32) -> Result<(), String> {
    if width != height && width != 2 * height {
        return Err(format!(
            "an environment map is square (pbrt-v4's equal-area octahedral map) or twice as wide as high (latitude–longitude), not {width}x{height}"
        ));
    }
    Ok(())
}

/// The size of glint's map a pbrt map is resampled to by default: as many texels across
/// each direction's circle.
pub fn resampled_size(width: u32, height: u32) -> (u32, u32) {
    if width == height {
        (2 * width, height.max(2))
    } else {
        (width, height.max(2))
    }
}

/// The illuminance pbrt-v4 gives an equal-area map (`illuminance`, scaled to by the
/// parameter of that name): the luminance of the texels above its horizon (light-space +z)
/// times their cosines, times 2π over the texel count. (That is half the map's illuminance
/// on a surface facing +z, whose texels each span 4π over the count; glint scales as pbrt
/// does, so that the scene renders as in pbrt.)
pub fn illuminance(width: u32, height: u32, pixels: &[Rgb]) -> Result<f32, String> {
    if width != height {
        return Err("`illuminance` needs pbrt-v4's square (equal-area) map".into());
    }
    let mut sum = 0.0f64;
    for y in 0..height {
        for x in 0..width {
            let st = Vec2::new((x as f32 + 0.5) / width as f32, (y as f32 + 0.5) / height as f32);
            let w = square_to_sphere(st);
            if w.z > 0.0 {
                let c = pixels[(y * width + x) as usize];
                sum += f64::from(c.dot(Rgb::new(0.2126, 0.7152, 0.0722)) * w.z);
            }
        }
    }
    Ok((sum * 2.0 * std::f64::consts::PI / (f64::from(width) * f64::from(height))) as f32)
}

/// A pbrt map (row 0 at the top) as glint's environment, on glint's grid of `size` (by
/// default `resampled_size`'s): `light_to_world` is the light's transform (its rotation
/// part). Returns width, height and pixels.
pub fn resample(
    width: u32,
    height: u32,
    pixels: &[Rgb],
    light_to_world: Mat3,
    size: Option<(u32, u32)>,
) -> Result<(u32, u32, Vec<Rgb>), String> {
    check_layout(width, height)?;
    let octahedral = width == height;
    let world_to_light = light_to_world.inverse();
    let (out_w, out_h) = size.unwrap_or_else(|| resampled_size(width, height));
    let mut out = Vec::with_capacity((out_w * out_h) as usize);
    for y in 0..out_h {
        for x in 0..out_w {
            // glint's grid: column x at u = (x + ½)/W, row y at v = y/(H − 1).
            let phi = 2.0 * std::f32::consts::PI * (x as f32 + 0.5) / out_w as f32;
            let theta = std::f32::consts::PI * y as f32 / (out_h - 1) as f32;
            let world = Vec3::new(theta.sin() * phi.sin(), theta.cos(), -theta.sin() * phi.cos());
            let d = (world_to_light * world).normalize_or_zero();
            out.push(if octahedral {
                let st = sphere_to_square(d);
                bilinear(width, height, pixels, st * Vec2::new(width as f32, height as f32), true)
            } else {
                // pbrt-v3: s = φ/2π about +z from +x, t = θ/π from +z (row 0).
                let phi = d.y.atan2(d.x).rem_euclid(2.0 * std::f32::consts::PI);
                let theta = d.z.clamp(-1.0, 1.0).acos();
                let st = Vec2::new(phi / (2.0 * std::f32::consts::PI), theta / std::f32::consts::PI);
                bilinear(width, height, pixels, st * Vec2::new(width as f32, height as f32), false)
            });
        }
    }
    Ok((out_w, out_h, out))
}

/// Bilinear lookup at continuous pixel coordinates (texel centres at +½); beyond the edges
/// the octahedral map continues mirrored across them (pbrt's `OctahedralSphere` wrap), the
/// latitude–longitude map wraps around in x and clamps in y.
fn bilinear(width: u32, height: u32, pixels: &[Rgb], p: Vec2, octahedral: bool) -> Rgb {
    let (w, h) = (width as i64, height as i64);
    let texel = |mut x: i64, mut y: i64| {
        if octahedral {
            if x < 0 {
                x = -x - 1;
                y = h - 1 - y;
            } else if x >= w {
                x = 2 * w - 1 - x;
                y = h - 1 - y;
            }
            if y < 0 {
                x = w - 1 - x;
                y = -y - 1;
            } else if y >= h {
                x = w - 1 - x;
                y = 2 * h - 1 - y;
            }
        } else {
            x = x.rem_euclid(w);
        }
        pixels[(y.clamp(0, h - 1) * w + x.clamp(0, w - 1)) as usize]
    };
    let q = p - Vec2::splat(0.5);
    let (x0, y0) = (q.x.floor() as i64, q.y.floor() as i64);
    let (fx, fy) = (q.x - q.x.floor(), q.y - q.y.floor());
    let top = texel(x0, y0) * (1.0 - fx) + texel(x0 + 1, y0) * fx;
    let bottom = texel(x0, y0 + 1) * (1.0 - fx) + texel(x0 + 1, y0 + 1) * fx;
    top * (1.0 - fy) + bottom * fy
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_equal_area_mapping_round_trips_and_puts_the_axes_where_pbrt_does() {
        assert!((square_to_sphere(Vec2::splat(0.5)) - Vec3::Z).length() < 1e-6);
        assert!((square_to_sphere(Vec2::new(1.0, 0.5)) - Vec3::X).length() < 1e-6);
        assert!((square_to_sphere(Vec2::new(0.5, 1.0)) - Vec3::Y).length() < 1e-6);
        assert!((square_to_sphere(Vec2::ZERO) + Vec3::Z).length() < 1e-6);
        for i in 0..400 {
            let p = Vec2::new((i % 20) as f32 / 19.0, (i / 20) as f32 / 19.0) * 0.98 + Vec2::splat(0.01);
            let d = square_to_sphere(p);
            assert!((d.length() - 1.0).abs() < 1e-5);
            assert!((sphere_to_square(d) - p).length() < 1e-4, "{p} → {d} → {}", sphere_to_square(d));
        }
    }

    #[test]
    fn equal_areas_of_the_square_are_equal_solid_angles() {
        // The fraction of directions with z > 0.5 is (1 − 0.5)/2 = ¼ of the sphere.
        let n = 400;
        let above = (0..n * n)
            .filter(|i| square_to_sphere(Vec2::new((i % n) as f32 + 0.5, (i / n) as f32 + 0.5) / n as f32).z > 0.5)
            .count();
        assert!((above as f64 / (n * n) as f64 - 0.25).abs() < 2e-3, "{above}");
    }

    #[test]
    fn a_map_bright_toward_plus_z_is_bright_toward_the_transformed_axis() {
        // An octahedral map lit only near its centre (+z in the light's frame), under pbrt's
        // usual `Rotate -90 1 0 0` (light +z → world +y): glint's top row is the bright one.
        let n = 32u32;
        let pixels: Vec<Rgb> = (0..n * n)
            .map(|i| {
                let st = Vec2::new((i % n) as f32 + 0.5, (i / n) as f32 + 0.5) / n as f32;
                Rgb::splat(square_to_sphere(st).z.max(0.0))
            })
            .collect();
        let rotation = Mat3::from_rotation_x(-std::f32::consts::FRAC_PI_2);
        assert!((rotation * Vec3::Z - Vec3::Y).length() < 1e-6);
        let (w, h, out) = resample(n, n, &pixels, rotation, None).unwrap();
        assert_eq!((w, h), (64, 32));
        let row_mean = |y: u32| (0..w).map(|x| out[(y * w + x) as usize].x).sum::<f32>() / w as f32;
        assert!(row_mean(0) > 0.95, "{}", row_mean(0));
        assert!(row_mean(h - 1) == 0.0);
        // The horizon row (θ = 90°): cos θ = 0.
        assert!(row_mean(h / 2) < 0.08, "{}", row_mean(h / 2));
    }
}
