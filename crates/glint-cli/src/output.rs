//! Image writers, chosen by the output file's extension: OpenEXR (32-bit float), Radiance HDR
//! (RGBE, negative values clamped to 0), PFM (float, rows stored bottom to top as the format
//! says) and PNG (8-bit sRGB, with exposure). Every
//! file glint writes goes through `write_file_atomically`: whole or not at all.

use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};

use glint_core::Rgb;
use thiserror::Error;

/// Why a file could not be written, or an image read back.
#[derive(Debug, Error)]
pub enum OutputError {
    #[error("cannot tell the image format of `{}`: the output must end in .png, .exr, .hdr or .pfm", path.display())]
    UnknownFormat { path: PathBuf },
    /// `what`: "output", "checkpoint".
    #[error("cannot write the {what} `{}`: {reason}", path.display())]
    Unwritable { what: &'static str, path: PathBuf, reason: String },
    #[error("cannot write `{}`: {reason}", path.display())]
    Unencodable { path: PathBuf, reason: String },
    #[error("cannot read the image `{}`: {reason}", path.display())]
    Unreadable { path: PathBuf, reason: String },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    Exr,
    /// Radiance RGBE.
    Hdr,
    Pfm,
    Png,
}

impl ImageFormat {
    pub fn from_path(path: &Path) -> Result<Self, OutputError> {
        match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
            Some("exr") => Ok(Self::Exr),
            Some("hdr") => Ok(Self::Hdr),
            Some("pfm") => Ok(Self::Pfm),
            Some("png") => Ok(Self::Png),
            _ => Err(OutputError::UnknownFormat { path: path.to_path_buf() }),
        }
    }
}

/// Checks, before a render starts, that the output can be written: a regular file (or a
/// new one) in a directory where glint can create its temporary file, or a character device
/// such as /dev/null. A FIFO, a socket or a directory is refused: opening a FIFO waits for a
/// reader that may never come.
pub fn check_writable(path: &Path) -> Result<ImageFormat, OutputError> {
    let format = ImageFormat::from_path(path)?;
    check_writable_file(path, "output")?;
    Ok(format)
}

/// `check_writable` for any file glint writes (`what`: "output", "checkpoint").
pub fn check_writable_file(path: &Path, what: &'static str) -> Result<(), OutputError> {
    let cannot = |why: &dyn std::fmt::Display| unwritable(what, path, why);
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => return Err(cannot(&"it is a directory")),
        Ok(m) if is_device(&m) => {
            return File::options().write(true).open(path).map(|_| ()).map_err(|e| cannot(&e));
        }
        Ok(m) if !m.is_file() => {
            return Err(cannot(&"it is not a regular file (a FIFO or socket?); glint writes files and devices only"))
        }
        // Renaming over it would replace it regardless: refuse, as writing into it would.
        Ok(m) if m.permissions().readonly() => return Err(cannot(&"it is read-only")),
        _ => {}
    }
    // Where the file will really be written: its temporary file goes beside it.
    let temporary = temporary_path(&real_path(path));
    File::create(&temporary).map_err(|e| cannot(&e))?;
    let _ = std::fs::remove_file(&temporary);
    Ok(())
}

fn unwritable(what: &'static str, path: &Path, why: &dyn std::fmt::Display) -> OutputError {
    OutputError::Unwritable { what, path: path.to_path_buf(), reason: why.to_string() }
}

#[cfg(unix)]
fn is_device(m: &std::fs::Metadata) -> bool {
    use std::os::unix::fs::FileTypeExt;
    m.file_type().is_char_device() || m.file_type().is_block_device()
}

#[cfg(not(unix))]
fn is_device(_: &std::fs::Metadata) -> bool {
    false
}

/// The file a path names, through a symbolic link (whose target is replaced, not the link).
fn real_path(path: &Path) -> PathBuf {
    std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf())
}

fn temporary_path(path: &Path) -> PathBuf {
    let name = path.file_name().map_or("glint".into(), |n| n.to_string_lossy().to_string());
    path.with_file_name(format!(".{name}.glint-{}.tmp", std::process::id()))
}

/// Writes `bytes` to `path` so that the file is either the old one or the new one whole: into
/// a temporary file beside it, flushed to disk, then renamed over it (a kill or a full disk
/// mid-write leaves the previous file as it was). A device is written directly, and every
/// error is reported (a full disk, /dev/full).
pub fn write_file_atomically(path: &Path, bytes: &[u8], what: &'static str) -> Result<(), OutputError> {
    let cannot = |why: &dyn std::fmt::Display| unwritable(what, path, why);
    if std::fs::metadata(path).is_ok_and(|m| is_device(&m)) {
        let mut device = File::options().write(true).open(path).map_err(|e| cannot(&e))?;
        return device.write_all(bytes).and_then(|_| device.flush()).map_err(|e| cannot(&e));
    }
    let target = real_path(path);
    let temporary = temporary_path(&target);
    let written = File::create(&temporary).and_then(|mut file| {
        file.write_all(bytes)?;
        file.sync_all()
    });
    let renamed = written.and_then(|_| std::fs::rename(&temporary, &target));
    if let Err(e) = renamed {
        let _ = std::fs::remove_file(&temporary);
        return Err(cannot(&e));
    }
    Ok(())
}

