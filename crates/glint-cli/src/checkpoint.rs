//! Checkpoints of a progressive render: the film's float accumulators and the sample count,
//! with a fingerprint of what was being rendered, so `--resume` continues exactly where the
//! render stopped (to the same image as an uninterrupted render) and refuses a mismatch.
//!
//! Format (little-endian): `GLINTCK2`, width u32, height u32, spp_done u32, seed u64,
//! fingerprint u64, then width·height RGB sums (3 × f32) and width·height weights (f32), then
//! the integrator's own state: its length u64 and its bytes (empty but for SPPM). `GLINTCK1`
//! files (without the state) are still read. Written to a temporary file and renamed, so a
//! crash mid-write never leaves a broken one.

use std::path::Path;

use glint_core::film::Film;
use glint_core::Rgb;

const MAGIC: &[u8; 8] = b"GLINTCK2";
const MAGIC_WITHOUT_STATE: &[u8; 8] = b"GLINTCK1";

pub struct Checkpoint {
    pub film: Film,
    pub spp_done: u32,
    pub seed: u64,
    pub fingerprint: u64,
    /// The integrator's state beyond the film.
    pub state: Vec<u8>,
}

/// FNV-1a over the parts that make a render what it is (scene text, integrator, settings).
pub fn fingerprint(parts: &[&[u8]]) -> u64 {
    let mut hash = 0xcbf2_9ce4_8422_2325u64;
    for part in parts {
        for &b in part.iter().chain(&[0xFF]) {
            hash ^= b as u64;
            hash = hash.wrapping_mul(0x0100_0000_01b3);
        }
    }
    hash
}

pub fn save(path: &Path, film: &Film, spp_done: u32, seed: u64, fingerprint: u64, state: &[u8]) -> Result<(), String> {
    let (sum, weight) = film.accumulators();
    let mut bytes = Vec::with_capacity(36 + sum.len() * 16);
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
    let temporary = path.with_extension("tmp-checkpoint");
    std::fs::write(&temporary, &bytes)
        .map_err(|e| format!("cannot write the checkpoint `{}`: {e}", temporary.display()))?;
    std::fs::rename(&temporary, path).map_err(|e| format!("cannot write the checkpoint `{}`: {e}", path.display()))
}

pub fn load(path: &Path) -> Result<Checkpoint, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read the checkpoint `{}`: {e}", path.display()))?;
    let bad = || format!("`{}` is not a glint checkpoint (or it is damaged)", path.display());
    if bytes.len() < 36 || (&bytes[..8] != MAGIC && &bytes[..8] != MAGIC_WITHOUT_STATE) {
        return Err(bad());
    }
    let with_state = &bytes[..8] == MAGIC;
    let u32_at = |i: usize| u32::from_le_bytes(bytes[i..i + 4].try_into().unwrap_or([0; 4]));
    let u64_at = |i: usize| u64::from_le_bytes(bytes[i..i + 8].try_into().unwrap_or([0; 8]));
    let (width, height, spp_done) = (u32_at(8), u32_at(12), u32_at(16));
    let (seed, fingerprint) = (u64_at(20), u64_at(28));
    let n = width as usize * height as usize;
    let film_end = 36 + n * 16;
    let state = if with_state {
        if bytes.len() < film_end + 8 {
            return Err(bad());
        }
        let length = u64_at(film_end) as usize;
        if bytes.len() != film_end + 8 + length {
            return Err(bad());
        }
        bytes[film_end + 8..].to_vec()
    } else {
        if bytes.len() != film_end {
            return Err(bad());
        }
        Vec::new()
    };
    let floats: Vec<f32> =
        bytes[36..film_end].chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
    let sum = floats[..3 * n].chunks_exact(3).map(|c| Rgb::new(c[0], c[1], c[2])).collect();
    let weight = floats[3 * n..].to_vec();
    let film = Film::from_accumulators(width, height, sum, weight).ok_or_else(bad)?;
    Ok(Checkpoint { film, spp_done, seed, fingerprint, state })
}
