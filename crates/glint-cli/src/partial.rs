//! Partial renders: one sample range of a render split across runs or machines
//! (`glint render --samples A..B`), and their merge (`glint merge`).
//!
//! A partial render is an OpenEXR image whose header records what it is part of (the render's
//! identity: scene, integrator, seed, sampler, filter, resolution) and which samples it holds
//! (`glint:samples`, as `A..B`, several ranges comma-separated), and whose extra channels hold
//! the film's exact sums (`ExactPixel`: three radiance sums and the weight, each an i128 in
//! four 32-bit limbs, least significant first, as unsigned-int channels `glint.sum.R.0` …
//! `glint.weight.3`). Integer sums do not depend on grouping, so parts merged give the sums,
//! and so the image, of one render of their union bit for bit.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glint_core::film::{ExactPixel, Film};
use thiserror::Error;

use crate::output::{check_writable, write_file_atomically, write_image, ImageFormat, OutputError};

/// The header attributes that must agree for parts to be merged: the render's identity (a
/// hash of the scene's files by content, the flags that change the image, the resolution) and,
/// spelled out for messages, the integrator, seed, sampler and filter.
pub const IDENTITY_KEYS: [&str; 5] =
    ["glint:integrator", "glint:seed", "glint:sampler", "glint:filter", "glint:identity"];
/// The header attribute listing the sample ranges a file holds.
pub const SAMPLES_KEY: &str = "glint:samples";

const SUMS: [&str; 4] = ["sum.R", "sum.G", "sum.B", "weight"];