/// Channels of an EXR beside its image: (full channel name, one value per pixel).
pub type Channels = Vec<(String, Vec<f32>)>;

/// A layer of three channels NAME.A, NAME.B, NAME.C, `suffixes` naming them: ["R", "G", "B"]
/// for colours, ["X", "Y", "Z"] for vectors.
pub fn layer(name: &str, suffixes: [&str; 3], pixels: &[Rgb]) -> Channels {
    suffixes
        .into_iter()
        .enumerate()
        .map(|(c, channel)| (format!("{name}.{channel}"), pixels.iter().map(|p| p.to_array()[c]).collect()))
        .collect()
}

/// Writes row-major pixels (row 0 = top). `exposure` (in stops) applies to PNG only;
/// `metadata` (name, value) pairs go into the EXR header as string attributes; `layers`
/// (channels: full name, values) go into an EXR beside the image (other formats hold the
/// image alone).
pub fn write_image(
    path: &Path,
    width: u32,
    height: u32,
    pixels: &[Rgb],
    exposure: f32,
    metadata: &[(&str, String)],
    layers: &[(String, Vec<f32>)],
) -> Result<(), OutputError> {
    let bytes = encode_image(ImageFormat::from_path(path)?, width, height, pixels, exposure, metadata, layers)
        .map_err(|reason| OutputError::Unencodable { path: path.to_path_buf(), reason })?;
    write_file_atomically(path, &bytes, "output")
}

/// The image file's bytes.
fn encode_image(
    format: ImageFormat,
    width: u32,
    height: u32,
    pixels: &[Rgb],
    exposure: f32,
    metadata: &[(&str, String)],
    layers: &[(String, Vec<f32>)],
) -> Result<Vec<u8>, String> {
    let mut bytes = Vec::new();
    match format {
        ImageFormat::Exr if !layers.is_empty() => {
            use exr::prelude::*;
            let mut list = SmallVec::<[AnyChannel<FlatSamples>; 4]>::new();
            for (c, name) in ["R", "G", "B"].into_iter().enumerate() {
                list.push(AnyChannel::new(name, FlatSamples::F32(pixels.iter().map(|p| p.to_array()[c]).collect())));
            }
            for (name, values) in layers {
                list.push(AnyChannel::new(name.as_str(), FlatSamples::F32(values.clone())));
            }
            let size = (width as usize, height as usize);
            let layer = Layer::new(size, LayerAttributes::default(), Encoding::FAST_LOSSLESS, AnyChannels::sort(list));
            let mut image = Image::from_layer(layer);
            for (name, value) in metadata {
                image.attributes.other.insert(Text::from(*name), AttributeValue::Text(Text::from(value.as_str())));
            }
            image.write().to_buffered(std::io::Cursor::new(&mut bytes)).map_err(|e| e.to_string())?;
        }
        ImageFormat::Exr => {
            use exr::prelude::*;
            let channels = SpecificChannels::rgb(|position: Vec2<usize>| {
                let p = pixels[position.y() * width as usize + position.x()];
                (p.x, p.y, p.z)
            });
            let mut image = Image::from_channels((width as usize, height as usize), channels);
            for (name, value) in metadata {
                image.attributes.other.insert(Text::from(*name), AttributeValue::Text(Text::from(value.as_str())));
            }
            image.write().to_buffered(std::io::Cursor::new(&mut bytes)).map_err(|e| e.to_string())?;
        }
        ImageFormat::Pfm => bytes = encode_pfm(width, height, pixels),
        ImageFormat::Hdr => {
            let rgb: Vec<f32> = pixels.iter().flat_map(|p| p.max(Rgb::ZERO).to_array()).collect();
            let image = image::Rgb32FImage::from_raw(width, height, rgb).ok_or("image size mismatch".to_string())?;
            image::DynamicImage::ImageRgb32F(image)
                .write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Hdr)
                .map_err(|e| e.to_string())?;
        }
        ImageFormat::Png => {
            let scale = exposure.exp2();
            let rgb: Vec<u8> = pixels.iter().flat_map(|p| (*p * scale).to_array().map(encode_srgb)).collect();
            image::RgbImage::from_raw(width, height, rgb)
                .ok_or("image size mismatch".to_string())?
                .write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Png)
                .map_err(|e| e.to_string())?;
        }
    }
    Ok(bytes)
}

fn encode_pfm(width: u32, height: u32, pixels: &[Rgb]) -> Vec<u8> {
    // A negative scale marks little-endian data.
    let mut out = format!("PF\n{width} {height}\n-1.0\n").into_bytes();
    out.reserve(pixels.len() * 12);
    for row in (0..height as usize).rev() {
        for p in &pixels[row * width as usize..(row + 1) * width as usize] {
            for c in p.to_array() {
                out.extend_from_slice(&c.to_le_bytes());
            }
        }
    }
    out
}

