//! Reading accessors: typed views into buffer data. Every offset, stride and count is
//! checked against the bytes that exist, with overflow-checked arithmetic, before anything
//! is read (the gltf crate's own reader trusts them and can panic on a hostile file).

use gltf::json::accessor::{ComponentType, Type};
use gltf::json::validation::Checked;
use gltf::json::Root;
use std::borrow::Cow;

/// Reads accessors of one document against its loaded buffers.
pub(super) struct Accessors<'a> {
    root: &'a Root,
    buffers: &'a [Cow<'a, [u8]>],
}

/// Elements `stride` bytes apart, each `size` bytes long; the slice holds all of them.
struct Strided<'b> {
    data: &'b [u8],
    stride: usize,
    size: usize,
    count: usize,
}

impl<'b> Strided<'b> {
    fn get(&self, i: usize) -> &'b [u8] {
        let start = i.saturating_mul(self.stride);
        self.data
            .get(start..start.saturating_add(self.size))
            .unwrap_or(&[])
    }
}

/// The first `N` bytes of `b` (zeros past its end: callers pass checked slices).
fn bytes<const N: usize>(b: &[u8]) -> [u8; N] {
    b.get(..N).and_then(|s| s.try_into().ok()).unwrap_or([0; N])
}

/// One component as a float, applying the normalisation rules of the glTF specification.
fn component(b: &[u8], ty: ComponentType, normalized: bool) -> f32 {
    match (ty, normalized) {
        (ComponentType::F32, _) => f32::from_le_bytes(bytes(b)),
        (ComponentType::I8, false) => i8::from_le_bytes(bytes(b)) as f32,
        (ComponentType::U8, false) => u8::from_le_bytes(bytes(b)) as f32,
        (ComponentType::I16, false) => i16::from_le_bytes(bytes(b)) as f32,
        (ComponentType::U16, false) => u16::from_le_bytes(bytes(b)) as f32,
        (ComponentType::U32, false) => u32::from_le_bytes(bytes(b)) as f32,
        (ComponentType::I8, true) => (i8::from_le_bytes(bytes(b)) as f32 / 127.0).max(-1.0),
        (ComponentType::U8, true) => u8::from_le_bytes(bytes(b)) as f32 / 255.0,
        (ComponentType::I16, true) => (i16::from_le_bytes(bytes(b)) as f32 / 32767.0).max(-1.0),
        (ComponentType::U16, true) => u16::from_le_bytes(bytes(b)) as f32 / 65535.0,
        (ComponentType::U32, true) => u32::from_le_bytes(bytes(b)) as f32 / u32::MAX as f32,
    }
}

/// An unsigned integer component (indices), or `None` for other component types.
fn unsigned(b: &[u8], ty: ComponentType) -> Option<u32> {
    match ty {
        ComponentType::U8 => Some(u8::from_le_bytes(bytes(b)) as u32),
        ComponentType::U16 => Some(u16::from_le_bytes(bytes(b)) as u32),
        ComponentType::U32 => Some(u32::from_le_bytes(bytes(b))),
        _ => None,
    }
}

fn type_name(ty: Type) -> &'static str {
    match ty {
        Type::Scalar => "SCALAR",
        Type::Vec2 => "VEC2",
        Type::Vec3 => "VEC3",
        Type::Vec4 => "VEC4",
        Type::Mat2 => "MAT2",
        Type::Mat3 => "MAT3",
        Type::Mat4 => "MAT4",
    }
}

