//! Inputs found by fuzzing the scene parsers (fuzz/README.md), replayed through the public
//! parsing functions: each once crashed, hung or exhausted memory, and must now give an
//! error (or a scene) quickly.

use prism::scene::{parse_gltf, LoadError};
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
