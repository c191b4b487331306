//! glTF 2.0 scenes (`.gltf` with external or embedded buffers, `.glb`), read by the `gltf`
//! crate (its accessors by glint: quantized and sparse), mapped onto glint's native scene
//! description and built by the same builder as TOML scenes: the node hierarchy (meshes
//! placed once or instanced), cameras, punctual lights (or a default environment),
//! metallic-roughness materials on glint's principled BSDF, alpha as a `mask`.
//! docs/gltf.md lists what maps to what.

mod accessors;
mod alpha;
mod materials;
mod nodes;
mod normal_scale;

use std::path::{Path, PathBuf};

use base64::Engine;

use crate::error::SceneError;
use crate::reader::{MadeFiles, ReadScene, Translation};
use crate::source::{MadeFile, Source};

/// Extensions whose meaning glint reads; others in `extensionsUsed` are named in a warning,
/// and a file that lists one of the others in `extensionsRequired` is refused.
const READ_EXTENSIONS: [&str; 10] = [
    "KHR_lights_punctual",
    "EXT_mesh_gpu_instancing",
    "KHR_mesh_quantization",
    "KHR_materials_transmission",
    "KHR_materials_ior",
    "KHR_materials_emissive_strength",
    "KHR_materials_clearcoat",
    "KHR_materials_volume",
    "KHR_texture_transform",
    "KHR_materials_unlit",
];

/// What the caller chooses about a glTF scene beyond its file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GltfOptions {
    /// Leave out the default environment that lights a file without punctual lights.
    pub no_default_light: bool,
}

/// Reads a glTF 2.0 scene into its native description, with the search path for the files it
/// names: its directory, then `search_path`.
pub(crate) fn read_file(path: &Path, search_path: &[PathBuf], options: GltfOptions) -> ReadScene {
    let (bytes, directories) = crate::reader::read_scene_file(path, search_path)?;
    let source = Source::search_path(directories);
    Ok((translate_bytes(&bytes, path, &source, options)?, source))
}

/// Translates glTF bytes (JSON or binary); `name` is used in messages, `source` resolves the
/// buffers and images it names.
pub(crate) fn translate_bytes(
    bytes: &[u8],
    name: &Path,
    source: &Source,
    options: GltfOptions,
) -> Result<Translation, SceneError> {
    let error = |m: String| SceneError::new(name, None, m);
    precheck(bytes).map_err(|m| error(format!("not a valid glTF 2.0 file: {m}")))?;
    let mut gltf = ::gltf::Gltf::from_slice_without_validation(bytes)
        .map_err(|e| error(format!("not a valid glTF 2.0 file: {e}")))?;
    // The crate's validation refuses every required extension it has no types for, even those
    // glint reads itself (KHR_mesh_quantization): glint decides, naming the extension, and the
    // crate validates the rest.
    let mut json = gltf.document.into_json();
    if let Some(extension) = json.extensions_required.iter().find(|e| !READ_EXTENSIONS.contains(&e.as_str())) {
        return Err(error(format!(
            "the file requires the extension {extension}, which glint does not read{}",
            why_not(extension)
        )));
    }
    json.extensions_required.clear();
    gltf.document = ::gltf::Document::from_json(json).map_err(|e| error(format!("not a valid glTF 2.0 file: {e}")))?;
    let mut warnings = Vec::new();
    for extension in gltf.extensions_used() {
        if !READ_EXTENSIONS.contains(&extension) {
            warnings.push(format!("{}: extension {extension} is not read; its effect is left out", name.display()));
        }
    }
    let buffers = read_buffers(&gltf, source).map_err(error)?;
    let mut made = Vec::new();
    let images = read_images(&gltf, &buffers, source, &mut made).map_err(error)?;
    let reader = nodes::Reader::new(&gltf.document, &buffers, &images, name, options);
    let (file, mut more) = reader.translate(&mut made).map_err(error)?;
    warnings.append(&mut more);
    Ok(Translation { made, warnings, ..Translation::new(file, String::new()) })
}

/// Why a required extension is not read, where there is more to say than that.
fn why_not(extension: &str) -> &'static str {
    match extension {
        "KHR_draco_mesh_compression" | "EXT_meshopt_compression" => {
            ": its meshes are compressed, and glint has no decoder for them (save the file uncompressed, e.g. with gltf-transform)"
        }
        "KHR_texture_basisu" => ": its textures are KTX2/Basis, which glint cannot decode (convert them to PNG or JPEG)",
        _ => "",
    }
}

