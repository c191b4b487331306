//! The readers fuzzed, each fed one input as a user's file would reach it, and the seed
//! inputs they start from (`corpus/TARGET/`, committed).

use std::path::{Path, PathBuf};

use clap::ValueEnum;
use glint_cli::checkpoint::{self, Expected, WeightRule};
use glint_cli::compare::{self, Image};
use glint_cli::description::Description;
use glint_core::Rgb;
use glint_scene::native::Format;
use glint_scene::Source;

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Target {
    /// The native scene format, TOML.
    Toml,
    /// The native scene format, JSON.
    Json,
    /// Mitsuba 3 XML (with its includes, meshes and textures beside it).
    Xml,
    /// pbrt-v4 scenes (a PLY mesh they name compiled in).
    Pbrt,
    /// glTF 2.0, binary (.glb) or JSON with its buffers embedded.
    Gltf,
    Obj,
    Ply,
    /// Checkpoints, as `--resume` reads them.
    Checkpoint,
    /// Image textures and environment maps (PNG, JPEG, EXR, HDR).
    Image,
    /// Partial renders (`render --samples`), as `glint merge` reads them.
    Partial,
    /// The Python module's `load_dict`: a dict (mutated JSON objects) made a description and
    /// read as the module reads it (`glint_cli::description`).
    Dict,
    /// `glint compare`'s metrics, ꟻLIP (LDR and HDR), Z-test and warnings on two small images
    /// made from the input's bytes as f32 pixels, NaN and infinities included: a width and a
    /// height byte (1 to 8), then the image's and the reference's channels.
    Compare,
}

/// A quad that the pbrt seed scenes' `plymesh` resolves to.
const QUAD_PLY: &[u8] = b"ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";

/// A small mesh that the seed scenes' mesh references resolve to.
const TRIANGLE_OBJ: &[u8] = b"v -1 -1 0\nv 1 -1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n";

impl Target {
    pub fn name(self) -> &'static str {
        match self {
            Target::Toml => "toml",
            Target::Json => "json",
            Target::Xml => "xml",
            Target::Pbrt => "pbrt",
            Target::Gltf => "gltf",
            Target::Obj => "obj",
            Target::Ply => "ply",
            Target::Checkpoint => "checkpoint",
            Target::Image => "image",
            Target::Partial => "partial",
            Target::Dict => "dict",
            Target::Compare => "compare",
        }
    }

    /// Words of the format for the mutator to insert.
    pub fn tokens(self) -> &'static [&'static str] {
        match self {
            Target::Toml => &[
                "[[shapes]]\n",
                "[materials.x]\n",
                " = ",
                "[",
                "]",
                "{",
                "}",
                "\"",
                "type = \"mesh\"\n",
                "transform = [",
                "\n",
                "#",
                "'''",
                "= inf",
                "= nan",
            ],
            Target::Json => &["{", "}", "[", "]", "\"", ":", ",", "\"type\"", "null", "1e400", "\"shapes\": ["],
            // A Python dict holds any key and any number: big, negative, nested.
            Target::Dict => {
                &["{", "}", "[", "]", "\"", ":", ",", "\"type\"", "null", "-1", "1e30", "{\"a\": [[[[", "\"\": "]
            }
            Target::Xml => &[
                "<",
                ">",
                "</",
                "/>",
                "<shape type=\"obj\">",
                "<include filename=\"",
                "<default name=\"a\" value=\"$a\"/>",
                "$",
                "\"",
                "<!--",
                "-->",
                "<![CDATA[",
                "&amp;",
                "<ref id=\"",
            ],
            Target::Pbrt => &[
                "[",
                "]",
                "\"",
                "#",
                "\n",
                "AttributeBegin\n",
                "AttributeEnd\n",
                "ObjectBegin \"a\"\n",
                "ObjectEnd\n",
                "ObjectInstance \"a\"\n",
                "Shape \"loopsubdiv\" \"integer levels\" 9 ",
                "\"point3 P\" [ ",
                "\"integer indices\" [ ",
                "1e38 ",
                "-1 ",
                "nan ",
                "ReverseOrientation\n",
                "Scale 0 0 0\n",
            ],
            Target::Obj => &[
                "v ",
                "vt ",
                "vn ",
                "f ",
                "/",
                "//",
                "\n",
                "-",
                "nan",
                "1e38",
                "o ",
                "g ",
                "mtllib x.mtl\n",
                "usemtl m\n",
            ],
            Target::Ply => &[
                "element vertex ",
                "element face ",
                "property float ",
                "property list uchar int vertex_indices\n",
                "format binary_little_endian 1.0\n",
                "format ascii 1.0\n",
                "end_header\n",
                "\n",
                " ",
            ],
            Target::Gltf => &[
                "{",
                "}",
                "[",
                "]",
                "\"",
                ":",
                ",",
                "\"byteOffset\": 4294967295",
                "\"count\": 1000000",
                "\"children\": [0]",
                "\"mode\": 5",
                "-1",
                "1e40",
            ],
            Target::Checkpoint | Target::Image | Target::Partial | Target::Compare => &[],
        }
    }
}

