//! A normal map's `scale` (glTF: the texture's normal n = 2·rgb − 1 becomes
//! normalize(scale·n.x, scale·n.y, n.z)) baked into an image of its own, decoded, among the
//! made files, read by glint's `normal-map` as any other. The scaled normal is
//! stored by its direction, which is all the normal map reads, in a form that stays within
//! [−1, 1]: (s·x, s·y, z) for |s| ≤ 1, and its multiple by 1/|s|, (±x, ±y, z/|s|), beyond.

use glam::Vec3;

use crate::source::MadeFile;

/// The image of the normal map `bytes` (PNG or JPEG, read raw) with `scale` applied.
pub fn scaled_image(bytes: &[u8], scale: f32) -> Result<MadeFile, String> {
    let (width, height, mut pixels) = crate::image::decode("normals.png", bytes, true)?;
    for c in &mut pixels {
        let n = scaled(2.0 * *c - Vec3::ONE, scale);
        *c = ((n + Vec3::ONE) * 0.5).clamp(Vec3::ZERO, Vec3::ONE);
    }
    Ok(MadeFile::Image { width, height, pixels })
}

/// A vector in the direction of (s·x, s·y, z), each component within [−1, 1] when n's are.
fn scaled(n: Vec3, s: f32) -> Vec3 {
    if s.abs() <= 1.0 {
        Vec3::new(s * n.x, s * n.y, n.z)
    } else {
        Vec3::new(s.signum() * n.x, s.signum() * n.y, n.z / s.abs())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scaling_keeps_the_direction_gltf_gives() {
        let n = Vec3::new(0.6, 0.0, 0.8);
        // s = ½: (0.3, 0, 0.8).
        assert_eq!(scaled(n, 0.5), Vec3::new(0.3, 0.0, 0.8));
        // s = 2: (1.2, 0, 0.8) ∝ (0.6, 0, 0.4).
        assert_eq!(scaled(n, 2.0), Vec3::new(0.6, 0.0, 0.4));
        // s = −2: (−1.2, 0, 0.8) ∝ (−0.6, 0, 0.4); s = 0: flat.
        assert_eq!(scaled(n, -2.0), Vec3::new(-0.6, 0.0, 0.4));
        assert_eq!(scaled(n, 0.0), Vec3::new(0.0, 0.0, 0.8));
    }

    #[test]
    fn the_scaled_image_holds_the_scaled_direction() {
        // One texel, n = (0.6, 0, 0.8) stored as rgb = (n + 1)/2 in 16 bits.
        let texel = [0.8f32, 0.5, 0.9].map(|v| (v * 65535.0).round() as u16);
        let mut png = Vec::new();
        image::ImageBuffer::<image::Rgb<u16>, _>::from_raw(1, 1, texel.to_vec())
            .unwrap()
            .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
            .unwrap();
        let MadeFile::Image { width: 1, height: 1, pixels } = scaled_image(&png, 2.0).unwrap() else {
            panic!("not one decoded texel")
        };
        let n = 2.0 * pixels[0] - Vec3::ONE;
        // ∝ (1.2, 0, 0.8): the normal tilts further, as glTF's scale 2 makes it.
        let expected = Vec3::new(1.2, 0.0, 0.8).normalize();
        assert!((n.normalize() - expected).length() < 1e-4, "{n}");
        assert!(pixels[0].cmpge(Vec3::ZERO).all() && pixels[0].cmple(Vec3::ONE).all());
    }
}
