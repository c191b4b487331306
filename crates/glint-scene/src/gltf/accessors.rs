//! glTF accessors read by glint itself: every component type the core specification and
//! KHR_mesh_quantization allow (floats; signed and unsigned 8-, 16- and 32-bit integers, as
//! stored or normalised), interleaved by their view's stride, and sparse accessors (a base,
//! or zeros, with the listed elements replaced). The `gltf` crate's reader takes positions and
//! normals as floats only and would read quantized ones as garbage; here every element is
//! bounds-checked, so a bad file is an error naming the accessor, never a panic.

use gltf::accessor::{DataType, Dimensions};

/// The types glTF allows for one use of an accessor.
pub struct Allowed {
    pub dimensions: &'static [Dimensions],
    pub types: &'static [DataType],
}

/// An accessor's elements, flattened (element after element, component after component), each
/// component through `convert`, which receives it normalised where the accessor says so.
pub fn read<T>(
    accessor: &gltf::Accessor,
    buffers: &[Vec<u8>],
    allowed: &Allowed,
    convert: impl Fn(f64) -> T,
) -> Result<Vec<T>, String> {
    let index = accessor.index();
    let (dimensions, data_type) = (accessor.dimensions(), accessor.data_type());
    if !allowed.dimensions.contains(&dimensions) || !allowed.types.contains(&data_type) {
        return Err(format!(
            "accessor {index} holds {dimensions:?} of {data_type:?}; here glTF expects {:?} of {:?}",
            allowed.dimensions, allowed.types
        ));
    }
    let normalized = accessor.normalized();
    if normalized && matches!(data_type, DataType::F32 | DataType::U32) {
        return Err(format!("accessor {index}: `normalized` is for 8- and 16-bit integers, not {data_type:?}"));
    }
    let count = accessor.count();
    if count == 0 {
        return Err(format!("accessor {index} has no elements"));
    }
    let components = dimensions.multiplicity();
    let total = count.checked_mul(components).filter(|n| {
        (*n as u64).saturating_mul(std::mem::size_of::<T>().max(4) as u64) <= crate::limits::memory_limit()
    });
    let Some(total) = total else {
        return Err(format!(
            "accessor {index}: {count} elements take more than the memory limit of {} ({})",
            crate::limits::describe(crate::limits::memory_limit()),
            crate::limits::RAISE
        ));
    };
    let size = data_type.size();
    let element = size * components;
    let value = |bytes: &[u8]| component(bytes, data_type, normalized);
    let mut out = Vec::with_capacity(total);
    match accessor.view() {
        Some(view) => {
            let bytes = view_bytes(&view, buffers)
                .ok_or_else(|| format!("accessor {index}: its buffer view lies outside its buffer"))?;
            let stride = view.stride().unwrap_or(element);
            if stride < element {
                return Err(format!(
                    "accessor {index}: its view's stride ({stride}) is shorter than an element ({element})"
                ));
            }
            let needed =
                (count - 1).checked_mul(stride).and_then(|x| x.checked_add(element)?.checked_add(accessor.offset()));
            if needed.is_none_or(|end| end > bytes.len()) {
                return Err(format!("accessor {index} reads past the end of its buffer view or buffer"));
            }
            for i in 0..count {
                let start = accessor.offset() + i * stride;
                for c in 0..components {
                    out.push(convert(value(&bytes[start + c * size..])));
                }
            }
        }
        // Without a view the base is zeros (only a sparse accessor may lack one).
        None if accessor.sparse().is_some() => out.extend((0..total).map(|_| convert(0.0))),
        None => return Err(format!("accessor {index} has no buffer view")),
    }
    if let Some(sparse) = accessor.sparse() {
        let at = |what: &str| format!("accessor {index}: its sparse {what} lie outside their buffer view");
        let n = sparse.count();
        let indices = sparse.indices();
        let index_type = match indices.index_type() {
            gltf::accessor::sparse::IndexType::U8 => DataType::U8,
            gltf::accessor::sparse::IndexType::U16 => DataType::U16,
            gltf::accessor::sparse::IndexType::U32 => DataType::U32,
        };
        let index_bytes = view_bytes(&indices.view(), buffers).ok_or_else(|| at("indices"))?;
        let index_bytes = n
            .checked_mul(index_type.size())
            .and_then(|len| index_bytes.get(indices.offset()..indices.offset().checked_add(len)?))
            .ok_or_else(|| at("indices"))?;
        let values = sparse.values();
        let value_bytes = view_bytes(&values.view(), buffers).ok_or_else(|| at("values"))?;
        let value_bytes = n
            .checked_mul(element)
            .and_then(|len| value_bytes.get(values.offset()..values.offset().checked_add(len)?))
            .ok_or_else(|| at("values"))?;
        for k in 0..n {
            let target = component(&index_bytes[k * index_type.size()..], index_type, false) as usize;
            if target >= count {
                return Err(format!("accessor {index}: sparse index {target} is past its {count} elements"));
            }
            for c in 0..components {
                out[target * components + c] = convert(value(&value_bytes[k * element + c * size..]));
            }
        }
    }
    Ok(out)
}