impl Target {
    /// Makes half the mutated checkpoints' checksums right again, so that the checks behind
    /// the checksum (the header against the render, the pixels, the weights) are reached.
    pub fn repair(self, rng: &mut crate::mutate::Rng, input: &mut [u8]) {
        if self == Target::Checkpoint && input.len() > 8 && rng.below(2) == 0 {
            let end = input.len() - 8;
            let sum = checkpoint::fingerprint(&[&input[..end]]);
            input[end..].copy_from_slice(&sum.to_le_bytes());
        }
    }
}

/// Runs inputs of one target; files that a target must read from disk go in `scratch`.
pub struct Runner {
    target: Target,
    scratch: PathBuf,
    expected: Option<Expected>,
}

impl Runner {
    pub fn new(target: Target, scratch: PathBuf) -> Self {
        if target == Target::Xml {
            // What the seed scenes refer to, beside the file that is fuzzed.
            for (name, bytes) in corpus_files("xml-files") {
                std::fs::write(scratch.join(name), bytes).expect("the XML scenes' files");
            }
        }
        // The checkpoint seeds' own render: width, height, seed and fingerprint from the first.
        let expected = (target == Target::Checkpoint).then(|| {
            let seed = &seeds(target)[0];
            let u32_at = |i: usize| u32::from_le_bytes(seed[i..i + 4].try_into().unwrap());
            let u64_at = |i: usize| u64::from_le_bytes(seed[i..i + 8].try_into().unwrap());
            Expected {
                width: u32_at(8),
                height: u32_at(12),
                seed: u64_at(20),
                fingerprint: u64_at(28),
                spp: 64,
                weights: WeightRule::PerPass,
                nonnegative: true,
            }
        });
        Self { target, scratch, expected }
    }

