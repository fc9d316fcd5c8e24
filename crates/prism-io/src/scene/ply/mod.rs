//! Stanford PLY meshes, read by hand: ASCII and binary (little- and big-endian) bodies,
//! `vertex` elements with positions and optional normals and uvs, `face` elements with a
//! vertex index list, and any other element or property skipped by its declared type.
//!
//! The file is never trusted with a size: the header's counts are checked against the
//! bytes that follow it before anything is allocated for them, and every list's length
//! against the bytes left, so a ten-byte file cannot ask for a billion vertices. Errors
//! name the header line, or the body's line and column (ASCII) or byte offset (binary),
//! with the element and property being read. docs/formats.md describes what is read.

mod body;
mod header;

use super::faces;
use super::mesh_file::{MeshFile, MeshPart};
use crate::source::{LoadError, Reader};
use body::{Ascii, Binary, BodyError, Location, Source};
use header::{Element, Format, Header, PropertyType, Scalar};
use prism::geometry::TriangleMesh;
use prism::math::{Vec2, Vec3};
use std::path::Path;

/// Reads the PLY file at `path` through `reader`.
pub fn load(path: &Path, reader: &mut Reader) -> Result<MeshFile, LoadError> {
    let bytes = reader
        .read(path)
        .map_err(|e| LoadError::unreadable(path, e))?;
    parse(&bytes, &path.display().to_string())
}

/// Reads PLY bytes; `path` names them in errors.
pub fn parse(bytes: &[u8], path: &str) -> Result<MeshFile, LoadError> {
    let header = header::parse(bytes).map_err(|e| LoadError::Syntax {
        path: path.to_string(),
        line: e.line,
        column: e.column,
        message: e.message,
    })?;
    let at_line = |line: usize, column: usize, message: String| LoadError::Syntax {
        path: path.to_string(),
        line,
        column,
        message,
    };
    let layout = Layout::new(&header, path).map_err(|(line, message)| at_line(line, 1, message))?;
    check_counts(&header, bytes.len() - header.body_start)
        .map_err(|(e, message)| at_line(e.line, e.count_column, message))?;

    let data = &bytes[header.body_start..];
    let read = match header.format {
        Format::Ascii => read_body(&header, &layout, Ascii::new(data, header.body_line)),
        Format::BinaryLittleEndian => read_body(
            &header,
            &layout,
            Binary::new(data, header.body_start, false),
        ),
        Format::BinaryBigEndian => {
            read_body(&header, &layout, Binary::new(data, header.body_start, true))
        }
    };
    let raw = read.map_err(|(e, context)| match e.at {
        Location::LineColumn(line, column) => LoadError::Syntax {
            path: path.to_string(),
            line,
            column,
            message: format!("{context}: {}", e.message),
        },
        Location::Byte(byte) => LoadError::Invalid {
            path: path.to_string(),
            message: format!("byte {byte} ({context}): {}", e.message),
        },
    })?;
    raw.into_mesh_file(path)
}

/// Where a vertex property goes: position, normal and uv components in that order.
#[derive(Clone, Copy, PartialEq)]
enum Slot {
    Component(usize),
    Skip,
}

const COMPONENTS: usize = 8;

/// How the face element lists its vertices.
#[derive(Clone, Copy, PartialEq, Eq)]
enum FaceList {
    /// `element face`: one polygon per instance.
    Polygons,
    /// `element tristrips`: triangle strips, each list holding strips separated by -1
    /// (as in the Georgia Tech and Cyberware models): vertices i, i+1, i+2 make triangle i,
    /// every other one with its winding turned back.
    Strips,
}

/// Which elements and properties hold the mesh.
struct Layout {
    vertex: usize,
    face: usize,
    face_list: FaceList,
    slots: Vec<Slot>,
    has_normals: bool,
    has_uvs: bool,
    /// The face element's index list property.
    indices: usize,
}

