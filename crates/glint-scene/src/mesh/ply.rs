use std::io::BufReader;

use glam::{Vec2, Vec3};
use glint_core::shapes::{Mesh, MeshAttribute};
use ply_rs::parser::Parser;
use ply_rs::ply::{Property, PropertyAccess};

#[derive(Default)]
struct Vertex {
    position: Vec3,
    normal: Option<Vec3>,
    uv: Option<Vec2>,
    /// The other properties' values, in the file's order.
    extra: Vec<f32>,
}

/// The properties a vertex reads itself (any other is an attribute).
const VERTEX_NAMES: [&str; 14] =
    ["x", "y", "z", "nx", "ny", "nz", "u", "v", "s", "t", "texture_u", "texture_v", "texture_s", "texture_t"];
const FACE_NAMES: [&str; 2] = ["vertex_indices", "vertex_index"];

fn scalar(p: &Property) -> Option<f32> {
    Some(match *p {
        Property::Float(v) => v,
        Property::Double(v) => v as f32,
        Property::Char(v) => v as f32,
        Property::UChar(v) => v as f32,
        Property::Short(v) => v as f32,
        Property::UShort(v) => v as f32,
        Property::Int(v) => v as f32,
        Property::UInt(v) => v as f32,
        _ => return None,
    })
}

impl PropertyAccess for Vertex {
    fn new() -> Self {
        Self::default()
    }
    fn set_property(&mut self, name: String, property: Property) {
        let Some(v) = scalar(&property) else { return };
        match name.as_str() {
            "x" => self.position.x = v,
            "y" => self.position.y = v,
            "z" => self.position.z = v,
            "nx" => self.normal.get_or_insert(Vec3::ZERO).x = v,
            "ny" => self.normal.get_or_insert(Vec3::ZERO).y = v,
            "nz" => self.normal.get_or_insert(Vec3::ZERO).z = v,
            "u" | "s" | "texture_u" | "texture_s" => self.uv.get_or_insert(Vec2::ZERO).x = v,
            "v" | "t" | "texture_v" | "texture_t" => self.uv.get_or_insert(Vec2::ZERO).y = v,
            _ => self.extra.push(attribute_value(&name, &property, v)),
        }
    }
}

/// An attribute's value: a colour channel stored as an integer read as a fraction of its
/// largest value (as Mitsuba reads 8- and 16-bit colours), any other number as it is.
fn attribute_value(name: &str, property: &Property, v: f32) -> f32 {
    let colour = matches!(name, "r" | "g" | "b" | "a" | "red" | "green" | "blue" | "alpha");
    match property {
        Property::UChar(_) if colour => v / 255.0,
        Property::UShort(_) if colour => v / 65535.0,
        _ => v,
    }
}

#[derive(Default)]
struct Face {
    indices: Vec<u32>,
    extra: Vec<f32>,
}

impl PropertyAccess for Face {
    fn new() -> Self {
        Self::default()
    }
    fn set_property(&mut self, name: String, property: Property) {
        if !FACE_NAMES.contains(&name.as_str()) {
            if let Some(v) = scalar(&property) {
                self.extra.push(attribute_value(&name, &property, v));
            }
            return;
        }
        self.indices = match property {
            Property::ListInt(v) => v.into_iter().map(|i| i as u32).collect(),
            Property::ListUInt(v) => v,
            Property::ListShort(v) => v.into_iter().map(|i| i as u32).collect(),
            Property::ListUShort(v) => v.into_iter().map(u32::from).collect(),
            Property::ListChar(v) => v.into_iter().map(|i| i as u32).collect(),
            Property::ListUChar(v) => v.into_iter().map(u32::from).collect(),
            _ => Vec::new(),
        };
    }
}