    /// Reads one input; `Ok` if the reader accepted it, `Err` with its message if not. A
    /// panic is what the fuzzer looks for.
    pub fn run(&self, input: &[u8]) -> Result<(), String> {
        match self.target {
            Target::Toml | Target::Json => {
                let text = std::str::from_utf8(input).map_err(|e| e.to_string())?;
                let format = if self.target == Target::Toml { Format::Toml } else { Format::Json };
                let files = [("meshes/torus.obj", TRIANGLE_OBJ), ("meshes/ring.obj", TRIANGLE_OBJ)];
                let source = Source::embedded(&files);
                glint_scene::parse_scene(text, format, "fuzz", &source).map(|_| ()).map_err(|e| e.to_string())
            }
            Target::Xml => {
                let path = self.scratch.join("scene.xml");
                std::fs::write(&path, input).map_err(|e| e.to_string())?;
                glint_scene::load_scene(&path).map(|_| ()).map_err(|e| e.to_string())
            }
            Target::Pbrt => {
                let text = std::str::from_utf8(input).map_err(|e| e.to_string())?;
                let files = [("quad.ply", QUAD_PLY)];
                glint_scene::parse_pbrt(text, Path::new("fuzz.pbrt"), Source::embedded(&files))
                    .map(|_| ())
                    .map_err(|e| e.to_string())
            }
            Target::Gltf => {
                let name = if input.starts_with(b"glTF") { "fuzz.glb" } else { "fuzz.gltf" };
                glint_scene::parse_gltf(input, Path::new(name), Source::embedded(&[]), Default::default())
                    .map(|_| ())
                    .map_err(|e| e.to_string())
            }
            Target::Obj => glint_scene::mesh::read_mesh("fuzz.obj", input).map(|_| ()),
            Target::Ply => glint_scene::mesh::read_mesh("fuzz.ply", input).map(|_| ()),
            Target::Checkpoint => {
                let expected = self.expected.as_ref().expect("made for checkpoints");
                checkpoint::parse(input, Path::new("fuzz.ckp"), expected).map(|_| ()).map_err(|e| e.to_string())
            }
            Target::Image => glint_scene::decode_image("fuzz", input, false).map(|_| ()),
            Target::Partial => {
                glint_cli::partial::decode(input, Path::new("fuzz.exr")).map(|_| ()).map_err(|e| e.to_string())
            }
            Target::Dict => {
                let description = Description::from_json(input).map_err(|e| e.to_string())?;
                if !matches!(description, Description::Table(_)) {
                    return Err("load_dict takes a dict".into());
                }
                let files = [("meshes/torus.obj", TRIANGLE_OBJ), ("meshes/ring.obj", TRIANGLE_OBJ)];
                let json = description.to_json().map_err(|e| e.to_string())?;
                json.load(&Source::embedded(&files)).map(|_| ()).map_err(|e| e.to_string())
            }
            Target::Compare => {
                let (image, reference) = compare_images(input);
                let variance =
                    Image { pixels: reference.pixels.iter().map(|p| p.abs()).collect(), ..reference.clone() };
                compare::metrics(&image, &reference)?;
                compare::flip(&image, &reference, 0.0)?;
                compare::hdr_flip(&image, &reference)?;
                compare::z_test(&image, &reference, &variance, 4)?;
                compare::warnings(Path::new("a.png"), &image, Path::new("b.exr"), &reference);
                Ok(())
            }
        }
    }
}

/// Two images of the same size from `input`: a width and a height byte (each 1 to 8), then
/// little-endian f32 channels, the image's and then the reference's, zeros past the end.
fn compare_images(input: &[u8]) -> (Image, Image) {
    let size = |i: usize| input.get(i).map_or(1, |b| u32::from(b % 8) + 1);
    let (width, height) = (size(0), size(1));
    let mut values = input.get(2..).unwrap_or_default().chunks(4).map(|c| {
        let mut bytes = [0u8; 4];
        bytes[..c.len()].copy_from_slice(c);
        f32::from_le_bytes(bytes)
    });
    let mut image = || {
        let pixels = (0..width * height)
            .map(|_| {
                let mut next = || values.next().unwrap_or(0.0);
                Rgb::new(next(), next(), next())
            })
            .collect();
        Image { width, height, pixels, attributes: Default::default() }
    };
    let first = image();
    (first, image())
}

fn corpus_dir(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("corpus").join(name)
}

fn corpus_files(name: &str) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(corpus_dir(name))
        .map(|entries| {
            entries
                .filter_map(Result::ok)
                .map(|e| (e.file_name().to_string_lossy().to_string(), std::fs::read(e.path()).unwrap_or_default()))
                .collect()
        })
        .unwrap_or_default();
    files.sort();
    files
}

/// The seed inputs of `target`, in name order (the dict target's after the JSON scenes).
pub fn seeds(target: Target) -> Vec<Vec<u8>> {
    let mut names = vec![target.name()];
    if target == Target::Dict {
        names.insert(0, Target::Json.name());
    }
    names.into_iter().flat_map(corpus_files).map(|(_, bytes)| bytes).collect()
}