#[derive(Debug, Error)]
pub enum MergeError {
    #[error("`{}`: {reason}", path.display())]
    Unreadable { path: PathBuf, reason: String },
    #[error("`{}` is not a partial render: {reason} (write one with `glint render --samples A..B -o part.exr`)", path.display())]
    NotPartial { path: PathBuf, reason: String },
    #[error("`{}` and `{}` are parts of different renders: their {what} differ (`{a}` and `{b}`)", first.display(), second.display())]
    Mismatch { first: PathBuf, second: PathBuf, what: String, a: String, b: String },
    #[error("`{}` and `{}` both hold samples {overlap}: a sample merged twice would count twice", first.display(), second.display())]
    Overlap { first: PathBuf, second: PathBuf, overlap: String },
    #[error("nothing to merge: give the parts after the output")]
    NoInputs,
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// A partial render read back: its size, header attributes, sample ranges and exact sums.
pub struct Partial {
    pub path: PathBuf,
    pub width: u32,
    pub height: u32,
    pub attributes: BTreeMap<String, String>,
    pub ranges: Vec<(u32, u32)>,
    pub sums: Vec<ExactPixel>,
}

/// Sample ranges as written in the header: `0..4,8..12`.
pub fn format_ranges(ranges: &[(u32, u32)]) -> String {
    ranges.iter().map(|(a, b)| format!("{a}..{b}")).collect::<Vec<_>>().join(",")
}

/// `A..B` (A < B) as (A, B).
pub fn parse_range(text: &str) -> Result<(u32, u32), String> {
    let (a, b) = text.split_once("..").ok_or_else(|| format!("expected A..B (for example 0..64), got `{text}`"))?;
    let number = |v: &str| v.trim().parse::<u32>().map_err(|_| format!("`{v}` is not a sample index"));
    let (a, b) = (number(a)?, number(b)?);
    check_range(a, b)?;
    Ok((a, b))
}

/// Refuses an empty range of samples (A..B holds A to B − 1).
pub fn check_range(a: u32, b: u32) -> Result<(), String> {
    if a >= b {
        return Err(format!("the range {a}..{b} is empty: it holds samples A to B − 1, so B must exceed A"));
    }
    Ok(())
}

/// Ranges sorted and joined where they touch.
fn normalise(mut ranges: Vec<(u32, u32)>) -> Vec<(u32, u32)> {
    ranges.sort_unstable();
    let mut out: Vec<(u32, u32)> = Vec::new();
    for (a, b) in ranges {
        match out.last_mut() {
            Some(last) if a <= last.1 => last.1 = last.1.max(b),
            _ => out.push((a, b)),
        }
    }
    out
}

/// The EXR bytes of a partial render: the image (from the exact sums), the header, the sums.
pub fn encode(film: &Film, attributes: &[(&str, String)]) -> Result<Vec<u8>, String> {
    use exr::prelude::*;
    let sums = film.exact_sums().ok_or("the film keeps no exact sums")?;
    let pixels = film.to_rgb();
    let mut list = SmallVec::<[AnyChannel<FlatSamples>; 4]>::new();
    for (c, name) in ["R", "G", "B"].into_iter().enumerate() {
        list.push(AnyChannel::new(name, FlatSamples::F32(pixels.iter().map(|p| p.to_array()[c]).collect())));
    }
    for (k, name) in SUMS.iter().enumerate() {
        for limb in 0..4 {
            let values = sums
                .iter()
                .map(|p| {
                    let v = if k < 3 { p.sum[k] } else { p.weight };
                    (v as u128 >> (32 * limb)) as u32
                })
                .collect();
            list.push(AnyChannel::new(format!("glint.{name}.{limb}").as_str(), FlatSamples::U32(values)));
        }
    }
    let size = (film.width as usize, film.height as usize);
    let layer = Layer::new(size, LayerAttributes::default(), Encoding::FAST_LOSSLESS, AnyChannels::sort(list));
    let mut image = Image::from_layer(layer);
    for (name, value) in attributes {
        image.attributes.other.insert(Text::from(*name), AttributeValue::Text(Text::from(value.as_str())));
    }
    let mut bytes = Vec::new();
    image.write().to_buffered(std::io::Cursor::new(&mut bytes)).map_err(|e| e.to_string())?;
    Ok(bytes)
}

/// Writes a partial render (whole or not at all).
pub fn write(path: &Path, film: &Film, attributes: &[(&str, String)]) -> Result<(), OutputError> {
    let bytes =
        encode(film, attributes).map_err(|reason| OutputError::Unencodable { path: path.to_path_buf(), reason })?;
    write_file_atomically(path, &bytes, "output")
}

/// Writes a partial render in the format `path`'s extension names: an EXR is a partial render
/// (its exact sums and header, to merge further); PNG, PFM and HDR hold the image alone. Any
/// other extension is refused before anything is written.
pub fn write_as_named(path: &Path, film: &Film, attributes: &[(&str, String)]) -> Result<(), OutputError> {
    match check_writable(path)? {
        ImageFormat::Exr => write(path, film, attributes),
        _ => write_image(path, film.width, film.height, &film.to_rgb(), 0.0, &[], &[]),
    }
}

/// Reads a partial render back.
pub fn read(path: &Path) -> Result<Partial, MergeError> {
    let bytes =
        std::fs::read(path).map_err(|e| MergeError::Unreadable { path: path.to_path_buf(), reason: e.to_string() })?;
    decode(&bytes, path)
}

/// A partial render from its file's bytes (`path` names it in messages).
pub fn decode(bytes: &[u8], path: &Path) -> Result<Partial, MergeError> {
    use exr::prelude::*;
    let unreadable = |reason: String| MergeError::Unreadable { path: path.to_path_buf(), reason };
    let not_partial = |reason: String| MergeError::NotPartial { path: path.to_path_buf(), reason };
    crate::output::check_exr_size(bytes).map_err(unreadable)?;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .from_buffered(std::io::Cursor::new(bytes))
        .map_err(|e| unreadable(format!("cannot read it as OpenEXR: {e}")))?;
    let layer = image.layer_data.first().ok_or_else(|| not_partial("it has no image layer".into()))?;
    let (width, height) = (layer.size.width() as u32, layer.size.height() as u32);
    let attributes = crate::output::exr_text_attributes(&image.attributes.other, &layer.attributes.other);
    let samples =
        attributes.get(SAMPLES_KEY).ok_or_else(|| not_partial(format!("its header has no `{SAMPLES_KEY}`")))?;
    let ranges = samples
        .split(',')
        .map(parse_range)
        .collect::<std::result::Result<Vec<_>, _>>()
        .map_err(|e| not_partial(format!("`{SAMPLES_KEY}` = `{samples}`: {e}")))?;
    let n = width as usize * height as usize;
    let channel = |name: &str| -> std::result::Result<&[u32], MergeError> {
        let found = layer.channel_data.list.iter().find(|c| c.name.to_string() == name);
        match found.map(|c| &c.sample_data) {
            Some(FlatSamples::U32(values)) if values.len() == n => Ok(values),
            Some(_) => Err(not_partial(format!("its channel `{name}` is not {n} unsigned integers"))),
            None => Err(not_partial(format!("it has no channel `{name}` (the exact sums)"))),
        }
    };
    let mut sums = vec![ExactPixel::default(); n];
    for (k, name) in SUMS.iter().enumerate() {
        for limb in 0..4 {
            let values = channel(&format!("glint.{name}.{limb}"))?;
            for (pixel, &v) in sums.iter_mut().zip(values) {
                let target = if k < 3 { &mut pixel.sum[k] } else { &mut pixel.weight };
                *target = (*target as u128 | (v as u128) << (32 * limb)) as i128;
            }
        }
    }
    Ok(Partial { path: path.to_path_buf(), width, height, attributes, ranges, sums })
}

/// Parts merged: the film of their exact sums, the header for it, and the samples it holds.
pub struct Merged {
    pub film: Film,
    pub attributes: Vec<(String, String)>,
    pub ranges: Vec<(u32, u32)>,
}

/// The parts added into one partial render: refused unless they are parts of one render
/// (same size and identity) holding disjoint samples.
pub fn merge(parts: Vec<Partial>) -> Result<Merged, MergeError> {
    let mut parts = parts.into_iter();
    let first = parts.next().ok_or(MergeError::NoInputs)?;
    let mut sums = first.sums.clone();
    let mut held: Vec<((u32, u32), PathBuf)> = first.ranges.iter().map(|r| (*r, first.path.clone())).collect();
    let render_seconds = |p: &Partial| p.attributes.get("glint:render_seconds").and_then(|s| s.parse::<f64>().ok());
    let mut seconds = vec![render_seconds(&first)];
    for part in parts {
        let mismatch = |what: &str, a: String, b: String| MergeError::Mismatch {
            first: first.path.clone(),
            second: part.path.clone(),
            what: what.to_string(),
            a,
            b,
        };
        if (part.width, part.height) != (first.width, first.height) {
            let size = |p: &Partial| format!("{}x{}", p.width, p.height);
            return Err(mismatch("resolutions", size(&first), size(&part)));
        }
        for key in IDENTITY_KEYS {
            let (a, b) = (first.attributes.get(key), part.attributes.get(key));
            if a != b {
                let shown = |v: Option<&String>| v.cloned().unwrap_or_else(|| "(none)".into());
                return Err(mismatch(&format!("`{key}`"), shown(a), shown(b)));
            }
        }
        for &(a, b) in &part.ranges {
            if let Some(((c, d), other)) = held.iter().find(|((c, d), _)| a < *d && *c < b) {
                let overlap = format!("{}..{}", a.max(*c), b.min(*d));
                return Err(MergeError::Overlap { first: other.clone(), second: part.path.clone(), overlap });
            }
        }
        held.extend(part.ranges.iter().map(|r| (*r, part.path.clone())));
        seconds.push(render_seconds(&part));
        for (total, add) in sums.iter_mut().zip(&part.sums) {
            total.merge(add);
        }
    }
    let ranges = normalise(held.into_iter().map(|(r, _)| r).collect());
    let film = Film::from_exact_sums(first.width, first.height, sums).expect("the sizes were checked");
    // The identity and the camera as the parts have them; the sample count and the render
    // time are the whole's (the parts' times summed, where each has one).
    let spp: u32 = ranges.iter().map(|(a, b)| b - a).sum();
    let seconds: Option<f64> = seconds.into_iter().sum();
    let mut attributes: Vec<(String, String)> = first
        .attributes
        .into_iter()
        .filter(|(k, _)| {
            k.starts_with("glint:") && ![SAMPLES_KEY, "glint:spp", "glint:render_seconds"].contains(&k.as_str())
        })
        .collect();
    attributes.push(("glint:spp".to_string(), spp.to_string()));
    if let Some(seconds) = seconds {
        attributes.push(("glint:render_seconds".to_string(), seconds.to_string()));
    }
    attributes.push((SAMPLES_KEY.to_string(), format_ranges(&ranges)));
    Ok(Merged { film, attributes, ranges })
}

#[cfg(test)]
mod tests {
    use glint_core::Rgb;

