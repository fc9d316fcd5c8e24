//! Inputs found while fuzzing the scene parsers (fuzz/README.md), replayed through the
//! public parsing functions: each once crashed, hung or exhausted memory, and must now give
//! an error quickly. Some came from reviewing what a fuzzer cannot see: files a scene names
//! (a device reads forever) and memory use that grows large without crashing.

use crate::common::mesh_files::glb;
use prism_io::scene::{parse_gltf, LoadError};
use std::path::Path;

fn gltf_error(json: &str) -> String {
    match parse_gltf(json.as_bytes(), Path::new("/nonexistent/fuzz/input.gltf")) {
        Err(e @ LoadError::Invalid { .. }) => e.to_string(),
        Err(e) => panic!("expected a whole-file error, got {e}"),
        Ok(_) => panic!("expected an error for {json}"),
    }
}

/// A buffer uri naming a device was read until memory ran out.
#[cfg(unix)]
#[test]
fn gltf_buffer_uri_naming_a_device_is_refused_unread() {
    let message =
        gltf_error(r#"{"asset":{"version":"2.0"},"buffers":[{"byteLength":4,"uri":"/dev/zero"}]}"#);
    assert!(message.contains("not a regular file"), "{message}");
}

/// An accessor without a bufferView is zeros, plus sparse substitutions. Eight meshes over
/// one with 16777215 elements made a 902-byte file take 6 GB and 30 s; such an accessor
/// may now hold at most one element per byte of buffer data.
#[test]
fn gltf_zero_filled_accessor_is_bounded_by_the_buffer_data() {
    let meshes = 8;
    let nodes: Vec<String> = (0..meshes).map(|i| format!(r#"{{"mesh":{i}}}"#)).collect();
    let primitives = vec![r#"{"primitives":[{"attributes":{"POSITION":0}}]}"#; meshes];
    let indices: Vec<String> = (0..meshes).map(|i| i.to_string()).collect();
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scenes":[{{"nodes":[{}]}}],"nodes":[{}],"meshes":[{}],
        "accessors":[{{"componentType":5126,"count":16777215,"type":"VEC3","sparse":{{"count":1,
        "indices":{{"bufferView":0,"componentType":5125}},"values":{{"bufferView":1}}}}}}],
        "bufferViews":[{{"buffer":0,"byteLength":4}},{{"buffer":0,"byteOffset":4,"byteLength":12}}],
        "buffers":[{{"byteLength":16,"uri":"data:application/octet-stream;base64,AAAAAAAAgD8AAABAAABAQA=="}}]}}"#,
        indices.join(","),
        nodes.join(","),
        primitives.join(",")
    );
    let message = gltf_error(&json);
    assert!(
        message.contains("16777215 elements") && message.contains("16 bytes"),
        "{message}"
    );
}

/// An OBJ file's `mtllib` naming a device was read until memory ran out.
#[cfg(unix)]
#[test]
fn obj_material_library_naming_a_device_is_refused_unread() {
    use prism_io::scene::mesh_file::Materials;
    let obj = "mtllib /dev/zero\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    match prism_io::scene::obj::parse(
        obj,
        Path::new("/nonexistent/fuzz/input.obj"),
        Materials::Read,
    ) {
        Err(e) => assert!(e.to_string().contains("not a regular file"), "{e}"),
        Ok(_) => panic!("expected an error for a device as material library"),
    }
}

/// A GLB file whose BIN chunk holds three vertices and a strip of `strip` u8 indices over
/// them, and whose scene places that one mesh in `nodes` nodes.
fn instanced_strip_glb(strip: usize, nodes: usize) -> Vec<u8> {
    let mut bin: Vec<u8> = [0f32, 0., 0., 1., 0., 0., 0., 1., 0.]
        .iter()
        .flat_map(|c| c.to_le_bytes())
        .collect();
    bin.extend((0..strip).map(|i| (i % 3) as u8));
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let list = |item: &dyn Fn(usize) -> String| -> String {
        (0..nodes).map(item).collect::<Vec<_>>().join(",")
    };
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scenes":[{{"nodes":[{}]}}],"nodes":[{}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":1,"mode":5}}]}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}},
        {{"bufferView":1,"componentType":5121,"count":{strip},"type":"SCALAR"}}],
        "bufferViews":[{{"buffer":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":{strip}}}],
        "buffers":[{{"byteLength":{}}}]}}"#,
        list(&|i| i.to_string()),
        list(&|_| r#"{"mesh":0}"#.to_string()),
        bin.len()
    )
    .into_bytes();
    glb(&json, &bin)
}

/// Placing one mesh in many nodes copies it each time: a 100 KB file could ask for 160
/// million triangles (some 16 GB). Placements are now bounded by the file's size; modest
/// instancing still loads.
#[test]
fn gltf_placed_triangles_are_bounded_by_the_file_size() {
    let path = Path::new("/nonexistent/fuzz/input.glb");
    let few = parse_gltf(&instanced_strip_glb(2000, 20), path).expect("20 instances load");
    assert_eq!(few.geometry.primitives.len(), 20 * 1998);
    match parse_gltf(&instanced_strip_glb(2000, 2000), path) {
        Err(e) => assert!(e.to_string().contains("3996000 triangles in all"), "{e}"),
        Ok(s) => panic!("{} triangles placed", s.geometry.primitives.len()),
    }
}