/// What the `gltf` crate's own validation indexes without checking (found by glint-fuzz):
/// each primitive's POSITION accessor must exist.
fn precheck(bytes: &[u8]) -> Result<(), String> {
    let json = match bytes.strip_prefix(b"glTF") {
        // A .glb: the JSON chunk's length at 12, its bytes from 20.
        Some(_) => {
            let length = bytes.get(12..16).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize);
            match length.and_then(|n| bytes.get(20..20usize.checked_add(n)?)) {
                Some(chunk) => chunk,
                None => return Ok(()), // the crate reports a cut file itself
            }
        }
        None => bytes,
    };
    // Read as the crate reads it: fields it ignores are skipped unchecked (even text that is
    // not UTF-8), so a `Value` would refuse files the crate accepts.
    #[derive(serde::Deserialize)]
    struct Root {
        #[serde(default)]
        accessors: Vec<serde::de::IgnoredAny>,
        #[serde(default)]
        meshes: Vec<Mesh>,
    }
    #[derive(serde::Deserialize)]
    struct Mesh {
        #[serde(default)]
        primitives: Vec<Primitive>,
    }
    #[derive(serde::Deserialize)]
    struct Primitive {
        // A map, as the crate reads it: of a key given twice the last counts.
        #[serde(default)]
        attributes: std::collections::BTreeMap<String, serde_json::Value>,
    }
    let root = serde_json::from_slice::<Root>(json).map_err(|e| format!("{e}"))?;
    let accessors = root.accessors.len();
    for primitive in root.meshes.iter().flat_map(|m| &m.primitives) {
        if let Some(position) = primitive.attributes.get("POSITION") {
            if position.as_u64().is_none_or(|i| (i as usize) >= accessors) {
                return Err(format!("a primitive's POSITION is accessor {position}, but there are {accessors}"));
            }
        }
    }
    Ok(())
}

/// Each buffer's bytes: the binary chunk of a .glb, a `data:` URI, or a file.
fn read_buffers(gltf: &::gltf::Gltf, source: &Source) -> Result<Vec<Vec<u8>>, String> {
    let mut buffers = Vec::new();
    for buffer in gltf.buffers() {
        let bytes = match buffer.source() {
            // Only the first buffer may be the binary chunk (glTF 2.0, GLB): one copy of it.
            ::gltf::buffer::Source::Bin if buffer.index() > 0 => {
                return Err(format!("buffer {} refers to the binary chunk, which only buffer 0 may", buffer.index()))
            }
            ::gltf::buffer::Source::Bin => gltf.blob.clone().ok_or_else(|| {
                format!("buffer {} refers to the binary chunk, which the file does not have", buffer.index())
            })?,
            // Only its `byteLength` is read: a longer file (or one that never ends) is not
            // read whole.
            ::gltf::buffer::Source::Uri(uri) => {
                read_uri(uri, source, buffer.length() as u64).map_err(|m| format!("buffer {}: {m}", buffer.index()))?
            }
        };
        if bytes.len() < buffer.length() {
            return Err(format!(
                "buffer {} declares {} bytes but holds {}",
                buffer.index(),
                buffer.length(),
                bytes.len()
            ));
        }
        buffers.push(bytes);
    }
    Ok(buffers)
}

/// A `data:` URI's bytes, or the first `at_most` of a file's (percent-decoded, relative to the
/// scene).
fn read_uri(uri: &str, source: &Source, at_most: u64) -> Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (header, data) = rest.split_once(',').ok_or("a data URI without a comma")?;
        if !header.ends_with(";base64") {
            return Err("a data URI that is not base64".into());
        }
        return base64::engine::general_purpose::STANDARD.decode(data).map_err(|e| format!("bad base64 data: {e}"));
    }
    source.read_at_most(&percent_decode(uri), at_most)
}

fn percent_decode(uri: &str) -> String {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        match (bytes[i], bytes.get(i + 1).copied().and_then(hex), bytes.get(i + 2).copied().and_then(hex)) {
            (b'%', Some(a), Some(b)) => {
                out.push((a * 16 + b) as u8);
                i += 3;
            }
            (b, _, _) => {
                out.push(b);
                i += 1;
            }
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// Each image as a file the native builder can read: a name in `made` (embedded or
/// `data:` images, and files, read once here), with its format's extension.
fn read_images(
    gltf: &::gltf::Gltf,
    buffers: &[Vec<u8>],
    source: &Source,
    made: &mut MadeFiles,
) -> Result<Vec<String>, String> {
    let mut names = Vec::new();
    let mut total = 0u64;
    for image in gltf.images() {
        let (bytes, mime) = match image.source() {
            ::gltf::image::Source::View { view, mime_type } => {
                let buffer = &buffers[view.buffer().index()];
                let end = view.offset().saturating_add(view.length());
                let range = view.offset()..end;
                let bytes = buffer
                    .get(range)
                    .ok_or_else(|| format!("image {}: its buffer view lies outside its buffer", image.index()))?;
                (bytes.to_vec(), Some(mime_type))
            }
            ::gltf::image::Source::Uri { uri, mime_type } => {
                (read_uri(uri, source, u64::MAX).map_err(|m| format!("image {}: {m}", image.index()))?, mime_type)
            }
        };
        let extension = match mime {
            Some("image/jpeg") => "jpg",
            Some("image/png") => "png",
            _ if bytes.starts_with(&[0xff, 0xd8]) => "jpg",
            _ => "png",
        };
        // Many images over one large view would each copy it.
        total += bytes.len() as u64;
        if total > crate::limits::memory_limit() {
            return Err(format!(
                "the images take more than the memory limit of {} ({})",
                crate::limits::describe(crate::limits::memory_limit()),
                crate::limits::RAISE
            ));
        }
        let name = format!("gltf-image-{}.{extension}", image.index());
        made.push((name.clone(), MadeFile::Bytes(bytes)));
        names.push(name);
    }
    Ok(names)
}
