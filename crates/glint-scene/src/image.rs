//! Texture images through the `image` crate: PNG and JPEG (sRGB-encoded, decoded to linear),
//! OpenEXR and Radiance HDR (linear as stored).

use glint_core::Rgb;

/// Width, height and linear RGB pixels (row 0 = top) of an image file's bytes; with `raw`, the
/// stored values as they are (a normal map's), never decoded from sRGB.
pub fn decode(name: &str, bytes: &[u8], raw: bool) -> Result<(u32, u32, Vec<Rgb>), String> {
    let image = decode_within_limit(bytes)?;
    let lower = name.to_ascii_lowercase();
    let linear_already = raw || lower.ends_with(".exr") || lower.ends_with(".hdr");
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

/// Width, height and alpha (row 0 = top; alpha is linear as stored) of an image file's bytes,
/// or `None` when the image has no alpha channel.
pub(crate) fn decode_alpha(bytes: &[u8]) -> Result<Option<(u32, u32, Vec<f32>)>, String> {
    let image = decode_within_limit(bytes)?;
    if !image.color().has_alpha() {
        return Ok(None);
    }
    let rgba = image.to_rgba32f();
    let (width, height) = rgba.dimensions();
    Ok(Some((width, height, rgba.pixels().map(|p| p.0[3]).collect())))
}

/// The decoded image, its size checked against the memory limit from its header first: a
/// 1.2 KB EXR declaring a large data window decoded to 1.2 GB (found by glint-fuzz). A pixel
/// takes up to 16 bytes decoded, 16 as RGBA f32, and 12 once ours.
fn decode_within_limit(bytes: &[u8]) -> Result<image::DynamicImage, String> {
    let reader = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| format!("cannot decode: {e}"))?;
    let (w, h) = reader.into_dimensions().map_err(|e| format!("cannot decode: {e}"))?;
    let needed = (u64::from(w) * u64::from(h)).saturating_mul(40);
    if needed > crate::limits::memory_limit() {
        return Err(format!(
            "the image is {w}x{h} pixels; decoding it takes about {}, more than the memory limit of {} ({})",
            crate::limits::describe(needed),
            crate::limits::describe(crate::limits::memory_limit()),
            crate::limits::RAISE
        ));
    }
    image::load_from_memory(bytes).map_err(|e| format!("cannot decode: {e}"))
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
    fn an_image_beyond_the_memory_limit_is_refused_from_its_header() {
        // A PNG header declaring 60000 x 60000 pixels (and no data to speak of).
        let mut chunk = b"IHDR".to_vec();
        chunk.extend_from_slice(&60000u32.to_be_bytes());
        chunk.extend_from_slice(&60000u32.to_be_bytes());
        chunk.extend_from_slice(&[8, 2, 0, 0, 0]);
        let mut crc = flate2::Crc::new();
        crc.update(&chunk);
        let mut png = b"\x89PNG\r\n\x1a\n\0\0\0\x0d".to_vec();
        png.extend_from_slice(&chunk);
        png.extend_from_slice(&crc.sum().to_be_bytes());
        png.extend_from_slice(b"\0\0\0\0IDAT\x35\xaf\x06\x1e\0\0\0\0IEND\xae\x42\x60\x82");
        let e = decode("big.png", &png, false).unwrap_err();
        assert!(e.contains("60000x60000") && e.contains("memory limit"), "{e}");
    }

    #[test]
    fn srgb_decoding_by_hand() {
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-6);
        assert!((srgb_to_linear(0.5) - 0.214_041).abs() < 1e-5);
    }

    #[test]
    fn hdr_and_exr_are_taken_as_linear() {
        let values = [Rgb::new(2.0, 0.5, 0.25), Rgb::new(420.0, 400.0, 360.0)];
        let img = image::Rgb32FImage::from_fn(2, 1, |x, _| image::Rgb(values[x as usize].to_array()));
        for format in [image::ImageFormat::Hdr, image::ImageFormat::OpenExr] {
            let mut bytes = std::io::Cursor::new(Vec::new());
            image::DynamicImage::ImageRgb32F(img.clone()).write_to(&mut bytes, format).unwrap();
            let name = if format == image::ImageFormat::Hdr { "sky.hdr" } else { "sky.exr" };
            let (_, _, px) = decode(name, bytes.get_ref(), false).unwrap();
            for (p, v) in px.iter().zip(values) {
                assert!(((*p - v) / v).abs().max_element() < 0.01, "{name}: {p} vs {v}");
            }
        }
    }

    #[test]
    fn png_round_trip_through_memory() {
        let img = image::RgbImage::from_raw(2, 1, vec![0, 0, 0, 255, 255, 255]).unwrap();
        let mut bytes = std::io::Cursor::new(Vec::new());
        img.write_to(&mut bytes, image::ImageFormat::Png).unwrap();
        let (w, h, px) = decode("t.png", bytes.get_ref(), false).unwrap();
        assert_eq!((w, h), (2, 1));
        assert_eq!(px[0], Rgb::ZERO);
        assert!((px[1] - Rgb::ONE).abs().max_element() < 1e-6);
        assert!(decode("t.png", b"garbage", false).is_err());
    }

    /// A raw PNG (a normal map) keeps its stored values: 128 is 128/255, not its sRGB decoding.
    #[test]
    fn raw_images_are_not_decoded_from_srgb() {
        let img = image::RgbImage::from_raw(1, 1, vec![128, 128, 255]).unwrap();
        let mut bytes = std::io::Cursor::new(Vec::new());
        img.write_to(&mut bytes, image::ImageFormat::Png).unwrap();
        let (_, _, raw) = decode("n.png", bytes.get_ref(), true).unwrap();
        assert!((raw[0] - Rgb::new(128.0 / 255.0, 128.0 / 255.0, 1.0)).abs().max_element() < 1e-6, "{}", raw[0]);
        let (_, _, decoded) = decode("n.png", bytes.get_ref(), false).unwrap();
        assert!((decoded[0].x - srgb_to_linear(128.0 / 255.0)).abs() < 1e-6);
    }
}