/// Faces with more than three vertices are split into fans.
pub(super) fn read(data: &[u8]) -> Result<Mesh, String> {
    check_header(data)?;
    let mut reader = BufReader::new(data);
    let vertex_parser = Parser::<Vertex>::new();
    let face_parser = Parser::<Face>::new();
    let header = vertex_parser.read_header(&mut reader).map_err(|e| format!("not a valid PLY header: {e}"))?;
    if let Some(vertex) = header.elements.get("vertex") {
        if let Some(axis) = ["x", "y", "z"].into_iter().find(|p| !vertex.properties.contains_key(*p)) {
            return Err(format!("the PLY vertices have no `{axis}` property (x, y and z are needed)"));
        }
    }
    if header.encoding == ply_rs::ply::Encoding::Ascii {
        check_ascii_numbers(data)?;
    }
    let (mut vertices, mut faces) = (Vec::new(), Vec::new());
    for (name, element) in &header.elements {
        match name.as_str() {
            "vertex" => {
                vertices = vertex_parser
                    .read_payload_for_element(&mut reader, element, &header)
                    .map_err(|e| format!("cannot read the PLY vertices: {e}"))?
            }
            "face" => {
                faces = face_parser
                    .read_payload_for_element(&mut reader, element, &header)
                    .map_err(|e| format!("cannot read the PLY faces: {e}"))?
            }
            other => return Err(format!("unsupported PLY element `{other}` (expected `vertex` and `face`)")),
        }
    }
    let extra_names = |element: &str, reserved: &[&str]| -> Vec<String> {
        header.elements.get(element).map_or(Vec::new(), |e| {
            e.properties
                .iter()
                .filter(|(name, p)| {
                    !reserved.contains(&name.as_str()) && matches!(p.data_type, ply_rs::ply::PropertyType::Scalar(_))
                })
                .map(|(name, _)| name.clone())
                .collect()
        })
    };
    let (vertex_extras, face_extras) = (extra_names("vertex", &VERTEX_NAMES), extra_names("face", &FACE_NAMES));
    let mut mesh = Mesh { positions: vertices.iter().map(|v| v.position).collect(), ..Default::default() };
    if vertices.iter().all(|v| v.normal.is_some()) && !vertices.is_empty() {
        mesh.normals = Some(vertices.iter().map(|v| v.normal.unwrap_or(Vec3::Z).normalize_or(Vec3::Z)).collect());
    }
    if vertices.iter().all(|v| v.uv.is_some()) && !vertices.is_empty() {
        mesh.uvs = Some(vertices.iter().map(|v| v.uv.unwrap_or_default()).collect());
    }
    // Each face's triangles, to repeat its attributes over its fan.
    let mut face_of_triangle = Vec::new();
    for (f, Face { indices, .. }) in faces.iter().enumerate() {
        if indices.len() < 3 {
            return Err(format!("face {f} has {} vertices; at least 3 are needed", indices.len()));
        }
        for k in 1..indices.len() - 1 {
            mesh.indices.push([indices[0], indices[k], indices[k + 1]]);
            face_of_triangle.push(f);
        }
    }
    for (name, first, dim) in attribute_groups(&vertex_extras) {
        let values = vertices.iter().flat_map(|v| v.extra[first..first + dim].iter().copied()).collect();
        mesh.attributes.push(MeshAttribute { name: format!("vertex_{name}"), values, dim, per_vertex: true });
    }
    for (name, first, dim) in attribute_groups(&face_extras) {
        let values =
            face_of_triangle.iter().flat_map(|&f| faces[f].extra[first..first + dim].iter().copied()).collect();
        mesh.attributes.push(MeshAttribute { name: format!("face_{name}"), values, dim, per_vertex: false });
    }
    Ok(mesh)
}

