//! Checkpoints of a progressive render: the film's float accumulators and the sample count,
//! with a fingerprint of what was being rendered, so `--resume` continues exactly where the
//! render stopped (to the same image as an uninterrupted render) and refuses a mismatch.
//!
//! Format (little-endian): `GLINTCK3`, width u32, height u32, spp_done u32, seed u64,
//! fingerprint u64, then width·height RGB sums (3 × f32) and width·height weights (f32), then
//! the integrator's own state: its length u64 and its bytes (empty but for SPPM), then an
//! FNV-1a checksum u64 of everything before it. `GLINTCK2` and `GLINTCK1` files, from before
//! the fingerprint covered the scene's files, are refused with that reason. Written to a
//! temporary file and renamed, so a crash
//! mid-write never leaves a broken one. A checkpoint is trusted only as far as it checks out:
//! its header against the render and the file's length, its pixels finite and their weights
//! what its passes give.

use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};

use glint_core::film::Film;
use glint_core::Rgb;
use thiserror::Error;

use crate::output::OutputError;

const MAGIC: &[u8; 8] = b"GLINTCK3";
/// Earlier formats (without a checksum; GLINTCK1 without the integrator's state either):
/// recognised, to be refused with the reason.
const OLDER_WITH_STATE: &[u8; 8] = b"GLINTCK2";
const OLDER_WITHOUT_STATE: &[u8; 8] = b"GLINTCK1";

pub struct Checkpoint {
    pub film: Film,
    pub spp_done: u32,
    /// The integrator's state beyond the film.
    pub state: Vec<u8>,
}

/// The fingerprint of a value (the render's identity): its derived `Hash` fed to FNV-1a,
/// which, unlike the standard library's hasher, is the same in every build, so a checkpoint
/// resumes under another build of glint.
pub fn fingerprint_of(value: &impl Hash) -> u64 {
    let mut hasher = Fnv1a(FNV_OFFSET);
    value.hash(&mut hasher);
    hasher.finish()
}

const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
const FNV_PRIME: u64 = 0x0100_0000_01b3;

struct Fnv1a(u64);

impl Hasher for Fnv1a {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= b as u64;
            self.0 = self.0.wrapping_mul(FNV_PRIME);
        }
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

/// FNV-1a over byte strings (a file's contents), each followed by 0xFF.
pub fn fingerprint(parts: &[&[u8]]) -> u64 {
    let mut hasher = Fnv1a(FNV_OFFSET);
    for part in parts {
        hasher.write(part);
        hasher.write(&[0xFF]);
    }
    hasher.finish()
}

/// What the render being resumed expects of a checkpoint. Every field of the file is checked
/// against it (and against the file's length, with checked arithmetic) before anything is
/// allocated or trusted.
pub struct Expected {
    pub width: u32,
    pub height: u32,
    pub seed: u64,
    pub fingerprint: u64,
    /// The render's target spp: a checkpoint may not hold more.
    pub spp: u32,
    pub weights: WeightRule,
    /// The filter has no negative lobes, so no pixel's sum can be negative.
    pub nonnegative: bool,
}

/// What every pixel's accumulated weight must be.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WeightRule {
    /// The number of passes: box-filtered camera samples, light tracing.
    PerPass,
    /// One: SPPM keeps its estimate in a film of weight 1.
    One,
    /// Any finite value (other filters spread a sample's weight over several pixels).
    Finite,
}

/// The header: magic, width, height, spp_done, seed, fingerprint.
const HEADER: usize = 36;

/// Why a checkpoint could not be read, or does not belong to this render.
#[derive(Debug, Error)]
pub enum CheckpointError {
    #[error("cannot read the checkpoint `{}`: {source}", path.display())]
    Unreadable { path: PathBuf, source: std::io::Error },
    #[error("the checkpoint `{}` is damaged or not a glint checkpoint: {why}", path.display())]
    Damaged { path: PathBuf, why: String },
    /// A sound checkpoint of another render (scene, settings, size, sample count, version).
    #[error("the checkpoint `{}` {why}", path.display())]
    Mismatched { path: PathBuf, why: String },
}