impl Layout {
    /// Finds the mesh in the header; errors name a header line.
    fn new(header: &Header, path: &str) -> Result<Layout, (usize, String)> {
        let last_line = header.body_line - 1;
        let find = |name: &str| header.elements.iter().position(|e| e.name == name);
        let vertex = find("vertex").ok_or_else(|| {
            (
                last_line,
                format!("{path} declares no 'element vertex'; expected one with x, y and z"),
            )
        })?;
        let (face, face_list) = find("face")
            .map(|f| (f, FaceList::Polygons))
            .or_else(|| find("tristrips").map(|f| (f, FaceList::Strips)))
            .ok_or_else(|| {
                (
                    last_line,
                    "no 'element face' or 'element tristrips': prism renders surfaces, not \
                     point clouds; expected an element face with a vertex_indices list"
                        .to_string(),
                )
            })?;

        let v = &header.elements[vertex];
        let position_of = |name: &str| v.properties.iter().position(|p| p.name == name);
        let mut slots = vec![Slot::Skip; v.properties.len()];
        let mut assign = |names: &[&str], first: usize| -> Result<bool, (usize, String)> {
            let found: Vec<Option<usize>> = names.iter().map(|n| position_of(n)).collect();
            if found.iter().all(Option::is_none) {
                return Ok(false);
            }
            if let Some(k) = found.iter().position(Option::is_none) {
                let present = names
                    .iter()
                    .zip(&found)
                    .find_map(|(n, f)| f.map(|i| (n, i)))
                    .expect("one is present");
                return Err((
                    v.properties[present.1].line,
                    format!(
                        "element vertex has {} but no {}; expected all of {}",
                        present.0,
                        names[k],
                        names.join(", ")
                    ),
                ));
            }
            for (k, i) in found.into_iter().enumerate() {
                let i = i.expect("all present");
                let p = &v.properties[i];
                if !matches!(p.ty, PropertyType::Scalar(_)) {
                    return Err((
                        p.line,
                        format!("vertex property {} is a list; expected a number", p.name),
                    ));
                }
                slots[i] = Slot::Component(first + k);
            }
            Ok(true)
        };
        if !assign(&["x", "y", "z"], 0)? {
            return Err((
                v.line,
                "element vertex has no x, y and z properties; expected positions".into(),
            ));
        }
        let has_normals = assign(&["nx", "ny", "nz"], 3)?;
        let mut has_uvs = false;
        for pair in [
            ["u", "v"],
            ["s", "t"],
            ["texture_u", "texture_v"],
            ["texture_s", "texture_t"],
        ] {
            if assign(&pair, 6)? {
                has_uvs = true;
                break;
            }
        }

        let f = &header.elements[face];
        let indices = f
            .properties
            .iter()
            .position(|p| p.name == "vertex_indices" || p.name == "vertex_index")
            .ok_or_else(|| {
                (
                    f.line,
                    format!(
                        "element {} has no vertex_indices property; expected 'property list \
                         uchar int vertex_indices'",
                        f.name
                    ),
                )
            })?;
        match f.properties[indices].ty {
            PropertyType::List { item, .. } if item.is_integer() => {}
            PropertyType::List { item, .. } => {
                return Err((
                    f.properties[indices].line,
                    format!(
                        "vertex indices of type {}; expected an integer type (int, uint, …)",
                        item.name()
                    ),
                ))
            }
            PropertyType::Scalar(_) => {
                return Err((
                    f.properties[indices].line,
                    "vertex_indices must be a list: expected 'property list uchar int \
                     vertex_indices'"
                        .into(),
                ))
            }
        }
        Ok(Layout {
            vertex,
            face,
            face_list,
            slots,
            has_normals,
            has_uvs,
            indices,
        })
    }
}

/// Refuses counts the body cannot hold, before anything is allocated for them: binary
/// instances need their fixed-size properties' bytes, text ones a character and a
/// separator per property.
fn check_counts(header: &Header, body_bytes: usize) -> Result<(), (&Element, String)> {
    let mut needed: u128 = 0;
    for element in &header.elements {
        let (per_instance, unit) = match header.format {
            Format::Ascii => (2 * element.properties.len() as u128, "values"),
            _ => (element.min_binary_size() as u128, "bytes"),
        };
        needed += element.count as u128 * per_instance;
        // The last text value needs no separator.
        let slack = u128::from(header.format == Format::Ascii);
        if needed > body_bytes as u128 + slack {
            let each = match header.format {
                Format::Ascii => format!("{} {unit}", element.properties.len()),
                _ => format!("{per_instance} {unit}"),
            };
            return Err((
                element,
                format!(
                    "element {} declares {} instances of at least {each} each, more than the \
                     {body_bytes} bytes after the header can hold",
                    element.name, element.count
                ),
            ));
        }
    }
    Ok(())
}

/// The mesh as read, before triangulation.
struct RawMesh {
    positions: Vec<Vec3>,
    normals: Option<Vec<Vec3>>,
    uvs: Option<Vec<Vec2>>,
    corners: Vec<u32>,
    face_sizes: Vec<u32>,
}

