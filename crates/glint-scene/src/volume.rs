//! Mitsuba's volume grid files (`.vol`, version 3, float32): the data of its `gridvolume`
//! textures, which heterogeneous media read their density and albedo from.
//!
//! Layout (little-endian): `VOL`, the version byte 3, the encoding (1: float32), the x, y
//! and z resolutions and the channel count (int32 each), the bounding box (min x, y, z then
//! max x, y, z, float32), then the values with x fastest, then y, then z, channels
//! interleaved.

use glam::Vec3;

/// A grid of values over a box.
#[derive(Clone, Debug, PartialEq)]
pub struct VolumeGrid {
    pub resolution: [usize; 3],
    pub channels: usize,
    pub min: Vec3,
    pub max: Vec3,
    /// ((z · ny + y) · nx + x) · channels + channel.
    pub values: Vec<f32>,
}

const HEADER: usize = 48;

/// A grid as a `.vol` file's bytes (what `read_vol` reads back, bit for bit).
pub(crate) fn write_vol(grid: &VolumeGrid) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(HEADER + 4 * grid.values.len());
    bytes.extend_from_slice(b"VOL\x03");
    let [x, y, z] = grid.resolution.map(|n| n as i32);
    for n in [1, x, y, z, grid.channels as i32] {
        bytes.extend_from_slice(&n.to_le_bytes());
    }
    for v in grid.min.to_array().iter().chain(&grid.max.to_array()).chain(&grid.values) {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    bytes
}

/// Reads a `.vol` file's bytes, or says what is wrong with them.
pub fn read_vol(bytes: &[u8]) -> Result<VolumeGrid, String> {
    if bytes.len() < HEADER || &bytes[..3] != b"VOL" {
        return Err("not a Mitsuba volume file (it starts with `VOL` and a 48-byte header)".into());
    }
    if bytes[3] != 3 {
        return Err(format!("volume file version {}: glint reads version 3", bytes[3]));
    }
    let int = |at: usize| i32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    let float = |at: usize| f32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    if int(4) != 1 {
        return Err(format!("volume encoding {}: glint reads float32 (1)", int(4)));
    }
    let (x, y, z, channels) = (int(8), int(12), int(16), int(20));
    if [x, y, z].iter().any(|&n| n <= 0) || !(channels == 1 || channels == 3) {
        return Err(format!("a {x}x{y}x{z} grid of {channels} channels: resolutions must be ≥ 1 and channels 1 or 3"));
    }
    let count = [x, y, z, channels].iter().try_fold(1u64, |n, &k| n.checked_mul(k as u64)).unwrap_or(u64::MAX);
    let needed = count.saturating_mul(4);
    if needed > crate::limits::memory_limit() {
        return Err(format!(
            "the grid holds {count} values, more than the memory limit of {} allows ({})",
            crate::limits::describe(crate::limits::memory_limit()),
            crate::limits::RAISE
        ));
    }
    let data = &bytes[HEADER..];
    if (data.len() as u64) < needed {
        return Err(format!("the file is cut short: {needed} bytes of values expected, {} found", data.len()));
    }
    let values: Vec<f32> =
        data[..needed as usize].chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(format!("value {i} is not a finite number"));
    }
    let min = Vec3::new(float(24), float(28), float(32));
    let max = Vec3::new(float(36), float(40), float(44));
    if !(min.is_finite() && max.is_finite() && min.cmplt(max).all()) {
        return Err(format!("the grid's box {min} – {max} is empty or not finite"));
    }
    Ok(VolumeGrid { resolution: [x as usize, y as usize, z as usize], channels: channels as usize, min, max, values })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vol(resolution: [i32; 3], channels: i32, values: &[f32]) -> Vec<u8> {
        let mut bytes = b"VOL\x03".to_vec();
        for n in [1, resolution[0], resolution[1], resolution[2], channels] {
            bytes.extend_from_slice(&n.to_le_bytes());
        }
        for f in [0.0f32, 0.0, 0.0, 1.0, 2.0, 3.0].iter().chain(values) {
            bytes.extend_from_slice(&f.to_le_bytes());
        }
        bytes
    }

    #[test]
    fn a_written_grid_reads_back_bit_for_bit() {
        let grid = VolumeGrid {
            resolution: [2, 1, 3],
            channels: 3,
            min: Vec3::new(-1.0, 0.0, 0.5),
            max: Vec3::new(1.0, 0.25, 2.0),
            values: (0..18).map(|i| i as f32 * 0.37).collect(),
        };
        assert_eq!(read_vol(&write_vol(&grid)).unwrap(), grid);
    }

    #[test]
    fn a_grid_reads_back_as_written() {
        let values: Vec<f32> = (0..18).map(|i| i as f32 * 0.5).collect();
        let grid = read_vol(&vol([2, 3, 1], 3, &values)).unwrap();
        assert_eq!((grid.resolution, grid.channels), ([2, 3, 1], 3));
        assert_eq!((grid.min, grid.max), (Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0)));
        // Voxel (1, 2, 0), channel 2: ((0·3 + 2)·2 + 1)·3 + 2 = 17.
        assert_eq!(grid.values[17], 8.5);
    }

    #[test]
    fn bad_files_are_refused_with_their_reason() {
        assert!(read_vol(b"PLY").unwrap_err().contains("not a Mitsuba volume"));
        let mut v2 = vol([1, 1, 1], 1, &[1.0]);
        v2[3] = 2;
        assert!(read_vol(&v2).unwrap_err().contains("version 2"));
        assert!(read_vol(&vol([0, 1, 1], 1, &[])).unwrap_err().contains("≥ 1"));
        assert!(read_vol(&vol([2, 2, 2], 1, &[1.0; 7])).unwrap_err().contains("cut short"));
        assert!(read_vol(&vol([1, 1, 1], 1, &[f32::NAN])).unwrap_err().contains("not a finite"));
        assert!(read_vol(&vol([1 << 30, 1 << 30, 4], 3, &[])).unwrap_err().contains("memory limit"));
    }

    /// The suite's own grids (../shared/mitsuba-data): 16³, σ_t one channel, albedo three.
    #[test]
    fn the_mitsuba_suites_grids_read() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../../shared/mitsuba-data/tests/scenes/participating_media/textures");
        for (name, channels) in [("sigmat.vol", 1), ("albedo.vol", 3)] {
            let file = dir.join(name);
            let bytes =
                std::fs::read(&file).unwrap_or_else(|e| panic!("{} (../shared/mitsuba-data): {e}", file.display()));
            let grid = read_vol(&bytes).unwrap();
            assert_eq!((grid.resolution, grid.channels), ([16, 16, 16], channels), "{name}");
            assert!(grid.values.iter().all(|v| *v >= 0.0));
        }
    }
}