/// The other properties of an element grouped as Mitsuba groups them into attributes: runs of
/// `PREFIX_x, _y, _z, _w` (or `_r, _g, _b, _a`, `_0 … _3`, `_1 … _4`) as one attribute `PREFIX`
/// of up to four values, `r, g, b (, a)` or `red, green, blue (, alpha)` as `color`, any
/// other property alone under its own name. (name, first index, dimension) each.
fn attribute_groups(names: &[String]) -> Vec<(String, usize, usize)> {
    const SCHEMES: [[&str; 4]; 4] =
        [["x", "y", "z", "w"], ["r", "g", "b", "a"], ["0", "1", "2", "3"], ["1", "2", "3", "4"]];
    const COLOURS: [[&str; 4]; 2] = [["r", "g", "b", "a"], ["red", "green", "blue", "alpha"]];
    // How many of `names[i..]` follow `run` (at most four).
    let run_length = |i: usize, run: &dyn Fn(usize) -> String| {
        (0..4).take_while(|&k| names.get(i + k).is_some_and(|n| *n == run(k))).count()
    };
    let mut groups = Vec::new();
    let mut i = 0;
    while i < names.len() {
        let colour = COLOURS.iter().map(|c| run_length(i, &|k| c[k].to_string())).max().unwrap_or(0);
        let (name, dim) = if colour >= 3 {
            ("color".to_string(), colour)
        } else if let Some((prefix, _)) = names[i].rsplit_once('_') {
            let dim = SCHEMES.iter().map(|s| run_length(i, &|k| format!("{prefix}_{}", s[k]))).max().unwrap_or(0);
            if dim > 0 {
                (prefix.to_string(), dim)
            } else {
                (names[i].clone(), 1)
            }
        } else {
            (names[i].clone(), 1)
        };
        groups.push((name, i, dim));
        i += dim;
    }
    groups
}

/// In an ASCII PLY, every word after the header is a finite number: the parser's own message
/// for one that is not ("Line 0: Couln't read element line.") named neither the line nor why.
fn check_ascii_numbers(data: &[u8]) -> Result<(), String> {
    let text = String::from_utf8_lossy(data);
    let mut lines = text.lines().enumerate();
    for (_, line) in lines.by_ref() {
        if line.trim() == "end_header" {
            break;
        }
    }
    for (index, line) in lines {
        if let Some(word) = line.split_whitespace().find(|w| !w.parse::<f64>().is_ok_and(f64::is_finite)) {
            return Err(format!("line {}: `{word}` is not a finite number", index + 1));
        }
    }
    Ok(())
}

/// The PLY header's grammar, checked before `ply-rs` reads it: that crate unwraps some of its
/// own parses (a format version of twenty nines panicked inside it, found by glint-fuzz), and
/// an element count larger than the file could hold is refused here before anything is read.
fn check_header(data: &[u8]) -> Result<(), String> {
    const SCALARS: [&str; 16] = [
        "char", "uchar", "short", "ushort", "int", "uint", "float", "double", "int8", "uint8", "int16", "uint16",
        "int32", "uint32", "float32", "float64",
    ];
    // The header ends at the first line that reads `end_header` (with \n, \r\n or \r).
    let end = data
        .windows(10)
        .enumerate()
        .position(|(i, w)| w == b"end_header" && (i == 0 || matches!(data[i - 1], b'\n' | b'\r')))
        .ok_or("not a valid PLY header: no end_header")?;
    let header = std::str::from_utf8(&data[..end]).map_err(|_| "not a valid PLY header: not text")?;
    let payload = (data.len() - end - 10) as u64;
    for (index, line) in header.split(['\n', '\r']).filter(|l| !l.is_empty()).enumerate() {
        let bad = |why: &str| format!("not a valid PLY header: line {}: {why}", index + 1);
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["ply"] if index == 0 => {}
            _ if index == 0 => return Err(bad("the file must start with `ply`")),
            ["format", "ascii" | "binary_little_endian" | "binary_big_endian", "1.0"] => {}
            ["format", ..] => return Err(bad("expected `format ascii|binary_little_endian|binary_big_endian 1.0`")),
            ["comment" | "obj_info", ..] | [] => {}
            ["element", _, count] => {
                let count: u64 = count.parse().map_err(|_| bad("the element count is not a whole number"))?;
                // Every element takes at least a byte.
                if count > payload {
                    return Err(bad("the element count is larger than the file could hold"));
                }
            }
            ["property", "list", count, item, _] if SCALARS.contains(count) && SCALARS.contains(item) => {}
            ["property", scalar, _] if SCALARS.contains(scalar) => {}
            ["property", ..] => return Err(bad("expected `property TYPE NAME` or `property list TYPE TYPE NAME`")),
            _ => return Err(bad(&format!("unexpected `{line}`"))),
        }
    }
    Ok(())
}