/// An EXR's text attributes: the image's, then its layer's (an EXR of one layer keeps custom
/// attributes in its one header, which the reader hands back with the layer).
pub fn exr_text_attributes(
    image: &std::collections::HashMap<exr::meta::attribute::Text, exr::meta::attribute::AttributeValue>,
    layer: &std::collections::HashMap<exr::meta::attribute::Text, exr::meta::attribute::AttributeValue>,
) -> std::collections::BTreeMap<String, String> {
    image
        .iter()
        .chain(layer)
        .filter_map(|(name, value)| match value {
            exr::meta::attribute::AttributeValue::Text(text) => Some((name.to_string(), text.to_string())),
            _ => None,
        })
        .collect()
}

/// Refuses an EXR whose header declares more pixel data than the memory limit allows, before
/// any of it is decoded: a few bytes of header can declare gigabytes (as glint-fuzz found for
/// textures). Counts 16 bytes per channel sample, the widest a reader holds.
pub fn check_exr_size(bytes: &[u8]) -> Result<(), String> {
    let meta = exr::meta::MetaData::read_from_buffered(std::io::Cursor::new(bytes), false)
        .map_err(|e| format!("cannot read it as OpenEXR: {e}"))?;
    let needed: u64 = meta
        .headers
        .iter()
        .map(|h| {
            let size = h.layer_size;
            (size.width() as u64).saturating_mul(size.height() as u64).saturating_mul(h.channels.list.len() as u64 * 16)
        })
        .fold(0u64, u64::saturating_add);
    let limit = glint_scene::memory_limit();
    if needed > limit {
        return Err(format!(
            "its header declares {} of pixel data, more than the memory limit of {} ({})",
            glint_scene::describe_bytes(needed),
            glint_scene::describe_bytes(limit),
            glint_scene::RAISE_MEMORY_LIMIT
        ));
    }
    Ok(())
}

/// Reads a PFM written by `write_pfm` (or any little-endian RGB PFM) back, row 0 = top.
pub fn read_pfm(path: &Path) -> Result<(u32, u32, Vec<Rgb>), OutputError> {
    let unreadable = |reason: &dyn std::fmt::Display| OutputError::Unreadable {
        path: path.to_path_buf(),
        reason: reason.to_string(),
    };
    let data = std::fs::read(path).map_err(|e| unreadable(&e))?;
    let mut header_end = 0;
    let mut fields = Vec::new();
    while fields.len() < 4 {
        let start = header_end;
        while header_end < data.len() && !data[header_end].is_ascii_whitespace() {
            header_end += 1;
        }
        fields.push(String::from_utf8_lossy(&data[start..header_end]).to_string());
        header_end += 1;
    }
    let (width, height): (u32, u32) = (
        fields[1].parse().map_err(|_| unreadable(&"bad width"))?,
        fields[2].parse().map_err(|_| unreadable(&"bad height"))?,
    );
    if fields[0] != "PF" || !fields[3].starts_with('-') {
        return Err(unreadable(&"expected a little-endian colour PFM"));
    }
    let floats: Vec<f32> =
        data[header_end..].chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect();
    if floats.len() != (width * height * 3) as usize {
        return Err(unreadable(&"PFM data size does not match its header"));
    }
    let mut pixels = vec![Rgb::ZERO; (width * height) as usize];
    for (i, c) in floats.chunks_exact(3).enumerate() {
        let (x, row_from_bottom) = (i as u32 % width, i as u32 / width);
        pixels[((height - 1 - row_from_bottom) * width + x) as usize] = Rgb::new(c[0], c[1], c[2]);
    }
    Ok((width, height, pixels))
}

/// Linear → sRGB transfer function (IEC 61966-2-1), clamped to [0, 1], rounded to 8 bits.
pub fn encode_srgb(linear: f32) -> u8 {
    let v = if linear.is_nan() { 0.0 } else { linear.clamp(0.0, 1.0) };
    let encoded = if v <= 0.003_130_8 { 12.92 * v } else { 1.055 * v.powf(1.0 / 2.4) - 0.055 };
    (encoded * 255.0 + 0.5) as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_encoding_by_hand() {
        assert_eq!(encode_srgb(0.0), 0);
        assert_eq!(encode_srgb(1.0), 255);
        assert_eq!(encode_srgb(2.0), 255);
        assert_eq!(encode_srgb(0.5), 188); // 1.055·0.5^(1/2.4) − 0.055 = 0.7354
        assert_eq!(encode_srgb(0.002), 7); // linear segment: 12.92·0.002·255 = 6.6
    }

    #[test]
    fn pfm_round_trip_keeps_row_order() {
        let dir = std::env::temp_dir().join(format!("glint-pfm-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("t.pfm");
        let pixels: Vec<Rgb> = (0..6).map(|i| Rgb::splat(i as f32)).collect();
        write_file_atomically(&path, &encode_pfm(3, 2, &pixels), "output").unwrap();
        assert_eq!(read_pfm(&path).unwrap(), (3, 2, pixels));
        std::fs::remove_dir_all(dir).unwrap();
    }
}