type ReadError = (BodyError, String);

fn read_body(header: &Header, layout: &Layout, mut src: impl Source) -> Result<RawMesh, ReadError> {
    let vertex_count = header.elements[layout.vertex].count;
    let face_count = header.elements[layout.face].count;
    // check_counts bounded both counts by the file's size.
    let mut raw = RawMesh {
        positions: Vec::with_capacity(vertex_count),
        normals: layout.has_normals.then(|| Vec::with_capacity(vertex_count)),
        uvs: layout.has_uvs.then(|| Vec::with_capacity(vertex_count)),
        corners: Vec::with_capacity(3 * face_count),
        face_sizes: Vec::with_capacity(face_count),
    };
    for (index, element) in header.elements.iter().enumerate() {
        if element.properties.is_empty() {
            continue; // Nothing to read, however many instances it declares.
        }
        if index == layout.vertex {
            read_vertices(element, layout, &mut src, &mut raw)?;
        } else if index == layout.face {
            read_faces(element, layout, vertex_count, &mut src, &mut raw)?;
        } else {
            for i in 0..element.count {
                skip_instance(element, &mut src)
                    .map_err(|e| (e, format!("element {} {i}", element.name)))?;
            }
        }
    }
    src.finish()
        .map_err(|e| (e, "after the last element".to_string()))?;
    Ok(raw)
}

fn read_vertices(
    element: &Element,
    layout: &Layout,
    src: &mut impl Source,
    raw: &mut RawMesh,
) -> Result<(), ReadError> {
    let context =
        |i: usize, p: usize| format!("vertex {i}, property {}", element.properties[p].name);
    for i in 0..element.count {
        let mut v = [0.0f32; COMPONENTS];
        for (p, property) in element.properties.iter().enumerate() {
            match (property.ty, layout.slots[p]) {
                (PropertyType::Scalar(ty), Slot::Component(k)) => {
                    let value = src.read(ty).map_err(|e| (e, context(i, p)))?;
                    v[k] = value as f32;
                    if !v[k].is_finite() {
                        let e = BodyError {
                            at: src.last(),
                            message: format!("{value:e} is not a finite 32-bit number"),
                        };
                        return Err((e, context(i, p)));
                    }
                }
                (PropertyType::Scalar(ty), _) => {
                    src.skip(ty, 1).map_err(|e| (e, context(i, p)))?;
                }
                (PropertyType::List { count, item }, _) => {
                    let n = list_length(src, count, item).map_err(|e| (e, context(i, p)))?;
                    src.skip(item, n).map_err(|e| (e, context(i, p)))?;
                }
            }
        }
        raw.positions.push(Vec3::new(v[0], v[1], v[2]));
        if let Some(n) = &mut raw.normals {
            n.push(Vec3::new(v[3], v[4], v[5]));
        }
        if let Some(uv) = &mut raw.uvs {
            uv.push(Vec2::new(v[6], v[7]));
        }
    }
    Ok(())
}

fn read_faces(
    element: &Element,
    layout: &Layout,
    vertex_count: usize,
    src: &mut impl Source,
    raw: &mut RawMesh,
) -> Result<(), ReadError> {
    let what = match layout.face_list {
        FaceList::Polygons => "face",
        FaceList::Strips => "strip list",
    };
    let context =
        |i: usize, p: usize| format!("{what} {i}, property {}", element.properties[p].name);
    let mut strip = Vec::new();
    for i in 0..element.count {
        for (p, property) in element.properties.iter().enumerate() {
            match property.ty {
                PropertyType::List { count, item }
                    if p == layout.indices && layout.face_list == FaceList::Strips =>
                {
                    let n = list_length(src, count, item).map_err(|e| (e, context(i, p)))?;
                    strip.clear();
                    for _ in 0..n {
                        let value = src.read(item).map_err(|e| (e, context(i, p)))?;
                        if value == -1.0 {
                            add_strip(&strip, raw);
                            strip.clear();
                            continue;
                        }
                        check_index(value, vertex_count, true, src)
                            .map_err(|e| (e, context(i, p)))?;
                        strip.push(value as u32);
                    }
                    add_strip(&strip, raw);
                }
                PropertyType::List { count, item } if p == layout.indices => {
                    let n = list_length(src, count, item).map_err(|e| (e, context(i, p)))?;
                    if n < 3 {
                        let e = BodyError {
                            at: src.last(),
                            message: format!("a face of {n} corners; expected at least 3"),
                        };
                        return Err((e, context(i, p)));
                    }
                    for _ in 0..n {
                        let value = src.read(item).map_err(|e| (e, context(i, p)))?;
                        check_index(value, vertex_count, false, src)
                            .map_err(|e| (e, context(i, p)))?;
                        raw.corners.push(value as u32);
                    }
                    raw.face_sizes.push(n as u32);
                }
                PropertyType::List { count, item } => {
                    let n = list_length(src, count, item).map_err(|e| (e, context(i, p)))?;
                    src.skip(item, n).map_err(|e| (e, context(i, p)))?;
                }
                PropertyType::Scalar(ty) => {
                    src.skip(ty, 1).map_err(|e| (e, context(i, p)))?;
                }
            }
        }
    }
    Ok(())
}

