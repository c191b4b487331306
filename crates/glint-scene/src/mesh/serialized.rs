//! Mitsuba's `.serialized` meshes: a little-endian header (format 0x041C, version 3 or 4), then
//! a zlib stream holding flags, the shape's name (version 4), the vertex and triangle counts,
//! positions, optional normals, texture coordinates and colours (single or double precision),
//! and u32 triangle indices. A file may hold several meshes one after another; a dictionary at
//! its end gives each one's offset (u64 in version 4, u32 in version 3) and their count.

use std::io::Read;

use flate2::read::ZlibDecoder;
use glam::{Vec2, Vec3};
use glint_core::shapes::{Mesh, MeshAttribute};

const FORMAT: u16 = 0x041C;
const HAS_NORMALS: u32 = 0x0001;
const HAS_TEXCOORDS: u32 = 0x0002;
const HAS_COLORS: u32 = 0x0008;
const FACE_NORMALS: u32 = 0x0010;
const DOUBLE_PRECISION: u32 = 0x2000;

/// Mesh `shape_index` of the file `data`.
pub(super) fn read(data: &[u8], shape_index: u32) -> Result<Mesh, String> {
    let version = header(data)?;
    let start = if shape_index == 0 { 0 } else { offset(data, version, shape_index)? };
    let part = data.get(start..).filter(|p| p.len() >= 4).ok_or("the mesh's offset lies past the end of the file")?;
    if header(part)? != version {
        return Err(format!("mesh {shape_index} does not start with the file's header"));
    }
    let limit = crate::limits::memory_limit();
    let mut stream = Stream { decoder: ZlibDecoder::new(&part[4..]).take(limit) };
    let flags = stream.u32()?;
    if version == 4 {
        // The shape's name, null-terminated (not used: the scene names its shapes).
        while stream.bytes::<1>()?[0] != 0 {}
    }
    let (vertex_count, triangle_count) = (stream.u64()?, stream.u64()?);
    // Each vertex takes 12 bytes and each triangle 12 at least: counts the stream cannot
    // hold are refused before anything is allocated for them.
    let needed = vertex_count.saturating_mul(12).saturating_add(triangle_count.saturating_mul(12));
    if needed > limit || vertex_count > u32::MAX as u64 {
        return Err(format!(
            "it declares {vertex_count} vertices and {triangle_count} triangles, more than the memory limit allows ({})",
            crate::limits::RAISE
        ));
    }
    let (vertices, triangles) = (vertex_count as usize, triangle_count as usize);
    let double = flags & DOUBLE_PRECISION != 0;
    let positions = stream.vectors::<3>(vertices, double)?.into_iter().map(Vec3::from).collect();
    let normals = if flags & HAS_NORMALS != 0 { Some(stream.vectors::<3>(vertices, double)?) } else { None };
    let uvs = if flags & HAS_TEXCOORDS != 0 { Some(stream.vectors::<2>(vertices, double)?) } else { None };
    let colours = if flags & HAS_COLORS != 0 { Some(stream.vectors::<3>(vertices, double)?) } else { None };
    let mut indices = Vec::with_capacity(triangles);
    for t in 0..triangles {
        let corners = [stream.u32()?, stream.u32()?, stream.u32()?];
        if let Some(&i) = corners.iter().find(|&&i| i as usize >= vertices) {
            return Err(format!("triangle {t} refers to vertex {i}, but the mesh has {vertices}"));
        }
        indices.push(corners);
    }
    let mut mesh =
        Mesh { positions, uvs: uvs.map(|u| u.into_iter().map(Vec2::from).collect()), indices, ..Mesh::default() };
    if flags & FACE_NORMALS == 0 {
        mesh.normals = normals.map(|n| n.into_iter().map(|n| Vec3::from(n).normalize_or(Vec3::Z)).collect());
    }
    if let Some(colours) = colours {
        let values = colours.into_iter().flatten().collect();
        mesh.attributes.push(MeshAttribute { name: "vertex_color".into(), values, dim: 3, per_vertex: true });
    }
    Ok(mesh)
}

/// The file's version, after checking its format identifier.
fn header(data: &[u8]) -> Result<u16, String> {
    let [a, b, c, d] = *data.first_chunk::<4>().ok_or("the file is too short for a serialized mesh header")?;
    if u16::from_le_bytes([a, b]) != FORMAT {
        return Err("not a Mitsuba serialized mesh (its first two bytes are not 0x041C)".into());
    }
    match u16::from_le_bytes([c, d]) {
        v @ (3 | 4) => Ok(v),
        v => Err(format!("serialized format version {v} is not supported (3 and 4 are)")),
    }
}