pub fn save(
    path: &Path,
    film: &Film,
    spp_done: u32,
    seed: u64,
    fingerprint: u64,
    state: &[u8],
) -> Result<(), OutputError> {
    let (sum, weight) = film.accumulators();
    let mut bytes = Vec::with_capacity(HEADER + sum.len() * 16 + 16 + state.len());
    bytes.extend_from_slice(MAGIC);
    for v in [film.width, film.height, spp_done] {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    bytes.extend_from_slice(&seed.to_le_bytes());
    bytes.extend_from_slice(&fingerprint.to_le_bytes());
    for s in sum {
        for c in s.to_array() {
            bytes.extend_from_slice(&c.to_le_bytes());
        }
    }
    for w in weight {
        bytes.extend_from_slice(&w.to_le_bytes());
    }
    bytes.extend_from_slice(&(state.len() as u64).to_le_bytes());
    bytes.extend_from_slice(state);
    let sum = checksum(&bytes);
    bytes.extend_from_slice(&sum.to_le_bytes());
    crate::output::write_file_atomically(path, &bytes, "checkpoint")
}

/// The checksum over a checkpoint's contents.
fn checksum(bytes: &[u8]) -> u64 {
    fingerprint(&[bytes])
}

pub fn load(path: &Path, expected: &Expected) -> Result<Checkpoint, CheckpointError> {
    let bytes =
        std::fs::read(path).map_err(|source| CheckpointError::Unreadable { path: path.to_path_buf(), source })?;
    parse(&bytes, path, expected)
}

/// A checkpoint from its bytes (`path` for messages only).
pub fn parse(bytes: &[u8], path: &Path, expected: &Expected) -> Result<Checkpoint, CheckpointError> {
    let refuse = |why: String| CheckpointError::Mismatched { path: path.to_path_buf(), why };
    let damaged = |why: &str| CheckpointError::Damaged { path: path.to_path_buf(), why: why.to_string() };
    if bytes.len() < HEADER {
        return Err(damaged("it is shorter than its header"));
    }
    let magic = &bytes[..8];
    if magic == OLDER_WITH_STATE || magic == OLDER_WITHOUT_STATE {
        return Err(refuse(
            "was written by an earlier glint, whose fingerprint did not cover the files the scene reads; render again"
                .into(),
        ));
    }
    if magic != MAGIC {
        return Err(damaged("it does not start with GLINTCK3"));
    }
    let u32_at = |i: usize| u32::from_le_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
    let u64_at = |i: usize| u64::from(u32_at(i)) | u64::from(u32_at(i + 4)) << 32;
    let (width, height, spp_done) = (u32_at(8), u32_at(12), u32_at(16));
    let (seed, fingerprint) = (u64_at(20), u64_at(28));
    if (width, height) != (expected.width, expected.height) {
        return Err(refuse(format!(
            "is of a {width}x{height} render; this one is {}x{}",
            expected.width, expected.height
        )));
    }
    if fingerprint != expected.fingerprint || seed != expected.seed {
        return Err(refuse("was made from another scene or other settings (the scene file and the files it reads, integrator, resolution, seed, methods and light sampling must be the same)".into()));
    }
    if spp_done == 0 || spp_done > expected.spp {
        return Err(refuse(format!(
            "holds {spp_done} samples per pixel; a checkpoint of this render holds 1 to {}",
            expected.spp
        )));
    }
    // Lengths in u64 with checks: a crafted header must not overflow them.
    let pixels = u64::from(width) * u64::from(height);
    let film_end = (HEADER as u64).checked_add(pixels.checked_mul(16).ok_or_else(|| damaged("its size overflows"))?);
    let film_end = film_end.ok_or_else(|| damaged("its size overflows"))?;
    let length_at = usize::try_from(film_end)
        .ok()
        .filter(|&i| i.checked_add(8).is_some_and(|end| end <= bytes.len()))
        .ok_or_else(|| damaged("it is cut short"))?;
    let length = u64_at(length_at);
    let start = film_end + 8;
    let payload_end = start.checked_add(length).ok_or_else(|| damaged("its size overflows"))?;
    if payload_end.checked_add(8) != Some(bytes.len() as u64) {
        return Err(damaged("its length does not match its header"));
    }
    let state = start as usize..payload_end as usize;
    let payload_end = payload_end as usize;
    if checksum(&bytes[..payload_end]) != u64_at(payload_end) {
        return Err(damaged("its checksum does not match its contents"));
    }
    let n = pixels as usize;
    let float = |i: usize| f32::from_bits(u32_at(HEADER + 4 * i));
    let sum: Vec<Rgb> = (0..n).map(|p| Rgb::new(float(3 * p), float(3 * p + 1), float(3 * p + 2))).collect();
    let weight: Vec<f32> = (0..n).map(|p| float(3 * n + p)).collect();
    for (p, (s, w)) in sum.iter().zip(&weight).enumerate() {
        let (x, y) = (p as u32 % width, p as u32 / width);
        let bad = |what: String| damaged(&format!("pixel ({x}, {y}) has {what}"));
        if !s.is_finite() || (expected.nonnegative && s.min_element() < 0.0) {
            return Err(bad(format!("the sum {s}")));
        }
        let weight_ok = match expected.weights {
            WeightRule::PerPass => *w == spp_done as f32,
            WeightRule::One => *w == 1.0,
            WeightRule::Finite => w.is_finite(),
        };
        if !weight_ok {
            return Err(bad(format!("the weight {w} after {spp_done} passes")));
        }
    }
    let film = Film::from_accumulators(width, height, sum, weight).ok_or_else(|| damaged("its film"))?;
    Ok(Checkpoint { film, spp_done, state: bytes[state].to_vec() })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// FNV-1a's published value for "a" (0xaf63dc4c8601ec8c): a hashed byte is fed as itself,
    /// so a render's identity hashes the same in every build.
    #[test]
    fn fingerprints_are_fnv_1a() {
        assert_eq!(fingerprint_of(&b'a'), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fingerprint(&[b"a"]), fingerprint_of(&(b'a', 0xFFu8)));
        assert_ne!(fingerprint_of(&(1u32, 2u32)), fingerprint_of(&(2u32, 1u32)));
    }
}
