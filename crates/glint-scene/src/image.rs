//! Texture images through the `image` crate: PNG and JPEG (sRGB-encoded, decoded to linear)
//! and OpenEXR (linear as stored).

use glint_core::Rgb;

/// Width, height and linear RGB pixels (row 0 = top) of an image file's bytes.
pub(crate) fn decode(name: &str, bytes: &[u8]) -> Result<(u32, u32, Vec<Rgb>), String> {
    let image = image::load_from_memory(bytes).map_err(|e| format!("cannot decode: {e}"))?;
    let linear_already = name.to_ascii_lowercase().ends_with(".exr");
    let rgb = image.to_rgb32f();
    let (width, height) = rgb.dimensions();
    let pixels = rgb
        .pixels()
        .map(|p| {
            let c = Rgb::from(p.0);
            if linear_already {
                c
            } else {
                Rgb::new(srgb_to_linear(c.x), srgb_to_linear(c.y), srgb_to_linear(c.z))
            }
        })
        .collect();
    Ok((width, height, pixels))
}

/// The sRGB decoding function (IEC 61966-2-1).
pub(crate) fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_decoding_by_hand() {
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-6);
        assert!((srgb_to_linear(0.5) - 0.214_041).abs() < 1e-5);
    }

    #[test]
    fn png_round_trip_through_memory() {
        let img = image::RgbImage::from_raw(2, 1, vec![0, 0, 0, 255, 255, 255]).unwrap();
        let mut bytes = std::io::Cursor::new(Vec::new());
        img.write_to(&mut bytes, image::ImageFormat::Png).unwrap();
        let (w, h, px) = decode("t.png", bytes.get_ref()).unwrap();
        assert_eq!((w, h), (2, 1));
        assert_eq!(px[0], Rgb::ZERO);
        assert!((px[1] - Rgb::ONE).abs().max_element() < 1e-6);
        assert!(decode("t.png", b"garbage").is_err());
    }
}