    use super::*;

    #[test]
    fn ranges_parse_and_join() {
        assert_eq!(parse_range("0..64"), Ok((0, 64)));
        assert!(parse_range("5..5").unwrap_err().contains("empty"));
        assert!(parse_range("7").unwrap_err().contains("A..B"));
        assert!(parse_range("a..3").unwrap_err().contains("not a sample index"));
        assert_eq!(normalise(vec![(8, 12), (0, 4), (4, 8), (20, 24)]), vec![(0, 12), (20, 24)]);
        assert_eq!(format_ranges(&[(0, 12), (20, 24)]), "0..12,20..24");
    }

    /// Sums written and read back are the same integers, negative and beyond 2⁹⁶ too.
    #[test]
    fn exact_sums_survive_the_file() {
        let dir = std::env::temp_dir().join(format!("glint-partial-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut film = Film::new(3, 2).with_exact_sums();
        film.add_sample(0, 0, Rgb::new(1.5, -2.0, 3e10), 1.0);
        film.add_sample(2, 1, Rgb::new(1e-12, 7.0, 0.25), 0.5);
        let path = dir.join("p.exr");
        write(&path, &film, &[(SAMPLES_KEY, "3..9".into())]).unwrap();
        let back = read(&path).unwrap();
        assert_eq!((back.width, back.height, back.ranges.clone()), (3, 2, vec![(3, 9)]));
        assert_eq!(back.sums, film.exact_sums().unwrap());
        assert!(back.sums[0].sum[1] < 0 && back.sums[0].sum[2] > 1i128 << 96);
        std::fs::remove_dir_all(dir).unwrap();
    }
}