/// Where mesh `shape_index` starts, from the dictionary at the end of the file.
fn offset(data: &[u8], version: u16, shape_index: u32) -> Result<usize, String> {
    let end = data.len();
    let count = end.checked_sub(4).map(|at| u32::from_le_bytes(data[at..].try_into().unwrap_or_default()));
    let count = count.ok_or("the file has no mesh dictionary")?;
    if shape_index >= count {
        return Err(format!(
            "`shape_index` {shape_index} is out of range: the file holds {count} meshes (0 to {})",
            count.saturating_sub(1)
        ));
    }
    let width = if version == 4 { 8 } else { 4 };
    let from_end = (count - shape_index) as usize * width + 4;
    let at = end.checked_sub(from_end).ok_or("the mesh dictionary is longer than the file")?;
    let offset = if version == 4 {
        u64::from_le_bytes(data[at..at + 8].try_into().unwrap_or_default())
    } else {
        u32::from_le_bytes(data[at..at + 4].try_into().unwrap_or_default()) as u64
    };
    usize::try_from(offset).map_err(|_| "a mesh offset does not fit in memory".into())
}

/// The decompressed stream, read as little-endian values.
struct Stream<R: Read> {
    decoder: R,
}

impl<R: Read> Stream<R> {
    fn bytes<const N: usize>(&mut self) -> Result<[u8; N], String> {
        let mut buffer = [0; N];
        self.decoder
            .read_exact(&mut buffer)
            .map_err(|e| format!("the compressed mesh data ends early or is corrupt: {e}"))?;
        Ok(buffer)
    }

    fn u32(&mut self) -> Result<u32, String> {
        self.bytes::<4>().map(u32::from_le_bytes)
    }

    fn u64(&mut self) -> Result<u64, String> {
        self.bytes::<8>().map(u64::from_le_bytes)
    }

    fn number(&mut self, double: bool) -> Result<f32, String> {
        let x =
            if double { f64::from_le_bytes(self.bytes::<8>()?) as f32 } else { f32::from_le_bytes(self.bytes::<4>()?) };
        if x.is_finite() {
            Ok(x)
        } else {
            Err(format!("the mesh holds a number that is not finite ({x})"))
        }
    }