impl<'a> Accessors<'a> {
    pub(super) fn new(root: &'a Root, buffers: &'a [Cow<'a, [u8]>]) -> Self {
        Accessors { root, buffers }
    }

    /// The total size of the document's buffers.
    fn buffer_bytes(&self) -> u64 {
        self.buffers.iter().map(|b| b.len() as u64).sum()
    }

    /// A VEC2, VEC3 or VEC4 attribute (`N` = 2, 3 or 4) as floats; every value must be
    /// finite.
    pub(super) fn floats<const N: usize>(&self, index: usize) -> Result<Vec<[f32; N]>, String> {
        let expected = match N {
            2 => Type::Vec2,
            3 => Type::Vec3,
            _ => Type::Vec4,
        };
        let (ty, normalized) = self.layout(index, expected)?;
        let size = ty.size();
        let values = self.elements(index, ty.size() * N, [0.0; N], |b| {
            std::array::from_fn(|k| component(b.get(k * size..).unwrap_or(&[]), ty, normalized))
        })?;
        if let Some(i) = values.iter().position(|v| v.iter().any(|c| !c.is_finite())) {
            return Err(format!(
                "accessor {index}: element {i} has a non-finite component"
            ));
        }
        Ok(values)
    }

    /// A SCALAR accessor of unsigned integers (vertex indices).
    pub(super) fn indices(&self, index: usize) -> Result<Vec<u32>, String> {
        let (ty, _) = self.layout(index, Type::Scalar)?;
        if unsigned(&[0; 4], ty).is_none() {
            return Err(format!(
                "accessor {index} holds {ty:?} components; indices must be unsigned bytes, \
                 shorts or ints (componentType 5121, 5123 or 5125)"
            ));
        }
        self.elements(index, ty.size(), 0, |b| unsigned(b, ty).unwrap_or(0))
    }

    /// The component type and normalisation of accessor `index`, checking its `type`.
    fn layout(&self, index: usize, expected: Type) -> Result<(ComponentType, bool), String> {
        let accessor = self.root.accessors.get(index).ok_or_else(|| {
            format!(
                "accessor {index} does not exist (the file has {})",
                self.root.accessors.len()
            )
        })?;
        let ty = match accessor.type_ {
            Checked::Valid(t) => t,
            Checked::Invalid => return Err(format!("accessor {index} has an invalid type")),
        };
        if ty != expected {
            return Err(format!(
                "accessor {index} has type {}; expected {}",
                type_name(ty),
                type_name(expected)
            ));
        }
        match accessor.component_type {
            Checked::Valid(c) => Ok((c.0, accessor.normalized)),
            Checked::Invalid => Err(format!("accessor {index} has an invalid componentType")),
        }
    }

    /// Decodes every element of accessor `index` (elements of `size` bytes), including
    /// sparse substitutions.
    fn elements<T: Copy>(
        &self,
        index: usize,
        size: usize,
        zero: T,
        decode: impl Fn(&[u8]) -> T,
    ) -> Result<Vec<T>, String> {
        let Some(accessor) = self.root.accessors.get(index) else {
            return Err(format!("accessor {index} does not exist"));
        };
        let count = accessor.count.0;
        let mut out = match accessor.buffer_view {
            Some(view) => {
                let offset = accessor.byte_offset.map_or(0, |o| o.0);
                let data = self
                    .strided(view.value(), offset, count, size, true)
                    .map_err(|e| format!("accessor {index}: {e}"))?;
                (0..data.count).map(|i| decode(data.get(i))).collect()
            }
            // Without a bufferView the elements are zeros, which cost the file nothing:
            // bound them by the data it does hold, so memory stays proportional to its size.
            None if count > self.buffer_bytes() => {
                return Err(format!(
                    "accessor {index} has no bufferView and {count} elements; prism accepts \
                     at most one zero-initialised element per byte of buffer data, and the \
                     file has {} bytes",
                    self.buffer_bytes()
                ))
            }
            None => vec![zero; count as usize],
        };

        if let Some(sparse) = &accessor.sparse {
            let n = sparse.count.0;
            if n > count {
                return Err(format!(
                    "accessor {index}: sparse.count {n} exceeds the accessor's count {count}"
                ));
            }
            let index_type = match sparse.indices.component_type {
                Checked::Valid(c) => c.0,
                Checked::Invalid => {
                    return Err(format!(
                        "accessor {index}: sparse.indices has an invalid componentType"
                    ))
                }
            };
            let targets = self
                .strided(
                    sparse.indices.buffer_view.value(),
                    sparse.indices.byte_offset.0,
                    n,
                    index_type.size(),
                    false,
                )
                .map_err(|e| format!("accessor {index}, sparse.indices: {e}"))?;
            let values = self
                .strided(
                    sparse.values.buffer_view.value(),
                    sparse.values.byte_offset.0,
                    n,
                    size,
                    false,
                )
                .map_err(|e| format!("accessor {index}, sparse.values: {e}"))?;
            for k in 0..targets.count {
                let target = unsigned(targets.get(k), index_type).unwrap_or(u32::MAX) as usize;
                let slot = out.get_mut(target).ok_or_else(|| {
                    format!(
                        "accessor {index}: sparse index {target} is beyond the accessor's \
                         {count} elements"
                    )
                })?;
                *slot = decode(values.get(k));
            }
        }
        Ok(out)
    }

    /// `count` elements of `size` bytes at `offset` in buffer view `view`. The view's
    /// byteStride applies where `strided_view` (vertex attributes); otherwise elements are
    /// packed.
    fn strided(
        &self,
        view: usize,
        offset: u64,
        count: u64,
        size: usize,
        strided_view: bool,
    ) -> Result<Strided<'a>, String> {
        let data = super::buffers::view(self.root, self.buffers, view)?;
        let view_len = data.len() as u64;
        let byte_stride = self.root.buffer_views.get(view).and_then(|v| v.byte_stride);
        let stride = match byte_stride {
            Some(s) if strided_view => s.0,
            _ => size,
        };
        if stride < size {
            return Err(format!(
                "bufferView {view} has byteStride {stride}, less than the {size}-byte elements \
                 read through it"
            ));
        }
        if count == 0 {
            return Ok(Strided {
                data: &[],
                stride,
                size,
                count: 0,
            });
        }
        // The last element needs only its own bytes, not a whole stride.
        let needed = (count - 1)
            .checked_mul(stride as u64)
            .and_then(|n| n.checked_add(size as u64));
        let end = needed.and_then(|n| n.checked_add(offset));
        match end {
            Some(end) if end <= view_len => Ok(Strided {
                data: &data[offset as usize..end as usize],
                stride,
                size,
                count: count as usize,
            }),
            _ => Err(format!(
                "{count} elements of {size} bytes, {stride} bytes apart from byte {offset}, do \
                 not fit in bufferView {view} ({view_len} bytes)"
            )),
        }
    }
}