/// Refuses a vertex index outside the vertices the file has.
fn check_index(
    value: f64,
    vertex_count: usize,
    strips: bool,
    src: &impl Source,
) -> Result<(), BodyError> {
    if value >= 0.0 && (value as usize) < vertex_count {
        return Ok(());
    }
    Err(BodyError {
        at: src.last(),
        message: format!(
            "vertex index {value}, but the file has {vertex_count} vertices: expected 0 to {}{}",
            vertex_count as i64 - 1,
            if strips { ", or -1 between strips" } else { "" }
        ),
    })
}

/// The triangles of one strip, as three-corner faces. Strips repeat a vertex to turn a
/// corner or to join two runs; the zero-area triangles that makes are left out.
fn add_strip(strip: &[u32], raw: &mut RawMesh) {
    for (k, w) in strip.windows(3).enumerate() {
        let (a, b, c) = (w[0], w[1], w[2]);
        if a == b || b == c || a == c {
            continue;
        }
        // Every other triangle runs the other way round; turn it back to keep the winding.
        let corners = if k % 2 == 0 { [a, b, c] } else { [b, a, c] };
        raw.corners.extend(corners);
        raw.face_sizes.push(3);
    }
}

fn skip_instance(element: &Element, src: &mut impl Source) -> Result<(), BodyError> {
    for property in &element.properties {
        match property.ty {
            PropertyType::Scalar(ty) => src.skip(ty, 1)?,
            PropertyType::List { count, item } => {
                let n = list_length(src, count, item)?;
                src.skip(item, n)?;
            }
        }
    }
    Ok(())
}

/// A list's length, checked against what the rest of the body can hold.
fn list_length(src: &mut impl Source, count: Scalar, item: Scalar) -> Result<usize, BodyError> {
    let n = src.read(count)?;
    if n < 0.0 {
        return Err(BodyError {
            at: src.last(),
            message: format!("a list length of {n}; expected a number ≥ 0"),
        });
    }
    let n = n as usize;
    let room = src.capacity(item);
    if n > room {
        return Err(BodyError {
            at: src.last(),
            message: format!(
                "a list of {n} {} values, but the rest of the file holds at most {room}",
                item.name()
            ),
        });
    }
    Ok(n)
}

impl RawMesh {
    fn into_mesh_file(self, path: &str) -> Result<MeshFile, LoadError> {
        let invalid = |message: String| LoadError::Invalid {
            path: path.to_string(),
            message,
        };
        let mut triangles = Vec::with_capacity(self.corners.len().saturating_sub(2));
        let mut scratch = Vec::new();
        let mut start = 0;
        for (face, &size) in self.face_sizes.iter().enumerate() {
            let corners = &self.corners[start..start + size as usize];
            faces::triangulate(&self.positions, corners, &mut triangles, &mut scratch)
                .map_err(|e| invalid(format!("face {face}: {e}")))?;
            start += size as usize;
        }
        let mut file = MeshFile {
            defined_vertices: self.positions.len(),
            ..MeshFile::default()
        };
        if triangles.is_empty() {
            return Ok(file);
        }
        if !faces::any_with_area(&self.positions, &triangles) {
            // The file then holds nothing: the caller's empty-mesh error says why.
            file.warnings.push(format!(
                "{path}: the mesh has only faces of zero area ({}); it is left out",
                self.face_sizes.len()
            ));
            return Ok(file);
        }
        let mesh = TriangleMesh::new(self.positions, triangles, self.normals, self.uvs)
            .map_err(|e| invalid(e.to_string()))?;
        file.parts.push(MeshPart {
            mesh,
            material: None,
        });
        Ok(file)
    }
}