    /// `count` vectors of `N` numbers.
    fn vectors<const N: usize>(&mut self, count: usize, double: bool) -> Result<Vec<[f32; N]>, String> {
        let mut out = Vec::with_capacity(count);
        for _ in 0..count {
            let mut v = [0.0; N];
            for x in &mut v {
                *x = self.number(double)?;
            }
            out.push(v);
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use std::io::Write;

    use flate2::write::ZlibEncoder;

    use super::*;

    /// One mesh as a serialized stream: a triangle and a quad's second half over four
    /// vertices, each vertex (x, y, z) = (i, 2i, 3i), normal +z, uv (i/4, 1 − i/4), colour
    /// (i/10, …) when the flags ask.
    fn mesh_bytes(version: u16, flags: u32, name: &str) -> Vec<u8> {
        let double = flags & DOUBLE_PRECISION != 0;
        let mut body = Vec::new();
        body.extend(flags.to_le_bytes());
        if version == 4 {
            body.extend(name.as_bytes());
            body.push(0);
        }
        body.extend(4u64.to_le_bytes());
        body.extend(2u64.to_le_bytes());
        let mut push = |values: Vec<f32>| {
            for v in values {
                if double {
                    body.extend((v as f64).to_le_bytes());
                } else {
                    body.extend(v.to_le_bytes());
                }
            }
        };
        push((0..4).flat_map(|i| [i as f32, 2.0 * i as f32, 3.0 * i as f32]).collect());
        if flags & HAS_NORMALS != 0 {
            push((0..4).flat_map(|_| [0.0, 0.0, 2.0]).collect());
        }
        if flags & HAS_TEXCOORDS != 0 {
            push((0..4).flat_map(|i| [i as f32 / 4.0, 1.0 - i as f32 / 4.0]).collect());
        }
        if flags & HAS_COLORS != 0 {
            push((0..4).flat_map(|i| [i as f32 / 10.0; 3]).collect());
        }
        for i in [0u32, 1, 2, 0, 2, 3] {
            body.extend(i.to_le_bytes());
        }
        let mut out = Vec::from(FORMAT.to_le_bytes());
        out.extend(version.to_le_bytes());
        let mut encoder = ZlibEncoder::new(Vec::new(), flate2::Compression::default());
        encoder.write_all(&body).unwrap();
        out.extend(encoder.finish().unwrap());
        out
    }

    /// Meshes one after another, then the dictionary of their offsets and their count.
    fn file(version: u16, meshes: &[Vec<u8>]) -> Vec<u8> {
        let mut out = Vec::new();
        let mut offsets = Vec::new();
        for m in meshes {
            offsets.push(out.len() as u64);
            out.extend(m);
        }
        for o in offsets {
            if version == 4 {
                out.extend(o.to_le_bytes());
            } else {
                out.extend((o as u32).to_le_bytes());
            }
        }
        out.extend((meshes.len() as u32).to_le_bytes());
        out
    }

    #[test]
    fn every_field_is_read_in_both_versions_and_either_precision() {
        for version in [3, 4] {
            for precision in [0x1000, DOUBLE_PRECISION] {
                let flags = HAS_NORMALS | HAS_TEXCOORDS | HAS_COLORS | precision;
                let m = read(&file(version, &[mesh_bytes(version, flags, "quad")]), 0).unwrap();
                assert_eq!(m.positions[3], Vec3::new(3.0, 6.0, 9.0), "v{version}");
                assert_eq!(m.indices, [[0, 1, 2], [0, 2, 3]]);
                assert_eq!(m.normals.as_ref().unwrap()[1], Vec3::Z, "normalised");
                assert_eq!(m.uvs.as_ref().unwrap()[1], Vec2::new(0.25, 0.75), "v not turned over");
                assert_eq!(m.attributes[0].name, "vertex_color");
                assert_eq!(&m.attributes[0].values[6..9], &[0.2; 3]);
            }
        }
        // Face normals asked: the file's vertex normals are dropped; no optional arrays.
        let m = read(&file(4, &[mesh_bytes(4, HAS_NORMALS | FACE_NORMALS, "")]), 0).unwrap();
        assert!(m.normals.is_none() && m.uvs.is_none() && m.attributes.is_empty());
    }

    #[test]
    fn shape_index_picks_a_mesh_by_the_dictionary_and_is_checked() {
        for version in [3, 4] {
            let meshes =
                [mesh_bytes(version, 0, "a"), mesh_bytes(version, HAS_TEXCOORDS, "b"), mesh_bytes(version, 0, "c")];
            let data = file(version, &meshes);
            assert!(read(&data, 0).unwrap().uvs.is_none());
            assert!(read(&data, 1).unwrap().uvs.is_some(), "v{version}: the second mesh has uvs");
            let e = read(&data, 3).unwrap_err();
            assert!(e.contains("out of range") && e.contains("3 meshes"), "{e}");
        }
    }

    #[test]
    fn broken_files_are_refused_with_a_reason() {
        let good = file(4, &[mesh_bytes(4, 0, "a")]);
        assert!(read(&good[..3], 0).unwrap_err().contains("too short"));
        let mut wrong = good.clone();
        wrong[0] = 0;
        assert!(read(&wrong, 0).unwrap_err().contains("0x041C"));
        let mut version = good.clone();
        version[2] = 9;
        assert!(read(&version, 0).unwrap_err().contains("version 9"));
        let truncated = &good[..good.len() - 20];
        let e = read(truncated, 0).unwrap_err();
        assert!(e.contains("ends early or is corrupt"), "{e}");
    }

    /// The suite's `matpreview.serialized` (version 3, three meshes), against what Mitsuba
    /// 3.9 reads from it: counts, a first position, uvs and triangle.
    #[test]
    fn the_suites_matpreview_reads_as_mitsuba_reads_it() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../../shared/mitsuba-data/common/meshes/matpreview.serialized");
        let data = std::fs::read(&path).unwrap_or_else(|e| panic!("{} (../shared/mitsuba-data): {e}", path.display()));
        let expected = [
            (289, 512, Vec3::new(-0.504_866_24, 0.574_720_86, 0.784_379), Vec2::new(0.644_658, 0.809_235_63)),
            (2078, 3936, Vec3::new(0.667_028_55, 0.276_292_26, 0.062_822_94), Vec2::new(0.159_145_41, 0.316_977_14)),
            (29439, 57152, Vec3::new(0.047_490_6, -0.449_503_18, -0.902_684_45), Vec2::new(0.903_927, 0.864_370_35)),
        ];
        for (index, (vertices, triangles, first, uv)) in expected.into_iter().enumerate() {
            let m = read(&data, index as u32).unwrap();
            assert_eq!((m.positions.len(), m.indices.len()), (vertices, triangles), "mesh {index}");
            assert!((m.positions[0] - first).abs().max_element() < 1e-6, "mesh {index}: {}", m.positions[0]);
            assert!((m.uvs.as_ref().unwrap()[0] - uv).abs().max_element() < 1e-6, "mesh {index}");
            assert_eq!(&m.indices[..2], &[[0, 1, 2], [1, 0, 3]]);
        }
    }
}