/// A buffer view's bytes, if it lies within its buffer.
fn view_bytes<'b>(view: &gltf::buffer::View, buffers: &'b [Vec<u8>]) -> Option<&'b [u8]> {
    let buffer = buffers.get(view.buffer().index())?;
    buffer.get(view.offset()..view.offset().checked_add(view.length())?)
}

/// One component from the start of `bytes` (little-endian, as glTF stores them), normalised
/// as glTF defines it: unsigned c / (2ⁿ − 1), signed max(c / (2ⁿ⁻¹ − 1), −1).
fn component(bytes: &[u8], data_type: DataType, normalized: bool) -> f64 {
    let b = |i: usize| bytes[i];
    match data_type {
        DataType::I8 => {
            let c = f64::from(b(0) as i8);
            if normalized {
                (c / 127.0).max(-1.0)
            } else {
                c
            }
        }
        DataType::U8 => {
            let c = f64::from(b(0));
            if normalized {
                c / 255.0
            } else {
                c
            }
        }
        DataType::I16 => {
            let c = f64::from(i16::from_le_bytes([b(0), b(1)]));
            if normalized {
                (c / 32767.0).max(-1.0)
            } else {
                c
            }
        }
        DataType::U16 => {
            let c = f64::from(u16::from_le_bytes([b(0), b(1)]));
            if normalized {
                c / 65535.0
            } else {
                c
            }
        }
        DataType::U32 => f64::from(u32::from_le_bytes([b(0), b(1), b(2), b(3)])),
        DataType::F32 => f64::from(f32::from_le_bytes([b(0), b(1), b(2), b(3)])),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn components_are_normalised_as_gltf_defines() {
        assert_eq!(component(&[255], DataType::U8, true), 1.0);
        assert_eq!(component(&[51], DataType::U8, true), 0.2);
        assert_eq!(component(&[51], DataType::U8, false), 51.0);
        // −128 and −127 both become −1; 127 is 1.
        assert_eq!(component(&[0x80], DataType::I8, true), -1.0);
        assert_eq!(component(&[0x81], DataType::I8, true), -1.0);
        assert_eq!(component(&[0x7f], DataType::I8, true), 1.0);
        assert_eq!(component(&(-300i16).to_le_bytes(), DataType::I16, false), -300.0);
        assert_eq!(component(&i16::MIN.to_le_bytes(), DataType::I16, true), -1.0);
        assert_eq!(component(&32767i16.to_le_bytes(), DataType::I16, true), 1.0);
        assert_eq!(component(&65535u16.to_le_bytes(), DataType::U16, true), 1.0);
        assert_eq!(component(&4_000_000_000u32.to_le_bytes(), DataType::U32, false), 4e9);
        assert_eq!(component(&0.25f32.to_le_bytes(), DataType::F32, false), 0.25);
    }
}
